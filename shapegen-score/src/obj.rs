//! Writing expressed models as Wavefront OBJ (readable by Blender and MeshLab).

use std::borrow::Cow;
use std::io::{self, Write};
use std::path::Path;

use shapegen_core::express::{Generator, Instance, Instances};
use shapegen_core::genome::Chromosome;

use crate::error::ScoreError;
use crate::files::write_atomically;
use crate::mesh::Mesh;

/// The meshes of a generator's shapes, indexed by shape id.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ShapeMeshes {
    names: Vec<Cow<'static, str>>,
    meshes: Vec<Mesh>,
}

impl ShapeMeshes {
    /// The built-in mesh of every shape of `generator` (see [`Mesh::builtin`]);
    /// fails on a shape without a built-in mesh.
    pub fn builtin<G: Generator>(generator: &G) -> Result<Self, ScoreError> {
        let names = generator.shapes().to_vec();
        let meshes = names
            .iter()
            .map(|n| Mesh::builtin(n).ok_or_else(|| ScoreError::UnknownShape(n.to_string())))
            .collect::<Result<_, _>>()?;
        Ok(Self { names, meshes })
    }

    /// Named meshes given directly: shape `i` is `names[i]` with `meshes[i]`.
    pub fn new(names: Vec<Cow<'static, str>>, meshes: Vec<Mesh>) -> Result<Self, ScoreError> {
        if names.len() != meshes.len() {
            return Err(ScoreError::Target(format!(
                "{} shape names for {} meshes",
                names.len(),
                meshes.len()
            )));
        }
        Ok(Self { names, meshes })
    }

    /// Replaces the mesh of shape `name` (e.g. by one loaded from a file).
    pub fn set(&mut self, name: &str, mesh: Mesh) -> Result<(), ScoreError> {
        let i = self
            .names
            .iter()
            .position(|n| n == name)
            .ok_or_else(|| ScoreError::UnknownShape(name.to_string()))?;
        self.meshes[i] = mesh;
        Ok(())
    }

    /// Checks that these are the meshes of the shapes `names` (a
    /// generator's, in its order).
    pub fn check_for(&self, names: &[Cow<'static, str>]) -> Result<(), ScoreError> {
        if self.names.as_slice() == names {
            return Ok(());
        }
        Err(ScoreError::Target(format!(
            "the meshes are for shapes [{}], the generator emits [{}]",
            self.names.join(", "),
            names.join(", ")
        )))
    }

    /// Number of shapes.
    #[must_use]
    pub fn len(&self) -> usize {
        self.meshes.len()
    }

    /// Whether there are no shapes.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.meshes.is_empty()
    }

    /// The mesh of shape `id`.
    #[must_use]
    pub fn mesh(&self, id: u16) -> &Mesh {
        &self.meshes[id as usize]
    }

    /// The name of shape `id`.
    #[must_use]
    pub fn name(&self, id: u16) -> &str {
        &self.names[id as usize]
    }
}

/// Writes `instances` as OBJ, one object per instance (`o cube_0`, ...),
/// with vertices in world coordinates.
pub fn write_obj<W: Write>(
    mut out: W,
    instances: &[Instance],
    shapes: &ShapeMeshes,
) -> io::Result<()> {
    writeln!(out, "# shapegen model: {} instances", instances.len())?;
    let mut base = 1u64;
    for (k, inst) in instances.iter().enumerate() {
        let mesh = shapes.mesh(inst.shape);
        writeln!(out, "o {}_{k}", shapes.name(inst.shape))?;
        for p in &mesh.positions {
            let q = inst.transform.transform_point3(*p);
            writeln!(out, "v {} {} {}", q.x, q.y, q.z)?;
        }
        for t in &mesh.triangles {
            let [a, b, c] = t.map(|i| base + i as u64);
            writeln!(out, "f {a} {b} {c}")?;
        }
        base += mesh.positions.len() as u64;
    }
    out.flush()
}

/// Expresses `chromosome` with `generator` and writes the model to `path`
/// as OBJ with `shapes` (e.g. [`ShapeMeshes::builtin`], or the meshes a
/// fitness scores with: `ModelFitness::meshes`), atomically: a temporary
/// file beside `path`, then a rename. Fails if `shapes` does not hold one
/// mesh per shape of the generator.
pub fn write_model<G: Generator>(
    path: &Path,
    generator: &G,
    chromosome: &Chromosome,
    shapes: &ShapeMeshes,
) -> Result<(), ScoreError> {
    shapes.check_for(generator.shapes())?;
    let mut model = Instances::default();
    generator.express(chromosome, &mut model);
    let mut text = Vec::new();
    write_obj(&mut text, &model.0, shapes).expect("writing to memory cannot fail");
    write_atomically(path, &text)
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Affine3A;

    #[test]
    fn objects_vertices_and_faces_are_numbered_across_instances() {
        let shapes = ShapeMeshes {
            names: vec!["cube".into()],
            meshes: vec![Mesh::unit_cube()],
        };
        let model = [
            Instance {
                shape: 0,
                transform: Affine3A::IDENTITY,
            },
            Instance {
                shape: 0,
                transform: Affine3A::from_translation([2.0, 0.0, 0.0].into()),
            },
        ];
        let mut out = Vec::new();
        write_obj(&mut out, &model, &shapes).unwrap();
        let text = String::from_utf8(out).unwrap();
        assert_eq!(text.lines().filter(|l| l.starts_with("o ")).count(), 2);
        assert_eq!(text.lines().filter(|l| l.starts_with("v ")).count(), 16);
        assert_eq!(text.lines().filter(|l| l.starts_with("f ")).count(), 24);
        // The second cube's faces use vertices 9..=16 and its vertices are moved by x + 2.
        let last_face = text.lines().rfind(|l| l.starts_with("f ")).unwrap();
        assert!(
            last_face
                .split(' ')
                .skip(1)
                .all(|i| (9..=16).contains(&i.parse::<u32>().unwrap()))
        );
        assert!(text.contains("v 1.5 -0.5 -0.5") && text.contains("v 2.5 0.5 0.5"));
    }
}
