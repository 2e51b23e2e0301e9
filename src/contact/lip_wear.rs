//! The `+` lip's wear under large sliding: where the slave points meet it, and where
//! their share of the wear goes (2D: a remap of intervals along the lip, [`LipChart`];
//! 3D: a nodal field on the master facets, [`MasterWear::nodal`]).
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
//! In 3D a lip is a surface, not a chain with an arc length: the master face of a 3D pair
//! ([`MasterWear::nodal`], depths at the master nodes) and the `+` lip of a 3D crack under
//! large sliding ([`MasterWear::cell_nodal`], depths at the mesh nodes of the cut cells)
//! carry a **nodal** field with lumped areas; a slave point's `+` share of the worn volume
//! goes to the nodes with the shape-function weights at its master point, and it reads the
//! depth interpolated there.
//! The worn volume is kept to round-off (the weights sum to 1); a uniform deposit stays
//! uniform to the accuracy with which the slave points integrate each vertex's hat
//! function (`docs/conventions.md`, "Contact").
//!
//! Entry point: [`LipChart::build`], then [`LipChart::overlaps`] (read by
//! [`super::state::face_master_wear`] and [`super::state::accumulate_wear`]).

use super::pairing::MasterPoint;
use super::points::ContactPoints;
use crate::enrich::CrackGeometry;
use crate::geometry::vec3::{dot, sub};
use std::collections::HashMap;
use std::sync::Mutex;

/// A master facet of a vertex-nodal field: its vertices' entries and positions.
type VertexFacet = ([u32; 3], [[f64; 3]; 3]);

/// A master facet of a cell-nodal field: its cell's type, the entries of the cell's nodes
/// and the facet's vertices in the cell's reference coordinates.
type CellFacet = (crate::element::CellType, Vec<u32>, [[f64; 3]; 3]);

/// The master surface's wear field: the master face of a meshed contact pair with wear
/// (2D and 3D), and the `+` lip of a 3D crack with wear under large sliding. Per entry,
/// the depth before the last solved step and that step's increment (the depth now is
/// their sum). Written once per converged step ([`MasterWear::deposit`], by
/// [`super::state::accumulate_wear`]), which first joins the last increment to the depth,
/// so a step reads the depth before it as the sum. Empty for cracks and pairs without it.
///
/// - 2D (a pair's master face): one entry per master facet, its area the facet's length;
///   fed and read through the [`LipChart`] overlaps.
/// - 3D (**nodal**): one entry per node, with its lumped area A_n = ∫ N_n dA: a pair's
///   master nodes with the facets' linear functions ([`MasterWear::nodal`], A_n = Σ (facet
///   area)/3), a crack's `+` lip on the mesh nodes of its cells with the cells' shape
///   functions ([`MasterWear::cell_nodal`]). A slave point i meeting the master surface at
///   Y leaves its `+` share of the worn volume, V_i = A_i Δw⁺_i, on the nodes with the
///   shape-function weights N_n(Y)
///   ([`MasterWear::spread`]): Δw_n = Σ_i V_i N_n(Y_i) / A_n. As Σ_n N_n = 1, the worn
///   volume Σ_n A_n w_n is Σ_i V_i to round-off. A point reads the depth interpolated at
///   its master point, Σ_n N_n(Y) w_n ([`MasterWear::read`]).
///
/// Interior mutability: the field belongs to the contact setup, which the solve holds
/// shared; [`crate::solve::setup::Setup::initial_state`] resets it at the start of a run.
#[derive(Debug, Default)]
pub struct MasterWear {
    field: Mutex<Vec<[f64; 2]>>,
    /// Per entry, its area (2D: the facet's length; 3D: the vertex's lumped area).
    area: Vec<f64>,
    /// 3D only: per master facet, its vertices' entries and positions (`None`: a facet
    /// without area).
    facets: Vec<Option<VertexFacet>>,
    /// 3D crack lips only ([`MasterWear::cell_nodal`]): per master facet, its cell's type,
    /// the entries of the cell's nodes and the facet's vertices in the cell's reference
    /// coordinates; the field is then Σ_a N_a w_a over the cell's nodes.
    cells: Vec<Option<CellFacet>>,
    /// 3D only: per entry, the vertex's position.
    x: Vec<[f64; 3]>,
}

impl Clone for MasterWear {
    fn clone(&self) -> Self {
        MasterWear {
            field: Mutex::new(self.get()),
            area: self.area.clone(),
            facets: self.facets.clone(),
            cells: self.cells.clone(),
            x: self.x.clone(),
        }
    }
}

impl MasterWear {
    /// A field of one depth per facet (2D), unworn; `areas` the facets' lengths.
    pub fn new(areas: Vec<f64>) -> Self {
        MasterWear { field: Mutex::new(vec![[0.0; 2]; areas.len()]), area: areas, ..Default::default() }
    }

