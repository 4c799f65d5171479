//! The rolling wheel (paper §4, Figs. 10-17): settling, then turns; the contact force over
//! the turns, its spectrum and oscillations per turn, the turn-averaged `J2`, and the
//! velocity field in successive stages.
//!
//! **Oscillations per turn (counting rule).** Within each full turn after settling, the
//! total contact force is smoothed by a centred moving average over the node-passage
//! period `2 pi / (omega N_rim)` (the base passes one rim node in that time: a ripple of the
//! mesh, not of the wheel), then every local maximum whose prominence is at least 10% of the
//! turn's force range counts as one oscillation
//! ([`crate::analysis::signal::count_oscillations`]).
//!
//! **Shape of the job.** [`simulate`] builds the observers of `observers` (history rows,
//! contact-force statistics, energy, the turn-averaged `J2` / von Mises, the velocity
//! snapshots, the progress bar), attaches them to the step loop in [`drive`], the one
//! place that speaks to the driver ([`crate::simulation`]), then collects their results
//! into the [`WheelSummary`], the VTK fields and the figures (`figures`).

mod collect;
mod drive;
use drive::RotationWatch;
pub use drive::{drive, LoopOutcome};
mod lines;
mod mesh;
mod seen;
pub(crate) mod summarise;
pub use lines::summary_lines;
pub use mesh::{build, check_disk, check_supported, read_mesh_file};
use summarise::{step_adequacy, summarise, warnings_before};
pub(crate) mod figures;
pub mod load;
pub(crate) mod observers;
pub(crate) mod traction;

pub(crate) use collect::record;

use crate::analysis::components::{
    fixed_frequency_per_turn, spectral_components, Component, ComponentKind, ComponentOptions,
};
use crate::bodies::wheel::{Support, WheelModel, WheelSpec};
use crate::material::PlaneModel;
use crate::mesh::generators::{disk_graded, disk_rings, DiskOptions};
use crate::mesh::gmsh::read_msh_tagged;
use crate::mesh::quality as mesh_quality;
use crate::mesh::zone::disk_zone;
use crate::mesh::Mesh;
use crate::modes::{bounce_mode, Bounce};
use crate::output::table::Columns;
use crate::run::error::RunError;
use crate::run::options::RunOptions;
use crate::scenario::{MeshSource, Run, Scenario, WheelScenario};
use observers::{
    ContactForceStats, ContactForceSummary, ContactNodesWriter, EnergyWatch, HistoryWriter,
    Observer, Progress, Snapshots, Timeline, TurnAverage, TurnAverageFields, VelocitySnapshots,
};
use serde::Serialize;
use std::f64::consts::PI;
use std::path::Path;
use traction::{TractionProfile, TractionSummary, TractionWatch};

