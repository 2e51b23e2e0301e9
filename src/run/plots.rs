//! The PNG plots written next to `summary.json` (`[output] plots = true`, the default),
//! drawn with `plotters` on its bitmap backend and a bundled font (no system fonts, no C
//! libraries):
//!
//! - `sif_<crack>.png`: K_I, K_II, K_III of the crack: along the front, one line per step
//!   (3D: against the angle about the front's centre for a closed front, the arc length
//!   otherwise), or against the load factor at each tip (2D);
//! - `contact_<crack>.png` (contact): the contact pressure −λ and the tangential slip along
//!   the crack, one line per step (2D), or their histograms at the last step (3D);
//! - `contact_convergence.png` (contact): the Newton correction against the iteration, one
//!   line per step;
//! - `energy.png` (dynamics): the energy history of `energy_history.csv` (kinetic, strain,
//!   external work, frictional dissipation, contact work and their total) against time;
//! - `crack_path.png` (crack growth, 2D): the body outline and each crack's path, equal
//!   axes ([`crack_path`], written by the growth loop at every entry);
//! - `crack_cycles.png` (fatigue growth): each growing crack's advance (the path length
//!   grown at its tips, summed) against the cumulative cycles ([`crack_cycles`], written by the growth loop).
//!
//! Entry points: [`write_plots`], [`crack_path`], [`crack_cycles`].

use crate::post::sif::SifPoint;
use crate::run::summary::{CrackInfo, EnergyInfo, Summary};
use crate::solve::observe::NewtonIteration;
use plotters::prelude::*;
use std::ops::Range;
use std::path::{Path, PathBuf};
use std::sync::Once;

/// DejaVu Sans cut down to the characters the plots use (`assets/fonts/README.md`).
const FONT: &[u8] = include_bytes!("../../assets/fonts/DejaVuSans-subset.ttf");

const SIZE: (u32, u32) = (1000, 900);

/// The contact values of one crack's points at one step.
#[derive(Debug, Clone, Default)]
pub struct ContactProfile {
    pub step: usize,
    /// The crack's name.
    pub crack: String,
    /// Position of each point along the crack (2D; empty in 3D).
    pub abscissa: Vec<f64>,
    /// Contact pressure −λ of each point (positive in compression).
    pub pressure: Vec<f64>,
    /// Tangential jump: signed along τ1 in 2D, its magnitude in 3D.
    pub slip: Vec<f64>,
}

/// What the plots are drawn from.
pub struct PlotData<'a> {
    pub summary: &'a Summary,
    /// Every contact Newton iteration of the run.
    pub newton: &'a [NewtonIteration],
    pub contact: &'a [ContactProfile],
    /// The energies of every time step of a dynamic run (empty in quasi-static runs).
    pub energy: &'a [EnergyInfo],
}

/// A crack name as a file name part.
pub fn file_part(name: &str) -> String {
    name.chars().map(|c| if c.is_ascii_alphanumeric() || c == '-' || c == '_' { c } else { '_' }).collect()
}

/// Writes the plots into `dir`; returns the files written.
pub fn write_plots(data: &PlotData<'_>, dir: &Path) -> Result<Vec<PathBuf>, String> {
    register_font();
    let s = data.summary;
    let mut written = vec![];
    let names: Vec<&str> =
        s.steps.first().map(|st| st.cracks.iter().map(|c| c.name.as_str()).collect()).unwrap_or_default();
    for (k, name) in names.iter().enumerate() {
        let per_step: Vec<(usize, f64, &CrackInfo)> =
            s.steps.iter().filter_map(|st| st.cracks.get(k).map(|c| (st.index, st.load_factor, c))).collect();
        if per_step.iter().all(|(_, _, c)| c.front.is_empty()) {
            continue;
        }
        let path = dir.join(format!("sif_{}.png", file_part(name)));
        let r = if s.dim == 3 { sif_along_front(&path, name, &per_step) } else { sif_at_tips(&path, name, &per_step) };
        r.map_err(|e| format!("{}: {e}", path.display()))?;
        written.push(path);
    }
    let mut cracks: Vec<&str> = data.contact.iter().map(|p| p.crack.as_str()).collect();
    cracks.dedup();
    for name in cracks {
        let profiles: Vec<&ContactProfile> = data.contact.iter().filter(|p| p.crack == name).collect();
        let path = dir.join(format!("contact_{}.png", file_part(name)));
        let r = if s.dim == 3 {
            contact_histograms(&path, name, &profiles)
        } else {
            contact_profiles(&path, name, &profiles)
        };
        r.map_err(|e| format!("{}: {e}", path.display()))?;
        written.push(path);
    }
    if !data.newton.is_empty() {
        let path = dir.join("contact_convergence.png");
        convergence(&path, data.newton).map_err(|e| format!("{}: {e}", path.display()))?;
        written.push(path);
    }
    if !data.energy.is_empty() {
        let path = dir.join("energy.png");
        energy_history(&path, data.energy).map_err(|e| format!("{}: {e}", path.display()))?;
        written.push(path);
    }
    Ok(written)
}

