//! The renderer's G-buffer against the silhouette rasterizer (coverage)
//! and per-pixel ray casting (depth), and the fitted cameras.

use std::borrow::Cow;

use crate::common::{
    camera, crossing_cubes, open_box, open_star, placement, star_prism, wavy_sheet,
};
use glam::{Affine3A, DVec3, Vec3};
use proptest::prelude::*;
use shapegen_core::express::Instance;
use shapegen_score::{
    BoundingSphere, Camera, GBuffer, Mesh, RasterShape, Rasterizer, RenderMeshes, Renderer,
    ShapeMeshes, fit_camera, fit_orthographic,
};

fn meshes() -> Vec<Mesh> {
    vec![
        Mesh::unit_cube(),
        Mesh::trunk(),
        Mesh::leaf(),
        star_prism(),
        open_box(),
        open_star(),
        wavy_sheet(),
        crossing_cubes(),
    ]
}

fn shape_meshes(meshes: &[Mesh]) -> ShapeMeshes {
    let names = (0..meshes.len())
        .map(|i| Cow::Owned(format!("shape{i}")))
        .collect();
    ShapeMeshes::new(names, meshes.to_vec()).unwrap()
}

/// Möller–Trumbore: the ray parameter where `o + t d` hits `tri`.
fn hit(tri: [DVec3; 3], o: DVec3, d: DVec3) -> Option<f64> {
    let (e1, e2) = (tri[1] - tri[0], tri[2] - tri[0]);
    let p = d.cross(e2);
    let det = e1.dot(p);
    if det.abs() < 1e-300 {
        return None;
    }
    let inv = 1.0 / det;
    let s = o - tri[0];
    let u = s.dot(p) * inv;
    let q = s.cross(e1);
    let v = d.dot(q) * inv;
    if u < 0.0 || v < 0.0 || u + v > 1.0 {
        return None;
    }
    Some(e2.dot(q) * inv)
}

/// Every world triangle of `instances`.
fn world_triangles(meshes: &[Mesh], instances: &[Instance]) -> Vec<[DVec3; 3]> {
    instances
        .iter()
        .flat_map(|inst| {
            let m = &meshes[inst.shape as usize];
            // In f64, as the renderer places them.
            let a = inst.transform;
            let place = move |p: Vec3| {
                let p = p.as_dvec3();
                a.matrix3.x_axis.as_dvec3() * p.x
                    + a.matrix3.y_axis.as_dvec3() * p.y
                    + a.matrix3.z_axis.as_dvec3() * p.z
                    + a.translation.as_dvec3()
            };
            m.triangles
                .iter()
                .map(move |t| t.map(|i| place(m.positions[i as usize])))
        })
        .collect()
}

fn covered_by_rasterizer(cam: &Camera, meshes: &[Mesh], instances: &[Instance]) -> Vec<bool> {
    let shapes: Vec<RasterShape> = meshes
        .iter()
        .map(|m| RasterShape::new("s", m).unwrap())
        .collect();
    let mut out = vec![false; (cam.width * cam.height) as usize];
    let mut rasterizer = Rasterizer::new();
    for inst in instances {
        rasterizer.spans(cam, &shapes[inst.shape as usize], &inst.transform, |s| {
            for c in s.c0..s.c1 {
                out[(s.row * cam.width + c) as usize] = true;
            }
        });
    }
    out
}

/// Pixels whose depth differs from ray casting (ignoring pixels where two
/// surfaces are within `1e-7` of each other or the ray grazes an edge).
fn depth_mismatches(cam: &Camera, g: &GBuffer, tris: &[[DVec3; 3]]) -> Vec<(usize, f64, f64)> {
    let mut bad = Vec::new();
    for r in 0..cam.height {
        for c in 0..cam.width {
            let i = (r * cam.width + c) as usize;
            let Some(depth) = g.depth(i) else { continue };
            let (o, d) = cam.pixel_ray(c, r);
            let mut hits: Vec<f64> = tris
                .iter()
                .filter_map(|t| hit(*t, o, d))
                .map(|t| cam.forward.dot(o + t * d - cam.eye))
                .filter(|z| *z >= cam.near && *z <= cam.far)
                .collect();
            hits.sort_by(f64::total_cmp);
            let Some(&nearest) = hits.first() else {
                continue; // an edge tie the two rules break differently
            };
            if hits
                .get(1)
                .is_some_and(|z| z - nearest < 1e-7 * z.abs().max(1.0))
            {
                continue;
            }
            if (depth - nearest).abs() > 1e-9 * nearest.abs().max(1.0) {
                bad.push((i, depth, nearest));
            }
        }
    }
    bad
}

