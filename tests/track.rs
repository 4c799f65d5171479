//! The track (`softway::track`): a UIC60 rail on discrete pads, half-sleepers and ballast,
//! against the beam on an elastic foundation and the exact beam on discrete springs (static),
//! the simply supported span (the pinned-pinned frequency), its own length (the ends), the
//! static deflection (a slow moving load), the sleeper-passing frequency (a load at speed)
//! and the single-dof P2 estimate. Each test prints its numbers.

use faer::c64;
use faer::linalg::solvers::Solve;
use softway::element::beam::BeamTheory;
use softway::simulation::Settings;
use softway::time::{Coriolis, Integrator};
use softway::track::moving::{run, MovingLoad, Passage, Sample};
use softway::track::receptance::{
    frequencies, log_frequencies, receptance, simply_supported_hz, Receptance, Wheel,
};
use softway::track::{Ends, Track, TrackSpec};
use std::sync::atomic::AtomicBool;

const LOAD: f64 = 100e3;

const SPACE_TIME: Integrator = Integrator::SpaceTime {
    alpha: 0.8,
    gamma: 0.0,
    coriolis: Coriolis::Implicit,
};

fn wheel() -> Wheel {
    Wheel {
        unsprung_mass: 800.0,
        load: LOAD,
        radius: 0.46,
    }
}

/// The uic60 set with `bays` bays of `ne` elements, `theory`, and free ends (statics).
fn static_track(theory: BeamTheory, bays: usize, ne: usize) -> Track {
    let mut s = TrackSpec::uic60();
    s.theory = theory;
    s.bays = bays;
    s.elements_per_bay = ne;
    s.ends = Ends::Free;
    s.build().unwrap()
}

/// The FE deflection (m, downwards) under `LOAD` at `x` (with the loaded element's own
/// response, `Track::deflection_under_load`).
fn fe_deflection(t: &Track, x: f64) -> f64 {
    let u = t.static_displacement(x, -LOAD).unwrap();
    -t.deflection_under_load(&u, x, -LOAD).unwrap()
}

/// The exact static deflection (m, downwards) under `LOAD` at `x0` of a simply supported
/// beam of the track's length on springs `k_s` (pad and ballast in series) at its interior
/// sleepers: the flexibility method with the beam's Green's function, bending
/// `b x (L^2 - b^2 - x^2) / (6 L EI)` (`x <= xi`, `b = L - xi`) plus, for Timoshenko, shear
/// `x b / (L kappa G A)`; sleeper reactions `R_j = k_s w_j` from `(I + k_s G) w = F g_0`.
fn discrete_exact(t: &Track, x0: f64) -> f64 {
    let s = &t.spec;
    let l = t.length();
    let ei = s.section.ei();
    let kga = s.section.shear_coefficient * s.section.shear_modulus * s.section.area;
    let shear = s.theory == BeamTheory::Timoshenko;
    let g = |x: f64, xi: f64| {
        let (x, xi) = if x <= xi { (x, xi) } else { (l - x, l - xi) };
        let b = l - xi;
        let bend = b * x * (l * l - b * b - x * x) / (6.0 * l * ei);
        bend + if shear { x * b / (l * kga) } else { 0.0 }
    };
    let ks = s.support_stiffness();
    let xs: Vec<f64> = (1..s.bays).map(|j| j as f64 * s.spacing).collect();
    let n = xs.len();
    let a = faer::Mat::<f64>::from_fn(n, n, |i, j| {
        f64::from(u8::from(i == j)) + ks * g(xs[i], xs[j])
    });
    let rhs = faer::Mat::<f64>::from_fn(n, 1, |i, _| LOAD * g(xs[i], x0));
    let w = a.partial_piv_lu().solve(&rhs);
    LOAD * g(x0, x0) - (0..n).map(|j| g(x0, xs[j]) * ks * w[(j, 0)]).sum::<f64>()
}

