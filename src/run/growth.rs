//! The crack growth loop, in one function (`run_growth`):
//!
//! ```text
//! for entry 0, 1, …, steps:
//!     solve the load steps on the current cracks ─► record the last one (VTU, SIFs)
//!     K at every tip ─► cycles of the increment that led here (fatigue, trapezoidal)
//!     stop? (last entry, K_eq > K_c, stop_length)
//!     criterion ─► kink angle θ and K_eq per tip ─► advance Δa per tip
//!     new geometry: one segment appended per growing tip (stop if it leaves the body or
//!     meets a crack)
//!     rebuild: level sets, cut, enrichment, contact points and multipliers
//! ```
//!
//! Each entry is one `steps[]` element of `summary.json` (index = entry, PVD time =
//! entry); the path is written to `crack_path.csv` as the run goes, and with `[output]
//! plots` drawn in `crack_path.png` (over the body outline) and, in fatigue, as the crack
//! advances against the cycles in `crack_cycles.png` (both rewritten at every entry, so
//! that a run stopped by an error keeps the path so far). In 2D the growing cracks are
//! polylines ([`crate::growth::polyline`]); in 3D (`run_growth_3d`) triangulated
//! surfaces whose front advances by a strip of triangles ([`crate::growth::surface`]),
//! with only `crack_cycles.png` among the plots. The model is rebuilt from the
//! case with the grown shapes (`shape = "mesh"` cracks), so everything downstream of the
//! level sets is rebuilt as for a fixed crack, but for the fill-reducing ordering in 2D:
//! the node order of entry 0's analysis is kept and expanded to each later entry's
//! unknowns (the node graph does not change with the crack:
//! [`crate::solve::ordering::reuse`]).
//! Contact starts each entry from the previous
//! entry's converged statuses (contact status, friction threshold; of the first load step)
//! at the points where the crack did not change, and from the case's initial statuses at
//! the others ([`CarriedStatuses`]).
//!
//! Fatigue with `min_load_factor` and contact in the model: each entry solves one more load
//! step after the case's, the cycle's minimum at t = f · t_max, from the maximum's converged
//! state, and takes K_min along the front from it (with the contact tractions); every
//! front point of a fatigue run gets its cycle (`set_cycle`: K_min, ΔK_eq), and the
//! criteria plan with the cycle's effective ranges (`planned_k`, `growth::fatigue`).

use super::plots::{self, CrackPath};
use super::summary::{CrackInfo, GrowthInfo};
use super::Recorder;
use crate::case::{resolve, Case, CaseError, PropagationDef};
use crate::contact::carry::CarriedStatuses;
use crate::contact::ContactSetup;
use crate::growth::criteria::{self, TipPlan};
use crate::growth::fatigue::{cycle_minimum, increment_cycles, ranges};
use crate::growth::polyline::{segments_meet, Body2d, GrowingCurve};
use crate::growth::surface::{
    interpolate_on_front, smooth_k_eq, smooth_k_eq_trusted, surface_crossings, Body3d, GrowingSurface,
};
use crate::growth::Propagation;
use crate::levelset::explicit::ExplicitError;
use crate::levelset::CrackShape;
use crate::mesh::Mesh;
use crate::physics::model::Model;
use crate::post::sif::{CycleMinimum, SifOptions, SifPoint};
use crate::solve::observe::SolveObserver;
use crate::solve::ordering::reuse::ReusedOrdering;
use crate::solve::statics::{self, SolveError, SolveOptions, SolveReport};
use std::fmt::Write as _;
use std::sync::Arc;

/// The header of `crack_path.csv`.
pub const CRACK_PATH_COLUMNS: &str =
    "entry,crack,point,x,y,z,K_I,K_II,K_III,G,advance,kink_angle_deg,cycles,K_I_min,K_II_min,K_III_min,dK_eq";

/// Checks a `[propagation]` case against its mesh: 2D, the increment below the body's
/// size, and every growing crack a segment, half-line or meshed open curve. Errors name
/// the key and line.
pub fn check_propagation(case: &Case, prop: &PropagationDef, mesh: &Mesh) -> Result<(), CaseError> {
    if mesh.dim == 3 {
        return check_propagation_3d(case, prop, mesh);
    }
    let body = Body2d::new(mesh);
    let (lo, hi) = mesh.bounding_box();
    let size = (hi[0] - lo[0]).max(hi[1] - lo[1]);
    if prop.options.increment >= size {
        return Err(prop.increment_at.error(
            "increment",
            format!("the increment {} is not smaller than the body (its size is {size})", prop.options.increment),
        ));
    }
    for c in case.cracks.iter().filter(|c| c.grow) {
        if GrowingCurve::from_shape(&c.shape, &body).is_none() {
            return Err(c.at.error(
                "shape",
                format!(
                    "crack '{}' is a {}: a growing 2D crack is a segment, a half_line or a meshed open curve (or give grow = false)",
                    c.name,
                    c.shape.name()
                ),
            ));
        }
    }
    Ok(())
}

/// [`check_propagation`] in 3D: the increment below the body's size, and every growing
/// crack a disc, an elliptic disc or a meshed surface with one closed front.
fn check_propagation_3d(case: &Case, prop: &PropagationDef, mesh: &Mesh) -> Result<(), CaseError> {
    let (lo, hi) = mesh.bounding_box();
    let size = (0..3).map(|i| hi[i] - lo[i]).fold(0.0, f64::max);
    if prop.options.increment >= size {
        return Err(prop.increment_at.error(
            "increment",
            format!("the increment {} is not smaller than the body (its size is {size})", prop.options.increment),
        ));
    }
    for c in case.cracks.iter().filter(|c| c.grow) {
        if let Err(why) = GrowingSurface::from_shape(&c.shape, mesh.typical_size()) {
            let interface = if c.shape.has_front() { "" } else { " (an interface: it has no front to grow)" };
            return Err(c
                .at
                .error("shape", format!("crack '{}' cannot grow{interface}: {why} (or give grow = false)", c.name)));
        }
    }
    Ok(())
}

