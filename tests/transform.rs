//! Design transformations: exact endpoints, a design transformed into
//! itself, valid shapes at every time, connected trees, determinism.

use proptest::prelude::*;
use rand::RngExt;
use shapegen::express::{Generator, Instance};
use shapegen::glam::{Affine3A, Vec3};
use shapegen::prelude::*;
use shapegen::rng::stream;
use shapegen::scenes::{
    Apartments, Castle, ClassicFacade, Farm, GridCity, Houses, ModernFacade, MonopodialTree,
    SpaceFillingCity, Spaceship, SympodialTree, TreeV1, TreeV2,
};
use shapegen::transform::{
    Blend, Design, Mixing, Mode, PairingMethod, Pivot, Placed, Settings, Transformation, Variety,
};

/// A random derivation: a random individual changed by random operators.
fn random_chromosome(graph: &Graph, seed: u64) -> Chromosome {
    let mut rng = stream(seed, &[]);
    let init = InitLength::Between { lo: 1, hi: 80 };
    let mut c = random_individual(graph, &init, &mut rng).unwrap();
    for _ in 0..rng.random_range(0..20) {
        match rng.random_range(0..3) {
            0 => drop(grow(graph, &mut c, &mut rng)),
            1 => drop(cut(graph, &mut c, &mut rng)),
            _ => drop(alter(graph, &mut c, &mut rng)),
        }
    }
    c
}

fn design<G>(g: G, seed: u64) -> Design
where
    G: Generator + Send + 'static,
    G::State: Blend,
{
    let c = random_chromosome(g.graph(), seed);
    Design::new(g, c).unwrap()
}

/// Instances as sortable rows: shape, then the transform's 12 numbers.
fn rows(shapes: impl Iterator<Item = (u16, Affine3A)>) -> Vec<(u16, [f32; 12])> {
    let mut v: Vec<_> = shapes.map(|(s, t)| (s, t.to_cols_array())).collect();
    v.sort_by(|a, b| a.partial_cmp(b).unwrap());
    v
}

fn placed_rows(p: &[Placed]) -> Vec<(u16, [f32; 12])> {
    rows(p.iter().map(|p| (p.shape, p.transform)))
}

/// A design's own instances, in the transformation's shape numbering.
fn own_rows(t: &Transformation, d: &Design) -> Vec<(u16, [f32; 12])> {
    let names = d.shapes();
    rows(d.express().iter().map(|i: &Instance| {
        let name = &names[i.shape as usize];
        let id = t.shapes().iter().position(|s| s == name).unwrap() as u16;
        (id, i.transform)
    }))
}

/// The same instances up to round-off (1e-5 of the largest entry): each
/// of `a` has its own close match in `b`. (Sorting both and comparing in
/// order is not enough: entries that differ in the last bits, as two
/// equal lengths computed two ways do, can swap the order of rows.)
fn close(a: &[(u16, [f32; 12])], b: &[(u16, [f32; 12])]) -> Result<(), TestCaseError> {
    prop_assert_eq!(a.len(), b.len());
    let near = |x: &(u16, [f32; 12]), y: &(u16, [f32; 12])| {
        let scale = x.1.iter().fold(1.0f32, |m, v| m.max(v.abs()));
        x.0 == y.0
            && x.1
                .iter()
                .zip(&y.1)
                .all(|(p, q)| (p - q).abs() <= 1e-5 * scale)
    };
    let mut used = vec![false; b.len()];
    for x in a {
        let found = (0..b.len()).find(|&j| !used[j] && near(x, &b[j]));
        prop_assert!(found.is_some(), "{:?} has no match", x);
        used[found.unwrap_or_default()] = true;
    }
    Ok(())
}

