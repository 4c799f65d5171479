//! The factorizations of the step matrix (issue 11): the fast paths (LU with AMD column
//! ordering, Cholesky for a symmetric `A`) reproduce the reference LU (COLAMD, faer's
//! default) on the bar and on the wheel with and without its Coriolis term, and every
//! solution satisfies `A x = b` checked by a product with the unfactored matrix; three
//! hundred free steps of the spinning wheel with softway's factor and solves (supernodal row
//! solves on the compact factors, the right-hand side by rows) reproduce the same steps made
//! with faer's LU and its own solve and sparse products to 1e-10 (test docs). The Matrix
//! Market file of a matrix reads back to the same entries. Through the solver's trait
//! ([`Factorization`]), the tuned factorizations (compact rows, the two-part split) solve as
//! the reference ones (faer's LU and Cholesky) on the wheel's step matrices and on random
//! sparse matrices, after a refactor and in a second factorization on the same analysis,
//! and count their symbolic analyses and numeric factorizations as they make them.

use softway::linalg::{
    is_symmetric, spmv_add, spmv_into, write_matrix_market, Factor, FactorKind, Factorization,
    FaerLlt, FaerLu, Ordering, Pattern, SparseLlt, SparseLu,
};
use softway::mesh::generators::disk_rings;
use softway::model::LinearModel;
use softway::problems::bar_model;
use softway::time::step::{FactorChoice, Stepper};
use softway::time::SpaceTimeParams;
use softway::wheel::{WheelModel, WheelSpec};

/// The paper's wheel (12 rings, pinned centre): its model and its fixed dofs.
fn wheel() -> (LinearModel, Vec<(usize, f64)>) {
    let w = WheelModel::new(disk_rings(0.1, 12).unwrap(), WheelSpec::paper()).unwrap();
    let bcs = w.fixed_dofs.iter().map(|&d| (d, 0.0)).collect();
    (w.model, bcs)
}

/// The bar of the paper's Fig. 8 (40 consistent elements), free.
fn bar() -> LinearModel {
    let b = softway::problems::BarImpact {
        length: 1.0,
        ea: 1.0,
        rho_a: 1.0,
        speed: 1.0,
        gap: 0.5,
        elements: 40,
        lumped: false,
        damping: 0.0,
    };
    let mesh = b.mesh();
    bar_model(&mesh, 1.0, 1.0, false, 0.0)
}

/// `max |A x - b| / max |b|` with `A` the stepper's unfactored matrix.
fn residual(pattern: &Pattern, a: &[f64], x: &[f64], b: &[f64]) -> f64 {
    let mut ax = vec![0.0; b.len()];
    spmv_into(pattern, a, x, &mut ax);
    let scale = b.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    ax.iter()
        .zip(b)
        .fold(0.0_f64, |m, (p, q)| m.max((p - q).abs()))
        / scale
}

/// Solves `A x = b` for a fixed, dof-varying `b` with the given choice; checks the residual
/// against the unfactored matrix and returns `x` and the factor used.
fn solve(
    model: &LinearModel,
    p: SpaceTimeParams,
    bcs: &[(usize, f64)],
    choice: FactorChoice,
) -> (Vec<f64>, FactorKind) {
    let mut st = Stepper::with_factor(model, p, bcs, choice).unwrap();
    let n = model.n();
    let mut b: Vec<f64> = (0..n).map(|i| (0.37 * i as f64).sin() + 0.1).collect();
    for &(d, _) in bcs {
        b[d] = 0.0;
    }
    let rhs = b.clone();
    st.solve(&mut b);
    let (pattern, a, _, _) = st.matrices();
    let r = residual(pattern, a, &b, &rhs);
    assert!(r < 1e-12, "{choice:?}: residual {r:e}");
    (b, st.factor_kind())
}

fn max_rel_diff(x: &[f64], y: &[f64]) -> f64 {
    let scale = y.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    x.iter()
        .zip(y)
        .fold(0.0_f64, |m, (a, b)| m.max((a - b).abs()))
        / scale
}

