//! The divergence guard: a run whose energy grows beyond what the work done on the system
//! can explain, whose contact pulls, or whose model leaves its validity, is stopped, never
//! reported as a result.
//!
//! **The bound.** The energy of a run obeys the balance
//! $$E(t) = E(t_0) + W(t) - D(t) + E_{num}(t),$$
//! $$E = \tfrac12 v^T M v + \tfrac12 u^T K u + E_{pen},$$
//! with `W` the work of the external loads and of the moving obstacles' contact forces,
//! `D >= 0` what damping, friction and the schemes' numerical dissipation take out, and
//! `E_num` what the discretization creates. `|W|` is bounded by the accumulated absolute
//! power
//! $$W^+(t) = \sum_k \Big(\big|f(t_k) \cdot (u_k - u_{k-1})\big| +
//!   h \sum_p |F_p|\\,|w_p| + h \sum_p |F_{t,p}|\\,|w_{t,p}|\Big)$$
//! (`F_p` a pair's normal force, `w_p` its obstacle's normal velocity at the pair, `F_t`,
//! `w_t` the tangential ones: a fixed obstacle does no work). The guard stops the run when
//! $$E(t_k) > \kappa\\,\big(E(t_0) + W^+(t_k)\big) + E_{floor},\qquad \kappa = 2,$$
//! checked every [`CHECK_STRIDE`] steps and at the last. `kappa = 2` because the largest
//! energy excursion a treatment is documented to make is the penalty spring's (+40% in
//! tests/on_block.rs; the exact hold's +10%), while a run past its stability limit grows
//! geometrically (the average-acceleration Newmark with exact contact on the rolling wheel:
//! x1e8 in 20 ms; central difference past `2 / omega_max`: x1e28) or settles at several
//! times its energy (a penalty of 1e30 N/m: x3). `E_floor` ([`ENERGY_FLOOR`]) keeps runs
//! that start at rest from tripping on round-off before any work is done.
//!
//! **Forces that push.** A contact can only push: every step the pairs' tensile forces
//! must sum to round-off ([`PULL_TOLERANCE`] of the largest compressive total so far, at
//! least [`PULL_FLOOR`]), else the run is stopped as diverged ([`Cause::Pulled`]). The
//! treatments release a tensile hold and never brake or give back by pulling, so a tension
//! means a step or a rim the treatment cannot follow.
//!
//! **A model outside its validity.** Two more stops share [`Diverged`]: a plastic solve
//! whose iteration reaches its cap ([`Cause::Unconverged`], checked by the simulation after
//! every step), and a pinned wheel whose rigid rotation against its frame makes the linear
//! model's error in the rim's reach pass a quarter of the flattening ([`Cause::Turned`],
//! the wheel run's rotation watch).
//!
//! The check costs two sparse quadratic forms every [`CHECK_STRIDE`] steps, and per step a
//! dot product with the load and the rows of the pairs that carry a force.

/// Steps between two energy checks.
pub const CHECK_STRIDE: usize = 64;

/// The ratio `kappa` of the bound (module docs).
pub const ENERGY_FACTOR: f64 = 2.0;

/// The energy below which the guard never trips, J.
pub const ENERGY_FLOOR: f64 = 1e-9;

/// The run's energy beyond its bound, or a contact that pulled (module docs).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Diverged {
    /// The step.
    pub step: usize,
    /// Its time, s.
    pub t: f64,
    /// What was found.
    pub cause: Cause,
}

/// What the guard found (module docs).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Cause {
    /// The energy exceeded its bound.
    Energy {
        /// The energy, J.
        energy: f64,
        /// The bound it exceeded, J.
        bound: f64,
        /// `kappa`.
        factor: f64,
    },
    /// The pairs' forces summed to a tension beyond round-off: a contact pulled.
    Pulled {
        /// The sum of the tensile pair forces, N (negative).
        force: f64,
        /// The largest compressive total force of the run so far, N.
        peak: f64,
    },
    /// The plastic iteration of a step did not converge within its cap: the flow is beyond
    /// what the step and the mesh resolve, or the support or material concentrates it
    /// without bound (a hub of 2.7 um: 113 iterations a step, a plastic strain of 180).
    Unconverged {
        /// The cap, corrections a solve.
        iterations: usize,
    },
    /// A pinned wheel turned against its frame so far that the linear model's error in the
    /// rim's reach, `R theta^2 / 2`, passed a stated part of the flattening: its contact
    /// force would be wrong by about as much (`softway::kinds::wheel::run`'s rotation watch).
    Turned {
        /// The rigid rotation, rad.
        theta: f64,
        /// `R theta^2 / 2` over the flattening.
        reach: f64,
        /// The part of the flattening beyond which the run is stopped.
        limit: f64,
    },
}

