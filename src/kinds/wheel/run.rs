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
pub(crate) mod figures;
pub mod load;
pub(crate) mod observers;
pub(crate) mod traction;

pub(crate) use collect::record;

use crate::analysis::components::{
    fixed_frequency_per_turn, spectral_components, Component, ComponentKind, ComponentOptions,
};
use crate::linalg::quadratic_form;
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
use crate::wheel::{Support, WheelModel, WheelSpec};
use observers::{
    ContactForceStats, ContactForceSummary, ContactNodesWriter, EnergyWatch, HistoryWriter,
    Observer, Progress, Snapshots, Timeline, TurnAverage, TurnAverageFields, VelocitySnapshots,
    WheelStep,
};
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

/// Builds the wheel model of a scenario.
///
/// # Errors
/// [`RunError`] for a bad mesh or a singular model.
pub fn build(ws: &WheelScenario, sc_path: &Path) -> Result<WheelModel, RunError> {
    let mesh: Mesh = match &ws.mesh {
        MeshSource::Rings(n) => {
            disk_rings(ws.spec.radius, *n).map_err(|e| RunError::input(sc_path, e))?
        }
        MeshSource::Graded { rim_nodes, grading } => disk_graded(
            ws.spec.radius,
            *rim_nodes,
            DiskOptions {
                grading: *grading,
                // A hub clamps the circle of its radius: the mesh is the annulus outside it.
                hub: match ws.spec.support {
                    Support::Hub { radius } => Some(radius),
                    Support::CentrePinned => None,
                },
            },
        )
        .map_err(|e| RunError::input(sc_path, e))?,
        MeshSource::Gmsh(p) => read_mesh_file(p, &ws.spec, sc_path)?,
        MeshSource::Zone(o) => {
            let z = disk_zone(o).map_err(|e| RunError::input(sc_path, e))?;
            let mut wm = WheelModel::new(z.mesh, ws.spec.clone())
                .map_err(|e| RunError::input(sc_path, e))?;
            wm.zone = Some((z.sources, z.step));
            return pressed_to_load(wm, ws, sc_path);
        }
    };
    let wm = WheelModel::new(mesh, ws.spec.clone()).map_err(|e| RunError::input(sc_path, e))?;
    pressed_to_load(wm, ws, sc_path)
}

/// The model with the flattening that carries `wheel.load` ([`load::flattening_for_load`]),
/// or as it is when the flattening was given.
fn pressed_to_load(
    mut wm: WheelModel,
    ws: &WheelScenario,
    sc_path: &Path,
) -> Result<WheelModel, RunError> {
    if let Some(p) = ws.load {
        let found = load::flattening_for_load(&wm, p)
            .map_err(|e| RunError::input(sc_path, format!("wheel.load = {p} N: {e}")))?;
        wm.spec.flattening.depth = found.depth;
    }
    Ok(wm)
}

/// Reads the wheel's Gmsh mesh `p` (the scenario's `wheel.mesh`) and checks it is a disk
/// of the wheel's radius about the axle ([`check_disk`]) held by its support in every part
/// ([`check_supported`]).
///
/// # Errors
/// [`RunError::Input`] naming the scenario `sc_path`, the key `wheel.mesh`, the mesh file
/// and what is wrong.
pub fn read_mesh_file(p: &Path, spec: &WheelSpec, sc_path: &Path) -> Result<Mesh, RunError> {
    let at_fault = |e: String| RunError::Input {
        path: sc_path.to_path_buf(),
        message: format!("`wheel.mesh` = \"{}\": {e}", p.display()),
    };
    let (mesh, tags) = read_msh_tagged(p).map_err(|e| at_fault(e.to_string()))?;
    check_disk(&mesh, &tags, spec.radius).map_err(at_fault)?;
    check_supported(&mesh, &tags, spec).map_err(at_fault)?;
    Ok(mesh)
}

