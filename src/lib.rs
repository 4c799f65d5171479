//! # softway
//!
//! Dynamic contact by the space-time finite element method in the velocity formulation,
//! after C. I. Bajer, *The space-time approach to rail/wheel contact and corrugations
//! problem* (Computer Assisted Mechanics and Engineering Sciences, 1998): an elastic wheel
//! rolling on its base, bars striking walls and each other, a rail on its sleepers, with the
//! paper's "soft way" contact and the classic integrators and contact treatments beside it.
//!
//! ## Using it from Rust
//!
//! A scenario is TOML text (the keys: [`scenario`]); [`run()`] runs it and returns its
//! [`Results`] in memory: the summary (`summary.json`'s object), the history as named
//! columns with units ([`run::Columns`], `history.csv`), the per-node contact rows, the
//! fields on the mesh and the screen lines; [`Results::save`] writes the command line's
//! files. The paper's bar (Fig. 8) striking a wall, checked against d'Alembert's answer
//! (the contact lasts `2 L / c` = 2 s, the force is `rho A c v0` = 1 N):
//!
//! ```
//! let text = r#"
//! kind = "bar_impact"
//! [time]
//! h = 0.01
//! t_end = 3.0
//! [bar]
//! length = 1.0
//! ea = 1.0
//! rho_a = 1.0
//! speed = 1.0
//! gap = 0.5
//! elements = 40
//! [contact]
//! method = "soft_way"
//! "#;
//! let sc = softway::scenario::Scenario::from_str(text, std::path::Path::new("bar.toml"))?;
//! let sc = softway::build::resolve(&sc)?;
//! let r = softway::run(&sc, &softway::RunOptions::default())?;
//! let run = &r.summary["runs"][0];
//! let duration = run["contact_duration"].as_f64().unwrap();
//! let force = run["mean_contact_force"].as_f64().unwrap();
//! assert!((duration - 2.0).abs() <= 2.0 * 0.01 + 1e-9, "{duration}"); // two steps
//! assert!((force - 1.0).abs() < 0.01, "{force}");
//! let f = r.history.column("contact_force_N").unwrap();
//! assert_eq!(f.len(), r.history.len());
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! ## The method in a page
//!
//! **Time step (paper §2, Eqs. 6-11, 24).** Over `[t0, t0 + h]` the velocity is linear in
//! time and the virtual velocity is a Dirac at `t0 + alpha h`. The semi-discrete equation
//! `M v' + C v + K u = f + r` then gives
//!
//! > (M + α h C + α²h²/2 K) v₁ = M v₀ − (1 − α) h C v₀ − h K u₀ − (α − α²/2) h² K v₀
//! > + h f(t₀ + α h) + h r,
//! >
//! > u₁ = u₀ + h [(1 − β) v₀ + β v₁],   β = 1 − α / (1 + γ).
//!
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
//! ## One engine, two contracts
//!
//! Every run goes through one driver ([`simulation::Simulation`]): a step loop over a ring of
//! three states (`t_{k-2}`, `t_{k-1}`, `t_k`) so that a treatment may step back and repeat
//! the previous interval, with observers called on final steps only. The driver takes any
//! integrator and any contact treatment through two contracts.
//!
//! **The integrator contract** ([`time::TimeIntegrator`]). Each
//! integrator solves per step one linear system with a constant factored matrix in an
//! unknown `x` that fixes the end state linearly:
//!
//! > A x = b + Σₚ cₚᵀ λₚ,   u₁ = U + μᵤ x,   v₁ = V + μᵥ x.
//!
//! Space-time: `x = v1`, `U = u0 + h(1-beta)v0`, `mu_u = h beta`, `V = 0`, `mu_v = 1`, and
//! `lambda` is an impulse (N s). Generalized-alpha family (Newmark, HHT, generalized-alpha,
//! central difference): `x = a1`, `mu_u = beta_N h^2`, `mu_v = gamma_N h`, and `lambda` is a
//! force (N). The contract: `predict` (`U`, `V`, `x_free = A^{-1} b`; it returns the
//! [`time::integrator::Step`] with the maps `mu_u`, `mu_v`, which the caller passes on to
//! `finish`), `inverse_column` (`A^{-1} e_d`), `finish`, `stiffness_point` (where `K u` is
//! evaluated), `set_step` (another `h` on the same symbolic analysis). The model, the loads
//! and the states that both contracts use are in [`model`], below `time` and `contact`.
//!
//! **The contact-treatment contract** ([`contact::ContactTreatment`]). A pair (node against obstacle, node against node:
//! [`contact::Pair`]) presents a row `c`, an offset `o` and a boundary velocity `w`, with the
//! gap `g = c.(X + u) - o`. A treatment turns the pairs and their states into rows
//!
//! > yₚ = y₀,ₚ + μₚ cₚ · x + rₚ λₚ
//!
//! of kind equality, unilateral (`y >= 0`, `lambda >= 0`, `y lambda = 0`) or bounded
//! (`|lambda| <= mu_f lambda_n`, for friction), which [`contact::rows::RowSolver`] solves
//! through the integrator's factored matrix and cached columns `A^{-1} e_d` (no
//! refactorization on a change of the active set); it judges the solution (accept, solve
//! again, step back) and records the pairs' forces (always in N). It works with a narrow
//! [`contact::Context`] that the driver lends it each step, not with the driver's engine.
//!
//! **Friction** (`Problem::friction`, scenario key `contact.friction`). The
//! Coulomb coefficient `mu` is carried by the treatment (given when it is built). With
//! `mu > 0` (2D models) a pair also presents a tangent ([`contact::Pair::tangent`]: the
//! normal turned by +90 degrees, with the surface's tangential velocity `w_t`), and every
//! normal row gets a bounded row `|lambda_t| <= mu lambda_n` on the slip velocity at the step
//! end, `y = (c_t.V - w_t) + mu_v c_t.x`: stick or slip, decided by the rows' active set
//! without refactorization. The soft way brakes the normal velocity only (the tangential
//! motion is no impact); friction acts on held pairs. The pairs report the tangential force,
//! slip power and dissipated energy; `RunStats::stick_slip_changes` counts the changes.
//!
//! | question | file |
//! |---|---|
//! | where is the step equation? | `src/time/step.rs` (space-time), `src/time/classic/` (the family's spectrum in `spectrum.rs`) |
//! | where is the integrator contract? | `src/time/integrator.rs` |
//! | where is the soft way? | `src/contact/softway.rs` |
//! | where are the other treatments? | `src/contact/complementarity.rs`, `mass_redistribution.rs`, `subdivision.rs` |
//! | where are constraint rows solved? | `src/contact/rows.rs` |
//! | where is the step loop? | `src/simulation/mod.rs` (what observers see: `view.rs`; the moving zone's relocation: `relocation.rs`) |
//! | where are the rotating-frame terms? | `src/frame.rs` |
//! | where are stresses and J2? | `src/element/tri3.rs`, `src/material.rs`, `src/plasticity.rs`; in 3D `src/element/solid.rs`, `src/element/j2_solid.rs` |
//! | where are the rail's beam and the track's springs? | `src/element/beam.rs`, `src/element/discrete.rs` |
//! | where are the wheel job's observers? | `src/kinds/wheel/run/observers.rs` |
//! | where are results held and written? | `src/run/results.rs`, `src/output/table.rs`, `src/output/save.rs` |
//! | where are the model, the loads and the states? | `src/model/` |
//! | what does a treatment see of the driver? | `src/contact/context.rs` |
//! | where is the contact search between bodies (and the bodies' frames)? | `src/contact/search.rs` |
//! | where are a model's bodies joined, and a pressed frame's inertial load? | `src/bodies/mod.rs` |
//! | where do discrete elements join bodies (an axle on springs, a sleeper's mass)? | `src/bodies/mod.rs` (`Joints`, `assemble_with`); the elements in `src/element/discrete.rs`; `tests/joints.rs` |
//! | where is a rigid base or obstacle as a body of the search? | `src/bodies/mod.rs` (`Body::rigid`); `tests/on_block.rs` compares it with the rotating base |
//! | where is the track (rail on pads, sleepers, ballast), its receptance and a moving load? | `src/bodies/rail/` (`TrackSpec`, `receptance.rs`, `hertz.rs`); the kinds `src/kinds/track/`; `tests/track.rs` |
//! | where is the command line? | `src/cli/` (`mod.rs`: parsing and the runs' subcommands; `analysis.rs`: modes, receptance, matrix, stability; `src/main.rs` only calls it) |
//! | what stops a run that blows up? | `src/guard.rs` (the energy bound), checked in `Simulation::run` |
//! | when are the searched pairs' targets found, and what if one is lost? | `src/contact/interface.rs` (each step's start, in `Simulation::run`) |
//! | where is a rail of beams as a contact surface (its own deflection between nodes)? | `src/contact/search.rs` (`Search::on_beams`); the rail body `Body::rail` in `src/bodies/mod.rs`; `tests/on_rail.rs` |
//! | where is the wheel on an elastic block (Hertz's half-width)? | `src/bodies/block.rs`; its job `src/kinds/wheel/on_block.rs`; `scenarios/wheel-on-block.toml` |
//! | where is the solver trait, and which factorizations implement it? | `src/linalg/solver.rs` (faer's: `reference.rs`; tuned: `lu.rs`, `llt.rs`, `triangle.rs`, `supernodal.rs`, `split/`) |
//! | where is the step's right-hand side formed? | `src/linalg/rhs/` (with its plain sparse-product reference) |
//! | what is a kind of model, and where is the list of kinds? | `src/scenario/kind.rs` (`Kind`, `Spec`, `Model`, `Registry`); `src/kinds/mod.rs` (`Registry::builtin`); each kind in `src/kinds/<kind>/`; `tests/kinds.rs` adds one |
//! | what does an element give the assembly, in any dimension? | `src/element/continuum.rs` (`Continuum`); the kernels `tri3.rs`, `tet4.rs`, `tet10.rs`, `hex8.rs` |
//! | where is a body of continuum cells in 2D or 3D built? | `src/bodies/solid.rs`; `tests/solid3d.rs` drops a 3D column on a floor |
//! | what does a contact search answer, in any dimension? | `src/contact/interface.rs` (`MasterSurface`; the planar segment search implements it) |
//! | which cells does a mesh hold (dimension, nodes, Gmsh and VTK codes)? | `src/mesh/mod.rs` (`Cells`, `CellKind`); `src/mesh/generators/solid.rs` (boxes in 3D) |
//! | how many threads does a run use, and where are they? | `src/linalg/team.rs` (`Par`, the run's `Team`); `RunOptions::par` |
//! | how is a run cancelled? | `run::Cancel` in `RunOptions::cancel` |
//!
//! ## Running from code
//!
//! The command line's `run` ([`run::run_scenario`]) streams the long tables into its
//! output folder during the run instead of holding them, so a long run's memory stays
//! flat; [`run()`] (above) holds them. A scenario file is read by
//! [`scenario::Scenario::from_file`], with command-line overrides by
//! [`scenario::Scenario::from_file_with`] ([`scenario::overrides`]).
//!
//! ## Module map
//! - [`mesh`]: meshes of any dimension (bars, triangles, tetrahedra, hexahedra: [`mesh::CellKind`]),
//!   generators (bar, hexagonal disk, rectangle, 3D box), Gmsh import.
//! - [`element`]: the continuum element contract ([`element::Continuum`]) and its kernels:
//!   bar, triangle, 4- and 10-node tetrahedra, 8-node hexahedra, 2D beam (Euler-Bernoulli,
//!   Timoshenko); discrete point masses, spring-dampers and hubs.
//! - [`material`]: linear elastic material, plane stress / strain.
//! - [`modes`]: natural frequencies and mode shapes, at rest and spinning (sparse
//!   shift-invert at any size; dense references).
//! - [`assembly`]: dof layout and element families, sparsity pattern once, element scatter
//!   (serial and parallel).
//! - [`linalg`]: sparse products; the solver trait ([`linalg::Factorization`]: factor,
//!   refactor on the same symbolic analysis, solve in place, counts kept by the
//!   factorization) with faer's LU and Cholesky as the reference and the tuned layouts
//!   (compact rows, supernodes, the two-part split) as the fast implementation; the step's
//!   right-hand-side operator; the dense solve; [`linalg::team`]: parallelism as a parameter
//!   ([`linalg::team::Par`]) and the run's own helper threads (`--threads n`: n - 1 of
//!   them, as many as the machine has free cores; the right-hand side in as many parts, the
//!   split factor and the energies in two), which park when idle.
//! - [`model`]: the linear model, the load, the states and the pairs' states (below `time`
//!   and `contact`).
//! - [`time`]: the scheme's parameters, the one-degree-of-freedom analysis, the step, and
//!   the classic integrators.
//! - [`contact`]: obstacles, pairs (node-obstacle, node-node), constraint rows, the
//!   treatments (the soft way, exact, penalty, mass redistribution, Moreau-Jean,
//!   subdivision) and the narrow context they work on; the contact search of a body's nodes
//!   against another body's surface segments, each body in its frame (fixed, translating,
//!   rotating: [`contact::search`]).
//! - [`bodies`]: a model as a set of bodies, each a mesh with its model, supports, load and
//!   frame (fixed, translating, pressed, rotating), joined on one pattern with the discrete
//!   elements between them and on dofs of their own ([`bodies::Joints`]: an axle node with
//!   its mass and load, springs and dampers); rigid bodies ([`bodies::Body::rigid`]); the
//!   inertial load of a pressed frame `-M 1 d''(t)`; the bodies themselves: the wheel in its
//!   frame ([`bodies::wheel`]), the bar ([`bodies::bar`]), the elastic block under the wheel
//!   met through the contact search with Hertz's line contact as its check
//!   ([`bodies::block`]), the rail on its supports with its receptance and the pinned-pinned,
//!   track and P2 frequencies ([`bodies::rail`]), a body of continuum cells in 2D or 3D
//!   ([`bodies::solid`]).
//! - [`kinds`]: the kinds of model a scenario names (`kind = "..."`), each in its folder,
//!   behind the contract of [`scenario::kind`]; [`kinds`]'s registry is their only list.
//! - [`simulation`]: the one driver: the step loop with step-back-and-repeat for any
//!   integrator and any treatment.
//! - [`wear`]: wear laws (Archard with Jendel's map, frictional power, USFD) and
//!   [`growth`]: the pass-by-pass growth of a surface profile by wear (`softway grow`).
//! - [`guard`]: the divergence guard (the energy against the initial energy plus the work
//!   done on the system), which stops a run that blows up.
//! - [`scenario`]: TOML scenarios, parsed and validated (plain data, the allowed
//!   combinations of model, integrator and contact in one table).
//! - [`build`]: what a scenario needs a model for (the central difference's step from
//!   `cfl`), before the jobs of [`run`](mod@run) start.
//! - `output` (the crate's own): CSV, JSON, VTK, plots; the writing of [`Results`]
//!   ([`Results::save`]) and of the command line's files ([`cli`]).
//! - [`analysis`]: signals (spectra, oscillation counts).
//! - [`cli`]: the command line (parse, validate, run, report); the binary only calls
//!   [`cli::main`]. It is the binary's, not a library API.
//! - [`prelude`]: what a user of the library calls most, in one `use`.
//!
//! Units are SI inside: m, s, kg, N, Pa.

