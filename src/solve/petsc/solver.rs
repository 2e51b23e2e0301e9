//! [`PetscSolver`]: one distributed matrix on the fixed pattern, its vectors and its `KSP`.
//!
//! `analyse` splits the equations into contiguous row blocks (one per rank), preallocates
//! the `MPIAIJ` matrix exactly (diagonal / off-diagonal block counts of each owned row,
//! PETSc's "new nonzero is an error" left on), builds the near null space and the `KSP`;
//! `factorize` inserts the owned rows of the new values and sets the preconditioner up
//! (GAMG's hierarchy, MUMPS's factorisation); `solve_in_place` solves, gathers the
//! solution on every rank and checks the residual ‖b − Ax‖/‖b‖ on the replicated values.
//!
//! Corrections of the contact loops (3D contact with the field split, an iterative
//! solve): the tolerance of a solve is `rtol` times the largest right-hand side since the
//! analysis, not times its own ([`CORRECTION_RTOL_CAP`]); a refill that leaves the split's
//! `u` block unchanged (small-sliding contact changes only the enriched unknowns and the
//! multipliers) keeps its GAMG set-up (`KSPSetReusePreconditioner` on the `u` KSP).
//!
//! Distributed assembly (`analyse_distributed`, `factorize_elements`): the row blocks and
//! their counts come from the layout (`assembly::layout::DistributedRows`), each element
//! matrix is added into the matrix as the assembly computes it (`MatSetValues`,
//! `ADD_VALUES`; PETSc's stash moves the entries of rows owned elsewhere), and the
//! residual is PETSc's `MatMult`: no rank holds a pattern or a value array.

use super::ffi::{self, check, PVec, PetscInt, IS, KSP, PC};
use super::{agree, initialize, insert_option_layers};
use crate::assembly::layout::DistributedRows;
use crate::solve::backend::{EquationPoints, LinearError, LinearMethod, LinearStats, PetscSettings, SystemStructure};
use std::ffi::CString;
use std::sync::Mutex;
use std::time::Instant;

/// The loosest relative tolerance of one solve of the 3D contact split. Its Newton
/// iterations solve for corrections whose right-hand side (the residual) shrinks to 1e-9
/// of the load's and below; each is solved to `rtol` times the largest right-hand side
/// since the analysis (the load's scale, `State::b_ref`), i.e. to the absolute accuracy
/// of the first solve, which the sum of the corrections keeps; relative to its own
/// right-hand side at most this loose. A correction of relative size 1e-6 then takes the
/// GMRES iterations of a 1e-4 reduction instead of 1e-10 (`docs/performance.md`, "PETSc
/// backend: the 3D penny with contact at 1 M unknowns").
pub const CORRECTION_RTOL_CAP: f64 = 1e-4;

/// MUMPS's workspace relaxation (`ICNTL(14)`, percent over the analysis's estimate) for
/// saddle points (systems with multipliers), instead of MUMPS's default (20 to 35 by the
/// number of processes). The 3D penny with contact of `tests/petsc_backend.rs` factorised
/// whole by MUMPS on 4 ranks failed with INFOG(1) = −9 (workspace too small: 83 109
/// entries short on one rank) on 6 of 11 runs with the default, on none of 6 with 100, for
/// 8% more peak memory per rank (115 → 124 MB; `docs/performance.md`, "PETSc backend on 4
/// ranks"). The options `-mat_mumps_icntl_14` and `-fieldsplit_e_mat_mumps_icntl_14`
/// override it.
pub const MUMPS_SADDLE_WORKSPACE_PERCENT: u32 = 100;

/// The PETSc objects of one solver. Raw pointers: used only under the solver's mutex, by
/// the thread that runs the solve.
struct Objects {
    a: ffi::Mat,
    ksp: KSP,
    b: PVec,
    x: PVec,
    scatter: ffi::VecScatter,
    all: PVec,
    is_u: IS,
    is_l: IS,
    /// The residual's work vector (distributed assembly).
    r: PVec,
}

// SAFETY: the objects are only touched through `PetscSolver`'s mutex, one call at a time.
unsafe impl Send for Objects {}

impl Drop for Objects {
    fn drop(&mut self) {
        // SAFETY: each pointer is null or a live object created in `analyse`; PETSc's
        // destroy functions accept null objects. After PetscFinalize nothing is destroyed.
        if super::SESSION.lock().ok().and_then(|s| s.as_ref().map(|s| s.finalized)).unwrap_or(true) {
            return;
        }
        unsafe {
            ffi::KSPDestroy(&mut self.ksp);
            ffi::MatDestroy(&mut self.a);
            ffi::VecDestroy(&mut self.b);
            ffi::VecDestroy(&mut self.x);
            ffi::VecScatterDestroy(&mut self.scatter);
            ffi::VecDestroy(&mut self.all);
            ffi::ISDestroy(&mut self.is_u);
            ffi::ISDestroy(&mut self.is_l);
            ffi::VecDestroy(&mut self.r);
        }
    }
}

/// What changes between calls: the objects, the values (for the residual check), the
/// figures of the last solve.
struct State {
    obj: Objects,
    values: Vec<f64>,
    factorized: bool,
    /// The matrix holds values (a refill zeroes it first).
    filled: bool,
    last_residual: f64,
    /// ‖b‖ of the last solve over the tolerance's scale (`b_ref`), as `last_residual`.
    last_rhs: f64,
    last_iterations: usize,
    numeric_s: f64,
    solve_s: f64,
    /// The largest right-hand-side norm since the analysis (the scale of the corrections'
    /// tolerance, [`CORRECTION_RTOL_CAP`]).
    b_ref: f64,
    /// The preconditioner has been set up once (the field split's KSPs exist).
    set_up_once: bool,
    /// Distributed assembly with contact ([`PetscSolver::set_bulk_elements`]): the K of
    /// the contact rows, kept to restore them before each refill of the contact terms.
    kept: KeptRows,
    /// The largest |K_jj| over the primal equations (distributed assembly with contact).
    bulk_diag_max: f64,
    /// Incremented at every [`PetscSolver::set_bulk_elements`]; its value at the last
    /// set-up, and whether the contact terms of that set-up left the `u` block alone.
    bulk_generation: u64,
    set_up_generation: u64,
    u_clean_last: bool,
    /// Every rank's peak resident memory (`VmHWM`, KiB) at the end of the last solve.
    peak_rss_kib: Vec<u64>,
}

/// The rows of K that the contact terms change (distributed assembly with contact): the
/// equations of the contact elements' dofs (`rows`, every rank's list), and this rank's
/// rows among them as K had them (compressed rows: the row, its columns and values).
#[derive(Default)]
struct KeptRows {
    valid: bool,
    rows: Vec<usize>,
    row: Vec<PetscInt>,
    ptr: Vec<usize>,
    cols: Vec<PetscInt>,
    vals: Vec<f64>,
}

