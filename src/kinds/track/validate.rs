//! The track's validation: `[track]` (a parameter set and its overrides), `[vehicle]` and
//! `[receptance]` into a [`TrackScenario`], every value under its key.

use crate::bodies::rail::{Ends, TrackSpec, SETS};
use crate::element::beam::BeamTheory;
use crate::material::{Elastic, PlaneModel};
use crate::scenario::raw::{RawIrregularity, RawReceptance, RawTrack, RawVehicle};
use crate::scenario::Ctx;
use crate::scenario::{
    ReceptanceRange, ScenarioError, TrackScenario, TrackWheel, Vehicle, VehicleModel,
};

mod irregularity;
use irregularity::irregularity;

/// The largest rail of a track scenario, elements.
const MAX_ELEMENTS: usize = 2_000_000;

/// The track scenario of `[track]`, `[vehicle]` and `[receptance]` (module docs).
pub(crate) fn track_model(
    cx: &Ctx,
    t: Option<RawTrack>,
    v: Option<RawVehicle>,
    (r, irr): (Option<RawReceptance>, Option<RawIrregularity>),
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
            *target = within(cx, key, cx.positive(key, x)?)?;
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
            let x = if strict {
                cx.positive(key, x)?
            } else {
                cx.non_negative(key, x)?
            };
            *target = within(cx, key, x)?;
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
    let vehicle = vehicle(cx, v, (&spec, t.spacing.is_some()))?;
    let receptance = receptance(cx, r)?;
    let irregularity = match irr {
        None => None,
        Some(_) if vehicle.model == VehicleModel::MovingLoad => {
            return Err(cx.invalid(
                "irregularity",
                "(a table)",
                "the moving load has no contact to feel it: remove [irregularity], or roll the wheel (vehicle.model = \"wheel\")",
            ))
        }
        Some(i) => Some(irregularity(cx, i)?),
    };
    Ok(TrackScenario {
        set,
        spec,
        vehicle,
        receptance,
        irregularity,
    })
}

/// The range of each of the track's values (`track.*`; the unit in the message): decades
/// beyond any railway track either side (UIC60 on its pads and ballast: 2.1e11 Pa,
/// 7.7e-3 m^2, 3.055e-5 m^4, 200 MN/m, 40 MN/m, 177.5 kg, 0.6 m), and within them the
/// track's matrices stay in proportion for the solves in floating point: a pad of 1e300 N/m
/// ran the receptance to NaN with exit 0, a ballast of 1e-300 N/m to a negative static
/// stiffness (issue 47).
const RANGES: [(&str, f64, f64, &str); 13] = [
    ("track.young", 1e8, 1e13, "Pa"),
    ("track.shear_modulus", 1e8, 1e13, "Pa"),
    ("track.shear_coefficient", 1e-3, 1.0, "(dimensionless)"),
    ("track.area", 1e-5, 1.0, "m^2"),
    ("track.inertia", 1e-10, 0.1, "m^4"),
    ("track.density", 100.0, 1e5, "kg/m^3"),
    ("track.pad_stiffness", 1e3, 1e12, "N/m"),
    ("track.pad_damping", 0.0, 1e9, "N s/m"),
    ("track.sleeper_mass", 1e-3, 1e5, "kg"),
    ("track.ballast_stiffness", 1e3, 1e12, "N/m"),
    ("track.ballast_damping", 0.0, 1e9, "N s/m"),
    ("track.spacing", 0.05, 10.0, "m"),
    ("track.head_radius", 1e-3, 1e3, "m"),
];

/// The range of the vehicle's values (`vehicle.*`): decades beyond any railway vehicle's
/// either side (800 kg unsprung, 100 kN, a 0.46 m wheel, 100 km/h), the lower load left at
/// none (a wheel without load is a case of its own). A speed of 1e-6 km/h and a load of
/// 1e12 N ran until the contact lost its rim nodes, naming no key (issue 47).
const VEHICLE_RANGES: [(&str, f64, f64, &str); 5] = [
    ("vehicle.speed", 0.1, 1e3, "m/s"),
    ("vehicle.speed_km_h", 0.36, 3.6e3, "km/h"),
    ("vehicle.axle_load", 0.0, 1e7, "N"),
    ("vehicle.unsprung_mass", 1.0, 1e5, "kg"),
    ("vehicle.wheel_radius", 0.05, 5.0, "m"),
];

