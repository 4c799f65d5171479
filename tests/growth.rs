//! The growth driver: the wear step against a runner whose wear is known in closed form,
//! the smoothing's effect, the reference pass, resume giving the same bits, Ctrl-C keeping
//! the finished passes; the wheel's runner on the paper's wheel; the scenario tables.

use softway::growth::report::summary;
use softway::growth::spectrum::{smoothing_gain, window_samples};
use softway::growth::{
    run_study, GrowthConfig, PassResult, PassRunner, Roughness, StudyState, SurfaceProfile,
    CHECKPOINT,
};
use softway::run::RunError;
use softway::wear::{FrictionalPower, WearLaw};
use std::f64::consts::PI;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};

/// A runner whose wear per sample is `c + b z + q z^2 + mesh(x)`: a uniform part `c`, a
/// feedback `b z` (each harmonic of the profile scaled), an optional nonlinearity and a
/// fixed pattern `mesh` that does not depend on the profile (what the reference pass
/// removes). Optionally sets the interrupt during a given pass.
struct Synthetic {
    n: usize,
    dx: f64,
    c: f64,
    b: f64,
    q: f64,
    mesh_order: usize,
    mesh_amp: f64,
    interrupt_at: Option<usize>,
    calls: usize,
}

impl Synthetic {
    fn new(b: f64) -> Self {
        Self {
            n: 128,
            dx: 2.0 * PI * 0.1 / 128.0,
            c: 3e-9,
            b,
            q: 0.0,
            mesh_order: 5,
            mesh_amp: 2e-10,
            interrupt_at: None,
            calls: 0,
        }
    }
}

impl PassRunner for Synthetic {
    fn grid(&self) -> (f64, f64, usize, bool) {
        (0.0, self.dx, self.n, true)
    }
    fn speed(&self) -> f64 {
        30.0
    }
    fn run_pass(
        &mut self,
        profile: &SurfaceProfile,
        pass: usize,
        interrupt: &AtomicBool,
    ) -> Result<PassResult, RunError> {
        self.calls += 1;
        if self.interrupt_at == Some(pass) {
            interrupt.store(true, Ordering::SeqCst);
        }
        let wear = profile
            .z
            .iter()
            .enumerate()
            .map(|(i, &z)| {
                let mesh =
                    self.mesh_amp * (2.0 * PI * (self.mesh_order * i) as f64 / self.n as f64).cos();
                self.c + self.b * z + self.q * z * z + mesh
            })
            .collect();
        Ok(PassResult {
            wear_depth: wear,
            plastic: vec![0.0; self.n],
            scalars: vec![("pass".into(), pass as f64)],
        })
    }

    fn run_reference(
        &mut self,
        profile: &SurfaceProfile,
        interrupt: &AtomicBool,
    ) -> Result<PassResult, RunError> {
        self.run_pass(profile, 0, interrupt)
    }
    fn carried_state(&self) -> Option<Vec<f64>> {
        None
    }
    fn restore_state(&mut self, state: Option<&[f64]>) -> Result<(), String> {
        softway::growth::no_carried_state(state)
    }
    /// No body: any finite profile.
    fn check_profile(&self, z: &[f64]) -> Result<(), String> {
        match z.iter().position(|v| !v.is_finite()) {
            None => Ok(()),
            Some(i) => Err(format!("sample {i} is {}", z[i])),
        }
    }
    fn extra_outputs(
        &mut self,
        _out: &Path,
        _bands: &[(f64, f64)],
        _plots: bool,
        _interrupt: &AtomicBool,
    ) -> Result<Vec<PathBuf>, RunError> {
        Ok(Vec::new())
    }
}

fn config(roughness: Roughness, smoothing_m: f64, reference: bool) -> GrowthConfig {
    GrowthConfig {
        passes: 5,
        passes_per_pass: 50.0,
        smoothing_m,
        cutoff_m: 0.0,
        reference,
        roughness,
        roughness_key: "growth.amplitude",
        wear: WearLaw::FrictionalPower(FrictionalPower { k_mass: 5.3e-9 }),
        wear_density: None,
        rail: Default::default(),
    }
}

fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("softway-growth-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn study(
    r: &mut Synthetic,
    c: &GrowthConfig,
    target: usize,
    out: &Path,
    resume: bool,
) -> softway::growth::StudyOutcome {
    let flag = AtomicBool::new(false);
    run_study(r, c, target, out, resume, "sha", &flag, |state, _| {
        softway::growth::report::write_all(out, state, c, 30.0, (false, false)).map(|_| ())
    })
    .unwrap()
}