/// Key figures of a wheel run (`summary.json`).
#[derive(Debug, Clone, Serialize)]
pub struct WheelSummary {
    /// Label.
    pub label: String,
    /// Wheel spin, rad/s.
    pub omega: f64,
    /// Rim speed `omega R`, km/h.
    pub speed_km_h: f64,
    /// The flattening the base presses the wheel to, m (`rolling.flattening`, or found for
    /// `wheel.load`).
    pub flattening_m: f64,
    /// The load asked for (`wheel.load`), N; null when the flattening was given.
    pub requested_load_n: Option<f64>,
    /// Rim pitches across Hertz's contact patch at the mean contact force (`2 a` over the
    /// rim's pitch under the contact): about the rim nodes in the patch.
    pub patch_rim_pitches: f64,
    /// Time step, s.
    pub h: f64,
    /// `alpha`.
    pub alpha: f64,
    /// `gamma` while rolling.
    pub gamma: f64,
    /// Degrees of freedom.
    pub dofs: usize,
    /// Nodes, triangles.
    pub nodes: usize,
    /// Triangles.
    pub triangles: usize,
    /// Turns rolled after settling.
    pub turns: f64,
    /// Steps.
    pub steps: usize,
    /// Mean contact force over the rolling phase, N.
    pub mean_contact_force: f64,
    /// Largest contact force over the rolling phase, N.
    pub max_contact_force: f64,
    /// Smallest contact force over the rolling phase, N.
    pub min_contact_force: f64,
    /// Mean number of rim nodes held.
    pub mean_nodes_in_contact: f64,
    /// Oscillations of the contact force in each full turn (module docs: counting rule).
    pub oscillations_per_turn: Vec<usize>,
    /// Frequency of the largest peak of the contact force's spectrum above the rotation
    /// frequency and away (+-10%) from the node-passing frequency and its harmonics, Hz.
    pub dominant_frequency_hz: Option<f64>,
    /// `dominant_frequency_hz` divided by the rotation frequency: cycles per turn.
    pub dominant_cycles_per_turn: Option<f64>,
    /// Frequency at which the base passes rim nodes, Hz (a mesh ripple).
    pub node_passing_frequency_hz: f64,
    /// The contact force's spectral components over the rolling phase, strongest first,
    /// each with its amplitude (N, half peak-to-peak) and kind: locked to the rotation
    /// (whole cycles per turn: the mesh's or the geometry's), node passing, or at a fixed
    /// frequency (a mode of the wheel on its support and contact)
    /// ([`crate::analysis::components`]).
    pub spectral_components: Vec<Component>,
    /// Length of the rolling record the spectrum, the spectral components and the per-turn
    /// counts were taken from, s: the whole rolling phase, or its latest
    /// [`crate::analysis::trace::SPECTRUM_WINDOW_CAP`] steps on a longer run (memory stays
    /// bounded).
    pub spectrum_window_s: f64,
    /// Cycles per turn of the largest fixed-frequency component (neither locked to the
    /// rotation nor node passing): a per-turn count that does not depend on which component
    /// happens to dominate ([`crate::analysis::components::fixed_frequency_per_turn`]).
    pub fixed_frequency_cycles_per_turn: Option<f64>,
    /// The bounce of the disk between its support and the contact held on the base
    /// ([`crate::modes::bounce_mode`]), Hz: the spectral component near it is `mode 0`.
    pub bounce_frequency_hz: Option<f64>,
    /// The bounce mode's effective mass in vertical translation over the total mass.
    pub bounce_vertical_mass_fraction: Option<f64>,
    /// The radius within which the support holds the nodes, m: the largest radius of a held
    /// node (a hub clamps the nodes within `wheel.hub_radius`, so on a disk of rings it is
    /// the radius of the last ring inside it; 0 for the pinned centre).
    pub support_radius_m: f64,
    /// Smallest angle of the mesh's triangles, degrees.
    pub mesh_min_angle_deg: f64,
    /// Largest aspect ratio of the mesh's triangles (`R_c / (2 r_i)`, 1 = equilateral;
    /// [`crate::mesh::quality()`]).
    pub mesh_max_aspect: f64,
    /// The mesh's rotational symmetry order (6 for the hexagonal disk, 1 for the graded one).
    pub mesh_symmetry_order: usize,
    /// Largest penetration seen, m.
    pub max_penetration: f64,
    /// Largest `J2` of the turn average, MPa^2.
    pub max_j2_turn_average_mpa2: f64,
    /// Largest von Mises stress of the turn average of `sqrt(3 J2)`, MPa.
    pub max_von_mises_turn_average_mpa: f64,
    /// Energy (kinetic + strain) at the end of settling and at the end, J.
    pub energy_after_settling: f64,
    /// Energy at the end, J.
    pub energy_final: f64,
    /// Brakings (steps stepped back).
    pub brakings: usize,
    /// Releases.
    pub releases: usize,
    /// Numeric factorizations of the step matrix over the run.
    pub factorizations: usize,
    /// Stick/slip changes of the friction rows over the run (each a dense re-solve on cached
    /// columns, never a factorization).
    pub stick_slip_changes: usize,
    /// Relocations of the refined zone (`wheel.zone_rim_nodes`; 0 without a zone).
    pub relocations: usize,
    /// Wall-clock time of the time loop, s.
    pub wall_time_s: f64,
    /// Time per step, microseconds.
    pub time_per_step_us: f64,
    /// True when interrupted.
    pub interrupted: bool,
    /// Warnings for the user (not in `summary.json`; [`crate::run::Results::warnings`]).
    #[serde(skip)]
    pub warnings: Vec<String>,
    /// Traction with friction (`contact.friction > 0`): creep force, stick and slip, Carter.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub traction: Option<TractionSummary>,
    /// The plastic wheel (`material.model = "j2"`): the iteration's cost, the plastic
    /// strain and the rim's permanent radial displacement.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub plastic: Option<PlasticSummary>,
    /// The wheel in large deformation (`material.geometry = "large"`): the iteration's cost,
    /// the strains and energy against the linear model's reading of the same displacement.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub large_deformation: Option<crate::kinds::wheel::large::LargeSummary>,
}

