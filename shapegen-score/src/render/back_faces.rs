//! Which faces a render may skip without changing a pixel.
//!
//! Cap a mesh's holes (a fan over each boundary loop) and it is a closed,
//! consistently wound surface, with an integer winding number `w` off it:
//! `0` outside its convex hull, changing by one across each face. A ray
//! from outside the hull has `w = 0` until its first crossing, so a face can
//! be the first one a ray meets only from a side where `w = 0`. [`closure`]
//! finds, once per mesh, from which side (if any) each face can be met
//! first ([`FirstHit`]): for a face that no other face cuts, `w` is the same
//! all along each side; across a face that others cut, it stays within a
//! range (see `first_hit_by_winding`). A face seen from its other
//! side, in pixels away from every hole's projection (a ray there crosses
//! no cap), is never the nearest surface, and the renderer skips it (see
//! `Renderer::facing`); covered pixels and depths stay exactly what drawing
//! every face gives.
//!
//! For a mesh that bounds solids (no face cut by another, each part wound
//! outward or each inward) this is back-face culling: `w ≥ 0` everywhere,
//! so no face is met first from its inner side. A self-intersecting mesh
//! (the paper's leaf, whose two sheets cross at hundreds of face pairs) gets
//! them from the winding number at each face's centroid (`O(n²)`, for
//! meshes of at most [`MAX_WINDING`] faces); a face seen from a side whose
//! range holds 0 is drawn.
//!
//! Which faces meet is decided with exact orientation predicates
//! (Shewchuk's, from the `robust` crate); a face whose winding number is not
//! within 0.05 of the integer it must be is kept, as is every face of a mesh
//! that is not manifold or consistently wound, or too large to check.
//!
//! Ties are the one exception, as for any two rules: a pixel centre exactly
//! on a silhouette *edge* is covered by the face met first iff by the face
//! skipped (they share the edge's crossing and lie on the same side of it),
//! but one exactly on a silhouette *vertex* may be covered by a skipped face
//! alone.

use std::collections::HashMap;

use glam::DVec3;
use robust::{Coord, Coord3D, orient2d, orient3d};

use crate::mesh::corners;

/// From which side of a face `[a, b, c]` (its normal `(b − a) × (c − a)`
/// pointing to `Plus`) a ray from outside the mesh's hull can meet it first.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum FirstHit {
    /// Only from the side its normal points to (a front face seen from there).
    Plus,
    /// Only from the other side.
    Minus,
    /// From neither (it is inside the mesh from both sides).
    Neither,
    /// Maybe from either (cut by another face, or not decided): always drawn.
    Either,
}

/// What lets a render skip some of a mesh's faces: from where each can be
/// met first, and the holes.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Closure {
    /// Per face of the mesh, in order.
    pub first_hit: Vec<FirstHit>,
    /// Each boundary loop's vertices in model space: every face is drawn
    /// where these project (their caps lie within the loops' convex hulls).
    pub holes: Vec<Vec<DVec3>>,
}

/// Meshes with more triangles than this are not checked (every face drawn).
const MAX_TRIANGLES: usize = 200_000;

/// Self-intersecting meshes with more triangles than this (caps included)
/// get no winding numbers (every face drawn): `O(n²)` solid angles.
pub(crate) const MAX_WINDING: usize = 3000;

/// At most this many overlapping bounding-box pairs a triangle are tested
/// before giving up (every face drawn).
const PAIRS_PER_TRIANGLE: usize = 64;

