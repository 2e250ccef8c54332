//! The design interface's latency (issue #21): after a scoring round of 24
//! models, with 100 scored so far, the next batch of 24 from the current pdf
//! (the GPR refit, rejection sampling and 24 thumbnails included), through
//! the server's request handler. Target on this machine: under 1 s.
//!
//! `cargo bench --bench design`; under `cargo test` it runs once as a smoke test.

use criterion::{BatchSize, Criterion, criterion_group, criterion_main};
use serde_json::{Value, json};
use shapegen::design::server::DesignServer;
use shapegen::design::tasks::wing_pairs;
use shapegen::experiment::Experiment;
use shapegen::genome::{Chromosome, ChromosomeData};

fn post(s: &DesignServer, path: &str, body: Value) -> Value {
    let r = s.respond("POST", path, body.to_string().as_bytes());
    assert_eq!(r.status, 200, "{}", String::from_utf8_lossy(&r.body));
    serde_json::from_slice(&r.body).unwrap()
}

/// Scores the shown batch by the wing-pair task (read from the session file).
fn score_batch(
    s: &DesignServer,
    state: &Value,
    session: &std::path::Path,
    graph: &shapegen::graph::Graph,
) -> Value {
    let saved: Value = serde_json::from_slice(&std::fs::read(session).unwrap()).unwrap();
    let scores: Vec<Value> = state["models"]
        .as_array()
        .unwrap()
        .iter()
        .map(|m| {
            let id = m["id"].as_u64().unwrap();
            let p = saved["pending"].as_array().unwrap().iter().find(|p| p["id"].as_u64() == Some(id)).unwrap();
            let data: ChromosomeData = serde_json::from_value(p["model"].clone()).unwrap();
            json!({"id": id, "score": wing_pairs(graph, &Chromosome::from_data(graph, &data).unwrap())})
        })
        .collect();
    post(s, "/api/score", json!({ "scores": scores }))
}

fn next_batch(c: &mut Criterion) {
    let dir = std::env::temp_dir().join(format!("shapegen-bench-design-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let session = dir.join("session.json");
    std::fs::remove_file(&session).ok();
    let graph = Experiment::builtin().graph().clone();
    // 100 scored: a default batch of 28, then three current-pdf batches of 24.
    let s = DesignServer::new(Experiment::builtin(), &session, 5).unwrap();
    let mut state = post(&s, "/api/sample", json!({"mode": "default", "count": 28}));
    state = score_batch(&s, &state, &session, &graph);
    for _ in 0..3 {
        state = post(&s, "/api/sample", json!({"mode": "current", "count": 24}));
        state = score_batch(&s, &state, &session, &graph);
    }
    assert_eq!(state["scored"], 100);
    // One more round of 24 scored: the measured step refits and draws.
    state = post(&s, "/api/sample", json!({"mode": "current", "count": 24}));
    score_batch(&s, &state, &session, &graph);
    let ready = std::fs::read(&session).unwrap();
    drop(s);
    let mut group = c.benchmark_group("design");
    group.sample_size(10);
    group.bench_function("next_batch_24_after_124_scored", |b| {
        b.iter_batched(
            || {
                std::fs::write(&session, &ready).unwrap();
                DesignServer::new(Experiment::builtin(), &session, 5).unwrap()
            },
            |s| {
                post(
                    &s,
                    "/api/sample?thumbnails=1",
                    json!({"mode": "current", "count": 24}),
                )
            },
            BatchSize::PerIteration,
        )
    });
    group.finish();
    std::fs::remove_dir_all(&dir).ok();
}

criterion_group!(benches, next_batch);
criterion_main!(benches);
