//! Two wheels of a bogie on one rail (`vehicle.wheelbase`, [`softway::track::rolling`],
//! Two wheels): each carries its own static load, each lifts the rail under the other as
//! the beam on an elastic foundation does, and the rail's wear under the pair is twice one
//! wheel's, by every model of the wear.

mod common;

use softway::contact::Treatment;
use softway::growth::{PassRunner, SurfaceProfile};
use softway::kinds::track::growth::{RailSliding, Sliding, TrackPass, WearPatch};
use softway::run::RunOptions;
use softway::scenario::Scenario;
use softway::simulation::Simulation;
use softway::time::{Coriolis, Integrator};
use softway::track::rolling::{Vehicle, WheelOnTrack};
use softway::wear::{Archard, WearLaw};
use std::f64::consts::PI;
use std::path::Path;
use std::sync::atomic::AtomicBool;

/// 240 rim nodes (12 mm pitch), 20 m/s, 64 bays with 20 absorbing at each end, 0.45 s.
const RIM: usize = 240;
const SPEED: f64 = 20.0;
const BAYS: usize = 64;
const DURATION: f64 = 0.45;
const SETTLE: f64 = 0.05;
/// Four bays: the second wheel meets the sleepers in the first's phase.
const WHEELBASE: f64 = 2.4;

/// One step's record: time, each wheel's contact force and the rail's deflection under
/// each axle (the second's NaN with one wheel).
struct Rec {
    t: f64,
    force: [f64; 2],
    rail_w: [f64; 2],
}

fn roll(wheelbase: Option<f64>) -> Vec<Rec> {
    let track = common::absorbing_track(BAYS);
    let vehicle = Vehicle {
        unsprung_mass: 800.0,
        axle_load: 100e3,
        speed: SPEED,
        suspension_stiffness: 0.0,
        suspension_damping: 0.0,
        gravity: 9.81,
        settle: SETTLE,
        creepage: 0.0,
        wheelbase,
    };
    // Both runs start with the first wheel at the same place, the second wheel just past
    // the sponge.
    let start = 21.0 * track.spacing + WHEELBASE;
    let wheel = common::steel_wheel_at(RIM, SPEED);
    let wot = WheelOnTrack::new(wheel, &track, vehicle, start, None).unwrap();
    let pitch = 2.0 * PI * wot.rim_radius / RIM as f64;
    let h = pitch / SPEED / 3.0;
    let steps = (DURATION / h).round() as usize;
    let integrator = Integrator::SpaceTime {
        alpha: 0.8,
        gamma: 0.0,
        coriolis: Coriolis::Implicit,
    };
    let mut problem = wot.problem(integrator, h, steps);
    problem.treatment = Treatment::Exact;
    let mut sim = Simulation::new(problem).unwrap();
    let n = wot.rim_pairs();
    let mut recs = Vec::with_capacity(steps + 1);
    sim.run(&AtomicBool::new(false), |v| {
        let (t, u) = (v.state.t, &v.state.state.u);
        let (a, b) = v.state.pairs.split_at(n);
        let x = wot.under_axle(t);
        let second = |f: f64| if wheelbase.is_some() { f } else { f64::NAN };
        recs.push(Rec {
            t,
            force: [
                a.iter().map(|p| p.force).sum(),
                second(b.iter().map(|p| p.force).sum()),
            ],
            rail_w: [
                wot.rail_deflection(x, u).unwrap(),
                second(wot.rail_deflection(x - WHEELBASE, u).unwrap_or(f64::NAN)),
            ],
        });
        Ok(())
    })
    .unwrap();
    recs
}

/// The mean of `f` over the records in a whole number of sleeper bays from 0.15 s on.
fn bay_mean(recs: &[Rec], f: impl Fn(&Rec) -> f64) -> f64 {
    let bay = 0.6 / SPEED;
    let t0 = 0.15;
    let t1 = t0 + ((DURATION - t0) / bay).floor() * bay;
    let w: Vec<f64> = recs
        .iter()
        .filter(|r| r.t >= t0 && r.t < t1)
        .map(f)
        .collect();
    w.iter().sum::<f64>() / w.len() as f64
}

