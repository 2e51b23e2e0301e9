//! Helpers shared by integration tests (`mod common;` in a test file).
//!
//! - [`paraview`]: run ParaView's `pvpython` on written VTK files and read back what its
//!   readers saw (skips loudly without ParaView, fails when `CI=true`).

// Every test binary compiles this module but uses only part of it.
#![allow(dead_code)]

pub mod paraview;
