//! The design server: every API call, bad requests, a second tab, concurrent
//! requests over real sockets, the session round trip; and the page in a
//! real headless browser (skipped, with a clear message, where no browser is
//! installed; `.ci/run` installs one).

use std::io::{Read, Write};
use std::net::{SocketAddr, TcpStream};
use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, mpsc};

use serde_json::{Value, json};
use shapegen::design::server::{DesignServer, Reply};
use shapegen::experiment::Experiment;

use crate::util::TempDir;

fn server(dir: &Path) -> DesignServer {
    DesignServer::new(Experiment::builtin(), &dir.join("session.json"), 3).unwrap()
}

fn call(s: &DesignServer, method: &str, url: &str, body: Value) -> (u16, Value) {
    let body = if body.is_null() {
        Vec::new()
    } else {
        body.to_string().into_bytes()
    };
    let Reply {
        status,
        body,
        content_type,
    } = s.respond(method, url, &body);
    assert_eq!(content_type, "application/json", "{url}");
    (status, serde_json::from_slice(&body).unwrap())
}

#[test]
fn every_call_of_the_api_and_its_errors() {
    let dir = TempDir::new("server", "api");
    let s = server(&dir);
    let page = s.respond("GET", "/", &[]);
    assert_eq!(
        (page.status, page.content_type),
        (200, "text/html; charset=utf-8")
    );
    assert!(String::from_utf8(page.body).unwrap().contains("Next batch"));
    let (code, state) = call(&s, "GET", "/api/state", Value::Null);
    assert_eq!(code, 200);
    assert_eq!(state["models"].as_array().unwrap().len(), 0);
    assert_eq!(state["revision"], 0);
    // Modes that need a preference, before there is one.
    let (code, e) = call(
        &s,
        "POST",
        "/api/sample",
        json!({"mode": "current", "revision": 0}),
    );
    assert_eq!(code, 422, "{e}");
    assert!(e["error"].as_str().unwrap().contains("learned preference"));
    let (code, state) = call(
        &s,
        "POST",
        "/api/sample",
        json!({"mode": "default", "count": 10, "revision": 0}),
    );
    assert_eq!(code, 200, "{state}");
    let ids: Vec<u64> = state["models"]
        .as_array()
        .unwrap()
        .iter()
        .map(|m| m["id"].as_u64().unwrap())
        .collect();
    assert_eq!(ids.len(), 10);
    let rev = state["revision"].as_u64().unwrap();
    assert_eq!(rev, 1);
    // Thumbnails, larger views and parameters.
    let t = s.respond("GET", &format!("/api/thumb/{}", ids[0]), &[]);
    assert_eq!((t.status, t.content_type), (200, "image/png"));
    assert!(image::load_from_memory(&t.body).unwrap().width() == 200);
    let v = s.respond("GET", &format!("/api/view/{}", ids[0]), &[]);
    assert_eq!(image::load_from_memory(&v.body).unwrap().width(), 3 * 360);
    let (code, m) = call(&s, "GET", &format!("/api/model/{}", ids[0]), Value::Null);
    assert_eq!(code, 200);
    assert_eq!(m["genes"][0]["node"], "S");
    assert_eq!(call(&s, "GET", "/api/model/999", Value::Null).0, 404);
    assert_eq!(call(&s, "GET", "/api/thumb/x", Value::Null).0, 400);
    // Bad scores change nothing; one bad score in a list rejects the list.
    let before = std::fs::read(dir.join("session.json")).unwrap();
    for bad in [
        json!({"scores": [{"id": ids[0], "score": 140.0}], "revision": rev}),
        json!({"scores": [{"id": ids[0], "score": 50.0}, {"id": 999, "score": 50.0}], "revision": rev}),
        json!({"scores": [{"id": ids[0], "score": "high"}], "revision": rev}),
        json!({"scores": [{"id": ids[0], "score": 50.0}], "revision": rev, "extra": 1}),
    ] {
        let (code, e) = call(&s, "POST", "/api/score", bad.clone());
        assert!(code == 400 || code == 404, "{bad}: {code} {e}");
        assert!(e["error"].is_string());
    }
    let garbage = s.respond("POST", "/api/score", b"{not json");
    assert_eq!(garbage.status, 400);
    assert_eq!(
        std::fs::read(dir.join("session.json")).unwrap(),
        before,
        "nothing was saved"
    );
    // A second tab with an older revision is refused.
    let (code, e) = call(
        &s,
        "POST",
        "/api/score",
        json!({"scores": [{"id": ids[0], "score": 50.0}], "revision": 0}),
    );
    assert_eq!(code, 409);
    assert!(e["error"].as_str().unwrap().contains("another tab"));
    // Scores, saved at once.
    let scores: Vec<Value> = ids
        .iter()
        .enumerate()
        .map(|(i, &id)| json!({"id": id, "score": if i % 2 == 0 { 90.0 } else { 5.0 }}))
        .collect();
    let (code, state) = call(
        &s,
        "POST",
        "/api/score",
        json!({"scores": scores, "revision": rev}),
    );
    assert_eq!(code, 200, "{state}");
    assert!(state["stale"].as_bool().unwrap());
    assert!(
        state["models"]
            .as_array()
            .unwrap()
            .iter()
            .all(|m| m["score"].is_f64())
    );
    let saved: Value =
        serde_json::from_slice(&std::fs::read(dir.join("session.json")).unwrap()).unwrap();
    assert_eq!(saved["factors"][0]["scored"].as_array().unwrap().len(), 10);
    // Sorting by score puts the 90s first.
    let (_, sorted) = call(&s, "GET", "/api/state?sort=score", Value::Null);
    let first: Vec<f64> = sorted["models"]
        .as_array()
        .unwrap()
        .iter()
        .take(5)
        .map(|m| m["score"].as_f64().unwrap())
        .collect();
    assert_eq!(first, vec![90.0; 5]);
    // The next batch refits first; predictions appear.
    let rev = sorted["revision"].as_u64().unwrap();
    let (code, state) = call(
        &s,
        "POST",
        "/api/sample",
        json!({"mode": "uncertain", "count": 6, "revision": rev}),
    );
    assert_eq!(code, 200, "{state}");
    assert!(state["learned"].as_bool().unwrap() && !state["stale"].as_bool().unwrap());
    assert!(
        state["models"]
            .as_array()
            .unwrap()
            .iter()
            .all(|m| m["predicted"].is_f64() && m["std"].is_f64())
    );
    let rev = state["revision"].as_u64().unwrap();
    // Similarity sort, factors, export.
    let target = state["models"][3]["id"].as_u64().unwrap();
    let (_, similar) = call(
        &s,
        "GET",
        &format!("/api/state?sort=similar:{target}"),
        Value::Null,
    );
    assert_eq!(similar["models"][0]["id"].as_u64(), Some(target));
    let (code, state) = call(
        &s,
        "POST",
        "/api/factor",
        json!({"name": "colour", "revision": rev}),
    );
    assert_eq!(code, 200);
    assert_eq!(
        state["factors"][state["current"].as_u64().unwrap() as usize]["name"],
        "colour"
    );
    assert_eq!(
        call(
            &s,
            "POST",
            "/api/factor",
            json!({"name": " ", "revision": rev + 1})
        )
        .0,
        400
    );
    let (code, state) = call(
        &s,
        "POST",
        "/api/factor",
        json!({"name": "preference", "revision": rev + 1}),
    );
    assert_eq!(code, 200);
    // Factors in and out of the product; a refit on request.
    let (code, state) = call(
        &s,
        "POST",
        "/api/factor",
        json!({"name": "colour", "active": false, "revision": state["revision"]}),
    );
    assert_eq!(code, 200, "{state}");
    assert_eq!(state["factors"][1]["active"], false);
    assert_eq!(
        call(
            &s,
            "POST",
            "/api/factor",
            json!({"name": "shape", "active": true})
        )
        .0,
        404
    );
    let (code, state) = call(
        &s,
        "POST",
        "/api/learn",
        json!({"revision": state["revision"]}),
    );
    assert_eq!(code, 200, "{state}");
    assert!(!state["stale"].as_bool().unwrap());
    assert_eq!(
        state["features"].as_array().unwrap().len(),
        1,
        "only the scored, active factor is fitted"
    );
    let (code, done) = call(
        &s,
        "POST",
        "/api/export",
        json!({"revision": state["revision"]}),
    );
    assert_eq!(code, 200, "{done}");
    assert!(dir.join("learned.json").exists());
    assert_eq!(call(&s, "POST", "/api/nope", json!({})).0, 404);
    assert_eq!(call(&s, "DELETE", "/api/state", Value::Null).0, 405);
    // The session round trip: a new server on the same file shows the same page.
    let (_, last) = call(&s, "GET", "/api/state", Value::Null);
    drop(s);
    let again = server(&dir);
    let (_, restored) = call(&again, "GET", "/api/state", Value::Null);
    assert_eq!(last, restored);
    // A session of another generator is refused.
    let text = std::fs::read_to_string("experiments/default.toml")
        .unwrap()
        .replace("generator = \"spaceship\"", "generator = \"tree_v2\"");
    let tree = dir.join("tree.toml");
    std::fs::write(&tree, text).unwrap();
    let tree = Experiment::load(&tree, &Default::default()).unwrap();
    let e = DesignServer::new(tree, &dir.join("session.json"), 1)
        .err()
        .unwrap();
    assert!(e.contains("not `tree_v2`"), "{e}");
}