/// Registers the bundled font as "sans-serif" (once per process).
fn register_font() {
    static FONT_ONCE: Once = Once::new();
    FONT_ONCE.call_once(|| {
        // The bundled font is valid (a unit test draws with it).
        let _ = plotters::style::register_font("sans-serif", FontStyle::Normal, FONT);
    });
}

type Fallible = Result<(), Box<dyn std::error::Error>>;

/// The legend of every plot: a framed, half-transparent box of the series labels at `pos`.
fn legend<'a, DB: DrawingBackend + 'a, CT: CoordTranslate>(
    chart: &mut ChartContext<'a, DB, CT>,
    pos: SeriesLabelPosition,
) -> Fallible
where
    DB::ErrorType: 'static,
{
    chart
        .configure_series_labels()
        .position(pos)
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .label_font(("sans-serif", 13))
        .draw()?;
    Ok(())
}

/// One crack of `crack_path.png`.
#[derive(Debug, Clone)]
pub struct CrackPath {
    pub name: String,
    /// The initial crack: its polyline before any growth.
    pub initial: Vec<[f64; 3]>,
    /// The grown polyline: the initial one with one vertex per increment at each growing
    /// tip (the tip of every entry).
    pub points: Vec<[f64; 3]>,
    /// Whether the crack grows (`grow = false`: drawn grey).
    pub grows: bool,
}

/// The colours of the growing cracks' paths in `crack_path.png` and `crack_cycles.png`,
/// in crack order (repeated past the last).
pub const PATH_COLOURS: [RGBColor; 4] =
    [RGBColor(214, 39, 40), RGBColor(31, 119, 180), RGBColor(44, 160, 44), RGBColor(148, 103, 189)];

/// The grey of the body outline in `crack_path.png` and of the cracks that do not grow.
pub const OUTLINE_COLOUR: RGBColor = RGBColor(110, 110, 110);

/// The pixel size of `crack_path.png` for a body of extent `dx` × `dy`: the longer side
/// 1000 pixels, the shorter in proportion but at least 600 (equal axes: the data ranges
/// are widened to the plot's aspect).
pub fn crack_path_size(dx: f64, dy: f64) -> (u32, u32) {
    let short = |r: f64| ((1000.0 * r).round() as u32).clamp(600, 1000);
    if dy > dx {
        (short(dx / dy), 1000)
    } else {
        (1000, short(dy / dx.max(f64::MIN_POSITIVE)))
    }
}

/// `crack_path.png`: the body outline (its boundary edges) in grey, each crack's grown
/// path in its colour with a dot at the tip of every entry, the initial crack in thick
/// black on top; equal axes.
pub fn crack_path(
    path: &Path,
    outline: &[([f64; 3], [f64; 3])],
    cracks: &[CrackPath],
    entry: usize,
) -> Result<(), String> {
    register_font();
    draw_crack_path(path, outline, cracks, entry).map_err(|e| format!("{}: {e}", path.display()))
}

