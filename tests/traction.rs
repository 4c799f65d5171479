//! The driven and braked wheel (`rolling.creepage` with `contact.friction`): full slip
//! carries exactly `mu P`, the creep curve rises monotonically through a free-rolling point
//! with a slope of Carter's order `2 R / (mu a)`, free rolling does not slide at the rolling
//! speed, stick/slip changes cost no factorization, and a creepage without friction is
//! refused.
//!
//! Carter is the exact answer of the uncoupled problem (`rolling.coupling = "uncoupled"`,
//! elastically similar bodies), and the creep force converges to it on a rim ladder
//! ([`uncoupled_creep_force_converges_to_carter_on_a_rim_ladder`]). It is not the answer of
//! the coupled one: on a rigid base the pressure strains the wheel only
//! (Dundurs' beta = 0.35 in plane stress, of the order of mu = 0.3), so the wheel has a
//! free-rolling creepage and the creep curve is not Carter's. Measured on the rim ladder
//! 144 / 288 / 576 nodes: free-rolling creepage 0.0021 / 0.0033 / 0.0046 and slope through it
//! 81 / 71 / 62 against Carter's 81-83 (not mesh-converged: docs/src/friction.md).
//! The slope is asserted within 30% of Carter's, which a wrong unit or sign would fail.
//!
//! The wheel is `scenarios/creep-curve.toml` on a coarser rim (144 nodes: the patch spans
//! about four rim pitches), a tenth of a turn after settling: about two seconds a run.

mod common;

use softway::build::resolve;
use softway::run::{run_scenario, RunOptions};
use softway::scenario::{set_key, Scenario};
use softway::simulation::Simulation;
use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;

fn scenario_text(rim_nodes: usize) -> String {
    let text = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("scenarios/creep-curve.toml"),
    )
    .unwrap();
    let text = set_key(&text, "wheel.rim_nodes", &rim_nodes.to_string()).unwrap();
    // Plots are not what these tests look at.
    set_key(&text, "output.plots", "false").unwrap()
}

fn scenario(xi: f64) -> Scenario {
    scenario_on(144, xi, "coupled")
}

/// The creep-curve wheel on `rim_nodes` rim nodes at creepage `xi`, with `rolling.coupling`.
fn scenario_on(rim_nodes: usize, xi: f64, coupling: &str) -> Scenario {
    let text = set_key(
        &scenario_text(rim_nodes),
        "rolling.creepage",
        &xi.to_string(),
    )
    .unwrap();
    let text = set_key(&text, "rolling.coupling", &format!("\"{coupling}\"")).unwrap();
    resolve(&Scenario::from_str(&text, Path::new("creep-curve-test.toml")).unwrap()).unwrap()
}

fn out_dir(name: &str) -> PathBuf {
    std::env::temp_dir().join(format!("softway-traction-{}-{name}", std::process::id()))
}

/// `(Q / (mu P), mean stick nodes, mean slip nodes, Hertz a)` of a run at creepage `xi`,
/// written in a folder of its own for the test `tag` (tests run in parallel).
fn traction(tag: &str, xi: f64) -> (f64, f64, f64, f64) {
    let t = traction_block(&format!("{tag}-xi{xi}"), &scenario(xi));
    let f = |k: &str| t[k].as_f64().unwrap();
    (
        f("traction_ratio"),
        f("mean_stick_nodes"),
        f("mean_slip_nodes"),
        f("hertz_half_width"),
    )
}

/// The `traction` block of `summary.json` of a run of `sc`, in a folder of its own for the
/// test `tag`.
/// Every run also asserts that friction dissipates ([`assert_dissipates`]).
fn traction_block(tag: &str, sc: &Scenario) -> serde_json::Value {
    let dir = out_dir(tag);
    run_scenario(sc, &dir, &RunOptions::default()).unwrap();
    let s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap();
    std::fs::remove_dir_all(&dir).ok();
    common::assert_dissipates(&s["traction"], OMEGA, sc.runs[0].params.h);
    s["traction"].clone()
}

/// `rolling.omega` of `scenarios/creep-curve.toml`, rad/s.
const OMEGA: f64 = 300.0;