/// The deflection (m) under a point load `LOAD` on the infinite beam on the smeared Winkler
/// foundation `k = k_s / s`: Euler-Bernoulli `F / (8 EI beta^3)`, `beta^4 = k / (4 EI)`
/// (Zimmermann); Timoshenko from `EI lambda^4 - (k EI / kappa G A) lambda^2 + k = 0`, the
/// two roots with negative real parts, `theta(0) = 0` and the shear `F / 2` at the load.
fn winkler(t: &Track) -> f64 {
    let s = &t.spec;
    let ei = s.section.ei();
    let k = s.support_stiffness() / s.spacing;
    if s.theory == BeamTheory::EulerBernoulli {
        let beta = (k / (4.0 * ei)).powf(0.25);
        return LOAD / (8.0 * ei * beta.powi(3));
    }
    let kga = s.section.shear_coefficient * s.section.shear_modulus * s.section.area;
    let p = k * ei / kga;
    let disc = c64::new(p * p - 4.0 * ei * k, 0.0).sqrt();
    let mu1 = (c64::new(p, 0.0) + disc) / (2.0 * ei);
    let lambda = [-mu1.sqrt(), -mu1.conj().sqrt()];
    // theta = Theta_i w_i; shear kGA (w' - theta) = kGA (lambda_i - Theta_i) w_i.
    let theta: Vec<c64> = lambda
        .iter()
        .map(|&l| l * kga / (c64::new(kga, 0.0) - l * l * ei))
        .collect();
    let shear: Vec<c64> = (0..2).map(|i| (lambda[i] - theta[i]) * kga).collect();
    // [theta0 theta1; shear0 shear1] [c0; c1] = [0; -F/2].
    let det = theta[0] * shear[1] - theta[1] * shear[0];
    let f = c64::new(-0.5 * LOAD, 0.0);
    let c0 = (-theta[1] * f) / det;
    let c1 = (theta[0] * f) / det;
    (c0 + c1).re.abs()
}

/// Static deflection against the beam on an elastic foundation (smeared supports) and the
/// exact beam on discrete springs, above a sleeper and at mid-span, Euler-Bernoulli and
/// Timoshenko; the mesh convergence under a load between nodes.
#[test]
fn static_deflection_matches_the_discrete_supports_and_the_smeared_foundation() {
    for theory in [BeamTheory::EulerBernoulli, BeamTheory::Timoshenko] {
        let t = static_track(theory, 40, 6);
        let w0 = winkler(&t);
        for (name, x) in [
            ("above a sleeper", t.middle()),
            ("mid-span", t.middle_span()),
        ] {
            let fe = fe_deflection(&t, x);
            let exact = discrete_exact(&t, x);
            let smearing = exact / w0 - 1.0;
            println!(
                "{theory:?} {name}: FE {fe:.6e} m, discrete exact {exact:.6e} m ({:+.1e}), Winkler {w0:.6e} m: smearing {:+.2}%",
                fe / exact - 1.0,
                100.0 * smearing
            );
            assert!((fe / exact - 1.0).abs() < 1e-6, "{fe} {exact}");
            // The tolerance against the smeared foundation is the smearing itself (the
            // discrete exact answer's distance from it), 3% at most here.
            assert!((fe / w0 - 1.0).abs() <= smearing.abs() + 1e-6);
            assert!(smearing.abs() < 0.03, "{smearing}");
        }
        // Under a load between nodes, a third of a bay past a sleeper (a third or two thirds
        // into an element for 1 to 16 elements a bay): the nodal values are exact; between
        // nodes their interpolation misses the loaded element's own response: for
        // Timoshenko mostly the kink of its shear (the shear force jumps by F, the slope by
        // F / kappa G A), about `F l xi (1 - xi) / kappa G A`, first order in the element's
        // length `l`; with that response added (`deflection_under_load`) the deflection
        // under the load is exact on any mesh.
        let x = 20.0 * 0.6 + 0.6 / 3.0;
        let (mut interpolated, mut corrected, mut kinks) = (Vec::new(), Vec::new(), Vec::new());
        for ne in [1, 2, 4, 8, 16] {
            let t = static_track(theory, 40, ne);
            let exact = discrete_exact(&t, x);
            let u = t.static_displacement(x, -LOAD).unwrap();
            interpolated.push(-t.deflection_at(&u, x).unwrap() / exact - 1.0);
            corrected.push(-t.deflection_under_load(&u, x, -LOAD).unwrap() / exact - 1.0);
            let kga = t.spec.section.shear_coefficient
                * t.spec.section.shear_modulus
                * t.spec.section.area;
            let l = 0.6 / ne as f64;
            kinks.push(-LOAD * l * (2.0 / 9.0) / (kga * exact));
        }
        let show = |v: &[f64]| {
            let s: Vec<String> = v.iter().map(|e| format!("{e:.2e}")).collect();
            s.join(", ")
        };
        println!(
            "{theory:?} under a load between nodes, 1-16 elements a bay: interpolated errors {} (Timoshenko's kink alone: {}); with the element's response {}",
            show(&interpolated),
            show(&kinks),
            show(&corrected)
        );
        assert!(corrected.iter().all(|e| e.abs() < 1e-9), "{corrected:?}");
        assert!(interpolated.windows(2).all(|w| w[1].abs() < w[0].abs()));
        match theory {
            BeamTheory::EulerBernoulli => assert!(interpolated[4].abs() < 1e-5),
            BeamTheory::Timoshenko => {
                for i in [3, 4] {
                    assert!((interpolated[i] / kinks[i] - 1.0).abs() < 0.1);
                }
            }
        }
    }
}

