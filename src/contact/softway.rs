//! The "soft way" (paper §3.1, Table 1) as a per-node state machine.
//!
//! A node about to penetrate an obstacle is braked in the step *before* the one in which the
//! penetration is found, so that it arrives on the obstacle with the obstacle's normal
//! velocity; it is then held while the reaction is compressive, released on tension, and the
//! braking reaction `R` is given back as an external force in its first free step.
//!
//! **Braking value (Eq. 26, generalised).** With indices -1, 0, 1 for `t_{i-2}, t_{i-1},
//! t_i` (penetration found at `t_i`), let `n, c` be the obstacle's half-space at `t_i`
//! (`n . x = c` on the surface) and `w` its surface normal velocity there. Writing
//! `p = n . x`, `q = n . v`, Eq. (10) twice gives
//! `p_1 = p_{-1} + h (1 - beta) q_{-1} + h q_0 + h beta q_1`. Asking `p_1 = c` (on the
//! surface at `t_i`) and `q_1 = w` (no relative normal velocity) gives
//! $$q_0 = \frac{c - p_{-1}}{h} - (1-\beta)\, q_{-1} - \beta w,$$
//! which for a fixed obstacle (`w = 0`) is Eq. (26), and the position at `t_{i-1}` is then
//! Eq. (27). Only the normal component is prescribed: the tangential motion stays free.
//!
//! **Holding.** Table 1 (item 6) holds the node with `v = 0`, i.e. `n . v_1 = w`. Asking
//! instead for a zero gap at `t_1` in one step, `n.v_1 = (c_1 - n.x_0 - h(1-beta) n.v_0) /
//! (h beta)`, is unstable: an error `e_0` in the relative normal velocity gives
//! `e_1 = -(1-beta)/beta e_0`, a factor -4 per step for `alpha = 0.8, gamma = 0` (any
//! `beta < 1/2`), so round-off grows into a spurious tension and the node chatters. The
//! holding velocity is therefore the surface velocity plus a deadbeat drift correction:
//! with `g* = n.x_0 + h[(1-beta) n.v_0 + beta w] - c_1`, the gap at `t_1` if `n.v_1 = w`,
//! $$n_1 \cdot v_1 = w - g^*/h .$$
//! The gap and velocity errors `(g, h e)` then evolve with the matrix
//! `[[1-beta, (1-beta)^2], [-1, -(1-beta)]]`, whose eigenvalues are both 0 (nilpotent): any
//! drift is gone after two steps, for every `beta` in `[0, 1]`. After a braking step
//! `g* = 0` and this is exactly Table 1's `v = w`.
//!
//! **Release.** A held node whose multiplier turns tensile (`lambda < 0`) is released; the
//! same step is solved again with a force `R` added on the node (Table 1, item 7), which
//! gives back the momentum taken by the arrival. `R h` is the impulse that would have
//! stopped the node's relative normal motion in the braking step,
//! `lambda_s = S^{-1}(w - C A^{-1} b)` (`S = C A^{-1} C^T`), i.e. the braking multiplier
//! `lambda_b = S^{-1}(v_bar - C A^{-1} b)` completed with `S^{-1}(w - v_bar)`, the part of
//! the approach momentum that the arrival step removes. Table 1's `R` (the braking reaction
//! alone) is about the fraction `(q_{-1} - v_bar)/(q_{-1} - w)` of it, anywhere in
//! `(-beta, 1 - beta]` depending on where the node happens to be inside the step; with
//! `lambda_s` the restored momentum does not depend on that phase, and for `h -> 0` it is
//! the node's effective mass times its approach speed, so the impact gives back the energy
//! it took (an elastic impact of the node).

use serde::Serialize;

/// Which contact treatment the driver applies.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ContactMethod {
    /// The soft way (Table 1): brake in the step before impact, hold, release on tension,
    /// give the momentum back; the momentum given back is the impulse that would have
    /// stopped the node in the braking step (module docs, Release), independent of where
    /// the node arrives inside the step.
    SoftWay,
    /// The soft way with Table 1's literal restore: the braking reaction `R` alone.
    SoftWayBrakingRestore,
    /// The soft way without giving the braking momentum back (for comparison: the rebound
    /// is slower).
    SoftWayNoRestore,
    /// Exact enforcement: the node is put on the obstacle in the step where penetration is
    /// found (a velocity jump), held while compressive; no braking, no momentum restoring.
    Exact,
}

impl ContactMethod {
    /// True for the methods that brake one step early.
    pub fn brakes(&self) -> bool {
        matches!(
            self,
            ContactMethod::SoftWay
                | ContactMethod::SoftWayBrakingRestore
                | ContactMethod::SoftWayNoRestore
        )
    }

    /// True when the braking impulse is given back at release.
    pub fn restores(&self) -> bool {
        matches!(
            self,
            ContactMethod::SoftWay | ContactMethod::SoftWayBrakingRestore
        )
    }

    /// True when the momentum given back is the full stopping impulse of the braking step
    /// (not Table 1's braking reaction alone).
    pub fn restores_stopping_impulse(&self) -> bool {
        matches!(self, ContactMethod::SoftWay)
    }
}

