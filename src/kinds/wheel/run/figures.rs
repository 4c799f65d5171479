//! The figures of a wheel run (PNG): the contact force over the turns (Fig. 12) and a zoom
//! (Fig. 13), its amplitude spectrum, the turn-averaged `J2` and von Mises maps
//! (Figs. 14, 16) with the rim profile of the turn-averaged `J2` against the angle, and the
//! velocity fields of the last turn (Fig. 17).

use super::{WheelResults, WheelSummary};
use crate::bodies::wheel::WheelModel;
use crate::output::plot::{
    line_plot, mesh_color_map_with, mesh_vector_fields, panels, sig, MeshColorMap, MeshOptions,
    MeshVectorField, Panel, Series, SeriesStyle,
};
use crate::run::error::RunError;
use std::path::{Path, PathBuf};

/// One figure to draw: its path once written.
type Job<'a> = Box<dyn FnOnce() -> Result<PathBuf, RunError> + Send + 'a>;

/// Writes the figures into `out`; returns their paths (in a fixed order).
///
/// The figures are independent: they are drawn side by side on the threads of the run's
/// pool (rayon), the largest first (on the paper's wheel drawing them took 0.7 s of a 4 s
/// run on one thread).
///
/// # Errors
/// [`RunError::Output`].
pub fn write(
    out: &Path,
    wm: &WheelModel,
    summary: &WheelSummary,
    r: &WheelResults,
    profile: &RimProfile,
) -> Result<Vec<PathBuf>, RunError> {
    let omega = summary.omega;
    let mut jobs: Vec<Job> = Vec::from(force_figures(out, summary, r));
    jobs.extend(spectrum_figure(out, r, summary, wm.rim.len()));
    jobs.extend(rim_profile_figure(out, omega, profile, rim_beat(wm)));
    jobs.extend(turn_average_maps(out, wm, r, omega));
    // Fig. 17: velocity fields, the largest figure: drawn first.
    let mut first = None;
    if let Some(job) = velocity_fields_figure(out, wm, r) {
        first = Some(jobs.len());
        jobs.push(job);
    }
    draw(jobs, first)
}

/// Draws the figures side by side, `first` first and then the others as listed; returns
/// their paths as listed.
///
/// Each of the pool's threads takes the next job from one list until none is left (a
/// parallel iterator would hand each thread a half of the list, fixed by position, and
/// the two largest figures could fall in one half: on the paper's wheel 0.24 s on one
/// thread against 0.12 s on the other).
fn draw(jobs: Vec<Job>, first: Option<usize>) -> Result<Vec<PathBuf>, RunError> {
    use std::sync::atomic::{AtomicUsize, Ordering};
    use std::sync::Mutex;
    // Drawn in the order (largest first, then as listed), returned as listed.
    let mut order: Vec<usize> = (0..jobs.len()).collect();
    if let Some(k) = first {
        order[..=k].rotate_right(1);
    }
    let mut slots: Vec<Option<Job>> = jobs.into_iter().map(Some).collect();
    let queue: Vec<(usize, Mutex<Option<Job>>)> = order
        .iter()
        .map(|&k| (k, Mutex::new(slots[k].take())))
        .collect();
    let next = AtomicUsize::new(0);
    let drawn: Mutex<Vec<(usize, Result<PathBuf, RunError>)>> = Mutex::new(Vec::new());
    let take = || loop {
        let i = next.fetch_add(1, Ordering::Relaxed);
        let Some((k, job)) = queue.get(i) else {
            return;
        };
        let job = job.lock().ok().and_then(|mut j| j.take());
        if let Some(job) = job {
            let r = job();
            if let Ok(mut d) = drawn.lock() {
                d.push((*k, r));
            }
        }
    };
    let threads = rayon::current_num_threads().clamp(1, queue.len().max(1));
    rayon::scope(|s| {
        for _ in 1..threads {
            s.spawn(|_| take());
        }
        take();
    });
    let mut files = drawn.into_inner().unwrap_or_else(|e| e.into_inner());
    files.sort_by_key(|f| f.0);
    files.into_iter().map(|(_, r)| r).collect()
}