#![warn(missing_docs)]
// Index loops over degrees of freedom mirror the equations; iterators would hide them.
#![allow(clippy::needless_range_loop)]

pub mod analysis;
pub mod assembly;
pub mod bodies;
pub mod build;
pub mod cli;
pub mod contact;
pub mod element;
pub mod finite;
pub mod frame;
pub mod frame3d;
pub mod growth;
pub mod guard;
pub mod kinds;
pub mod linalg;
pub mod material;
pub mod mesh;
pub mod model;
pub mod modes;
pub(crate) mod output;
pub mod plasticity;
pub mod run;
pub mod scenario;
pub mod simulation;
pub mod time;
pub mod wear;

// The bodies' former paths, kept for the library's users and the tests (hidden: the
// documented paths are under `bodies`).
#[doc(hidden)]
pub use bodies::{bar as problems, rail as track, wheel};
/// Models of more than one body: the wheel on its elastic block ([`bodies::block`]).
#[doc(hidden)]
pub mod models {
    pub use crate::bodies::block as wheel_on_block;
}

pub use run::{run, Results, RunError, RunOptions};

/// What a user of the library calls most, in one `use softway::prelude::*`: a scenario read,
/// resolved and run ([`scenario::Scenario`], [`build::resolve`], [`run()`], [`Results`]);
/// the kinds' registry to add a kind of one's own ([`scenario::kind`]); a model built in
/// code from bodies of continuum cells in any dimension ([`bodies::solid`],
/// [`bodies::assemble`]) and stepped by the driver ([`simulation::Simulation`]) with
/// obstacles and pairs ([`contact`]).
pub mod prelude {
    pub use crate::bodies::solid::{solid, Solid, SolidSpec};
    pub use crate::bodies::{assemble, assemble_with, Body, Joints};
    pub use crate::build::resolve;
    pub use crate::contact::search::Motion;
    pub use crate::contact::{FrictionLaw, Interface, Obstacle, Pair, Treatment};
    pub use crate::element::{CellStresses, Continuum};
    pub use crate::material::{Elastic, PlaneModel};
    pub use crate::mesh::{CellKind, Cells, Mesh};
    pub use crate::run::{run, Results, RunError, RunOptions};
    pub use crate::scenario::kind::{Kind, Model, Registry, Spec};
    pub use crate::scenario::Scenario;
    pub use crate::simulation::{Problem, Simulation};
    pub use crate::time::Integrator;
}

/// The git commit this build was compiled from (`git describe --always`: the short hash;
/// `-dirty` when the crate's sources, `src/`, `crates/`, `build.rs`, `Cargo.toml` and
/// `Cargo.lock`, differed from it at the build), or `None` when not built
/// from a git checkout (a crates.io package, a tarball). Set by the build script; recorded
/// in `summary.json` (`softway_git_commit`) and in each output folder's `scenario.toml`.
pub const GIT_COMMIT: Option<&str> = option_env!("SOFTWAY_GIT_COMMIT");
