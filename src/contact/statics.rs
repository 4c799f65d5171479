//! Static frictionless contact of nodes against a rigid half-space, by an active-set method:
//! solve `K u = f + sum_i lambda_i n` with `n . (X_i + u_i) = c` on the active nodes
//! (Lagrange multipliers through the factored `K`, as in the dynamic step), then drop a
//! tensile active node (`lambda_i < 0`) or add a penetrating free node, the one of least
//! index among all of them (Murty's rule); repeat until the set does not change. One change
//! at a time: changing every violated node at once can cycle (it did on a coarse graded
//! disk, with an alternating 13 MN / -9 MN pair); the least-index rule terminates on a
//! positive definite `S = C K^-1 C^T`, where choosing the most violated row has no such
//! guarantee. (`S` is positive definite when `K` with the fixed dofs is: a wheel held at
//! its centre node alone, free to turn, is not, and there every rule may cycle.)

use crate::contact::HalfSpace;
use crate::linalg::dense_solve_in_place;
use crate::linalg::{LinalgError, Pattern, SparseLu};

/// The result of a static contact solve.
#[derive(Debug, Clone)]
pub struct StaticContact {
    /// Displacement, m.
    pub u: Vec<f64>,
    /// Active nodes and their contact forces (N, compressive positive).
    pub active: Vec<(usize, f64)>,
    /// Active-set iterations.
    pub iterations: usize,
}

/// Solves the static contact of the `candidates` (2D nodes) against `plane`, with `K` on
/// `pattern`, fixed dofs `fixed`, load `f` and reference positions `x`.
///
/// # Errors
/// [`LinalgError`] when `K` with the fixed dofs is singular.
pub fn solve(
    pattern: &Pattern,
    k: &[f64],
    fixed: &[usize],
    f: &[f64],
    x: &[f64],
    candidates: &[usize],
    plane: HalfSpace,
) -> Result<StaticContact, LinalgError> {
    let rows: Vec<Vec<(usize, f64)>> = candidates.iter().map(|&i| vec![(i, 1.0)]).collect();
    solve_rows(pattern, k, fixed, f, x, &rows, plane)
}

/// As [`solve`], with each candidate a weighted gap: `candidates[c]` lists nodes and weights
/// (summing to 1), the gap is that of the weighted position `sum_k w_k (X_k + u_k)` and the
/// multiplier reaches the nodes in the same proportions (the mortar-weighted gap of
/// [`crate::contact::Pair::Weighted`]). The active list names each row by its first node.
///
/// # Errors
/// [`LinalgError`] when `K` with the fixed dofs is singular.
pub fn solve_rows(
    pattern: &Pattern,
    k: &[f64],
    fixed: &[usize],
    f: &[f64],
    x: &[f64],
    candidates: &[Vec<(usize, f64)>],
    plane: HalfSpace,
) -> Result<StaticContact, LinalgError> {
    let n = pattern.nrows();
    let mut is_fixed = vec![false; n];
    for &d in fixed {
        is_fixed[d] = true;
    }
    let mut a = k.to_vec();
    crate::linalg::set_identity_rows(pattern, &mut a, &is_fixed);
    let mut lu = SparseLu::new(pattern, &a)?;
    let mut u0: Vec<f64> = f
        .iter()
        .zip(&is_fixed)
        .map(|(&v, &fx)| if fx { 0.0 } else { v })
        .collect();
    lu.solve_in_place(&mut u0);
    // K^-1 n at a candidate node (normal columns), computed when it first becomes active.
    let mut cols: Vec<Option<Vec<f64>>> = vec![None; candidates.len()];
    let mut column = |c: usize, cols: &mut Vec<Option<Vec<f64>>>| {
        if cols[c].is_none() {
            let mut e = vec![0.0; n];
            for &(i, w) in &candidates[c] {
                if !(is_fixed[2 * i] || is_fixed[2 * i + 1]) {
                    e[2 * i] += w * plane.normal[0];
                    e[2 * i + 1] += w * plane.normal[1];
                }
            }
            lu.solve_in_place(&mut e);
            cols[c] = Some(e);
        }
    };
    let gap = |u: &[f64], c: usize| {
        candidates[c]
            .iter()
            .map(|&(i, w)| w * plane.gap([x[2 * i] + u[2 * i], x[2 * i + 1] + u[2 * i + 1], 0.0]))
            .sum::<f64>()
    };
    let mut active: Vec<usize> = (0..candidates.len())
        .filter(|&c| gap(&u0, c) < 0.0)
        .collect();
    let mut u = u0.clone();
    let mut lam = Vec::new();
    let limit = 100.max(4 * candidates.len());
    for it in 1..=limit {
        for &c in &active {
            column(c, &mut cols);
        }
        let cols_ref = |c: usize| cols[c].as_deref().unwrap_or(&[]);
        let m = active.len();
        let mut s = vec![0.0; m * m];
        let mut r = vec![0.0; m];
        for (p, &cp_) in active.iter().enumerate() {
            r[p] = -gap(&u0, cp_);
            for (q, &cq) in active.iter().enumerate() {
                s[p * m + q] = candidates[cp_]
                    .iter()
                    .map(|&(i, w)| {
                        w * (plane.normal[0] * cols_ref(cq)[2 * i]
                            + plane.normal[1] * cols_ref(cq)[2 * i + 1])
                    })
                    .sum();
            }
        }
        dense_solve_in_place(&mut s, &mut r, m);
        u.copy_from_slice(&u0);
        for (q, &cq) in active.iter().enumerate() {
            for (ui, ci) in u.iter_mut().zip(cols_ref(cq)) {
                *ui += r[q] * ci;
            }
        }
        lam = r;
        // One change at a time, the violator of least index (Murty's rule: it cannot cycle
        // on the symmetric positive definite `S`): a tensile active row is dropped, a
        // penetrating free one added.
        let mut next = active.clone();
        let tol = -1e-12 * plane.offset.abs().max(1.0);
        let lam_tol = -1e-10 * lam.iter().fold(0.0f64, |m, l| m.max(l.abs()));
        let tensile = active
            .iter()
            .zip(&lam)
            .find(|(_, &l)| l < lam_tol)
            .map(|(&c, _)| c);
        let penetrating = (0..candidates.len()).find(|c| !active.contains(c) && gap(&u, *c) < tol);
        match (tensile, penetrating) {
            (Some(t), Some(p)) if p < t => next.push(p),
            (Some(t), _) => next.retain(|&a| a != t),
            (None, Some(p)) => next.push(p),
            (None, None) => {}
        }
        next.sort_unstable();
        if next == active {
            return Ok(StaticContact {
                u,
                active: active
                    .iter()
                    .zip(&lam)
                    .map(|(&c, &l)| (candidates[c][0].0, l))
                    .collect(),
                iterations: it,
            });
        }
        active = next;
    }
    Ok(StaticContact {
        u,
        active: active
            .iter()
            .zip(&lam)
            .map(|(&c, &l)| (candidates[c][0].0, l))
            .collect(),
        iterations: limit,
    })
}