/// Fig. 12, the contact force over the turns, and Fig. 13, a zoom on a quarter of the last
/// turn, in kN.
///
/// Fig. 12 has two panels (issue 48: on one axis from 0 to 850 kN the flatness it is meant
/// to show could not be seen): the whole run, the settling shaded, and the rolling phase
/// alone on an axis about the mean, with the least and the largest force over the turns
/// and their spread in percent of the mean in the title.
fn force_figures<'a>(out: &'a Path, summary: &WheelSummary, r: &WheelResults) -> [Job<'a>; 2] {
    let omega = summary.omega;
    let (t_settle, turn_time) = (r.timeline.t_settle, r.timeline.turn_time);
    let full_turns = r.timeline.full_turns();
    let kn = |f: f64| 1e-3 * f;
    let (mean, fmin, fmax) = (kn(r.forces.mean), kn(r.forces.min), kn(r.forces.max));
    // Fig. 12: force over the turns.
    let (plot_t, plot_f) = &r.forces.plot;
    let turns_axis: Vec<f64> = plot_t.iter().map(|t| (t - t_settle) / turn_time).collect();
    let force_kn: Vec<f64> = plot_f.iter().map(|&f| kn(f)).collect();
    let mean_label = format!("mean over the turns, {} kN", sig(mean, 4));
    let mut p = Panel::new(
        format!(
            "Contact force, omega = {} rad/s ({} km/h)",
            sig(omega, 3),
            sig(summary.speed_km_h, 3)
        ),
        "turns after settling",
        "contact force [kN]",
    );
    p.series.push(Series::new(
        "contact force",
        turns_axis.clone(),
        force_kn.clone(),
        SeriesStyle::Line,
    ));
    p.hlines.push((mean, mean_label.clone()));
    if let Some(&t0) = turns_axis.first() {
        if t0 < 0.0 {
            p.vspans
                .push((t0, 0.0, "settling: the base pressed in".to_string()));
        }
    }
    // The rolling phase about its mean.
    let spread = if mean > 0.0 {
        100.0 * (fmax - fmin) / mean
    } else {
        f64::NAN
    };
    let mut pr = Panel::new(
        format!(
            "Rolling phase: between {} and {} kN, max - min = {} % of the mean",
            sig(fmin, 4),
            sig(fmax, 4),
            sig(spread, 2)
        ),
        "turns after settling",
        "contact force [kN]",
    );
    let (roll_t, roll_f): (Vec<f64>, Vec<f64>) = turns_axis
        .iter()
        .zip(&force_kn)
        .filter(|(t, _)| **t >= 0.0)
        .map(|(&t, &f)| (t, f))
        .unzip();
    // The force averaged over a rim node's passage: what the wheel does turn by turn
    // (a pattern fixed to the mesh shows there), the node-passing ripple out.
    let dt = if roll_t.len() > 1 {
        (roll_t[roll_t.len() - 1] - roll_t[0]) / (roll_t.len() - 1) as f64 * turn_time
    } else {
        0.0
    };
    let node_pass = r.forces.node_passing_hz;
    let window = if dt > 0.0 && node_pass > 0.0 {
        (1.0 / node_pass / dt).round().max(1.0) as usize
    } else {
        1
    };
    let mut smooth = crate::analysis::signal::moving_average(&roll_f, window);
    // Half a window at each end averages fewer samples: left out.
    let cut = (window / 2).min(smooth.len() / 2);
    let n = smooth.len();
    smooth[..cut].fill(f64::NAN);
    smooth[n - cut..].fill(f64::NAN);
    pr.series.push(Series::new(
        "contact force",
        roll_t.clone(),
        roll_f,
        SeriesStyle::Line,
    ));
    if window > 1 {
        pr.series.push(Series::new(
            "mean over a rim node's passage",
            roll_t,
            smooth,
            SeriesStyle::Line,
        ));
    }
    pr.hlines.push((mean, mean_label));
    pr.hlines.push((fmin, String::new()));
    pr.hlines.push((fmax, String::new()));
    let half = (fmax - mean).max(mean - fmin);
    if half.is_finite() && half > 0.0 {
        pr.y_range = Some((mean - 1.6 * half, mean + 1.6 * half));
    }
    pr.note = "Dashed: the mean, and the least and largest force over the turns. Upper \
               panel: the whole run on an axis from zero; lower: the rolling phase on an \
               axis about its mean."
        .into();
    // Fig. 13: a zoom on a quarter of the last turn.
    let z0 = full_turns - 1.0;
    let mut pz = Panel::new(
        "Contact force (zoom on a quarter turn)",
        "turns after settling",
        "contact force [kN]",
    );
    pz.series.push(Series::new(
        "contact force",
        turns_axis,
        force_kn,
        SeriesStyle::Line,
    ));
    pz.x_range = Some((z0, z0 + 0.25));
    [
        Box::new(move || {
            let png = out.join("contact_force.png");
            panels(&png, &[p, pr], 2, 1, (1400, 1000)).map_err(|e| RunError::output(&png, e))?;
            Ok(png)
        }),
        Box::new(move || {
            let png = out.join("contact_force_zoom.png");
            line_plot(&png, &pz, (1400, 700)).map_err(|e| RunError::output(&png, e))?;
            Ok(png)
        }),
    ]
}

