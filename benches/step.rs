//! The space-time step of the wheel (free step: right-hand side, solve, update) on disks
//! of 12 (the paper's), 48 and 192 rings; the structure and the factorization are built
//! outside the timed loop. Also the step with four nodes held on the base (multipliers
//! through the factored matrix). Compare the sizes as ratios within one run.

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use softway::contact::rows::{Row, RowKind, RowSolver, Terms};
use softway::mesh::generators::disk_rings;
use softway::time::step::Stepper;
use softway::time::SpaceTimeParams;
use softway::wheel::{WheelModel, WheelSpec};

fn wheel(rings: usize) -> WheelModel {
    let spec = WheelSpec::paper();
    WheelModel::new(disk_rings(0.1, rings).unwrap(), spec).unwrap()
}

fn bench_step(c: &mut Criterion) {
    let mut g = c.benchmark_group("wheel_step");
    g.sample_size(10);
    for rings in [12usize, 48, 192] {
        let w = wheel(rings);
        let n = w.model.n();
        let p = SpaceTimeParams {
            alpha: 0.8,
            gamma: 0.2,
            h: 2e-6,
        };
        let bcs: Vec<(usize, f64)> = w.fixed_dofs.iter().map(|&d| (d, 0.0)).collect();
        let mut st = Stepper::new(&w.model, p, &bcs).unwrap();
        let u = w.u_spin.clone();
        let v: Vec<f64> = (0..n).map(|i| 1e-3 * (i as f64).sin()).collect();
        let mut b = vec![0.0; n];
        let mut u1 = vec![0.0; n];
        let bottom = w.rim[w.rim.len() * 3 / 4];
        let mut rows = RowSolver::new(n, 4, 8);
        for k in 0..4 {
            let node = w.rim[(w.rim.iter().position(|&x| x == bottom).unwrap() + k) % w.rim.len()];
            let mut terms = Terms::default();
            terms.push(2 * node + 1, 1.0);
            rows.push(Row {
                pair: k,
                terms,
                kind: RowKind::Equality,
                y0: 0.0,
                mu: 1.0,
                reg: 0.0,
            });
        }
        g.bench_with_input(
            BenchmarkId::new("free", format!("{rings} rings, {n} dofs")),
            &rings,
            |bch, _| {
                bch.iter(|| {
                    st.rhs_into(&u, &v, &w.load, &mut b);
                    st.solve(&mut b);
                    st.update_displacement(0.333, &u, &v, &b, &mut u1);
                    b[0]
                })
            },
        );
        g.bench_with_input(
            BenchmarkId::new("four_held", format!("{rings} rings, {n} dofs")),
            &rings,
            |bch, _| {
                bch.iter(|| {
                    st.rhs_into(&u, &v, &w.load, &mut b);
                    st.solve(&mut b);
                    rows.solve(&mut st, &mut b, 0.0);
                    st.update_displacement(0.333, &u, &v, &b, &mut u1);
                    rows.lambda()[0]
                })
            },
        );
    }
    g.finish();
}

criterion_group!(benches, bench_step);
criterion_main!(benches);
