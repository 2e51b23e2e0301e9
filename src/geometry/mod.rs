//! Pure geometry shared by every layer: quadrature rules on reference shapes and the
//! small 3-vector helpers.
//!
//! Entry points: [`quadrature::QuadratureRule`] and its constructors
//! ([`quadrature::gauss_line`], [`quadrature::gauss_triangle`], ...); [`vec3`].

pub mod quadrature;
pub mod vec3;