fn draw_crack_path(path: &Path, outline: &[([f64; 3], [f64; 3])], cracks: &[CrackPath], entry: usize) -> Fallible {
    // The body's box (the cracks' if no outline): a half-line crack's polyline starts
    // outside the body, so the paths are clipped to it.
    let all = || outline.iter().flat_map(|(a, b)| [*a, *b]);
    let all: Vec<[f64; 3]> = if outline.is_empty() {
        cracks.iter().flat_map(|c| c.points.iter().cloned()).collect()
    } else {
        all().collect()
    };
    let lo = [0, 1].map(|i| all.iter().map(|p| p[i]).fold(f64::INFINITY, f64::min));
    let hi = [0, 1].map(|i| all.iter().map(|p| p[i]).fold(f64::NEG_INFINITY, f64::max));
    let clip = |pts: &[[f64; 3]]| -> Vec<Vec<(f64, f64)>> { clip_polyline(pts, lo, hi) };
    let (mut xr, mut yr) = (range(all.iter().map(|p| p[0])), range(all.iter().map(|p| p[1])));
    let size = crack_path_size(xr.end - xr.start, yr.end - yr.start);
    let root = BitMapBackend::new(path, size).into_drawing_area();
    root.fill(&WHITE)?;
    let root = root.titled(&format!("crack path after {entry} growth increments"), ("sans-serif", 22))?;
    let (margin, x_label, y_label) = (12u32, 40u32, 70u32);
    // Equal axes: widen the range whose units per pixel are fewer.
    let (w, h) = root.dim_in_pixel();
    let pw = w.saturating_sub(2 * margin + y_label).max(1) as f64;
    let ph = h.saturating_sub(2 * margin + x_label).max(1) as f64;
    let per_px = ((xr.end - xr.start) / pw).max((yr.end - yr.start) / ph);
    let widen = |r: Range<f64>, px: f64| {
        let (c, half) = (0.5 * (r.start + r.end), 0.5 * per_px * px);
        (c - half)..(c + half)
    };
    xr = widen(xr, pw);
    yr = widen(yr, ph);
    let mut chart = ChartBuilder::on(&root)
        .margin(margin)
        .x_label_area_size(x_label)
        .y_label_area_size(y_label)
        .build_cartesian_2d(xr.clone(), yr.clone())?;
    chart
        .configure_mesh()
        .disable_mesh()
        .x_desc("x")
        .y_desc("y")
        .x_label_formatter(&|v| tick(*v, &xr))
        .y_label_formatter(&|v| tick(*v, &yr))
        .label_style(("sans-serif", 14))
        .draw()?;
    chart.draw_series(
        outline.iter().map(|(a, b)| PathElement::new(vec![(a[0], a[1]), (b[0], b[1])], OUTLINE_COLOUR.stroke_width(2))),
    )?;
    let mut growing = 0;
    for c in cracks {
        let col = if c.grows {
            growing += 1;
            PATH_COLOURS[(growing - 1) % PATH_COLOURS.len()]
        } else {
            OUTLINE_COLOUR
        };
        let series =
            chart.draw_series(clip(&c.points).into_iter().map(|p| PathElement::new(p, col.stroke_width(3))))?;
        let label = if c.grows { format!("crack '{}'", c.name) } else { format!("crack '{}' (grow = false)", c.name) };
        series.label(label).legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], col.stroke_width(3)));
        let tips = c.points.iter().filter(|p| !c.initial.contains(p));
        chart.draw_series(tips.map(|p| Circle::new((p[0], p[1]), 4, col.filled())))?;
    }
    for (i, c) in cracks.iter().enumerate() {
        let series =
            chart.draw_series(clip(&c.initial).into_iter().map(|p| PathElement::new(p, BLACK.stroke_width(4))))?;
        if i == 0 {
            series
                .label("initial crack")
                .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], BLACK.stroke_width(4)));
        }
    }
    legend(&mut chart, SeriesLabelPosition::UpperRight)?;
    root.present()?;
    Ok(())
}

/// The pieces of a polyline inside the box `lo`–`hi` (each segment clipped by
/// Liang–Barsky; consecutive clipped segments joined).
fn clip_polyline(points: &[[f64; 3]], lo: [f64; 2], hi: [f64; 2]) -> Vec<Vec<(f64, f64)>> {
    let mut pieces: Vec<Vec<(f64, f64)>> = vec![];
    let mut open = false;
    for w in points.windows(2) {
        let (p, d) = ([w[0][0], w[0][1]], [w[1][0] - w[0][0], w[1][1] - w[0][1]]);
        let (mut t0, mut t1) = (0.0f64, 1.0f64);
        let mut inside = true;
        for i in 0..2 {
            for (q, r) in [(-d[i], p[i] - lo[i]), (d[i], hi[i] - p[i])] {
                if q == 0.0 {
                    inside &= r >= 0.0;
                } else if q < 0.0 {
                    t0 = t0.max(r / q);
                } else {
                    t1 = t1.min(r / q);
                }
            }
        }
        if !inside || t0 > t1 {
            open = false;
            continue;
        }
        let at = |t: f64| (p[0] + t * d[0], p[1] + t * d[1]);
        if !(open && t0 == 0.0) {
            pieces.push(vec![at(t0)]);
        }
        pieces.last_mut().expect("a piece").push(at(t1));
        open = t1 == 1.0;
    }
    pieces
}

/// `crack_cycles.png`: the advance of each growing crack (the path length grown at its
/// tips, summed) against the cumulative cycles, one point per entry. `names[k]` goes with `history[i].1[k]`.
pub fn crack_cycles(path: &Path, names: &[String], history: &[(f64, Vec<f64>)]) -> Result<(), String> {
    register_font();
    draw_crack_cycles(path, names, history).map_err(|e| format!("{}: {e}", path.display()))
}

