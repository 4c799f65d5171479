//! The wheel run's screen summary.

use super::*;
use crate::output::terminal::{grouped, quantity};

/// Screen lines of a summary.
pub fn summary_lines(s: &WheelSummary) -> Vec<String> {
    let mut lines = base_lines(s);
    if let Some(l) = &s.large_deformation {
        lines.push(format!(
            "large deformation ({:?}): {} iterations ({:.2} per step, at most {} in one solve, {} unconverged, tolerance {:e}); at the end the largest Green strain {:.3e} (the linear strain of the same displacement {:.3e}), stored energy {:.4e} J (the linear reading {:.4e} J); the largest rotation against the frame {:.3e} rad",
            l.law,
            l.iterations,
            l.iterations_per_step,
            l.max_in_one_solve,
            l.unconverged,
            l.tolerance,
            l.max_green_strain,
            l.max_linear_strain,
            l.stored_energy_j,
            l.linear_reading_energy_j,
            l.max_rotation_rad,
        ));
    }
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
            "traction (mu = {}, creepage {:.3} %): Q = {}, P = {}, Q/(mu P) = {:.4} (Carter {:.4}); {:.2} nodes in stick, {:.2} in slip; stick half-width {:.3} mm (Hertz a = {:.3} mm); friction energy {:.3e} J",
            t.friction,
            t.creepage * 100.0,
            quantity(t.traction, "N"),
            quantity(t.normal, "N"),
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

/// The lines every wheel run prints: forces in kN (or MN), lengths in mm, frequencies in
/// Hz or kHz, times in us or ms ([`quantity`]); every number's full precision is in
/// `summary.json`.
fn base_lines(s: &WheelSummary) -> Vec<String> {
    let ripple = if s.mean_contact_force.abs() > 0.0 {
        format!(
            " (max - min {:.2} % of the mean)",
            100.0 * (s.max_contact_force - s.min_contact_force) / s.mean_contact_force
        )
    } else {
        String::new()
    };
    vec![
        format!(
            "omega = {} rad/s ({:.0} km/h), {} dofs, {} steps of {} in {} ({}/step)",
            (s.omega * 1e4).round() / 1e4,
            s.speed_km_h,
            grouped(s.dofs as f64),
            grouped(s.steps as f64),
            quantity(s.h, "s"),
            quantity(s.wall_time_s, "s"),
            quantity(s.time_per_step_us * 1e-6, "s")
        ),
        format!(
            "rolling contact force: mean {}, min {}, max {}{ripple}; {:.2} nodes in contact on average",
            quantity(s.mean_contact_force, "N"),
            quantity(s.min_contact_force, "N"),
            quantity(s.max_contact_force, "N"),
            s.mean_nodes_in_contact
        ),
        match s.requested_load_n {
            Some(p) => format!(
                "flattening {}, found for the load {} (static); Hertz's patch spans {:.1} rim pitches",
                quantity(s.flattening_m, "m"),
                quantity(p, "N"),
                s.patch_rim_pitches
            ),
            None => format!(
                "flattening {}; Hertz's patch spans {:.1} rim pitches",
                quantity(s.flattening_m, "m"),
                s.patch_rim_pitches
            ),
        },
        format!(
            "oscillations per turn {:?}; dominant frequency {} ({} cycles per turn); node passing {}",
            s.oscillations_per_turn,
            s.dominant_frequency_hz.map(|f| quantity(f, "Hz")).unwrap_or_else(|| "-".into()),
            s.dominant_cycles_per_turn.map(|f| format!("{f:.2}")).unwrap_or_else(|| "-".into()),
            quantity(s.node_passing_frequency_hz, "Hz")
        ),
        format!(
            "{}; max penetration {}; energy {:.6} J after settling, {:.6} J at the end",
            if s.max_j2_turn_average_mpa2.is_nan() {
                format!("no turn averages ({} relocations of the refined zone)", s.relocations)
            } else {
                format!(
                    "turn-averaged J2 max {:.4e} MPa^2, von Mises max {:.1} MPa",
                    s.max_j2_turn_average_mpa2, s.max_von_mises_turn_average_mpa
                )
            },
            quantity(s.max_penetration, "m"),
            Sig(s.energy_after_settling),
            Sig(s.energy_final)
        ),
        format!(
            "spectral components (frequency, cycles per turn, amplitude, kind): {}",
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
                .map(|f| quantity(f, "Hz"))
                .unwrap_or_else(|| "-".into()),
            s.mesh_min_angle_deg,
            s.mesh_max_aspect,
            s.mesh_symmetry_order
        ),
    ]
}

/// An energy with six significant digits (a run's energy drifts in its fifth).
struct Sig(f64);

impl std::fmt::Display for Sig {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let v = self.0;
        if !v.is_finite() || v == 0.0 || !(1e-3..1e9).contains(&v.abs()) {
            return write!(f, "{v:.5e}");
        }
        let d = v.abs().log10().floor() as i32;
        let decimals = (5 - d).max(0) as usize;
        write!(f, "{v:.decimals$}")
    }
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
        "{}, {:.2}, {}, {kind}",
        quantity(c.hz, "Hz"),
        c.cycles_per_turn,
        quantity(c.amplitude, "N")
    )
}
