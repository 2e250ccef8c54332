//! `curves.png`: mean best fitness over time with a std band per method.

use std::path::Path;
use std::sync::OnceLock;

use plotters::prelude::*;
use plotters::style::{FontStyle, register_font};

use super::CliError;

/// One method's mean curve: `(seconds, mean, std)` points.
pub struct Series {
    /// Legend name.
    pub name: String,
    /// The points, by increasing time.
    pub points: Vec<(f64, f64, f64)>,
}

/// Where a TrueType font is looked for (first found wins); `SHAPEGEN_FONT` first.
const FONTS: [&str; 6] = [
    "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf",
    "/usr/share/fonts/TTF/DejaVuSans.ttf",
    "/usr/share/fonts/dejavu/DejaVuSans.ttf",
    "/usr/share/fonts/truetype/liberation/LiberationSans-Regular.ttf",
    "/Library/Fonts/Arial.ttf",
    "C:\\Windows\\Fonts\\arial.ttf",
];

/// Registers a system font for the plot's text once; false if none is found.
fn font() -> bool {
    static FOUND: OnceLock<bool> = OnceLock::new();
    *FOUND.get_or_init(|| {
        let env = std::env::var("SHAPEGEN_FONT").ok();
        env.iter()
            .map(String::as_str)
            .chain(FONTS)
            .filter_map(|p| std::fs::read(p).ok())
            .any(|bytes| {
                register_font(
                    "sans-serif",
                    FontStyle::Normal,
                    Box::leak(bytes.into_boxed_slice()),
                )
                .is_ok()
            })
    })
}

const COLOURS: [RGBColor; 6] = [
    RGBColor(214, 39, 40),
    RGBColor(31, 119, 180),
    RGBColor(44, 160, 44),
    RGBColor(255, 127, 14),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
];

/// Draws the curves into a PNG. Returns a warning if no font was found (the
/// plot then has no text).
pub fn curves(
    path: &Path,
    title: &str,
    seconds: f64,
    optimum: Option<f64>,
    series: &[Series],
) -> Result<Option<String>, CliError> {
    with_font(path, |text| {
        draw(path, title, seconds, optimum, series, text)
    })
}

/// Runs `draw` with whether a font was found, and turns its error into a
/// [`CliError`]; returns a warning if the picture has no text.
fn with_font(
    path: &Path,
    draw: impl FnOnce(bool) -> Result<(), Box<dyn std::error::Error>>,
) -> Result<Option<String>, CliError> {
    let text = font();
    draw(text).map_err(|e| CliError::msg(format!("cannot draw {}: {e}", path.display())))?;
    Ok((!text).then(|| {
        format!(
            "no TrueType font found (set SHAPEGEN_FONT): {} has no text",
            path.display()
        )
    }))
}

fn draw(
    path: &Path,
    title: &str,
    seconds: f64,
    optimum: Option<f64>,
    series: &[Series],
    text: bool,
) -> Result<(), Box<dyn std::error::Error>> {
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for s in series {
        for &(_, m, d) in &s.points {
            lo = lo.min(m - d);
            hi = hi.max(m + d);
        }
    }
    if let Some(o) = optimum {
        hi = hi.max(o);
    }
    if !(lo.is_finite() && hi.is_finite()) {
        (lo, hi) = (0.0, 1.0);
    }
    let pad = ((hi - lo) * 0.05).max(1e-3);
    let root = BitMapBackend::new(path, (1000, 620)).into_drawing_area();
    root.fill(&WHITE)?;
    let mut builder = ChartBuilder::on(&root);
    builder.margin(14);
    if text {
        builder
            .caption(title, ("sans-serif", 20))
            .x_label_area_size(44)
            .y_label_area_size(64);
    }
    let mut chart = builder.build_cartesian_2d(0f64..seconds, (lo - pad)..(hi + pad))?;
    if text {
        chart
            .configure_mesh()
            .x_desc("wall-clock seconds")
            .y_desc("best fitness so far")
            .light_line_style(WHITE.mix(0.0))
            .draw()?;
    } else {
        chart.configure_mesh().disable_axes().draw()?;
    }
    if let Some(o) = optimum {
        let line = chart.draw_series(LineSeries::new(
            [(0.0, o), (seconds, o)],
            BLACK.mix(0.4).stroke_width(1),
        ))?;
        if text {
            line.label(format!("optimum {o}"))
                .legend(|(x, y)| PathElement::new([(x, y), (x + 20, y)], BLACK.mix(0.4)));
        }
    }
    for (i, s) in series.iter().enumerate() {
        let colour = COLOURS[i % COLOURS.len()];
        if s.points.is_empty() {
            continue;
        }
        let band: Vec<(f64, f64)> = s
            .points
            .iter()
            .map(|&(t, m, d)| (t, m + d))
            .chain(s.points.iter().rev().map(|&(t, m, d)| (t, m - d)))
            .collect();
        chart.draw_series(std::iter::once(Polygon::new(
            band,
            colour.mix(0.18).filled(),
        )))?;
        let line = chart.draw_series(LineSeries::new(
            s.points.iter().map(|&(t, m, _)| (t, m)),
            colour.stroke_width(2),
        ))?;
        if text {
            line.label(s.name.clone()).legend(move |(x, y)| {
                PathElement::new([(x, y), (x + 20, y)], colour.stroke_width(2))
            });
        }
        // A curve that ends before the budget (every run stopped early)
        // ends in a dot, so it does not read as cut off by the picture.
        if let Some(&(t, m, _)) = s.points.last()
            && t < seconds * 0.99
        {
            chart.draw_series(std::iter::once(Circle::new((t, m), 4, colour.filled())))?;
        }
    }
    if text {
        chart
            .configure_series_labels()
            .position(SeriesLabelPosition::LowerRight)
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK.mix(0.3))
            .draw()?;
    }
    root.present()?;
    Ok(())
}

