//! Stress intensity factors by the interaction integral (domain form) with Williams
//! auxiliary fields, including the crack-face traction term.
//!
//! Entry point: [`crack_sifs`].
//!
//! The volume integrals of all the front points are computed in one pass over the cells:
//! each cell's quadrature-point data (basis, ∇u, σ, frame, auxiliary fields) once, added
//! to every front point whose domain holds the cell (the integrand is linear in θ and
//! ∇θ). `sif/per_point_reference.rs` keeps the per-point path as a test-only reference.
//!
//! For a front point P with local frame (e1 ahead of the front, e2 normal to the crack,
//! e3 along the front; see `docs/conventions.md`):
//!
//! ```text
//! I = ∫_V (σ_ij u^aux_i,1 + σ^aux_ij u_i,1 − σ_ik ε^aux_ik δ_1j) q_,j dV  −  ∫_faces t_i u^aux_i,1 q dS
//!     − ∫_Γ (σ_ij u^aux_i,1 + σ^aux_ij u_i,1 − σ_ik ε^aux_ik δ_1j) m_j q dS
//! K_I  = E* I(mode I aux) / (2 L_q),  K_II = E* I(mode II aux) / (2 L_q),  K_III = μ I(mode III aux) / L_q
//! ```
//! with all components in the local frame, E* = E/(1 − ν²) in plane strain and 3D, E in
//! plane stress; L_q = 1 in 2D and L_q = ∫_front q ds in 3D. The weight q is 1 at nodes
//! within the domain radius of P (3D: of the front, times a hat of the same half-width
//! along the front around P) and 0 elsewhere, interpolated by the shape functions.
//! The polar coordinates (r, θ) at each integration point come from the level sets:
//! r = √(φn² + φt²), θ = atan2(φn, φt). The local frame: in 2D, e1 ∥ ∇φt and
//! e2 = e3 × e1 with e3 = +z (so K_II has the same sign at both tips of a straight crack);
//! in 3D, the nodal frame of `nodal_directions` (e1 ∥ ∇φt projected normal to e2 ∥ ∇φn,
//! averaged around each node) interpolated to the point, e3 = e1 × e2.
//!
//! Curved 3D fronts. The auxiliary fields are the plane-strain Williams fields written in
//! that turning frame, u^aux = Σ_m u'_m(r, θ) e_m(x), with σ^aux and ε^aux the 2D
//! (plane-strain) fields in the frame. These neither balance nor derive from u^aux once the
//! frame turns, and the domain integral then needs the term ∫ P_kj,j θ_k dV
//! (Gosz, Dolbow & Moran 1998; Gosz & Moran 2002), which is added:
//!
//! ```text
//! P_kj,j θ_k = σ_ij θ_k ∂_k(sym ∇u^aux − ε^aux)_ij + (div σ^aux)_i u_i,k θ_k
//! sym ∇u^aux − ε^aux = Σ_m u'_m sym ∇e_m,   div σ^aux = σ'_ab [(∇e_a) e_b + e_a div e_b]
//! ```
//! with ∇e_m from the interpolated nodal frame and, in the first term, the derivative of
//! ∇e_m along θ taken as −(div e1)(θ·e1)∇e_m (exact for a planar crack with a curved front,
//! where ∇e_m ∝ κ/(1 + κ x1); an approximation on non-planar cracks). The energy term uses
//! W = σ : ε^aux and P_kj = σ_ij u^aux_i,k + σ^aux_ij u_i,k − W δ_kj with the full
//! ∇u^aux (frame rotation included). On the penny crack under shear
//! (`tests/fracture_sifs_3d.rs`, a = 1, front cells 0.09) the mean errors against Kassir &
//! Sih went from −6.7% / −22.6% (K_II) and −14.5% / −36.2% (|K_III|) at domain radius
//! 0.15 / 0.5 without these terms to −2.1% / −2.8% and −1.9% / −2.9% with them (within 3%
//! at 0.25 and 0.35 too); K_I under tension from −2.8% / −2.8% to −1.4% / −0.1%.
//! The face-traction term keeps the level-set frame and leaves out the rotation of e_m
//! (zero for a planar crack, where e_m does not change along e1).
//! The last term is over the part Γ of the body's outer boundary where q ≠ 0 (outward
//! normal m): the divergence theorem leaves it when a domain takes in the boundary (a
//! crack near a free edge, a radius larger than the ligament, a surface crack's front
//! meeting its face). σ m is the finite-element traction there (the load or the reaction
//! up to the discretisation: first-order accurate), so K no longer depends on whether the
//! domain stays inside the body. Before it was added, a centre crack at a/W = 0.9 gave K_I
//! 17%, 47% and 67% low with domains of 1.5, 3 and 6 times the ligament
//! (`fracture_sifs_2d.rs`). Boundary faces cut by the crack are integrated in two parts
//! at the crack in 2D, and by a degree-8 rule in 3D.
//!
//! Faces the front ends on (3D: faces whose normal m is within 45° of the front's tangent
//! e3, the faces of a slab a through crack crosses, the face a surface crack opens on).
//! With θ = q e1 ⊥ m the term is −∫ P_k3 θ_k m_3 dS, P_13 = σ_i3 u^aux_i,1 + σ^aux_i3 u_i,1
//! (W drops: θ·m = 0). The plane-strain auxiliary fields give, per mode:
//! - modes I, II (u^aux_3 = 0, σ^aux_α3 = 0, σ^aux_33 = ν(σ^aux_11 + σ^aux_22)):
//!   σ_13 u^aux_1,1 + σ_23 u^aux_2,1 + σ^aux_33 u_3,1;
//! - mode III (u^aux = u^aux_3 e3, σ^aux_α3 only): σ_33 u^aux_3,1 + σ^aux_13 u_1,1 + σ^aux_23 u_2,1.
//!
//! On a face held along its normal (u_3 prescribed, x and y free: σ_13 = σ_23 = 0,
//! u_3,1 = 0), the mode I/II integrand vanishes, while the mode III one does not: σ_33 =
//! ν(σ_11 + σ_22) ≠ 0 meets u^aux_3,1 ~ r^(−1/2), and σ^aux_α3 meets u_α,1. It is what
//! balances the volume part: in a plane-strain slab the fields do not vary along e3, the
//! volume integrand of mode III reduces to P_13 q ∂_3h (h the hat along the front), whose
//! integral through the thickness is ∫ P_13 q dA (h(top) − h(bottom)), the face terms'
//! opposite. Without them a front point whose domain reaches one face only got K_III =
//! ±0.15 (K_II = 0.40) in the held slab of `docs/reliability.md`; with one point at
//! mid-thickness the two faces cancel. So a face whose nodes all hold every component
//! along its normal keeps its term, for every mode (exact in the continuum; on a roller
//! face the mode I/II part is zero up to the finite-element σ_α3, on a clamped face it is
//! not), integrated on pieces split at the crack (φn = 0 where φt < 0, the displacement
//! jumps there) and collapsed with ρ = t² towards the point where the front meets the
//! face (the integrand behaves like 1/r there): `held_face_rule`.
//! On a traction-free face σ_i3 = 0 and the integrands are σ^aux_33 u_3,1 (I, II) and
//! σ^aux_α3 u_α,1 (III). The mode I/II term reads the face's Poisson displacement u_3 right
//! where the front meets the free surface, whose 3D corner singularity (K → 0 there for
//! ν > 0) the plane-strain auxiliary fields and the √r enrichment do not describe: it is
//! left out (before the held faces' enriched unknowns were held, `physics::held_faces`,
//! the held slab of `fracture_sifs_3d.rs` got K_II = 0.7% of K_I with it). The mode III
//! term is kept, on the same split and graded pieces as a held face: the divergence of
//! σ^aux_i3 u_i,1 q over the domain leaves exactly it on the face, so without it the
//! domain integral of K_III reads a rigid rotation of the body (u_α,1 ≠ 0) as a mode III
//! (an edge through crack at ν = 0 got K_III = ±0.18 = 11% of K_I with one set of
//! supports and ±0.005 with another; 4e-5 with the term,
//! `through_crack_k3_is_zero_whatever_rigid_rotation_the_supports_allow`). The front
//! points whose domains reach a free face are the ones `growth::surface` does not trust.
//! The face term takes the traction on the + lip (the − lip carries the opposite):
//! a pressure p gives t⁺ = p n; contact tractions enter the same way. Its integrand
//! behaves like 1/√r near the front: facets touching the front take a rule graded towards
//! it, and in 2D so do the segments that start within twice their length of a front point
//! (a front just short of a mesh edge; with a plain Gauss rule there the closed interior
//! crack of `tests/contact_friction_cracks.rs` gave K_I = 2.4e-3 σ√(πa) at one tip of
//! the 161 mesh instead of < 1e-4).
//! G = (K_I² + K_II²)/E* + K_III² (1 + ν)/E.

use crate::cut::{facet_quadrature, CellStatus};
use crate::element::{self, MAX_NODES};
use crate::enrich::basis::{field_at, CellBasis, Evaluator};
use crate::geometry::vec3::{cross, dot, unit};
use crate::physics::material::{Analysis, Isotropic};
use crate::physics::model::Model;
use crate::physics::xfem::cell_points;
use rayon::prelude::*;
use std::f64::consts::PI;

#[cfg(test)]
mod per_point_reference;

/// Stress intensity factors at one front point.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct SifPoint {
    pub x: [f64; 3],
    /// Propagation direction (in the crack surface, normal to the front).
    pub e1: [f64; 3],
    /// Crack normal side of the frame.
    pub e2: [f64; 3],
    /// Front tangent.
    pub e3: [f64; 3],
    #[serde(rename = "KI")]
    pub k1: f64,
    #[serde(rename = "KII")]
    pub k2: f64,
    #[serde(rename = "KIII")]
    pub k3: f64,
    #[serde(rename = "G")]
    pub g: f64,
    /// Fatigue growth: the K at the load cycle's minimum and the cycle's ΔK_eq here
    /// (`KI_min`, `KII_min`, `KIII_min`, `dK_eq` beside the others; absent otherwise).
    #[serde(flatten)]
    pub cycle: Option<CycleMinimum>,
}

/// The K at the minimum of a fatigue load cycle at a front point (the point's own K are
/// the maximum's) and the ΔK_eq of the cycle's effective ranges (`growth::fatigue`).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct CycleMinimum {
    #[serde(rename = "KI_min")]
    pub k1: f64,
    #[serde(rename = "KII_min")]
    pub k2: f64,
    #[serde(rename = "KIII_min")]
    pub k3: f64,
    #[serde(rename = "dK_eq")]
    pub dk_eq: f64,
}