/// A raw HTTP request over a socket; the response's status and body.
fn http(addr: SocketAddr, method: &str, path: &str, body: &str) -> (u16, String) {
    let mut stream = TcpStream::connect(addr).unwrap();
    write!(
        stream,
        "{method} {path} HTTP/1.1\r\nHost: {addr}\r\nOrigin: http://{addr}\r\nContent-Type: application/json\r\nContent-Length: {}\r\nConnection: close\r\n\r\n{body}",
        body.len()
    )
    .unwrap();
    answer(stream)
}

/// Sends `raw` as it is; the response's status and body.
fn raw(addr: SocketAddr, raw: &[u8]) -> (u16, String) {
    let mut stream = TcpStream::connect(addr).unwrap();
    stream.write_all(raw).unwrap();
    answer(stream)
}

/// Reads a response to its end: status and body.
fn answer(mut stream: TcpStream) -> (u16, String) {
    stream
        .set_read_timeout(Some(std::time::Duration::from_secs(30)))
        .unwrap();
    let mut bytes = Vec::new();
    stream.read_to_end(&mut bytes).unwrap_or_default();
    let text = String::from_utf8_lossy(&bytes);
    let status = text
        .split(' ')
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(0);
    let body = text
        .split_once("\r\n\r\n")
        .map(|b| b.1.to_string())
        .unwrap_or_default();
    (status, body)
}