fn draw_crack_cycles(path: &Path, names: &[String], history: &[(f64, Vec<f64>)]) -> Fallible {
    let root = BitMapBackend::new(path, (SIZE.0, SIZE.1 * 2 / 3)).into_drawing_area();
    root.fill(&WHITE)?;
    let root = root.titled("fatigue: crack advance against cycles", ("sans-serif", 22))?;
    let xr = range(history.iter().map(|h| h.0).chain([0.0]));
    let yr = range(history.iter().flat_map(|h| h.1.iter().cloned()));
    let mut chart = ChartBuilder::on(&root)
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(90)
        .build_cartesian_2d(xr.clone(), yr.clone())?;
    chart
        .configure_mesh()
        .x_desc("cycles N")
        .y_desc("crack advance along the path (tips summed)")
        .x_label_formatter(&|v| tick(*v, &xr))
        .y_label_formatter(&|v| tick(*v, &yr))
        .label_style(("sans-serif", 14))
        .draw()?;
    for (k, name) in names.iter().enumerate() {
        let col = PATH_COLOURS[k % PATH_COLOURS.len()];
        let pts: Vec<(f64, f64)> = history.iter().filter_map(|h| h.1.get(k).map(|&l| (h.0, l))).collect();
        chart
            .draw_series(LineSeries::new(pts.clone(), col.stroke_width(2)))?
            .label(format!("crack '{name}'"))
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], col.stroke_width(2)));
        chart.draw_series(pts.iter().map(|&p| Circle::new(p, 4, col.filled())))?;
    }
    legend(&mut chart, SeriesLabelPosition::UpperLeft)?;
    root.present()?;
    Ok(())
}

/// The colour of series `i` of `n` (blue for the first step to red for the last).
fn colour(i: usize, n: usize) -> RGBColor {
    let f = if n > 1 { i as f64 / (n - 1) as f64 } else { 1.0 };
    let hsl = HSLColor(0.66 * (1.0 - f), 0.85, 0.42);
    let (r, g, b) = hsl.rgb();
    RGBColor(r, g, b)
}

/// A tick label for an axis spanning `r`: plain decimals with as many digits as the
/// span needs, scientific notation for very small or large values.
fn tick(v: f64, r: &Range<f64>) -> String {
    let span = (r.end - r.start).abs();
    let big = r.start.abs().max(r.end.abs());
    if v == 0.0 {
        return "0".into();
    }
    if !(1e-3..1e5).contains(&big) {
        return format!("{v:.2e}");
    }
    let digits = (-(span / 10.0).log10().floor()).clamp(0.0, 6.0) as usize;
    let s = format!("{v:.digits$}");
    // A value that rounds to zero is "0", not "-0.0".
    if s.trim_start_matches('-').chars().all(|c| c == '0' || c == '.') {
        return "0".into();
    }
    s
}

/// A padded range around the values (never empty).
fn range(values: impl Iterator<Item = f64>) -> Range<f64> {
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for v in values.filter(|v| v.is_finite()) {
        lo = lo.min(v);
        hi = hi.max(v);
    }
    if !lo.is_finite() {
        return -1.0..1.0;
    }
    let pad = if hi > lo { 0.06 * (hi - lo) } else { 0.1 * lo.abs().max(hi.abs()).max(1e-30) };
    (lo - pad)..(hi + pad)
}

/// Which steps get a series: all of them up to 12, else 12 spread ones with the last.
fn shown(n: usize) -> Vec<usize> {
    if n <= 12 {
        return (0..n).collect();
    }
    let mut v: Vec<usize> = (0..12).map(|i| i * (n - 1) / 11).collect();
    v.dedup();
    v
}