/// The G-buffer of `instances` seen by `cam` covers exactly the
/// rasterizer's pixels with the ray-cast depths.
fn check_exact(cam: &Camera, meshes: &[Mesh], instances: &[Instance]) -> Result<(), TestCaseError> {
    let prepared = RenderMeshes::new(&shape_meshes(meshes)).unwrap();
    let mut renderer = Renderer::new();
    let g = renderer.render(&prepared, instances, cam);
    let expected = covered_by_rasterizer(cam, meshes, instances);
    let differ = (0..expected.len())
        .filter(|&i| g.covered(i) != expected[i])
        .count();
    prop_assert_eq!(
        differ,
        0,
        "{} pixels differ from the rasterizer's coverage",
        differ
    );
    let bad = depth_mismatches(cam, g, &world_triangles(meshes, instances));
    prop_assert!(
        bad.is_empty(),
        "{} depths differ, e.g. {:?}",
        bad.len(),
        &bad[..bad.len().min(3)]
    );
    // Visible pixels per face add up to the covered pixels.
    let visible: u64 = g.terminal_pixels().iter().sum();
    prop_assert_eq!(visible as usize, g.covered_pixels());
    for f in g.faces() {
        prop_assert!(f.visible <= f.drawn);
        prop_assert!((f.normal.length() - 1.0).abs() < 1e-5);
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 128, ..ProptestConfig::default() })]

    /// The covered pixels are exactly the silhouette rasterizer's, and the
    /// depth at each pixel centre is the nearest surface's by ray casting.
    #[test]
    fn gbuffer_coverage_and_depth_are_exact(cam in camera(), placements in proptest::collection::vec((placement(0.2..2.0, Vec3::splat(-2.0), Vec3::splat(2.0)), 0u16..8), 1..5)) {
        let instances: Vec<Instance> = placements.iter().map(|&(transform, shape)| Instance::new(shape, transform)).collect();
        check_exact(&cam, &meshes(), &instances)?;
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, ..ProptestConfig::default() })]

    /// A model's bounding sphere, fitted to its meshes' hull vertices, holds
    /// every placed vertex (however the instances are stretched) and is
    /// within 10 % of the same construction over every vertex (both are a
    /// heuristic that the points given steer; 2,000 cases saw at most
    /// 5.9 %, and a later run found one of 6.3 %, kept in the regressions).
    #[test]
    fn bounding_spheres_hold_every_vertex(placements in proptest::collection::vec((placement(0.05..3.0, Vec3::splat(-4.0), Vec3::splat(4.0)), 0u16..8), 1..40)) {
        let meshes = meshes();
        let prepared = RenderMeshes::new(&shape_meshes(&meshes)).unwrap();
        let instances: Vec<Instance> = placements.iter().map(|&(transform, shape)| Instance::new(shape, transform)).collect();
        let sphere = prepared.bounding_sphere(&instances).unwrap();
        let points: Vec<DVec3> = world_triangles(&meshes, &instances).into_iter().flatten().collect();
        for p in &points {
            let d = p.distance(sphere.center);
            prop_assert!(d <= sphere.radius * (1.0 + 1e-12), "{p} is {d} from the centre, radius {}", sphere.radius);
        }
        let reference = BoundingSphere::of(&points).unwrap();
        prop_assert!(sphere.radius <= reference.radius * 1.10, "{} against {} over every vertex", sphere.radius, reference.radius);
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 32, ..ProptestConfig::default() })]

    /// Many instances crowded together and seen by fitted cameras (nothing
    /// cut by the depth range, most triangles hidden, so the occlusion test
    /// skips triangles and instances): still exactly the rasterizer's
    /// coverage and the ray-cast depth.
    #[test]
    fn crowded_scenes_stay_exact(azimuth in -3.2f64..3.2, elevation in -1.2f64..1.2, ortho in any::<bool>(), placements in proptest::collection::vec((placement(0.3..1.5, Vec3::splat(-0.8), Vec3::splat(0.8)), 0u16..8), 10..30)) {
        let meshes = meshes();
        let prepared = RenderMeshes::new(&shape_meshes(&meshes)).unwrap();
        let instances: Vec<Instance> = placements.iter().map(|&(transform, shape)| Instance::new(shape, transform)).collect();
        let sphere = prepared.bounding_sphere(&instances).unwrap();
        let dir = BoundingSphere::direction(azimuth, elevation);
        let cam = if ortho {
            fit_orthographic(&sphere, dir, (96, 80)).unwrap()
        } else {
            fit_camera(&sphere, dir, 0.8, (96, 80)).unwrap()
        };
        check_exact(&cam, &meshes, &instances)?;
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, ..ProptestConfig::default() })]

    /// Back faces are skipped only where that changes nothing: mirrored
    /// instances (which turn a mesh's winding inside out) and open meshes
    /// (whose holes show back faces) give the rasterizer's coverage, the
    /// ray-cast depth, and the same depth and terminal per pixel as drawing
    /// every face.
    #[test]
    fn skipping_back_faces_changes_no_pixel(cam in camera(), placements in proptest::collection::vec((placement(0.2..2.0, Vec3::splat(-2.0), Vec3::splat(2.0)), 0u16..8, 0usize..4), 1..5)) {
        let meshes = meshes();
        let instances: Vec<Instance> = placements
            .iter()
            .map(|&(transform, shape, mirror)| {
                let mut flip = Vec3::ONE;
                if mirror < 3 {
                    flip[mirror] = -1.0;
                }
                Instance::new(shape, transform * Affine3A::from_scale(flip))
            })
            .collect();
        check_exact(&cam, &meshes, &instances)?;
        let prepared = RenderMeshes::new(&shape_meshes(&meshes)).unwrap();
        let mut fast = Renderer::new();
        let mut all = Renderer::new().drawing_all_faces();
        let (g, h) = (fast.render(&prepared, &instances, &cam), all.render(&prepared, &instances, &cam));
        // Not the number of faces drawn: drawing a back face first can let
        // the occlusion test skip a front face behind it, so drawing every
        // face may draw fewer (a concave star, seen in CI).
        for i in 0..g.len() {
            prop_assert_eq!(g.depth(i), h.depth(i), "pixel {}", i);
            prop_assert_eq!(g.terminal(i), h.terminal(i), "pixel {}", i);
        }
        prop_assert_eq!(g.terminal_pixels(), h.terminal_pixels());
        // Faces may be summed in another order: equal up to rounding.
        for (a, b) in g.visible_area().iter().zip(h.visible_area()) {
            prop_assert!((a - b).abs() <= 1e-9 * (1.0 + b.abs()), "visible area {} != {}", a, b);
        }
    }
}

