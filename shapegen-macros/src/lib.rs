//! The `generator!` procedural macro of shapegen.
//!
//! Not implemented yet: the DSL that compiles a generator declaration into a
//! static `GraphSpec` and specialized expression code is the next milestone.
//! Until then, build graphs at run time with
//! `shapegen_core::graph::GraphBuilder`.
