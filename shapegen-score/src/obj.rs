//! Writing expressed models as Wavefront OBJ (readable by Blender and MeshLab).

use std::io::{self, Write};
use std::path::Path;

use shapegen_core::express::{Generator, Instance, Instances};
use shapegen_core::genome::Chromosome;

use crate::error::ScoreError;
use crate::files::write_atomically;
use crate::shapes::ShapeMeshes;

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
    use crate::mesh::Mesh;
    use glam::Affine3A;

    #[test]
    fn objects_vertices_and_faces_are_numbered_across_instances() {
        let shapes = ShapeMeshes::new(vec!["cube".into()], vec![Mesh::unit_cube()]).unwrap();
        let model = [
            Instance::new(0, Affine3A::IDENTITY),
            Instance::new(0, Affine3A::from_translation([2.0, 0.0, 0.0].into())),
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