fn track_with_pads(pad: f64, ne: usize) -> Track {
    let mut s = TrackSpec::uic60();
    s.pad_stiffness = pad;
    s.elements_per_bay = ne;
    s.build().unwrap()
}

/// The mid-span receptance's peak near 1 kHz is the simply supported span's frequency
/// (Timoshenko, exact) whatever the pads: the Bloch wave of wavelength `2 s` has its nodes on
/// the pads. The pads move the anti-resonance above the sleeper: down towards it as they
/// soften.
#[test]
fn the_pinned_pinned_peak_is_the_span_frequency_and_the_anti_resonance_follows_the_pads() {
    let freqs = log_frequencies(20.0, 3000.0, 200);
    let s = TrackSpec::uic60();
    let exact = simply_supported_hz(&s.section, s.theory, s.spacing);
    let mut antis = Vec::new();
    for pad in [2e9, 500e6, 200e6, 100e6, 50e6] {
        let t = track_with_pads(pad, 6);
        let r = receptance(&t, &freqs).unwrap();
        let f = frequencies(&t, &r, &wheel()).unwrap();
        let (pp, anti) = (
            f.pinned_pinned_hz.unwrap(),
            f.above_sleeper_antiresonance_hz.unwrap(),
        );
        println!(
            "pads {:.0} MN/m: pinned-pinned {pp:.1} Hz ({:+.2}% from the span's {exact:.1} Hz), anti-resonance above the sleeper {anti:.1} Hz",
            pad / 1e6,
            100.0 * (pp / exact - 1.0)
        );
        assert!((pp / exact - 1.0).abs() < 0.01);
        if pad == 200e6 {
            assert!((anti / pp - 1.0).abs() < 0.05, "{anti} {pp}");
        }
        antis.push(anti);
    }
    assert!(antis.windows(2).all(|w| w[1] < w[0]), "{antis:?}");
    // The 0.4% left is the mesh's: twelve elements a bay come closer.
    let fine = track_with_pads(200e6, 12);
    let f = frequencies(&fine, &receptance(&fine, &freqs).unwrap(), &wheel()).unwrap();
    let pp = f.pinned_pinned_hz.unwrap();
    println!(
        "12 elements a bay: pinned-pinned {pp:.1} Hz ({:+.2}%)",
        100.0 * (pp / exact - 1.0)
    );
    assert!((pp / exact - 1.0).abs() < 0.002);
}

/// The largest relative change of the two receptances between `a` and `b`, over all
/// frequencies and away from the two band edges (within 10% of the pinned-pinned frequency,
/// and above 2.75 kHz: the second edge is at 2.9 kHz).
fn receptance_change(a: &Receptance, b: &Receptance, pp: f64) -> (f64, f64) {
    let (mut all, mut away) = (0.0f64, 0.0f64);
    for i in 0..a.frequency_hz.len() {
        let f = a.frequency_hz[i];
        let d = ((a.mid_span[i] - b.mid_span[i]).norm() / b.mid_span[i].norm())
            .max((a.above_sleeper[i] - b.above_sleeper[i]).norm() / b.above_sleeper[i].norm());
        all = all.max(d);
        if (f / pp - 1.0).abs() > 0.1 && f < 2750.0 {
            away = away.max(d);
        }
    }
    (all, away)
}

/// The deflection under a load at 30 m/s over ten bays from four bays before the middle.
fn passage_at_speed(t: &Track) -> Vec<Sample> {
    let passage = Passage {
        load: MovingLoad {
            force: LOAD,
            speed: 30.0,
            start: t.middle() - 4.0 * t.spec.spacing,
        },
        distance: 10.0 * t.spec.spacing,
        integrator: SPACE_TIME,
        h: 1e-4,
        static_reference: false,
    };
    let mut out = Vec::new();
    run(
        t,
        &passage,
        Settings::default(),
        &AtomicBool::new(false),
        |s| {
            out.push(*s);
            Ok(())
        },
    )
    .unwrap();
    out
}

