//! Solids: meshes ready for inside tests along lines.
//!
//! A [`Solid`] answers one question: where does a line enter and leave the
//! mesh? Convex meshes (the unit cube, frusta) answer analytically from
//! their face planes; any other mesh collects its crossings through a BVH.
//! Both use `f64` and the same tie rule: a point is inside iff an odd number
//! of crossings lie at or before it along the line (spans are half-open, `[a, b)`).
//!
//! A mesh with holes has no inside by parity; [`Inside::WindingNumber`]
//! decides by the generalized winding number instead (see [`Inside`]).

use std::collections::HashMap;
use std::time::Duration;

use glam::{DVec3, Vec3A};
use obvhs::aabb::Aabb;
use obvhs::bvh2::Bvh2;
use obvhs::ray::Ray;
use obvhs::{Boundable, BvhBuildParams};

use crate::error::ScoreError;
use crate::mesh::Mesh;

/// A mesh prepared for line queries.
#[derive(Clone, Debug)]
pub enum Solid {
    /// A convex mesh, as the intersection of its face half-spaces.
    Convex(Convex),
    /// Any other mesh, queried through a BVH.
    Mesh(MeshSolid),
}

/// How the inside of a mesh is decided.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Inside {
    /// Ray parity (the paper's rule): a point is inside iff the line through
    /// it crosses the surface an odd number of times before it. Exact for
    /// closed meshes; a mesh with holes gets streaks along the rows.
    #[default]
    Parity,
    /// The generalized winding number `w(p) = Σ Ω_t(p) / 4π` over the
    /// triangles' solid angles (Jacobson et al. 2013): inside iff `|w| ≥ ½`.
    /// Equal to parity for closed, consistently oriented meshes; degrades
    /// gracefully for holes and open sheets. Costs one solid angle per
    /// boundary edge per cell of the mesh's bounding box (computed exactly:
    /// signed crossings plus a cone closing the holes), so meant for
    /// targets more than for model shapes.
    WindingNumber,
}

impl Solid {
    /// A solid for `mesh` (named `name` in errors): convex if it is, else
    /// BVH-backed; inside by ray parity.
    pub fn new(name: &str, mesh: &Mesh) -> Result<Self, ScoreError> {
        Self::with_inside(name, mesh, Inside::Parity)
    }

    /// A solid for `mesh` whose inside is decided by `inside`. A closed
    /// convex mesh becomes [`Solid::Convex`] (both rules agree on it).
    pub fn with_inside(name: &str, mesh: &Mesh, inside: Inside) -> Result<Self, ScoreError> {
        check(name, mesh)?;
        if let Some(c) = Convex::from_mesh(mesh) {
            return Ok(Self::Convex(c));
        }
        let mut solid = MeshSolid::new(mesh);
        if inside == Inside::WindingNumber {
            solid.winding = Some(Winding::new(mesh, &mesh.boundary_chain()));
        }
        Ok(Self::Mesh(solid))
    }

    /// Local-space bounds (min, max).
    #[must_use]
    pub fn bounds(&self) -> (DVec3, DVec3) {
        match self {
            Self::Convex(c) => c.bounds,
            Self::Mesh(m) => m.bounds,
        }
    }

    /// Appends to `out` the line parameters `t` (sorted) at which the line
    /// `o + t v`, `t ∈ [0, len]`, crosses the surface; a point is inside iff
    /// an odd number of crossings lie at or before it.
    pub fn crossings(&self, o: DVec3, v: DVec3, len: f64, out: &mut Vec<f64>) {
        match self {
            Self::Convex(c) => {
                if let Some((a, b)) = c.clip(o, v) {
                    let (a, b) = (a.max(0.0), b.min(len));
                    if a < b {
                        out.push(a);
                        out.push(b);
                    }
                }
            }
            Self::Mesh(m) => m.crossings(o, v, len, out),
        }
    }
}

/// Every vertex finite, every index in range, at least one triangle.
pub(crate) fn check(name: &str, mesh: &Mesh) -> Result<(), ScoreError> {
    let bad = |reason: String| ScoreError::Mesh {
        name: name.to_string(),
        reason,
    };
    if mesh.triangles.is_empty() {
        return Err(bad("it has no triangles".into()));
    }
    if let Some(i) = mesh.positions.iter().position(|p| !p.is_finite()) {
        return Err(bad(format!("vertex {i} is not finite")));
    }
    let n = mesh.positions.len() as u32;
    if let Some(t) = mesh
        .triangles
        .iter()
        .position(|t| t.iter().any(|&i| i >= n))
    {
        return Err(bad(format!(
            "triangle {t} indexes a vertex out of range ({} vertices)",
            n
        )));
    }
    Ok(())
}