/// The front's abscissa: the angle (degrees) about its centre for a closed front, the arc
/// length along it otherwise; with the axis name.
fn front_abscissa(front: &[SifPoint]) -> (Vec<f64>, &'static str) {
    let n = front.len();
    let dist =
        |a: [f64; 3], b: [f64; 3]| ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt();
    let mut c = [0.0; 3];
    for p in front {
        for i in 0..3 {
            c[i] += p.x[i] / n as f64;
        }
    }
    // Closed: the centre is far from every point compared with the spacing.
    let spacing =
        (0..n).map(|i| (0..n).filter(|&j| j != i).map(|j| dist(front[i].x, front[j].x)).fold(f64::INFINITY, f64::min));
    let h = spacing.fold(0.0, f64::max);
    let r_min = front.iter().map(|p| dist(p.x, c)).fold(f64::INFINITY, f64::min);
    if n >= 6 && r_min > 2.0 * h {
        // Normal of the crack plane: the mean e2; in-plane axes from the first point.
        let mut nrm = [0.0; 3];
        for p in front {
            for i in 0..3 {
                nrm[i] += p.e2[i];
            }
        }
        let unit = |v: [f64; 3]| {
            let l = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt().max(f64::MIN_POSITIVE);
            [v[0] / l, v[1] / l, v[2] / l]
        };
        let nrm = unit(nrm);
        // First in-plane axis: the projection of x on the plane; the plane's global
        // axis closest to x if possible.
        let pick = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]
            .into_iter()
            .min_by(|a, b| dot(*a, nrm).abs().total_cmp(&dot(*b, nrm).abs()))
            .expect("three axes");
        let a = unit(sub(pick, scale(nrm, dot(pick, nrm))));
        let b = cross(nrm, a);
        let theta = front
            .iter()
            .map(|p| {
                let d = sub(p.x, c);
                dot(d, b).atan2(dot(d, a)).to_degrees()
            })
            .collect();
        return (theta, "angle about the front's centre (degrees)");
    }
    // Open: arc length from the end farthest from the centre, along a nearest-neighbour chain.
    let start = (0..n).max_by(|&i, &j| dist(front[i].x, c).total_cmp(&dist(front[j].x, c))).unwrap_or(0);
    let mut s = vec![0.0; n];
    let mut done = vec![false; n];
    let (mut cur, mut acc) = (start, 0.0);
    done[cur] = true;
    for _ in 1..n {
        let next = (0..n)
            .filter(|&j| !done[j])
            .min_by(|&i, &j| dist(front[cur].x, front[i].x).total_cmp(&dist(front[cur].x, front[j].x)))
            .expect("a point left");
        acc += dist(front[cur].x, front[next].x);
        s[next] = acc;
        done[next] = true;
        cur = next;
    }
    (s, "arc length along the front")
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
fn scale(a: [f64; 3], s: f64) -> [f64; 3] {
    [a[0] * s, a[1] * s, a[2] * s]
}
fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
}

const K_NAMES: [&str; 3] = ["K_I", "K_II", "K_III"];

fn k_of(p: &SifPoint, m: usize) -> f64 {
    [p.k1, p.k2, p.k3][m]
}

/// 3D: K along the front, one panel per mode, one line per step.
fn sif_along_front(path: &Path, name: &str, steps: &[(usize, f64, &CrackInfo)]) -> Fallible {
    let root = BitMapBackend::new(path, SIZE).into_drawing_area();
    root.fill(&WHITE)?;
    let root = root.titled(&format!("crack '{name}': stress intensity factors along the front"), ("sans-serif", 22))?;
    let panels = root.split_evenly((3, 1));
    let abscissae: Vec<(Vec<f64>, &str)> = steps.iter().map(|(_, _, c)| front_abscissa(&c.front)).collect();
    let xr = range(abscissae.iter().flat_map(|(s, _)| s.iter().cloned()));
    let xdesc = abscissae.first().map_or("", |a| a.1);
    let show = shown(steps.len());
    for (m, panel) in panels.iter().enumerate() {
        let yr = range(steps.iter().flat_map(|(_, _, c)| c.front.iter().map(move |p| k_of(p, m))));
        let mut chart = ChartBuilder::on(panel)
            .margin(8)
            .x_label_area_size(40)
            .y_label_area_size(80)
            .build_cartesian_2d(xr.clone(), yr)?;
        let yr = chart.y_range();
        chart
            .configure_mesh()
            .x_desc(xdesc)
            .y_desc(K_NAMES[m])
            .y_label_formatter(&|v| tick(*v, &yr))
            .label_style(("sans-serif", 14))
            .draw()?;
        for (i, &si) in show.iter().enumerate() {
            let (step, _, c) = steps[si];
            let mut pts: Vec<(f64, f64)> =
                abscissae[si].0.iter().zip(&c.front).map(|(&s, p)| (s, k_of(p, m))).collect();
            pts.sort_by(|a, b| a.0.total_cmp(&b.0));
            let col = colour(i, show.len());
            chart
                .draw_series(LineSeries::new(pts.clone(), col.stroke_width(2)))?
                .label(format!("step {step}"))
                .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], col.stroke_width(2)));
            chart.draw_series(pts.iter().map(|&p| Circle::new(p, 2, col.filled())))?;
        }
        if m == 0 {
            legend(&mut chart, SeriesLabelPosition::MiddleRight)?;
        }
    }
    root.present()?;
    Ok(())
}