/// One tip of a growing crack at one entry: its front point in the entry's SIF list and
/// which end of the polyline it is.
#[derive(Debug, Clone, Copy)]
struct Tip {
    crack: usize,
    point: usize,
    end: usize,
    x: [f64; 3],
    e1: [f64; 3],
    e2: [f64; 3],
    k1: f64,
    k2: f64,
    /// The (K_I, K_II) the criterion plans with: the cycle's ranges in fatigue
    /// ([`planned_k`]), else k1, k2.
    d1: f64,
    d2: f64,
}

/// Runs the growth loop of `rec.case`, starting from the model built on the initial
/// cracks. Stops cleanly (status ok, the reason in `warnings`) when a crack reaches the
/// boundary or another crack, when K_eq exceeds `fracture_toughness`, when no tip is
/// above the threshold, or at `stop_length`.
pub(super) fn run_growth(
    rec: &mut Recorder<'_>,
    mesh: &Mesh,
    model: Model<'_>,
    contact: Option<ContactSetup>,
    prop: &Propagation,
    options: &SolveOptions,
    observer: &dyn SolveObserver,
) -> Result<SolveReport, SolveError> {
    // The node graph does not change with the crack: the ordering of the first entry's
    // analysis is reused by the later ones (`solve::ordering::reuse`).
    let options = &SolveOptions {
        reuse_ordering: Some(options.reuse_ordering.clone().unwrap_or_else(|| Arc::new(ReusedOrdering::new()))),
        ..options.clone()
    };
    let mut model = model;
    add_cycle_minimum(&mut model, contact.as_ref(), prop);
    if mesh.dim == 3 {
        return run_growth_3d(rec, mesh, model, contact, prop, options, observer);
    }
    let case = rec.case;
    rec.n_steps = prop.steps;
    let fail = |m: String| SolveError::Callback(m);
    let body = Body2d::new(mesh);
    let mut curves: Vec<Option<GrowingCurve>> =
        case.cracks.iter().map(|c| if c.grow { GrowingCurve::from_shape(&c.shape, &body) } else { None }).collect();
    let mut grown_case = case.clone();
    let (mut model, mut contact) = (model, contact);
    // The converged contact statuses of the previous entry, to start the next from.
    let mut carried: Option<CarriedStatuses> = None;
    let csv_path = rec.out_dir.join("crack_path.csv");
    let mut csv = format!("{CRACK_PATH_COLUMNS}\n");
    let mut cycles = 0.0;
    // The plan of the increment that led to the current entry: per crack, (end, plan) in
    // the previous entry's front order; and the tip that advanced by Δa_max.
    let mut previous: Vec<Vec<(usize, TipPlan)>> = vec![vec![]; case.cracks.len()];
    let mut leader: Option<(usize, usize, TipPlan)> = None;
    let mut total: Option<SolveReport> = None;
    // The plots: the body outline, each crack's initial polyline (frozen cracks drawn as
    // they are, when they are open curves) and the advances against the cycles.
    let outline: Vec<([f64; 3], [f64; 3])> = if case.output.plots {
        mesh.boundary_faces().iter().map(|f| (mesh.nodes[f.nodes()[0]], mesh.nodes[f.nodes()[1]])).collect()
    } else {
        vec![]
    };
    let initial: Vec<Option<Vec<[f64; 3]>>> =
        case.cracks.iter().map(|c| GrowingCurve::from_shape(&c.shape, &body).map(|g| g.points)).collect();
    let mut lengths: Vec<(f64, Vec<f64>)> = vec![];
    for entry in 0..=prop.steps {
        // Solve on the current cracks; record the last load step as this entry.
        if entry > 0 {
            let shapes = curves.iter().enumerate().filter_map(|(k, c)| c.as_ref().map(|c| (k, c.shape())));
            (model, contact) = rebuild(&mut grown_case, shapes, mesh, entry, prop)?;
        }
        let report = solve_entry(rec, &model, contact.as_ref(), options, observer, entry, &mut carried, prop)?;
        total = Some(add_timings(total, report));

        // K at every tip of the growing cracks.
        let step = rec.summary.steps.last_mut().expect("the entry was recorded");
        let mut tips: Vec<Tip> = vec![];
        for (k, curve) in curves.iter().enumerate() {
            let Some(curve) = curve else { continue };
            for (i, f) in step.cracks[k].front.iter().enumerate() {
                let end = (0..2)
                    .filter(|&e| curve.tips[e])
                    .min_by(|&a, &b| dist(curve.end(a), f.x).total_cmp(&dist(curve.end(b), f.x)));
                let Some(end) = end else { continue };
                let d = planned_k(f);
                let (x, e1, e2, k1, k2) = (f.x, f.e1, f.e2, f.k1, f.k2);
                tips.push(Tip { crack: k, point: i, end, x, e1, e2, k1, k2, d1: d[0], d2: d[1] });
            }
            let found = tips.iter().filter(|t| t.crack == k).count();
            let expected = curve.tips.iter().filter(|t| **t).count();
            if found != expected {
                return Err(fail(format!(
                    "step {entry}: crack '{}' has {found} front points for its {expected} tips",
                    case.cracks[k].name
                )));
            }
        }
        if let Some(t) = tips.iter().find(|t| ![t.k1, t.k2, t.d1, t.d2].iter().all(|k| k.is_finite())) {
            return Err(fail(format!(
                "step {entry}: crack '{}': K is not finite at the front point {:?}",
                case.cracks[t.crack].name, t.x
            )));
        }
        let k_eq_of = |k1: f64, k2: f64| {
            let th = criteria::kink_angle(prop.criterion, k1, k2);
            criteria::equivalent_k(prop.criterion, k1, k2, th)
        };
        // The static K_eq (the fracture toughness reads it) and the planned one (ΔK_eq in
        // fatigue: the cycles and the advances).
        let k_eq_now = |t: &Tip| k_eq_of(t.k1, t.k2);
        let drive_now = |t: &Tip| k_eq_of(t.d1, t.d2);

        // Cycles of the increment that led here: trapezoidal, K_eq at both ends of the
        // leading tip's advance.
        if let (Some(f), Some((k, end, p))) = (prop.fatigue, leader) {
            let now = tips.iter().find(|t| t.crack == k && t.end == end).map(drive_now);
            if let Some(k_end) = now {
                cycles += increment_cycles(&f, p.advance, p.k_eq, k_end);
            }
        }
        for (k, info) in step.cracks.iter_mut().enumerate() {
            let prev = &previous[k];
            info.growth = Some(GrowthInfo {
                cycles,
                advance_max: prev.iter().map(|(_, p)| p.advance).fold(0.0, f64::max),
                kink_angle_deg: prev.iter().map(|(_, p)| p.theta.to_degrees()).collect(),
            });
            for (i, f) in info.front.iter().enumerate() {
                let end = tips.iter().find(|t| t.crack == k && t.point == i).map(|t| t.end);
                let p = end.and_then(|e| prev.iter().find(|(pe, _)| *pe == e)).map(|(_, p)| *p);
                let (adv, th) = p.map_or((0.0, 0.0), |p| (p.advance, p.theta.to_degrees()));
                path_row(&mut csv, entry, &info.name, i, f, adv, th, cycles);
            }
        }
        std::fs::write(&csv_path, &csv).map_err(|e| fail(format!("{}: {e}", csv_path.display())))?;
        if case.output.plots {
            lengths.push((cycles, curves.iter().flatten().map(|c| c.grown[0] + c.grown[1]).collect()));
            write_growth_plots(rec, &outline, &initial, &curves, prop.fatigue.is_some(), &lengths, entry)
                .map_err(fail)?;
        }

        // Stop: an unstable point, the last entry, or the stop length reached.
        let unstable = prop.fracture_toughness.and_then(|kc| tips.iter().find(|t| k_eq_now(t) > kc)).map(|t| {
            (case.cracks[t.crack].name.as_str(), k_eq_now(t), format!("{} ({:.6}, {:.6})", t.point, t.x[0], t.x[1]))
        });
        let grown = curves.iter().flatten().flat_map(|c| c.grown).fold(0.0, f64::max);
        if let Some(why) = stop_after(prop, entry, grown, unstable, "a tip") {
            rec.summary.warnings.extend(why);
            break;
        }
        let remaining = prop.stop_length.map_or(f64::INFINITY, |l| l - grown);

        // Direction and advance of every tip.
        let ks: Vec<(f64, f64, bool)> = tips.iter().map(|t| (t.d1, t.d2, true)).collect();
        let Some(mut plan) = criteria::plan(&ks, prop) else {
            rec.summary
                .warnings
                .push(format!("no front point is above the growth threshold at step {entry}: growth stopped"));
            break;
        };
        let max_advance = plan.iter().map(|p| p.advance).fold(0.0, f64::max);
        if max_advance > remaining {
            for p in plan.iter_mut() {
                p.advance *= remaining / max_advance;
            }
        }

        // The new geometry: one segment per advancing tip, inside the body and clear of
        // every crack.
        let new_points = match new_segments(case, &body, &curves, &tips, &plan, entry) {
            Ok(n) => n,
            Err(stop) => {
                rec.summary.warnings.push(stop);
                break;
            }
        };
        for n in new_points {
            curves[n.crack].as_mut().expect("a growing crack").extend(n.end, n.to);
        }
        for v in previous.iter_mut() {
            v.clear();
        }
        for (t, p) in tips.iter().zip(&plan) {
            previous[t.crack].push((t.end, *p));
        }
        leader = tips
            .iter()
            .zip(&plan)
            .max_by(|a, b| a.1.advance.total_cmp(&b.1.advance))
            .map(|(t, p)| (t.crack, t.end, *p));
    }
    Ok(total.expect("entry 0 was solved"))
}

