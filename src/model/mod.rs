//! The model below the driver: what `time/` and `contact/` share, with no dependence on
//! either.
//!
//! - [`LinearModel`]: the semi-discrete model `M v' + C v + K u = f` on one sparsity
//!   pattern (paper Eq. 22: `C` holds `eta_z` and, in a rotating frame, the Coriolis terms).
//! - [`LoadFn`]: the external load `f(t)`.
//! - [`State`]: `(u, v, a)` at one instant; [`Snapshot`]: a state at the end of a step with
//!   its step index, time and the contact pairs' states ([`PairState`], [`PairMode`]).
//! - [`Terms`]: the coefficients `c` of a constraint row on a few dofs (a contact pair's
//!   normal or tangent on its nodes' dofs).
//! - [`InternalForce`]: a nonlinear internal force `K u - f_nl(u; s)` (a plastic body), and
//!   [`Nonlinear`]: its initial-stress iteration on the elastic factor, with the states of
//!   the driver's three snapshots.

pub mod internal;
mod state;
mod terms;

pub use internal::{InternalForce, Nonlinear, NonlinearStats, DEFAULT_MAX_ITERATIONS, DEFAULT_TOL};
pub use state::{PairMode, PairState, Snapshot, State};
pub use terms::{Terms, MAX_TERMS};

use crate::assembly::Assembler;
use crate::linalg::Pattern;

/// External force at time `t` (s), written into the slice (N per dof; overwrite it).
pub type LoadFn = Box<dyn Fn(f64, &mut [f64]) + Send + Sync>;

/// The semi-discrete linear model `M v' + C v + K u = f` on one sparsity pattern.
#[derive(Debug, Clone)]
pub struct LinearModel {
    /// Pattern and element map.
    pub assembler: Assembler,
    /// Mass matrix values.
    pub m: Vec<f64>,
    /// Stiffness matrix values (elastic plus, in a rotating frame, spin terms).
    pub k: Vec<f64>,
    /// Damping matrix values (`eta_z` of Eq. 22, Coriolis in a rotating frame).
    pub c: Vec<f64>,
}

impl LinearModel {
    /// The model with no mass, damping or stiffness on the pattern of `assembler`.
    pub fn zeros(assembler: Assembler) -> Self {
        let z = assembler.zeros();
        Self {
            m: z.clone(),
            k: z.clone(),
            c: z,
            assembler,
        }
    }

    /// Number of degrees of freedom.
    pub fn n(&self) -> usize {
        self.assembler.pattern.nrows()
    }

    /// The pattern.
    pub fn pattern(&self) -> &Pattern {
        &self.assembler.pattern
    }
}
