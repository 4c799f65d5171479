//! The parameters of the space-time velocity scheme.

use serde::Serialize;

/// Parameters of the space-time scheme (paper §2.1 and §2.3).
///
/// - `alpha` (dimensionless, default 0.8): position `t0 + alpha h` of the Dirac virtual
///   velocity, Eq. (8). `alpha = 1` is explicit in the velocity update.
/// - `gamma` (dimensionless, default 0): numerical dissipation, Eq. (24).
/// - `beta = 1 - alpha / (1 + gamma)`: weight of `v1` in the displacement update Eq. (10);
///   `gamma = 0` gives the energy-preserving `beta = 1 - alpha` of Eq. (11).
/// - `h` (s): the time step.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct SpaceTimeParams {
    /// `alpha`, in (0, 1].
    pub alpha: f64,
    /// `gamma`, in [0, 1].
    pub gamma: f64,
    /// Time step `h`, s.
    pub h: f64,
}

impl SpaceTimeParams {
    /// Default `alpha` (the paper's bar, Fig. 8).
    pub const DEFAULT_ALPHA: f64 = 0.8;
    /// Default `gamma` (no numerical dissipation).
    pub const DEFAULT_GAMMA: f64 = 0.0;

    /// `beta = 1 - alpha / (1 + gamma)`, Eq. (24).
    pub fn beta(&self) -> f64 {
        beta(self.alpha, self.gamma)
    }
}

/// How the step treats a damping matrix `C` with a skew part `G = (C - C^T)/2` (the
/// Coriolis term of a rotating frame; scenario key `time.coriolis`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Coriolis {
    /// `G` in the step's matrix `A = M + alpha h C + alpha^2 h^2/2 K`, Eq. (18): the exact
    /// scheme, an unsymmetric `A` factored by LU.
    #[default]
    Implicit,
    /// `G` on the right-hand side at the extrapolated velocity `v0 + h a0` (`a0` the last
    /// step's mean acceleration): `A` keeps the symmetric part of `C` only and gets a
    /// Cholesky factor. Its stability and accuracy against the exact scheme are those of
    /// [`crate::time::sdof::gyroscopic_table`].
    Extrapolated,
}

impl Coriolis {
    /// The scenario value.
    pub fn name(self) -> &'static str {
        match self {
            Coriolis::Implicit => "implicit",
            Coriolis::Extrapolated => "extrapolated",
        }
    }
}

/// `beta = 1 - alpha / (1 + gamma)`, Eq. (24).
pub fn beta(alpha: f64, gamma: f64) -> f64 {
    1.0 - alpha / (1.0 + gamma)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gamma_zero_gives_the_energy_preserving_beta_of_eq_11() {
        for a in [0.5, 0.75, 0.8, 1.0] {
            assert_eq!(beta(a, 0.0), 1.0 - a);
        }
        assert!((beta(0.8, 0.2) - (1.0 - 0.8 / 1.2)).abs() < 1e-15);
    }

    #[test]
    fn documented_defaults() {
        assert_eq!(SpaceTimeParams::DEFAULT_ALPHA, 0.8);
        assert_eq!(SpaceTimeParams::DEFAULT_GAMMA, 0.0);
    }
}
