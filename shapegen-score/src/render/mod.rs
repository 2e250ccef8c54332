//! A z-buffered CPU renderer of expressed models: the pictures a user looks
//! at and the G-buffers that view attributes are computed from (Lienhard's
//! thesis, chapter 3).
//!
//! Each triangle is filled with the silhouette rasterizer's own row filling
//! and centre rule (`raster::fill_triangle`, clipped to the depth range like
//! the rasterizer's triangle path), so the set of covered pixels is exactly
//! the [`Rasterizer`](crate::Rasterizer)'s coverage of the same instances
//! and camera. A pixel keeps the nearest triangle at its centre: the depth
//! is the exact intersection of the pixel's centre ray with the triangle's
//! plane (one division a pixel), the face's normal, area and terminal type
//! come from a per-face table ([`Face`]).
//!
//! Faces are skipped where that provably changes nothing: a face seen from
//! a side where a ray from outside the mesh's hull cannot meet it first,
//! away from the mesh's holes (back-face culling for meshes that bound
//! solids; decided per face by winding numbers for self-intersecting ones;
//! `back_faces` holds the proof and the exact checks).
//!
//! - [`RenderMeshes`]: a generator's shape meshes prepared once;
//! - [`Renderer`]: working memory; [`Renderer::render`] fills a [`GBuffer`],
//!   [`Renderer::picture`] shades an image (with supersampling);
//! - [`Style`]: three-point [`Lights`], a [`Palette`] per terminal type,
//!   flat or Lambert [`Shading`], white or transparent [`Background`];
//! - [`BoundingSphere`] and [`fit_camera`]: the camera at the distance where
//!   the model's bounding sphere fits the frustum tightly.

mod back_faces;
mod fit;
mod gbuffer;
mod shade;

use glam::{DVec2, DVec3};
use shapegen_core::express::Instance;

use fit::farthest_squared;
pub use fit::{BoundingSphere, fit_camera, fit_orthographic, frame_tightly};
pub use gbuffer::{Face, GBuffer};
pub use shade::{Background, Light, Lights, Palette, Shading, Style};
pub(crate) use shade::{face_colour, luma};

use crate::camera::Camera;
use crate::error::ScoreError;
use crate::mesh::corners;
use crate::raster::{Edge, View, clip_depth, fill_convex, fill_triangle};
use crate::shapes::ShapeMeshes;
use back_faces::FirstHit;

/// One shape's mesh prepared for rendering.
#[derive(Clone, Debug)]
struct RenderMesh {
    positions: Vec<DVec3>,
    triangles: Vec<[u32; 3]>,
    /// Present if some of the mesh's faces can be skipped (see `back_faces`).
    closure: Option<back_faces::Closure>,
    /// The vertices farthest along some of [`HULL_DIRECTIONS`] directions:
    /// vertices of the convex hull, which bounding spheres are fitted to
    /// (an affine placement keeps them hull vertices).
    hull: Vec<DVec3>,
    /// A sphere around every vertex, local: centre and radius.
    around: (DVec3, f64),
}

/// How many directions (spread over the sphere) pick a mesh's hull
/// vertices for fitting bounding spheres ([`RenderMesh::hull`]).
const HULL_DIRECTIONS: usize = 256;

/// The vertices of `positions` farthest along each of [`HULL_DIRECTIONS`]
/// directions on a Fibonacci sphere, without repeats, in index order.
fn hull_vertices(positions: &[DVec3]) -> Vec<DVec3> {
    let mut chosen = vec![false; positions.len()];
    let golden = std::f64::consts::PI * (3.0 - 5f64.sqrt());
    for k in 0..HULL_DIRECTIONS {
        let y = 1.0 - 2.0 * (k as f64 + 0.5) / HULL_DIRECTIONS as f64;
        let r = (1.0 - y * y).sqrt();
        let phi = golden * k as f64;
        let d = DVec3::new(r * phi.cos(), y, r * phi.sin());
        let best = positions
            .iter()
            .enumerate()
            .max_by(|a, b| a.1.dot(d).total_cmp(&b.1.dot(d)))
            .map(|(i, _)| i);
        if let Some(i) = best {
            chosen[i] = true;
        }
    }
    positions
        .iter()
        .zip(chosen)
        .filter_map(|(p, c)| c.then_some(*p))
        .collect()
}