/// `x` under `key` (> 0) within its [`VEHICLE_RANGES`] entry.
fn vehicle_within(cx: &Ctx, key: &str, x: f64) -> Result<f64, ScenarioError> {
    let x = cx.positive(key, x)?;
    match VEHICLE_RANGES.iter().find(|r| r.0 == key) {
        Some(&(_, lo, hi, unit)) if !(lo..=hi).contains(&x) => Err(cx.invalid(
            key,
            x,
            &format!("must be from {lo:e} to {hi:e} {unit} (decades around any railway vehicle's)"),
        )),
        _ => Ok(x),
    }
}

/// `x` under `key` within its [`RANGES`] entry.
fn within(cx: &Ctx, key: &str, x: f64) -> Result<f64, ScenarioError> {
    match RANGES.iter().find(|r| r.0 == key) {
        Some(&(_, lo, hi, unit)) if !(lo..=hi).contains(&x) => Err(cx.invalid(
            key,
            x,
            &format!("must be from {lo:e} to {hi:e} {unit} (decades around any railway track's; beyond, the track's matrices fall out of proportion for its solves)"),
        )),
        _ => Ok(x),
    }
}

/// The highest frequency of `[receptance]`, Hz: the rail as a beam on discrete supports
/// is a model of a few kilohertz; far above, `omega^2 M` swamps the stiffness in floating
/// point (`f_max = 1e300` wrote NaN with exit 0, issue 47).
const F_MAX_HZ: f64 = 1e5;

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

/// `vehicle.creepage` (default 0): finite, in [-0.5, 0.5] (the wheel turns at `V (1 + xi) /
/// R_s`, so forwards and no faster than 1.5 times rolling; measured creep curves saturate
/// by a few per cent).
fn creepage(cx: &Ctx, xi: Option<f64>) -> Result<f64, ScenarioError> {
    let xi = xi.unwrap_or(0.0);
    if xi.is_finite() && (-0.5..=0.5).contains(&xi) {
        Ok(xi)
    } else {
        Err(cx.invalid(
            "vehicle.creepage",
            xi,
            "must be in [-0.5, 0.5]: the longitudinal creepage xi, omega = V (1 + xi) / R_s (positive: traction)",
        ))
    }
}

