//! Transformation files (TOML): two designs, match overrides, settings,
//! timelines and how to show the sequence. Every table refuses unknown
//! keys; mistakes are reported as `file:line:column`.
//!
//! ```toml
//! [first]
//! generator = "monopodial_tree"
//! model = "default"            # or chromosome = "best.json", or seed = 7
//!
//! [second]
//! generator = "sympodial_tree"
//! model = "default"
//!
//! [[design]]                   # more designs, for `--variations` (any number)
//! generator = "tree_v2"
//! seed = 3
//!
//! [blend]
//! pairing = "munkres"          # or "mutual_nearest"
//! mode = "grow"                # or "thesis"
//! pivot = "base"               # or "centre"
//! spacer = "wall"              # the tag of split rules' spacers (default)
//! merge = false                # one-to-many matches, intersecting blends merged
//!
//! [matches]
//! add = [["A", "B"]]           # first generator's node, second's
//! remove = []
//!
//! [[timeline]]                 # one per match to change; the rest span [0, 1]
//! first = "A"
//! second = "B"
//! start = 0.0
//! end = 0.6
//! threshold = 0.3
//!
//! [frames]
//! count = 200
//! size = 400
//! azimuth = 30.0               # degrees about the vertical (default 35)
//! elevation = 20.0             # degrees above the horizon (default 20)
//! ```

use std::path::{Path, PathBuf};

use serde::Deserialize;
use toml::Spanned;

use super::{Design, Mode, PairingMethod, Pivot, Settings, Timeline, Transformation};
use crate::registry::Registry;

/// A transformation file that cannot be used.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum TransformFileError {
    /// The file cannot be read.
    #[error("{}: cannot read the transformation: {source}", path.display())]
    Read {
        /// The file.
        path: PathBuf,
        /// The cause.
        source: std::io::Error,
    },
    /// A key is missing, unknown or has an unusable value.
    #[error("{file}:{line}:{column}: {message}")]
    Invalid {
        /// The file.
        file: String,
        /// 1-based line.
        line: usize,
        /// 1-based column.
        column: usize,
        /// What is wrong (with the key's name).
        message: String,
    },
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct File {
    first: Spanned<Side>,
    second: Spanned<Side>,
    #[serde(default)]
    design: Vec<Spanned<Side>>,
    #[serde(default)]
    blend: Blending,
    #[serde(default)]
    matches: MatchEdits,
    #[serde(default)]
    timeline: Vec<Spanned<TimelineEntry>>,
    #[serde(default)]
    frames: Frames,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct Side {
    generator: Spanned<String>,
    model: Option<Spanned<String>>,
    chromosome: Option<Spanned<String>>,
    seed: Option<u64>,
}

#[derive(Default, Deserialize)]
#[serde(deny_unknown_fields, default)]
struct Blending {
    pairing: PairingMethod,
    mode: Mode,
    pivot: Pivot,
    spacer: Option<Spanned<String>>,
    merge: bool,
}

#[derive(Default, Deserialize)]
#[serde(deny_unknown_fields, default)]
struct MatchEdits {
    add: Vec<Spanned<(String, String)>>,
    remove: Vec<Spanned<(String, String)>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct TimelineEntry {
    first: String,
    second: String,
    #[serde(flatten)]
    timeline: Timeline,
}

/// `[frames]`: how a sequence is shown.
#[derive(Clone, Copy, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Frames {
    /// Frames in the sequence, both ends included (at least 2).
    pub count: usize,
    /// Side of each frame's picture, in pixels.
    pub size: u32,
    /// The camera's angle about the vertical, in degrees.
    pub azimuth: f64,
    /// The camera's angle above the horizon, in degrees.
    pub elevation: f64,
}

impl Frames {
    /// How many frames a sequence may have.
    pub const COUNTS: std::ops::RangeInclusive<usize> = 2..=10_000;

    /// Why `count` frames are not a sequence, if they are not.
    #[must_use]
    pub fn count_problem(count: usize) -> Option<String> {
        (!Self::COUNTS.contains(&count)).then(|| {
            format!(
                "between {} and {} frames",
                Self::COUNTS.start(),
                Self::COUNTS.end()
            )
        })
    }
}

impl Default for Frames {
    fn default() -> Self {
        Self {
            count: 60,
            size: 360,
            azimuth: 35.0,
            elevation: 20.0,
        }
    }
}

/// A loaded transformation file.
#[derive(Debug)]
pub struct TransformFile {
    /// The transformation it describes.
    pub transformation: Transformation,
    /// The designs of `[[design]]` tables, which variations mix with the
    /// first and the second ([`Variety`](super::Variety)).
    pub more: Vec<Design>,
    /// How to show it.
    pub frames: Frames,
    /// Files it read (chromosomes), which outputs must not replace.
    pub inputs: Vec<PathBuf>,
    /// The user's edits: matches added or removed and timelines set (the
    /// thesis's "#Edits", Tab. 5.1).
    pub edits: usize,
}

struct Src<'a> {
    name: String,
    text: &'a str,
}

impl Src<'_> {
    fn error(
        &self,
        span: std::ops::Range<usize>,
        message: impl Into<String>,
    ) -> TransformFileError {
        let at = span.start.min(self.text.len());
        let before = &self.text[..at];
        TransformFileError::Invalid {
            file: self.name.clone(),
            line: before.matches('\n').count() + 1,
            column: before.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1,
            message: message.into(),
        }
    }
}

impl TransformFile {
    /// Reads `path`, naming generators from `registry`; chromosome files
    /// are read relative to the file's folder.
    pub fn load(path: &Path, registry: &Registry) -> Result<Self, TransformFileError> {
        let text = std::fs::read_to_string(path).map_err(|source| TransformFileError::Read {
            path: path.to_path_buf(),
            source,
        })?;
        let base = path.parent().unwrap_or(Path::new("."));
        Self::parse(&path.display().to_string(), &text, base, registry)
    }