/// A sphere around `positions` (all finite): its box's centre and the
/// largest distance from it.
fn local_sphere(positions: &[DVec3]) -> (DVec3, f64) {
    let (lo, hi) = positions
        .iter()
        .fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), p| {
            (lo.min(*p), hi.max(*p))
        });
    let c = 0.5 * (lo + hi);
    (c, farthest_squared(positions.iter().copied(), c).sqrt())
}

/// The sum of the squares of `m`'s entries: its squared Frobenius norm,
/// which bounds the square of its largest singular value.
fn frobenius_squared(m: &glam::DMat3) -> f64 {
    m.x_axis.length_squared() + m.y_axis.length_squared() + m.z_axis.length_squared()
}

/// A generator's shape meshes prepared for rendering (checked and welded
/// once), with the shapes' names for the palette.
#[derive(Clone, Debug)]
pub struct RenderMeshes {
    meshes: Vec<RenderMesh>,
    /// The terminal types' names.
    names: Vec<String>,
    /// Whether an instance's terminal type is its emitting node (else its shape).
    by_node: bool,
}

impl RenderMeshes {
    /// Prepares every mesh of `shapes` (fails on a mesh the scorers would
    /// refuse: no triangles, indices out of range, non-finite vertices).
    pub fn new(shapes: &ShapeMeshes) -> Result<Self, ScoreError> {
        let mut meshes = Vec::with_capacity(shapes.len());
        let mut names = Vec::with_capacity(shapes.len());
        for id in 0..shapes.len() as u16 {
            let (name, mesh) = (shapes.name(id), shapes.mesh(id));
            crate::solid::check(name, mesh)?;
            let mesh = mesh.with_welded_vertices();
            let positions: Vec<DVec3> = mesh.positions.iter().map(|p| p.as_dvec3()).collect();
            let closure = back_faces::closure(&positions, &mesh.triangles);
            meshes.push(RenderMesh {
                hull: hull_vertices(&positions),
                around: local_sphere(&positions),
                positions,
                triangles: mesh.triangles,
                closure,
            });
            names.push(name.to_string());
        }
        Ok(Self {
            meshes,
            names,
            by_node: false,
        })
    }

    /// Takes an instance's terminal type to be the node that emitted it
    /// ([`Instance::node`]) instead of its shape: `node_names` are the
    /// generator's nodes, by id (for the palette). A generator with one
    /// shape (a spaceship of boxes) shows its parts this way. Give nodes
    /// that emit nothing an empty name: they then take no palette colour.
    #[must_use]
    pub fn with_node_terminals(mut self, node_names: Vec<String>) -> Self {
        if !node_names.is_empty() {
            self.names = node_names;
            self.by_node = true;
        }
        self
    }

    /// The terminal type of `inst`.
    #[inline]
    fn terminal(&self, inst: &Instance) -> u16 {
        let t = if self.by_node { inst.node } else { inst.shape };
        t.min(self.names.len().saturating_sub(1) as u16)
    }

    /// The share of shape `id`'s faces that renders may skip when they are
    /// seen from the side where they cannot be the nearest surface (0 if
    /// none may: a mesh that is not a consistently wound surface once its
    /// holes are capped). All of them for a mesh that bounds solids (then
    /// this is back-face culling); fewer for a self-intersecting mesh,
    /// whose faces cut by others are always drawn. See `back_faces`.
    #[must_use]
    pub fn skippable_faces(&self, id: u16) -> f64 {
        self.meshes
            .get(id as usize)
            .and_then(|m| m.closure.as_ref())
            .map_or(0.0, |c| {
                let n = c
                    .first_hit
                    .iter()
                    .filter(|&&f| f != FirstHit::Either)
                    .count();
                n as f64 / c.first_hit.len().max(1) as f64
            })
    }

    /// Number of shapes.
    #[must_use]
    pub fn len(&self) -> usize {
        self.meshes.len()
    }

    /// Number of terminal types (shapes, or nodes after
    /// [`with_node_terminals`](Self::with_node_terminals)).
    #[must_use]
    pub fn terminal_types(&self) -> usize {
        self.names.len()
    }

