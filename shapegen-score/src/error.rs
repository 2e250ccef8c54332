//! Errors of the scoring crate.

use std::path::PathBuf;

/// What can go wrong when loading, writing or scoring geometry.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ScoreError {
    /// A generator emits a shape with no mesh.
    #[error("no mesh for shape `{0}`: built-in shapes are `cube`, `frustum` and `leaf`")]
    UnknownShape(String),
    /// A voxel grid with empty or non-finite bounds or no cells.
    #[error("invalid voxel grid: {0}")]
    Grid(String),
    /// A mesh unusable as a solid (no triangles, non-finite vertices, bad indices).
    #[error("invalid mesh `{name}`: {reason}")]
    Mesh {
        /// Which mesh.
        name: String,
        /// What is wrong.
        reason: String,
    },
    /// An OBJ file that cannot be read as a triangle mesh.
    #[error("{}: not a usable OBJ mesh: {reason}", path.display())]
    Obj {
        /// The file.
        path: PathBuf,
        /// What is wrong.
        reason: String,
    },
    /// A camera that cannot be used.
    #[error("invalid camera: {0}")]
    Camera(String),
    /// An image that cannot be read or written.
    #[error("{}: {reason}", path.display())]
    Image {
        /// The file.
        path: PathBuf,
        /// What is wrong.
        reason: String,
    },
    /// A target that cannot be used.
    #[error("invalid target: {0}")]
    Target(String),
    /// A target (or group of targets) that covers no cell of the grid.
    #[error("invalid target: {reason}")]
    EmptyTarget {
        /// The target (its group's first, by index in the scene's list).
        target: usize,
        /// Why it covers no cell.
        reason: String,
    },
    /// Reading or writing a file failed.
    #[error("{}: {source}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// The cause.
        source: std::io::Error,
    },
}
