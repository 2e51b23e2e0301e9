//! Parameter sweeps: one case run once per value of one numeric key
//! (`fissure sweep case.toml --set 'cracks.0.contact.friction=[0, 0.3, 0.6, 1.1]'`).
//!
//! Every value is read and validated before the first solve (a wrong key or type stops
//! the sweep with the override named); then each value runs into its own folder
//! `<out>/<key's last segment>=<value>/` and `<out>/sweep.csv` gathers one row per value
//! with the main figures of its last load step (columns in `docs/case-format.md`,
//! "Sweeps"). A value whose solve fails gets `status = failed` and the sweep goes on.
//!
//! Entry points: [`sweep_case`], [`SweepPlan::new`].

use crate::case::overrides::Override;
use crate::case::{Case, CaseError};
use crate::run::summary::Summary;
use crate::run::{self, RunError, RunOptions};
use std::path::{Path, PathBuf};
use toml_edit::Value;

/// The swept key with its values and the fixed overrides applied to every run.
#[derive(Debug, Clone)]
pub struct SweepPlan {
    /// The `--set` whose value is the list (for the CSV header and errors).
    pub swept: Override,
    pub values: Vec<f64>,
    /// The other `--set` overrides, the same for every value.
    pub fixed: Vec<Override>,
}

impl SweepPlan {
    /// Splits the overrides into the swept one and the fixed ones. The swept override is
    /// the one whose value is a list on a key that does not hold a list in the case file
    /// (so `--set mesh.divisions=[40, 40]` stays a plain override); exactly one is needed.
    pub fn new(case_text: &str, overrides: Vec<Override>) -> Result<SweepPlan, CaseError> {
        let holds_list = |o: &Override| crate::case::overrides::holds_array(case_text, o);
        let (lists, fixed): (Vec<Override>, Vec<Override>) =
            overrides.into_iter().partition(|o| matches!(o.value, Value::Array(_)) && !holds_list(o));
        let swept = match lists.len() {
            1 => lists.into_iter().next().expect("one"),
            0 => {
                return Err(CaseError {
                    file: "fissure sweep".into(),
                    line: None,
                    key: String::new(),
                    message: "no swept key: give one --set KEY=[v1, v2, ...] with a list of numbers".into(),
                })
            }
            _ => {
                let names: Vec<String> = lists.iter().map(|o| o.to_string()).collect();
                return Err(lists[1].error(format!("one swept key at a time; lists given in {}", names.join(" and "))));
            }
        };
        let Value::Array(a) = &swept.value else { unreachable!("partitioned on arrays") };
        let mut values = vec![];
        for v in a.iter() {
            match v {
                Value::Integer(i) => values.push(*i.value() as f64),
                Value::Float(f) if f.value().is_finite() => values.push(*f.value()),
                other => {
                    return Err(swept.error(format!(
                        "a sweep takes a list of numbers; '{}' is not a number",
                        other.to_string().trim()
                    )))
                }
            }
        }
        if values.is_empty() {
            return Err(swept.error("the list of values is empty"));
        }
        for (i, v) in values.iter().enumerate() {
            if values[..i].contains(v) {
                return Err(swept.error(format!("the value {v} is given twice")));
            }
        }
        Ok(SweepPlan { swept, values, fixed })
    }

    /// The overrides of run `i`: the fixed ones, then the swept key at its value.
    pub fn overrides(&self, i: usize) -> Vec<Override> {
        let Value::Array(a) = &self.swept.value else { unreachable!() };
        let mut v = a.get(i).expect("one value per run").clone();
        *v.decor_mut() = Default::default();
        let mut all = self.fixed.clone();
        all.push(self.swept.with_value(v));
        all
    }

    /// The output folder of run `i`, inside the sweep's folder.
    pub fn folder(&self, i: usize) -> String {
        let last = self.swept.path.last().expect("a key");
        format!("{last}={}", self.values[i])
    }
}

/// One run of a sweep.
#[derive(Debug, Clone)]
pub struct SweepRun {
    pub value: f64,
    pub dir: PathBuf,
    /// The summary written (None when the run failed before writing one).
    pub summary: Option<Summary>,
    /// The error of a failed run.
    pub error: Option<String>,
}

/// What a sweep did.
#[derive(Debug, Clone)]
pub struct SweepReport {
    pub plan: SweepPlan,
    pub runs: Vec<SweepRun>,
    pub csv: PathBuf,
}

