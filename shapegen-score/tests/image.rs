//! Image targets: PNG sketches, counts against brute-force coverage, overlays.

use crate::common::{placement, shared};
use glam::{Affine3A, DVec3, Quat, Vec3};
use proptest::prelude::*;
use shapegen_score::Camera;
use shapegen_score::Mesh;
use shapegen_score::{ImageScratch, ImageTarget};
use shapegen_score::{RasterShape, reference::reference_coverage};

fn camera(w: u32, h: u32) -> Camera {
    Camera::orbit(
        -1.2,
        0.3,
        6.0,
        DVec3::ZERO,
        60f64.to_radians(),
        0.1,
        100.0,
        (w, h),
    )
    .unwrap()
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 48, ..ProptestConfig::default() })]

    /// G, B and the weight sum equal what the brute-force coverage gives,
    /// and a second model counted in the same scratch starts from nothing.
    /// Up to ten boxes, leaves and trunks of very different sizes, so that
    /// some are hidden behind the others. Two targets: weights of three
    /// values (counted by class) and of eleven (pixel by pixel, whose sum
    /// is then exactly the row-major one).
    #[test]
    fn counts_match_brute_force(instances in proptest::collection::vec((placement(0.1..2.5, Vec3::splat(-1.5), Vec3::splat(1.5)), 0usize..3), 1..10)) {
        let cam = camera(48, 36);
        // A checkerboard of attracting (+1), repelling (−2) and don't-care (0) pixels.
        let few: Vec<f32> = (0..48 * 36).map(|i| [1.0, -2.0, 0.0][(i / 5 + i / 48) % 3]).collect();
        // Eleven values from −1 to 1.5, not all sums of which are exact.
        let many: Vec<f32> = (0..48 * 36).map(|i| ((i * 37) % 11) as f32 * 0.25 - 1.0 + 0.1).collect();
        for (weights, by_pixel) in [(few, false), (many, true)] {
            let target = ImageTarget::new(cam, weights.clone()).unwrap();
            let shapes = [Mesh::unit_cube(), Mesh::leaf(), Mesh::trunk()].map(|m| RasterShape::new("shape", &m).unwrap());
            let placed: Vec<(&RasterShape, Affine3A)> = instances.iter().map(|(t, k)| (&shapes[*k], *t)).collect();
            let mut scratch = ImageScratch::new(std::slice::from_ref(&target));
            for round in 0..2 {
                let used = &placed[..placed.len() - round.min(placed.len() - 1)];
                scratch.begin();
                for (shape, t) in used {
                    scratch.add(std::slice::from_ref(&target), shape, t);
                }
                let c = scratch.counts_for(std::slice::from_ref(&target));
                let cover = reference_coverage(&cam, used);
                let good = cover.iter().zip(&weights).filter(|(c, w)| **c && **w > 0.0).count() as u64;
                let bad = cover.iter().zip(&weights).filter(|(c, w)| **c && **w < 0.0).count() as u64;
                let weight: f64 = cover.iter().zip(&weights).filter(|(c, _)| **c).map(|(_, w)| f64::from(*w)).sum();
                prop_assert_eq!((c.good, c.bad), (good, bad));
                if by_pixel {
                    // Pixel by pixel: the same additions in the same order.
                    prop_assert_eq!(c.weight, weight);
                } else {
                    prop_assert!((c.weight - weight).abs() < 1e-9);
                }
                prop_assert_eq!(scratch.covered(0), cover);
            }
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 48, ..ProptestConfig::default() })]

    /// Models made of instances seen before (the same shape and transform,
    /// in this model or an earlier one, as an optimizer's models are) count
    /// the same through the instance cache of `add_shape` as through `add`
    /// with a fresh scratch: one target, or two whose second camera has its
    /// near plane through the instances (clipped triangles take the other
    /// path of the rasterizer).
    #[test]
    fn cached_instances_count_as_fresh_ones(
        pool in proptest::collection::vec(placement(0.2..2.0, Vec3::splat(-1.5), Vec3::splat(1.5)), 1..5),
        models in proptest::collection::vec(proptest::collection::vec((0usize..8, 0usize..4), 1..6), 1..5),
        two in any::<bool>(),
    ) {
        let weights: Vec<f32> = (0..48 * 36).map(|i| [1.0, -2.0, 0.0][(i / 5 + i / 48) % 3]).collect();
        let near = Camera::orbit(0.7, 0.2, 6.0, DVec3::ZERO, 60f64.to_radians(), 5.6, 100.0, (40, 30)).unwrap();
        let mut targets = vec![ImageTarget::new(camera(48, 36), weights).unwrap()];
        if two {
            targets.push(ImageTarget::new(near, vec![1.0; 40 * 30]).unwrap());
        }
        // Two shapes drawn every time (8 and 16 vertices), two remembered
        // (32 and 48); the same transform on two shapes must not share an
        // entry.
        let shapes = [Mesh::unit_cube(), Mesh::leaf(), Mesh::trunk(), Mesh::frustum(24, 0.5, 0.1)]
            .map(|m| RasterShape::new("shape", &m).unwrap());
        let mut cached = ImageScratch::new(&targets);
        for model in &models {
            cached.begin();
            let mut fresh = ImageScratch::new(&targets);
            fresh.begin();
            for &(k, shape) in model {
                let t = &pool[k % pool.len()];
                cached.add_shape(&targets, shape as u16, &shapes[shape], t);
                fresh.add(&targets, &shapes[shape], t);
            }
            prop_assert_eq!(cached.counts_for(&targets), fresh.counts_for(&targets));
            for i in 0..targets.len() {
                prop_assert_eq!(cached.covered(i), fresh.covered(i));
            }
        }
    }
}

