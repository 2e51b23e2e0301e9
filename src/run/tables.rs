//! The CSV tables written next to `summary.json` (documented in `docs/outputs.md`; their
//! columns are public interface):
//!
//! - `sif.csv`: one row per step, crack and front point:
//!   `step,crack,point,x,y,z,K_I,K_II,K_III,G`;
//! - `contact.csv` (runs with contact): one row per step and contact crack:
//!   `step,crack,points,active,stick,slip,lambda_min,lambda_max,friction_iterations,active_set_iterations,newton_iterations,geometry_iterations,residual`.
//!
//! Both are written from the [`Summary`], so they hold exactly the figures of
//! `summary.json`. Entry point: [`write_tables`].

use crate::run::summary::Summary;
use serde::Serialize;
use std::path::{Path, PathBuf};

/// The header of `sif.csv`.
pub const SIF_COLUMNS: [&str; 10] = ["step", "crack", "point", "x", "y", "z", "K_I", "K_II", "K_III", "G"];

/// The header of `contact.csv`.
pub const CONTACT_COLUMNS: [&str; 13] = [
    "step",
    "crack",
    "points",
    "active",
    "stick",
    "slip",
    "lambda_min",
    "lambda_max",
    "friction_iterations",
    "active_set_iterations",
    "newton_iterations",
    "geometry_iterations",
    "residual",
];

#[derive(Serialize)]
struct SifRow<'a> {
    step: usize,
    crack: &'a str,
    /// 1-based front point (2D: the tip number).
    point: usize,
    x: f64,
    y: f64,
    z: f64,
    #[serde(rename = "K_I")]
    k1: f64,
    #[serde(rename = "K_II")]
    k2: f64,
    #[serde(rename = "K_III")]
    k3: f64,
    #[serde(rename = "G")]
    g: f64,
}

#[derive(Serialize)]
struct ContactRow<'a> {
    step: usize,
    crack: &'a str,
    points: usize,
    active: usize,
    stick: usize,
    slip: usize,
    lambda_min: f64,
    lambda_max: f64,
    friction_iterations: usize,
    active_set_iterations: usize,
    newton_iterations: usize,
    /// Empty without large sliding.
    geometry_iterations: Option<usize>,
    residual: f64,
}

/// Writes `sif.csv` (when a crack has a front) and `contact.csv` (with contact) into
/// `dir`; returns the files written.
pub fn write_tables(summary: &Summary, dir: &Path) -> Result<Vec<PathBuf>, String> {
    let mut written = vec![];
    let has_front = summary.steps.iter().any(|s| s.cracks.iter().any(|c| !c.front.is_empty()));
    if has_front {
        let path = dir.join("sif.csv");
        let mut w = csv::Writer::from_path(&path).map_err(|e| format!("{}: {e}", path.display()))?;
        let err = |e: csv::Error| format!("{}: {e}", path.display());
        for s in &summary.steps {
            for c in &s.cracks {
                for (i, p) in c.front.iter().enumerate() {
                    w.serialize(SifRow {
                        step: s.index,
                        crack: &c.name,
                        point: i + 1,
                        x: p.x[0],
                        y: p.x[1],
                        z: p.x[2],
                        k1: p.k1,
                        k2: p.k2,
                        k3: p.k3,
                        g: p.g,
                    })
                    .map_err(err)?;
                }
            }
        }
        w.flush().map_err(|e| format!("{}: {e}", path.display()))?;
        written.push(path);
    }
    if summary.steps.iter().any(|s| s.contact.is_some()) {
        let path = dir.join("contact.csv");
        let mut w = csv::Writer::from_path(&path).map_err(|e| format!("{}: {e}", path.display()))?;
        let err = |e: csv::Error| format!("{}: {e}", path.display());
        for s in &summary.steps {
            let Some(c) = &s.contact else { continue };
            for k in &c.cracks {
                w.serialize(ContactRow {
                    step: s.index,
                    crack: &k.name,
                    points: k.points,
                    active: k.active,
                    stick: k.stick,
                    slip: k.slip,
                    lambda_min: k.lambda_min,
                    lambda_max: k.lambda_max,
                    friction_iterations: c.iterations.friction,
                    active_set_iterations: c.iterations.active_set,
                    newton_iterations: c.iterations.newton,
                    geometry_iterations: c.iterations.geometry,
                    residual: c.residual,
                })
                .map_err(err)?;
            }
        }
        w.flush().map_err(|e| format!("{}: {e}", path.display()))?;
        written.push(path);
    }
    Ok(written)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_headers_are_the_documented_columns() {
        // serde writes the header from the row's field names: they must be the constants.
        let mut w = csv::Writer::from_writer(vec![]);
        w.serialize(SifRow { step: 1, crack: "c", point: 1, x: 0., y: 0., z: 0., k1: 0., k2: 0., k3: 0., g: 0. })
            .unwrap();
        let text = String::from_utf8(w.into_inner().unwrap()).unwrap();
        assert_eq!(text.lines().next().unwrap(), SIF_COLUMNS.join(","));
        let mut w = csv::Writer::from_writer(vec![]);
        w.serialize(ContactRow {
            step: 1,
            crack: "c",
            points: 0,
            active: 0,
            stick: 0,
            slip: 0,
            lambda_min: 0.,
            lambda_max: 0.,
            friction_iterations: 0,
            active_set_iterations: 0,
            newton_iterations: 0,
            geometry_iterations: None,
            residual: 0.,
        })
        .unwrap();
        let text = String::from_utf8(w.into_inner().unwrap()).unwrap();
        assert_eq!(text.lines().next().unwrap(), CONTACT_COLUMNS.join(","));
    }
}