    /// Whether there are no shapes.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.meshes.is_empty()
    }

    /// The terminal types' names, by id (the shapes', or the nodes').
    #[must_use]
    pub fn names(&self) -> &[String] {
        &self.names
    }

    /// The bounding sphere of `instances` (every vertex placed), or `None`
    /// if there is nothing finite to bound.
    ///
    /// The centre is fitted to the placed hull vertices of each mesh
    /// ([`BoundingSphere::of`]'s construction on a few vertices a mesh
    /// instead of all); the radius then holds every vertex, though only
    /// instances that may reach beyond the hull vertices' sphere are placed
    /// vertex by vertex.
    #[must_use]
    pub fn bounding_sphere(&self, instances: &[Instance]) -> Option<BoundingSphere> {
        let placed = |inst: &Instance| {
            let mesh = self.meshes.get(inst.shape as usize)?;
            Some((mesh, crate::voxelize::to_f64(&inst.transform)))
        };
        let mut points = Vec::new();
        for (mesh, m) in instances.iter().filter_map(placed) {
            // The directions that picked the hull vertices are spread evenly
            // in the mesh's frame; a stretched instance squeezes them
            // together, so it gives every vertex instead.
            let frobenius2 = frobenius_squared(&m.matrix3);
            let det = m.matrix3.determinant().abs();
            let even = frobenius2 <= 3.0 * 1.1 * det.powf(2.0 / 3.0);
            let vertices = if even { &mesh.hull } else { &mesh.positions };
            points.extend(
                vertices
                    .iter()
                    .map(|p| m.transform_point3(*p))
                    .filter(|p| p.is_finite()),
            );
        }
        let center = BoundingSphere::fit_center(&points)?;
        let mut r2 = farthest_squared(points.iter().copied(), center);
        for (mesh, m) in instances.iter().filter_map(placed) {
            // The placed local sphere holds the instance: its centre moves
            // with `m`, its radius grows by at most `m`'s largest singular
            // value, which the Frobenius norm bounds.
            let (c, r) = mesh.around;
            let stretch = frobenius_squared(&m.matrix3).sqrt();
            let reach = m.transform_point3(c).distance(center) + r * stretch;
            if reach.is_finite() && reach * reach * (1.0 + 1e-9) <= r2 {
                continue;
            }
            let placed = mesh.positions.iter().map(|p| m.transform_point3(*p));
            r2 = r2.max(farthest_squared(placed.filter(|p| p.is_finite()), center));
        }
        Some(BoundingSphere::with_radius(center, r2.sqrt()))
    }
}

/// Reusable working memory for rendering.
#[derive(Clone, Debug, Default)]
pub struct Renderer {
    gbuffer: GBuffer,
    view: Vec<DVec3>,
    pixels: Vec<DVec2>,
    clip: Vec<DVec3>,
    clip2: Vec<DVec3>,
    hull: Vec<DVec2>,
    edges: Vec<Edge>,
    /// The pixel boxes where the current instance's holes are seen.
    holes: Vec<(DVec2, DVec2)>,
    /// The current instance's triangles seen through its holes, drawn last.
    later: Vec<u32>,
    /// Whether every face is drawn (else faces are skipped where that is
    /// exact, the default).
    all_faces: bool,
    /// Instances by increasing depth of their origin.
    order: Vec<(f64, u32)>,
}

impl Renderer {
    /// Empty working memory.
    #[must_use]
    pub fn new() -> Self {
        Self::default()
    }

    /// Draws every face, even those proven not to change the G-buffer when
    /// skipped (see [`RenderMeshes::skippable_faces`]): for checking that
    /// proof; slower.
    #[must_use]
    pub fn drawing_all_faces(mut self) -> Self {
        self.all_faces = true;
        self
    }

    /// Renders `instances` of `meshes` seen by `camera` into the G-buffer
    /// (returned; valid until the next render). Instances of unknown shapes
    /// and instances with a non-finite vertex are skipped, as the scorers do.
    pub fn render(
        &mut self,
        meshes: &RenderMeshes,
        instances: &[Instance],
        camera: &Camera,
    ) -> &GBuffer {
        self.gbuffer.reset(camera, meshes.terminal_types());
        let view = View::new(camera);
        // Front to back, so that instances wholly behind what is already
        // drawn are found and skipped (see `draw`).
        self.order.clear();
        self.order
            .extend(instances.iter().enumerate().map(|(i, inst)| {
                let z = camera
                    .forward
                    .dot(inst.transform.translation.as_dvec3() - camera.eye);
                (if z.is_finite() { z } else { f64::INFINITY }, i as u32)
            }));
        self.order
            .sort_unstable_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        for k in 0..self.order.len() {
            let inst = &instances[self.order[k].1 as usize];
            if let Some(mesh) = meshes.meshes.get(inst.shape as usize) {
                self.draw(&view, mesh, inst, meshes.terminal(inst));
            }
        }
        self.gbuffer.finish();
        &self.gbuffer
    }

