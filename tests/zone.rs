//! The moving refined zone (`wheel.zone_rim_nodes`; the paper's Fig. 4b): its relocation is
//! an exact relabelling where the mesh does not change, and with a zone the rolling wheel
//! reaches the answer of the uniformly refined rim of the same mesh family with under half
//! its unknowns.
//!
//! Measured (scenarios/wheel.toml's wheel on the zone family, one turn after settling, 89
//! relocations): uniform rims of 144 / 288 / 576 / 1152 nodes give 842.58 / 836.50 / 834.75 /
//! 833.86 kN; a 144-node rim with a 576-node zone gives 835.07 kN on 5,688 dofs against
//! 12,672, with the same ripple (max - min 1.90 against 1.84 kN), and with a 1152-node zone
//! 834.18 kN on 6,646 dofs against 22,752 (0.82 against 0.81 kN).

mod common;

use softway::build::resolve;
use softway::run::{run_scenario, RunOptions};
use softway::scenario::Scenario;
use softway::simulation::{Relocation, Simulation};
use std::sync::atomic::AtomicBool;

/// scenarios/wheel.toml on the zone family: `rim_nodes` outside the zone, `zone` inside,
/// `turns` after settling.
fn scenario(rim_nodes: usize, zone: usize, turns: f64) -> Scenario {
    let (rim_nodes, zone, turns) = (rim_nodes.to_string(), zone.to_string(), turns.to_string());
    let (path, text) = common::shipped(
        "wheel",
        &[
            ("wheel.rim_nodes", &rim_nodes),
            ("wheel.zone_rim_nodes", &zone),
            ("rolling.turns", &turns),
            ("output.plots", "false"),
        ],
    );
    resolve(&Scenario::from_str(&text, &path).unwrap()).unwrap()
}

/// The contact force at every step of `sim`'s run, and its counters.
fn contact_forces(sim: &mut Simulation) -> (Vec<f64>, softway::simulation::RunStats) {
    let mut f = Vec::new();
    let stats = sim
        .run(&AtomicBool::new(false), |s| {
            f.push(s.contact_force);
            Ok(())
        })
        .unwrap();
    (f, stats)
}

/// On a mesh of the family without a zone (the same pitch everywhere) every node has a node
/// one sector ahead: a relocation turns the frame by one sector and relabels the state, the
/// pairs' states and the base exactly. The run with relocations gives the contact force of
/// the run without them at every step (to round-off), through settling, arrivals, holds and
/// releases.
#[test]
fn relocation_without_a_zone_is_an_exact_relabelling() {
    let sc = scenario(144, 144, 0.05);
    let run = &sc.runs[0];
    let Some(ws) = run.model.get::<softway::scenario::WheelScenario>() else {
        panic!("a wheel")
    };
    let wm = softway::kinds::wheel::run::build(ws, &sc.path).unwrap();
    let (sources, step) = wm.zone.clone().unwrap();
    let steps = 3_000;
    let forces = |relocate: bool| {
        let pb = wm.problem(run.integrator, run.params.h, vec![], run.contact, steps);
        let mut sim = Simulation::new(pb).unwrap();
        if relocate {
            sim.set_relocation(Relocation {
                sources: sources.clone(),
                step,
                omega: ws.spec.omega,
                angle0: 0.0,
                turned: sources.len(),
            })
            .unwrap();
        }
        contact_forces(&mut sim)
    };
    let (plain, s0) = forces(false);
    let (moved, s1) = forces(true);
    assert_eq!(s0.relocations, 0);
    assert!(s1.relocations >= 15, "{s1:?}");
    assert!(s1.brakings > 10 && s1.releases > 10, "{s1:?}");
    let scale = plain.iter().cloned().fold(0.0, f64::max);
    assert!(scale > 1e5, "{scale}");
    let worst = plain
        .iter()
        .zip(&moved)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    eprintln!("worst {worst} N of {scale} N, {s1:?}");
    assert!(worst < 1e-7 * scale, "worst {worst} N of {scale} N");
}

