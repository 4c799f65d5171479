//! # softway
//!
//! Dynamic contact by the space-time finite element method in the velocity formulation,
//! after C. I. Bajer, *The space-time approach to rail/wheel contact and corrugations
//! problem* (Computer Assisted Mechanics and Engineering Sciences, 1998).
//!
//! ## The method in a page
//!
//! **Time step (paper §2, Eqs. 6-11, 24).** Over `[t0, t0 + h]` the velocity is linear in
//! time and the virtual velocity is a Dirac at `t0 + alpha h`. The semi-discrete equation
//! `M v' + C v + K u = f + r` then gives
//! $$\big(M + \alpha h C + \tfrac{\alpha^2h^2}{2}K\big) v_1 = M v_0 - (1-\alpha)hCv_0 - hKu_0
//!   \;-\; (\alpha - \tfrac{\alpha^2}{2})h^2 K v_0 + h f(t_0 + \alpha h) + h r,$$
//! $$u_1 = u_0 + h[(1-\beta)v_0 + \beta v_1],\qquad \beta = 1 - \alpha/(1+\gamma).$$
//! For one degree of freedom this is Eq. (9) with Eq. (10); `gamma = 0` preserves energy
//! (Eq. 11) and `gamma > 0` adds numerical dissipation (Eq. 24). See [`time`].
//!
//! **Contact, the soft way (§3.1, Table 1, Eqs. 26-27).** A node that would penetrate an
//! obstacle at `t_i` is braked in `[t_{i-2}, t_{i-1}]` so that it lands on the obstacle at
//! `t_i` with zero relative normal velocity, held while the reaction is compressive,
//! released on tension, and its braking reaction is given back as a force. Constraints are
//! imposed with Lagrange multipliers through the factored matrix. See [`contact`] and
//! [`simulation`].
//!
//! ## Module map
//! - [`mesh`]: meshes, generators (bar, hexagonal disk, rectangle), Gmsh import.
//! - [`element`]: bar and triangle kernels.
//! - [`material`]: linear elastic material, plane stress / strain.
//! - [`modes`]: natural frequencies and mode shapes, at rest and spinning (dense).
//! - [`assembly`]: sparsity pattern once, element scatter (serial and parallel).
//! - [`linalg`]: sparse products, sparse LU with reusable symbolic analysis.
//! - [`time`]: the scheme's parameters, the one-degree-of-freedom analysis, the step, and
//!   the classic integrators.
//! - [`contact`]: obstacles and the soft-way state machine.
//! - [`simulation`]: the step loop with step-back-and-repeat.
//! - [`lab`]: the contact laboratory: every integrator (space-time, Newmark family, central
//!   difference) with exact enforcement, penalty, mass redistribution, Moreau-Jean and the
//!   paper's time subdivision (Fig. 5), on linear gaps (node-wall, node-node).
//! - [`scenario`]: TOML scenarios, parsed and validated (plain data, the allowed
//!   combinations of model, integrator and contact in one table).
//! - [`build`]: what a scenario needs a model for (the central difference's step from
//!   `cfl`), before the jobs of [`run`] start.
//! - [`output`]: CSV, JSON, VTK, plots.
//! - [`analysis`]: signals (spectra, oscillation counts).
//!
//! Units are SI inside: m, s, kg, N, Pa.

#![warn(missing_docs)]
// Index loops over degrees of freedom mirror the equations; iterators would hide them.
#![allow(clippy::needless_range_loop)]

pub mod analysis;
pub mod assembly;
pub mod build;
pub mod contact;
pub mod element;
pub mod frame;
pub mod lab;
pub mod linalg;
pub mod material;
pub mod mesh;
pub mod modes;
pub mod output;
pub mod problems;
pub mod run;
pub mod scenario;
pub mod simulation;
pub mod time;
pub mod wheel;
