//! The design interface in a browser (thesis §4.6): a small HTTP server
//! over a [`Session`] and one page with no build step, embedded in the
//! binary (`shapegen design serve`).
//!
//! The page shows the batch as a grid of thumbnails (all from the default
//! model's best view, as the thesis's interface) with the learned
//! preference and its uncertainty; the user selects models and scores them
//! 0–100, asks for the next batch by mode (default, current, complementary,
//! uncertain, scored), sorts, switches factors and exports the learned
//! generator. Every change is saved to the session file atomically before
//! the answer is sent, so closing the page loses nothing and reopening it
//! shows the same state.
//!
//! The JSON API, under `/api/`:
//!
//! | request | what it does |
//! |---|---|
//! | `GET state[?sort=score\|uncertainty\|random\|similar:ID][&thumbnails=1]` | the session: factors, the batch with scores, predictions (and thumbnails as `data:` URIs), the revision |
//! | `POST sample {"mode", "count", "revision"}` | refits if scores came in since, then draws a batch |
//! | `POST score {"scores": [{"id", "score"}], "revision"}` | scores models of the batch for the current factor |
//! | `POST factor {"name", "revision"}` | switches to (or creates) a factor |
//! | `POST factor {"name", "active", "revision"}` | takes a factor into the preference (the product of the active ones) or leaves it out |
//! | `POST learn {"revision"}` | refits the preference now |
//! | `POST export {"revision"}` | writes the learned generator beside the session |
//! | `GET thumb/ID` | a model's thumbnail (PNG) |
//! | `GET view/ID` | a model larger, from three views (PNG) |
//! | `GET model/ID` | a model's genes and parameters |
//!
//! Every `POST` answers with the state, taking the same query as `GET state`.
//! A request that names an older revision than the session's is refused with
//! 409: another tab or window changed the session since this page loaded it.
//!
//! Only the page itself is answered: a request
//! whose `Host` is not this server's address gets 403 (a site that rebinds
//! its name to 127.0.0.1), and so does a `POST` without the page's own
//! `Origin`; a `POST` that is not `application/json` gets 415. Bodies are
//! limited to 1 MiB, declared lengths past it refused before any byte is
//! read, and a request must arrive within 10 s.

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::Mutex;

use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use serde_json::json;

use super::session::{Mode, Session, SessionError};
use crate::design::{FactorOptions, Learner, StructureOptions};
use crate::experiment::Experiment;
use crate::genome::Chromosome;
use crate::graph::ParamDist;

/// Why a change was refused because the session changed elsewhere.
const CHANGED_ELSEWHERE: &str = "the session was changed in another tab, window or program since this page loaded it: reload the page to see its current state (nothing was changed)";

/// The page, embedded.
const PAGE: &str = include_str!("page.html");

/// An answer: status, content type, body.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Reply {
    /// HTTP status.
    pub status: u16,
    /// Content type.
    pub content_type: &'static str,
    /// Body.
    pub body: Vec<u8>,
}

impl Reply {
    fn json(status: u16, value: &serde_json::Value) -> Self {
        Self {
            status,
            content_type: "application/json",
            body: value.to_string().into_bytes(),
        }
    }

    /// A JSON error answer: `{"error": message}`.
    pub(super) fn error(status: u16, message: impl Into<String>) -> Self {
        Self::json(status, &json!({ "error": message.into() }))
    }

    fn png(bytes: Vec<u8>) -> Self {
        Self {
            status: 200,
            content_type: "image/png",
            body: bytes,
        }
    }
}

struct State {
    session: Session,
    /// Thumbnails by model id (PNG).
    thumbnails: HashMap<u64, Vec<u8>>,
}

