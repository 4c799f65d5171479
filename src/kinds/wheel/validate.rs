//! The wheel's validation: `[wheel]`, `[material]` and `[rolling]` into a
//! [`WheelScenario`]; the `[block]` under it and the settings a wheel's run refuses in
//! combination: [`super::rules`].

use crate::bodies::wheel::{ContactSurface, Coupling, Support, WheelSpec};
use crate::contact::obstacle::Flattening;
use crate::material::{Elastic, PlaneModel};
use crate::scenario::raw::{RawMaterial, RawRolling, RawWheel};
use crate::scenario::{Ctx, MeshSource, ScenarioError, WheelScenario, DEFAULT_HUB_FRACTION};
use std::path::Path;

/// The wheel of `[wheel]`, `[material]` and `[rolling]`, each value checked under its key
/// (in the order of the keys' checks below: the first error found is the one reported).
pub(crate) fn wheel_model(
    cx: &Ctx,
    w: Option<RawWheel>,
    m: Option<RawMaterial>,
    r: Option<RawRolling>,
) -> Result<WheelScenario, ScenarioError> {
    let w = w.ok_or_else(|| cx.missing("wheel", "kind = \"wheel\" needs a [wheel] table"))?;
    let m = m.ok_or_else(|| {
        cx.missing(
            "material",
            "the wheel's [material] (young, poisson, density)",
        )
    })?;
    let r = r.ok_or_else(|| {
        cx.missing(
            "rolling",
            "[rolling] (omega, flattening, settle_time, turns)",
        )
    })?;
    let radius = cx.positive("wheel.radius", w.radius)?;
    let thickness = cx.positive("wheel.thickness", w.thickness)?;
    let material = wheel_material(cx, &m)?;
    let plastic = plasticity(cx, &m, material)?;
    let large = super::large_keys::large_of(cx, &m)?;
    let mesh = disk_mesh(cx, &w)?;
    let plane = plane_model(cx, &w)?;
    let lumped = wheel_mass(cx, &w)?;
    let support = support(cx, &w, radius, &mesh)?;
    point_hub(cx, support, radius, plastic.is_some())?;
    let mesh = zone_mesh(cx, &w, mesh, support, radius)?;
    let load = w.load.map(|p| cx.positive("wheel.load", p)).transpose()?;
    let rolling = rolling(cx, &r, radius, load)?;
    let damping = cx.non_negative("wheel.damping", w.damping.unwrap_or(0.0))?;
    let coupling = coupling(cx, &r)?;
    let surface = contact_surface(cx, &w)?;
    let fields_per_turn = cx.count(
        "rolling.fields_per_turn",
        r.fields_per_turn.unwrap_or(8),
        1000,
    )?;
    if let (Some(true), Some(_)) = (w.stress_stiffening, large) {
        return Err(cx.invalid(
            "wheel.stress_stiffening",
            true,
            "with material.geometry = \"large\" the centrifugal prestress's stiffening is part of the nonlinear force: remove the key",
        ));
    }
    if let (Some(s), Some(false)) = (w.stress_stiffening, w.rotating_frame) {
        return Err(cx.invalid(
            "wheel.stress_stiffening",
            s,
            "the stress stiffening of the spinning wheel's rotating frame, not used with wheel.rotating_frame = false: remove it",
        ));
    }
    Ok(WheelScenario {
        spec: WheelSpec {
            radius,
            thickness,
            material,
            plane,
            lumped,
            damping,
            support,
            omega: rolling.omega,
            flattening: rolling.flattening,
            stress_stiffening: w.stress_stiffening.unwrap_or(large.is_none()),
            rotating_frame: w.rotating_frame.unwrap_or(true),
            creepage: rolling.creepage,
            coupling,
            surface,
        },
        mesh,
        turns: rolling.turns,
        settle_gamma: rolling.settle_gamma,
        fields_per_turn,
        block: None,
        load,
        plastic,
        large,
    })
}

/// The smallest hub of a plastic wheel, as a fraction of its radius.
const PLASTIC_HUB_MIN_FRACTION: f64 = 1e-3;

