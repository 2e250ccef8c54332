//! The facade's integration tests, in one binary (far less linking than one
//! binary per file): one module per area. The core crate's own tests live in
//! `shapegen-core/tests/`, the macro's UI tests in `shapegen-macros/tests/`.

/// The `shapegen` command line end to end: run, compare, render, resume, Ctrl-C.
#[cfg(feature = "cli")]
mod cli;
/// A user's own generator through the whole command line.
#[cfg(feature = "cli")]
mod custom_generator;
/// Designing a pdf from preference scores: sessions and `shapegen design`.
#[cfg(feature = "cli")]
mod design;
/// The design server: its HTTP API and the page in a headless browser.
#[cfg(feature = "cli")]
mod design_server;
/// The macro's generated code against the run-time interpreter.
mod express_props;
/// Thumbnail galleries: the command, its files and clustering invariants.
#[cfg(feature = "cli")]
mod gallery;
/// Evaluating a fitness allocates nothing after warm-up.
mod no_alloc;
/// The binary against careless and hostile input.
#[cfg(feature = "cli")]
mod robustness;
/// The paper's generators: structure and placement.
mod scenes;
/// Design transformations: endpoints, identity, validity, connected trees.
mod transform;
/// Helpers the modules share.
#[cfg_attr(not(feature = "cli"), allow(dead_code))]
mod util;
