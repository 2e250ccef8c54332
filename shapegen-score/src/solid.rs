//! Solids: meshes ready for inside tests along the lattice's rows.
//!
//! A [`Solid`] answers one question: where does a row line enter and leave
//! the mesh? Convex meshes (the unit cube, frusta) answer analytically from
//! their face planes; any other mesh is a [`MeshSolid`], whose placed
//! triangles ([`RowTri`]) are rasterized onto the rows they cross (see
//! [`voxelize`](crate::voxelize)). Both use `f64` and the same tie rule: a
//! point is inside iff an odd number of crossings lie at or before it along
//! the row (spans are half-open, `[a, b)`).
//!
//! A mesh with holes has no inside by parity; [`Inside::WindingNumber`]
//! decides by the generalized winding number instead (see [`Inside`]).

use std::collections::HashMap;

use glam::DVec3;

use crate::error::ScoreError;
use crate::mesh::{Mesh, corners};

/// A mesh prepared for line queries.
#[derive(Clone, Debug)]
pub enum Solid {
    /// A convex mesh, as the intersection of its face half-spaces.
    Convex(Convex),
    /// Any other mesh, rasterized triangle by triangle onto the rows.
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
    /// A solid for `mesh` (named `name` in errors): convex if it is, else a
    /// [`MeshSolid`]; inside by ray parity.
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
        let pts: Vec<DVec3> = mesh.positions.iter().map(|p| p.as_dvec3()).collect();
        let (lo, hi) = bounds(&pts);
        let eps = 1e-6 * (hi - lo).max_element().max(1e-12);
        let mut planes: Vec<(DVec3, f64)> = Vec::new();
        for t in &mesh.triangles {
            let [a, b, c] = corners(&pts, *t);
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
        // Closedness last: most meshes that are not convex fail above, early.
        (planes.len() >= 4 && mesh.boundary_chain().is_empty()).then_some(Self {
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

/// An arbitrary mesh: its triangles, placed and rasterized onto the lattice
/// rows of each instance (no acceleration structure to build or walk).
#[derive(Clone, Debug)]
pub struct MeshSolid {
    /// Distinct vertex positions (welded by exact position), local frame.
    positions: Vec<DVec3>,
    /// Triangles indexing `positions`.
    triangles: Vec<[u32; 3]>,
    /// The distinct edges `[i, j]` (`i < j`), and per triangle its three
    /// edges `a → b`, `b → c`, `c → a` as `2 · edge + reversed` (reversed:
    /// the triangle runs `j → i`): placing a mesh computes each edge's
    /// function once for the two triangles that share it.
    edges: Vec<[u32; 2]>,
    triangle_edges: Vec<[u32; 3]>,
    bounds: (DVec3, DVec3),
    boundary_edges: usize,
    /// Present in [`Inside::WindingNumber`] mode.
    winding: Option<Winding>,
}

/// What the winding-number inside test needs beyond the mesh.
///
/// The mesh `M` minus a cone `K` over its boundary chain is closed
/// (`∂K = ∂M`), so its winding number is the signed count of a line's
/// crossings before the point; hence `w_M = w_{M−K} + w_K`, where `w_K` sums
/// one solid angle per boundary edge. Each connected loop of the chain gets
/// its own cone, from the mean of its vertices, so that a cone stays as small
/// as its hole. The cones are stored reversed (`−K`), so that `M` and `−K`
/// together are a consistently oriented closed surface for the crossing tie
/// rule.
#[derive(Clone, Debug)]
pub struct Winding {
    /// Triangles `(apex, b, a)` for every boundary edge `a → b`, grouped by loop.
    reversed_cone: Vec<[DVec3; 3]>,
}

impl Winding {
    fn new(mesh: &Mesh, chain: &[[u32; 2]]) -> Self {
        let p = |i: u32| mesh.positions[i as usize].as_dvec3();
        // Connected loops of the chain (union-find over its vertices).
        let mut parent: HashMap<u32, u32> = HashMap::new();
        fn root(parent: &mut HashMap<u32, u32>, v: u32) -> u32 {
            let mut r = v;
            while let Some(&q) = parent.get(&r)
                && q != r
            {
                r = q;
            }
            parent.insert(v, r);
            r
        }
        for &[a, b] in chain {
            parent.entry(a).or_insert(a);
            parent.entry(b).or_insert(b);
            let (ra, rb) = (root(&mut parent, a), root(&mut parent, b));
            if ra != rb {
                parent.insert(ra.max(rb), ra.min(rb));
            }
        }
        let mut loops: std::collections::BTreeMap<u32, Vec<[u32; 2]>> = Default::default();
        for &e in chain {
            loops.entry(root(&mut parent, e[0])).or_default().push(e);
        }
        let mut reversed_cone = Vec::with_capacity(chain.len());
        for edges in loops.values() {
            let apex = edges.iter().map(|e| p(e[0])).sum::<DVec3>() / edges.len() as f64;
            reversed_cone.extend(edges.iter().map(|&[a, b]| [apex, p(b), p(a)]));
        }
        Self { reversed_cone }
    }

    /// The reversed cones' triangles, in the mesh's local frame.
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

impl MeshSolid {
    /// The mesh, with vertices welded by exact position (which
    /// [`Solid::new`] has checked).
    #[must_use]
    pub fn new(mesh: &Mesh) -> Self {
        let welded = mesh.with_welded_vertices();
        let positions: Vec<DVec3> = welded.positions.iter().map(|p| p.as_dvec3()).collect();
        let Topology {
            edges,
            triangle_edges,
            boundary_edges,
        } = Topology::new(positions.len(), &welded.triangles);
        Self {
            bounds: bounds(&positions),
            positions,
            triangles: welded.triangles,
            edges,
            triangle_edges,
            boundary_edges,
            winding: None,
        }
    }

    /// The winding-number data, in [`Inside::WindingNumber`] mode.
    #[must_use]
    pub fn winding(&self) -> Option<&Winding> {
        self.winding.as_ref()
    }

    /// The distinct vertex positions, in the local frame.
    #[must_use]
    pub fn positions(&self) -> &[DVec3] {
        &self.positions
    }

    /// The triangles, as indices into [`positions`](Self::positions).
    #[must_use]
    pub fn triangle_indices(&self) -> &[[u32; 3]] {
        &self.triangles
    }

    /// The triangles, in the local frame.
    pub fn triangles(&self) -> impl ExactSizeIterator<Item = [DVec3; 3]> + '_ {
        self.triangles.iter().map(|t| corners(&self.positions, *t))
    }

    /// The distinct edges `[i, j]` (`i < j`) of the triangles.
    #[must_use]
    pub fn edges(&self) -> &[[u32; 2]] {
        &self.edges
    }

    /// Per triangle, its edges `a → b`, `b → c`, `c → a` as `2 · e + r`:
    /// edge `e` of [`edges`](Self::edges), run backwards iff `r = 1`.
    #[must_use]
    pub fn triangle_edges(&self) -> &[[u32; 3]] {
        &self.triangle_edges
    }

    /// Edges used by exactly one triangle after welding vertices by position:
    /// 0 for a watertight mesh; parity inside tests are unreliable otherwise.
    #[must_use]
    pub fn boundary_edges(&self) -> usize {
        self.boundary_edges
    }
}

/// A triangle in the world frame, prepared for the lattice's row lines
/// (lines along +x through cell centres `(y, z)`).
///
/// Whether a row line passes through the triangle is decided by the signs of
/// the three edge functions of its projection onto the yz plane. Each is a
/// fixed affine function of `(y, z)`, computed from a canonical order of the
/// edge's endpoints (lexicographic in x, y, z), so the two triangles sharing
/// an edge evaluate exactly opposite signs and a line through an edge or
/// vertex is counted by exactly one of the triangles around it (a consistent
/// tie rule). A triangle parallel to the rows is crossed by none.
#[derive(Clone, Copy, Debug)]
pub struct RowTri {
    /// Per edge, on its canonical endpoints `p, q`:
    /// `(p_y − y)(q_z − z) − (p_z − z)(q_y − y) = c0 + cz·z + cy·y`.
    edges: [[f64; 3]; 3],
    /// Per edge: whether the canonical order runs against the triangle's.
    flips: [bool; 3],
    /// The crossing's x on the triangle's plane: `x0 + xz·z + xy·y`.
    plane: [f64; 3],
    /// `(b − a) × (c − a)`, x component.
    nx: f64,
    /// The projection's bounds: `(y_lo, y_hi, z_lo, z_hi)`.
    yz: [f64; 4],
}

/// What [`RowTri::line`] takes of a triangle, with the edge functions
/// borrowed from where they were computed: placing a mesh computes each
/// edge's once, for the two triangles that share it, and its crossings are
/// found from these without copying the edges into a [`RowTri`] (the
/// copies went through the stack in pieces that later loads could not take
/// from the stores, stalling each triangle).
#[derive(Clone, Copy, Debug)]
pub(crate) struct RowFunctions<'a> {
    edges: [&'a [f64; 3]; 3],
    flips: [bool; 3],
    plane: [f64; 3],
    nx: f64,
}

impl<'a> RowFunctions<'a> {
    /// Of world triangle `v`, whose edges `a → b`, `b → c`, `c → a` have the
    /// [`row_edge`] coefficients `edges` and flips `flips`.
    #[inline]
    pub(crate) fn new(v: [DVec3; 3], edges: [&'a [f64; 3]; 3], flips: [bool; 3]) -> Self {
        let [a, b, c] = v;
        let n = (b - a).cross(c - a);
        Self {
            edges,
            flips,
            plane: [a.x + (n.y * a.y + n.z * a.z) / n.x, -n.z / n.x, -n.y / n.x],
            nx: n.x,
        }
    }

    /// [`RowTri::parallel`].
    #[inline]
    pub(crate) fn parallel(&self) -> bool {
        self.nx == 0.0
    }

    /// [`RowTri::sign`].
    #[inline]
    pub(crate) fn sign(&self) -> f64 {
        self.nx.signum()
    }

    /// [`RowTri::line`].
    #[inline]
    pub(crate) fn line(&self, z: f64) -> RowLine {
        let e = |k: usize| [self.edges[k][0] + self.edges[k][1] * z, self.edges[k][2]];
        RowLine {
            edges: [e(0), e(1), e(2)],
            flips: self.flips,
            plane: [self.plane[0] + self.plane[1] * z, self.plane[2]],
            crossed: !self.parallel(),
        }
    }
}

/// A [`RowTri`] restricted to the row line at one `z`: what every row of
/// that line needs, computed once.
#[derive(Clone, Copy, Debug)]
pub struct RowLine {
    edges: [[f64; 2]; 3],
    flips: [bool; 3],
    plane: [f64; 2],
    crossed: bool,
}

impl RowLine {
    /// The x where the row line through `y` (at this line's `z`) crosses
    /// the triangle, if it does.
    #[inline]
    #[must_use]
    pub fn cross(&self, y: f64) -> Option<f64> {
        let (crossed, x) = self.crossing(y);
        crossed.then_some(x)
    }

    /// [`cross`](Self::cross) without a branch: whether the row line
    /// through `y` crosses the triangle, and where it meets its plane
    /// (meaningless when it does not cross).
    #[inline]
    #[must_use]
    pub fn crossing(&self, y: f64) -> (bool, f64) {
        let side = |k: usize| (self.edges[k][0] + self.edges[k][1] * y >= 0.0) != self.flips[k];
        // All three evaluated (no early exit): the outcome is unpredictable.
        let (s0, s1, s2) = (side(0), side(1), side(2));
        (
            (s0 == s1) & (s1 == s2) & self.crossed,
            self.plane[0] + self.plane[1] * y,
        )
    }
}

/// The edge function of the triangle edge `p → q` for [`RowTri`]: its
/// coefficients `[c0, cz, cy]` on the canonical order of the endpoints
/// (lexicographic in x, y, z), and whether that order runs against `p → q`.
///
/// Without a branch, as which endpoint comes first is a coin toss: the
/// coefficients on `q → p` are those on `p → q` negated (each a difference
/// of the same two rounded terms, taken the other way round), so they are
/// computed on `p → q` and their sign bits flipped when `q` comes first.
/// They equal the coefficients computed on the canonical order but for the
/// sign of a zero, which no comparison of an edge function with zero sees.
/// (Selecting the endpoints instead compiled to a branch.)
#[inline]
pub(crate) fn row_edge(p: DVec3, q: DVec3) -> ([f64; 3], bool) {
    // `(p.x, p.y, p.z) < (q.x, q.y, q.z)`, each comparison evaluated.
    let before = (p.x < q.x) | ((p.x == q.x) & ((p.y < q.y) | ((p.y == q.y) & (p.z < q.z))));
    let sign = u64::from(!before) << 63;
    let canonical = |v: f64| f64::from_bits(v.to_bits() ^ sign);
    (
        [
            canonical(p.y * q.z - p.z * q.y),
            canonical(q.y - p.y),
            canonical(p.z - q.z),
        ],
        !before,
    )
}

/// The bounds `[y_lo, y_hi, z_lo, z_hi]` of the projection of triangle
/// `v` onto the yz plane, as [`RowTri::yz_bounds`] holds them.
#[inline]
pub(crate) fn yz_bounds([a, b, c]: [DVec3; 3]) -> [f64; 4] {
    [
        a.y.min(b.y).min(c.y),
        a.y.max(b.y).max(c.y),
        a.z.min(b.z).min(c.z),
        a.z.max(b.z).max(c.z),
    ]
}

impl RowTri {
    /// Every field's bits, zeros of either sign as `+0`: for tests that two
    /// ways of preparing a triangle agree exactly.
    #[cfg(test)]
    pub(crate) fn bits(&self) -> Vec<u64> {
        let floats = self
            .edges
            .iter()
            .flatten()
            .chain(&self.plane)
            .chain(&self.yz);
        floats
            .chain([&self.nx])
            .map(|&v| (v + 0.0).to_bits())
            .chain(self.flips.map(u64::from))
            .collect()
    }

    /// Prepares the world triangle `v`.
    #[must_use]
    pub fn new(v: [DVec3; 3]) -> Self {
        let [a, b, c] = v;
        let [(e0, f0), (e1, f1), (e2, f2)] = [row_edge(a, b), row_edge(b, c), row_edge(c, a)];
        Self::with_edges(v, [&e0, &e1, &e2], [f0, f1, f2])
    }

    /// [`new`](Self::new) with the [`row_edge`]s of `a → b`, `b → c` and
    /// `c → a` computed already (placing a mesh shares them between the two
    /// triangles of each edge): their coefficients and flips.
    #[inline]
    pub(crate) fn with_edges(v: [DVec3; 3], edges: [&[f64; 3]; 3], flips: [bool; 3]) -> Self {
        Self::with_functions(v, &RowFunctions::new(v, edges, flips))
    }

    /// The world triangle `v` whose row functions are `f` (made of `v`).
    #[inline]
    pub(crate) fn with_functions(v: [DVec3; 3], f: &RowFunctions) -> Self {
        Self {
            edges: [*f.edges[0], *f.edges[1], *f.edges[2]],
            flips: f.flips,
            plane: f.plane,
            nx: f.nx,
            yz: yz_bounds(v),
        }
    }

    /// The functions [`line`](Self::line) takes its row line from.
    #[inline]
    pub(crate) fn functions(&self) -> RowFunctions<'_> {
        RowFunctions {
            edges: [&self.edges[0], &self.edges[1], &self.edges[2]],
            flips: self.flips,
            plane: self.plane,
            nx: self.nx,
        }
    }

    /// The projection's bounds `(y_lo, y_hi, z_lo, z_hi)`.
    #[must_use]
    pub fn yz_bounds(&self) -> [f64; 4] {
        self.yz
    }

    /// Whether the triangle is parallel to the rows (no row crosses it).
    #[must_use]
    pub fn parallel(&self) -> bool {
        self.functions().parallel()
    }

    /// `+1` if a line along +x leaves the triangle's front side (the side
    /// its counter-clockwise normal points to) where it crosses, else `−1`.
    #[must_use]
    pub fn sign(&self) -> f64 {
        self.functions().sign()
    }

    /// The triangle on the row line at `z`.
    #[inline]
    #[must_use]
    pub fn line(&self, z: f64) -> RowLine {
        self.functions().line(z)
    }

    /// The y extent `(lo, hi)` of the projection's cross-section at `z`,
    /// up to rounding (callers widen it), if the line meets it.
    ///
    /// `nx` is twice the projection's signed area, and a point is inside
    /// where every edge function, taken in the triangle's own order, has its
    /// sign; each edge thus keeps one side of its root along y.
    #[must_use]
    pub fn y_section(&self, z: f64) -> Option<(f64, f64)> {
        let line = self.line(z);
        let [mut lo, mut hi, ..] = self.yz;
        let sigma = self.nx.signum();
        for (e, &flip) in line.edges.iter().zip(&self.flips) {
            let s = if flip { -sigma } else { sigma };
            let (d, c) = (s * e[0], s * e[1]);
            if c > 0.0 {
                lo = lo.max(-d / c);
            } else if c < 0.0 {
                hi = hi.min(-d / c);
            } else if d < 0.0 {
                return None;
            }
        }
        (lo <= hi).then_some((lo, hi))
    }

    /// The x where the row line through `(y, z)` crosses the triangle, if it
    /// does: [`line`](Self::line)`(z).cross(y)`.
    #[inline]
    #[must_use]
    pub fn cross(&self, y: f64, z: f64) -> Option<f64> {
        self.line(z).cross(y)
    }
}

/// Where the line `o + t v` crosses triangle `tri`, if it does: the same
/// rule as [`RowTri::cross`] for any line (the image rasterizer's
/// reference casts one per pixel).
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

/// What [`MeshSolid`] keeps of a welded mesh's edges: the distinct edges
/// `[i, j]` (`i < j`) in the order the triangles first use them, each
/// triangle's three edges (see [`MeshSolid::triangle_edges`]), and how
/// many edges have exactly one incident triangle (not counting edges whose
/// endpoints are one vertex).
///
/// Without hashing: a triangle corner's edge `a → b` is sorted into the
/// bucket of its lower endpoint (a counting sort over the vertices), each
/// bucket sorted by the higher endpoint and the corner's index, so that
/// every run of one edge starts with its first use. The cost is linear in
/// the triangles but for the sorts of the buckets, as small as the
/// vertices' degrees. (A `HashMap` of the edges, a second welding and a
/// sort of every edge for the boundary took 16 ms of the 69k-triangle
/// bunny's 33 ms scene.)
struct Topology {
    edges: Vec<[u32; 2]>,
    triangle_edges: Vec<[u32; 3]>,
    boundary_edges: usize,
}

impl Topology {
    /// Of `triangles` over `vertices` vertices (every index below it).
    fn new(vertices: usize, triangles: &[[u32; 3]]) -> Self {
        let corners = 3 * triangles.len();
        let edge = |c: usize| {
            let t = triangles[c / 3];
            let (a, b) = (t[c % 3], t[(c + 1) % 3]);
            (a.min(b), a.max(b))
        };
        // Counting sort of the corners by their edge's lower endpoint.
        let mut start = vec![0u32; vertices + 1];
        for c in 0..corners {
            start[edge(c).0 as usize + 1] += 1;
        }
        for v in 0..vertices {
            start[v + 1] += start[v];
        }
        let mut next = start.clone();
        let mut bucket = vec![0u64; corners];
        for c in 0..corners {
            let (lo, hi) = edge(c);
            let slot = &mut next[lo as usize];
            bucket[*slot as usize] = u64::from(hi) << 32 | c as u64;
            *slot += 1;
        }
        // Per corner, the first corner that uses its edge.
        let mut first = vec![0u32; corners];
        let mut boundary_edges = 0;
        for (v, ends) in start.windows(2).enumerate() {
            let bucket = &mut bucket[ends[0] as usize..ends[1] as usize];
            bucket.sort_unstable();
            for run in bucket.chunk_by(|x, y| x >> 32 == y >> 32) {
                let head = run[0] as u32;
                for &k in run {
                    first[k as u32 as usize] = head;
                }
                boundary_edges += usize::from(run.len() == 1 && (run[0] >> 32) as usize != v);
            }
        }
        // Edges numbered in order of first use.
        let mut id = vec![0u32; corners];
        let mut edges = Vec::new();
        for c in 0..corners {
            let f = first[c] as usize;
            id[c] = if f == c {
                let (lo, hi) = edge(c);
                edges.push([lo, hi]);
                (edges.len() - 1) as u32
            } else {
                id[f]
            };
        }
        let triangle_edges = triangles
            .iter()
            .enumerate()
            .map(|(t, tri)| {
                [0, 1, 2].map(|k| 2 * id[3 * t + k] + u32::from(tri[k] > tri[(k + 1) % 3]))
            })
            .collect();
        Self {
            edges,
            triangle_edges,
            boundary_edges,
        }
    }
}

#[cfg(test)]
mod tests {
    use glam::DVec3;
    use proptest::prelude::*;

    use super::{Topology, row_edge};

    /// `MeshSolid::new`'s edges as first written: a `HashMap` of the
    /// edges, in order of first use.
    fn edge_topology_reference(triangles: &[[u32; 3]]) -> (Vec<[u32; 2]>, Vec<[u32; 3]>) {
        let mut index: std::collections::HashMap<[u32; 2], u32> = std::collections::HashMap::new();
        let mut edges = Vec::new();
        let triangle_edges = triangles
            .iter()
            .map(|t| {
                [0, 1, 2].map(|k| {
                    let (a, b) = (t[k], t[(k + 1) % 3]);
                    let key = [a.min(b), a.max(b)];
                    let e = *index.entry(key).or_insert_with(|| {
                        edges.push(key);
                        (edges.len() - 1) as u32
                    });
                    2 * e + u32::from(a > b)
                })
            })
            .collect();
        (edges, triangle_edges)
    }

    /// Boundary edges as first counted: every edge with distinct
    /// endpoints, sorted, runs of one.
    fn boundary_edges_reference(triangles: &[[u32; 3]]) -> usize {
        let mut edges: Vec<(u32, u32)> = Vec::new();
        for t in triangles {
            for (a, b) in [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])] {
                if a != b {
                    edges.push((a.min(b), a.max(b)));
                }
            }
        }
        edges.sort_unstable();
        edges
            .chunk_by(|x, y| x == y)
            .filter(|run| run.len() == 1)
            .count()
    }

    /// [`row_edge`] as first written: the endpoints put in canonical order,
    /// then the coefficients computed on it.
    fn row_edge_reference(p: DVec3, q: DVec3) -> ([f64; 3], bool) {
        let before = (p.x, p.y, p.z) < (q.x, q.y, q.z);
        let (p, q) = if before { (p, q) } else { (q, p) };
        ([p.y * q.z - p.z * q.y, q.y - p.y, p.z - q.z], !before)
    }

    fn coordinate() -> impl Strategy<Value = f64> {
        prop_oneof![
            (-3i8..4).prop_map(|c| f64::from(c) * 0.5),
            -1e3..1e3f64,
            Just(0.0),
            Just(-0.0),
        ]
    }

    proptest! {
        /// The same coefficients as on the canonical order, but for the
        /// sign of a zero, and the same flip; on endpoints that share
        /// coordinates or coincide as well as random ones.
        #[test]
        fn row_edge_is_on_the_canonical_order(
            p in prop::array::uniform3(coordinate()),
            q in prop::array::uniform3(coordinate()),
            same in 0usize..4,
        ) {
            let (p, mut q) = (DVec3::from(p), DVec3::from(q));
            for axis in 0..same.min(3) {
                q[axis] = p[axis];
            }
            let (c, flip) = row_edge(p, q);
            let (r, r_flip) = row_edge_reference(p, q);
            prop_assert_eq!(flip, r_flip);
            prop_assert_eq!(c.map(|v| (v + 0.0).to_bits()), r.map(|v| (v + 0.0).to_bits()));
        }

        /// The same edges in the same order, the same triangle edges and
        /// the same boundary count as the hash map and the sort, on meshes
        /// over few vertices (edges shared by many triangles, vertices of
        /// high degree) with degenerate triangles (a vertex repeated, all
        /// three the same) among them.
        #[test]
        fn topology_equals_the_references(
            vertices in 1u32..24,
            corners in prop::collection::vec((0u32..24, 0u32..24, 0u32..24, 0u8..8), 1..200),
        ) {
            let triangles: Vec<[u32; 3]> = corners
                .iter()
                .map(|&(a, b, c, kind)| {
                    let [a, b, c] = [a, b, c].map(|i| i % vertices);
                    match kind {
                        0 => [a, a, c],
                        1 => [a, a, a],
                        _ => [a, b, c],
                    }
                })
                .collect();
            let topology = Topology::new(vertices as usize, &triangles);
            let (edges, triangle_edges) = edge_topology_reference(&triangles);
            prop_assert_eq!(&topology.edges, &edges);
            prop_assert_eq!(&topology.triangle_edges, &triangle_edges);
            prop_assert_eq!(topology.boundary_edges, boundary_edges_reference(&triangles));
        }
    }
}
