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
//! **Elastic stick (a tangential spring with return mapping).** With a tangential stiffness
//! `k_t` (N/m per pair) a sticking pair is not rigid: it carries the force of a spring
//! stretched by the pair's slip since it last stuck, `F_t = F_t0 - k_t h v_t` over a step
//! (`v_t` the slip velocity at the step end, backward Euler), and slides when that trial
//! force leaves the cone, `|F_t| = mu F_n` (the return mapping of elastoplasticity: the
//! spring's elastic slip is given back, the rest is plastic). In a row it is a regularized
//! stick, `y = v_t + (lambda_t - lambda_t0) f / (k_t h) = 0` ([`super::rows`], `reg`), so it
//! costs no factorization. The spring stores `F_t^2 / (2 k_t)` per pair (counted with the
//! stored contact energy); the energy dissipated by friction is the slip work less that
//! store's growth. `k_t = 0` is the rigid stick (Coulomb's exact law). The penalty treatment
//! takes the normal penalty stiffness for `k_t` unless it is given; the others take a rigid
//! stick. Like a penalty stiffness, `k_t` is per pair.
//!
//! **Memory: the coefficient follows the slip.** Without memory the coefficient is a
//! function of the slip speed alone, taken at the step's start. A coefficient that falls
//! with the speed is then negative damping on every sliding node, `N |dmu/dv|` against the
//! node's mass: the smaller the element, the faster a node's slip oscillates (stick-slip at
//! the pitch's scale, the micro-slip oscillation explicit codes have met), and the
//! continuum's law has no length to converge to. With a memory `L` (`contact.friction_memory_um`,
//! a slip distance) a pair carries its coefficient as a state
//! ([`crate::model::PairState::friction_coefficient`]) that relaxes towards the falling law's
//! over the distance slid, `d mu / ds = -(mu - mu_ss(|v|)) / L` (the slip law of
//! rate-and-state friction, Ruina 1983, with the exponential falling law as its steady
//! curve). Over a step at the slip speed `|v|` of its end,
//! `mu_1 = mu_ss(|v|) + (mu_0 - mu_ss(|v|)) exp(-|v| h / L)` ([`FrictionLaw::relaxed`]), exact
//! for a constant speed; the next step's bound is `mu_1`. A pair that lands starts at
//! `mu_s` (the surfaces at rest); a sticking pair keeps its state, and so does a pair out
//! of contact (a node that chatters does not start again at `mu_s`). Nothing heals it with
//! time: a wheel's rim without a moving zone brings its material back to the patch after a
//! turn with the state it left with; a moving zone (`wheel.zone_sectors`) brings fresh
//! material, at rest, into the patch. Oscillations of a
//! node whose slip in a period is much less than `L` no longer move its coefficient, so the
//! mesh's scale loses the negative damping, while the patch's (slip distances of `L` and
//! more) keeps the falling law. The step must resolve the memory, `|v| h << L`.
//!
//! **In the step.** Each bounded tangential row ([`super::rows::RowKind::Bounded`]) takes
//! `mu(|v|)` at the pair's tangential relative velocity at the start of the step,
//! `c_t . v0 - w_t` (the slip speed of a sliding pair, about 0 for a sticking one, the
//! sliding speed of the surfaces for a pair that lands). The bound is thus explicit in the
//! slip speed (lagged one step), which keeps the frictional step a linear complementarity
//! problem on the factored matrix; the lag is `h |dmu/dv| |dv/dt|`, first order in `h`.
//!
//! **In 3D** a pair has two tangential rows ([`push_rows`]) bounded together by Coulomb's
//! isotropic cone, `|F_t| <= mu F_n` on the tangential vector ([`super::rows`], Coulomb's
//! cone): the slip direction is found in the tangent plane, the force opposing the slip
//! velocity; `mu` is taken at the slip speed `|v_t|`, and an elastic stick has a spring per
//! tangent (the same `k_t`: isotropic).

use super::rows::{Row, RowKind, RowSolver};
use crate::model::Terms;
use crate::time::integrator::Maps;

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
    /// The tangential (stick) stiffness `k_t`, N/m per pair (0: a rigid stick, or the normal
    /// stiffness with the penalty treatment; module docs).
    pub tangential_stiffness: f64,
    /// The memory `L`, m: the slip distance over which a pair's coefficient follows the
    /// falling law (module docs, Memory); 0: the coefficient at the step's start slip speed.
    pub memory: f64,
}

