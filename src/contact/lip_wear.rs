//! The `+` lip's wear under large sliding (2D): where the slave points meet it, and where
//! their share of the wear goes.
//!
//! Under large sliding a slave point (on the `−` lip, [`super::pairing`]) faces a part of
//! the `+` lip that changes as it slides. Its own lip's wear w⁻ moves with it
//! ([`super::law::PointState::wear`]`[1]`); the `+` lip's wear w⁺ is a field of the `+`
//! lip, sampled at the same contact points (`wear[0]` of point j is the `+` lip's wear at
//! the point's reference position). Each contact point stands for an interval of its facet
//! (the facet's points, in order along it, tile it in proportion to their integration
//! weights). A slave point's interval, moved to its master point, overlaps `+` lip
//! intervals there (on the master facet and, past its ends, on the neighbouring facets);
//! the overlap lengths o_ij are the weights of a conservative remap, used both ways:
//!
//! ```text
//! facing wear (read):  w⁺ seen by slave i = Σ_j o_ij w⁺_j / Σ_j o_ij
//! deposit (write):     Δw⁺_j += A_i Δw⁺_i · o_ij / (Σ_k o_ik · A_j)     (A: point weights)
//! ```
//!
//! A uniform wear stays uniform (a `+` interval covered by slave intervals gets its own
//! length back) and the worn volume Σ A (w⁺ + w⁻) is kept to round-off. Small sliding
//! needs none of this: each point faces itself.
//!
//! A meshed contact pair (`[[contact_pairs]]`, 2D) is the same with two surfaces: the
//! slave face's wear w⁻ moves with its contact points (`wear[1]`, `wear[0]` stays 0), and
//! the master face's wear w⁺ is a field on the master facets ([`MasterWear`], one depth per
//! facet, held by the pair's [`super::points::ContactCrack::master_wear`]): the master
//! facets are chained by their shared nodes (an open or closed chain) with an arc length,
//! each facet is one interval of it, and a slave point's interval (its share of its slave
//! facet, centred as its integration weight tiles the facet) is moved to its master point,
//! oriented along the master chain as the slave facet's tangent runs there (the two faces
//! of a pair run in opposite directions). The same overlap weights read the facing wear and
//! deposit the `+` share, with A_j the master facet's length.
//!
//! Entry point: [`LipChart::build`], then [`LipChart::overlaps`] (read by
//! [`super::state::face_master_wear`] and [`super::state::accumulate_wear`]).

use super::pairing::MasterPoint;
use super::points::ContactPoints;
use crate::enrich::CrackGeometry;
use crate::geometry::vec3::{dot, sub};
use std::collections::HashMap;
use std::sync::Mutex;

/// The master face's wear of a meshed contact pair with wear (2D): per master facet, the
/// depth before the last solved step and that step's increment (the depth now is their
/// sum). Written once per converged step ([`MasterWear::deposit`], by
/// [`super::state::accumulate_wear`]), which first joins the last increment to the depth,
/// so a step reads the depth before it as the sum. Empty for cracks and pairs without wear.
/// Interior mutability: the field belongs to the pair's setup, which the solve holds
/// shared; [`crate::solve::setup::Setup::initial_state`] resets it at the start of a run.
#[derive(Debug, Default)]
pub struct MasterWear(Mutex<Vec<[f64; 2]>>);

impl Clone for MasterWear {
    fn clone(&self) -> Self {
        MasterWear(Mutex::new(self.get()))
    }
}

impl MasterWear {
    /// A field of `n` facets, unworn.
    pub fn new(n: usize) -> Self {
        MasterWear(Mutex::new(vec![[0.0; 2]; n]))
    }

    /// Per facet, (depth before the last solved step, its increment).
    pub fn get(&self) -> Vec<[f64; 2]> {
        self.0.lock().map(|v| v.clone()).unwrap_or_default()
    }

    /// Per facet, the depth after the last solved step.
    pub fn now(&self) -> Vec<f64> {
        self.get().iter().map(|w| w[0] + w[1]).collect()
    }