/// From where each of `triangles` over `positions` (welded: a shared edge
/// has the same vertex indices on both sides) can be met first, or `None`
/// if that is known of none.
pub(crate) fn closure(positions: &[DVec3], triangles: &[[u32; 3]]) -> Option<Closure> {
    if triangles.is_empty() || triangles.len() > MAX_TRIANGLES {
        return None;
    }
    if !positions.iter().all(|p| p.is_finite()) {
        return None;
    }
    // Every directed edge once: a manifold, consistently oriented surface.
    let mut edges: HashMap<(u32, u32), u32> = HashMap::with_capacity(3 * triangles.len());
    for (t, &[a, b, c]) in triangles.iter().enumerate() {
        if a == b || b == c || c == a || [a, b, c].iter().any(|&i| i as usize >= positions.len()) {
            return None;
        }
        for e in [(a, b), (b, c), (c, a)] {
            if edges.insert(e, t as u32).is_some() {
                return None;
            }
        }
    }
    // Boundary edges (no opposite twin) chained into loops, capped by fans
    // from their centroids.
    let mut next: HashMap<u32, u32> = HashMap::new();
    for &(a, b) in edges.keys() {
        if !edges.contains_key(&(b, a)) && next.insert(a, b).is_some() {
            return None; // two boundary edges leave one vertex
        }
    }
    let mut points = positions.to_vec();
    let mut tris = triangles.to_vec();
    let mut holes = Vec::new();
    let mut starts: Vec<u32> = next.keys().copied().collect();
    starts.sort_unstable();
    let mut done = std::collections::HashSet::new();
    for start in starts {
        if done.contains(&start) {
            continue;
        }
        let mut ring = vec![start];
        let mut v = *next.get(&start)?;
        while v != start {
            if ring.len() > next.len() || !done.insert(v) {
                return None;
            }
            ring.push(v);
            v = *next.get(&v)?;
        }
        done.insert(start);
        let loop_points: Vec<DVec3> = ring.iter().map(|&i| positions[i as usize]).collect();
        let centre = loop_points.iter().sum::<DVec3>() / loop_points.len() as f64;
        let c = points.len() as u32;
        points.push(centre);
        for k in 0..ring.len() {
            let (a, b) = (ring[k], ring[(k + 1) % ring.len()]);
            tris.push([c, b, a]);
        }
        holes.push(loop_points);
    }
    // Too large for winding numbers: only a mesh without cuts will do.
    let cutters = cut_faces(&points, &tris, tris.len() > MAX_WINDING)?;
    let first_hit = if cutters.iter().all(Vec::is_empty)
        && let Some(outward) = orientation(&points, &tris)
    {
        // Bounds solids: `w ≥ 0` everywhere, `w₊ = w₋ − 1` for outward
        // normals, so no face is met first from its inner side.
        let side = if outward > 0.0 {
            FirstHit::Plus
        } else {
            FirstHit::Minus
        };
        vec![side; triangles.len()]
    } else if tris.len() <= MAX_WINDING {
        (0..triangles.len())
            .map(|i| first_hit_by_winding(&points, &tris, i, &cutters[i]))
            .collect()
    } else {
        return None;
    };
    first_hit
        .iter()
        .any(|&f| f != FirstHit::Either)
        .then_some(Closure { first_hit, holes })
}

/// From where face `i` of the closed surface `tris` can be met first.
///
/// Its sides' winding numbers `w₊` (where its normal points) and
/// `w₋ = w₊ + 1` average to the winding number at its centroid `c` (the
/// principal value: the face itself counts 0). Elsewhere on the face, `w₊`
/// differs from its value at `c` by the faces that cut it (`cutters`)
/// between the two points: a straight path beside the face from `c` crosses
/// each cutter at most once, from `c`'s side of it, which fixes the sign of
/// that step. So `w₊` stays within a range, and a side whose range misses 0
/// is never met first.
fn first_hit_by_winding(
    points: &[DVec3],
    tris: &[[u32; 3]],
    i: usize,
    cutters: &[u32],
) -> FirstHit {
    let [a, b, c] = tris[i].map(|v| points[v as usize]);
    let centroid = (a + b + c) / 3.0;
    let total: f64 = tris
        .iter()
        .enumerate()
        .filter(|&(j, _)| j != i)
        .map(|(_, t)| crate::solid::solid_angle(&t.map(|v| points[v as usize]), centroid))
        .sum();
    let plus = total / (4.0 * std::f64::consts::PI) - 0.5;
    let n = plus.round();
    // (Also when NaN.)
    if (plus - n).abs().partial_cmp(&0.05) != Some(std::cmp::Ordering::Less) {
        return FirstHit::Either;
    }
    // Crossing a face from its `+` side to its `−` side adds 1 to `w`.
    let (mut lo, mut hi) = (n as i64, n as i64);
    for &j in cutters {
        let [p, q, r] = tris[j as usize].map(|v| points[v as usize]);
        match side(p, q, r, centroid) {
            // Shewchuk's sign: negative on the side the normal points to.
            s if s < 0 => hi += 1,
            s if s > 0 => lo -= 1,
            _ => return FirstHit::Either,
        }
    }
    let plus_may_be_zero = lo <= 0 && 0 <= hi;
    let minus_may_be_zero = lo <= -1 && -1 <= hi;
    match (plus_may_be_zero, minus_may_be_zero) {
        (true, true) => FirstHit::Either,
        (true, false) => FirstHit::Plus,
        (false, true) => FirstHit::Minus,
        (false, false) => FirstHit::Neither,
    }
}

