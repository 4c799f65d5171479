//! The lowest modes at any size: shift-invert on the sparse factorizations of the step's
//! solver (faer's LU and Cholesky behind [`crate::linalg::Factor`]), a block Krylov space
//! and a Rayleigh-Ritz projection. Nothing dense but the small projected problem: memory
//! grows as the dofs times the basis (a few dozen vectors), time as a few dozen solves.
//!
//! **At rest** ([`natural_modes_sparse`]): `K phi = mu M phi` on the free dofs, `mu =
//! omega^2`. With a shift `sigma < 0` below every eigenvalue, `A = K - sigma M` is positive
//! definite (also with rigid modes, `mu = 0`) and the operator `A^-1 M` has the eigenvalues
//! `theta = 1 / (mu - sigma)`, largest for the lowest `mu`, and is symmetric in the `M` inner
//! product. The basis `V` is `M`-orthonormal; the projected `H = V^T M A^-1 M V` is
//! symmetric and solved densely; a Ritz pair is kept when its residual
//! `|A^-1 M x - theta x|_M` is below `1e-11 theta`.
//!
//! **Spinning** ([`spinning_modes_sparse`]): `(K_eff + lambda C + lambda^2 M) phi = 0` in
//! its first companion form on `z = [phi, lambda phi]`,
//! $$\begin{pmatrix}0 & I\\\\ -K_{\rm eff} & -C\end{pmatrix} z
//!   = \lambda \begin{pmatrix}I & 0\\\\ 0 & M\end{pmatrix} z .$$
//! With a real shift `sigma < 0`, `(A - sigma B)^-1 B y` is, for `y = [y1, y2]`,
//! `x1 = -Q(sigma)^-1 (M y2 + (C + sigma M) y1)`, `x2 = y1 + sigma x1`, with
//! `Q(sigma) = K_eff + sigma C + sigma^2 M` factored once (LU: `C` is skew), `sigma` half the
//! lowest elastic rest frequency (rad/s). Its eigenvalues
//! `theta = 1 / (lambda - sigma)` are largest for the `lambda` nearest the origin, i.e. the
//! lowest frequencies `lambda = +- i omega`; the projected Hessenberg-like `H = V^T W` is
//! solved by the dense nonsymmetric eigensolver, and each Ritz value refined by the root of
//! `u^H Q(lambda) u = 0` nearest it (`u` its Ritz vector; a stationary functional of the
//! gyroscopic problem).
//!
//! Blocks of four vectors start the space, so that the pairs of equal frequencies of a disk
//! (multiplicity two) are found as pairs, which a single-vector Krylov space would miss.
//! `tests/modes.rs` checks the frequencies against the dense analyses to 1e-8.

use super::spinning::{angular_momentum, zero_frequency_modes};
use super::*;
use crate::linalg::{set_identity_rows, spmv_add, Factor, Pattern};

/// Vectors per block of the Krylov space.
const BLOCK: usize = 4;

/// A Ritz pair is kept when its residual is below this times `|theta|` (self-adjoint
/// operator; at least a millionth of the largest `|theta|`, which a rigid mode makes large)
/// or times the largest `|theta|` found (the others: their accuracy is bounded by that of
/// the solves, relative to the operator's norm).
const RITZ_TOLERANCE: f64 = 1e-11;

/// The largest Krylov basis tried, vectors.
const MAX_BASIS: usize = 1200;

/// The operator, its inner product and the dofs it lives on, for [`ritz_pairs`].
struct Operator<'a> {
    /// Length of a vector.
    len: usize,
    /// `y = OP x`.
    apply: &'a dyn Fn(&[f64], &mut [f64]),
    /// The inner product `x^T B y`.
    dot: &'a dyn Fn(&[f64], &[f64]) -> f64,
    /// Zeroes the entries of the fixed dofs.
    project: &'a dyn Fn(&mut [f64]),
    /// Whether `OP` is self-adjoint in the inner product.
    symmetric: bool,
}

/// A Ritz pair: `theta` and its vector (real and imaginary parts).
struct Ritz {
    theta: faer::c64,
    re: Vec<f64>,
    im: Vec<f64>,
}

