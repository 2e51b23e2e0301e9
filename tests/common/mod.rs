//! Helpers shared by integration tests (`mod common;` in a test file).
//!
//! - [`paraview`]: run ParaView's `pvpython` on written VTK files and read back what its
//!   readers saw (skips loudly without ParaView, fails when `CI=true`).
//! - [`dynamics`]: the dynamics tests' model building and momentum weights.
//! - [`model`]: building models in code (supports, loads) and convergence rates.
//! - [`penny_block`]: the penny-block case text (shared with the benches and the library's
//!   test-only SIF reference).
//! - [`run_cli`]: run `fissure run` on a case text and read its `summary.json`.

// Every test binary compiles this module but uses only part of it.
#![allow(dead_code)]

pub mod contact;
pub mod dynamics;
pub mod fracture;
pub mod model;
pub mod newman_raju;
pub mod paraview;
pub mod penny_block;
pub mod sliding;

/// Writes `text` to `<CARGO_TARGET_TMPDIR>/<dir>/<name>.toml`, runs `fissure run` on it
/// (output in `<dir>/<name>/`) and returns its `summary.json`; panics with the run's
/// stderr when it fails.
pub fn run_cli(dir: &str, name: &str, text: &str) -> serde_json::Value {
    run_cli_with_env(dir, name, text, &[])
}

/// [`run_cli`] with environment variables set for the run (developer switches).
pub fn run_cli_with_env(dir: &str, name: &str, text: &str, env: &[(&str, &str)]) -> serde_json::Value {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join(dir);
    std::fs::create_dir_all(&dir).unwrap();
    let case = dir.join(format!("{name}.toml"));
    std::fs::write(&case, text).unwrap();
    let out = dir.join(name);
    let run = std::process::Command::new(env!("CARGO_BIN_EXE_fissure"))
        .args(["run", case.to_str().unwrap(), "--quiet", "--out", out.to_str().unwrap()])
        .envs(env.iter().copied())
        .output()
        .unwrap();
    assert!(run.status.success(), "{name}: {}", String::from_utf8_lossy(&run.stderr));
    serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap()
}
