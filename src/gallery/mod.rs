//! Thumbnail galleries (Lienhard's thesis, chapter 3, Alg. 3.1): what a
//! generator can make, at a glance.
//!
//! [`Gallery::sample`] takes a generator's [default model](crate::ops::default_model)
//! (or one the caller names), finds its [best view](crate::score::best_view),
//! draws samples by [uncontrolled generation](crate::ops::uncontrolled),
//! renders each from that view and computes its view attributes, clusters
//! them by k-means++ (seeded with the default model, weighted by the
//! thesis's clustering weights), takes the member nearest each centre as
//! its representative and sorts the representatives around the default
//! model by their angle in the attributes' first two principal components.
//! [`Gallery::of`] does the same for given models (a final population
//! around its best model). [`Gallery::write`] writes `gallery.png`,
//! `index.html` and `gallery.json`.
//!
//! ```
//! use shapegen::gallery::{Gallery, GalleryOptions};
//! use shapegen::experiment::Experiment;
//!
//! let experiment = Experiment::builtin();
//! let options = GalleryOptions { samples: 12, clusters: 4, thumbnail: 48, ..GalleryOptions::default() };
//! let gallery = Gallery::sample(&experiment, &options, &|_| {})?;
//! assert_eq!(gallery.models.len(), 13); // the default model and 12 samples
//! assert!(gallery.around.len() <= 3);
//! # Ok::<(), shapegen::gallery::GalleryError>(())
//! ```

pub mod cluster;
mod page;

pub use page::GALLERY_FILES;

use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use crate::express::{Generator, Instance, Instances};
use crate::genome::Chromosome;
use crate::graph::Graph;
use crate::ops::OpError;
use crate::score::{
    AttributeWeights, BestView, BoundingSphere, Camera, ModelFitness, RenderMeshes, Renderer,
    Scene, ScoreError, ShapeMeshes, Style, ViewAttributes, ViewSampling, Viewpoint,
    best_view_around, frame_tightly,
};

/// What a gallery needs of a generator: its graph, its shapes' meshes, and
/// the instances of a chromosome's model.
pub trait Models: Sync {
    /// The generator graph (with the limits models are drawn within).
    fn graph(&self) -> &Graph;
    /// The mesh of each shape.
    fn meshes(&self) -> &ShapeMeshes;
    /// The instances the model of `chromosome` emits.
    fn instances(&self, chromosome: &Chromosome) -> Vec<Instance>;
}

/// Every instance `generator` emits for `chromosome`.
fn expressed<G: Generator>(generator: &G, chromosome: &Chromosome) -> Vec<Instance> {
    let mut model = Instances::default();
    generator.express(chromosome, &mut model);
    model.0
}

impl<G: Generator, S: Scene> Models for ModelFitness<G, S> {
    fn graph(&self) -> &Graph {
        self.generator().graph()
    }
    fn meshes(&self) -> &ShapeMeshes {
        ModelFitness::meshes(self)
    }
    fn instances(&self, chromosome: &Chromosome) -> Vec<Instance> {
        expressed(self.generator(), chromosome)
    }
}

/// A generator with the meshes of its shapes.
impl<G: Generator> Models for (G, ShapeMeshes) {
    fn graph(&self) -> &Graph {
        self.0.graph()
    }
    fn meshes(&self) -> &ShapeMeshes {
        &self.1
    }
    fn instances(&self, chromosome: &Chromosome) -> Vec<Instance> {
        expressed(&self.0, chromosome)
    }
}