/// Adds every element matrix `fill` hands over into `a` (`ADD_VALUES`, eliminated rows and
/// columns passed as −1, which PETSc skips), each checked for non-finite entries first;
/// with `u_rows`, also says whether some nonzero entry couples two equations of the
/// split's `u` block. A failure on one rank fails on every rank. Collective.
fn add_elements(
    a: ffi::Mat,
    fill: &mut crate::assembly::layout::ElementFill<'_>,
    u_rows: Option<&[bool]>,
) -> Result<bool, LinearError> {
    let mut bad: Option<LinearError> = None;
    let mut failed: Option<String> = None;
    let mut idx: Vec<PetscInt> = vec![];
    let mut touches_u = false;
    fill(&mut |eqs: &[u32], ke: &[f64]| {
        if bad.is_some() || failed.is_some() {
            return;
        }
        let m = eqs.len();
        if let Some(k) = ke.iter().position(|v| !v.is_finite()) {
            let (row, col) = (eqs[k / m], eqs[k % m]);
            if row != crate::assembly::NO_EQ && col != crate::assembly::NO_EQ {
                bad = Some(LinearError::NonFiniteMatrix { row: row as usize, col: col as usize, value: ke[k] });
                return;
            }
        }
        if let (Some(u), false) = (u_rows, touches_u) {
            let in_u = |q: u32| q != crate::assembly::NO_EQ && u.get(q as usize).copied().unwrap_or(false);
            touches_u = (0..m).any(|i| in_u(eqs[i]) && (0..m).any(|j| in_u(eqs[j]) && ke[i * m + j] != 0.0));
        }
        idx.clear();
        idx.extend(eqs.iter().map(|&q| if q == crate::assembly::NO_EQ { -1 } else { q as PetscInt }));
        // SAFETY: `m` row and column indices and `m × m` values, row-major (PETSc's
        // default orientation).
        if let Err(e) = check("MatSetValues", unsafe {
            ffi::MatSetValues(a, m as PetscInt, idx.as_ptr(), m as PetscInt, idx.as_ptr(), ke.as_ptr(), ffi::ADD_VALUES)
        }) {
            failed = Some(e);
        }
    });
    let local: Result<(), LinearError> = match (bad, failed) {
        (Some(e), _) => Err(e),
        (None, Some(e)) => Err(LinearError::Petsc(format!(
            "{e} (an element entry outside the preallocated pattern of the distributed matrix?)"
        ))),
        (None, None) => Ok(()),
    };
    let agreed = agree(local.clone().map_err(|e| e.to_string()));
    local?;
    agreed.map_err(petsc_err)?;
    Ok(touches_u)
}

/// Puts the kept rows of K back into `a` (`INSERT_VALUES`, this rank's own rows).
fn restore_kept(a: ffi::Mat, kept: &KeptRows) -> Result<(), LinearError> {
    // SAFETY: one owned row at a time, its columns and values.
    let done: Result<(), String> = (|| unsafe {
        for (i, row) in kept.row.iter().enumerate() {
            let r = kept.ptr[i]..kept.ptr[i + 1];
            check(
                "MatSetValues",
                ffi::MatSetValues(
                    a,
                    1,
                    row,
                    r.len() as PetscInt,
                    kept.cols[r.clone()].as_ptr(),
                    kept.vals[r].as_ptr(),
                    ffi::INSERT_VALUES,
                ),
            )?;
        }
        Ok(())
    })();
    agree(done).map_err(petsc_err)
}

/// `MatAssemblyBegin` and `MatAssemblyEnd` of `kind`, agreed over the ranks. Collective.
fn assemble(a: ffi::Mat, kind: std::os::raw::c_int) -> Result<(), LinearError> {
    // SAFETY: a live matrix; collective calls made by every rank.
    let done: Result<(), String> = (|| unsafe {
        check("MatAssemblyBegin", ffi::MatAssemblyBegin(a, kind))?;
        check("MatAssemblyEnd", ffi::MatAssemblyEnd(a, kind))
    })();
    agree(done).map_err(petsc_err)
}

/// The operators of `ksp` set to `a` and its preconditioner set up; with `reuse_u`, the
/// field split's `u` KSP (when the PC is a field split) told to keep (`true`) or redo
/// (`false`) its set-up (`KSPSetReusePreconditioner`). Collective.
fn set_up_preconditioner(ksp: KSP, a: ffi::Mat, reuse_u: Option<bool>) -> Result<(), String> {
    // SAFETY: live objects; collective calls made by every rank.
    unsafe {
        check("KSPSetOperators", ffi::KSPSetOperators(ksp, a, a))?;
        if let Some(reuse) = reuse_u {
            let mut pc: PC = std::ptr::null_mut();
            let mut name: *const std::os::raw::c_char = std::ptr::null();
            check("KSPGetPC", ffi::KSPGetPC(ksp, &mut pc))?;
            check("PCGetType", ffi::PCGetType(pc, &mut name))?;
            if type_name(name) == "fieldsplit" {
                let mut count: PetscInt = 0;
                let mut subs: *mut KSP = std::ptr::null_mut();
                check("PCFieldSplitGetSubKSP", ffi::PCFieldSplitGetSubKSP(pc, &mut count, &mut subs))?;
                let flag = if reuse { ffi::PETSC_TRUE } else { ffi::PETSC_FALSE };
                let reused = if count > 0 && !subs.is_null() {
                    check("KSPSetReusePreconditioner", ffi::KSPSetReusePreconditioner(*subs, flag))
                } else {
                    Ok(())
                };
                if let (Some(free), false) = (ffi::PetscTrFree, subs.is_null()) {
                    free(subs.cast(), 0, cstr("factorize").as_ptr(), cstr(file!()).as_ptr());
                }
                reused?;
            }
        }
        check("KSPSetUp", ffi::KSPSetUp(ksp)).map_err(|e| format!("the preconditioner's set-up (KSPSetUp) failed: {e}"))
    }
}

/// The PETSc backend: a `MPIAIJ` matrix on the analysed pattern, filled row block by row
/// block, and a `KSP` (see the module doc of [`super`]).
pub struct PetscSolver {
    method: LinearMethod,
    n: usize,
    n_primal: usize,
    /// The pattern in compressed columns (for the residual check).
    col_ptr: Vec<usize>,
    row_idx: Vec<usize>,
    /// This rank's rows `lo..hi`.
    lo: usize,
    hi: usize,
    /// Per owned row (`row_ptr[r - lo]..`): the columns and the positions of the entries
    /// in the value array.
    row_ptr: Vec<usize>,
    cols: Vec<PetscInt>,
    positions: Vec<usize>,
    /// Distributed assembly: the element matrices are added into the matrix by
    /// [`Self::factorize_elements`] (no pattern, no values here), and the residual is
    /// computed by PETSc.
    distributed: bool,
    /// The KSP's relative tolerance after the options; with `scaled_tolerance` relative to
    /// the largest right-hand side since the analysis ([`CORRECTION_RTOL_CAP`]).
    rtol: f64,
    scaled_tolerance: bool,
    /// The equations of the split's `u` block (3D contact split, replicated values; empty
    /// otherwise): a refill that leaves its values unchanged keeps its GAMG set-up.
    u_rows: Vec<bool>,
    symbolic_s: f64,
    state: Mutex<State>,
}

fn petsc_err(e: String) -> LinearError {
    LinearError::Petsc(e)
}

fn cstr(s: &str) -> CString {
    CString::new(s).unwrap_or_default()
}

/// The name PETSc reports for a KSP or PC type.
fn type_name(p: *const std::os::raw::c_char) -> String {
    if p.is_null() {
        return String::new();
    }
    // SAFETY: a NUL-terminated type name owned by the PETSc object.
    unsafe { std::ffi::CStr::from_ptr(p) }.to_string_lossy().into_owned()
}