/// Checks that a façade's walls, pillars, ledges and window frames
/// (everything but the panes in front) tile the rectangle they span on
/// the xy plane, with no gap (a 40 × 20 grid of points) and no overlap
/// (their areas add up to its area); returns its width and height.
fn tiled(
    names: &[std::borrow::Cow<'static, str>],
    shapes: &[Placed],
) -> Result<Vec3, TestCaseError> {
    let pane = names.iter().position(|s| s == "window").map(|i| i as u16);
    let boxes: Vec<Affine3A> = shapes
        .iter()
        .filter(|p| Some(p.shape) != pane)
        .map(|p| p.transform)
        .collect();
    let half = |b: &Affine3A| Vec3::new(b.matrix3.x_axis.x, b.matrix3.y_axis.y, 0.0).abs() * 0.5;
    let (mut lo, mut hi) = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
    for b in &boxes {
        let c = Vec3::from(b.translation);
        lo = lo.min(c - half(b));
        hi = hi.max(c + half(b));
    }
    let e = hi - lo;
    let area: f32 = boxes.iter().map(|b| 4.0 * half(b).x * half(b).y).sum();
    prop_assert!(
        (area - e.x * e.y).abs() <= 1e-3 * e.x * e.y,
        "area {} of a {} x {} façade",
        area,
        e.x,
        e.y
    );
    for i in 0..40 {
        for j in 0..20 {
            let p = Vec3::new(
                lo.x + e.x * (i as f32 + 0.5) / 40.0,
                lo.y + e.y * (j as f32 + 0.5) / 20.0,
                0.0,
            );
            let covered = boxes.iter().any(|b| {
                let (c, h) = (Vec3::from(b.translation), half(b));
                (p.x - c.x).abs() <= h.x + 1e-4 && (p.y - c.y).abs() <= h.y + 1e-4
            });
            prop_assert!(
                covered,
                "({}, {}) of a {} x {} façade is bare",
                p.x,
                p.y,
                e.x,
                e.y
            );
        }
    }
    Ok(e)
}

fn settings(k: u8) -> Settings {
    Settings {
        pairing: if k & 1 == 0 {
            PairingMethod::Munkres
        } else {
            PairingMethod::MutualNearest
        },
        mode: if k & 2 == 0 { Mode::Grow } else { Mode::Thesis },
        pivot: if k & 4 == 0 {
            Pivot::Centre
        } else {
            Pivot::Base
        },
        merge: false,
    }
}

fn endpoints_and_validity(a: Design, b: Design, k: u8, t: f32) -> Result<(), TestCaseError> {
    let tr = Transformation::new(a.clone(), b.clone()).with_settings(settings(k));
    close(&placed_rows(&tr.at(0.0)), &own_rows(&tr, &a))?;
    close(&placed_rows(&tr.at(1.0)), &own_rows(&tr, &b))?;
    for p in tr.at(t) {
        let (s, r, x) = p.transform.to_scale_rotation_translation();
        prop_assert!(s.is_finite() && r.is_finite() && x.is_finite(), "{:?}", p);
        prop_assert!(s.min_element() >= 0.0, "negative size {:?}", p);
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 48, ..ProptestConfig::default() })]

    #[test]
    fn endpoints_are_the_designs_tree_pair(sa: u64, sb: u64, k in 0u8..8, t in 0.0f32..1.0) {
        endpoints_and_validity(design(MonopodialTree, sa), design(SympodialTree, sb), k, t)?;
    }

    #[test]
    fn endpoints_are_the_designs_trees_v1_v2(sa: u64, sb: u64, k in 0u8..8, t in 0.0f32..1.0) {
        endpoints_and_validity(design(TreeV1, sa), design(TreeV2, sb), k, t)?;
    }

    #[test]
    fn endpoints_are_the_designs_spaceships(sa: u64, sb: u64, k in 0u8..8, t in 0.0f32..1.0) {
        endpoints_and_validity(design(Spaceship, sa), design(Spaceship, sb), k, t)?;
    }

    #[test]
    fn endpoints_are_the_designs_cities(sa: u64, sb: u64, k in 0u8..8, t in 0.0f32..1.0) {
        endpoints_and_validity(design(SpaceFillingCity, sa), design(GridCity, sb), k, t)?;
    }

    #[test]
    fn endpoints_are_the_designs_facades(sa: u64, sb: u64, k in 0u8..8, t in 0.0f32..1.0) {
        endpoints_and_validity(design(ClassicFacade, sa), design(ModernFacade, sb), k, t)?;
    }

    #[test]
    fn endpoints_are_the_designs_farm_castle(sa: u64, sb: u64, k in 0u8..8, t in 0.0f32..1.0) {
        endpoints_and_validity(design(Farm, sa), design(Castle, sb), k, t)?;
    }

    /// Merged split rules partition the shape they split: the façade's
    /// walls, pillars, ledges and window frames (everything but the panes
    /// in front) tile the blended façade without gap or overlap.
    #[test]
    fn merged_facades_tile_the_facade(sa: u64, sb: u64, swap: bool, t in 0.0f32..1.0) {
        let sample = |g: &dyn Fn(u64) -> Design, seed| g(seed);
        let classic = |seed| {
            let c = uncontrolled(ClassicFacade.graph(), &mut stream(seed, &[])).unwrap();
            Design::new(ClassicFacade, c).unwrap()
        };
        let modern = |seed| {
            let c = uncontrolled(ModernFacade.graph(), &mut stream(seed, &[])).unwrap();
            Design::new(ModernFacade, c).unwrap()
        };
        let (a, b) = if swap {
            (sample(&modern, sa), sample(&classic, sb))
        } else {
            (sample(&classic, sa), sample(&modern, sb))
        };
        let tr = Transformation::new(a, b);
        // The façade's width and height at each end, from its shapes.
        let (ea, eb) = (tiled(tr.shapes(), &tr.at(0.0))?, tiled(tr.shapes(), &tr.at(1.0))?);
        let (w, h) = (ea.x + (eb.x - ea.x) * t, ea.y + (eb.y - ea.y) * t);
        let e = tiled(tr.shapes(), &tr.at(t))?;
        prop_assert!((e.x - w).abs() <= 1e-3 * w && (e.y - h).abs() <= 1e-3 * h, "{} x {} façade, expected {} x {}", e.x, e.y, w, h);
    }

    /// Variations of four façades are made of merged splits: each tiles
    /// its façade; the same seed gives the same variation.
    #[test]
    fn facade_variations_tile_their_facades(seeds in prop::array::uniform4(any::<u64>()), seed: u64, switch: bool) {
        let designs: Vec<Design> = seeds
            .iter()
            .enumerate()
            .map(|(k, &s)| {
                let mut rng = stream(s, &[]);
                if k % 2 == 0 {
                    Design::new(ClassicFacade, uncontrolled(ClassicFacade.graph(), &mut rng).unwrap()).unwrap()
                } else {
                    Design::new(ModernFacade, uncontrolled(ModernFacade.graph(), &mut rng).unwrap()).unwrap()
                }
            })
            .collect();
        let variety = Variety::new(designs).unwrap();
        let mixing = if switch { Mixing::Switch } else { Mixing::Blend };
        let v = variety.variation(seed, mixing);
        tiled(variety.shapes(), &v)?;
        prop_assert_eq!(v, variety.variation(seed, mixing));
    }

    /// Variations of farms and castles place valid shapes only.
    #[test]
    fn building_variations_are_valid(seeds in prop::array::uniform4(any::<u64>()), seed: u64, switch: bool) {
        let designs: Vec<Design> = seeds
            .iter()
            .enumerate()
            .map(|(k, &s)| if k % 2 == 0 { design(Farm, s) } else { design(Castle, s) })
            .collect();
        let variety = Variety::new(designs).unwrap();
        let v = variety.variation(seed, if switch { Mixing::Switch } else { Mixing::Blend });
        for p in &v {
            let (sc, r, x) = p.transform.to_scale_rotation_translation();
            prop_assert!(sc.is_finite() && r.is_finite() && x.is_finite(), "{:?}", p);
            prop_assert!((p.shape as usize) < variety.shapes().len());
        }
    }

    #[test]
    fn a_design_into_itself_is_itself(s: u64, which in 0u8..5, k in 0u8..8, t in 0.0f32..1.0) {
        let d = match which {
            0 => design(MonopodialTree, s),
            1 => design(TreeV2, s),
            2 => design(Spaceship, s),
            3 => design(ClassicFacade, s),
            _ => design(GridCity, s),
        };
        let tr = Transformation::new(d.clone(), d.clone()).with_settings(settings(k));
        close(&placed_rows(&tr.at(t)), &own_rows(&tr, &d))?;
    }

    /// Turtle trees blended about their attachment points stay connected:
    /// every segment starts at the tip of another (or on the ground).
    #[test]
    fn tree_pair_stays_connected(sa: u64, sb: u64, pairing in 0u8..2, grow: bool, t in 0.0f32..1.0) {
        let mut s = settings(pairing);
        s.pivot = Pivot::Base;
        s.mode = if grow { Mode::Grow } else { Mode::Thesis };
        let tr = Transformation::new(design(MonopodialTree, sa), design(SympodialTree, sb))
            .with_settings(s);
        let shapes = tr.at(t);
        let tips: Vec<Vec3> = shapes
            .iter()
            .map(|p| p.transform.transform_point3(Vec3::new(0.0, 0.5, 0.0)))
            .collect();
        for p in &shapes {
            let base = p.transform.transform_point3(Vec3::new(0.0, -0.5, 0.0));
            let length = p.transform.transform_vector3(Vec3::Y).length();
            // 1e-4 of the length, and f32 round-off for segments faded to
            // almost nothing (coordinates are about 1, their ulp 1e-7).
            let tol = 1e-4 * length + 1e-6;
            let on_ground = base.length() <= tol;
            let attached = tips.iter().any(|tip| tip.distance(base) <= tol);
            prop_assert!(on_ground || attached, "segment at {base} of length {length} hangs free");
        }
    }
}

