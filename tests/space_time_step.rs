//! The multi-degree-of-freedom step against the closed form of Eqs. (9)-(10), and the
//! multiplier solve against a direct solve of the bordered system.

use faer::linalg::solvers::Solve;
use softway::assembly::Assembler;
use softway::contact::rows::{Row, RowKind, RowSolver, Terms};
use softway::mesh::{Cells, Mesh};
use softway::model::LinearModel;
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
    let asm = Assembler::new(&mesh);
    LinearModel {
        m: vec![m],
        k: vec![k],
        c: vec![0.0],
        assembler: asm,
    }
}

#[test]
fn one_dof_step_is_eq_9_and_eq_10_exactly() {
    let (m, k) = (2.5, 40.0);
    for (alpha, gamma, h) in [
        (0.8, 0.0, 0.05),
        (0.75, 0.2, 0.2),
        (1.0, 0.0, 0.01),
        (0.71, 0.5, 0.3),
    ] {
        let p = SpaceTimeParams { alpha, gamma, h };
        let mut st = Stepper::new(&one_dof(m, k), p, &[]).unwrap();
        let (mut u, mut v) = (vec![0.3], vec![-1.2]);
        let (mut xr, mut vr) = (0.3, -1.2);
        let mut b = vec![0.0];
        let mut u1 = vec![0.0];
        for _ in 0..50 {
            st.rhs_into(&u, &v, &[], &[0.0], &mut b);
            st.solve(&mut b);
            st.update_displacement(p.beta(), &u, &v, &b, &mut u1);
            (u[0], v[0]) = (u1[0], b[0]);
            (xr, vr) = sdof::step(m, k, 0.0, p, xr, vr);
            assert!((u[0] - xr).abs() < 1e-12 * (1.0 + xr.abs()));
            assert!((v[0] - vr).abs() < 1e-12 * (1.0 + vr.abs()));
        }
    }
}

#[test]
fn multipliers_match_the_bordered_system() {
    // A chain of 6 bars, 7 nodes; constrain nodes 2 and 6 (normal +1 and -1).
    let n_el = 6;
    let mesh = Mesh {
        dim: 1,
        coords: (0..=n_el).map(|i| i as f64 * 0.2).collect(),
        cells: Cells::Bar2((0..n_el).map(|i| [i, i + 1]).collect()),
        node_sets: BTreeMap::new(),
    };
    let asm = Assembler::new(&mesh);
    let mut m = asm.zeros();
    let mut k = asm.zeros();
    let mut c = asm.zeros();
    asm.assemble_serial_into(&mut m, |_, o| {
        o.copy_from_slice(&[0.2 / 3.0, 0.1 / 3.0, 0.1 / 3.0, 0.2 / 3.0])
    });
    asm.assemble_serial_into(&mut k, |_, o| o.copy_from_slice(&[5.0, -5.0, -5.0, 5.0]));
    asm.assemble_serial_into(&mut c, |_, o| o.copy_from_slice(&[0.01, 0.0, 0.0, 0.01]));
    let model = LinearModel {
        assembler: asm.clone(),
        m,
        k,
        c,
    };
    let p = SpaceTimeParams {
        alpha: 0.8,
        gamma: 0.1,
        h: 0.05,
    };
    let mut st = Stepper::new(&model, p, &[(0, 0.0)]).unwrap();
    let n = n_el + 1;
    let u: Vec<f64> = (0..n).map(|i| 0.01 * i as f64).collect();
    let v: Vec<f64> = (0..n).map(|i| (i as f64 * 0.7).sin()).collect();
    let f: Vec<f64> = (0..n).map(|i| 0.1 * i as f64).collect();
    let mut b = vec![0.0; n];
    st.rhs_into(&u, &v, &[], &f, &mut b);
    let b0 = b.clone();
    // Velocity constraints c.v1 = g as equality rows y = -g + c.x on x = v1.
    let cons = [(2usize, 1.0, 0.25), (6, -1.0, 0.1)];
    let mut rows = RowSolver::new(n, 2, 2);
    for (q, &(node, c, g)) in cons.iter().enumerate() {
        let mut terms = Terms::default();
        terms.push(node, c);
        rows.push(Row {
            pair: q,
            terms,
            kind: RowKind::Equality,
            y0: -g,
            mu: 1.0,
            reg: 0.0,
        });
    }
    st.solve(&mut b);
    rows.solve(&mut st, &mut b, 0.0);
    let lam = rows.lambda().to_vec();
    // Direct dense bordered solve with the Dirichlet dof 0 eliminated.
    let (a, hh) = (p.alpha, p.h);
    let md = asm.to_dense(&model.m);
    let kd = asm.to_dense(&model.k);
    let cd = asm.to_dense(&model.c);
    let nb = n - 1 + 2;
    let mut big = faer::Mat::<f64>::zeros(nb, nb);
    let mut rhs = faer::Mat::<f64>::zeros(nb, 1);
    for i in 1..n {
        for j in 1..n {
            big[(i - 1, j - 1)] =
                md[(i, j)] + a * hh * cd[(i, j)] + 0.5 * a * a * hh * hh * kd[(i, j)];
        }
        rhs[(i - 1, 0)] = b0[i];
    }
    for (q, &(node, c, g)) in cons.iter().enumerate() {
        big[(node - 1, n - 1 + q)] = -c;
        big[(n - 1 + q, node - 1)] = c;
        rhs[(n - 1 + q, 0)] = g;
    }
    let x = big.partial_piv_lu().solve(&rhs);
    assert!(b[0].abs() < 1e-14);
    for i in 1..n {
        assert!(
            (b[i] - x[(i - 1, 0)]).abs() < 1e-10,
            "v[{i}] {} vs {}",
            b[i],
            x[(i - 1, 0)]
        );
    }
    for q in 0..2 {
        assert!((lam[q] - x[(n - 1 + q, 0)]).abs() < 1e-10);
    }
    assert!((b[2] - 0.25).abs() < 1e-12 && (-b[6] - 0.1).abs() < 1e-12);
}