/// 2D: K_I and K_II at each tip against the load factor.
fn sif_at_tips(path: &Path, name: &str, steps: &[(usize, f64, &CrackInfo)]) -> Fallible {
    let root = BitMapBackend::new(path, (SIZE.0, SIZE.1 * 2 / 3)).into_drawing_area();
    root.fill(&WHITE)?;
    let root = root.titled(&format!("crack '{name}': stress intensity factors at the tips"), ("sans-serif", 22))?;
    let panels = root.split_evenly((2, 1));
    let n_tips = steps.iter().map(|(_, _, c)| c.front.len()).max().unwrap_or(0);
    let xr = range(steps.iter().map(|s| s.1).chain([0.0]));
    for (m, panel) in panels.iter().enumerate() {
        let yr = range(steps.iter().flat_map(|(_, _, c)| c.front.iter().map(move |p| k_of(p, m))).chain([0.0]));
        let mut chart = ChartBuilder::on(panel)
            .margin(8)
            .x_label_area_size(40)
            .y_label_area_size(80)
            .build_cartesian_2d(xr.clone(), yr)?;
        let yr = chart.y_range();
        chart
            .configure_mesh()
            .x_desc("load factor")
            .y_desc(K_NAMES[m])
            .y_label_formatter(&|v| tick(*v, &yr))
            .label_style(("sans-serif", 14))
            .draw()?;
        for tip in 0..n_tips {
            let pts: Vec<(f64, f64)> =
                steps.iter().filter_map(|(_, t, c)| c.front.get(tip).map(|p| (*t, k_of(p, m)))).collect();
            let col = colour(tip, n_tips);
            let at = steps.last().and_then(|(_, _, c)| c.front.get(tip)).map(|p| p.x).unwrap_or([0.0; 3]);
            chart
                .draw_series(LineSeries::new(pts.clone(), col.stroke_width(2)))?
                .label(format!("tip {} ({:.3}, {:.3})", tip + 1, at[0], at[1]))
                .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], col.stroke_width(2)));
            chart.draw_series(pts.iter().map(|&p| Circle::new(p, 4, col.filled())))?;
        }
        legend(&mut chart, SeriesLabelPosition::MiddleRight)?;
    }
    root.present()?;
    Ok(())
}

/// 2D: pressure and slip along the crack, one line per step.
fn contact_profiles(path: &Path, name: &str, profiles: &[&ContactProfile]) -> Fallible {
    let root = BitMapBackend::new(path, (SIZE.0, SIZE.1 * 2 / 3)).into_drawing_area();
    root.fill(&WHITE)?;
    let root = root.titled(&format!("crack '{name}': contact along the crack"), ("sans-serif", 22))?;
    let panels = root.split_evenly((2, 1));
    let xr = range(profiles.iter().flat_map(|p| p.abscissa.iter().cloned()));
    let show = shown(profiles.len());
    for (m, panel) in panels.iter().enumerate() {
        let value = |p: &ContactProfile| if m == 0 { p.pressure.clone() } else { p.slip.clone() };
        let yr = range(profiles.iter().flat_map(|p| value(p)).chain([0.0]));
        let mut chart = ChartBuilder::on(panel)
            .margin(8)
            .x_label_area_size(40)
            .y_label_area_size(80)
            .build_cartesian_2d(xr.clone(), yr)?;
        let ydesc = if m == 0 { "contact pressure −λ" } else { "tangential slip ⟦u⟧·τ" };
        let yr = chart.y_range();
        chart
            .configure_mesh()
            .x_desc("position along the crack")
            .y_desc(ydesc)
            .y_label_formatter(&|v| tick(*v, &yr))
            .label_style(("sans-serif", 14))
            .draw()?;
        for (i, &si) in show.iter().enumerate() {
            let p = profiles[si];
            let mut pts: Vec<(f64, f64)> = p.abscissa.iter().cloned().zip(value(p)).collect();
            pts.sort_by(|a, b| a.0.total_cmp(&b.0));
            let col = colour(i, show.len());
            chart
                .draw_series(LineSeries::new(pts, col.stroke_width(2)))?
                .label(format!("step {}", p.step))
                .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], col.stroke_width(2)));
        }
        if m == 0 {
            legend(&mut chart, SeriesLabelPosition::MiddleRight)?;
        }
    }
    root.present()?;
    Ok(())
}

