//! Triangle meshes: the built-in shapes and their bounds.

use std::io::BufRead;
use std::path::Path;

use glam::Vec3;

use crate::error::ScoreError;

/// What the OBJ reader would drop silently: NUL bytes (not a text file)
/// and faces with fewer than three vertices, each reported with its line.
fn check_obj_lines(bytes: &[u8]) -> Result<(), String> {
    for (k, line) in bytes.split(|&b| b == b'\n').enumerate() {
        if line.contains(&0) {
            return Err(format!(
                "line {}: a NUL byte (this is not a text OBJ file)",
                k + 1
            ));
        }
        let text = String::from_utf8_lossy(line);
        let mut words = text.split_whitespace();
        if words.next() == Some("f") {
            let corners = words.take_while(|w| !w.starts_with('#')).count();
            if corners < 3 {
                return Err(format!(
                    "line {}: a face with {corners} vertices (a face needs at least 3)",
                    k + 1
                ));
            }
        }
    }
    Ok(())
}

/// The values at a triangle's three corners `t` (indices into `values`).
///
/// Written out element by element: `t.map(|i| values[i as usize])` built
/// the array through the stack in pieces that the loads right after could
/// not take from the stores (a stall per triangle, seen in the voxelizer's
/// and the renderer's profiles).
#[inline(always)]
pub(crate) fn corners<T: Copy>(values: &[T], t: [u32; 3]) -> [T; 3] {
    [
        values[t[0] as usize],
        values[t[1] as usize],
        values[t[2] as usize],
    ]
}

/// Where a mesh (e.g. a target in its own units) goes in the world: scaled,
/// then rotated about x, then y, then z (degrees, right-handed:
/// counter-clockwise seen from the axis's positive end), then translated;
/// then, if `fit` is given, scaled uniformly and centred into that box.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Placement {
    /// Scale per axis (`Vec3::splat(s)` keeps proportions).
    pub scale: Vec3,
    /// Rotation angles about x, y and z in degrees, applied in that order.
    pub rotate_degrees: Vec3,
    /// Translation.
    pub translate: Vec3,
    /// A box to fit the placed mesh into (see [`Mesh::fit_into`]).
    pub fit: Option<(Vec3, Vec3)>,
}

impl Default for Placement {
    fn default() -> Self {
        Self {
            scale: Vec3::ONE,
            rotate_degrees: Vec3::ZERO,
            translate: Vec3::ZERO,
            fit: None,
        }
    }
}

/// The uniform scale and shift that fits the box `bounds` into `[min, max]`
/// (see [`Mesh::fit_into`]).
#[must_use]
pub fn fit_transform((lo, hi): (Vec3, Vec3), min: Vec3, max: Vec3) -> glam::Affine3A {
    let size = (hi - lo).as_dvec3();
    let room = (max - min).as_dvec3();
    let scale = (0..3)
        .filter(|&a| size[a] > 0.0)
        .map(|a| room[a] / size[a])
        .fold(f64::INFINITY, f64::min);
    let scale = if scale.is_finite() { scale } else { 1.0 };
    let from = ((lo + hi) * 0.5).as_dvec3();
    let to = ((min + max) * 0.5).as_dvec3();
    glam::Affine3A::from_scale_rotation_translation(
        Vec3::splat(scale as f32),
        glam::Quat::IDENTITY,
        (to - from * scale).as_vec3(),
    )
}

impl Placement {
    /// Places several meshes as one (their arrangement is kept): the same
    /// scale, rotation and translation for each, then one fit of their
    /// common bounds.
    #[must_use]
    pub fn place_all<'a>(&self, meshes: impl IntoIterator<Item = &'a Mesh>) -> Vec<Mesh> {
        let moved: Vec<Mesh> = meshes
            .into_iter()
            .map(|m| m.transformed(&self.transform()))
            .collect();
        let Some((min, max)) = self.fit else {
            return moved;
        };
        let bounds = moved.iter().map(Mesh::bounds).fold(
            (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
            |(lo, hi), (a, b)| (lo.min(a), hi.max(b)),
        );
        let fit = fit_transform(bounds, min, max);
        moved.iter().map(|m| m.transformed(&fit)).collect()
    }

    /// The scale, rotation and translation as one transform (without `fit`).
    #[must_use]
    pub fn transform(&self) -> glam::Affine3A {
        let r = self.rotate_degrees * (std::f32::consts::PI / 180.0);
        let rotation = glam::Mat3::from_rotation_z(r.z)
            * glam::Mat3::from_rotation_y(r.y)
            * glam::Mat3::from_rotation_x(r.x);
        glam::Affine3A::from_mat3_translation(
            rotation * glam::Mat3::from_diagonal(self.scale),
            self.translate,
        )
    }
}

