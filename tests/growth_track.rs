//! The rail's side of a growth study ([`softway::kinds::track::growth`]): one pass of the wheel
//! over the track lays the wear the continuum predicts.

use softway::growth::{PassRunner, SurfaceProfile};
use softway::kinds::track::growth::{predicted_growth, RailSliding, Sliding, TrackPass, WearPatch};
use softway::kinds::track::polygon::WheelTrackPass;
use softway::run::RunOptions;
use softway::scenario::Scenario;
use softway::wear::{Archard, WearLaw};
use std::f64::consts::PI;
use std::path::Path;
use std::sync::atomic::AtomicBool;

fn scenario(speed_km_h: f64, travel_bays: usize) -> Scenario {
    let text = format!(
        r#"
name = "rail-wear"
kind = "track"
[track]
set = "uic60"
bays = 40
end_bays = 12
elements_per_bay = 6
[vehicle]
model = "wheel"
unsprung_mass = 800.0
axle_load = 100e3
wheel_radius = 0.46
speed_km_h = {speed_km_h}
travel_bays = {travel_bays}
settle_bays = 4
wheel_rim_nodes = 720
wheel_thickness = 0.02
[contact]
method = "exact"
[time]
alpha = 0.8
gamma = 0.0
"#
    );
    let spec = Scenario::from_str(&text, Path::new("rail-wear.toml")).expect("scenario");
    softway::build::resolve(&spec).expect("built")
}

/// The amplitude of `v`'s harmonic of wavelength `lambda` (m), sampled at `dx`, its mean
/// removed (a least-squares fit of a sine and a cosine).
fn amplitude(v: &[f64], dx: f64, lambda: f64) -> f64 {
    let m = v.iter().sum::<f64>() / v.len() as f64;
    let k = 2.0 * std::f64::consts::PI / lambda;
    let (mut c, mut s, mut cc, mut ss) = (0.0, 0.0, 0.0, 0.0);
    for (i, &x) in v.iter().enumerate() {
        let (si, co) = (k * i as f64 * dx).sin_cos();
        c += (x - m) * co;
        s += (x - m) * si;
        cc += co * co;
        ss += si * si;
    }
    ((c / cc).powi(2) + (s / ss).powi(2)).sqrt()
}

/// The largest relative amplitude of `v` over the wavelengths 9-35 mm (the corrugation
/// band and below it).
fn short_content(v: &[f64], dx: f64) -> f64 {
    let m = v.iter().sum::<f64>() / v.len() as f64;
    (0..60)
        .map(|i| 9e-3 * (35.0f64 / 9.0).powf(i as f64 / 59.0))
        .map(|l| amplitude(v, dx, l) / m)
        .fold(0.0, f64::max)
}

struct Pass {
    depth: Vec<f64>,
    force_at: Vec<f64>,
    mean_force: f64,
    dx: f64,
}

fn one_pass(patch: WearPatch, law: WearLaw, gamma: f64) -> Pass {
    let sc = scenario(100.0, 4);
    let sliding = Sliding::Steady(RailSliding {
        creepage: gamma,
        traction_coefficient: 0.2,
        density: 7850.0,
    });
    let opts = RunOptions {
        progress: false,
        ..RunOptions::default()
    };
    let mut pass = TrackPass::new(&sc, 1e-3, law, sliding, patch, opts).expect("pass");
    let (x0, dx, n, periodic) = pass.grid();
    assert!(!periodic);
    let flat = SurfaceProfile {
        x0,
        dx,
        z: vec![0.0; n],
        periodic: false,
    };
    let r = pass
        .run_pass(&flat, 0, &AtomicBool::new(false))
        .expect("pass runs");
    let scalar = |name: &str| {
        r.scalars
            .iter()
            .find(|(k, _)| k == name)
            .map(|(_, v)| *v)
            .unwrap()
    };
    // The inner grid, less two patch lengths at its start (the passage begins with the
    // patch on the grid's first point).
    let inner = pass.inner();
    let inner = inner.start + 20..inner.end - 20;
    // The force when the axle was over each point of the grid.
    let trace = pass.last_force();
    let force_at = inner
        .clone()
        .map(|j| {
            let x = x0 + j as f64 * dx;
            let i = trace
                .partition_point(|&(xt, _)| xt < x)
                .clamp(1, trace.len() - 1);
            let ((xa, fa), (xb, fb)) = (trace[i - 1], trace[i]);
            fa + (fb - fa) * (x - xa) / (xb - xa)
        })
        .collect();
    Pass {
        depth: r.wear_depth[inner].to_vec(),
        force_at,
        mean_force: scalar("mean_force_n"),
        dx,
    }
}

