//! The wheel's load as a force (`wheel.load`, N): the flattening that carries it, found by a
//! static contact solve, and what the rim's pitch makes of the patch it gives.
//!
//! The run presses the wheel kinematically, to the flattening `d` of the paper (the base at
//! `R - d` from the axle, [`crate::contact::obstacle::RotatingLine`]). Given a load `P`
//! instead, [`flattening_for_load`] finds the `d` at which the spinning wheel, pressed on the
//! base at its starting angle, carries `P` in static equilibrium:
//! `K_eff u = K_eff u_c + sum_i lambda_i n` with the rim nodes on the base
//! ([`crate::contact::statics`], frictionless, node gaps), `K_eff` the rotating frame's
//! effective stiffness and `u_c` the centrifugal expansion ([`crate::bodies::wheel`]): the
//! equilibrium about which the rolling run oscillates. The contact force `F(d)` is
//! increasing and piecewise linear in `d` (linear between changes of the active set);
//! `F(d) = P` is solved by secants safeguarded by bisection, to 1e-9 of `P`.

use crate::bodies::wheel::{Support, WheelModel};
use crate::contact::obstacle::Obstacle;
use crate::contact::statics;
use std::f64::consts::PI;

/// The static contact of the wheel pressed to the flattening `depth` (m) on its base at its
/// starting angle: the total force (N) and the active rim nodes with their forces.
///
/// # Errors
/// A message when the stiffness with the supports is singular.
pub fn static_contact(wm: &WheelModel, depth: f64) -> Result<(f64, Vec<(usize, f64)>), String> {
    let sol = static_solution(wm, depth)?;
    Ok((sol.active.iter().map(|a| a.1).sum(), sol.active))
}

/// The static contact of [`static_contact`] in full: the displacement (from the unloaded,
/// unspun reference) and the active rim nodes with their forces.
///
/// # Errors
/// A message when the stiffness with the supports is singular.
pub fn static_solution(wm: &WheelModel, depth: f64) -> Result<statics::StaticContact, String> {
    // The base at its starting angle (where a refined zone is centred; the zone's frame
    // keeps the contact there), pressed to `depth`.
    let mut base = wm.base();
    base.flattening.depth = depth;
    base.flattening.settle_time = 0.0;
    let t = 0.0;
    let hs = base.half_space(t, [0.0; 3]);
    let mut fixed = wm.fixed_dofs.clone();
    if matches!(wm.spec.support, Support::CentrePinned) {
        // The pinned wheel's rigid rotation: held by the tangential dof of the rim node
        // opposite the base (no reaction: the contact forces pass near the axle).
        let e = base.direction(t);
        let far = |i: usize| {
            let p = wm.mesh.point(i);
            -(p[0] * e[0] + p[1] * e[1])
        };
        if let Some(&top) = wm.rim.iter().max_by(|&&a, &&b| far(a).total_cmp(&far(b))) {
            fixed.push(if e[1].abs() > e[0].abs() {
                2 * top
            } else {
                2 * top + 1
            });
        }
    }
    let x = wm.mesh.reference_positions();
    let sol = statics::solve(
        wm.model.pattern(),
        &wm.model.k,
        &fixed,
        &wm.load,
        &x,
        &wm.rim,
        hs,
    )
    .map_err(|e| format!("the static contact solve for wheel.load: {e}"))?;
    Ok(sol)
}

/// The flattening found for a load, and the static patch it gives.
#[derive(Debug, Clone, PartialEq)]
pub struct LoadFlattening {
    /// The flattening, m.
    pub depth: f64,
    /// The static contact force at that flattening, N (the load to 1e-9).
    pub force: f64,
    /// Rim nodes carrying a force in the static patch.
    pub nodes_in_contact: usize,
    /// Static solves made.
    pub solves: usize,
}