/// Runs `case_path` once per value of the swept override into `out_dir/<key>=<value>/`
/// and writes `out_dir/sweep.csv`. Case errors (any value) stop the sweep before the
/// first solve; solve failures are recorded in their row.
pub fn sweep_case(
    case_path: &Path,
    out_dir: &Path,
    overrides: Vec<Override>,
    opts: &RunOptions,
) -> Result<SweepReport, RunError> {
    let text = std::fs::read_to_string(case_path).map_err(|e| {
        RunError::Case(CaseError {
            file: case_path.display().to_string(),
            line: None,
            key: String::new(),
            message: format!("cannot read the case file: {e}"),
        })
    })?;
    let plan = SweepPlan::new(&text, overrides).map_err(RunError::Case)?;
    // Validate every value before solving anything.
    for i in 0..plan.values.len() {
        Case::parse_with(&text, case_path, &plan.overrides(i)).map_err(RunError::Case)?;
    }
    std::fs::create_dir_all(out_dir).map_err(|e| RunError::Output(format!("{}: {e}", out_dir.display())))?;
    let csv = out_dir.join("sweep.csv");
    let mut runs: Vec<SweepRun> = vec![];
    for i in 0..plan.values.len() {
        let dir = out_dir.join(plan.folder(i));
        if opts.verbose {
            eprintln!(
                "sweep {}/{}: {} into {}",
                i + 1,
                plan.values.len(),
                plan.overrides(i).last().expect("swept"),
                dir.display()
            );
        }
        let run_opts = RunOptions { overrides: plan.overrides(i), ..opts.clone() };
        let (summary, error) = match run::run_case(case_path, &dir, &run_opts) {
            Ok(s) => (Some(s), None),
            Err(e @ RunError::Case(_)) => return Err(e),
            // The row of a failed run keeps its status and error (its folder keeps the
            // converged steps and summary.json).
            Err(e) => (None, Some(e.to_string())),
        };
        runs.push(SweepRun { value: plan.values[i], dir, summary, error });
        write_csv(&csv, &plan, &runs).map_err(|e| RunError::Output(format!("{}: {e}", csv.display())))?;
    }
    Ok(SweepReport { plan, runs, csv })
}

/// The columns and cells of one run's row, in column order.
fn row_cells(s: &Summary) -> Vec<(String, String)> {
    let mut cells: Vec<(String, String)> = vec![];
    let Some(step) = s.steps.last() else { return cells };
    cells.push(("steps".into(), s.steps.len().to_string()));
    cells.push(("load_factor".into(), num(step.load_factor)));
    cells.push(("max_displacement".into(), num(step.max_displacement)));
    cells.push(("max_von_mises".into(), num(step.max_von_mises)));
    for c in &step.cracks {
        if s.dim == 2 {
            for (j, p) in c.front.iter().enumerate() {
                for (name, v) in [("KI", p.k1), ("KII", p.k2), ("G", p.g)] {
                    cells.push((format!("{}.tip{j}.{name}", c.name), num(v)));
                }
            }
        } else if !c.front.is_empty() {
            let n = c.front.len() as f64;
            for (name, get) in [
                ("KI", (|p| p.k1) as fn(&crate::post::sif::SifPoint) -> f64),
                ("KII", |p| p.k2),
                ("KIII", |p| p.k3),
                ("G", |p| p.g),
            ] {
                let v: Vec<f64> = c.front.iter().map(get).collect();
                let min = v.iter().cloned().fold(f64::INFINITY, f64::min);
                let max = v.iter().cloned().fold(f64::NEG_INFINITY, f64::max);
                cells.push((format!("{}.{name}_min", c.name), num(min)));
                cells.push((format!("{}.{name}_mean", c.name), num(v.iter().sum::<f64>() / n)));
                cells.push((format!("{}.{name}_max", c.name), num(max)));
            }
        }
    }
    if let Some(ct) = &step.contact {
        for (name, v) in [
            ("points", ct.points),
            ("active", ct.active),
            ("stick", ct.stick),
            ("slip", ct.slip),
            ("newton", ct.iterations.newton),
            ("active_set", ct.iterations.active_set),
            ("friction_passes", ct.iterations.friction),
        ] {
            cells.push((format!("contact.{name}"), v.to_string()));
        }
        cells.push(("contact.lambda_min".into(), num(ct.lambda_min)));
        cells.push(("contact.lambda_max".into(), num(ct.lambda_max)));
    }
    cells
}

fn num(v: f64) -> String {
    format!("{v:.10e}")
}

/// CSV field quoting (RFC 4180).
fn quote(s: &str) -> String {
    if s.contains([',', '"', '\n']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_string()
    }
}

fn write_csv(path: &Path, plan: &SweepPlan, runs: &[SweepRun]) -> std::io::Result<()> {
    let rows: Vec<Vec<(String, String)>> =
        runs.iter().map(|r| r.summary.as_ref().map(row_cells).unwrap_or_default()).collect();
    // Columns: the union over the rows, in first-seen order.
    let mut columns: Vec<String> = vec![];
    for row in &rows {
        for (c, _) in row {
            if !columns.contains(c) {
                columns.push(c.clone());
            }
        }
    }
    let mut out = String::new();
    let head: Vec<String> = [plan.swept.path.join("."), "status".into(), "dir".into()]
        .into_iter()
        .chain(columns.iter().cloned())
        .chain(["error".to_string()])
        .collect();
    out.push_str(&head.iter().map(|h| quote(h)).collect::<Vec<_>>().join(","));
    out.push('\n');
    for (r, row) in runs.iter().zip(&rows) {
        let status = if r.error.is_some() { "failed" } else { "ok" };
        let dir = r.dir.file_name().map(|d| d.to_string_lossy().to_string()).unwrap_or_default();
        let mut cells = vec![format!("{}", r.value), status.to_string(), quote(&dir)];
        for c in &columns {
            cells.push(row.iter().find(|(k, _)| k == c).map(|(_, v)| v.clone()).unwrap_or_default());
        }
        cells.push(quote(r.error.as_deref().unwrap_or("")));
        out.push_str(&cells.join(","));
        out.push('\n');
    }
    std::fs::write(path, out)
}