/// The design server: an experiment's generator, a session file and what
/// the page shows.
pub struct DesignServer {
    experiment: Experiment,
    path: PathBuf,
    learned_path: PathBuf,
    thumbnail: u32,
    /// The default model's best view, from which every thumbnail is drawn
    /// (`None` if the default model emits nothing: then each model's own).
    viewpoint: std::sync::OnceLock<Option<crate::score::Viewpoint>>,
    state: Mutex<State>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct SampleRequest {
    mode: Mode,
    #[serde(default = "default_count")]
    count: usize,
    revision: Option<u64>,
}

fn default_count() -> usize {
    24
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct ScoreRequest {
    scores: Vec<ScoreItem>,
    revision: Option<u64>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct ScoreItem {
    id: u64,
    score: f64,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct FactorRequest {
    name: String,
    /// Take the factor into the preference (true) or leave it out (false);
    /// without it, the factor becomes the one scores go to.
    active: Option<bool>,
    revision: Option<u64>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RevisionOnly {
    revision: Option<u64>,
}

/// One model as the page shows it.
#[derive(Serialize)]
struct ModelView {
    id: u64,
    score: Option<f64>,
    predicted: Option<f64>,
    std: Option<f64>,
    /// The thumbnail as a `data:` URI (with `thumbnails=1`).
    #[serde(skip_serializing_if = "Option::is_none")]
    thumbnail: Option<String>,
}

impl DesignServer {
    /// A server for `experiment`'s generator on the session at `path`
    /// (created if missing; a session of another generator is an error).
    pub fn new(experiment: Experiment, path: &Path, seed: u64) -> Result<Self, String> {
        let session = if path.exists() {
            Session::load(path, experiment.generator(), experiment.graph())
                .map_err(|e| e.to_string())?
        } else {
            let mut s = Session::new(experiment.generator(), experiment.graph(), seed);
            s.save(path)
                .map_err(|e| format!("cannot create the session: {e}"))?;
            s
        };
        let learned_path = path.with_file_name("learned.json");
        Ok(Self {
            experiment,
            path: path.to_path_buf(),
            learned_path,
            thumbnail: 200,
            viewpoint: std::sync::OnceLock::new(),
            state: Mutex::new(State {
                session,
                thumbnails: HashMap::new(),
            }),
        })
    }

    /// Answers one request (the HTTP loop's core, callable without sockets).
    pub fn respond(&self, method: &str, url: &str, body: &[u8]) -> Reply {
        let (path, query) = url.split_once('?').unwrap_or((url, ""));
        let route: Vec<&str> = path.trim_matches('/').split('/').collect();
        match (method, route.as_slice()) {
            ("GET", [""] | ["index.html"]) => Reply {
                status: 200,
                content_type: "text/html; charset=utf-8",
                body: PAGE.as_bytes().to_vec(),
            },
            ("GET", ["api", "state"]) => self.state_reply(query),
            ("GET", ["api", "thumb", id]) => self.with_id(id, |id| self.thumbnail(id)),
            ("GET", ["api", "view", id]) => self.with_id(id, |id| self.large_view(id)),
            ("GET", ["api", "model", id]) => self.with_id(id, |id| self.model(id)),
            ("POST", ["api", action]) => self.post(action, query, body),
            (_, ["api", ..]) => Reply::error(405, format!("{method} {path} is not an API call")),
            _ => Reply::error(404, format!("no page at {path}")),
        }
    }

    fn with_id(&self, id: &str, f: impl FnOnce(u64) -> Reply) -> Reply {
        match id.trim_end_matches(".png").parse() {
            Ok(id) => f(id),
            Err(_) => Reply::error(400, format!("`{id}` is not a model id")),
        }
    }

    /// Takes the session from disk if another program (a `design` command,
    /// a second server) saved it since this server read or wrote it;
    /// whether it did. A file that cannot be read or is no valid session is
    /// left to the next save, which refuses to replace it.
    fn refresh(&self, state: &mut State) -> bool {
        match Session::revision_on_disk(&self.path) {
            Ok(Some(r)) if r != state.session.revision => {
                match Session::load(
                    &self.path,
                    self.experiment.generator(),
                    self.experiment.graph(),
                ) {
                    Ok(session) => {
                        state.session = session;
                        true
                    }
                    Err(_) => false,
                }
            }
            _ => false,
        }
    }

    fn lock(&self) -> std::sync::MutexGuard<'_, State> {
        // A panic while holding the lock would leave the session as saved on
        // disk; the in-memory copy is still usable.
        self.state
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner)
    }

    /// A change to the session, as one transaction: the action works on a
    /// copy, which is saved with the next revision and only then replaces
    /// the session in memory, so a refused or failed request leaves memory
    /// and disk as they were.
    fn post(&self, action: &str, query: &str, body: &[u8]) -> Reply {
        fn parse<'a, T: Deserialize<'a>>(body: &'a [u8]) -> Result<T, Reply> {
            serde_json::from_slice(body)
                .map_err(|e| Reply::error(400, format!("malformed request: {e}")))
        }
        let graph = self.experiment.graph();
        let refit = |session: &mut Session| -> Result<(), Reply> {
            if session.stale {
                session
                    .learn(graph, FactorOptions::default())
                    .map_err(|e| Reply::error(422, e.to_string()))?;
            }
            Ok(())
        };
        let mut state = self.lock();
        if self.refresh(&mut state) {
            return Reply::error(409, CHANGED_ELSEWHERE);
        }
        let current = state.session.revision;
        let check = |revision: Option<u64>| -> Result<(), Reply> {
            match revision {
                Some(r) if r != current => Err(Reply::error(409, CHANGED_ELSEWHERE)),
                _ => Ok(()),
            }
        };
        let mut next = state.session.clone();
        let mut thumbnails = Vec::new();
        // Whether `next` differs from the saved session.
        let result: Result<bool, Reply> = (|| match action {
            "sample" => {
                let r: SampleRequest = parse(body)?;
                check(r.revision)?;
                if r.count == 0 || r.count > 200 {
                    return Err(Reply::error(
                        400,
                        format!("count must be 1 to 200, got {}", r.count),
                    ));
                }
                refit(&mut next)?;
                let shown = next
                    .sample(graph, r.mode, r.count)
                    .map_err(|e| Reply::error(422, e.to_string()))?;
                thumbnails = shown
                    .par_iter()
                    .map(|s| self.render(&s.model, self.thumbnail).map(|png| (s.id, png)))
                    .collect::<Result<_, _>>()
                    .map_err(|e| Reply::error(500, e))?;
                Ok(true)
            }
            "score" => {
                let r: ScoreRequest = parse(body)?;
                check(r.revision)?;
                // All checked before any is applied: a bad one changes nothing.
                if let Some(bad) = r.scores.iter().find(|s| !(0.0..=100.0).contains(&s.score)) {
                    return Err(Reply::error(
                        400,
                        format!("score {} of model {} is outside 0..=100", bad.score, bad.id),
                    ));
                }
                for s in &r.scores {
                    next.score(s.id, s.score)
                        .map_err(|e| Reply::error(404, e.to_string()))?;
                }
                Ok(true)
            }
            "factor" => {
                let r: FactorRequest = parse(body)?;
                check(r.revision)?;
                match r.active {
                    None => next
                        .select_factor(&r.name)
                        .map_err(|e| Reply::error(400, e.to_string()))?,
                    Some(active) => next
                        .set_active(r.name.trim(), active)
                        .map_err(|e| Reply::error(404, e.to_string()))?,
                }
                Ok(true)
            }
            "learn" => {
                let r: RevisionOnly = parse(body)?;
                check(r.revision)?;
                next.learn(graph, FactorOptions::default())
                    .map_err(|e| Reply::error(422, e.to_string()))?;
                Ok(true)
            }
            "export" => {
                let r: RevisionOnly = parse(body)?;
                check(r.revision)?;
                let refitted = next.stale;
                refit(&mut next)?;
                let (pdf, _, _) = next
                    .export(
                        graph,
                        Learner::Structure,
                        1000,
                        StructureOptions::default(),
                        &mut next.export_stream(None),
                    )
                    .map_err(|e| Reply::error(422, e.to_string()))?;
                crate::output::write_json(&self.learned_path, &pdf)
                    .map_err(|e| Reply::error(500, e.to_string()))?;
                Ok(refitted)
            }
            other => Err(Reply::error(404, format!("no API call `{other}`"))),
        })();
        let changed = match result {
            Ok(changed) => changed,
            Err(reply) => return reply,
        };
        if changed {
            match next.save(&self.path) {
                Ok(()) => state.session = next,
                Err(SessionError::Changed { .. }) => {
                    // Another program saved between the refresh and now.
                    self.refresh(&mut state);
                    return Reply::error(409, CHANGED_ELSEWHERE);
                }
                Err(e) => return Reply::error(500, format!("cannot save the session: {e}")),
            }
        }
        state.thumbnails.extend(thumbnails);
        drop(state);
        let mut reply = self.state_reply(query);
        if action == "export"
            && let Ok(mut v) = serde_json::from_slice::<serde_json::Value>(&reply.body)
        {
            v["exported"] = json!(self.learned_path.display().to_string());
            reply = Reply::json(200, &v);
        }
        reply
    }

    /// A thumbnail from the default model's best view, as the thesis's
    /// interface shows them (each model's own best view if the default
    /// model emits nothing).
    fn render(&self, model: &Chromosome, size: u32) -> Result<Vec<u8>, String> {
        let viewpoint = *self.viewpoint.get_or_init(|| {
            crate::ops::default_model(self.experiment.graph())
                .ok()
                .and_then(|d| {
                    crate::gallery::best_viewpoint(&self.experiment, &d)
                        .ok()
                        .flatten()
                })
        });
        let img = match viewpoint {
            Some(v) => crate::gallery::picture_from(&self.experiment, model, v, size),
            None => crate::gallery::best_view_picture(&self.experiment, model, size),
        }
        .map_err(|e| e.to_string())?;
        crate::score::png_bytes(Path::new("thumbnail.png"), &img).map_err(|e| e.to_string())
    }

    /// Renders the thumbnails of the shown models that have none yet (after
    /// a restart the cache is empty).
    fn render_missing(&self) {
        let missing: Vec<(u64, Chromosome)> = {
            let state = self.lock();
            state
                .session
                .shown
                .iter()
                .filter(|id| !state.thumbnails.contains_key(id))
                .filter_map(|&id| self.chromosome(&state, id).ok().map(|(c, _)| (id, c)))
                .collect()
        };
        let rendered: Vec<(u64, Vec<u8>)> = missing
            .par_iter()
            .filter_map(|(id, c)| self.render(c, self.thumbnail).ok().map(|png| (*id, png)))
            .collect();
        self.lock().thumbnails.extend(rendered);
    }

    fn chromosome(&self, state: &State, id: u64) -> Result<(Chromosome, Option<f64>), Reply> {
        let (data, score) = state
            .session
            .model(id)
            .ok_or_else(|| Reply::error(404, format!("no model {id} in this session")))?;
        let c = Chromosome::from_data(self.experiment.graph(), data)
            .map_err(|e| Reply::error(500, e.to_string()))?;
        Ok((c, score))
    }

    fn thumbnail(&self, id: u64) -> Reply {
        let mut state = self.lock();
        if let Some(png) = state.thumbnails.get(&id) {
            return Reply::png(png.clone());
        }
        match self.chromosome(&state, id) {
            Ok((c, _)) => match self.render(&c, self.thumbnail) {
                Ok(png) => {
                    state.thumbnails.insert(id, png.clone());
                    Reply::png(png)
                }
                Err(e) => Reply::error(500, e),
            },
            Err(r) => r,
        }
    }

    fn large_view(&self, id: u64) -> Reply {
        let c = match self.chromosome(&self.lock(), id) {
            Ok((c, _)) => c,
            Err(r) => return r,
        };
        match crate::gallery::views_picture(&self.experiment, &c, 360) {
            Ok(img) => match crate::score::png_bytes(Path::new("view.png"), &img) {
                Ok(png) => Reply::png(png),
                Err(e) => Reply::error(500, e.to_string()),
            },
            Err(e) => Reply::error(500, e.to_string()),
        }
    }

    fn model(&self, id: u64) -> Reply {
        let state = self.lock();
        let (c, score) = match self.chromosome(&state, id) {
            Ok(x) => x,
            Err(r) => return r,
        };
        let graph = self.experiment.graph();
        let genes: Vec<serde_json::Value> = c
            .genes(graph)
            .map(|g| {
                let spec = graph.node(g.node());
                let params: serde_json::Map<String, serde_json::Value> = spec
                    .params
                    .iter()
                    .enumerate()
                    .map(|(k, p)| {
                        let v = match p.dist {
                            ParamDist::F32(_) => json!(g.param_f32(k)),
                            ParamDist::Vec2(_) => json!(g.param_vec2(k)),
                            ParamDist::Vec3(_) => json!(g.param_vec3(k)),
                            ParamDist::Int(_) => json!(g.param_int(k)),
                            ParamDist::Choice(_) => json!(g.param_choice(k)),
                        };
                        (p.name.to_string(), v)
                    })
                    .collect();
                json!({ "node": spec.name, "params": params })
            })
            .collect();
        let predicted = state.session.learned.as_ref().map(|p| p.predict(graph, &c));
        Reply::json(
            200,
            &json!({
                "id": id,
                "score": score,
                "predicted": predicted.map(|p| p.0),
                "std": predicted.map(|p| p.1),
                "genes": genes,
            }),
        )
    }

    fn state_reply(&self, query: &str) -> Reply {
        let mut sort = "";
        let mut with_thumbnails = false;
        for pair in query.split('&') {
            match pair.split_once('=') {
                Some(("sort", v)) => sort = v,
                Some(("thumbnails", v)) => with_thumbnails = v == "1",
                _ => {}
            }
        }
        if with_thumbnails {
            self.render_missing();
        }
        let mut state = self.lock();
        self.refresh(&mut state);
        let s = &state.session;
        let graph = self.experiment.graph();
        let mut models: Vec<(ModelView, Option<Chromosome>)> = s
            .shown
            .iter()
            .filter_map(|&id| {
                let (data, score) = s.model(id)?;
                let c = Chromosome::from_data(graph, data).ok();
                let p = c
                    .as_ref()
                    .and_then(|c| s.learned.as_ref().map(|l| l.predict(graph, c)));
                let thumbnail = with_thumbnails.then(|| {
                    state.thumbnails.get(&id).map(|png| {
                        use base64::Engine as _;
                        format!(
                            "data:image/png;base64,{}",
                            base64::engine::general_purpose::STANDARD.encode(png)
                        )
                    })
                });
                Some((
                    ModelView {
                        id,
                        score,
                        predicted: p.map(|p| p.0),
                        std: p.map(|p| p.1),
                        thumbnail: thumbnail.flatten(),
                    },
                    c,
                ))
            })
            .collect();
        match sort {
            "score" => models.sort_by(|a, b| {
                let key = |m: &ModelView| m.score.or(m.predicted).unwrap_or(-1.0);
                key(&b.0).total_cmp(&key(&a.0))
            }),
            "uncertainty" => {
                models.sort_by(|a, b| b.0.std.unwrap_or(0.0).total_cmp(&a.0.std.unwrap_or(0.0)))
            }
            "random" => {
                let mut rng = crate::rng::stream(s.seed, &[0x7261_6e64, s.revision]);
                use rand::seq::SliceRandom as _;
                models.shuffle(&mut rng);
            }
            other => {
                if let Some(target) = other
                    .strip_prefix("similar:")
                    .and_then(|t| t.parse::<u64>().ok())
                {
                    let base = models
                        .iter()
                        .find(|m| m.0.id == target)
                        .and_then(|m| m.1.clone());
                    if let (Some(base), Some(p)) = (base, s.learned.as_ref()) {
                        models.sort_by(|a, b| {
                            let d = |m: &Option<Chromosome>| {
                                m.as_ref().map_or(f64::MAX, |c| p.distance(graph, &base, c))
                            };
                            d(&a.1).total_cmp(&d(&b.1))
                        });
                    }
                }
            }
        }
        let factors: Vec<serde_json::Value> = s
            .factors
            .iter()
            .map(|f| json!({ "name": f.name, "scored": f.scored.len(), "active": f.active }))
            .collect();
        let features: Vec<serde_json::Value> = s
            .learned
            .as_ref()
            .map(|p| {
                p.factors
                    .iter()
                    .map(|f| json!({ "factor": f.name, "top": f.top_features(graph, 5) }))
                    .collect()
            })
            .unwrap_or_default();
        Reply::json(
            200,
            &json!({
                "generator": s.generator,
                "revision": s.revision,
                "factors": factors,
                "current": s.current,
                "mode": s.mode.map(Mode::name),
                "learned": s.learned.is_some(),
                "stale": s.stale,
                "scored": s.scored_count(),
                "features": features,
                "models": models.into_iter().map(|m| m.0).collect::<Vec<_>>(),
                "session": self.path.display().to_string(),
            }),
        )
    }

    /// Serves on `address` (e.g. `127.0.0.1:8765`; port 0 picks a free one)
    /// until `stop` returns true (looked at ten times a second); `ready` is
    /// called with the bound address. Every change was saved when it was
    /// answered, so stopping loses nothing. Requests are bounded in size and
    /// time and answered only from this server's own page (see the module's
    /// documentation).
    pub fn serve(
        &self,
        address: &str,
        ready: impl FnOnce(std::net::SocketAddr),
        stop: &(dyn Fn() -> bool + Sync),
    ) -> Result<(), String> {
        let listener = std::net::TcpListener::bind(address)
            .map_err(|e| format!("cannot listen on {address}: {e}"))?;
        let bound = listener
            .local_addr()
            .map_err(|e| format!("cannot listen on {address}: {e}"))?;
        ready(bound);
        let respond = |method: &str, target: &str, body: &[u8]| {
            // A panic in one request must not take the server down.
            std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
                self.respond(method, target, body)
            }))
            .unwrap_or_else(|_| {
                Reply::error(500, "internal error (the session on disk is unchanged)")
            })
        };
        super::http::serve(&listener, stop, &respond)
            .map_err(|e| format!("serving on {bound}: {e}"))
    }
}
