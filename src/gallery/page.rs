//! A gallery's files: `gallery.png` (the centre model large, the
//! representatives around it), `index.html` (self-contained: every
//! thumbnail embedded, cluster sizes, attributes, links to each model's
//! OBJ and chromosome) and `gallery.json`; the models in `models/`.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use base64::Engine as _;
use serde::Serialize;

use super::{Gallery, GalleryError, Models};
use crate::genome::Chromosome;
use crate::score::{ATTRIBUTE_NAMES, png_bytes, write_atomically, write_obj};

/// The files [`Gallery::write`] writes (besides `models/`).
pub const GALLERY_FILES: [&str; 3] = ["gallery.png", "index.html", "gallery.json"];

#[derive(Serialize)]
struct JsonModel {
    index: usize,
    cluster: usize,
    genes: usize,
    instances: usize,
    /// Clustering attributes a1–a8 (a5' and a6').
    attributes: [f64; 8],
    projection: [f64; 2],
    obj: Option<String>,
    chromosome: Option<String>,
}

#[derive(Serialize)]
struct JsonGallery<'a> {
    centre: &'a str,
    attribute_names: [&'static str; 8],
    best_view: JsonView,
    clusters: &'a [super::GalleryCluster],
    /// Representatives, clockwise from the top (indices into `models`).
    around: &'a [usize],
    models: Vec<JsonModel>,
}

#[derive(Serialize)]
struct JsonView {
    azimuth_degrees: f64,
    elevation_degrees: f64,
    index: usize,
    scores: Vec<f64>,
}

impl Gallery {
    /// The picture of the gallery: the centre model in the middle, the
    /// representatives around it on a circle at a third of its size,
    /// clockwise from the top in [`around`](Self::around) order.
    #[must_use]
    pub fn picture(&self) -> image::RgbaImage {
        let blank = image::RgbaImage::new(0, 0);
        let thumbnail = |m: usize| self.models[m].thumbnail.as_ref().unwrap_or(&blank);
        let centre = thumbnail(0);
        let t = f64::from(centre.width()) / 3.0;
        let k = self.around.len() as f64;
        let r = (2.9 * t).max(k * 1.2 * t / std::f64::consts::TAU);
        let side = (2.0 * r + 1.4 * t).ceil() as u32;
        let mut canvas = image::RgbaImage::from_pixel(side, side, image::Rgba([255; 4]));
        let mid = f64::from(side) / 2.0;
        paste(&mut canvas, centre, mid, mid);
        for (j, &m) in self.around.iter().enumerate() {
            let a = std::f64::consts::TAU * j as f64 / k;
            paste(
                &mut canvas,
                thumbnail(m),
                mid + r * a.sin(),
                mid - r * a.cos(),
            );
        }
        canvas
    }

    /// Writes `gallery.png`, `index.html`, `gallery.json`, and the centre
    /// model and each representative as `models/NN.obj` and
    /// `models/NN.json` (chromosome), each file atomically; `title` heads
    /// the page. Returns the files written.
    pub fn write(
        &self,
        dir: &Path,
        models: &dyn Models,
        title: &str,
    ) -> Result<Vec<PathBuf>, GalleryError> {
        let io = |path: &Path, e: std::io::Error| {
            GalleryError::Score(crate::score::ScoreError::Io {
                path: path.to_path_buf(),
                source: e,
            })
        };
        let model_dir = dir.join("models");
        std::fs::create_dir_all(&model_dir).map_err(|e| io(&model_dir, e))?;
        let mut written = Vec::new();
        // The centre (00) and the representatives in order (01, 02, ...).
        let shown: Vec<usize> = std::iter::once(0)
            .chain(self.around.iter().copied())
            .collect();
        let mut files = vec![(None, None); self.models.len()];
        for (n, &m) in shown.iter().enumerate() {
            let model = &self.models[m];
            let Some(chromosome) = &model.chromosome else {
                continue; // a model given as instances: the picture shows it
            };
            let obj = model_dir.join(format!("{n:02}.obj"));
            let mut text = Vec::new();
            write_obj(&mut text, &models.instances(chromosome), models.meshes())
                .map_err(|e| io(&obj, e))?;
            write_atomically(&obj, &text)?;
            let json = model_dir.join(format!("{n:02}.json"));
            let data = chromosome.to_data(models.graph());
            let text = serde_json::to_string_pretty(&data).expect("chromosome data serializes");
            write_atomically(&json, text.as_bytes())?;
            files[m] = (
                Some(format!("models/{n:02}.obj")),
                Some(format!("models/{n:02}.json")),
            );
            written.extend([obj, json]);
        }
        // The gallery picture is composed and encoded once, for its file and the page.
        let png = dir.join("gallery.png");
        let picture = png_bytes(&png, &self.picture())?;
        write_atomically(&png, &picture)?;
        written.push(png);
        let html = dir.join("index.html");
        write_atomically(
            &html,
            self.html(title, &shown, &files, &picture)?.as_bytes(),
        )?;
        written.push(html);
        let json = dir.join("gallery.json");
        let v = &self.best_view;
        let doc = JsonGallery {
            centre: &self.centre,
            attribute_names: ATTRIBUTE_NAMES,
            best_view: JsonView {
                azimuth_degrees: v.viewpoint.azimuth.to_degrees(),
                elevation_degrees: v.viewpoint.elevation.to_degrees(),
                index: v.index,
                scores: v.scores.clone(),
            },
            clusters: &self.clusters,
            around: &self.around,
            models: self
                .models
                .iter()
                .enumerate()
                .map(|(i, m)| JsonModel {
                    index: i,
                    cluster: m.cluster,
                    genes: m.chromosome.as_ref().map_or(0, Chromosome::len),
                    instances: m.instances,
                    attributes: m.attributes.for_clustering(),
                    projection: m.projection,
                    obj: files[i].0.clone(),
                    chromosome: files[i].1.clone(),
                })
                .collect(),
        };
        let text = serde_json::to_string_pretty(&doc).expect("gallery serializes");
        write_atomically(&json, text.as_bytes())?;
        written.push(json);
        Ok(written)
    }