/// The rigid-body modes of the standard unknowns (translations, then rotations about the
/// centroid of the points), zero on the enriched unknowns and the multipliers, for the
/// equations `0..m`; orthonormalised (modified Gram–Schmidt). `component[q]` is the
/// displacement component of a standard equation, `u8::MAX` for the others.
pub(super) fn rigid_modes(points: &EquationPoints<'_>, component: &[u8], m: usize) -> Vec<Vec<f64>> {
    let dim = points.dim;
    let mut centre = [0.0; 3];
    let mut count: f64 = 0.0;
    for &p in points.point_of_eq.iter().take(m) {
        if p != crate::solve::backend::NO_POINT {
            let c = points.coords[p as usize];
            for k in 0..3 {
                centre[k] += c[k];
            }
            count += 1.0;
        }
    }
    for c in &mut centre {
        *c /= count.max(1.0);
    }
    let n_modes = if dim == 2 { 3 } else { 6 };
    let mut modes = vec![vec![0.0; m]; n_modes];
    for q in 0..m {
        let c = component.get(q).copied().unwrap_or(u8::MAX) as usize;
        let p = points.point_of_eq.get(q).copied().unwrap_or(crate::solve::backend::NO_POINT);
        if c >= dim || p == crate::solve::backend::NO_POINT {
            continue;
        }
        let xp = points.coords[p as usize];
        let x = [xp[0] - centre[0], xp[1] - centre[1], xp[2] - centre[2]];
        modes[c][q] = 1.0;
        if dim == 2 {
            // Rotation about z: (−y, x).
            modes[2][q] = if c == 0 { -x[1] } else { x[0] };
        } else {
            // Rotations about x (0, −z, y), y (z, 0, −x), z (−y, x, 0).
            let r = [[0.0, -x[2], x[1]], [x[2], 0.0, -x[0]], [-x[1], x[0], 0.0]];
            for (k, rk) in r.iter().enumerate() {
                modes[3 + k][q] = rk[c];
            }
        }
    }
    let mut out: Vec<Vec<f64>> = vec![];
    for mut v in modes {
        for u in &out {
            let d: f64 = v.iter().zip(u).map(|(a, b)| a * b).sum();
            v.iter_mut().zip(u).for_each(|(a, b)| *a -= d * b);
        }
        let norm = v.iter().map(|a| a * a).sum::<f64>().sqrt();
        if norm > 1e-12 * (m as f64).sqrt() {
            v.iter_mut().for_each(|a| *a /= norm);
            out.push(v);
        }
    }
    out
}

impl PetscSolver {
    /// Symbolic phase: the row blocks, the preallocated matrix, the vectors, the near null
    /// space (rigid-body modes of `components`, given with the points) and the `KSP` with
    /// its options. Collective: every rank calls it with the same arguments.
    pub fn analyse(
        system: &SystemStructure<'_>,
        settings: &PetscSettings,
        components: Option<&[u8]>,
    ) -> Result<PetscSolver, LinearError> {
        Self::analyse_mode(system, settings, components, None)
    }

    /// [`Self::analyse`] for distributed assembly: `system.pattern` is empty (only its
    /// size counts); this rank owns the equations `rows.rows`, and the matrix is
    /// preallocated from the layout's exact counts of their columns inside and outside the
    /// block (`rows.d_nnz`, `rows.o_nnz`). The values come through
    /// [`Self::factorize_elements`]. Collective.
    pub fn analyse_distributed(
        system: &SystemStructure<'_>,
        settings: &PetscSettings,
        components: Option<&[u8]>,
        rows: &DistributedRows,
    ) -> Result<PetscSolver, LinearError> {
        Self::analyse_mode(system, settings, components, Some(rows))
    }