/// The ends: the receptance in the middle and the deflection under a moving load change
/// negligibly when the track is twice as long.
#[test]
fn the_absorbing_ends_reflect_negligibly() {
    let freqs = log_frequencies(20.0, 3000.0, 300);
    let build = |bays: usize, ends: Ends| {
        let mut s = TrackSpec::uic60();
        s.bays = bays;
        s.ends = ends;
        s.build().unwrap()
    };
    let sponge = TrackSpec::uic60().ends;
    let Ends::Absorbing { bays: nb, damping } = sponge else {
        unreachable!()
    };
    let short = build(100, sponge);
    let long = build(200, sponge);
    let f = frequencies(&short, &receptance(&short, &freqs).unwrap(), &wheel()).unwrap();
    let pp = f.pinned_pinned_hz.unwrap();
    let (all, away) = receptance_change(
        &receptance(&short, &freqs).unwrap(),
        &receptance(&long, &freqs).unwrap(),
        pp,
    );
    let free = receptance_change(
        &receptance(&build(100, Ends::Free), &freqs).unwrap(),
        &receptance(&build(200, Ends::Free), &freqs).unwrap(),
        pp,
    );
    println!(
        "receptance, 100 against 200 bays ({nb} sponge bays, eta_max {damping} 1/s): {away:.1e} away from the band edges, {all:.1e} at them; free ends: {:.1e} and {:.1e}",
        free.1, free.0
    );
    assert!(away < 1e-4, "{away}");
    assert!(away < free.1);
    let change = |a: &[Sample], b: &[Sample]| {
        let peak = a.iter().map(|s| s.deflection.abs()).fold(0.0, f64::max);
        let diff = a
            .iter()
            .zip(b)
            .map(|(p, q)| (p.deflection - q.deflection).abs())
            .fold(0.0, f64::max);
        (diff / peak, peak)
    };
    let (moving, peak) = change(&passage_at_speed(&short), &passage_at_speed(&long));
    let (moving_free, _) = change(
        &passage_at_speed(&build(100, Ends::Free)),
        &passage_at_speed(&build(200, Ends::Free)),
    );
    println!(
        "moving load at 30 m/s, 100 against 200 bays: the deflection under the load differs by {moving:.1e} of its peak {peak:.4e} m (free ends: {moving_free:.1e})"
    );
    assert!(moving < 1e-4);
}

/// A load moving at 1 m/s deflects the rail as a static load standing where it is.
#[test]
fn a_slow_load_reproduces_the_static_deflection() {
    let t = TrackSpec::uic60().build().unwrap();
    let passage = Passage {
        load: MovingLoad {
            force: LOAD,
            speed: 1.0,
            start: t.middle(),
        },
        distance: t.spec.spacing,
        integrator: SPACE_TIME,
        h: 1e-3,
        static_reference: true,
    };
    let mut worst = 0.0f64;
    let mut range = (f64::INFINITY, 0.0f64);
    run(
        &t,
        &passage,
        Settings::default(),
        &AtomicBool::new(false),
        |s| {
            worst = worst.max((s.deflection / s.static_deflection - 1.0).abs());
            range = (
                range.0.min(s.static_deflection),
                range.1.max(s.static_deflection),
            );
            Ok(())
        },
    )
    .unwrap();
    println!(
        "1 m/s over a bay: static deflection {:.4e}-{:.4e} m, largest relative difference {worst:.2e}",
        range.0, range.1
    );
    assert!(worst < 0.01, "{worst}");
}

/// At 30 m/s the deflection under the load varies at the sleeper-passing frequency
/// `V / s = 50 Hz`: the strongest component of its spectrum after the first two bays.
#[test]
fn at_speed_the_deflection_varies_at_the_sleeper_passing_frequency() {
    let t = TrackSpec::uic60().build().unwrap();
    let samples = passage_at_speed(&t);
    let skip = samples
        .iter()
        .position(|s| s.x >= t.middle() - 2.0 * t.spec.spacing)
        .unwrap();
    let y: Vec<f64> = samples[skip..].iter().map(|s| s.deflection).collect();
    let spec = softway::analysis::signal::amplitude_spectrum(&y, 1e-4);
    let (f, a) = softway::analysis::signal::dominant_peak(&spec, 5.0).unwrap();
    let passing = 30.0 / t.spec.spacing;
    let mean = y.iter().sum::<f64>() / y.len() as f64;
    println!(
        "30 m/s: deflection under the load {mean:.4e} m, dominant component {f:.2} Hz (sleeper passing {passing:.1} Hz), amplitude {a:.3e} m"
    );
    let df = spec.frequency_hz[1];
    assert!((f - passing).abs() < 0.5 * df, "{f} {passing} {df}");
}

