//! The factor's memory: the prediction checked against the memory available after the
//! symbolic phase, and the allocation of its large buffers, reporting failure as an error
//! instead of aborting.
//!
//! Entry points: [`check_factor_memory`], [`try_zeroed_vec`].

use crate::solve::backend::LinearError;
use faer::dyn_stack::StackReq;

/// Bytes the numeric phase of a factor will hold: the values of `L` (`nnz_factor`
/// entries; unknown for LU, counted as 0), the scratch of the factorisation and of a
/// solve (`reqs`), the scaled copy of the matrix values (`matrix_nnz`) and a few vectors
/// of `n` entries (scaling, right-hand side, residual, correction).
pub(super) fn predicted_bytes(nnz_factor: Option<usize>, reqs: &[StackReq], matrix_nnz: usize, n: usize) -> u64 {
    let words = nnz_factor.unwrap_or(0) as u64 + matrix_nnz as u64 + 6 * n as u64;
    8 * words + reqs.iter().map(|r| r.size_bytes() as u64).sum::<u64>()
}

/// Refuses a factor whose predicted size ([`predicted_bytes`]) exceeds `limit`, or, without
/// a limit, the memory available now ([`available_memory`]): a clear error before the
/// numeric phase instead of a crash or the OOM killer in the middle of it.
pub(super) fn check_factor_memory(
    nnz_factor: Option<usize>,
    reqs: &[StackReq],
    matrix_nnz: usize,
    n: usize,
    limit: Option<u64>,
) -> Result<(), LinearError> {
    let predicted = predicted_bytes(nnz_factor, reqs, matrix_nnz, n);
    match limit.or_else(available_memory) {
        Some(available) if predicted > available => Err(LinearError::FactorTooLarge {
            predicted_bytes: predicted,
            available_bytes: available,
            nnz_factor: nnz_factor.unwrap_or(0),
        }),
        _ => Ok(()),
    }
}

/// The memory this process may still use, in bytes: the smaller of the kernel's estimate
/// of the memory available without swapping (`MemAvailable` in `/proc/meminfo`) and the
/// room left under the cgroup's limit (`memory.max` − `memory.current`, cgroup v2), when
/// they can be read; `None` otherwise (then nothing is checked).
pub fn available_memory() -> Option<u64> {
    let meminfo = std::fs::read_to_string("/proc/meminfo").ok().and_then(|s| {
        s.lines()
            .find_map(|l| l.strip_prefix("MemAvailable:"))
            .and_then(|v| v.trim().trim_end_matches("kB").trim().parse::<u64>().ok())
            .map(|kb| kb * 1024)
    });
    let read = |p: &str| std::fs::read_to_string(p).ok().and_then(|s| s.trim().parse::<u64>().ok());
    let cgroup = read("/sys/fs/cgroup/memory.max")
        .and_then(|max| read("/sys/fs/cgroup/memory.current").map(|cur| max.saturating_sub(cur)));
    match (meminfo, cgroup) {
        (Some(a), Some(b)) => Some(a.min(b)),
        (a, b) => a.or(b),
    }
}

/// A vector of `len` zeros from `alloc_zeroed`: large blocks come zeroed from the
/// system, so nothing is written here (the factor's pages are first touched by the
/// numeric phase instead of being filled twice). Transparent huge pages were tried for
/// this buffer (`MADV_HUGEPAGE`): faster when the kernel had free huge pages, but with
/// the usual `defrag = madvise` setting the faults then compact memory synchronously,
/// and on a busy machine that cost up to a second of system time.
pub(crate) fn try_zeroed_vec(len: usize) -> Result<Vec<f64>, LinearError> {
    if len == 0 {
        return Ok(Vec::new());
    }
    let layout = std::alloc::Layout::array::<f64>(len).map_err(|_| LinearError::OutOfMemory)?;
    // SAFETY: the layout has a nonzero size.
    let ptr = unsafe { std::alloc::alloc_zeroed(layout) }.cast::<f64>();
    if ptr.is_null() {
        return Err(LinearError::OutOfMemory);
    }
    // SAFETY: `ptr` was allocated by the global allocator with the layout of `len` f64,
    // and all-zero bytes are the f64 value 0.0, so all `len` elements are initialised.
    Ok(unsafe { Vec::from_raw_parts(ptr, len, len) })
}