/// A harmonic of order k under wear `b z` changes by the factor `1 - N_w b g_k` per simulated
/// pass (`g_k` the smoothing's gain), so its growth rate is
/// `20 log10 |1 - N_w b g_k| / N_w * 1e5` dB per 1e5 real passes; the uniform part is the
/// uniform loss; the reference removes the fixed pattern (its order stays at zero).
#[test]
fn growth_rate_of_a_harmonic_is_the_closed_form_with_and_without_smoothing() {
    let k = 9usize;
    let n = 128;
    let length = 2.0 * PI * 0.1;
    for (b, smoothing) in [(-4e-4, 0.0), (2e-3, 0.0), (-4e-4, 0.02)] {
        let mut r = Synthetic::new(b);
        let c = config(
            Roughness::Harmonic {
                amplitude: 1e-6,
                wavelength: length / k as f64,
            },
            smoothing,
            true,
        );
        let out = tmp(&format!("closed-{b}-{smoothing}"));
        let o = study(&mut r, &c, 6, &out, false);
        let s = summary(&o.state, &c, 30.0);
        let g = smoothing_gain(window_samples(r.dx, smoothing), k, n);
        let factor = 1.0 - c.passes_per_pass * b * g;
        let want = 20.0 * factor.abs().log10() / c.passes_per_pass * 1e5;
        let got = &s.orders[k - 1];
        assert!(
            (got.rate_db_per_1e5 - want).abs() < 1e-6 * want.abs().max(1.0),
            "b {b}, smoothing {smoothing}: {} against {want}",
            got.rate_db_per_1e5
        );
        assert!((got.rate_last_db_per_1e5 - want).abs() < 1e-6 * want.abs().max(1.0));
        // The uniform loss: N_w c per pass.
        let loss = 6.0 * c.passes_per_pass * r.c;
        assert!((s.uniform_loss_m / loss - 1.0).abs() < 1e-9);
        // The fixed pattern was removed by the reference pass.
        assert!(s.orders[r.mesh_order - 1].amplitude_final_m < 1e-18);
        assert!(s.reference_wear_rms_m.unwrap() > 1e-10);
        // Smoothing over 20 mm (5 samples of 4.9 mm) scales the order-9 wear by g < 1.
        if smoothing > 0.0 {
            assert!(g < 0.9 && g > 0.0, "{g}");
        }
        let _ = std::fs::remove_dir_all(&out);
    }
    // A cutoff above the harmonic's wavelength: its wear is removed, it does not change.
    let mut r = Synthetic::new(2e-3);
    let mut c = config(
        Roughness::Harmonic {
            amplitude: 1e-6,
            wavelength: length / k as f64,
        },
        0.0,
        true,
    );
    c.cutoff_m = 1.01 * length / k as f64;
    let out = tmp("cutoff");
    let o = study(&mut r, &c, 3, &out, false);
    let s = summary(&o.state, &c, 30.0);
    assert!(s.orders[k - 1].rate_db_per_1e5.abs() < 1e-9);
    assert!((s.orders[k - 1].amplitude_final_m / 1e-6 - 1.0).abs() < 1e-12);
    let _ = std::fs::remove_dir_all(&out);
    // Without the reference the fixed pattern grows linearly: N_w mesh_amp per pass.
    let mut r = Synthetic::new(0.0);
    let c = config(Roughness::None, 0.0, false);
    let out = tmp("no-reference");
    let o = study(&mut r, &c, 4, &out, false);
    let s = summary(&o.state, &c, 30.0);
    let a = s.orders[r.mesh_order - 1].amplitude_final_m;
    assert!(
        (a / (4.0 * c.passes_per_pass * r.mesh_amp) - 1.0).abs() < 1e-9,
        "{a:e}"
    );
    let _ = std::fs::remove_dir_all(&out);
}

/// A study stopped after 3 passes and resumed to 7 gives the same bits as 7 passes at once
/// (profiles, wear, the files written from them).
#[test]
fn resume_gives_the_same_bits() {
    let c = config(
        Roughness::Spectrum {
            bands: vec![
                (0.1, -10.0),
                (0.05, -12.0),
                (0.0251, -15.0),
                (0.0126, -18.0),
            ],
            seed: 3,
        },
        0.012,
        true,
    );
    let make = || {
        let mut r = Synthetic::new(-3e-4);
        r.q = 50.0; // a nonlinearity: orders mix
        r
    };
    let a = tmp("resume-a");
    let o_a = study(&mut make(), &c, 7, &a, false);
    let b = tmp("resume-b");
    let o_b1 = study(&mut make(), &c, 3, &b, false);
    assert_eq!(o_b1.state.passes.len(), 3);
    let mut r = make();
    let o_b = study(&mut r, &c, 7, &b, true);
    assert_eq!(
        r.calls, 4,
        "the resumed study runs the 4 passes left, no reference again"
    );
    assert_eq!(o_b.passes_run, 4);
    for (p, q) in o_a.state.passes.iter().zip(&o_b.state.passes) {
        let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(&p.z.0), bits(&q.z.0));
        assert_eq!(bits(&p.wear.0), bits(&q.wear.0));
    }
    for f in ["profile.csv", "bands.csv", "orders.csv"] {
        let x = std::fs::read(a.join(f)).unwrap();
        let y = std::fs::read(b.join(f)).unwrap();
        assert!(x == y, "{f} differs");
    }
    // The checkpoint read back is the state.
    let read = StudyState::read(&b.join(CHECKPOINT)).unwrap();
    assert_eq!(read.passes.len(), 7);
    assert_eq!(read.passes[6].z, o_a.state.passes[6].z);
    // A checkpoint of another scenario text is refused.
    let flag = AtomicBool::new(false);
    let e = run_study(&mut make(), &c, 8, &b, true, "other", &flag, |_, _| Ok(()))
        .unwrap_err()
        .to_string();
    assert!(e.contains("another scenario"), "{e}");
    let _ = std::fs::remove_dir_all(&a);
    let _ = std::fs::remove_dir_all(&b);
}