/// `+1` or `−1` if every connected part of the closed surface `tris` encloses
/// a volume of that sign; `None` if the signs differ or one is too small to
/// tell.
fn orientation(points: &[DVec3], tris: &[[u32; 3]]) -> Option<f64> {
    // Parts: triangles joined through shared edges.
    let mut parent: Vec<u32> = (0..tris.len() as u32).collect();
    fn find(parent: &mut [u32], mut i: u32) -> u32 {
        while parent[i as usize] != i {
            parent[i as usize] = parent[parent[i as usize] as usize];
            i = parent[i as usize];
        }
        i
    }
    let mut owner: HashMap<(u32, u32), u32> = HashMap::with_capacity(3 * tris.len());
    for (t, &[a, b, c]) in tris.iter().enumerate() {
        for (u, v) in [(a, b), (b, c), (c, a)] {
            if let Some(&s) = owner.get(&(v, u)) {
                let (x, y) = (find(&mut parent, s), find(&mut parent, t as u32));
                parent[x as usize] = y;
            }
            owner.insert((u, v), t as u32);
        }
    }
    let centre = points.iter().sum::<DVec3>() / points.len() as f64;
    // Per part: the signed volume and the sum of its terms' magnitudes.
    let mut volume: HashMap<u32, (f64, f64)> = HashMap::new();
    for (t, tri) in tris.iter().enumerate() {
        let [a, b, c] = tri.map(|i| points[i as usize] - centre);
        let term = a.dot(b.cross(c));
        let e = volume.entry(find(&mut parent, t as u32)).or_default();
        e.0 += term;
        e.1 += term.abs();
    }
    let mut sign = None;
    for &(v, size) in volume.values() {
        // (NaN sizes fail too.)
        if v.abs().partial_cmp(&(1e-9 * size)) != Some(std::cmp::Ordering::Greater) {
            return None;
        }
        let s = v.signum();
        if *sign.get_or_insert(s) != s {
            return None;
        }
    }
    sign
}

/// Per triangle of `tris`, the others it meets beyond the edges and
/// vertices they share (exactly; `None` when over budget, or at the first
/// cut if `only_uncut`).
fn cut_faces(points: &[DVec3], tris: &[[u32; 3]], only_uncut: bool) -> Option<Vec<Vec<u32>>> {
    let boxes: Vec<(DVec3, DVec3)> = tris
        .iter()
        .map(|t| {
            let [a, b, c] = corners(points, *t);
            (a.min(b).min(c), a.max(b).max(c))
        })
        .collect();
    let mut order: Vec<u32> = (0..tris.len() as u32).collect();
    order.sort_unstable_by(|&i, &j| boxes[i as usize].0.x.total_cmp(&boxes[j as usize].0.x));
    let mut budget = PAIRS_PER_TRIANGLE * tris.len();
    let mut cutters = vec![Vec::new(); tris.len()];
    for (k, &i) in order.iter().enumerate() {
        let (lo, hi) = boxes[i as usize];
        for &j in &order[k + 1..] {
            let (lo2, hi2) = boxes[j as usize];
            if lo2.x > hi.x {
                break;
            }
            if lo2.y > hi.y || hi2.y < lo.y || lo2.z > hi.z || hi2.z < lo.z {
                continue;
            }
            budget = budget.checked_sub(1)?;
            if !apart(points, tris[i as usize], tris[j as usize]) {
                if only_uncut {
                    return None;
                }
                cutters[i as usize].push(j);
                cutters[j as usize].push(i);
            }
        }
    }
    Some(cutters)
}

