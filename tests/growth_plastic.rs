//! The plastic wheel's growth study (`material.model = "j2"` under `softway grow`): the
//! plastic state carried from pass to pass, so that a wheel below its shakedown limit stops
//! flowing and one above it ratchets; the plastic part of the profile counted once in the
//! surface the next pass meets; resume bit for bit with the plastic state; a yield stress
//! out of reach giving the elastic study.
//!
//! The wheel is `scenarios/polygon.toml` coarsened (96 rim nodes, h = 1e-5 s) in plane
//! strain, pressed to 0.2 mm: a mean force of about 1.92e5 N on its 1 cm, Hertz's
//! `p0 = 2 P' / (pi a)` with `a = sqrt(4 P' R / (pi E*))` about 3.6 GPa. With Prager's
//! kinematic hardening (`C = 20 GPa`) the two loads below are `p0/k` = 2.8 (`sigma_y` =
//! 2.2 GPa) and 5.2 (1.2 GPa), `k = sigma_y / sqrt 3`: either side of the line-contact
//! shakedown limit of a kinematically hardening material (4 in free rolling, Johnson,
//! *Contact Mechanics*, 1985, §9.3; lower with traction).

use softway::growth::{run_study, PassRunner, StudyState, SurfaceProfile, CHECKPOINT};
use softway::kinds::wheel::growth::WheelPassRunner;
use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;

fn runner(extra: &[&str]) -> (WheelPassRunner, softway::growth::GrowthConfig) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenarios/polygon.toml");
    let mut sets = vec![
        "wheel.rim_nodes=96",
        "time.h=1e-5",
        "rolling.settle_time=1.5e-3",
        "growth.reference=false",
        "wheel.plane=\"strain\"",
        "rolling.flattening=2e-4",
    ];
    sets.extend_from_slice(extra);
    let sets: Vec<softway::scenario::Override> = sets
        .iter()
        .map(|s| softway::scenario::Override::parse(s).unwrap())
        .collect();
    let sc = softway::scenario::Scenario::from_file_with(&path, &sets).unwrap();
    let sc = softway::build::resolve(&sc).unwrap();
    let cfg = sc.growth.clone().unwrap();
    let r = WheelPassRunner::new(&sc, cfg.wear, cfg.wear_density, softway::run::Par::Seq).unwrap();
    (r, cfg)
}

fn j2(yield_stress: &'static str) -> Vec<&'static str> {
    vec![
        "material.model=\"j2\"",
        yield_stress,
        "material.hardening=\"armstrong_frederick\"",
        "material.af_c=20e9",
        "material.af_gamma=0.0",
    ]
}

fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!(
        "softway-growth-plastic-{}-{name}",
        std::process::id()
    ));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn study(
    r: &mut WheelPassRunner,
    c: &softway::growth::GrowthConfig,
    passes: usize,
    out: &Path,
    resume: bool,
) -> StudyState {
    let flag = AtomicBool::new(false);
    run_study(r, c, passes, out, resume, "sha", &flag, |_, _| Ok(()))
        .unwrap()
        .state
}

/// A pass scalar by name.
fn scalar(s: &StudyState, pass: usize, name: &str) -> f64 {
    let p = &s.passes[pass];
    let i = p.scalar_names.iter().position(|n| n == name).unwrap();
    p.scalar_values.0[i]
}

/// Below the shakedown limit the first pass flows and the next ones almost not (the
/// residual stresses and the backstress it left are carried); above it every pass flows
/// again (ratcheting). A runner that forgets the state between passes flows in its second
/// pass as much as in its first: the shakedown is the carried state's doing.
#[test]
fn plastic_state_carried_pass_to_pass_shakes_down_below_the_limit_and_ratchets_above() {
    let (mut low, c) = runner(&j2("material.yield_stress=2.2e9"));
    let out = tmp("low");
    let s = study(&mut low, &c, 3, &out, false);
    let inc = |s: &StudyState, p| scalar(s, p, "plastic_increment_rms_m");
    let eq = |s: &StudyState, p| scalar(s, p, "max_equivalent_plastic_strain");
    let (i0, i1, i2) = (inc(&s, 0), inc(&s, 1), inc(&s, 2));
    eprintln!(
        "p0/k 2.8: increments {i0:.3e} {i1:.3e} {i2:.3e} m; max eq strain {:.4e} {:.4e} {:.4e}",
        eq(&s, 0),
        eq(&s, 1),
        eq(&s, 2)
    );
    assert!(i0 > 1e-7, "the first pass flows: {i0:e} m");
    assert!(
        i1 < 0.05 * i0 && i2 < 0.05 * i0,
        "shakedown: {i0:e} {i1:e} {i2:e}"
    );
    assert!(
        eq(&s, 2) - eq(&s, 1) < 0.05 * eq(&s, 0),
        "the plastic strain stops growing: {} {} {}",
        eq(&s, 0),
        eq(&s, 1),
        eq(&s, 2)
    );
    for p in 0..3 {
        assert_eq!(scalar(&s, p, "plastic_unconverged"), 0.0);
    }

    // Forgetting the state: a fresh runner for the second pass, on the same profile.
    let (mut fresh, _) = runner(&j2("material.yield_stress=2.2e9"));
    let profile = SurfaceProfile {
        x0: s.x0.0[0],
        dx: s.dx.0[0],
        z: s.passes[0].z.0.clone(),
        periodic: true,
    };
    let flag = AtomicBool::new(false);
    let r = fresh.run_pass(&profile, 1, &flag).unwrap();
    let again = softway::growth::spectrum::rms(&r.plastic);
    eprintln!("a runner without the carried state: second-pass increment {again:.3e} m");
    assert!(again > 0.5 * i0, "{again:e} against {i0:e}");

    let (mut high, c) = runner(&j2("material.yield_stress=1.2e9"));
    let s = study(&mut high, &c, 3, &tmp("high"), false);
    eprintln!(
        "p0/k 5.2: increments {:.3e} {:.3e} {:.3e} m; max eq strain {:.4e} {:.4e} {:.4e}",
        inc(&s, 0),
        inc(&s, 1),
        inc(&s, 2),
        eq(&s, 0),
        eq(&s, 1),
        eq(&s, 2)
    );
    assert!(
        eq(&s, 1) - eq(&s, 0) > 0.5 * eq(&s, 0) && eq(&s, 2) - eq(&s, 1) > 0.5 * eq(&s, 0),
        "ratcheting: {} {} {}",
        eq(&s, 0),
        eq(&s, 1),
        eq(&s, 2)
    );
    let _ = std::fs::remove_dir_all(out);
}