/// Archard's law over a flat rail: a rail point's worn depth over a pass is the
/// continuum's `k gamma P / (H w)` (module docs of `growth::track`), as a mean over the
/// passage against the mean contact force and point by point against the force when the
/// axle was over it; the nodal wear carries a ripple at 9-35 mm the force does not have.
#[test]
fn a_pass_wears_the_rail_as_the_continuum_under_the_force_it_carries() {
    let (k, hard, gamma, w) = (1e-4, 3e9, 0.01, 0.02);
    let law = WearLaw::Archard(Archard {
        k,
        hardness: hard,
        map: None,
    });
    let hz = one_pass(WearPatch::Hertz, law, gamma);
    let scale = k * gamma / (hard * w);
    let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len() as f64;
    let mean_depth = mean(&hz.depth);
    let continuum = scale * hz.mean_force;
    println!(
        "hertz: mean depth {mean_depth:.4e} m against k gamma P / (H w) = {continuum:.4e} m ({:+.3}%)",
        100.0 * (mean_depth / continuum - 1.0)
    );
    assert!((mean_depth / continuum - 1.0).abs() < 0.005);
    // Point by point: the depth is the force at that point through the patch's filter
    // (10 mm long), which passes the force's content at long wavelengths; both smoothed
    // over 12 mm (the node-passing ripple of the force, 4 mm, is the patch's to filter).
    let smooth = |v: &[f64]| -> Vec<f64> {
        let m = 6;
        (m..v.len() - m)
            .map(|i| v[i - m..=i + m].iter().sum::<f64>() / (2 * m + 1) as f64)
            .collect()
    };
    let (sd, sf) = (smooth(&hz.depth), smooth(&hz.force_at));
    let diff: Vec<f64> = sd
        .iter()
        .zip(&sf)
        .map(|(d, f)| d / (scale * f) - 1.0)
        .collect();
    let rms = (diff.iter().map(|e| e * e).sum::<f64>() / diff.len() as f64).sqrt();
    let fstd = {
        let m = mean(&sf);
        (sf.iter().map(|f| (f / m - 1.0).powi(2)).sum::<f64>() / sf.len() as f64).sqrt()
    };
    let (d_short, f_short) = (
        short_content(&hz.depth, hz.dx),
        short_content(&hz.force_at, hz.dx),
    );
    println!(
        "hertz: depth against the force there: rms {rms:.2e} (the force's own rms variation {fstd:.2e}); 9-35 mm content: depth {d_short:.2e}, force {f_short:.2e}"
    );
    assert!(rms < 0.2 * fstd, "{rms} against {fstd}");
    assert!(
        d_short < 1.5 * f_short + 1e-4,
        "{d_short} against {f_short}"
    );

    let nodes = one_pass(WearPatch::Nodes, law, gamma);
    let nd = mean(&nodes.depth);
    let n_short = short_content(&nodes.depth, nodes.dx);
    println!(
        "nodes: mean depth {nd:.4e} m ({:+.3}%); 9-35 mm content {n_short:.2e}",
        100.0 * (nd / (scale * nodes.mean_force) - 1.0)
    );
    assert!((nd / (scale * nodes.mean_force) - 1.0).abs() < 0.01);
}