/// A plastic wheel's hub holds a ring of material, not a point: a hub below a thousandth of
/// the radius carries the wheel's reaction on a few nodes at the centre, where the plastic
/// flow then grows without bound (a hub of 0.7 um took over two minutes a growth pass in
/// its plastic iterations, where the estimate said seconds). The elastic wheel keeps any
/// hub (its pinned centre is `support = "centre"`).
fn point_hub(cx: &Ctx, support: Support, radius: f64, plastic: bool) -> Result<(), ScenarioError> {
    match support {
        Support::Hub { radius: hr } if plastic && hr < PLASTIC_HUB_MIN_FRACTION * radius => {
            Err(cx.invalid(
                "wheel.hub_radius",
                hr,
                &format!(
                    "a plastic wheel (material.model = \"j2\") needs a hub of at least {} m (a thousandth of wheel.radius): a smaller one concentrates the plastic flow at the centre without bound",
                    PLASTIC_HUB_MIN_FRACTION * radius
                ),
            ))
        }
        _ => Ok(()),
    }
}

/// `[material]`'s plasticity: `model`, `yield_stress`, `hardening` and its constants, each
/// key refused where the model or the hardening does not use it.
fn plasticity(
    cx: &Ctx,
    m: &RawMaterial,
    elastic: Elastic,
) -> Result<Option<crate::scenario::Plastic>, ScenarioError> {
    use crate::plasticity::J2Material;
    let unused = |key: &str, given: bool, why: &str| -> Result<(), ScenarioError> {
        if given {
            Err(cx.invalid(&format!("material.{key}"), "(given)", why))
        } else {
            Ok(())
        }
    };
    let keys = [
        ("yield_stress", m.yield_stress.is_some()),
        ("hardening", m.hardening.is_some()),
        ("hardening_modulus", m.hardening_modulus.is_some()),
        ("voce_q", m.voce_q.is_some()),
        ("voce_b", m.voce_b.is_some()),
        ("af_c", m.af_c.is_some()),
        ("af_gamma", m.af_gamma.is_some()),
        ("plastic_tolerance", m.plastic_tolerance.is_some()),
    ];
    match m.model.as_deref().unwrap_or("elastic") {
        "elastic" => {
            for (k, given) in keys {
                unused(
                    k,
                    given,
                    "a key of the plastic material, used with material.model = \"j2\" only",
                )?;
            }
            return Ok(None);
        }
        "j2" => {}
        o => {
            return Err(cx.invalid(
                "material.model",
                format!("\"{o}\""),
                "allowed: \"elastic\", \"j2\"",
            ))
        }
    }
    let sy = m.yield_stress.ok_or_else(|| {
        cx.missing(
            "material.yield_stress",
            "material.model = \"j2\" needs the yield stress, Pa",
        )
    })?;
    let yield_stress = cx.positive("material.yield_stress", sy)?;
    let hardening = m.hardening.as_deref().unwrap_or("none");
    let (isotropic, kinematic) = hardening_of(cx, m, hardening)?;
    let tolerance = m.plastic_tolerance.unwrap_or(crate::model::DEFAULT_TOL);
    if !(tolerance > 0.0 && tolerance < 1.0) {
        return Err(cx.invalid(
            "material.plastic_tolerance",
            tolerance,
            "the residual relative to the internal force, in (0, 1)",
        ));
    }
    Ok(Some(crate::scenario::Plastic {
        material: J2Material {
            elastic,
            yield_stress,
            isotropic,
            kinematic,
        },
        tolerance,
    }))
}