/// Writes pictures side by side, each with its label below (no labels if
/// no font is found: then a warning is returned, as for [`curves`]).
pub fn labelled_row(
    path: &Path,
    items: &[(String, image::RgbaImage)],
) -> Result<Option<String>, CliError> {
    let side = items
        .iter()
        .map(|(_, p)| p.width().max(p.height()))
        .max()
        .unwrap_or(1);
    let (gap, label) = (16u32, 36u32);
    let n = items.len().max(1) as u32;
    let (w, h) = (n * side + (n + 1) * gap, side + label + gap);
    let mut canvas = image::RgbImage::from_pixel(w, h, image::Rgb([255, 255, 255]));
    for (k, (_, picture)) in items.iter().enumerate() {
        let x0 = gap + k as u32 * (side + gap);
        for (x, y, p) in picture.enumerate_pixels() {
            let a = f32::from(p[3]) / 255.0;
            let blend = |c: u8| (f32::from(c) * a + 255.0 * (1.0 - a)).round() as u8;
            canvas.put_pixel(
                x0 + x,
                gap + y,
                image::Rgb([blend(p[0]), blend(p[1]), blend(p[2])]),
            );
        }
    }
    let text = font();
    if text {
        let mut buffer = canvas.into_raw();
        {
            let area = BitMapBackend::with_buffer(&mut buffer, (w, h)).into_drawing_area();
            let style = ("sans-serif", 22).into_font().color(&BLACK);
            for (k, (name, _)) in items.iter().enumerate() {
                let x = (gap + k as u32 * (side + gap) + side / 2) as i32;
                let (tw, _) = area.estimate_text_size(name, &style).unwrap_or((0, 0));
                area.draw_text(name, &style, (x - tw as i32 / 2, (gap + side + 6) as i32))
                    .map_err(|e| CliError::msg(format!("cannot draw {}: {e}", path.display())))?;
            }
            area.present()
                .map_err(|e| CliError::msg(format!("cannot draw {}: {e}", path.display())))?;
        }
        canvas = image::RgbImage::from_raw(w, h, buffer).expect("the buffer keeps its size");
    }
    crate::score::write_png(path, &canvas)?;
    Ok((!text).then(|| {
        format!(
            "no TrueType font found (set SHAPEGEN_FONT): {} has no labels",
            path.display()
        )
    }))
}

/// Colours of a panel's levels: grey, purple, orange.
const LEVELS: [RGBColor; 3] = [
    RGBColor(90, 90, 90),
    RGBColor(148, 103, 189),
    RGBColor(255, 127, 14),
];

/// One panel of [`panels`]: lines over a log-scaled y axis and levels.
#[derive(Clone, Debug)]
pub struct Panel {
    /// Its title.
    pub title: String,
    /// Lines: a name and `(x, y)` points.
    pub lines: Vec<(String, Vec<(f64, f64)>)>,
    /// Horizontal levels: a name and a value.
    pub levels: Vec<(String, f64)>,
}

/// Draws panels in a grid of `columns`, each with a log y axis from
/// `y_min` to 1 (values below are drawn at `y_min`). Returns a warning if
/// no font was found, as [`curves`] does.
pub fn panels(
    path: &Path,
    x_desc: &str,
    y_desc: &str,
    columns: usize,
    y_min: f64,
    panels: &[Panel],
) -> Result<Option<String>, CliError> {
    with_font(path, |text| {
        draw_panels(path, x_desc, y_desc, columns, y_min, panels, text)
    })
}