/// The linear growth of the rail's roughness from the time-domain passes against the
/// frequency-domain prediction from the receptances ([`predicted_growth`]), an independent
/// computation: a flat pass and a pass over a sum of 48 harmonics of 1 um at random phases
/// (10-400 mm); the difference of their wear, projected on each harmonic, is the wear in
/// phase and in quadrature per unit of its amplitude.
#[test]
fn the_rails_linear_growth_follows_the_receptances() {
    let sc = scenario(100.0, 8);
    let law = WearLaw::Archard(Archard {
        k: 1e-4,
        hardness: 3e9,
        map: None,
    });
    let sliding = Sliding::Steady(RailSliding {
        creepage: 0.01,
        traction_coefficient: 0.2,
        density: 7850.0,
    });
    let opts = RunOptions {
        progress: false,
        ..RunOptions::default()
    };
    let mut pass = TrackPass::new(&sc, 1e-3, law, sliding, WearPatch::Hertz, opts).unwrap();
    let (x0, dx, n, _) = pass.grid();
    let stop = AtomicBool::new(false);
    let flat = SurfaceProfile {
        x0,
        dx,
        z: vec![0.0; n],
        periodic: false,
    };
    let r0 = pass.run_pass(&flat, 0, &stop).unwrap();
    let scalar = |name: &str| {
        r0.scalars
            .iter()
            .find(|(k, _)| k == name)
            .map(|(_, v)| *v)
            .unwrap()
    };
    let (force, k_c) = (scalar("mean_force_n"), scalar("contact_stiffness_n_m"));
    let m = 48;
    let lams: Vec<f64> = (0..m)
        .map(|i| 0.010 * 40f64.powf(i as f64 / (m - 1) as f64))
        .collect();
    // Phases from a fixed linear congruential sequence.
    let mut state = 12345u64;
    let phases: Vec<f64> = (0..m)
        .map(|_| {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            2.0 * PI * ((state >> 11) as f64 / (1u64 << 53) as f64)
        })
        .collect();
    let amp = 1e-6;
    let z: Vec<f64> = (0..n)
        .map(|j| {
            let x = j as f64 * dx;
            (0..m)
                .map(|i| amp * (2.0 * PI * x / lams[i] + phases[i]).sin())
                .sum()
        })
        .collect();
    let rough = SurfaceProfile {
        x0,
        dx,
        z,
        periodic: false,
    };
    let r1 = pass.run_pass(&rough, 1, &stop).unwrap();
    let inner = pass.inner();
    let mean_depth = r0.wear_depth[inner.clone()].iter().sum::<f64>() / inner.len() as f64;
    let track = pass.track().spec.build().unwrap();
    let a = pass.patch_of(force).a;
    let pred = predicted_growth(
        &track,
        (pass.track().vehicle.unsprung_mass, k_c),
        pass.speed(),
        a,
        mean_depth / force,
        &lams,
    )
    .unwrap();
    let (mut d2, mut p2, mut q2, mut qp2, mut agree, mut growing) = (0.0, 0.0, 0.0, 0.0, 0, 0);
    for i in 0..m {
        let k = 2.0 * PI / lams[i];
        // Projected under a Hann window (the leakage of the other harmonics and of the
        // sidebands the sleepers' period puts beside each one kept out).
        let (mut si, mut co, mut ww) = (0.0, 0.0, 0.0);
        let len = inner.len() as f64;
        for (q, j) in inner.clone().enumerate() {
            let w = 0.5 - 0.5 * (2.0 * PI * q as f64 / len).cos();
            let ph = k * j as f64 * dx + phases[i];
            let dw = r1.wear_depth[j] - r0.wear_depth[j];
            si += w * dw * ph.sin();
            co += w * dw * ph.cos();
            ww += w;
        }
        let (inp, quad) = (2.0 * si / ww / amp, 2.0 * co / ww / amp);
        let p = pred[i];
        println!(
            "{:7.1} mm {:7.1} Hz: in phase {inp:+.3e} (predicted {:+.3e}), quadrature {quad:+.3e} ({:+.3e})",
            1e3 * lams[i],
            p.frequency_hz,
            p.in_phase,
            p.quadrature
        );
        // Compared from 28 mm up: below, the wheel's own elastic dynamics and the two
        // nodes in the patch depart from the rigid mass on a spring of the prediction.
        if lams[i] >= 0.028 {
            d2 += (inp - p.in_phase).powi(2);
            p2 += p.in_phase.powi(2);
            q2 += (quad - p.quadrature).powi(2);
            qp2 += p.quadrature.powi(2);
            if p.in_phase < -5e-7 {
                growing += 1;
                agree += usize::from(inp < 0.0);
            }
        }
    }
    let (e_in, e_q) = ((d2 / p2).sqrt(), (q2 / qp2).sqrt());
    println!(
        "k_c {k_c:.4e} N/m, a {:.2} mm; relative rms difference: in phase {e_in:.3}, quadrature {e_q:.3}; growing bands predicted {growing}, of which the passes grow {agree}",
        1e3 * a
    );
    assert!(e_in < 0.35, "in phase: {e_in}");
    assert!(e_q < 0.2, "quadrature: {e_q}");
    assert!(
        growing >= 6 && agree * 10 >= growing * 8,
        "{agree} of {growing}"
    );
}

