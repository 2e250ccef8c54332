//! `shapegen transform`: a transformation file to a sequence of pictures.

use std::time::Instant;

use base64::Engine;
use image::codecs::gif::{GifEncoder, Repeat};

use super::args::TransformArgs;
use super::{Cli, CliError, guard};
use crate::experiment::ExperimentError;
use crate::output::{Stage, write_json};
use crate::score::{Viewpoint, write_png_rgba};
use crate::transform::sequence::{
    FrameFacts, Occupancy, Painter, Smoothness, change, contact_sheet, frame_times, instances,
    meshes, visible,
};
use crate::transform::{Frames, Placed, TransformFile};

/// Frames shown on the contact sheet at most.
const SHEET_FRAMES: usize = 12;
/// Frames the animation and the page hold at most (evenly chosen), and
/// their largest side: what stays in memory whatever `--frames` asks.
const SHOWN_FRAMES: usize = 300;
const SHOWN_SIZE: u32 = 360;
/// What the command writes into `--out`.
const OUTPUTS: [&str; 6] = [
    "frames",
    "contact.png",
    "sequence.gif",
    "index.html",
    "sequence.json",
    "summary.json",
];

/// Runs `shapegen transform`.
pub(super) fn transform(cli: &Cli, args: &TransformArgs) -> Result<(), CliError> {
    crate::experiment::check_regular_file(&args.file).map_err(CliError::msg)?;
    let file =
        TransformFile::load(&args.file, &cli.registry).map_err(|e| CliError::msg(e.to_string()))?;
    if let Some(n) = args.variations {
        return super::variations::variations(args, file, n);
    }
    let count = args.frames.unwrap_or(file.frames.count);
    if let Some(problem) = Frames::count_problem(count) {
        return Err(CliError::msg(format!("--frames: {problem}")));
    }
    let times = match args.at {
        Some(t) if (0.0..=1.0).contains(&t) => vec![t],
        Some(t) => return Err(CliError::msg(format!("--at {t}: a time in [0, 1]"))),
        None => frame_times(count),
    };
    let _taken = guard::take_output_dir(&args.out)?;
    let mut inputs = file.inputs.clone();
    inputs.push(args.file.clone());
    let outputs: Vec<_> = OUTPUTS.iter().map(|f| args.out.join(f)).collect();
    guard::refuse_overwriting_inputs(&outputs, &inputs)?;
    let t = &file.transformation;
    let viewpoint = Viewpoint {
        azimuth: file.frames.azimuth.to_radians(),
        elevation: file.frames.elevation.to_radians(),
    };
    let mut painter = Painter::new(t, viewpoint, file.frames.size)?;
    let mut occupancy = Occupancy::new(t, 96)?;
    let mut previous: Option<Vec<u64>> = None;
    let obj_meshes = if args.obj { Some(meshes(t)?) } else { None };
    // Every `every`-th frame (and the last) is kept for the sheet, the GIF and the page.
    let every = times.len().div_ceil(SHOWN_FRAMES);
    let stage = Stage::new(&args.out)?;
    let out = stage.path();
    std::fs::create_dir_all(out.join("frames")).map_err(|e| ExperimentError::write(out, e))?;
    let bar = (!args.quiet && times.len() > 1)
        .then(|| super::progress::counting_bar(times.len(), "frames", "transforming"));
    let mut facts = Vec::with_capacity(times.len());
    // The frames the sheet, the animation and the page show (indices into facts).
    let mut pictures = Vec::new();
    let mut shown = Vec::new();
    let mut shapes: Vec<Placed> = Vec::new();
    let started = Instant::now();
    for (k, &time) in times.iter().enumerate() {
        if guard::interrupted() {
            return Err(CliError::msg("interrupted; nothing was written"));
        }
        let clock = Instant::now();
        t.at_into(time, &mut shapes);
        let derive_ms = clock.elapsed().as_secs_f64() * 1e3;
        let picture = painter.paint(&shapes);
        let cells = occupancy.cells(&shapes);
        let change = previous.as_ref().map_or(0.0, |p| change(p, &cells));
        previous = Some(cells);
        write_png_rgba(&out.join(format!("frames/frame_{k:03}.png")), &picture)?;
        if let Some(meshes) = &obj_meshes {
            let path = out.join(format!("frames/frame_{k:03}.obj"));
            let mut bytes = Vec::new();
            crate::score::write_obj(&mut bytes, &instances(&shapes), meshes)
                .map_err(|e| ExperimentError::write(&path, e))?;
            crate::score::write_atomically(&path, &bytes)?;
        }
        facts.push(FrameFacts {
            t: time,
            instances: shapes.len(),
            visible: visible(&shapes, painter.scale()),
            derive_ms,
            change,
        });
        if k % every == 0 || k + 1 == times.len() {
            pictures.push(if picture.width() > SHOWN_SIZE {
                image::imageops::resize(
                    &picture,
                    SHOWN_SIZE,
                    SHOWN_SIZE,
                    image::imageops::FilterType::Triangle,
                )
            } else {
                picture
            });
            shown.push(facts.len() - 1);
        }
        if let Some(bar) = &bar {
            bar.set_position(k as u64 + 1);
        }
    }
    if let Some(bar) = &bar {
        bar.finish_and_clear();
    }
    let step = pictures.len().div_ceil(SHEET_FRAMES).max(1);
    let mut sheet: Vec<_> = pictures.iter().step_by(step).cloned().collect();
    if pictures.len() > 1 && (pictures.len() - 1) % step != 0 {
        sheet.push(pictures[pictures.len() - 1].clone());
    }
    write_png_rgba(&out.join("contact.png"), &contact_sheet(&sheet, 4, 240))?;
    if pictures.len() > 1 {
        write_gif(&out.join("sequence.gif"), &pictures)?;
    }
    let title = format!(
        "{} → {}",
        t.first().graph().name(),
        t.second().graph().name()
    );
    let shown_facts: Vec<FrameFacts> = shown.iter().map(|&k| facts[k].clone()).collect();
    write_page(&out.join("index.html"), &title, &pictures, &shown_facts)?;
    let smoothness = Smoothness::of(&facts);
    let summary = serde_json::json!({
        "file": args.file.display().to_string(),
        "first": t.first().graph().name(),
        "second": t.second().graph().name(),
        "matches": t.matches().pairs().len(),
        "settings": {
            "pairing": t.settings().pairing,
            "mode": t.settings().mode,
            "pivot": t.settings().pivot,
        },
        "smoothness": smoothness,
        "rules": t.matched_rules().0,
        "matched_rules_percent": t.matched_rules().1,
        "parameters": 3 * t.matches().pairs().len(),
        "edits": file.edits,
        "terminals_mean": facts.iter().map(|f| f.instances as f64).sum::<f64>() / facts.len() as f64,
        "frames": facts,
    });
    write_json(&out.join("sequence.json"), &summary)?;
    write_json(
        &out.join("summary.json"),
        &serde_json::json!({ "frames": times.len(), "seconds": started.elapsed().as_secs_f64() }),
    )?;
    stage.publish()?;
    let (first, second) = (t.first().graph().name(), t.second().graph().name());
    if let [only] = facts.as_slice() {
        outln!(
            "`{first}` into `{second}` at t = {}: {} instances, {:.2} ms; wrote {}",
            only.t,
            only.instances,
            only.derive_ms,
            args.out.display()
        );
    } else {
        outln!(
            "{} frames of `{first}` into `{second}` ({} matches, {:.2} ms per model; largest change between frames {:.4} (1 - IoU), 95th percentile {:.4}, instance count changes {}) in {}",
            times.len(),
            t.matches().pairs().len(),
            facts.iter().map(|f| f.derive_ms).sum::<f64>() / facts.len() as f64,
            smoothness.largest_change,
            smoothness.p95_change,
            smoothness.count_changes,
            args.out.display()
        );
    }
    Ok(())
}