fn c3(p: DVec3) -> Coord3D<f64> {
    Coord3D {
        x: p.x,
        y: p.y,
        z: p.z,
    }
}

/// The sign of the exact orientation of `d` against the plane `a b c`.
fn side(a: DVec3, b: DVec3, c: DVec3, d: DVec3) -> i8 {
    let o = orient3d(c3(a), c3(b), c3(c), c3(d));
    (o > 0.0) as i8 - (o < 0.0) as i8
}

/// Whether triangles `s` and `t` meet only where they share vertices.
fn apart(points: &[DVec3], s: [u32; 3], t: [u32; 3]) -> bool {
    let shared: Vec<u32> = s.iter().copied().filter(|v| t.contains(v)).collect();
    let p = |i: u32| points[i as usize];
    let others = |tri: [u32; 3]| -> Vec<DVec3> {
        tri.iter()
            .copied()
            .filter(|v| !shared.contains(v))
            .map(p)
            .collect()
    };
    let (os, ot) = (others(s), others(t));
    match shared.len() {
        // Two triangles on one edge `u v`, third vertices `x` and `y`: they
        // meet only on the edge unless coplanar with `x`, `y` on one side.
        2 => {
            let (u, v, x, y) = (p(shared[0]), p(shared[1]), os[0], ot[0]);
            side(u, v, x, y) != 0 || {
                let axis = dominant_axis((v - u).cross(x - u));
                let sx = side2(u, v, x, axis);
                let sy = side2(u, v, y, axis);
                sx * sy < 0
            }
        }
        // One vertex `v`: apart if either triangle's far edge lies strictly
        // on one side of the other's plane.
        1 => {
            let v = p(shared[0]);
            let strictly = |a: DVec3, b: DVec3, x: DVec3, y: DVec3| {
                let (sx, sy) = (side(v, a, b, x), side(v, a, b, y));
                sx != 0 && sx == sy
            };
            if strictly(os[0], os[1], ot[0], ot[1]) || strictly(ot[0], ot[1], os[0], os[1]) {
                return true;
            }
            // Otherwise `t` crosses the plane of `s` along a segment from
            // `v` to a point `x` of its far edge: they meet beyond `v` iff
            // `x` lies in the corner of `s` at `v`. With `q` a far vertex of
            // `t` off that plane, the plane `v p q` cuts the plane of `s`
            // along `v p`, and `x` (between `q` and the other far vertex
            // `r`) is on the side of `r`.
            let [p1, p2] = [os[0], os[1]];
            let (q, r) = match (side(v, p1, p2, ot[0]), side(v, p1, p2, ot[1])) {
                (0, 0) => (None, ot[1]),
                (0, _) => (Some(ot[1]), ot[0]),
                _ => (Some(ot[0]), ot[1]),
            };
            if let Some(q) = q {
                let f = |p: DVec3, x: DVec3| side(v, p, q, x);
                let inside = f(p1, r) * f(p1, p2) >= 0 && f(p2, r) * f(p2, p1) >= 0;
                return !inside;
            }
            // Coplanar: apart iff a line along an edge `v a` has the other
            // triangle's far vertices strictly outside, or on the line but
            // on the far side of `v` from `a`.
            if side(v, os[0], os[1], ot[0]) != 0 || side(v, os[0], os[1], ot[1]) != 0 {
                return false;
            }
            let axis = dominant_axis((os[0] - v).cross(os[1] - v));
            let outside = |a: DVec3, inner: DVec3, other: &[DVec3]| {
                let s = side2(v, a, inner, axis);
                s != 0
                    && other.iter().all(|&x| match side2(v, a, x, axis) {
                        0 => behind(v, a, x),
                        t => t == -s,
                    })
            };
            outside(os[0], os[1], &ot)
                || outside(os[1], os[0], &ot)
                || outside(ot[0], ot[1], &os)
                || outside(ot[1], ot[0], &os)
        }
        0 => disjoint(os.try_into().unwrap(), ot.try_into().unwrap()),
        _ => false,
    }
}