/// With a second wheel 2.4 m behind the first each wheel's mean contact force over whole
/// bays is its static load `F_axle + m_u g` (each axle's momentum balance), and the rail
/// under each axle sits higher than under a wheel alone by the other wheel's uplift: for the
/// beam on an elastic foundation (Winkler's; the supports smeared along the rail,
/// `k_f = (k_p k_b / (k_p + k_b)) / s`, `beta = (k_f / (4 E I))^(1/4)`) the deflection a
/// load makes at the distance `L` is `e^(-beta L) (cos beta L + sin beta L)` of the one
/// under it: -4.1 % at 2.4 m, an independent answer.
#[test]
fn two_wheels_carry_their_loads_and_lift_the_rail_under_each_other() {
    let one = roll(None);
    let two = roll(Some(WHEELBASE));
    let load = 100e3 + 800.0 * 9.81;
    for (k, name) in ["first", "second"].iter().enumerate() {
        let f = bay_mean(&two, |r| r.force[k]);
        println!(
            "{name} wheel: mean force {f:.1} N against the static load {load:.1} N ({:+.3} %)",
            100.0 * (f / load - 1.0)
        );
        assert!((f / load - 1.0).abs() < 5e-3, "{name}: {f} against {load}");
    }
    let track = common::absorbing_track(BAYS);
    let kf = track.pad_stiffness * track.ballast_stiffness
        / (track.pad_stiffness + track.ballast_stiffness)
        / track.spacing;
    let beta = (kf / (4.0 * track.section.young * track.section.inertia)).powf(0.25);
    let bl = beta * WHEELBASE;
    let winkler = (-bl).exp() * (bl.cos() + bl.sin());
    let alone = bay_mean(&one, |r| r.rail_w[0]);
    for (k, name) in ["first", "second"].iter().enumerate() {
        let w = bay_mean(&two, |r| r.rail_w[k]);
        let eta = w / alone - 1.0;
        println!(
            "rail under the {name} axle: {w:.4e} m against {alone:.4e} m alone: {:+.2} % (Winkler {:+.2} %)",
            100.0 * eta,
            100.0 * winkler
        );
        assert!(winkler < -0.02, "{winkler}");
        assert!(
            (eta / winkler - 1.0).abs() < 0.25,
            "{name}: {eta} against {winkler}"
        );
    }
}

/// The study's track and wheel, one wheel or two (`wheelbase`); `dynamic`: driving at 1 %
/// creepage with Coulomb friction (`mu = 0.3`) against the primary suspension, as
/// `scenarios/corrugation-friction.toml`, so that the rail wears by each rim node's own slip.
fn scenario(wheelbase: &str, dynamic: bool) -> Scenario {
    let (drive, friction, gamma) = if dynamic {
        (
            "creepage = 0.01\nsuspension_stiffness = 1e7\nsuspension_damping = 1.8e5",
            "friction = 0.3",
            0.2,
        )
    } else {
        ("", "", 0.0)
    };
    let text = format!(
        r#"
name = "rail-wear-two"
kind = "track"
[track]
set = "uic60"
bays = 48
end_bays = 12
elements_per_bay = 6
[vehicle]
model = "wheel"
unsprung_mass = 800.0
axle_load = 100e3
wheel_radius = 0.46
speed_km_h = 100.0
travel_bays = 4
settle_bays = 4
wheel_rim_nodes = 360
wheel_thickness = 0.02
{wheelbase}
{drive}
[contact]
method = "exact"
{friction}
[time]
alpha = 0.8
gamma = {gamma}
"#
    );
    let spec = Scenario::from_str(&text, Path::new("rail-wear-two.toml")).expect("scenario");
    softway::build::resolve(&spec).expect("built")
}

/// A flat rail's pass: the mean worn depth away from the grid's ends and the pass's
/// scalars.
fn flat_pass(
    sc: &Scenario,
    patch: WearPatch,
    sliding: Sliding,
) -> Result<(f64, Vec<(String, f64)>), String> {
    let law = WearLaw::Archard(Archard {
        k: 1e-4,
        hardness: 3e9,
        map: None,
    });
    let opts = RunOptions {
        progress: false,
        ..RunOptions::default()
    };
    let mut pass =
        TrackPass::new(sc, 1e-3, law, sliding, patch, opts).map_err(|e| e.to_string())?;
    let (x0, dx, n, _) = pass.grid();
    let flat = SurfaceProfile {
        x0,
        dx,
        z: vec![0.0; n],
        periodic: false,
    };
    let r = pass
        .run_pass(&flat, 0, &AtomicBool::new(false))
        .map_err(|e| e.to_string())?;
    let inner = pass.inner();
    let inner = inner.start + 20..inner.end - 20;
    let d = &r.wear_depth[inner];
    Ok((d.iter().sum::<f64>() / d.len() as f64, r.scalars))
}

const STEADY: Sliding = Sliding::Steady(RailSliding {
    creepage: 0.01,
    traction_coefficient: 0.2,
    density: 7850.0,
});