/// Runs a server on a free port until the returned flag is set.
fn spawn(dir: &Path) -> (SocketAddr, Arc<AtomicBool>, std::thread::JoinHandle<()>) {
    let s = server(dir);
    let stop = Arc::new(AtomicBool::new(false));
    let (tx, rx) = mpsc::channel();
    let flag = Arc::clone(&stop);
    let handle = std::thread::spawn(move || {
        s.serve("127.0.0.1:0", |addr| tx.send(addr).unwrap(), &|| {
            flag.load(Ordering::SeqCst)
        })
        .unwrap();
    });
    (rx.recv().unwrap(), stop, handle)
}

#[test]
fn concurrent_requests_over_sockets_keep_every_score() {
    let dir = TempDir::new("server", "concurrent");
    let (addr, stop, handle) = spawn(&dir);
    let (code, body) = http(
        addr,
        "POST",
        "/api/sample",
        r#"{"mode": "default", "count": 16}"#,
    );
    assert_eq!(code, 200, "{body}");
    let state: Value = serde_json::from_str(&body).unwrap();
    let ids: Vec<u64> = state["models"]
        .as_array()
        .unwrap()
        .iter()
        .map(|m| m["id"].as_u64().unwrap())
        .collect();
    // 16 clients score one model each, while 16 others read state and thumbnails.
    let threads: Vec<_> = ids
        .iter()
        .map(|&id| {
            std::thread::spawn(move || {
                let (a, _) = http(
                    addr,
                    "POST",
                    "/api/score",
                    &format!(r#"{{"scores": [{{"id": {id}, "score": {}}}]}}"#, id % 100),
                );
                let (b, _) = http(addr, "GET", "/api/state", "");
                let (c, _) = http(addr, "GET", &format!("/api/thumb/{id}"), "");
                (a, b, c)
            })
        })
        .collect();
    for t in threads {
        assert_eq!(t.join().unwrap(), (200, 200, 200));
    }
    let (code, body) = http(addr, "GET", "/api/state", "");
    assert_eq!(code, 200);
    let state: Value = serde_json::from_str(&body).unwrap();
    assert_eq!(
        state["factors"][0]["scored"], 16,
        "every concurrent score was kept"
    );
    let saved: Value =
        serde_json::from_slice(&std::fs::read(dir.join("session.json")).unwrap()).unwrap();
    assert_eq!(saved["factors"][0]["scored"].as_array().unwrap().len(), 16);
    // Oversized and malformed requests.
    let big = format!(r#"{{"scores": [], "pad": "{}"}}"#, "x".repeat(2 << 20));
    assert_eq!(http(addr, "POST", "/api/score", &big).0, 413);
    assert_eq!(http(addr, "POST", "/api/sample", "[1,2").0, 400);
    assert_eq!(http(addr, "GET", "/nothing", "").0, 404);
    stop.store(true, Ordering::SeqCst);
    handle.join().unwrap();
}

/// The page in headless Chromium, driven by `tests/browser/design.mjs`
/// (Playwright). Skips, saying why, when Node.js, Chromium or
/// playwright-core is missing. With `SHAPEGEN_SCREENSHOTS=DIR` the
/// screenshots go to DIR (the README's come from there).
#[test]
fn the_page_in_a_headless_browser() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let script = root.join("tests/browser/design.mjs");
    let chromium = std::env::var("CHROMIUM").unwrap_or_else(|_| "/usr/bin/chromium".into());
    let missing = if std::process::Command::new("node")
        .arg("--version")
        .output()
        .is_err()
    {
        Some("Node.js (node) is not installed".to_string())
    } else if !Path::new(&chromium).exists() {
        Some(format!(
            "no Chromium at {chromium} (set CHROMIUM, or install Debian's chromium)"
        ))
    } else if !root
        .join("tests/browser/node_modules/playwright-core")
        .exists()
    {
        Some("playwright-core is not installed (run `npm ci` in tests/browser)".to_string())
    } else {
        None
    };
    if let Some(why) = missing {
        eprintln!("SKIPPED the_page_in_a_headless_browser: {why}; .ci/run installs what it needs");
        return;
    }
    let dir = TempDir::new("server", "browser");
    let shots =
        std::env::var("SHAPEGEN_SCREENSHOTS").map_or_else(|_| dir.join("shots"), Into::into);
    std::fs::create_dir_all(&shots).unwrap();
    let (addr, stop, handle) = spawn(&dir);
    let out = std::process::Command::new("node")
        .arg(&script)
        .arg(format!("http://{addr}/"))
        .arg(&shots)
        .env("CHROMIUM", &chromium)
        .output()
        .unwrap();
    stop.store(true, Ordering::SeqCst);
    handle.join().unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{stdout}\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let result: Value = serde_json::from_str(stdout.trim().lines().last().unwrap()).unwrap();
    assert_eq!(result["ok"], true);
    // The current pdf of a preference for one or two wing pairs shows models
    // predicted well above the middle.
    assert!(
        result["mean_predicted"].as_f64().unwrap() > 50.0,
        "{result}"
    );
    for shot in ["1-empty", "2-batch", "3-scored", "4-current", "5-detail"] {
        let img = image::open(shots.join(format!("{shot}.png"))).unwrap();
        assert_eq!(img.width(), 1280, "{shot}");
    }
    // The session on disk holds the 24 scores the browser gave.
    let saved: Value =
        serde_json::from_slice(&std::fs::read(dir.join("session.json")).unwrap()).unwrap();
    assert_eq!(saved["factors"][0]["scored"].as_array().unwrap().len(), 24);
}

/// The session file's bytes.
fn saved(dir: &Path) -> Vec<u8> {
    std::fs::read(dir.join("session.json")).unwrap()
}

/// Finding 1 of the hostile sweep (#54): a body length far past the limit
/// is refused before anything is read or allocated, and the server lives on.
#[test]
fn a_huge_declared_body_is_refused_and_the_server_lives_on() {
    let dir = TempDir::new("server", "huge");
    let (addr, stop, handle) = spawn(&dir);
    for length in ["99999999999", "18446744073709551615", "1048577"] {
        let (code, body) = raw(
            addr,
            format!(
                "POST /api/score HTTP/1.1\r\nHost: {addr}\r\nOrigin: http://{addr}\r\nContent-Type: application/json\r\nContent-Length: {length}\r\n\r\n{{"
            )
            .as_bytes(),
        );
        assert!(code == 413 || code == 400, "{length}: {code} {body}");
    }
    // Chunked bodies (of any announced size) are refused, not read.
    let (code, _) = raw(
        addr,
        format!("POST /api/score HTTP/1.1\r\nHost: {addr}\r\nOrigin: http://{addr}\r\nContent-Type: application/json\r\nTransfer-Encoding: chunked\r\n\r\nffffffffffffffff\r\n").as_bytes(),
    );
    assert_eq!(code, 411);
    assert_eq!(http(addr, "GET", "/api/state", "").0, 200, "still serving");
    stop.store(true, Ordering::SeqCst);
    handle.join().unwrap();
}

/// Finding 2: pages of other origins, and names rebound to 127.0.0.1,
/// neither change nor read the session.
#[test]
fn other_origins_and_foreign_hosts_are_refused() {
    let dir = TempDir::new("server", "origin");
    let (addr, stop, handle) = spawn(&dir);
    let before = saved(&dir);
    let sample = r#"{"mode": "default", "count": 4}"#;
    let post = |headers: &str| {
        raw(
            addr,
            format!(
                "POST /api/sample HTTP/1.1\r\n{headers}\r\nContent-Length: {}\r\n\r\n{sample}",
                sample.len()
            )
            .as_bytes(),
        )
    };
    // A cross-origin fetch with mode "no-cors": a simple content type and
    // the attacker's Origin.
    let (code, body) = post(&format!(
        "Host: {addr}\r\nOrigin: http://evil.example\r\nContent-Type: text/plain;charset=UTF-8"
    ));
    assert_eq!(code, 403, "{body}");
    assert!(body.contains("evil.example"), "{body}");
    // The same with JSON, and from a sandboxed frame (Origin: null).
    for origin in ["http://evil.example", "null", "http://127.0.0.1:1"] {
        let (code, _) = post(&format!(
            "Host: {addr}\r\nOrigin: {origin}\r\nContent-Type: application/json"
        ));
        assert_eq!(code, 403, "{origin}");
    }
    // Without an Origin, or with the right one and no JSON.
    assert_eq!(
        post(&format!("Host: {addr}\r\nContent-Type: application/json")).0,
        403
    );
    assert_eq!(
        post(&format!(
            "Host: {addr}\r\nOrigin: http://{addr}\r\nContent-Type: application/x-www-form-urlencoded"
        ))
        .0,
        415
    );
    // DNS rebinding: the attacker's name, now resolving to 127.0.0.1.
    let rebound = format!("evil.example:{}", addr.port());
    assert_eq!(
        post(&format!(
            "Host: {rebound}\r\nOrigin: http://{rebound}\r\nContent-Type: application/json"
        ))
        .0,
        403
    );
    let (code, body) = raw(
        addr,
        format!("GET /api/state HTTP/1.1\r\nHost: {rebound}\r\n\r\n").as_bytes(),
    );
    assert_eq!(code, 403);
    assert!(!body.contains("models"), "{body}");
    assert_eq!(saved(&dir), before, "nothing was changed");
    // The page's own requests pass, by address and by `localhost`.
    assert_eq!(http(addr, "POST", "/api/sample", sample).0, 200);
    let local = format!("localhost:{}", addr.port());
    let (code, body) = post(&format!(
        "Host: {local}\r\nOrigin: http://{local}\r\nContent-Type: application/json"
    ));
    assert_eq!(code, 200, "{body}");
    stop.store(true, Ordering::SeqCst);
    handle.join().unwrap();
}

/// Finding 5: stalled uploads neither freeze the server nor hold off a stop.
#[test]
fn stalled_clients_neither_freeze_the_server_nor_hold_off_a_stop() {
    use std::time::{Duration, Instant};
    let dir = TempDir::new("server", "stalled");
    let (addr, stop, handle) = spawn(&dir);
    // Twelve clients that send half a head and wait, and twelve that
    // promise a body and send none of it.
    let mut stalled = Vec::new();
    for i in 0..24 {
        let mut s = TcpStream::connect(addr).unwrap();
        if i % 2 == 0 {
            s.write_all(b"POST /api/score HTTP/1.1\r\nHost: 127")
                .unwrap();
        } else {
            write!(
                s,
                "POST /api/score HTTP/1.1\r\nHost: {addr}\r\nOrigin: http://{addr}\r\nContent-Type: application/json\r\nContent-Length: 1000\r\n\r\n{{"
            )
            .unwrap();
        }
        stalled.push(s);
    }
    std::thread::sleep(Duration::from_millis(200));
    let start = Instant::now();
    for _ in 0..5 {
        assert_eq!(http(addr, "GET", "/api/state", "").0, 200);
    }
    assert!(
        start.elapsed() < Duration::from_secs(3),
        "answered while 24 clients stall: {:?}",
        start.elapsed()
    );
    // A stop is honoured within a second while they still stall.
    let start = Instant::now();
    stop.store(true, Ordering::SeqCst);
    handle.join().unwrap();
    assert!(
        start.elapsed() < Duration::from_secs(1),
        "stopped after {:?}",
        start.elapsed()
    );
    drop(stalled);
}

/// A client that never finishes its request is answered 408 after the
/// deadline and its connection closed.
#[test]
fn a_request_past_its_deadline_is_closed() {
    use std::time::{Duration, Instant};
    let dir = TempDir::new("server", "deadline");
    let (addr, stop, handle) = spawn(&dir);
    let mut s = TcpStream::connect(addr).unwrap();
    // A byte a second: never a complete head.
    let start = Instant::now();
    s.write_all(b"GET /api/state HTTP/1.1\r\nX: ").unwrap();
    s.set_read_timeout(Some(Duration::from_millis(500)))
        .unwrap();
    let mut got = Vec::new();
    let mut buf = [0u8; 512];
    loop {
        match s.read(&mut buf) {
            Ok(0) => break,
            Ok(n) => got.extend_from_slice(&buf[..n]),
            Err(_) => {
                assert!(
                    start.elapsed() < Duration::from_secs(15),
                    "still open after 15 s"
                );
                if s.write_all(b"a").is_err() {
                    break;
                }
            }
        }
    }
    let text = String::from_utf8_lossy(&got);
    assert!(text.starts_with("HTTP/1.1 408"), "{text}");
    assert!(start.elapsed() >= Duration::from_secs(9));
    stop.store(true, Ordering::SeqCst);
    handle.join().unwrap();
}
