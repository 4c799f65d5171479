//! The choice of an integrator ([`Integrator`], scenario key `integrator`) and the errors of
//! building one; the integrators themselves implement the contract of
//! [`super::integrator`].

use crate::linalg::LinalgError;
use crate::time::classic::{ClassicError, ClassicParams};
use crate::time::Coriolis;
use serde::Serialize;

/// The choice of an integrator, with its parameters (scenario key `integrator`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[serde(tag = "name", rename_all = "snake_case")]
pub enum Integrator {
    /// The space-time velocity scheme (Eqs. 6-10, 24).
    SpaceTime {
        /// `alpha` in (0, 1].
        alpha: f64,
        /// `gamma` in [0, 1].
        gamma: f64,
        /// Where the Coriolis term goes (`time.coriolis`).
        coriolis: Coriolis,
    },
    /// A member of the generalized-alpha family ([`crate::time::classic`]).
    Classic {
        /// Short name.
        kind: ClassicKind,
        /// Its parameters.
        params: ClassicParams,
    },
}

/// The classic integrators by name.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ClassicKind {
    /// Newmark average acceleration (`beta = 1/4`, `gamma = 1/2`).
    Newmark,
    /// Newmark with `gamma_N > 1/2`.
    NewmarkDissipative,
    /// HHT-alpha.
    Hht,
    /// Generalized-alpha (Chung-Hulbert).
    GeneralizedAlpha,
    /// Explicit central difference.
    CentralDifference,
}

impl Integrator {
    /// The name used in tables.
    pub fn name(&self) -> String {
        match self {
            Integrator::SpaceTime {
                alpha,
                gamma,
                coriolis: Coriolis::Implicit,
            } => format!("space_time(alpha={alpha} gamma={gamma})"),
            Integrator::SpaceTime {
                alpha,
                gamma,
                coriolis,
            } => format!(
                "space_time(alpha={alpha} gamma={gamma} coriolis={})",
                coriolis.name()
            ),
            Integrator::Classic { kind, params } => match kind {
                ClassicKind::Newmark => "newmark".into(),
                ClassicKind::NewmarkDissipative => format!("newmark({:.2})", params.gamma),
                ClassicKind::Hht => format!("hht({:.3})", -params.alpha_f),
                ClassicKind::GeneralizedAlpha => {
                    format!("gen_alpha({:.2})", crate::time::classic::rho_inf(*params))
                }
                ClassicKind::CentralDifference => "central_difference".into(),
            },
        }
    }

    /// True for the explicit central difference.
    pub fn is_explicit(&self) -> bool {
        matches!(self, Integrator::Classic { params, .. } if params.is_explicit())
    }

    /// True for the space-time scheme.
    pub fn is_space_time(&self) -> bool {
        matches!(self, Integrator::SpaceTime { .. })
    }
}

/// Errors of building an integrator.
#[derive(Debug, thiserror::Error)]
pub enum BuildError {
    /// A matrix could not be factored.
    #[error(transparent)]
    Linalg(#[from] LinalgError),
    /// A classic integrator could not be set up.
    #[error(transparent)]
    Classic(#[from] ClassicError),
}
