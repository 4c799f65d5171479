//! The space-time step of the wheel (free step: right-hand side, solve, update) on the
//! hexagonal disks of 12 (the paper's), 48 and 192 rings and on the graded disks of the
//! converged wheel (288 and 576 rim nodes, clamped hub); the structure and the
//! factorization are built outside the timed loop. Also the step with four nodes held on the base (multipliers
//! through the factored matrix). Compare the sizes as ratios within one run.
//!
//! `wheel_step/free_before`: the free step as it was before issue 11 (faer's default sparse
//! LU, COLAMD ordering and its generic solve; two sparse products for the right-hand side),
//! beside `wheel_step/free` (softway's factor and solve now) in the same run.
//!
//! `wheel_step/free_extrapolated`, `wheel_step/four_held_extrapolated`: the same steps with
//! the Coriolis term on the right-hand side (`time.coriolis = "extrapolated"`): a Cholesky
//! factor of the symmetric part, one more vector gathered by the right-hand side.
//!
//! `factor/*`: the free step with each factorization of `A` on the same ladder, in one run:
//! the LU with COLAMD (faer's default ordering, softway's factor before issue 11), the LU
//! with AMD (the default for the wheel, whose Coriolis term makes `A` unsymmetric), and on
//! the wheel without its Coriolis term (a symmetric `A`) the Cholesky factor (the default for
//! symmetric matrices), beside faer's supernodal Cholesky and its own solve
//! (`no_coriolis_llt_faer_supernodal`). The stored entries of each factor are printed on
//! stderr.
//!
//! `threads/1`, `threads/2`: the free step of the meshes whose factor is split into two parts
//! solved side by side (10,000 dofs and more: 48 and 192 rings) on a pool of one thread and
//! of two; the speed-up is their ratio in one run.
//!
//! `bandwidth/*`: a streaming read of 1, 16 and 256 MiB (the caches and the memory). A
//! floor for each free step is printed on stderr: the bytes the step reads, as stored
//! (`Stepper::free_step_bytes`: the factors' arrays as the solve reads them, the right-hand
//! side's, the vectors), over the read bandwidth measured on a block of that same size (the
//! level of the memory the step's data lives in), by one thread or, for a split factor,
//! two.

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::sparse::linalg::cholesky::{factorize_symbolic_cholesky, CholeskySymbolicParams, LltRef};

use faer::sparse::linalg::SupernodalThreshold;
use faer::sparse::SparseColMatRef;
use faer::Side;
use faer::{Conj, MatMut, Par};
use softway::contact::rows::{Row, RowKind, RowSolver, Terms};
use softway::linalg::team::Team;
use softway::linalg::{spmv_add, FactorKind, FaerLu, HugeBuf, Ordering};
use softway::mesh::generators::{disk_graded, disk_rings, DiskOptions};
use softway::mesh::Mesh;
use softway::time::step::{FactorChoice, Stepper};
use softway::time::{Coriolis, SpaceTimeParams};
use softway::wheel::{Support, WheelModel, WheelSpec};

/// The ladder: (label, mesh, support) of the paper's family and of the converged wheel.
fn ladder() -> Vec<(String, Mesh, Support)> {
    let mut l: Vec<(String, Mesh, Support)> = [12usize, 48, 192]
        .iter()
        .map(|&r| {
            (
                format!("{r} rings"),
                disk_rings(0.1, r).unwrap(),
                Support::CentrePinned,
            )
        })
        .collect();
    for n in [288usize, 576] {
        l.push((
            format!("graded {n} rim nodes"),
            disk_graded(0.1, n, DiskOptions::default()).unwrap(),
            Support::Hub { radius: 0.01 },
        ));
    }
    l
}

/// The wheel on `mesh` with `support` (the paper's data otherwise), the benches' step
/// (alpha 0.8, gamma 0.2, h = 2 us) and its fixed dofs as Dirichlet conditions.
fn wheel(mesh: Mesh, support: Support) -> (WheelModel, SpaceTimeParams, Vec<(usize, f64)>) {
    let spec = WheelSpec {
        support,
        ..WheelSpec::paper()
    };
    let w = WheelModel::new(mesh, spec).unwrap();
    let p = SpaceTimeParams {
        alpha: 0.8,
        gamma: 0.2,
        h: 2e-6,
    };
    let bcs = w.fixed_dofs.iter().map(|&d| (d, 0.0)).collect();
    (w, p, bcs)
}

