//! Helpers shared by integration tests (`mod common;` in a test file).
//!
//! - [`paraview`]: run ParaView's `pvpython` on written VTK files and read back what its
//!   readers saw (skips loudly without ParaView, fails when `CI=true`).
//! - [`model`]: building models in code (supports, loads) and convergence rates.

// Every test binary compiles this module but uses only part of it.
#![allow(dead_code)]

pub mod contact;
pub mod fracture;
pub mod model;
pub mod paraview;
pub mod sliding;
