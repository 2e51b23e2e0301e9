//! Linear isotropic elasticity: Lamé constants for 3D, plane strain and plane stress,
//! stress from strain, von Mises.
//!
//! Entry point: [`Isotropic`].
//!
//! Voigt order: 2D `[xx, yy, xy]`, 3D `[xx, yy, zz, yz, xz, xy]`; strains in Voigt
//! form carry engineering shear (γ = 2ε) internally, but output tensors (strain,
//! stress) are written as tensor components: see `docs/conventions.md`.

/// The modelling hypothesis for the out-of-plane direction.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Analysis {
    PlaneStrain,
    PlaneStress,
    ThreeD,
}

impl Analysis {
    pub fn dim(self) -> usize {
        match self {
            Analysis::ThreeD => 3,
            _ => 2,
        }
    }
    pub fn name(self) -> &'static str {
        match self {
            Analysis::PlaneStrain => "plane_strain",
            Analysis::PlaneStress => "plane_stress",
            Analysis::ThreeD => "3d",
        }
    }
}

/// An isotropic linear elastic material.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Isotropic {
    pub young: f64,
    pub poisson: f64,
}

impl Isotropic {
    /// Shear modulus μ.
    pub fn mu(&self) -> f64 {
        self.young / (2.0 * (1.0 + self.poisson))
    }
    /// Lamé λ of the 3D law.
    pub fn lambda_3d(&self) -> f64 {
        self.young * self.poisson / ((1.0 + self.poisson) * (1.0 - 2.0 * self.poisson))
    }
    /// The λ that the in-plane law uses: λ for 3D and plane strain, 2λμ/(λ + 2μ) for plane stress.
    pub fn lambda_in_plane(&self, analysis: Analysis) -> f64 {
        let (l, m) = (self.lambda_3d(), self.mu());
        match analysis {
            Analysis::PlaneStress => 2.0 * l * m / (l + 2.0 * m),
            _ => l,
        }
    }

    /// Full 3×3 stress tensor from the in-plane (or 3D) small-strain tensor `eps`.
    /// In plane strain σ_zz = ν(σ_xx + σ_yy); in plane stress σ_zz = 0 (ε_zz is free).
    pub fn stress(&self, analysis: Analysis, eps: &[[f64; 3]; 3]) -> [[f64; 3]; 3] {
        let mu = self.mu();
        let lam = self.lambda_in_plane(analysis);
        let d = analysis.dim();
        let tr: f64 = (0..d).map(|i| eps[i][i]).sum();
        let mut s = [[0.0; 3]; 3];
        for i in 0..d {
            for j in 0..d {
                s[i][j] = 2.0 * mu * eps[i][j];
            }
            s[i][i] += lam * tr;
        }
        if analysis == Analysis::PlaneStrain {
            s[2][2] = self.poisson * (s[0][0] + s[1][1]);
        }
        s
    }
}

/// Von Mises equivalent stress of a full 3×3 stress tensor, computed on the tensor scaled
/// by its largest component so that its squares neither underflow (stresses of 1e-200
/// gave 0) nor overflow (1e170 gave infinity) where the result itself is representable.
pub fn von_mises(s: &[[f64; 3]; 3]) -> f64 {
    if let Some(bad) = s.iter().flatten().find(|v| !v.is_finite()) {
        // Non-finite stays non-finite for the result guard: NaN if any, else infinity.
        return if s.iter().flatten().any(|v| v.is_nan()) { f64::NAN } else { bad.abs() };
    }
    let m = s.iter().flatten().fold(0.0f64, |m, v| m.max(v.abs()));
    if m == 0.0 {
        return 0.0;
    }
    let t = |i: usize, j: usize| s[i][j] / m;
    let a = (t(0, 0) - t(1, 1)).powi(2) + (t(1, 1) - t(2, 2)).powi(2) + (t(2, 2) - t(0, 0)).powi(2);
    let b = t(0, 1).powi(2) + t(1, 2).powi(2) + t(0, 2).powi(2);
    m * (0.5 * a + 3.0 * b).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn uniaxial_stress_gives_young_modulus() {
        // Plane stress, ε_xx = 1e-3, ε_yy = −ν ε_xx: σ_xx = E ε_xx, σ_yy = 0.
        let m = Isotropic { young: 200.0, poisson: 0.3 };
        let eps = [[1e-3, 0.0, 0.0], [0.0, -0.3e-3, 0.0], [0.0; 3]];
        let s = m.stress(Analysis::PlaneStress, &eps);
        assert!((s[0][0] - 0.2).abs() < 1e-14 && s[1][1].abs() < 1e-14);
        assert!((von_mises(&s) - 0.2).abs() < 1e-14);
    }

    /// Uniaxial σ at the ends of the double range: von Mises = σ exactly scaled (1e-200
    /// gave 0 and 1e170 infinity when the squares were taken unscaled); non-finite stays
    /// non-finite.
    #[test]
    fn von_mises_neither_underflows_nor_overflows() {
        for sigma in [1e-200, 1.0, 1e170, 1e300] {
            let s = [[sigma, 0.0, 0.0], [0.0; 3], [0.0; 3]];
            assert!((von_mises(&s) / sigma - 1.0).abs() < 1e-15, "{sigma:e}: {}", von_mises(&s));
            let shear = [[0.0, sigma, 0.0], [sigma, 0.0, 0.0], [0.0; 3]];
            assert!((von_mises(&shear) / (sigma * 3f64.sqrt()) - 1.0).abs() < 1e-15);
        }
        assert_eq!(von_mises(&[[0.0; 3]; 3]), 0.0);
        assert!(von_mises(&[[f64::NAN, 0.0, 0.0], [0.0; 3], [0.0; 3]]).is_nan());
        assert_eq!(von_mises(&[[f64::INFINITY, 0.0, 0.0], [0.0; 3], [0.0; 3]]), f64::INFINITY);
    }
}
