//! A design session: the models a user scored, per factor, and what was
//! learned from them, in one JSON file that every step reads and rewrites
//! atomically, so a session can be stopped and resumed at any point.
//!
//! The steps (what `shapegen design sample | learn | export` do):
//! 1. [`Session::sample`] draws a batch of models by a [`Mode`] and keeps
//!    them as *pending* (with ids) until they are scored;
//! 2. [`Session::score`] moves a pending model, with its score (0–100), to
//!    the current factor's scored models (or re-scores a scored one);
//! 3. [`Session::learn`] fits every factor that has scores;
//! 4. [`Session::export`] draws training models from the learned preference
//!    by rejection sampling and fits a [`LearnedPdf`].

use std::path::Path;

use rand::Rng;
use serde::{Deserialize, Serialize};
use shapegen_design::{
    DesignError, Factor, FactorOptions, LearnedPdf, Learner, Preference, RejectionSampler,
    StructureOptions, StructureReport, learn_pdf,
};

use crate::genome::{Chromosome, ChromosomeData};
use crate::graph::Graph;
use crate::ops::uncontrolled;

/// Current version of the session file format.
pub const SESSION_VERSION: u32 = 1;

/// What went wrong with a session.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum SessionError {
    /// Reading or writing the file.
    #[error("{path}: {source}")]
    Io {
        /// The file.
        path: String,
        /// Why.
        source: std::io::Error,
    },
    /// The file is not a session.
    #[error("{path} is not a shapegen design session: {why}")]
    Format {
        /// The file.
        path: String,
        /// Why.
        why: String,
    },
    /// The session belongs to another generator.
    #[error(
        "the session is for generator `{found}`, not `{expected}` (its graph changed, or another experiment was given)"
    )]
    ForeignGenerator {
        /// The session's.
        found: String,
        /// The experiment's.
        expected: String,
    },
    /// A score outside 0–100 or not a number.
    #[error("score {score} of model {id} is outside 0..=100")]
    ScoreRange {
        /// The model.
        id: u64,
        /// The score.
        score: f64,
    },
    /// An id that is neither pending nor scored.
    #[error("no model {0} in this session (it was not sampled here, or its batch was replaced)")]
    UnknownModel(u64),
    /// A factor the session does not have.
    #[error("no factor `{0}` in this session")]
    UnknownFactor(String),
    /// A mode that needs a learned preference, before any.
    #[error("mode `{0}` needs a learned preference: score some models and run `learn` first")]
    NotLearned(&'static str),
    /// The file changed on disk since this copy was read: another program
    /// (the design server, another `design` command) saved it. Nothing was
    /// written.
    #[error(
        "{path} was changed by another program since it was read (it is at revision {found}, this copy was read at {read}): nothing was saved; run the command again, or reload the page"
    )]
    Changed {
        /// The file.
        path: String,
        /// The revision this copy was read at (`none`: a new session).
        read: String,
        /// The revision on disk (`none`: no file).
        found: String,
    },
    /// A factor's name the session does not take.
    #[error(
        "a factor's name must be 1 to {MAX_FACTOR_NAME} characters (not counting spaces around it), got `{0}`"
    )]
    FactorName(String),
    /// Every model id was used.
    #[error("the session has used every model id: start a new session")]
    IdsExhausted,
    /// Learning or sampling.
    #[error(transparent)]
    Design(#[from] DesignError),
}

/// Longest factor name, in characters.
pub const MAX_FACTOR_NAME: usize = 80;

/// How a batch of models is chosen (the thesis's §4.6).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
#[cfg_attr(feature = "cli", derive(clap::ValueEnum))]
pub enum Mode {
    /// From the generator's default pdf (uncontrolled generation).
    Default,
    /// From the current pdf: the default reweighted by the learned preference.
    Current,
    /// From the complementary pdf: reweighted by 100 minus the preference.
    Complementary,
    /// The default samples the preference is least sure about.
    Uncertain,
    /// The current factor's scored models, to correct mistakes.
    Scored,
}

impl Mode {
    /// The mode's name as the command line spells it.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::Default => "default",
            Self::Current => "current",
            Self::Complementary => "complementary",
            Self::Uncertain => "uncertain",
            Self::Scored => "scored",
        }
    }
}

/// A scored model.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Scored {
    /// Its id in the session.
    pub id: u64,
    /// The model.
    pub model: ChromosomeData,
    /// Its score, 0–100.
    pub score: f64,
}