fn write_gif(path: &std::path::Path, frames: &[image::RgbaImage]) -> Result<(), CliError> {
    let mut bytes = Vec::new();
    {
        let mut encoder = GifEncoder::new_with_speed(&mut bytes, 10);
        encoder
            .set_repeat(Repeat::Infinite)
            .map_err(|e| ExperimentError::write(path, e))?;
        let delay = image::Delay::from_numer_denom_ms(40, 1);
        for f in frames {
            encoder
                .encode_frame(image::Frame::from_parts(f.clone(), 0, 0, delay))
                .map_err(|e| ExperimentError::write(path, e))?;
        }
    }
    crate::score::write_atomically(path, &bytes)?;
    Ok(())
}

/// A page with every frame embedded and a slider over the timeline.
fn write_page(
    path: &std::path::Path,
    title: &str,
    frames: &[image::RgbaImage],
    facts: &[FrameFacts],
) -> Result<(), CliError> {
    let mut uris = Vec::with_capacity(frames.len());
    for f in frames {
        let png = crate::score::png_bytes(path, f)?;
        uris.push(format!(
            "data:image/png;base64,{}",
            base64::engine::general_purpose::STANDARD.encode(png)
        ));
    }
    let times: Vec<f32> = facts.iter().map(|f| f.t).collect();
    let data = serde_json::json!({ "frames": uris, "times": times }).to_string();
    let title = title
        .replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;");
    let html = PAGE
        .replace("{{TITLE}}", &title)
        .replace("{{LAST}}", &(frames.len().saturating_sub(1)).to_string())
        .replace("{{DATA}}", &data.replace("</", "<\\/"));
    crate::score::write_atomically(path, html.as_bytes())?;
    Ok(())
}

const PAGE: &str = r#"<!doctype html>
<html lang="en"><head><meta charset="utf-8"><title>shapegen transformation</title>
<style>body{font-family:sans-serif;margin:2em;background:#fafafa}img{display:block;border:1px solid #ccc;background:#fff;max-width:100%}
input{width:min(100%,640px)}</style></head>
<body><h1>Design transformation: {{TITLE}}</h1>
<img id="frame" alt="the design at the chosen time">
<p><label>t = <output id="t">0</output><br><input id="slider" type="range" min="0" max="{{LAST}}" value="0"></label>
<button id="play" type="button">play</button></p>
<script id="data" type="application/json">{{DATA}}</script>
<script>
const data = JSON.parse(document.getElementById('data').textContent);
const img = document.getElementById('frame'), slider = document.getElementById('slider'), out = document.getElementById('t');
function show(k) { img.src = data.frames[k]; out.textContent = data.times[k].toFixed(3); }
slider.addEventListener('input', () => show(+slider.value));
let timer = null;
document.getElementById('play').addEventListener('click', () => {
  if (timer) { clearInterval(timer); timer = null; return; }
  timer = setInterval(() => { slider.value = (+slider.value + 1) % data.frames.length; show(+slider.value); }, 40);
});
show(0);
</script></body></html>
"#;
