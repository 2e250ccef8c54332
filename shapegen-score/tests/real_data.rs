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
use shapegen_score::reference;
use shapegen_score::{Grid, Mesh, Voxelizer};
use shapegen_score::{Inside, Solid};

/// Every OBJ under `../shared/data/{models,paper}`, sorted; `None` (with a
/// message) when there are none, and the test is skipped.
fn meshes() -> Option<Vec<PathBuf>> {
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
    if out.is_empty() {
        eprintln!("skipping: ../shared/data is not there");
        return None;
    }
    Some(out)
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
    let Some(paths) = meshes() else {
        return;
    };
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

/// Every open mesh under the winding-number rule: the fast path (signed
/// crossings plus a cone over the holes) equals the brute-force sum of
/// every triangle's solid angle on a 20³ grid (9³ for the bunny), away
/// from the ½ threshold.
#[test]
fn open_shared_meshes_by_winding_number() {
    let Some(paths) = meshes() else {
        return;
    };
    for path in &paths {
        let name = path.file_name().unwrap().to_string_lossy().into_owned();
        let Ok(mesh) = Mesh::load_obj(path).map(|m| m.normalized()) else {
            continue;
        };
        if mesh.boundary_chain().is_empty() {
            continue;
        }
        // The brute-force sum costs cells × triangles: the 69k-triangle
        // bunny (223 boundary edges, so its cones' clusters and bounds are
        // exercised) on a coarser grid.
        let n = if mesh.triangles.len() > 20_000 { 9 } else { 20 };
        let g = Grid::cube(Vec3::splat(-0.5), Vec3::splat(0.5), n).unwrap();
        let parity = span_cells(&g, &Solid::new(&name, &mesh).unwrap());
        let solid = Solid::with_inside(&name, &mesh, Inside::WindingNumber).unwrap();
        let fast = span_cells(&g, &solid);
        let numbers = reference::winding_numbers(&g, &solid, &Affine3A::IDENTITY);
        let tie = |w: f64| (w.abs() - 0.5).abs() < 1e-9;
        let slow: HashSet<IVec3> = numbers
            .iter()
            .filter(|(_, w)| !tie(*w) && w.abs() >= 0.5)
            .map(|(c, _)| *c)
            .collect();
        let ties: HashSet<IVec3> = numbers
            .iter()
            .filter(|(_, w)| tie(*w))
            .map(|(c, _)| *c)
            .collect();
        let differ = fast
            .symmetric_difference(&slow)
            .filter(|c| !ties.contains(*c))
            .count();
        assert_eq!(
            differ, 0,
            "{name}: {differ} cells differ from the solid-angle sum"
        );
        eprintln!(
            "{name}: {} cells by winding number, {} by parity at {n}³, equal to the solid-angle sum",
            fast.len(),
            parity.len()
        );
    }
}
