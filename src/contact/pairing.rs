//! Large sliding (formulation §7): pairing of the slave contact points (on the `−` lip)
//! with the master lip (the `+` lip) in the deformed configuration, and the kinematics of a
//! paired point.
//!
//! Entry points: [`pair`] (one pairing of every point of the large-sliding cracks) and
//! [`ElementBasis`] (the basis of a contact element that couples a slave cell with the
//! master cells of its points).
//!
//! ```text
//! slave point X (cell c⁻, lip −)        x⁻ = X + u⁻(X)
//! master lip: facets F, deformed        x⁺(Y) = Y + u⁺(Y),  Y ∈ F (vertices mapped, facets kept flat)
//! pairing: Y = argmin |x⁺(Y) − x⁻| within a narrow band (BVH of the deformed master facets)
//! jump:   ⟦u⟧ = x⁺(Y) − x⁻ = (Y − X) + u⁺(Y) − u⁻(X)        (Y = X: small sliding)
//! ```
//!
//! With the pairing frozen (inside the geometry loop), ⟦u⟧ is linear in the dofs: the
//! contact terms couple the slave cell with the master cell of Y, which need not be its
//! neighbour. A point whose closest master point lies on the boundary of the master lip
//! with a tangential offset (it has slid past the end of the master lip), or that has no
//! master point within the band, is out of contact.
//!
//! The BVH queries are parry's (`Polyline` in 2D, `TriMesh` in 3D), in parallel with rayon.

use super::points::ContactPoints;
use crate::enrich::basis::{field_at, BasisFn, CellBasis, Evaluator};
use crate::enrich::{CrackGeometry, Enrichment};
use crate::mesh::Mesh;
use rayon::prelude::*;
use std::collections::HashMap;

/// Where a slave point meets the master lip.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MasterPoint {
    /// Master facet (index in the crack's cut).
    pub facet: u32,
    /// The cell owning the master facet.
    pub cell: u32,
    /// Reference coordinates of Y in that cell.
    pub xi: [f64; 3],
    /// Position of Y in the undeformed configuration.
    pub x: [f64; 3],
}

/// The outcome of pairing one slave point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum PointPairing {
    /// Paired with a master point.
    Paired(MasterPoint),
    /// The closest master point is on the boundary of the master lip and the slave point is
    /// beside it, not in front of it: the point has slid off the master lip.
    OutsideLip,
    /// No master facet within the narrow band (the lips are far apart here).
    Far,
    /// The projection could not be computed (non-finite displacement or geometry).
    Failed,
    /// Paired (its master point in the initial configuration), but outside the contact
    /// zone of its pair ([`super::zone`]): held open, its contact terms without
    /// displacement unknowns (as an unpaired point's), its friction law on every packet of
    /// its terms (as a paired point's). Checked at every converged step.
    Dormant(MasterPoint),
}

/// Counts of the pairing outcomes.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct PairingCounts {
    pub paired: usize,
    pub outside: usize,
    pub far: usize,
    pub failed: usize,
    /// Of the `paired` points, those outside the contact zone ([`PointPairing::Dormant`]).
    pub zone_out: usize,
}

/// The pairing of every contact point (identity for small-sliding cracks).
#[derive(Debug, Clone, Default)]
pub struct Pairing {
    /// Per contact point.
    pub points: Vec<PointPairing>,
    /// Per contact element (facet with points): the master cells its points use, other than
    /// the facet's own cell, sorted. This is what the sparsity pattern depends on.
    pub facet_masters: Vec<Vec<u32>>,
    /// Per contact crack, per multiplier packet: whether any of its points is paired.
    /// Unpaired points do not take part in the laws of such a packet (see
    /// [`Pairing::law_terms`]).
    pub packet_paired: Vec<Vec<bool>>,
    /// Per contact element (facet with points): whether any of its points is paired (not
    /// dormant). A meshed pair's facet without one has no displacement unknowns in the
    /// pattern (`kernel::ContactKernel`; pairs in small sliding).
    pub facet_coupled: Vec<bool>,
    /// Per contact crack: the contact zone's threshold on the reference gap it was paired
    /// with ([`super::zone`]; infinite: the whole band). Empty: every crack's band.
    pub zone: Vec<f64>,
    pub counts: PairingCounts,
    /// The jumps of the functions at each paired point (`super::state::point_values`),
    /// built on first use: they depend on the pairing and the reference geometry only.
    pub jumps: std::sync::OnceLock<JumpStencils>,
}

