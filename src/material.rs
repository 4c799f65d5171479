//! Linear elastic material and the section data of 1D and 2D models.
//!
//! Units are SI inside softway: Pa for moduli, kg/m^3 for density, m for lengths.
//!
//! # Stress invariants of the plane models
//!
//! A plane model carries the in-plane stress $[\sigma_{xx}, \sigma_{yy}, \tau_{xy}]$; the
//! out-of-plane shears are zero and the out-of-plane normal stress is
//!
//! - plane stress: $\sigma_{zz} = 0$;
//! - plane strain ($\varepsilon_{zz} = 0$, so $\sigma_{zz} - \nu(\sigma_{xx} + \sigma_{yy}) = 0$
//!   by Hooke's law): $\sigma_{zz} = \nu(\sigma_{xx} + \sigma_{yy})$
//!   ([`PlaneModel::sigma_zz`]).
//!
//! The second invariant of the deviatoric stress $s = \sigma - \tfrac13
//! \operatorname{tr}\sigma\, I$ of that full 3D state, and the von Mises stress, are
//! ([`j2`], [`von_mises`], [`PlaneModel::stress_invariants`])
//!
//! $$J_2 = \tfrac12 s : s
//!   = \tfrac16\left[(\sigma_{xx} - \sigma_{yy})^2 + (\sigma_{yy} - \sigma_{zz})^2 +
//!   (\sigma_{zz} - \sigma_{xx})^2\right] + \tau_{xy}^2,\qquad
//!   \sigma_{\text{vM}} = \sqrt{3 J_2},$$
//!
//! so in plane strain $J_2$ includes $\sigma_{zz}$ through the two differences
//! $\sigma_{yy} - \sigma_{zz}$ and $\sigma_{zz} - \sigma_{xx}$, and in plane stress those
//! reduce to $\sigma_{yy}$ and $\sigma_{xx}$. Checks: uniaxial stress $\sigma$ gives
//! $J_2 = \sigma^2/3$ (von Mises $|\sigma|$), pure shear $\tau$ gives $J_2 = \tau^2$
//! (von Mises $\sqrt3\,|\tau|$), a hydrostatic state gives 0.

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
    /// stress, `nu (sigma_xx + sigma_yy)` in plane strain), Pa.
    pub fn sigma_zz(&self, m: &Elastic, sxx: f64, syy: f64) -> f64 {
        match self {
            PlaneModel::Stress => 0.0,
            PlaneModel::Strain => m.poisson * (sxx + syy),
        }
    }

    /// `J2` (Pa^2) and the von Mises stress (Pa) of the in-plane stress
    /// `s = [sxx, syy, txy]` (Pa), with this model's `sigma_zz` (module docs).
    pub fn stress_invariants(&self, m: &Elastic, s: [f64; 3]) -> (f64, f64) {
        let szz = self.sigma_zz(m, s[0], s[1]);
        (j2(s[0], s[1], s[2], szz), von_mises(s[0], s[1], s[2], szz))
    }
}

/// Second invariant of the deviatoric stress, `J2 = 1/2 s:s` (Pa^2), of the stress state
/// with the in-plane components `sxx, syy, txy` and the out-of-plane normal stress `szz`
/// (Pa; no out-of-plane shear). Module docs.
pub fn j2(sxx: f64, syy: f64, txy: f64, szz: f64) -> f64 {
    ((sxx - syy).powi(2) + (syy - szz).powi(2) + (szz - sxx).powi(2)) / 6.0 + txy * txy
}