/// Checks that every part of the mesh (its triangles joined through shared nodes) holds a
/// node of the wheel's support: a part with no path to the support would float free (a disk
/// and a separate annulus run with the annulus carrying no load). `tags` are the nodes' Gmsh
/// tags, for the message. A support that holds no node at all is left to
/// [`WheelModel::new`].
///
/// # Errors
/// A message naming the parts, a node of the loose part (Gmsh tag) and the support.
pub fn check_supported(mesh: &Mesh, tags: &[u64], spec: &WheelSpec) -> Result<(), String> {
    let crate::mesh::Cells::Tri3(tris) = &mesh.cells else {
        return Ok(());
    };
    let Ok(held) = crate::wheel::held_nodes(mesh, spec) else {
        return Ok(());
    };
    let n = mesh.n_nodes();
    let mut parent: Vec<usize> = (0..n).collect();
    fn root(parent: &mut [usize], mut i: usize) -> usize {
        while parent[i] != i {
            parent[i] = parent[parent[i]];
            i = parent[i];
        }
        i
    }
    for t in tris {
        for k in 1..3 {
            let (a, b) = (root(&mut parent, t[0]), root(&mut parent, t[k]));
            parent[a.max(b)] = a.min(b);
        }
    }
    let mut supported = vec![false; n];
    for &i in &held {
        let r = root(&mut parent, i);
        supported[r] = true;
    }
    let tag = |i: usize| tags.get(i).copied().unwrap_or(i as u64);
    let roots: Vec<usize> = (0..n).map(|i| root(&mut parent, i)).collect();
    let mut parts: Vec<usize> = roots.clone();
    parts.sort_unstable();
    parts.dedup();
    // The loose part holding the smallest node tag, its size and that tag.
    let loose = (0..n)
        .filter(|&i| !supported[roots[i]])
        .min_by_key(|&i| tag(i));
    let Some(first) = loose else {
        return Ok(());
    };
    let size = roots.iter().filter(|&&r| r == roots[first]).count();
    let support = match spec.support {
        Support::CentrePinned => format!("the pinned centre, node {}", tag(held[0])),
        Support::Hub { radius } => format!(
            "the hub's {} nodes within wheel.hub_radius = {radius} m",
            held.len()
        ),
    };
    Err(format!(
        "the mesh is in {} parts and one of {size} nodes (node {} among them) has no path to the support ({support}): it would float free; join the parts (Gmsh: Coherence Mesh) or remove the loose one",
        parts.len(),
        tag(first)
    ))
}

/// Relative tolerance on the radius of the rim of a mesh read from a file.
const RIM_TOLERANCE: f64 = 1e-3;

/// Checks that a mesh read from a file is a disk of `radius` (m) centred at the axle: its
/// largest radius is `radius`, every node of its outer boundary (boundary nodes beyond half
/// the radius) is on that circle, and so is every node of a `"rim"` group. `tags` are the
/// nodes' Gmsh tags, for the message.
///
/// # Errors
/// A message naming the node (Gmsh tag), its position and what is allowed.
pub fn check_disk(mesh: &Mesh, tags: &[u64], radius: f64) -> Result<(), String> {
    let r = |i: usize| mesh.point(i)[0].hypot(mesh.point(i)[1]);
    let tag = |i: usize| tags.get(i).copied().unwrap_or(i as u64);
    let off = |i: usize| (r(i) / radius - 1.0).abs() > RIM_TOLERANCE;
    let describe = |i: usize, what: &str| {
        format!(
            "node {} at ({:.6e}, {:.6e}) m, {what}, is at radius {:.6e} m: the wheel's rim must be the circle of wheel.radius = {radius} m about the axle (0, 0), within {RIM_TOLERANCE:e} (an off-centre, out-of-round or wrongly scaled mesh)",
            tag(i),
            mesh.point(i)[0],
            mesh.point(i)[1],
            r(i)
        )
    };
    let Some(far) = (0..mesh.n_nodes()).max_by(|&a, &b| r(a).total_cmp(&r(b))) else {
        return Err("the mesh has no nodes".into());
    };
    if off(far) {
        return Err(describe(far, "the farthest from the axle"));
    }
    if let crate::mesh::Cells::Tri3(tris) = &mesh.cells {
        let mut edges: std::collections::HashMap<(usize, usize), u32> =
            std::collections::HashMap::new();
        for t in tris {
            for (a, b) in [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])] {
                *edges.entry((a.min(b), a.max(b))).or_default() += 1;
            }
        }
        let mut boundary: Vec<usize> = edges
            .iter()
            .filter(|(_, &n)| n == 1)
            .flat_map(|(&(a, b), _)| [a, b])
            .filter(|&i| r(i) > 0.5 * radius)
            .collect();
        boundary.sort_unstable();
        if let Some(&i) = boundary.iter().find(|&&i| off(i)) {
            return Err(describe(i, "on the outer boundary"));
        }
    }
    if let Some(&i) = mesh
        .node_set("rim")
        .unwrap_or(&[])
        .iter()
        .find(|&&i| off(i))
    {
        return Err(describe(i, "in the group \"rim\""));
    }
    Ok(())
}

