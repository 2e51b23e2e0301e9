//! Allocation of the factor's large buffers, reporting failure as
//! [`LinearError::OutOfMemory`] instead of aborting.
//!
//! Entry point: [`try_zeroed_vec`].

use crate::solve::backend::LinearError;

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
