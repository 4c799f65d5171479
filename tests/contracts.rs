//! The integrator contract below the driver: `predict` returns the step it predicted (its
//! `beta`, maps and force per multiplier), and `finish` reads that value, not a state left
//! in the integrator; so the order of the calls between them does not matter.

use softway::assembly::Assembler;
use softway::mesh::{Cells, Mesh};
use softway::model::{LinearModel, LoadFn, State};
use softway::time::classic::{ClassicParams, ClassicStepper};
use softway::time::integrator::{MultiplierUnit, Step, TimeIntegrator};
use softway::time::params::beta;
use softway::time::sdof;
use softway::time::step::Stepper;
use softway::time::SpaceTimeParams;
use std::collections::BTreeMap;

fn one_dof(m: f64, k: f64) -> LinearModel {
    let mesh = Mesh {
        dim: 1,
        coords: vec![0.0],
        cells: Cells::Bar2(vec![]),
        node_sets: BTreeMap::new(),
    };
    LinearModel {
        m: vec![m],
        k: vec![k],
        c: vec![0.0],
        assembler: Assembler::new(&mesh),
    }
}

/// One prediction from `s0` at `t0` without load: the step, the predictors and `x_free`.
fn predict(st: &mut dyn TimeIntegrator, t0: f64, s0: &State) -> (Step, State, Vec<f64>) {
    let load: LoadFn = Box::new(|_, f| f.fill(0.0));
    let (mut pred, mut x, mut f) = (State::zeros(1), vec![0.0], vec![0.0]);
    let step = st.predict(t0, s0, &load, &[0.0], &mut f, &mut pred, &mut x);
    (step, pred, x)
}

/// A space-time oscillator whose `gamma` changes at `t = 0.5` (0 -> 0.6): the step predicted
/// at `t0 = 0.2` carries `beta = 1 - alpha/(1 + 0) = 0.2` (Eq. 24) and the one at `0.7`
/// `beta = 1 - alpha/1.6 = 0.5`. Finishing the first step after predicting the second gives
/// the same end state bit for bit as finishing it at once (the integrator used to keep the
/// last predicted `beta` and apply it to whatever step was finished), and that end state is
/// Eqs. (9)-(10) in closed form with the first step's `beta`.
#[test]
fn a_predicted_step_is_finished_with_its_own_beta_whatever_was_predicted_since() {
    let (m, k, alpha, h) = (2.5, 40.0, 0.8, 0.1);
    let p = SpaceTimeParams {
        alpha,
        gamma: 0.0,
        h,
    };
    let mut st = Stepper::new(&one_dof(m, k), p, &[])
        .unwrap()
        .with_schedule(vec![(0.5, 0.6)]);
    let s0 = State {
        u: vec![0.3],
        v: vec![-1.2],
        a: vec![0.0],
    };
    let (a, pred_a, x_a) = predict(&mut st, 0.2, &s0);
    assert_eq!(a, st.step_at(0.2));
    assert_eq!(
        (a.t0, a.h, a.unit, a.explicit),
        (0.2, h, MultiplierUnit::Impulse, false)
    );
    assert_eq!(a.weight, beta(alpha, 0.0));
    assert!((a.weight - 0.2).abs() < 1e-15);
    assert_eq!(
        (a.maps.mu_u, a.maps.mu_v, a.maps.force),
        (h * a.weight, 1.0, 1.0 / h)
    );
    let mut alone = State::zeros(1);
    st.finish(&a, &s0, &pred_a, &x_a, &mut alone);

    let (b, _, _) = predict(&mut st, 0.7, &s0);
    assert!(
        (b.weight - 0.5).abs() < 1e-15,
        "beta after the switch: {}",
        b.weight
    );
    let mut after = State::zeros(1);
    st.finish(&a, &s0, &pred_a, &x_a, &mut after);
    assert_eq!(after, alone);

    let (u1, v1) = sdof::step(m, k, 0.0, p, s0.u[0], s0.v[0]);
    assert!(
        (alone.u[0] - u1).abs() < 1e-14 * (1.0 + u1.abs()),
        "{} {u1}",
        alone.u[0]
    );
    assert!(
        (alone.v[0] - v1).abs() < 1e-14 * (1.0 + v1.abs()),
        "{} {v1}",
        alone.v[0]
    );
    // With the second step's beta the end state would differ: the test can tell.
    let pb = SpaceTimeParams { gamma: 0.6, ..p };
    let (u1b, _) = sdof::step(m, k, 0.0, pb, s0.u[0], s0.v[0]);
    assert!((u1b - u1).abs() > 1e-3, "{u1b} {u1}");
}

/// Newmark's average acceleration: the step is `mu_u = beta_N h^2`, `mu_v = gamma_N h`, a
/// force per unit multiplier, the displacement weight `beta_N h`; the end state is
/// `u1 = U + mu_u a1`, `v1 = V + mu_v a1`, and the undamped oscillator keeps its energy
/// `(m v^2 + k u^2)/2` over a step (the trapezoidal rule), to round-off.
#[test]
fn the_newmark_step_carries_its_maps_and_conserves_the_oscillators_energy() {
    let (m, k, h) = (2.5, 40.0, 0.1);
    let params = ClassicParams::average_acceleration();
    let mut st = ClassicStepper::new(&one_dof(m, k), params, h, &[]).unwrap();
    let load: LoadFn = Box::new(|_, f| f.fill(0.0));
    let mut s0 = State {
        u: vec![0.3],
        v: vec![-1.2],
        a: vec![0.0],
    };
    st.initialize(0.0, &mut s0, &load, &[]).unwrap();
    assert!(
        (s0.a[0] + k * 0.3 / m).abs() < 1e-14,
        "a0 = -k u0 / m: {}",
        s0.a[0]
    );
    let (step, pred, x) = predict(&mut st, 0.0, &s0);
    assert_eq!(step.unit, MultiplierUnit::Force);
    // "Explicit" is a diagonal `A`, as one dof's is (`ClassicStepper::is_diagonal`).
    assert_eq!(step.explicit, st.is_diagonal());
    assert_eq!(step.weight, 0.25 * h);
    assert_eq!(
        (step.maps.mu_u, step.maps.mu_v, step.maps.force),
        (0.25 * h * h, 0.5 * h, 1.0)
    );
    let mut s1 = State::zeros(1);
    TimeIntegrator::finish(&st, &step, &s0, &pred, &x, &mut s1);
    assert_eq!(s1.u[0], pred.u[0] + step.maps.mu_u * x[0]);
    assert_eq!(s1.v[0], pred.v[0] + step.maps.mu_v * x[0]);
    let energy = |s: &State| 0.5 * (m * s.v[0] * s.v[0] + k * s.u[0] * s.u[0]);
    assert!(
        (energy(&s1) - energy(&s0)).abs() < 1e-14 * energy(&s0),
        "{} {}",
        energy(&s1),
        energy(&s0)
    );
    let cd =
        ClassicStepper::new(&one_dof(m, k), ClassicParams::central_difference(), h, &[]).unwrap();
    assert!(cd.step_at(0.0).explicit);
}