/// `[vehicle]`: the wheel and its passage, which must stay between the absorbing zones.
fn vehicle(
    cx: &Ctx,
    v: Option<RawVehicle>,
    (spec, spacing_given): (&TrackSpec, bool),
) -> Result<Vehicle, ScenarioError> {
    let v = v.ok_or_else(|| {
        cx.missing(
            "vehicle",
            "kind = \"track\" needs a [vehicle] table with its speed (vehicle.speed, m/s, or vehicle.speed_km_h)",
        )
    })?;
    let model = match v.model.as_deref() {
        None | Some("wheel") => VehicleModel::Wheel,
        Some("moving_load") => VehicleModel::MovingLoad,
        Some(other) => {
            return Err(cx.invalid(
                "vehicle.model",
                format!("\"{other}\""),
                "allowed: \"wheel\" (the elastic wheel rolling on its hub), \"moving_load\" (a constant force)",
            ))
        }
    };
    let speed = vehicle_speed(cx, &v)?;
    let wheel_only = [
        ("vehicle.settle_bays", v.settle_bays.is_some()),
        (
            "vehicle.suspension_stiffness",
            v.suspension_stiffness.is_some(),
        ),
        ("vehicle.suspension_damping", v.suspension_damping.is_some()),
        ("vehicle.gravity", v.gravity.is_some()),
        ("vehicle.creepage", v.creepage.is_some()),
        ("vehicle.wheelbase", v.wheelbase.is_some()),
        ("vehicle.wheel_rim_nodes", v.wheel_rim_nodes.is_some()),
        ("vehicle.wheel_thickness", v.wheel_thickness.is_some()),
        ("vehicle.wheel_hub_radius", v.wheel_hub_radius.is_some()),
        ("vehicle.wheel_grading", v.wheel_grading.is_some()),
        ("vehicle.wheel_rim_band", v.wheel_rim_band.is_some()),
        ("vehicle.wheel_plane", v.wheel_plane.is_some()),
    ];
    if model == VehicleModel::MovingLoad {
        if let Some((key, _)) = wheel_only.iter().find(|(_, given)| *given) {
            return Err(cx.invalid(
                key,
                "(given)",
                "only used with vehicle.model = \"wheel\" (the moving load is a constant force)",
            ));
        }
    }
    let (wheel, radius) = track_wheel(cx, &v, spec)?;
    let default_travel = match model {
        VehicleModel::Wheel => 20,
        VehicleModel::MovingLoad => 6,
    };
    let vehicle = Vehicle {
        model,
        unsprung_mass: vehicle_within(
            cx,
            "vehicle.unsprung_mass",
            v.unsprung_mass.unwrap_or(800.0),
        )?,
        axle_load: vehicle_within(cx, "vehicle.axle_load", v.axle_load.unwrap_or(100e3))?,
        wheel_radius: radius,
        speed,
        travel_bays: cx.count(
            "vehicle.travel_bays",
            v.travel_bays.unwrap_or(default_travel),
            1_000_000,
        )?,
        settle_bays: match v.settle_bays {
            Some(b) => cx.count("vehicle.settle_bays", b, 1_000_000)?,
            None if model == VehicleModel::Wheel => 4,
            None => 0,
        },
        suspension_stiffness: cx.non_negative(
            "vehicle.suspension_stiffness",
            v.suspension_stiffness.unwrap_or(0.0),
        )?,
        suspension_damping: cx.non_negative(
            "vehicle.suspension_damping",
            v.suspension_damping.unwrap_or(0.0),
        )?,
        gravity: cx.non_negative("vehicle.gravity", v.gravity.unwrap_or(9.81))?,
        creepage: creepage(cx, v.creepage)?,
        wheelbase: match v.wheelbase {
            Some(l) => Some(cx.positive("vehicle.wheelbase", l)?),
            None => None,
        },
        wheel,
    };
    if model == VehicleModel::Wheel && vehicle.settle_bays < 2 {
        return Err(cx.invalid(
            "vehicle.settle_bays",
            vehicle.settle_bays,
            "give at least 2 (the load is applied over the first half of them)",
        ));
    }
    if model == VehicleModel::Wheel {
        // The key the user set among those that set the loading time, for the message.
        let key = if let Some(b) = v.settle_bays {
            ("vehicle.settle_bays", b.to_string())
        } else if spacing_given {
            ("track.spacing", spec.spacing.to_string())
        } else if let Some(s) = v.speed {
            ("vehicle.speed", s.to_string())
        } else {
            (
                "vehicle.speed_km_h",
                v.speed_km_h.unwrap_or_default().to_string(),
            )
        };
        settle_time(cx, key, &vehicle, spec)?;
    }
    check_room(cx, &vehicle, spec)?;
    Ok(vehicle)
}

/// `vehicle.speed` (m/s) or `vehicle.speed_km_h`, one of them, in m/s.
fn vehicle_speed(cx: &Ctx, v: &RawVehicle) -> Result<f64, ScenarioError> {
    match (v.speed, v.speed_km_h) {
        (Some(s), None) => vehicle_within(cx, "vehicle.speed", s),
        (None, Some(k)) => Ok(vehicle_within(cx, "vehicle.speed_km_h", k)? / 3.6),
        (Some(s), Some(_)) => Err(cx.invalid(
            "vehicle.speed",
            s,
            "give vehicle.speed (m/s) or vehicle.speed_km_h, not both",
        )),
        (None, None) => Err(cx.missing(
            "vehicle.speed",
            "the speed along the track: vehicle.speed (m/s) or vehicle.speed_km_h",
        )),
    }
}

/// The wheel of `[vehicle]` (`vehicle.wheel_*`) and its radius, m.
fn track_wheel(
    cx: &Ctx,
    v: &RawVehicle,
    spec: &TrackSpec,
) -> Result<(TrackWheel, f64), ScenarioError> {
    let radius = vehicle_within(cx, "vehicle.wheel_radius", v.wheel_radius.unwrap_or(0.46))?;
    let plane = match v.wheel_plane.as_deref().unwrap_or("strain") {
        "strain" => PlaneModel::Strain,
        "stress" => PlaneModel::Stress,
        o => {
            return Err(cx.invalid(
                "vehicle.wheel_plane",
                format!("\"{o}\""),
                "allowed: \"strain\", \"stress\"",
            ))
        }
    };
    let hub = cx.positive(
        "vehicle.wheel_hub_radius",
        v.wheel_hub_radius.unwrap_or(0.1),
    )?;
    if hub >= 0.8 * radius {
        return Err(cx.invalid(
            "vehicle.wheel_hub_radius",
            hub,
            &format!(
                "must be below 0.8 vehicle.wheel_radius = {} m",
                0.8 * radius
            ),
        ));
    }
    let grading = v.wheel_grading.unwrap_or(1.3);
    if !(grading.is_finite() && (1.0..=2.0).contains(&grading)) {
        return Err(cx.invalid("vehicle.wheel_grading", grading, "must be in [1, 2]"));
    }
    let wheel = TrackWheel {
        rim_nodes: cx.count(
            "vehicle.wheel_rim_nodes",
            v.wheel_rim_nodes.unwrap_or(720),
            100_000,
        )?,
        thickness: cx.positive("vehicle.wheel_thickness", v.wheel_thickness.unwrap_or(0.02))?,
        hub_radius: hub,
        grading,
        rim_band: None,
        plane,
        material: Elastic {
            young: 2.1e11,
            poisson: spec.poisson,
            density: 7850.0,
        },
    };
    if wheel.rim_nodes < 64 {
        return Err(cx.invalid(
            "vehicle.wheel_rim_nodes",
            wheel.rim_nodes,
            "give at least 64 rim nodes",
        ));
    }
    let wheel = TrackWheel {
        rim_band: rim_band(cx, v.wheel_rim_band, &wheel, radius)?,
        ..wheel
    };
    Ok((wheel, radius))
}

