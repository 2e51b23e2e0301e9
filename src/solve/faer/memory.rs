//! The factor's memory: the prediction checked against the memory available after the
//! symbolic phase, and the allocation of its large buffers, reporting failure as an error
//! instead of aborting.
//!
//! Entry points: [`check_factor_memory`], [`try_zeroed_vec`].

use crate::solve::backend::LinearError;
use faer::dyn_stack::StackReq;

/// Bytes the numeric phase of a factor will hold: the values of `L` (`nnz_factor`
/// entries of `entry_bytes` each: 8 in double precision, 4 in single; unknown for LU,
/// counted as 0), the scratch of the factorisation and of a solve (`reqs`), the scaled
/// copy of the matrix values (`matrix_nnz`; in single precision also its single-precision
/// copy, 4 bytes an entry, held during the numeric phase) and a few vectors of `n`
/// entries (scaling, right-hand side, residual, correction; in single precision also the
/// conjugate-gradient vectors).
pub(super) fn predicted_bytes(
    nnz_factor: Option<usize>,
    entry_bytes: u64,
    reqs: &[StackReq],
    matrix_nnz: usize,
    n: usize,
) -> u64 {
    let single = entry_bytes < 8;
    let words = matrix_nnz as u64 + if single { 9 } else { 6 } * n as u64;
    let single_copy = if single { 4 * matrix_nnz as u64 } else { 0 };
    entry_bytes * nnz_factor.unwrap_or(0) as u64
        + 8 * words
        + single_copy
        + reqs.iter().map(|r| r.size_bytes() as u64).sum::<u64>()
}

/// Refuses a factor whose predicted size ([`predicted_bytes`]) exceeds `limit`, or, without
/// a limit, the memory available now ([`available_memory`]): a clear error before the
/// numeric phase instead of a crash or the OOM killer in the middle of it.
pub(super) fn check_factor_memory(
    nnz_factor: Option<usize>,
    entry_bytes: u64,
    reqs: &[StackReq],
    matrix_nnz: usize,
    n: usize,
    limit: Option<u64>,
) -> Result<(), LinearError> {
    let predicted = predicted_bytes(nnz_factor, entry_bytes, reqs, matrix_nnz, n);
    match limit.or_else(available_memory) {
        Some(available) if predicted > available => Err(LinearError::FactorTooLarge {
            predicted_bytes: predicted,
            available_bytes: available,
            nnz_factor: nnz_factor.unwrap_or(0),
        }),
        _ => Ok(()),
    }
}

/// The memory this process may still use, in bytes ([`crate::memory::available_bytes`]:
/// `MemAvailable`, the cgroup's limit and the address-space limit); `None` when none can
/// be read (then nothing is checked).
pub fn available_memory() -> Option<u64> {
    crate::memory::available_bytes().map(|b| b as u64)
}

/// A vector of `len` zeros from `alloc_zeroed`: large blocks come zeroed from the
/// system, so nothing is written here (the factor's pages are first touched by the
/// numeric phase instead of being filled twice). Transparent huge pages were tried for
/// this buffer (`MADV_HUGEPAGE`): faster when the kernel had free huge pages, but with
/// the usual `defrag = madvise` setting the faults then compact memory synchronously,
/// and on a busy machine that cost up to a second of system time.
pub(crate) fn try_zeroed_vec<T: ZeroBits>(len: usize) -> Result<Vec<T>, LinearError> {
    if len == 0 {
        return Ok(Vec::new());
    }
    let layout = std::alloc::Layout::array::<T>(len).map_err(|_| LinearError::OutOfMemory)?;
    // SAFETY: the layout has a nonzero size.
    let ptr = unsafe { std::alloc::alloc_zeroed(layout) }.cast::<T>();
    if ptr.is_null() {
        return Err(LinearError::OutOfMemory);
    }
    // SAFETY: `ptr` was allocated by the global allocator with the layout of `len` T,
    // and all-zero bytes are a valid T (`ZeroBits`), so all `len` elements are initialised.
    Ok(unsafe { Vec::from_raw_parts(ptr, len, len) })
}

/// Types whose all-zero bit pattern is a valid value (the floats' 0.0).
///
/// # Safety
/// Only for types for which all-zero bytes are a valid, initialised value.
pub(crate) unsafe trait ZeroBits: Copy {}
// SAFETY: all-zero bytes are 0.0.
unsafe impl ZeroBits for f64 {}
// SAFETY: all-zero bytes are 0.0.
unsafe impl ZeroBits for f32 {}