/// The same with the wheel in large deformation (the hyperelastic force of
/// `softway::finite`, its state the last two steps' nodal forces): a relocation turns the
/// mesh by one of its symmetries, under which the nonlinear force `K u - f_int(u)` turns
/// with the nodes, so the relabelled state is the state of the turned wheel. The contact
/// force with and without relocations agrees to round-off, through arrivals, holds and
/// releases, with the same corrections of the iteration: its predictions (the last two
/// steps' forces) are relabelled too. Left unrelabelled they start the iteration elsewhere:
/// 90 corrections more over the run and the force apart by 1.8e-10 of its peak, against
/// 7e-14 relabelled. A plastic body's element states are still refused.
#[test]
fn relocation_in_large_deformation_is_a_relabelling_to_the_iterations_tolerance() {
    // The wheel of the large-deformation run (no linear stress stiffening).
    let (path, text) = common::shipped(
        "wheel",
        &[
            ("wheel.rim_nodes", "144"),
            ("wheel.zone_rim_nodes", "144"),
            ("rolling.turns", "0.05"),
            ("material.geometry", "\"large\""),
            ("output.plots", "false"),
        ],
    );
    let sc = resolve(&Scenario::from_str(&text, &path).unwrap()).unwrap();
    let run = &sc.runs[0];
    let Some(ws) = run.model.get::<softway::scenario::WheelScenario>() else {
        panic!("a wheel")
    };
    let wm = softway::kinds::wheel::run::build(ws, &sc.path).unwrap();
    let (sources, step) = wm.zone.clone().unwrap();
    let steps = 3_000;
    let tol = 1e-9;
    let large = ws.large.unwrap();
    let body = || Box::new(softway::kinds::wheel::large::finite_body(&wm, large));
    let relocation = || Relocation {
        sources: sources.clone(),
        step,
        omega: ws.spec.omega,
        angle0: 0.0,
        turned: sources.len(),
    };
    let forces = |relocate: bool, force_first: bool| {
        let pb = wm.problem(run.integrator, run.params.h, vec![], run.contact, steps);
        let mut sim = Simulation::new(pb).unwrap();
        // Either order of setting the zone and the force is accepted.
        if relocate && !force_first {
            sim.set_relocation(relocation()).unwrap();
        }
        sim.set_internal_force(body(), tol, 200).unwrap();
        if relocate && force_first {
            sim.set_relocation(relocation()).unwrap();
        }
        let (f, stats) = contact_forces(&mut sim);
        let nl = sim.nonlinear().map(|n| n.stats()).unwrap();
        (f, stats, nl)
    };
    let (plain, s0, n0) = forces(false, true);
    let (moved, s1, n1) = forces(true, true);
    let (moved2, _, _) = forces(true, false);
    assert_eq!(s0.relocations, 0);
    assert!(s1.relocations >= 15, "{s1:?}");
    assert!(s1.brakings > 10 && s1.releases > 10, "{s1:?}");
    assert_eq!((n0.unconverged, n1.unconverged), (0, 0), "{n0:?} {n1:?}");
    let scale = plain.iter().cloned().fold(0.0, f64::max);
    assert!(scale > 1e5, "{scale}");
    let worst = |other: &[f64]| {
        plain
            .iter()
            .zip(other)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max)
    };
    let (w1, w2) = (worst(&moved), worst(&moved2));
    eprintln!("worst {w1} / {w2} N of {scale} N, {s1:?}, {n0:?} {n1:?}");
    assert!(
        w1 < 1e-12 * scale && w2 < 1e-12 * scale,
        "worst {w1} / {w2} N of {scale} N"
    );
    assert_eq!(n0.iterations, n1.iterations, "{n0:?} {n1:?}");
    // The force's state is what makes it movable: a plastic body's is refused.
    let pb = wm.problem(run.integrator, run.params.h, vec![], run.contact, steps);
    let mut sim = Simulation::new(pb).unwrap();
    sim.set_relocation(relocation()).unwrap();
    let plastic = softway::plasticity::PlasticBody::new(
        softway::plasticity::J2Material {
            elastic: wm.spec.material,
            yield_stress: 3e8,
            isotropic: softway::plasticity::Isotropic {
                modulus: 0.0,
                voce_q: 0.0,
                voce_b: 0.0,
            },
            kinematic: softway::plasticity::Kinematic { c: 0.0, gamma: 0.0 },
        },
        wm.spec.plane,
        wm.spec.thickness,
        wm.triangles.clone(),
        wm.geometry.clone(),
    );
    let err = sim
        .set_internal_force(Box::new(plastic), 1e-6, 200)
        .unwrap_err();
    assert!(err.to_string().contains("element states"), "{err}");
}