/// `vehicle.wheel_rim_band`: the depth (m) of the band under the rim meshed with the rim's
/// symmetry, at least the rim's pitch and leaving a tenth of the radius and the hub inside.
fn rim_band(
    cx: &Ctx,
    band: Option<f64>,
    wheel: &TrackWheel,
    radius: f64,
) -> Result<Option<f64>, ScenarioError> {
    let Some(b) = band else {
        return Ok(None);
    };
    let pitch = std::f64::consts::TAU * radius / wheel.rim_nodes as f64;
    let most = radius - (0.1 * radius).max(wheel.hub_radius + 2.0 * pitch);
    if !(b.is_finite() && b >= pitch && b <= most) {
        return Err(cx.invalid(
            "vehicle.wheel_rim_band",
            b,
            &format!("the depth (m) of the band under the rim meshed with the rim's symmetry: at least the rim's pitch ({pitch:.3e} m) and at most {most:.3e} m (a tenth of the radius, and the hub, left inside)"),
        ));
    }
    Ok(Some(b))
}

/// The recorded travel, centred on the middle sleeper, and the wheel's settling bays before
/// it stay out of the absorbing zones.
fn check_room(cx: &Ctx, vehicle: &Vehicle, spec: &TrackSpec) -> Result<(), ScenarioError> {
    let zone = match spec.ends {
        Ends::Absorbing { bays, .. } => bays,
        Ends::Free => 0,
    };
    // The recorded travel is centred on the middle sleeper; the wheel's settling bays come
    // before it: all of it must stay out of the absorbing zones. A second wheel starts its
    // wheelbase behind the first, and the first runs its wheelbase further.
    let wheelbase_bays = vehicle
        .wheelbase
        .map_or(0, |l| (l / spec.spacing).ceil() as usize);
    let before = vehicle.travel_bays.div_ceil(2) + vehicle.settle_bays + wheelbase_bays;
    let after = vehicle.travel_bays.div_ceil(2) + wheelbase_bays;
    let room_before = (spec.bays / 2).saturating_sub(zone);
    let room_after = (spec.bays - spec.bays / 2).saturating_sub(zone);
    if before > room_before || after > room_after {
        let one_wheel_fits =
            before - wheelbase_bays <= room_before && after - wheelbase_bays <= room_after;
        let (key, value) = if let (Some(l), true) = (vehicle.wheelbase, one_wheel_fits) {
            ("vehicle.wheelbase", l.to_string())
        } else if after > room_after || vehicle.settle_bays == 0 {
            ("vehicle.travel_bays", vehicle.travel_bays.to_string())
        } else {
            ("vehicle.settle_bays", vehicle.settle_bays.to_string())
        };
        let wheelbase = if wheelbase_bays > 0 {
            format!(" + the wheelbase's {wheelbase_bays}")
        } else {
            String::new()
        };
        return Err(cx.invalid(
            key,
            value,
            &format!(
                "the load must travel between the absorbing zones (track.end_bays = {zone} at each end of {} bays): vehicle.travel_bays / 2 + vehicle.settle_bays{wheelbase} = {before} bays before the middle, {room_before} there; vehicle.travel_bays / 2{wheelbase} = {after} after it, {room_after} there (more track.bays make room)",
                spec.bays,
            ),
        ));
    }
    Ok(())
}

