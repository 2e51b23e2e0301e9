#![allow(dead_code)]
//! Runs the `fissure` binary on a case text with a time limit and collects what a user
//! sees: the exit status, stderr, and `summary.json` when one was written.

use std::path::PathBuf;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

pub struct Outcome {
    /// Exit status; `None` when killed (time limit) or ended by a signal (abort).
    pub code: Option<i32>,
    pub stderr: String,
    pub summary: Option<serde_json::Value>,
    pub timed_out: bool,
    pub out: PathBuf,
}

/// `fissure run` (or `check` when `check`) on `text` written as `<dir>/<name>.toml`.
pub fn fissure(dir: &str, name: &str, text: &str, check: bool, limit: Duration) -> Outcome {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join(dir);
    std::fs::create_dir_all(&dir).unwrap();
    let case = dir.join(format!("{name}.toml"));
    std::fs::write(&case, text).unwrap();
    let out = dir.join(name);
    let _ = std::fs::remove_dir_all(&out);
    let err_path = dir.join(format!("{name}.stderr"));
    let err = std::fs::File::create(&err_path).unwrap();
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_fissure"));
    if check {
        cmd.args(["check", case.to_str().unwrap()]);
    } else {
        cmd.args(["run", case.to_str().unwrap(), "--quiet", "--out", out.to_str().unwrap()]);
    }
    let mut child = cmd.stdout(Stdio::null()).stderr(Stdio::from(err)).spawn().unwrap();
    let start = Instant::now();
    let mut timed_out = false;
    let status = loop {
        if let Some(s) = child.try_wait().unwrap() {
            break Some(s);
        }
        if start.elapsed() > limit {
            let _ = child.kill();
            let _ = child.wait();
            timed_out = true;
            break None;
        }
        std::thread::sleep(Duration::from_millis(20));
    };
    let stderr = std::fs::read_to_string(&err_path).unwrap_or_default();
    let summary = std::fs::read_to_string(out.join("summary.json")).ok().and_then(|t| serde_json::from_str(&t).ok());
    Outcome { code: status.and_then(|s| s.code()), stderr, summary, timed_out, out }
}

/// The JSON paths of every number that is not finite (serde_json writes NaN and
/// infinities as `null`) among the keys that hold figures: nulls are allowed only where
/// `summary-json.md` documents an optional value (`vtu`, `tip_radius`, `error`, `pvd`).
pub fn non_finite_figures(v: &serde_json::Value) -> Vec<String> {
    fn walk(v: &serde_json::Value, path: String, out: &mut Vec<String>) {
        match v {
            serde_json::Value::Null => {
                let optional = ["vtu", "tip_radius", "error", "pvd", "geometry", "pairing", "contact"];
                if !optional.iter().any(|k| path.ends_with(&format!(".{k}"))) {
                    out.push(path);
                }
            }
            serde_json::Value::Number(n) if !n.as_f64().is_some_and(f64::is_finite) => out.push(path),
            serde_json::Value::Array(a) => {
                for (i, x) in a.iter().enumerate() {
                    walk(x, format!("{path}[{i}]"), out);
                }
            }
            serde_json::Value::Object(o) => {
                for (k, x) in o {
                    walk(x, format!("{path}.{k}"), out);
                }
            }
            _ => {}
        }
    }
    let mut out = vec![];
    walk(v, String::new(), &mut out);
    out
}