/// Why a gallery could not be made or written.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum GalleryError {
    /// Unusable options.
    #[error("gallery options: {0}")]
    Options(String),
    /// The generator cannot make a model within its limits.
    #[error("the generator cannot make a model: {0}")]
    Model(#[from] OpError),
    /// Rendering or writing.
    #[error(transparent)]
    Score(#[from] ScoreError),
    /// A sample could not be drawn (or was not a model of the generator).
    #[error("cannot draw a sample: {0}")]
    Sample(String),
    /// No model has anything to look at.
    #[error("none of the {0} models emits any geometry, so there is nothing to show")]
    Empty(usize),
}

/// How a gallery is made.
#[derive(Clone, Debug, PartialEq)]
pub struct GalleryOptions {
    /// Models drawn by uncontrolled generation ([`Gallery::sample`]).
    pub samples: usize,
    /// Clusters; the representatives are those of the clusters without the
    /// centre model (13 for the thesis's 14).
    pub clusters: usize,
    /// Seed of the samples and of k-means++.
    pub seed: u64,
    /// Viewpoints for the best view and the renders attributes come from.
    pub sampling: ViewSampling,
    /// Weights of the best view's score (the thesis's by default).
    pub best_view_weights: AttributeWeights,
    /// Weights of the clustering distance (the thesis's by default).
    pub clustering_weights: AttributeWeights,
    /// Side of a representative's thumbnail in pixels; the centre model's is three times larger.
    pub thumbnail: u32,
    /// How the thumbnails look.
    pub style: Style,
    /// The model in the middle of [`Gallery::sample`]'s gallery; the
    /// generator's default model if `None`.
    pub default_model: Option<Chromosome>,
    /// What a terminal type is (colours and attributes a7, a8).
    pub terminals: Terminals,
    /// Whether thumbnails are zoomed to the model (the attributes always
    /// come from the thesis's camera, fitted to the bounding sphere).
    pub tight_thumbnails: bool,
}

/// What counts as one terminal type: a model's parts are coloured, and
/// attributes a7 and a8 counted, by it.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Terminals {
    /// The emitting node if the generator has one shape (a spaceship of
    /// boxes), else the shape (a tree's trunks and leaves).
    #[default]
    Auto,
    /// The instance's shape.
    Shapes,
    /// The node whose gene emitted the instance.
    Nodes,
}

impl Default for GalleryOptions {
    /// The thesis's: 200 samples, 14 clusters, 32 viewpoints, its weights;
    /// 160-pixel thumbnails (480 for the centre), supersampled 3×.
    fn default() -> Self {
        Self {
            samples: 200,
            clusters: 14,
            seed: 1,
            sampling: ViewSampling::default(),
            best_view_weights: AttributeWeights::BEST_VIEW,
            clustering_weights: AttributeWeights::CLUSTERING,
            thumbnail: 160,
            style: Style::default(),
            default_model: None,
            terminals: Terminals::Auto,
            tight_thumbnails: true,
        }
    }
}

impl GalleryOptions {
    /// The most samples a gallery draws.
    pub const MAX_SAMPLES: usize = 100_000;

    fn check(&self) -> Result<(), GalleryError> {
        let bad = |m: String| Err(GalleryError::Options(m));
        if self.samples > Self::MAX_SAMPLES {
            return bad(format!("at most {} samples", Self::MAX_SAMPLES));
        }
        if self.clusters < 2 || self.clusters > 1000 {
            return bad(format!(
                "clusters must be 2 to 1000 (the centre's and at least one more), got {}",
                self.clusters
            ));
        }
        if !(16..=1024).contains(&self.thumbnail) {
            return bad(format!(
                "thumbnails must be 16 to 1024 pixels across, got {}",
                self.thumbnail
            ));
        }
        if let Some(p) = self.sampling.problem() {
            return bad(p);
        }
        for (what, w) in [
            ("best-view", &self.best_view_weights),
            ("clustering", &self.clustering_weights),
        ] {
            if let Some(p) = w.problem() {
                return bad(format!("{what} weights: {p}"));
            }
        }
        Ok(())
    }
}

/// One model of a gallery.
#[derive(Clone, Debug)]
pub struct GalleryModel {
    /// Its chromosome; `None` for models given as instances
    /// ([`Gallery::of_instances`]).
    pub chromosome: Option<Chromosome>,
    /// Its view attributes from the gallery's view.
    pub attributes: ViewAttributes,
    /// Its cluster.
    pub cluster: usize,
    /// Its picture from the gallery's view (the centre model's three times
    /// larger): for the models the gallery shows, the centre and the
    /// representatives; `None` for the others (not rendered).
    pub thumbnail: Option<image::RgbaImage>,
    /// Instances it emits.
    pub instances: usize,
    /// Its position in the attributes' first two principal components.
    pub projection: [f64; 2],
}