/// Closed meshes (the cube, the star prism) and the open box skip their
/// back faces, an open sheet does not (it bounds nothing), crossing cubes
/// the faces the other cube does not cut; a cube seen from outside draws
/// only the faces toward the eye.
#[test]
fn closed_meshes_draw_only_the_faces_toward_the_eye() {
    let all = RenderMeshes::new(&shape_meshes(&meshes())).unwrap();
    let skips: Vec<f64> = (0..8).map(|id| all.skippable_faces(id)).collect();
    // Cube, trunk, leaf, star prism, open box, open star, wavy sheet (the
    // fan capping its rim cuts 30 of its 128 faces; as its rim surrounds
    // it, its faces are skipped only where the rim is out of view),
    // crossing cubes (half their faces cut by the other).
    assert_eq!(skips, [1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 98.0 / 128.0, 0.5]);
    let meshes = [Mesh::unit_cube()];
    let prepared = RenderMeshes::new(&shape_meshes(&meshes)).unwrap();
    let cam = Camera::orbit(0.7, 0.5, 4.0, DVec3::ZERO, 0.9, 0.1, 10.0, (64, 64)).unwrap();
    let instances = [Instance::new(0, Affine3A::IDENTITY)];
    let fast = Renderer::new().render(&prepared, &instances, &cam).clone();
    let all = Renderer::new()
        .drawing_all_faces()
        .render(&prepared, &instances, &cam)
        .clone();
    assert_eq!(prepared.skippable_faces(0), 1.0);
    // Three sides are seen: six triangles, against all twelve.
    assert_eq!(fast.faces().len(), 6);
    assert_eq!(all.faces().len(), 12);
    assert_eq!(fast.coverage(), all.coverage());
}

