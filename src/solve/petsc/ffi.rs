//! The hand-written C declarations of the PETSc 3.18 functions the PETSc backend calls
//! (about 45; no bindgen, no third-party bindings). PETSc objects are opaque pointers;
//! `MPI_Comm` is the `mpi` crate's. The enum values are those of the 3.18 headers
//! (`petscsystypes.h`, `petscmat.h`, `petscvec.h`), checked there; `PetscInt` is 32-bit
//! (Debian's `libpetsc-real-dev`; a 64-bit-index PETSc would need `PetscInt = i64`).
//!
//! Entry point: the `extern "C"` block; [`check`] turns an error code into a message.

#![allow(non_camel_case_types, non_snake_case, non_upper_case_globals, clippy::upper_case_acronyms)]

use mpi::ffi::MPI_Comm;
use std::os::raw::{c_char, c_int, c_void};

pub type PetscErrorCode = c_int;
pub type PetscInt = c_int;
pub type PetscScalar = f64;
pub type PetscReal = f64;
/// `PetscBool` is a C enum: `PETSC_FALSE = 0`, `PETSC_TRUE = 1`.
pub type PetscBool = c_int;
pub type Mat = *mut c_void;
pub type PVec = *mut c_void;
pub type KSP = *mut c_void;
pub type PC = *mut c_void;
pub type IS = *mut c_void;
pub type MatNullSpace = *mut c_void;
pub type VecScatter = *mut c_void;

pub const PETSC_FALSE: PetscBool = 0;
pub const PETSC_TRUE: PetscBool = 1;
/// `InsertMode`: `NOT_SET_VALUES, INSERT_VALUES, ADD_VALUES, …`.
pub const INSERT_VALUES: c_int = 1;
pub const ADD_VALUES: c_int = 2;
/// `NormType`: `NORM_1 = 0, NORM_2 = 1`.
pub const NORM_2: c_int = 1;
/// `MatAssemblyType`: `MAT_FLUSH_ASSEMBLY = 1, MAT_FINAL_ASSEMBLY = 0`.
pub const MAT_FINAL_ASSEMBLY: c_int = 0;
pub const MAT_FLUSH_ASSEMBLY: c_int = 1;
/// `MatOption`: `MAT_NEW_NONZERO_ALLOCATION_ERR = 19`.
pub const MAT_NEW_NONZERO_ALLOCATION_ERR: c_int = 19;
/// `ScatterMode`: `SCATTER_FORWARD = 0`.
pub const SCATTER_FORWARD: c_int = 0;
/// `PetscCopyMode`: `PETSC_COPY_VALUES = 0`.
pub const PETSC_COPY_VALUES: c_int = 0;
/// `PCCompositeType`: `PC_COMPOSITE_SYMMETRIC_MULTIPLICATIVE` (petscpctypes.h).
pub const PC_COMPOSITE_SYMMETRIC_MULTIPLICATIVE: c_int = 2;
/// `PCCompositeType`: `PC_COMPOSITE_MULTIPLICATIVE` (petscpctypes.h).
pub const PC_COMPOSITE_MULTIPLICATIVE: c_int = 1;
/// `PCSide`: `PC_RIGHT = 1` (petscpctypes.h).
pub const PC_RIGHT: c_int = 1;
/// `PETSC_DEFAULT` (`#define PETSC_DEFAULT -2`), for the tolerances left to PETSc.
pub const PETSC_DEFAULT: PetscInt = -2;