/// One cluster.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct GalleryCluster {
    /// Models in it.
    pub size: usize,
    /// The member nearest its centre (an index into [`Gallery::models`]).
    pub representative: usize,
}

/// A thumbnail gallery: the centre model, the others, their clusters and
/// the representatives in the order they are placed around the centre.
#[derive(Clone, Debug)]
pub struct Gallery {
    /// What the centre model is ("default model", "best model").
    pub centre: String,
    /// The best view of the centre model, from which every model is shown.
    pub best_view: BestView,
    /// Every model; `models[0]` is the centre.
    pub models: Vec<GalleryModel>,
    /// The clusters.
    pub clusters: Vec<GalleryCluster>,
    /// The representatives of the clusters without the centre model,
    /// clockwise from the top.
    pub around: Vec<usize>,
    /// What the user should know about how it was made (e.g. a default
    /// model that emits nothing).
    pub notes: Vec<String>,
}

impl Gallery {
    /// The gallery of a generator: its default model (or
    /// `options.default_model`) in the middle, `options.samples` models by
    /// uncontrolled generation (sample `i` from the random stream
    /// `(seed, i)`, so the result does not depend on the thread count).
    /// `progress` is called with the number of models done so far.
    pub fn sample(
        models: &dyn Models,
        options: &GalleryOptions,
        progress: &(dyn Fn(usize) + Sync),
    ) -> Result<Self, GalleryError> {
        let graph = models.graph();
        Self::sample_with(models, options, progress, &|rng| {
            crate::ops::uncontrolled(graph, rng).map_err(|e| e.to_string())
        })
    }

    /// [`sample`](Self::sample) with the samples drawn by `draw` (e.g. a
    /// learned pdf's sampler) instead of uncontrolled generation; each
    /// sample must be a model of `models`' graph.
    pub fn sample_with(
        models: &dyn Models,
        options: &GalleryOptions,
        progress: &(dyn Fn(usize) + Sync),
        draw: &(dyn Fn(&mut crate::rng::ShapeRng) -> Result<Chromosome, String> + Sync),
    ) -> Result<Self, GalleryError> {
        options.check()?;
        let graph = models.graph();
        let centre = match &options.default_model {
            Some(c) => {
                c.validate(graph).map_err(|e| {
                    GalleryError::Options(format!(
                        "the default model is not of this generator: {e}"
                    ))
                })?;
                c.clone()
            }
            None => crate::ops::default_model(graph)?,
        };
        let samples = (0..options.samples)
            .into_par_iter()
            .map(|i| {
                let mut rng = crate::rng::stream(options.seed, &[0x6761_6c6c, i as u64]);
                let m = draw(&mut rng).map_err(GalleryError::Sample)?;
                m.validate(graph).map_err(|e| {
                    GalleryError::Sample(format!("not a model of the generator: {e}"))
                })?;
                Ok(m)
            })
            .collect::<Result<Vec<_>, GalleryError>>()?;
        Self::build("default model", models, centre, samples, options, progress)
    }

    /// The gallery of given models around `centre` (e.g. a final
    /// population around its best model, `label` "best model").
    pub fn of(
        label: &str,
        models: &dyn Models,
        centre: Chromosome,
        others: Vec<Chromosome>,
        options: &GalleryOptions,
        progress: &(dyn Fn(usize) + Sync),
    ) -> Result<Self, GalleryError> {
        options.check()?;
        Self::build(label, models, centre, others, options, progress)
    }

    /// The gallery of models given as their instances (e.g. design
    /// variations, [`crate::transform::Variety`]): `models[0]` in the
    /// middle, every model coloured by shape with `meshes`.
    pub fn of_instances(
        label: &str,
        meshes: &ShapeMeshes,
        models: Vec<Vec<Instance>>,
        options: &GalleryOptions,
        progress: &(dyn Fn(usize) + Sync),
    ) -> Result<Self, GalleryError> {
        options.check()?;
        if models.is_empty() {
            return Err(GalleryError::Empty(0));
        }
        let meshes = RenderMeshes::new(meshes)?;
        let all = vec![None; models.len()];
        Self::assemble(label, meshes, all, models, options, progress)
    }