/// Options of the SIF computation.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct SifOptions {
    /// Domain radius (default: three times the mean edge length of the front cells).
    pub radius: Option<f64>,
}

/// Traction on the + lip of a crack facet at a point (the − lip carries the opposite).
pub type FaceTraction<'a> = dyn Fn(usize, [f64; 3]) -> [f64; 3] + Sync + 'a;

/// Auxiliary (Williams) fields of one mode at local polar coordinates (r, θ):
/// displacement gradient ∂u_i/∂x'_j and stress σ_ij, in the local frame.
struct Aux {
    disp: [f64; 3],
    grad: [[f64; 3]; 3],
    stress: [[f64; 3]; 3],
}

/// The trigonometry of the auxiliary fields at polar coordinates (r, θ), shared by the
/// modes: √r, sin and cos of θ/2, θ and 3θ/2.
#[derive(Debug, Clone, Copy)]
struct Polar {
    r: f64,
    sr: f64,
    s: f64,
    c: f64,
    st: f64,
    ct: f64,
    s3: f64,
    c3: f64,
}

impl Polar {
    fn new(r: f64, th: f64) -> Self {
        let (s, c) = (0.5 * th).sin_cos();
        let (st, ct) = th.sin_cos();
        let (s3, c3) = (1.5 * th).sin_cos();
        Polar { r, sr: r.sqrt(), s, c, st, ct, s3, c3 }
    }
}

/// Mode 0 = I, 1 = II, 2 = III (unit K). `kappa` is Kolosov's constant, `three_d` adds
/// the plane-strain σ33.
fn williams(mode: usize, r: f64, th: f64, mu: f64, kappa: f64, nu: f64, three_d: bool) -> Aux {
    williams_at(mode, &Polar::new(r, th), mu, kappa, nu, three_d)
}

/// [`williams`] at a point whose trigonometry is computed ([`Polar`]).
fn williams_at(mode: usize, p: &Polar, mu: f64, kappa: f64, nu: f64, three_d: bool) -> Aux {
    let Polar { r, sr, s, c, st, ct, s3, c3 } = *p;
    let a = 1.0 / (2.0 * mu * (2.0 * PI).sqrt());
    let fs = 1.0 / (2.0 * PI * r).sqrt();
    // u_i = √r g_i(θ): ∂u/∂r = g/(2√r), ∂u/∂θ = √r g'.
    let (g, dg): ([f64; 3], [f64; 3]) = match mode {
        0 => (
            [a * c * (kappa - ct), a * s * (kappa - ct), 0.0],
            [a * (-0.5 * s * (kappa - ct) + c * st), a * (0.5 * c * (kappa - ct) + s * st), 0.0],
        ),
        1 => (
            [a * s * (kappa + 2.0 + ct), -a * c * (kappa - 2.0 + ct), 0.0],
            [a * (0.5 * c * (kappa + 2.0 + ct) - s * st), a * (0.5 * s * (kappa - 2.0 + ct) + c * st), 0.0],
        ),
        _ => {
            let b = 2.0 / (mu * (2.0 * PI).sqrt());
            ([0.0, 0.0, b * s], [0.0, 0.0, 0.5 * b * c])
        }
    };
    let mut grad = [[0.0; 3]; 3];
    for i in 0..3 {
        let dr = g[i] / (2.0 * sr);
        let dt = sr * dg[i];
        grad[i][0] = ct * dr - st / r * dt;
        grad[i][1] = st * dr + ct / r * dt;
    }
    let mut stress = [[0.0; 3]; 3];
    match mode {
        0 => {
            stress[0][0] = fs * c * (1.0 - s * s3);
            stress[1][1] = fs * c * (1.0 + s * s3);
            stress[0][1] = fs * s * c * c3;
        }
        1 => {
            stress[0][0] = -fs * s * (2.0 + c * c3);
            stress[1][1] = fs * s * c * c3;
            stress[0][1] = fs * c * (1.0 - s * s3);
        }
        _ => {
            stress[0][2] = -fs * s;
            stress[1][2] = fs * c;
        }
    }
    stress[1][0] = stress[0][1];
    stress[2][0] = stress[0][2];
    stress[2][1] = stress[1][2];
    if three_d && mode < 2 {
        stress[2][2] = nu * (stress[0][0] + stress[1][1]);
    }
    Aux { disp: [sr * g[0], sr * g[1], sr * g[2]], grad, stress }
}

/// A front point with its frame (before the integral).
#[derive(Debug, Clone, Copy)]
struct FrontSample {
    x: [f64; 3],
    cell: usize,
    e3: [f64; 3],
}

/// Front points: the tips in 2D; in 3D points spread along the front polylines at a
/// spacing close to `spacing`.
fn front_samples(model: &Model<'_>, crack: usize, spacing: f64, size: f64) -> Vec<FrontSample> {
    let cut = &model.cracks[crack].cut;
    let mesh = model.mesh;
    let tol = 1e-9 * size;
    if mesh.dim == 2 {
        let mut out: Vec<FrontSample> = vec![];
        for p in &cut.front {
            if let Some(&x) = p.points.first() {
                if !out.iter().any(|s| (0..3).map(|i| (s.x[i] - x[i]).powi(2)).sum::<f64>().sqrt() < tol) {
                    out.push(FrontSample { x, cell: p.cell, e3: [0.0, 0.0, 1.0] });
                }
            }
        }
        return out;
    }
    // 3D: chain the front segments into polylines.
    let mut pts: Vec<[f64; 3]> = vec![];
    let id = |x: [f64; 3], pts: &mut Vec<[f64; 3]>| -> usize {
        if let Some(i) = pts.iter().position(|p| (0..3).map(|k| (p[k] - x[k]).powi(2)).sum::<f64>().sqrt() < tol) {
            i
        } else {
            pts.push(x);
            pts.len() - 1
        }
    };
    let mut segs: Vec<(usize, usize, usize)> = vec![];
    for p in &cut.front {
        if p.points.len() == 2 {
            let (a, b) = (id(p.points[0], &mut pts), id(p.points[1], &mut pts));
            if a != b {
                segs.push((a, b, p.cell));
            }
        }
    }
    let mut adj: Vec<Vec<usize>> = vec![vec![]; pts.len()];
    for (k, s) in segs.iter().enumerate() {
        adj[s.0].push(k);
        adj[s.1].push(k);
    }
    let mut used = vec![false; segs.len()];
    let mut out = vec![];
    while let Some(start_seg) = (0..segs.len()).find(|&k| !used[k]) {
        // Walk back to an end (a point with one segment) or around a loop.
        let mut cur = segs[start_seg].0;
        let mut prev_seg = start_seg;
        for _ in 0..segs.len() {
            if adj[cur].len() != 2 {
                break;
            }
            let next = adj[cur].iter().copied().find(|&k| k != prev_seg && !used[k]);
            match next {
                Some(k) if k != start_seg => {
                    cur = if segs[k].0 == cur { segs[k].1 } else { segs[k].0 };
                    prev_seg = k;
                }
                _ => break,
            }
        }
        // Walk forward from `cur`, collecting the polyline.
        let mut chain: Vec<(usize, usize)> = vec![]; // (point, cell of the segment leaving it)
        let mut p = cur;
        while let Some(k) = adj[p].iter().copied().find(|&k| !used[k]) {
            used[k] = true;
            chain.push((p, segs[k].2));
            p = if segs[k].0 == p { segs[k].1 } else { segs[k].0 };
        }
        let last = p;
        if chain.is_empty() {
            continue;
        }
        let mut poly: Vec<[f64; 3]> = chain.iter().map(|c| pts[c.0]).collect();
        poly.push(pts[last]);
        let cells: Vec<usize> = chain.iter().map(|c| c.1).collect();
        let lens: Vec<f64> =
            poly.windows(2).map(|w| (0..3).map(|k| (w[1][k] - w[0][k]).powi(2)).sum::<f64>().sqrt()).collect();
        let total: f64 = lens.iter().sum();
        let n = ((total / spacing).round() as usize).max(1);
        for j in 0..n {
            let target = (j as f64 + 0.5) * total / n as f64;
            let mut acc = 0.0;
            for (k, &l) in lens.iter().enumerate() {
                if acc + l >= target || k + 1 == lens.len() {
                    let s = if l > 0.0 { ((target - acc) / l).clamp(0.0, 1.0) } else { 0.0 };
                    let (a, b) = (poly[k], poly[k + 1]);
                    let x = [a[0] + s * (b[0] - a[0]), a[1] + s * (b[1] - a[1]), a[2] + s * (b[2] - a[2])];
                    out.push(FrontSample { x, cell: cells[k], e3: unit([b[0] - a[0], b[1] - a[1], b[2] - a[2]]) });
                    break;
                }
                acc += l;
            }
        }
    }
    out
}

/// The domain radius of the interaction integral of crack `crack` and the mean edge length
/// of its front cells: `opts.radius`, or three times that length (0 without a front).
pub fn domain_radius(model: &Model<'_>, crack: usize, opts: &SifOptions) -> (f64, f64) {
    let mesh = model.mesh;
    let cut = &model.cracks[crack].cut;
    let front_cells: Vec<usize> =
        cut.cut_cells.iter().filter(|c| c.status == CellStatus::Front).map(|c| c.cell).collect();
    if front_cells.is_empty() {
        return (opts.radius.unwrap_or(0.0), 0.0);
    }
    let h = front_cells.iter().map(|&c| mesh.cell_edge_length(c)).sum::<f64>() / front_cells.len() as f64;
    (opts.radius.unwrap_or(3.0 * h), h)
}

/// Pairs (i, j) of the front points of crack `crack` whose SIF domains take in another
/// part of the front: point j lies across (not along) the front tangent at i, within the
/// distance where the weight q of point i is non-zero around another front: radius + h in
/// 2D (q = 1 in the disc of that radius), 3 × radius in 3D (nodes within the radius of any
/// front and within twice the radius of the point). Their K values mix both fronts (the
/// other tip of a short crack, the far side of a small penny, the opposite front of a
/// narrow through crack).
pub fn overlapping_domains(
    model: &Model<'_>,
    crack: usize,
    opts: &SifOptions,
    points: &[SifPoint],
) -> Vec<(usize, usize)> {
    let (radius, h) = domain_radius(model, crack, opts);
    let three_d = model.mesh.dim == 3;
    let reach = if three_d { 3.0 * radius } else { radius + h };
    let mut out = vec![];
    for (i, p) in points.iter().enumerate() {
        for (j, q) in points.iter().enumerate() {
            let d = [q.x[0] - p.x[0], q.x[1] - p.x[1], q.x[2] - p.x[2]];
            let dist = dot(d, d).sqrt();
            let across = !three_d || dot(d, p.e3).abs() < 0.5 * dist;
            if i != j && dist <= reach && across {
                out.push((i, j));
            }
        }
    }
    out
}

