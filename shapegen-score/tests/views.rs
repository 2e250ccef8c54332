//! View attributes against hand-computed values, and best views on scenes
//! with a known answer.

use std::borrow::Cow;

use glam::{Affine3A, DVec3, Vec3};
use shapegen_core::express::Instance;
use shapegen_score::{
    AttributeWeights, Camera, Mesh, Palette, RenderMeshes, Renderer, Shading, ShapeMeshes, Style,
    ViewAttributes, ViewSampling, Viewpoint, best_view,
};

fn meshes(n: usize) -> RenderMeshes {
    let names = (0..n).map(|i| Cow::Owned(format!("part{i}"))).collect();
    RenderMeshes::new(&ShapeMeshes::new(names, vec![Mesh::unit_cube(); n]).unwrap()).unwrap()
}

fn close(a: f64, b: f64, what: &str) {
    assert!((a - b).abs() < 1e-9, "{what}: {a} vs {b}");
}

/// Two unit cubes of two terminal types side by side, seen face on by an
/// orthographic camera 4 units high on 40 × 40 pixels: two 10 × 10 squares
/// making one 20 × 10 rectangle. Every attribute by hand:
#[test]
fn attributes_of_two_squares_match_hand_computed_values() {
    let m = meshes(2);
    let cam = Camera::orthographic(
        DVec3::new(0.0, 0.0, -5.0),
        DVec3::Z,
        DVec3::Y,
        4.0,
        0.1,
        10.0,
        (40, 40),
    )
    .unwrap();
    let at = |x: f32, shape: u16| Instance {
        shape,
        node: 0,
        transform: Affine3A::from_translation(Vec3::new(x, 0.0, 0.0)),
    };
    let mut renderer = Renderer::new();
    let g = renderer.render(&m, &[at(-0.5, 0), at(0.5, 1)], &cam);
    let (red, blue) = ([200u8, 40, 40], [40u8, 40, 200]);
    let style = Style {
        shading: Shading::Flat,
        palette: Palette::Colors(vec![red, blue]),
        ..Style::fast()
    };
    let a = ViewAttributes::of(g, &m, &style);
    let (d, l) = (40.0f64, 40.0f64 / 2f64.sqrt());
    // a1: 200 pixels of the circle of diameter 40.
    close(
        a.pixel_count,
        200.0 / (std::f64::consts::PI / 4.0 * d * d),
        "a1",
    );
    // a2: two faces of 1 m² visible.
    close(a.surface, 3f64.ln() / 1e6f64.ln(), "a2");
    // a3: the rectangle's outline pixels, 2·20 + 2·8 = 56.
    close(a.silhouette, (56.0 / l).ln() / 16f64.ln(), "a3");
    // a4: half the pixels at each luminance: RMS = half the difference.
    let luma = |c: [u8; 3]| {
        (0.2126 * f64::from(c[0]) + 0.7152 * f64::from(c[1]) + 0.0722 * f64::from(c[2])) / 255.0
    };
    assert!((a.contrast - 0.5 * (luma(red) - luma(blue)).abs()).abs() < 1e-6);
    // a5: every normal faces the camera: neither left nor right.
    close(a.normal_balance, 0.5, "a5'");
    close(a.normal_ratio, 0.75, "a5");
    // a6: a box 10 high and 20 wide.
    let log = 0.5f64.ln() / l.ln();
    close(a.form, 1.0 - log.abs(), "a6");
    close(a.form_ratio, 0.5 * (log + 1.0), "a6'");
    // a7, a8: two terminal types, equal areas.
    close(a.terminal_types, 2f64.ln() / 100f64.ln(), "a7");
    close(a.terminal_entropy, 2f64.ln() / 100f64.ln(), "a8");
}