/// Per contact point of a large-sliding crack or pair with a master point (paired or
/// dormant), the functions of its contact element with a non-zero jump φ⁺(Y) − φ⁻(X): their
/// dofs (`dim` of them) and the jump, in the element basis' order, so that ⟦u⟧ at the
/// point is a gather of `u` (`super::state::point_values`, the same sum in the same order
/// as from the element basis). Empty for the other points.
#[derive(Debug, Clone, Default)]
pub struct JumpStencils {
    /// Point `p`'s terms are `offsets[p]..offsets[p + 1]`.
    pub offsets: Vec<usize>,
    pub dofs: Vec<[u32; 3]>,
    pub jumps: Vec<f64>,
    /// Whether the maps of the point's cells were regular ([`super::state::paired_jumps`]).
    pub regular: Vec<bool>,
}

impl Pairing {
    /// The master point of contact point `p`, if it is paired.
    #[inline]
    pub fn master(&self, p: usize) -> Option<&MasterPoint> {
        match &self.points[p] {
            PointPairing::Paired(m) => Some(m),
            _ => None,
        }
    }

    /// The master point of contact point `p` in the pairing, also for a dormant point
    /// (outside the contact zone, [`super::zone`]).
    #[inline]
    pub fn reference_master(&self, p: usize) -> Option<&MasterPoint> {
        match &self.points[p] {
            PointPairing::Paired(m) | PointPairing::Dormant(m) => Some(m),
            _ => None,
        }
    }

    /// Whether point `p` is outside its pair's contact zone ([`super::zone`]).
    #[inline]
    pub fn is_dormant(&self, p: usize) -> bool {
        matches!(self.points[p], PointPairing::Dormant(_))
    }

    /// Whether the contact elements of `other` have the same unknowns as this pairing's
    /// (the same master cells and the same facets with displacement unknowns): the same
    /// pattern.
    pub fn same_pattern(&self, other: &Pairing) -> bool {
        self.facet_masters == other.facet_masters && self.facet_coupled == other.facet_coupled
    }

    /// The multiplier terms through which point `p` takes part in the friction law: all of
    /// them for a paired point (dormant or not); for an unpaired point (out of contact), only the packets
    /// without any paired point. Without this, the open friction law (Λ = 0) of the points
    /// that slid off the lip would compete with the sliding law inside the packets at the
    /// edge of the contact zone with an arbitrary relative weight (the open law is
    /// dimensionless, the sliding one scales with μλ̄/ρ_τ), and stick the sliding edge
    /// there. The normal law keeps every term: its open and contact parts have the same
    /// units (λ/ρ_n and d_n), and the open points steady the edge packets.
    pub fn law_terms(&self, crack: usize, p: usize, terms: &[(u32, f64)], out: &mut Vec<(u32, f64)>) {
        out.clear();
        match self.points[p] {
            PointPairing::Paired(_) | PointPairing::Dormant(_) => out.extend_from_slice(terms),
            _ => {
                let flags = &self.packet_paired[crack];
                out.extend(terms.iter().filter(|(j, _)| !flags.get(*j as usize).copied().unwrap_or(false)));
            }
        }
    }

    /// Largest distance (undeformed configuration) between the master points of two
    /// pairings, and whether any point changed between paired and unpaired.
    pub fn change_from(&self, other: &Pairing) -> (f64, bool) {
        let mut d = 0.0f64;
        let mut flipped = false;
        for (a, b) in self.points.iter().zip(&other.points) {
            match (a, b) {
                (PointPairing::Paired(a), PointPairing::Paired(b))
                | (PointPairing::Dormant(a), PointPairing::Dormant(b)) => {
                    let s: f64 = (0..3).map(|i| (a.x[i] - b.x[i]).powi(2)).sum();
                    d = d.max(s.sqrt());
                }
                (PointPairing::Paired(_) | PointPairing::Dormant(_), _)
                | (_, PointPairing::Paired(_) | PointPairing::Dormant(_)) => flipped = true,
                _ => {}
            }
        }
        (d, flipped)
    }
}

