//! Gaussian elimination with partial pivoting on the small dense systems of the contact rows
//! (the multipliers' system `C A^{-1} C^T lambda = g - C A^{-1} b` of the active constraints,
//! [`crate::contact::rows`]) and of the static contact iteration.

/// Gaussian elimination with partial pivoting on a small dense row-major `k x k` system;
/// the solution replaces `r`. A singular system (two identical constraints) gets the
/// minimum-norm-like treatment of zeroing the dependent multiplier.
///
/// The rows' updates run on AVX2's instructions where the processor has them
/// (`linalg::with_avx2`): the same multiplications and subtractions in the same
/// order, so the same bits, four entries at a time. A 3D rolling patch of 40 nodes poses 120
/// rows.
pub fn dense_solve_in_place(s: &mut [f64], r: &mut [f64], k: usize) {
    crate::linalg::with_avx2!(dense_solve_here(s, r, k), dense_solve_avx2(s, r, k))
}

/// [`dense_solve_here`] compiled for AVX2.
///
/// # Safety
/// The processor must have AVX2.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn dense_solve_avx2(s: &mut [f64], r: &mut [f64], k: usize) {
    dense_solve_here(s, r, k);
}

#[inline(always)]
fn dense_solve_here(s: &mut [f64], r: &mut [f64], k: usize) {
    let s = &mut s[..k * k];
    let r = &mut r[..k];
    let scale = (0..k)
        .map(|i| s[i * k + i].abs())
        .fold(0.0, f64::max)
        .max(f64::MIN_POSITIVE);
    for col in 0..k {
        let mut piv = col;
        for row in col + 1..k {
            if s[row * k + col].abs() > s[piv * k + col].abs() {
                piv = row;
            }
        }
        if piv != col {
            let (a, b) = s.split_at_mut(piv * k);
            a[col * k..col * k + k].swap_with_slice(&mut b[..k]);
            r.swap(col, piv);
        }
        let d = s[col * k + col];
        if d.abs() <= 1e-14 * scale {
            s[col * k + col] = 0.0;
            continue;
        }
        let (top, below) = s.split_at_mut((col + 1) * k);
        let pivot = &top[col * k + col..col * k + k];
        let rc = r[col];
        for (row, target) in below.chunks_exact_mut(k).enumerate() {
            let f = target[col] / d;
            if f != 0.0 {
                for (t, &p) in target[col..].iter_mut().zip(pivot) {
                    *t -= f * p;
                }
                r[col + 1 + row] -= f * rc;
            }
        }
    }
    for col in (0..k).rev() {
        let d = s[col * k + col];
        if d == 0.0 {
            r[col] = 0.0;
            continue;
        }
        let mut acc = r[col];
        for c in col + 1..k {
            acc -= s[col * k + c] * r[c];
        }
        r[col] = acc / d;
    }
}

/// From this many rows up, [`DenseLu`] factors with faer's blocked LU (its kernels use the
/// processor's widest vectors, AVX-512 where present) rather than the elimination above, whose
/// rank-one updates stream the whole matrix through the cache at every column.
/// `cargo bench --bench dense` on the 2-core AMD EPYC of the project's machines: the two are
/// even at 48 rows; the blocked LU takes 0.81 of the elimination's time at 64, 0.45 at 240,
/// 0.38 at 429 (a 143-node patch) and 0.34 at 768.
pub const BLOCKED_MIN_ROWS: usize = 64;

/// The dense solve of [`dense_solve_in_place`] on a large system: faer's blocked LU with
/// partial pivoting (`faer::linalg::lu::partial_pivoting`), its workspace kept between
/// solves so that a solve allocates nothing once the largest system has been seen.
///
/// The row-major `k x k` matrix `S` is read as the column-major `S^T`, factored `S^T = P L U`,
/// and `S x = r` solved as `U^T L^T P^T x = r`: the layout faer prefers, no transposing copy.
/// Pivoting the rows of `S^T` is pivoting the columns of `S`, as stable.
///
/// A singular system (a pivot of `U` at most `1e-14` of the largest diagonal entry, as
/// [`dense_solve_in_place`] tests its pivots) is solved again by the elimination on a copy
/// taken before the factorization: its treatment of a dependent row (the multiplier zeroed)
/// is the one the contact rows rely on.
#[derive(Default)]
pub struct DenseLu {
    copy: Vec<f64>,
    perm: Vec<usize>,
    perm_inv: Vec<usize>,
    mem: Option<(usize, faer::dyn_stack::MemBuffer)>,
    blocked: usize,
    fallbacks: usize,
}