    /// The G-buffer of the last render.
    #[must_use]
    pub fn gbuffer(&self) -> &GBuffer {
        &self.gbuffer
    }

    /// A shaded picture of `instances` seen by `camera` (rendered at
    /// `style.supersample`² samples a pixel and averaged; fewer for
    /// pictures over 4096 / `supersample` pixels a side).
    pub fn picture(
        &mut self,
        meshes: &RenderMeshes,
        instances: &[Instance],
        camera: &Camera,
        style: &Style,
    ) -> image::RgbaImage {
        // Supersampled renders stay within 4096 pixels a side (200 MB of
        // G-buffer): larger pictures get fewer samples.
        let side = camera.width.max(camera.height).max(1);
        let s = style.supersample.clamp(1, 8).min((4096 / side).max(1));
        let big = |side: u32| (side * s).min(Camera::MAX_SIDE);
        let mut fine = *camera;
        fine.width = big(camera.width);
        fine.height = big(camera.height);
        let palette = style.palette.for_names(meshes.names());
        let gbuffer = self.render(meshes, instances, &fine);
        shade::picture(gbuffer, style, &palette, (camera.width, camera.height))
    }

    fn draw(&mut self, view: &View, mesh: &RenderMesh, inst: &Instance, terminal: u16) {
        let camera = *view.camera();
        let m = view.affine() * crate::voxelize::to_f64(&inst.transform);
        let proj = view.projector();
        let (near, far) = (camera.near, camera.far);
        let in_range = |v: &DVec3| v.z >= near && v.z <= far;
        // Back faces may be skipped only if every ray starts outside the
        // mesh's hull: all of it strictly beyond the near plane.
        let mut beyond_near = true;
        let n = mesh.positions.len();
        self.view.clear();
        self.pixels.clear();
        // One pass: placed vertices, their pixels, and what the occlusion
        // test below needs (whether all are in the depth range, their
        // pixel bounds and nearest depth).
        let (mut finite, mut all_in) = (true, true);
        let (mut lo, mut hi) = (DVec2::INFINITY, DVec2::NEG_INFINITY);
        let mut zmin = f64::INFINITY;
        for p in &mesh.positions {
            let v = m.transform_point3(*p);
            let px = proj.to_pixel(v);
            finite &= v.is_finite();
            all_in &= in_range(&v);
            beyond_near &= v.z > near;
            lo = lo.min(px);
            hi = hi.max(px);
            zmin = zmin.min(v.z);
            self.view.push(v);
            self.pixels.push(px);
        }
        if !finite || n == 0 {
            return;
        }
        let (cx, cy, sx, sy, perspective) = proj.constants();
        // Occlusion: an instance wholly in the depth range whose every
        // pixel is already covered by something nearer than its nearest
        // vertex can add nothing (a pixel only takes a strictly nearer face).
        let mut bounds = None;
        if all_in {
            let b = self.gbuffer.pixel_box(lo, hi);
            if self.gbuffer.hidden(b, key_of(zmin, perspective)) {
                return;
            }
            bounds = Some(b);
        }
        // Whether faces may be skipped, and the sign that turns a view-space
        // `(b − a) × (c − a)` to the model's (−1 for mirrored instances).
        let det = m.matrix3.determinant();
        let turn = if det.is_finite() && det != 0.0 {
            det.signum()
        } else {
            0.0
        };
        let first_hit = match &mesh.closure {
            Some(closure) if all_in && beyond_near && turn != 0.0 && !self.all_faces => {
                self.holes.clear();
                for hole in &closure.holes {
                    let (mut lo, mut hi) = (DVec2::INFINITY, DVec2::NEG_INFINITY);
                    for p in hole {
                        let px = proj.to_pixel(m.transform_point3(*p));
                        lo = lo.min(px);
                        hi = hi.max(px);
                    }
                    // A pixel of margin for the rounding of the crossings.
                    self.holes.push((lo - 1.0, hi + 1.0));
                }
                Some(&closure.first_hit[..])
            }
            _ => None,
        };
        let ctx = Draw {
            camera,
            constants: (cx, cy, sx, sy),
            perspective,
            terminal,
            bounds,
            turn,
            first_hit,
        };
        // Faces that may be met first are drawn first: they hide the others
        // seen through holes, which the occlusion tests then may skip.
        let mut later = std::mem::take(&mut self.later);
        later.clear();
        for (i, t) in mesh.triangles.iter().enumerate() {
            match self.facing(&ctx, i, *t) {
                Facing::First => self.triangle(&ctx, *t),
                Facing::Later => later.push(i as u32),
                Facing::Hidden => {}
            }
        }
        for &i in &later {
            self.triangle(&ctx, mesh.triangles[i as usize]);
        }
        self.later = later;
        if let Some(b) = bounds {
            self.gbuffer.update_tiles(b);
        } else {
            self.gbuffer.forget_tiles();
        }
    }