/// A part of the boundary that a SIF domain may take in.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LoadedBoundary {
    /// A node of a face carrying load `k` (index into [`Model::loads`]).
    Load(usize),
    /// A node with a prescribed displacement of `[[dirichlet]]` group `k` (index into
    /// [`Model::dirichlet_groups`]).
    Held(usize),
}

/// Where the interaction-integral domains of crack `crack`'s front points take in a
/// loaded or held part of the outer boundary: (the front point, the nearest such node's
/// position, its distance, what it is, the number of front points concerned), for the
/// nearest one; `None` if no domain does. The domain of a point reaches `radius + h`
/// (the weight q is 1 within the radius and falls to 0 over one cell); there the
/// integral's boundary term takes the load or the reaction from the finite-element
/// stress, which converges at first order only.
pub fn domains_on_loaded_boundary(
    model: &Model<'_>,
    crack: usize,
    opts: &SifOptions,
    points: &[SifPoint],
) -> Option<(usize, [f64; 3], f64, LoadedBoundary, usize)> {
    if points.is_empty() {
        return None;
    }
    let (radius, h) = domain_radius(model, crack, opts);
    let reach = radius + h;
    let mesh = model.mesh;
    let mut nodes: Vec<(usize, LoadedBoundary)> = vec![];
    for (f, face) in model.faces.iter().enumerate() {
        let k = model.face_load.get(f).copied().unwrap_or(u32::MAX) as usize;
        if k < model.loads.len() {
            nodes.extend(face.nodes.iter().filter(|&&n| n != usize::MAX).map(|&n| (n, LoadedBoundary::Load(k))));
        }
    }
    nodes.extend(model.dirichlet.iter().map(|d| (d.node, LoadedBoundary::Held(d.group as usize))));
    nodes.sort_unstable_by_key(|a| a.0);
    nodes.dedup_by_key(|a| a.0);
    let mut best: Option<(usize, [f64; 3], f64, LoadedBoundary)> = None;
    let mut count = 0;
    for (i, p) in points.iter().enumerate() {
        let mut hit = false;
        for &(n, what) in &nodes {
            let x = mesh.nodes[n];
            let d = [x[0] - p.x[0], x[1] - p.x[1], x[2] - p.x[2]];
            let dist = dot(d, d).sqrt();
            if dist < reach {
                hit = true;
                if best.is_none_or(|b| dist < b.2) {
                    best = Some((i, x, dist, what));
                }
            }
        }
        count += hit as usize;
    }
    best.map(|(i, x, d, w)| (i, x, d, w, count))
}

/// The front point of crack `crack` with the thinnest ligament, when it is under two
/// cells: the distance from the front point to the outer boundary measured along the
/// direction of growth `e1` (the ligament ahead of the front) and along `±e2` (the
/// material over and under a crack running near a face), as (the front point, the
/// boundary point reached, its distance, the number of front points under two cells).
/// The ligament is then not resolved by the mesh and K there is not reliable (a penny crack
/// tangent to a face gives a K that grows with the mesh). Faces beside or behind the front
/// are not a ligament: the face a surface crack breaks through, a cell or two from its
/// front points near it, is not reported here (the crack's depth is, [`shallow_crack`]).
/// The distances are exact along the rays, over the boundary faces within two cells.
pub fn fronts_near_the_boundary(
    model: &Model<'_>,
    crack: usize,
    opts: &SifOptions,
    points: &[SifPoint],
) -> Option<(usize, [f64; 3], f64, usize)> {
    let (_, h) = domain_radius(model, crack, opts);
    let hits = boundary_along(model, points, 2.0 * h, |p| vec![p.e1, p.e2, scale(p.e2, -1.0)]);
    let n = hits.iter().flatten().count();
    let (i, (d, y)) =
        hits.into_iter().enumerate().filter_map(|(i, h)| h.map(|h| (i, h))).min_by(|a, b| a.1 .0.total_cmp(&b.1 .0))?;
    Some((i, y, d, n))
}

/// Whether crack `crack` is shallower than two cells: the outer boundary behind its
/// front, along `−e1` (back across the crack: the depth of a surface crack below the face
/// it breaks through, the length of an edge crack), is within two cells of the front
/// point farthest from it, as (that front point, the boundary point reached, its distance,
/// the number of front points within two cells of it). The front points of a surface
/// crack near the face are near it behind them whatever the crack's depth, so only the
/// deepest point counts (the front points whose ray runs along the face, reaching no
/// boundary, do not count); an embedded crack's rays cross it and reach the far side. A
/// crack that shallow is not resolved by the mesh and its K is not reliable.
pub fn shallow_crack(
    model: &Model<'_>,
    crack: usize,
    opts: &SifOptions,
    points: &[SifPoint],
) -> Option<(usize, [f64; 3], f64, usize)> {
    let (_, h) = domain_radius(model, crack, opts);
    let behind = |p: &SifPoint| vec![scale(p.e1, -1.0)];
    // Cheap first: no front point within two cells of the boundary behind it.
    let near = boundary_along(model, points, 2.0 * h, behind).iter().flatten().count();
    if near == 0 {
        return None;
    }
    let (lo, hi) = model.mesh.bounding_box();
    let diagonal = ((hi[0] - lo[0]).powi(2) + (hi[1] - lo[1]).powi(2) + (hi[2] - lo[2]).powi(2)).sqrt();
    let hits = boundary_along(model, points, 1.01 * diagonal, behind);
    let (i, (d, y)) =
        hits.into_iter().enumerate().filter_map(|(i, h)| h.map(|h| (i, h))).max_by(|a, b| a.1 .0.total_cmp(&b.1 .0))?;
    (d < 2.0 * h).then_some((i, y, d, near))
}

fn scale(a: [f64; 3], s: f64) -> [f64; 3] {
    [s * a[0], s * a[1], s * a[2]]
}

/// For each front point, the nearest crossing of the outer boundary closer than `reach`
/// along its rays `dirs` (distance, point).
fn boundary_along(
    model: &Model<'_>,
    points: &[SifPoint],
    reach: f64,
    dirs: impl Fn(&SifPoint) -> Vec<[f64; 3]>,
) -> Vec<Option<(f64, [f64; 3])>> {
    if points.is_empty() || reach <= 0.0 {
        return vec![None; points.len()];
    }
    let mesh = model.mesh;
    let (near, lo, hi) = cells_near(model, points.iter().map(|p| p.x), reach);
    let faces = boundary_faces_near(model, &near, lo, hi);
    // The boundary as segments (2D) or triangles (3D; quads split in two).
    let mut pieces: Vec<[[f64; 3]; 3]> = vec![];
    for &(c, lf) in &faces {
        let cell = &mesh.cells[c];
        let (_, loc) = cell.kind.faces()[lf];
        let x: Vec<[f64; 3]> = loc.iter().map(|&a| mesh.nodes[cell.nodes[a]]).collect();
        match x.len() {
            2 => pieces.push([x[0], x[1], x[1]]),
            3 => pieces.push([x[0], x[1], x[2]]),
            _ => {
                pieces.push([x[0], x[1], x[2]]);
                pieces.push([x[0], x[2], x[3]]);
            }
        }
    }
    let two_d = mesh.dim == 2;
    // A front point on the boundary (a front touching a face) is at distance 0.
    let tol = 1e-9 * reach;
    points
        .iter()
        .map(|p| {
            let mut best: Option<(f64, [f64; 3])> = None;
            for d in dirs(p) {
                let t = pieces
                    .iter()
                    .filter_map(|f| if two_d { ray_segment(p.x, d, f[0], f[1]) } else { ray_triangle(p.x, d, f) })
                    .filter(|&t| t >= -tol && t < reach)
                    .fold(f64::INFINITY, f64::min);
                if t < reach && best.is_none_or(|b| t < b.0) {
                    let t = t.max(0.0);
                    best = Some((t, [p.x[0] + t * d[0], p.x[1] + t * d[1], p.x[2] + t * d[2]]));
                }
            }
            best
        })
        .collect()
}

/// The parameter `t` at which the ray `x + t d` (in the plane z = 0, `d` a unit vector)
/// crosses the segment `a b`, if it does.
fn ray_segment(x: [f64; 3], d: [f64; 3], a: [f64; 3], b: [f64; 3]) -> Option<f64> {
    let e = [b[0] - a[0], b[1] - a[1]];
    let det = d[0] * (-e[1]) - d[1] * (-e[0]);
    let scale = (e[0] * e[0] + e[1] * e[1]).sqrt();
    if det.abs() <= 1e-12 * scale {
        return None;
    }
    let r = [a[0] - x[0], a[1] - x[1]];
    let t = (r[0] * (-e[1]) - r[1] * (-e[0])) / det;
    let s = (d[0] * r[1] - d[1] * r[0]) / det;
    (-1e-9..=1.0 + 1e-9).contains(&s).then_some(t)
}