extern "C" {
    pub static mut PETSC_COMM_WORLD: MPI_Comm;
    /// Indexed by the (possibly negative) `KSPConvergedReason`.
    pub static KSPConvergedReasons: *const *const c_char;

    pub fn PetscInitialize(
        argc: *mut c_int,
        args: *mut *mut *mut c_char,
        file: *const c_char,
        help: *const c_char,
    ) -> PetscErrorCode;
    pub fn PetscFinalize() -> PetscErrorCode;
    pub fn PetscPushErrorHandler(
        handler: extern "C" fn(
            MPI_Comm,
            c_int,
            *const c_char,
            *const c_char,
            PetscErrorCode,
            c_int,
            *const c_char,
            *mut c_void,
        ) -> PetscErrorCode,
        ctx: *mut c_void,
    ) -> PetscErrorCode;
    pub fn PetscErrorMessage(code: c_int, text: *mut *const c_char, specific: *mut *mut c_char) -> PetscErrorCode;
    pub fn PetscOptionsInsertString(options: *mut c_void, text: *const c_char) -> PetscErrorCode;
    pub fn PetscOptionsHasName(
        options: *mut c_void,
        pre: *const c_char,
        name: *const c_char,
        set: *mut PetscBool,
    ) -> PetscErrorCode;
    pub fn PetscObjectCompose(obj: *mut c_void, name: *const c_char, ptr: *mut c_void) -> PetscErrorCode;

    pub fn MatCreate(comm: MPI_Comm, a: *mut Mat) -> PetscErrorCode;
    pub fn MatSetSizes(a: Mat, m: PetscInt, n: PetscInt, gm: PetscInt, gn: PetscInt) -> PetscErrorCode;
    pub fn MatSetType(a: Mat, kind: *const c_char) -> PetscErrorCode;
    pub fn MatSetBlockSize(a: Mat, bs: PetscInt) -> PetscErrorCode;
    pub fn MatSeqAIJSetPreallocation(a: Mat, nz: PetscInt, nnz: *const PetscInt) -> PetscErrorCode;
    pub fn MatMPIAIJSetPreallocation(
        a: Mat,
        d_nz: PetscInt,
        d_nnz: *const PetscInt,
        o_nz: PetscInt,
        o_nnz: *const PetscInt,
    ) -> PetscErrorCode;
    pub fn MatSetOption(a: Mat, op: c_int, flag: PetscBool) -> PetscErrorCode;
    pub fn MatSetValues(
        a: Mat,
        m: PetscInt,
        rows: *const PetscInt,
        n: PetscInt,
        cols: *const PetscInt,
        v: *const PetscScalar,
        mode: c_int,
    ) -> PetscErrorCode;
    pub fn MatAssemblyBegin(a: Mat, kind: c_int) -> PetscErrorCode;
    pub fn MatZeroEntries(a: Mat) -> PetscErrorCode;
    pub fn MatMult(a: Mat, x: PVec, y: PVec) -> PetscErrorCode;
    pub fn MatGetDiagonal(a: Mat, v: PVec) -> PetscErrorCode;
    pub fn MatGetRow(
        a: Mat,
        row: PetscInt,
        ncols: *mut PetscInt,
        cols: *mut *const PetscInt,
        vals: *mut *const PetscScalar,
    ) -> PetscErrorCode;
    pub fn MatRestoreRow(
        a: Mat,
        row: PetscInt,
        ncols: *mut PetscInt,
        cols: *mut *const PetscInt,
        vals: *mut *const PetscScalar,
    ) -> PetscErrorCode;
    pub fn VecDuplicate(v: PVec, w: *mut PVec) -> PetscErrorCode;
    pub fn VecAYPX(y: PVec, beta: PetscScalar, x: PVec) -> PetscErrorCode;
    pub fn VecNorm(v: PVec, kind: c_int, norm: *mut PetscReal) -> PetscErrorCode;
    pub fn MatAssemblyEnd(a: Mat, kind: c_int) -> PetscErrorCode;
    pub fn MatSetNearNullSpace(a: Mat, space: MatNullSpace) -> PetscErrorCode;
    pub fn MatDestroy(a: *mut Mat) -> PetscErrorCode;
    pub fn MatNullSpaceCreate(
        comm: MPI_Comm,
        has_constant: PetscBool,
        n: PetscInt,
        vecs: *const PVec,
        space: *mut MatNullSpace,
    ) -> PetscErrorCode;
    pub fn MatNullSpaceDestroy(space: *mut MatNullSpace) -> PetscErrorCode;

    pub fn VecCreateMPI(comm: MPI_Comm, n: PetscInt, gn: PetscInt, v: *mut PVec) -> PetscErrorCode;
    pub fn VecGetArray(v: PVec, a: *mut *mut PetscScalar) -> PetscErrorCode;
    pub fn VecRestoreArray(v: PVec, a: *mut *mut PetscScalar) -> PetscErrorCode;
    pub fn VecGetArrayRead(v: PVec, a: *mut *const PetscScalar) -> PetscErrorCode;
    pub fn VecRestoreArrayRead(v: PVec, a: *mut *const PetscScalar) -> PetscErrorCode;
    pub fn VecDestroy(v: *mut PVec) -> PetscErrorCode;
    pub fn VecScatterCreateToAll(v: PVec, ctx: *mut VecScatter, all: *mut PVec) -> PetscErrorCode;
    pub fn VecScatterBegin(ctx: VecScatter, x: PVec, y: PVec, mode: c_int, smode: c_int) -> PetscErrorCode;
    pub fn VecScatterEnd(ctx: VecScatter, x: PVec, y: PVec, mode: c_int, smode: c_int) -> PetscErrorCode;
    pub fn VecScatterDestroy(ctx: *mut VecScatter) -> PetscErrorCode;

    pub fn KSPCreate(comm: MPI_Comm, ksp: *mut KSP) -> PetscErrorCode;
    pub fn KSPSetOperators(ksp: KSP, a: Mat, p: Mat) -> PetscErrorCode;
    pub fn KSPSetType(ksp: KSP, kind: *const c_char) -> PetscErrorCode;
    pub fn KSPGetType(ksp: KSP, kind: *mut *const c_char) -> PetscErrorCode;
    pub fn KSPGetPC(ksp: KSP, pc: *mut PC) -> PetscErrorCode;
    pub fn KSPSetTolerances(
        ksp: KSP,
        rtol: PetscReal,
        abstol: PetscReal,
        dtol: PetscReal,
        maxits: PetscInt,
    ) -> PetscErrorCode;
    pub fn KSPGetTolerances(
        ksp: KSP,
        rtol: *mut PetscReal,
        abstol: *mut PetscReal,
        dtol: *mut PetscReal,
        maxits: *mut PetscInt,
    ) -> PetscErrorCode;
    pub fn KSPSetFromOptions(ksp: KSP) -> PetscErrorCode;
    pub fn KSPSetPCSide(ksp: KSP, side: c_int) -> PetscErrorCode;
    pub fn KSPGMRESSetRestart(ksp: KSP, restart: PetscInt) -> PetscErrorCode;
    pub fn KSPSetUp(ksp: KSP) -> PetscErrorCode;
    pub fn KSPSolve(ksp: KSP, b: PVec, x: PVec) -> PetscErrorCode;
    pub fn KSPGetConvergedReason(ksp: KSP, reason: *mut c_int) -> PetscErrorCode;
    pub fn KSPGetIterationNumber(ksp: KSP, its: *mut PetscInt) -> PetscErrorCode;
    pub fn KSPDestroy(ksp: *mut KSP) -> PetscErrorCode;

    pub fn PCSetType(pc: PC, kind: *const c_char) -> PetscErrorCode;
    pub fn PCSetCoordinates(pc: PC, dim: PetscInt, nloc: PetscInt, coords: *mut PetscReal) -> PetscErrorCode;
    pub fn PCGetType(pc: PC, kind: *mut *const c_char) -> PetscErrorCode;
    pub fn PCFactorSetMatSolverType(pc: PC, kind: *const c_char) -> PetscErrorCode;
    pub fn PCFieldSplitSetIS(pc: PC, name: *const c_char, is: IS) -> PetscErrorCode;
    pub fn PCFieldSplitSetType(pc: PC, kind: c_int) -> PetscErrorCode;
    /// The split's KSPs (after its set-up), in an array the caller frees ([`PetscTrFree`]).
    pub fn PCFieldSplitGetSubKSP(pc: PC, n: *mut PetscInt, subksp: *mut *mut KSP) -> PetscErrorCode;
    pub fn KSPSetReusePreconditioner(ksp: KSP, flag: PetscBool) -> PetscErrorCode;
    /// PETSc's `free` (the function behind the `PetscFree` macro).
    pub static PetscTrFree:
        Option<unsafe extern "C" fn(*mut c_void, c_int, *const c_char, *const c_char) -> PetscErrorCode>;

    pub fn ISCreateGeneral(
        comm: MPI_Comm,
        n: PetscInt,
        idx: *const PetscInt,
        mode: c_int,
        is: *mut IS,
    ) -> PetscErrorCode;
    pub fn ISDestroy(is: *mut IS) -> PetscErrorCode;
    pub fn ISSetBlockSize(is: IS, bs: PetscInt) -> PetscErrorCode;
}