/// The growth loop in 3D (the stages of [`run_growth`]): the growing cracks are
/// triangulated surfaces ([`crate::growth::surface`]). At each entry the SIF points of a
/// growing crack's front each get a kink and a driving force ([`criteria::drive_3d`]),
/// K_eq is smoothed along each front ([`smooth_k_eq`]), and the advances follow
/// ([`criteria::advances`], over every growing crack together); these are interpolated onto the front vertices along the
/// front, the front moves, is re-sampled at the local cell size and joined by a strip of
/// triangles. Fatigue: the cycles of an increment are the trapezoidal rule at each SIF
/// point that advanced (its K_eq before, and after at the new front's SIF point nearest
/// where it moved), averaged over those points (by the Paris-proportional advance they
/// all give the same cycles at the start). A new front vertex within one cell of the
/// body surface or beyond it stops the growth ("reached the boundary"), unless the
/// nearest face is one the front already runs out through (a surface crack, whose front
/// ends slide along that face; their K_eq is extrapolated from inside, [`smoothed_drives`]).
/// Meeting another crack is not checked in 3D.
fn run_growth_3d(
    rec: &mut Recorder<'_>,
    mesh: &Mesh,
    model: Model<'_>,
    contact: Option<ContactSetup>,
    prop: &Propagation,
    options: &SolveOptions,
    observer: &dyn SolveObserver,
) -> Result<SolveReport, SolveError> {
    let case = rec.case;
    rec.n_steps = prop.steps;
    let fail = |m: String| SolveError::Callback(m);
    let body = Body3d::new(mesh);
    // The growing surfaces, their fronts sampled at the size of the cells they cross.
    let mut surfaces: Vec<Option<GrowingSurface>> = vec![];
    for c in &case.cracks {
        if !c.grow {
            surfaces.push(None);
            continue;
        }
        let why = |e: String| fail(format!("crack '{}' cannot grow: {e}", c.name));
        let first = GrowingSurface::from_shape(&c.shape, mesh.typical_size()).map_err(why)?;
        let spacing = body.spacing(&first.front_points());
        surfaces.push(Some(GrowingSurface::from_shape(&c.shape, spacing).map_err(why)?));
    }
    let mut grown_case = case.clone();
    let (mut model, mut contact) = (model, contact);
    // The converged contact statuses of the previous entry, to start the next from.
    let mut carried: Option<CarriedStatuses> = None;
    let csv_path = rec.out_dir.join("crack_path.csv");
    let mut csv = format!("{CRACK_PATH_COLUMNS}\n");
    let mut cycles = 0.0;
    // The increment that led to the current entry: per crack, its SIF points then and
    // their plans.
    let mut previous: Vec<Vec<(SifPoint, TipPlan)>> = vec![vec![]; case.cracks.len()];
    let mut total: Option<SolveReport> = None;
    let mut lengths: Vec<(f64, Vec<f64>)> = vec![];
    let moved = |p: &SifPoint, plan: &TipPlan| {
        let (c, s) = (plan.theta.cos(), plan.theta.sin());
        let d = [c * p.e1[0] + s * p.e2[0], c * p.e1[1] + s * p.e2[1], c * p.e1[2] + s * p.e2[2]];
        [p.x[0] + plan.advance * d[0], p.x[1] + plan.advance * d[1], p.x[2] + plan.advance * d[2]]
    };
    for entry in 0..=prop.steps {
        if entry > 0 {
            let shapes = surfaces.iter().enumerate().filter_map(|(k, s)| s.as_ref().map(|s| (k, s.shape())));
            (model, contact) = rebuild(&mut grown_case, shapes, mesh, entry, prop)?;
        }
        let report = solve_entry(rec, &model, contact.as_ref(), options, observer, entry, &mut carried, prop)?;
        total = Some(add_timings(total, report));

        // K at the SIF points of every growing crack.
        let step = rec.summary.steps.last_mut().expect("the entry was recorded");
        let mut points: Vec<(usize, SifPoint)> = vec![];
        for (k, s) in surfaces.iter().enumerate() {
            if s.is_none() {
                continue;
            }
            let front = &step.cracks[k].front;
            if front.is_empty() {
                return Err(fail(format!(
                    "step {entry}: crack '{}' has no front point inside the body",
                    case.cracks[k].name
                )));
            }
            let finite = |p: &SifPoint| [p.k1, p.k2, p.k3].into_iter().chain(planned_k(p)).all(f64::is_finite);
            if let Some(p) = front.iter().find(|p| !finite(p)) {
                return Err(fail(format!(
                    "step {entry}: crack '{}': K is not finite at the front point {:?}",
                    case.cracks[k].name, p.x
                )));
            }
            points.extend(front.iter().map(|p| (k, *p)));
        }
        // The kink and the driving force of every point, K_eq smoothed along its front.
        // (In fatigue the criterion reads the cycle's ranges, `planned_k`.)
        let planned: Vec<(usize, SifPoint)> = points
            .iter()
            .map(|(k, p)| {
                let [k1, k2, k3] = planned_k(p);
                (*k, SifPoint { k1, k2, k3, ..*p })
            })
            .collect();
        let (drives, ends) = smoothed_drives(prop, case, &body, &surfaces, &planned);
        let nearest = |k: usize, x: [f64; 3]| {
            (0..points.len())
                .filter(|&i| points[i].0 == k)
                .min_by(|&a, &b| dist(points[a].1.x, x).total_cmp(&dist(points[b].1.x, x)))
        };

        // Cycles of the increment that led here (trapezoidal at each advanced point).
        if let Some(f) = prop.fatigue {
            let mut sum = (0.0, 0usize);
            for (k, prev) in previous.iter().enumerate() {
                for (p, plan) in prev.iter().filter(|(_, plan)| plan.advance > 0.0) {
                    if let Some(end) = nearest(k, moved(p, plan)) {
                        sum.0 += increment_cycles(&f, plan.advance, plan.k_eq, drives[end].1);
                        sum.1 += 1;
                    }
                }
            }
            if sum.1 > 0 {
                cycles += sum.0 / sum.1 as f64;
            }
        }
        for (k, info) in step.cracks.iter_mut().enumerate() {
            let prev = &previous[k];
            info.growth = Some(GrowthInfo {
                cycles,
                advance_max: prev.iter().map(|(_, p)| p.advance).fold(0.0, f64::max),
                kink_angle_deg: prev.iter().map(|(_, p)| p.theta.to_degrees()).collect(),
            });
            for (i, f) in info.front.iter().enumerate() {
                // The increment's plan at the previous point that moved nearest to here.
                let p =
                    prev.iter().min_by(|a, b| dist(moved(&a.0, &a.1), f.x).total_cmp(&dist(moved(&b.0, &b.1), f.x)));
                let (adv, th) = p.map_or((0.0, 0.0), |(_, p)| (p.advance, p.theta.to_degrees()));
                path_row(&mut csv, entry, &info.name, i, f, adv, th, cycles);
            }
        }
        std::fs::write(&csv_path, &csv).map_err(|e| fail(format!("{}: {e}", csv_path.display())))?;
        if case.output.plots && prop.fatigue.is_some() {
            lengths.push((cycles, surfaces.iter().flatten().map(|s| s.grown).collect()));
            let names: Vec<String> =
                case.cracks.iter().zip(&surfaces).filter(|(_, s)| s.is_some()).map(|(c, _)| c.name.clone()).collect();
            let clock = std::time::Instant::now();
            plots::crack_cycles(&rec.out_dir.join("crack_cycles.png"), &names, &lengths).map_err(fail)?;
            rec.output_s += clock.elapsed().as_secs_f64();
        }

        // Stop: an unstable point, the last entry, or the stop length reached.
        // (The maximum's K_eq, smoothed: in fatigue `drives` are the ΔK_eq.)
        let static_drives = match (prop.fracture_toughness, prop.fatigue) {
            (Some(_), Some(_)) => smoothed_drives(prop, case, &body, &surfaces, &points).0,
            _ => vec![],
        };
        let static_drives = if static_drives.is_empty() { &drives } else { &static_drives };
        let unstable = prop
            .fracture_toughness
            .and_then(|kc| points.iter().enumerate().find(|(i, _)| static_drives[*i].1 > kc))
            .map(|(i, (k, p))| {
                let k_eq = static_drives[i].1;
                let i = i - points.iter().position(|(c, _)| c == k).unwrap_or(0);
                (case.cracks[*k].name.as_str(), k_eq, format!("{i} ({:.6}, {:.6}, {:.6})", p.x[0], p.x[1], p.x[2]))
            });
        let grown = surfaces.iter().flatten().map(|s| s.grown).fold(0.0, f64::max);
        if let Some(why) = stop_after(prop, entry, grown, unstable, "a front") {
            rec.summary.warnings.extend(why);
            break;
        }
        let remaining = prop.stop_length.map_or(f64::INFINITY, |l| l - grown);

        // Kink and advance of every SIF point.
        // (The front ends of surface cracks are planned with the points, so that they
        // share the normalisation by the largest driving force.)
        let mut all = drives.clone();
        all.extend(ends.iter().map(|e| e.drive));
        let Some(mut plan) = criteria::advances(&all, prop) else {
            rec.summary
                .warnings
                .push(format!("no front point is above the growth threshold at step {entry}: growth stopped"));
            break;
        };
        let max_advance = plan.iter().map(|p| p.advance).fold(0.0, f64::max);
        if max_advance > remaining {
            for p in plan.iter_mut() {
                p.advance *= remaining / max_advance;
            }
        }
        let end_plans = plan.split_off(points.len());

        // The new fronts: the advances interpolated onto the front vertices (and from the
        // front ends of a surface crack to the part of its loop outside the body); every
        // new vertex inside the body, at least one cell from its surface, but for those
        // near or beyond a face the front already runs out through (a surface crack's).
        let mut grown_surfaces = surfaces.clone();
        let mut stop = None;
        for (k, s) in grown_surfaces.iter_mut().enumerate() {
            let Some(s) = s else { continue };
            let mine: Vec<(usize, &SifPoint)> =
                points.iter().enumerate().filter(|(_, (c, _))| *c == k).map(|(i, (_, p))| (i, p)).collect();
            let mut at: Vec<[f64; 3]> = mine.iter().map(|(_, p)| p.x).collect();
            let mut adv: Vec<f64> = mine.iter().map(|(i, _)| plan[*i].advance).collect();
            let mut th: Vec<f64> = mine.iter().map(|(i, _)| plan[*i].theta).collect();
            for (e, p) in ends.iter().zip(&end_plans).filter(|(e, _)| e.crack == k) {
                at.push(e.x);
                adv.push(p.advance);
                th.push(p.theta);
            }
            let front = s.front_points();
            let open = body.open_faces(&front);
            let spacing = body.spacing(&front);
            let adv = interpolate_on_front(&front, &at, &adv);
            let th = interpolate_on_front(&front, &at, &th);
            let new = s.advance(&adv, &th, spacing);
            let stops = |x: &[f64; 3]| body.depth(*x) < body.cell_size(*x) && !body.faces_open(*x, &open);
            if let Some((i, x)) = new.iter().enumerate().find(|(_, x)| stops(x)) {
                let from = front.iter().copied().min_by(|a, b| dist(*a, *x).total_cmp(&dist(*b, *x))).unwrap_or(*x);
                stop = Some(format!(
                    "crack '{}' reached the boundary at step {entry}: its front near ({:.6}, {:.6}, {:.6}) would grow to ({:.6}, {:.6}, {:.6}) (new front point {i}), within one cell of the surface or beyond it; growth stopped",
                    case.cracks[k].name, from[0], from[1], from[2], x[0], x[1], x[2]
                ));
                break;
            }
        }
        if let Some(stop) = stop {
            rec.summary.warnings.push(stop);
            break;
        }
        surfaces = grown_surfaces;
        for v in previous.iter_mut() {
            v.clear();
        }
        for ((k, p), pl) in points.iter().zip(&plan) {
            previous[*k].push((*p, *pl));
        }
    }
    Ok(total.expect("entry 0 was solved"))
}