/// For `x` on the line through `v` and `a` (`a ≠ v`): whether it lies
/// strictly on the other side of `v` (exact: compares coordinates).
fn behind(v: DVec3, a: DVec3, x: DVec3) -> bool {
    let k = (0..3).find(|&k| a[k] != v[k]).unwrap_or(0);
    (a[k] > v[k] && x[k] < v[k]) || (a[k] < v[k] && x[k] > v[k])
}

/// Whether two triangles without common vertices are disjoint (touching
/// counts as meeting).
fn disjoint(s: [DVec3; 3], t: [DVec3; 3]) -> bool {
    let ds = s.map(|x| side(t[0], t[1], t[2], x));
    let dt = t.map(|x| side(s[0], s[1], s[2], x));
    let one_side = |d: [i8; 3]| d[0] != 0 && d[0] == d[1] && d[1] == d[2];
    if one_side(ds) || one_side(dt) {
        return true;
    }
    if ds == [0; 3] {
        // Coplanar: apart iff some edge has the other triangle strictly outside.
        let axis = dominant_axis((s[1] - s[0]).cross(s[2] - s[0]));
        let separates = |tri: [DVec3; 3], other: [DVec3; 3]| {
            (0..3).any(|k| {
                let (a, b, c) = (tri[k], tri[(k + 1) % 3], tri[(k + 2) % 3]);
                let inner = side2(a, b, c, axis);
                inner != 0 && other.iter().all(|&x| side2(a, b, x, axis) == -inner)
            })
        };
        return separates(s, t) || separates(t, s);
    }
    // Not coplanar: two triangles meet iff an edge of one meets the other.
    (0..3).all(|k| {
        !segment_may_meet(s[k], s[(k + 1) % 3], t) && !segment_may_meet(t[k], t[(k + 1) % 3], s)
    })
}

/// Whether segment `a b` may meet triangle `t` (`true` when touching).
fn segment_may_meet(a: DVec3, b: DVec3, t: [DVec3; 3]) -> bool {
    let (sa, sb) = (side(t[0], t[1], t[2], a), side(t[0], t[1], t[2], b));
    if sa != 0 && sa == sb {
        return false;
    }
    if sa == 0 && sb == 0 {
        // In the triangle's plane: apart iff an edge line of the triangle
        // has the segment strictly outside, or the segment's line has the
        // whole triangle strictly on one side.
        let axis = dominant_axis((t[1] - t[0]).cross(t[2] - t[0]));
        let outside_edge = (0..3).any(|k| {
            let (p, q, r) = (t[k], t[(k + 1) % 3], t[(k + 2) % 3]);
            let inner = side2(p, q, r, axis);
            inner != 0 && side2(p, q, a, axis) == -inner && side2(p, q, b, axis) == -inner
        });
        let s = t.map(|x| side2(a, b, x, axis));
        let beside_line = s[0] != 0 && s[0] == s[1] && s[1] == s[2];
        return !(outside_edge || beside_line);
    }
    let s = [
        side(a, b, t[0], t[1]),
        side(a, b, t[1], t[2]),
        side(a, b, t[2], t[0]),
    ];
    // The line through `a b` passes outside the triangle iff it is on
    // strictly different sides of two of its edges.
    !(s.contains(&1) && s.contains(&-1))
}