    fn analyse_mode(
        system: &SystemStructure<'_>,
        settings: &PetscSettings,
        components: Option<&[u8]>,
        owned: Option<&DistributedRows>,
    ) -> Result<PetscSolver, LinearError> {
        let distributed = owned.is_some();
        let clock = Instant::now();
        let (rank, size) = initialize().map_err(petsc_err)?;
        let pattern = system.pattern;
        let n = pattern.n;
        if system.n_primal > n {
            return Err(LinearError::InvalidPrimalCount { n_primal: system.n_primal, n });
        }
        if system.method == LinearMethod::Cholesky && system.n_primal < n {
            return Err(LinearError::CholeskyWithMultipliers { n_multipliers: n - system.n_primal });
        }
        let nnz = owned.map_or(pattern.nnz(), |o| o.nnz_total);
        if n > PetscInt::MAX as usize || nnz > PetscInt::MAX as usize {
            return Err(LinearError::Petsc(format!(
                "{n} unknowns and {nnz} entries exceed this PETSc's 32-bit indices (build PETSc with \
                 --with-64-bit-indices)"
            )));
        }
        let (lo, hi) = match owned {
            Some(o) if o.rows.end <= n && o.d_nnz.len() == o.rows.len() && o.o_nnz.len() == o.rows.len() => {
                (o.rows.start, o.rows.end)
            }
            Some(o) => {
                return Err(LinearError::Internal(format!(
                    "distributed rows {:?} with {} and {} counts for {n} equations",
                    o.rows,
                    o.d_nnz.len(),
                    o.o_nnz.len()
                )))
            }
            None => (n * rank / size, n * (rank + 1) / size),
        };
        // The owned rows in compressed rows, columns ascending within a row (replicated
        // assembly only; empty with distributed assembly).
        let rows_here = if distributed { 0 } else { hi - lo };
        let mut row_ptr = vec![0usize; rows_here + 1];
        for j in (0..n).filter(|_| !distributed) {
            for &i in &pattern.row_idx[pattern.col_ptr[j]..pattern.col_ptr[j + 1]] {
                if (lo..hi).contains(&i) {
                    row_ptr[i - lo + 1] += 1;
                }
            }
        }
        for r in 0..rows_here {
            row_ptr[r + 1] += row_ptr[r];
        }
        let mut next = row_ptr.clone();
        let mut cols = vec![0 as PetscInt; row_ptr[rows_here]];
        let mut positions = vec![0usize; row_ptr[rows_here]];
        for j in (0..n).filter(|_| !distributed) {
            for k in pattern.col_ptr[j]..pattern.col_ptr[j + 1] {
                let i = pattern.row_idx[k];
                if (lo..hi).contains(&i) {
                    let at = next[i - lo];
                    cols[at] = j as PetscInt;
                    positions[at] = k;
                    next[i - lo] += 1;
                }
            }
        }
        let (d_nnz, o_nnz) = match owned {
            Some(o) => (
                o.d_nnz.iter().map(|&c| c as PetscInt).collect::<Vec<_>>(),
                o.o_nnz.iter().map(|&c| c as PetscInt).collect::<Vec<_>>(),
            ),
            None => {
                let mut d_nnz = vec![0 as PetscInt; rows_here];
                let mut o_nnz = vec![0 as PetscInt; rows_here];
                for r in 0..rows_here {
                    for &c in &cols[row_ptr[r]..row_ptr[r + 1]] {
                        if (lo..hi).contains(&(c as usize)) {
                            d_nnz[r] += 1;
                        } else {
                            o_nnz[r] += 1;
                        }
                    }
                }
                (d_nnz, o_nnz)
            }
        };
        let local = (hi - lo) as PetscInt;
        // Node blocks (distributed layouts whose equations keep them): GAMG aggregates
        // nodes, its strength graph has a vertex per node instead of per component.
        let block = owned.map_or(1, |o| o.block).max(1);
        let mut obj = Objects {
            a: std::ptr::null_mut(),
            ksp: std::ptr::null_mut(),
            b: std::ptr::null_mut(),
            x: std::ptr::null_mut(),
            scatter: std::ptr::null_mut(),
            all: std::ptr::null_mut(),
            is_u: std::ptr::null_mut(),
            is_l: std::ptr::null_mut(),
            r: std::ptr::null_mut(),
        };
        // SAFETY (whole block): every call receives live objects created just above and
        // arrays of the lengths PETSc expects (the owned rows' counts).
        let comm = unsafe { ffi::PETSC_COMM_WORLD };
        let built: Result<(), String> = (|| unsafe {
            check("MatCreate", ffi::MatCreate(comm, &mut obj.a))?;
            check("MatSetSizes", ffi::MatSetSizes(obj.a, local, local, n as PetscInt, n as PetscInt))?;
            check("MatSetType", ffi::MatSetType(obj.a, cstr("aij").as_ptr()))?;
            if block > 1 {
                check("MatSetBlockSize", ffi::MatSetBlockSize(obj.a, block as PetscInt))?;
            }
            check("MatSeqAIJSetPreallocation", ffi::MatSeqAIJSetPreallocation(obj.a, 0, d_nnz.as_ptr()))?;
            check(
                "MatMPIAIJSetPreallocation",
                ffi::MatMPIAIJSetPreallocation(obj.a, 0, d_nnz.as_ptr(), 0, o_nnz.as_ptr()),
            )?;
            check("MatSetOption", ffi::MatSetOption(obj.a, ffi::MAT_NEW_NONZERO_ALLOCATION_ERR, ffi::PETSC_TRUE))?;
            check("VecCreateMPI", ffi::VecCreateMPI(comm, local, n as PetscInt, &mut obj.b))?;
            check("VecCreateMPI", ffi::VecCreateMPI(comm, local, n as PetscInt, &mut obj.x))?;
            check("VecScatterCreateToAll", ffi::VecScatterCreateToAll(obj.x, &mut obj.scatter, &mut obj.all))?;
            check("VecDuplicate", ffi::VecDuplicate(obj.b, &mut obj.r))?;
            Ok(())
        })();
        agree(built).map_err(petsc_err)?;
        drop((d_nnz, o_nnz));

        // The near null space: on the whole matrix without multipliers, on the primal
        // block (the field split's "u") with them. Without multipliers but with enriched
        // unknowns, the field split (when asked for) separates the standard unknowns "u"
        // from the enriched ones "e", and "u" gets the modes too.
        let n_primal = system.n_primal;
        let modes = match (system.points, components) {
            (Some(points), Some(component)) => rigid_modes(points, component, n_primal),
            _ => vec![],
        };
        let enriched = |q: usize| components.is_some_and(|c| c.get(q).copied().unwrap_or(u8::MAX) == u8::MAX);
        // With enriched unknowns the split is standard "u" / the rest "e": the enriched
        // unknowns, and in 3D the multipliers if any (contact couples the multipliers to
        // the jumps, which the enriched unknowns alone carry, so "u" is plain elasticity
        // and the whole saddle point sits in "e"). 2D saddle points keep the split
        // displacements "u" / multipliers "l".
        let dim = system.points.map_or(0, |p| p.dim);
        let split_enriched = components.is_some() && (n_primal == n || dim == 3) && (0..n_primal).any(enriched);
        // Index sets of the field split: owned standard (primal) rows, owned enriched and
        // multiplier (multiplier) rows.
        let (owned_u, owned_l): (Vec<PetscInt>, Vec<PetscInt>) = if split_enriched {
            let (u, e): (Vec<usize>, Vec<usize>) = (lo..hi).partition(|&q| !enriched(q));
            (u.into_iter().map(|i| i as PetscInt).collect(), e.into_iter().map(|i| i as PetscInt).collect())
        } else {
            (
                (lo..hi.min(n_primal)).map(|i| i as PetscInt).collect(),
                (lo.max(n_primal)..hi.max(n_primal)).map(|i| i as PetscInt).collect(),
            )
        };
        let n_u = if split_enriched { (0..n).filter(|&q| !enriched(q)).count() } else { n_primal };
        let u_rows: Vec<bool> =
            if split_enriched && n_primal < n { (0..n).map(|q| !enriched(q)).collect() } else { vec![] };
        let nullspace: Result<(), String> = (|| unsafe {
            if n_primal < n || split_enriched {
                for (owned, is) in [(&owned_u, &mut obj.is_u), (&owned_l, &mut obj.is_l)] {
                    check(
                        "ISCreateGeneral",
                        ffi::ISCreateGeneral(comm, owned.len() as PetscInt, owned.as_ptr(), ffi::PETSC_COPY_VALUES, is),
                    )?;
                    if block > 1 {
                        check("ISSetBlockSize", ffi::ISSetBlockSize(*is, block as PetscInt))?;
                    }
                }
            }
            if modes.is_empty() {
                return Ok(());
            }
            // (rows of the vectors, their global size, attach to the "u" index set?)
            let mut targets: Vec<(&[PetscInt], usize, bool)> = vec![];
            if n_primal < n || split_enriched {
                targets.push((&owned_u, n_u, true));
            }
            if n_primal == n {
                let all: &[PetscInt] = &[];
                targets.push((all, n, false));
            }
            for (rows, global, on_is) in targets {
                let local = if on_is { rows.len() } else { hi - lo };
                let mut vecs: Vec<PVec> = vec![];
                for mode in &modes {
                    let mut v: PVec = std::ptr::null_mut();
                    check("VecCreateMPI", ffi::VecCreateMPI(comm, local as PetscInt, global as PetscInt, &mut v))?;
                    let mut a: *mut f64 = std::ptr::null_mut();
                    check("VecGetArray", ffi::VecGetArray(v, &mut a))?;
                    if local > 0 {
                        let out = std::slice::from_raw_parts_mut(a, local);
                        if on_is {
                            out.iter_mut().zip(rows).for_each(|(o, &q)| *o = mode[q as usize]);
                        } else {
                            out.copy_from_slice(&mode[lo..hi]);
                        }
                    }
                    check("VecRestoreArray", ffi::VecRestoreArray(v, &mut a))?;
                    vecs.push(v);
                }
                let mut space: ffi::MatNullSpace = std::ptr::null_mut();
                check(
                    "MatNullSpaceCreate",
                    ffi::MatNullSpaceCreate(comm, ffi::PETSC_FALSE, vecs.len() as PetscInt, vecs.as_ptr(), &mut space),
                )?;
                if on_is {
                    // PCFIELDSPLIT hands it to the "u" block's matrix.
                    check(
                        "PetscObjectCompose",
                        ffi::PetscObjectCompose(obj.is_u, cstr("nearnullspace").as_ptr(), space),
                    )?;
                } else {
                    check("MatSetNearNullSpace", ffi::MatSetNearNullSpace(obj.a, space))?;
                }
                check("MatNullSpaceDestroy", ffi::MatNullSpaceDestroy(&mut space))?;
                for v in &mut vecs {
                    check("VecDestroy", ffi::VecDestroy(v))?;
                }
            }
            Ok(())
        })();
        agree(nullspace).map_err(petsc_err)?;

        // The KSP: defaults, the case file's choices, then PETSc's options database.
        // With enriched unknowns, GAMG alone stalls (its aggregates know nothing of the
        // Heaviside and tip functions: 190 CG iterations on a 7 120-equation centre crack,
        // 10 000 without convergence at 1e5): CG with a symmetric block Gauss–Seidel field
        // split, GAMG on the standard unknowns (with the rigid-body modes), LU by MUMPS on
        // the enriched ones (24 and 45 iterations).
        // With multipliers (contact) and enriched unknowns in 3D: GMRES (right
        // preconditioned, so that its tolerance is on the true residual) with a
        // multiplicative split, GAMG on "u" and LU by MUMPS on "e" (the enriched unknowns
        // and the multipliers, the saddle point): the LU of the whole 3D system grows as n²
        // (docs/performance.md, "PETSc backend: the 3D penny crack with contact"). In 2D
        // the whole system's LU (n^1.5) stays the default: exact and cheap.
        let saddle_split = split_enriched && n_primal < n;
        let (default_ksp, default_pc) = match system.method {
            LinearMethod::Cholesky if split_enriched => ("cg", "fieldsplit"),
            LinearMethod::Cholesky => ("cg", "gamg"),
            _ if saddle_split => ("gmres", "fieldsplit"),
            _ => ("preonly", "lu"),
        };
        let ksp_type = settings.ksp.as_deref().unwrap_or(default_ksp);
        let pc_type = settings.pc.as_deref().unwrap_or(default_pc);
        let mut ksp_rtol = settings.rtol;
        let mut scaled_tolerance = false;
        let configured: Result<(), String> = (|| unsafe {
            check("KSPCreate", ffi::KSPCreate(comm, &mut obj.ksp))?;
            check("KSPSetOperators", ffi::KSPSetOperators(obj.ksp, obj.a, obj.a))?;
            check("KSPSetType", ffi::KSPSetType(obj.ksp, cstr(ksp_type).as_ptr()))
                .map_err(|e| format!("[solver.petsc] ksp = \"{ksp_type}\": {e}"))?;
            let mut pc: PC = std::ptr::null_mut();
            check("KSPGetPC", ffi::KSPGetPC(obj.ksp, &mut pc))?;
            check("PCSetType", ffi::PCSetType(pc, cstr(pc_type).as_ptr()))
                .map_err(|e| format!("[solver.petsc] pc = \"{pc_type}\": {e}"))?;
            // LU and Cholesky by MUMPS (distributed); a no-op for the other PCs.
            check("PCFactorSetMatSolverType", ffi::PCFactorSetMatSolverType(pc, cstr("mumps").as_ptr()))?;
            if split_enriched && pc_type == "fieldsplit" {
                // Defaults of the standard / enriched split, before the user's layers.
                let composite = if saddle_split {
                    ffi::PC_COMPOSITE_MULTIPLICATIVE
                } else {
                    ffi::PC_COMPOSITE_SYMMETRIC_MULTIPLICATIVE
                };
                check("PCFieldSplitSetType", ffi::PCFieldSplitSetType(pc, composite))?;
                super::insert_options(
                    "-fieldsplit_u_pc_type gamg -fieldsplit_e_pc_type lu -fieldsplit_e_pc_factor_mat_solver_type mumps",
                )?;
            }
            if n_primal < n {
                // MUMPS on a saddle point (the whole system's LU, or the split's "e" block
                // with the multipliers): its workspace is estimated at the analysis, and
                // the pivots delayed off the multipliers' zero diagonal can need more
                // (INFOG(1) = −9, "DIVERGED_PC_FAILED"). How many varies from run to run
                // of the same case (4 ranks; likely because the entries several ranks add
                // are summed in the order their messages arrive, so the values, hence the
                // pivots, differ in their last bits). A larger relaxation, before the
                // user's layers (they win).
                super::insert_options(&format!(
                    "-mat_mumps_icntl_14 {MUMPS_SADDLE_WORKSPACE_PERCENT} \
                     -fieldsplit_e_mat_mumps_icntl_14 {MUMPS_SADDLE_WORKSPACE_PERCENT}"
                ))?;
            }
            check(
                "KSPSetTolerances",
                ffi::KSPSetTolerances(
                    obj.ksp,
                    settings.rtol,
                    ffi::PETSC_DEFAULT as f64,
                    ffi::PETSC_DEFAULT as f64,
                    ffi::PETSC_DEFAULT,
                ),
            )?;
            insert_option_layers(&settings.options)?;
            check("KSPSetFromOptions", ffi::KSPSetFromOptions(obj.ksp))
                .map_err(|e| format!("PETSc rejected the solver options: {e}"))?;
            let mut kind: *const std::os::raw::c_char = std::ptr::null();
            check("KSPGetType", ffi::KSPGetType(obj.ksp, &mut kind))?;
            let has_option = |name: &str| -> Result<bool, String> {
                let mut set = ffi::PETSC_FALSE;
                check(
                    "PetscOptionsHasName",
                    ffi::PetscOptionsHasName(std::ptr::null_mut(), std::ptr::null(), cstr(name).as_ptr(), &mut set),
                )?;
                Ok(set != ffi::PETSC_FALSE)
            };
            if saddle_split {
                // LU chosen by the options (`-pc_type lu`) on a 3D contact system whose
                // default is the split: by MUMPS too (PETSc's own LU does not pivot, and
                // fails on the zero diagonal of the saddle point), unless the options name
                // the package.
                let mut pc: PC = std::ptr::null_mut();
                check("KSPGetPC", ffi::KSPGetPC(obj.ksp, &mut pc))?;
                if !has_option("-pc_factor_mat_solver_type")? {
                    check("PCFactorSetMatSolverType", ffi::PCFactorSetMatSolverType(pc, cstr("mumps").as_ptr()))?;
                }
            }
            if saddle_split && type_name(kind) == "gmres" {
                // Right preconditioning (the tolerance on the true residual) and a restart
                // longer than the iterations, unless the options chose otherwise.
                if !has_option("-ksp_pc_side")? {
                    check("KSPSetPCSide", ffi::KSPSetPCSide(obj.ksp, ffi::PC_RIGHT))?;
                }
                if !has_option("-ksp_gmres_restart")? {
                    check("KSPGMRESSetRestart", ffi::KSPGMRESSetRestart(obj.ksp, 200))?;
                }
            }
            let (mut abstol, mut dtol, mut maxits) = (0.0, 0.0, 0 as PetscInt);
            check(
                "KSPGetTolerances",
                ffi::KSPGetTolerances(obj.ksp, &mut ksp_rtol, &mut abstol, &mut dtol, &mut maxits),
            )?;
            scaled_tolerance = saddle_split && type_name(kind) != "preonly";
            let mut pc: PC = std::ptr::null_mut();
            check("KSPGetPC", ffi::KSPGetPC(obj.ksp, &mut pc))?;
            let mut name: *const std::os::raw::c_char = std::ptr::null();
            check("PCGetType", ffi::PCGetType(pc, &mut name))?;
            if type_name(name) == "gamg" && block > 1 && block == dim && !modes.is_empty() && n_primal == n {
                // Node blocks: GAMG builds the rigid-body modes of each node from its
                // coordinates, in its own array, instead of copying them from a near null
                // space of six distributed vectors that would stay alive beside it.
                let points = system.points.expect("modes come with points");
                let mut coords: Vec<f64> = Vec::with_capacity(hi - lo);
                for q in (lo..hi).step_by(block) {
                    let p = points.point_of_eq[q];
                    let x = if p == crate::solve::backend::NO_POINT { [0.0; 3] } else { points.coords[p as usize] };
                    coords.extend_from_slice(&x[..dim]);
                }
                check("MatSetNearNullSpace", ffi::MatSetNearNullSpace(obj.a, std::ptr::null_mut()))?;
                check(
                    "PCSetCoordinates",
                    ffi::PCSetCoordinates(pc, dim as PetscInt, ((hi - lo) / block) as PetscInt, coords.as_mut_ptr()),
                )?;
            }
            if type_name(name) == "fieldsplit" {
                if n_primal == n && !split_enriched {
                    return Err("pc = fieldsplit needs a system with multipliers (displacements \"u\" / \
                                multipliers \"l\") or enriched unknowns (standard \"u\" / enriched and \
                                multipliers \"e\"); this one has neither"
                        .into());
                }
                let second = if split_enriched { "e" } else { "l" };
                check("PCFieldSplitSetIS", ffi::PCFieldSplitSetIS(pc, cstr("u").as_ptr(), obj.is_u))?;
                check("PCFieldSplitSetIS", ffi::PCFieldSplitSetIS(pc, cstr(second).as_ptr(), obj.is_l))?;
            }
            Ok(())
        })();
        agree(configured).map_err(petsc_err)?;
        let state = State {
            obj,
            values: vec![],
            factorized: false,
            filled: false,
            last_residual: f64::NAN,
            last_rhs: f64::NAN,
            last_iterations: 0,
            numeric_s: 0.0,
            solve_s: 0.0,
            b_ref: 0.0,
            set_up_once: false,
            kept: KeptRows::default(),
            bulk_diag_max: 0.0,
            bulk_generation: 0,
            set_up_generation: 0,
            u_clean_last: false,
            peak_rss_kib: vec![],
        };
        Ok(PetscSolver {
            method: system.method,
            n,
            n_primal,
            col_ptr: if distributed { vec![] } else { pattern.col_ptr.clone() },
            row_idx: if distributed { vec![] } else { pattern.row_idx.clone() },
            lo,
            hi,
            row_ptr,
            cols,
            positions,
            distributed,
            rtol: ksp_rtol,
            scaled_tolerance,
            u_rows,
            symbolic_s: clock.elapsed().as_secs_f64(),
            state: Mutex::new(state),
        })
    }