/// A model shown but not scored yet.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Pending {
    /// Its id in the session.
    pub id: u64,
    /// The model.
    pub model: ChromosomeData,
}

/// One factor's scores.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct FactorScores {
    /// The factor's name.
    pub name: String,
    /// Its scored models.
    pub scored: Vec<Scored>,
    /// Whether it is part of the preference (the product of the active
    /// factors with scores).
    #[serde(default = "active")]
    pub active: bool,
}

fn active() -> bool {
    true
}

/// A model of a batch with what the preference predicts for it.
#[derive(Clone, Debug)]
pub struct Shown {
    /// Its id (what a score names).
    pub id: u64,
    /// The model.
    pub model: Chromosome,
    /// Predicted score and its standard deviation, once learned.
    pub predicted: Option<(f64, f64)>,
    /// Its score so far (mode `scored`).
    pub score: Option<f64>,
}

/// A design session.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Session {
    /// Format version ([`SESSION_VERSION`]).
    pub version: u32,
    /// The generator's name.
    pub generator: String,
    /// Its graph's fingerprint (16 hex digits).
    pub fingerprint: String,
    /// The factors; the preference is their product.
    pub factors: Vec<FactorScores>,
    /// The factor that scores go to.
    pub current: usize,
    /// The last batch's models not scored yet.
    pub pending: Vec<Pending>,
    /// The next model id.
    pub next_id: u64,
    /// Batches drawn so far (each draws from its own random stream).
    pub batches: u64,
    /// Seed of the session's random streams.
    pub seed: u64,
    /// The learned factors (one per factor with scores), after `learn`.
    #[serde(default)]
    pub learned: Option<Preference>,
    /// The models of the last batch, in the order shown (pending or scored).
    #[serde(default)]
    pub shown: Vec<u64>,
    /// How the last batch was drawn.
    #[serde(default)]
    pub mode: Option<Mode>,
    /// Scores given since the last `learn` (a refit is due).
    #[serde(default)]
    pub stale: bool,
    /// How many times the session was saved (by the design server or a
    /// `design` command): a page that sends an older revision is told the
    /// session changed elsewhere, and a writer that read an older one is
    /// refused (see [`save`](Self::save)).
    #[serde(default)]
    pub revision: u64,
    /// The revision on disk when this copy was read or last saved; `None`
    /// for a session not yet saved.
    #[serde(skip)]
    read_at: Option<u64>,
}

/// What [`Session::revision_on_disk`] reads of the file.
#[derive(Deserialize)]
struct OnDisk {
    #[serde(default)]
    revision: u64,
}

/// `name` trimmed, if it is a factor's name the session takes.
fn check_factor_name(name: &str) -> Result<&str, SessionError> {
    let trimmed = name.trim();
    let length = trimmed.chars().count();
    if length == 0 || length > MAX_FACTOR_NAME || trimmed.chars().any(char::is_control) {
        return Err(SessionError::FactorName(name.to_string()));
    }
    Ok(trimmed)
}

fn fingerprint(graph: &Graph) -> String {
    format!("{:016x}", graph.fingerprint())
}

impl Session {
    /// A new session for `graph` with one factor called `preference`.
    #[must_use]
    pub fn new(generator: &str, graph: &Graph, seed: u64) -> Self {
        Self {
            version: SESSION_VERSION,
            generator: generator.to_string(),
            fingerprint: fingerprint(graph),
            factors: vec![FactorScores {
                name: "preference".into(),
                scored: Vec::new(),
                active: true,
            }],
            current: 0,
            pending: Vec::new(),
            next_id: 0,
            batches: 0,
            seed,
            learned: None,
            shown: Vec::new(),
            mode: None,
            stale: false,
            revision: 0,
            read_at: None,
        }
    }