/// The coordinate axis along which a normal is largest (the plane projects
/// onto the other two without collapsing).
fn dominant_axis(n: DVec3) -> usize {
    let n = n.abs();
    if n.x >= n.y && n.x >= n.z {
        0
    } else if n.y >= n.z {
        1
    } else {
        2
    }
}

/// The sign of the exact 2-D orientation of `c` against `a b`, dropping
/// coordinate `axis`.
fn side2(a: DVec3, b: DVec3, c: DVec3, axis: usize) -> i8 {
    let drop = |p: DVec3| match axis {
        0 => Coord { x: p.y, y: p.z },
        1 => Coord { x: p.z, y: p.x },
        _ => Coord { x: p.x, y: p.y },
    };
    let o = orient2d(drop(a), drop(b), drop(c));
    (o > 0.0) as i8 - (o < 0.0) as i8
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cube() -> (Vec<DVec3>, Vec<[u32; 3]>) {
        let m = crate::mesh::Mesh::unit_cube().with_welded_vertices();
        (
            m.positions.iter().map(|p| p.as_dvec3()).collect(),
            m.triangles,
        )
    }

    #[test]
    fn a_closed_cube_is_met_from_outside() {
        let (p, t) = cube();
        let c = closure(&p, &t).expect("a cube bounds a solid");
        assert!(c.holes.is_empty());
        assert_eq!(c.first_hit, vec![FirstHit::Plus; 12]);
        let flipped: Vec<[u32; 3]> = t.iter().map(|&[a, b, c]| [a, c, b]).collect();
        let f = closure(&p, &flipped).expect("so does an inside-out cube");
        assert_eq!(f.first_hit, vec![FirstHit::Minus; 12]);
    }

    #[test]
    fn an_open_cube_is_capped_over_its_hole() {
        let (p, mut t) = cube();
        t.truncate(10); // one face (two triangles) removed
        let c = closure(&p, &t).expect("capped, the open cube bounds a solid");
        assert_eq!(c.holes.len(), 1);
        assert_eq!(c.holes[0].len(), 4);
        assert_eq!(c.first_hit, vec![FirstHit::Plus; 10]);
    }

    #[test]
    fn crossing_meshes_keep_their_cut_faces_and_skip_the_buried_ones() {
        let (p, t) = cube();
        let n = p.len() as u32;
        // Two cubes of one mesh, the second shifted by 0.3 along each axis.
        let mut p2 = p.clone();
        p2.extend(p.iter().map(|v| *v + DVec3::splat(0.3)));
        let mut t2 = t.clone();
        t2.extend(t.iter().map(|tri| tri.map(|i| i + n)));
        let c = closure(&p2, &t2).expect("cubes crossing");
        let count = |f: FirstHit| c.first_hit.iter().filter(|&&x| x == f).count();
        // Each cube has three faces (six triangles) cut by the other and
        // three wholly outside it.
        assert_eq!(count(FirstHit::Either), 12);
        assert_eq!(count(FirstHit::Plus), 12);
        // A small cube inside a big one, the big one's faces cut by a third
        // cube: the small one's faces are never met first.
        let mut p3 = p2.clone();
        p3.extend(p.iter().map(|v| *v * 0.25));
        let mut t3 = t2.clone();
        t3.extend(t.iter().map(|tri| tri.map(|i| i + 2 * n)));
        let c = closure(&p3, &t3).expect("nested cubes");
        assert_eq!(&c.first_hit[24..], &[FirstHit::Neither; 12]);
        // Two disjoint cubes, one inside out: each met from its outside.
        let mut p4 = p.clone();
        p4.extend(p.iter().map(|v| *v + DVec3::splat(3.0)));
        let mut t4 = t.clone();
        t4.extend(t.iter().map(|&[a, b, c]| [a + n, c + n, b + n]));
        let c = closure(&p4, &t4).expect("parts wound both ways");
        assert_eq!(&c.first_hit[..12], &[FirstHit::Plus; 12]);
        assert_eq!(&c.first_hit[12..], &[FirstHit::Minus; 12]);
    }

    #[test]
    fn meshes_that_are_not_closed_surfaces_are_refused() {
        let (p, t) = cube();
        // One triangle flipped: an edge used twice in one direction.
        let mut t5 = t.clone();
        t5[0] = [t5[0][0], t5[0][2], t5[0][1]];
        assert!(closure(&p, &t5).is_none());
        // A lone sheet: its cap lies on it, so every face is cut.
        assert!(closure(&p, &t[..2]).is_none());
    }

    #[test]
    fn triangles_sharing_a_vertex_meet_iff_one_enters_the_others_corner() {
        // s: a corner at the origin in the plane z = 0, opening toward +x.
        let points = [
            DVec3::ZERO,
            DVec3::new(1.0, -0.5, 0.0),
            DVec3::new(1.0, 0.5, 0.0),
            // A wall through the origin crossing z = 0 along the x axis:
            // into the corner when it leans toward +x, beside it toward −x.
            DVec3::new(1.0, 0.0, -1.0),
            DVec3::new(0.5, 0.0, 1.0),
            DVec3::new(-1.0, 0.0, -1.0),
            DVec3::new(-0.5, 0.0, 1.0),
            // A second corner in the same plane, opening toward −x.
            DVec3::new(-1.0, -0.5, 0.0),
            DVec3::new(-1.0, 0.5, 0.0),
            // A third, overlapping the first.
            DVec3::new(1.0, 0.0, 0.0),
            DVec3::new(0.5, 1.0, 0.0),
        ];
        assert!(!apart(&points, [0, 1, 2], [0, 3, 4]));
        assert!(apart(&points, [0, 1, 2], [0, 5, 6]));
        assert!(apart(&points, [0, 1, 2], [0, 7, 8]));
        assert!(
            !apart(&points, [0, 1, 2], [0, 9, 10]),
            "overlapping, coplanar"
        );
    }

    #[test]
    fn the_orientation_sign_is_negative_where_the_normal_points() {
        let (o, x, y) = (DVec3::ZERO, DVec3::X, DVec3::Y);
        assert_eq!(side(o, x, y, DVec3::Z), -1);
        assert_eq!(side(o, x, y, -DVec3::Z), 1);
    }

    #[test]
    fn touching_triangles_count_as_meeting() {
        let tri = |a: [f64; 3], b: [f64; 3], c: [f64; 3]| {
            [DVec3::from(a), DVec3::from(b), DVec3::from(c)]
        };
        let s = tri([0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]);
        // Crossing through the interior.
        assert!(!disjoint(
            s,
            tri([0.2, 0.2, -1.0], [0.2, 0.2, 1.0], [0.3, 0.25, 1.0])
        ));
        // A vertex exactly on the other's interior.
        assert!(!disjoint(
            s,
            tri([0.2, 0.2, 0.0], [0.2, 0.2, 1.0], [0.3, 0.25, 1.0])
        ));
        // Above, apart.
        assert!(disjoint(
            s,
            tri([0.2, 0.2, 1e-12], [0.2, 0.2, 1.0], [0.3, 0.25, 1.0])
        ));
        // Coplanar: overlapping, then apart.
        assert!(!disjoint(
            s,
            tri([0.2, 0.2, 0.0], [2.0, 0.2, 0.0], [0.2, 2.0, 0.0])
        ));
        assert!(disjoint(
            s,
            tri([0.6, 0.6, 0.0], [2.0, 0.6, 0.0], [0.6, 2.0, 0.0])
        ));
        // An edge in the other's plane, beside it, then across it.
        assert!(disjoint(
            s,
            tri([1.0, 1.0, 0.0], [2.0, 0.5, 0.0], [1.5, 1.0, 1.0])
        ));
        assert!(!disjoint(
            s,
            tri([0.1, 0.1, 0.0], [2.0, 0.5, 0.0], [1.5, 1.0, 1.0])
        ));
        // Crossing the plane beside the triangle, not through it.
        assert!(disjoint(
            s,
            tri([2.0, 2.0, -1.0], [2.0, 2.0, 1.0], [3.0, 2.0, 0.0])
        ));
    }
}