    fn html(
        &self,
        title: &str,
        shown: &[usize],
        files: &[(Option<String>, Option<String>)],
        gallery_png: &[u8],
    ) -> Result<String, GalleryError> {
        let encoded = |bytes: &[u8]| {
            format!(
                "data:image/png;base64,{}",
                base64::engine::general_purpose::STANDARD.encode(bytes)
            )
        };
        let data_url = |img: &image::RgbaImage| -> Result<String, GalleryError> {
            Ok(encoded(&png_bytes(Path::new("thumbnail.png"), img)?))
        };
        let esc = |s: &str| {
            s.replace('&', "&amp;")
                .replace('<', "&lt;")
                .replace('>', "&gt;")
                .replace('"', "&quot;")
        };
        let mut h = String::new();
        let v = &self.best_view.viewpoint;
        let _ = write!(
            h,
            "<!doctype html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\
             <title>{t}</title><style>\
             body{{font-family:system-ui,sans-serif;margin:2em;color:#222;background:#fafafa}}\
             .grid{{display:flex;flex-wrap:wrap;gap:1em}}\
             .card{{background:#fff;border:1px solid #ddd;border-radius:6px;padding:.6em;font-size:.85em}}\
             .card img{{display:block;image-rendering:auto}}\
             table{{border-collapse:collapse;margin-top:.4em}}td{{padding:0 .5em 0 0}}\
             .centre{{border-color:#4e79a7;border-width:2px}}\
             </style></head><body>\n<h1>{t}</h1>\n<p>{n} models; {c} clusters; \
             every model seen from the {centre}'s best view \
             (azimuth {az:.0}°, elevation {el:.0}°).</p>\n<img src=\"{g}\" alt=\"gallery\" \
             style=\"max-width:100%\">\n<h2>The {centre} and the cluster representatives</h2>\n\
             <div class=\"grid\">\n",
            t = esc(title),
            n = self.models.len(),
            c = self.clusters.len(),
            centre = esc(&self.centre),
            az = v.azimuth.to_degrees(),
            el = v.elevation.to_degrees(),
            g = encoded(gallery_png),
        );
        for (n, &m) in shown.iter().enumerate() {
            let model = &self.models[m];
            let size = self.clusters[model.cluster].size;
            let label = if n == 0 {
                esc(&self.centre)
            } else if model.instances == 0 {
                format!("representative {n} (emits nothing)")
            } else {
                format!("representative {n}")
            };
            let blank = image::RgbaImage::new(0, 0);
            let thumbnail = model.thumbnail.as_ref().unwrap_or(&blank);
            let _ = write!(
                h,
                "<div class=\"card{cls}\"><img src=\"{img}\" width=\"{w}\" alt=\"{label}\">\
                 <b>{label}</b><br>cluster of {size}, {genes} genes, {inst} instances<br>",
                cls = if n == 0 { " centre" } else { "" },
                img = data_url(thumbnail)?,
                w = 160.min(thumbnail.width()),
                genes = model.chromosome.as_ref().map_or(0, Chromosome::len),
                inst = model.instances,
            );
            if let (Some(obj), Some(json)) = &files[m] {
                let _ = write!(
                    h,
                    "<a href=\"{obj}\">OBJ</a> · <a href=\"{json}\">chromosome</a>"
                );
            }
            h.push_str("<table>");
            for (name, value) in ATTRIBUTE_NAMES
                .iter()
                .zip(model.attributes.for_clustering())
            {
                let _ = write!(h, "<tr><td>{name}</td><td>{value:.3}</td></tr>");
            }
            h.push_str("</table></div>\n");
        }
        h.push_str("</div>\n<h2>Cluster sizes</h2>\n<p>");
        let mut sizes: Vec<usize> = self.clusters.iter().map(|c| c.size).collect();
        sizes.sort_unstable_by(|a, b| b.cmp(a));
        let _ = write!(
            h,
            "{}</p>\n</body></html>\n",
            sizes
                .iter()
                .map(usize::to_string)
                .collect::<Vec<_>>()
                .join(", ")
        );
        Ok(h)
    }
}

/// Draws `img` over `canvas` centred at `(x, y)` (alpha-blended), with a
/// light grey frame.
fn paste(canvas: &mut image::RgbaImage, img: &image::RgbaImage, x: f64, y: f64) {
    let (w, h) = (img.width() as i64, img.height() as i64);
    let (x0, y0) = (
        (x - w as f64 / 2.0).round() as i64,
        (y - h as f64 / 2.0).round() as i64,
    );
    for j in -1..=h {
        for i in -1..=w {
            let (cx, cy) = (x0 + i, y0 + j);
            if cx < 0
                || cy < 0
                || cx >= i64::from(canvas.width())
                || cy >= i64::from(canvas.height())
            {
                continue;
            }
            let dst = canvas.get_pixel_mut(cx as u32, cy as u32);
            if i < 0 || j < 0 || i == w || j == h {
                *dst = image::Rgba([210, 210, 210, 255]);
                continue;
            }
            let src = img.get_pixel(i as u32, j as u32);
            let a = f32::from(src[3]) / 255.0;
            for k in 0..3 {
                dst[k] = (f32::from(src[k]) * a + f32::from(dst[k]) * (1.0 - a)).round() as u8;
            }
            dst[3] = 255;
        }
    }
}