/// The message of the error PETSc raised last (its first, innermost report), taken by
/// [`check`].
static LAST_ERROR: std::sync::Mutex<Option<String>> = std::sync::Mutex::new(None);

/// `PETSC_ERROR_INITIAL` of `PetscErrorType`.
const PETSC_ERROR_INITIAL: c_int = 0;

/// Our PETSc error handler (installed by `PetscPushErrorHandler` after `PetscInitialize`):
/// records the innermost message and returns the code, so that the error reaches the
/// caller on every rank. PETSc's default handler prints on the communicator's first rank
/// only and makes the other ranks sleep 10 s and exit with status 0 — a rank leaving alone.
pub extern "C" fn record_error(
    _comm: MPI_Comm,
    _line: c_int,
    func: *const c_char,
    _file: *const c_char,
    code: PetscErrorCode,
    kind: c_int,
    message: *const c_char,
    _ctx: *mut c_void,
) -> PetscErrorCode {
    if kind == PETSC_ERROR_INITIAL {
        let text = |p: *const c_char| {
            if p.is_null() {
                String::new()
            } else {
                // SAFETY: PETSc passes NUL-terminated strings.
                unsafe { std::ffi::CStr::from_ptr(p) }.to_string_lossy().into_owned()
            }
        };
        if let Ok(mut last) = LAST_ERROR.lock() {
            *last = Some(format!("{} (in {})", text(message).trim(), text(func)));
        }
    }
    code
}

