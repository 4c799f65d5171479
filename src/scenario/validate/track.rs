//! The track's validation: `[track]` (a parameter set and its overrides), `[vehicle]` and
//! `[receptance]` into a [`TrackScenario`], every value under its key.

use super::super::raw::{RawReceptance, RawTrack, RawVehicle};
use super::super::{ReceptanceRange, ScenarioError, TrackScenario, Vehicle};
use super::Ctx;
use crate::element::beam::BeamTheory;
use crate::track::{Ends, TrackSpec, SETS};

/// The largest rail of a track scenario, elements.
const MAX_ELEMENTS: usize = 2_000_000;

/// The track scenario of `[track]`, `[vehicle]` and `[receptance]` (module docs).
pub(super) fn track_model(
    cx: &Ctx,
    t: Option<RawTrack>,
    v: Option<RawVehicle>,
    r: Option<RawReceptance>,
) -> Result<TrackScenario, ScenarioError> {
    let t = t.unwrap_or_default();
    let set = t.set.clone().unwrap_or_else(|| "uic60".into());
    let mut spec = TrackSpec::named(&set).map_err(|_| {
        let known: Vec<String> = SETS.iter().map(|s| format!("\"{s}\"")).collect();
        cx.invalid(
            "track.set",
            format!("\"{set}\""),
            &format!("allowed: {}", known.join(", ")),
        )
    })?;
    spec.theory = match t.theory.as_deref() {
        None => spec.theory,
        Some("timoshenko") => BeamTheory::Timoshenko,
        Some("euler_bernoulli") => BeamTheory::EulerBernoulli,
        Some(other) => {
            return Err(cx.invalid(
                "track.theory",
                format!("\"{other}\""),
                "allowed: \"timoshenko\", \"euler_bernoulli\"",
            ))
        }
    };
    let sec = &mut spec.section;
    for (key, value, target) in [
        ("track.young", t.young, &mut sec.young),
        (
            "track.shear_modulus",
            t.shear_modulus,
            &mut sec.shear_modulus,
        ),
        (
            "track.shear_coefficient",
            t.shear_coefficient,
            &mut sec.shear_coefficient,
        ),
        ("track.area", t.area, &mut sec.area),
        ("track.inertia", t.inertia, &mut sec.inertia),
        ("track.density", t.density, &mut sec.density),
    ] {
        if let Some(x) = value {
            *target = cx.positive(key, x)?;
        }
    }
    for (key, value, target, strict) in [
        (
            "track.pad_stiffness",
            t.pad_stiffness,
            &mut spec.pad_stiffness,
            true,
        ),
        (
            "track.pad_damping",
            t.pad_damping,
            &mut spec.pad_damping,
            false,
        ),
        (
            "track.sleeper_mass",
            t.sleeper_mass,
            &mut spec.sleeper_mass,
            true,
        ),
        (
            "track.ballast_stiffness",
            t.ballast_stiffness,
            &mut spec.ballast_stiffness,
            true,
        ),
        (
            "track.ballast_damping",
            t.ballast_damping,
            &mut spec.ballast_damping,
            false,
        ),
        ("track.spacing", t.spacing, &mut spec.spacing, true),
        (
            "track.head_radius",
            t.head_radius,
            &mut spec.head_radius,
            true,
        ),
    ] {
        if let Some(x) = value {
            *target = if strict {
                cx.positive(key, x)?
            } else {
                cx.non_negative(key, x)?
            };
        }
    }
    if let Some(nu) = t.poisson {
        if !(nu.is_finite() && nu > -1.0 && nu < 0.5) {
            return Err(cx.invalid("track.poisson", nu, "must be in (-1, 0.5)"));
        }
        spec.poisson = nu;
    }
    if let Some(b) = t.bays {
        spec.bays = cx.count("track.bays", b, 1_000_000)?;
    }
    if spec.bays < 2 {
        return Err(cx.invalid("track.bays", spec.bays, "give at least 2 bays"));
    }
    if let Some(e) = t.elements_per_bay {
        spec.elements_per_bay = cx.count("track.elements_per_bay", e, 1000)?;
    }
    let elements = spec.bays * spec.elements_per_bay;
    if elements > MAX_ELEMENTS {
        return Err(cx.invalid(
            "track.elements_per_bay",
            spec.elements_per_bay,
            &format!(
                "the rail would have {elements} elements (track.bays times track.elements_per_bay; at most {MAX_ELEMENTS})"
            ),
        ));
    }
    spec.ends = ends(cx, &t, spec)?;
    let vehicle = vehicle(cx, v, &spec)?;
    let receptance = receptance(cx, r)?;
    Ok(TrackScenario {
        set,
        spec,
        vehicle,
        receptance,
    })
}