#[test]
fn the_default_tree_pair_blends_every_segment() {
    let a = Design::default_model(MonopodialTree).unwrap();
    let b = Design::default_model(SympodialTree).unwrap();
    assert_eq!(a.express().len(), 511);
    assert_eq!(b.express().len(), 511);
    let tr = Transformation::new(a, b).with_settings(Settings {
        pivot: Pivot::Base,
        ..Settings::default()
    });
    let half = tr.at(0.5);
    assert_eq!(half.len(), 511);
    assert!(
        half.iter()
            .all(|p| matches!(p.source, shapegen::transform::Source::Both(..)))
    );
    // Same inputs, same sequence.
    assert_eq!(tr.at(0.37), tr.at(0.37));
}

/// One-to-many matches (thesis Fig. 5.12): six houses into two blocks.
/// Every house blends toward a block, none vanishes; halfway the houses
/// bound for one block have merged; the end is the two blocks, each once.
#[test]
fn houses_merge_into_apartment_blocks() {
    let a = Design::default_model(Houses).unwrap();
    let b = Design::default_model(Apartments).unwrap();
    let merged = Transformation::new(a.clone(), b.clone()).with_settings(Settings {
        merge: true,
        ..Settings::default()
    });
    assert_eq!(merged.at(0.0).len(), 12); // six houses and their roofs
    let end = merged.at(1.0);
    assert_eq!(end.len(), 2, "{end:?}");
    let own: Vec<Affine3A> = b.express().iter().map(|i| i.transform).collect();
    for p in &end {
        assert!(
            own.iter().any(|o| o.abs_diff_eq(p.transform, 1e-4)),
            "{p:?}"
        );
    }
    // Every house is on its way to a block: none is faded.
    let half = merged.at(0.6);
    assert!(
        half.iter()
            .all(|p| matches!(p.source, shapegen::transform::Source::Both(..)))
    );
    assert!(half.len() < 12, "nothing merged halfway: {}", half.len());
    // One-to-one, four houses have no block and shrink away instead.
    let one = Transformation::new(a, b);
    assert!(
        one.at(0.6)
            .iter()
            .any(|p| !matches!(p.source, shapegen::transform::Source::Both(..)))
    );
}