/// 3D: histograms of the pressure and the slip magnitude at the last step.
fn contact_histograms(path: &Path, name: &str, profiles: &[&ContactProfile]) -> Fallible {
    let Some(last) = profiles.last() else { return Ok(()) };
    let root = BitMapBackend::new(path, (SIZE.0, SIZE.1 * 2 / 3)).into_drawing_area();
    root.fill(&WHITE)?;
    let title = format!("crack '{name}': contact at step {} ({} points)", last.step, last.pressure.len());
    let root = root.titled(&title, ("sans-serif", 22))?;
    let panels = root.split_evenly((1, 2));
    for (m, panel) in panels.iter().enumerate() {
        let values = if m == 0 { &last.pressure } else { &last.slip };
        let xr = range(values.iter().cloned());
        let bins = 30;
        let w = (xr.end - xr.start) / bins as f64;
        let mut counts = vec![0usize; bins];
        for v in values.iter().filter(|v| v.is_finite()) {
            counts[(((v - xr.start) / w) as usize).min(bins - 1)] += 1;
        }
        let top = counts.iter().cloned().max().unwrap_or(1).max(1) as f64 * 1.08;
        let mut chart = ChartBuilder::on(panel)
            .margin(10)
            .x_label_area_size(40)
            .y_label_area_size(60)
            .build_cartesian_2d(xr.clone(), 0.0..top)?;
        let xdesc = if m == 0 { "contact pressure −λ" } else { "slip |⟦u⟧_τ|" };
        chart
            .configure_mesh()
            .x_desc(xdesc)
            .y_desc("contact points")
            .x_labels(6)
            .label_style(("sans-serif", 14))
            .draw()?;
        let col = if m == 0 { RGBColor(30, 90, 180) } else { RGBColor(200, 80, 30) };
        chart.draw_series(counts.iter().enumerate().map(|(i, &c)| {
            let x0 = xr.start + i as f64 * w;
            Rectangle::new([(x0, 0.0), (x0 + w, c as f64)], col.filled())
        }))?;
    }
    root.present()?;
    Ok(())
}

/// The Newton corrections of each step against the iteration.
fn convergence(path: &Path, newton: &[NewtonIteration]) -> Fallible {
    let root = BitMapBackend::new(path, (SIZE.0, SIZE.1 * 2 / 3)).into_drawing_area();
    root.fill(&WHITE)?;
    let root = root.titled("contact loops: Newton correction per iteration", ("sans-serif", 22))?;
    let mut steps: Vec<usize> = newton.iter().map(|n| n.step).collect();
    steps.dedup();
    let floor = 1e-16;
    let corr = |n: &NewtonIteration| if n.correction.is_finite() { n.correction.max(floor) } else { 1.0 };
    let lo = newton.iter().map(corr).fold(f64::INFINITY, f64::min);
    let hi = newton.iter().map(corr).fold(0.0, f64::max);
    let max_it = newton.iter().map(|n| n.newton).max().unwrap_or(1) as f64;
    let mut chart = ChartBuilder::on(&root)
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(80)
        .build_cartesian_2d(0.5..max_it + 0.5, (lo / 3.0..hi * 3.0).log_scale())?;
    chart
        .configure_mesh()
        .x_desc("Newton iteration of the step")
        .y_desc("relative correction")
        .x_labels(max_it as usize + 2)
        .x_label_formatter(&|v| {
            if (v - v.round()).abs() < 1e-9 && *v >= 1.0 {
                format!("{v:.0}")
            } else {
                String::new()
            }
        })
        .y_label_formatter(&|v| format!("{v:.0e}"))
        .label_style(("sans-serif", 14))
        .draw()?;
    let show = shown(steps.len());
    for (i, &si) in show.iter().enumerate() {
        let step = steps[si];
        let pts: Vec<(f64, f64)> =
            newton.iter().filter(|n| n.step == step).map(|n| (n.newton as f64, corr(n))).collect();
        let col = colour(i, show.len());
        chart
            .draw_series(LineSeries::new(pts.clone(), col.stroke_width(2)))?
            .label(format!("step {step}"))
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], col.stroke_width(2)));
        chart.draw_series(pts.iter().map(|&p| Circle::new(p, 3, col.filled())))?;
    }
    legend(&mut chart, SeriesLabelPosition::MiddleRight)?;
    root.present()?;
    Ok(())
}

