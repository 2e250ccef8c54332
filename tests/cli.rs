//! The main command as a user runs it: results are written and consistent.

use std::process::Command;

#[test]
fn the_default_run_writes_consistent_results() {
    let out = std::env::temp_dir().join(format!("shapegen-cli-test-{}", std::process::id()));
    let status = Command::new(env!("CARGO_BIN_EXE_shapegen"))
        .args(["--generations", "15", "--seed", "3", "--out"])
        .arg(&out)
        .status()
        .expect("the binary runs");
    assert!(status.success());
    for f in [
        "best.obj",
        "target.obj",
        "best.json",
        "curve.csv",
        "summary.json",
    ] {
        assert!(out.join(f).is_file(), "{f} missing");
    }
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(summary["generations"], 15);
    assert_eq!(summary["seed"], 3);
    let best = summary["best_fitness"].as_f64().unwrap();
    assert!(best > 0.0 && best <= 2.0, "{best}");
    // The curve's last row is the final generation, and its best so far is the summary's.
    let curve = std::fs::read_to_string(out.join("curve.csv")).unwrap();
    let rows: Vec<Vec<f64>> = curve
        .lines()
        .skip(1)
        .map(|l| l.split(',').map(|x| x.parse().unwrap()).collect())
        .collect();
    assert_eq!(rows.len(), 16);
    let best_in_curve = rows.iter().map(|r| r[3]).fold(f64::NEG_INFINITY, f64::max);
    assert_eq!(best_in_curve, best);
    assert_eq!(
        rows.last().unwrap()[2],
        summary["evaluations"].as_f64().unwrap()
    );
    // The chromosome file is valid for the spaceship graph.
    let data: shapegen::genome::ChromosomeData =
        serde_json::from_str(&std::fs::read_to_string(out.join("best.json")).unwrap()).unwrap();
    let graph =
        shapegen::graph::Graph::new(shapegen::scenes::Spaceship::spec().clone().with_limits(
            shapegen::graph::Limits {
                max_depth: Some(15),
                min_len: 4,
                max_len: Some(100),
            },
        ))
        .unwrap();
    let c = shapegen::genome::Chromosome::from_data(&graph, &data).unwrap();
    assert_eq!(c.len() as u64, summary["best_genes"].as_u64().unwrap());
    // A bad option is a clear error, not a panic.
    let bad = Command::new(env!("CARGO_BIN_EXE_shapegen"))
        .args(["--generations", "many"])
        .output()
        .unwrap();
    assert!(!bad.status.success());
    assert!(String::from_utf8_lossy(&bad.stderr).contains("invalid value"));
    std::fs::remove_dir_all(&out).ok();
}
