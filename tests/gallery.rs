//! Thumbnail galleries: `shapegen gallery` as a user runs it (files,
//! links, the same result on any number of threads, clear errors), and the
//! library's clustering invariants.

use std::path::Path;
use std::process::Command;

use shapegen::experiment::Experiment;
use shapegen::gallery::{Gallery, GalleryOptions, Models, cluster};
use shapegen::prelude::*;
use shapegen::rng::stream;

use crate::util::{json, temp};

fn shapegen(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_shapegen"))
        .args(args)
        .output()
        .expect("the binary runs")
}

fn gallery(out: &Path, threads: &str) {
    let o = shapegen(&[
        "gallery",
        "--samples",
        "30",
        "--clusters",
        "6",
        "--thumbnail",
        "48",
        "--seed",
        "5",
        "--threads",
        threads,
        "-q",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
}

#[test]
fn the_gallery_command_writes_a_linked_page_the_same_on_any_thread_count() {
    let (one, two) = (temp("gallery", "one"), temp("gallery", "two"));
    gallery(&one, "1");
    gallery(&two, "2");
    for f in ["gallery.png", "gallery.json", "index.html"] {
        assert_eq!(
            std::fs::read(one.join(f)).unwrap(),
            std::fs::read(two.join(f)).unwrap(),
            "{f} differs between 1 and 2 threads"
        );
    }
    let doc = json(&one.join("gallery.json"));
    let models = doc["models"].as_array().unwrap();
    assert_eq!(models.len(), 31, "the default model and 30 samples");
    let clusters = doc["clusters"].as_array().unwrap();
    assert!(clusters.len() <= 6 && clusters.len() >= 2);
    let sizes: u64 = clusters.iter().map(|c| c["size"].as_u64().unwrap()).sum();
    assert_eq!(sizes, 31);
    let around = doc["around"].as_array().unwrap();
    assert!(!around.is_empty() && around.len() < clusters.len());
    // Every representative and the centre link existing files, which the page links too.
    let page = std::fs::read_to_string(one.join("index.html")).unwrap();
    assert!(page.contains("data:image/png;base64,"));
    let mut linked = 0;
    for m in models {
        if let Some(obj) = m["obj"].as_str() {
            let chromosome = m["chromosome"].as_str().unwrap();
            assert!(one.join(obj).is_file() && one.join(chromosome).is_file());
            assert!(page.contains(obj) && page.contains(chromosome));
            linked += 1;
        }
    }
    assert_eq!(linked, around.len() + 1);
    // The centre thumbnail is three times a representative's; the picture is large.
    let png = image::open(one.join("gallery.png")).unwrap();
    assert!(png.width() >= 7 * 48 && png.width() == png.height());
    // A linked chromosome renders to its model.
    let rendered = temp("gallery", "render");
    let o = shapegen(&[
        "render",
        one.join("models/01.json").to_str().unwrap(),
        "--out",
        rendered.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert_eq!(
        std::fs::read(rendered.join("best.obj")).unwrap(),
        std::fs::read(one.join("models/01.obj")).unwrap()
    );
    // The default model can be named.
    let named = temp("gallery", "named");
    let o = shapegen(&[
        "gallery",
        "--samples",
        "8",
        "--clusters",
        "3",
        "--thumbnail",
        "32",
        "--default-model",
        one.join("models/01.json").to_str().unwrap(),
        "-q",
        "--out",
        named.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert_eq!(
        std::fs::read(named.join("models/00.obj")).unwrap(),
        std::fs::read(one.join("models/01.obj")).unwrap()
    );
    for d in [one, two, rendered, named] {
        std::fs::remove_dir_all(d).ok();
    }
}

#[test]
fn bad_gallery_options_are_clear_errors() {
    let out = temp("gallery", "bad");
    let o = out.to_str().unwrap();
    for (args, says) in [
        (vec!["--clusters", "1"], "clusters must be 2"),
        (vec!["--thumbnail", "4"], "thumbnails must be"),
        (vec!["--samples", "1000000000"], "at most"),
        (vec!["--default-model", "/"], "directory"),
        (vec!["--default-model", "/nonexistent.json"], "nonexistent"),
    ] {
        let mut all = vec!["gallery", "-q", "--out", o];
        all.extend(args.iter());
        let r = shapegen(&all);
        let err = String::from_utf8_lossy(&r.stderr);
        assert!(!r.status.success(), "{args:?} should fail");
        assert!(!err.contains("panicked"), "{err}");
        assert!(err.contains(says), "{args:?}: {err}");
    }
    std::fs::remove_dir_all(&out).ok();
}

/// On a final population: every model is in a cluster, each representative
/// is the member nearest its cluster's centre and stands for a cluster
/// other than the centre's, one per cluster.
#[test]
fn a_population_gallery_picks_one_nearest_member_per_other_cluster() {
    let experiment = Experiment::builtin();
    let graph = Models::graph(&experiment).clone();
    let mut rng = stream(9, &[]);
    let models: Vec<Chromosome> = (0..40)
        .map(|_| random_individual(&graph, &InitLength::Around { l0: 30 }, &mut rng).unwrap())
        .collect();
    let options = GalleryOptions {
        clusters: 7,
        thumbnail: 24,
        ..GalleryOptions::default()
    };
    let g = Gallery::of(
        "best model",
        &experiment,
        models[0].clone(),
        models[1..].to_vec(),
        &options,
        &|_| {},
    )
    .unwrap();
    assert_eq!(g.models.len(), 40);
    let centre_cluster = g.models[0].cluster;
    let w = options.clustering_weights.0;
    let mut seen = std::collections::BTreeSet::new();
    for &r in &g.around {
        let c = g.models[r].cluster;
        assert_ne!(c, centre_cluster);
        assert!(seen.insert(c), "two representatives of cluster {c}");
        assert_eq!(g.clusters[c].representative, r);
        // Nearest to the centre (the mean of its members).
        let members: Vec<[f64; 8]> = g
            .models
            .iter()
            .filter(|m| m.cluster == c)
            .map(|m| m.attributes.for_clustering())
            .collect();
        let mean: [f64; 8] = std::array::from_fn(|k| {
            members.iter().map(|m| m[k]).sum::<f64>() / members.len() as f64
        });
        let d = cluster::distance(&w, &g.models[r].attributes.for_clustering(), &mean);
        for m in &members {
            assert!(d <= cluster::distance(&w, m, &mean) + 1e-12);
        }
    }
    let non_empty = g.clusters.iter().filter(|c| c.size > 0).count();
    assert_eq!(g.around.len(), non_empty - 1);
}