/// The amplitude spectrum of the contact force (none without one), with the frequencies
/// the summary names: the node passing and its harmonics, the bounce mode, the rotation's
/// first harmonics, and each classified component at its amplitude.
fn spectrum_figure<'a>(
    out: &'a Path,
    r: &WheelResults,
    summary: &WheelSummary,
    rim_nodes: usize,
) -> Option<Job<'a>> {
    if r.forces.spectrum.frequency_hz.is_empty() {
        return None;
    }
    let h = r.timeline.h;
    let (rot_hz, node_pass_hz) = (r.forces.rotation_hz, r.forces.node_passing_hz);
    let (lo, hi) = (0.5 * rot_hz, (20.0 * node_pass_hz).min(0.5 / h));
    let mut ps = Panel::new(
        "Amplitude spectrum of the contact force (rolling phase; largest peak per log bin)",
        "frequency [Hz]",
        "amplitude [N]",
    );
    ps.x_log = true;
    ps.y_log = true;
    ps.x_range = Some((lo, hi));
    let (f, a) = peak_envelope(
        &r.forces.spectrum.frequency_hz,
        &r.forces.spectrum.amplitude,
        lo,
        hi,
        1200,
    );
    // Five decades below the largest peak.
    let amax = a.iter().cloned().fold(0.0, f64::max);
    let (f, a): (Vec<f64>, Vec<f64>) = f
        .into_iter()
        .zip(a)
        .filter(|(_, x)| *x >= amax * 1e-5)
        .unzip();
    ps.y_range = Some((amax * 1e-5, amax * 2.0));
    ps.series
        .push(Series::new("amplitude", f, a, SeriesStyle::Line));
    // The expected frequencies, one legend entry per family.
    let np_label = node_passing_label(rim_nodes, node_pass_hz, rot_hz);
    for k in 1..=5 {
        let fk = k as f64 * node_pass_hz;
        if fk > hi {
            break;
        }
        ps.vlines.push((fk, np_label.clone()));
    }
    if let Some(fb) = summary.bounce_frequency_hz {
        ps.vlines
            .push((fb, format!("bounce mode, contact held ({} Hz)", sig(fb, 4))));
    }
    let rot_label = format!("rotation ({} Hz) x 1..5", sig(rot_hz, 3));
    for k in 1..=5 {
        ps.vlines.push((k as f64 * rot_hz, rot_label.clone()));
    }
    // The classified components at their amplitude, one marker series per kind.
    use crate::analysis::components::ComponentKind;
    type IsKind = fn(&ComponentKind) -> bool;
    let kinds: [(&str, IsKind); 4] = [
        ("components: node passing", |k| {
            matches!(k, ComponentKind::NodePassing { .. })
        }),
        ("components: mode (bounce)", |k| {
            matches!(k, ComponentKind::Mode { .. })
        }),
        ("components: locked to the rotation", |k| {
            matches!(k, ComponentKind::Locked { .. })
        }),
        ("components: unclassified", |k| {
            matches!(k, ComponentKind::Unclassified)
        }),
    ];
    for (label, is) in kinds {
        let (cf, ca): (Vec<f64>, Vec<f64>) = summary
            .spectral_components
            .iter()
            .filter(|c| is(&c.kind))
            .map(|c| (c.hz, c.amplitude))
            .unzip();
        if !cf.is_empty() {
            ps.series
                .push(Series::new(label, cf, ca, SeriesStyle::Markers));
        }
    }
    ps.note = "Markers: the components of summary.json's spectral_components (frequency, \
               amplitude, kind); dashed lines: where the node passing, the bounce mode and \
               the rotation's harmonics are expected."
        .into();
    Some(Box::new(move || {
        let png = out.join("spectrum.png");
        line_plot(&png, &ps, (1400, 700)).map_err(|e| RunError::output(&png, e))?;
        Ok(png)
    }))
}