/// `track.ends` with `track.end_bays` and `track.end_damping` (absorbing ends only; the
/// set's own by default).
fn ends(cx: &Ctx, t: &RawTrack, spec: TrackSpec) -> Result<Ends, ScenarioError> {
    let (set_bays, set_damping) = match spec.ends {
        Ends::Absorbing { bays, damping } => (bays, damping),
        Ends::Free => (30, 1000.0),
    };
    match t.ends.as_deref() {
        Some("free") => {
            for (key, given) in [
                ("track.end_bays", t.end_bays.map(|b| b as f64)),
                ("track.end_damping", t.end_damping),
            ] {
                if let Some(x) = given {
                    return Err(cx.invalid(key, x, "only used with track.ends = \"absorbing\""));
                }
            }
            Ok(Ends::Free)
        }
        None | Some("absorbing") => {
            let bays = match t.end_bays {
                Some(b) => cx.count("track.end_bays", b, 1_000_000)?,
                None => set_bays,
            };
            if 2 * bays >= spec.bays {
                return Err(cx.invalid(
                    "track.end_bays",
                    bays,
                    &format!(
                        "the two absorbing zones must leave bays between them: 2 end_bays < track.bays = {}",
                        spec.bays
                    ),
                ));
            }
            let damping = match t.end_damping {
                Some(d) => cx.non_negative("track.end_damping", d)?,
                None => set_damping,
            };
            Ok(Ends::Absorbing { bays, damping })
        }
        Some(other) => Err(cx.invalid(
            "track.ends",
            format!("\"{other}\""),
            "allowed: \"absorbing\" (damping graded up over the end bays), \"free\"",
        )),
    }
}

/// `[vehicle]`: the wheel and its passage, which must stay between the absorbing zones.
fn vehicle(cx: &Ctx, v: Option<RawVehicle>, spec: &TrackSpec) -> Result<Vehicle, ScenarioError> {
    let v = v.ok_or_else(|| {
        cx.missing(
            "vehicle",
            "kind = \"track\" needs a [vehicle] table with its speed, m/s",
        )
    })?;
    let speed = v.speed.ok_or_else(|| {
        cx.missing(
            "vehicle.speed",
            "the speed of the load along the track, m/s",
        )
    })?;
    let vehicle = Vehicle {
        unsprung_mass: cx.positive("vehicle.unsprung_mass", v.unsprung_mass.unwrap_or(800.0))?,
        axle_load: cx.positive("vehicle.axle_load", v.axle_load.unwrap_or(100e3))?,
        wheel_radius: cx.positive("vehicle.wheel_radius", v.wheel_radius.unwrap_or(0.46))?,
        speed: cx.positive("vehicle.speed", speed)?,
        travel_bays: cx.count("vehicle.travel_bays", v.travel_bays.unwrap_or(6), 1_000_000)?,
    };
    let zone = match spec.ends {
        Ends::Absorbing { bays, .. } => bays,
        Ends::Free => 0,
    };
    // The load crosses travel_bays bays centred on the middle sleeper: half of them each
    // side, rounded up, must stay out of the absorbing zone.
    let room = (spec.bays / 2).min(spec.bays - spec.bays / 2) - zone;
    if vehicle.travel_bays.div_ceil(2) > room {
        return Err(cx.invalid(
            "vehicle.travel_bays",
            vehicle.travel_bays,
            &format!(
                "the load must travel between the absorbing zones (track.end_bays = {zone} at each end of {} bays): at most {} bays",
                spec.bays,
                2 * room
            ),
        ));
    }
    Ok(vehicle)
}

/// `[receptance]`: `points` frequencies from `f_min` to `f_max`.
fn receptance(cx: &Ctx, r: Option<RawReceptance>) -> Result<ReceptanceRange, ScenarioError> {
    let r = r.unwrap_or_default();
    let f_min = cx.positive("receptance.f_min", r.f_min.unwrap_or(20.0))?;
    let f_max = cx.positive("receptance.f_max", r.f_max.unwrap_or(3000.0))?;
    if f_max <= f_min {
        return Err(cx.invalid(
            "receptance.f_max",
            f_max,
            &format!("must be above receptance.f_min = {f_min} Hz"),
        ));
    }
    let points = cx.count("receptance.points", r.points.unwrap_or(400), 100_000)?;
    if points < 3 {
        return Err(cx.invalid(
            "receptance.points",
            points,
            "give at least 3 frequencies (an extremum needs neighbours)",
        ));
    }
    Ok(ReceptanceRange {
        f_min,
        f_max,
        points,
    })
}