/// Carter's problem (`rolling.coupling = "uncoupled"`: the tangential tractions on a twin
/// disk, so the pressure strains nothing the slip sees): free rolling carries no creep
/// force, braking is driving mirrored, and on the rim ladder 144 / 288 / 576 the creep force
/// at a creepage of 0.5 % (partial slip, Q about 0.37 mu P) approaches Carter's
/// `Q/(mu P) = 1 - (1 - xi R/(mu a))^2` with the error falling at every rung and within 2 %
/// on the finest; its stick zone is Carter's `c = a sqrt(1 - Q/(mu P))` within a quarter of
/// a rim pitch, centred at Carter's `a - c` (the leading edge) within half a pitch, and the
/// RMS difference of the traction profile from Carter's `q(s)` falls at every rung, below a
/// tenth of `mu p0` on the finest. Measured: errors +8.9 %, +3.3 %, +1.0 % (1152 rim nodes:
/// +0.2 %; docs/src/friction.md); profile 0.113, 0.082, 0.072 (1152: 0.062).
#[test]
fn uncoupled_creep_force_converges_to_carter_on_a_rim_ladder() {
    let free = traction_block("unc-free", &scenario_on(144, 0.0, "uncoupled"));
    let ratio = |t: &serde_json::Value| t["traction_ratio"].as_f64().unwrap();
    assert!(ratio(&free).abs() < 0.01, "free rolling: {free}");
    let braked = traction_block("unc-braked", &scenario_on(144, -0.005, "uncoupled"));
    let (mut errors, mut profile) = (Vec::new(), Vec::new());
    for rim in [144, 288, 576] {
        let t = traction_block(&format!("unc-{rim}"), &scenario_on(rim, 0.005, "uncoupled"));
        let f = |k: &str| t[k].as_f64().unwrap();
        if rim == 144 {
            assert!(
                (ratio(&braked) + f("traction_ratio")).abs() < 0.02,
                "{braked} {t}"
            );
        }
        errors.push(f("traction_ratio") / f("carter_traction_ratio") - 1.0);
        let pitch = f("pitch_over_half_width") * f("hertz_half_width");
        let dc = f("measured_stick_half_width") - f("carter_stick_half_width");
        assert!(
            dc.abs() < 0.25 * pitch + 0.02 * f("hertz_half_width"),
            "{rim} rim nodes: stick half-width off Carter's by {dc} m: {t}"
        );
        // The stick zone at the leading edge (s > 0), where Carter puts it, `a - c`.
        let dx = f("measured_stick_centre") - f("carter_stick_centre");
        assert!(
            f("measured_stick_centre") > 0.0 && dx.abs() < 0.5 * pitch,
            "{rim} rim nodes: stick zone centred {dx} m off Carter's: {t}"
        );
        profile.push(f("carter_traction_rms"));
    }
    for e in [&errors, &profile] {
        for w in e.windows(2) {
            assert!(w[1].abs() < w[0].abs(), "not falling: {e:?}");
        }
    }
    assert!(errors[2].abs() < 0.02, "{errors:?}");
    assert!(profile[2] < 0.1, "{profile:?}");
}

/// Full slip carries `mu P`. On the 288-node rim: 0.99999 at both signs. (On 144 rim nodes
/// it is 0.9974, with half a node sticking on average: an arriving node's impact impulse
/// bounds a friction impulse large enough to stop its slip for a step, a share of the force
/// that falls with the rim pitch.)
#[test]
fn full_slip_carries_mu_p_with_the_sign_of_the_creepage() {
    // Carter's saturation creepage is mu a / R = 0.024: 0.04 slides the whole patch.
    for xi in [0.04, -0.04] {
        let t = traction_block(&format!("full-slip-{xi}"), &scenario_on(288, xi, "coupled"));
        let f = |k: &str| t[k].as_f64().unwrap();
        let (ratio, stick, slip) = (
            f("traction_ratio"),
            f("mean_stick_nodes"),
            f("mean_slip_nodes"),
        );
        assert!(
            (ratio - xi.signum()).abs() < 1e-3,
            "xi {xi}: Q/(mu P) = {ratio}"
        );
        assert!(stick < 0.02 * slip, "xi {xi}: stick {stick}, slip {slip}");
    }
}