/// `softway grow` on a track refuses a study without its sliding, and on the wheel a rail's
/// key, naming the file and the key.
#[test]
fn a_rails_study_names_its_missing_and_misplaced_keys() {
    let dir = std::env::temp_dir().join(format!("softway-rail-keys-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let track = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/scenarios/corrugation.toml"
    ))
    .unwrap();
    let no_creep: String = track
        .lines()
        .filter(|l| !l.starts_with("creepage"))
        .map(|l| format!("{l}\n"))
        .collect();
    let f = dir.join("no-creep.toml");
    std::fs::write(&f, no_creep).unwrap();
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_softway"))
        .args([
            "grow",
            f.to_str().unwrap(),
            "--out",
            dir.join("o1").to_str().unwrap(),
        ])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(
        err.contains("no-creep.toml") && err.contains("growth.creepage"),
        "{err}"
    );
    let wheel = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/scenarios/polygon.toml"
    ))
    .unwrap();
    let f = dir.join("wheel-dx.toml");
    std::fs::write(&f, wheel.replace("[growth]\n", "[growth]\ndx = 1e-3\n")).unwrap();
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_softway"))
        .args([
            "grow",
            f.to_str().unwrap(),
            "--out",
            dir.join("o2").to_str().unwrap(),
        ])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(
        err.contains("wheel-dx.toml") && err.contains("growth.dx"),
        "{err}"
    );
    assert!(!dir.join("o2").join("summary.json").exists());
    let _ = std::fs::remove_dir_all(&dir);
}

/// The scenario of `scenario` driven at the creepage `xi` with Coulomb friction `mu`, the
/// axle held along the track by a suspension (as `scenarios/track-traction.toml`).
fn driven(speed_km_h: f64, travel_bays: usize, xi: f64, mu: f64) -> Scenario {
    let text = format!(
        r#"
name = "rail-wear-driven"
kind = "track"
[track]
set = "uic60"
bays = 40
end_bays = 12
elements_per_bay = 6
[vehicle]
model = "wheel"
unsprung_mass = 800.0
axle_load = 100e3
wheel_radius = 0.46
speed_km_h = {speed_km_h}
travel_bays = {travel_bays}
settle_bays = 4
wheel_rim_nodes = 720
wheel_thickness = 0.02
creepage = {xi}
suspension_stiffness = 1e7
suspension_damping = 1.8e5
[contact]
method = "exact"
friction = {mu}
[time]
alpha = 0.8
gamma = 0.2
"#
    );
    let spec = Scenario::from_str(&text, Path::new("rail-wear-driven.toml")).expect("scenario");
    softway::build::resolve(&spec).expect("built")
}