#[test]
fn unknown_names_in_matches_are_errors_that_name_them() {
    let mut tr = Transformation::new(
        Design::default_model(TreeV1).unwrap(),
        Design::default_model(TreeV2).unwrap(),
    );
    let e = tr.add_match("b", "Branch").unwrap_err().to_string();
    assert!(e.contains("`Branch`") && e.contains("b, n, m"), "{e}");
    let e = tr.remove_match("S", "S").unwrap_err().to_string();
    assert!(e.contains("start"), "{e}");
    let e = tr.remove_match("b", "T").unwrap_err().to_string();
    assert!(e.contains("not a semantic match"), "{e}");
    tr.remove_match("b", "n").unwrap();
    assert!(tr.matches().of(2, 3).is_none());
}

#[cfg(feature = "cli")]
mod command {
    use crate::util::{TempDir, json};
    use std::process::Command;

    fn shapegen(args: &[&str]) -> std::process::Output {
        Command::new(env!("CARGO_BIN_EXE_shapegen"))
            .args(args)
            .output()
            .unwrap()
    }

    #[test]
    fn writes_frames_sheet_gif_page_and_facts() {
        let dir = TempDir::new("transform", "files");
        let file = concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/transformations/tree_lsystems.toml"
        );
        let out = dir.join("out");
        let o = shapegen(&[
            "transform",
            file,
            "--frames",
            "5",
            "--obj",
            "-q",
            "--out",
            out.to_str().unwrap(),
        ]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        for f in [
            "frames/frame_000.png",
            "frames/frame_004.obj",
            "contact.png",
            "sequence.gif",
            "index.html",
        ] {
            assert!(out.join(f).is_file(), "{f}");
        }
        let facts = json(&out.join("sequence.json"));
        let frames = facts["frames"].as_array().unwrap();
        assert_eq!(frames.len(), 5);
        assert!(frames.iter().all(|f| f["instances"] == 511));
        let picture = image::open(out.join("frames/frame_002.png"))
            .unwrap()
            .to_rgba8();
        let inked = picture
            .pixels()
            .filter(|p| p.0[..3] != [255, 255, 255])
            .count();
        assert!(
            inked > 500,
            "the middle frame is nearly blank ({inked} pixels)"
        );
    }

