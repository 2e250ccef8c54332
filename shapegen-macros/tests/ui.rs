//! Compile-fail and compile-pass tests of `generator!` (trybuild).
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
    let t = trybuild::TestCases::new();
    t.pass("tests/ui/pass_*.rs");
    for case in std::fs::read_dir("tests/ui").unwrap() {
        let path = case.unwrap().path();
        let name = path.file_name().unwrap().to_string_lossy().into_owned();
        if name.ends_with(".rs") && !name.starts_with("pass_") {
            t.compile_fail(&path);
        }
    }
}
