//! A design: a generator and one of its derivations, with the generator's
//! state type erased so that two designs of any generators co-derive.

use std::any::Any;
use std::borrow::Cow;
use std::sync::Arc;

use crate::express::{Generator, Instance, Instances, ModelSink, Pending, Scope, ShapeId};
use crate::genome::Chromosome;
use crate::glam::Affine3A;
use crate::graph::{Axis, Graph, NodeId};

use super::TransformError;
use super::blend::Blend;

/// A state of either design, behind its scope.
pub(crate) trait StateObj: Send + Sync {
    fn scope(&self) -> Scope;
    fn with_scope(&self, scope: Scope) -> Box<dyn StateObj>;
    fn clone_box(&self) -> Box<dyn StateObj>;
    fn as_any(&self) -> &dyn Any;
}

impl<T: Blend> StateObj for T {
    fn scope(&self) -> Scope {
        Blend::scope(self)
    }

    fn with_scope(&self, scope: Scope) -> Box<dyn StateObj> {
        Box::new(Blend::with_scope(self, scope))
    }

    fn clone_box(&self) -> Box<dyn StateObj> {
        Box::new(self.clone())
    }

    fn as_any(&self) -> &dyn Any {
        self
    }
}

pub(crate) type DynState = Box<dyn StateObj>;

/// One derivation step of a generator, on erased states.
pub(crate) trait Stepper: Send + Sync {
    fn graph(&self) -> &Graph;
    fn shapes(&self) -> &[Cow<'static, str>];
    fn axiom(&self) -> DynState;
    /// Expresses gene `pos` from `state`: instances into `out`, children
    /// (position, state) onto `children` in schedule order. Returns the
    /// split the gene made, if it splits (its children are then the parts).
    fn step(
        &self,
        chromosome: &Chromosome,
        pos: u32,
        state: &dyn StateObj,
        out: &mut Instances,
        children: &mut Vec<(u32, DynState)>,
    ) -> Option<(Axis, Scope)>;
    /// Expresses the whole subtree of gene `pos` from `state` into `out`.
    fn subtree(&self, chromosome: &Chromosome, pos: u32, state: &dyn StateObj, out: &mut Instances);
}

/// A sink that keeps instances and hears where a gene splits.
struct Listening<'a> {
    out: &'a mut Instances,
    split: Option<(Axis, Scope)>,
}

impl ModelSink for Listening<'_> {
    fn emit(&mut self, shape: ShapeId, transform: &Affine3A) {
        self.out.emit(shape, transform);
    }

    fn emit_from(&mut self, node: NodeId, shape: ShapeId, transform: &Affine3A) {
        self.out.emit_from(node, shape, transform);
    }

    fn split(&mut self, _: NodeId, axis: Axis, scope: &Scope) {
        self.split = Some((axis, *scope));
    }
}

struct Erased<G>(G);

impl<G> Erased<G>
where
    G: Generator,
    G::State: Blend,
{
    fn state(state: &dyn StateObj) -> G::State {
        state
            .as_any()
            .downcast_ref::<G::State>()
            .expect("a design's genes receive its own states")
            .clone()
    }
}

impl<G> Stepper for Erased<G>
where
    G: Generator + Send,
    G::State: Blend,
{
    fn graph(&self) -> &Graph {
        self.0.graph()
    }

    fn shapes(&self) -> &[Cow<'static, str>] {
        self.0.shapes()
    }

    fn axiom(&self) -> DynState {
        Box::new(self.0.axiom())
    }

    fn step(
        &self,
        chromosome: &Chromosome,
        pos: u32,
        state: &dyn StateObj,
        out: &mut Instances,
        children: &mut Vec<(u32, DynState)>,
    ) -> Option<(Axis, Scope)> {
        let mut pending = Pending::new();
        let mut sink = Listening { out, split: None };
        self.0
            .express_gene(chromosome, pos, Self::state(state), &mut sink, &mut pending);
        children.extend(pending.drain().map(|(p, s)| (p, Box::new(s) as DynState)));
        sink.split
    }

    fn subtree(
        &self,
        chromosome: &Chromosome,
        pos: u32,
        state: &dyn StateObj,
        out: &mut Instances,
    ) {
        self.0.express_from(
            chromosome,
            pos,
            Self::state(state),
            out,
            &mut Pending::new(),
        );
    }
}

/// One side of a transformation: a generator and one chromosome of it.
#[derive(Clone)]
pub struct Design {
    generator: Arc<dyn Stepper>,
    chromosome: Chromosome,
}

impl std::fmt::Debug for Design {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Design")
            .field("generator", &self.generator.graph().name())
            .field("genes", &self.chromosome.len())
            .finish()
    }
}

impl Design {
    /// `chromosome` of `generator`, checked against its graph.
    pub fn new<G>(generator: G, chromosome: Chromosome) -> Result<Self, TransformError>
    where
        G: Generator + Send + 'static,
        G::State: Blend,
    {
        chromosome
            .validate(generator.graph())
            .map_err(|e| TransformError::Chromosome(e.to_string()))?;
        Ok(Self {
            generator: Arc::new(Erased(generator)),
            chromosome,
        })
    }

    /// The generator's default model (every slot of probability ≥ ½, central parameters).
    pub fn default_model<G>(generator: G) -> Result<Self, TransformError>
    where
        G: Generator + Send + 'static,
        G::State: Blend,
    {
        let c = crate::ops::default_model(generator.graph())
            .map_err(|e| TransformError::Chromosome(e.to_string()))?;
        Self::new(generator, c)
    }

    pub(crate) fn stepper(&self) -> &dyn Stepper {
        &*self.generator
    }

    /// The generator's graph.
    #[must_use]
    pub fn graph(&self) -> &Graph {
        self.generator.graph()
    }

    /// The generator's shape names.
    #[must_use]
    pub fn shapes(&self) -> &[Cow<'static, str>] {
        self.generator.shapes()
    }

    /// The derivation.
    #[must_use]
    pub fn chromosome(&self) -> &Chromosome {
        &self.chromosome
    }

    /// The design as its own generator expresses it.
    #[must_use]
    pub fn express(&self) -> Vec<Instance> {
        let mut out = Instances::default();
        let axiom = self.generator.axiom();
        self.generator
            .subtree(&self.chromosome, 0, &*axiom, &mut out);
        out.0
    }
}
