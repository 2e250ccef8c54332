//! Errors of the scoring crate.

use std::path::PathBuf;

/// What can go wrong when loading, writing or scoring geometry.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ScoreError {
    /// A generator emits a shape with no mesh.
    #[error("no mesh for shape `{0}`: built-in shapes are `cube`, `frustum` and `leaf`")]
    UnknownShape(String),
    /// Reading or writing a file failed.
    #[error("{}: {source}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// The cause.
        source: std::io::Error,
    },
}
