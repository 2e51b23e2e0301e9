//! Pure geometry shared by every layer: quadrature rules on reference shapes.
//!
//! Entry point: [`quadrature::QuadratureRule`] and its constructors
//! ([`quadrature::gauss_line`], [`quadrature::gauss_triangle`], ...).
//! Cutting simplices by level sets will live here too (it is pure geometry).

pub mod quadrature;