    /// Reads a session and checks it against `graph` (the generator's
    /// fingerprint, and every stored model against the graph).
    pub fn load(path: &Path, generator: &str, graph: &Graph) -> Result<Self, SessionError> {
        let text = std::fs::read_to_string(path).map_err(|source| SessionError::Io {
            path: path.display().to_string(),
            source,
        })?;
        let format = |why: String| SessionError::Format {
            path: path.display().to_string(),
            why,
        };
        let mut session: Self = serde_json::from_str(&text).map_err(|e| format(e.to_string()))?;
        session.read_at = Some(session.revision);
        if session.version != SESSION_VERSION {
            return Err(format(format!(
                "format version {} (this build reads {SESSION_VERSION})",
                session.version
            )));
        }
        if session.fingerprint != fingerprint(graph) {
            return Err(SessionError::ForeignGenerator {
                found: session.generator,
                expected: generator.to_string(),
            });
        }
        if session.factors.is_empty() || session.current >= session.factors.len() {
            return Err(format(
                "no factor, or the current factor does not exist".into(),
            ));
        }
        let all = session.pending.iter().map(|p| (p.id, &p.model)).chain(
            session
                .factors
                .iter()
                .flat_map(|f| f.scored.iter().map(|s| (s.id, &s.model))),
        );
        for (id, data) in all {
            Chromosome::from_data(graph, data).map_err(|e| format(format!("model {id}: {e}")))?;
        }
        for s in session.factors.iter().flat_map(|f| &f.scored) {
            if !(0.0..=100.0).contains(&s.score) {
                return Err(SessionError::ScoreRange {
                    id: s.id,
                    score: s.score,
                });
            }
        }
        session.check_ids().map_err(format)?;
        for f in &session.factors {
            check_factor_name(&f.name).map_err(|e| format(e.to_string()))?;
        }
        if let Some(p) = &session.learned {
            p.check(graph)
                .map_err(|e| format(format!("its learned preference: {e}")))?;
        }
        Ok(session)
    }

    /// Every id below `next_id`, none twice in the pending batch or in one
    /// factor, every shown one stored.
    fn check_ids(&self) -> Result<(), String> {
        let lists = std::iter::once((
            "the pending batch".to_string(),
            self.pending.iter().map(|p| p.id).collect::<Vec<u64>>(),
        ))
        .chain(self.factors.iter().map(|f| {
            (
                format!("factor `{}`", f.name),
                f.scored.iter().map(|s| s.id).collect(),
            )
        }));
        for (what, mut ids) in lists {
            ids.sort_unstable();
            if let Some(w) = ids.windows(2).find(|w| w[0] == w[1]) {
                return Err(format!("{what} holds model {} twice", w[0]));
            }
            if let Some(&last) = ids.last()
                && last >= self.next_id
            {
                return Err(format!(
                    "{what} holds model {last}, but the next id is {}",
                    self.next_id
                ));
            }
        }
        if let Some(id) = self.shown.iter().find(|&&id| self.model(id).is_none()) {
            return Err(format!("it shows model {id}, which it does not hold"));
        }
        Ok(())
    }

    /// Writes the session atomically (a temporary file renamed over it) as
    /// the next revision, unless the file changed since this copy was read
    /// or last saved: then nothing is written and the error is
    /// [`SessionError::Changed`]. Writers in other processes (the design
    /// server, `design` commands) are kept apart by an advisory lock on
    /// `PATH.lock` beside the file while they compare and write, so no
    /// writer ever replaces a revision it did not read.
    pub fn save(&mut self, path: &Path) -> Result<(), SessionError> {
        let io = |source: std::io::Error| SessionError::Io {
            path: path.display().to_string(),
            source,
        };
        let mut lock_name = path.file_name().unwrap_or_default().to_os_string();
        lock_name.push(".lock");
        let lock = std::fs::OpenOptions::new()
            .create(true)
            .truncate(false)
            .write(true)
            .open(path.with_file_name(lock_name))
            .map_err(io)?;
        lock.lock().map_err(io)?;
        let on_disk = Self::revision_on_disk(path)?;
        // A file removed since it was read loses nothing by being written.
        if on_disk.is_some() && on_disk != self.read_at {
            let show = |r: Option<u64>| r.map_or_else(|| "none".into(), |r| r.to_string());
            return Err(SessionError::Changed {
                path: path.display().to_string(),
                read: show(self.read_at),
                found: show(on_disk),
            });
        }
        let mut next = self.clone();
        next.revision = match self.read_at {
            Some(r) => r + 1,
            None => self.revision,
        };
        let text = serde_json::to_string_pretty(&next).map_err(|e| SessionError::Format {
            path: path.display().to_string(),
            why: e.to_string(),
        })?;
        crate::score::write_atomically(path, text.as_bytes())
            .map_err(|e| io(std::io::Error::other(e.to_string())))?;
        self.revision = next.revision;
        self.read_at = Some(next.revision);
        Ok(())
    }