    /// A nodal field on the triangles `facets` (3D), unworn; `key(f, k)` names the vertex
    /// k of facet f (equal keys: one vertex).
    pub fn nodal<K: std::hash::Hash + Eq>(facets: &[crate::cut::Facet], key: impl Fn(usize, usize) -> K) -> Self {
        let mut index: HashMap<K, u32> = HashMap::new();
        let (mut area, mut x) = (vec![], vec![]);
        let mut out = Vec::with_capacity(facets.len());
        for (f, fv) in facets.iter().enumerate() {
            if fv.vertices.len() != 3 || !(fv.measure > 0.0) {
                out.push(None);
                continue;
            }
            let mut ids = [0u32; 3];
            for (k, id) in ids.iter_mut().enumerate() {
                *id = *index.entry(key(f, k)).or_insert_with(|| {
                    area.push(0.0);
                    x.push(fv.vertices[k]);
                    (area.len() - 1) as u32
                });
                area[*id as usize] += fv.measure / 3.0;
            }
            out.push(Some((ids, [fv.vertices[0], fv.vertices[1], fv.vertices[2]])));
        }
        MasterWear { field: Mutex::new(vec![[0.0; 2]; area.len()]), area, facets: out, x, ..Default::default() }
    }

    /// A field on the mesh nodes of the cells that own the triangles `facets` (the `+` lip
    /// of a 3D crack), unworn: w(Y) = Σ_a N_a(Y) w_a over the nodes a of Y's cell, with
    /// the lumped areas A_a = ∫_lip N_a dA (3-point rule on each facet). The cut's own
    /// vertices are not used: a plane cutting tetrahedra leaves slivers whose vertices
    /// have tiny areas, and their depths would be the ratio of two small, noisy deposits;
    /// a mesh node's support on the lip is some 2h × 2h, wide against the slave points'
    /// spacing.
    pub fn cell_nodal(mesh: &crate::mesh::Mesh, facets: &[crate::cut::Facet]) -> Self {
        let mut index: HashMap<usize, u32> = HashMap::new();
        let (mut area, mut x) = (vec![], vec![]);
        let mut cells = Vec::with_capacity(facets.len());
        let mut nv = vec![0.0; 27];
        let mut dn = vec![[0.0; 3]; 27];
        for fv in facets {
            if fv.vertices.len() != 3 || fv.vertices_ref.len() != 3 || !(fv.measure > 0.0) || fv.cell >= mesh.n_cells()
            {
                cells.push(None);
                continue;
            }
            let cell = &mesh.cells[fv.cell];
            let ids: Vec<u32> = cell
                .nodes()
                .iter()
                .map(|&a| {
                    *index.entry(a).or_insert_with(|| {
                        area.push(0.0);
                        x.push(mesh.nodes[a]);
                        (area.len() - 1) as u32
                    })
                })
                .collect();
            let r = [fv.vertices_ref[0], fv.vertices_ref[1], fv.vertices_ref[2]];
            for b in [
                [2.0 / 3.0, 1.0 / 6.0, 1.0 / 6.0],
                [1.0 / 6.0, 2.0 / 3.0, 1.0 / 6.0],
                [1.0 / 6.0, 1.0 / 6.0, 2.0 / 3.0],
            ] {
                let xi: [f64; 3] = std::array::from_fn(|i| b[0] * r[0][i] + b[1] * r[1][i] + b[2] * r[2][i]);
                crate::element::shape(cell.kind, &xi, &mut nv[..ids.len()], &mut dn[..ids.len()]);
                for (k, &id) in ids.iter().enumerate() {
                    area[id as usize] += fv.measure / 3.0 * nv[k];
                }
            }
            cells.push(Some((cell.kind, ids, r)));
        }
        MasterWear { field: Mutex::new(vec![[0.0; 2]; area.len()]), area, cells, x, ..Default::default() }
    }

    /// The entries and weights of the field at master point `m` (3D), summing to 1;
    /// empty for a facet outside the field.
    fn weights_at(&self, f: usize, y: [f64; 3], xi: [f64; 3], out: &mut Vec<(usize, f64)>) {
        out.clear();
        if let Some(Some((kind, ids, _))) = self.cells.get(f) {
            let mut nv = [0.0; 27];
            let mut dn = [[0.0; 3]; 27];
            crate::element::shape(*kind, &xi, &mut nv[..ids.len()], &mut dn[..ids.len()]);
            let sum: f64 = nv[..ids.len()].iter().map(|v| v.max(0.0)).sum();
            if sum > 0.0 {
                out.extend(ids.iter().zip(&nv).map(|(&id, &v)| (id as usize, v.max(0.0) / sum)));
            }
        } else if let Some(w) = self.weights(f, y) {
            out.extend_from_slice(&w);
        }
    }

    /// Whether the field is nodal (3D).
    pub fn is_nodal(&self) -> bool {
        !self.facets.is_empty() || !self.cells.is_empty()
    }

