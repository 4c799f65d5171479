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
}
