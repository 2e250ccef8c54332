//! Pictures of one grid slice: target and model cells.

use std::path::Path;

use super::VolumeScene;
use crate::error::ScoreError;

impl VolumeScene {
    /// Writes a PNG of the cells of one grid slice: the slice perpendicular
    /// to `axis` (0 = x, 1 = y, 2 = z) at cell `index`, coloured like the
    /// image overlay (target only light blue, model only red, both green,
    /// the rest white; cells hit twice or more darker). `hits` comes from
    /// [`VolumeScratch::hits`](crate::VolumeScratch::hits). Each cell becomes `scale × scale` pixels; the
    /// image's up direction is the next axis (y for x and z slices, z for y).
    pub fn write_slice(
        &self,
        path: &Path,
        hits: &[u8],
        axis: usize,
        index: u32,
        scale: u32,
    ) -> Result<(), ScoreError> {
        let d = self.grid.dims();
        let bad = |reason: String| ScoreError::Image {
            path: path.to_path_buf(),
            reason,
        };
        if axis > 2 || index >= d[axis] || hits.len() != self.grid.len() || scale == 0 {
            return Err(bad(format!(
                "no slice {index} along axis {axis} of a {}×{}×{} grid with {} hit counts",
                d.x,
                d.y,
                d.z,
                hits.len()
            )));
        }
        // (horizontal, vertical) axes of the picture.
        let (u, v) = match axis {
            0 => (2, 1),
            1 => (0, 2),
            _ => (0, 1),
        };
        let (w, h) = (d[u] * scale, d[v] * scale);
        let img = image::RgbImage::from_fn(w, h, |px, py| {
            let mut c = glam::UVec3::ZERO;
            c[axis] = index;
            c[u] = px / scale;
            c[v] = d[v] - 1 - py / scale;
            let i = self.grid.index(c);
            let (t, m) = (self.target[i], hits[i]);
            image::Rgb(match (t, m) {
                (true, 0) => [150, 190, 240],
                (true, 1) => [0, 128, 0],
                (true, _) => [0, 70, 0],
                (false, 0) => [255, 255, 255],
                (false, 1) => [220, 40, 40],
                (false, _) => [130, 20, 20],
            })
        });
        crate::files::write_png(path, &img)
    }
}
