//! Compile-fail tests of `generator!` (trybuild): each `tests/ui/*.rs`
//! must fail with the compiler output in its `.stderr` file.
//!
//! The expected compiler output (`tests/ui/*.stderr`) depends on the rustc
//! version, so the test runs only on the version that wrote it (see
//! `UI_RUSTC`); on another one it says so and passes without checking.
//! After reading new output, accept it with `TRYBUILD=overwrite`.

/// The rustc version the `.stderr` files were written with.
const UI_RUSTC: &str = "rustc 1.95.0";

#[test]
fn ui() {
    let rustc = std::env::var("RUSTC").unwrap_or_else(|_| "rustc".into());
    let version = std::process::Command::new(rustc)
        .arg("--version")
        .output()
        .map(|o| String::from_utf8_lossy(&o.stdout).into_owned())
        .unwrap_or_default();
    if !version.starts_with(UI_RUSTC) {
        eprintln!("skipping the UI tests: they were written for {UI_RUSTC}, this is {version}");
        return;
    }
    // Compile-fail cases only: trybuild then type-checks instead of
    // building (generators that must compile are `tests/generators.rs`).
    let t = trybuild::TestCases::new();
    t.compile_fail("tests/ui/*.rs");
}