/// The flattening at which the wheel carries `load` (N) statically (module docs).
///
/// # Errors
/// A message when the static solve fails or the load cannot be reached with a flattening
/// below a tenth of the radius.
pub fn flattening_for_load(wm: &WheelModel, load: f64) -> Result<LoadFlattening, String> {
    let limit = 0.1 * wm.spec.radius;
    let mut solves = 0;
    let mut force = |d: f64| {
        solves += 1;
        static_contact(wm, d)
    };
    // Bracket [lo, hi] with F(lo) < P <= F(hi), from 0 (no force) upwards.
    let (mut lo, mut f_lo) = (0.0, 0.0);
    let mut d = 1e-5 * wm.spec.radius;
    let (mut hi, mut f_hi) = loop {
        let (f, _) = force(d)?;
        if f >= load {
            break (d, f);
        }
        (lo, f_lo) = (d, f);
        if d >= limit {
            return Err(format!(
                "wheel.load = {load} N: the wheel carries only {f:.4e} N at a flattening of a tenth of its radius ({limit} m); give a smaller load"
            ));
        }
        // The force grows about linearly with the flattening: aim past the load.
        d = if f > 0.0 {
            (d * 1.2 * load / f).min(limit)
        } else {
            (4.0 * d).min(limit)
        };
    };
    let tol = 1e-9 * load;
    let mut best = (hi, f_hi);
    for _ in 0..200 {
        if (best.1 - load).abs() <= tol {
            break;
        }
        // Secant between the bracket's ends, bisection when it would land near an end.
        let secant = lo + (load - f_lo) * (hi - lo) / (f_hi - f_lo);
        let w = hi - lo;
        let d = if secant > lo + 0.01 * w && secant < hi - 0.01 * w {
            secant
        } else {
            0.5 * (lo + hi)
        };
        let (f, _) = force(d)?;
        if (f - load).abs() < (best.1 - load).abs() {
            best = (d, f);
        }
        if f < load {
            (lo, f_lo) = (d, f);
        } else {
            (hi, f_hi) = (d, f);
        }
        if hi - lo <= 1e-15 * hi {
            break;
        }
    }
    let (_, active) = force(best.0)?;
    Ok(LoadFlattening {
        depth: best.0,
        force: best.1,
        nodes_in_contact: active.iter().filter(|a| a.1 > 0.0).count(),
        solves,
    })
}

/// Hertz's half-width of the contact of a cylinder of radius `radius` (m) on a rigid plane
/// under `force` (N) over `thickness` (m): `a = sqrt(4 P' R / (pi E*))` with
/// `P' = force / thickness` and `E* = E` in plane stress, `E / (1 - nu^2)` in plane strain
/// (the rigid base's share is nil). Johnson, *Contact Mechanics* (1985), Eq. 4.43.
pub fn hertz_half_width(wm: &WheelModel, force: f64) -> f64 {
    let e = wm.spec.material.young;
    let e_star = match wm.spec.plane {
        crate::material::PlaneModel::Stress => e,
        crate::material::PlaneModel::Strain => {
            e / (1.0 - wm.spec.material.poisson * wm.spec.material.poisson)
        }
    };
    (4.0 * force / wm.spec.thickness * wm.spec.radius / (PI * e_star)).sqrt()
}

/// Fewest rim pitches across Hertz's patch (`2 a` over the rim's pitch, about the rim nodes
/// in it) below which a run is warned about: the patch is then resolved by a few nodes, and
/// the contact force jumps as each one enters and leaves (a 0.46 m Gmsh wheel ran with 1.8
/// nodes in contact and no word). Six: `wheel.toml` (288 rim nodes, 6.5 pitches, 6.7 nodes
/// in contact on average) is mesh-converged in its mean force to 0.7% with a ripple of 1.5%;
/// its 144-node rim (3.2 pitches) is 0.7% off with a ripple of 7%.
pub const MIN_PATCH_NODES: f64 = 6.0;

/// The warning for a rim too coarse for the contact patch at `force` (N): Hertz's width
/// `2 a` over the rim's pitch under the contact below [`MIN_PATCH_NODES`]; `None` when the
/// rim is fine enough.
pub fn coarse_rim_warning(wm: &WheelModel, force: f64, label: &str) -> Option<String> {
    if !(force.is_finite() && force > 0.0) {
        return None;
    }
    let a = hertz_half_width(wm, force);
    let pitch = 2.0 * PI * wm.spec.radius / wm.passing_nodes() as f64;
    let nodes = 2.0 * a / pitch;
    (nodes < MIN_PATCH_NODES).then(|| {
        let needed = (MIN_PATCH_NODES * wm.passing_nodes() as f64 / nodes).ceil();
        format!(
            "{label}: the rim is coarse for the contact patch: Hertz's width 2a = {:.3} mm at {:.4e} N spans {nodes:.1} rim pitches ({:.3} mm), fewer than {MIN_PATCH_NODES}: the force will jump as nodes enter and leave; refine the rim (about {needed} rim nodes, or a refined zone, wheel.zone_rim_nodes)",
            2e3 * a,
            force,
            1e3 * pitch
        )
    })
}