/// A front end of a surface crack: where its front loop crosses the body surface, with
/// the kink and driving force extrapolated there from the points inside.
#[derive(Debug, Clone, Copy)]
struct FrontEnd {
    crack: usize,
    x: [f64; 3],
    drive: (f64, f64, bool),
}

/// The kink θ and driving force K_eq,3D of every SIF point of the growing cracks' fronts
/// (`points[i] = (crack, point)`), as `(θ, K_eq, grows)` for [`criteria::advances`], with
/// K_eq smoothed along each crack's front ([`smooth_k_eq`]): the K of neighbouring
/// points come from overlapping domains and scatter by a percent or two about the field,
/// and the advance Δa_max (K_eq/K_eq,max)^p normalised by a raw maximum would let the
/// noisiest point set the scale of every other (the smoothed field keeps a uniform K
/// uniform, so a penny grows as a circle). θ is not smoothed here (the front vertices'
/// kink angles are, by [`GrowingSurface::advance`]).
///
/// A surface crack (a front that runs out of the body through a face): the points within
/// the SIF domain radius of that face (their domain cut by it, their K lowered by the
/// corner singularity where the front meets the free surface: −4.5% at φ ≈ 7° in
/// tests/surface_crack_newman_raju.rs) are not trusted; their K_eq, and that of the front
/// ends (where the loop crosses the face, returned as [`FrontEnd`]s with the θ of the
/// nearest point), are the linear extrapolation along the front of the smoothed K_eq of
/// the points inside ([`smooth_k_eq_trusted`]; docs/conventions.md, "Crack growth").
fn smoothed_drives(
    prop: &Propagation,
    case: &Case,
    body: &Body3d,
    surfaces: &[Option<GrowingSurface>],
    points: &[(usize, SifPoint)],
) -> (Vec<(f64, f64, bool)>, Vec<FrontEnd>) {
    let mut out: Vec<(f64, f64, bool)> = points
        .iter()
        .map(|(_, p)| criteria::drive_3d(prop.criterion, p.k1, p.k2, p.k3))
        .map(|(t, k)| (t, k, true))
        .collect();
    let mut ends = vec![];
    for (k, s) in surfaces.iter().enumerate() {
        let Some(s) = s else { continue };
        let mine: Vec<usize> = (0..points.len()).filter(|&i| points[i].0 == k).collect();
        let at: Vec<[f64; 3]> = mine.iter().map(|&i| points[i].1.x).collect();
        let k_eq: Vec<f64> = mine.iter().map(|&i| out[i].1).collect();
        let front = s.front_points();
        let open = body.open_faces(&front);
        if open.is_empty() {
            for (&i, v) in mine.iter().zip(smooth_k_eq(&front, &at, &k_eq)) {
                out[i].1 = v;
            }
            continue;
        }
        let radius = case.cracks[k].sif_radius;
        let trusted: Vec<bool> = at
            .iter()
            .map(|x| {
                let layer = radius.unwrap_or(3.0 * body.cell_size(*x));
                body.depth(*x) >= layer || !body.faces_open(*x, &open)
            })
            .collect();
        let crossings = surface_crossings(&front, body);
        let (fit, at_ends) = smooth_k_eq_trusted(&front, &at, &k_eq, &trusted, &crossings);
        for (&i, v) in mine.iter().zip(fit) {
            out[i].1 = v;
        }
        for (x, v) in crossings.iter().zip(at_ends) {
            let near =
                mine.iter().copied().min_by(|&a, &b| dist(points[a].1.x, *x).total_cmp(&dist(points[b].1.x, *x)));
            let theta = near.map_or(0.0, |i| out[i].0);
            ends.push(FrontEnd { crack: k, x: *x, drive: (theta, v, true) });
        }
    }
    (out, ends)
}