    /// Per entry, (depth before the last solved step, its increment).
    pub fn get(&self) -> Vec<[f64; 2]> {
        self.field.lock().map(|v| v.clone()).unwrap_or_default()
    }

    /// Per entry, the depth after the last solved step.
    pub fn now(&self) -> Vec<f64> {
        self.get().iter().map(|w| w[0] + w[1]).collect()
    }

    /// Per entry, its area (2D: the facet's length; 3D: the vertex's lumped area).
    pub fn areas(&self) -> &[f64] {
        &self.area
    }

    /// 3D: per entry, the vertex's position (empty in 2D).
    pub fn positions(&self) -> &[[f64; 3]] {
        &self.x
    }

    /// The worn volume of the field after the last solved step, Σ A_n w_n.
    pub fn volume(&self) -> f64 {
        self.now().iter().zip(&self.area).map(|(w, a)| w * a).sum()
    }

    /// 3D: the entries of master facet `f`'s vertices and their shape-function weights at
    /// `y` (barycentric, clamped to the facet, summing to 1); `None` for a facet outside
    /// the field.
    pub fn weights(&self, f: usize, y: [f64; 3]) -> Option<[(usize, f64); 3]> {
        let (ids, v) = self.facets.get(f).copied().flatten()?;
        let b = super::facet_barycentric(&v, y);
        let mut c = [b[0].max(0.0), b[1].max(0.0), b[2].max(0.0)];
        let sum = c[0] + c[1] + c[2];
        if !(sum > 0.0) {
            c = [1.0 / 3.0; 3];
        } else {
            c.iter_mut().for_each(|x| *x /= sum);
        }
        Some([(ids[0] as usize, c[0]), (ids[1] as usize, c[1]), (ids[2] as usize, c[2])])
    }

    /// 3D: the depth after the last solved step at master point `m`, interpolated from the
    /// field's nodes (0 for a facet outside the field).
    pub fn read(&self, m: &super::pairing::MasterPoint) -> f64 {
        let mut w = Vec::with_capacity(8);
        self.weights_at(m.facet as usize, m.x, m.xi, &mut w);
        let Ok(field) = self.field.lock() else { return 0.0 };
        w.iter().map(|&(n, c)| c * (field[n][0] + field[n][1])).sum()
    }

    /// 3D: adds the worn volume `volume` left at master point `m` to the depth increments
    /// `step` (per entry): `volume`·N_n(Y)/A_n at each node n. Returns whether the facet is
    /// in the field.
    pub fn spread(&self, m: &super::pairing::MasterPoint, volume: f64, step: &mut [f64]) -> bool {
        let mut w = Vec::with_capacity(8);
        self.weights_at(m.facet as usize, m.x, m.xi, &mut w);
        for &(n, c) in &w {
            if self.area[n] > 0.0 {
                step[n] += volume * c / self.area[n];
            }
        }
        !w.is_empty()
    }

    /// 3D: the depths after the last solved step at master facet `f`'s vertices.
    pub fn vertex_depths(&self, f: usize) -> Option<[f64; 3]> {
        if let Some(Some((_, _, r))) = self.cells.get(f) {
            let field = self.field.lock().ok()?.clone();
            let mut w = Vec::with_capacity(8);
            let mut out = [0.0; 3];
            for (k, xi) in r.iter().enumerate() {
                self.weights_at(f, [0.0; 3], *xi, &mut w);
                out[k] = w.iter().map(|&(n, c)| c * (field[n][0] + field[n][1])).sum();
            }
            return Some(out);
        }
        let (ids, _) = self.facets.get(f).copied().flatten()?;
        let field = self.field.lock().ok()?;
        Some(ids.map(|n| field[n as usize][0] + field[n as usize][1]))
    }

    /// Back to unworn (the start of a run).
    pub fn reset(&self) {
        if let Ok(mut v) = self.field.lock() {
            v.iter_mut().for_each(|w| *w = [0.0; 2]);
        }
    }

    /// Ends a converged step: the last increment joins the depth and `step` (per entry)
    /// becomes the new increment.
    pub fn deposit(&self, step: &[f64]) {
        if let Ok(mut v) = self.field.lock() {
            for (w, &d) in v.iter_mut().zip(step) {
                *w = [w[0] + w[1], d];
            }
        }
    }

    pub fn len(&self) -> usize {
        self.area.len()
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
    /// Whether crack `cc` of `points` has a `+` lip wear met away from its own points: a
    /// crack with large sliding and wear, or a contact pair with wear (always paired). In
    /// 2D the remap of this chart serves it; in 3D the nodal [`MasterWear`] of the crack or
    /// pair does, and the chart holds nothing for it.
    pub fn applies(points: &ContactPoints, cc: usize) -> bool {
        let c = &points.cracks[cc];
        c.large_sliding && c.law.wear.is_some()
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
            // 3D: the `+` lip's or master face's field is nodal (`MasterWear::nodal`).
            if !Self::applies(points, ci) || points.dim != 2 {
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