/// The default factor is Cholesky where `A` is symmetric (the bar; the wheel without its
/// Coriolis term) and the LU with AMD ordering where it is not (the spinning wheel); each
/// reproduces the reference LU (COLAMD) to 1e-12 of the solution's largest entry.
#[test]
fn fast_factors_reproduce_the_reference_lu() {
    let reference = FactorChoice::Kind(FactorKind::Lu(Ordering::Colamd));
    let p_bar = SpaceTimeParams {
        alpha: 0.8,
        gamma: 0.0,
        h: 0.01,
    };
    let p_wheel = SpaceTimeParams {
        alpha: 0.8,
        gamma: 0.2,
        h: 2e-6,
    };
    let (spinning, bcs) = wheel();
    let mut still = spinning.clone();
    still.c.fill(0.0);
    let bar = bar();
    for (name, model, p, bcs, want) in [
        ("bar", &bar, p_bar, &[][..], FactorKind::Llt),
        (
            "wheel without Coriolis",
            &still,
            p_wheel,
            &bcs[..],
            FactorKind::Llt,
        ),
        (
            "spinning wheel",
            &spinning,
            p_wheel,
            &bcs[..],
            FactorKind::Lu(Ordering::Amd),
        ),
    ] {
        let (x_ref, kind_ref) = solve(model, p, bcs, reference);
        assert_eq!(kind_ref, FactorKind::Lu(Ordering::Colamd));
        let (x, kind) = solve(model, p, bcs, FactorChoice::Auto);
        assert_eq!(kind, want, "{name}");
        let d = max_rel_diff(&x, &x_ref);
        assert!(d < 1e-12, "{name}: {kind:?} vs the reference LU: {d:e}");
    }
}

/// Three hundred free steps of the paper's spinning wheel reproduce faer's LU
/// ([`steps_against_faers_lu`]).
#[test]
fn three_hundred_steps_reproduce_faers_lu() {
    let (v, u, parts) = steps_against_faers_lu(12, 300);
    assert!(parts.is_none(), "the paper's wheel is solved on one thread");
    assert!(v.iter().chain(&u).all(|x| x.is_finite()));
}

/// The 48-ring disk (14,114 dofs): its factor is split into two parts solved side by side
/// and its right-hand side formed in two halves (issue 11). Twenty free steps on a pool of
/// two threads reproduce faer's LU as above, and give the same velocities and displacements,
/// bit for bit, as on a pool of one thread.
#[test]
fn split_steps_reproduce_faers_lu_on_any_number_of_threads() {
    let on = |threads: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| steps_against_faers_lu(48, 20))
    };
    let (v2, u2, parts) = on(2);
    let (p0, p1, top) = parts.expect("the 48-ring factor is split");
    assert!(p0.min(p1) * 2 > p0.max(p1) && top * 10 < p0 + p1 + top);
    let (v1, u1, _) = on(1);
    let same = |x: &[f64], y: &[f64]| x.iter().zip(y).all(|(p, q)| p.to_bits() == q.to_bits());
    assert!(same(&v1, &v2) && same(&u1, &u2), "one thread against two");
}