/// The wear from the run's own friction (`growth.sliding = "dynamic"`): each rim node in
/// slip wears by Archard's law at its own slip speed and carries `mu` times its normal
/// force, so over a pass the worn depth is `k / (mu H w V)` times the frictional power, on
/// either patch. In full slip (`xi` of 1 and 2 %, four and eight times the saturation
/// creepage `mu a / R`) the creep force is `mu P` and the frictional power the creep force's
/// work on the rigid slip (steady rolling: the patch's elastic energy does not change), so
/// between two creepages it grows by `mu P V d(xi)` (an energy balance the contact code does
/// not impose; the loaded wheel's rolling radius, which shifts the slip by a constant, drops
/// out of the difference), and the wear is the steady model's `k xi P / (H w)` but for that
/// shift. In partial slip the stick zone does not wear: less traction and less wear than
/// the steady model's full sliding.
#[test]
fn the_dynamic_friction_wears_the_rail_by_the_frictional_power() {
    let (k, hard, mu, w) = (1e-4, 3e9, 0.3, 0.02);
    let law = WearLaw::Archard(Archard {
        k,
        hardness: hard,
        map: None,
    });
    let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len() as f64;
    // (xi, Q / (mu P), P, frictional power, depth over the steady model's).
    let mut runs = Vec::new();
    for (xi, patch) in [
        (0.01, WearPatch::Hertz),
        (0.02, WearPatch::Hertz),
        (0.01, WearPatch::Nodes),
        (0.002, WearPatch::Hertz),
    ] {
        let sc = driven(100.0, 3, xi, mu);
        let opts = RunOptions {
            progress: false,
            ..RunOptions::default()
        };
        let sliding = Sliding::Dynamic { density: 7850.0 };
        let mut pass = TrackPass::new(&sc, 1e-3, law, sliding, patch, opts).expect("pass");
        let (x0, dx, n, _) = pass.grid();
        let flat = SurfaceProfile {
            x0,
            dx,
            z: vec![0.0; n],
            periodic: false,
        };
        let r = pass
            .run_pass(&flat, 0, &AtomicBool::new(false))
            .expect("pass runs");
        let scalar = |name: &str| {
            r.scalars
                .iter()
                .find(|(key, _)| key == name)
                .map(|(_, v)| *v)
                .unwrap_or_else(|| panic!("{name}"))
        };
        let (q, p, power) = (
            scalar("mean_traction_n"),
            scalar("mean_force_n"),
            scalar("frictional_power_w"),
        );
        let inner = pass.inner();
        let inner = inner.start + 20..inner.end - 20;
        let depth = mean(&r.wear_depth[inner]);
        let v = pass.speed();
        let by_power = k * power / (mu * hard * w * v);
        let steady = k * xi * p / (hard * w);
        println!(
            "xi {xi}, {patch:?}: Q/(mu P) {:.4}, sliding share {:.3}, frictional power {power:.1} W (Q xi V {:.1} W); mean depth {depth:.4e} m against k P_f / (mu H w V) {by_power:.4e} ({:+.2}%), the steady model's {steady:.4e}",
            q / (mu * p),
            scalar("sliding_share"),
            scalar("creep_power_w"),
            100.0 * (depth / by_power - 1.0)
        );
        assert!(
            (depth / by_power - 1.0).abs() < 0.02,
            "{depth} against {by_power}"
        );
        runs.push((xi, q / (mu * p), p, power, depth / steady, v));
    }
    // Full slip: the traction saturated, the power's growth between the two creepages.
    for r in &runs[..3] {
        assert!(r.1 > 0.97 && r.1 <= 1.0 + 1e-9, "Q / (mu P) {}", r.1);
    }
    let ((xa, _, pa, wa, _, v), (xb, _, pb, wb, _, _)) = (runs[0], runs[1]);
    let expected = mu * 0.5 * (pa + pb) * v * (xb - xa);
    println!(
        "full slip: frictional power from xi {xa} to {xb}: {:.1} W against mu P V d(xi) {expected:.1} W",
        wb - wa
    );
    assert!(((wb - wa) / expected - 1.0).abs() < 0.03);
    // The wear over the steady model's: the rolling radius's shift of the slip, the same
    // on both patches.
    assert!(runs[0].4 < 1.0 && runs[0].4 > 0.85, "{}", runs[0].4);
    assert!((runs[2].4 / runs[0].4 - 1.0).abs() < 0.02);
    // Partial slip: less traction and less wear than full sliding.
    let (_, sat, _, _, to_steady, _) = runs[3];
    assert!(sat < 0.9, "{sat}");
    assert!(to_steady < 0.8 * runs[0].4, "{to_steady}");
}