/// `material.hardening` and its constants (`hardening_modulus`, `voce_q`, `voce_b`, `af_c`,
/// `af_gamma`), each refused where the hardening does not use it.
fn hardening_of(
    cx: &Ctx,
    m: &RawMaterial,
    hardening: &str,
) -> Result<(crate::plasticity::Isotropic, crate::plasticity::Kinematic), ScenarioError> {
    use crate::plasticity::{Isotropic, Kinematic};
    let unused = |key: &str, given: bool, why: &str| -> Result<(), ScenarioError> {
        if given {
            Err(cx.invalid(&format!("material.{key}"), "(given)", why))
        } else {
            Ok(())
        }
    };
    let modulus = |why: &str| {
        m.hardening_modulus
            .ok_or_else(|| cx.missing("material.hardening_modulus", why))
            .and_then(|h| cx.non_negative("material.hardening_modulus", h))
    };
    let (mut isotropic, mut kinematic) = (
        Isotropic {
            modulus: 0.0,
            voce_q: 0.0,
            voce_b: 0.0,
        },
        Kinematic { c: 0.0, gamma: 0.0 },
    );
    let only = |h: &str| format!("used with material.hardening = \"{h}\" only");
    match hardening {
        "none" => {
            unused(
                "hardening_modulus",
                m.hardening_modulus.is_some(),
                "a hardening constant, not used with material.hardening = \"none\"",
            )?;
        }
        "isotropic" => {
            isotropic.modulus = modulus("hardening = \"isotropic\" needs hardening_modulus, Pa (0 with voce_q for Voce's law alone)")?;
            isotropic.voce_q = cx.non_negative("material.voce_q", m.voce_q.unwrap_or(0.0))?;
            if isotropic.voce_q > 0.0 {
                let b = m.voce_b.ok_or_else(|| {
                    cx.missing(
                        "material.voce_b",
                        "Voce's law (voce_q > 0) needs its rate voce_b",
                    )
                })?;
                isotropic.voce_b = cx.positive("material.voce_b", b)?;
            } else {
                unused(
                    "voce_b",
                    m.voce_b.is_some(),
                    "Voce's rate, used with voce_q > 0 only",
                )?;
            }
        }
        "kinematic" => {
            kinematic.c =
                modulus("hardening = \"kinematic\" (Prager) needs hardening_modulus, Pa")?;
        }
        "armstrong_frederick" => {
            unused(
                "hardening_modulus",
                m.hardening_modulus.is_some(),
                "Armstrong-Frederick's constants are af_c and af_gamma",
            )?;
            let c = m.af_c.ok_or_else(|| {
                cx.missing(
                    "material.af_c",
                    "hardening = \"armstrong_frederick\" needs af_c, Pa",
                )
            })?;
            let g = m.af_gamma.ok_or_else(|| {
                cx.missing(
                    "material.af_gamma",
                    "hardening = \"armstrong_frederick\" needs af_gamma (dimensionless)",
                )
            })?;
            kinematic.c = cx.positive("material.af_c", c)?;
            kinematic.gamma = cx.non_negative("material.af_gamma", g)?;
        }
        o => {
            return Err(cx.invalid(
                "material.hardening",
                format!("\"{o}\""),
                "allowed: \"none\", \"isotropic\", \"kinematic\", \"armstrong_frederick\"",
            ))
        }
    }
    if hardening != "isotropic" {
        unused("voce_q", m.voce_q.is_some(), &only("isotropic"))?;
        unused("voce_b", m.voce_b.is_some(), &only("isotropic"))?;
    }
    if hardening != "armstrong_frederick" {
        unused("af_c", m.af_c.is_some(), &only("armstrong_frederick"))?;
        unused(
            "af_gamma",
            m.af_gamma.is_some(),
            &only("armstrong_frederick"),
        )?;
    }
    Ok((isotropic, kinematic))
}

/// The wheel's `[material]`: Young's modulus, Poisson's ratio, density.
fn wheel_material(cx: &Ctx, m: &RawMaterial) -> Result<Elastic, ScenarioError> {
    let young = cx.positive("material.young", m.young)?;
    if !(m.poisson.is_finite() && m.poisson > -1.0 && m.poisson < 0.5) {
        return Err(cx.invalid(
            "material.poisson",
            m.poisson,
            "Poisson's ratio must be in (-1, 0.5)",
        ));
    }
    let density = cx.positive("material.density", m.density)?;
    Ok(Elastic {
        young,
        poisson: m.poisson,
        density,
    })
}