/// Instances inside, behind and overlapping others, and one off the image,
/// cover what brute force says in either order, and a model scored after
/// a bigger one starts from nothing.
#[test]
fn overlapping_instances_cover_their_union_in_any_order() {
    let cam = camera(48, 36);
    let target = ImageTarget::new(cam, vec![1.0; 48 * 36]).unwrap();
    let targets = std::slice::from_ref(&target);
    let cube = RasterShape::new("cube", &Mesh::unit_cube()).unwrap();
    let leaf = RasterShape::new("leaf", &Mesh::leaf()).unwrap();
    let at = |scale: f32, x: f32, y: f32, z: f32| {
        Affine3A::from_scale_rotation_translation(
            Vec3::splat(scale),
            Quat::from_rotation_y(0.4),
            Vec3::new(x, y, z),
        )
    };
    // A big box, then a small box and a leaf inside it, a leaf behind it
    // (seen from the camera), one peeking out at its side, and a leaf above
    // the image.
    let model = [
        (&cube, at(2.0, 0.0, 0.0, 0.0)),
        (&cube, at(0.3, 0.1, 0.2, 0.1)),
        (&leaf, at(0.5, 0.0, 0.0, 0.0)),
        (&leaf, at(0.5, -0.5, -0.4, 1.3)),
        (&leaf, at(1.0, 1.8, 0.0, 0.0)),
        (&leaf, at(1.0, 0.0, 8.0, 0.0)),
    ];
    let expected = reference_coverage(&cam, &model);
    let pixels = expected.iter().filter(|&&c| c).count() as u64;
    assert!(pixels > 0 && pixels < 48 * 36);
    let mut scratch = ImageScratch::new(targets);
    for order in [model.to_vec(), model.iter().rev().cloned().collect()] {
        scratch.begin();
        for (shape, t) in &order {
            scratch.add(targets, shape, t);
        }
        assert_eq!(scratch.covered(0), expected);
        assert_eq!(scratch.counts_for(targets).good, pixels);
    }
    // The small box alone, after the whole model.
    scratch.begin();
    scratch.add(targets, model[1].0, &model[1].1);
    assert_eq!(scratch.covered(0), reference_coverage(&cam, &model[1..2]));
}

#[test]
fn png_sketches_load_with_the_red_channel_rule() {
    let Some(path) = shared("data/paper/tree_target_sketch1.png") else {
        eprintln!("skipping: ../shared/data/paper/tree_target_sketch1.png is not there");
        return;
    };
    let t = ImageTarget::from_png(&path, camera(800, 600), 1.0, -1.0).unwrap();
    // The notes count 42,320 pixels with red = 0 (anti-aliased grey ones are not target).
    assert_eq!(t.target_pixels(), 42_320);
    let err = ImageTarget::from_png(&path, camera(640, 480), 1.0, -1.0)
        .unwrap_err()
        .to_string();
    assert!(err.contains("800×600") && err.contains("640×480"), "{err}");
}