fn draw_panels(
    path: &Path,
    x_desc: &str,
    y_desc: &str,
    columns: usize,
    y_min: f64,
    panels: &[Panel],
    text: bool,
) -> Result<(), Box<dyn std::error::Error>> {
    let columns = columns.max(1);
    let rows = panels.len().div_ceil(columns).max(1);
    let (pw, ph) = (640u32, 400u32);
    let root =
        BitMapBackend::new(path, (pw * columns as u32, ph * rows as u32)).into_drawing_area();
    root.fill(&WHITE)?;
    let areas = root.split_evenly((rows, columns));
    let x_max = panels
        .iter()
        .flat_map(|p| p.lines.iter().flat_map(|l| l.1.iter().map(|q| q.0)))
        .fold(1.0f64, f64::max);
    for (panel, area) in panels.iter().zip(areas) {
        let mut builder = ChartBuilder::on(&area);
        builder.margin(10);
        if text {
            builder
                .caption(&panel.title, ("sans-serif", 14))
                .x_label_area_size(36)
                .y_label_area_size(52);
        }
        let mut chart =
            builder.build_cartesian_2d(0f64..x_max * 1.02, (y_min..1.0f64).log_scale())?;
        if text {
            chart
                .configure_mesh()
                .x_desc(x_desc)
                .y_desc(y_desc)
                .x_label_formatter(&|x| format!("{x:.0}"))
                .light_line_style(WHITE.mix(0.0))
                .draw()?;
        } else {
            chart.configure_mesh().disable_axes().draw()?;
        }
        let clamp = |y: f64| y.clamp(y_min, 1.0);
        for (i, (name, value)) in panel.levels.iter().enumerate() {
            let colour = LEVELS[i % LEVELS.len()];
            let line = chart.draw_series(DashedLineSeries::new(
                [(0.0, clamp(*value)), (x_max * 1.02, clamp(*value))],
                6,
                4,
                colour.stroke_width(1),
            ))?;
            if text {
                line.label(format!("{name} {value:.4}"))
                    .legend(move |(x, y)| PathElement::new([(x, y), (x + 20, y)], colour));
            }
        }
        for (i, (name, points)) in panel.lines.iter().enumerate() {
            let colour = COLOURS[i % COLOURS.len()];
            chart.draw_series(
                points
                    .iter()
                    .map(|&(x, y)| Circle::new((x, clamp(y)), 3, colour.filled())),
            )?;
            let line = chart.draw_series(LineSeries::new(
                points.iter().map(|&(x, y)| (x, clamp(y))),
                colour.stroke_width(2),
            ))?;
            if text {
                line.label(name.clone()).legend(move |(x, y)| {
                    PathElement::new([(x, y), (x + 20, y)], colour.stroke_width(2))
                });
            }
        }
        if text {
            chart
                .configure_series_labels()
                .position(SeriesLabelPosition::UpperRight)
                .label_font(("sans-serif", 12))
                .background_style(WHITE.mix(0.85))
                .border_style(BLACK.mix(0.3))
                .draw()?;
        }
    }
    root.present()?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn draws_with_and_without_text() {
        let dir = std::env::temp_dir().join(format!("shapegen-plot-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let series = [
            Series {
                name: "ga".into(),
                points: vec![(0.0, 0.1, 0.05), (1.0, 0.5, 0.1), (2.0, 0.9, 0.02)],
            },
            Series {
                name: "smc".into(),
                points: Vec::new(),
            },
        ];
        for text in [false, font()] {
            let path = dir.join(format!("curves-{text}.png"));
            draw(&path, "test", 2.0, Some(1.0), &series, text).unwrap();
            let img = image::open(&path).unwrap().to_rgb8();
            assert_eq!(img.dimensions(), (1000, 620));
            // The GA's red line is drawn.
            assert!(img.pixels().any(|p| p.0 == [214, 39, 40]));
        }
        let panel = Panel {
            title: "t".into(),
            lines: vec![("gpr".into(), vec![(10.0, 0.5), (100.0, 0.001)])],
            levels: vec![("default".into(), 0.3)],
        };
        for text in [false, font()] {
            let path = dir.join(format!("panels-{text}.png"));
            draw_panels(
                &path,
                "x",
                "y",
                2,
                1e-4,
                &[panel.clone(), panel.clone(), panel.clone()],
                text,
            )
            .unwrap();
            let img = image::open(&path).unwrap().to_rgb8();
            assert_eq!(img.dimensions(), (1280, 800));
            assert!(img.pixels().any(|p| p.0 == [214, 39, 40]));
        }
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