    /// The KSP and PC types in use (after the options), e.g. `("cg", "gamg")`.
    pub fn types(&self) -> (String, String) {
        let Ok(st) = self.state.lock() else { return Default::default() };
        let (mut k, mut p): (*const std::os::raw::c_char, *const std::os::raw::c_char) =
            (std::ptr::null(), std::ptr::null());
        let mut pc: PC = std::ptr::null_mut();
        // SAFETY: a live KSP; the names are owned by the objects.
        unsafe {
            ffi::KSPGetType(st.obj.ksp, &mut k);
            ffi::KSPGetPC(st.obj.ksp, &mut pc);
            ffi::PCGetType(pc, &mut p);
        }
        (type_name(k), type_name(p))
    }

    /// Numeric phase: the owned rows of `values` into the matrix, assembly, and the
    /// preconditioner's set-up (GAMG hierarchy, MUMPS factorisation). Collective.
    pub fn factorize(&mut self, values: &[f64]) -> Result<(), LinearError> {
        let clock = Instant::now();
        let st = self.state.get_mut().map_err(|_| LinearError::Internal("poisoned PETSc state".into()))?;
        st.factorized = false;
        if self.distributed {
            return Err(LinearError::Internal(
                "a solver of distributed assembly takes its values element by element (factorize_elements)".into(),
            ));
        }
        let nnz = self.row_idx.len();
        if values.len() != nnz {
            return Err(LinearError::LengthMismatch { what: "value array", expected: nnz, got: values.len() });
        }
        // Replicated values: every rank finds the same entry.
        if let Some(k) = values.iter().position(|v| !v.is_finite()) {
            let col = self.col_ptr.partition_point(|&p| p <= k) - 1;
            return Err(LinearError::NonFiniteMatrix { row: self.row_idx[k], col, value: values[k] });
        }
        // The split's `u` block (the standard unknowns: the uncracked body's stiffness) as
        // at the last set-up: its GAMG hierarchy is kept (exactly the same preconditioner).
        let u_same = st.set_up_once
            && !self.u_rows.is_empty()
            && st.values.len() == nnz
            && (0..self.n).filter(|&j| self.u_rows[j]).all(|j| {
                (self.col_ptr[j]..self.col_ptr[j + 1])
                    .all(|k| !self.u_rows[self.row_idx[k]] || values[k].to_bits() == st.values[k].to_bits())
            });
        let a = st.obj.a;
        let inserted: Result<(), String> = (|| {
            let mut buf = vec![];
            for r in 0..self.hi - self.lo {
                let range = self.row_ptr[r]..self.row_ptr[r + 1];
                buf.clear();
                buf.extend(self.positions[range.clone()].iter().map(|&k| values[k]));
                let row = (self.lo + r) as PetscInt;
                // SAFETY: one row, `buf.len()` columns and values.
                check("MatSetValues", unsafe {
                    ffi::MatSetValues(
                        a,
                        1,
                        &row,
                        buf.len() as PetscInt,
                        self.cols[range].as_ptr(),
                        buf.as_ptr(),
                        ffi::INSERT_VALUES,
                    )
                })?;
            }
            Ok(())
        })();
        agree(inserted).map_err(petsc_err)?;
        assemble(a, ffi::MAT_FINAL_ASSEMBLY)?;
        let reuse_u = (st.set_up_once && !self.u_rows.is_empty()).then_some(u_same);
        agree(set_up_preconditioner(st.obj.ksp, a, reuse_u)).map_err(petsc_err)?;
        st.set_up_once = true;
        st.values.clear();
        st.values.extend_from_slice(values);
        st.factorized = true;
        st.filled = true;
        st.numeric_s = clock.elapsed().as_secs_f64();
        Ok(())
    }