/// The legend of the node passing's lines: labelled with the count per turn that gives its
/// frequency, `f / f_rot` (issue 48: a moving zone's pitch, 4608 per turn, on a rim of 426
/// nodes was labelled "426 per turn (53144 Hz)"), said to be the zone's pitch when it is not
/// the rim's node count.
fn node_passing_label(rim_nodes: usize, node_pass_hz: f64, rot_hz: f64) -> String {
    let per_turn = if rot_hz > 0.0 {
        (node_pass_hz / rot_hz).round() as usize
    } else {
        rim_nodes
    };
    let hz = sig(node_pass_hz, 4);
    if per_turn == rim_nodes {
        format!("node passing, {per_turn} per turn ({hz} Hz) x 1..5")
    } else {
        format!("node passing, {per_turn} per turn: the zone's pitch ({hz} Hz) x 1..5")
    }
}

/// The rim profile of the turn-averaged J2 against the angle, as the departure from its
/// mean (none without a profile).
fn rim_profile_figure<'a>(
    out: &'a Path,
    omega: f64,
    profile: &RimProfile,
    beat: Option<(usize, usize)>,
) -> Option<Job<'a>> {
    // The rim profile of the turn-averaged J2 and von Mises: at the rim nodes (recovered
    // from the elements round each), against the angle (where a corrugation pattern would
    // show).
    let (angles, j2_rim) = (&profile.angles_deg, &profile.j2_mpa2);
    if angles.is_empty() {
        return None;
    }
    // Drawn as the departure from the mean, in percent: in steady rolling every rim
    // point passes through the same history, so a flat line is the wheel's answer and
    // what departs from it reads against its size.
    let m = j2_rim.iter().sum::<f64>() / j2_rim.len() as f64;
    let mut pr = Panel::new(
        format!(
            "Turn-averaged J2 at the rim nodes, omega = {} rad/s ({} rim nodes; mean {} MPa²)",
            sig(omega, 3),
            angles.len(),
            sig(m, 4)
        ),
        "angle of the rim node [deg]",
        "J2 / mean - 1 [%]",
    );
    pr.series.push(Series::new(
        "J2, turn average",
        angles.clone(),
        // A run stopped before its turn average began has J2 = 0 everywhere: no
        // departure to draw.
        j2_rim
            .iter()
            .map(|j| if m > 0.0 { 100.0 * (j / m - 1.0) } else { 0.0 })
            .collect(),
        SeriesStyle::Line,
    ));
    pr.hlines.push((0.0, "the mean".to_string()));
    pr.x_range = Some((-180.0, 180.0));
    // The pattern's count per turn, and what it is.
    let dev: Vec<f64> = j2_rim.iter().map(|j| j - m).collect();
    if let Some(k) = dominant_harmonic(angles, &dev) {
        let spacing = 360.0 / k as f64;
        pr.note = match beat {
            Some((rim, inner)) if rim - inner == k => format!(
                "The pattern repeats {k} times per turn (every {spacing:.1} deg): it is the \
                 mesh's, not the rolling's. The triangles under the rim join its {rim} nodes \
                 to the {inner} of the next ring, which come into line {k} = {rim} - {inner} \
                 times per turn; in steady rolling every rim point passes through the same \
                 loading, so the wheel's own answer is a flat line."
            ),
            _ => format!(
                "The strongest pattern repeats {k} times per turn (every {spacing:.1} deg). In \
                 steady rolling every rim point passes through the same loading, so the \
                 wheel's own answer is a flat line: a pattern fixed to the rim's angle belongs \
                 to the mesh unless it stays when the mesh is refined."
            ),
        };
    }
    Some(Box::new(move || {
        let png = out.join("j2_rim_profile.png");
        line_plot(&png, &pr, (1400, 600)).map_err(|e| RunError::output(&png, e))?;
        Ok(png)
    }))
}

