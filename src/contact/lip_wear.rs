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
//! Entry point: [`LipChart::build`], then [`LipChart::overlaps`] (read by
//! [`super::state::face_master_wear`] and [`super::state::accumulate_wear`]).

use super::pairing::MasterPoint;
use super::points::ContactPoints;
use crate::enrich::CrackGeometry;
use crate::geometry::vec3::{dot, sub};
use std::collections::HashMap;

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
    /// Per contact crack (index in `ContactPoints::cracks`): facet index in the crack's cut
    /// → its place on a chain.
    facets: Vec<HashMap<usize, FacetChart>>,
    /// Per chain: the points' intervals [a, b] of σ, in order (they tile the chain in
    /// proportion to the points' weights).
    chains: Vec<Vec<(f64, f64, usize)>>,
}

impl LipChart {
    /// Whether crack `cc` of `points` needs the remap: a 2D crack (not a contact pair)
    /// with large sliding and wear.
    pub fn applies(points: &ContactPoints, cc: usize) -> bool {
        let c = &points.cracks[cc];
        points.dim == 2 && c.large_sliding && c.pair.is_none() && c.law.wear.is_some()
    }

    /// The chart of every crack that needs it ([`LipChart::applies`]); `None` if none does.
    pub fn build(points: &ContactPoints, cracks: &[CrackGeometry]) -> Option<LipChart> {
        if !(0..points.cracks.len()).any(|c| Self::applies(points, c)) {
            return None;
        }
        let mut chart = LipChart {
            at: vec![None; points.points.len()],
            interval: vec![[0.0; 2]; points.points.len()],
            facets: vec![HashMap::new(); points.cracks.len()],
            chains: vec![],
        };
        for (ci, cc) in points.cracks.iter().enumerate() {
            if !Self::applies(points, ci) {
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

    /// The overlaps (point j of the lip, length o_ij) of slave point `i`'s interval, moved
    /// to its master point `m`, with the points' intervals of the master's chain. Empty
    /// when point `i` is not charted.
    pub fn overlaps(&self, points: &ContactPoints, i: usize, m: &MasterPoint, out: &mut Vec<(usize, f64)>) {
        out.clear();
        let Some((_, own_sigma)) = self.at[i] else { return };
        let c = points.points[i].crack;
        let Some(fc) = self.facets[c].get(&(m.facet as usize)) else { return };
        let [a, b] = self.interval[i];
        let sy = fc.sigma(m.x);
        let (lo, hi) = (sy + a - own_sigma, sy + b - own_sigma);
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