/// The plastic wheel's figures (`summary.json`, `plastic`).
#[derive(Debug, Clone, Serialize)]
pub struct PlasticSummary {
    /// The iteration's tolerance (residual over internal force).
    pub tolerance: f64,
    /// Corrections of the initial-stress iteration over the run (a right-hand side and a
    /// solve on the elastic factor each; [`crate::model::internal`]).
    pub plastic_iterations: usize,
    /// `plastic_iterations` per step.
    pub plastic_iterations_per_step: f64,
    /// Most corrections in one solve.
    pub plastic_max_in_one_solve: usize,
    /// Solves stopped at the cap without reaching the tolerance.
    pub plastic_unconverged: usize,
    /// Largest equivalent plastic strain of an element at the end.
    pub max_equivalent_plastic_strain: f64,
    /// Elements with plastic strain at the end.
    pub plastic_elements: usize,
    /// The rim's permanent radial displacement (load taken off;
    /// [`crate::plasticity::permanent_radial_displacement`]): smallest and largest, m.
    pub rim_permanent_radial_displacement_min_m: f64,
    /// Largest, m.
    pub rim_permanent_radial_displacement_max_m: f64,
}

/// The plastic wheel's state at the end of a run.
#[derive(Debug, Clone)]
pub struct PlasticRecord {
    /// Equivalent plastic strain per element.
    pub equivalent_plastic_strain: Vec<f64>,
    /// The rim's permanent radial displacement: `(arc length m, displacement m)` per rim
    /// node.
    pub rim: Vec<(f64, f64)>,
}

/// What one wheel run gives: the tables (held, or streamed into the folder given to
/// [`simulate`]), the summary and what the fields, profiles and figures are made of.
#[derive(Debug)]
pub struct WheelRecord {
    /// The key figures.
    pub summary: WheelSummary,
    /// `history.csv`'s table.
    pub history: Columns,
    /// `contact_nodes.csv`'s table.
    pub contact_nodes: Columns,
    /// `traction_history.csv`'s table (with friction).
    pub traction_history: Option<Columns>,
    /// The observers' results.
    pub results: WheelResults,
    /// The rim profile of the turn-averaged `J2`.
    pub profile: figures::RimProfile,
    /// The traction's figures and steady profile (with friction).
    pub traction: Option<(TractionSummary, TractionProfile)>,
    /// The plastic state at the end (`material.model = "j2"`).
    pub plastic: Option<PlasticRecord>,
}

