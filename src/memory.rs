//! The memory a model needs, estimated from its sizes before anything is built, and the
//! memory the machine has available: a model that cannot fit fails at once with a clear
//! message (needed against available) instead of aborting on an allocation failure in
//! the mesh generator, the pattern or the factorisation.
//!
//! Entry points: [`Estimate::of_model`], [`available_bytes`], [`Estimate::check`].
//!
//! The estimate is a lower bound, so that it never refuses a model that would fit: the
//! mesh (coordinates and cell connectivity), the lower triangle of the sparse matrix
//! (8-byte values and 4-byte indices, one entry per pair of dofs of neighbouring
//! nodes) and the values of the Cholesky factor with a nested-dissection ordering,
//! nnz(L) ≈ 4 n log₂ n in 2D and 25 n^{4/3} in 3D (measured: 5.6 n log₂ n and
//! 33–38 n^{4/3}, `docs/performance.md`), n being the number of unknowns. The peak
//! measured in `docs/performance.md` is about twice this bound.

use std::fmt;

/// Bytes of one mesh node (three coordinates) and one cell (kind and eight node slots).
const NODE_BYTES: f64 = 24.0;
const CELL_BYTES: f64 = 72.0;

/// The memory of a model, by part (bytes, as `f64`: absurd sizes must not overflow).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Estimate {
    pub mesh: f64,
    pub pattern: f64,
    pub factor: f64,
}

/// A model that does not fit in the available memory.
#[derive(Debug, Clone, PartialEq)]
pub struct TooLarge {
    pub estimate: Estimate,
    pub available: f64,
}

fn gib(b: f64) -> String {
    if b >= 1e-3 * (1u64 << 30) as f64 {
        format!("{:.3} GiB", b / (1u64 << 30) as f64)
    } else {
        format!("{:.1} MiB", b / (1u64 << 20) as f64)
    }
}

impl fmt::Display for TooLarge {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let e = &self.estimate;
        write!(
            f,
            "the model needs at least {} (mesh {}, matrix {}, factor {}) but {} are available (the least of MemAvailable, the cgroup's memory.max and the address-space limit)",
            gib(e.total()),
            gib(e.mesh),
            gib(e.pattern),
            gib(e.factor),
            gib(self.available)
        )
    }
}

impl Estimate {
    /// The estimate for a `dim`-dimensional mesh of `nodes` nodes and `cells` cells with
    /// `dofs` displacement unknowns (enriched ones included); `nodes_per_cell` and the
    /// number of nodes a node is coupled with (`neighbours`, itself included: 9 for a
    /// quad4 grid, 27 for hex8) size the matrix.
    pub fn of_model(dim: usize, nodes: f64, cells: f64, nodes_per_cell: f64, dofs: f64, neighbours: f64) -> Estimate {
        let mesh = nodes * NODE_BYTES + cells * CELL_BYTES.max(8.0 * nodes_per_cell);
        let pattern = 0.5 * dofs * dim as f64 * neighbours * 12.0;
        let n = dofs.max(2.0);
        let nnz_l = if dim == 2 { 4.0 * n * n.log2() } else { 25.0 * n.powf(4.0 / 3.0) };
        Estimate { mesh, pattern, factor: 8.0 * nnz_l.max(n) }
    }

    /// Entries of the factor in the estimate.
    pub fn factor_entries(&self) -> f64 {
        self.factor / 8.0
    }

    /// The same model with the factor in single precision (`[solver] precision =
    /// "mixed"`): 4 bytes an entry instead of 8.
    pub fn single_precision_factor(self) -> Estimate {
        Estimate { factor: 0.5 * self.factor, ..self }
    }

    /// The same model solved without a factorisation (the PETSc backend's Krylov methods
    /// with a multigrid or other preconditioner: the matrix, and its hierarchy, which the
    /// lower bound does not count).
    pub fn without_factor(self) -> Estimate {
        Estimate { factor: 0.0, ..self }
    }

    pub fn total(&self) -> f64 {
        self.mesh + self.pattern + self.factor
    }

    /// Fails when the estimate exceeds `available` bytes (`None`: unknown, no check).
    pub fn check(&self, available: Option<f64>) -> Result<(), TooLarge> {
        match available {
            Some(a) if self.total() > a => Err(TooLarge { estimate: *self, available: a }),
            _ => Ok(()),
        }
    }
}