/// `steps` free steps of the wheel on `rings` rings (its spin load, a varying initial
/// velocity): softway's step (`rhs_into`, `solve`, `update_displacement`) against the same
/// scheme made with faer's LU (COLAMD) and its generic solve, the right-hand side by two
/// column-oriented sparse products. At every step the velocities agree to 1e-10 of the
/// largest initial velocity and the displacements to 1e-10 of their largest entry. Returns
/// softway's last velocities and displacements and its factor's parts.
#[allow(clippy::type_complexity)]
fn steps_against_faers_lu(
    rings: usize,
    steps: usize,
) -> (Vec<f64>, Vec<f64>, Option<(usize, usize, usize)>) {
    let w = WheelModel::new(disk_rings(0.1, rings).unwrap(), WheelSpec::paper()).unwrap();
    let n = w.model.n();
    let p = SpaceTimeParams {
        alpha: 0.8,
        gamma: 0.2,
        h: 2e-6,
    };
    let bcs: Vec<(usize, f64)> = w.fixed_dofs.iter().map(|&d| (d, 0.0)).collect();
    let mut st = Stepper::new(&w.model, p, &bcs).unwrap();
    assert_eq!(st.factor_kind(), FactorKind::Lu(Ordering::Amd));
    let (pattern, a, bv, k) = st.matrices();
    let (pattern, a, bv, k) = (pattern.clone(), a.to_vec(), bv.to_vec(), k.to_vec());
    let mut reference = FaerLu::new(&pattern, &a).unwrap();
    let beta = p.beta();
    let v0: Vec<f64> = (0..n).map(|i| 1e-3 * (0.7 * i as f64).sin()).collect();
    let (mut u, mut v) = (w.u_spin.clone(), v0.clone());
    // The velocity decays by two orders over the steps while the right-hand side carries the
    // balance of the spin load and the elastic force (`h f - h K u`, about 1e-4 against a
    // velocity of 1e-5): that cancellation leaves round-off of the order of 1e-16 * |h K u|,
    // which two summation orders place differently. The velocities are therefore compared
    // on the scale of the initial velocity (the displacements on their own).
    let v_scale = v0.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
    let (mut u_ref, mut v_ref) = (w.u_spin.clone(), v0);
    let (mut b, mut u1) = (vec![0.0; n], vec![0.0; n]);
    for step in 0..steps {
        st.rhs_into(&u, &v, &[], &w.load, &mut b);
        st.solve(&mut b);
        st.update_displacement(beta, &u, &v, &b, &mut u1);
        std::mem::swap(&mut u, &mut u1);
        v.copy_from_slice(&b);
        // The reference step.
        for (bi, fi) in b.iter_mut().zip(&w.load) {
            *bi = p.h * fi;
        }
        spmv_add(&pattern, &bv, 1.0, &v_ref, &mut b);
        spmv_add(&pattern, &k, -p.h, &u_ref, &mut b);
        for &(d, _) in &bcs {
            b[d] = 0.0;
        }
        reference.solve_in_place(&mut b);
        for i in 0..n {
            u_ref[i] += p.h * ((1.0 - beta) * v_ref[i] + beta * b[i]);
        }
        v_ref.copy_from_slice(&b);
        let dv = v
            .iter()
            .zip(&v_ref)
            .fold(0.0_f64, |m, (a, b)| m.max((a - b).abs()))
            / v_scale;
        let du = max_rel_diff(&u, &u_ref);
        assert!(
            dv < 1e-10 && du < 1e-10,
            "step {step}: velocities {dv:e}, displacements {du:e}"
        );
    }
    let parts = st.factor_parts();
    (v, u, parts)
}

