//! `[rail]` of a `rolling3d` scenario: the elastic rail's keys, checked against the wheel's
//! ([`crate::bodies::rolling3d::RailBlock`]).

use super::{RawRail, RawRolling, RawWheel};
use crate::bodies::rolling3d::{RailBlock, RailProfile, SliceZone};
use crate::scenario::{Ctx, ScenarioError};

/// `[rail]`: the elastic rail in place of the rigid base, checked against the wheel's
/// other keys (the rail meets the wheel alone, without a twin, a moving zone or spin).
pub(super) fn rail_block(
    cx: &Ctx,
    rail: &RawRail,
    w: &RawWheel,
    r: &RawRolling,
    (radius, thickness, sectors): (f64, f64, usize),
    (depth_mm, crown, zone): (f64, Option<f64>, Option<SliceZone>),
) -> Result<RailBlock, ScenarioError> {
    let refuse = |key: &str, value: String, why: &str| {
        Err(cx.invalid(
            key,
            value,
            &format!("{why} with an elastic rail ([rail]; remove it, or the [rail] table for the rigid base)"),
        ))
    };
    if let Some(c) = r.coupling.as_deref().filter(|c| *c != "coupled") {
        return refuse(
            "rolling.coupling",
            format!("\"{c}\""),
            "must be \"coupled\": the rail is the wheel's other body, no twin",
        );
    }
    if w.cyclic_columns == Some(true) {
        return refuse("wheel.cyclic_columns", "true".into(), "the columns of the rail's dofs do not repeat round the axle: the turned columns are not built");
    }
    let profile = match rail.profile.as_deref() {
        None | Some("bar") => {
            if let Some(i) = rail.inclination {
                return Err(cx.invalid("rail.inclination", i, "an inclination is the UIC60 rail's: set rail.profile = \"uic60\", or remove it for the bar"));
            }
            RailProfile::Bar
        }
        Some("uic60") => {
            for (key, v) in [("rail.height_mm", rail.height_mm), ("rail.width_mm", rail.width_mm), ("rail.fine_depth_mm", rail.fine_depth_mm)] {
                if let Some(v) = v {
                    return Err(cx.invalid(key, v, "the UIC60 section has its own: remove the key, or set rail.profile = \"bar\" for a bar of that size"));
                }
            }
            RailProfile::Uic60 {
                inclination: cx.within("rail.inclination", rail.inclination.unwrap_or(0.0), -0.2, 0.2)?,
            }
        }
        Some(other) => {
            return Err(cx.invalid(
                "rail.profile",
                format!("\"{other}\""),
                "\"bar\" (a rectangular bar with the base's crown) or \"uic60\" (the 60E1 section, its head's crest radius 0.3 m)",
            ))
        }
    };
    if let (RailProfile::Uic60 { inclination }, Some(phi)) =
        (profile, r.spin_creepage.filter(|p| *p != 0.0))
    {
        if inclination != 0.0 {
            return refuse(
                "rolling.spin_creepage",
                phi.to_string(),
                "a spin on an inclined rail is not built: the patch sits off the wheel's mid-plane, about which the spin turns (set rail.inclination = 0)",
            );
        }
    }
    let uic60 = matches!(profile, RailProfile::Uic60 { .. });
    let mm = |key: &str, v: Option<f64>, default: f64, lo: f64, hi: f64| {
        cx.within(key, v.unwrap_or(1e3 * default), 1e3 * lo, 1e3 * hi)
            .map(|v| 1e-3 * v)
    };
    // The UIC60 section: its head 72 mm wide, 172 mm high.
    let (width, height) = if uic60 {
        (0.072, 0.172)
    } else {
        (
            mm(
                "rail.width_mm",
                rail.width_mm,
                thickness,
                1e-4,
                10.0 * radius,
            )?,
            mm(
                "rail.height_mm",
                rail.height_mm,
                thickness.max(0.2 * radius),
                1e-4,
                10.0 * radius,
            )?,
        )
    };
    let pitch = mm(
        "rail.pitch_mm",
        rail.pitch_mm,
        2.0 * std::f64::consts::PI * radius / sectors as f64,
        1e-6,
        0.5 * width.min(height),
    )?;
    if let Some(rc) = crown.filter(|rc| !uic60 && *rc <= 0.5 * width) {
        return Err(cx.invalid(
            "rolling.crown_radius_m",
            rc,
            &format!(
                "must be above half the rail's width (rail.width_mm = {})",
                1e3 * width
            ),
        ));
    }
    // Fine where the wheel's zone is (its axial half-width, depth and growth), else
    // across where the patch can reach: the whole width under a line contact, about the
    // crown's Hertz semi-axis (2.5 sqrt(R_c d)) under a crown.
    let fine_default = crown.or(uic60.then_some(0.3)).map_or(0.5 * width, |rc| {
        (2.5 * (rc * 1e-3 * depth_mm).sqrt()).clamp(pitch, 0.5 * width)
    });
    let fine_across = zone
        .and_then(|z| z.axial)
        .unwrap_or(fine_default)
        .min(0.5 * width);
    let fine_below = zone
        .and_then(|z| z.depth)
        .unwrap_or(fine_default)
        .min(height);
    let fine_half_width = mm(
        "rail.fine_half_width_mm",
        rail.fine_half_width_mm,
        fine_across,
        0.0,
        0.5 * width,
    )?;
    let fine_depth = mm(
        "rail.fine_depth_mm",
        rail.fine_depth_mm,
        fine_below,
        0.0,
        height,
    )?;
    let growth = cx.within(
        "rail.growth",
        rail.growth
            .unwrap_or_else(|| zone.and_then(|z| z.growth).unwrap_or(1.3)),
        1.0,
        2.0,
    )?;
    let periodic = rail.periodic.unwrap_or(!uic60);
    if periodic && uic60 {
        return Err(cx.invalid(
            "rail.periodic",
            true,
            "a rail closed on itself is the bar's (the UIC60 rail's margins are graded, its stations unequal): remove it, or set rail.profile = \"bar\"",
        ));
    }
    let mut block = RailBlock {
        height,
        width,
        pitch,
        fine_half_width,
        fine_depth,
        growth,
        margin: 0.0,
        rolled: 0.0,
        profile,
        periodic,
        ring: None,
    };
    // The patch kept from the rail's free ends: the rail's height (graded along a UIC60
    // rail's margins), or eight fine half-widths, the larger.
    block.margin = mm(
        "rail.margin_mm",
        rail.margin_mm,
        height.max(8.0 * fine_half_width),
        0.0,
        100.0 * radius,
    )?;
    // A closed rail's seam (a station without top facets) kept beyond the rim nodes the
    // patch may meet: the zone's half arc (else four fine half-widths), the search's reach
    // and two pitches.
    let seam = zone.map_or(4.0 * fine_half_width, |z| 0.5 * z.width * radius)
        + block.reach(1e-3 * depth_mm)
        + 2.0 * pitch;
    if let Some(l) = rail.length_mm {
        if !periodic {
            return Err(cx.invalid(
                "rail.length_mm",
                l,
                "a length is a closed rail's, its ring rolled over again (rail.periodic = true, the bar's default); an open rail is as long as the run's rolling and two margins",
            ));
        }
        let least = 2.0 * block.margin + 2.0 * pitch;
        if !(l.is_finite() && 1e-3 * l >= least && 1e-3 * l <= 1000.0 * radius) {
            return Err(cx.invalid(
                "rail.length_mm",
                l,
                &format!(
                    "a ring holds a margin each side of the patch and two pitches: from {:.1} mm (rail.margin_mm = {:.1} twice, the pitch {:.2} mm twice) to {:.0} mm",
                    1e3 * least,
                    1e3 * block.margin,
                    1e3 * pitch,
                    1e6 * radius
                ),
            ));
        }
        block.ring = Some(1e-3 * l);
    }
    if periodic && block.margin < seam {
        return Err(cx.invalid(
            "rail.margin_mm",
            1e3 * block.margin,
            &format!(
                "a rail closed on itself (rail.periodic) keeps its seam, whose station has no top facets, beyond the rim nodes the patch meets: at least {:.1} mm (the zone's half arc, the search's reach and two pitches), or rail.periodic = false",
                1e3 * seam
            ),
        ));
    }
    Ok(block)
}