/// `growth.sliding`: an unknown model, the dynamic model on a frictionless scenario and the
/// steady model's keys beside the dynamic one are refused before any pass, naming the file
/// and the key.
#[test]
fn the_dynamic_sliding_names_what_it_needs() {
    let dir = std::env::temp_dir().join(format!("softway-rail-sliding-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let read = |name: &str| {
        std::fs::read_to_string(
            Path::new(env!("CARGO_MANIFEST_DIR"))
                .join("scenarios")
                .join(name),
        )
        .unwrap()
    };
    let (steady, dynamic) = (read("corrugation.toml"), read("corrugation-friction.toml"));
    let cases = [
        (
            "bogus.toml",
            dynamic.replace("sliding = \"dynamic\"", "sliding = \"sticky\""),
            vec!["growth.sliding", "\"sticky\"", "\"steady\"", "\"dynamic\""],
        ),
        (
            "frictionless.toml",
            steady
                .lines()
                .filter(|l| !l.starts_with("creepage") && !l.starts_with("traction_coefficient"))
                .map(|l| format!("{l}\n"))
                .collect::<String>()
                .replace("[growth]\n", "[growth]\nsliding = \"dynamic\"\n"),
            vec![
                "growth.sliding = \"dynamic\"",
                "this scenario has contact.friction = 0",
            ],
        ),
        (
            "both.toml",
            dynamic.replace("[growth]\n", "[growth]\ncreepage = 0.005\n"),
            vec!["growth.creepage", "vehicle.creepage"],
        ),
    ];
    for (name, text, words) in cases {
        let f = dir.join(name);
        std::fs::write(&f, text).unwrap();
        let o = dir.join(format!("out-{name}"));
        let out = std::process::Command::new(env!("CARGO_BIN_EXE_softway"))
            .args(["grow", f.to_str().unwrap(), "--out", o.to_str().unwrap()])
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{name}: {err}");
        assert!(err.contains(name), "{name}: {err}");
        for w in words {
            assert!(err.contains(w), "{name}: `{w}` not in {err}");
        }
        assert!(!o.join("summary.json").exists(), "{name}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// The wheel's side of a study on the track (`growth.surface = "wheel"`,
/// [`softway::kinds::track::polygon`]): one pass of the smooth wheel in full slip records one
/// full turn (`2 pi R_s / (V (1 + xi))`, to a step) and wears the rim by Archard's law at each
/// node's own slip, so that the worn volume is `k / (mu H)` times the frictional energy of
/// the turn (a sliding node carries `mu N`), and the frictional power is the creep force's
/// work on the slip, below `mu P xi V` by the loaded rim's rolling radius (the rail's check
/// above puts that shift at 0.06 % of creepage).
#[test]
fn a_wheels_pass_on_the_track_wears_its_rim_by_the_frictional_power() {
    let (k, hard, mu, w, xi) = (1e-4, 3e9, 0.3, 0.02, 0.01);
    let law = WearLaw::Archard(Archard {
        k,
        hardness: hard,
        map: None,
    });
    let text = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("scenarios/track-traction.toml"),
    )
    .unwrap()
    .replace("travel_bays = 20 ", "travel_bays = 5  ")
    .replace("wheel_rim_nodes = 720", "wheel_rim_nodes = 360")
    .replace("bays = 100 ", "bays = 50\nend_bays = 15\n");
    let spec = Scenario::from_str(&text, Path::new("wheel-wear.toml")).expect("scenario");
    let sc = softway::build::resolve(&spec).expect("built");
    let opts = RunOptions {
        progress: false,
        ..RunOptions::default()
    };
    let mut pass = WheelTrackPass::new(&sc, law, 7850.0, opts).expect("pass");
    let (x0, dx, n, periodic) = pass.grid();
    assert!(periodic && n == 360 && x0 == 0.0);
    let r = pass
        .run_pass(
            &SurfaceProfile {
                x0,
                dx,
                z: vec![0.0; n],
                periodic: true,
            },
            0,
            &AtomicBool::new(false),
        )
        .expect("pass runs");
    let scalar = |name: &str| {
        r.scalars
            .iter()
            .find(|(key, _)| key == name)
            .map(|(_, v)| *v)
            .unwrap_or_else(|| panic!("{name}"))
    };
    let h = sc.runs[0].params.h;
    let (v, radius) = (pass.speed(), 0.46);
    let turn = scalar("turn_steps") * h;
    let expected_turn = 2.0 * PI * radius / (v * (1.0 + xi));
    let energy = scalar("frictional_power_w") * turn;
    let mean = r.wear_depth.iter().sum::<f64>() / n as f64;
    let by_energy = k * energy / (mu * hard * 2.0 * PI * radius * w);
    let p = scalar("mean_force_n");
    println!(
        "turn {turn:.5e} s (2 pi R / (V (1 + xi)) {expected_turn:.5e}); Q/(mu P) {:.4}; frictional power {:.1} W against mu P xi V {:.1} W; mean depth {mean:.4e} m against k E_f / (mu H 2 pi R w) {by_energy:.4e} ({:+.3}%)",
        scalar("traction_ratio") / mu,
        scalar("frictional_power_w"),
        mu * p * xi * v,
        100.0 * (mean / by_energy - 1.0)
    );
    // The spun rim is a little larger than the wheel's radius: a turn within 0.5 %.
    assert!((turn / expected_turn - 1.0).abs() < 5e-3);
    assert!((scalar("traction_ratio") / mu - 1.0).abs() < 0.03);
    assert!(
        (mean / by_energy - 1.0).abs() < 0.01,
        "{mean} against {by_energy}"
    );
    let slip = scalar("frictional_power_w") / (mu * p * v);
    assert!(slip < xi && slip > xi - 0.002, "effective creepage {slip}");
    // Every node crosses the patch once: each one wears, none twice as much as the mean.
    let (lo, hi) = r
        .wear_depth
        .iter()
        .fold((f64::INFINITY, 0.0f64), |(a, b), &d| (a.min(d), b.max(d)));
    assert!(lo > 0.3 * mean && hi < 2.0 * mean, "{lo} {mean} {hi}");
}

/// `growth.surface`: an unknown surface, the rail's keys on the wheel's study, a
/// frictionless wheel and a recorded travel shorter than a turn are refused before any
/// pass, naming the file and the key.
#[test]
fn the_wheels_study_on_the_track_names_what_it_needs() {
    let dir = std::env::temp_dir().join(format!("softway-wheel-track-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let base = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("scenarios/polygon-track.toml"),
    )
    .unwrap();
    let cases = [
        (
            "surface.toml",
            base.replace("surface = \"wheel\"", "surface = \"axle\""),
            vec!["growth.surface", "\"axle\"", "\"rail\"", "\"wheel\""],
        ),
        (
            "dx.toml",
            base.replace("[growth]\n", "[growth]\ndx = 1e-3\n"),
            vec!["growth.dx", "growth.surface = \"wheel\""],
        ),
        (
            "frictionless.toml",
            base.replace("friction = 0.3\n", "")
                .replace("creepage = 0.005 ", "creepage = 0.0   "),
            vec!["growth.surface = \"wheel\"", "contact.friction = 0"],
        ),
        (
            "short.toml",
            base.replace("travel_bays = 6 ", "travel_bays = 3 "),
            vec!["vehicle.travel_bays = 3", "at least 5 bays"],
        ),
    ];
    for (name, text, words) in cases {
        let f = dir.join(name);
        std::fs::write(&f, text).unwrap();
        let o = dir.join(format!("out-{name}"));
        let out = std::process::Command::new(env!("CARGO_BIN_EXE_softway"))
            .args(["grow", f.to_str().unwrap(), "--out", o.to_str().unwrap()])
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{name}: {err}");
        assert!(err.contains(name), "{name}: {err}");
        for w in words {
            assert!(err.contains(w), "{name}: `{w}` not in {err}");
        }
        assert!(!o.join("summary.json").exists(), "{name}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}