/// Figs. 14/16: the maps of the turn-averaged J2 and von Mises (none with a moving zone:
/// module docs of [`crate::kinds::wheel::run`]).
fn turn_average_maps<'a>(
    out: &'a Path,
    wm: &'a WheelModel,
    r: &'a WheelResults,
    omega: f64,
) -> Vec<Job<'a>> {
    let maps = if r.fields.j2_mpa2.is_empty() {
        Vec::new()
    } else {
        vec![
            (
                "j2_turn_average.png",
                &r.fields.j2_mpa2,
                "J2 [MPa²]",
                "J2 averaged over one full turn",
            ),
            (
                "von_mises_turn_average.png",
                &r.fields.von_mises_mpa,
                "von Mises [MPa]",
                "von Mises stress averaged over one full turn",
            ),
        ]
    };
    let mut jobs: Vec<Job<'a>> = Vec::new();
    for (name, vals, label, title) in maps {
        jobs.push(Box::new(move || {
            let png = out.join(name);
            // The point support at the axle concentrates the reaction in its few elements;
            // the colour scale stops at the 97th percentile so that the rim shows.
            let top = percentile(vals, 0.97);
            let vmax = vals.iter().cloned().fold(0.0, f64::max);
            let clipped = vmax > 1.5 * top;
            let opts = MeshOptions {
                value_range: clipped.then_some((0.0, top)),
                ..Default::default()
            };
            let title = format!("{title}, {} rad/s", sig(omega, 3));
            let xy = planar(&wm.mesh);
            let label = label.to_string();
            let note = if clipped {
                format!(
                    "Colour scale clipped at the 97th percentile of the elements, {} \
                     ({:.0}% of the maximum {}, in the few elements round the axle, \
                     where the support concentrates the reaction): larger values are drawn \
                     in the top colour (the triangle on the colour bar), so that the rim shows.",
                    sig(top, 3),
                    100.0 * top / vmax,
                    sig(vmax, 3)
                )
            } else {
                String::new()
            };
            mesh_color_map_with(
                &png,
                &MeshColorMap {
                    points: &xy,
                    triangles: &wm.triangles,
                    cell_values: vals,
                    title,
                    colorbar_label: label,
                    length_unit_scale: 100.0,
                    length_unit: "cm".into(),
                    note,
                },
                (1100, 1000),
                &opts,
            )
            .map_err(|e| RunError::output(&png, e))?;
            Ok(png)
        }));
    }
    jobs
}

/// The nodes of the planar `mesh` as the plots take them, `[x, y]` each.
fn planar(mesh: &crate::mesh::Mesh) -> Vec<[f64; 2]> {
    mesh.points().map(|p| [p[0], p[1]]).collect()
}