    /// The revision of the session file at `path` (`None` if there is no
    /// file): what a holder of a session compares with its own to see
    /// whether another program saved it.
    pub fn revision_on_disk(path: &Path) -> Result<Option<u64>, SessionError> {
        match std::fs::read(path) {
            Ok(bytes) => serde_json::from_slice::<OnDisk>(&bytes)
                .map(|d| Some(d.revision))
                .map_err(|e| SessionError::Format {
                    path: path.display().to_string(),
                    why: e.to_string(),
                }),
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(None),
            Err(source) => Err(SessionError::Io {
                path: path.display().to_string(),
                source,
            }),
        }
    }

    /// Makes `name` (trimmed; 1 to [`MAX_FACTOR_NAME`] characters) the
    /// current factor, creating it if needed.
    pub fn select_factor(&mut self, name: &str) -> Result<(), SessionError> {
        let name = check_factor_name(name)?;
        match self.factors.iter().position(|f| f.name == name) {
            Some(i) => self.current = i,
            None => {
                self.factors.push(FactorScores {
                    name: name.to_string(),
                    scored: Vec::new(),
                    active: true,
                });
                self.current = self.factors.len() - 1;
            }
        }
        Ok(())
    }

    /// Takes factor `name` into the preference or leaves it out; the
    /// preference is refitted at the next [`learn`](Self::learn).
    pub fn set_active(&mut self, name: &str, active: bool) -> Result<(), SessionError> {
        let f = self
            .factors
            .iter_mut()
            .find(|f| f.name == name)
            .ok_or_else(|| SessionError::UnknownFactor(name.to_string()))?;
        if f.active != active {
            f.active = active;
            self.stale = true;
        }
        Ok(())
    }

    /// Scored models over all factors.
    #[must_use]
    pub fn scored_count(&self) -> usize {
        self.factors.iter().map(|f| f.scored.len()).sum()
    }

    /// Draws a batch of `count` models by `mode`; they replace the pending
    /// batch. Batch `b` draws from the random stream `(seed, b)`.
    pub fn sample(
        &mut self,
        graph: &Graph,
        mode: Mode,
        count: usize,
    ) -> Result<Vec<Shown>, SessionError> {
        let preference = self.learned.clone();
        let predict = |m: &Chromosome| preference.as_ref().map(|p| p.predict(graph, m));
        let mut rng = crate::rng::stream(self.seed, &[0x6465_7369, self.batches]);
        let models: Vec<(Option<u64>, Chromosome, Option<f64>)> = match mode {
            Mode::Default => (0..count)
                .map(|_| uncontrolled(graph, &mut rng).map(|m| (None, m, None)))
                .collect::<Result<_, _>>()
                .map_err(DesignError::from)?,
            Mode::Current | Mode::Complementary => {
                let p = preference
                    .as_ref()
                    .ok_or(SessionError::NotLearned(mode.name()))?;
                let complementary = mode == Mode::Complementary;
                let u = |m: &Chromosome| {
                    let v = p.value(graph, m);
                    if complementary { 1.0 - v } else { v }
                };
                let mut sampler =
                    RejectionSampler::new(graph, &u, 200, &mut rng)?.with_max_proposals(200_000);
                (0..count)
                    .map(|_| sampler.sample(&mut rng).map(|m| (None, m, None)))
                    .collect::<Result<_, _>>()?
            }
            Mode::Uncertain => {
                let p = preference
                    .as_ref()
                    .ok_or(SessionError::NotLearned(mode.name()))?;
                let mut pool: Vec<(f64, Chromosome)> = (0..count * 10)
                    .map(|_| uncontrolled(graph, &mut rng).map(|m| (p.predict(graph, &m).1, m)))
                    .collect::<Result<_, _>>()
                    .map_err(DesignError::from)?;
                pool.sort_by(|a, b| b.0.total_cmp(&a.0));
                pool.into_iter()
                    .take(count)
                    .map(|(_, m)| (None, m, None))
                    .collect()
            }
            Mode::Scored => {
                let factor = &self.factors[self.current];
                let mut scored: Vec<&Scored> = factor.scored.iter().collect();
                scored.sort_by(|a, b| b.score.total_cmp(&a.score).then(a.id.cmp(&b.id)));
                scored
                    .into_iter()
                    .take(count)
                    .map(|s| {
                        Chromosome::from_data(graph, &s.model)
                            .map(|m| (Some(s.id), m, Some(s.score)))
                            .map_err(|e| SessionError::Design(e.into()))
                    })
                    .collect::<Result<_, _>>()?
            }
        };
        let fresh = models.iter().filter(|m| m.0.is_none()).count() as u64;
        if self.next_id.checked_add(fresh).is_none() {
            return Err(SessionError::IdsExhausted);
        }
        self.batches += 1;
        self.pending.clear();
        self.mode = Some(mode);
        let mut shown = Vec::with_capacity(models.len());
        for (id, model, score) in models {
            let id = id.unwrap_or_else(|| {
                let id = self.next_id;
                self.next_id += 1;
                id
            });
            if score.is_none() {
                self.pending.push(Pending {
                    id,
                    model: model.to_data(graph),
                });
            }
            shown.push(Shown {
                id,
                predicted: predict(&model),
                model,
                score,
            });
        }
        self.shown = shown.iter().map(|s| s.id).collect();
        Ok(shown)
    }

