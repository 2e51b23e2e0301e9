//! Output file formats: VTU pieces and PVD collections for ParaView. Formats only: io
//! imports nothing from the rest of the crate (the `summary.json` schema is the run's,
//! `run::summary`).
//!
//! Entry points: [`vtu::write_vtu`], [`vtu::write_pvd`].

pub mod vtu;