/// A convex solid: `n · p <= d` for every face plane `(n, d)`.
#[derive(Clone, Debug)]
pub struct Convex {
    planes: Vec<(DVec3, f64)>,
    bounds: (DVec3, DVec3),
}

impl Convex {
    /// The half-space form of `mesh` if it is closed (an empty
    /// [boundary chain](Mesh::boundary_chain)) and convex (every vertex on
    /// the inner side of every face plane, within a relative 1e-6), else
    /// `None`. An open mesh is not the intersection of its face planes: a
    /// box without two opposite faces is a tube.
    #[must_use]
    pub fn from_mesh(mesh: &Mesh) -> Option<Self> {
        if !mesh.boundary_chain().is_empty() {
            return None;
        }
        let pts: Vec<DVec3> = mesh.positions.iter().map(|p| p.as_dvec3()).collect();
        let (lo, hi) = bounds(&pts);
        let eps = 1e-6 * (hi - lo).max_element().max(1e-12);
        let mut planes: Vec<(DVec3, f64)> = Vec::new();
        for t in &mesh.triangles {
            let [a, b, c] = t.map(|i| pts[i as usize]);
            let n = (b - a).cross(c - a);
            if n.length() <= 1e-12 * (hi - lo).max_element().powi(2) {
                continue; // degenerate triangle
            }
            let n = n.normalize();
            let d = n.dot(a);
            if pts.iter().any(|p| n.dot(*p) > d + eps) {
                return None;
            }
            if !planes
                .iter()
                .any(|(m, e)| (*m - n).abs().max_element() < 1e-9 && (e - d).abs() < 1e-9)
            {
                planes.push((n, d));
            }
        }
        (planes.len() >= 4).then_some(Self {
            planes,
            bounds: (lo, hi),
        })
    }

    /// Whether `p` satisfies every face plane (closed).
    #[must_use]
    pub fn contains(&self, p: DVec3) -> bool {
        self.planes.iter().all(|&(n, d)| n.dot(p) <= d)
    }

    /// Distance from `p` to the nearest face plane (0 on the surface).
    #[must_use]
    pub fn plane_distance(&self, p: DVec3) -> f64 {
        self.planes
            .iter()
            .map(|&(n, d)| (n.dot(p) - d).abs())
            .fold(f64::INFINITY, f64::min)
    }

    /// The face planes `(n, d)`: inside iff `n · p <= d` for all.
    #[must_use]
    pub fn planes(&self) -> &[(DVec3, f64)] {
        &self.planes
    }

    /// The parameter interval where `o + t v` is inside, if any.
    #[must_use]
    pub fn clip(&self, o: DVec3, v: DVec3) -> Option<(f64, f64)> {
        let (mut a, mut b) = (f64::NEG_INFINITY, f64::INFINITY);
        for &(n, d) in &self.planes {
            let (no, nv) = (n.dot(o), n.dot(v));
            if nv == 0.0 {
                if no > d {
                    return None;
                }
            } else {
                let t = (d - no) / nv;
                if nv > 0.0 { b = b.min(t) } else { a = a.max(t) }
            }
        }
        (a < b).then_some((a, b))
    }
}

/// One triangle of a [`MeshSolid`], with a slightly padded box for the BVH.
#[derive(Clone, Copy, Debug)]
struct Tri {
    v: [DVec3; 3],
    aabb: Aabb,
}

impl Boundable for Tri {
    fn aabb(&self) -> Aabb {
        self.aabb
    }
}

/// An arbitrary mesh queried through a bottom-level BVH (built once).
#[derive(Clone)]
pub struct MeshSolid {
    /// Triangles in BVH order (so leaves index them directly).
    tris: Vec<Tri>,
    bvh: Bvh2,
    bounds: (DVec3, DVec3),
    boundary_edges: usize,
    /// Present in [`Inside::WindingNumber`] mode.
    winding: Option<Winding>,
}

