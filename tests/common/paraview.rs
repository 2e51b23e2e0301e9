//! Ask ParaView what it reads in our `.vtu` / `.pvd` files.
//!
//! Runs `pvpython tests/paraview/check_vtk.py FILE...` (see the script's docstring for the
//! JSON it prints) and parses the one JSON line of its stdout; pvpython's stderr (VTK log
//! lines, warnings) is ignored unless the run fails.
//!
//! Without pvpython (neither `$FISSURE_PVPYTHON`, nor on `PATH`, nor `/usr/bin/pvpython`) the helpers print a loud
//! warning and return `None` so that the calling test can skip, except when the environment
//! variable `CI` is `true`: then a missing pvpython is a test failure.
//!
//! pvpython takes a second or two to start: check several files in one call with
//! [`pvpython_check_many`].

use std::io::Read;
use std::path::{Path, PathBuf};
use std::process::{Command, ExitStatus, Stdio};
use std::time::{Duration, Instant};

use serde_json::Value;

/// How long one pvpython run may take before it is killed.
const TIMEOUT: Duration = Duration::from_secs(300);

/// The check script, from the crate root.
pub fn check_script() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/paraview/check_vtk.py")
}

/// Where pvpython is: `$FISSURE_PVPYTHON` if set (to point at another ParaView, or at a
/// missing file to exercise the skip path), else the first `pvpython` on `PATH`, else
/// `/usr/bin/pvpython`.
pub fn find_pvpython() -> Option<PathBuf> {
    if let Some(p) = std::env::var_os("FISSURE_PVPYTHON").filter(|p| !p.is_empty()) {
        return Some(PathBuf::from(p)).filter(|p| is_executable(p));
    }
    let on_path = std::env::var_os("PATH")
        .into_iter()
        .flat_map(|p| std::env::split_paths(&p).collect::<Vec<_>>())
        .map(|dir| dir.join("pvpython"));
    on_path.chain([PathBuf::from("/usr/bin/pvpython")]).find(|p| is_executable(p))
}

fn is_executable(p: &Path) -> bool {
    use std::os::unix::fs::PermissionsExt;
    std::fs::metadata(p).map(|m| m.is_file() && m.permissions().mode() & 0o111 != 0).unwrap_or(false)
}

fn in_ci() -> bool {
    std::env::var("CI").is_ok_and(|v| v == "true")
}

/// pvpython, or `None` after a loud warning; panics when `CI=true` and pvpython is missing.
pub fn pvpython_or_skip(test: &str) -> Option<PathBuf> {
    if let Some(p) = find_pvpython() {
        return Some(p);
    }
    let message = "pvpython not found ($FISSURE_PVPYTHON, PATH, /usr/bin/pvpython): install Debian's `paraview` and \
                   `python3-paraview` (see .ci/run)";
    if in_ci() {
        panic!("{test}: {message}; CI=true, so this is a failure, not a skip");
    }
    eprintln!();
    eprintln!("!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!");
    eprintln!("!!! WARNING: SKIPPED {test}: {message}");
    eprintln!("!!! (with CI=true this is an error)");
    eprintln!("!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!!");
    eprintln!();
    None
}

/// What one pvpython run gave: its exit status, the parsed JSON line, and stderr.
#[derive(Debug)]
pub struct PvRun {
    pub status: ExitStatus,
    pub json: Option<Value>,
    pub stdout: String,
    pub stderr: String,
}

impl PvRun {
    /// A description of the run for failure messages.
    pub fn report(&self) -> String {
        format!(
            "pvpython exited with {}\n--- stdout ---\n{}\n--- stderr ---\n{}",
            self.status, self.stdout, self.stderr
        )
    }
}

/// Runs the check script on `paths` with `extra_args` (e.g. `["--expect", "{...}"]`) and
/// returns whatever happened, whatever the exit status; `None` when pvpython is missing
/// (outside CI). Panics if pvpython cannot be started or runs longer than five minutes.
pub fn pvpython_run(paths: &[&Path], extra_args: &[&str]) -> Option<PvRun> {
    let pvpython = pvpython_or_skip(&format!("ParaView check of {paths:?}"))?;
    let mut cmd = Command::new(&pvpython);
    cmd.arg(check_script()).args(paths).args(extra_args);
    Some(run_to_end(cmd, &format!("pvpython on {paths:?}")))
}

/// `xvfb-run` (on `PATH` or `/usr/bin/xvfb-run`), or `None` after a loud warning; panics
/// when `CI=true` and it is missing.
pub fn xvfb_run_or_skip(test: &str) -> Option<PathBuf> {
    let on_path = std::env::var_os("PATH")
        .into_iter()
        .flat_map(|p| std::env::split_paths(&p).collect::<Vec<_>>())
        .map(|dir| dir.join("xvfb-run"));
    if let Some(p) = on_path.chain([PathBuf::from("/usr/bin/xvfb-run")]).find(|p| is_executable(p)) {
        return Some(p);
    }
    let message = "xvfb-run not found (PATH, /usr/bin/xvfb-run): install Debian's `xvfb` (see .ci/run)";
    if in_ci() {
        panic!("{test}: {message}; CI=true, so this is a failure, not a skip");
    }
    eprintln!();
    eprintln!("!!! WARNING: SKIPPED {test}: {message}");
    eprintln!("!!! (with CI=true this is an error)");
    eprintln!();
    None
}