    fn build(
        label: &str,
        models: &dyn Models,
        centre: Chromosome,
        others: Vec<Chromosome>,
        options: &GalleryOptions,
        progress: &(dyn Fn(usize) + Sync),
    ) -> Result<Self, GalleryError> {
        let meshes = render_meshes(models, options.terminals)?;
        let mut all = vec![centre];
        all.extend(others);
        let instances: Vec<Vec<Instance>> = all.par_iter().map(|c| models.instances(c)).collect();
        let all = all.into_iter().map(Some).collect();
        Self::assemble(label, meshes, all, instances, options, progress)
    }

    /// The gallery of models with these instances (and chromosomes, where
    /// they have one).
    fn assemble(
        label: &str,
        meshes: RenderMeshes,
        mut all: Vec<Option<Chromosome>>,
        instances: Vec<Vec<Instance>>,
        options: &GalleryOptions,
        progress: &(dyn Fn(usize) + Sync),
    ) -> Result<Self, GalleryError> {
        // Each model's bounding sphere, once.
        let mut instances: Vec<(Vec<Instance>, Option<BoundingSphere>)> = instances
            .into_par_iter()
            .map(|inst| {
                let sphere = meshes.bounding_sphere(&inst);
                (inst, sphere)
            })
            .collect();
        let mut notes = Vec::new();
        let mut label = label.to_string();
        if instances[0].1.is_none() {
            // An empty centre shows nothing: the first model that shows
            // something takes its place.
            let first = (1..all.len())
                .find(|&i| instances[i].1.is_some())
                .ok_or(GalleryError::Empty(all.len()))?;
            notes.push(format!(
                "the {label} emits no geometry, so model {first} is in the middle instead"
            ));
            label = format!("model {first} (the {label} emits nothing)");
            all.swap(0, first);
            instances.swap(0, first);
        }
        let mut renderer = Renderer::new();
        let fast = Style {
            supersample: 1,
            ..options.style.clone()
        };
        let (centre, centre_sphere) = &instances[0];
        let view = best_view_around(
            &mut renderer,
            &meshes,
            centre,
            centre_sphere.as_ref().expect("the centre has geometry"),
            &options.sampling,
            &options.best_view_weights,
            &fast,
        )?;
        let viewpoint = view.viewpoint;
        let fov = options.sampling.fov_y;
        let side = options.sampling.size;
        let done = std::sync::atomic::AtomicUsize::new(0);
        // Every model's attributes from the view, and the camera its
        // thumbnail would be taken with.
        let seen: Vec<(ViewAttributes, Option<Camera>)> = instances
            .par_iter()
            .map_init(Renderer::new, |renderer, (inst, sphere)| {
                let out = match sphere {
                    None => Ok((ViewAttributes::default(), None)),
                    Some(sphere) => (|| {
                        let camera = viewpoint.camera(sphere, fov, (side, side))?;
                        let g = renderer.render(&meshes, inst, &camera);
                        let attributes = ViewAttributes::of(g, &meshes, &fast);
                        let camera = if options.tight_thumbnails {
                            frame_tightly(&camera, g, 0.08)
                        } else {
                            camera
                        };
                        Ok::<_, ScoreError>((attributes, Some(camera)))
                    })(),
                };
                progress(done.fetch_add(1, std::sync::atomic::Ordering::Relaxed) + 1);
                out
            })
            .collect::<Result<_, _>>()?;
        let points: Vec<[f64; 8]> = seen.iter().map(|(a, _)| a.for_clustering()).collect();
        let w = options.clustering_weights.0;
        let clustering = cluster::kmeans_pp(&points, &w, options.clusters, 0, options.seed);
        let projection = cluster::pca_2d(&points, &w);
        let mut clusters: Vec<GalleryCluster> = clustering
            .centers
            .iter()
            .map(|_| GalleryCluster {
                size: 0,
                representative: 0,
            })
            .collect();
        let mut nearest = vec![f64::INFINITY; clusters.len()];
        for (i, &c) in clustering.assignment.iter().enumerate() {
            clusters[c].size += 1;
            let d = cluster::distance(&w, &points[i], &clustering.centers[c]);
            if d < nearest[c] {
                nearest[c] = d;
                clusters[c].representative = i;
            }
        }
        let centre_cluster = clustering.assignment[0];
        let reps: Vec<usize> = clusters
            .iter()
            .enumerate()
            .filter(|(c, k)| *c != centre_cluster && k.size > 0)
            .map(|(_, k)| k.representative)
            .collect();
        let around = cluster::radial_order(&reps, &projection, projection[0]);
        // Thumbnails of what the picture and the page show: the centre
        // (three times larger) and the representatives.
        let shown: Vec<usize> = std::iter::once(0).chain(around.iter().copied()).collect();
        let pictures: Vec<image::RgbaImage> = shown
            .par_iter()
            .map_init(Renderer::new, |renderer, &i| {
                let t = if i == 0 { 3 } else { 1 } * options.thumbnail;
                match seen[i].1 {
                    None => empty_thumbnail(t),
                    Some(mut camera) => {
                        camera.width = t;
                        camera.height = t;
                        renderer.picture(&meshes, &instances[i].0, &camera, &options.style)
                    }
                }
            })
            .collect();
        let mut thumbnails: Vec<Option<image::RgbaImage>> = vec![None; all.len()];
        for (&i, picture) in shown.iter().zip(pictures) {
            thumbnails[i] = Some(picture);
        }
        let models = all
            .into_iter()
            .zip(seen)
            .zip(thumbnails)
            .enumerate()
            .map(
                |(i, ((chromosome, (attributes, _)), thumbnail))| GalleryModel {
                    chromosome,
                    attributes,
                    cluster: clustering.assignment[i],
                    thumbnail,
                    instances: instances[i].0.len(),
                    projection: projection[i],
                },
            )
            .collect();
        Ok(Self {
            centre: label,
            notes,
            best_view: view,
            models,
            clusters,
            around,
        })
    }
}