/// The disk's mesh: `wheel.rings`, `wheel.rim_nodes` (with `wheel.grading`) or
/// `wheel.mesh` (a Gmsh file, relative to the scenario), one of them at most.
fn disk_mesh(cx: &Ctx, w: &RawWheel) -> Result<MeshSource, ScenarioError> {
    let given = [
        ("wheel.rings", w.rings.is_some()),
        ("wheel.rim_nodes", w.rim_nodes.is_some()),
        ("wheel.mesh", w.mesh.is_some()),
    ];
    if given.iter().filter(|g| g.1).count() > 1 {
        let names: Vec<&str> = given.iter().filter(|g| g.1).map(|g| g.0).collect();
        return Err(cx.invalid(
            names[1],
            format!("given with {}", names[0]),
            "give one of wheel.rings, wheel.rim_nodes or wheel.mesh",
        ));
    }
    if w.rim_band.is_some() && w.rim_nodes.is_none() {
        return Err(cx.invalid(
            "wheel.rim_band",
            w.rim_band.unwrap_or_default(),
            "the symmetric band of the disk of wheel.rim_nodes; give wheel.rim_nodes",
        ));
    }
    if w.grading.is_some() && w.rim_nodes.is_none() {
        return Err(cx.invalid(
            "wheel.grading",
            w.grading.unwrap_or_default(),
            "the grading of the disk of wheel.rim_nodes; give wheel.rim_nodes",
        ));
    }
    Ok(match (w.rings, &w.mesh) {
        (None, None) if w.rim_nodes.is_some() => {
            let n = cx.count("wheel.rim_nodes", w.rim_nodes.unwrap_or(0), 100_000)?;
            if n < 12 {
                return Err(cx.invalid("wheel.rim_nodes", n, "at least 12 rim nodes"));
            }
            let grading = w
                .grading
                .unwrap_or(crate::mesh::generators::DiskOptions::DEFAULT_GRADING);
            if !(1.0..=2.0).contains(&grading) {
                return Err(cx.invalid("wheel.grading", grading, "in [1, 2]"));
            }
            let band = match w.rim_band {
                None => None,
                Some(b) => {
                    let pitch = std::f64::consts::TAU * w.radius / n as f64;
                    let hub = w.hub_radius.unwrap_or(0.0);
                    let most = w.radius - (0.1 * w.radius).max(hub + 2.0 * pitch);
                    if !(b.is_finite() && b >= pitch && b <= most) {
                        return Err(cx.invalid(
                            "wheel.rim_band",
                            b,
                            &format!("the depth (m) of the band under the rim meshed with the rim's symmetry: at least the rim's pitch ({pitch:.3e} m) and at most {most:.3e} m (a tenth of the radius, and the hub, left inside)"),
                        ));
                    }
                    Some(b)
                }
            };
            MeshSource::Graded {
                rim_nodes: n,
                grading,
                band,
            }
        }
        (Some(n), _) => MeshSource::Rings(cx.count("wheel.rings", n, 400)?),
        (None, Some(f)) => {
            let p = Path::new(f);
            let p = if p.is_relative() {
                cx.path().parent().unwrap_or(Path::new(".")).join(p)
            } else {
                p.to_path_buf()
            };
            MeshSource::Gmsh(p)
        }
        (None, None) => MeshSource::Rings(12),
    })
}

/// `wheel.plane`: plane stress (default) or plane strain.
fn plane_model(cx: &Ctx, w: &RawWheel) -> Result<PlaneModel, ScenarioError> {
    Ok(match w.plane.as_deref().unwrap_or("stress") {
        "stress" => PlaneModel::Stress,
        "strain" => PlaneModel::Strain,
        o => {
            return Err(cx.invalid(
                "wheel.plane",
                format!("\"{o}\""),
                "allowed: \"stress\", \"strain\"",
            ))
        }
    })
}

/// `wheel.mass`: lumped (`true`) or consistent (`false`, the default).
fn wheel_mass(cx: &Ctx, w: &RawWheel) -> Result<bool, ScenarioError> {
    Ok(match w.mass.as_deref().unwrap_or("consistent") {
        "consistent" => false,
        "lumped" => true,
        o => {
            return Err(cx.invalid(
                "wheel.mass",
                format!("\"{o}\""),
                "allowed: \"consistent\", \"lumped\"",
            ))
        }
    })
}