    #[test]
    fn variations_write_pictures_a_gallery_and_seeds_that_reproduce_them() {
        let dir = TempDir::new("transform", "variations");
        let file = concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/transformations/building_variety.toml"
        );
        let run = |name: &str, threads: &str| {
            let out = dir.join(name);
            let o = Command::new(env!("CARGO_BIN_EXE_shapegen"))
                .env("RAYON_NUM_THREADS", threads)
                .args([
                    "transform",
                    file,
                    "--variations",
                    "6",
                    "--seed",
                    "9",
                    "--out",
                ])
                .arg(&out)
                .output()
                .unwrap();
            assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
            out
        };
        let (one, two) = (run("one", "1"), run("two", "2"));
        for f in [
            "variations/000.png",
            "variations/005.png",
            "variations.png",
            "gallery.png",
        ] {
            assert!(one.join(f).is_file(), "{f}");
        }
        let facts = json(&one.join("variations.json"));
        let list = facts["variations"].as_array().unwrap();
        assert_eq!(list.len(), 6);
        assert_eq!(list[5]["seed"], 14);
        assert_eq!(facts["designs"].as_array().unwrap().len(), 4);
        // The same seeds give the same variations whatever the thread count.
        assert_eq!(facts, json(&two.join("variations.json")));
        assert_eq!(
            std::fs::read(one.join("variations/003.png")).unwrap(),
            std::fs::read(two.join("variations/003.png")).unwrap()
        );
        // Zero variations is an error that names the flag.
        let lone = dir.join("lone.toml");
        std::fs::write(
            &lone,
            "[first]\ngenerator = \"farm\"\n[second]\ngenerator = \"farm\"\n",
        )
        .unwrap();
        let o = shapegen(&[
            "transform",
            lone.to_str().unwrap(),
            "--variations",
            "0",
            "--out",
            dir.join("x").to_str().unwrap(),
        ]);
        assert!(!o.status.success());
        assert!(
            String::from_utf8_lossy(&o.stderr).contains("--variations 0"),
            "{}",
            String::from_utf8_lossy(&o.stderr)
        );
    }

    #[test]
    fn mistakes_in_the_file_name_their_line() {
        let dir = TempDir::new("transform", "mistakes");
        let file = dir.join("t.toml");
        for (text, expected) in [
            (
                "[first]\ngenerator = \"tree_v1\"\n[second]\ngenerator = \"nope\"\n",
                ":4:13: `second.generator`: no generator `nope`",
            ),
            (
                "[first]\ngenerator = \"tree_v1\"\n[second]\ngenerator = \"tree_v2\"\n[matches]\nadd = [[\"b\", \"Branch\"]]\n",
                ":6:8: `matches.add`: the second generator has no node `Branch`",
            ),
            (
                "[first]\ngenerator = \"tree_v1\"\ncolour = 1\n[second]\ngenerator = \"tree_v2\"\n",
                ":3:1: `first.colour`: unknown field",
            ),
        ] {
            std::fs::write(&file, text).unwrap();
            let o = shapegen(&[
                "transform",
                file.to_str().unwrap(),
                "--out",
                dir.join("o").to_str().unwrap(),
            ]);
            let err = String::from_utf8_lossy(&o.stderr);
            assert!(!o.status.success());
            assert!(err.contains(expected), "{err}");
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 32, ..ProptestConfig::default() })]

    /// Partners are chosen once: between the endpoints, every t has the
    /// same shapes from the same sources (in grow mode, where nothing is
    /// dropped before the ends), only placed differently.
    #[test]
    fn no_shape_changes_partner_mid_sequence(sa: u64, sb: u64, t in 0.01f32..0.99, u in 0.01f32..0.99) {
        let tr = Transformation::new(design(TreeV1, sa), design(TreeV2, sb));
        let sources = |x: f32| {
            let mut v: Vec<String> = tr.at(x).iter().map(|p| format!("{:?}", p.source)).collect();
            v.sort();
            v
        };
        prop_assert_eq!(sources(t), sources(u));
    }
}