/// A 144-node rim refined to 576 nodes in a zone of 30 degrees that follows the contact
/// reaches the mean force of the uniform 576-node rim within 0.2 % with the same
/// node-passing ripple (within 50 %), on less than half the unknowns, and the relocations
/// (a few hundredths of the nodes interpolated each) keep the energy to 1e-5.
#[test]
fn a_moving_zone_reaches_the_uniformly_refined_rim_with_fewer_unknowns() {
    let summary = |rim: usize, zone: usize| {
        let dir =
            std::env::temp_dir().join(format!("softway-zone-{}-{rim}-{zone}", std::process::id()));
        run_scenario(&scenario(rim, zone, 0.25), &dir, &RunOptions::default()).unwrap();
        let s: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap())
                .unwrap();
        std::fs::remove_dir_all(&dir).ok();
        s
    };
    let uniform = summary(576, 576);
    let zone = summary(144, 576);
    let f = |s: &serde_json::Value, k: &str| s[k].as_f64().unwrap();
    let (mu, mz) = (
        f(&uniform, "mean_contact_force"),
        f(&zone, "mean_contact_force"),
    );
    let ripple = |s: &serde_json::Value| f(s, "max_contact_force") - f(s, "min_contact_force");
    eprintln!(
        "uniform: {mu} N, ripple {} N, {} dofs; zone: {mz} N, ripple {} N, {} dofs, {} relocations",
        ripple(&uniform),
        f(&uniform, "dofs"),
        ripple(&zone),
        f(&zone, "dofs"),
        f(&zone, "relocations")
    );
    assert!((mz / mu - 1.0).abs() < 2e-3, "{mz} vs {mu}");
    assert!(ripple(&zone) < 1.5 * ripple(&uniform));
    assert!(f(&zone, "dofs") < 0.5 * f(&uniform, "dofs"));
    assert!(f(&zone, "relocations") > 30.0);
    let drift = f(&zone, "energy_final") / f(&zone, "energy_after_settling") - 1.0;
    assert!(drift.abs() < 1e-5, "{drift}");
    // Both meshes clamp the same hub.
    assert_eq!(
        f(&zone, "support_radius_m"),
        f(&uniform, "support_radius_m")
    );
}

/// The zone's keys are checked: a rim that is not the sectors times a power of two, a zone
/// pitch that is not the rim's times one, a zone with the uncoupled problem, a depth that is
/// not a length, or a pinned centre.
#[test]
fn zone_keys_are_checked() {
    let with = |pairs: &[(&str, &str)]| {
        let (path, t) = common::shipped("wheel", pairs);
        Scenario::from_str(&t, &path)
            .and_then(|s| resolve(&s))
            .map(|_| ())
            .unwrap_err()
            .to_string()
    };
    let e = with(&[("wheel.rim_nodes", "100"), ("wheel.zone_rim_nodes", "400")]);
    assert!(
        e.contains("wheel.rim_nodes") && e.contains("power of two"),
        "{e}"
    );
    let e = with(&[("wheel.rim_nodes", "144"), ("wheel.zone_rim_nodes", "500")]);
    assert!(e.contains("wheel.zone_rim_nodes"), "{e}");
    let e = with(&[
        ("wheel.rim_nodes", "144"),
        ("wheel.zone_rim_nodes", "576"),
        ("contact.friction", "0.3"),
        ("rolling.coupling", "\"uncoupled\""),
    ]);
    assert!(e.contains("uncoupled"), "{e}");
    let e = with(&[
        ("wheel.rim_nodes", "144"),
        ("wheel.zone_rim_nodes", "576"),
        ("wheel.zone_depth", "-1e-3"),
    ]);
    assert!(e.contains("wheel.zone_depth"), "{e}");
    let e = with(&[("wheel.zone_depth", "1e-3")]);
    assert!(e.contains("wheel.zone_rim_nodes"), "{e}");
    let e = with(&[
        ("wheel.rim_nodes", "144"),
        ("wheel.zone_rim_nodes", "576"),
        ("wheel.support", "\"centre\""),
    ]);
    assert!(e.contains("support"), "{e}");
    let e = with(&[("wheel.zone_width", "30")]);
    assert!(e.contains("wheel.zone_rim_nodes"), "{e}");
}