/// Four neighbouring rim nodes held on the base (their vertical velocity zero), from the
/// bottom of the wheel: the rows of the contact solve.
fn four_held(w: &WheelModel) -> RowSolver {
    let n = w.model.n();
    let bottom = w.rim.len() * 3 / 4;
    let mut rows = RowSolver::new(n, 4, 8);
    for k in 0..4 {
        let node = w.rim[(bottom + k) % w.rim.len()];
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
    rows
}

/// `free{suffix}` (right-hand side, solve, update) and `four_held{suffix}` (the same with
/// four rim nodes held through the factored matrix) of `st` from the state `(u, v, a)`.
fn free_and_held(
    g: &mut criterion::BenchmarkGroup<'_, criterion::measurement::WallTime>,
    label: &str,
    suffix: &str,
    st: &mut Stepper,
    w: &WheelModel,
    [u, v, a]: [&[f64]; 3],
) {
    let n = w.model.n();
    let (mut b, mut u1) = (vec![0.0; n], vec![0.0; n]);
    let mut rows = four_held(w);
    g.bench_with_input(
        BenchmarkId::new(format!("free{suffix}"), format!("{label}, {n} dofs")),
        &n,
        |bch, _| {
            // On a thread of the pool, as a run is (`run::run_scenario`).
            rayon::scope(|_| {
                bch.iter(|| {
                    st.rhs_into(u, v, a, &w.load, &mut b);
                    st.solve(&mut b);
                    st.update_displacement(0.333, u, v, &b, &mut u1);
                    b[0]
                })
            })
        },
    );
    g.bench_with_input(
        BenchmarkId::new(format!("four_held{suffix}"), format!("{label}, {n} dofs")),
        &n,
        |bch, _| {
            rayon::scope(|_| {
                bch.iter(|| {
                    st.rhs_into(u, v, a, &w.load, &mut b);
                    st.solve(&mut b);
                    rows.solve(st, &mut b, 0.0);
                    st.update_displacement(0.333, u, v, &b, &mut u1);
                    rows.lambda()[0]
                })
            })
        },
    );
}

fn bench_step(c: &mut Criterion) {
    let mut g = c.benchmark_group("wheel_step");
    g.sample_size(10);
    for (label, mesh, support) in ladder() {
        let (w, p, bcs) = wheel(mesh, support);
        let n = w.model.n();
        let mut st = Stepper::new(&w.model, p, &bcs).unwrap();
        {
            let bytes = st.free_step_bytes();
            // A split factor is read by two threads: its floor is that of two readers.
            let threads = if st.factor_parts().is_some() { 2 } else { 1 };
            let bw = read_bandwidth_gb_s(bytes, threads);
            eprintln!(
                "floor: {label}, {n} dofs: {:.2} MB per free step at {bw:.1} GB/s ({threads} thread(s)) = {:.1} us",
                bytes as f64 / 1e6,
                bytes as f64 / (bw * 1e3)
            );
            if let Some((p0, p1, top)) = st.factor_parts() {
                eprintln!("parts: {label}: {p0} and {p1} unknowns side by side, then {top}");
            }
        }
        let u = w.u_spin.clone();
        let v: Vec<f64> = (0..n).map(|i| 1e-3 * (i as f64).sin()).collect();
        let mut b = vec![0.0; n];
        let mut u1 = vec![0.0; n];
        // The free step as softway did it before issue 11: faer's default sparse LU (COLAMD,
        // its generic solve) and two sparse products for the right-hand side.
        {
            let (pattern, a, bv, k) = st.matrices();
            let (pattern, a, bv, k) = (pattern.clone(), a.to_vec(), bv.to_vec(), k.to_vec());
            let mut reference = FaerLu::new(&pattern, &a).unwrap();
            let h = p.h;
            g.bench_with_input(
                BenchmarkId::new("free_before", format!("{label}, {n} dofs")),
                &n,
                |bch, _| {
                    bch.iter(|| {
                        for (bi, fi) in b.iter_mut().zip(&w.load) {
                            *bi = h * fi;
                        }
                        spmv_add(&pattern, &bv, 1.0, &v, &mut b);
                        spmv_add(&pattern, &k, -h, &u, &mut b);
                        for &d in &w.fixed_dofs {
                            b[d] = 0.0;
                        }
                        reference.solve_in_place(&mut b);
                        st.update_displacement(0.333, &u, &v, &b, &mut u1);
                        b[0]
                    })
                },
            );
        }
        free_and_held(&mut g, &label, "", &mut st, &w, [&u, &v, &[]]);
        drop(st);
        let mut st = Stepper::with_options(
            &w.model,
            p,
            &bcs,
            FactorChoice::Auto,
            Coriolis::Extrapolated,
        )
        .unwrap();
        eprintln!(
            "coriolis extrapolated: {label}: {:?}, factor nnz {}",
            st.factor_kind(),
            st.factor_nnz()
        );
        let acc: Vec<f64> = (0..n).map(|i| 1e-3 * (i as f64).cos()).collect();
        free_and_held(&mut g, &label, "_extrapolated", &mut st, &w, [&u, &v, &acc]);
    }
    g.finish();
}

fn bench_factor(c: &mut Criterion) {
    let mut g = c.benchmark_group("factor");
    g.sample_size(10);
    g.warm_up_time(std::time::Duration::from_millis(500));
    g.measurement_time(std::time::Duration::from_secs(2));
    for (label, mesh, support) in ladder() {
        let (w, p, bcs) = wheel(mesh, support);
        let n = w.model.n();
        let mut symmetric = w.model.clone();
        symmetric.c.fill(0.0);
        let u = w.u_spin.clone();
        let v: Vec<f64> = (0..n).map(|i| 1e-3 * (i as f64).sin()).collect();
        let mut b = vec![0.0; n];
        let cases = [
            ("lu_colamd", &w.model, FactorKind::Lu(Ordering::Colamd)),
            ("lu_amd", &w.model, FactorKind::Lu(Ordering::Amd)),
            (
                "no_coriolis_lu_colamd",
                &symmetric,
                FactorKind::Lu(Ordering::Colamd),
            ),
            (
                "no_coriolis_lu_amd",
                &symmetric,
                FactorKind::Lu(Ordering::Amd),
            ),
            ("no_coriolis_llt", &symmetric, FactorKind::Llt),
        ];
        for (name, model, kind) in cases {
            let mut st = Stepper::with_factor(model, p, &bcs, FactorChoice::Kind(kind)).unwrap();
            eprintln!("factor nnz: {label}, {n} dofs, {name}: {}", st.factor_nnz());
            g.bench_with_input(
                BenchmarkId::new(name, format!("{label}, {n} dofs")),
                &n,
                |bch, _| {
                    bch.iter(|| {
                        st.rhs_into(&u, &v, &[], &w.load, &mut b);
                        st.solve(&mut b);
                        b[0]
                    })
                },
            );
        }
        // faer's supernodal Cholesky (AMD) and its own solve, on the symmetric `A`.
        let st =
            Stepper::with_factor(&symmetric, p, &bcs, FactorChoice::Kind(FactorKind::Llt)).unwrap();
        let (pattern, a, _, _) = st.matrices();
        let symbolic = factorize_symbolic_cholesky(
            pattern.as_ref(),
            Side::Upper,
            Default::default(),
            CholeskySymbolicParams {
                supernodal_flop_ratio_threshold: SupernodalThreshold::FORCE_SUPERNODAL,
                ..Default::default()
            },
        )
        .unwrap();
        let mut l_values = vec![0.0; symbolic.len_val()];
        let mut scratch = MemBuffer::new(
            symbolic.factorize_numeric_llt_scratch::<f64>(Par::Seq, Default::default()),
        );
        symbolic
            .factorize_numeric_llt::<f64>(
                &mut l_values,
                SparseColMatRef::new(pattern.as_ref(), a),
                Side::Upper,
                Default::default(),
                Par::Seq,
                MemStack::new(&mut scratch),
                Default::default(),
            )
            .unwrap();
        eprintln!(
            "factor nnz: {label}, {n} dofs, no_coriolis_llt_faer_supernodal: {} (dense blocks)",
            symbolic.len_val()
        );
        let mut solve_scratch = MemBuffer::new(symbolic.solve_in_place_scratch::<f64>(1, Par::Seq));
        let (fixed, load) = (&w.fixed_dofs, &w.load);
        g.bench_with_input(
            BenchmarkId::new(
                "no_coriolis_llt_faer_supernodal",
                format!("{label}, {n} dofs"),
            ),
            &n,
            |bch, _| {
                bch.iter(|| {
                    st.rhs_into(&u, &v, &[], load, &mut b);
                    for &d in fixed {
                        b[d] = 0.0;
                    }
                    LltRef::new(&symbolic, &l_values).solve_in_place_with_conj(
                        Conj::No,
                        MatMut::from_column_major_slice_mut(&mut b, n, 1),
                        Par::Seq,
                        MemStack::new(&mut solve_scratch),
                    );
                    b[0]
                })
            },
        );
    }
    g.finish();
}

/// The free step on one thread and on two, for the meshes whose factor is split into two
/// parts solved side by side (`Stepper::factor_parts`): the speed-up is the ratio of the
/// two in one run. The results are the same bit for bit (asserted in `linalg`'s tests).
fn bench_threads(c: &mut Criterion) {
    let mut g = c.benchmark_group("threads");
    g.sample_size(10);
    for (label, mesh, support) in ladder() {
        let (w, p, bcs) = wheel(mesh, support);
        let n = w.model.n();
        let mut st = Stepper::new(&w.model, p, &bcs).unwrap();
        if st.factor_parts().is_none() {
            continue;
        }
        let u = w.u_spin.clone();
        let v: Vec<f64> = (0..n).map(|i| 1e-3 * (i as f64).sin()).collect();
        let mut b = vec![0.0; n];
        let mut u1 = vec![0.0; n];
        for threads in [1usize, 2] {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            // A run's team of the pool's threads (`Simulation::set_par`).
            let team = pool.install(|| Team::new(softway::linalg::team::Par::current()));
            st.set_team(&team);
            g.bench_with_input(
                BenchmarkId::new(format!("{threads}"), format!("{label}, {n} dofs")),
                &n,
                |bch, _| {
                    pool.install(|| {
                        bch.iter(|| {
                            st.rhs_into(&u, &v, &[], &w.load, &mut b);
                            st.solve(&mut b);
                            st.update_displacement(0.333, &u, &v, &b, &mut u1);
                            b[0]
                        })
                    })
                },
            );
        }
    }
    g.finish();
}

/// Bytes of the blocks whose read bandwidth `bench_bandwidth` measures.
const BANDWIDTH_BLOCKS: [usize; 3] = [1 << 20, 16 << 20, 256 << 20];

/// The sum of a block of `f64` (a streaming read; sixteen partial sums, so that the
/// additions' latency does not bound the rate: four sums read at most 8 bytes a cycle, less
/// than one thread reads from the last-level cache).
fn read_sum(block: &[f64]) -> f64 {
    let mut acc = [0.0; 16];
    for c in block.chunks_exact(16) {
        for k in 0..16 {
            acc[k] += c[k];
        }
    }
    acc.iter().sum()
}

/// Measured read bandwidth (GB/s, best of a few rounds) of a block of `bytes` (rounded up
/// to 64 KiB), read again and again: the bandwidth of the level of the memory a working set
/// of that size lives in, read by one thread or, with `threads = 2`, by two threads each
/// reading its half side by side (`rayon::join`, as a split step reads its two parts).
fn read_bandwidth_gb_s(bytes: usize, threads: usize) -> f64 {
    let size = bytes.div_ceil(64 << 10) * (64 << 10);
    // On huge pages from 1 MiB, as the step's factors and right-hand side.
    let values: Vec<f64> = (0..size / 8).map(|i| i as f64).collect();
    let block = HugeBuf::from_slice(&values);
    let (first, second) = block.split_at(block.len() / 2);
    let reps = ((1usize << 30) / size).max(2);
    // On a thread of the pool, as the step is timed.
    let best = rayon::scope(|_| {
        let mut best = f64::INFINITY;
        for _ in 0..5 {
            let t = std::time::Instant::now();
            for _ in 0..reps {
                if threads >= 2 {
                    std::hint::black_box(rayon::join(
                        || read_sum(std::hint::black_box(first)),
                        || read_sum(std::hint::black_box(second)),
                    ));
                } else {
                    std::hint::black_box(read_sum(std::hint::black_box(&block)));
                }
            }
            best = best.min(t.elapsed().as_secs_f64() / reps as f64);
        }
        best
    });
    size as f64 / best / 1e9
}

fn bench_bandwidth(c: &mut Criterion) {
    let mut g = c.benchmark_group("bandwidth");
    g.sample_size(10);
    for size in BANDWIDTH_BLOCKS {
        let block: Vec<f64> = (0..size / 8).map(|i| i as f64).collect();
        g.throughput(criterion::Throughput::Bytes(size as u64));
        g.bench_with_input(
            BenchmarkId::new("read", format!("{} MiB", size >> 20)),
            &size,
            |bch, _| bch.iter(|| read_sum(std::hint::black_box(&block))),
        );
    }
    g.finish();
}

criterion_group!(
    benches,
    bench_step,
    bench_factor,
    bench_threads,
    bench_bandwidth
);
criterion_main!(benches);