    /// Whether triangle `i` (`t`) of the instance being drawn may be the
    /// first surface met, or is to be drawn after those (seen through a
    /// hole), or can be skipped.
    fn facing(&self, ctx: &Draw, i: usize, t: [u32; 3]) -> Facing {
        let Some(first_hit) = ctx.first_hit else {
            return Facing::First;
        };
        let side = first_hit[i];
        if side == FirstHit::Either {
            return Facing::First;
        }
        // The eye's side of the face, in the model's terms.
        let [a, b, c] = corners(&self.view, t);
        let raw = (b - a).cross(c - a) * ctx.turn;
        let (toward, scale2) = if ctx.perspective {
            (-raw.dot(a), a.length_squared())
        } else {
            (-raw.z, 1.0)
        };
        // With a margin of 10⁻⁹·|raw|·scale (compared squared, without
        // roots): a face seen nearly edge on may be met first.
        if toward * toward <= 1e-18 * raw.length_squared() * scale2 {
            return Facing::First;
        }
        let plus = toward > 0.0;
        if (side == FirstHit::Plus && plus) || (side == FirstHit::Minus && !plus) {
            return Facing::First;
        }
        // Away from every hole, this face is never the nearest surface
        // (see `back_faces`).
        let [pa, pb, pc] = corners(&self.pixels, t);
        let (lo, hi) = (pa.min(pb).min(pc), pa.max(pb).max(pc));
        let seen_through = self
            .holes
            .iter()
            .any(|(hlo, hhi)| lo.x <= hhi.x && hi.x >= hlo.x && lo.y <= hhi.y && hi.y >= hlo.y);
        if seen_through {
            Facing::Later
        } else {
            Facing::Hidden
        }
    }

    /// Draws triangle `t` of the instance being drawn, unless the occlusion
    /// tests show that it is hidden.
    fn triangle(&mut self, ctx: &Draw, t: [u32; 3]) {
        let camera = &ctx.camera;
        let (near, far, perspective) = (camera.near, camera.far, ctx.perspective);
        let in_range = |v: &DVec3| v.z >= near && v.z <= far;
        let [a, b, c] = corners(&self.view, t);
        if ctx.bounds.is_some() {
            // The instance is wholly in the depth range, so the triangle
            // covers only pixels whose centres its vertices' box holds
            // (none: nothing to draw), with keys at least its nearest
            // vertex's. It is hidden if all those pixels already hold
            // nearer keys (the tiles are as they were before this instance:
            // farthest keys only shrink as faces are drawn, so older tiles
            // are conservative).
            let [pa, pb, pc] = corners(&self.pixels, t);
            let Some(centres) = self
                .gbuffer
                .centres_in(pa.min(pb).min(pc), pa.max(pb).max(pc))
            else {
                return;
            };
            let key = key_of(a.z.min(b.z).min(c.z), perspective);
            if self.gbuffer.hidden_triangle(centres, key) {
                return;
            }
        }
        // The face and its depth plane are made on its first span (many
        // triangles cover no pixel centre); its pixels are counted here and
        // added to the face once.
        let mut made: Option<(u32, Plane)> = None;
        let mut drawn = 0;
        let gbuffer = &mut self.gbuffer;
        let mut f = |s: crate::PixelSpan| {
            let (index, plane) = made.get_or_insert_with(|| {
                let raw = (b - a).cross(c - a);
                let plane = Plane::new(raw, [a, b, c], ctx.constants, perspective, near, far);
                (
                    gbuffer.push_face(Face::new(raw, [a, b, c], ctx.terminal, perspective)),
                    plane,
                )
            });
            gbuffer.span(s, *index, plane);
            drawn += s.c1 - s.c0;
        };
        if in_range(&a) && in_range(&b) && in_range(&c) {
            let px = corners(&self.pixels, t);
            fill_triangle(camera, px, &mut f);
        } else {
            self.clip.clear();
            self.clip.extend([a, b, c]);
            clip_depth(&mut self.clip, &mut self.clip2, near, far);
            if self.clip.len() < 3 {
                return;
            }
            let proj = camera.projector();
            self.hull.clear();
            self.hull
                .extend(self.clip.iter().map(|v| proj.to_pixel(*v)));
            fill_convex(camera, &self.hull, &mut self.edges, &mut f);
        }
        if let Some((index, _)) = made {
            self.gbuffer.add_drawn(index, drawn);
        }
    }
}