/// Through the command line, a short zone run (plots on) writes the wheel's outputs but the
/// per-element turn averages, which a relabelling of the nodes has no meaning for: no J2 maps,
/// `null` for their maxima, and its relocations in `summary.json`.
#[test]
fn a_zone_run_writes_its_outputs_without_turn_averages() {
    let (_, text) = common::shipped(
        "wheel-zone",
        &[
            ("wheel.zone_rim_nodes", "288"),
            ("rolling.turns", "0.02"),
            ("rolling.settle_time", "1e-3"),
        ],
    );
    let sc = common::scenario("zone-cli", &text);
    let out = sc.with_extension("out");
    let o = common::cli([
        "run".as_ref(),
        sc.as_os_str(),
        "--out".as_ref(),
        out.as_os_str(),
        "--quiet".as_ref(),
    ]);
    assert_eq!(o.code, 0, "{}", o.stderr);
    for f in [
        "summary.json",
        "history.csv",
        "contact_force.png",
        "spectrum.png",
    ] {
        assert!(out.join(f).is_file(), "{f}");
    }
    for f in [
        "j2_turn_average.png",
        "j2_turn_average.vtu",
        "j2_rim_profile.png",
    ] {
        assert!(!out.join(f).exists(), "{f}");
    }
    let s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert!(s["max_j2_turn_average_mpa2"].is_null(), "{s}");
    assert!(s["relocations"].as_u64().unwrap() >= 3, "{s}");
    std::fs::remove_dir_all(sc.parent().unwrap()).ok();
}

/// scenarios/creep-curve.toml (mu = 0.3, the 4 cm hub) on the zone family: `rim_nodes`
/// outside the zone, `zone` inside, at creepage `xi`, `turns` after settling.
fn creep_scenario(rim_nodes: usize, zone: usize, xi: f64, turns: f64) -> Scenario {
    let (rim_nodes, zone, xi, turns) = (
        rim_nodes.to_string(),
        zone.to_string(),
        xi.to_string(),
        turns.to_string(),
    );
    let (path, text) = common::shipped(
        "creep-curve",
        &[
            ("wheel.rim_nodes", &rim_nodes),
            ("wheel.zone_rim_nodes", &zone),
            ("rolling.creepage", &xi),
            ("rolling.turns", &turns),
            ("output.plots", "false"),
        ],
    );
    resolve(&Scenario::from_str(&text, &path).unwrap()).unwrap()
}