impl std::fmt::Display for Diverged {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let (step, t) = (self.step, self.t);
        match self.cause {
            Cause::Energy {
                energy,
                bound,
                factor,
            } => write!(
                f,
                "the run diverged at step {step} (t = {t:e} s): its energy {energy:.4e} J exceeds {factor} x (initial energy + work done on it) = {bound:.4e} J; a step beyond the integrator's stability limit (`time.h`, `time.cfl`, `time.alpha`), a penalty too stiff for the step (`contact.penalty`), an integrator that does not suit the contact (`time.integrator` with `contact.method`) or an ill-posed material (`material.*`)"
            ),
            Cause::Pulled { force, peak } => write!(
                f,
                "the run diverged at step {step} (t = {t:e} s): its contact pulled with {:.4e} N (the largest compressive total so far {peak:.4e} N), and a contact can only push; a step too long for the contact's events (`time.h` against a rim node's passage), a rim too coarse for the contact patch (`wheel.rim_nodes`; on a track `vehicle.wheel_rim_nodes`) or a treatment that does not suit them (`contact.method`)",
                -force
            ),
            Cause::Unconverged { iterations } => write!(
                f,
                "the run was stopped at step {step} (t = {t:e} s): its plastic iteration did not converge within {iterations} corrections (`material.plastic_tolerance`): the plastic flow is beyond what the step and the mesh resolve (`time.h`, `wheel.rim_nodes`), or the support or the material concentrates it without bound (`wheel.hub_radius`, `material.yield_stress`)"
            ),
            Cause::Turned {
                theta,
                reach,
                limit,
            } => write!(
                f,
                "the run was stopped at step {step} (t = {t:e} s): the wheel turned {theta:.3e} rad against its frame (its rigid rotation about the pinned centre, which only the contact holds), and a linear model misses the rim's reach R theta^2 / 2 = {:.0}% of the flattening, beyond {:.0}%: its contact force would be wrong by about as much; hold the wheel by its hub (`wheel.support = \"hub\"`)",
                100.0 * reach,
                100.0 * limit
            ),
        }
    }
}

impl std::error::Error for Diverged {}

/// The tension a step's pairs may sum to before the guard stops the run, relative to the
/// largest compressive total force so far (round-off of the multipliers).
pub const PULL_TOLERANCE: f64 = 1e-9;

/// The tension below which the guard never trips, N.
pub const PULL_FLOOR: f64 = 1e-9;

/// What the guard does when the bound is exceeded.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub enum GuardMode {
    /// Stop the run with [`Diverged`] (every job that reports a result).
    #[default]
    Stop,
    /// Record the first divergence ([`DivergenceGuard::first`]) and go on: the integrator
    /// and treatment lab (`softway compare`), whose rows show what a combination does and
    /// mark the ones that diverged.
    Record,
}

/// The guard's running sums (module docs).
#[derive(Debug, Clone, Default)]
pub struct DivergenceGuard {
    mode: GuardMode,
    first: Option<Diverged>,
    initial: Option<f64>,
    work: f64,
    steps: usize,
    /// The largest compressive total contact force so far, N.
    peak_force: f64,
    /// The load at the step's end (work memory).
    load: Vec<f64>,
}

impl DivergenceGuard {
    /// A guard for a model of `n` dofs.
    pub fn new(n: usize) -> Self {
        Self {
            load: vec![0.0; n],
            ..Self::default()
        }
    }

    /// Sets what the guard does past its bound.
    pub fn set_mode(&mut self, mode: GuardMode) {
        self.mode = mode;
    }

    /// The first divergence recorded ([`GuardMode::Record`]).
    pub fn first(&self) -> Option<Diverged> {
        self.first
    }

    /// The load buffer to fill with `f(t_k)` before [`DivergenceGuard::add_step`].
    pub fn load_mut(&mut self) -> &mut [f64] {
        &mut self.load
    }

    /// Records the initial energy, J (the first call only).
    pub fn start(&mut self, energy: f64) {
        self.initial.get_or_insert(energy);
    }

    /// Adds one final step's work bound: the load's `|f . (u1 - u0)|` (with the load put in
    /// [`DivergenceGuard::load_mut`]) and the obstacles' `contact_work` (J, `h sum |F||w|`).
    /// Returns true when the energy is due for a check.
    pub fn add_step(&mut self, u0: &[f64], u1: &[f64], contact_work: f64) -> bool {
        let mut fw = 0.0;
        for ((f, a), b) in self.load.iter().zip(u0).zip(u1) {
            fw += f * (b - a);
        }
        self.work += fw.abs() + contact_work.abs();
        self.steps += 1;
        self.steps % CHECK_STRIDE == 0
    }