/// `wheel.support` and `wheel.hub_radius`: the pinned centre or a clamped hub (default, a
/// tenth of the radius). On the graded disk of `wheel.rim_nodes` the hub leaves room for
/// two rim pitches of elements: `hub_radius < radius (1 - 4 pi / rim_nodes)`
/// ([`crate::mesh::generators::disk_graded`]).
fn support(
    cx: &Ctx,
    w: &RawWheel,
    radius: f64,
    mesh: &MeshSource,
) -> Result<Support, ScenarioError> {
    // Default: a hub clamped over a tenth of the radius (the pinned centre is a point
    // support whose stiffness vanishes as the mesh is refined; `softway::wheel`).
    Ok(match w.support.as_deref().unwrap_or("hub") {
        "centre" | "center" => {
            if let Some(hr) = w.hub_radius {
                return Err(cx.invalid(
                    "wheel.hub_radius",
                    hr,
                    "only with support = \"hub\" (the centre node is pinned)",
                ));
            }
            Support::CentrePinned
        }
        "hub" => {
            let hr = w.hub_radius.unwrap_or(DEFAULT_HUB_FRACTION * radius);
            let hr = cx.positive("wheel.hub_radius", hr)?;
            if hr >= radius {
                return Err(cx.invalid(
                    "wheel.hub_radius",
                    hr,
                    &format!("must be smaller than wheel.radius = {radius}"),
                ));
            }
            if let MeshSource::Graded { rim_nodes, .. } = *mesh {
                let max = radius * (1.0 - 2.0 * std::f64::consts::TAU / rim_nodes as f64);
                if hr >= max {
                    return Err(cx.invalid(
                        "wheel.hub_radius",
                        hr,
                        &format!("must be below wheel.radius (1 - 4 pi / wheel.rim_nodes) = {max:.6} m: the graded disk keeps two rim pitches of elements between the hub and the rim"),
                    ));
                }
            }
            Support::Hub { radius: hr }
        }
        o => {
            return Err(cx.invalid(
                "wheel.support",
                format!("\"{o}\""),
                "allowed: \"centre\", \"hub\"",
            ))
        }
    })
}