/// The energy history of a dynamic run: every column of `energy_history.csv` against time
/// (the total thick and black: flat for a conserving scheme).
fn energy_history(path: &Path, rows: &[EnergyInfo]) -> Fallible {
    let root = BitMapBackend::new(path, (SIZE.0, SIZE.1 * 2 / 3)).into_drawing_area();
    root.fill(&WHITE)?;
    let root = root.titled("energy history", ("sans-serif", 22))?;
    type Column = fn(&EnergyInfo) -> f64;
    let series: [(&str, Column, RGBColor); 6] = [
        ("kinetic", |e| e.kinetic, RGBColor(31, 119, 180)),
        ("strain", |e| e.strain, RGBColor(255, 127, 14)),
        ("external work", |e| e.external_work, RGBColor(44, 160, 44)),
        ("frictional dissipation", |e| e.frictional_dissipation, RGBColor(214, 39, 40)),
        ("contact work", |e| e.contact_work, RGBColor(148, 103, 189)),
        ("total", |e| e.total, BLACK),
    ];
    let xr = range(rows.iter().map(|e| e.time));
    let yr = range(rows.iter().flat_map(|e| series.iter().map(move |(_, f, _)| f(e))).chain([0.0]));
    let mut chart = ChartBuilder::on(&root)
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(90)
        .build_cartesian_2d(xr.clone(), yr)?;
    let yr = chart.y_range();
    chart
        .configure_mesh()
        .x_desc("time")
        .y_desc("energy")
        .x_label_formatter(&|v| tick(*v, &xr))
        .y_label_formatter(&|v| tick(*v, &yr))
        .label_style(("sans-serif", 14))
        .draw()?;
    for (name, f, col) in series {
        let width = if name == "total" { 3 } else { 2 };
        let pts: Vec<(f64, f64)> = rows.iter().map(|e| (e.time, f(e))).collect();
        chart
            .draw_series(LineSeries::new(pts, col.stroke_width(width)))?
            .label(name)
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], col.stroke_width(width)));
    }
    legend(&mut chart, SeriesLabelPosition::MiddleRight)?;
    root.present()?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tick_labels_are_distinct_on_small_ranges() {
        let r = -4.6e-5..6.9e-5;
        assert_eq!(tick(5e-5, &r), "5.00e-5");
        let r = -0.3..0.0;
        assert_ne!(tick(-0.05, &r), tick(-0.1, &r));
        assert_eq!(tick(-0.05, &r), "-0.05");
    }

    #[test]
    fn polylines_are_clipped_to_the_box() {
        let p = |x: f64, y: f64| [x, y, 0.0];
        // From outside on the left, in, then out at the top and back in.
        let pieces = clip_polyline(&[p(-2.0, 0.5), p(0.5, 0.5), p(0.5, 2.0), p(0.8, 0.5)], [0.0, 0.0], [1.0, 1.0]);
        assert_eq!(pieces.len(), 2, "{pieces:?}");
        assert_eq!(pieces[0], vec![(0.0, 0.5), (0.5, 0.5), (0.5, 1.0)]);
        let end = pieces[1][1];
        assert!((pieces[1][0].0 - 0.7).abs() < 1e-12 && pieces[1][0].1 == 1.0 && end == (0.8, 0.5), "{pieces:?}");
        assert!(clip_polyline(&[p(2.0, 2.0), p(3.0, 2.0)], [0.0, 0.0], [1.0, 1.0]).is_empty());
        assert_eq!(tick(-1e-17, &(-1.0..1.0)), "0");
    }

    #[test]
    fn the_bundled_font_loads() {
        assert!(ab_glyph_font_ok(FONT));
    }

    fn ab_glyph_font_ok(bytes: &'static [u8]) -> bool {
        plotters::style::register_font("fissure-test", FontStyle::Normal, bytes).is_ok()
    }

    #[test]
    fn a_closed_front_is_plotted_against_its_angle_and_an_open_one_against_its_length() {
        let p = |x: [f64; 3]| SifPoint {
            x,
            e1: [0.0; 3],
            e2: [0.0, 0.0, 1.0],
            e3: [0.0; 3],
            k1: 0.0,
            k2: 0.0,
            k3: 0.0,
            g: 0.0,
            cycle: None,
        };
        let circle: Vec<SifPoint> =
            (0..16).map(|i| (i as f64 * 22.5f64).to_radians()).map(|a| p([2.0 + a.cos(), a.sin(), 0.5])).collect();
        let (s, what) = front_abscissa(&circle);
        assert!(what.starts_with("angle"), "{what}");
        assert!((s[4] - 90.0).abs() < 1e-9 && (s[8].abs() - 180.0).abs() < 1e-9, "{s:?}");
        let line: Vec<SifPoint> = [0.3, 0.0, 0.2, 0.05].iter().map(|&y| p([1.0, y, 0.0])).collect();
        let (s, what) = front_abscissa(&line);
        assert!(what.starts_with("arc length"), "{what}");
        let expect = [0.0, 0.3, 0.1, 0.25];
        assert!(s.iter().zip(expect).all(|(a, b)| (a - b).abs() < 1e-12), "{s:?}");
    }
}