/// Renders the jobs of `jobs` (a JSON file, see `tests/paraview/render_view.py`) offscreen
/// with `xvfb-run -a pvpython`; `None` when pvpython or xvfb-run is missing (outside CI).
pub fn pvpython_render(jobs: &Path, test: &str) -> Option<PvRun> {
    let pvpython = pvpython_or_skip(test)?;
    let xvfb = xvfb_run_or_skip(test)?;
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/paraview/render_view.py");
    // A loaded machine can leave the new X server unable to take the connection ("bad X
    // server connection"): that is the virtual display, not our files, so try again.
    let mut attempt = 0;
    loop {
        attempt += 1;
        let mut cmd = Command::new(&xvfb);
        cmd.args(["-a", "-s", "-screen 0 1280x1024x24 -nolisten tcp"]).arg(&pvpython).arg(&script).arg(jobs);
        let run = run_to_end(cmd, &format!("xvfb-run pvpython render_view.py {}", jobs.display()));
        let display_failed = run.json.is_none() && run.stderr.contains("bad X server connection");
        if !display_failed || attempt == 3 {
            return Some(run);
        }
        eprintln!("{test}: the virtual X display refused pvpython (attempt {attempt} of 3), trying again");
    }
}

/// Runs `cmd` to its end (killed after [`TIMEOUT`]: a panic), collecting its output and
/// the last JSON line of its stdout.
fn run_to_end(mut cmd: Command, what: &str) -> PvRun {
    let mut child = cmd
        .env("PYTHONDONTWRITEBYTECODE", "1")
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap_or_else(|e| panic!("cannot start {what}: {e}"));
    let drain = |mut pipe: Box<dyn Read + Send>| {
        std::thread::spawn(move || {
            let mut s = Vec::new();
            let _ = pipe.read_to_end(&mut s);
            String::from_utf8_lossy(&s).into_owned()
        })
    };
    let out = drain(Box::new(child.stdout.take().expect("piped stdout")));
    let err = drain(Box::new(child.stderr.take().expect("piped stderr")));
    let start = Instant::now();
    let status = loop {
        if let Some(status) = child.try_wait().expect("waiting for pvpython") {
            break status;
        }
        if start.elapsed() > TIMEOUT {
            let _ = child.kill();
            let _ = child.wait();
            panic!("{what} did not finish within {TIMEOUT:?}");
        }
        std::thread::sleep(Duration::from_millis(50));
    };
    let stdout = out.join().unwrap_or_default();
    let stderr = err.join().unwrap_or_default();
    // The script prints exactly one JSON line; take the last line that parses.
    let json =
        stdout.lines().rev().filter(|l| l.trim_start().starts_with('{')).find_map(|l| serde_json::from_str(l).ok());
    PvRun { status, json, stdout, stderr }
}

/// What ParaView read in each of `paths` (one description per path, in order), or `None`
/// when pvpython is missing outside CI. Panics if a reader reported an error.
pub fn pvpython_check_many(paths: &[&Path]) -> Option<Vec<Value>> {
    let run = pvpython_run(paths, &[])?;
    let Some(json) = &run.json else { panic!("no JSON from the ParaView check\n{}", run.report()) };
    if !run.status.success() {
        panic!("ParaView could not read {paths:?} cleanly:\n{}\n{}", errors_of(json), run.report());
    }
    let files = if paths.len() == 1 {
        vec![json.clone()]
    } else {
        json["files"].as_array().cloned().unwrap_or_else(|| panic!("no \"files\" in {json}"))
    };
    assert_eq!(files.len(), paths.len(), "one description per file expected: {json}");
    for f in &files {
        assert_eq!(f["ok"], Value::Bool(true), "ParaView reported errors: {f}");
    }
    Some(files)
}

/// What ParaView read in `path` (`.vtu` or `.pvd`), or `None` when pvpython is missing outside
/// CI. Panics if the reader reported an error.
pub fn pvpython_check(path: &Path) -> Option<Value> {
    pvpython_check_many(&[path]).map(|mut v| v.remove(0))
}

/// The error messages of a description (or of every file of a multi-file result).
pub fn errors_of(json: &Value) -> String {
    let mut lines = Vec::new();
    let files = json["files"].as_array().cloned().unwrap_or_else(|| vec![json.clone()]);
    for f in files {
        for e in f["errors"].as_array().into_iter().flatten() {
            lines.push(format!("{}: {}", f["path"], e.as_str().unwrap_or_default()));
        }
    }
    lines.join("\n")
}