/// `mesh`, or with `wheel.zone_rim_nodes` the moving refined zone on the graded disk of
/// `mesh` (`wheel.zone_sectors`, `wheel.zone_width`; a hub needed).
fn zone_mesh(
    cx: &Ctx,
    w: &RawWheel,
    mesh: MeshSource,
    support: Support,
    radius: f64,
) -> Result<MeshSource, ScenarioError> {
    Ok(match (w.zone_rim_nodes, mesh) {
        (None, mesh) => {
            for (k, given) in [
                ("wheel.zone_width", w.zone_width.is_some()),
                ("wheel.zone_sectors", w.zone_sectors.is_some()),
                ("wheel.zone_depth", w.zone_depth.is_some()),
            ] {
                if given {
                    return Err(cx.invalid(
                        k,
                        "(given)",
                        "a key of the moving refined zone: give wheel.zone_rim_nodes too",
                    ));
                }
            }
            mesh
        }
        (Some(z), MeshSource::Graded { band: Some(b), .. }) => {
            return Err(cx.invalid(
                "wheel.rim_band",
                b,
                &format!("the symmetric band of the disk of wheel.rim_nodes, not used by the refined zone's mesh (wheel.zone_rim_nodes = {z}): remove one of them"),
            ))
        }
        (Some(z), MeshSource::Graded { .. }) if w.grading.is_some() => {
            return Err(cx.invalid(
                "wheel.grading",
                w.grading.unwrap_or_default(),
                &format!("the grading of the disk of wheel.rim_nodes, not used by the refined zone's mesh (wheel.zone_rim_nodes = {z}, graded by the zone's own rule): remove it"),
            ))
        }
        (Some(z), MeshSource::Graded { rim_nodes, .. }) => {
            let Support::Hub { radius: hub_radius } = support else {
                return Err(cx.invalid(
                    "wheel.zone_rim_nodes",
                    z,
                    "the refined zone's mesh is the annulus on the hub: needs support = \"hub\"",
                ));
            };
            let sectors = cx.count("wheel.zone_sectors", w.zone_sectors.unwrap_or(72), 720)?;
            if sectors < 8 {
                return Err(cx.invalid("wheel.zone_sectors", sectors, "at least 8 sectors"));
            }
            let pow2 = |a: usize, b: usize| a % b == 0 && (a / b).is_power_of_two();
            if !pow2(rim_nodes, sectors) {
                return Err(cx.invalid(
                    "wheel.rim_nodes",
                    rim_nodes,
                    &format!("with a refined zone: wheel.zone_sectors = {sectors} times a power of two (e.g. {}, {})", sectors, 2 * sectors),
                ));
            }
            let zn = cx.count("wheel.zone_rim_nodes", z, 100_000)?;
            if !pow2(zn, rim_nodes) {
                return Err(cx.invalid(
                    "wheel.zone_rim_nodes",
                    zn,
                    &format!("wheel.rim_nodes = {rim_nodes} times 1, 2, 4, 8, ... (the rim's pitch in the zone; times 1: the same mesh family without a zone)"),
                ));
            }
            let width = w.zone_width.unwrap_or(30.0);
            let min = 2.0 * 360.0 / sectors as f64;
            if !(width.is_finite() && width >= min && width <= 180.0) {
                return Err(cx.invalid(
                    "wheel.zone_width",
                    width,
                    &format!("the zone's arc of the rim in degrees, from two sectors ({min}) to 180"),
                ));
            }
            let depth = match w.zone_depth {
                None => None,
                Some(l) if l.is_finite() && l > 0.0 && l < radius - hub_radius => Some(l),
                Some(l) => {
                    return Err(cx.invalid(
                        "wheel.zone_depth",
                        l,
                        &format!("the depth (m) to which the zone keeps its pitch's scale, above 0 and below the rim's depth over the hub ({} m); about the contact's half-width", radius - hub_radius),
                    ))
                }
            };
            MeshSource::Zone(crate::mesh::zone::ZoneOptions {
                radius,
                hub_radius,
                sectors,
                rim_nodes,
                zone_rim_nodes: zn,
                zone_width: width.to_radians(),
                grading: 0.3,
                depth,
            })
        }
        (Some(z), _) => {
            return Err(cx.invalid(
                "wheel.zone_rim_nodes",
                z,
                "the refined zone is a generated mesh: give wheel.rim_nodes (the rim's pitch outside the zone), not wheel.rings or wheel.mesh",
            ))
        }
    })
}

/// The validated numbers of `[rolling]` (its `coupling` apart: [`coupling`]).
struct Rolling {
    /// `rolling.omega`, rad/s.
    omega: f64,
    /// `rolling.flattening` and `rolling.settle_time`.
    flattening: Flattening,
    /// `rolling.turns`.
    turns: f64,
    /// `rolling.settle_gamma`, if given.
    settle_gamma: Option<f64>,
    /// `rolling.creepage` (default 0).
    creepage: f64,
}