/// Ctrl-C during a pass: the pass is dropped, the finished ones are kept in the checkpoint.
#[test]
fn interrupt_keeps_the_finished_passes() {
    let c = config(
        Roughness::Harmonic {
            amplitude: 1e-6,
            wavelength: 0.05,
        },
        0.0,
        false,
    );
    let out = tmp("interrupt");
    let mut r = Synthetic::new(1e-4);
    r.interrupt_at = Some(2);
    let flag = AtomicBool::new(false);
    let o = run_study(&mut r, &c, 5, &out, false, "sha", &flag, |_, _| Ok(())).unwrap();
    assert!(o.interrupted);
    assert_eq!(o.state.passes.len(), 2);
    assert_eq!(
        StudyState::read(&out.join(CHECKPOINT))
            .unwrap()
            .passes
            .len(),
        2
    );
    let _ = std::fs::remove_dir_all(&out);
}

/// The paper's wheel (scenarios/polygon.toml, coarsened): a pass wears the rim where it
/// slips; the mean force is the smooth wheel's; the wear of one turn integrates to the
/// friction energy of the turn through the law (frictional power: worn mass = k_mass x
/// frictional work).
#[test]
fn wheel_pass_wears_by_the_frictional_work() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenarios/polygon.toml");
    let sets: Vec<softway::scenario::Override> = [
        "wheel.rim_nodes=96",
        "time.h=1e-5",
        "rolling.settle_time=1.5e-3",
        "growth.reference=false",
    ]
    .iter()
    .map(|s| softway::scenario::Override::parse(s).unwrap())
    .collect();
    let sc = softway::scenario::Scenario::from_file_with(&path, &sets).unwrap();
    let sc = softway::build::resolve(&sc).unwrap();
    let cfg = sc.growth.clone().unwrap();
    let mut runner = softway::kinds::wheel::growth::WheelPassRunner::new(
        &sc,
        cfg.wear,
        cfg.wear_density,
        softway::run::Par::Seq,
    )
    .unwrap();
    let (_, dx, n, periodic) = runner.grid();
    assert!(periodic && n == 96);
    let flat = SurfaceProfile {
        x0: 0.0,
        dx,
        z: vec![0.0; n],
        periodic: true,
    };
    let flag = AtomicBool::new(false);
    let r = runner.run_pass(&flat, 0, &flag).unwrap();
    let get = |k: &str| r.scalars.iter().find(|s| s.0 == k).unwrap().1;
    assert!(r.wear_depth.iter().all(|w| *w >= 0.0));
    let mean = r.wear_depth.iter().sum::<f64>() / n as f64;
    assert!(mean > 0.0);
    // The worn mass of the turn over k_mass is the frictional work of the turn: about the
    // creep force times the creepage's slip distance, Q xi (2 pi R).
    let mass = mean * n as f64 * dx * 0.01 * 7830.0;
    let work = mass / 5.3e-9;
    let q = get("mean_tangential_force_n").abs();
    let slip_distance = 0.01 * 2.0 * PI * 0.1;
    let ratio = work / (q * slip_distance);
    assert!(
        ratio > 0.5 && ratio < 1.5,
        "work {work:e} J against Q xi L {:e} J",
        q * slip_distance
    );
    // The same pass on a rim with a 1 um harmonic: the mean force stays the smooth wheel's.
    let z: Vec<f64> = (0..n)
        .map(|i| 1e-6 * (2.0 * PI * (7 * i) as f64 / n as f64).sin())
        .collect();
    let rough = SurfaceProfile { z, ..flat };
    let r2 = runner.run_pass(&rough, 1, &flag).unwrap();
    let f1 = get("mean_force_n");
    let f2 = r2.scalars.iter().find(|s| s.0 == "mean_force_n").unwrap().1;
    assert!((f2 / f1 - 1.0).abs() < 1e-3, "{f1} {f2}");
}

/// The scenario's [growth] / [wear] tables: unknown keys and bad values refused naming the
/// file and the key.
#[test]
fn growth_tables_are_validated() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenarios/polygon.toml");
    let text = std::fs::read_to_string(&path).unwrap();
    let bad = [
        (
            "passes_per_pass = 100.0",
            "passes_per_pass = 0.0",
            "growth.passes_per_pass",
        ),
        ("smoothing = 5e-3", "smoothin = 5e-3", "smoothin"),
        ("law = \"frictional_power\"", "law = \"magic\"", "wear.law"),
        ("seed = 1", "seed = 1\namplitude = 1e-6", "growth.amplitude"),
    ];
    for (from, to, key) in bad {
        let t = text.replacen(from, to, 1);
        let e = softway::scenario::Scenario::from_str(&t, Path::new("polygon.toml"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("polygon.toml") && e.contains(key), "{e}");
    }
}
