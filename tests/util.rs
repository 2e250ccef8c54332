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

/// A fresh temporary directory that is removed when the test ends, unless
/// it fails (then what it wrote stays for a look). Derefs to its path.
pub struct TempDir(PathBuf);

impl TempDir {
    /// [`temp`], removed at the end.
    pub fn new(area: &str, name: &str) -> Self {
        Self(temp(area, name))
    }
}

impl std::ops::Deref for TempDir {
    type Target = Path;

    fn deref(&self) -> &Path {
        &self.0
    }
}

impl AsRef<Path> for TempDir {
    fn as_ref(&self) -> &Path {
        &self.0
    }
}

impl Drop for TempDir {
    fn drop(&mut self) {
        if !std::thread::panicking() {
            std::fs::remove_dir_all(&self.0).ok();
        }
    }
}

/// A JSON file, parsed.
pub fn json(path: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}