/// Whether the growth stops after `entry`, and the warning that says why (`None` inside:
/// the last entry, no warning): a front point whose K_eq exceeds the fracture toughness
/// (`unstable`: the crack, its K_eq and the point), or a growth of `grown` (the largest
/// advance so far of `what`, "a tip" or "a front") that reached `stop_length`.
fn stop_after(
    prop: &Propagation,
    entry: usize,
    grown: f64,
    unstable: Option<(&str, f64, String)>,
    what: &str,
) -> Option<Option<String>> {
    if let (Some((crack, k_eq, at)), Some(kc)) = (unstable, prop.fracture_toughness) {
        return Some(Some(format!(
            "crack '{crack}': K_eq = {k_eq:.6e} exceeds the fracture toughness {kc:.6e} at the front point {at} at step {entry}: unstable growth, stopped"
        )));
    }
    if entry == prop.steps {
        return Some(None);
    }
    let remaining = prop.stop_length.map_or(f64::INFINITY, |l| l - grown);
    (remaining <= 1e-9 * prop.increment)
        .then(|| Some(format!("{what} has grown by stop_length at step {entry}: growth stopped")))
}

/// Puts the grown cracks' `shapes` (crack index, shape) into `grown_case` and builds the
/// model and contact of `entry` from it.
fn rebuild<'m>(
    grown_case: &mut Case,
    shapes: impl Iterator<Item = (usize, Result<CrackShape, ExplicitError>)>,
    mesh: &'m Mesh,
    entry: usize,
    prop: &Propagation,
) -> Result<(Model<'m>, Option<ContactSetup>), SolveError> {
    for (k, shape) in shapes {
        grown_case.cracks[k].shape = shape.map_err(|e| {
            SolveError::Callback(format!(
                "step {entry}: crack '{}': the grown crack is invalid: {e}",
                grown_case.cracks[k].name
            ))
        })?;
    }
    let grown_case = &*grown_case;
    let (mut model, contact) = resolve::build_model(grown_case, mesh)
        .and_then(|m| resolve::build_contact(grown_case, &m).map(|c| (m, c)))
        .map_err(|e| {
            SolveError::Callback(format!("step {entry}: the grown crack could not be set up: {}", e.message))
        })?;
    add_cycle_minimum(&mut model, contact.as_ref(), prop);
    Ok((model, contact))
}