/// Runs one wheel run: build the observers, attach them to the step loop ([`drive`]),
/// collect. The tables are streamed into the folder `stream` (`history.csv`,
/// `contact_nodes.csv`, `traction_history.csv`) when given, else held in memory.
///
/// # Errors
/// [`RunError`].
pub fn simulate(
    wm: &WheelModel,
    ws: &WheelScenario,
    run: &Run,
    sc: &Scenario,
    stream: Option<&Path>,
    opts: &RunOptions,
) -> Result<WheelRecord, RunError> {
    // The bounce of the disk between its support and the contact: the settling's shortest
    // time and the node-passing resonance warning, before the run.
    let bounce = bounce_mode(wm, wm.spec.flattening.depth).ok();
    step_adequacy(wm, ws, run, sc, bounce)?;
    if let Some(out) = stream {
        std::fs::create_dir_all(out).map_err(|e| RunError::output(out, e))?;
    }
    let file = |name: &str| stream.map(|out| out.join(name));
    let h = run.params.h;
    let timeline = Timeline {
        h,
        t_settle: ws.spec.flattening.settle_time,
        turn_time: 2.0 * PI / ws.spec.omega,
        turns: ws.turns,
    };
    let steps = (ws.duration() / h).round() as usize;
    let last_turn = timeline.last_full_turn();
    let warnings = warnings_before(wm, ws, run, bounce);
    let mut history = HistoryWriter::create(
        file("history.csv").as_deref(),
        sc.history_stride,
        wm.base(),
        steps,
    )?;
    let with_friction = run.friction.is_some_and(|l| l.is_active());
    let mut nodes = ContactNodesWriter::create(
        file("contact_nodes.csv").as_deref(),
        sc.history_stride,
        &wm.rim,
        with_friction,
    )?;
    let mut forces = ContactForceStats::new(timeline, steps);
    let mut energy = EnergyWatch::new(timeline);
    let mut average = TurnAverage::new(wm, timeline, last_turn, ws.large.is_some());
    let mut snapshots =
        VelocitySnapshots::new(timeline, last_turn.0, ws.fields_per_turn, wm.mesh.n_dofs());
    let mut progress = Progress::new(steps, &run.label, opts);
    let mu = run.friction.filter(|l| l.is_active()).map(|l| l.static_mu);
    let mut traction = match mu {
        Some(_) => Some(TractionWatch::create(
            wm,
            timeline,
            file("traction_history.csv").as_deref(),
            sc.history_stride,
        )?),
        None => None,
    };
    // Behind the loop (module `crate::simulation::behind`): the tables, statistics and sums.
    let mut watchers: Vec<&mut (dyn Observer + Send)> = vec![
        &mut history,
        &mut nodes,
        &mut forces,
        &mut energy,
        &mut snapshots,
    ];
    // With a moving zone the nodes are relabelled as the zone follows the contact: a
    // per-element turn average would mix material points, so none is taken.
    if wm.zone.is_none() {
        watchers.push(&mut average);
    }
    if let Some(t) = traction.as_mut() {
        watchers.push(t);
    }
    // On the stepping thread: the progress and the guard that stops the run at its step.
    let mut rotation = RotationWatch::new(wm, ws.large.is_some());
    let mut inline: Vec<&mut dyn Observer> = vec![&mut progress];
    if wm.zone.is_none() {
        inline.push(&mut rotation);
    }
    let (outcome, plastic_state, u_end) = drive(
        wm,
        ws,
        run,
        (steps, timeline, sc.history_stride),
        (&mut watchers, &mut inline),
        opts,
    )?;
    drop((watchers, inline));
    progress.finish();
    let traction = match (traction, mu) {
        (Some(t), Some(mu)) => {
            let e = &ws.spec.material;
            let e_star = match ws.spec.plane {
                PlaneModel::Stress => e.young,
                PlaneModel::Strain => e.young / (1.0 - e.poisson * e.poisson),
            };
            Some(t.finish(
                mu,
                ws.spec.creepage,
                (ws.spec.radius, ws.spec.thickness, e_star),
            )?)
        }
        _ => None,
    };
    let results = WheelResults {
        timeline,
        outcome,
        forces: forces.finish(ws.spec.omega, wm.passing_nodes()),
        energy: energy.finish(),
        fields: if wm.zone.is_some() {
            TurnAverageFields {
                j2_mpa2: Vec::new(),
                von_mises_mpa: Vec::new(),
            }
        } else {
            average.finish()
        },
        snapshots: snapshots.finish(),
    };
    let mut summary = summarise(wm, ws, run, &results, bounce);
    summary.warnings = warnings;
    if let Some(large) = ws.large {
        summary.large_deformation = Some(crate::kinds::wheel::large::summary(
            wm,
            large,
            crate::kinds::wheel::large::Iterations {
                total: outcome.plastic_iterations,
                steps: outcome.steps,
                max_in_one_solve: outcome.plastic_max_in_one_solve,
                unconverged: outcome.plastic_unconverged,
            },
            &u_end,
            rotation.max().0,
        ));
    }
    if let Some(w) = rotation.warning(&run.label) {
        summary.warnings.push(w);
    }
    let plastic = match (ws.plastic, plastic_state) {
        (Some(pl), Some(state)) => {
            let (record, ps) = plastic_results(wm, ws, pl, &state, &outcome, sc_path_of(sc))?;
            summary.plastic = Some(ps);
            Some(record)
        }
        _ => None,
    };
    let (traction, traction_history) = match traction {
        Some((ts, profile, table)) => {
            summary.traction = Some(ts.clone());
            (Some((ts, profile)), Some(table))
        }
        None => (None, None),
    };
    Ok(WheelRecord {
        history: history.finish()?,
        contact_nodes: nodes.finish()?,
        traction_history,
        profile: figures::RimProfile::of(wm, &results),
        summary,
        results,
        traction,
        plastic,
    })
}

