//! `shapegen transform FILE --variations N`: variety from several designs
//! (thesis §5.5.1): the variations' pictures, their gallery, and how many
//! differ from every other and from the designs.

use std::time::Instant;

use rayon::prelude::*;

use super::args::{MixingArg, TransformArgs};
use super::{CliError, guard};
use crate::experiment::ExperimentError;
use crate::gallery::{Gallery, GalleryOptions};
use crate::output::{Stage, write_json};
use crate::score::{Viewpoint, write_png_rgba};
use crate::transform::sequence::{
    Occupancy, Painter, change, contact_sheet, instances, named_meshes,
};
use crate::transform::{Mixing, Placed, TransformFile, Variety};

/// The most variations one run makes.
const MAX_VARIATIONS: usize = 100_000;
/// Variations on the contact sheet at most.
const SHEET: usize = 48;
/// Side of each variation's picture.
const PICTURE: u32 = 240;
/// Cells along each side of the grid distinctness is measured on.
const GRID: u32 = 64;
/// Two models with an IoU at or above this are not distinct.
const SAME_IOU: f64 = 0.9;
/// Most variations whose distinctness is measured: every pair is compared
/// (2,000 take about 15 s on two cores).
const MAX_COMPARED: usize = 2_000;
/// What the command writes into `--out`.
const OUTPUTS: [&str; 5] = [
    "variations",
    "variations.png",
    "gallery.png",
    "variations.json",
    "summary.json",
];

