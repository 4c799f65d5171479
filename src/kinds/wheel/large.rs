//! The wheel in large deformation (`material.geometry = "large"`): the geometrically
//! nonlinear internal force of [`crate::finite`] (hyperelastic triangles in the total
//! Lagrangian form, the paper's instantaneous updated Lagrangian form written on the
//! initial configuration; the module's docs argue the equivalence) in place of the linear
//! `K u` of the wheel's triangles, solved on the step's elastic factor by the initial-stress
//! iteration of [`crate::model::internal`].
//!
//! # In the rotating frame
//!
//! The wheel's equation in its frame ([`crate::frame`]) is
//! `M a + (C + G) v + f_int(u) - Omega^2 M u = f_c`, with the Coriolis matrix `G` and the
//! centrifugal terms `Omega^2 M (X + u)` exact and linear in `u` for any deformation; only
//! the elastic force `f_int` is nonlinear. The model's step matrix holds `K - Omega^2 M`
//! (the linear `K` of the same triangles); the force adds `f_nl = K u - f_int(u)` as a load
//! ([`crate::finite::FiniteBody`]), so the solved equation is the nonlinear one to the
//! iteration's tolerance. The centrifugal prestress's geometric stiffness
//! (`wheel.stress_stiffening` of the linear model) is part of `f_int` here (its derivative
//! at the spun state), so the linear term is left out: `wheel.stress_stiffening` defaults to
//! false and `true` is refused.
//!
//! # What it changes
//!
//! A rigid rotation of the disk against its frame makes no strain: the pinned centre's
//! rocking, which a linear model turns into a false shortening of the rim
//! (`R theta^2 / 2`), is then physics, and the run's rotation watch no longer stops it
//! ([`super::run`]). The contact sees the rim nodes where they are, `X + u`, in either
//! model.
//!
//! # Not built with it (refused by name)
//!
//! The elastic block, the uncoupled twin and the subdivision treatment (the wheel's
//! `rules`). With `material.model = "j2"` the wheel is plastic at finite strain
//! ([`crate::finite::FinitePlastic`], Saint Venant-Kirchhoff in its elastic part; the
//! moving zone is then refused: its element states do not travel with a relabelling).
//! The moving refined zone works: the force's state is nodal (the last two steps' `f_nl`),
//! and a relocation, a symmetry of the mesh, turns it with the nodes
//! ([`crate::model::InternalForce::nodal_state`]; `tests/zone.rs` checks the run with and
//! without relocations agree to round-off).

use crate::bodies::wheel::WheelModel;
use crate::finite::{FiniteBody, Hyperelastic};
use serde::Serialize;

/// The default tolerance of the large-deformation wheel's iteration, `1e-6`: on the paper's
/// wheel (`scenarios/wheel.toml`, one turn) the mean contact force at `1e-6` and at `1e-10`
/// differ by 6e-9 of it and the energy by 3e-9, at 1.65 against 4.9 corrections a step.
pub const DEFAULT_TOLERANCE: f64 = 1e-6;

/// The wheel's large-deformation model (`material.geometry = "large"`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Large {
    /// The hyperelastic law (`material.law`, default Saint Venant-Kirchhoff).
    pub law: Hyperelastic,
    /// The iteration's tolerance: the residual relative to the internal force
    /// (`material.geometry_tolerance`, default [`DEFAULT_TOLERANCE`]).
    pub tolerance: f64,
}

/// The wheel's triangles as a hyperelastic body on the model's dofs.
pub fn finite_body(wm: &WheelModel, large: Large) -> FiniteBody {
    FiniteBody::planar(
        large.law,
        &wm.spec.material,
        wm.spec.plane,
        wm.spec.thickness,
        &wm.triangles,
        &wm.geometry,
        wm.model.n(),
    )
}

/// The large-deformation wheel's figures (`summary.json`, `large_deformation`).
#[derive(Debug, Clone, Serialize)]
pub struct LargeSummary {
    /// The hyperelastic law.
    pub law: Hyperelastic,
    /// The iteration's tolerance (residual over internal force).
    pub tolerance: f64,
    /// Corrections of the initial-stress iteration over the run (a right-hand side and a
    /// solve on the elastic factor each).
    pub iterations: usize,
    /// `iterations` per step.
    pub iterations_per_step: f64,
    /// Most corrections in one solve.
    pub max_in_one_solve: usize,
    /// Solves stopped at the cap without reaching the tolerance.
    pub unconverged: usize,
    /// The largest Green strain of a triangle at the end (Frobenius norm).
    pub max_green_strain: f64,
    /// The largest linear strain `sym(grad u)` of a triangle at the end: beside the Green
    /// strain, what the linear model would have called strain (a rigid rotation's
    /// `sqrt(2) (1 - cos theta)` included).
    pub max_linear_strain: f64,
    /// The stored energy `W(u)` of the wheel's triangles at the end, J.
    pub stored_energy_j: f64,
    /// The linear model's reading `u^T K u / 2` of the same displacement, J (beside it: a
    /// rigid rotation against the frame counts there).
    pub linear_reading_energy_j: f64,
    /// The largest rigid rotation of the rim against the frame over the run, rad (`sin
    /// theta` of the rim's mean rotation about the centre).
    pub max_rotation_rad: f64,
}

/// The nonlinear iteration's counters over a run (the run loop's, handed over as numbers).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Iterations {
    /// Corrections over the run.
    pub total: usize,
    /// Steps of the run.
    pub steps: usize,
    /// Most corrections in one solve.
    pub max_in_one_solve: usize,
    /// Solves left at the iteration cap.
    pub unconverged: usize,
}

/// The summary of a large-deformation run from its counters `o` and its last displacement
/// `u`, with the largest rotation `max_rotation` the run's watch saw.
pub(crate) fn summary(
    wm: &WheelModel,
    large: Large,
    o: Iterations,
    u: &[f64],
    max_rotation: f64,
) -> LargeSummary {
    let body = finite_body(wm, large);
    let (max_green_strain, max_linear_strain) = body.max_strains(u);
    let (stored_energy_j, linear_reading_energy_j) = body.energies(u);
    LargeSummary {
        law: large.law,
        tolerance: large.tolerance,
        iterations: o.total,
        iterations_per_step: o.total as f64 / o.steps.max(1) as f64,
        max_in_one_solve: o.max_in_one_solve,
        unconverged: o.unconverged,
        max_green_strain,
        max_linear_strain,
        stored_energy_j,
        linear_reading_energy_j,
        max_rotation_rad: max_rotation,
    }
}