/// A timeline with start = end is a rule switch: the first design before
/// it, the second from it on; a later start holds the first design longer.
#[test]
fn timelines_switch_and_delay() {
    let a = Design::default_model(MonopodialTree).unwrap();
    let b = Design::default_model(SympodialTree).unwrap();
    let mut tr = Transformation::new(a.clone(), b.clone());
    tr.set_all_timelines(shapegen::transform::Timeline {
        start: 0.5,
        end: 0.5,
        threshold: 0.5,
    })
    .unwrap();
    close(&placed_rows(&tr.at(0.49)), &own_rows(&tr, &a)).unwrap();
    close(&placed_rows(&tr.at(0.5)), &own_rows(&tr, &b)).unwrap();
    let mut late = Transformation::new(a.clone(), b);
    late.set_all_timelines(shapegen::transform::Timeline {
        start: 0.6,
        end: 1.0,
        threshold: 0.8,
    })
    .unwrap();
    close(&placed_rows(&late.at(0.6)), &own_rows(&late, &a)).unwrap();
    assert_ne!(placed_rows(&late.at(0.8)), own_rows(&late, &a));
    let bad = shapegen::transform::Timeline {
        start: 0.9,
        end: 0.1,
        threshold: 0.5,
    };
    assert!(late.set_all_timelines(bad).is_err());
}