    /// Numeric phase of distributed assembly: `fill` hands this rank's element matrices
    /// to the sink it is given (the element's equations, `NO_EQ` for eliminated dofs, and
    /// its values row-major), each added into the matrix at once (`MatSetValues`,
    /// `ADD_VALUES`, eliminated rows and columns passed as −1, which PETSc skips); then the
    /// assembly (the stash's entries to their owners) and the preconditioner's set-up. A
    /// refill (a second call) zeroes the matrix first, keeping its nonzero structure. A
    /// non-finite entry or an entry outside the preallocation fails on every rank.
    /// Collective.
    pub fn factorize_elements(
        &mut self,
        fill: &mut crate::assembly::layout::ElementFill<'_>,
    ) -> Result<(), LinearError> {
        let st = self.state.get_mut().map_err(|_| LinearError::Internal("poisoned PETSc state".into()))?;
        if !self.distributed {
            return Err(LinearError::Internal("factorize_elements needs a solver of distributed assembly".into()));
        }
        st.factorized = false;
        let a = st.obj.a;
        // SAFETY: a live matrix; collective.
        let zeroed = if st.filled { check("MatZeroEntries", unsafe { ffi::MatZeroEntries(a) }) } else { Ok(()) };
        agree(zeroed).map_err(petsc_err)?;
        st.filled = true;
        add_elements(a, fill, None)?;
        assemble(a, ffi::MAT_FINAL_ASSEMBLY)?;
        let set_up_clock = Instant::now();
        // SAFETY: as above.
        let set_up: Result<(), String> = (|| unsafe {
            check("KSPSetOperators", ffi::KSPSetOperators(st.obj.ksp, a, a))?;
            check("KSPSetUp", ffi::KSPSetUp(st.obj.ksp))
                .map_err(|e| format!("the preconditioner's set-up (KSPSetUp) failed: {e}"))
        })();
        agree(set_up).map_err(petsc_err)?;
        st.factorized = true;
        st.numeric_s = set_up_clock.elapsed().as_secs_f64();
        Ok(())
    }

    /// Distributed assembly with contact, the bulk: the matrix zeroed (a refill) and every
    /// element matrix of `fill` (this rank's elements of the fixed kernels: K) added into
    /// it, then assembled; no preconditioner set-up (the contact terms come first,
    /// [`Self::refill_contact`]). Records the largest |K_jj| of the primal equations
    /// ([`Self::bulk_diagonal_max`]) and forgets the kept contact rows. Collective.
    pub fn set_bulk_elements(
        &mut self,
        fill: &mut crate::assembly::layout::ElementFill<'_>,
    ) -> Result<(), LinearError> {
        let st = self.state.get_mut().map_err(|_| LinearError::Internal("poisoned PETSc state".into()))?;
        if !self.distributed {
            return Err(LinearError::Internal("set_bulk_elements needs a solver of distributed assembly".into()));
        }
        st.factorized = false;
        let a = st.obj.a;
        // SAFETY: a live matrix; collective.
        let zeroed = if st.filled { check("MatZeroEntries", unsafe { ffi::MatZeroEntries(a) }) } else { Ok(()) };
        agree(zeroed).map_err(petsc_err)?;
        st.filled = true;
        add_elements(a, fill, None)?;
        assemble(a, ffi::MAT_FINAL_ASSEMBLY)?;
        let (lo, hi, n_primal) = (self.lo, self.hi, self.n_primal);
        let mut local_max = 0.0f64;
        // SAFETY: live objects; the diagonal vector has the owned length `hi − lo`.
        let diagonal: Result<(), String> = (|| unsafe {
            check("MatGetDiagonal", ffi::MatGetDiagonal(a, st.obj.r))?;
            let mut d: *const f64 = std::ptr::null();
            check("VecGetArrayRead", ffi::VecGetArrayRead(st.obj.r, &mut d))?;
            if hi > lo {
                let d = std::slice::from_raw_parts(d, hi - lo);
                local_max = (lo..hi.min(n_primal)).map(|q| d[q - lo].abs()).fold(0.0, f64::max);
            }
            check("VecRestoreArrayRead", ffi::VecRestoreArrayRead(st.obj.r, &mut d))
        })();
        agree(diagonal).map_err(petsc_err)?;
        st.bulk_diag_max = super::max_over_ranks(local_max);
        st.kept = KeptRows::default();
        st.bulk_generation += 1;
        Ok(())
    }