/// Fig. 17: the velocity fields of the last turn (none without snapshots).
fn velocity_fields_figure<'a>(
    out: &'a Path,
    wm: &'a WheelModel,
    r: &'a WheelResults,
) -> Option<Job<'a>> {
    if r.snapshots.v.is_empty() {
        return None;
    }
    let base = wm.base();
    Some(Box::new(move || {
        let vecs: Vec<Vec<[f64; 2]>> = r
            .snapshots
            .v
            .iter()
            .map(|v| v.chunks(2).map(|c| [c[0], c[1]]).collect())
            .collect();
        let xy = planar(&wm.mesh);
        // The base at each instant: the line at `radius - flattening` from the axle,
        // normal to the direction (sin a, -cos a) of the base angle a.
        let base_line = |t: f64| -> [[f64; 2]; 2] {
            let a = base.angle(t);
            let (ex, ey) = (a.sin(), -a.cos());
            let rho = base.radius - base.flattening.at(t);
            let (cx, cy) = (base.centre[0] + rho * ex, base.centre[1] + rho * ey);
            let l = 0.45 * base.radius;
            [[cx - l * ey, cy + l * ex], [cx + l * ey, cy - l * ex]]
        };
        let angle = "The base angle is measured from the downward vertical (0 deg: below the \
                     axle), anticlockwise: the base turns about the wheel at omega in the \
                     wheel's frame.";
        let arrows = "Arrows: the velocity at evenly spread nodes, centred on them, one scale \
                      for all panels.";
        let note = if wm.zone.is_none() {
            format!("The base (red line) is drawn where it is at each instant. {angle} {arrows}")
        } else {
            format!("{angle} Each panel is drawn in the zone's frame. {arrows}")
        };
        let frames: Vec<MeshVectorField> = vecs
            .iter()
            .zip(&r.snapshots.t)
            .map(|(v, t)| MeshVectorField {
                points: &xy,
                triangles: &wm.triangles,
                vectors: v,
                title: if wm.zone.is_some() {
                    // The zone's frame turns with the base, sector by sector.
                    format!(
                        "base at {:.0} deg, drawn in the zone's frame",
                        base.angle(*t).to_degrees().rem_euclid(360.0)
                    )
                } else {
                    format!(
                        "base at {:.0} deg",
                        base.angle(*t).to_degrees().rem_euclid(360.0)
                    )
                },
                colorbar_label: "velocity in the wheel's frame [m/s]".into(),
                length_unit_scale: 100.0,
                length_unit: "cm".into(),
                // The zone's frame turns with the base: the base is not drawn there.
                overlay: if wm.zone.is_none() {
                    vec![base_line(*t)]
                } else {
                    Vec::new()
                },
                note: note.clone(),
            })
            .collect();
        let png = out.join("velocity_fields.png");
        mesh_vector_fields(&png, &frames, 4, (1800, 1000))
            .map_err(|e| RunError::output(&png, e))?;
        Ok(png)
    }))
}

/// The turn-averaged J2 and von Mises at the rim nodes (`rim_profile`: area-weighted over
/// the elements round each rim node).
#[derive(Debug, Clone, Default)]
pub struct RimProfile {
    /// The rim nodes' angles, degrees in (-180, 180], increasing.
    pub angles_deg: Vec<f64>,
    /// J2 at each, MPa^2.
    pub j2_mpa2: Vec<f64>,
    /// von Mises at each, MPa.
    pub von_mises_mpa: Vec<f64>,
}

impl RimProfile {
    /// The profile of the run's turn averages (empty without them: a moving zone).
    pub fn of(wm: &WheelModel, r: &WheelResults) -> Self {
        rim_profile(wm, &r.fields.j2_mpa2, &r.fields.von_mises_mpa)
    }
}

/// Writes `j2_rim_profile.csv` (`angle_deg, j2_mpa2, von_mises_mpa` at the rim nodes, see
/// `rim_profile`) into `out`, plots or not; none without a turn average (a moving zone).
///
/// # Errors
/// [`RunError::Output`].
pub fn write_rim_profile(out: &Path, p: &RimProfile) -> Result<Option<PathBuf>, RunError> {
    let (angles, j2, vm) = (&p.angles_deg, &p.j2_mpa2, &p.von_mises_mpa);
    if angles.is_empty() {
        return Ok(None);
    }
    let csv = out.join("j2_rim_profile.csv");
    let mut body = crate::output::csv::record(["angle_deg", "j2_mpa2", "von_mises_mpa"]);
    for ((a, j), v) in angles.iter().zip(j2).zip(vm) {
        crate::output::csv::push_record(&mut body, [a, j, v].map(|x| format!("{x:e}")));
    }
    crate::output::files::write_atomic(&csv, body.as_bytes())
        .map_err(|e| RunError::output(&csv, e))?;
    Ok(Some(csv))
}