#[test]
fn creep_curve_rises_through_free_rolling_with_carters_slope() {
    let xis = [-0.01, 0.0, 0.005, 0.01, 0.02];
    let runs: Vec<(f64, f64, f64, f64)> = xis.iter().map(|&x| traction("curve", x)).collect();
    for w in runs.windows(2) {
        assert!(w[1].0 > w[0].0, "not increasing: {runs:?}");
    }
    // Partial slip in between: both stick and slip nodes in the patch.
    assert!(runs[3].1 > 0.5 && runs[3].2 > 0.5, "{runs:?}");
    // The free-rolling creepage (Q = 0) lies between 0 and 0.005 (an elastic wheel on a rigid
    // base: the pressure strains the wheel's surface only).
    assert!(runs[1].0 < 0.0 && runs[2].0 > 0.0, "{runs:?}");
    // Carter's initial slope d(Q/mu P)/d xi = 2 R / (mu a), through the free-rolling point.
    let (mu, radius, a) = (0.3, 0.1, runs[2].3);
    let slope = (runs[2].0 - runs[1].0) / 0.005;
    let carter = 2.0 * radius / (mu * a);
    assert!(
        (slope / carter - 1.0).abs() < 0.3,
        "slope {slope} vs Carter {carter}"
    );
}

/// Free rolling with friction at zero creepage transmits a small creep force only (the
/// free-rolling offset), not the full slip of a base sliding at omega rho.
#[test]
fn free_rolling_with_friction_does_not_slide_at_the_rolling_speed() {
    let (ratio, stick, slip, _) = traction("free", 0.0);
    assert!(ratio.abs() < 0.4, "{ratio}");
    assert!(stick > 2.0 * slip, "stick {stick}, slip {slip}");
}

#[test]
fn stick_slip_changes_cost_no_factorization() {
    let sc = scenario(0.01);
    let run = &sc.runs[0];
    let Some(ws) = run.model.get::<softway::scenario::WheelScenario>() else {
        panic!("a wheel")
    };
    let wm = softway::kinds::wheel::run::build(ws, &sc.path).unwrap();
    let steps = 2_800;
    // One gamma throughout (a gamma schedule refactors once when it changes).
    let mut pb = wm.problem(run.integrator, run.params.h, vec![], run.contact, steps);
    pb.friction = Some(0.3.into());
    let mut sim = Simulation::new(pb).unwrap();
    let stats = sim.run(&AtomicBool::new(false), |_| Ok(())).unwrap();
    assert!(stats.stick_slip_changes > 10, "{stats:?}");
    assert!(stats.factorizations <= 2, "{stats:?}");
}

#[test]
fn creepage_without_friction_is_refused() {
    let text = set_key(&scenario_text(144), "rolling.creepage", "0.01").unwrap();
    let text = set_key(&text, "contact.friction", "0.0").unwrap();
    let err = Scenario::from_str(&text, Path::new("t.toml")).unwrap_err();
    let msg = err.to_string();
    assert!(
        msg.contains("rolling.creepage") && msg.contains("contact.friction"),
        "{msg}"
    );
    for bad in ["1.5", "nan"] {
        let text = set_key(&scenario_text(144), "rolling.creepage", bad).unwrap();
        let msg = Scenario::from_str(&text, Path::new("t.toml"))
            .unwrap_err()
            .to_string();
        assert!(msg.contains("rolling.creepage"), "{msg}");
    }
}

