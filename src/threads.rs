//! The process's worker threads: rayon's global pool, built with the calling thread as one
//! of its workers.
//!
//! Entry point: [`init`], called once by each program's `main` (the `fissure` command, the
//! benchmarks, the Python module) before any parallel work.
//!
//! Why: the solver makes thousands of short parallel calls per load step (faer's dense
//! factorisations and triangular solves of the contact block, the contact assembly). From a
//! thread outside the pool each call is handed to the pool and the caller sleeps on a lock
//! until it is done: two futex round trips and an idle core per call (254 000 futex calls
//! and 4–6 s of system time on the 3D Hertz bench row). With the caller in the pool a
//! call is a work-stealing `join`, as inside any rayon job. The number of threads is
//! rayon's default (`RAYON_NUM_THREADS`, else the number of cores), the caller counted.
//! Measured in `docs/performance.md` ("The calling thread in the pool").

/// Builds rayon's global pool with the calling thread as one of its workers. Returns
/// `false` (and changes nothing) when the global pool already exists, e.g. when a library
/// user built it or a parallel call ran before: everything then works as before, the
/// calls from this thread being handed to the pool.
pub fn init() -> bool {
    rayon::ThreadPoolBuilder::new().use_current_thread().build_global().is_ok()
}