/// An indexed triangle mesh.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Mesh {
    /// Vertex positions.
    pub positions: Vec<Vec3>,
    /// Triangles as indices into `positions`, counter-clockwise seen from outside.
    pub triangles: Vec<[u32; 3]>,
}

impl Mesh {
    /// For every vertex, the first vertex at exactly the same position
    /// (itself if none comes before): vertices welded by position, as the
    /// edge and boundary checks see them.
    #[must_use]
    pub fn welded(&self) -> Vec<u32> {
        // Sorted by (position bits, index): each run of one position starts
        // with its first index.
        let key = |i: u32| self.positions[i as usize].to_array().map(f32::to_bits);
        let mut order: Vec<u32> = (0..self.positions.len() as u32).collect();
        order.sort_unstable_by_key(|&i| (key(i), i));
        let mut id = vec![0; self.positions.len()];
        for run in order.chunk_by(|&a, &b| key(a) == key(b)) {
            for &i in run {
                id[i as usize] = run[0];
            }
        }
        id
    }

    /// The same triangles with one vertex per distinct position: vertices
    /// at exactly the same position (see [`welded`](Self::welded)) merged
    /// into the first, the others dropped (the kept ones stay in order).
    /// OBJ files often repeat a position once per face corner
    /// (for its normal or texture coordinate); the paper's `leaf.obj` has
    /// 1,722 vertices at 294 positions, so a rasterizer that projects every
    /// vertex does six times the work it needs.
    #[must_use]
    pub fn with_welded_vertices(&self) -> Self {
        let id = self.welded();
        let mut new_index = vec![u32::MAX; self.positions.len()];
        let mut positions = Vec::new();
        for (i, &first) in id.iter().enumerate() {
            if first as usize == i {
                new_index[i] = positions.len() as u32;
                positions.push(self.positions[i]);
            }
        }
        let triangles = self
            .triangles
            .iter()
            .map(|t| t.map(|v| new_index[id[v as usize] as usize]))
            .collect();
        Self {
            positions,
            triangles,
        }
    }

