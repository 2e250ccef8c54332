//! Every mesh in `../shared/data/models/` and `../shared/data/paper/`:
//! loads, voxelizes at 128³ without failing, and, where watertight, agrees
//! at 128³ with the brute-force reference (each row's crossings with every
//! triangle, no BVH, no spans; rows split across threads). Meshes that are
//! not watertight are reported with their boundary-edge count, and their
//! parity cells compared too (but for the 69k-triangle bunny's).

use std::collections::HashSet;
use std::path::PathBuf;

use glam::{Affine3A, IVec3, Vec3};
use rayon::prelude::*;
use shapegen_score::solid::Solid;
use shapegen_score::voxelize::reference;
use shapegen_score::{Grid, Mesh, Voxelizer};

fn meshes() -> Vec<PathBuf> {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../shared/data");
    let mut out = Vec::new();
    for dir in ["models", "paper"] {
        if let Ok(entries) = std::fs::read_dir(root.join(dir)) {
            out.extend(
                entries
                    .flatten()
                    .map(|e| e.path())
                    .filter(|p| p.extension().is_some_and(|e| e == "obj")),
            );
        }
    }
    out.sort();
    out
}

fn span_cells(grid: &Grid, solid: &Solid) -> HashSet<IVec3> {
    let mut cells = HashSet::new();
    Voxelizer::new().spans(grid, solid, &Affine3A::IDENTITY, |s| {
        cells.extend((s.x0..s.x1).map(|x| IVec3::new(x as i32, s.y as i32, s.z as i32)));
    });
    cells
}

#[test]
fn every_shared_mesh_voxelizes() {
    let paths = meshes();
    if paths.is_empty() {
        eprintln!("skipping: ../shared/data is not there");
        return;
    }
    let mut report = Vec::new();
    for path in &paths {
        let name = path.file_name().unwrap().to_string_lossy().into_owned();
        let mesh = match Mesh::load_obj(path) {
            Ok(m) => m.normalized(),
            Err(e) => {
                report.push(format!("{name}: not loaded: {e}"));
                continue;
            }
        };
        let solid = Solid::new(&name, &mesh).unwrap();
        let fine = Grid::cube(Vec3::splat(-0.5), Vec3::splat(0.5), 128).unwrap();
        let cells = span_cells(&fine, &solid);
        let open = match &solid {
            Solid::Mesh(m) => m.boundary_edges(),
            Solid::Convex(_) => 0,
        };
        // Open meshes have no inside; their parity cells are still compared
        // (the same crossings rule), except the 69k-triangle bunny's (~1.1
        // billion brute-force tests).
        if open > 0 && mesh.triangles.len() > 20_000 {
            report.push(format!(
                "{name}: {} triangles, NOT watertight ({open} boundary edges), {} cells at 128³",
                mesh.triangles.len(),
                cells.len()
            ));
            continue;
        }
        let slow: HashSet<IVec3> = if matches!(solid, Solid::Mesh(_)) {
            (0..128)
                .into_par_iter()
                .flat_map_iter(|z| {
                    reference::mesh_cells_by_row_parity(
                        &fine,
                        &solid,
                        &Affine3A::IDENTITY,
                        z..z + 1,
                    )
                })
                .collect()
        } else {
            reference::cells_by_parity(&fine, &solid, &Affine3A::IDENTITY)
                .into_iter()
                .collect()
        };
        assert_eq!(cells, slow, "{name}: spans differ from the reference");
        let kind = if open > 0 {
            format!("NOT watertight ({open} boundary edges), parity")
        } else {
            "watertight".to_owned()
        };
        report.push(format!(
            "{name}: {} triangles, {kind}, {} cells at 128³, equal to the reference",
            mesh.triangles.len(),
            cells.len()
        ));
    }
    for line in &report {
        eprintln!("{line}");
    }
    assert_eq!(report.len(), paths.len());
}