/// The surface the next pass meets is the smooth rim plus the profile (plus the plastic
/// flow's uniform radius change): the plastic part is in the carried state's residual
/// displacement and not again in the moved nodes. Counting it twice would leave the
/// carried plastic profile itself as the difference.
#[test]
fn plastic_part_of_the_profile_is_counted_once() {
    let (mut r, c) = runner(&j2("material.yield_stress=1.2e9"));
    let s = study(&mut r, &c, 2, &tmp("once"), false);
    let n = s.n;
    let carried = &s
        .runner
        .as_ref()
        .expect("a plastic study checkpoints its state")
        .0;
    let plastic_profile = &carried[carried.len() - n..];
    let plastic_rms = softway::growth::spectrum::rms(plastic_profile);
    let profile = s.current();
    let surface = r.rim_surface_at_rest(&profile).unwrap();
    let smooth = r.smooth_rim_radii();
    let d: Vec<f64> = (0..n)
        .map(|i| surface[i] - smooth[i] - profile.z[i])
        .collect();
    let mean = softway::growth::spectrum::mean(&d);
    let dev = d.iter().map(|x| (x - mean).powi(2)).sum::<f64>().sqrt() / (n as f64).sqrt();
    eprintln!("plastic profile rms {plastic_rms:.3e} m; surface - smooth - z: mean {mean:.3e} m, rms about it {dev:.3e} m");
    assert!(plastic_rms > 1e-7);
    assert!(dev < 0.02 * plastic_rms, "{dev:e} against {plastic_rms:e}");
    // The mean is the plastic flow's radius change (negative: the rim is flattened in).
    assert!(mean < 0.0);
}

/// A plastic study stopped after one pass and resumed gives the bits of the one that ran
/// through, the plastic state included; a yield stress out of reach gives the elastic
/// study's passes.
#[test]
fn plastic_study_resumes_bit_for_bit_and_an_unreachable_yield_is_elastic() {
    let (mut r, c) = runner(&j2("material.yield_stress=1.2e9"));
    let a = tmp("a");
    let whole = study(&mut r, &c, 2, &a, false);
    let b = tmp("b");
    let (mut r1, _) = runner(&j2("material.yield_stress=1.2e9"));
    study(&mut r1, &c, 1, &b, false);
    let (mut r2, _) = runner(&j2("material.yield_stress=1.2e9"));
    let resumed = study(&mut r2, &c, 2, &b, true);
    assert_eq!(whole.runner, resumed.runner);
    for (p, q) in whole.passes.iter().zip(&resumed.passes) {
        assert_eq!(p.z, q.z);
        assert_eq!(p.wear, q.wear);
    }
    assert!(StudyState::read(&b.join(CHECKPOINT))
        .unwrap()
        .runner
        .is_some());

    // An elastic runner refuses the plastic checkpoint.
    let (mut elastic, c) = runner(&[]);
    let flag = AtomicBool::new(false);
    let e =
        run_study(&mut elastic, &c, 3, &b, true, "sha", &flag, |_, _| Ok(())).expect_err("refused");
    assert!(e.to_string().contains("plastic"), "{e}");

    let (mut elastic, c) = runner(&[]);
    let es = study(&mut elastic, &c, 1, &tmp("el"), false);
    let (mut hard, _) = runner(&j2("material.yield_stress=1e15"));
    let hs = study(&mut hard, &c, 1, &tmp("hard"), false);
    assert_eq!(scalar(&hs, 0, "max_equivalent_plastic_strain"), 0.0);
    let (ze, zh) = (&es.passes[0].z.0, &hs.passes[0].z.0);
    let scale = softway::growth::spectrum::rms(ze);
    let diff = ze
        .iter()
        .zip(zh)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    assert!(diff < 1e-9 * scale, "{diff:e} against {scale:e}");
    for dir in [a, b] {
        let _ = std::fs::remove_dir_all(dir);
    }
}