/// The rim nodes, sorted by their angle (degrees, in (-180, 180]), with the area-weighted
/// mean of `j2` and of `vm` over the elements round each (a nodal recovery: one element's
/// value depends on its shape, and the rim's triangles alternate, outward and inward).
fn rim_profile(wm: &WheelModel, j2: &[f64], vm: &[f64]) -> RimProfile {
    let mut out = RimProfile::default();
    // No turn average (a moving zone): no profile.
    if j2.is_empty() {
        return out;
    }
    let mut slot = vec![usize::MAX; wm.mesh.n_nodes()];
    for (k, &n) in wm.rim.iter().enumerate() {
        slot[n] = k;
    }
    // (sum of area, area * j2, area * vm) per rim node.
    let mut acc = vec![(0.0, 0.0, 0.0); wm.rim.len()];
    let p = |n: usize| wm.mesh.point(n);
    for (e, t) in wm.triangles.iter().enumerate() {
        let (a, b, c) = (p(t[0]), p(t[1]), p(t[2]));
        let area = 0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1])).abs();
        for &n in t {
            if slot[n] != usize::MAX {
                let s = &mut acc[slot[n]];
                s.0 += area;
                s.1 += area * j2[e];
                s.2 += area * vm[e];
            }
        }
    }
    let mut rows: Vec<(f64, f64, f64)> = wm
        .rim
        .iter()
        .zip(&acc)
        .filter(|(_, s)| s.0 > 0.0)
        .map(|(&n, s)| (p(n)[1].atan2(p(n)[0]).to_degrees(), s.1 / s.0, s.2 / s.0))
        .collect();
    rows.sort_by(|a, b| a.0.total_cmp(&b.0));
    for (a, j, v) in rows {
        out.angles_deg.push(a);
        out.j2_mpa2.push(j);
        out.von_mises_mpa.push(v);
    }
    out
}

/// The whole number `k` of cycles per turn (1 up to half the samples) with the largest
/// Fourier amplitude of `v` sampled at `angles_deg` round the rim; `None` for a flat `v`.
fn dominant_harmonic(angles_deg: &[f64], v: &[f64]) -> Option<usize> {
    let n = v.len();
    let mut best: Option<(usize, f64)> = None;
    for k in 1..=n / 2 {
        let (mut c, mut s) = (0.0, 0.0);
        for (&a, &x) in angles_deg.iter().zip(v) {
            let t = k as f64 * a.to_radians();
            c += x * t.cos();
            s += x * t.sin();
        }
        let amp = c.hypot(s);
        if amp > best.map_or(0.0, |b| b.1) {
            best = Some((k, amp));
        }
    }
    best.map(|b| b.0)
}

/// The node counts of the rim and of the ring of nodes next inside it, when the mesh's
/// nodes lie on rings (the graded disk); `None` otherwise.
fn rim_beat(wm: &WheelModel) -> Option<(usize, usize)> {
    let radius = |n: usize| {
        let p = wm.mesh.point(n);
        p[0].hypot(p[1])
    };
    let r_rim = wm.rim.iter().map(|&n| radius(n)).fold(0.0, f64::max);
    let tol = 1e-9 * r_rim;
    let below: Vec<f64> = (0..wm.mesh.n_nodes())
        .map(radius)
        .filter(|&r| r < r_rim - 1e3 * tol)
        .collect();
    let r_in = below.iter().cloned().fold(0.0, f64::max);
    let inner = below
        .iter()
        .filter(|&&r| (r - r_in).abs() <= 1e3 * tol)
        .count();
    // A ring: several nodes on one circle, fewer than the rim.
    (inner >= 3 && inner < wm.rim.len()).then_some((wm.rim.len(), inner))
}