    /// Distributed assembly with contact: keeps this rank's rows of K among `rows` (the
    /// equations of the contact elements' dofs, the same list on every rank), which the
    /// contact terms change, so that [`Self::refill_contact`] can restore them and
    /// [`Self::bulk_product`] multiply by K. A list already kept is kept; another one puts
    /// the old rows back first (the matrix is K again and needs a refill before a solve).
    /// Collective.
    pub fn keep_bulk_rows(&mut self, rows: &[usize]) -> Result<(), LinearError> {
        let st = self.state.get_mut().map_err(|_| LinearError::Internal("poisoned PETSc state".into()))?;
        if !self.distributed || !st.filled {
            return Err(LinearError::Internal("keep_bulk_rows needs the bulk of a distributed matrix".into()));
        }
        if st.kept.valid && st.kept.rows == rows {
            return Ok(());
        }
        let a = st.obj.a;
        if st.kept.valid {
            restore_kept(a, &st.kept)?;
            assemble(a, ffi::MAT_FINAL_ASSEMBLY)?;
            st.factorized = false;
        }
        let mut kept = KeptRows { valid: true, rows: rows.to_vec(), ptr: vec![0], ..Default::default() };
        // SAFETY: owned rows of an assembled matrix, one row gotten (and restored) at a time.
        let read: Result<(), String> = (|| unsafe {
            for &q in rows.iter().filter(|&&q| (self.lo..self.hi).contains(&q)) {
                let row = q as PetscInt;
                let mut nc: PetscInt = 0;
                let (mut cols, mut vals): (*const PetscInt, *const f64) = (std::ptr::null(), std::ptr::null());
                check("MatGetRow", ffi::MatGetRow(a, row, &mut nc, &mut cols, &mut vals))?;
                if nc > 0 {
                    kept.cols.extend_from_slice(std::slice::from_raw_parts(cols, nc as usize));
                    kept.vals.extend_from_slice(std::slice::from_raw_parts(vals, nc as usize));
                }
                check("MatRestoreRow", ffi::MatRestoreRow(a, row, &mut nc, &mut cols, &mut vals))?;
                kept.row.push(row);
                kept.ptr.push(kept.cols.len());
            }
            Ok(())
        })();
        agree(read).map_err(petsc_err)?;
        st.kept = kept;
        Ok(())
    }

    /// Distributed assembly with contact: `out` = K x on this rank's rows, zero on the
    /// others (`x` every equation's value, the same on every rank); the sum of `out` over
    /// the ranks is K x. The matrix holds K plus the contact terms of the last refill, which
    /// touch only the kept rows: those rows are multiplied from the kept K. Collective.
    pub fn bulk_product(&self, x: &[f64], out: &mut [f64]) -> Result<(), LinearError> {
        let st = self.state.lock().map_err(|_| LinearError::Internal("poisoned PETSc state".into()))?;
        if !self.distributed || x.len() != self.n || out.len() != self.n {
            return Err(LinearError::Internal(
                "bulk_product needs a distributed solver and vectors of its size".into(),
            ));
        }
        let (lo, hi, o) = (self.lo, self.hi, &st.obj);
        out.fill(0.0);
        // SAFETY: live objects; the arrays have the owned length `hi − lo`.
        let done: Result<(), String> = (|| unsafe {
            let mut arr: *mut f64 = std::ptr::null_mut();
            check("VecGetArray", ffi::VecGetArray(o.x, &mut arr))?;
            if hi > lo {
                std::slice::from_raw_parts_mut(arr, hi - lo).copy_from_slice(&x[lo..hi]);
            }
            check("VecRestoreArray", ffi::VecRestoreArray(o.x, &mut arr))?;
            check("MatMult", ffi::MatMult(o.a, o.x, o.r))?;
            let mut y: *const f64 = std::ptr::null();
            check("VecGetArrayRead", ffi::VecGetArrayRead(o.r, &mut y))?;
            if hi > lo {
                out[lo..hi].copy_from_slice(std::slice::from_raw_parts(y, hi - lo));
            }
            check("VecRestoreArrayRead", ffi::VecRestoreArrayRead(o.r, &mut y))
        })();
        agree(done).map_err(petsc_err)?;
        let k = &st.kept;
        for (i, &row) in k.row.iter().enumerate() {
            let r = k.ptr[i]..k.ptr[i + 1];
            out[row as usize] = k.cols[r.clone()].iter().zip(&k.vals[r]).map(|(&c, v)| v * x[c as usize]).sum();
        }
        Ok(())
    }

    /// Distributed assembly with contact, the numeric phase: the kept rows of K put back,
    /// every element matrix of `fill` (this rank's contact elements) added, then the
    /// preconditioner's set-up. The field split's `u` block keeps its GAMG set-up when
    /// neither these contact terms nor those of the last set-up touch it and K is the
    /// same. Needs [`Self::keep_bulk_rows`] first. Collective.
    pub fn refill_contact(&mut self, fill: &mut crate::assembly::layout::ElementFill<'_>) -> Result<(), LinearError> {
        let st = self.state.get_mut().map_err(|_| LinearError::Internal("poisoned PETSc state".into()))?;
        if !self.distributed || !st.kept.valid {
            return Err(LinearError::Internal(
                "refill_contact needs a distributed solver whose contact rows are kept (keep_bulk_rows)".into(),
            ));
        }
        st.factorized = false;
        let a = st.obj.a;
        restore_kept(a, &st.kept)?;
        // Inserted values must reach the matrix before values are added.
        assemble(a, ffi::MAT_FLUSH_ASSEMBLY)?;
        let u_rows = (!self.u_rows.is_empty()).then_some(&self.u_rows[..]);
        let touches_u = super::on_any_rank(add_elements(a, fill, u_rows)?);
        assemble(a, ffi::MAT_FINAL_ASSEMBLY)?;
        let set_up_clock = Instant::now();
        let u_same = st.set_up_once && st.set_up_generation == st.bulk_generation && st.u_clean_last && !touches_u;
        let reuse_u = (st.set_up_once && u_rows.is_some()).then_some(u_same);
        agree(set_up_preconditioner(st.obj.ksp, a, reuse_u)).map_err(petsc_err)?;
        st.set_up_once = true;
        st.set_up_generation = st.bulk_generation;
        st.u_clean_last = !touches_u;
        st.factorized = true;
        st.numeric_s = set_up_clock.elapsed().as_secs_f64();
        Ok(())
    }

    /// The largest |K_jj| over the primal equations, recorded by
    /// [`Self::set_bulk_elements`] (0 before).
    pub fn bulk_diagonal_max(&self) -> f64 {
        self.state.lock().map(|s| s.bulk_diag_max).unwrap_or(0.0)
    }