/// The thumbnail of a model that emits nothing: a faint cross on white.
fn empty_thumbnail(side: u32) -> image::RgbaImage {
    let mut img = image::RgbaImage::from_pixel(side, side, image::Rgba([255; 4]));
    let (lo, hi) = (side / 3, side - side / 3);
    for k in lo..hi {
        for d in 0..2u32 {
            for (x, y) in [
                (k, (k + d).min(side - 1)),
                (side - 1 - k, (k + d).min(side - 1)),
            ] {
                img.put_pixel(x, y, image::Rgba([200, 200, 200, 255]));
            }
        }
    }
    img
}

/// `models`' meshes prepared for rendering, with terminal types as `terminals` says.
pub fn render_meshes(
    models: &dyn Models,
    terminals: Terminals,
) -> Result<RenderMeshes, GalleryError> {
    let meshes = RenderMeshes::new(models.meshes())?;
    let graph = models.graph();
    let by_node = match terminals {
        Terminals::Auto => models.meshes().len() == 1,
        Terminals::Shapes => false,
        Terminals::Nodes => true,
    };
    if !by_node {
        return Ok(meshes);
    }
    // Nodes that emit nothing are unnamed: they take no palette colour.
    Ok(meshes.with_node_terminals(
        (0..graph.node_count() as u16)
            .map(|n| {
                if graph.emits(n) {
                    graph.node(n).name.to_string()
                } else {
                    String::new()
                }
            })
            .collect(),
    ))
}

/// The model of `chromosome` from its best view (thesis weights, 32
/// viewpoints), `size` pixels square, framed tightly and supersampled; a
/// faint cross if it emits nothing.
pub fn best_view_picture(
    models: &dyn Models,
    chromosome: &Chromosome,
    size: u32,
) -> Result<image::RgbaImage, GalleryError> {
    let meshes = render_meshes(models, Terminals::Auto)?;
    best_view_picture_of(&meshes, &models.instances(chromosome), size)
}

/// [`best_view_picture`] of `instances` of `meshes` already prepared.
pub fn best_view_picture_of(
    meshes: &RenderMeshes,
    instances: &[Instance],
    size: u32,
) -> Result<image::RgbaImage, GalleryError> {
    Ok(views_of(meshes, instances, size, 1)?
        .pop()
        .expect("one view"))
}