/// A unit cube seen face on (orthographic): one face of area 1 visible, the
/// four side faces edge on (no pixels), the back face hidden.
#[test]
fn a_cube_face_on_shows_one_unit_of_area() {
    let meshes = [Mesh::unit_cube()];
    let prepared = RenderMeshes::new(&shape_meshes(&meshes)).unwrap();
    let cam = Camera::orthographic(
        DVec3::new(0.0, 0.0, -5.0),
        DVec3::Z,
        DVec3::Y,
        2.0,
        0.1,
        10.0,
        (40, 40),
    )
    .unwrap();
    let instances = [Instance::new(0, Affine3A::IDENTITY)];
    let mut renderer = Renderer::new();
    let g = renderer.render(&prepared, &instances, &cam);
    // 1 of 2 units across 40 pixels: 20 × 20 pixels.
    assert_eq!(g.covered_pixels(), 400);
    let area = g.visible_area();
    assert!((area[0] - 1.0).abs() < 1e-12, "{area:?}");
    // The depth is the front face's: eye at z = −5, face at z = −0.5.
    let i = (20 * 40 + 20) as usize;
    assert!((g.depth(i).unwrap() - 4.5).abs() < 1e-12);
    // Its normal faces the camera.
    assert!((g.normal(i).unwrap() - Vec3::NEG_Z).length() < 1e-6);
}

/// The bounding sphere holds every point and is near-minimal on points
/// spread over a known sphere; the fitted cameras show it whole and large.
#[test]
fn fitted_cameras_frame_the_bounding_sphere() {
    let mut rng = shapegen_core::rng::stream(5, &[]);
    use rand::RngExt;
    for case in 0..20 {
        let c = DVec3::new(
            rng.random_range(-5.0..5.0),
            rng.random_range(-5.0..5.0),
            rng.random_range(-5.0..5.0),
        );
        let r = rng.random_range(0.1..10.0);
        let mut points: Vec<DVec3> = (0..400)
            .map(|_| {
                let v = DVec3::new(
                    rng.random_range(-1.0..1.0),
                    rng.random_range(-1.0..1.0),
                    rng.random_range(-1.0..1.0),
                );
                c + r * v.normalize_or(DVec3::X)
            })
            .collect();
        // Interior points do not change the minimal sphere.
        points.extend((0..100).map(|k| c + r * 0.5 * DVec3::splat(f64::from(k) / 100.0 - 0.5)));
        let s = BoundingSphere::of(&points).unwrap();
        for p in &points {
            assert!(
                p.distance(s.center) <= s.radius * (1.0 + 1e-12),
                "case {case}"
            );
        }
        assert!(s.radius <= 1.05 * r, "case {case}: {} vs {r}", s.radius);
    }
    // A cube: its sphere's projection fills the image across; the cube's
    // picture is well inside and large.
    let meshes = [Mesh::unit_cube()];
    let prepared = RenderMeshes::new(&shape_meshes(&meshes)).unwrap();
    let instances = [Instance {
        shape: 0,
        node: 0,
        transform: Affine3A::from_translation(Vec3::new(3.0, 1.0, -2.0)),
    }];
    let sphere = prepared.bounding_sphere(&instances).unwrap();
    assert!((sphere.radius - 3f64.sqrt() / 2.0).abs() < 0.01 * sphere.radius);
    for cam in [
        fit_camera(
            &sphere,
            BoundingSphere::direction(0.7, 0.4),
            40f64.to_radians(),
            (120, 80),
        )
        .unwrap(),
        fit_orthographic(&sphere, BoundingSphere::direction(-2.0, 0.2), (80, 120)).unwrap(),
    ] {
        let mut renderer = Renderer::new();
        let g = renderer.render(&prepared, &instances, &cam);
        let (w, h) = (cam.width as usize, cam.height as usize);
        let (mut lo, mut hi) = ((usize::MAX, usize::MAX), (0, 0));
        for i in (0..g.len()).filter(|&i| g.covered(i)) {
            let (x, y) = (i % w, i / w);
            lo = (lo.0.min(x), lo.1.min(y));
            hi = (hi.0.max(x), hi.1.max(y));
        }
        // Inside the image with a margin, and at least half the narrow side.
        assert!(
            lo.0 > 0 && lo.1 > 0 && hi.0 < w - 1 && hi.1 < h - 1,
            "{lo:?} {hi:?}"
        );
        let narrow = w.min(h);
        assert!(
            hi.0 - lo.0 >= narrow / 2 || hi.1 - lo.1 >= narrow / 2,
            "{lo:?} {hi:?}"
        );
    }
}