/// Whether the entries solve the fatigue cycle's minimum: `min_load_factor` with contact
/// in the model (without contact the model is linear, K_min = f K_max).
fn solves_minimum(prop: &Propagation, contact: Option<&ContactSetup>) -> bool {
    contact.is_some() && prop.fatigue.is_some_and(|f| f.min_load_factor.is_some())
}

/// Appends the cycle's minimum to the model's load steps when the entries solve it
/// ([`solves_minimum`]): one more step at t = f · t_max, after the case's last.
fn add_cycle_minimum(model: &mut Model<'_>, contact: Option<&ContactSetup>, prop: &Propagation) {
    if !solves_minimum(prop, contact) {
        return;
    }
    let f = prop.fatigue.and_then(|f| f.min_load_factor).unwrap_or(0.0);
    let t_max = model.load_factors.last().copied().unwrap_or(1.0);
    model.load_factors.push(f * t_max);
}

/// The (K_I, K_II, K_III) the criterion plans with at a front point: in fatigue (the point
/// has its cycle, [`set_cycle`]) the cycle's effective ranges, else the point's K.
fn planned_k(p: &SifPoint) -> [f64; 3] {
    let k = [p.k1, p.k2, p.k3];
    p.cycle.map_or(k, |c| ranges(k, [c.k1, c.k2, c.k3]))
}

