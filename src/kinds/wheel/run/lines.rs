//! The wheel run's screen summary.

use super::*;

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
