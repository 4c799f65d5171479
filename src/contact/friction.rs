//! The friction law of the contact pairs: Coulomb, a coefficient that depends on the slip
//! speed (the falling curve of squeal and corrugation studies), and a viscoplastic
//! overstress (the paper's rheological law, §1).
//!
//! `mu(v) = mu_k + (mu_s - mu_k) exp(-|v| / v_s)`: the static coefficient `mu_s` at rest,
//! tending to the kinetic `mu_k` as the slip speed `|v|` grows past the Stribeck velocity
//! `v_s` (m/s). With `mu_k = mu_s` it is Coulomb's constant coefficient.
//!
//! **Viscoplastic (Perzyna) friction.** With a viscosity `eta` (N s/m per contact pair) a
//! pair sticks while `|F_t| <= mu F_n` and slides with the overstress `|F_t| = mu F_n + eta
//! |v|`: its slip rate is the excess over the bound divided by `eta`
//! ([`super::rows::RowKind::Bounded`]); `eta = 0` is Coulomb's rigid-plastic limit. Like a
//! penalty stiffness, `eta` is per pair, so it scales with the rim pitch.
//!
//! **In the step.** Each bounded tangential row ([`super::rows::RowKind::Bounded`]) takes
//! `mu(|v|)` at the pair's tangential relative velocity at the start of the step,
//! `c_t . v0 - w_t` (the slip speed of a sliding pair, about 0 for a sticking one, the
//! sliding speed of the surfaces for a pair that lands). The bound is thus explicit in the
//! slip speed (lagged one step), which keeps the frictional step a linear complementarity
//! problem on the factored matrix; the lag is `h |dmu/dv| |dv/dt|`, first order in `h`.

/// A friction law (module docs).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FrictionLaw {
    /// The static coefficient `mu_s` (Coulomb's `mu` when `kinetic == static_mu`).
    pub static_mu: f64,
    /// The kinetic coefficient `mu_k` reached at high slip speed.
    pub kinetic: f64,
    /// The Stribeck velocity `v_s`, m/s (unused for Coulomb).
    pub velocity: f64,
    /// The viscoplastic viscosity `eta`, N s/m per pair (0: none).
    pub viscosity: f64,
}

impl FrictionLaw {
    /// Coulomb's law with the constant coefficient `mu`.
    pub fn coulomb(mu: f64) -> Self {
        Self {
            static_mu: mu,
            kinetic: mu,
            velocity: 1.0,
            viscosity: 0.0,
        }
    }

    /// The coefficient at slip speed `v`, m/s.
    pub fn coefficient(&self, v: f64) -> f64 {
        if self.kinetic == self.static_mu {
            self.static_mu
        } else {
            self.kinetic + (self.static_mu - self.kinetic) * (-v.abs() / self.velocity).exp()
        }
    }

    /// Some friction at some speed (a law that is zero everywhere adds no rows).
    pub fn is_active(&self) -> bool {
        self.static_mu > 0.0 || self.kinetic > 0.0
    }

    /// Refuses coefficients that are not finite and `>= 0` and a Stribeck velocity that is
    /// not finite and `> 0`.
    ///
    /// # Errors
    /// One line naming the scenario key (`contact.friction`, `contact.friction_kinetic`,
    /// `contact.friction_velocity`).
    pub fn check(&self) -> Result<(), String> {
        for (key, v) in [
            ("contact.friction", self.static_mu),
            ("contact.friction_kinetic", self.kinetic),
        ] {
            if !(v.is_finite() && v >= 0.0) {
                return Err(format!("{key} must be a finite coefficient >= 0, got {v}"));
            }
        }
        if !(self.viscosity.is_finite() && self.viscosity >= 0.0) {
            return Err(format!(
                "contact.friction_viscosity must be a finite viscosity >= 0 (N s/m per contact pair), got {}",
                self.viscosity
            ));
        }
        if !(self.velocity.is_finite() && self.velocity > 0.0) {
            return Err(format!(
                "contact.friction_velocity must be a finite speed > 0 (m/s), got {}",
                self.velocity
            ));
        }
        Ok(())
    }
}

impl From<f64> for FrictionLaw {
    fn from(mu: f64) -> Self {
        Self::coulomb(mu)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn falling_law_goes_from_static_to_kinetic() {
        let law = FrictionLaw {
            static_mu: 0.4,
            kinetic: 0.2,
            velocity: 0.5,
            viscosity: 0.0,
        };
        assert_eq!(law.coefficient(0.0), 0.4);
        assert!((law.coefficient(0.5) - (0.2 + 0.2 / std::f64::consts::E)).abs() < 1e-15);
        assert!((law.coefficient(-0.5) - law.coefficient(0.5)).abs() < 1e-15);
        assert!((law.coefficient(100.0) - 0.2).abs() < 1e-15);
        assert_eq!(FrictionLaw::from(0.3).coefficient(7.0), 0.3);
        assert!(law.check().is_ok());
        let bad = FrictionLaw {
            velocity: 0.0,
            ..law
        };
        assert!(bad
            .check()
            .unwrap_err()
            .contains("contact.friction_velocity"));
    }
}