/// Options of the pairing.
#[derive(Debug, Clone, Copy)]
pub struct PairingOptions {
    /// Narrow band, as a multiple of the mean cut-cell size: master facets farther than
    /// this from a slave point are not searched.
    pub band: f64,
    /// Tolerance on the tangential offset of a projection onto the lip boundary, relative
    /// to the cell size.
    pub outside_tolerance: f64,
    /// The same tolerance for a slave point on the boundary of its own lip ([`EDGE_REACH`]).
    pub edge_reach: f64,
}

impl Default for PairingOptions {
    fn default() -> Self {
        PairingOptions { band: 2.0, outside_tolerance: 1e-6, edge_reach: EDGE_REACH }
    }
}

/// How far (× the cell size) a slave point lying on the boundary of its own lip may stand
/// beside the master lip's boundary and still face it.
///
/// A contact point stands for the part of the slave lip around it; it is off the master
/// lip when most of that part lies beyond the master lip's boundary. For a point inside the
/// slave lip that is the point itself beyond the boundary (offset > 0, to
/// `outside_tolerance`). A point *on* the slave lip's boundary (`vertex` or `nodes`
/// integration: the lateral faces of a through interface, a crack front, a punch face as
/// wide as its base) stands for the lip on one side of it only, about half a cell deep:
/// it is off when the master boundary has receded past the middle of that, a quarter of a
/// cell. Where both lips end on the same face of the body their boundaries coincide in
/// the reference configuration and stand apart by the deformation only (strain × size):
/// with the point's own tolerance (1e-6 h) such a point flipped between paired and off
/// with the sign of a lateral offset of about 1e-7 h, and the geometry loop of a 3D interface
/// whose normal is a coordinate axis never settled (`tests/large_sliding_3d_axis_aligned.rs`).
pub const EDGE_REACH: f64 = 0.25;

/// Deformed positions x + u^side of points of one cell's lip, with the cell's basis built
/// once for all of them.
#[derive(Default)]
struct Deformer {
    basis: CellBasis,
    vals: Vec<f64>,
    grads: Vec<[f64; 3]>,
}

impl Deformer {
    fn prepare(&mut self, ev: &Evaluator<'_>, cell: usize) {
        self.basis.build(ev.mesh, ev.enr, cell);
        let nb = self.basis.len();
        self.vals.resize(nb, 0.0);
        self.grads.resize(nb, [0.0; 3]);
    }

    /// The deformed position of the point `xi` (reference) / `x` (physical) of the prepared
    /// cell, on lip `side`; `None` if it is not finite or the map is singular.
    fn at(
        &mut self,
        ev: &Evaluator<'_>,
        cell: usize,
        xi: &[f64; 3],
        x: &[f64; 3],
        side: i8,
        u: &[f64],
    ) -> Option<[f64; 3]> {
        ev.eval(cell, &self.basis, xi, (side != 0).then_some(side), &mut self.vals, &mut self.grads).ok()?;
        let (v, _) = field_at(ev.mesh.dim, &self.basis, &self.vals, &self.grads, u);
        let y = [x[0] + v[0], x[1] + v[1], x[2] + v[2]];
        y.iter().all(|c| c.is_finite()).then_some(y)
    }
}

/// The master lip of one crack in the deformed configuration, with its BVH.
enum MasterShape {
    Line(parry2d_f64::shape::Polyline),
    Surface(parry3d_f64::shape::TriMesh),
    Empty,
}

impl MasterShape {
    /// (facet, closest point) within `max_dist` of `x`.
    fn project(&self, x: [f64; 3], max_dist: f64) -> Option<(u32, [f64; 3])> {
        match self {
            MasterShape::Line(s) => {
                let p = parry2d_f64::math::Vector::new(x[0], x[1]);
                let (id, proj) = parry2d_f64::shape::CompositeShapeRef(s).project_local_point(p, max_dist, false)?;
                Some((id, [proj.point.x, proj.point.y, 0.0]))
            }
            MasterShape::Surface(s) => {
                let p = parry3d_f64::math::Vector::new(x[0], x[1], x[2]);
                let (id, proj) = parry3d_f64::shape::CompositeShapeRef(s).project_local_point(p, max_dist, false)?;
                Some((id, [proj.point.x, proj.point.y, proj.point.z]))
            }
            MasterShape::Empty => None,
        }
    }
}

