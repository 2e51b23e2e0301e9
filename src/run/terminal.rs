//! What a run shows on the terminal (stderr): a progress line for the phase being worked
//! on (an `indicatif` spinner, hidden when stderr is not a terminal or with `--quiet`), a
//! compact table after each load step (the SIFs of every crack, the contact figures, the
//! step's warnings), and with `--verbose` one line per contact Newton iteration.
//!
//! Entry points: [`Terminal`] (it is also the [`SolveObserver`] of the solve) and
//! [`step_table`] (the text printed after a step).

use crate::run::summary::StepInfo;
use crate::solve::observe::{NewtonIteration, Phase, SolveObserver};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::fmt::Write;
use std::sync::Mutex;
use std::time::Duration;

/// The terminal of a run.
pub struct Terminal {
    bar: ProgressBar,
    quiet: bool,
    verbose: bool,
    /// `step i/n` once the load steps have started.
    step: Mutex<String>,
}

impl Terminal {
    /// `quiet`: print nothing (errors are the caller's). `verbose`: print every contact
    /// Newton iteration.
    pub fn new(quiet: bool, verbose: bool) -> Terminal {
        let target = if quiet { ProgressDrawTarget::hidden() } else { ProgressDrawTarget::stderr() };
        let bar = ProgressBar::with_draw_target(None, target);
        let style = ProgressStyle::with_template("{spinner} {elapsed:>4} {wide_msg}").expect("a valid template");
        bar.set_style(style);
        if !bar.is_hidden() {
            bar.enable_steady_tick(Duration::from_millis(120));
        }
        Terminal { bar, quiet, verbose: verbose && !quiet, step: Mutex::new(String::new()) }
    }

    /// Shows what the run is doing now.
    pub fn phase(&self, what: &str) {
        let step = self.step.lock().map(|s| s.clone()).unwrap_or_default();
        if step.is_empty() {
            self.bar.set_message(what.to_string());
        } else {
            self.bar.set_message(format!("{step} · {what}"));
        }
    }

    /// Prints lines above the progress line (stderr; nothing when quiet).
    pub fn print(&self, text: &str) {
        if self.quiet {
            return;
        }
        let text = text.trim_end_matches('\n');
        self.bar.suspend(|| eprintln!("{text}"));
    }

    /// Removes the progress line.
    pub fn finish(&self) {
        self.bar.finish_and_clear();
    }
}

impl Drop for Terminal {
    fn drop(&mut self) {
        self.bar.finish_and_clear();
    }
}

impl SolveObserver for Terminal {
    fn phase(&self, phase: Phase) {
        match phase {
            Phase::Pattern { equations } => self.phase(&format!("sparsity pattern ({equations} unknowns)")),
            Phase::Symbolic { equations, nnz_matrix } => self.phase(&format!(
                "ordering and symbolic factorisation ({equations} equations, {nnz_matrix} matrix entries)"
            )),
            Phase::Factorisation { step: _, nnz_factor } => match nnz_factor {
                Some(n) => self.phase(&format!("factorisation ({} factor entries)", si(n as f64))),
                None => self.phase("factorisation"),
            },
            Phase::Step { index, total } => {
                if let Ok(mut s) = self.step.lock() {
                    *s = format!("step {index}/{total}");
                }
                self.phase("assembly and solve");
            }
            Phase::ContactLoops { step: _, geometry } => {
                if geometry > 1 {
                    self.phase(&format!("contact loops (geometry pass {geometry})"));
                } else {
                    self.phase("contact loops");
                }
            }
            Phase::Pairing { step: _ } => self.phase("pairing the contact points"),
        }
    }

    fn newton(&self, it: &NewtonIteration) {
        self.phase(&format!(
            "contact: friction pass {}, active set {}, Newton {}, correction {:.1e}",
            it.friction, it.active_set, it.newton, it.correction
        ));
        if self.verbose {
            self.print(&newton_line(it));
        }
    }
}

/// One `--verbose` line for a Newton iteration.
pub fn newton_line(it: &NewtonIteration) -> String {
    format!(
        "  newton {:>3}  (step {}, friction pass {}, active set {})  open {} stick {} slip {}  changed {}  correction {:.3e}{}",
        it.newton,
        it.step,
        it.friction,
        it.active_set,
        it.open,
        it.stick,
        it.slip,
        it.changed,
        it.correction,
        if it.factorised { "" } else { "  (factor reused)" }
    )
}

/// A number with 4 significant digits, in scientific notation when far from 1.
fn num(v: f64) -> String {
    let a = v.abs();
    if v == 0.0 || (1e-3..1e5).contains(&a) {
        format!("{v:.4}")
    } else {
        format!("{v:.4e}")
    }
}

/// A count with an SI prefix (k, M, G).
fn si(v: f64) -> String {
    match v {
        v if v >= 1e9 => format!("{:.2}G", v / 1e9),
        v if v >= 1e6 => format!("{:.2}M", v / 1e6),
        v if v >= 1e3 => format!("{:.1}k", v / 1e3),
        v => format!("{v:.0}"),
    }
}

