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
mod lines;
mod mesh;
mod seen;
mod summarise;
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
use crate::linalg::{quadratic_form, quadratic_forms};
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
    WheelStep,
};
use seen::{batches, Batch, Seen};
use serde::Serialize;
use std::f64::consts::PI;
use std::path::Path;
use std::time::Instant;
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
    let mut average = TurnAverage::new(wm, timeline, last_turn);
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
    let mut rotation = RotationWatch::new(wm);
    let mut inline: Vec<&mut dyn Observer> = vec![&mut progress];
    if wm.zone.is_none() {
        inline.push(&mut rotation);
    }
    let (outcome, plastic_state) = drive(
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

/// What the step loop reports back, in the job's terms.
#[derive(Debug, Clone, Copy)]
pub struct LoopOutcome {
    /// Steps taken.
    pub steps: usize,
    /// Brakings (steps stepped back).
    pub brakings: usize,
    /// Releases.
    pub releases: usize,
    /// Stopped by Ctrl-C.
    pub interrupted: bool,
    /// Numeric factorizations of the step matrix (a gamma schedule changes it once).
    pub factorizations: usize,
    /// Stick/slip changes of the friction rows (dense re-solves, no factorization).
    pub stick_slip_changes: usize,
    /// Relocations of the refined zone.
    pub relocations: usize,
    /// Wall-clock time of the loop, s.
    pub wall_time_s: f64,
    /// Corrections of the plastic iteration (0 when elastic).
    pub plastic_iterations: usize,
    /// Solves whose plastic iteration stopped at the cap.
    pub plastic_unconverged: usize,
    /// Most plastic corrections in one solve.
    pub plastic_max_in_one_solve: usize,
}

/// Runs the wheel's step loop with the observers attached: the one place that speaks to
/// the driver (the [`crate::simulation::Problem`] of [`WheelModel::problem`],
/// [`crate::simulation::Simulation`], its step view and counters). With a plastic wheel
/// (`material.model = "j2"`) the plastic body is the driver's internal force, and its state
/// at the end is returned beside the counters.
///
/// # Errors
/// [`RunError::Simulation`] (an observer's I/O error included).
pub fn drive(
    wm: &WheelModel,
    ws: &WheelScenario,
    run: &Run,
    (steps, timeline, stride): (usize, Timeline, usize),
    (observers, inline): Sides<'_, '_, '_, '_>,
    opts: &RunOptions,
) -> Result<(LoopOutcome, Option<Vec<f64>>), RunError> {
    use crate::simulation::Simulation;
    let sim_error = |source| RunError::Simulation {
        run: run.label.clone(),
        source,
    };
    let gamma_schedule = ws.gamma_schedule(run.params.gamma);
    let mut problem = wm.problem(
        run.integrator,
        run.params.h,
        gamma_schedule,
        run.contact,
        steps,
    );
    problem.friction = run.friction;
    let mut sim = Simulation::with_settings(problem, opts.settings()).map_err(sim_error)?;
    if let Some(pl) = ws.plastic {
        sim.set_internal_force(
            Box::new(plastic_body(wm, ws, pl)),
            pl.tolerance,
            crate::model::DEFAULT_MAX_ITERATIONS,
        )
        .map_err(sim_error)?;
    }
    if let Some((sources, step)) = &wm.zone {
        sim.set_relocation(crate::simulation::Relocation {
            sources: sources.clone(),
            step: *step,
            omega: ws.spec.omega,
            angle0: 0.0,
        })
        .map_err(sim_error)?;
    }
    let start = Instant::now();
    // The energies (two sparse quadratic forms) only where they are written: every
    // `stride`-th step, the first step of the rolling phase and the last one.
    let stride = stride.max(1);
    let timing = Timing {
        timeline,
        stride,
        last_turn: timeline.last_full_turn(),
        with_friction: run.friction.is_some_and(|l| l.is_active()),
    };
    // Behind the loop (module `seen`) where the stepping thread is alone on its core: a
    // run with threads to spare, a factor solved on one thread (below the split's order),
    // a wheel coupled to its base. Else every observer on the stepping thread.
    let n = wm.mesh.n_dofs();
    let behind = matches!(opts.par(), crate::linalg::team::Par::Threads(_))
        && n < crate::linalg::SPLIT_MIN_ORDER
        && wm.twin.is_none();
    let (stats, observed) = if behind {
        drive_behind(wm, &mut sim, timing, (observers, inline), opts)
    } else {
        let stats = drive_inline(wm, &mut sim, timing, (observers, inline), opts);
        (stats, Ok(()))
    };
    // An observer's error is the cause of a stop the loop reports as its own.
    observed.map_err(|e| sim_error(crate::simulation::SimError::Output(e)))?;
    let stats = stats.map_err(|e| sim_error(stopped_by_observer(e)))?;
    let plastic_state = sim.nonlinear().map(|nl| nl.state(1).to_vec());
    Ok((
        LoopOutcome {
            steps: stats.steps,
            brakings: stats.brakings,
            releases: stats.releases,
            interrupted: stats.interrupted,
            factorizations: stats.factorizations,
            stick_slip_changes: stats.stick_slip_changes,
            relocations: stats.relocations,
            wall_time_s: start.elapsed().as_secs_f64(),
            plastic_iterations: stats.plastic_iterations,
            plastic_unconverged: stats.plastic_unconverged,
            plastic_max_in_one_solve: stats.plastic_max_in_one_solve,
        },
        plastic_state,
    ))
}

/// When a wheel run's observers want what (the steps' schedule of [`drive`]).
#[derive(Debug, Clone, Copy)]
struct Timing {
    timeline: Timeline,
    /// The tables' and energies' stride.
    stride: usize,
    /// The last full turn (the turn average and the velocity snapshots), s.
    last_turn: (f64, f64),
    /// Friction: the traction's watch reads the pairs every step.
    with_friction: bool,
}

impl Timing {
    /// True when step `k` at `t` reports its energies (`last`: the run's last step;
    /// `rolling_seen`: the rolling phase was reached before, updated).
    fn energy_due(&self, k: usize, t: f64, last: bool, rolling_seen: &mut bool) -> bool {
        let first_rolling = !*rolling_seen && self.timeline.rolling(t);
        *rolling_seen |= first_rolling;
        k % self.stride == 0 || last || first_rolling
    }
}

/// The observers behind the loop and those on the stepping thread.
type Sides<'a, 'b, 'c, 'd> = (
    &'a mut [&'b mut (dyn Observer + Send + 'b)],
    &'c mut [&'d mut (dyn Observer + 'd)],
);

/// The step loop with every observer on the stepping thread (an uncoupled twin: the
/// observers see the wheel's own state, the sum of the disk's and its twin's).
fn drive_inline(
    wm: &WheelModel,
    sim: &mut crate::simulation::Simulation,
    timing: Timing,
    (observers, inline): Sides<'_, '_, '_, '_>,
    opts: &RunOptions,
) -> Result<crate::simulation::RunStats, crate::simulation::SimError> {
    let mut rolling_seen = false;
    let twin = wm.twin.is_some();
    let own = if twin { wm.mesh.n_dofs() } else { 0 };
    let (mut u_own, mut v_own) = (vec![0.0; own], vec![0.0; own]);
    sim.run(opts.cancel.flag(), |s| {
        let st = s.state;
        let due = timing.energy_due(st.k, st.t, s.last, &mut rolling_seen);
        let (u, v): (&[f64], &[f64]) = if twin {
            wm.own_state(&st.u, &mut u_own);
            wm.own_state(&st.v, &mut v_own);
            (&u_own, &v_own)
        } else {
            (&st.u, &st.v)
        };
        let energy = due.then(|| {
            if twin {
                let p = wm.model.pattern();
                (
                    0.5 * quadratic_form(p, &wm.model.m, v),
                    0.5 * quadratic_form(p, &wm.k_elastic, u),
                )
            } else {
                s.energies()
            }
        });
        let step = WheelStep {
            k: st.k,
            t: st.t,
            u,
            v,
            energy,
            penalty: s.penalty,
            contact_force: s.contact_force,
            held: s.held,
            min_gap: st.pairs.iter().map(|p| p.gap).fold(f64::INFINITY, f64::min),
            pairs: &st.pairs,
            slip_power: s.slip_power,
            friction_dissipated: s.friction_dissipated,
            frame_angle: s.frame_angle,
            team: Some(s.team()),
        };
        observers.iter_mut().try_for_each(|o| o.observe(&step))?;
        inline.iter_mut().try_for_each(|o| o.observe(&step))
    })
}

/// The step loop with the observers of `observers` behind it ([`crate::simulation::behind`],
/// module `seen`), those of `inline` on the stepping thread. The wheel is coupled to its
/// base (no twin).
fn drive_behind(
    wm: &WheelModel,
    sim: &mut crate::simulation::Simulation,
    timing: Timing,
    (observers, inline): Sides<'_, '_, '_, '_>,
    opts: &RunOptions,
) -> (
    Result<crate::simulation::RunStats, crate::simulation::SimError>,
    std::io::Result<()>,
) {
    let mut rolling_seen = false;
    // The energies behind the loop, except with a plastic wheel (its state corrects them).
    let forms = sim
        .energy_matrices()
        .map(|(p, m, k)| (p.clone(), m.to_vec(), k.to_vec()));
    let (h, (t0, t1)) = (timing.timeline.h, timing.last_turn);
    let energies = |seen: &Seen| {
        seen.energy.or_else(|| {
            let (p, m, k) = forms.as_ref()?;
            seen.want_energy.then(|| {
                let (mv, ku) = quadratic_forms(p, (m, &seen.v), (k, &seen.u));
                (0.5 * mv, 0.5 * ku)
            })
        })
    };
    let observe = |batch: &mut Batch| {
        let len = std::mem::take(&mut batch.len);
        batch.items[..len].iter().try_for_each(|seen| {
            let step = seen.step(energies(seen), None);
            observers.iter_mut().try_for_each(|o| o.observe(&step))
        })
    };
    let slots = batches(wm.mesh.n_dofs(), wm.rim.len());
    crate::simulation::behind::behind(slots, observe, |feed| {
        sim.run(opts.cancel.flag(), |s| {
            let st = s.state;
            let want_energy = timing.energy_due(st.k, st.t, s.last, &mut rolling_seen);
            // With the plastic state's correction: here, where the state is.
            let energy = (want_energy && forms.is_none()).then(|| s.energies());
            let batch = feed.current().map_err(std::io::Error::other)?;
            let seen = &mut batch.items[batch.len];
            // Module `seen`: the state where an observer reads it, the pairs likewise.
            seen.fields = want_energy || timing.timeline.within(st.t, t0 - h, t1 + h);
            seen.with_pairs = timing.with_friction || st.k % timing.stride == 0 || s.last;
            if seen.fields {
                seen.u.copy_from_slice(&st.u);
                seen.v.copy_from_slice(&st.v);
            }
            seen.pairs.clear();
            if seen.with_pairs {
                seen.pairs.extend_from_slice(&st.pairs);
            }
            (seen.k, seen.t, seen.energy, seen.want_energy) = (st.k, st.t, energy, want_energy);
            (seen.penalty, seen.contact_force, seen.held) = (s.penalty, s.contact_force, s.held);
            seen.min_gap = st.pairs.iter().map(|p| p.gap).fold(f64::INFINITY, f64::min);
            (seen.slip_power, seen.friction_dissipated) = (s.slip_power, s.friction_dissipated);
            seen.frame_angle = s.frame_angle;
            // The stepping thread's observers read the state in place.
            let step = WheelStep {
                u: &st.u,
                v: &st.v,
                pairs: &st.pairs,
                ..seen.step(energy, Some(s.team()))
            };
            // A stop of the guard here still leaves its step to the observers, as before.
            let inline_result = inline.iter_mut().try_for_each(|o| o.observe(&step));
            batch.len += 1;
            if batch.len == batch.items.len() {
                feed.send().map_err(std::io::Error::other)?;
            }
            inline_result
        })
    })
}

/// An observer's stop ([`RotationWatch`]: a [`crate::guard::Diverged`] carried in the
/// I/O error an observer returns) as the guard's own; other errors as they are.
fn stopped_by_observer(e: crate::simulation::SimError) -> crate::simulation::SimError {
    use crate::simulation::SimError;
    match e {
        SimError::Output(io) => {
            match io
                .get_ref()
                .and_then(|x| x.downcast_ref::<crate::guard::Diverged>())
            {
                Some(d) => SimError::Diverged(*d),
                None => SimError::Output(io),
            }
        }
        e => e,
    }
}

/// The wheel's rigid rotation about its centre against its frame, `theta = sum (x u_y -
/// y u_x) / sum r^2` over the rim nodes, watched every step. The model is linear: a rotation
/// `theta` shortens the rim's reach by `R theta^2 / 2`, which it does not see. A clamped hub
/// holds the rotation; the paper's pinned centre does not, and the contact's lever arms
/// rock the disk: about 2e-3 rad at 300 rad/s on the paper's mesh, 0.04 rad at 520 rad/s
/// (Fig. 15's fastest point: 8% of the flattening) and at 100 rad/s. Past 1% of the
/// flattening ([`ROTATION_REACH`]) the run warns, with the figure; past a quarter of it
/// ([`ROTATION_STOP`]) the run is stopped ([`crate::guard::Cause::Turned`]): the contact
/// force is then wrong by about as much (the penetration it sees is `d + R theta^2 / 2`
/// for a flattening `d`), and such a run (a 24-node rim at 31 rad/s: 0.14 rad, 100% of the
/// flattening, its energy up tenfold) is not a result.
struct RotationWatch {
    /// The rim nodes' dofs and reference coordinates `(dof, x, y)`.
    rim: Vec<(usize, f64, f64)>,
    /// `sum r^2` over them.
    r2: f64,
    /// The spun rim's radius and the flattening, m.
    radius: f64,
    depth: f64,
    /// The largest `|theta|` seen, rad, and its time, s.
    max: (f64, f64),
}

/// The rim's shortening by a rigid rotation, as a fraction of the flattening, beyond which
/// a wheel run warns ([`RotationWatch`]).
const ROTATION_REACH: f64 = 0.01;

/// The rim's shortening by a rigid rotation, as a fraction of the flattening, beyond which
/// a wheel run is stopped ([`RotationWatch`]).
const ROTATION_STOP: f64 = 0.25;

impl RotationWatch {
    fn new(wm: &WheelModel) -> Self {
        let rim: Vec<(usize, f64, f64)> = wm
            .rim
            .iter()
            .map(|&i| {
                let p = wm.mesh.point(i);
                (2 * i, p[0], p[1])
            })
            .collect();
        let r2 = rim.iter().map(|&(_, x, y)| x * x + y * y).sum::<f64>();
        Self {
            rim,
            r2,
            radius: wm.spinning_radius(),
            depth: wm.spec.flattening.depth,
            max: (0.0, 0.0),
        }
    }

    /// The warning when the rotation passed [`ROTATION_REACH`] of the flattening.
    fn warning(&self, label: &str) -> Option<String> {
        let (radius, depth) = (self.radius, self.depth);
        let (theta, t) = self.max;
        let reach = radius * theta * theta / 2.0;
        (depth > 0.0 && reach > ROTATION_REACH * depth).then(|| {
            format!(
                "{label}: the wheel turned up to {theta:.3e} rad against its frame (at t = {t:.4e} s; its rigid rotation about the centre, which only the contact holds): a linear model misses the rim's shortening R theta^2 / 2 = {:.1}% of the flattening; hold the wheel by its hub (`wheel.support = \"hub\"`)",
                100.0 * reach / depth
            )
        })
    }
}

impl Observer for RotationWatch {
    fn observe(&mut self, s: &WheelStep) -> std::io::Result<()> {
        if self.r2 > 0.0 {
            let m: f64 = self
                .rim
                .iter()
                .map(|&(d, x, y)| x * s.u[d + 1] - y * s.u[d])
                .sum();
            let theta = (m / self.r2).abs();
            if theta > self.max.0 {
                self.max = (theta, s.t);
                let reach = self.radius * theta * theta / 2.0 / self.depth;
                if self.depth > 0.0 && reach > ROTATION_STOP {
                    return Err(std::io::Error::other(crate::guard::Diverged {
                        step: s.k,
                        t: s.t,
                        cause: crate::guard::Cause::Turned {
                            theta,
                            reach,
                            limit: ROTATION_STOP,
                        },
                    }));
                }
            }
        }
        Ok(())
    }
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
