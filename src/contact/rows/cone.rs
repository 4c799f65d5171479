//! Coulomb's cone of a 3D pair in the active set: the trial force's rule (the module docs of
//! [`super`], Coulomb's cone).

use super::{Activity, ConeMove, RowSolver, CONE_TURN};

impl RowSolver {
    /// The weight `c` of a 3D pair's trial force `tau = lambda - c y`: the inverse of the
    /// mean of `W`'s diagonal over its two tangential rows (a force per unit of slip, the
    /// pair's own stiffness against sliding).
    pub(super) fn trial_weight(&self, p: usize, o: usize, k: usize) -> f64 {
        2.0 / (self.w[p * k + p] + self.w[o * k + o]).max(f64::MIN_POSITIVE)
    }

    /// One pass of the cone's rules on the 3D pair of tangential rows `p < o` with the
    /// normal row and coefficient `(normal, mu_f)` (module docs, Coulomb's cone): follow
    /// the normal row in and out, start sliding outside the disk, stick again on a
    /// reversal, else turn the sliding direction toward `-y / |y|` (when `may_turn`).
    pub(super) fn cone(
        &mut self,
        p: usize,
        o: usize,
        (normal, mu_f): (usize, f64),
        k: usize,
        may_turn: bool,
    ) -> ConeMove {
        // A pair whose normal row pulls (a held pair in tension, which the treatment
        // releases after this solve) carries no friction: its bound `mu_f max(lambda_q, 0)`
        // is zero, and a slide on a negative `lambda_q` would push along its slip and turn
        // its direction round at every re-solve.
        let normal_on = self.state[normal] != Activity::Off;
        let both = |s: &mut Vec<Activity>, a: Activity, b: Activity| {
            s[p] = a;
            s[o] = b;
        };
        match (self.state[p], self.state[o]) {
            (Activity::Off, _) if normal_on => {
                both(&mut self.state, Activity::On, Activity::On);
                ConeMove::State
            }
            (Activity::On | Activity::Slip(_), _) if !normal_on => {
                both(&mut self.state, Activity::Off, Activity::Off);
                ConeMove::State
            }
            (Activity::On, _) => {
                let bound = mu_f * self.lambda[normal].max(0.0);
                let f = self.lambda[p].hypot(self.lambda[o]);
                if f > bound * (1.0 + 1e-12) {
                    // Sticking, the trial force is the force itself.
                    let d = (self.lambda[p] / f, self.lambda[o] / f);
                    both(&mut self.state, Activity::Slip(d.0), Activity::Slip(d.1));
                    self.kappa[p] = bound / f;
                    self.kappa[o] = bound / f;
                    self.stick_slip += 1;
                    ConeMove::State
                } else {
                    ConeMove::None
                }
            }
            (Activity::Slip(dp), Activity::Slip(dq)) => {
                // The trial force `tau = lambda - c y` (module docs): back inside the bound,
                // the pair sticks; outside, it slides along `tau`.
                let (yp, yo) = (self.y(p, k), self.y(o, k));
                let c = self.trial_weight(p, o, k);
                let (tp, to) = (self.lambda[p] - c * yp, self.lambda[o] - c * yo);
                let trial = tp.hypot(to);
                let bound = mu_f * self.lambda[normal].max(0.0);
                if trial <= bound {
                    both(&mut self.state, Activity::On, Activity::On);
                    self.stick_slip += 1;
                    return ConeMove::State;
                }
                let kappa = bound / trial;
                self.kappa[p] = kappa;
                self.kappa[o] = kappa;
                // A pair whose normal row pulls (a held pair in tension, released by the
                // treatment after this solve) keeps its direction: on a negative bound the
                // trial force turns round at every re-solve.
                if !may_turn || self.lambda[normal] <= 0.0 {
                    return ConeMove::None;
                }
                let d = (tp / trial, to / trial);
                if (d.0 - dp).abs() + (d.1 - dq).abs() > CONE_TURN {
                    both(&mut self.state, Activity::Slip(d.0), Activity::Slip(d.1));
                    ConeMove::Turn
                } else {
                    ConeMove::None
                }
            }
            _ => ConeMove::None,
        }
    }
}