/// The model of `chromosome` from `views` viewpoints around it (its best
/// view first, then turned about the vertical by equal steps), side by side
/// in one picture, each `size` pixels square: the larger look of a design
/// page.
pub fn views_picture(
    models: &dyn Models,
    chromosome: &Chromosome,
    size: u32,
) -> Result<image::RgbaImage, GalleryError> {
    let meshes = render_meshes(models, Terminals::Auto)?;
    let pictures = views_of(&meshes, &models.instances(chromosome), size, 3)?;
    let mut out = image::RgbaImage::from_pixel(
        size * pictures.len() as u32,
        size,
        image::Rgba([255, 255, 255, 255]),
    );
    for (k, p) in pictures.iter().enumerate() {
        image::imageops::overlay(&mut out, p, i64::from(size) * k as i64, 0);
    }
    Ok(out)
}

/// Pictures from the best view and `count - 1` more turned about the vertical.
fn views_of(
    meshes: &RenderMeshes,
    instances: &[Instance],
    size: u32,
    count: usize,
) -> Result<Vec<image::RgbaImage>, GalleryError> {
    let Some(sphere) = meshes.bounding_sphere(instances) else {
        return Ok(vec![empty_thumbnail(size); count]);
    };
    let mut renderer = Renderer::new();
    let view = best_view_around(
        &mut renderer,
        meshes,
        instances,
        &sphere,
        &ViewSampling::default(),
        &AttributeWeights::BEST_VIEW,
        &Style::fast(),
    )?;
    (0..count)
        .map(|k| {
            let mut viewpoint = view.viewpoint;
            viewpoint.azimuth += std::f64::consts::TAU * k as f64 / count as f64;
            picture_at(&mut renderer, meshes, instances, &sphere, viewpoint, size)
        })
        .collect()
}

/// The best viewpoint of `chromosome`'s model (the thesis's 32 viewpoints
/// and weights), or `None` if it emits nothing.
pub fn best_viewpoint(
    models: &dyn Models,
    chromosome: &Chromosome,
) -> Result<Option<Viewpoint>, GalleryError> {
    let meshes = render_meshes(models, Terminals::Auto)?;
    let instances = models.instances(chromosome);
    let Some(sphere) = meshes.bounding_sphere(&instances) else {
        return Ok(None);
    };
    let view = best_view_around(
        &mut Renderer::new(),
        &meshes,
        &instances,
        &sphere,
        &ViewSampling::default(),
        &AttributeWeights::BEST_VIEW,
        &Style::fast(),
    )?;
    Ok(Some(view.viewpoint))
}

/// The model of `chromosome` from `viewpoint` (e.g. the default model's
/// best view, so that every thumbnail of a page looks from the same side),
/// `size` pixels square, framed tightly and supersampled; a faint cross if
/// it emits nothing.
pub fn picture_from(
    models: &dyn Models,
    chromosome: &Chromosome,
    viewpoint: Viewpoint,
    size: u32,
) -> Result<image::RgbaImage, GalleryError> {
    let meshes = render_meshes(models, Terminals::Auto)?;
    let instances = models.instances(chromosome);
    let Some(sphere) = meshes.bounding_sphere(&instances) else {
        return Ok(empty_thumbnail(size));
    };
    picture_at(
        &mut Renderer::new(),
        &meshes,
        &instances,
        &sphere,
        viewpoint,
        size,
    )
}

/// One picture from `viewpoint`, its camera fitted to `sphere` and then
/// zoomed onto what it covers.
fn picture_at(
    renderer: &mut Renderer,
    meshes: &RenderMeshes,
    instances: &[Instance],
    sphere: &BoundingSphere,
    viewpoint: Viewpoint,
    size: u32,
) -> Result<image::RgbaImage, GalleryError> {
    let sampling = ViewSampling::default();
    let camera = viewpoint.camera(sphere, sampling.fov_y, (sampling.size, sampling.size))?;
    let g = renderer.render(meshes, instances, &camera);
    let mut camera = frame_tightly(&camera, g, 0.06);
    camera.width = size;
    camera.height = size;
    Ok(renderer.picture(meshes, instances, &camera, &Style::default()))
}
