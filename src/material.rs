//! Linear elastic material and the section data of 1D and 2D models.
//!
//! Units are SI inside softway: Pa for moduli, kg/m^3 for density, m for lengths.

use serde::Serialize;

/// Linear isotropic elastic material.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Elastic {
    /// Young's modulus `E`, Pa.
    pub young: f64,
    /// Poisson's ratio `nu`, dimensionless, in (-1, 0.5).
    pub poisson: f64,
    /// Mass density `rho`, kg/m^3.
    pub density: f64,
}

impl Elastic {
    /// Longitudinal bar wave speed `c = sqrt(E / rho)`, m/s.
    pub fn bar_wave_speed(&self) -> f64 {
        (self.young / self.density).sqrt()
    }
}

/// The 2D hypothesis of a plane model.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum PlaneModel {
    /// Plane stress (`sigma_zz = 0`): thin plates, the paper's wheel.
    Stress,
    /// Plane strain (`eps_zz = 0`): long bodies.
    Strain,
}

impl PlaneModel {
    /// The 3x3 elasticity matrix `E` of Eq. (13) in Voigt form
    /// `[sigma_xx, sigma_yy, tau_xy] = E [eps_xx, eps_yy, gamma_xy]`.
    pub fn elasticity_matrix(&self, m: &Elastic) -> [[f64; 3]; 3] {
        let (e, nu) = (m.young, m.poisson);
        match self {
            PlaneModel::Stress => {
                let c = e / (1.0 - nu * nu);
                [
                    [c, c * nu, 0.0],
                    [c * nu, c, 0.0],
                    [0.0, 0.0, c * (1.0 - nu) / 2.0],
                ]
            }
            PlaneModel::Strain => {
                let c = e / ((1.0 + nu) * (1.0 - 2.0 * nu));
                [
                    [c * (1.0 - nu), c * nu, 0.0],
                    [c * nu, c * (1.0 - nu), 0.0],
                    [0.0, 0.0, c * (1.0 - 2.0 * nu) / 2.0],
                ]
            }
        }
    }

    /// The out-of-plane normal stress `sigma_zz` for given in-plane stresses (zero in plane
    /// stress, `nu (sigma_xx + sigma_yy)` in plane strain).
    pub fn sigma_zz(&self, m: &Elastic, sxx: f64, syy: f64) -> f64 {
        match self {
            PlaneModel::Stress => 0.0,
            PlaneModel::Strain => m.poisson * (sxx + syy),
        }
    }
}