fn percentile(v: &[f64], q: f64) -> f64 {
    let mut s: Vec<f64> = v.iter().cloned().filter(|x| x.is_finite()).collect();
    if s.is_empty() {
        return 0.0;
    }
    s.sort_by(f64::total_cmp);
    s[((s.len() - 1) as f64 * q).round() as usize]
}

/// The largest amplitude in each of `bins` log-spaced frequency bins over `[lo, hi]` (a
/// peak envelope that keeps every peak of a dense spectrum drawable).
fn peak_envelope(f: &[f64], a: &[f64], lo: f64, hi: f64, bins: usize) -> (Vec<f64>, Vec<f64>) {
    let (llo, lhi) = (lo.max(f64::MIN_POSITIVE).ln(), hi.ln());
    let mut best: Vec<Option<(f64, f64)>> = vec![None; bins];
    for (&fi, &ai) in f.iter().zip(a) {
        if fi < lo || fi > hi || ai.is_nan() || ai <= 0.0 {
            continue;
        }
        let k = (((fi.ln() - llo) / (lhi - llo)) * bins as f64)
            .floor()
            .clamp(0.0, (bins - 1) as f64) as usize;
        if best[k].is_none_or(|(_, b)| ai > b) {
            best[k] = Some((fi, ai));
        }
    }
    best.into_iter().flatten().unzip()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bodies::wheel::WheelSpec;
    use crate::mesh::generators::{disk_graded, DiskOptions};
    use std::f64::consts::PI;

    /// The rim profile has one entry per rim node, sorted by angle; a field constant over
    /// the mesh is recovered exactly, and a field that is `1` on the elements touching one
    /// rim node and `0` elsewhere gives `1` at that node and `0` two rim nodes away.
    #[test]
    fn rim_profile_recovers_nodal_values() {
        let wm = WheelModel::new(
            disk_graded(0.1, 72, DiskOptions::default()).unwrap(),
            WheelSpec::paper(),
        )
        .unwrap();
        let ne = wm.triangles.len();
        let p = rim_profile(&wm, &vec![3.0; ne], &vec![2.0; ne]);
        let (angles, j2, vm) = (p.angles_deg, p.j2_mpa2, p.von_mises_mpa);
        assert_eq!(angles.len(), wm.rim.len());
        assert!(angles.windows(2).all(|w| w[0] < w[1]));
        assert!(j2.iter().all(|&v| (v - 3.0).abs() < 1e-12));
        assert!(vm.iter().all(|&v| (v - 2.0).abs() < 1e-12));
        let node = wm.rim[5];
        let touch: Vec<f64> = wm
            .triangles
            .iter()
            .map(|t| if t.contains(&node) { 1.0 } else { 0.0 })
            .collect();
        let p = rim_profile(&wm, &touch, &touch);
        let (angles, j2) = (p.angles_deg, p.j2_mpa2);
        let p = wm.mesh.point(node);
        let a = p[1].atan2(p[0]).to_degrees();
        let k = angles.iter().position(|&x| (x - a).abs() < 1e-9).unwrap();
        assert!((j2[k] - 1.0).abs() < 1e-12);
        let n = angles.len();
        // Two rim nodes away, nothing of it is left.
        assert_eq!(j2[(k + 2) % n], 0.0);
        assert_eq!(j2[(k + n - 2) % n], 0.0);
    }

    /// Issue 48: `wheel-realistic`'s spectrum said "426 per turn (53144 Hz)"; 53,144 Hz at
    /// omega = 72.46 rad/s is 4,608 per turn, the zone's pitch.
    #[test]
    fn issue_48_node_passing_label_names_the_count_of_its_frequency() {
        let omega = 72.463_768_115_942_03;
        let rot = omega / (2.0 * PI);
        let label = node_passing_label(426, 4608.0 * rot, rot);
        assert!(label.contains("4608 per turn: the zone's pitch"), "{label}");
        assert!(label.contains("53140 Hz"), "{label}");
        let label = node_passing_label(288, 288.0 * 300.0 / (2.0 * PI), 300.0 / (2.0 * PI));
        assert_eq!(label, "node passing, 288 per turn (13750 Hz) x 1..5");
    }
}