/// The parameter `t` at which the ray `x + t d` (`d` a unit vector) crosses the triangle
/// `f`, if it does (Möller–Trumbore).
fn ray_triangle(x: [f64; 3], d: [f64; 3], f: &[[f64; 3]; 3]) -> Option<f64> {
    let sub = |a: [f64; 3], b: [f64; 3]| [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
    let e1 = sub(f[1], f[0]);
    let e2 = sub(f[2], f[0]);
    let p = cross(d, e2);
    let det = dot(e1, p);
    let area = dot(cross(e1, e2), cross(e1, e2)).sqrt();
    if det.abs() <= 1e-12 * area {
        return None;
    }
    let s = sub(x, f[0]);
    let u = dot(s, p) / det;
    let q = cross(s, e1);
    let v = dot(d, q) / det;
    let eps = 1e-9;
    (u >= -eps && v >= -eps && u + v <= 1.0 + eps).then(|| dot(e2, q) / det)
}

/// Stress intensity factors along the front of crack `crack` for the dof vector `u`.
/// `traction` gives the traction on the + lip of loaded facets (pressure, contact).
pub fn crack_sifs(
    model: &Model<'_>,
    crack: usize,
    u: &[f64],
    traction: Option<&FaceTraction<'_>>,
    opts: &SifOptions,
) -> Vec<SifPoint> {
    with_front_context(model, crack, opts, |samples, ctx| {
        // The volume integrals in one pass over the cells: each cell's quadrature-point data
        // once, added to every front point whose domain holds it (each cell lies in about two).
        let domains: Vec<(f64, Vec<(usize, NodalQ)>)> =
            samples.par_iter().map(|s| domain_of(model, crack, s, ctx)).collect();
        let mut members: Vec<(usize, Member)> = domains
            .iter()
            .enumerate()
            .flat_map(|(i, d)| {
                let am = AuxMaterial::of(model, samples[i].cell);
                d.1.iter().map(move |&(c, q)| (c, (i, am, q)))
            })
            .collect();
        members.sort_by_key(|m| (m.0, m.1 .0));
        let cells: Vec<(usize, Vec<Member>)> =
            members.chunk_by(|a, b| a.0 == b.0).map(|g| (g[0].0, g.iter().map(|m| m.1).collect())).collect();
        drop(members);
        let parts: Vec<Vec<(usize, [f64; 3])>> =
            cells.par_iter().map(|(c, ms)| cell_volume_terms(model, crack, u, ctx, *c, ms)).collect();
        // Summed in cell order, whatever the threads: the result does not depend on them.
        let mut ints = vec![[0.0; 3]; samples.len()];
        for (i, v) in parts.into_iter().flatten() {
            for m in 0..3 {
                ints[i][m] += v[m];
            }
        }
        samples
            .par_iter()
            .enumerate()
            .map(|(i, s)| finish_point(model, crack, u, traction, s, ctx, ints[i], domains[i].0))
            .collect()
    })
}

/// Runs `f` on the front samples of crack `crack` and the context they share (domain
/// radius, level sets, nodal directions, the cells near the front and their boundary
/// faces); no front, no points.
fn with_front_context(
    model: &Model<'_>,
    crack: usize,
    opts: &SifOptions,
    f: impl FnOnce(&[FrontSample], &SifContext<'_>) -> Vec<SifPoint>,
) -> Vec<SifPoint> {
    let mesh = model.mesh;
    let cr = &model.cracks[crack];
    let Some(lst) = cr.levelsets.lst.as_ref() else { return vec![] };
    let lsn = &cr.levelsets.lsn;
    if !cr.cut.cut_cells.iter().any(|c| c.status == CellStatus::Front) {
        return vec![];
    }
    let (rd, h) = domain_radius(model, crack, opts);
    let size = mesh.typical_size();
    let samples = front_samples(model, crack, rd, size);
    let dirs = nodal_directions(model, crack, 2.0 * rd + 2.0 * h);
    // Cells that may reach a front point: a node within `reach` of the bounding box of
    // the points (each point then checks its own distance on these only).
    let reach = 2.0 * rd + size;
    let (near, lo, hi) = cells_near(model, samples.iter().map(|s| s.x), reach);
    let boundary = boundary_faces_near(model, &near, lo, hi);
    // The components each node holds (bit c: a `[[dirichlet]]` condition on component c).
    let mut held = vec![0u8; mesh.n_nodes()];
    for d in &model.dirichlet {
        held[d.node] |= 1 << d.component;
    }
    let ctx = SifContext { rd, reach, lsn, lst, dirs: &dirs, cells: &near, boundary: &boundary, held: &held };
    f(&samples, &ctx)
}

/// What every front point of a crack shares in [`sif_at`].
struct SifContext<'a> {
    /// Domain radius.
    rd: f64,
    /// Cells with a node farther than this from the point are skipped.
    reach: f64,
    lsn: &'a [f64],
    lst: &'a [f64],
    dirs: &'a [[[f64; 3]; 2]],
    /// The cells near the front (a superset of those any point needs).
    cells: &'a [usize],
    /// The faces of those cells on the outer boundary of the body: (cell, local face).
    boundary: &'a [(usize, usize)],
    /// Per node, the displacement components a Dirichlet condition holds (bit c).
    held: &'a [u8],
}

/// Propagation direction e1 at the nodes within `reach` of the front: the cell-averaged
/// level-set gradients around the node, e1 = ∇φt projected normal to ∇φn, normalised.
/// Nodes farther away get zero. The virtual crack extension θ = q e1 is interpolated from
/// these nodal values, so it is continuous (the G-θ method's requirement) and its gradient
/// carries the curvature of the front.
fn nodal_directions(model: &Model<'_>, crack: usize, reach: f64) -> Vec<[[f64; 3]; 2]> {
    let mesh = model.mesh;
    let cr = &model.cracks[crack];
    let (lsn, Some(lst)) = (&cr.levelsets.lsn, cr.levelsets.lst.as_ref()) else {
        return vec![[[0.0; 3]; 2]; mesh.n_nodes()];
    };
    let near: Vec<bool> = (0..mesh.n_nodes()).map(|a| (lsn[a] * lsn[a] + lst[a] * lst[a]).sqrt() <= reach).collect();
    let mut gn = vec![[0.0; 3]; mesh.n_nodes()];
    let mut gt = vec![[0.0; 3]; mesh.n_nodes()];
    let mut xs = [[0.0; 3]; MAX_NODES];
    let mut n = [0.0; MAX_NODES];
    let mut dn = [[0.0; 3]; MAX_NODES];
    let mut g = [[0.0; 3]; MAX_NODES];
    for (c, cell) in mesh.cells.iter().enumerate() {
        let v = cell.nodes();
        if !v.iter().any(|&a| near[a]) {
            continue;
        }
        let nn = mesh.cell_coords(c, &mut xs);
        element::shape(cell.kind, &cell.kind.reference_centroid(), &mut n, &mut dn);
        let Ok(det) = element::physical_gradients(mesh.dim, &xs[..nn], &dn[..nn], &mut g) else { continue };
        let w = det.abs() * cell.kind.reference_measure();
        let (mut cn, mut ct) = ([0.0; 3], [0.0; 3]);
        for a in 0..nn {
            for i in 0..3 {
                cn[i] += g[a][i] * lsn[v[a]];
                ct[i] += g[a][i] * lst[v[a]];
            }
        }
        for &a in v {
            for i in 0..3 {
                gn[a][i] += w * cn[i];
                gt[a][i] += w * ct[i];
            }
        }
    }
    (0..mesh.n_nodes())
        .map(|a| {
            if !near[a] {
                return [[0.0; 3]; 2];
            }
            let nrm = unit(gn[a]);
            let d = dot(gt[a], nrm);
            [unit([gt[a][0] - d * nrm[0], gt[a][1] - d * nrm[1], gt[a][2] - d * nrm[2]]), nrm]
        })
        .collect()
}

/// The constants of the auxiliary fields at a front point, from the material of its cell:
/// μ, ν, E, Kolosov's κ and E* (plane stress: E; plane strain and 3D: E/(1 − ν²)).
#[derive(Debug, Clone, Copy, PartialEq)]
struct AuxMaterial {
    mu: f64,
    nu: f64,
    e: f64,
    kappa: f64,
    e_star: f64,
}

impl AuxMaterial {
    fn of(model: &Model<'_>, cell: usize) -> Self {
        let mat: Isotropic = model.materials[model.cell_material[cell] as usize];
        let (mu, nu, e) = (mat.mu(), mat.poisson, mat.young);
        let (kappa, e_star) = match model.analysis {
            Analysis::PlaneStress => ((3.0 - nu) / (1.0 + nu), e),
            _ => (3.0 - 4.0 * nu, e / (1.0 - nu * nu)),
        };
        AuxMaterial { mu, nu, e, kappa, e_star }
    }
}

/// The weight q of front point `s` at node `n`.
fn q_node(model: &Model<'_>, ctx: &SifContext<'_>, s: &FrontSample, n: usize) -> f64 {
    let (rd, lsn, lst) = (ctx.rd, ctx.lsn, ctx.lst);
    let x = model.mesh.nodes[n];
    if model.mesh.dim == 3 {
        // Distance to the front (level sets) within the cylinder of half-length rd around
        // P along the front; the Euclidean cut-off keeps other parts of the front (the far
        // side of a penny, the other front of a through crack) out.
        let d = (lsn[n] * lsn[n] + lst[n] * lst[n]).sqrt();
        let rel = [x[0] - s.x[0], x[1] - s.x[1], x[2] - s.x[2]];
        let along = dot(rel, s.e3).abs();
        if d <= rd && dot(rel, rel).sqrt() <= 2.0 * rd {
            (1.0 - along / rd).max(0.0)
        } else {
            0.0
        }
    } else {
        let d = ((x[0] - s.x[0]).powi(2) + (x[1] - s.x[1]).powi(2)).sqrt();
        if d <= rd {
            1.0
        } else {
            0.0
        }
    }
}

/// The local frame at a point of cell `c` (shape values `nv`, physical gradients `gv`)
/// from the level sets there, and the polar coordinates (r, θ); `side` fixes the sign of
/// φn in a cell cut by the crack.
fn level_set_frame(
    model: &Model<'_>,
    crack: usize,
    ctx: &SifContext<'_>,
    c: usize,
    nv: &[f64],
    gv: &[[f64; 3]],
    side: Option<i8>,
) -> ([[f64; 3]; 3], f64, f64) {
    let (lsn, lst) = (ctx.lsn, ctx.lst);
    let cell = &model.mesh.cells[c];
    let (pn, pt) = level_set_values(model, crack, ctx, c, nv, side);
    let (mut gn, mut gt) = ([0.0; 3], [0.0; 3]);
    for a in 0..nv.len() {
        let node = cell.nodes[a];
        for i in 0..3 {
            gn[i] += gv[a][i] * lsn[node];
            gt[i] += gv[a][i] * lst[node];
        }
    }
    let nrm = unit(gn);
    let mut e1 = gt;
    let d = dot(e1, nrm);
    for i in 0..3 {
        e1[i] -= d * nrm[i];
    }
    let e1 = unit(e1);
    let (e2, x2) = if model.mesh.dim == 3 {
        (nrm, pn)
    } else {
        let e2 = cross([0.0, 0.0, 1.0], e1);
        let sgn = if dot(e2, nrm) >= 0.0 { 1.0 } else { -1.0 };
        (e2, sgn * pn)
    };
    let e3 = cross(e1, e2);
    let r = (pn * pn + pt * pt).sqrt().max(1e-300);
    ([e1, e2, e3], r, x2.atan2(pt))
}

/// φn and φt at a point of cell `c` (shape values `nv`); `side` fixes the sign of φn in
/// a cell cut by the crack.
fn level_set_values(
    model: &Model<'_>,
    crack: usize,
    ctx: &SifContext<'_>,
    c: usize,
    nv: &[f64],
    side: Option<i8>,
) -> (f64, f64) {
    let (lsn, lst) = (ctx.lsn, ctx.lst);
    let cell = &model.mesh.cells[c];
    let (mut pn, mut pt) = (0.0, 0.0);
    for a in 0..nv.len() {
        let node = cell.nodes[a];
        pn += nv[a] * lsn[node];
        pt += nv[a] * lst[node];
    }
    if let (Some(sd), true) = (side, model.enrichment.cell_crack[c] == Some(crack as u16)) {
        pn = sd as f64 * pn.abs();
    }
    (pn, pt)
}

/// The weights q at the nodes of a cell.
type NodalQ = [f64; MAX_NODES];

/// The domain of front point `s`: its normalisation L_q = ∫ q ds along the front (3D;
/// 1 in 2D) and the cells where the virtual extension θ = q e1 varies (the only ones
/// the volume integral gets anything from), with q at their nodes.
fn domain_of(model: &Model<'_>, crack: usize, s: &FrontSample, ctx: &SifContext<'_>) -> (f64, Vec<(usize, NodalQ)>) {
    let mesh = model.mesh;
    let three_d = mesh.dim == 3;
    let cr = &model.cracks[crack];
    let mut lq = if three_d { 0.0 } else { 1.0 };
    let mut out = vec![];
    let mut n = [0.0; MAX_NODES];
    let mut dn = [[0.0; 3]; MAX_NODES];
    for &c in ctx.cells {
        let cell = &mesh.cells[c];
        let v = cell.nodes();
        // Cheap distance filter.
        if v.iter().all(|&a| (0..3).map(|i| (mesh.nodes[a][i] - s.x[i]).powi(2)).sum::<f64>().sqrt() > ctx.reach) {
            continue;
        }
        let mut qv = [0.0; MAX_NODES];
        let mut any = false;
        let mut varies = false;
        let mut th0 = [0.0; 3];
        for (a, &node) in v.iter().enumerate() {
            qv[a] = q_node(model, ctx, s, node);
            let th: [f64; 3] = std::array::from_fn(|i| qv[a] * ctx.dirs[node][0][i]);
            if a == 0 {
                th0 = th;
            }
            any |= qv[a] != 0.0;
            varies |= th != th0;
        }
        if !any {
            continue;
        }
        // Normalisation ∫ q ds along the front (3D).
        if three_d {
            let nn = v.len();
            let cut = &cr.cut;
            if let Some(cc) = cut.cell_cut(c) {
                for fp in &cut.front[cc.front.clone()] {
                    if fp.points.len() == 2 && fp.points_ref.len() == 2 {
                        let mut qa = [0.0; 2];
                        for (k, xi) in fp.points_ref.iter().enumerate() {
                            element::shape(cell.kind, xi, &mut n, &mut dn);
                            qa[k] = (0..nn).map(|a| n[a] * qv[a]).sum();
                        }
                        let l = (0..3).map(|i| (fp.points[1][i] - fp.points[0][i]).powi(2)).sum::<f64>().sqrt();
                        lq += 0.5 * (qa[0] + qa[1]) * l;
                    }
                }
            }
        }
        if varies {
            out.push((c, qv));
        }
    }
    (lq, out)
}

/// One front point's share of a cell: (its index, its auxiliary material, q at the
/// cell's nodes).
type Member = (usize, AuxMaterial, NodalQ);

/// The volume part of the interaction integrals of every front point whose domain holds
/// cell `c` (`members`, all of that cell): the basis, the displacement gradient, the
/// stress, the frame and the auxiliary fields are evaluated once per quadrature point;
/// the integrand is linear in θ and ∇θ, `val = A : ∇θ + B · θ`, so each front point adds
/// `A : ∇θ + B · θ` with its own θ. Returns (front point, [mode I, II, III]).
fn cell_volume_terms(
    model: &Model<'_>,
    crack: usize,
    u: &[f64],
    ctx: &SifContext<'_>,
    c: usize,
    members: &[Member],
) -> Vec<(usize, [f64; 3])> {
    let mesh = model.mesh;
    let dim = mesh.dim;
    let three_d = dim == 3;
    let dirs = ctx.dirs;
    let cell = &mesh.cells[c];
    let ev = Evaluator { mesh, enr: &model.enrichment, cracks: &model.cracks };
    let mut basis = CellBasis::default();
    basis.build(mesh, &model.enrichment, c);
    let mut vals = vec![0.0; basis.len()];
    let mut grads = vec![[0.0; 3]; basis.len()];
    let mut points = vec![];
    cell_points(mesh, &model.enrichment, &model.cracks, c, &model.xfem_quadrature, 4, &mut points);
    let nn = cell.kind.n_nodes();
    let mut n = [0.0; MAX_NODES];
    let mut g = [[0.0; 3]; MAX_NODES];
    let cmat = model.materials[model.cell_material[c] as usize];
    let n_modes = if three_d { 3 } else { 2 };
    // θ_a = q_a e1_a at the nodes, per member.
    let th: Vec<[[f64; 3]; MAX_NODES]> = members
        .iter()
        .map(|m| {
            std::array::from_fn(|a| {
                if a < nn {
                    std::array::from_fn(|i| m.2[a] * dirs[cell.nodes[a]][0][i])
                } else {
                    [0.0; 3]
                }
            })
        })
        .collect();
    // The distinct auxiliary materials (one unless the front crosses materials).
    let mut mats: Vec<AuxMaterial> = vec![];
    let which: Vec<usize> = members
        .iter()
        .map(|m| {
            mats.iter().position(|x| *x == m.1).unwrap_or_else(|| {
                mats.push(m.1);
                mats.len() - 1
            })
        })
        .collect();
    let mut coef = vec![[([[0.0; 3]; 3], [0.0; 3]); 3]; mats.len()];
    let mut acc = vec![[0.0; 3]; members.len()];
    // The cell's dof values, gathered once for its points.
    let u_local: Vec<f64> = basis.dofs.iter().map(|&d| u[d as usize]).collect();
    // ∂θ_k/∂x_j of each member: constant over a simplex (computed at its first point).
    let affine = cell.kind.is_simplex();
    let mut dths = vec![[[0.0; 3]; 3]; members.len()];
    let mut dths_ready = false;
    for &(xi, w, side) in &points {
        let Ok(pi) = ev.eval_with_shape(c, &basis, &xi, side, &mut vals, &mut grads, &mut n, &mut g) else {
            continue;
        };
        if !(affine && dths_ready) {
            for (dth, th) in dths.iter_mut().zip(&th) {
                *dth = [[0.0; 3]; 3];
                for a in 0..nn {
                    for k in 0..3 {
                        for j in 0..3 {
                            dth[k][j] += th[a][k] * g[a][j];
                        }
                    }
                }
            }
            dths_ready = true;
        }
        // The frame (e1, e2 = n, e3 = e1 × e2) interpolated from the nodes, and its
        // gradient: the auxiliary fields live in a frame that turns along a curved front.
        let (fr, dfr) = nodal_frame_at(&cell.nodes[..nn], &n[..nn], &g[..nn], dirs, three_d);
        let gu = field_gradient_local(dim, &grads, &u_local);
        let mut eps = [[0.0; 3]; 3];
        for i in 0..3 {
            for j in 0..3 {
                eps[i][j] = 0.5 * (gu[i][j] + gu[j][i]);
            }
        }
        let sig = cmat.stress(model.analysis, &eps);
        let (rot, r, theta) = if three_d {
            // The auxiliary fields' frame is the interpolated nodal one, whose gradient
            // `dfr` enters the curvature terms below (the level-set gradients are
            // constant per tet4 cell: their frame turns only across faces); the level
            // sets give (r, θ), with x2 = φn (e2 = n).
            let (pn, pt) = level_set_values(model, crack, ctx, c, &n[..nn], side);
            let e2 = unit(fr[1]);
            let d = dot(fr[0], e2);
            let e1 = unit([fr[0][0] - d * e2[0], fr[0][1] - d * e2[1], fr[0][2] - d * e2[2]]);
            ([e1, e2, cross(e1, e2)], (pn * pn + pt * pt).sqrt().max(1e-300), pn.atan2(pt))
        } else {
            level_set_frame(model, crack, ctx, c, &n[..nn], &g[..nn], side)
        };
        let de1 = dfr[0][0][0] + dfr[0][1][1] + dfr[0][2][2];
        // σ : sym ∇e_m, m = 1, 2, 3.
        let mut sd = [0.0; 3];
        if three_d {
            for (m, sdm) in sd.iter_mut().enumerate() {
                for i in 0..3 {
                    for j in 0..3 {
                        *sdm += sig[i][j] * 0.5 * (dfr[m][i][j] + dfr[m][j][i]);
                    }
                }
            }
        }
        let polar = Polar::new(r, theta);
        for (am, cf) in mats.iter().zip(coef.iter_mut()) {
            for (mode, (a, b)) in cf.iter_mut().enumerate().take(n_modes) {
                let aux = williams_at(mode, &polar, am.mu, am.kappa, am.nu, three_d);
                let (mut ga, sa) = (to_global(&rot, &aux.grad), to_global(&rot, &aux.stress));
                // The plane-strain strain ε^aux = sym(g0), consistent with σ^aux.
                let g0 = ga;
                // u^aux = Σ_k u'_k e_k: add Σ_k u'_k ∂e_k/∂x_j (the local frame's rotation).
                for k in 0..3 {
                    if aux.disp[k] != 0.0 {
                        for i in 0..3 {
                            for j in 0..3 {
                                ga[i][j] += aux.disp[k] * dfr[k][i][j];
                            }
                        }
                    }
                }
                // Interaction energy σ : ε^aux.
                let mut wint = 0.0;
                for i in 0..3 {
                    for k in 0..3 {
                        wint += sig[i][k] * 0.5 * (g0[i][k] + g0[k][i]);
                    }
                }
                // A_kj = σ_ij ∂u^aux_i/∂x_k + σ^aux_ij ∂u_i/∂x_k − W δ_kj.
                for k in 0..3 {
                    for j in 0..3 {
                        let mut v = 0.0;
                        for i in 0..3 {
                            v += sig[i][j] * ga[i][k] + sa[i][j] * gu[i][k];
                        }
                        a[k][j] = v;
                    }
                    a[k][k] -= wint;
                }
                *b = [0.0; 3];
                if three_d {
                    // Incompatibility, σ_ij θ_k ∂_k(sym ∇u^aux − ε^aux)_ij with
                    // sym ∇u^aux − ε^aux = Σ_m u'_m sym ∇e_m:
                    // Σ_m [θ·∇u'_m + u'_m (θ·∇)] σ : sym ∇e_m, where (θ·∇) ∇e_m is taken as
                    // −(div e1)(θ·e1) ∇e_m (exact for a planar crack: ∇e_m ∝ κ/(1 + κ x1)).
                    for m in 0..3 {
                        let c1 = aux.grad[m][0] - de1 * aux.disp[m];
                        let c2 = aux.grad[m][1];
                        for k in 0..3 {
                            b[k] += sd[m] * (c1 * rot[0][k] + c2 * rot[1][k]);
                        }
                    }
                    // Non-equilibrium, (div σ^aux)_i u_i,k θ_k, with (the 2D Williams stress
                    // balances in the (e1, e2) plane) div σ^aux = σ'_ab [(∇e_a) e_b + e_a div e_b].
                    let mut dv = [0.0; 3];
                    for a_ in 0..3 {
                        for bb in 0..3 {
                            let sab = aux.stress[a_][bb];
                            if sab == 0.0 {
                                continue;
                            }
                            let tr = dfr[bb][0][0] + dfr[bb][1][1] + dfr[bb][2][2];
                            for i in 0..3 {
                                let mut de = 0.0;
                                for j in 0..3 {
                                    de += dfr[a_][i][j] * rot[bb][j];
                                }
                                dv[i] += sab * (de + rot[a_][i] * tr);
                            }
                        }
                    }
                    for i in 0..3 {
                        for k in 0..3 {
                            b[k] += dv[i] * gu[i][k];
                        }
                    }
                }
            }
        }
        let wd = w * pi.det;
        for (((acc, th), dth), &mi) in acc.iter_mut().zip(&th).zip(&dths).zip(&which) {
            // θ at the point, θ = Σ N_a q_a e1_a.
            let mut thp = [0.0; 3];
            for a in 0..nn {
                for k in 0..3 {
                    thp[k] += n[a] * th[a][k];
                }
            }
            for (mode, (a, b)) in coef[mi].iter().enumerate().take(n_modes) {
                let mut val = 0.0;
                for k in 0..3 {
                    val += b[k] * thp[k];
                    for j in 0..3 {
                        val += a[k][j] * dth[k][j];
                    }
                }
                acc[mode] += wd * val;
            }
        }
    }
    members.iter().zip(acc).map(|(m, v)| (m.0, v)).collect()
}

/// ∇u at a point from the gradients `grads` of a cell's basis functions and the cell's
/// dof values `u_local` (basis-major, as `CellBasis::dofs`): `field_at`'s gradient, the
/// same sums in the same order.
fn field_gradient_local(dim: usize, grads: &[[f64; 3]], u_local: &[f64]) -> [[f64; 3]; 3] {
    let mut gu = [[0.0; 3]; 3];
    for (k, gk) in grads.iter().enumerate() {
        for i in 0..dim {
            let d = u_local[k * dim + i];
            if d == 0.0 {
                continue;
            }
            for j in 0..dim {
                gu[i][j] += gk[j] * d;
            }
        }
    }
    gu
}

/// The surface terms of front point `s`'s interaction integrals (the outer boundary
/// within its domain, the crack-face tractions), added to the volume part `ints`, and
/// the SIFs from them with the normalisation `lq`.
#[allow(clippy::too_many_arguments)]
fn finish_point(
    model: &Model<'_>,
    crack: usize,
    u: &[f64],
    traction: Option<&FaceTraction<'_>>,
    s: &FrontSample,
    ctx: &SifContext<'_>,
    mut ints: [f64; 3],
    lq: f64,
) -> SifPoint {
    let (lsn, dirs, boundary) = (ctx.lsn, ctx.dirs, ctx.boundary);
    let mesh = model.mesh;
    let dim = mesh.dim;
    let three_d = dim == 3;
    let cr = &model.cracks[crack];
    let AuxMaterial { mu, nu, e, kappa, e_star } = AuxMaterial::of(model, s.cell);
    let q_node = |n: usize| q_node(model, ctx, s, n);
    let frame =
        |c: usize, nv: &[f64], gv: &[[f64; 3]], side: Option<i8>| level_set_frame(model, crack, ctx, c, nv, gv, side);
    let ev = Evaluator { mesh, enr: &model.enrichment, cracks: &model.cracks };
    let mut basis = CellBasis::default();
    let mut vals = vec![];
    let mut grads = vec![];
    let mut qv = [0.0; MAX_NODES];
    let mut n = [0.0; MAX_NODES];
    let mut dn = [[0.0; 3]; MAX_NODES];
    let mut g = [[0.0; 3]; MAX_NODES];
    let mut xs = [[0.0; 3]; MAX_NODES];
    // Outer-boundary term: where the domain takes in a part of the body's boundary Γ
    // (θ ≠ 0 there), the divergence theorem leaves −∫_Γ P_kj θ_k m_j dS, m the outward
    // normal, with σ m the finite-element traction (zero on a free face up to the
    // discretisation, the load or the reaction elsewhere).
    for &(c, lf) in boundary {
        let cell = &mesh.cells[c];
        let (ft, loc) = cell.kind.faces()[lf];
        let nf = ft.n_nodes();
        let fq: Vec<f64> = loc.iter().map(|&a| q_node(cell.nodes[a])).collect();
        if fq.iter().all(|&q| q == 0.0) {
            continue;
        }
        let nn = mesh.cell_coords(c, &mut xs);
        let mut th = [[0.0; 3]; MAX_NODES];
        for (a, &node) in cell.nodes().iter().enumerate() {
            let q = q_node(node);
            for i in 0..3 {
                th[a][i] = q * dirs[node][0][i];
            }
        }
        let fx: Vec<[f64; 3]> = loc.iter().map(|&a| xs[a]).collect();
        let centroid = element::map_point(&vec![1.0 / nn as f64; nn], &xs[..nn]);
        let refs = cell.kind.reference_nodes();
        // The face's quadrature, split at the crack in 2D where it crosses the face (the
        // displacement jumps there); a high-degree rule otherwise (the auxiliary fields are
        // singular at the front).
        let fl: Vec<f64> = loc.iter().map(|&a| lsn[cell.nodes[a]]).collect();
        let cut_here = model.enrichment.cell_crack[c] == Some(crack as u16);
        let mut rule: Vec<([f64; 3], f64)> = vec![];
        let base = ft.quadrature(8);
        if ft == element::FaceType::Line2 && cut_here && fl[0] * fl[1] < 0.0 {
            // η ∈ [−1, 1]: the zero of φn at η0.
            let t0 = fl[0] / (fl[0] - fl[1]);
            let eta0 = -1.0 + 2.0 * t0;
            for (lo_, hi_) in [(-1.0, eta0), (eta0, 1.0)] {
                for (p, w) in base.iter() {
                    let half = 0.5 * (hi_ - lo_);
                    rule.push(([lo_ + half * (p[0] + 1.0), 0.0, 0.0], w * half));
                }
            }
        } else {
            rule.extend(base.iter().map(|(p, w)| (*p, w)));
        }
        // A face the front ends on: held along its normal (every face node holds every
        // component the normal has), its term is kept for every mode; free, for mode III
        // only (module doc, "Faces the front ends on"); either is integrated by pieces
        // split at the crack and graded towards the front.
        let m0 = {
            let mut fnv = [0.0; 4];
            let mut fdn = [[0.0; 3]; 4];
            let c0 = if ft == element::FaceType::Tri3 { [1.0 / 3.0, 1.0 / 3.0, 0.0] } else { [0.0; 3] };
            ft.shape(&c0, &mut fnv[..nf], &mut fdn[..nf]);
            element::face_measure_and_normal(ft, &fx, &fdn[..nf]).1
        };
        let held_normal = three_d
            && (0..3).all(|i| m0[i].abs() <= 1e-6 || loc.iter().all(|&a| ctx.held[cell.nodes[a]] & (1 << i) != 0));
        let end_face = three_d && dot(m0, s.e3).abs() > std::f64::consts::FRAC_1_SQRT_2;
        let mut sides: Vec<Option<i8>> = vec![None; rule.len()];
        if end_face {
            let ft_n: Vec<f64> = loc.iter().map(|&a| ctx.lst[cell.nodes[a]]).collect();
            let pieces = held_face_rule(ft, &fl, &ft_n, 8);
            rule = pieces.iter().map(|p| (p.0, p.1)).collect();
            sides = pieces.iter().map(|p| if cut_here { p.2 } else { None }).collect();
        }
        basis.build(mesh, &model.enrichment, c);
        vals.resize(basis.len(), 0.0);
        grads.resize(basis.len(), [0.0; 3]);
        let cmat = model.materials[model.cell_material[c] as usize];
        let mut fnv = [0.0; 4];
        let mut fdn = [[0.0; 3]; 4];
        for ((eta, w), side) in rule.into_iter().zip(sides) {
            ft.shape(&eta, &mut fnv[..nf], &mut fdn[..nf]);
            let (meas, mut m) = element::face_measure_and_normal(ft, &fx, &fdn[..nf]);
            let x = element::map_point(&fnv[..nf], &fx);
            if dot([x[0] - centroid[0], x[1] - centroid[1], x[2] - centroid[2]], m) < 0.0 {
                m = [-m[0], -m[1], -m[2]];
            }
            let mut xi = [0.0; 3];
            for (a, &la) in loc.iter().enumerate() {
                for i in 0..3 {
                    xi[i] += fnv[a] * refs[la][i];
                }
            }
            if ev.eval(c, &basis, &xi, side, &mut vals, &mut grads).is_err() {
                continue;
            }
            element::shape(cell.kind, &xi, &mut n, &mut dn);
            if element::physical_gradients(dim, &xs[..nn], &dn[..nn], &mut g).is_err() {
                continue;
            }
            let mut thp = [0.0; 3];
            for a in 0..nn {
                for i in 0..3 {
                    thp[i] += n[a] * th[a][i];
                }
            }
            if thp == [0.0; 3] {
                continue;
            }
            let (fr, dfr) = nodal_frame_at(&cell.nodes[..nn], &n[..nn], &g[..nn], dirs, three_d);
            let (mut rot, r, theta) = frame(c, &n[..nn], &g[..nn], side);
            let mut free_end = false;
            if three_d {
                let e2 = unit(fr[1]);
                let d = dot(fr[0], e2);
                let e1 = unit([fr[0][0] - d * e2[0], fr[0][1] - d * e2[1], fr[0][2] - d * e2[2]]);
                rot = [e1, e2, cross(e1, e2)];
                // A free face the front ends on (its normal near the front's tangent e3:
                // the free faces of a slab, the face a surface crack opens on) keeps its
                // mode-III term only; a face held along its normal keeps all (module doc,
                // "Faces the front ends on").
                free_end = dot(m, rot[2]).abs() > std::f64::consts::FRAC_1_SQRT_2 && !held_normal;
            }
            let (_, gu) = field_at(dim, &basis, &vals, &grads, u);
            let mut eps = [[0.0; 3]; 3];
            for i in 0..3 {
                for j in 0..3 {
                    eps[i][j] = 0.5 * (gu[i][j] + gu[j][i]);
                }
            }
            let sig = cmat.stress(model.analysis, &eps);
            let sm: [f64; 3] = std::array::from_fn(|i| (0..3).map(|j| sig[i][j] * m[j]).sum());
            let thm = dot(thp, m);
            for (mode, acc) in ints.iter_mut().enumerate().take(if three_d { 3 } else { 2 }) {
                // On a free face the front ends on only the mode-III term is kept (module
                // doc, "Faces the front ends on").
                if free_end && mode < 2 {
                    continue;
                }
                let aux = williams(mode, r, theta, mu, kappa, nu, three_d);
                let (mut ga, sa) = (to_global(&rot, &aux.grad), to_global(&rot, &aux.stress));
                let g0 = ga;
                for k in 0..3 {
                    if aux.disp[k] != 0.0 {
                        for i in 0..3 {
                            for j in 0..3 {
                                ga[i][j] += aux.disp[k] * dfr[k][i][j];
                            }
                        }
                    }
                }
                let mut wint = 0.0;
                let mut val = 0.0;
                for i in 0..3 {
                    let sam: f64 = (0..3).map(|j| sa[i][j] * m[j]).sum();
                    for k in 0..3 {
                        wint += sig[i][k] * 0.5 * (g0[i][k] + g0[k][i]);
                        val += (sm[i] * ga[i][k] + sam * gu[i][k]) * thp[k];
                    }
                }
                val -= wint * thm;
                *acc -= w * meas * val;
            }
        }
    }
    // Crack-face traction term: −∫ t⁺_i [[∂u^aux_i/∂x_k]] θ_k dS.
    if let Some(tr) = traction {
        // 2D: the front points, for the segments that end near one (a front just past a
        // mesh edge), where the integrand behaves like 1/√r without a front vertex.
        let front: Vec<[f64; 3]> = if three_d {
            vec![]
        } else {
            cr.cut
                .facets
                .iter()
                .flat_map(|f| f.vertices.iter().zip(&f.vertex_on_front).filter(|(_, &b)| b).map(|(x, _)| *x))
                .collect()
        };
        for (fi, f) in cr.cut.facets.iter().enumerate() {
            let c = f.cell;
            let cell = &mesh.cells[c];
            if cell.nodes().iter().all(|&a| q_node(a) == 0.0) {
                continue;
            }
            let nn = cell.kind.n_nodes();
            let mut th = [[0.0; 3]; MAX_NODES];
            for (a, &node) in cell.nodes().iter().enumerate() {
                qv[a] = q_node(node);
                for i in 0..3 {
                    th[a][i] = qv[a] * dirs[node][0][i];
                }
            }
            let near = near_front_vertex(f, &front);
            let (pts, wts) = if f.vertex_on_front.iter().any(|&b| b) {
                graded_facet_rule(f, 10)
            } else if let Some((v, d0)) = near {
                near_front_segment_rule(f, v, d0, 10)
            } else {
                facet_quadrature(f, 4)
            };
            for (xi, w) in pts.iter().zip(&wts) {
                element::shape(cell.kind, xi, &mut n, &mut dn);
                let mesh_xs = mesh.cell_coords(c, &mut xs);
                if element::physical_gradients(dim, &xs[..mesh_xs], &dn[..nn], &mut g).is_err() {
                    continue;
                }
                let mut thp = [0.0; 3];
                for a in 0..nn {
                    for i in 0..3 {
                        thp[i] += n[a] * th[a][i];
                    }
                }
                if thp == [0.0; 3] {
                    continue;
                }
                let x = element::map_point(&n[..nn], &xs[..nn]);
                let t = tr(fi, x);
                let (rot, r, _) = frame(c, &n[..nn], &g[..nn], Some(1));
                let t_l = [dot(rot[0], t), dot(rot[1], t), dot(rot[2], t)];
                let th_l = [dot(rot[0], thp), dot(rot[1], thp), dot(rot[2], thp)];
                // The + lip is θ = +π in the frame when e2 · n > 0 (always in 3D).
                let upper = if dot(rot[1], f.normal) >= 0.0 { PI } else { -PI };
                for (mode, acc) in ints.iter_mut().enumerate().take(if three_d { 3 } else { 2 }) {
                    let ap = williams(mode, r, upper, mu, kappa, nu, three_d);
                    let am = williams(mode, r, -upper, mu, kappa, nu, three_d);
                    let mut val = 0.0;
                    for i in 0..3 {
                        for k in 0..3 {
                            // t⁺ on the + lip, −t⁺ on the − lip.
                            val += t_l[i] * (ap.grad[i][k] - am.grad[i][k]) * th_l[k];
                        }
                    }
                    *acc -= w * val;
                }
            }
        }
    }
    let lq = if lq > 0.0 { lq } else { 1.0 };
    let k1 = e_star * ints[0] / (2.0 * lq);
    let k2 = e_star * ints[1] / (2.0 * lq);
    let k3 = if three_d { mu * ints[2] / lq } else { 0.0 };
    let gval = (k1 * k1 + k2 * k2) / e_star + k3 * k3 * (1.0 + nu) / e;
    let (e1, e2, e3) = point_frame(model, crack, s);
    SifPoint { x: s.x, e1, e2, e3, k1, k2, k3, g: gval, cycle: None }
}

/// `Rᵀ A R`: a tensor from the local frame (rows of `rot`) to the global axes.
fn to_global(rot: &[[f64; 3]; 3], m: &[[f64; 3]; 3]) -> [[f64; 3]; 3] {
    // A R first (t_kj = Σ_l A_kl R_lj), then Rᵀ (A R).
    let mut t = [[0.0; 3]; 3];
    for k in 0..3 {
        for j in 0..3 {
            t[k][j] = m[k][0] * rot[0][j] + m[k][1] * rot[1][j] + m[k][2] * rot[2][j];
        }
    }
    let mut o = [[0.0; 3]; 3];
    for i in 0..3 {
        for j in 0..3 {
            o[i][j] = rot[0][i] * t[0][j] + rot[1][i] * t[1][j] + rot[2][i] * t[2][j];
        }
    }
    o
}

/// The cells with a node in the bounding box of `points` grown by `reach`, and that box.
fn cells_near(
    model: &Model<'_>,
    points: impl Iterator<Item = [f64; 3]>,
    reach: f64,
) -> (Vec<usize>, [f64; 3], [f64; 3]) {
    let mesh = model.mesh;
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for x in points {
        for i in 0..3 {
            lo[i] = lo[i].min(x[i] - reach);
            hi[i] = hi[i].max(x[i] + reach);
        }
    }
    let near = (0..mesh.n_cells())
        .into_par_iter()
        .filter(|&c| {
            mesh.cells[c]
                .nodes()
                .iter()
                .any(|&a| (0..3).all(|i| mesh.nodes[a][i] >= lo[i] && mesh.nodes[a][i] <= hi[i]))
        })
        .collect();
    (near, lo, hi)
}

/// The faces of `cells` on the outer boundary of the body, as (cell, local face), among
/// those with a node inside the box `lo`–`hi`. `cells` must hold every cell with a node
/// in the box: a face with a node there is then shared by two of them unless it is on
/// the boundary.
fn boundary_faces_near(model: &Model<'_>, cells: &[usize], lo: [f64; 3], hi: [f64; 3]) -> Vec<(usize, usize)> {
    let mesh = model.mesh;
    let inside = |a: usize| (0..3).all(|i| mesh.nodes[a][i] >= lo[i] && mesh.nodes[a][i] <= hi[i]);
    let mut seen: std::collections::HashMap<[usize; 4], (usize, usize, u32)> = std::collections::HashMap::new();
    for &c in cells {
        let cell = &mesh.cells[c];
        for (lf, (_, loc)) in cell.kind.faces().iter().enumerate() {
            if !loc.iter().any(|&a| inside(cell.nodes[a])) {
                continue;
            }
            let mut key = [usize::MAX; 4];
            for (i, &a) in loc.iter().enumerate() {
                key[i] = cell.nodes[a];
            }
            key[..loc.len()].sort_unstable();
            seen.entry(key).and_modify(|e| e.2 += 1).or_insert((c, lf, 1));
        }
    }
    let mut out: Vec<(usize, usize)> = seen.into_values().filter(|e| e.2 == 1).map(|e| (e.0, e.1)).collect();
    out.sort_unstable();
    out
}

/// The nodal frame (e1, e2) interpolated at a point of a cell with shape values `n` and
/// physical gradients `g`, and the gradients ∂e_m,i/∂x_j of e1, e2 and e3 = e1 × e2
/// (zero in 2D, where the frame does not turn).
fn nodal_frame_at(
    nodes: &[usize],
    n: &[f64],
    g: &[[f64; 3]],
    dirs: &[[[f64; 3]; 2]],
    three_d: bool,
) -> ([[f64; 3]; 2], [[[f64; 3]; 3]; 3]) {
    let mut fr = [[0.0; 3]; 2];
    let mut dfr = [[[0.0; 3]; 3]; 3];
    for (a, &node) in nodes.iter().enumerate() {
        for f in 0..2 {
            for i in 0..3 {
                fr[f][i] += n[a] * dirs[node][f][i];
                for j in 0..3 {
                    dfr[f][i][j] += dirs[node][f][i] * g[a][j];
                }
            }
        }
    }
    if !three_d {
        return (fr, [[[0.0; 3]; 3]; 3]);
    }
    for i in 0..3 {
        for j in 0..3 {
            // ∂(e1 × e2)_i/∂x_j
            let (i1, i2) = ((i + 1) % 3, (i + 2) % 3);
            dfr[2][i][j] = dfr[0][i1][j] * fr[1][i2] + fr[0][i1] * dfr[1][i2][j]
                - dfr[0][i2][j] * fr[1][i1]
                - fr[0][i2] * dfr[1][i1][j];
        }
    }
    (fr, dfr)
}

/// The local frame at a front sample, from the level-set gradients of its cell.
fn point_frame(model: &Model<'_>, crack: usize, s: &FrontSample) -> ([f64; 3], [f64; 3], [f64; 3]) {
    let mesh = model.mesh;
    let cr = &model.cracks[crack];
    let cell = &mesh.cells[s.cell];
    let mut xs = [[0.0; 3]; MAX_NODES];
    let nn = mesh.cell_coords(s.cell, &mut xs);
    let mut n = [0.0; MAX_NODES];
    let mut dn = [[0.0; 3]; MAX_NODES];
    let mut g = [[0.0; 3]; MAX_NODES];
    element::shape(cell.kind, &cell.kind.reference_centroid(), &mut n, &mut dn);
    if element::physical_gradients(mesh.dim, &xs[..nn], &dn[..nn], &mut g).is_err() {
        return ([1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]);
    }
    let lst = cr.levelsets.lst.as_deref().unwrap_or(&cr.levelsets.lsn);
    let (mut gn, mut gt) = ([0.0; 3], [0.0; 3]);
    for a in 0..nn {
        for i in 0..3 {
            gn[i] += g[a][i] * cr.levelsets.lsn[cell.nodes[a]];
            gt[i] += g[a][i] * lst[cell.nodes[a]];
        }
    }
    let nrm = unit(gn);
    let d = dot(gt, nrm);
    let e1 = unit([gt[0] - d * nrm[0], gt[1] - d * nrm[1], gt[2] - d * nrm[2]]);
    if mesh.dim == 2 {
        let e3 = [0.0, 0.0, 1.0];
        (e1, cross(e3, e1), e3)
    } else {
        (e1, nrm, cross(e1, nrm))
    }
}

/// The vertex of a 2D segment facet without a front vertex that lies nearer to a front
/// point than twice the segment's length, and that distance.
fn near_front_vertex(f: &crate::cut::Facet, front: &[[f64; 3]]) -> Option<(usize, f64)> {
    if f.vertices.len() != 2 || f.vertex_on_front.iter().any(|&b| b) {
        return None;
    }
    let mut best: Option<(usize, f64)> = None;
    for p in front {
        for v in 0..2 {
            let d = ((f.vertices[v][0] - p[0]).powi(2) + (f.vertices[v][1] - p[1]).powi(2)).sqrt();
            if best.is_none_or(|b| d < b.1) {
                best = Some((v, d));
            }
        }
    }
    best.filter(|&(_, d)| d > 0.0 && d < 2.0 * f.measure)
}

/// A rule on a segment facet whose vertex `near` lies at distance `d0` from a front point:
/// Gauss in t with r = d0 + s = R t² (R = d0 + length), t ∈ [√(d0/R), 1], which makes the
/// 1/√r behaviour of the face-term integrand smooth (a plain Gauss rule on a segment that
/// starts a few percent of its length from the front is off by percents there).
fn near_front_segment_rule(f: &crate::cut::Facet, near: usize, d0: f64, n: usize) -> (Vec<[f64; 3]>, Vec<f64>) {
    use crate::geometry::quadrature::gauss_legendre;
    let (x, w) = gauss_legendre(n);
    let len = f.measure;
    let big_r = d0 + len;
    let t0 = (d0 / big_r).sqrt();
    let (a, b) = (f.vertices_ref[near], f.vertices_ref[1 - near]);
    let (mut pts, mut wts) = (vec![], vec![]);
    for (x, w) in x.iter().zip(&w) {
        let t = t0 + (1.0 - t0) * 0.5 * (x + 1.0);
        let wt = (1.0 - t0) * 0.5 * w;
        let frac = ((big_r * t * t - d0) / len).clamp(0.0, 1.0);
        pts.push([a[0] + frac * (b[0] - a[0]), a[1] + frac * (b[1] - a[1]), a[2] + frac * (b[2] - a[2])]);
        wts.push(2.0 * big_r * t * wt);
    }
    (pts, wts)
}

/// A rule on a facet graded towards its vertices on the front, where the face-term
/// integrand behaves like 1/√r: 2D, s = t² along the segment from the front vertex;
/// 3D, the triangle collapsed onto its front vertex or edge with the distance ρ = t².
/// Points in the parent reference coordinates, weights in physical measure.
fn graded_facet_rule(f: &crate::cut::Facet, n: usize) -> (Vec<[f64; 3]>, Vec<f64>) {
    use crate::geometry::quadrature::gauss_legendre;
    let (x, w) = gauss_legendre(n);
    let g01: Vec<(f64, f64)> = x.iter().zip(&w).map(|(x, w)| (0.5 * (x + 1.0), 0.5 * w)).collect();
    let on: Vec<usize> = (0..f.vertices_ref.len()).filter(|&k| f.vertex_on_front[k]).collect();
    let off: Vec<usize> = (0..f.vertices_ref.len()).filter(|&k| !f.vertex_on_front[k]).collect();
    let lerp = |a: &[f64; 3], b: &[f64; 3], s: f64| {
        [a[0] + s * (b[0] - a[0]), a[1] + s * (b[1] - a[1]), a[2] + s * (b[2] - a[2])]
    };
    let (mut pts, mut wts) = (vec![], vec![]);
    let vr = &f.vertices_ref;
    match (vr.len(), on.len()) {
        (2, _) => {
            let (p, q) = (on[0], 1 - on[0]);
            for &(t, wt) in &g01 {
                pts.push(lerp(&vr[p], &vr[q], t * t));
                wts.push(f.measure * 2.0 * t * wt);
            }
        }
        (3, 1) => {
            // x = P + ρ (A + v (B − A) − P), area element 2 |T| ρ dρ dv, ρ = t².
            let (p, a, b) = (on[0], off[0], off[1]);
            for &(t, wt) in &g01 {
                let rho = t * t;
                for &(v, wv) in &g01 {
                    let e = lerp(&vr[a], &vr[b], v);
                    pts.push(lerp(&vr[p], &e, rho));
                    wts.push(2.0 * f.measure * rho * 2.0 * t * wt * wv);
                }
            }
        }
        (3, _) => {
            // Edge P0–P1 on the front, C opposite: x = (1 − ρ)(P0 + a (P1 − P0)) + ρ C,
            // area element 2 |T| (1 − ρ) dρ da, ρ = t².
            let (p0, p1) = (on[0], on[1]);
            let c = 3 - p0 - p1;
            for &(t, wt) in &g01 {
                let rho = t * t;
                for &(a, wa) in &g01 {
                    let e = lerp(&vr[p0], &vr[p1], a);
                    pts.push(lerp(&e, &vr[c], rho));
                    wts.push(2.0 * f.measure * (1.0 - rho) * 2.0 * t * wt * wa);
                }
            }
        }
        _ => return facet_quadrature(f, 4),
    }
    (pts, wts)
}

/// A rule on a boundary face (reference coordinates of the face, weights in reference
/// measure) for the term of a face the front ends on: the face is split where φt < 0 at
/// the crack (φn = 0), across which the displacement jumps, and each convex piece is fanned
/// into triangles from its vertex nearest the front (smallest √(φn² + φt²)), each triangle
/// collapsed onto that vertex with the distance ρ = t² (the integrand behaves like 1/r at
/// the point where the front meets the face; with ρ = t² both 1/r and 1/√r become smooth).
/// `ln`, `lt`: φn and φt at the face's nodes, taken as linear in the reference coordinates
/// between them (exact on the edges). Returns (η, weight, side of the crack or `None`
/// ahead of the front).
fn held_face_rule(ft: element::FaceType, ln: &[f64], lt: &[f64], n: usize) -> Vec<([f64; 3], f64, Option<i8>)> {
    use crate::geometry::quadrature::gauss_legendre;
    let refs = match ft {
        element::FaceType::Tri3 => element::CellType::Tri3.reference_nodes(),
        element::FaceType::Quad4 => element::CellType::Quad4.reference_nodes(),
        element::FaceType::Line2 => return vec![],
    };
    // Vertices (η, φn, φt).
    type V = ([f64; 3], f64, f64);
    let poly: Vec<V> = refs.iter().zip(ln.iter().zip(lt)).map(|(x, (&a, &b))| (*x, a, b)).collect();
    // Sutherland–Hodgman on the sign of a vertex value: (value < 0 part, value ≥ 0 part).
    let split = |poly: &[V], val: &dyn Fn(&V) -> f64| -> (Vec<V>, Vec<V>) {
        let (mut neg, mut pos) = (vec![], vec![]);
        for k in 0..poly.len() {
            let (a, b) = (poly[k], poly[(k + 1) % poly.len()]);
            let (va, vb) = (val(&a), val(&b));
            if va < 0.0 {
                neg.push(a);
            } else {
                pos.push(a);
            }
            if (va < 0.0) != (vb < 0.0) {
                let t = va / (va - vb);
                let lerp = |x: f64, y: f64| x + t * (y - x);
                let p = (std::array::from_fn(|i| lerp(a.0[i], b.0[i])), lerp(a.1, b.1), lerp(a.2, b.2));
                neg.push(p);
                pos.push(p);
            }
        }
        (neg, pos)
    };
    let (behind, ahead) = split(&poly, &|v| v.2);
    let (minus, plus) = split(&behind, &|v| v.1);
    // Ahead of the front the field is continuous, but the point where the front meets the
    // face is a vertex of the pieces on both sides of φn = 0 (the collapsed vertex).
    let (ahead_minus, ahead_plus) = split(&ahead, &|v| v.1);
    let (x, w) = gauss_legendre(n);
    let g01: Vec<(f64, f64)> = x.iter().zip(&w).map(|(x, w)| (0.5 * (x + 1.0), 0.5 * w)).collect();
    let mut out = vec![];
    for (piece, side) in [(minus, Some(-1i8)), (plus, Some(1)), (ahead_minus, None), (ahead_plus, None)] {
        if piece.len() < 3 {
            continue;
        }
        let r = |v: &V| v.1.hypot(v.2);
        let k0 = (0..piece.len()).min_by(|&a, &b| r(&piece[a]).total_cmp(&r(&piece[b]))).unwrap_or(0);
        let p = piece[k0].0;
        for j in 1..piece.len() - 1 {
            let (a, b) = (piece[(k0 + j) % piece.len()].0, piece[(k0 + j + 1) % piece.len()].0);
            let e1 = [a[0] - p[0], a[1] - p[1]];
            let e2 = [b[0] - p[0], b[1] - p[1]];
            let area = 0.5 * (e1[0] * e2[1] - e1[1] * e2[0]).abs();
            if area <= 0.0 {
                continue;
            }
            // x = P + ρ (A + v (B − A) − P), reference area element 2 |T| ρ dρ dv, ρ = t².
            for &(t, wt) in &g01 {
                let rho = t * t;
                for &(v, wv) in &g01 {
                    let e = [a[0] + v * (b[0] - a[0]), a[1] + v * (b[1] - a[1]), 0.0];
                    let xi = [p[0] + rho * (e[0] - p[0]), p[1] + rho * (e[1] - p[1]), 0.0];
                    out.push((xi, 2.0 * area * rho * 2.0 * t * wt * wv, side));
                }
            }
        }
    }
    out
}