/// With friction the relocation carries the pairs' tangential states as it carries the
/// normal ones: on a mesh of the family without a zone the driven wheel (creepage 1 %,
/// stick and slip in the patch) gives, with and without relocations, the same contact
/// force, the same creep force and the same friction energy at every step (to round-off),
/// through settling, arrivals, stick/slip changes and releases.
#[test]
fn relocation_with_friction_is_an_exact_relabelling() {
    let sc = creep_scenario(144, 144, 0.01, 0.05);
    let run = &sc.runs[0];
    let Some(ws) = run.model.get::<softway::scenario::WheelScenario>() else {
        panic!("a wheel")
    };
    let wm = softway::kinds::wheel::run::build(ws, &sc.path).unwrap();
    let (sources, step) = wm.zone.clone().unwrap();
    let steps = 3_000;
    let series = |relocate: bool| {
        let mut pb = wm.problem(run.integrator, run.params.h, vec![], run.contact, steps);
        pb.friction = run.friction;
        let mut sim = Simulation::new(pb).unwrap();
        if relocate {
            sim.set_relocation(Relocation {
                sources: sources.clone(),
                step,
                omega: ws.spec.omega,
                angle0: 0.0,
                turned: sources.len(),
            })
            .unwrap();
        }
        let mut f = Vec::new();
        let stats = sim
            .run(&AtomicBool::new(false), |s| {
                let q: f64 = s.state.pairs.iter().map(|p| p.tangential_force).sum();
                let slipping = s.state.pairs.iter().filter(|p| p.held && p.sliding).count();
                f.push((s.contact_force, q, s.friction_dissipated, slipping));
                Ok(())
            })
            .unwrap();
        (f, stats)
    };
    let (plain, s0) = series(false);
    let (moved, s1) = series(true);
    assert_eq!(s0.relocations, 0);
    assert!(s1.relocations >= 15, "{s1:?}");
    assert!(s1.brakings > 10 && s1.releases > 10, "{s1:?}");
    assert!(s1.stick_slip_changes > 10, "{s1:?}");
    let last = plain.last().unwrap();
    let (scale_n, scale_t, energy) = (
        plain.iter().map(|x| x.0).fold(0.0, f64::max),
        plain.iter().map(|x| x.1.abs()).fold(0.0, f64::max),
        last.2,
    );
    assert!(scale_t > 0.1 * 0.3 * scale_n, "{scale_t} of {scale_n}");
    let slipping = plain.iter().map(|x| x.3).max().unwrap_or(0);
    assert!(
        energy > 0.0 && slipping > 0,
        "{last:?}, {slipping} slipping"
    );
    let worst = |k: fn(&(f64, f64, f64, usize)) -> f64| {
        plain
            .iter()
            .zip(&moved)
            .map(|(a, b)| (k(a) - k(b)).abs())
            .fold(0.0, f64::max)
    };
    let (wn, wt, we) = (worst(|x| x.0), worst(|x| x.1), worst(|x| x.2));
    eprintln!(
        "worst: normal {wn} N of {scale_n}, tangential {wt} N of {scale_t}, friction energy {we} J of {energy}; {s1:?}"
    );
    assert!(wn < 1e-7 * scale_n, "normal {wn} N of {scale_n} N");
    assert!(wt < 1e-7 * scale_t, "tangential {wt} N of {scale_t} N");
    assert!(we < 1e-7 * energy, "friction energy {we} J of {energy} J");
    assert!(plain.iter().zip(&moved).all(|(a, b)| a.3 == b.3));
}

/// With friction in the zone: a 144-node rim refined to 576 nodes in the moving zone gives
/// the creep force of the uniform 576-node rim within 1 % (driven at 1 %, partial slip),
/// and the friction energy carried through the relocations within 2 %.
#[test]
fn a_moving_zone_with_friction_gives_the_creep_force_of_the_fine_rim() {
    let summary = |rim: usize, zone: usize| {
        let dir = std::env::temp_dir().join(format!(
            "softway-zone-creep-{}-{rim}-{zone}",
            std::process::id()
        ));
        let sc = creep_scenario(rim, zone, 0.01, 0.1);
        run_scenario(&sc, &dir, &RunOptions::default()).unwrap();
        let s: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap())
                .unwrap();
        std::fs::remove_dir_all(&dir).ok();
        // `rolling.omega` of scenarios/creep-curve.toml: 300 rad/s.
        common::assert_dissipates(&s["traction"], 300.0, sc.runs[0].params.h);
        s
    };
    let uniform = summary(576, 576);
    let zone = summary(144, 576);
    let t = |s: &serde_json::Value, k: &str| s["traction"][k].as_f64().unwrap();
    let (qu, qz) = (t(&uniform, "traction"), t(&zone, "traction"));
    let (eu, ez) = (t(&uniform, "friction_energy"), t(&zone, "friction_energy"));
    eprintln!(
        "uniform 576: Q {qu} N (Q/mu P {}), friction energy {eu} J, {} dofs; zone: Q {qz} N ({}), {ez} J, {} dofs, {} relocations",
        t(&uniform, "traction_ratio"),
        uniform["dofs"],
        t(&zone, "traction_ratio"),
        zone["dofs"],
        zone["relocations"]
    );
    assert!(zone["relocations"].as_f64().unwrap() > 10.0);
    assert!(qu > 0.2 * 0.3 * t(&uniform, "normal"), "{qu}");
    assert!((qz / qu - 1.0).abs() < 0.01, "{qz} vs {qu}");
    assert!((ez / eu - 1.0).abs() < 0.02, "{ez} vs {eu}");
}
