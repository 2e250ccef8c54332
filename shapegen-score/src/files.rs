//! Writing result files so that no reader ever sees half of one.

use std::io::{self, Write};
use std::path::Path;

use crate::error::ScoreError;

/// Writes `bytes` to `path` atomically: a temporary file in the same
/// folder, synced, then renamed over `path`; the temporary file is removed
/// if any step fails.
pub fn write_atomically(path: &Path, bytes: &[u8]) -> Result<(), ScoreError> {
    let name = path.file_name().map_or_else(
        || std::ffi::OsString::from("output"),
        std::ffi::OsStr::to_os_string,
    );
    let mut tmp_name = std::ffi::OsString::from(".");
    tmp_name.push(&name);
    tmp_name.push(format!(".{}.tmp", std::process::id()));
    let tmp = path.with_file_name(tmp_name);
    let write = || -> io::Result<()> {
        let mut f = std::fs::File::create(&tmp)?;
        f.write_all(bytes)?;
        f.sync_all()?;
        std::fs::rename(&tmp, path)
    };
    write().map_err(|source| {
        std::fs::remove_file(&tmp).ok();
        ScoreError::Io {
            path: path.to_path_buf(),
            source,
        }
    })
}

/// Encodes `img` as PNG and writes it to `path` atomically.
pub fn write_png(path: &Path, img: &image::RgbImage) -> Result<(), ScoreError> {
    write_atomically(path, &encode(path, img)?)
}

/// Encodes `img` (with its alpha channel) as PNG and writes it to `path` atomically.
pub fn write_png_rgba(path: &Path, img: &image::RgbaImage) -> Result<(), ScoreError> {
    write_atomically(path, &png_bytes(path, img)?)
}

/// `img` encoded as PNG (`path` names it in errors).
pub fn png_bytes(path: &Path, img: &image::RgbaImage) -> Result<Vec<u8>, ScoreError> {
    encode(path, img)
}

/// Any 8-bit image encoded as PNG.
fn encode<P>(path: &Path, img: &image::ImageBuffer<P, Vec<u8>>) -> Result<Vec<u8>, ScoreError>
where
    P: image::Pixel<Subpixel = u8> + image::PixelWithColorType,
{
    let mut bytes = Vec::new();
    img.write_to(&mut io::Cursor::new(&mut bytes), image::ImageFormat::Png)
        .map_err(|e| ScoreError::Image {
            path: path.to_path_buf(),
            reason: e.to_string(),
        })?;
    Ok(bytes)
}