    /// Back to unworn (the start of a run).
    pub fn reset(&self) {
        if let Ok(mut v) = self.0.lock() {
            v.iter_mut().for_each(|w| *w = [0.0; 2]);
        }
    }

    /// Ends a converged step: the last increment joins the depth and `step` (per facet)
    /// becomes the new increment.
    pub fn deposit(&self, step: &[f64]) {
        if let Ok(mut v) = self.0.lock() {
            for (w, &d) in v.iter_mut().zip(step) {
                *w = [w[0] + w[1], d];
            }
        }
    }

    pub fn len(&self) -> usize {
        self.0.lock().map(|v| v.len()).unwrap_or(0)
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

/// One facet of a lip, placed on its chain: arc length σ = `start` + s (or
/// `start` + len − s when `reversed`), s the arc length from its first vertex.
#[derive(Debug, Clone, Copy)]
struct FacetChart {
    v0: [f64; 3],
    /// Unit tangent from the first vertex to the second.
    t: [f64; 3],
    len: f64,
    chain: usize,
    start: f64,
    reversed: bool,
}

impl FacetChart {
    /// The chain's arc length at physical position `x` of this facet.
    fn sigma(&self, x: [f64; 3]) -> f64 {
        let s = dot(sub(x, self.v0), self.t).clamp(0.0, self.len);
        self.start + if self.reversed { self.len - s } else { s }
    }
}

/// The intervals of the contact points of the large-sliding cracks with wear along their
/// lips: each lip a chain of facets joined at shared vertices, with an arc length σ.
#[derive(Debug, Clone, Default)]
pub struct LipChart {
    /// Per contact point: (chain, σ) of its position; `None` for points of other cracks.
    at: Vec<Option<(usize, f64)>>,
    /// Per contact point: its interval [a, b] of σ on its chain.
    interval: Vec<[f64; 2]>,
    /// Per contact point of a pair: its interval relative to its own position along its
    /// slave facet's unit tangent, and that tangent; `None` for points of cracks.
    slave: Vec<Option<([f64; 2], [f64; 3])>>,
    /// Per contact crack (index in `ContactPoints::cracks`): facet index in the crack's cut
    /// → its place on a chain.
    facets: Vec<HashMap<usize, FacetChart>>,
    /// Per chain: the points' intervals [a, b] of σ, in order (they tile the chain in
    /// proportion to the points' weights).
    chains: Vec<Vec<(f64, f64, usize)>>,
}

impl LipChart {
    /// Whether crack `cc` of `points` needs the remap: a 2D crack with large sliding and
    /// wear, or a 2D contact pair with wear (always paired).
    pub fn applies(points: &ContactPoints, cc: usize) -> bool {
        let c = &points.cracks[cc];
        points.dim == 2 && c.large_sliding && c.law.wear.is_some()
    }

    /// The chart of every crack that needs it ([`LipChart::applies`]); `None` if none does.
    pub fn build(points: &ContactPoints, cracks: &[CrackGeometry]) -> Option<LipChart> {
        if !(0..points.cracks.len()).any(|c| Self::applies(points, c)) {
            return None;
        }
        let mut chart = LipChart {
            at: vec![None; points.points.len()],
            interval: vec![[0.0; 2]; points.points.len()],
            slave: vec![None; points.points.len()],
            facets: vec![HashMap::new(); points.cracks.len()],
            chains: vec![],
        };
        for (ci, cc) in points.cracks.iter().enumerate() {
            if !Self::applies(points, ci) {
                continue;
            }
            if let Some(pair) = &cc.pair {
                chart.add_pair(points, ci, pair);
                continue;
            }
            let facets = &cracks[cc.crack].cut.facets;
            let ok = |f: usize| facets[f].vertices.len() == 2 && facets[f].measure > 0.0;
            let h = cc.cell_size.max(f64::MIN_POSITIVE);
            let key = |x: &[f64; 3]| ((x[0] / (1e-7 * h)).round() as i64, (x[1] / (1e-7 * h)).round() as i64);
            let mut at_vertex: HashMap<(i64, i64), Vec<(usize, usize)>> = HashMap::new();
            for f in (0..facets.len()).filter(|&f| ok(f)) {
                for (k, v) in facets[f].vertices.iter().enumerate() {
                    at_vertex.entry(key(v)).or_default().push((f, k));
                }
            }
            // The facet across vertex `end` of facet f, and the vertex of it there.
            let across = |f: usize, end: usize| -> Option<(usize, usize)> {
                at_vertex[&key(&facets[f].vertices[end])].iter().copied().find(|&(g, _)| g != f)
            };
            let map = &mut chart.facets[ci];
            for f0 in (0..facets.len()).filter(|&f| ok(f)) {
                if map.contains_key(&f0) {
                    continue;
                }
                // Back to the start of f0's chain (or once round a closed one) ...
                let (mut f, mut end) = (f0, 0usize);
                let mut seen = 0;
                while let Some((g, k)) = across(f, end) {
                    if g == f0 || seen > facets.len() {
                        break;
                    }
                    (f, end) = (g, 1 - k);
                    seen += 1;
                }
                // ... then along it, leaving each facet by the vertex opposite `end`.
                let chain = chart.chains.len();
                chart.chains.push(vec![]);
                let mut sigma = 0.0;
                loop {
                    let fv = &facets[f];
                    let d = sub(fv.vertices[1], fv.vertices[0]);
                    let len = dot(d, d).sqrt();
                    let t = [d[0] / len, d[1] / len, 0.0];
                    map.insert(f, FacetChart { v0: fv.vertices[0], t, len, chain, start: sigma, reversed: end == 1 });
                    sigma += len;
                    match across(f, 1 - end) {
                        Some((g, k)) if !map.contains_key(&g) => (f, end) = (g, k),
                        _ => break,
                    }
                }
            }
            // The points on their chains, in order, tiling each chain by their weights.
            let mut on_chain: Vec<Vec<(f64, usize)>> = vec![vec![]; chart.chains.len()];
            for (c, f, range) in &points.facets {
                if *c != ci {
                    continue;
                }
                let Some(fc) = map.get(f) else { continue };
                for p in range.clone() {
                    let sigma = fc.sigma(points.points[p].x);
                    chart.at[p] = Some((fc.chain, sigma));
                    on_chain[fc.chain].push((sigma, p));
                }
            }
            for (chain, mut pts) in on_chain.into_iter().enumerate() {
                if pts.is_empty() {
                    continue;
                }
                pts.sort_by(|a, b| a.0.total_cmp(&b.0));
                let length: f64 = map.values().filter(|fc| fc.chain == chain).map(|fc| fc.len).sum();
                let total: f64 = pts.iter().map(|&(_, p)| points.points[p].weight).sum();
                if total <= 0.0 {
                    continue;
                }
                let scale = length / total;
                let mut a = 0.0;
                for (_, p) in pts {
                    let b = a + points.points[p].weight * scale;
                    chart.chains[chain].push((a, b, p));
                    chart.interval[p] = [a, b];
                    a = b;
                }
            }
        }
        Some(chart)
    }

    /// The chart of contact pair `ci`: its master facets chained by their shared nodes,
    /// one interval per facet (index j = the master facet), and each slave point's
    /// interval on its slave facet (module doc).
    fn add_pair(&mut self, points: &ContactPoints, ci: usize, pair: &super::surfaces::PairSurfaces) {
        let facets = &pair.master;
        let ok = |f: usize| facets[f].vertices.len() == 2 && facets[f].measure > 0.0;
        let node = |f: usize, k: usize| facets[f].vertex_nodes[k].unwrap_or(usize::MAX);
        let mut at_node: HashMap<usize, Vec<(usize, usize)>> = HashMap::new();
        for f in (0..facets.len()).filter(|&f| ok(f)) {
            for k in 0..2 {
                at_node.entry(node(f, k)).or_default().push((f, k));
            }
        }
        let across = |f: usize, end: usize| -> Option<(usize, usize)> {
            at_node[&node(f, end)].iter().copied().find(|&(g, _)| g != f)
        };
        let map = &mut self.facets[ci];
        for f0 in (0..facets.len()).filter(|&f| ok(f)) {
            if map.contains_key(&f0) {
                continue;
            }
            let (mut f, mut end) = (f0, 0usize);
            let mut seen = 0;
            while let Some((g, k)) = across(f, end) {
                if g == f0 || seen > facets.len() {
                    break;
                }
                (f, end) = (g, 1 - k);
                seen += 1;
            }
            let chain = self.chains.len();
            self.chains.push(vec![]);
            let mut sigma = 0.0;
            loop {
                let fv = &facets[f];
                let d = sub(fv.vertices[1], fv.vertices[0]);
                let len = dot(d, d).sqrt();
                let t = [d[0] / len, d[1] / len, 0.0];
                map.insert(f, FacetChart { v0: fv.vertices[0], t, len, chain, start: sigma, reversed: end == 1 });
                self.chains[chain].push((sigma, sigma + len, f));
                sigma += len;
                match across(f, 1 - end) {
                    Some((g, k)) if !map.contains_key(&g) => (f, end) = (g, k),
                    _ => break,
                }
            }
        }
        // The slave points: each facet's points, in order along it, tile it by their weights.
        for (c, f, range) in &points.facets {
            if *c != ci {
                continue;
            }
            let fv = &pair.slave[*f];
            let d = sub(fv.vertices[1], fv.vertices[0]);
            let len = dot(d, d).sqrt();
            if !(len > 0.0) {
                continue;
            }
            let t = [d[0] / len, d[1] / len, 0.0];
            let mut pts: Vec<(f64, usize)> =
                range.clone().map(|p| (dot(sub(points.points[p].x, fv.vertices[0]), t), p)).collect();
            pts.sort_by(|a, b| a.0.total_cmp(&b.0));
            let total: f64 = pts.iter().map(|&(_, p)| points.points[p].weight).sum();
            if !(total > 0.0) {
                continue;
            }
            let mut a = 0.0;
            for (s, p) in pts {
                let b = a + points.points[p].weight * len / total;
                self.slave[p] = Some(([a - s, b - s], t));
                a = b;
            }
        }
    }

    /// The overlaps (point j of the lip, length o_ij) of slave point `i`'s interval, moved
    /// to its master point `m`, with the points' intervals of the master's chain; for a
    /// contact pair, j is the master facet (a [`MasterWear`] entry). Empty when point `i`
    /// is not charted.
    pub fn overlaps(&self, points: &ContactPoints, i: usize, m: &MasterPoint, out: &mut Vec<(usize, f64)>) {
        out.clear();
        let c = points.points[i].crack;
        let Some(fc) = self.facets[c].get(&(m.facet as usize)) else { return };
        let sy = fc.sigma(m.x);
        let (lo, hi) = if let Some(([a, b], t)) = self.slave[i] {
            // The slave facet's direction along the master chain there.
            let along = dot(t, fc.t) * if fc.reversed { -1.0 } else { 1.0 };
            if along >= 0.0 {
                (sy + a, sy + b)
            } else {
                (sy - b, sy - a)
            }
        } else {
            let Some((_, own_sigma)) = self.at[i] else { return };
            let [a, b] = self.interval[i];
            (sy + a - own_sigma, sy + b - own_sigma)
        };
        let chain = &self.chains[fc.chain];
        let first = chain.partition_point(|x| x.1 <= lo);
        for &(aj, bj, j) in &chain[first..] {
            if aj >= hi {
                break;
            }
            let o = hi.min(bj) - lo.max(aj);
            if o > 0.0 {
                out.push((j, o));
            }
        }
        if out.is_empty() {
            // A zero-weight slave point, or one past the end of the chain: the master
            // point's nearest interval.
            if let Some(&(_, _, j)) =
                chain.iter().min_by(|x, y| (0.5 * (x.0 + x.1) - sy).abs().total_cmp(&(0.5 * (y.0 + y.1) - sy).abs()))
            {
                out.push((j, 1.0));
            }
        }
    }
}