/// Screen lines of a summary.
pub fn summary_lines(s: &WheelSummary) -> Vec<String> {
    let mut lines = base_lines(s);
    if let Some(p) = &s.plastic {
        lines.push(format!(
            "plastic: {} iterations ({:.2} per step, at most {} in one solve, {} unconverged, tolerance {:e}); max equivalent plastic strain {:.3e} in {} elements; rim's permanent radial displacement {:.3e} to {:.3e} m",
            p.plastic_iterations,
            p.plastic_iterations_per_step,
            p.plastic_max_in_one_solve,
            p.plastic_unconverged,
            p.tolerance,
            p.max_equivalent_plastic_strain,
            p.plastic_elements,
            p.rim_permanent_radial_displacement_min_m,
            p.rim_permanent_radial_displacement_max_m
        ));
    }
    if let Some(t) = &s.traction {
        lines.push(format!(
            "traction (mu = {}, creepage {:.3e}): Q = {:.4e} N, P = {:.4e} N, Q/(mu P) = {:.4} (Carter {:.4}); {:.2} nodes in stick, {:.2} in slip; stick half-width {:.3} mm (Hertz a = {:.3} mm); friction energy {:.3e} J",
            t.friction,
            t.creepage,
            t.traction,
            t.normal,
            t.traction_ratio,
            t.carter_traction_ratio,
            t.mean_stick_nodes,
            t.mean_slip_nodes,
            t.measured_stick_half_width * 1e3,
            t.hertz_half_width * 1e3,
            t.friction_energy
        ));
    }
    lines
}

/// The lines every wheel run prints.
fn base_lines(s: &WheelSummary) -> Vec<String> {
    vec![
        format!(
            "omega = {} rad/s ({:.0} km/h), {} dofs, {} steps of {:.3e} s in {:.2} s ({:.1} us/step)",
            (s.omega * 1e4).round() / 1e4, s.speed_km_h, s.dofs, s.steps, s.h, s.wall_time_s, s.time_per_step_us
        ),
        format!(
            "contact force over the turns: mean {:.4e} N, min {:.4e} N, max {:.4e} N; {:.2} nodes in contact on average",
            s.mean_contact_force, s.min_contact_force, s.max_contact_force, s.mean_nodes_in_contact
        ),
        match s.requested_load_n {
            Some(p) => format!(
                "flattening {:.4e} m, found for the load {p:.4e} N (static); Hertz's patch spans {:.1} rim pitches",
                s.flattening_m, s.patch_rim_pitches
            ),
            None => format!(
                "flattening {:.4e} m; Hertz's patch spans {:.1} rim pitches",
                s.flattening_m, s.patch_rim_pitches
            ),
        },
        format!(
            "oscillations per turn {:?}; dominant frequency {} ({} cycles per turn); node passing {:.1} Hz",
            s.oscillations_per_turn,
            s.dominant_frequency_hz.map(|f| format!("{f:.1} Hz")).unwrap_or_else(|| "-".into()),
            s.dominant_cycles_per_turn.map(|f| format!("{f:.2}")).unwrap_or_else(|| "-".into()),
            s.node_passing_frequency_hz
        ),
        format!(
            "{}; max penetration {:.2e} m; energy {:.4e} -> {:.4e} J",
            if s.max_j2_turn_average_mpa2.is_nan() {
                format!("no turn averages ({} relocations of the refined zone)", s.relocations)
            } else {
                format!(
                    "turn-averaged J2 max {:.4e} MPa^2, von Mises max {:.2} MPa",
                    s.max_j2_turn_average_mpa2, s.max_von_mises_turn_average_mpa
                )
            },
            s.max_penetration,
            s.energy_after_settling,
            s.energy_final
        ),
        format!(
            "spectral components (Hz, per turn, amplitude, kind): {}",
            s.spectral_components
                .iter()
                .take(5)
                .map(describe)
                .collect::<Vec<_>>()
                .join("; ")
        ),
        format!(
            "bounce of the wheel on its support and contact {}; mesh: smallest angle {:.1} deg, largest aspect {:.2}, rotational symmetry order {}",
            s.bounce_frequency_hz
                .map(|f| format!("{f:.1} Hz"))
                .unwrap_or_else(|| "-".into()),
            s.mesh_min_angle_deg,
            s.mesh_max_aspect,
            s.mesh_symmetry_order
        ),
    ]
}