/// The Coriolis term on the right-hand side (`Coriolis::Extrapolated`) on the spinning
/// wheel: a Cholesky factor of the symmetric `A_s = M + alpha h C_s + alpha^2 h^2/2 K`, and
/// three hundred free steps reproduce the same scheme made independently (faer's LU of
/// `A_s`, the right-hand side `B_s v0 - h K u0 - h G (v0 + alpha h a0) + h f` by
/// column-oriented sparse products, `a0 = (v0 - v_-1)/h`) to 1e-10, and stay within 1e-2
/// of the initial velocity from the exact scheme's velocities (measured 3.6e-3: the initial
/// field `sin(0.7 i)` lies mostly in the highest modes, `omega h` near 1, where the
/// extrapolation's eigenvalues differ most from the exact ones, by up to 7e-4 per step
/// at this spin; `softway::time::sdof` tests).
#[test]
fn extrapolated_coriolis_steps_reproduce_an_independent_step() {
    use softway::time::Coriolis;
    let w = WheelModel::new(disk_rings(0.1, 12).unwrap(), WheelSpec::paper()).unwrap();
    let n = w.model.n();
    let p = SpaceTimeParams {
        alpha: 0.8,
        gamma: 0.2,
        h: 2e-6,
    };
    let bcs: Vec<(usize, f64)> = w.fixed_dofs.iter().map(|&d| (d, 0.0)).collect();
    let mut st = Stepper::with_options(
        &w.model,
        p,
        &bcs,
        FactorChoice::Auto,
        Coriolis::Extrapolated,
    )
    .unwrap();
    assert_eq!(st.coriolis(), Coriolis::Extrapolated);
    assert_eq!(st.factor_kind(), FactorKind::Llt);
    let mut exact = Stepper::new(&w.model, p, &bcs).unwrap();
    assert_eq!(exact.coriolis(), Coriolis::Implicit);
    // The independent step: C split by hand on the pattern.
    let pattern = w.model.pattern().clone();
    let (cp, ri) = (pattern.col_ptr(), pattern.row_idx());
    let at = |i: usize, j: usize| cp[j] + ri[cp[j]..cp[j + 1]].binary_search(&i).unwrap();
    let (mut cs, mut g) = (vec![0.0; w.model.c.len()], vec![0.0; w.model.c.len()]);
    for j in 0..n {
        for q in cp[j]..cp[j + 1] {
            let t = at(j, ri[q]);
            cs[q] = 0.5 * (w.model.c[q] + w.model.c[t]);
            g[q] = 0.5 * (w.model.c[q] - w.model.c[t]);
        }
    }
    assert_eq!(st.skew().unwrap(), &g[..]);
    let sym = LinearModel {
        c: cs,
        ..w.model.clone()
    };
    let by_hand = Stepper::new(&sym, p, &bcs).unwrap();
    assert_eq!(by_hand.factor_kind(), FactorKind::Llt);
    let (_, a_s, b_s, k) = by_hand.matrices();
    let mut reference = FaerLu::new(&pattern, a_s).unwrap();
    let beta = p.beta();
    let v0: Vec<f64> = (0..n).map(|i| 1e-3 * (0.7 * i as f64).sin()).collect();
    let v_scale = v0.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
    let (mut u, mut v, mut a) = (w.u_spin.clone(), v0.clone(), vec![0.0; n]);
    let (mut u_ref, mut v_ref, mut a_ref) = (w.u_spin.clone(), v0.clone(), vec![0.0; n]);
    let (mut u_ex, mut v_ex) = (w.u_spin.clone(), v0);
    let (mut b, mut u1, mut wv) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
    let mut worst_exact: f64 = 0.0;
    for step in 0..300 {
        st.rhs_into(&u, &v, &a, &w.load, &mut b);
        st.solve(&mut b);
        st.update_displacement(beta, &u, &v, &b, &mut u1);
        std::mem::swap(&mut u, &mut u1);
        for i in 0..n {
            a[i] = (b[i] - v[i]) / p.h;
        }
        v.copy_from_slice(&b);
        // The reference.
        for (bi, fi) in b.iter_mut().zip(&w.load) {
            *bi = p.h * fi;
        }
        for i in 0..n {
            wv[i] = v_ref[i] + p.alpha * p.h * a_ref[i];
        }
        spmv_add(&pattern, b_s, 1.0, &v_ref, &mut b);
        spmv_add(&pattern, k, -p.h, &u_ref, &mut b);
        spmv_add(&pattern, &g, -p.h, &wv, &mut b);
        for &(d, _) in &bcs {
            b[d] = 0.0;
        }
        reference.solve_in_place(&mut b);
        for i in 0..n {
            u_ref[i] += p.h * ((1.0 - beta) * v_ref[i] + beta * b[i]);
            a_ref[i] = (b[i] - v_ref[i]) / p.h;
        }
        v_ref.copy_from_slice(&b);
        let dv = v
            .iter()
            .zip(&v_ref)
            .fold(0.0_f64, |m, (x, y)| m.max((x - y).abs()))
            / v_scale;
        let du = max_rel_diff(&u, &u_ref);
        assert!(
            dv < 1e-10 && du < 1e-10,
            "step {step}: velocities {dv:e}, displacements {du:e}"
        );
        // The exact scheme.
        exact.rhs_into(&u_ex, &v_ex, &[], &w.load, &mut b);
        exact.solve(&mut b);
        exact.update_displacement(beta, &u_ex, &v_ex, &b, &mut u1);
        std::mem::swap(&mut u_ex, &mut u1);
        v_ex.copy_from_slice(&b);
        let de = v
            .iter()
            .zip(&v_ex)
            .fold(0.0_f64, |m, (x, y)| m.max((x - y).abs()))
            / v_scale;
        worst_exact = worst_exact.max(de);
    }
    assert!(
        worst_exact < 1e-2,
        "against the exact scheme: {worst_exact:e}"
    );
}

/// The symmetry test sees the skew Coriolis term and nothing else.
#[test]
fn symmetry_is_detected_on_the_values() {
    let (spinning, _) = wheel();
    let pattern = spinning.pattern();
    assert!(is_symmetric(pattern, &spinning.m, 0.0));
    assert!(is_symmetric(pattern, &spinning.k, 1e-14));
    assert!(!is_symmetric(pattern, &spinning.c, 1e-14));
}

