//! A point mass on springs (a hub node of its own, `softway::element::discrete`) run through
//! the space-time step (`softway::time::step::Stepper`): its periods against the exact
//! `2 pi sqrt(m / k)`, the suddenly applied load's mean `F / k`, and the observed second
//! order of the period error on a ladder of steps (equal to the scheme's predicted error).

use softway::assembly::{Assembler, DofLayout};
use softway::element::discrete::{Discrete, Hub, Link, SpringDamper, SpringKind};
use softway::time::sdof::amplification;
use softway::time::step::{LinearModel, Stepper};
use softway::time::SpaceTimeParams;
use std::f64::consts::PI;

/// `[1.234e-5, ...]` for a printed ladder.
fn sci(v: &[f64]) -> String {
    let s: Vec<String> = v.iter().map(|x| format!("{x:.3e}")).collect();
    format!("[{}]", s.join(", "))
}

const MASS: f64 = 177.5;
const KX: f64 = 40.0e6;
const KY: f64 = 200.0e6;
const LOAD: f64 = -50.0e3;

/// A 2D hub (two translations) of mass `MASS` on a spring `KX` along x and `KY` along y to
/// the ground, loaded by `LOAD` along y.
fn hub_model() -> (LinearModel, Discrete) {
    let mut layout = DofLayout::new();
    let hub = layout.push_nodes(1, 2).start;
    let mut d = Discrete::new();
    d.add_hub(
        &layout,
        &Hub {
            node: hub,
            translations: 2,
            mass: MASS,
            inertia: 0.0,
            load: vec![0.0, LOAD],
        },
    )
    .unwrap();
    for (c, k) in [(0, KX), (1, KY)] {
        d.add_spring(SpringDamper {
            link: Link::Ground(layout.dof(hub, c).unwrap()),
            kind: SpringKind::Translational,
            stiffness: k,
            damping: 0.0,
        })
        .unwrap();
    }
    let asm = Assembler::try_with_families(layout.n_dofs(), d.families().to_vec()).unwrap();
    let (mut m, mut c, mut k) = (asm.zeros(), asm.zeros(), asm.zeros());
    d.add_matrices_into(&asm, 0, &mut m, &mut c, &mut k)
        .unwrap();
    (
        LinearModel {
            assembler: asm,
            m,
            k,
            c,
        },
        d,
    )
}

/// Runs `periods` periods of the x motion (`u_x(0) = 1 mm`, at rest) with `steps_per_period`
/// steps of the x period; the load acts from t = 0. Returns the periods of x and of
/// `y - F / k_y` measured between the first and last upward zero crossings (linear
/// interpolation), and the mean of y over whole y periods.
fn run(alpha: f64, steps_per_period: usize, periods: usize) -> (f64, f64, f64) {
    let (model, d) = hub_model();
    let tx = 2.0 * PI * (MASS / KX).sqrt();
    let h = tx / steps_per_period as f64;
    let p = SpaceTimeParams {
        alpha,
        gamma: 0.0,
        h,
    };
    let mut st = Stepper::new(&model, p, &[]).unwrap();
    let (mut u, mut v) = (vec![1.0e-3, 0.0], vec![0.0; 2]);
    let (mut b, mut u1, mut f) = (vec![0.0; 2], vec![0.0; 2], vec![0.0; 2]);
    let y_static = LOAD / KY;
    let mut cross: [Vec<f64>; 2] = [Vec::new(), Vec::new()];
    let mut y_sum = 0.0;
    let mut y_steps = 0usize;
    let steps = steps_per_period * periods;
    for i in 0..steps {
        f.fill(0.0);
        d.add_load_into(1.0, &mut f);
        st.rhs_into(&u, &v, &[], &f, &mut b);
        st.solve(&mut b);
        st.update_displacement(p.beta(), &u, &v, &b, &mut u1);
        let s0 = [u[0], u[1] - y_static];
        let s1 = [u1[0], u1[1] - y_static];
        for c in 0..2 {
            if s0[c] < 0.0 && s1[c] >= 0.0 {
                cross[c].push(h * (i as f64 + s0[c] / (s0[c] - s1[c])));
            }
        }
        if cross[1].len() == 1 || (cross[1].len() > 1 && cross[1].len() < 21) {
            y_sum += 0.5 * (u[1] + u1[1]);
            y_steps += 1;
        }
        u.copy_from_slice(&u1);
        v.copy_from_slice(&b);
    }
    let period = |c: &Vec<f64>| (c[c.len() - 1] - c[0]) / (c.len() - 1) as f64;
    (period(&cross[0]), period(&cross[1]), y_sum / y_steps as f64)
}

#[test]
fn hub_on_springs_oscillates_at_its_exact_periods() {
    let tx = 2.0 * PI * (MASS / KX).sqrt();
    let ty = 2.0 * PI * (MASS / KY).sqrt();
    for alpha in [0.5, 0.8] {
        let (px, py, mean) = run(alpha, 400, 20);
        let (ex, ey) = ((px - tx) / tx, (py - ty) / ty);
        let em = (mean - LOAD / KY) / (LOAD / KY);
        println!(
            "alpha {alpha}, T_x/400: T_x {px:.6e} s ({ex:.2e}), T_y {py:.6e} s ({ey:.2e}), mean y / (F/k) - 1 = {em:.2e}"
        );
        assert!(ex.abs() < 1e-3 && ey.abs() < 1e-3);
        assert!(em.abs() < 1e-3);
    }
}

#[test]
fn hub_period_error_falls_at_second_order() {
    let tx = 2.0 * PI * (MASS / KX).sqrt();
    for alpha in [0.5, 0.8] {
        let errs: Vec<f64> = [25, 50, 100, 200]
            .iter()
            .map(|&n| (run(alpha, n, 20).0 - tx).abs() / tx)
            .collect();
        let orders: Vec<f64> = errs.windows(2).map(|w| (w[0] / w[1]).log2()).collect();
        println!(
            "alpha {alpha}: period errors {}, orders {orders:.3?}",
            sci(&errs)
        );
        for o in orders {
            assert!((o - 2.0).abs() < 0.1, "order {o}");
        }
        // The measured period error is the scheme's, predicted by the eigenvalues of the
        // one-dof amplification matrix at omega h = 2 pi / n (Eqs. 9-10).
        for (&n, &e) in [25usize, 50, 100, 200].iter().zip(&errs) {
            let predicted = amplification(alpha, 0.0, 2.0 * PI / n as f64).period_error;
            assert!(
                (e - predicted).abs() < 1e-2 * predicted,
                "{n}: {e} vs {predicted}"
            );
        }
    }
}