/// Pictures: the background is white or transparent, the model's pixels
/// opaque and coloured; supersampling blends the edges; more light on a
/// face turned to the key light.
#[test]
fn pictures_are_lit_supersampled_and_optionally_transparent() {
    use shapegen_score::{Background, Style};
    let meshes = [Mesh::unit_cube()];
    let prepared = RenderMeshes::new(&shape_meshes(&meshes)).unwrap();
    let instances = [Instance::new(0, Affine3A::from_rotation_y(0.6))];
    let sphere = prepared.bounding_sphere(&instances).unwrap();
    let cam = fit_camera(&sphere, BoundingSphere::direction(0.3, 0.5), 0.7, (64, 64)).unwrap();
    let mut renderer = Renderer::new();
    let coverage = renderer.render(&prepared, &instances, &cam).coverage();
    let clear = Style {
        background: Background::Transparent,
        supersample: 1,
        ..Style::default()
    };
    let img = renderer.picture(&prepared, &instances, &cam, &clear);
    assert_eq!(img.dimensions(), (64, 64));
    for (i, p) in img.pixels().enumerate() {
        assert_eq!(p[3], if coverage[i] { 255 } else { 0 }, "pixel {i}");
    }
    let white = renderer.picture(&prepared, &instances, &cam, &Style::default());
    let corner = white.get_pixel(0, 0);
    assert_eq!(corner.0, [255, 255, 255, 255]);
    // Supersampled: some edge pixels are between background and model.
    let smooth = Style {
        background: Background::Transparent,
        ..Style::default()
    };
    let img = renderer.picture(&prepared, &instances, &cam, &smooth);
    assert!(img.pixels().any(|p| p[3] > 0 && p[3] < 255));
    // Three faces show, with three different intensities.
    let mut shades: Vec<[u8; 3]> = white
        .pixels()
        .filter(|p| p.0 != [255; 4])
        .map(|p| [p[0], p[1], p[2]])
        .collect();
    shades.sort_unstable();
    shades.dedup();
    assert!(shades.len() >= 3, "{shades:?}");
}

/// Every mesh of `../shared/data/{models,paper}` (real, often
/// self-intersecting: the paper's leaf) seen from eight fitted cameras:
/// the faces skipped change no pixel's coverage, depth or terminal.
#[test]
fn shared_meshes_render_the_same_with_faces_skipped() {
    let root = std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../shared/data");
    let mut paths: Vec<_> = ["models", "paper"]
        .iter()
        .filter_map(|d| std::fs::read_dir(root.join(d)).ok())
        .flat_map(|e| e.flatten().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|e| e == "obj"))
        .collect();
    paths.sort();
    if paths.is_empty() {
        eprintln!("skipping: ../shared/data is not there");
        return;
    }
    for path in paths {
        let mesh = Mesh::load_obj(&path).unwrap().normalized();
        let meshes = [mesh];
        let prepared = RenderMeshes::new(&shape_meshes(&meshes)).unwrap();
        eprintln!(
            "{}: {} triangles, {:.0}% of faces skippable",
            path.display(),
            meshes[0].triangles.len(),
            100.0 * prepared.skippable_faces(0)
        );
        let instances = [Instance::new(0, Affine3A::IDENTITY)];
        let sphere = prepared.bounding_sphere(&instances).unwrap();
        let (mut fast, mut all) = (Renderer::new(), Renderer::new().drawing_all_faces());
        for k in 0..8 {
            let dir = BoundingSphere::direction(0.8 * k as f64, 0.9 * ((k % 3) as f64 - 1.0));
            let cam = if k % 2 == 0 {
                fit_camera(&sphere, dir, 0.8, (96, 80)).unwrap()
            } else {
                fit_orthographic(&sphere, dir, (96, 80)).unwrap()
            };
            let (g, h) = (
                fast.render(&prepared, &instances, &cam),
                all.render(&prepared, &instances, &cam),
            );
            let expected = covered_by_rasterizer(&cam, &meshes, &instances);
            for (i, &covered) in expected.iter().enumerate() {
                assert_eq!(
                    g.covered(i),
                    covered,
                    "{} view {k} pixel {i}",
                    path.display()
                );
                assert_eq!(
                    g.depth(i),
                    h.depth(i),
                    "{} view {k} pixel {i}",
                    path.display()
                );
                assert_eq!(g.terminal(i), h.terminal(i));
            }
        }
    }
}