/// One `crack_path.csv` row: front point `i` of crack `name` in entry `entry`, its advance
/// and kink angle (degrees) in the increment that led here, the cumulative cycles.
#[allow(clippy::too_many_arguments)]
fn path_row(csv: &mut String, entry: usize, name: &str, i: usize, f: &SifPoint, adv: f64, th: f64, cycles: f64) {
    let _ = writeln!(
        csv,
        "{entry},{name},{i},{},{},{},{},{},{},{},{adv},{th},{cycles},{}",
        f.x[0],
        f.x[1],
        f.x[2],
        f.k1,
        f.k2,
        f.k3,
        f.g,
        cycle_columns(f)
    );
}

/// The `K_I_min,K_II_min,K_III_min,dK_eq` fields of a `crack_path.csv` row (empty without
/// a cycle).
fn cycle_columns(p: &SifPoint) -> String {
    p.cycle.map_or_else(|| ",,,".to_string(), |c| format!("{},{},{},{}", c.k1, c.k2, c.k3, c.dk_eq))
}

/// In fatigue, the cycle of every front point of the entry just recorded (`cracks`): its K
/// at the minimum, the `solved` one (per crack, the same front points in the same order)
/// or R (f) × the maximum's ([`cycle_minimum`]), and the ΔK_eq of the effective ranges by
/// the criterion (unsmoothed).
fn set_cycle(
    prop: &Propagation,
    cracks: &mut [CrackInfo],
    solved: Option<&[Vec<SifPoint>]>,
    entry: usize,
) -> Result<(), SolveError> {
    let Some(f) = prop.fatigue else { return Ok(()) };
    for (k, info) in cracks.iter_mut().enumerate() {
        let mins = solved.map(|m| &m[k]);
        if let Some(m) = mins.filter(|m| m.len() != info.front.len()) {
            return Err(SolveError::Callback(format!(
                "step {entry}: crack '{}': the cycle's minimum has {} front points, its maximum {}",
                info.name,
                m.len(),
                info.front.len()
            )));
        }
        for (i, p) in info.front.iter_mut().enumerate() {
            let k_max = [p.k1, p.k2, p.k3];
            let k_min = mins.map_or_else(|| cycle_minimum(&f, k_max), |m| [m[i].k1, m[i].k2, m[i].k3]);
            let [d1, d2, d3] = ranges(k_max, k_min);
            let (_, dk_eq) = criteria::drive_3d(prop.criterion, d1, d2, d3);
            p.cycle = Some(CycleMinimum { k1: k_min[0], k2: k_min[1], k3: k_min[2], dk_eq });
        }
    }
    Ok(())
}

/// Writes the level sets of `entry`, solves its load steps and records the last one. The
/// contact points start from the `carried` statuses of the previous entry where the crack
/// did not change (the same points at the same places, [`CarriedStatuses`]), and `carried`
/// is replaced by this entry's converged statuses of its first load step, for the next.
#[allow(clippy::too_many_arguments)]
fn solve_entry(
    rec: &mut Recorder<'_>,
    model: &Model<'_>,
    contact: Option<&ContactSetup>,
    options: &SolveOptions,
    observer: &dyn SolveObserver,
    entry: usize,
    carried: &mut Option<CarriedStatuses>,
    prop: &Propagation,
) -> Result<SolveReport, SolveError> {
    let case = rec.case;
    if case.output.vtu {
        rec.levelset_file = format!("{}_levelsets_{entry:04}.vtu", case.name);
        rec.write_levelsets(model).map_err(SolveError::Callback)?;
    }
    // The case's steps; with the cycle's minimum solved, one more after them (its SIFs only).
    let minimum = solves_minimum(prop, contact);
    let n_steps = model.load_factors.len() - usize::from(minimum);
    let mut seen = 0;
    let mut captured = None;
    let mut minima: Option<Vec<Vec<SifPoint>>> = None;
    let report = statics::solve_load_steps_carrying(model, contact, options, carried.as_ref(), observer, &mut |s| {
        seen += 1;
        if seen == 1 {
            captured = contact.map(|c| CarriedStatuses::capture(&c.points, s.contact_state));
        }
        if seen == n_steps {
            rec.record(model, contact, s, Some(entry))
        } else if minimum && seen == n_steps + 1 {
            let clock = std::time::Instant::now();
            let fronts = case
                .cracks
                .iter()
                .enumerate()
                .map(|(k, c)| super::crack_front(model, contact, &s, k, &SifOptions { radius: c.sif_radius }))
                .collect();
            minima = Some(fronts);
            rec.sif_s += clock.elapsed().as_secs_f64();
            Ok(())
        } else {
            Ok(())
        }
    })?;
    *carried = captured;
    if minimum && minima.is_none() {
        return Err(SolveError::Callback(format!("step {entry}: the fatigue cycle's minimum was not solved")));
    }
    let step = rec.summary.steps.last_mut().expect("the entry was recorded");
    set_cycle(prop, &mut step.cracks, minima.as_deref(), entry)?;
    Ok(report)
}