/// Pairs every contact point of the large-sliding cracks with the master lip deformed by
/// `u`; points of small-sliding cracks are paired with themselves. `zone`: per contact
/// crack, the contact zone's threshold on the reference gap ([`super::zone`]; a paired
/// point beyond it is [`PointPairing::Dormant`]); empty or infinite: the whole band.
pub fn pair(
    mesh: &Mesh,
    enr: &Enrichment,
    cracks: &[CrackGeometry],
    points: &ContactPoints,
    u: &[f64],
    opts: &PairingOptions,
    zone: &[f64],
) -> Pairing {
    let dim = mesh.dim;
    let ev = Evaluator { mesh, enr, cracks };
    let mut out = vec![PointPairing::Failed; points.points.len()];
    let zero = if points.cracks.iter().any(|c| !c.repair && c.large_sliding) { vec![0.0; u.len()] } else { vec![] };
    for (ci, cc) in points.cracks.iter().enumerate() {
        // A crack's master lip is its `+` lip; a contact pair's, its master facets (the
        // standard basis, no lip side), in the initial configuration unless it re-pairs.
        let (master_facets, boundary, side_m, side_s) = match &cc.pair {
            Some(p) => (&p.master[..], &p.master_boundary, 0, 0),
            None => (&cracks[cc.crack].cut.facets[..], &cc.lip_boundary, 1, -1),
        };
        // The slave lip's facets and boundary (a crack's two lips share the facets of its cut).
        let (slave_facets, slave_boundary) = match &cc.pair {
            Some(p) => (&p.slave[..], &p.slave_boundary),
            None => (master_facets, &cc.lip_boundary),
        };
        let u = if cc.repair || cc.pair.is_none() { u } else { &zero[..] };
        if !cc.large_sliding {
            for (p, o) in points.points.iter().zip(out.iter_mut()).filter(|(p, _)| p.crack == ci) {
                *o = PointPairing::Paired(MasterPoint { facet: p.facet as u32, cell: p.cell as u32, xi: p.xi, x: p.x });
            }
            continue;
        }
        let edge = SlaveEdge::new(dim, slave_facets, slave_boundary, cc.cell_size);
        // Deformed master facets (+ lip): `dim` vertices per facet, back to back (a facet
        // that cannot be deformed is `None`).
        let deformed_facets: Vec<Option<[[f64; 3]; 3]>> = master_facets
            .par_iter()
            .map_init(Deformer::default, |d, f| {
                if f.vertices.len() != dim {
                    return None;
                }
                d.prepare(&ev, f.cell);
                let mut v = [[0.0; 3]; 3];
                for k in 0..dim {
                    v[k] = d.at(&ev, f.cell, &f.vertices_ref[k], &f.vertices[k], side_m, u)?;
                }
                Some(v)
            })
            .collect();
        let h = cc.cell_size;
        let shape = master_shape(dim, &deformed_facets);
        // Slave points facet by facet (one basis per facet).
        let results: Vec<(usize, PointPairing)> = points
            .facets
            .par_iter()
            .filter(|(c, _, _)| *c == ci)
            .map_init(Deformer::default, |d, (_, _, range)| {
                let cell = points.points[range.start].cell;
                d.prepare(&ev, cell);
                range
                    .clone()
                    .map(|pi| {
                        let p = &points.points[pi];
                        let Some(xs) = d.at(&ev, p.cell, &p.xi, &p.x, side_s, u) else {
                            return (pi, PointPairing::Failed);
                        };
                        // A point on its own lip's boundary faces the master lip up to
                        // EDGE_REACH beyond the master's boundary.
                        let tol = if edge.holds(p.facet, p.x) { opts.edge_reach } else { opts.outside_tolerance };
                        (
                            pi,
                            project_point(
                                dim,
                                master_facets,
                                &shape,
                                &deformed_facets,
                                boundary,
                                xs,
                                h,
                                opts.band,
                                tol,
                            ),
                        )
                    })
                    .collect::<Vec<_>>()
            })
            .flatten()
            .collect();
        let z = zone.get(ci).copied().unwrap_or(f64::INFINITY);
        for (pi, r) in results {
            out[pi] = match r {
                PointPairing::Paired(m) if super::zone::reference_gap(cc, &points.points[pi], &m) > z => {
                    PointPairing::Dormant(m)
                }
                r => r,
            };
        }
    }
    let mut counts = PairingCounts::default();
    for o in &out {
        match o {
            PointPairing::Paired(_) => counts.paired += 1,
            PointPairing::Dormant(_) => {
                counts.paired += 1;
                counts.zone_out += 1;
            }
            PointPairing::OutsideLip => counts.outside += 1,
            PointPairing::Far => counts.far += 1,
            PointPairing::Failed => counts.failed += 1,
        }
    }
    let facet_masters = points
        .facets
        .iter()
        .map(|(_, _, range)| {
            let own = points.points[range.start].cell as u32;
            let mut m: Vec<u32> = out[range.clone()]
                .iter()
                .filter_map(|o| if let PointPairing::Paired(m) = o { Some(m.cell) } else { None })
                .filter(|&c| c != own)
                .collect();
            m.sort_unstable();
            m.dedup();
            m
        })
        .collect();
    let facet_coupled = points
        .facets
        .iter()
        .map(|(_, _, range)| out[range.clone()].iter().any(|o| matches!(o, PointPairing::Paired(_))))
        .collect();
    let mut packet_paired: Vec<Vec<bool>> = points.cracks.iter().map(|cc| vec![false; cc.space.n_unknowns]).collect();
    for (p, o) in points.points.iter().zip(&out) {
        if matches!(o, PointPairing::Paired(_) | PointPairing::Dormant(_)) {
            for &(j, _) in &p.terms {
                packet_paired[p.crack][j as usize] = true;
            }
        }
    }
    let zone = (0..points.cracks.len()).map(|c| zone.get(c).copied().unwrap_or(f64::INFINITY)).collect();
    Pairing { points: out, facet_masters, packet_paired, facet_coupled, zone, counts, jumps: Default::default() }
}