    /// Parses `text` (named `name` in errors); chromosome paths are relative to `base`.
    pub fn parse(
        name: &str,
        text: &str,
        base: &Path,
        registry: &Registry,
    ) -> Result<Self, TransformFileError> {
        let src = Src {
            name: name.to_string(),
            text,
        };
        let file: File = match toml::de::Deserializer::parse(text) {
            Err(e) => return Err(src.error(e.span().unwrap_or(0..0), e.message())),
            Ok(de) => serde_path_to_error::deserialize(de).map_err(|e| {
                let key = crate::experiment::toml_key(e.path());
                let inner = e.into_inner();
                let message = if key.is_empty() {
                    inner.message().to_string()
                } else {
                    format!("`{key}`: {}", inner.message())
                };
                src.error(inner.span().unwrap_or(0..0), message)
            })?,
        };
        let mut inputs = Vec::new();
        let a = design(&src, &file.first, "first", base, registry, &mut inputs)?;
        let b = design(&src, &file.second, "second", base, registry, &mut inputs)?;
        let more = file
            .design
            .iter()
            .map(|d| design(&src, d, "design", base, registry, &mut inputs))
            .collect::<Result<Vec<_>, _>>()?;
        let mut t = Transformation::new(a, b).with_settings(Settings {
            pairing: file.blend.pairing,
            mode: file.blend.mode,
            pivot: file.blend.pivot,
            merge: file.blend.merge,
        });
        if let Some(spacer) = &file.blend.spacer {
            t = t
                .with_spacer(spacer.get_ref())
                .map_err(|e| src.error(spacer.span(), format!("`blend.spacer`: {e}")))?;
        }
        for m in &file.matches.add {
            let (x, y) = m.get_ref();
            t.add_match(x, y)
                .map_err(|e| src.error(m.span(), format!("`matches.add`: {e}")))?;
        }
        for m in &file.matches.remove {
            let (x, y) = m.get_ref();
            t.remove_match(x, y)
                .map_err(|e| src.error(m.span(), format!("`matches.remove`: {e}")))?;
        }
        for e in &file.timeline {
            let entry = e.get_ref();
            t.set_timeline(&entry.first, &entry.second, entry.timeline)
                .map_err(|err| src.error(e.span(), format!("`timeline`: {err}")))?;
        }
        let f = file.frames;
        if let Some(problem) = Frames::count_problem(f.count) {
            return Err(src.error(0..0, format!("`frames.count`: {problem}")));
        }
        if !(16..=4096).contains(&f.size) {
            return Err(src.error(0..0, "`frames.size`: between 16 and 4096 pixels"));
        }
        if !f.azimuth.is_finite() || !(-89.0..=89.0).contains(&f.elevation) {
            return Err(src.error(
                0..0,
                "`frames`: azimuth is a finite angle, elevation within ±89 degrees",
            ));
        }
        Ok(Self {
            transformation: t,
            more,
            frames: f,
            inputs,
            edits: file.matches.add.len() + file.matches.remove.len() + file.timeline.len(),
        })
    }
}

fn design(
    src: &Src<'_>,
    side: &Spanned<Side>,
    which: &str,
    base: &Path,
    registry: &Registry,
    inputs: &mut Vec<PathBuf>,
) -> Result<Design, TransformFileError> {
    let s = side.get_ref();
    let name = s.generator.get_ref();
    let Some(graph) = registry.graph(name) else {
        return Err(src.error(
            s.generator.span(),
            format!(
                "`{which}.generator`: no generator `{name}` (registered: {})",
                registry.names().collect::<Vec<_>>().join(", ")
            ),
        ));
    };
    let given = usize::from(s.model.is_some())
        + usize::from(s.chromosome.is_some())
        + usize::from(s.seed.is_some());
    if given > 1 {
        return Err(src.error(
            side.span(),
            format!("`{which}`: give one of `model`, `chromosome` and `seed`"),
        ));
    }
    let chromosome = if let Some(path) = &s.chromosome {
        let p = base.join(path.get_ref());
        let text = std::fs::read_to_string(&p).map_err(|e| {
            src.error(
                path.span(),
                format!("`{which}.chromosome`: cannot read {}: {e}", p.display()),
            )
        })?;
        inputs.push(p.clone());
        let data: crate::genome::ChromosomeData = serde_json::from_str(&text).map_err(|e| {
            src.error(
                path.span(),
                format!(
                    "`{which}.chromosome`: {}: not a chromosome file: {e}",
                    p.display()
                ),
            )
        })?;
        crate::genome::Chromosome::from_data(graph, &data).map_err(|e| {
            src.error(
                path.span(),
                format!("`{which}.chromosome`: {}: {e}", p.display()),
            )
        })?
    } else if let Some(seed) = s.seed {
        let mut rng = crate::rng::stream(seed, &[0x7472_616e]);
        crate::ops::uncontrolled(graph, &mut rng)
            .map_err(|e| src.error(side.span(), format!("`{which}.seed`: {e}")))?
    } else {
        if let Some(m) = &s.model
            && m.get_ref() != "default"
        {
            return Err(src.error(
                m.span(),
                format!("`{which}.model`: the only model by name is \"default\""),
            ));
        }
        crate::ops::default_model(graph)
            .map_err(|e| src.error(side.span(), format!("`{which}`: {e}")))?
    };
    registry
        .design(name, chromosome)
        .map_err(|e| src.error(side.span(), format!("`{which}`: {e}")))
}