/// What the winding-number inside test needs beyond the mesh.
///
/// The mesh `M` minus the cone `K` from one apex over its boundary chain is
/// closed (`∂K = ∂M`), so its winding number is the signed count of a
/// line's crossings before the point; hence `w_M = w_{M−K} + w_K`, where
/// `w_K` sums one solid angle per boundary edge. The cone is stored
/// reversed (`−K`), so that `M` and `−K` together are a consistently
/// oriented closed surface for the crossing tie rule.
#[derive(Clone, Debug)]
pub struct Winding {
    /// Triangles `(apex, b, a)` for every boundary edge `a → b`.
    reversed_cone: Vec<[DVec3; 3]>,
}

impl Winding {
    fn new(mesh: &Mesh, chain: &[[u32; 2]]) -> Self {
        let p = |i: u32| mesh.positions[i as usize].as_dvec3();
        let apex = chain.iter().map(|e| p(e[0])).sum::<DVec3>() / chain.len().max(1) as f64;
        Self {
            reversed_cone: chain.iter().map(|&[a, b]| [apex, p(b), p(a)]).collect(),
        }
    }

    /// The reversed cone's triangles, in the mesh's local frame.
    #[must_use]
    pub fn reversed_cone(&self) -> &[[DVec3; 3]] {
        &self.reversed_cone
    }
}

/// The signed solid angle of triangle `t` seen from `p` (Van Oosterom and
/// Strackee 1983): positive when `t` turns counter-clockwise seen from `p`,
/// so a closed outward-facing mesh sums to `4π` inside and `0` outside.
#[must_use]
pub fn solid_angle(t: &[DVec3; 3], p: DVec3) -> f64 {
    let (a, b, c) = (t[0] - p, t[1] - p, t[2] - p);
    let (la, lb, lc) = (a.length(), b.length(), c.length());
    let det = a.dot(b.cross(c));
    let den = la * lb * lc + a.dot(b) * lc + a.dot(c) * lb + b.dot(c) * la;
    2.0 * det.atan2(den)
}

impl std::fmt::Debug for MeshSolid {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("MeshSolid")
            .field("triangles", &self.tris.len())
            .field("bvh_nodes", &self.bvh.nodes.len())
            .field("bounds", &self.bounds)
            .field("boundary_edges", &self.boundary_edges)
            .field(
                "winding_cone",
                &self.winding.as_ref().map(|w| w.reversed_cone.len()),
            )
            .finish()
    }
}

impl MeshSolid {
    /// Builds the BVH of `mesh` (which [`Solid::new`] has checked).
    #[must_use]
    pub fn new(mesh: &Mesh) -> Self {
        let pts: Vec<DVec3> = mesh.positions.iter().map(|p| p.as_dvec3()).collect();
        let bounds = bounds(&pts);
        // Pad boxes so that f32 ray/box tests never drop a triangle the exact test would hit.
        let pad = 1e-5 * (bounds.1 - bounds.0).max_element().max(1e-6);
        let tris: Vec<Tri> = mesh
            .triangles
            .iter()
            .map(|t| {
                let v = t.map(|i| pts[i as usize]);
                let lo = v[0].min(v[1]).min(v[2]) - pad;
                let hi = v[0].max(v[1]).max(v[2]) + pad;
                Tri {
                    v,
                    aabb: Aabb::new(Vec3A::from(lo.as_vec3()), Vec3A::from(hi.as_vec3())),
                }
            })
            .collect();
        let mut build_time = Duration::ZERO;
        let bvh = obvhs::bvh2::builder::build_bvh2(
            &tris,
            BvhBuildParams::medium_build(),
            &mut build_time,
        );
        let tris = bvh
            .primitive_indices
            .iter()
            .map(|&i| tris[i as usize])
            .collect();
        Self {
            tris,
            bvh,
            bounds,
            boundary_edges: boundary_edges(mesh),
            winding: None,
        }
    }

    /// The winding-number data, in [`Inside::WindingNumber`] mode.
    #[must_use]
    pub fn winding(&self) -> Option<&Winding> {
        self.winding.as_ref()
    }

    /// The triangles, in the local frame.
    pub fn triangles(&self) -> impl ExactSizeIterator<Item = &[DVec3; 3]> {
        self.tris.iter().map(|t| &t.v)
    }