/// The boundary of a slave lip: which slave points lie on it (on a boundary side of their
/// own facet, or at a vertex of a boundary side of another facet: a facet may touch the
/// boundary with a vertex only).
struct SlaveEdge<'a> {
    dim: usize,
    facets: &'a [crate::cut::Facet],
    boundary: &'a [Vec<bool>],
    /// Quantised positions of the boundary sides' vertices.
    vertices: std::collections::HashSet<[i64; 3]>,
    scale: f64,
}

impl<'a> SlaveEdge<'a> {
    fn new(dim: usize, facets: &'a [crate::cut::Facet], boundary: &'a [Vec<bool>], h: f64) -> SlaveEdge<'a> {
        // The quantum of `cut::lip_boundary`.
        let scale = 1e-7 * h.max(f64::MIN_POSITIVE);
        let mut e = SlaveEdge { dim, facets, boundary, vertices: Default::default(), scale };
        for (f, b) in facets.iter().zip(boundary) {
            let nv = f.vertices.len();
            for (k, _) in b.iter().enumerate().filter(|(_, &on)| on) {
                if dim == 2 {
                    e.vertices.insert(e.key(&f.vertices[k]));
                } else if nv == 3 {
                    e.vertices.insert(e.key(&f.vertices[(k + 1) % 3]));
                    e.vertices.insert(e.key(&f.vertices[(k + 2) % 3]));
                }
            }
        }
        e
    }

    fn key(&self, x: &[f64; 3]) -> [i64; 3] {
        [(x[0] / self.scale).round() as i64, (x[1] / self.scale).round() as i64, (x[2] / self.scale).round() as i64]
    }

    /// Whether the point `x` of slave facet `f` lies on the slave lip's boundary.
    fn holds(&self, f: usize, x: [f64; 3]) -> bool {
        if self.vertices.contains(&self.key(&x)) {
            return true;
        }
        match (self.facets.get(f), self.boundary.get(f)) {
            (Some(facet), Some(b)) if facet.vertices.len() == self.dim => {
                boundary_touch(self.dim, b, &super::facet_barycentric(&facet.vertices, x))
            }
            _ => false,
        }
    }
}