#[test]
fn bad_images_are_clear_errors_and_overlays_round_trip() {
    let dir = std::env::temp_dir().join(format!("shapegen-image-test-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let garbage = dir.join("garbage.png");
    std::fs::write(&garbage, b"not a png at all").unwrap();
    let err = ImageTarget::from_png(&garbage, camera(8, 8), 1.0, -1.0)
        .unwrap_err()
        .to_string();
    assert!(err.contains("garbage.png"), "{err}");
    let missing = ImageTarget::from_png(&dir.join("missing.png"), camera(8, 8), 1.0, -1.0)
        .unwrap_err()
        .to_string();
    assert!(missing.contains("missing.png"), "{missing}");
    assert!(ImageTarget::new(camera(8, 8), vec![0.0; 63]).is_err());
    assert!(ImageTarget::new(camera(8, 8), vec![f32::NAN; 64]).is_err());
    // Overlay: target left half, model top half.
    let t = ImageTarget::new(
        camera(8, 8),
        (0..64)
            .map(|i| if i % 8 < 4 { 1.0 } else { -1.0 })
            .collect(),
    )
    .unwrap();
    let covered: Vec<bool> = (0..64).map(|i| i < 32).collect();
    let out = dir.join("overlay.png");
    t.write_overlay(&out, &covered).unwrap();
    let back = ImageTarget::from_png(&out, camera(8, 8), 1.0, 0.0).unwrap();
    // Red is 0 only for "both" (dark green): the top-left quarter.
    assert_eq!(back.target_pixels(), 16);
    std::fs::remove_dir_all(&dir).ok();
}

/// A 40×30 PNG: a disk of radius 8 at the centre drawn with `inside`, the
/// rest `outside` (RGBA).
fn disk_png(name: &str, inside: [u8; 4], outside: [u8; 4]) -> std::path::PathBuf {
    let path =
        std::env::temp_dir().join(format!("shapegen-mask-{name}-{}.png", std::process::id()));
    let img = image::RgbaImage::from_fn(40, 30, |c, r| {
        let (dx, dy) = (c as f32 + 0.5 - 20.0, r as f32 + 0.5 - 15.0);
        image::Rgba(if dx * dx + dy * dy < 64.0 {
            inside
        } else {
            outside
        })
    });
    img.save(&path).unwrap();
    path
}

/// Pixels of the disk of [`disk_png`].
fn disk_pixels() -> u64 {
    (0..40 * 30)
        .filter(|i| {
            let (dx, dy) = ((i % 40) as f32 + 0.5 - 20.0, (i / 40) as f32 + 0.5 - 15.0);
            dx * dx + dy * dy < 64.0
        })
        .count() as u64
}

#[test]
fn png_masks_read_transparency_and_shading() {
    use shapegen_score::PngMask;
    let cam = camera(40, 30);
    let masked =
        |path: &std::path::Path, mask| ImageTarget::from_png_masked(path, cam, mask, 1.0, -1.0);
    let dark = PngMask::Dark { threshold: 0.5 };
    let alpha = PngMask::Alpha { threshold: 0.5 };
    let alpha_dark = PngMask::AlphaDark { threshold: 0.5 };

    // Black strokes on a transparent *black* background: transparency is
    // read, so only the disk is target, never 100 %.
    let cutout = disk_png("cutout", [0, 0, 0, 255], [0, 0, 0, 0]);
    for mask in [PngMask::Red0, dark, alpha, alpha_dark] {
        let t = masked(&cutout, mask).unwrap();
        assert_eq!(t.target_pixels(), disk_pixels(), "{}", mask.name());
    }

    // A white shape on a transparent background: only opacity finds it.
    let white = disk_png("white", [255, 255, 255, 255], [0, 0, 0, 0]);
    assert_eq!(
        masked(&white, alpha).unwrap().target_pixels(),
        disk_pixels()
    );
    let err = masked(&white, dark).unwrap_err().to_string();
    assert!(err.contains("no pixel") && err.contains("alpha"), "{err}");

    // A shaded render (grey, red 120) on white: the paper's red-0 rule finds
    // nothing and says what to use; `dark` finds the model.
    let render = disk_png("render", [120, 110, 100, 255], [255, 255, 255, 255]);
    let err = masked(&render, PngMask::Red0).unwrap_err().to_string();
    assert!(
        err.contains("red0") && err.contains("no pixel") && err.contains("dark"),
        "{err}"
    );
    assert_eq!(
        masked(&render, dark).unwrap().target_pixels(),
        disk_pixels()
    );
    // Too low a threshold finds nothing either; opacity finds every pixel: both errors.
    assert!(masked(&render, PngMask::Dark { threshold: 0.1 }).is_err());
    let err = masked(&render, alpha).unwrap_err().to_string();
    assert!(err.contains("every pixel"), "{err}");

    // An image of another size names both sizes.
    let err = ImageTarget::from_png_masked(&render, camera(80, 60), dark, 1.0, -1.0)
        .unwrap_err()
        .to_string();
    assert!(err.contains("40×30") && err.contains("80×60"), "{err}");
    for p in [cutout, white, render] {
        std::fs::remove_file(p).ok();
    }
}

#[test]
fn quality_counts_pixels_of_the_model_and_the_target() {
    use shapegen_score::{ImageTargets, Quality};
    // An orthographic camera on −z: pixel (c, r) sees x = 10 − c − ½ (the
    // paper's mirrored handedness), y = 5 − r − ½, over 20 × 10 pixels.
    let cam = Camera::orthographic(
        DVec3::new(0.0, 0.0, -5.0),
        DVec3::Z,
        DVec3::Y,
        10.0,
        0.1,
        20.0,
        (20, 10),
    )
    .unwrap();
    // Target: the left half of the image (100 pixels).
    let weights = (0..200)
        .map(|i| if i % 20 < 10 { 1.0 } else { -1.0 })
        .collect();
    let targets = ImageTargets::new(vec![ImageTarget::new(cam, weights).unwrap()]).unwrap();
    // Model: a 10 × 10 box covering the middle 10 columns (50 in the target).
    let shape = RasterShape::new("cube", &Mesh::unit_cube()).unwrap();
    let mut scratch = ImageScratch::new(targets.targets());
    scratch.begin();
    scratch.add(
        targets.targets(),
        &shape,
        &Affine3A::from_scale(Vec3::new(10.0, 10.0, 1.0)),
    );
    let q = targets.quality(&scratch);
    assert_eq!(q, vec![Quality::from_counts(50, 100, 100)]);
    assert!((q[0].iou - 1.0 / 3.0).abs() < 1e-12);
}