    /// Gives model `id` (pending, or scored for the current factor) the
    /// score `score` for the current factor.
    pub fn score(&mut self, id: u64, score: f64) -> Result<(), SessionError> {
        if !(0.0..=100.0).contains(&score) {
            return Err(SessionError::ScoreRange { id, score });
        }
        let factor = &mut self.factors[self.current];
        if let Some(s) = factor.scored.iter_mut().find(|s| s.id == id) {
            s.score = score;
            self.stale = true;
            return Ok(());
        }
        let at = self
            .pending
            .iter()
            .position(|p| p.id == id)
            .ok_or(SessionError::UnknownModel(id))?;
        let p = self.pending.remove(at);
        factor.scored.push(Scored {
            id,
            model: p.model,
            score,
        });
        self.stale = true;
        Ok(())
    }

    /// Model `id` as stored (pending, or scored for any factor) and its
    /// score for the current factor, if any.
    #[must_use]
    pub fn model(&self, id: u64) -> Option<(&ChromosomeData, Option<f64>)> {
        let current = self.factors[self.current]
            .scored
            .iter()
            .find(|s| s.id == id);
        if let Some(s) = current {
            return Some((&s.model, Some(s.score)));
        }
        self.pending
            .iter()
            .find(|p| p.id == id)
            .map(|p| &p.model)
            .or_else(|| {
                self.factors
                    .iter()
                    .flat_map(|f| &f.scored)
                    .find(|s| s.id == id)
                    .map(|s| &s.model)
            })
            .map(|m| (m, None))
    }

    /// Fits one factor per active factor with scores; the preference is their product.
    pub fn learn(
        &mut self,
        graph: &Graph,
        options: FactorOptions,
    ) -> Result<&Preference, SessionError> {
        let mut factors = Vec::new();
        for f in self
            .factors
            .iter()
            .filter(|f| f.active && !f.scored.is_empty())
        {
            let models: Vec<Chromosome> = f
                .scored
                .iter()
                .map(|s| Chromosome::from_data(graph, &s.model))
                .collect::<Result<_, _>>()
                .map_err(DesignError::from)?;
            let scores: Vec<f64> = f.scored.iter().map(|s| s.score).collect();
            factors.push(Factor::fit(&f.name, graph, &models, &scores, options)?);
        }
        if factors.is_empty() {
            return Err(DesignError::NoScores.into());
        }
        self.stale = false;
        Ok(self.learned.insert(Preference { factors }))
    }

    /// The random stream [`export`](Self::export) draws from by default:
    /// derived from `seed`, else the session's seed.
    #[must_use]
    pub fn export_stream(&self, seed: Option<u64>) -> crate::rng::ShapeRng {
        crate::rng::stream(seed.unwrap_or(self.seed), &[0x6578_706f])
    }

    /// Draws `training` models from the learned preference (rejection
    /// sampling with `rng`, e.g. [`export_stream`](Self::export_stream))
    /// and fits a learned pdf with `learner`.
    pub fn export<R: Rng>(
        &self,
        graph: &Graph,
        learner: Learner,
        training: usize,
        options: StructureOptions,
        rng: &mut R,
    ) -> Result<(LearnedPdf, Option<StructureReport>, f64), SessionError> {
        let p = self
            .learned
            .as_ref()
            .ok_or(SessionError::NotLearned("export"))?;
        let u = |m: &Chromosome| p.value(graph, m);
        let mut sampler = RejectionSampler::new(graph, &u, 500, rng)?;
        let models: Vec<Chromosome> = (0..training.max(1))
            .map(|_| sampler.sample(rng))
            .collect::<Result<_, _>>()?;
        let acceptance = models.len() as f64 / sampler.proposals().max(1) as f64;
        let (mut pdf, report) = learn_pdf(graph, &models, p, learner, options)?;
        pdf.generator.clone_from(&self.generator);
        Ok((pdf, report, acceptance))
    }
}