/// Friction dissipates (issue 33), on the driven wheel in partial slip (xi = 0.01, 144 rim
/// nodes, the stick zone at the leading edge, slip at the trailing one): every pair's
/// `slip_power = -F_t s_1` is `>= 0` at every step to the round-off floor `1e3 eps omega R
/// |F_t|` (a sticking pair's end slip rate is its row's residual, a difference of speeds of
/// order `omega R`: measured 1-30 `eps omega R`), the friction energy never falls by more
/// than the sum of those floors, and friction never reports more than the energy that left
/// the wheel.
///
/// The balance, in the wheel's frame (`M v' + C v + K u = f + r`, `C`'s skew Coriolis part
/// doing no work, `K` the effective stiffness about the spinning equilibrium and `f` its
/// constant load): the energy `E = v.M v/2 + u.K u/2 - f.u` gains the base's work `W` less
/// the friction's `D` and less what the scheme takes out (`gamma`'s numerical dissipation, the
/// kinetic energy of the velocity jumps of arriving nodes and of slips stopped within a step).
/// `W` is summed independently of `D`: the normal force on the node's normal displacement
/// (a held node moves with the base) and the friction force on the rail's displacement over
/// the step, `h [(1 - beta) w_t0 + beta w_t1]` (Eq. 10's rule on the rail velocities of the
/// rows of the previous step and of this one, the velocities a sticking node is held to).
/// Asserted: `W - dE - D >= -1e-3 W` (measured: +3% of `W`, the scheme's share). Exact
/// enforcement (the soft way gives momentum back at release as a load of its own).
#[test]
fn friction_dissipates_at_every_pair_and_step_within_the_energy_the_base_supplies() {
    use softway::linalg::sparse::quadratic_form;
    let sc = scenario(0.01);
    let run = &sc.runs[0];
    let Some(ws) = run.model.get::<softway::scenario::WheelScenario>() else {
        panic!("a wheel")
    };
    let wm = softway::kinds::wheel::run::build(ws, &sc.path).unwrap();
    let steps = 3_000;
    let problem = || {
        let exact = softway::contact::Treatment::Exact;
        let mut pb = wm.problem(run.integrator, run.params.h, vec![], exact, steps);
        pb.friction = Some(0.3.into());
        pb
    };
    let pb = problem();
    // A second copy for the rows' geometry and the energy (the first moves into the run).
    let geo = problem();
    let base = wm.base();
    let floor_v = 1e3 * f64::EPSILON * base.omega * base.radius;
    let h = pb.h;
    let mut f = vec![0.0; geo.model.n()];
    (geo.load)(0.0, &mut f);
    let energy = |u: &[f64], v: &[f64]| {
        let fu: f64 = f.iter().zip(u).map(|(a, b)| a * b).sum();
        0.5 * quadratic_form(geo.model.pattern(), &geo.model.m, v)
            + 0.5 * quadratic_form(geo.model.pattern(), &geo.model.k, u)
            - fu
    };
    let beta = match run.integrator {
        softway::time::Integrator::SpaceTime { alpha, gamma, .. } => 1.0 - alpha / (1.0 + gamma),
        _ => panic!("the creep wheel runs the space-time scheme"),
    };
    let mut u0 = geo.u0.clone();
    let mut w_prev = vec![f64::NAN; geo.pairs.len()];
    let (mut e0, mut base_work, mut last_d) = (None, 0.0, 0.0);
    let (mut min_speed, mut min_drop_margin) = (f64::INFINITY, f64::INFINITY);
    let (mut e_end, mut d_end) = (0.0, 0.0);
    let mut sim = Simulation::new(pb).unwrap();
    sim.run(&AtomicBool::new(false), |view| {
        let s = view.state;
        let (obst, ifc, x) = (&geo.obstacles, &geo.interfaces, &geo.reference);
        let mut allowed = 0.0;
        for (p, (pair, ps)) in geo.pairs.iter().zip(&s.pairs).enumerate() {
            // The rows' geometry of this step: at t1 on u0.
            let tangent = pair.tangent(obst, ifc, 2, x, &u0, s.t, 0).unwrap();
            if ps.force != 0.0 {
                let g = pair.geometry(obst, ifc, 2, x, &u0, s.t);
                base_work += ps.force * (g.terms.dot(&s.u) - g.terms.dot(&u0));
            }
            let ft = ps.tangential_force;
            if ft != 0.0 {
                // The rail's displacement over the step by Eq. (10)'s rule on the rows' rail
                // velocities of the previous step and this one.
                let w0 = if w_prev[p].is_nan() {
                    tangent.w
                } else {
                    w_prev[p]
                };
                base_work += h * ft * ((1.0 - beta) * w0 + beta * tangent.w);
                min_speed = min_speed.min(ps.slip_power / ft.abs() / floor_v);
                allowed += h * ft.abs() * floor_v;
            }
            w_prev[p] = tangent.w;
        }
        u0.copy_from_slice(&s.u);
        let d = view.friction_dissipated;
        // The step's fall of the friction energy against its floor: >= 0 when within it.
        let margin = (d - last_d + allowed) / allowed.max(f64::MIN_POSITIVE);
        min_drop_margin = min_drop_margin.min(margin);
        last_d = d;
        let e = energy(&s.u, &s.v);
        e0.get_or_insert(e);
        (e_end, d_end) = (e, d);
        Ok(())
    })
    .unwrap();
    let de = e_end - e0.unwrap();
    let scheme = base_work - de - d_end;
    eprintln!(
        "least slip_power / (|F_t| floor) {min_speed:.3e}; base's work {base_work:.4e} J, energy change {de:.4e} J, friction {d_end:.4e} J, the scheme's share {scheme:.4e} J ({:.4} of the work)",
        scheme / base_work
    );
    assert!(min_speed >= -1.0, "{min_speed}");
    assert!(min_drop_margin >= 0.0, "{min_drop_margin}");
    assert!(d_end > 0.0 && base_work > 0.0, "{d_end} {base_work}");
    assert!(scheme >= -1e-3 * base_work, "{scheme} of {base_work}");
}
