//! Every mesh in `../shared/data/models/` and `../shared/data/paper/`:
//! loads, voxelizes at 128³ without failing, and, where watertight, agrees
//! with the brute-force per-row reference (checked on a 24³ grid, which keeps
//! the all-triangles reference affordable for the 69k-triangle bunny).
//! Meshes that are not watertight are reported with their boundary-edge count.

use std::collections::HashSet;
use std::path::PathBuf;

use glam::{Affine3A, IVec3, Vec3};
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
        if open > 0 {
            report.push(format!(
                "{name}: {} triangles, NOT watertight ({open} boundary edges), {} cells at 128³",
                mesh.triangles.len(),
                cells.len()
            ));
            continue;
        }
        let coarse = Grid::cube(Vec3::splat(-0.5), Vec3::splat(0.5), 24).unwrap();
        let fast = span_cells(&coarse, &solid);
        let slow: HashSet<IVec3> = reference::cells_by_parity(&coarse, &solid, &Affine3A::IDENTITY)
            .into_iter()
            .collect();
        assert_eq!(fast, slow, "{name}: spans differ from the reference");
        report.push(format!(
            "{name}: {} triangles, watertight, {} cells at 128³, equal to the reference at 24³",
            mesh.triangles.len(),
            cells.len()
        ));
    }
    for line in &report {
        eprintln!("{line}");
    }
    assert_eq!(report.len(), paths.len());
}