/// The table printed after a step: the step line; per crack its K at the front points
/// (2D: each tip; 3D: min / mean / max along the front); the contact figures; the
/// warnings of the step.
pub fn step_table(step: &StepInfo, n_steps: usize, dim: usize, warnings: &[String]) -> String {
    let mut t = String::new();
    let _ = writeln!(
        t,
        "step {}/{}  load factor {}  residual {:.1e}  max |u| {:.4e}",
        step.index,
        n_steps,
        num(step.load_factor),
        step.solver.residual,
        step.max_displacement
    );
    let fronts: Vec<_> = step.cracks.iter().filter(|c| !c.front.is_empty()).collect();
    if !fronts.is_empty() {
        let w = fronts.iter().map(|c| c.name.len()).max().unwrap_or(5).max(5);
        let at =
            |i: usize, p: &crate::post::sif::SifPoint| format!("tip {} ({}, {})", i + 1, short(p.x[0]), short(p.x[1]));
        let f = if dim == 2 {
            fronts.iter().flat_map(|c| c.front.iter().enumerate().map(|(i, p)| at(i, p).len())).max().unwrap_or(0)
        } else {
            fronts.iter().map(|c| format!("{} points, mean", c.front.len()).len()).max().unwrap_or(0)
        }
        .max(5);
        let _ = writeln!(t, "  {:<w$}  {:<f$} {:>12} {:>12} {:>12}", "crack", "front", "K_I", "K_II", "K_III");
        for c in fronts {
            if dim == 2 {
                for (i, p) in c.front.iter().enumerate() {
                    let _ = writeln!(
                        t,
                        "  {:<w$}  {:<f$} {:>12} {:>12} {:>12}",
                        c.name,
                        at(i, p),
                        num(p.k1),
                        num(p.k2),
                        num(p.k3)
                    );
                }
            } else {
                let n = c.front.len() as f64;
                let stats = |f: &dyn Fn(&crate::post::sif::SifPoint) -> f64| {
                    let v: Vec<f64> = c.front.iter().map(f).collect();
                    let min = v.iter().cloned().fold(f64::INFINITY, f64::min);
                    let max = v.iter().cloned().fold(f64::NEG_INFINITY, f64::max);
                    (min, v.iter().sum::<f64>() / n, max)
                };
                let k = [stats(&|p| p.k1), stats(&|p| p.k2), stats(&|p| p.k3)];
                let label = format!("{} points", c.front.len());
                for (row, pick) in [("min", 0), ("mean", 1), ("max", 2)] {
                    let v = |s: (f64, f64, f64)| [s.0, s.1, s.2][pick];
                    let name = if pick == 0 { c.name.as_str() } else { "" };
                    let front = if pick == 0 { format!("{label}, {row}") } else { row.to_string() };
                    let _ = writeln!(
                        t,
                        "  {:<w$}  {:<f$} {:>12} {:>12} {:>12}",
                        name,
                        front,
                        num(v(k[0])),
                        num(v(k[1])),
                        num(v(k[2]))
                    );
                }
            }
        }
    }
    if let Some(c) = &step.contact {
        let it = &c.iterations;
        let _ = write!(
            t,
            "  contact: {} points, {} active ({} stick, {} slip), λ in [{}, {}]; iterations: friction {}, active set {}, Newton {}",
            c.points,
            c.active,
            c.stick,
            c.slip,
            num(c.lambda_min),
            num(c.lambda_max),
            it.friction,
            it.active_set,
            it.newton
        );
        if let Some(g) = it.geometry {
            let _ = write!(t, ", geometry {g}");
        }
        let _ = writeln!(t, "; {} factorisations", c.factorizations);
    }
    for w in warnings {
        let _ = writeln!(t, "  warning: {w}");
    }
    t
}

/// A coordinate, short.
fn short(v: f64) -> String {
    let s = format!("{v:.4}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    if s == "-0" {
        "0".into()
    } else {
        s.to_string()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::post::sif::SifPoint;
    use crate::run::summary::{ContactInfo, CrackInfo};

    #[test]
    fn the_step_table_shows_the_tips_the_contact_and_the_warnings() {
        let p = |x: f64, k1: f64| SifPoint {
            x: [x, 0.0, 0.0],
            e1: [1.0, 0.0, 0.0],
            e2: [0.0, 1.0, 0.0],
            e3: [0.0, 0.0, 1.0],
            k1,
            k2: -2.0,
            k3: 0.0,
            g: 0.0,
            cycle: None,
        };
        let step = StepInfo {
            index: 2,
            load_factor: 0.5,
            cracks: vec![CrackInfo {
                name: "c".into(),
                tip_radius: None,
                front: vec![p(-1.0, 3.0), p(1.0, 4.0)],
                growth: None,
            }],
            contact: Some(ContactInfo { points: 10, active: 8, stick: 3, slip: 5, ..Default::default() }),
            ..Default::default()
        };
        let t = step_table(&step, 4, 2, &["watch out".into()]);
        assert!(t.starts_with("step 2/4  load factor 0.5000"), "{t}");
        assert!(t.contains("tip 1 (-1, 0)") && t.contains("3.0000") && t.contains("-2.0000"), "{t}");
        assert!(t.contains("tip 2 (1, 0)") && t.contains("4.0000"), "{t}");
        assert!(t.contains("10 points, 8 active (3 stick, 5 slip)"), "{t}");
        assert!(t.contains("warning: watch out"), "{t}");
        // 3D: min / mean / max along the front.
        let t = step_table(&step, 4, 3, &[]);
        assert!(t.contains("2 points, min") && t.contains("3.5000") && t.contains("max"), "{t}");
    }
}