    /// Appends `(t, s)` for every crossing of the line `o + t v`,
    /// `t ∈ [0, len]`, with the mesh and (in winding-number mode) its
    /// reversed boundary cone, sorted by `t`; `s = ±1` is the sign of `v`
    /// along the crossed triangle's normal (+1 leaving an outward surface).
    pub fn signed_crossings(&self, o: DVec3, v: DVec3, len: f64, out: &mut Vec<(f64, f64)>) {
        let start = out.len();
        let sign = |t: &[DVec3; 3]| v.dot((t[1] - t[0]).cross(t[2] - t[0])).signum();
        let ray = self.ray(o, v, len);
        self.bvh.ray_traverse_anyhit(ray, |_, id| {
            let tri = &self.tris[id].v;
            if let Some(t) = cross(tri, o, v) {
                out.push((t, sign(tri)));
            }
        });
        if let Some(w) = &self.winding {
            for tri in &w.reversed_cone {
                if let Some(t) = cross(tri, o, v) {
                    out.push((t, sign(tri)));
                }
            }
        }
        out[start..].sort_unstable_by(|a, b| a.0.total_cmp(&b.0));
    }

    fn ray(&self, o: DVec3, v: DVec3, len: f64) -> Ray {
        let margin = 1e-3 * len.max(1.0);
        Ray::new(
            Vec3A::from(o.as_vec3()),
            Vec3A::from(v.as_vec3()),
            -margin as f32,
            (len + margin) as f32,
        )
    }

    /// Edges used by exactly one triangle after welding vertices by position:
    /// 0 for a watertight mesh; parity inside tests are unreliable otherwise.
    #[must_use]
    pub fn boundary_edges(&self) -> usize {
        self.boundary_edges
    }

    /// See [`Solid::crossings`].
    pub fn crossings(&self, o: DVec3, v: DVec3, len: f64, out: &mut Vec<f64>) {
        let start = out.len();
        let ray = self.ray(o, v, len);
        self.bvh.ray_traverse_anyhit(ray, |_, id| {
            if let Some(t) = cross(&self.tris[id].v, o, v) {
                out.push(t);
            }
        });
        out[start..].sort_unstable_by(f64::total_cmp);
    }

    /// The same crossings by testing every triangle (the reference for tests).
    pub fn crossings_brute_force(&self, o: DVec3, v: DVec3, out: &mut Vec<f64>) {
        let start = out.len();
        out.extend(self.tris.iter().filter_map(|t| cross(&t.v, o, v)));
        out[start..].sort_unstable_by(f64::total_cmp);
    }
}

/// Where the line `o + t v` crosses triangle `tri`, if it does.
///
/// The sides of the three edges are Plücker signs computed with a canonical
/// order of each edge's endpoints, so the two triangles sharing an edge see
/// exactly opposite signs, and a line through an edge or vertex is counted
/// by exactly one of the triangles around it (a consistent tie rule).
#[inline]
pub(crate) fn cross(tri: &[DVec3; 3], o: DVec3, v: DVec3) -> Option<f64> {
    let side = |p: DVec3, q: DVec3| -> bool {
        let canonical = |a: DVec3, b: DVec3| v.dot((a - o).cross(b - o)) >= 0.0;
        if (p.x, p.y, p.z) < (q.x, q.y, q.z) {
            canonical(p, q)
        } else {
            !canonical(q, p)
        }
    };
    let [a, b, c] = *tri;
    let s = side(a, b);
    if side(b, c) != s || side(c, a) != s {
        return None;
    }
    let n = (b - a).cross(c - a);
    let vn = v.dot(n);
    if vn == 0.0 {
        return None; // the line lies in the triangle's plane
    }
    Some((a - o).dot(n) / vn)
}

fn bounds(pts: &[DVec3]) -> (DVec3, DVec3) {
    pts.iter()
        .fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), p| {
            (lo.min(*p), hi.max(*p))
        })
}

/// Edges with exactly one incident triangle, vertices welded by exact position.
fn boundary_edges(mesh: &Mesh) -> usize {
    let weld = mesh.welded();
    let mut edges: HashMap<(u32, u32), u32> = HashMap::new();
    for t in &mesh.triangles {
        for (a, b) in [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])] {
            let (a, b) = (weld[a as usize], weld[b as usize]);
            if a != b {
                *edges.entry((a.min(b), a.max(b))).or_default() += 1;
            }
        }
    }
    edges.values().filter(|&&n| n == 1).count()
}