/// One spectral component in a few words.
fn describe(c: &Component) -> String {
    let kind = match c.kind {
        ComponentKind::NodePassing { harmonic } => format!("node passing x{harmonic}"),
        ComponentKind::Mode { .. } => "bounce mode".into(),
        ComponentKind::Locked { cycles_per_turn } => format!("locked, {cycles_per_turn} per turn"),
        ComponentKind::Unclassified => "fixed frequency".into(),
    };
    format!(
        "{:.1} Hz, {:.2}, {:.3e} N, {kind}",
        c.hz, c.cycles_per_turn, c.amplitude
    )
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
    let mut watchers: Vec<&mut dyn Observer> = vec![
        &mut history,
        &mut nodes,
        &mut forces,
        &mut energy,
        &mut snapshots,
        &mut progress,
    ];
    // With a moving zone the nodes are relabelled as the zone follows the contact: a
    // per-element turn average would mix material points, so none is taken.
    if wm.zone.is_none() {
        watchers.push(&mut average);
    }
    if let Some(t) = traction.as_mut() {
        watchers.push(t);
    }
    let mut rotation = RotationWatch::new(wm);
    if wm.zone.is_none() {
        watchers.push(&mut rotation);
    }
    let (outcome, plastic_state) = drive(
        wm,
        ws,
        run,
        (steps, timeline, sc.history_stride),
        &mut watchers,
        opts,
    )?;
    drop(watchers);
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
    observers: &mut [&mut dyn Observer],
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
    let mut rolling_seen = false;
    // Uncoupled (a twin disk): the observers see the wheel's own state, the sum of the two.
    let twin = wm.twin.is_some();
    let own = if twin { wm.mesh.n_dofs() } else { 0 };
    let (mut u_own, mut v_own) = (vec![0.0; own], vec![0.0; own]);
    let stats = sim
        .run(opts.cancel.flag(), |s| {
            let st = s.state;
            let first_rolling = !rolling_seen && timeline.rolling(st.t);
            rolling_seen |= first_rolling;
            let (u, v): (&[f64], &[f64]) = if twin {
                wm.own_state(&st.u, &mut u_own);
                wm.own_state(&st.v, &mut v_own);
                (&u_own, &v_own)
            } else {
                (&st.u, &st.v)
            };
            let energy = (st.k % stride == 0 || s.last || first_rolling).then(|| {
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
            };
            observers.iter_mut().try_for_each(|o| o.observe(&step))
        })
        .map_err(|e| sim_error(stopped_by_observer(e)))?;
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

/// The key figures of a run.
fn summarise(
    wm: &WheelModel,
    ws: &WheelScenario,
    run: &Run,
    r: &WheelResults,
    bounce: Option<Bounce>,
) -> WheelSummary {
    let omega = ws.spec.omega;
    let (f, o) = (&r.forces, &r.outcome);
    let (tr, fr) = (&f.window.0, &f.window.1);
    let modes: Vec<f64> = bounce.iter().map(|b| b.frequency_hz).collect();
    let components = spectral_components(
        tr,
        fr,
        omega,
        wm.passing_nodes(),
        &modes,
        &ComponentOptions::default(),
    );
    let q = mesh_quality(&wm.mesh);
    WheelSummary {
        label: run.label.clone(),
        omega,
        speed_km_h: omega * ws.spec.radius * 3.6,
        flattening_m: wm.spec.flattening.depth,
        requested_load_n: ws.load,
        patch_rim_pitches: 2.0 * load::hertz_half_width(wm, f.mean) * wm.passing_nodes() as f64
            / (2.0 * PI * wm.spec.radius),
        h: run.params.h,
        alpha: run.params.alpha,
        gamma: run.params.gamma,
        dofs: wm.mesh.n_dofs(),
        nodes: wm.mesh.n_nodes(),
        triangles: wm.triangles.len(),
        turns: ws.turns,
        steps: o.steps,
        mean_contact_force: f.mean,
        max_contact_force: f.max,
        min_contact_force: f.min,
        mean_nodes_in_contact: f.mean_nodes_held,
        oscillations_per_turn: f.oscillations_per_turn.clone(),
        dominant_frequency_hz: f.dominant.map(|d| d.0),
        dominant_cycles_per_turn: f.dominant.map(|d| d.0 / f.rotation_hz),
        node_passing_frequency_hz: f.node_passing_hz,
        fixed_frequency_cycles_per_turn: fixed_frequency_per_turn(&components),
        spectral_components: components,
        spectrum_window_s: f.window.0.len() as f64 * run.params.h,
        bounce_frequency_hz: bounce.map(|b| b.frequency_hz),
        support_radius_m: wm.support_radius(),
        bounce_vertical_mass_fraction: bounce.map(|b| b.vertical_mass_fraction),
        mesh_min_angle_deg: q.min_angle_deg,
        mesh_max_aspect: q.max_aspect,
        mesh_symmetry_order: q.symmetry_order,
        max_penetration: f.max_penetration,
        max_j2_turn_average_mpa2: max_or_nan(&r.fields.j2_mpa2),
        max_von_mises_turn_average_mpa: max_or_nan(&r.fields.von_mises_mpa),
        energy_after_settling: r.energy.0,
        energy_final: r.energy.1,
        brakings: o.brakings,
        releases: o.releases,
        factorizations: o.factorizations,
        stick_slip_changes: o.stick_slip_changes,
        relocations: o.relocations,
        wall_time_s: o.wall_time_s,
        time_per_step_us: o.wall_time_s / o.steps.max(1) as f64 * 1e6,
        interrupted: o.interrupted,
        warnings: Vec::new(),
        traction: None,
        plastic: None,
    }
}

/// The largest value, NaN (null in JSON) when there is none (no turn average with a moving
/// zone).
fn max_or_nan(v: &[f64]) -> f64 {
    if v.is_empty() {
        f64::NAN
    } else {
        v.iter().cloned().fold(0.0, f64::max)
    }
}

/// What to warn about before a wheel run, and the bounce it was found from: the node
/// passing near the bounce of the wheel on its support and contact (a resonance), a hub
/// that holds fewer nodes than its radius asks.
/// Steps a rim node's passage under the base must take at least (the wheel job refuses a longer step before the run).
pub const STEPS_PER_PASSAGE_MIN: f64 = 2.0;

/// The largest stretch of the rim by the spin, relative to its radius, that a run accepts
/// (a steel rim at 500 m/s; a wheel at 30 m/s: 3.5e-5).
pub const MAX_SPIN_STRETCH: f64 = 0.01;

/// Refuses a spin that stretches the rim beyond [`MAX_SPIN_STRETCH`] (small strains), a rim
/// whose base chord at the flattening is shorter than the rim's pitch (the
/// contact is lost between two nodes: a 400 m wheel at 1 mm on 48 nodes touched 3% of the
/// time, and its spectrum had nothing to draw after the run), and a step longer than half a
/// rim node's passage under the base,
/// `t_pass = 2 pi / (omega N)` (`N` the rim's nodes at the pitch under the contact): the
/// contact would jump a node between steps, and the soft way, which brakes a node in the
/// step before it lands, would act on nodes it never saw coming (before this check:
/// negative contact forces and 0.65 mm of penetration at h = 3e-4 s on the paper's wheel,
/// whose passage takes 290 us), and a settling shorter than one period of the disk's bounce
/// on its support and contact (`bounce`: the base would strike the wheel).
fn step_adequacy(
    wm: &WheelModel,
    ws: &WheelScenario,
    run: &Run,
    sc: &Scenario,
    bounce: Option<Bounce>,
) -> Result<(), RunError> {
    let passing = wm.passing_nodes() as f64;
    // The rim touches the base over the angle 2 phi_c, cos(phi_c) = 1 - d / R (module docs
    // of `contact`: the flattening d measured from the spinning rim's radius R).
    let (radius, depth) = (wm.spinning_radius(), wm.spec.flattening.depth);
    let stretch = radius / wm.spec.radius - 1.0;
    if stretch > MAX_SPIN_STRETCH {
        return Err(RunError::input(
            &sc.path,
            format!(
                "run `{}`: the spin at `rolling.omega` = {} rad/s stretches the rim by {:.3e} of its radius (rim speed {:.4e} m/s): the model is linear, for strains up to {MAX_SPIN_STRETCH}; lower `rolling.omega` or `wheel.radius`",
                run.label,
                ws.spec.omega,
                stretch,
                ws.spec.omega.abs() * wm.spec.radius
            ),
        ));
    }
    if depth > 0.0 && depth < radius {
        let phi_c = (1.0 - depth / radius).acos();
        let pitch = 2.0 * PI / passing;
        if 2.0 * phi_c < pitch {
            return Err(RunError::input(
                &sc.path,
                format!(
                    "run `{}`: the base's chord at the flattening {depth:e} m spans {:.3} of the rim's pitch ({:.4e} m of {:.4e} m at {passing} rim nodes and radius {radius:.4e} m): between two nodes none touches the base and the contact force falls to zero; take `wheel.rim_nodes` >= {} or a deeper `rolling.flattening` (or `wheel.load`)",
                    run.label,
                    2.0 * phi_c / pitch,
                    2.0 * radius * phi_c.sin(),
                    radius * pitch,
                    (PI / phi_c).ceil()
                ),
            ));
        }
    }
    // The base pressed in faster than the disk's bounce on its support and contact strikes
    // it: the rim's lowest nodes take the flattening within a step or a few, the soft way
    // catches them there (a penetration of the whole flattening), and the energy of the
    // blow stays in the run (a 96-node rim pressed 1 mm in 6 ns: 0.67 mm, 0.002 J -> 523 J).
    let settle = wm.spec.flattening.settle_time;
    if depth > 0.0 {
        // The bounce's period, or where its mode is not found (a rim too coarse for the
        // patch to hold a node), the time a compression wave takes to cross the disk: a
        // lower bound of any loading time.
        let material = &wm.spec.material;
        let (period, what) = match bounce.filter(|b| b.frequency_hz > 0.0) {
            Some(b) => (
                1.0 / b.frequency_hz,
                format!(
                    "one period of the wheel's bounce on its support and contact ({:.3e} s at {:.1} Hz)",
                    1.0 / b.frequency_hz,
                    b.frequency_hz
                ),
            ),
            None => {
                let t = 2.0 * wm.spec.radius / (material.young / material.density).sqrt();
                (
                    t,
                    format!("the time a compression wave takes to cross the wheel ({t:.3e} s, 2 R / sqrt(E / rho))"),
                )
            }
        };
        if settle < period {
            return Err(RunError::input(
                &sc.path,
                format!(
                    "run `{}`: `rolling.settle_time` = {settle:e} s presses the base to the flattening {depth:e} m in less than {what}: the base would strike the wheel, not load it; take `rolling.settle_time` >= {period:.3e} s",
                    run.label
                ),
            ));
        }
    }
    let t_pass = 2.0 * PI / (ws.spec.omega.abs() * passing);
    let h = run.params.h;
    if ws.spec.omega != 0.0 && h * STEPS_PER_PASSAGE_MIN > t_pass {
        return Err(RunError::input(
            &sc.path,
            format!(
                "run `{}`: the step `{}` = {h:e} s is longer than half a rim node's passage under the base ({t_pass:.3e} s: {passing} rim nodes at `rolling.omega` = {} rad/s): the contact would jump nodes between steps; take h <= {:.3e} s",
                run.label,
                run.step_key,
                ws.spec.omega,
                t_pass / STEPS_PER_PASSAGE_MIN
            ),
        ));
    }
    Ok(())
}

fn warnings_before(
    wm: &WheelModel,
    ws: &WheelScenario,
    run: &Run,
    bounce: Option<Bounce>,
) -> Vec<String> {
    let mut warnings = Vec::new();
    // The node-passing harmonics that would drive the bounce (a resonance warning).
    // A rim too coarse for the patch: Hertz's width at the load (or at the static force of
    // the flattening given) against the rim's pitch.
    let force = ws.load.or_else(|| {
        load::static_contact(wm, wm.spec.flattening.depth)
            .ok()
            .map(|f| f.0)
    });
    if let Some(w) = force.and_then(|f| load::coarse_rim_warning(wm, f, &run.label)) {
        warnings.push(w);
    }
    if let Some(b) = bounce {
        let passing = ws.spec.omega * wm.passing_nodes() as f64 / (2.0 * PI);
        for k in 1..=4 {
            let f = k as f64 * passing;
            if (f / b.frequency_hz - 1.0).abs() < 0.05 {
                warnings.push(format!(
                    "{}: the node passing ({k} x {passing:.1} Hz = {f:.1} Hz) is within 5% of the bounce of the wheel on its support and contact ({:.1} Hz): expect a resonance (change omega, the rim nodes or the support)",
                    run.label, b.frequency_hz
                ));
            }
        }
    }
    // A hub holds the nodes within its radius: say so when the mesh has none near its circle
    // (a disk of rings, a Gmsh mesh), where the clamp is smaller than asked.
    if let Support::Hub { radius } = ws.spec.support {
        let held = wm.support_radius();
        if held < 0.95 * radius {
            warnings.push(format!(
                "{}: the hub of radius {radius} m holds the nodes within it, the outermost at {held:.4e} m: the mesh has no node on the hub's circle (generated disks with rim_nodes mesh it; support_radius_m in summary.json)",
                run.label
            ));
        }
    }
    warnings
}
