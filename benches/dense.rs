//! The contact rows' dense solve (`C A^-1 C^T lambda = g`, `contact::rows`) at the sizes a
//! 3D rolling patch poses: 3 rows a node in contact, 40 to 256 nodes. `elimination/k` is the
//! unblocked Gaussian elimination (`linalg::dense_solve_in_place`), `blocked/k` faer's blocked
//! LU through `linalg::DenseLu` from its threshold `BLOCKED_MIN_ROWS` up. The system is diagonally dominant with a nonsymmetric part, like a patch's with
//! sliding rows.

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};

use softway::linalg::{dense_solve_in_place, DenseLu, BLOCKED_MIN_ROWS};

fn system(k: usize) -> (Vec<f64>, Vec<f64>) {
    let s = (0..k * k)
        .map(|i| {
            let (a, b) = (i / k, i % k);
            let near = 1.0 / (1.0 + (a as f64 - b as f64).abs());
            near + 0.01 * (0.37 * i as f64).sin() + if a == b { 2.0 } else { 0.0 }
        })
        .collect();
    let r = (0..k).map(|i| (1.1 * i as f64).cos()).collect();
    (s, r)
}

fn bench(c: &mut Criterion) {
    let mut g = c.benchmark_group("dense");
    g.sample_size(20);
    for k in [48, 64, 120, 240, 429, 768] {
        let (s, r) = system(k);
        let (mut s1, mut r1) = (s.clone(), r.clone());
        g.bench_with_input(BenchmarkId::new("elimination", k), &k, |b, &k| {
            b.iter(|| {
                s1.copy_from_slice(&s);
                r1.copy_from_slice(&r);
                dense_solve_in_place(&mut s1, &mut r1, k);
            })
        });
        if k >= BLOCKED_MIN_ROWS {
            let mut lu = DenseLu::new();
            g.bench_with_input(BenchmarkId::new("blocked", k), &k, |b, &k| {
                b.iter(|| {
                    s1.copy_from_slice(&s);
                    r1.copy_from_slice(&r);
                    lu.solve_in_place(&mut s1, &mut r1, k);
                })
            });
        }
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