/// The constraint a contact pair gets in the next step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum PairMode {
    /// No constraint.
    Free,
    /// Braking: `normal . v = q` at the end of the step (Eq. 26).
    Brake {
        /// Prescribed normal velocity, m/s.
        q: f64,
        /// The obstacle's normal at the instant of arrival.
        normal: [f64; 2],
        /// The obstacle's surface normal velocity at the instant of arrival, m/s.
        w: f64,
    },
    /// Held on the obstacle: relative normal velocity zero at the end of the step, with a
    /// deadbeat correction of any gap drift ([`holding_velocity`]).
    Hold,
}

/// The state of one (node, obstacle) pair at the end of a step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PairState {
    /// The constraint for the next step.
    pub mode: PairMode,
    /// Force to add on the node in the next step (the arrival momentum given back), N.
    pub restore: Option<[f64; 2]>,
    /// The force `R = lambda_s / h` (vector, N) to give back at release, kept since the last
    /// braking (module docs, Release).
    pub brake_force: [f64; 2],
    /// Constraint force of the step that ended here (`lambda / h`, N, positive when
    /// compressive), braking included.
    pub force: f64,
    /// Held on the obstacle at the end of the step.
    pub held: bool,
    /// Braked in the step that ended here.
    pub braked: bool,
    /// Released in the step that ended here.
    pub released: bool,
    /// Gap at the end of the step, m (negative: penetration).
    pub gap: f64,
}

impl Default for PairState {
    fn default() -> Self {
        Self {
            mode: PairMode::Free,
            restore: None,
            brake_force: [0.0; 2],
            force: 0.0,
            held: false,
            braked: false,
            released: false,
            gap: f64::INFINITY,
        }
    }
}

/// The braking normal velocity of Eq. (26), generalised to a moving obstacle (module docs):
/// `q0 = (c - n.x_{-1})/h - (1 - beta) n.v_{-1} - beta w`.
pub fn braking_velocity(c: f64, p_prev: f64, q_prev: f64, w: f64, h: f64, beta: f64) -> f64 {
    (c - p_prev) / h - (1.0 - beta) * q_prev - beta * w
}

/// The holding normal velocity (module docs): the surface velocity `w` corrected by the
/// gap `g*` the node would have at the end of the step if it moved with the surface,
/// `w - g*/h` (deadbeat, stable for every `beta`).
pub fn holding_velocity(c1: f64, p0: f64, q0: f64, w: f64, h: f64, beta: f64) -> f64 {
    let g_star = p0 + h * ((1.0 - beta) * q0 + beta * w) - c1;
    w - g_star / h
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn braking_then_holding_lands_on_the_obstacle_eqs_26_27() {
        // Fixed wall at x_c in 1D written with n = +1 (p = x).
        let (x_c, h, beta) = (0.5, 0.1, 0.2);
        let (xm1, vm1) = (0.32, 1.3);
        let v0 = braking_velocity(x_c, xm1, vm1, 0.0, h, beta);
        assert!((v0 - ((x_c - xm1) / h - (1.0 - beta) * vm1)).abs() < 1e-14);
        let x0 = xm1 + h * ((1.0 - beta) * vm1 + beta * v0);
        // Eq. (27).
        let x0_27 = (1.0 - beta) * xm1 + beta * x_c + (1.0 - beta).powi(2) * h * vm1;
        assert!((x0 - x0_27).abs() < 1e-14);
        // The holding step gives v1 = 0 and x1 = x_cont.
        let v1 = holding_velocity(x_c, x0, v0, 0.0, h, beta);
        assert!(v1.abs() < 1e-12);
        let x1 = x0 + h * ((1.0 - beta) * v0 + beta * v1);
        assert!((x1 - x_c).abs() < 1e-14);
    }

    #[test]
    fn holding_removes_a_velocity_error_instead_of_amplifying_it() {
        // On the wall with a small velocity error: the old zero-gap law multiplied it by
        // -(1-beta)/beta each step; the deadbeat law clears gap and error in two steps.
        let (x_c, h, beta) = (0.5, 0.01, 0.2);
        let (mut x, mut v) = (x_c, 1e-6);
        for _ in 0..50 {
            let v1 = holding_velocity(x_c, x, v, 0.0, h, beta);
            x += h * ((1.0 - beta) * v + beta * v1);
            v = v1;
        }
        assert!(
            v.abs() < 1e-12 && (x - x_c).abs() < 1e-15,
            "v {v:e}, gap {:e}",
            x - x_c
        );
    }

    #[test]
    fn moving_obstacle_arrival_has_the_obstacle_velocity() {
        let (h, beta, w) = (0.01, 0.3, -0.7);
        let (pm1, qm1) = (0.0, 2.0);
        let c1 = 0.035;
        let q0 = braking_velocity(c1, pm1, qm1, w, h, beta);
        let p0 = pm1 + h * ((1.0 - beta) * qm1 + beta * q0);
        let q1 = holding_velocity(c1, p0, q0, w, h, beta);
        assert!((q1 - w).abs() < 1e-10);
    }
}
