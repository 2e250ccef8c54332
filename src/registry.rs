//! The one table of generators that experiment files and the command line
//! can name: the paper's scenes register themselves here
//! ([`scenes::register`](crate::scenes::register)) exactly as a user's
//! own generators do.
//!
//! ```
//! use shapegen::registry::Registry;
//! use shapegen::scenes::Spaceship;
//!
//! let mut registry = Registry::builtin();
//! assert!(registry.contains("tree_v2"));
//! // A user's generator (here the spaceship again, under a new name):
//! registry.register("my_ship", Spaceship);
//! assert!(registry.names().any(|n| n == "my_ship"));
//! ```

use std::fmt;
use std::sync::Arc;

use crate::experiment::ExperimentError;
use crate::experiment::problem::{ModelProblem, Problem, SceneOutputs, SceneSetup};
use crate::express::Generator;
use crate::genome::Chromosome;
use crate::graph::Graph;
use crate::score::ModelFitness;
use crate::score::ShapeMeshes;
use crate::transform::{Blend, Design, TransformError};

/// Named generators. Names are matched exactly; registering a name again
/// replaces the earlier generator (so a program may override a built-in).
#[derive(Clone, Default)]
pub struct Registry {
    entries: Vec<(String, Arc<dyn Registered>)>,
}

impl fmt::Debug for Registry {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_list().entries(self.names()).finish()
    }
}

impl Registry {
    /// An empty registry.
    #[must_use]
    pub fn new() -> Self {
        Self::default()
    }

    /// The paper's generators (`spaceship`, `tree_v1`, `tree_v2`,
    /// `space_filling_city`, `grid_city`; see [`scenes`](crate::scenes)).
    #[must_use]
    pub fn builtin() -> Self {
        let mut registry = Self::new();
        crate::scenes::register(&mut registry);
        registry
    }

    /// Adds `generator` under `name` (replacing a generator of that name).
    /// Its state must say how a design transformation blends it
    /// ([`Blend`]); the default [`Scope`](crate::express::Scope) does.
    pub fn register<G>(&mut self, name: &str, generator: G) -> &mut Self
    where
        G: Generator + Send + 'static,
        G::State: Blend,
    {
        let entry: Arc<dyn Registered> = Arc::new(Entry(Arc::new(generator)));
        match self.entries.iter_mut().find(|(n, _)| n == name) {
            Some(slot) => slot.1 = entry,
            None => self.entries.push((name.to_string(), entry)),
        }
        self
    }

    /// [`register`](Self::register), by value, for chaining.
    #[must_use]
    pub fn with<G>(mut self, name: &str, generator: G) -> Self
    where
        G: Generator + Send + 'static,
        G::State: Blend,
    {
        self.register(name, generator);
        self
    }

    /// Whether a generator is registered under `name`.
    #[must_use]
    pub fn contains(&self, name: &str) -> bool {
        self.get(name).is_some()
    }

    /// The registered names, in registration order.
    pub fn names(&self) -> impl Iterator<Item = &str> {
        self.entries.iter().map(|(n, _)| n.as_str())
    }

    /// The graph of generator `name`.
    #[must_use]
    pub fn graph(&self, name: &str) -> Option<&Graph> {
        self.get(name).map(|g| g.graph())
    }

    /// `chromosome` of generator `name`, as one side of a design
    /// transformation ([`transform`](crate::transform)).
    pub fn design(&self, name: &str, chromosome: Chromosome) -> Result<Design, TransformError> {
        match self.get(name) {
            Some(g) => g.design(chromosome),
            None => Err(TransformError::UnknownGenerator {
                name: name.to_string(),
                known: self.list(),
            }),
        }
    }

    /// The names as a sentence for error messages (`a, b, c`).
    pub(crate) fn list(&self) -> String {
        let names: Vec<&str> = self.names().collect();
        if names.is_empty() {
            "none is registered".into()
        } else {
            names.join(", ")
        }
    }

    pub(crate) fn get(&self, name: &str) -> Option<&dyn Registered> {
        self.entries
            .iter()
            .find(|(n, _)| n == name)
            .map(|(_, g)| &**g)
    }
}

/// A registered generator, with its type erased: what an experiment needs
/// of it to build its problem.
pub(crate) trait Registered: Send + Sync {
    /// The generator's own graph (its own limits).
    fn graph(&self) -> &Graph;
    /// The names of its shapes.
    fn shapes(&self) -> &[std::borrow::Cow<'static, str>];
    /// The generator scored on `scene` with `graph`'s limits and `shapes`.
    fn problem(
        &self,
        graph: Graph,
        shapes: ShapeMeshes,
        scene: SceneSetup,
    ) -> Result<Box<dyn Problem>, ExperimentError>;
    /// `chromosome` of the generator, as one side of a transformation.
    fn design(&self, chromosome: Chromosome) -> Result<Design, TransformError>;
}

struct Entry<G>(Arc<G>);

impl<G> Registered for Entry<G>
where
    G: Generator + Send + 'static,
    G::State: Blend,
{
    fn design(&self, chromosome: Chromosome) -> Result<Design, TransformError> {
        Design::new(Arc::clone(&self.0), chromosome)
    }

    fn graph(&self) -> &Graph {
        self.0.graph()
    }

    fn shapes(&self) -> &[std::borrow::Cow<'static, str>] {
        self.0.shapes()
    }

    fn problem(
        &self,
        graph: Graph,
        shapes: ShapeMeshes,
        scene: SceneSetup,
    ) -> Result<Box<dyn Problem>, ExperimentError> {
        let generator = Arc::clone(&self.0);
        match scene {
            SceneSetup::Volume {
                scene,
                score,
                targets,
            } => boxed(graph, generator, &shapes, *scene, score, Some(targets)),
            SceneSetup::Image { scene, score } => {
                boxed(graph, generator, &shapes, scene, score, None)
            }
        }
    }
}

/// `generator` scored on `scene`: the one path volume and image scenes share.
fn boxed<G, S>(
    graph: Graph,
    generator: G,
    shapes: &ShapeMeshes,
    scene: S,
    score: S::Score,
    target_meshes: Option<ShapeMeshes>,
) -> Result<Box<dyn Problem>, ExperimentError>
where
    G: Generator + Send + 'static,
    G::State: Send,
    S: SceneOutputs + Send + Sync + 'static,
    S::Shape: Send + Sync,
    S::Score: Send + Sync,
{
    let limits = *graph.limits();
    let fitness = ModelFitness::new(generator, scene, shapes, score)?.with_limits(limits);
    Ok(Box::new(ModelProblem {
        graph,
        fitness,
        target_meshes,
    }))
}