/// Pairs one deformed slave position with the master lip.
#[allow(clippy::too_many_arguments)]
fn project_point(
    dim: usize,
    facets: &[crate::cut::Facet],
    shape: &MasterShape,
    deformed_facets: &[Option<[[f64; 3]; 3]>],
    boundary: &[Vec<bool>],
    xs: [f64; 3],
    h: f64,
    band: f64,
    outside_tolerance: f64,
) -> PointPairing {
    let Some((fm, y)) = shape.project(xs, band * h) else {
        return PointPairing::Far;
    };
    let fm = fm as usize;
    let Some(dv) = deformed_facets.get(fm).and_then(|d| d.as_ref()) else {
        return PointPairing::Failed;
    };
    let dv = &dv[..dim];
    let bary = super::facet_barycentric(dv, y);
    // Slid off the lip: the projection is on the lip boundary and the point is beside the
    // lip (its offset has a tangential part).
    let on_edge = bary.iter().any(|&b| b <= 1e-12);
    if on_edge && boundary_touch(dim, &boundary[fm], &bary) {
        let n = facet_normal(dim, dv).unwrap_or(facets[fm].normal);
        let r = [xs[0] - y[0], xs[1] - y[1], xs[2] - y[2]];
        let rn = r[0] * n[0] + r[1] * n[1] + r[2] * n[2];
        let rt = (0..3).map(|i| (r[i] - rn * n[i]).powi(2)).sum::<f64>().sqrt();
        if rt > outside_tolerance * h {
            return PointPairing::OutsideLip;
        }
    }
    let f = &facets[fm];
    let mut m = MasterPoint { facet: fm as u32, cell: f.cell as u32, xi: [0.0; 3], x: [0.0; 3] };
    for (v, b) in bary.iter().enumerate() {
        for i in 0..3 {
            m.xi[i] += b * f.vertices_ref[v][i];
            m.x[i] += b * f.vertices[v][i];
        }
    }
    PointPairing::Paired(m)
}

/// The BVH shape of the deformed master facets (facets that could not be deformed are
/// collapsed to a far-away point so that indices stay aligned).
fn master_shape(dim: usize, facets: &[Option<[[f64; 3]; 3]>]) -> MasterShape {
    if facets.is_empty() {
        return MasterShape::Empty;
    }
    let far = 1e30;
    if dim == 2 {
        use parry2d_f64::math::Vector;
        let mut v = Vec::with_capacity(2 * facets.len());
        let mut idx = Vec::with_capacity(facets.len());
        for (k, f) in facets.iter().enumerate() {
            match f {
                Some(f) => {
                    v.push(Vector::new(f[0][0], f[0][1]));
                    v.push(Vector::new(f[1][0], f[1][1]));
                }
                _ => {
                    v.push(Vector::new(far, far));
                    v.push(Vector::new(far, far));
                }
            }
            idx.push([2 * k as u32, 2 * k as u32 + 1]);
        }
        MasterShape::Line(parry2d_f64::shape::Polyline::new(v, Some(idx)))
    } else {
        use parry3d_f64::math::Vector;
        let mut v = Vec::with_capacity(3 * facets.len());
        let mut idx = Vec::with_capacity(facets.len());
        for (k, f) in facets.iter().enumerate() {
            match f {
                Some(f) => {
                    for p in f {
                        v.push(Vector::new(p[0], p[1], p[2]));
                    }
                }
                _ => {
                    for d in 0..3 {
                        v.push(Vector::new(far + d as f64, far, far));
                    }
                }
            }
            let b = 3 * k as u32;
            idx.push([b, b + 1, b + 2]);
        }
        match parry3d_f64::shape::TriMesh::new(v, idx) {
            Ok(t) => MasterShape::Surface(t),
            Err(_) => MasterShape::Empty,
        }
    }
}

/// Unit normal of a deformed facet.
fn facet_normal(dim: usize, v: &[[f64; 3]]) -> Option<[f64; 3]> {
    let e1 = [v[1][0] - v[0][0], v[1][1] - v[0][1], v[1][2] - v[0][2]];
    let n = if dim == 2 {
        [-e1[1], e1[0], 0.0]
    } else {
        let e2 = [v[2][0] - v[0][0], v[2][1] - v[0][1], v[2][2] - v[0][2]];
        [e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]]
    };
    let l = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
    (l > 0.0 && l.is_finite()).then(|| [n[0] / l, n[1] / l, n[2] / l])
}