impl FrictionLaw {
    /// Coulomb's law with the constant coefficient `mu`.
    pub fn coulomb(mu: f64) -> Self {
        Self {
            static_mu: mu,
            kinetic: mu,
            velocity: 1.0,
            viscosity: 0.0,
            tangential_stiffness: 0.0,
            memory: 0.0,
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

    /// A pair's coefficient `mu0` after a step `h` at the slip speed `speed` with memory
    /// (module docs, Memory): `mu_ss + (mu0 - mu_ss) exp(-|v| h / L)`, `mu_ss` the falling
    /// law's coefficient at `speed`.
    pub fn relaxed(&self, mu0: f64, speed: f64, h: f64) -> f64 {
        let steady = self.coefficient(speed);
        if self.memory > 0.0 {
            steady + (mu0 - steady) * (-speed.abs() * h / self.memory).exp()
        } else {
            steady
        }
    }

    /// The coefficient state a pair carries to the next step, with memory: its state
    /// `prev` (`None`: at rest, `mu_s`) relaxed over a step `h` at the slip velocity
    /// `slips` (the tangents' rates at the step's end); `None` without memory.
    pub fn remember(&self, prev: Option<f64>, slips: [f64; 2], h: f64) -> Option<f64> {
        (self.memory > 0.0)
            .then(|| self.relaxed(prev.unwrap_or(self.static_mu), slips[0].hypot(slips[1]), h))
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
        if !(self.tangential_stiffness.is_finite() && self.tangential_stiffness >= 0.0) {
            return Err(format!(
                "contact.tangential_stiffness must be a finite stiffness >= 0 (N/m per contact pair), got {}",
                self.tangential_stiffness
            ));
        }
        if !(self.memory.is_finite() && self.memory >= 0.0) {
            return Err(format!(
                "contact.friction_memory_um must be a finite slip distance >= 0 (um), got {}",
                1e6 * self.memory
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

/// The tangential spring of one step (module docs: elastic stick), for the tangential row of
/// a pair: its regularization `reg = f / (k_t h)` and the offset `-reg lambda_t0` of its `y0`,
/// from the pair's tangential force at the step start `f0` (N), the force per unit multiplier
/// `f` and the step `h`; `(0, 0)` for a rigid stick (`k_t = 0`).
pub fn stick_spring(kt: f64, f0: f64, force_per_multiplier: f64, h: f64) -> (f64, f64) {
    if kt > 0.0 {
        let reg = force_per_multiplier / (kt * h);
        (reg, -reg * f0 / force_per_multiplier)
    } else {
        (0.0, 0.0)
    }
}

/// The energy a tangential spring of stiffness `kt` holds at the force `f` (N): `f^2/(2 kt)`,
/// 0 for a rigid stick.
pub fn spring_energy(kt: f64, f: f64) -> f64 {
    if kt > 0.0 {
        0.5 * f * f / kt
    } else {
        0.0
    }
}

impl From<f64> for FrictionLaw {
    fn from(mu: f64) -> Self {
        Self::coulomb(mu)
    }
}

/// The friction rows of pair `p` beside its normal row `normal` ([`super::rows`]): one
/// bounded row per tangent `(c_t, w_t)` with `y = (c_t.V - w_t) + mu_v c_t.x`, the slip
/// velocity at the step's end through the integrator's maps `maps` (`v_pred = V`), and an
/// elastic stick's spring ([`stick_spring`], the spring forces `f0` at the step's start)
/// when `kt > 0`. In 3D (`tangents[1]` given) the two rows name each other: their bound is
/// Coulomb's cone on the tangential vector, the coefficient taken at the slip speed
/// `|s|` of the start velocities `v0`; in 2D at the one tangent's slip rate, as before.
/// With memory the coefficient is the pair's `state` instead (module docs, Memory).
pub fn push_rows(
    rows: &mut RowSolver,
    law: &FrictionLaw,
    (p, normal): (usize, usize),
    tangents: [Option<(Terms, f64)>; 2],
    (v0, v_pred): (&[f64], &[f64]),
    (kt, f0, state): (f64, [f64; 2], Option<f64>),
    (maps, h): (Maps, f64),
) {
    let slip = |k: usize| tangents[k].map_or(0.0, |(t, w): (Terms, f64)| t.dot(v0) - w);
    let speed = match tangents[1] {
        Some(_) => slip(0).hypot(slip(1)),
        None => slip(0),
    };
    // With memory the pair's state (at rest: mu_s), else the law at the start's speed.
    let mu_f = if law.memory > 0.0 {
        state.unwrap_or(law.static_mu)
    } else {
        law.coefficient(speed)
    };
    let first = rows.rows().len();
    for (k, tangent) in tangents.iter().enumerate() {
        let Some((terms, w)) = *tangent else { continue };
        let (reg, dy) = stick_spring(kt, f0[k], maps.force, h);
        rows.push(Row {
            pair: p,
            terms,
            kind: RowKind::Bounded {
                normal,
                mu_f,
                eta: law.viscosity / maps.force,
                with: tangents[1].map(|_| first + 1 - k),
            },
            y0: terms.dot(v_pred) - w + dy,
            mu: maps.mu_v,
            reg,
        });
    }
}

/// Which tangent of its pair the bounded row `i` of `rows` is: 1 for the second row of a
/// 3D pair (its partner comes first), else 0.
pub fn tangent_index(rows: &[Row], i: usize) -> usize {
    match rows[i].kind {
        RowKind::Bounded { with: Some(o), .. } if o < i => 1,
        _ => 0,
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
            tangential_stiffness: 0.0,
            memory: 0.0,
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