/// The wheel's bounce on the track, Hz: the single-dof estimate `sqrt(k / m_u) / (2 pi)`
/// of the unsprung mass `m_u` on Hertz's spring `k_H` at the static load in series with
/// the track's static stiffness, the rail as an infinite beam on its supports smeared
/// along it, `2 k_f / beta` with `k_f = (k_p k_b / (k_p + k_b)) / s` and
/// `beta = (k_f / (4 EI))^(1/4)` (Winkler's foundation; 9.2e7 N/m for UIC60 against the
/// discrete track's 8.5e7 N/m at mid-span). The track's mass that moves with the wheel is
/// left out, so it is above the P2 frequency (52.3 Hz for `scenarios/track.toml`, 800 kg
/// under 107.8 kN, against its P2 of 43.8 Hz): its period is a lower bound of the bounce's.
/// `None` where Hertz's contact is not defined.
fn bounce_hz(v: &Vehicle, spec: &TrackSpec) -> Option<f64> {
    let load = v.axle_load + v.unsprung_mass * v.gravity;
    let k_h = crate::bodies::rail::hertz::contact(
        load,
        v.wheel_radius,
        spec.head_radius,
        spec.section.young,
        spec.poisson,
    )?
    .stiffness;
    let (kp, kb) = (spec.pad_stiffness, spec.ballast_stiffness);
    let k_f = kp * kb / (kp + kb) / spec.spacing;
    let beta = (k_f / (4.0 * spec.section.ei())).powf(0.25);
    let k_track = 2.0 * k_f / beta;
    let k = 1.0 / (1.0 / k_h + 1.0 / k_track);
    let f = (k / v.unsprung_mass).sqrt() / (2.0 * std::f64::consts::PI);
    (f.is_finite() && f > 0.0).then_some(f)
}

/// The load's raised cosine comes on over the first half of the settling bays
/// (`vehicle.settle_bays`, `track.spacing`) at the vehicle's speed: refused, under `key`,
/// when that is shorter than one period of the wheel's bounce on the track
/// ([`bounce_hz`]): the load would strike the track, not settle on it, and the bounce
/// would ring through the passage (issue 47: 2 bays at 200 km/h, 10.8 ms against 19.8 ms,
/// ran to a mean force 17% below the static load with exit 0; a spacing of 0.01 m, 63%
/// below). The rigid-base wheel's `rolling.settle_time` is held to its bounce the same way
/// ([`crate::kinds::wheel::run`]).
fn settle_time(
    cx: &Ctx,
    (key, value): (&str, String),
    v: &Vehicle,
    spec: &TrackSpec,
) -> Result<(), ScenarioError> {
    let Some(f_b) = bounce_hz(v, spec) else {
        return Ok(());
    };
    let period = 1.0 / f_b;
    let ramp_m = 0.5 * v.settle_bays as f64 * spec.spacing;
    let ramp = ramp_m / v.speed;
    if ramp >= period {
        return Ok(());
    }
    let need = (2.0 * v.speed * period / spec.spacing).ceil();
    let take = if need <= 1e6 {
        format!("take vehicle.settle_bays >= {need} (with track.bays for the room)")
    } else {
        format!("it would take {need:.3e} settling bays, beyond any track: check vehicle.unsprung_mass, vehicle.axle_load and the speed")
    };
    Err(cx.invalid(
        key,
        value,
        &format!(
            "the load comes on over half of vehicle.settle_bays = {} bays of track.spacing = {} m, {ramp_m:.4} m in {ramp:.4e} s at {:.2} m/s, less than one period of the wheel's bounce on the track ({period:.4e} s: {f_b:.4e} Hz, the unsprung mass on the contact and the track's static stiffness): the load would strike the track and the bounce ring through the passage; {take}",
            v.settle_bays,
            spec.spacing,
            v.speed,
        ),
    ))
}

/// `[receptance]`: `points` frequencies from `f_min` to `f_max`.
fn receptance(cx: &Ctx, r: Option<RawReceptance>) -> Result<ReceptanceRange, ScenarioError> {
    let r = r.unwrap_or_default();
    let f_min = cx.positive("receptance.f_min", r.f_min.unwrap_or(20.0))?;
    let f_max = cx.positive("receptance.f_max", r.f_max.unwrap_or(3000.0))?;
    if f_max > F_MAX_HZ {
        return Err(cx.invalid(
            "receptance.f_max",
            f_max,
            &format!("must be at most {F_MAX_HZ:e} Hz (the rail as a beam on its supports is a model of a few kHz)"),
        ));
    }
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