/// What `Renderer::triangle` needs of the instance being drawn.
struct Draw<'a> {
    camera: Camera,
    constants: (f64, f64, f64, f64),
    perspective: bool,
    terminal: u16,
    /// The instance's pixel box, if it is wholly in the depth range (then
    /// its triangles get occlusion tests).
    bounds: Option<gbuffer::PixelBox>,
    /// `det` of the instance's placement in view space: `−1` if mirrored.
    turn: f64,
    /// Per face, from where it may be met first, if faces may be skipped.
    first_hit: Option<&'a [FirstHit]>,
}

/// Whether a face is drawn (see `Renderer::facing`).
enum Facing {
    /// It may be the first surface met: drawn at once.
    First,
    /// Seen through a hole: drawn after the others.
    Later,
    /// Never the nearest surface: skipped.
    Hidden,
}

/// A triangle's depth *key* at pixel centres, linear in the pixel
/// coordinates: `key = a + b·x + c·y`, smaller is nearer. The key is
/// `−1/Z` for a perspective camera (`1/Z` is affine in screen space) and
/// `Z` for an orthographic one, clamped to the keys of `near` and `far`.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Plane {
    a: f64,
    b: f64,
    c: f64,
    lo: f64,
    hi: f64,
}

/// The depth key of depth `z` (see [`Plane`]).
#[inline]
pub(crate) fn key_of(z: f64, perspective: bool) -> f64 {
    if perspective { -1.0 / z } else { z }
}

/// The depth of key `k` (see [`Plane`]).
#[inline]
pub(crate) fn depth_of(k: f64, perspective: bool) -> f64 {
    if perspective { -1.0 / k } else { k }
}

impl Plane {
    fn new(
        n: DVec3,
        v: [DVec3; 3],
        (cx, cy, sx, sy): (f64, f64, f64, f64),
        perspective: bool,
        near: f64,
        far: f64,
    ) -> Self {
        let d = n.dot(v[0]);
        let (lo, hi) = (key_of(near, perspective), key_of(far, perspective));
        // The pixel centre (x, y) is the view point (X, Y) with
        // X = (x − cx)/sx·w, Y = −(y − cy)/sy·w, where w = Z (perspective) or 1.
        let (bx, by) = (n.x / sx, -n.y / sy);
        let a0 = -bx * cx - by * cy;
        let (a, b, c) = if perspective {
            // n·(X, Y, Z) = d with (X, Y) = Z·(dir): 1/Z = (n·dir)/d.
            let r = -1.0 / d;
            ((a0 + n.z) * r, bx * r, by * r)
        } else {
            // Z = (d − n.x·X − n.y·Y) / n.z.
            let r = 1.0 / n.z;
            ((d - a0) * r, -bx * r, -by * r)
        };
        if a.is_finite() && b.is_finite() && c.is_finite() {
            return Self { a, b, c, lo, hi };
        }
        // Seen edge on (or through the eye): the nearest vertex's depth.
        let z = v[0].z.min(v[1].z).min(v[2].z).clamp(near, far);
        Self {
            a: key_of(z, perspective),
            b: 0.0,
            c: 0.0,
            lo,
            hi,
        }
    }

    /// The row's key at `x = 0` and its slope along x.
    #[inline(always)]
    pub(crate) fn row(&self, y: f64) -> (f64, f64) {
        (self.a + self.c * y, self.b)
    }

    /// A key clamped to the depth range, with plain comparisons (the
    /// coefficients are finite, so a key is never NaN; `f64::max` would
    /// spend instructions on it).
    #[inline(always)]
    pub(crate) fn clamp(&self, k: f64) -> f64 {
        let k = if k < self.lo { self.lo } else { k };
        if k > self.hi { self.hi } else { k }
    }
}