    /// Every rank's peak resident memory (`VmHWM`, KiB) at the end of the last solve.
    pub fn peak_rss_kib(&self) -> Vec<u64> {
        self.state.lock().map(|s| s.peak_rss_kib.clone()).unwrap_or_default()
    }

    /// Solves `A x = b` (`rhs`: `b` on entry, `x` on every rank on success), then checks
    /// the residual on the replicated values. Collective.
    pub fn solve_in_place(&self, rhs: &mut [f64]) -> Result<(), LinearError> {
        let clock = Instant::now();
        let mut guard = self.state.lock().map_err(|_| LinearError::Internal("poisoned PETSc state".into()))?;
        let st = &mut *guard;
        if !st.factorized {
            return Err(LinearError::NotFactorized);
        }
        if rhs.len() != self.n {
            return Err(LinearError::LengthMismatch { what: "right-hand side", expected: self.n, got: rhs.len() });
        }
        if let Some(index) = rhs.iter().position(|v| !v.is_finite()) {
            return Err(LinearError::NonFiniteRhs { index, value: rhs[index] });
        }
        let b_norm = rhs.iter().map(|v| v * v).sum::<f64>().sqrt();
        // Distributed assembly: `rhs` is a sum over the ranks, which need not round alike
        // on every rank; the tolerance (a local decision of every rank's KSP) must be the
        // same everywhere: the largest, an exact all-reduce.
        let b_norm = if self.distributed { super::max_over_ranks(b_norm) } else { b_norm };
        if b_norm == 0.0 {
            rhs.fill(0.0);
            st.last_residual = 0.0;
            st.last_rhs = 0.0;
            st.last_iterations = 0;
            return Ok(());
        }
        // The scale of the tolerance: this right-hand side, or for the corrections of the
        // 3D contact split the largest since the analysis ([`CORRECTION_RTOL_CAP`]).
        let reference = if self.scaled_tolerance { st.b_ref.max(b_norm) } else { b_norm };
        st.b_ref = reference;
        let rtol = (self.rtol * reference / b_norm).min(CORRECTION_RTOL_CAP.max(self.rtol));
        // The replicated residual check needs b after the solve; PETSc's (distributed
        // assembly) does not: no copy then.
        let b = if self.distributed { vec![] } else { rhs.to_vec() };
        let o = &st.obj;
        let mut reason = 0;
        let mut its: PetscInt = 0;
        let mut r_norm: f64 = f64::NAN;
        // SAFETY: live objects; the arrays have the owned length `hi − lo` (b, x) and `n`
        // (the gathered vector).
        let solved: Result<(), String> = (|| unsafe {
            let mut arr: *mut f64 = std::ptr::null_mut();
            check("VecGetArray", ffi::VecGetArray(o.b, &mut arr))?;
            if self.hi > self.lo {
                std::slice::from_raw_parts_mut(arr, self.hi - self.lo).copy_from_slice(&rhs[self.lo..self.hi]);
            }
            check("VecRestoreArray", ffi::VecRestoreArray(o.b, &mut arr))?;
            // PETSC_DEFAULT keeps the other tolerances (the options' `-ksp_max_it`, …).
            check(
                "KSPSetTolerances",
                ffi::KSPSetTolerances(
                    o.ksp,
                    rtol,
                    ffi::PETSC_DEFAULT as f64,
                    ffi::PETSC_DEFAULT as f64,
                    ffi::PETSC_DEFAULT,
                ),
            )?;
            check("KSPSolve", ffi::KSPSolve(o.ksp, o.b, o.x))?;
            check("KSPGetConvergedReason", ffi::KSPGetConvergedReason(o.ksp, &mut reason))?;
            check("KSPGetIterationNumber", ffi::KSPGetIterationNumber(o.ksp, &mut its))?;
            check(
                "VecScatterBegin",
                ffi::VecScatterBegin(o.scatter, o.x, o.all, ffi::INSERT_VALUES, ffi::SCATTER_FORWARD),
            )?;
            check(
                "VecScatterEnd",
                ffi::VecScatterEnd(o.scatter, o.x, o.all, ffi::INSERT_VALUES, ffi::SCATTER_FORWARD),
            )?;
            let mut all: *const f64 = std::ptr::null();
            check("VecGetArrayRead", ffi::VecGetArrayRead(o.all, &mut all))?;
            rhs.copy_from_slice(std::slice::from_raw_parts(all, self.n));
            check("VecRestoreArrayRead", ffi::VecRestoreArrayRead(o.all, &mut all))?;
            if self.distributed {
                // r = b − A x on the distributed matrix (no rank has all the values).
                check("MatMult", ffi::MatMult(o.a, o.x, o.r))?;
                check("VecAYPX", ffi::VecAYPX(o.r, -1.0, o.b))?;
                check("VecNorm", ffi::VecNorm(o.r, ffi::NORM_2, &mut r_norm))?;
            }
            Ok(())
        })();
        agree(solved).map_err(petsc_err)?;
        st.peak_rss_kib = super::gather_over_ranks(super::peak_rss_kib());
        // Relative to the tolerance's scale (the right-hand side, or the largest since the
        // analysis for the corrections of the 3D contact split).
        let residual = if self.distributed {
            r_norm / reference
        } else {
            // The residual on the replicated values: the same on every rank.
            let mut r = b;
            for j in 0..self.n {
                let xj = rhs[j];
                for k in self.col_ptr[j]..self.col_ptr[j + 1] {
                    r[self.row_idx[k]] -= st.values[k] * xj;
                }
            }
            r.iter().map(|v| v * v).sum::<f64>().sqrt() / reference
        };
        st.last_residual = residual;
        st.last_rhs = b_norm / reference;
        st.last_iterations = its.max(0) as usize;
        st.solve_s = clock.elapsed().as_secs_f64();
        if reason < 0 || !residual.is_finite() {
            return Err(LinearError::KspDiverged {
                reason: ffi::converged_reason_name(reason),
                iterations: its.max(0) as usize,
                relative_residual: residual,
            });
        }
        Ok(())
    }

    /// Whether the values are partial sums of distributed assembly
    /// ([`Self::analyse_distributed`]).
    pub fn is_distributed(&self) -> bool {
        self.distributed
    }

    pub fn method(&self) -> LinearMethod {
        self.method
    }

    pub fn n(&self) -> usize {
        self.n
    }

    pub fn n_primal(&self) -> usize {
        self.n_primal
    }

    /// ‖Ax − b‖/‖b‖ of the last solve and its Krylov iterations; for the corrections of the
    /// 3D contact split ‖Ax − b‖ over the largest ‖b‖ since the analysis.
    pub fn last_residual(&self) -> (f64, usize) {
        self.state.lock().map(|s| (s.last_residual, s.last_iterations)).unwrap_or((f64::NAN, 0))
    }

    /// ‖b‖ and ‖Ax − b‖ of the last solve, both over the tolerance's scale (the largest
    /// ‖b‖ since the analysis for the corrections of the 3D contact split, else ‖b‖).
    pub fn last_rhs_and_residual(&self) -> (f64, f64) {
        self.state.lock().map(|s| (s.last_rhs, s.last_residual)).unwrap_or((f64::NAN, f64::NAN))
    }

    pub fn stats(&self) -> LinearStats {
        let (numeric_s, solve_s) = self.state.lock().map(|s| (s.numeric_s, s.solve_s)).unwrap_or_default();
        LinearStats {
            nnz_factor: None,
            flops_factor: None,
            factor_scratch_bytes: None,
            symbolic_s: self.symbolic_s,
            numeric_s,
            solve_s,
            ..Default::default()
        }
    }
}
