//! Gaussian elimination with partial pivoting on the small dense systems of the contact rows
//! (the multipliers' system `C A^{-1} C^T lambda = g - C A^{-1} b` of the active constraints,
//! [`crate::contact::rows`]) and of the static contact iteration.

/// Gaussian elimination with partial pivoting on a small dense row-major `k x k` system;
/// the solution replaces `r`. A singular system (two identical constraints) gets the
/// minimum-norm-like treatment of zeroing the dependent multiplier.
pub fn dense_solve_in_place(s: &mut [f64], r: &mut [f64], k: usize) {
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