/// A Matrix Market file lists every stored entry, 1-based, and reads back to the matrix.
#[test]
fn matrix_market_reads_back() {
    let model = bar();
    let pattern = model.pattern();
    let mut out = Vec::new();
    write_matrix_market(&mut out, pattern, &model.k, "bar stiffness").unwrap();
    let text = String::from_utf8(out).unwrap();
    let mut lines = text.lines().filter(|l| !l.starts_with('%'));
    let dims: Vec<usize> = lines
        .next()
        .unwrap()
        .split_whitespace()
        .map(|w| w.parse().unwrap())
        .collect();
    assert_eq!(dims, vec![model.n(), model.n(), model.k.len()]);
    let mut dense = vec![0.0; model.n() * model.n()];
    for l in lines {
        let w: Vec<&str> = l.split_whitespace().collect();
        let (i, j): (usize, usize) = (w[0].parse().unwrap(), w[1].parse().unwrap());
        dense[(i - 1) * model.n() + j - 1] += w[2].parse::<f64>().unwrap();
    }
    // The product with a vector agrees with the sparse product.
    let x: Vec<f64> = (0..model.n()).map(|i| 1.0 + i as f64).collect();
    let mut y = vec![0.0; model.n()];
    spmv_into(pattern, &model.k, &x, &mut y);
    for i in 0..model.n() {
        let yi: f64 = (0..model.n())
            .map(|j| dense[i * model.n() + j] * x[j])
            .sum();
        assert!((yi - y[i]).abs() <= 1e-12 * y[i].abs().max(1.0), "row {i}");
    }
}

