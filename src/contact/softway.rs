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
//! **Holding.** While held, the node's normal velocity at the end of each step is chosen so
//! that the gap is exactly zero there: from `n_1 . x_1 = c_1` and Eq. (10),
//! $$n_1 \cdot v_1 = \frac{c_1 - n_1\cdot x_0 - h(1-\beta)\, n_1 \cdot v_0}{h\beta},$$
//! which equals `w` after a braking step and is `0` for a fixed obstacle, as in Table 1
//! (item 6, `v = 0`). For `beta = 0` (explicit `alpha = 1`, `gamma = 0`) the position does
//! not depend on `v_1` and the velocity condition `n . v_1 = w` is used instead.
//!
//! **Release.** A held node whose multiplier turns tensile (`lambda < 0`) is released; the
//! same step is solved again with the braking reaction `R` added as an external force on the
//! node (Table 1, item 7), which gives back the impulse `R h` taken by braking.

use serde::Serialize;

/// Which contact treatment the driver applies.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ContactMethod {
    /// The paper's soft way: brake in the step before impact, hold, release on tension,
    /// give the momentum back (Table 1).
    SoftWay,
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
        matches!(self, ContactMethod::SoftWay | ContactMethod::SoftWayNoRestore)
    }

    /// True when the braking impulse is given back at release.
    pub fn restores(&self) -> bool {
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
    },
    /// Held on the obstacle: zero gap at the end of the step.
    Hold,
}

/// The state of one (node, obstacle) pair at the end of a step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PairState {
    /// The constraint for the next step.
    pub mode: PairMode,
    /// Force to add on the node in the next step (the braking reaction given back), N.
    pub restore: Option<[f64; 2]>,
    /// The braking reaction `R` (vector, N) kept since the last braking.
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

/// The normal velocity that puts the node exactly on the surface at the end of the step
/// (holding), or `w` when `beta` is too small for the position to depend on `v_1`.
pub fn holding_velocity(c1: f64, p0: f64, q0: f64, w: f64, h: f64, beta: f64) -> f64 {
    if beta < 1e-9 {
        w
    } else {
        (c1 - p0 - h * (1.0 - beta) * q0) / (h * beta)
    }
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