/// P2 against the single-dof estimate: lower, because the track's mass moves with the wheel.
#[test]
fn p2_is_below_the_single_dof_estimate_by_the_track_mass() {
    let t = TrackSpec::uic60().build().unwrap();
    let freqs = log_frequencies(20.0, 3000.0, 300);
    let r = receptance(&t, &freqs).unwrap();
    let f = frequencies(&t, &r, &wheel()).unwrap();
    let p2 = f.p2_hz.unwrap();
    let single = f.p2_single_dof_hz;
    // The track mass that, added to the wheel's on the same k_eff, gives the P2 frequency.
    let mass = wheel().unsprung_mass * ((single / p2).powi(2) - 1.0);
    println!(
        "P2 {p2:.1} Hz (above the sleeper {:.1} Hz; second coupled minimum {:.1} Hz), single dof {single:.1} Hz ({:+.1}%): k_H {:.3e} N/m, track {:.3e} N/m, equivalent track mass {mass:.0} kg; track resonance {:.1} Hz, pinned-pinned {:.1} Hz",
        f.p2_above_sleeper_hz.unwrap(),
        f.second_coupled_hz.unwrap_or(f64::NAN),
        100.0 * (p2 / single - 1.0),
        f.hertz_stiffness,
        f.static_stiffness_mid_span,
        f.track_resonance_hz.unwrap(),
        f.pinned_pinned_hz.unwrap(),
    );
    assert!(p2 < single && p2 > 0.7 * single, "{p2} {single}");
    assert!(mass > 50.0 && mass < 1000.0, "{mass}");
}

/// The command line: `softway receptance` and `softway run` on the shipped scenario write
/// their files, and the summaries hold the frequencies the library finds.
#[test]
fn the_commands_write_the_receptance_and_the_passage() {
    let dir = std::env::temp_dir().join(format!("softway-track-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let scenario = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/scenarios/track-moving-load.toml"
    );
    let softway = |args: &[&str]| {
        let o = std::process::Command::new(env!("CARGO_BIN_EXE_softway"))
            .args(args)
            .output()
            .unwrap();
        let text = String::from_utf8_lossy(&o.stdout).into_owned();
        assert!(
            o.status.success(),
            "{text}{}",
            String::from_utf8_lossy(&o.stderr)
        );
        text
    };
    let rec = dir.join("rec");
    print!(
        "{}",
        softway(&["receptance", scenario, "--out", rec.to_str().unwrap()])
    );
    let csv = std::fs::read_to_string(rec.join("receptance.csv")).unwrap();
    assert!(csv.starts_with(
        "frequency_Hz,mid_span_magnitude_m_per_N,mid_span_phase_deg,above_sleeper_magnitude_m_per_N,above_sleeper_phase_deg\n"
    ));
    assert_eq!(csv.lines().count(), 401);
    assert!(rec.join("receptance.png").exists());
    let s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(rec.join("summary.json")).unwrap()).unwrap();
    let t = TrackSpec::uic60().build().unwrap();
    let r = receptance(&t, &log_frequencies(20.0, 3000.0, 400)).unwrap();
    let f = frequencies(&t, &r, &wheel()).unwrap();
    for (key, want) in [
        ("pinned_pinned_hz", f.pinned_pinned_hz),
        ("track_resonance_hz", f.track_resonance_hz),
        ("p2_hz", f.p2_hz),
    ] {
        assert_eq!(s[key].as_f64(), want, "{key}");
    }
    assert_eq!(s["parameters"]["track"]["pad_stiffness_N_m"], 200e6);
    let run = dir.join("run");
    print!(
        "{}",
        softway(&["run", scenario, "--quiet", "--out", run.to_str().unwrap()])
    );
    let history = std::fs::read_to_string(run.join("history.csv")).unwrap();
    assert!(history.starts_with(
        "run,t_s,x_m,deflection_m,static_deflection_m,pad_force_nearest_N,nearest_sleeper,pad_force_middle_N\n"
    ));
    assert!(run.join("track.png").exists());
    let s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(run.join("summary.json")).unwrap()).unwrap();
    let dominant = s["runs"][0]["dominant_frequency_hz"].as_f64().unwrap();
    assert!((dominant - 50.0).abs() < 0.5, "{dominant}");
    let _ = std::fs::remove_dir_all(&dir);
}
