//! The wheel run's summary from its observers, the step's adequacy and the warnings.

use super::*;

/// The key figures of a run.
pub(super) fn summarise(
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
        large_deformation: None,
    }
}

/// The largest value, NaN (null in JSON) when there is none (no turn average with a moving
/// zone).
pub(super) fn max_or_nan(v: &[f64]) -> f64 {
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
pub(super) fn step_adequacy(
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
                "run `{}`: the spin at `rolling.omega` = {} rad/s stretches the rim by {:.3e} of its radius (rim speed {:.4e} m/s): the model is linear, for strains up to {MAX_SPIN_STRETCH}; lower `rolling.omega` or `wheel.radius` (the stretch is of order `material.density` omega^2 R^2 / `material.young` = {:.3e} / {:.3e})",
                run.label,
                ws.spec.omega,
                stretch,
                ws.spec.omega.abs() * wm.spec.radius,
                wm.spec.material.density * (ws.spec.omega * wm.spec.radius).powi(2),
                wm.spec.material.young,
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

pub(super) fn warnings_before(
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