fn scalar(scalars: &[(String, f64)], key: &str) -> f64 {
    scalars
        .iter()
        .find(|(k, _)| k == key)
        .unwrap_or_else(|| panic!("no {key} in {scalars:?}"))
        .1
}

/// A bogie's pass wears the rail twice as deep as one wheel's (Archard's wear is linear in
/// the force, and each wheel carries its static load), by each model of the wear: the
/// steady creepage on Hertz's patch and on the rim nodes' own, and each node's own
/// friction in the run (each wheel then in full slip, its traction `mu` times its force).
#[test]
fn a_second_wheel_doubles_the_rails_wear_by_every_model() {
    for patch in [WearPatch::Hertz, WearPatch::Nodes] {
        let (one, _) = flat_pass(&scenario("", false), patch, STEADY).unwrap();
        let (two, s) = flat_pass(&scenario("wheelbase = 2.5", false), patch, STEADY).unwrap();
        println!(
            "steady, {patch:?}: mean worn depth one wheel {one:.4e} m, two {two:.4e} m: {:.4}x",
            two / one
        );
        assert!(
            (two / one - 2.0).abs() < 0.01,
            "{patch:?}: {two} against {one}"
        );
        let (f1, f2) = (
            scalar(&s, "mean_force_n"),
            scalar(&s, "trailing_mean_force_n"),
        );
        assert!((f2 / f1 - 1.0).abs() < 0.01, "{f1} {f2}");
    }
    let dynamic = Sliding::Dynamic { density: 7850.0 };
    for patch in [WearPatch::Hertz, WearPatch::Nodes] {
        let (one, s1) = flat_pass(&scenario("", true), patch, dynamic).unwrap();
        let (two, s) = flat_pass(&scenario("wheelbase = 2.5", true), patch, dynamic).unwrap();
        let (q1, q2) = (
            scalar(&s, "traction_ratio"),
            scalar(&s, "trailing_traction_ratio"),
        );
        let (f1, f2) = (
            scalar(&s, "mean_force_n"),
            scalar(&s, "trailing_mean_force_n"),
        );
        println!(
            "dynamic, {patch:?}: mean worn depth one wheel {one:.4e} m, two {two:.4e} m: {:.4}x; Q/P {q1:.5} / {q2:.5}, P {f1:.1} / {f2:.1} N (one wheel {:.1})",
            two / one,
            scalar(&s1, "mean_force_n")
        );
        // Full slip under both wheels: the traction is mu P, the wear Archard's on it.
        for q in [q1, q2, scalar(&s1, "traction_ratio")] {
            assert!((q / 0.3 - 1.0).abs() < 0.01, "{q}");
        }
        let expected = (f1 + f2) / scalar(&s1, "mean_force_n");
        assert!(
            (two / one / expected - 1.0).abs() < 0.02,
            "{patch:?}: {two} against {one} (expected {expected}x)"
        );
    }
}

/// The second wheel's key is refused where it has no meaning or no room, naming the file
/// and the key.
#[test]
fn the_wheelbase_is_refused_without_room_or_a_wheel() {
    let dir = std::env::temp_dir().join(format!("softway-two-wheels-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let track =
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/scenarios/track.toml"))
            .unwrap();
    let cases = [
        (
            "no-room.toml",
            track.replace("[vehicle]\n", "[vehicle]\nwheelbase = 30.0\n"),
            "vehicle.wheelbase",
        ),
        (
            "negative.toml",
            track.replace("[vehicle]\n", "[vehicle]\nwheelbase = -2.5\n"),
            "vehicle.wheelbase",
        ),
        (
            "moving.toml",
            track
                .replace("model = \"wheel\"", "model = \"moving_load\"")
                .lines()
                .filter(|l| !l.starts_with("wheel_") && !l.starts_with("settle_bays"))
                .map(|l| format!("{l}\n"))
                .collect::<String>()
                .replace("[vehicle]\n", "[vehicle]\nwheelbase = 2.5\n"),
            "vehicle.wheelbase",
        ),
    ];
    for (name, text, key) in cases {
        let f = dir.join(name);
        std::fs::write(&f, text).unwrap();
        let out = std::process::Command::new(env!("CARGO_BIN_EXE_softway"))
            .args([
                "run",
                f.to_str().unwrap(),
                "--out",
                dir.join("o").to_str().unwrap(),
            ])
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{name}: {err}");
        assert!(err.contains(name) && err.contains(key), "{name}: {err}");
        assert!(!dir.join("o").join("summary.json").exists());
    }
    let _ = std::fs::remove_dir_all(&dir);
}