/// Runs `shapegen transform FILE --variations N`.
pub(super) fn variations(
    args: &TransformArgs,
    file: TransformFile,
    count: usize,
) -> Result<(), CliError> {
    if !(1..=MAX_VARIATIONS).contains(&count) {
        return Err(CliError::msg(format!(
            "--variations {count}: between 1 and {MAX_VARIATIONS}"
        )));
    }
    let mixing = match args.mixing {
        MixingArg::Blend => Mixing::Blend,
        MixingArg::Switch => Mixing::Switch,
    };
    let t = &file.transformation;
    let mut designs = vec![t.first().clone(), t.second().clone()];
    designs.extend(file.more.iter().cloned());
    let variety = Variety::new(designs).map_err(|e| CliError::msg(e.to_string()))?;
    let _taken = guard::take_output_dir(&args.out)?;
    let mut inputs = file.inputs.clone();
    inputs.push(args.file.clone());
    let outputs: Vec<_> = OUTPUTS.iter().map(|f| args.out.join(f)).collect();
    guard::refuse_overwriting_inputs(&outputs, &inputs)?;
    let started = Instant::now();
    let seeds: Vec<u64> = (0..count as u64)
        .map(|i| args.seed.wrapping_add(i))
        .collect();
    let models: Vec<Vec<Placed>> = seeds
        .par_iter()
        .map(|&s| variety.variation(s, mixing))
        .collect();
    if guard::interrupted() {
        return Err(CliError::msg("interrupted; nothing was written"));
    }
    let names = variety.shapes();
    // The designs in the variety's shape numbering.
    let originals: Vec<Vec<Placed>> = variety
        .designs()
        .iter()
        .map(|d| {
            d.express()
                .iter()
                .map(|i| Placed {
                    shape: names
                        .iter()
                        .position(|n| *n == d.shapes()[i.shape as usize])
                        .expect("a design's shapes are the variety's")
                        as u16,
                    transform: i.transform,
                    source: crate::transform::Source::A(i.node),
                })
                .collect()
        })
        .collect();
    let distinct = if count <= MAX_COMPARED {
        Some(distinct(names, &models, &originals)?)
    } else {
        None
    };
    let stage = Stage::new(&args.out)?;
    let out = stage.path();
    let dir = out.join("variations");
    std::fs::create_dir_all(&dir).map_err(|e| ExperimentError::write(&dir, e))?;
    let viewpoint = Viewpoint {
        azimuth: file.frames.azimuth.to_radians(),
        elevation: file.frames.elevation.to_radians(),
    };
    let framing: Vec<Placed> = models.iter().chain(&originals).flatten().copied().collect();
    let painter = Painter::framing(names, &framing, viewpoint, PICTURE)?;
    let obj_meshes = if args.obj {
        Some(named_meshes(names)?)
    } else {
        None
    };
    let bar = (!args.quiet && count > 1)
        .then(|| super::progress::counting_bar(count, "variations", "drawing"));
    let sheet: Vec<image::RgbaImage> = models
        .par_iter()
        .enumerate()
        .map_init(
            || painter.clone(),
            |painter, (k, shapes)| -> Result<Option<image::RgbaImage>, CliError> {
                if let Some(bar) = &bar {
                    bar.inc(1);
                }
                let picture = painter.paint(shapes);
                write_png_rgba(&dir.join(format!("{k:03}.png")), &picture)?;
                if let Some(meshes) = &obj_meshes {
                    let path = dir.join(format!("{k:03}.obj"));
                    let mut bytes = Vec::new();
                    crate::score::write_obj(&mut bytes, &instances(shapes), meshes)
                        .map_err(|e| ExperimentError::write(&path, e))?;
                    crate::score::write_atomically(&path, &bytes)?;
                }
                Ok((k < SHEET).then_some(picture))
            },
        )
        .collect::<Result<Vec<_>, _>>()?
        .into_iter()
        .flatten()
        .collect();
    if let Some(bar) = &bar {
        bar.finish_and_clear();
    }
    write_png_rgba(&out.join("variations.png"), &contact_sheet(&sheet, 8, 160))?;
    // The gallery: the first design in the middle, the variations around it.
    let mut gallery_models = vec![instances(&originals[0])];
    gallery_models.extend(models.iter().map(|m| instances(m)));
    let options = GalleryOptions {
        clusters: 14.min(count + 1).max(2),
        seed: args.seed,
        ..GalleryOptions::default()
    };
    let gallery = Gallery::of_instances(
        "first design",
        &named_meshes(names)?,
        gallery_models,
        &options,
        &|_| {},
    )
    .map_err(|e| CliError::msg(e.to_string()))?;
    write_png_rgba(&out.join("gallery.png"), &gallery.picture())?;
    let clusters = gallery.clusters.iter().filter(|c| c.size > 0).count();
    let share = distinct
        .as_ref()
        .map(|d| 100.0 * d.iter().filter(|d| **d).count() as f64 / count as f64);
    let json = serde_json::json!({
        "file": args.file.display().to_string(),
        "designs": variety.designs().iter().map(|d| serde_json::json!({
            "generator": d.graph().name(),
            "genes": d.chromosome().len(),
        })).collect::<Vec<_>>(),
        "mixing": mixing,
        "seed": args.seed,
        "count": count,
        "distinct_percent": share,
        "distinct_iou_below": SAME_IOU,
        "gallery_clusters": clusters,
        "variations": models.iter().enumerate().map(|(k, m)| serde_json::json!({
            "index": k,
            "seed": seeds[k],
            "instances": m.len(),
            "distinct": distinct.as_ref().map(|d| d[k]),
            "cluster": gallery.models[k + 1].cluster,
            "picture": format!("variations/{k:03}.png"),
        })).collect::<Vec<_>>(),
        "reproduce": "Variety::new(designs)?.variation(seed, mixing) with the designs in this order",
    });
    write_json(&out.join("variations.json"), &json)?;
    write_json(
        &out.join("summary.json"),
        &serde_json::json!({ "variations": count, "seconds": started.elapsed().as_secs_f64() }),
    )?;
    stage.publish()?;
    outln!(
        "{count} variations of {} designs ({}): {}, {clusters} gallery clusters, {:.1} s; in {}",
        variety.designs().len(),
        match mixing {
            Mixing::Blend => "blended",
            Mixing::Switch => "rules switched",
        },
        match share {
            Some(s) => format!(
                "{s:.1} % distinct (IoU below {SAME_IOU} with every other and every design)"
            ),
            None => format!("distinctness not measured above {MAX_COMPARED} variations"),
        },
        started.elapsed().as_secs_f64(),
        args.out.display()
    );
    Ok(())
}

/// For each variation, whether its IoU with every other variation and
/// every design is below [`SAME_IOU`] (on one grid fitted to them all).
fn distinct(
    names: &[std::borrow::Cow<'static, str>],
    models: &[Vec<Placed>],
    designs: &[Vec<Placed>],
) -> Result<Vec<bool>, CliError> {
    let all = models.iter().chain(designs).flatten();
    let occupancy = Occupancy::around(names, all, GRID)?;
    let cells: Vec<Vec<u64>> = models
        .iter()
        .chain(designs)
        .collect::<Vec<_>>()
        .par_iter()
        .map_init(|| occupancy.clone(), |o, m| o.cells(m))
        .collect();
    let n = models.len();
    Ok((0..n)
        .into_par_iter()
        .map(|i| {
            (0..cells.len())
                .filter(|&j| j != i)
                .all(|j| 1.0 - change(&cells[i], &cells[j]) < SAME_IOU)
        })
        .collect())
}