/// The memory this process may still use, in bytes: the smallest of the kernel's estimate
/// of the memory available without swapping (`MemAvailable` in `/proc/meminfo`), the room
/// left under the cgroup's limit (`memory.max` − `memory.current`, cgroup v2) and the
/// room left under the process's address-space limit (`ulimit -v`: the soft "Max address
/// space" of `/proc/self/limits` − `VmSize` of `/proc/self/status`), among those that can
/// be read; `None` when none can (then nothing is checked).
pub fn available_bytes() -> Option<f64> {
    let read = |p: &str| std::fs::read_to_string(p).ok();
    let meminfo = read("/proc/meminfo").and_then(|t| parse_meminfo(&t));
    let number = |p: &str| read(p).and_then(|s| s.trim().parse::<f64>().ok());
    let cgroup = number("/sys/fs/cgroup/memory.max")
        .and_then(|max| number("/sys/fs/cgroup/memory.current").map(|cur| (max - cur).max(0.0)));
    let address_space = read("/proc/self/limits").and_then(|t| parse_address_space_limit(&t)).and_then(|limit| {
        read("/proc/self/status").and_then(|t| parse_vm_size(&t)).map(|used| (limit - used).max(0.0))
    });
    [meminfo, cgroup, address_space].into_iter().flatten().reduce(f64::min)
}

/// The soft "Max address space" limit of `/proc/self/limits` in bytes (`None` when
/// unlimited or unreadable).
fn parse_address_space_limit(text: &str) -> Option<f64> {
    let rest = text.lines().find_map(|l| l.strip_prefix("Max address space"))?;
    rest.split_whitespace().next()?.parse().ok()
}

/// `VmSize` of `/proc/self/status` in bytes.
fn parse_vm_size(text: &str) -> Option<f64> {
    let rest = text.lines().find_map(|l| l.strip_prefix("VmSize:"))?;
    let kb: f64 = rest.trim().trim_end_matches("kB").trim().parse().ok()?;
    Some(kb * 1024.0)
}

fn parse_meminfo(text: &str) -> Option<f64> {
    let line = text.lines().find(|l| l.starts_with("MemAvailable:"))?;
    let mut it = line.split_whitespace().skip(1);
    let v: f64 = it.next()?.parse().ok()?;
    let unit = match it.next() {
        Some("kB") | Some("KB") => 1024.0,
        Some("MB") => 1024.0 * 1024.0,
        None => 1.0,
        Some(_) => return None,
    };
    Some(v * unit)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The lower bound stays below the peaks measured in docs/performance.md (2D 1M
    /// equations: 2224 MB; 3D 285 660 equations: 7983 MB) and above half of them.
    #[test]
    fn estimate_is_a_lower_bound_of_the_measured_peaks() {
        let mb = (1u64 << 20) as f64;
        let e2 = Estimate::of_model(2, 500_556.0, 500_000.0, 4.0, 1_001_112.0, 9.0).total() / mb;
        assert!(e2 < 2224.0 && e2 > 0.3 * 2224.0, "2D: {e2} MB");
        let e3 = Estimate::of_model(3, 95_220.0, 91_125.0, 8.0, 285_660.0, 27.0).total() / mb;
        assert!(e3 < 7983.0 && e3 > 0.3 * 7983.0, "3D: {e3} MB");
        let t = Estimate::of_model(2, 1e12, 1e12, 4.0, 2e12, 9.0).check(Some(24.0 * 1024.0 * mb)).unwrap_err();
        assert!(t.to_string().starts_with("the model needs at least"), "{t}");
        let none = Estimate::of_model(3, 95_220.0, 91_125.0, 8.0, 285_660.0, 27.0).without_factor();
        assert_eq!((none.factor, none.total()), (0.0, none.mesh + none.pattern));
        let half = Estimate::of_model(3, 95_220.0, 91_125.0, 8.0, 285_660.0, 27.0).single_precision_factor();
        let full = Estimate::of_model(3, 95_220.0, 91_125.0, 8.0, 285_660.0, 27.0);
        assert_eq!(half.factor, 0.5 * full.factor);
        assert_eq!(half.mesh + half.pattern, full.mesh + full.pattern);
        assert_eq!(parse_meminfo("MemTotal: 10 kB\nMemAvailable:   2048 kB\n"), Some(2048.0 * 1024.0));
        let limits = "Max stack size            8388608              unlimited            bytes\nMax address space         2048000000           unlimited            bytes\n";
        assert_eq!(parse_address_space_limit(limits), Some(2_048_000_000.0));
        assert_eq!(
            parse_address_space_limit("Max address space         unlimited            unlimited            bytes\n"),
            None
        );
        assert_eq!(parse_vm_size("Name:\tx\nVmSize:\t    3760 kB\n"), Some(3760.0 * 1024.0));
    }
}