    /// The boundary of the mesh as a chain: every triangle's three directed
    /// edges, summed with opposite directions cancelling, a non-zero sum `m`
    /// giving `|m|` copies of the edge in its direction (vertex indices).
    /// Vertices at the same position count as one (the first index is
    /// used). Empty for a closed, consistently oriented mesh; always a
    /// cycle (every vertex starts as many edges as it ends).
    #[must_use]
    pub fn boundary_chain(&self) -> Vec<[u32; 2]> {
        let id = self.welded();
        // Every directed edge as (low, high, ±1), sorted: each run sums one
        // undirected edge's net multiplicity.
        let mut net: Vec<(u32, u32, i32)> = Vec::with_capacity(3 * self.triangles.len());
        for t in &self.triangles {
            for (a, b) in [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])] {
                let (a, b) = (id[a as usize], id[b as usize]);
                if a < b {
                    net.push((a, b, 1));
                } else if b < a {
                    net.push((b, a, -1));
                }
            }
        }
        net.sort_unstable();
        let mut chain = Vec::new();
        for run in net.chunk_by(|x, y| (x.0, x.1) == (y.0, y.1)) {
            let (a, b) = (run[0].0, run[0].1);
            let m: i32 = run.iter().map(|e| e.2).sum();
            let edge = if m > 0 { [a, b] } else { [b, a] };
            chain.extend(std::iter::repeat_n(edge, m.unsigned_abs() as usize));
        }
        chain
    }

    /// The axis-aligned unit cube centred at the origin (12 triangles).
    #[must_use]
    pub fn unit_cube() -> Self {
        let positions = (0..8)
            .map(|i| {
                Vec3::new(
                    (i & 1) as f32 - 0.5,
                    ((i >> 1) & 1) as f32 - 0.5,
                    ((i >> 2) & 1) as f32 - 0.5,
                )
            })
            .collect();
        // Two triangles per face, outward normals.
        let triangles = vec![
            [0, 2, 1],
            [1, 2, 3], // z = −0.5
            [4, 5, 6],
            [5, 7, 6], // z = +0.5
            [0, 1, 4],
            [1, 5, 4], // y = −0.5
            [2, 6, 3],
            [3, 6, 7], // y = +0.5
            [0, 4, 2],
            [2, 4, 6], // x = −0.5
            [1, 3, 5],
            [3, 7, 5], // x = +0.5
        ];
        Self {
            positions,
            triangles,
        }
    }

    /// A closed frustum along y with `sides` sides, from radius
    /// `bottom_radius` at y = −0.5 to `top_radius` at y = +0.5, centred at
    /// the origin. The paper's trunk is `frustum(16, 0.5, 0.29)`.
    #[must_use]
    pub fn frustum(sides: u32, bottom_radius: f32, top_radius: f32) -> Self {
        let sides = sides.max(3);
        let mut positions = Vec::with_capacity(2 * sides as usize + 2);
        for (r, y) in [(bottom_radius, -0.5), (top_radius, 0.5)] {
            for i in 0..sides {
                let a = std::f32::consts::TAU * i as f32 / sides as f32;
                positions.push(Vec3::new(r * a.cos(), y, -r * a.sin()));
            }
        }
        let (bottom, top) = (2 * sides, 2 * sides + 1);
        positions.push(Vec3::new(0.0, -0.5, 0.0));
        positions.push(Vec3::new(0.0, 0.5, 0.0));
        let mut triangles = Vec::with_capacity(4 * sides as usize);
        for i in 0..sides {
            let j = (i + 1) % sides;
            // Side quad (counter-clockwise seen from outside: angles grow toward −z).
            triangles.push([i, j, sides + i]);
            triangles.push([j, sides + j, sides + i]);
            triangles.push([bottom, j, i]);
            triangles.push([top, sides + i, sides + j]);
        }
        Self {
            positions,
            triangles,
        }
    }

    /// The paper's trunk: a closed 16-sided frustum, radii 0.5 and 0.29.
    #[must_use]
    pub fn trunk() -> Self {
        Self::frustum(16, 0.5, 0.29)
    }

    /// A gable roof filling the unit box: a triangular prism with its base
    /// on y = −0.5 and its ridge along x at y = +0.5.
    #[must_use]
    pub fn roof() -> Self {
        let positions = vec![
            Vec3::new(-0.5, -0.5, -0.5),
            Vec3::new(0.5, -0.5, -0.5),
            Vec3::new(-0.5, -0.5, 0.5),
            Vec3::new(0.5, -0.5, 0.5),
            Vec3::new(-0.5, 0.5, 0.0),
            Vec3::new(0.5, 0.5, 0.0),
        ];
        let triangles = vec![
            [0, 1, 2],
            [1, 3, 2], // base, y = −0.5
            [0, 4, 1],
            [1, 4, 5], // slope toward −z
            [2, 3, 4],
            [3, 5, 4], // slope toward +z
            [0, 2, 4], // gable, x = −0.5
            [1, 5, 3], // gable, x = +0.5
        ];
        Self {
            positions,
            triangles,
        }
    }

    /// A simple closed leaf made by shapegen (a flat, pointed blade with a
    /// little thickness), filling the unit box. It stands in for the paper's
    /// `leaf.obj` where no mesh file is given.
    #[must_use]
    pub fn leaf() -> Self {
        // Outline in the xy plane: stem at the bottom, tip at the top.
        let outline = [
            (0.0, -0.5),
            (0.35, -0.3),
            (0.5, 0.0),
            (0.35, 0.25),
            (0.0, 0.5),
            (-0.35, 0.25),
            (-0.5, 0.0),
            (-0.35, -0.3),
        ];
        let n = outline.len() as u32;
        let mut positions: Vec<Vec3> = Vec::with_capacity(2 * outline.len());
        for z in [-0.5, 0.5] {
            positions.extend(outline.iter().map(|&(x, y)| Vec3::new(x, y, z)));
        }
        let mut triangles = Vec::new();
        for i in 1..n - 1 {
            triangles.push([0, i + 1, i]); // back face (z = −0.5), fan
            triangles.push([n, n + i, n + i + 1]); // front face (z = +0.5)
        }
        for i in 0..n {
            let j = (i + 1) % n;
            triangles.push([i, j, n + i]);
            triangles.push([j, n + j, n + i]);
        }
        Self {
            positions,
            triangles,
        }
    }

    /// The built-in mesh for a shape name: `cube`, `frustum` or `trunk`, `leaf`, `roof`.
    #[must_use]
    pub fn builtin(name: &str) -> Option<Self> {
        match name {
            "cube" => Some(Self::unit_cube()),
            "frustum" | "trunk" => Some(Self::trunk()),
            "leaf" => Some(Self::leaf()),
            "roof" => Some(Self::roof()),
            _ => None,
        }
    }

    /// Loads a triangle mesh from an OBJ file (all objects merged, polygons
    /// triangulated, materials ignored). Fails with the file's name on a
    /// missing or malformed file, a mesh without triangles or a non-finite vertex.
    pub fn load_obj(path: &Path) -> Result<Self, ScoreError> {
        let file = std::fs::File::open(path).map_err(|source| ScoreError::Io {
            path: path.to_path_buf(),
            source,
        })?;
        Self::read_obj(&mut std::io::BufReader::new(file), path)
    }

    /// Reads an OBJ mesh from `reader`; `path` names it in errors.
    pub fn read_obj(reader: &mut impl BufRead, path: &Path) -> Result<Self, ScoreError> {
        let bad = |reason: String| ScoreError::Obj {
            path: path.to_path_buf(),
            reason,
        };
        let mut bytes = Vec::new();
        reader
            .read_to_end(&mut bytes)
            .map_err(|e| bad(e.to_string()))?;
        // Editors on Windows may start a UTF-8 file with a byte-order mark.
        if bytes.starts_with(b"\xEF\xBB\xBF") {
            bytes.drain(..3);
        }
        check_obj_lines(&bytes).map_err(bad)?;
        let options = tobj::LoadOptions {
            single_index: true,
            triangulate: true,
            ..Default::default()
        };
        let (models, _materials) =
            tobj::load_obj_buf(&mut std::io::Cursor::new(bytes), &options, |_| {
                Err(tobj::LoadError::OpenFileFailed)
            })
            .map_err(|e| bad(e.to_string()))?;
        let mut mesh = Self::default();
        for m in &models {
            let base = mesh.positions.len() as u32;
            let p = &m.mesh.positions;
            if p.len() % 3 != 0 {
                return Err(bad(format!(
                    "object `{}` has a truncated vertex list",
                    m.name
                )));
            }
            mesh.positions
                .extend(p.chunks_exact(3).map(|c| Vec3::new(c[0], c[1], c[2])));
            let n = (p.len() / 3) as u32;
            for t in m.mesh.indices.chunks_exact(3) {
                if t.iter().any(|&i| i >= n) {
                    return Err(bad(format!(
                        "object `{}` has a face with a vertex index out of range",
                        m.name
                    )));
                }
                mesh.triangles.push([base + t[0], base + t[1], base + t[2]]);
            }
        }
        if mesh.triangles.is_empty() {
            return Err(bad("it has no faces".into()));
        }
        if let Some(i) = mesh.positions.iter().position(|p| !p.is_finite()) {
            return Err(bad(format!("vertex {} is not finite", i + 1)));
        }
        Ok(mesh)
    }

    /// The same mesh scaled and moved to fill the unit box `[−½, ½]³` *per
    /// axis* (the paper's convention for shape meshes: each axis is scaled on
    /// its own, so proportions change; a flat axis stays flat). To keep the
    /// proportions use [`fit_into`](Self::fit_into).
    #[must_use]
    pub fn normalized(&self) -> Self {
        let (lo, hi) = self.bounds();
        let size = hi - lo;
        let centre = (lo + hi) * 0.5;
        let scale = Vec3::select(size.cmpgt(Vec3::ZERO), size.recip(), Vec3::ZERO);
        Self {
            positions: self
                .positions
                .iter()
                .map(|p| (*p - centre) * scale)
                .collect(),
            triangles: self.triangles.clone(),
        }
    }

    /// The mesh with every vertex moved by `transform` (triangles are kept;
    /// a mirroring transform leaves them inside out).
    #[must_use]
    pub fn transformed(&self, transform: &glam::Affine3A) -> Self {
        Self {
            positions: self
                .positions
                .iter()
                .map(|p| transform.transform_point3(*p))
                .collect(),
            triangles: self.triangles.clone(),
        }
    }

    /// The mesh scaled uniformly (proportions kept) and centred so that its
    /// bounding box fits the box `[min, max]` as tightly as possible: the
    /// scale is the smallest ratio of box size to mesh size over the axes
    /// where the mesh is not flat. A mesh flat on every axis (a point) is
    /// only moved to the box's centre.
    #[must_use]
    pub fn fit_into(&self, min: Vec3, max: Vec3) -> Self {
        self.transformed(&fit_transform(self.bounds(), min, max))
    }

    /// The mesh placed by `placement` (see [`Placement`]).
    #[must_use]
    pub fn placed(&self, placement: &Placement) -> Self {
        placement
            .place_all([self])
            .pop()
            .expect("one mesh in, one out")
    }

    /// The smallest axis-aligned box holding every vertex, as (min, max).
    #[must_use]
    pub fn bounds(&self) -> (Vec3, Vec3) {
        self.positions.iter().fold(
            (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
            |(lo, hi), p| (lo.min(*p), hi.max(*p)),
        )
    }

    /// Signed volume (positive for a closed mesh with outward-facing triangles).
    #[must_use]
    pub fn volume(&self) -> f64 {
        self.triangles
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|i| self.positions[i as usize].as_dvec3());
                a.dot(b.cross(c)) / 6.0
            })
            .sum()
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn fit_into_keeps_proportions_and_fills_the_tightest_axis() {
        // A 2 × 1 × 1 box, 1000× too large, fitted into [0, 4] × [0, 4] × [0, 1].
        let big = super::Mesh::unit_cube().transformed(&glam::Affine3A::from_scale(
            glam::Vec3::new(2000.0, 1000.0, 1000.0),
        ));
        let fitted = big.fit_into(glam::Vec3::ZERO, glam::Vec3::new(4.0, 4.0, 1.0));
        let (lo, hi) = fitted.bounds();
        let size = hi - lo;
        // z is the tightest (1 / 1000): the box becomes 2 × 1 × 1, centred.
        assert!(
            (size - glam::Vec3::new(2.0, 1.0, 1.0)).abs().max_element() < 1e-5,
            "{size}"
        );
        assert!(
            ((lo + hi) * 0.5 - glam::Vec3::new(2.0, 2.0, 0.5))
                .abs()
                .max_element()
                < 1e-5
        );
        // A point is only moved.
        let point = super::Mesh {
            positions: vec![glam::Vec3::ONE; 3],
            triangles: vec![[0, 1, 2]],
        };
        let moved = point.fit_into(glam::Vec3::ZERO, glam::Vec3::splat(2.0));
        assert_eq!(moved.positions[0], glam::Vec3::ONE);
    }

    #[test]
    fn placement_scales_then_rotates_then_translates() {
        let p = super::Placement {
            scale: glam::Vec3::new(2.0, 1.0, 1.0),
            rotate_degrees: glam::Vec3::new(0.0, 0.0, 90.0),
            translate: glam::Vec3::new(0.0, 0.0, 5.0),
            fit: None,
        };
        // (1, 0, 0) → scaled (2, 0, 0) → rotated about z to (0, 2, 0) → (0, 2, 5).
        let q = p.transform().transform_point3(glam::Vec3::X);
        assert!((q - glam::Vec3::new(0.0, 2.0, 5.0)).length() < 1e-5, "{q}");
        // Rotations apply about x first, then y: (0, 1, 0) → x 90° → (0, 0, 1) → y 90° → (1, 0, 0).
        let p = super::Placement {
            rotate_degrees: glam::Vec3::new(90.0, 90.0, 0.0),
            ..Default::default()
        };
        let q = p.transform().transform_point3(glam::Vec3::Y);
        assert!((q - glam::Vec3::X).length() < 1e-5, "{q}");
    }

    use super::*;

    /// Welding keeps every triangle's corner positions and leaves one
    /// vertex per distinct position.
    #[test]
    fn welding_merges_repeated_positions_only() {
        // A quad as two triangles with their own corners (as OBJ exporters
        // write them), plus an unused vertex and a nearly equal one.
        let p = |x: f32, y: f32| Vec3::new(x, y, 0.0);
        let mesh = Mesh {
            positions: vec![
                p(0.0, 0.0),
                p(1.0, 0.0),
                p(1.0, 1.0),
                p(0.0, 0.0),
                p(1.0, 1.0),
                p(0.0, 1.0),
                p(5.0, 5.0),
                p(1.0, 1.0 + f32::EPSILON),
            ],
            triangles: vec![[0, 1, 2], [3, 4, 5], [7, 4, 3]],
        };
        let welded = mesh.with_welded_vertices();
        assert_eq!(welded.positions.len(), 6); // four corners, (5, 5), the near one
        assert_eq!(welded.triangles.len(), mesh.triangles.len());
        for (a, b) in mesh.triangles.iter().zip(&welded.triangles) {
            for k in 0..3 {
                assert_eq!(
                    mesh.positions[a[k] as usize],
                    welded.positions[b[k] as usize]
                );
            }
        }
        assert_eq!(welded.triangles[1], [0, 2, 3]);
        let ids: Vec<u32> = (0..welded.positions.len() as u32).collect();
        assert_eq!(welded.welded(), ids, "welding twice changes nothing");
        assert_eq!(welded.boundary_chain().len(), mesh.boundary_chain().len());
    }

    #[test]
    fn builtins_fill_the_unit_box_and_face_outward() {
        for name in ["cube", "frustum", "leaf", "roof"] {
            let m = Mesh::builtin(name).unwrap();
            let (lo, hi) = m.bounds();
            assert!(
                lo.abs_diff_eq(Vec3::splat(-0.5), 1e-6) && hi.abs_diff_eq(Vec3::splat(0.5), 1e-6),
                "{name}: {lo} {hi}"
            );
            assert!(m.volume() > 0.0, "{name} is inside out");
        }
        assert!((Mesh::unit_cube().volume() - 1.0).abs() < 1e-9);
        assert!((Mesh::roof().volume() - 0.5).abs() < 1e-9);
        // A 16-sided frustum's volume is close to the cone frustum's π h (R² + R r + r²) / 3.
        let (r0, r1) = (0.5f64, 0.29f64);
        let cone = std::f64::consts::PI * (r0 * r0 + r0 * r1 + r1 * r1) / 3.0;
        let v = Mesh::trunk().volume();
        assert!((v - cone).abs() / cone < 0.03, "{v} vs {cone}");
        assert!(Mesh::builtin("sphere").is_none());
    }

    #[test]
    fn obj_reading_reports_bad_files() {
        let read = |text: &str| Mesh::read_obj(&mut text.as_bytes(), Path::new("t.obj"));
        let quad = read("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n").unwrap();
        assert_eq!(quad.triangles.len(), 2);
        for (text, needle) in [
            ("v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 2 9\n", "t.obj"),
            ("v 0 0 0\n", "no faces"),
            ("v 0 0 nan\nv 1 0 0\nv 1 1 0\nf 1 2 3\n", "not finite"),
            ("v 0 zero 0\nf 1 1 1\n", "t.obj"),
            ("", "no faces"),
        ] {
            let err = read(text).unwrap_err().to_string();
            assert!(err.contains(needle), "{text:?}: {err}");
        }
        let missing = Mesh::load_obj(Path::new("/nonexistent/x.obj"))
            .unwrap_err()
            .to_string();
        assert!(missing.contains("/nonexistent/x.obj"), "{missing}");
        // Normalization fills the unit box.
        let (lo, hi) = quad.normalized().bounds();
        assert_eq!(
            (lo, hi),
            (Vec3::new(-0.5, -0.5, 0.0), Vec3::new(0.5, 0.5, 0.0))
        );
    }
}