    /// The bound at this point, J.
    pub fn bound(&self) -> f64 {
        ENERGY_FACTOR * (self.initial.unwrap_or(0.0) + self.work) + ENERGY_FLOOR
    }

    /// Checks the energy `energy` (J) of step `step` at time `t`.
    ///
    /// # Errors
    /// [`Diverged`] when it exceeds [`DivergenceGuard::bound`] or is not finite, in
    /// [`GuardMode::Stop`] (in [`GuardMode::Record`] the first is kept instead).
    pub fn check(&mut self, step: usize, t: f64, energy: f64) -> Result<(), Diverged> {
        let bound = self.bound();
        if energy <= bound {
            return Ok(());
        }
        self.found(Diverged {
            step,
            t,
            cause: Cause::Energy {
                energy,
                bound,
                factor: ENERGY_FACTOR,
            },
        })
    }

    /// Checks the sign of step `step`'s pair forces at time `t`: `push` the sum of the
    /// compressive ones and `pull` of the tensile ones (<= 0), N.
    ///
    /// # Errors
    /// [`Diverged`] with [`Cause::Pulled`] when `pull` exceeds round-off
    /// ([`PULL_TOLERANCE`] of the largest compressive total so far, [`PULL_FLOOR`]), in
    /// [`GuardMode::Stop`] (in [`GuardMode::Record`] the first is kept instead).
    pub fn check_forces(
        &mut self,
        step: usize,
        t: f64,
        push: f64,
        pull: f64,
    ) -> Result<(), Diverged> {
        self.peak_force = self.peak_force.max(push);
        if pull >= -(PULL_TOLERANCE * self.peak_force + PULL_FLOOR) {
            return Ok(());
        }
        self.found(Diverged {
            step,
            t,
            cause: Cause::Pulled {
                force: pull,
                peak: self.peak_force,
            },
        })
    }

    fn found(&mut self, d: Diverged) -> Result<(), Diverged> {
        match self.mode {
            GuardMode::Stop => Err(d),
            GuardMode::Record => {
                self.first.get_or_insert(d);
                Ok(())
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A constant load's work is `f . (u_end - u_start)` when the motion is monotone, and
    /// the bound is twice the initial energy plus that work.
    #[test]
    fn the_bound_follows_the_work_done() {
        let mut g = DivergenceGuard::new(2);
        g.start(1.0);
        g.start(5.0);
        g.load_mut().copy_from_slice(&[2.0, -1.0]);
        let mut u = [0.0, 0.0];
        for k in 0..CHECK_STRIDE {
            let u1 = [u[0] + 0.1, u[1] - 0.05];
            let due = g.add_step(&u, &u1, 0.01);
            assert_eq!(due, k + 1 == CHECK_STRIDE);
            u = u1;
        }
        let work = CHECK_STRIDE as f64 * (0.2 + 0.05 + 0.01);
        assert!((g.bound() - (2.0 * (1.0 + work) + ENERGY_FLOOR)).abs() < 1e-12);
        assert!(g.check(16, 1.0, 2.0 * (1.0 + work) - 1e-6).is_ok());
        let e = g.check(16, 1.0, 2.0 * (1.0 + work) + 1e-6).unwrap_err();
        assert_eq!(e.step, 16);
        assert!(g.check(16, 1.0, f64::NAN).is_err());
        g.set_mode(GuardMode::Record);
        assert!(g.check(32, 2.0, 1e9).is_ok());
        assert!(g.check(48, 3.0, 1e10).is_ok());
        assert_eq!(g.first().map(|d| d.step), Some(32));
    }

    /// A tension beyond round-off of the largest compressive total so far stops the run;
    /// round-off does not.
    #[test]
    fn a_contact_that_pulls_is_stopped() {
        let mut g = DivergenceGuard::new(1);
        assert!(g.check_forces(1, 0.1, 0.0, -0.5 * PULL_FLOOR).is_ok());
        assert!(g.check_forces(2, 0.2, 1e5, 0.0).is_ok());
        assert!(g.check_forces(3, 0.3, 5e4, -1e-5).is_ok());
        let e = g.check_forces(4, 0.4, 5e4, -1e-3).unwrap_err();
        assert_eq!(e.step, 4);
        assert_eq!(
            e.cause,
            Cause::Pulled {
                force: -1e-3,
                peak: 1e5
            }
        );
        let msg = e.to_string();
        assert!(
            msg.contains("pulled with 1.0000e-3 N") && msg.contains("time.h"),
            "{msg}"
        );
    }
}