/// `(pattern, values)` of a random sparse matrix of order `n`: a structurally symmetric
/// pattern (each row coupled to `per_row` random others), random values in `[-1, 1]`
/// (symmetric ones when `symmetric`), a diagonal of one plus the row's absolute sum
/// (strictly diagonally dominant: regular, and positive definite when symmetric).
fn random_matrix(n: usize, per_row: usize, symmetric: bool, seed: u64) -> (Pattern, Vec<f64>) {
    let mut state = seed;
    let mut next = move || {
        // Knuth's MMIX linear congruential generator, the top 53 bits.
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    let mut t = Vec::new();
    for i in 0..n {
        for _ in 0..per_row {
            let j = (next() * n as f64) as usize % n;
            if j == i {
                continue;
            }
            let v = 2.0 * next() - 1.0;
            let w = if symmetric { v } else { 2.0 * next() - 1.0 };
            t.push(faer::sparse::Triplet::new(i, j, v));
            t.push(faer::sparse::Triplet::new(j, i, w));
        }
    }
    let mut row_sum = vec![0.0; n];
    for e in &t {
        row_sum[e.row] += f64::abs(e.val);
    }
    for (i, s) in row_sum.iter().enumerate() {
        t.push(faer::sparse::Triplet::new(i, i, 1.0 + s));
    }
    // Duplicates are summed, symmetrically: the sums stay symmetric and dominated.
    let m = faer::sparse::SparseColMat::<usize, f64>::try_new_from_triplets(n, n, &t).unwrap();
    (m.symbolic().to_owned().unwrap(), m.val().to_vec())
}

/// `x` with `A x = b` by `F`, for a fixed, index-varying `b`.
fn solved<F: Factorization>(f: &mut F) -> Vec<f64> {
    let mut x: Vec<f64> = (0..f.n()).map(|i| (0.37 * i as f64).sin() + 0.1).collect();
    f.solve_in_place(&mut x);
    x
}

/// The tuned factorization `F` against the reference `R` on `values` and on two other
/// matrices of the same pattern (the diagonal scaled by 1.5, then by 2: diagonally dominant
/// alike), each solution within `1e-12` of the reference's largest entry: factored, then
/// refactored on the same analysis, then in a second factorization sharing it. The counts:
/// one analysis and one numeric factorization, one analysis and two, none and one.
/// Returns the largest relative difference seen.
fn tuned_against_reference<F: Factorization, R: Factorization>(
    name: &str,
    pattern: &Pattern,
    values: &[f64],
) -> f64 {
    let scaled = |s: f64| -> Vec<f64> {
        let (cp, ri) = (pattern.col_ptr(), pattern.row_idx());
        let mut v = values.to_vec();
        for j in 0..pattern.ncols() {
            for p in cp[j]..cp[j + 1] {
                if ri[p] == j {
                    v[p] *= s;
                }
            }
        }
        v
    };
    let agree = |x: &[f64], values: &[f64], what: &str| {
        let x_ref = solved(&mut R::factor(pattern, values).unwrap());
        let d = max_rel_diff(x, &x_ref);
        assert!(d < 1e-12, "{name}, {what}: {d:e} from the reference");
        let b: Vec<f64> = (0..x.len())
            .map(|i| (0.37 * i as f64).sin() + 0.1)
            .collect();
        let r = residual(pattern, values, x, &b);
        assert!(r < 1e-12, "{name}, {what}: residual {r:e}");
        d
    };
    let mut f = F::factor(pattern, values).unwrap();
    assert_eq!(f.n(), pattern.nrows());
    assert_eq!((f.symbolic_analyses(), f.numeric_factorizations()), (1, 1));
    let mut worst = agree(&solved(&mut f), values, "factor");
    let v2 = scaled(1.5);
    f.refactor(pattern, &v2).unwrap();
    assert_eq!((f.symbolic_analyses(), f.numeric_factorizations()), (1, 2));
    worst = worst.max(agree(&solved(&mut f), &v2, "refactor"));
    let v3 = scaled(2.0);
    let mut g = f.with_values(pattern, &v3).unwrap();
    assert_eq!((g.symbolic_analyses(), g.numeric_factorizations()), (0, 1));
    assert_eq!((f.symbolic_analyses(), f.numeric_factorizations()), (1, 2));
    worst = worst.max(agree(&solved(&mut g), &v3, "with_values"));
    // The first factor still holds its own values.
    worst.max(agree(&solved(&mut f), &v2, "refactor, after with_values"))
}

/// The tuned LU and Cholesky (compact rows below 1,500 unknowns, the two-part split from
/// there on) solve as faer's LU and Cholesky through the solver's trait: on the step
/// matrices of the paper's wheel (938 dofs) and of an 18-ring wheel (2,054 dofs, split),
/// spinning (unsymmetric: LU) and without the Coriolis term (symmetric positive definite:
/// Cholesky), and on random sparse matrices, unsymmetric and symmetric positive definite.
#[test]
fn tuned_factorizations_solve_as_the_reference_through_the_trait() {
    let p = SpaceTimeParams {
        alpha: 0.8,
        gamma: 0.2,
        h: 2e-6,
    };
    let mut worst: f64 = 0.0;
    for rings in [12, 18] {
        let w = WheelModel::new(disk_rings(0.1, rings).unwrap(), WheelSpec::paper()).unwrap();
        let bcs: Vec<(usize, f64)> = w.fixed_dofs.iter().map(|&d| (d, 0.0)).collect();
        let mut still = w.model.clone();
        still.c.fill(0.0);
        for (model, kind) in [
            (&w.model, FactorKind::Lu(Ordering::Amd)),
            (&still, FactorKind::Llt),
        ] {
            let st = Stepper::with_factor(model, p, &bcs, FactorChoice::Kind(kind)).unwrap();
            assert_eq!(st.factor_parts().is_some(), rings == 18, "{rings} rings");
            let (pattern, a, _, _) = st.matrices();
            let name = format!("{rings}-ring wheel, {kind:?}");
            worst = worst.max(match kind {
                FactorKind::Llt => {
                    assert!(is_symmetric(pattern, a, 1e-14));
                    tuned_against_reference::<SparseLlt, FaerLlt>(&name, pattern, a)
                }
                _ => tuned_against_reference::<SparseLu, FaerLu>(&name, pattern, a),
            });
            worst = worst.max(tuned_against_reference::<Factor, FaerLu>(&name, pattern, a));
        }
    }
    for n in [700, 2000] {
        let (pattern, unsym) = random_matrix(n, 4, false, 29 + n as u64);
        assert!(!is_symmetric(&pattern, &unsym, 1e-3));
        let name = format!("random unsymmetric, order {n}");
        worst = worst.max(tuned_against_reference::<SparseLu, FaerLu>(
            &name, &pattern, &unsym,
        ));
        let (pattern, spd) = random_matrix(n, 4, true, 31 + n as u64);
        let name = format!("random SPD, order {n}");
        worst = worst.max(tuned_against_reference::<SparseLlt, FaerLlt>(
            &name, &pattern, &spd,
        ));
        worst = worst.max(tuned_against_reference::<SparseLlt, FaerLu>(
            &name, &pattern, &spd,
        ));
    }
    println!("largest relative difference from the reference: {worst:e}");
}