/// One new segment of an increment: at end `end` of crack `crack`, from its tip to `to`.
struct NewSegment {
    crack: usize,
    end: usize,
    from: [f64; 3],
    to: [f64; 3],
}

/// The new segment of every advancing tip, or why the growth stops
/// here: a tip that would leave the body or come within one cell of its surface, or a
/// segment that would meet a crack (or another new segment) or end within one cell of it.
fn new_segments(
    case: &Case,
    body: &Body2d,
    curves: &[Option<GrowingCurve>],
    tips: &[Tip],
    plan: &[TipPlan],
    entry: usize,
) -> Result<Vec<NewSegment>, String> {
    let mut new_points: Vec<NewSegment> = vec![];
    for (t, p) in tips.iter().zip(plan) {
        if p.advance <= 0.0 {
            continue;
        }
        let (c, s) = (p.theta.cos(), p.theta.sin());
        let d = [c * t.e1[0] + s * t.e2[0], c * t.e1[1] + s * t.e2[1], 0.0];
        let from = curves[t.crack].as_ref().expect("a growing crack").end(t.end);
        let to = [from[0] + p.advance * d[0], from[1] + p.advance * d[1], 0.0];
        let name = &case.cracks[t.crack].name;
        if !body.contains_segment(from, to) || body.depth(to) < body.cell_size(to) {
            // Which boundary: the face groups of the edge nearest the point it would reach
            // (an inner boundary, a hole, is named as the outer edge is).
            let groups = body.nearest_boundary_groups(to);
            let quoted: Vec<String> = groups.iter().map(|g| format!("'{g}'")).collect();
            let at = if quoted.is_empty() { String::new() } else { format!(" (face group {})", quoted.join(", ")) };
            return Err(format!(
                "crack '{name}' reached the boundary at step {entry}: its tip at ({:.6}, {:.6}) would grow to ({:.6}, {:.6}), within one cell of the surface{at} or beyond it; growth stopped",
                from[0], from[1], to[0], to[1]
            ));
        }
        let clearance = body.cell_size(to);
        let other = curves.iter().enumerate().find_map(|(j, c)| {
            let c = c.as_ref()?;
            let meets = if j == t.crack {
                // Its own polyline, without the segment that ends at this tip.
                let n = c.points.len();
                let pts = if t.end == 0 { &c.points[1..] } else { &c.points[..n - 1] };
                pts.windows(2).any(|w| segments_meet(from, to, w[0], w[1]))
            } else {
                c.crosses(from, to) || c.distance(to) < clearance
            };
            meets.then_some(j)
        });
        let other = other.or_else(|| {
            new_points
                .iter()
                .find_map(|n| (segments_meet(from, to, n.from, n.to) || dist(to, n.to) < clearance).then_some(n.crack))
        });
        if let Some(j) = other {
            return Err(format!(
                "crack '{name}' would grow into crack '{}' at step {entry} (a junction, not supported): growth stopped",
                case.cracks[j].name
            ));
        }
        new_points.push(NewSegment { crack: t.crack, end: t.end, from, to });
    }
    Ok(new_points)
}

/// Draws `crack_path.png` and, in fatigue, `crack_cycles.png` at `entry`.
fn write_growth_plots(
    rec: &mut Recorder<'_>,
    outline: &[([f64; 3], [f64; 3])],
    initial: &[Option<Vec<[f64; 3]>>],
    curves: &[Option<GrowingCurve>],
    fatigue: bool,
    lengths: &[(f64, Vec<f64>)],
    entry: usize,
) -> Result<(), String> {
    let clock = std::time::Instant::now();
    let case = rec.case;
    let paths: Vec<CrackPath> = case
        .cracks
        .iter()
        .zip(initial.iter().zip(curves))
        .filter_map(|(c, (init, curve))| {
            let init = init.as_ref()?;
            let points = curve.as_ref().map_or_else(|| init.clone(), |g| g.points.clone());
            Some(CrackPath { name: c.name.clone(), initial: init.clone(), points, grows: curve.is_some() })
        })
        .collect();
    plots::crack_path(&rec.out_dir.join("crack_path.png"), outline, &paths, entry)?;
    if fatigue {
        let names: Vec<String> =
            case.cracks.iter().zip(curves).filter(|(_, g)| g.is_some()).map(|(c, _)| c.name.clone()).collect();
        plots::crack_cycles(&rec.out_dir.join("crack_cycles.png"), &names, lengths)?;
    }
    rec.output_s += clock.elapsed().as_secs_f64();
    Ok(())
}

fn dist(a: [f64; 3], b: [f64; 3]) -> f64 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
}

/// The report of the last entry with the timings of every entry summed.
fn add_timings(total: Option<SolveReport>, mut r: SolveReport) -> SolveReport {
    if let Some(t) = total {
        let (a, b) = (&mut r.timings, &t.timings);
        a.pattern += b.pattern;
        a.assembly += b.assembly;
        a.symbolic += b.symbolic;
        a.numeric += b.numeric;
        a.solve += b.solve;
        a.pairing += b.pairing;
    }
    r
}