impl std::fmt::Debug for DenseLu {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("DenseLu")
            .field("rows", &self.perm.len())
            .field("blocked", &self.blocked)
            .field("fallbacks", &self.fallbacks)
            .finish()
    }
}

impl Clone for DenseLu {
    /// A fresh workspace: the buffers are scratch, refilled by each solve.
    fn clone(&self) -> Self {
        Self::default()
    }
}

impl DenseLu {
    /// An empty workspace; it grows to the largest system solved.
    pub fn new() -> Self {
        Self::default()
    }

    /// Systems solved by the blocked factorization so far.
    pub fn blocked_solves(&self) -> usize {
        self.blocked
    }

    /// Blocked solves that met a singular system and were solved again by the elimination.
    pub fn fallbacks(&self) -> usize {
        self.fallbacks
    }

    /// Solve the row-major `k x k` system `s x = r` in place (`r` becomes `x`; `s` is
    /// overwritten), as [`dense_solve_in_place`] does.
    pub fn solve_in_place(&mut self, s: &mut [f64], r: &mut [f64], k: usize) {
        if k < BLOCKED_MIN_ROWS {
            dense_solve_in_place(s, r, k);
            return;
        }
        use faer::dyn_stack::{MemBuffer, MemStack};
        use faer::linalg::lu::partial_pivoting::{factor, solve};
        use faer::{MatMut, Par};
        let s = &mut s[..k * k];
        let r = &mut r[..k];
        self.blocked += 1;
        let scale = (0..k)
            .map(|i| s[i * k + i].abs())
            .fold(0.0, f64::max)
            .max(f64::MIN_POSITIVE);
        if self.copy.len() < k * k {
            self.copy.resize(k * k, 0.0);
            self.perm.resize(k, 0);
            self.perm_inv.resize(k, 0);
        }
        self.copy[..k * k].copy_from_slice(s);
        if self.mem.as_ref().is_none_or(|(n, _)| *n < k) {
            let req =
                factor::lu_in_place_scratch::<usize, f64>(k, k, Par::Seq, Default::default()).or(
                    solve::solve_transpose_in_place_scratch::<usize, f64>(k, 1, Par::Seq),
                );
            self.mem = Some((k, MemBuffer::new(req)));
        }
        let (_, mem) = self.mem.as_mut().expect("the workspace was just made");
        // Column-major `k x k` over row-major storage: `S^T`.
        let mut lu = MatMut::from_column_major_slice_mut(s, k, k);
        let (_, perm) = factor::lu_in_place(
            lu.as_mut(),
            &mut self.perm[..k],
            &mut self.perm_inv[..k],
            Par::Seq,
            MemStack::new(mem),
            Default::default(),
        );
        if (0..k).any(|i| lu[(i, i)].abs() <= 1e-14 * scale || !lu[(i, i)].is_finite()) {
            self.fallbacks += 1;
            s.copy_from_slice(&self.copy[..k * k]);
            dense_solve_in_place(s, r, k);
            return;
        }
        let rhs = MatMut::from_column_major_slice_mut(r, k, 1);
        solve::solve_transpose_in_place(
            lu.as_ref(),
            lu.as_ref(),
            perm,
            rhs,
            Par::Seq,
            MemStack::new(mem),
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The elimination as first written, one indexed entry at a time.
    fn reference(s: &mut [f64], r: &mut [f64], k: usize) {
        let scale = (0..k)
            .map(|i| s[i * k + i].abs())
            .fold(0.0, f64::max)
            .max(f64::MIN_POSITIVE);
        for col in 0..k {
            let mut piv = col;
            for row in col + 1..k {
                if s[row * k + col].abs() > s[piv * k + col].abs() {
                    piv = row;
                }
            }
            if piv != col {
                for c in 0..k {
                    s.swap(col * k + c, piv * k + c);
                }
                r.swap(col, piv);
            }
            let d = s[col * k + col];
            if d.abs() <= 1e-14 * scale {
                s[col * k + col] = 0.0;
                continue;
            }
            for row in col + 1..k {
                let f = s[row * k + col] / d;
                if f != 0.0 {
                    for c in col..k {
                        s[row * k + c] -= f * s[col * k + c];
                    }
                    r[row] -= f * r[col];
                }
            }
        }
        for col in (0..k).rev() {
            let d = s[col * k + col];
            if d == 0.0 {
                r[col] = 0.0;
                continue;
            }
            let mut acc = r[col];
            for c in col + 1..k {
                acc -= s[col * k + c] * r[c];
            }
            r[col] = acc / d;
        }
    }

    /// The same bits as the entry-by-entry elimination, on systems that pivot, on a singular
    /// one (two equal rows), and a residual of round-off on the regular ones.
    #[test]
    fn rows_updated_by_slices_give_the_same_bits() {
        for k in [1, 2, 5, 33, 120] {
            for singular in [false, true] {
                let mut s: Vec<f64> = (0..k * k)
                    .map(|i| (0.37 * i as f64).sin() + if i % (k + 1) == 0 { 0.1 } else { 0.0 })
                    .collect();
                if singular && k > 2 {
                    let (a, b) = s.split_at_mut(2 * k);
                    b[..k].copy_from_slice(&a[k..2 * k]);
                }
                let r: Vec<f64> = (0..k).map(|i| (1.1 * i as f64).cos()).collect();
                let (mut s1, mut r1) = (s.clone(), r.clone());
                let (mut s2, mut r2) = (s.clone(), r.clone());
                dense_solve_in_place(&mut s1, &mut r1, k);
                reference(&mut s2, &mut r2, k);
                assert!(
                    r1.iter().zip(&r2).all(|(a, b)| a.to_bits() == b.to_bits()),
                    "k = {k}, singular = {singular}"
                );
                if !singular || k <= 2 {
                    let res = (0..k)
                        .map(|i| {
                            let ax: f64 = (0..k).map(|j| s[i * k + j] * r1[j]).sum();
                            (ax - r[i]).abs()
                        })
                        .fold(0.0, f64::max);
                    assert!(res < 1e-9, "k = {k}: residual {res:e}");
                }
            }
        }
    }

    fn system(k: usize, singular: bool) -> (Vec<f64>, Vec<f64>) {
        let mut s: Vec<f64> = (0..k * k)
            .map(|i| (0.37 * i as f64).sin() + if i % (k + 1) == 0 { 0.1 } else { 0.0 })
            .collect();
        if singular {
            let (a, b) = s.split_at_mut(2 * k);
            b[..k].copy_from_slice(&a[k..2 * k]);
        }
        let r = (0..k).map(|i| (1.1 * i as f64).cos()).collect();
        (s, r)
    }

    fn residual(s: &[f64], x: &[f64], r: &[f64], k: usize) -> f64 {
        (0..k)
            .map(|i| {
                let ax: f64 = (0..k).map(|j| s[i * k + j] * x[j]).sum();
                (ax - r[i]).abs()
            })
            .fold(0.0, f64::max)
    }

    /// The blocked LU solves a regular system (pivoting: the diagonal is weak) to round-off and
    /// agrees with the elimination; a singular one (two equal rows) falls back to the
    /// elimination's bits; the workspace serves a smaller system after a larger one.
    #[test]
    fn the_blocked_lu_agrees_with_the_elimination_and_falls_back_on_a_singular_system() {
        let mut lu = DenseLu::new();
        for k in [300, BLOCKED_MIN_ROWS, 150] {
            let (s, r) = system(k, false);
            let (mut s1, mut x1) = (s.clone(), r.clone());
            let (mut s2, mut x2) = (s.clone(), r.clone());
            lu.solve_in_place(&mut s1, &mut x1, k);
            dense_solve_in_place(&mut s2, &mut x2, k);
            let norm = x2.iter().fold(0.0_f64, |a, v| a.max(v.abs()));
            let diff = x1
                .iter()
                .zip(&x2)
                .fold(0.0_f64, |a, (p, q)| a.max((p - q).abs()));
            assert!(residual(&s, &x1, &r, k) < 1e-9, "k = {k}");
            assert!(diff <= 1e-9 * norm, "k = {k}: {diff:e} of {norm:e}");
        }
        assert_eq!((lu.blocked_solves(), lu.fallbacks()), (3, 0));
        let k = 200;
        let (s, r) = system(k, true);
        let (mut s1, mut x1) = (s.clone(), r.clone());
        let (mut s2, mut x2) = (s.clone(), r.clone());
        lu.solve_in_place(&mut s1, &mut x1, k);
        dense_solve_in_place(&mut s2, &mut x2, k);
        assert_eq!(lu.fallbacks(), 1);
        assert!(x1.iter().zip(&x2).all(|(a, b)| a.to_bits() == b.to_bits()));
        // Below the threshold: the elimination itself.
        let k = BLOCKED_MIN_ROWS - 1;
        let (s, r) = system(k, false);
        let (mut s1, mut x1) = (s.clone(), r.clone());
        let (mut s2, mut x2) = (s, r);
        lu.solve_in_place(&mut s1, &mut x1, k);
        dense_solve_in_place(&mut s2, &mut x2, k);
        assert!(x1.iter().zip(&x2).all(|(a, b)| a.to_bits() == b.to_bits()));
        assert_eq!(lu.blocked_solves(), 4);
    }
}