/// Whether a projection with barycentrics `bary` touches a lip-boundary side of its facet.
fn boundary_touch(dim: usize, boundary: &[bool], bary: &[f64]) -> bool {
    if dim == 2 {
        // At vertex k: barycentric k is 1 (the other is 0).
        bary.iter().enumerate().any(|(k, &b)| b >= 1.0 - 1e-12 && boundary[k])
    } else {
        bary.iter().enumerate().any(|(k, &b)| b <= 1e-12 && boundary[k])
    }
}

/// The local basis of a contact element under large sliding: the functions of the slave
/// cell, then those of each master cell not already present, with the map from each
/// cell's functions to local indices.
#[derive(Debug, Default)]
pub struct ElementBasis {
    /// Global dofs, basis-major (`dofs[k * dim + i]`).
    pub dofs: Vec<u32>,
    cells: Vec<usize>,
    bases: Vec<CellBasis>,
    maps: Vec<Vec<u32>>,
    vals: Vec<f64>,
    grads: Vec<[f64; 3]>,
    /// First dof of a function → its local index (kept between builds, cleared each time).
    index: HashMap<u32, u32>,
}

impl ElementBasis {
    /// Builds the basis of the slave cell `own` and the master cells `masters`. With
    /// `keep` (sorted mesh nodes), only the functions of those nodes: a meshed contact
    /// pair keeps the nodes of its faces, since every other function of a cell vanishes on
    /// its boundary faces (standard or enriched, each is its node's shape function times
    /// something); the element then couples no interior node, and the condensed factor's
    /// crack block is smaller.
    pub fn build(&mut self, mesh: &Mesh, enr: &Enrichment, own: usize, masters: &[u32], keep: Option<&[usize]>) {
        let dim = mesh.dim;
        self.dofs.clear();
        self.cells.clear();
        self.index.clear();
        let n_cells = 1 + masters.len();
        if self.bases.len() < n_cells {
            self.bases.resize_with(n_cells, CellBasis::default);
            self.maps.resize_with(n_cells, Vec::new);
        }
        for (k, c) in std::iter::once(own).chain(masters.iter().map(|&c| c as usize)).enumerate() {
            self.cells.push(c);
            let b = &mut self.bases[k];
            b.build(mesh, enr, c);
            let map = &mut self.maps[k];
            map.clear();
            let nodes = mesh.cells[c].nodes();
            for f in 0..b.len() {
                if let Some(keep) = keep {
                    let a = match b.funcs[f] {
                        BasisFn::Standard { a } | BasisFn::Heaviside { a, .. } | BasisFn::Tip { a, .. } => a,
                    };
                    if keep.binary_search(&nodes[a as usize]).is_err() {
                        map.push(u32::MAX);
                        continue;
                    }
                }
                let key = b.dofs[f * dim];
                let next = (self.dofs.len() / dim) as u32;
                let local = *self.index.entry(key).or_insert_with(|| {
                    self.dofs.extend_from_slice(&b.dofs[f * dim..f * dim + dim]);
                    next
                });
                map.push(local);
            }
        }
    }

    /// Number of basis functions.
    pub fn len(&self, dim: usize) -> usize {
        self.dofs.len() / dim
    }

    /// Adds `sign ×` the values of the basis of `cell` (lip `side`; 0: the side of the
    /// point, for a meshed contact pair) at `xi` to `out`
    /// (indexed by local function). Returns false if the cell is not in the element or the
    /// map is singular.
    pub fn add_values(
        &mut self,
        ev: &Evaluator<'_>,
        cell: usize,
        xi: &[f64; 3],
        side: i8,
        sign: f64,
        out: &mut [f64],
    ) -> bool {
        let Some(k) = self.cells.iter().position(|&c| c == cell) else {
            return false;
        };
        let b = &self.bases[k];
        let nb = b.len();
        self.vals.resize(nb, 0.0);
        self.grads.resize(nb, [0.0; 3]);
        if ev.eval(cell, b, xi, (side != 0).then_some(side), &mut self.vals, &mut self.grads).is_err() {
            return false;
        }
        for (f, &l) in self.maps[k].iter().enumerate() {
            if l != u32::MAX {
                out[l as usize] += sign * self.vals[f];
            }
        }
        true
    }
}