/// A deterministic start vector (xorshift), so that a run is reproducible.
fn start_vector(len: usize, seed: u64) -> Vec<f64> {
    let mut s = seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1;
    (0..len)
        .map(|_| {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            (s >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        })
        .collect()
}

/// The `want` Ritz pairs of largest `|theta|` of `op`, all converged: a block Krylov space
/// grown until they are (at most the free dimension `dim`).
fn ritz_pairs(op: &Operator, want: usize, dim: usize) -> Result<Vec<Ritz>, ModesError> {
    let n = op.len;
    let mut v: Vec<Vec<f64>> = Vec::new();
    let mut w: Vec<Vec<f64>> = Vec::new();
    let orthonormal_add = |v: &mut Vec<Vec<f64>>, mut x: Vec<f64>| -> bool {
        (op.project)(&mut x);
        let norm0 = (op.dot)(&x, &x).sqrt();
        for _ in 0..2 {
            for q in v.iter() {
                let c = (op.dot)(q, &x);
                for (a, b) in x.iter_mut().zip(q) {
                    *a -= c * b;
                }
            }
        }
        let norm = (op.dot)(&x, &x).sqrt();
        if norm.is_nan() || norm <= 1e-10 * norm0 || !norm.is_finite() {
            return false;
        }
        x.iter_mut().for_each(|a| *a /= norm);
        v.push(x);
        true
    };
    let mut seed = 1;
    let mut next: Vec<Vec<f64>> = (0..BLOCK)
        .map(|_| {
            seed += 1;
            start_vector(n, seed)
        })
        .collect();
    let mut target = (2 * want + 2 * BLOCK).max(3 * BLOCK);
    loop {
        let before = v.len();
        // Grow the space to `target` vectors.
        while v.len() < target.min(dim) {
            let mut added = 0;
            for x in std::mem::take(&mut next) {
                if orthonormal_add(&mut v, x) {
                    added += 1;
                }
            }
            if added == 0 {
                // Deflated: restart the block from fresh vectors.
                seed += 1;
                if !orthonormal_add(&mut v, start_vector(n, seed)) {
                    break;
                }
            }
            for q in &v[w.len()..] {
                let mut y = vec![0.0; n];
                (op.apply)(q, &mut y);
                (op.project)(&mut y);
                next.push(y.clone());
                w.push(y);
            }
        }
        let m = v.len();
        let stalled = m == before;
        // The projection H = V^T B W.
        let mut h = Mat::<f64>::zeros(m, m);
        for j in 0..m {
            for i in 0..m {
                h[(i, j)] = (op.dot)(&v[i], &w[j]);
            }
        }
        let mut pairs: Vec<(faer::c64, Vec<faer::c64>)> = if op.symmetric {
            let hs = Mat::<f64>::from_fn(m, m, |i, j| 0.5 * (h[(i, j)] + h[(j, i)]));
            let e = hs
                .self_adjoint_eigen(Side::Lower)
                .map_err(|_| ModesError::NoConvergence("projected self-adjoint"))?;
            (0..m)
                .map(|k| {
                    (
                        faer::c64::new(e.S().column_vector()[k], 0.0),
                        (0..m).map(|i| faer::c64::new(e.U()[(i, k)], 0.0)).collect(),
                    )
                })
                .collect()
        } else {
            let e = h
                .eigen()
                .map_err(|_| ModesError::NoConvergence("projected nonsymmetric"))?;
            (0..m)
                .map(|k| {
                    (
                        e.S().column_vector()[k],
                        (0..m).map(|i| e.U()[(i, k)]).collect(),
                    )
                })
                .collect()
        };
        pairs.sort_by(|a, b| b.0.norm().total_cmp(&a.0.norm()));
        pairs.truncate(want.min(m));
        let theta_max = pairs.first().map_or(0.0, |p| p.0.norm());
        let mut out = Vec::with_capacity(pairs.len());
        let mut converged = true;
        for (theta, y) in pairs {
            let (mut re, mut im) = (vec![0.0; n], vec![0.0; n]);
            let (mut rre, mut rim) = (vec![0.0; n], vec![0.0; n]);
            for (k, c) in y.iter().enumerate() {
                for i in 0..n {
                    re[i] += c.re * v[k][i];
                    im[i] += c.im * v[k][i];
                    rre[i] += c.re * w[k][i];
                    rim[i] += c.im * w[k][i];
                }
            }
            // r = W y - theta V y.
            for i in 0..n {
                rre[i] -= theta.re * re[i] - theta.im * im[i];
                rim[i] -= theta.re * im[i] + theta.im * re[i];
            }
            let res = ((op.dot)(&rre, &rre) + (op.dot)(&rim, &rim)).sqrt();
            let norm = ((op.dot)(&re, &re) + (op.dot)(&im, &im)).sqrt();
            let scale = if op.symmetric {
                theta.norm().max(1e-6 * theta_max)
            } else {
                theta_max
            };
            if res.is_nan() || res > RITZ_TOLERANCE * scale * norm {
                converged = false;
            }
            out.push(Ritz { theta, re, im });
        }
        if converged && out.len() >= want.min(dim) {
            return Ok(out);
        }
        if m >= dim || target >= MAX_BASIS || stalled {
            // The whole space: the projection is the problem itself, to rounding.
            if converged || m >= dim {
                return Ok(out);
            }
            return Err(ModesError::SparseNoConvergence {
                wanted: want,
                basis: m,
            });
        }
        target = (target * 3 / 2).min(dim.max(1)).min(MAX_BASIS);
    }
}

/// `x^H A x` for `x = a + i b` and the real matrix `A` on `pattern`.
fn hermitian_form(pattern: &Pattern, values: &[f64], a: &[f64], b: &[f64]) -> faer::c64 {
    let dot = |x: &[f64], y: &[f64]| m_dot(pattern, values, x, y);
    faer::c64::new(dot(a, a) + dot(b, b), dot(a, b) - dot(b, a))
}

/// The root nearest `guess` of `u^H (K + lambda C + lambda^2 M) u = 0`, `u = a + i b`: the
/// eigenvalue of the Ritz vector `u` by the quadratic's Rayleigh functional. For the
/// gyroscopic problem (`K`, `M` symmetric, `C` skew) the left eigenvector is `conj(u)`, so
/// the functional is stationary at an eigenvector and its error is of the second order in
/// the vector's: the Krylov space's accuracy, squared.
fn rayleigh_root(
    pattern: &Pattern,
    (k, c, m): (&[f64], &[f64], &[f64]),
    a: &[f64],
    b: &[f64],
    guess: faer::c64,
) -> faer::c64 {
    let (mk, mc, mm) = (
        hermitian_form(pattern, k, a, b),
        hermitian_form(pattern, c, a, b),
        hermitian_form(pattern, m, a, b),
    );
    if mm.norm() == 0.0 {
        return guess;
    }
    let disc = (mc * mc - mk * mm * 4.0).sqrt();
    let r1 = (-mc + disc) / (mm * 2.0);
    let r2 = (-mc - disc) / (mm * 2.0);
    let best = if (r1 - guess).norm() <= (r2 - guess).norm() {
        r1
    } else {
        r2
    };
    // Keep the Ritz value if the functional lands farther than the Krylov space's own
    // accuracy allows (a vector not yet an eigenvector).
    if (best - guess).norm() <= 1e-6 * guess.norm().max(f64::MIN_POSITIVE) {
        best
    } else {
        guess
    }
}

/// `x^T M y` on `pattern`.
fn m_dot(pattern: &Pattern, m: &[f64], x: &[f64], y: &[f64]) -> f64 {
    let mut my = vec![0.0; x.len()];
    spmv_add(pattern, m, 1.0, y, &mut my);
    x.iter().zip(&my).map(|(a, b)| a * b).sum()
}

/// An estimate of the largest `mu = omega^2` of `(K, M)`: the largest `K_ii / M_ii` over
/// the free dofs.
fn mu_max_estimate(pattern: &Pattern, k: &[f64], m: &[f64], fixed: &[bool]) -> f64 {
    let cp = pattern.col_ptr();
    let ri = pattern.row_idx();
    let mut best: f64 = 0.0;
    for j in 0..pattern.ncols() {
        if fixed[j] {
            continue;
        }
        let (mut kj, mut mj) = (0.0, 0.0);
        for p in cp[j]..cp[j + 1] {
            if ri[p] == j {
                kj = k[p];
                mj = m[p];
            }
        }
        if mj > 0.0 {
            best = best.max(kj.abs() / mj);
        }
    }
    best
}

/// The rest modes by the sparse shift-invert solver: as [`natural_modes`] (the zero-frequency
/// modes, then the `count` lowest elastic ones with their wavenumbers), at any size.
///
/// # Errors
/// [`ModesError::NoFreeDofs`], [`ModesError::NotFinite`], [`ModesError::NoConvergence`];
/// a singular shifted stiffness as [`ModesError::MassNotPositive`].
pub fn natural_modes_sparse(model: &WheelModel, count: usize) -> Result<Vec<Mode>, ModesError> {
    let mut modes = natural_modes_sparse_of(&wheel_matrices(model), count)?;
    for mode in &mut modes {
        if mode.kind == "elastic" {
            mode.wavenumber = rim_wavenumber(model, &mode.shape);
        }
    }
    Ok(modes)
}

/// [`natural_modes_sparse`] for any model given by its matrices (`wavenumber` left `None`).
///
/// # Errors
/// As [`natural_modes_sparse`], plus [`ModesError::MatrixSize`] and
/// [`ModesError::FixedDofOutOfRange`].
pub fn natural_modes_sparse_of(sys: &Matrices, count: usize) -> Result<Vec<Mode>, ModesError> {
    let pattern = &sys.assembler.pattern;
    let n = pattern.nrows();
    check_values(sys.assembler, sys.m, "mass")?;
    check_values(sys.assembler, sys.k, "stiffness")?;
    let free = FreeDofs::new(n, sys.fixed_dofs)?;
    let mut fixed = vec![true; n];
    for &d in &free.dofs {
        fixed[d] = false;
    }
    let mu_max = mu_max_estimate(pattern, sys.k, sys.m, &fixed);
    let sigma = -1e-7 * mu_max;
    let mut a: Vec<f64> = sys
        .k
        .iter()
        .zip(sys.m)
        .map(|(k, m)| k - sigma * m)
        .collect();
    set_identity_rows(pattern, &mut a, &fixed);
    // The factor's solve takes `&mut` (its scratch): borrowed per application.
    let factor = std::cell::RefCell::new(
        Factor::auto(pattern, &a).map_err(|_| ModesError::MassNotPositive { index: 0 })?,
    );
    let project = |x: &mut [f64]| {
        for (xi, &f) in x.iter_mut().zip(&fixed) {
            if f {
                *xi = 0.0;
            }
        }
    };
    let apply = |x: &[f64], y: &mut [f64]| {
        y.iter_mut().for_each(|v| *v = 0.0);
        spmv_add(pattern, sys.m, 1.0, x, y);
        project(y);
        factor.borrow_mut().solve_in_place(y);
    };
    let dot = |x: &[f64], y: &[f64]| m_dot(pattern, sys.m, x, y);
    let op = Operator {
        len: n,
        apply: &apply,
        dot: &dot,
        project: &project,
        symmetric: true,
    };
    // Rigid modes are at most three in 2D: ask for that many more.
    let ritz = ritz_pairs(&op, count + 3, free.len())?;
    let tol = ZERO_FREQUENCY_RATIO * mu_max.sqrt();
    let mut found: Vec<(f64, Vec<f64>)> = ritz
        .into_iter()
        .map(|r| (sigma + 1.0 / r.theta.re, r.re))
        .collect();
    found.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut modes = Vec::new();
    let mut elastic = 0;
    for (mu, mut shape) in found {
        let w = mu.abs().sqrt();
        let kind = if mu < 0.0 && w >= tol {
            "negative stiffness".to_string()
        } else if w < tol {
            String::new()
        } else if elastic < count {
            elastic += 1;
            "elastic".to_string()
        } else {
            break;
        };
        normalise(&mut shape);
        let (frequency_hz, kind) = if kind.is_empty() {
            (0.0, rigid_kind(sys.mesh, &shape).to_string())
        } else {
            (w / (2.0 * std::f64::consts::PI), kind)
        };
        modes.push(Mode {
            frequency_hz,
            period_us: period_us(frequency_hz),
            shape,
            kind,
            wavenumber: None,
        });
    }
    Ok(modes)
}

/// The spinning wheel's modes in its rotating frame by the sparse shift-invert solver: as
/// [`spinning_modes`] (the zero-frequency modes, then the `count` lowest oscillating ones,
/// each matched to its rest mode by mass share, split pairs labelled forward / backward),
/// at any size.
///
/// # Errors
/// As [`natural_modes_sparse`].
pub fn spinning_modes_sparse(
    model: &WheelModel,
    count: usize,
) -> Result<Vec<SpinMode>, ModesError> {
    let lm = &model.model;
    let asm = &lm.assembler;
    let pattern = &asm.pattern;
    let n = pattern.nrows();
    check_values(asm, &lm.m, "mass")?;
    check_values(asm, &lm.k, "stiffness")?;
    check_values(asm, &lm.c, "damping")?;
    let free = FreeDofs::new(n, &model.fixed_dofs)?;
    let mut fixed = vec![true; n];
    for &d in &free.dofs {
        fixed[d] = false;
    }
    let w_max = mu_max_estimate(pattern, &lm.k, &lm.m, &fixed).sqrt();
    // The rest modes to match against (rigid first, as the dense analysis lists them); the
    // shift half the lowest elastic one's circular frequency, so that the modes asked for
    // are not far below the rigid ones in the operator's spectrum.
    let rest = natural_modes_sparse(model, count + 8)?;
    let w_low = rest
        .iter()
        .find(|r| r.kind == "elastic")
        .map_or(1e-4 * w_max, |r| {
            2.0 * std::f64::consts::PI * r.frequency_hz
        });
    let sigma = -0.5 * w_low;
    let mut q: Vec<f64> = (0..lm.k.len())
        .map(|p| lm.k[p] + sigma * lm.c[p] + sigma * sigma * lm.m[p])
        .collect();
    set_identity_rows(pattern, &mut q, &fixed);
    let factor = std::cell::RefCell::new(
        Factor::auto(pattern, &q).map_err(|_| ModesError::MassNotPositive { index: 0 })?,
    );
    let project = |x: &mut [f64]| {
        for (i, &f) in fixed.iter().enumerate() {
            if f {
                x[i] = 0.0;
                x[n + i] = 0.0;
            }
        }
    };
    let apply = |y: &[f64], x: &mut [f64]| {
        let (y1, y2) = y.split_at(n);
        let (x1, x2) = x.split_at_mut(n);
        x1.iter_mut().for_each(|v| *v = 0.0);
        spmv_add(pattern, &lm.m, 1.0, y2, x1);
        spmv_add(pattern, &lm.c, 1.0, y1, x1);
        spmv_add(pattern, &lm.m, sigma, y1, x1);
        for (i, &f) in fixed.iter().enumerate() {
            if f {
                x1[i] = 0.0;
            }
        }
        factor.borrow_mut().solve_in_place(x1);
        x1.iter_mut().for_each(|v| *v = -*v);
        for i in 0..n {
            x2[i] = y1[i] + sigma * x1[i];
        }
    };
    let dot = |x: &[f64], y: &[f64]| x.iter().zip(y).map(|(a, b)| a * b).sum::<f64>();
    let op = Operator {
        len: 2 * n,
        apply: &apply,
        dot: &dot,
        project: &project,
        symmetric: false,
    };
    // Both members of each conjugate pair, and up to three rigid pairs.
    let ritz = ritz_pairs(&op, 2 * count + 6, 2 * free.len())?;
    let tol = ZERO_FREQUENCY_RATIO * w_max;
    // Each Ritz value refined by the quadratic's Rayleigh functional of its vector.
    let lambdas: Vec<[f64; 2]> = ritz
        .iter()
        .map(|r| {
            let l = faer::c64::new(sigma, 0.0) + faer::c64::new(1.0, 0.0) / r.theta;
            let l = rayleigh_root(pattern, (&lm.k, &lm.c, &lm.m), &r.re[..n], &r.im[..n], l);
            [l.re, l.im]
        })
        .collect();
    let mut modes = zero_frequency_modes(&lambdas, tol);
    let rest_m: Vec<f64> = rest
        .iter()
        .map(|r| m_dot(pattern, &lm.m, &r.shape, &r.shape))
        .collect();
    let mut osc: Vec<usize> = (0..lambdas.len())
        .filter(|&i| lambdas[i][1] >= tol)
        .collect();
    osc.sort_by(|&x, &y| lambdas[x][1].total_cmp(&lambdas[y][1]));
    osc.truncate(count);
    let omega_frame = if model.spec.rotating_frame {
        -model.spec.omega
    } else {
        0.0
    };
    for i in osc {
        let (ure, uim) = (&ritz[i].re[..n], &ritz[i].im[..n]);
        let share = |k: usize| {
            let a = m_dot(pattern, &lm.m, &rest[k].shape, ure);
            let b = m_dot(pattern, &lm.m, &rest[k].shape, uim);
            (a * a + b * b) / rest_m[k].max(f64::MIN_POSITIVE)
        };
        let best = (0..rest.len())
            .max_by(|&a, &b| share(a).total_cmp(&share(b)))
            .unwrap_or(0);
        let fb = rest.get(best).map_or(0.0, |r| r.frequency_hz);
        let paired = rest.iter().enumerate().any(|(k, r)| {
            k != best
                && super::paired(
                    2.0 * std::f64::consts::PI * fb,
                    2.0 * std::f64::consts::PI * r.frequency_hz,
                    omega_frame,
                )
        });
        let j = angular_momentum(asm, &lm.m, ure, uim, model.mesh.dim);
        let whirl = if !paired || omega_frame == 0.0 || j == 0.0 {
            Whirl::Standing
        } else if j * omega_frame > 0.0 {
            Whirl::Forward
        } else {
            Whirl::Backward
        };
        let [re, im] = lambdas[i];
        let frequency_hz = im / (2.0 * std::f64::consts::PI);
        modes.push(SpinMode {
            frequency_hz,
            period_us: period_us(frequency_hz),
            growth_rate: re,
            rest_frequency_hz: fb,
            rest_index: Some(best),
            paired,
            whirl,
            angular_momentum: j,
            kind: "elastic".to_string(),
        });
    }
    Ok(modes)
}
