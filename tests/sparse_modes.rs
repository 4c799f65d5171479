//! The sparse shift-invert modes (`softway modes` at any size) against the dense analyses:
//! at rest and spinning on the paper's mesh, spinning on a graded hub wheel, and on
//! `wheel.toml` (beyond the dense spinning analysis's size) against the first-order Coriolis
//! splitting.

use softway::modes::{natural_modes, natural_modes_sparse, spinning_modes, spinning_modes_sparse};
use softway::scenario::{Override, Scenario};
use softway::wheel::WheelModel;
use std::path::Path;

/// The wheel of a shipped scenario, with overrides.
fn shipped(name: &str, sets: &[&str]) -> WheelModel {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("scenarios")
        .join(name);
    let text = std::fs::read_to_string(&path).unwrap();
    let sets: Vec<Override> = sets.iter().map(|s| Override::parse(s).unwrap()).collect();
    let sc: Scenario<_> = softway::scenario::overrides::read_with(
        &text,
        &path,
        &sets,
        &softway::kinds::Registry::builtin(),
    )
    .unwrap()
    .0;
    let Some(ws) = sc.runs[0].model.get::<softway::scenario::WheelScenario>() else {
        panic!("{name} is not a wheel")
    };
    softway::kinds::wheel::run::build(ws, &sc.path).unwrap()
}

fn assert_close(what: &str, dense: &[(f64, String)], sparse: &[(f64, String)], tol: f64) {
    assert_eq!(
        dense.len(),
        sparse.len(),
        "{what}: {dense:?} against {sparse:?}"
    );
    for (d, s) in dense.iter().zip(sparse) {
        assert_eq!(d.1, s.1, "{what}: {dense:?} against {sparse:?}");
        let err = if d.0 == 0.0 {
            s.0.abs()
        } else {
            (s.0 / d.0 - 1.0).abs()
        };
        assert!(err <= tol, "{what}: {} against {} Hz ({err:e})", s.0, d.0);
    }
    println!(
        "{what}: {} modes agree, e.g. {:.6} Hz",
        dense.len(),
        dense.last().unwrap().0
    );
}

#[test]
fn rest_and_spinning_modes_on_the_paper_mesh_match_the_dense_ones() {
    let wm = shipped("wheel-paper-mesh.toml", &[]);
    let key = |f: f64, k: &str| (f, k.to_string());
    let d: Vec<_> = natural_modes(&wm, 12)
        .unwrap()
        .iter()
        .map(|m| key(m.frequency_hz, &m.kind))
        .collect();
    let s: Vec<_> = natural_modes_sparse(&wm, 12)
        .unwrap()
        .iter()
        .map(|m| key(m.frequency_hz, &m.kind))
        .collect();
    assert_close("paper mesh at rest", &d, &s, 1e-8);
    let dense = spinning_modes(&wm, 8).unwrap();
    let sparse = spinning_modes_sparse(&wm, 8).unwrap();
    let k = |v: &[softway::modes::SpinMode]| -> Vec<(f64, String)> {
        v.iter()
            .map(|m| key(m.frequency_hz, &format!("{} {}", m.kind, m.whirl)))
            .collect()
    };
    assert_close("paper mesh spinning", &k(&dense), &k(&sparse), 1e-8);
    let mut dj: f64 = 0.0;
    for (a, b) in dense.iter().zip(&sparse) {
        // The rest mode matched: the same frequency (either member of an exact pair).
        assert!((a.rest_frequency_hz - b.rest_frequency_hz).abs() <= 1e-8 * a.rest_frequency_hz);
        dj = dj.max((a.angular_momentum - b.angular_momentum).abs());
    }
    println!("largest difference of the modal angular momenta {dj:e}");
    assert!(dj < 1e-4);
}

#[test]
fn spinning_modes_of_a_graded_hub_wheel_match_the_dense_ones() {
    let wm = shipped("wheel.toml", &["wheel.rim_nodes=96"]);
    let k = |v: &[softway::modes::SpinMode]| -> Vec<(f64, String)> {
        v.iter()
            .map(|m| (m.frequency_hz, format!("{} {}", m.kind, m.whirl)))
            .collect()
    };
    let dense = spinning_modes(&wm, 10).unwrap();
    let sparse = spinning_modes_sparse(&wm, 10).unwrap();
    assert_close("graded 96 spinning", &k(&dense), &k(&sparse), 1e-8);
}

/// `wheel.toml` (3,408 dofs, past the dense spinning analysis): each whirling pair's half
/// difference (two modes of opposite angular momentum from a near pair of rest modes) is the
/// first-order Coriolis splitting `|Omega j| / (2 pi)` of its modal angular momentum `j`
/// (module docs of `softway::modes`), to 2%; the rest modes match the dense ones to 1e-8.
#[test]
fn spinning_modes_of_wheel_toml_split_as_coriolis_predicts() {
    let wm = shipped("wheel.toml", &[]);
    let d: Vec<_> = natural_modes(&wm, 8)
        .unwrap()
        .iter()
        .map(|m| (m.frequency_hz, m.kind.clone()))
        .collect();
    let s: Vec<_> = natural_modes_sparse(&wm, 8)
        .unwrap()
        .iter()
        .map(|m| (m.frequency_hz, m.kind.clone()))
        .collect();
    assert_close("wheel.toml at rest", &d, &s, 1e-8);
    let t0 = std::time::Instant::now();
    let modes = spinning_modes_sparse(&wm, 12).unwrap();
    println!(
        "wheel.toml spinning: {} modes in {:?}",
        modes.len(),
        t0.elapsed()
    );
    let omega = wm.spec.omega;
    for m in &modes {
        println!(
            "{:.3} Hz (rest {:.3} Hz, #{:?}), j = {:.4}, {}",
            m.frequency_hz, m.rest_frequency_hz, m.rest_index, m.angular_momentum, m.whirl
        );
    }
    // Whirling pairs: consecutive modes of opposite angular momentum, |j| > 0.5.
    let mut pairs = 0;
    for w in modes.windows(2) {
        let (f, b) = (&w[0], &w[1]);
        if f.angular_momentum.abs() < 0.5
            || (f.angular_momentum + b.angular_momentum).abs() > 0.05
            || (b.rest_frequency_hz / f.rest_frequency_hz - 1.0).abs() > 1e-3
        {
            continue;
        }
        let half = 0.5 * (b.frequency_hz - f.frequency_hz);
        let predicted = (omega * f.angular_momentum).abs() / (2.0 * std::f64::consts::PI);
        println!(
            "pair {:.2} / {:.2} Hz: half split {half:.3} Hz, first order {predicted:.3} Hz",
            f.frequency_hz, b.frequency_hz
        );
        assert!(
            (half / predicted - 1.0).abs() < 0.02,
            "{half} against {predicted}"
        );
        pairs += 1;
    }
    assert!(pairs >= 2, "{modes:?}");
}
