//! Helpers the test modules share.

use std::path::{Path, PathBuf};

/// A fresh temporary directory for one test (`area` and `name` keep tests
/// of different modules apart).
pub fn temp(area: &str, name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("shapegen-{area}-{name}-{}", std::process::id()));
    std::fs::remove_dir_all(&dir).ok();
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// A JSON file, parsed.
pub fn json(path: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}