/// The scenario's path (errors name it).
fn sc_path_of(sc: &Scenario) -> &Path {
    &sc.path
}

/// The plastic wheel's record and figures from its state at the end of the run.
///
/// # Errors
/// [`RunError`] when the elastic stiffness with the support is singular.
fn plastic_results(
    wm: &WheelModel,
    ws: &WheelScenario,
    pl: crate::scenario::Plastic,
    state: &[f64],
    o: &LoopOutcome,
    sc_path: &Path,
) -> Result<(PlasticRecord, PlasticSummary), RunError> {
    let body = plastic_body(wm, ws, pl);
    let mut eq = vec![0.0; wm.triangles.len()];
    body.equivalent_plastic_strain_into(state, &mut eq);
    let rim = crate::plasticity::permanent_radial_displacement(
        &body,
        state,
        (wm.model.pattern(), &wm.k_elastic, &wm.fixed_dofs),
        &wm.mesh.reference_positions(),
        &wm.rim,
    )
    .map_err(|e| RunError::input(sc_path, e))?;
    let summary = PlasticSummary {
        tolerance: pl.tolerance,
        plastic_iterations: o.plastic_iterations,
        plastic_iterations_per_step: o.plastic_iterations as f64 / o.steps.max(1) as f64,
        plastic_max_in_one_solve: o.plastic_max_in_one_solve,
        plastic_unconverged: o.plastic_unconverged,
        max_equivalent_plastic_strain: eq.iter().fold(0.0, |m: f64, v| m.max(*v)),
        plastic_elements: eq.iter().filter(|&&v| v > 0.0).count(),
        rim_permanent_radial_displacement_min_m: rim
            .iter()
            .map(|r| r.1)
            .fold(f64::INFINITY, f64::min),
        rim_permanent_radial_displacement_max_m: rim
            .iter()
            .map(|r| r.1)
            .fold(f64::NEG_INFINITY, f64::max),
    };
    Ok((
        PlasticRecord {
            equivalent_plastic_strain: eq,
            rim,
        },
        summary,
    ))
}

/// The plastic body of the wheel's triangles.
pub(crate) fn plastic_body(
    wm: &WheelModel,
    ws: &WheelScenario,
    pl: crate::scenario::Plastic,
) -> crate::plasticity::PlasticBody {
    crate::plasticity::PlasticBody::new(
        pl.material,
        ws.spec.plane,
        ws.spec.thickness,
        wm.triangles.clone(),
        wm.geometry.clone(),
    )
}

/// The observers' results of a run.
#[derive(Debug, Clone)]
pub struct WheelResults {
    /// The run's phases.
    pub timeline: Timeline,
    /// The loop's counters.
    pub outcome: LoopOutcome,
    /// Contact-force figures and the force over time.
    pub forces: ContactForceSummary,
    /// Energy after settling and at the end, J.
    pub energy: (f64, f64),
    /// Turn-averaged `J2` and von Mises.
    pub fields: TurnAverageFields,
    /// Velocity snapshots of the last full turn.
    pub snapshots: Snapshots,
}