/// Turning the normals left raises a5' (more pixels pointing left).
#[test]
fn normals_turned_left_count_as_left() {
    let m = meshes(1);
    let cam = Camera::look_at(
        DVec3::new(0.0, 0.0, 6.0),
        DVec3::ZERO,
        DVec3::Y,
        0.6,
        0.1,
        20.0,
        (64, 64),
    )
    .unwrap();
    let mut renderer = Renderer::new();
    // A cube turned about +y shows two faces, of unequal sizes, one facing
    // left and one right; turned the other way, the mirror image.
    let turned = Instance::new(0, Affine3A::from_rotation_y(0.5));
    let a = ViewAttributes::of(renderer.render(&m, &[turned], &cam), &m, &Style::fast());
    let mirrored = Instance::new(0, Affine3A::from_rotation_y(-0.5));
    let b = ViewAttributes::of(renderer.render(&m, &[mirrored], &cam), &m, &Style::fast());
    // Mirror images: the balances add up to 1, and neither is ½.
    assert!(
        (a.normal_balance + b.normal_balance - 1.0).abs() < 0.05,
        "{a:?} {b:?}"
    );
    assert!((a.normal_balance - 0.5).abs() > 0.1);
}

/// Two towers (the thesis's Fig. 3.3): seen along the line through both,
/// one hides the other, and that view scores lowest; the best view shows both.
#[test]
fn the_view_hiding_one_tower_behind_the_other_scores_lowest() {
    let m = meshes(2);
    let tower = |x: f32, shape| Instance {
        shape,
        node: 0,
        transform: Affine3A::from_scale_rotation_translation(
            Vec3::new(1.0, 5.0, 1.0),
            glam::Quat::IDENTITY,
            Vec3::new(x, 2.5, 0.0),
        ),
    };
    // Each tower is of two terminal types: body and a cap on top.
    let cap = |x: f32| Instance {
        shape: 1,
        node: 0,
        transform: Affine3A::from_scale_rotation_translation(
            Vec3::new(0.6, 0.6, 0.6),
            glam::Quat::IDENTITY,
            Vec3::new(x, 5.3, 0.0),
        ),
    };
    let scene = [tower(-2.0, 0), tower(2.0, 0), cap(-2.0), cap(2.0)];
    let sampling = ViewSampling {
        azimuths: 32,
        elevations: vec![std::f64::consts::PI / 8.0],
        ..ViewSampling::default()
    };
    let mut renderer = Renderer::new();
    let best = best_view(
        &mut renderer,
        &m,
        &scene,
        &sampling,
        &AttributeWeights::BEST_VIEW,
        &Style::fast(),
    )
    .unwrap();
    let lowest = (0..best.scores.len())
        .min_by(|&a, &b| best.scores[a].total_cmp(&best.scores[b]))
        .unwrap();
    let along = |v: &Viewpoint| {
        let a = v.azimuth.rem_euclid(std::f64::consts::PI);
        a.min(std::f64::consts::PI - a)
    };
    // The towers stand on the x axis: azimuth 0 or π looks along it.
    assert!(
        along(&best.viewpoints[lowest]) < 1e-9,
        "lowest at azimuth {}",
        best.viewpoints[lowest].azimuth
    );
    // The best view sees both towers side by side (far from the axis).
    assert!(
        along(&best.viewpoint) > 0.5,
        "best at {}",
        best.viewpoint.azimuth
    );
    assert_eq!(best.scores.len(), 32);
}

#[test]
fn bad_samplings_and_weights_are_errors() {
    let m = meshes(1);
    let one = [Instance::new(0, Affine3A::IDENTITY)];
    let mut r = Renderer::new();
    let style = Style::fast();
    let w = AttributeWeights::BEST_VIEW;
    let none = ViewSampling {
        azimuths: 0,
        ..ViewSampling::default()
    };
    assert!(best_view(&mut r, &m, &one, &none, &w, &style).is_err());
    let steep = ViewSampling {
        elevations: vec![2.0],
        ..ViewSampling::default()
    };
    assert!(best_view(&mut r, &m, &one, &steep, &w, &style).is_err());
    let zero = AttributeWeights([0.0; 8]);
    assert!(best_view(&mut r, &m, &one, &ViewSampling::default(), &zero, &style).is_err());
    // Nothing to look at.
    assert!(best_view(&mut r, &m, &[], &ViewSampling::default(), &w, &style).is_err());
}