/// `[rolling]`: the speed, the flattening (below the wheel's `radius`) and its settling,
/// the turns, the settling's `gamma` and the creepage.
fn rolling(
    cx: &Ctx,
    r: &RawRolling,
    radius: f64,
    load: Option<f64>,
) -> Result<Rolling, ScenarioError> {
    let omega =
        match (r.omega, r.speed_km_h) {
            (Some(_), Some(v)) => return Err(cx.invalid(
                "rolling.speed_km_h",
                v,
                "given with rolling.omega: give one of them (speed_km_h = 3.6 omega wheel.radius)",
            )),
            (None, None) => {
                return Err(cx.missing(
                    "rolling.omega",
                    "the wheel's spin, rad/s (or rolling.speed_km_h, the rim's speed in km/h)",
                ))
            }
            (Some(omega), None) => omega,
            (None, Some(v)) => {
                if !(v.is_finite() && v > 0.0) {
                    return Err(cx.invalid(
                        "rolling.speed_km_h",
                        v,
                        "the rim's speed must be a finite number > 0, km/h",
                    ));
                }
                v / 3.6 / radius
            }
        };
    if !(omega.is_finite() && omega > 0.0) {
        return Err(cx.invalid(
            "rolling.omega",
            omega,
            "the wheel's angular speed must be a finite number > 0, rad/s",
        ));
    }
    let depth = match (r.flattening, load) {
        (Some(_), Some(p)) => {
            return Err(cx.invalid(
                "wheel.load",
                p,
                "given with rolling.flattening: the load sets the flattening (found by a static contact solve); give one of them",
            ))
        }
        (None, None) => {
            return Err(cx.missing(
                "rolling.flattening",
                "how far the base presses the wheel, m (or wheel.load, the wheel's load in N, which sets it)",
            ))
        }
        // Found when the model is built (crate::kinds::wheel::run::build).
        (None, Some(_)) => f64::NAN,
        (Some(d), None) => cx.positive("rolling.flattening", d)?,
    };
    // The contact counts a gap below 1e-9 R as closed (crate::bodies::wheel): a flattening within a
    // thousand of those is no press at all (the run ends with no contact force to analyse).
    if depth < 1e-6 * radius {
        return Err(cx.invalid(
            "rolling.flattening",
            depth,
            &format!(
                "the flattening must be at least 1e-6 wheel.radius = {:e} m (the contact's gap tolerance is 1e-9 of the radius: below that the wheel is not pressed)",
                1e-6 * radius
            ),
        ));
    }
    if depth >= radius {
        return Err(cx.invalid(
            "rolling.flattening",
            depth,
            &format!("the flattening must be smaller than wheel.radius = {radius} m"),
        ));
    }
    let settle_time = cx.non_negative("rolling.settle_time", r.settle_time)?;
    let turns = cx.positive("rolling.turns", r.turns)?;
    let settle_gamma = match r.settle_gamma {
        Some(g) if settle_time == 0.0 => return Err(cx.invalid(
            "rolling.settle_gamma",
            g,
            "gamma while settling, not used with rolling.settle_time = 0 (no settling): remove it",
        )),
        Some(g) => Some(cx.gamma("rolling.settle_gamma", g)?),
        None => None,
    };
    let creepage = r.creepage.unwrap_or(0.0);
    if !(creepage.is_finite() && creepage.abs() < 1.0) {
        return Err(cx.invalid(
            "rolling.creepage",
            creepage,
            "the creepage (omega rho - V)/(omega rho) must be a finite number between -1 and 1 \
             (railway creepages are below 0.01)",
        ));
    }
    Ok(Rolling {
        omega,
        flattening: Flattening { depth, settle_time },
        turns,
        settle_gamma,
        creepage,
    })
}

/// `rolling.coupling`: coupled (default) or uncoupled (Carter's twin disk).
fn coupling(cx: &Ctx, r: &RawRolling) -> Result<Coupling, ScenarioError> {
    Ok(match r.coupling.as_deref().unwrap_or("coupled") {
        "coupled" => Coupling::Coupled,
        "uncoupled" => Coupling::Uncoupled,
        o => {
            return Err(cx.invalid(
                "rolling.coupling",
                format!("\"{o}\""),
                "allowed: \"coupled\" (the elastic wheel on its rigid base), \"uncoupled\" (Carter's elastically similar bodies: a twin disk carries the tangential tractions)",
            ))
        }
    })
}

/// `wheel.contact_surface`: a gap per rim node (default) or per rim segment.
fn contact_surface(cx: &Ctx, w: &RawWheel) -> Result<ContactSurface, ScenarioError> {
    Ok(match w.contact_surface.as_deref().unwrap_or("nodes") {
        "nodes" => ContactSurface::Nodes,
        "segments" => ContactSurface::Segments,
        o => {
            return Err(cx.invalid(
                "wheel.contact_surface",
                format!("\"{o}\""),
                "allowed: \"nodes\" (a gap per rim node), \"segments\" (mortar-weighted gaps on the rim's segments)",
            ))
        }
    })
}