/// `Err` with the call's name, the code, PETSc's text for the code and the message PETSc
/// raised when `code` is not 0.
pub fn check(call: &'static str, code: PetscErrorCode) -> Result<(), String> {
    let raised = LAST_ERROR.lock().ok().and_then(|mut l| l.take());
    if code == 0 {
        return Ok(());
    }
    let mut text: *const c_char = std::ptr::null();
    // SAFETY: PetscErrorMessage only writes a pointer to a static string.
    let known = unsafe { PetscErrorMessage(code, &mut text, std::ptr::null_mut()) } == 0 && !text.is_null();
    let what = if known {
        // SAFETY: a NUL-terminated static string of PETSc's.
        unsafe { std::ffi::CStr::from_ptr(text) }.to_string_lossy().into_owned()
    } else {
        "unknown error".to_string()
    };
    match raised {
        Some(m) => Err(format!("{call} failed with PETSc error {code} ({what}): {m}")),
        None => Err(format!("{call} failed with PETSc error {code} ({what})")),
    }
}

/// PETSc's name of a `KSPConvergedReason` (e.g. `DIVERGED_ITS`).
pub fn converged_reason_name(reason: c_int) -> String {
    // SAFETY: KSPConvergedReasons points into a static array covering the reasons -11..=9
    // of PETSc 3.18 (the `KSPConvergedReason` enum); other values are not looked up.
    if !(-11..=9).contains(&reason) {
        return format!("reason {reason}");
    }
    unsafe {
        let name = *KSPConvergedReasons.offset(reason as isize);
        if name.is_null() {
            format!("reason {reason}")
        } else {
            std::ffi::CStr::from_ptr(name).to_string_lossy().into_owned()
        }
    }
}