/// Von Mises equivalent stress `sqrt(3 J2)` (Pa), see [`j2`].
pub fn von_mises(sxx: f64, syy: f64, txy: f64, szz: f64) -> f64 {
    (3.0 * j2(sxx, syy, txy, szz)).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    const STEEL: Elastic = Elastic {
        young: 2.05e11,
        poisson: 0.3,
        density: 7830.0,
    };

    fn close(a: f64, b: f64, tol: f64) -> bool {
        (a - b).abs() <= tol * a.abs().max(b.abs())
    }

    #[test]
    fn j2_and_von_mises_of_simple_states() {
        let s = -123.0e6;
        assert!(close(j2(s, 0.0, 0.0, 0.0), s * s / 3.0, 1e-15));
        assert!(close(j2(0.0, s, 0.0, 0.0), s * s / 3.0, 1e-15));
        assert!(close(j2(0.0, 0.0, 0.0, s), s * s / 3.0, 1e-15));
        assert!(close(von_mises(s, 0.0, 0.0, 0.0), s.abs(), 1e-15));
        // Pure shear: J2 = tau^2, von Mises = sqrt(3) tau; also as sxx = -syy = tau.
        let tau = 40.0e6;
        assert!(close(j2(0.0, 0.0, tau, 0.0), tau * tau, 1e-15));
        assert!(close(j2(tau, -tau, 0.0, 0.0), tau * tau, 1e-15));
        assert!(close(
            von_mises(tau, -tau, 0.0, 0.0),
            3f64.sqrt() * tau,
            1e-15
        ));
        // Hydrostatic: zero.
        assert_eq!(j2(5.0e6, 5.0e6, 0.0, 5.0e6), 0.0);
        // Against 1/2 s:s computed from the deviator.
        let (sxx, syy, txy, szz): (f64, f64, f64, f64) = (3.0, -1.5, 0.7, 0.4);
        let p = (sxx + syy + szz) / 3.0;
        let ss = (sxx - p).powi(2) + (syy - p).powi(2) + (szz - p).powi(2) + 2.0 * txy * txy;
        assert!(close(j2(sxx, syy, txy, szz), 0.5 * ss, 1e-14));
    }

    #[test]
    fn plane_invariants_include_sigma_zz_in_plane_strain_only() {
        let nu = STEEL.poisson;
        let s = 200.0e6;
        // Uniaxial in-plane stress. Plane stress: J2 = s^2/3.
        let (j, vm) = PlaneModel::Stress.stress_invariants(&STEEL, [s, 0.0, 0.0]);
        assert!(close(j, s * s / 3.0, 1e-15) && close(vm, s, 1e-15));
        // Plane strain: sigma_zz = nu s, J2 = [s^2 + (nu s)^2 + (nu s - s)^2] / 6
        // = s^2 (1 - nu + nu^2) / 3 (0.79 s^2 / 3 for nu = 0.3).
        assert!(close(
            PlaneModel::Strain.sigma_zz(&STEEL, s, 0.0),
            nu * s,
            1e-15
        ));
        let (j, vm) = PlaneModel::Strain.stress_invariants(&STEEL, [s, 0.0, 0.0]);
        assert!(close(j, s * s * 0.79 / 3.0, 1e-14), "{j}");
        assert!(close(vm, s * 0.79f64.sqrt(), 1e-14));
        // Equal biaxial s, s: plane stress J2 = s^2/3; plane strain sigma_zz = 2 nu s and
        // J2 = (1 - 2 nu)^2 s^2 / 3 (0.16 s^2 / 3).
        let (j, _) = PlaneModel::Stress.stress_invariants(&STEEL, [s, s, 0.0]);
        assert!(close(j, s * s / 3.0, 1e-15));
        let (j, _) = PlaneModel::Strain.stress_invariants(&STEEL, [s, s, 0.0]);
        assert!(close(j, s * s * 0.16 / 3.0, 1e-13), "{j}");
        // Pure shear tau: sigma_zz = 0 in both, J2 = tau^2.
        let tau = 70.0e6;
        for pm in [PlaneModel::Stress, PlaneModel::Strain] {
            let (j, vm) = pm.stress_invariants(&STEEL, [0.0, 0.0, tau]);
            assert!(close(j, tau * tau, 1e-15) && close(vm, 3f64.sqrt() * tau, 1e-15));
        }
    }
}
