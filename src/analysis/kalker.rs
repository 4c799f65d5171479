//! Kalker's linear creep coefficients of an elliptic contact area between two bodies of one
//! material (J.J. Kalker, *Three-dimensional elastic bodies in rolling contact*, Kluwer 1990,
//! Table E.3; the same values as Johnson's *Contact mechanics*, Table 8.1, after Kalker 1967):
//! in full adhesion and vanishing creepage,
//! $$F_x = -G c^2 C_{11} \xi,\qquad F_y = -G c^2 C_{22} \eta - G c^3 C_{23} \varphi,\qquad
//! M_z = G c^3 C_{23} \eta - G c^4 C_{33} \varphi,$$
//! `c = sqrt(a b)`, `G` the pair's combined modulus `2 / (1/G_1 + 1/G_2)`.
//!
//! [`kalker_table`] gives `C_11`, `C_22` and `C_23` at a Poisson's ratio and a semi-axis
//! ratio `a/b` (`a` along the rolling), interpolated as CONTACT interpolates the table
//! (`src/m_hertz.f90`, subroutine `linrol`): linearly in `g = min(a/b, b/a)` between the
//! table's rows of 0.1, and in `nu` by the parabola through the reciprocals at `nu = 0, 0.25,
//! 0.5`. `validation/halfspace3d/halfspace.py` (`kalker_table`) is the same rule in numpy,
//! and its full-stick solver reproduces the table within 0.5 % at `a/b = 1` and `0.5`.

// The table's 3.14 entries are Kalker's numbers, not pi.
#[allow(clippy::approx_constant)]
/// The table for `a <= b`, rows `a/b = 0.1, 0.2, ..., 1.0`: `C_11` at `nu = 0, 0.25, 0.5`,
/// `C_22` at the same, `C_23` at the same.
const A_BELOW_B: [[f64; 9]; 10] = [
    [2.51, 3.31, 4.85, 2.51, 2.52, 2.53, 0.334, 0.473, 0.731],
    [2.59, 3.37, 4.81, 2.59, 2.63, 2.66, 0.483, 0.603, 0.809],
    [2.68, 3.44, 4.80, 2.68, 2.75, 2.81, 0.607, 0.715, 0.889],
    [2.78, 3.53, 4.82, 2.78, 2.88, 2.98, 0.720, 0.823, 0.977],
    [2.88, 3.62, 4.83, 2.88, 3.01, 3.14, 0.827, 0.929, 1.07],
    [2.98, 3.72, 4.91, 2.98, 3.14, 3.31, 0.930, 1.03, 1.18],
    [3.09, 3.81, 4.97, 3.09, 3.28, 3.48, 1.03, 1.14, 1.29],
    [3.19, 3.91, 5.05, 3.19, 3.41, 3.65, 1.13, 1.25, 1.40],
    [3.29, 4.01, 5.12, 3.29, 3.54, 3.82, 1.23, 1.36, 1.51],
    [3.40, 4.12, 5.20, 3.40, 3.67, 3.98, 1.33, 1.47, 1.63],
];

/// The table for `a >= b`, rows `b/a = 0.1, 0.2, ..., 1.0`.
const A_ABOVE_B: [[f64; 9]; 10] = [
    [10.7, 11.7, 12.9, 10.7, 12.8, 16.0, 12.2, 14.6, 18.0],
    [6.96, 7.78, 8.82, 6.96, 8.14, 9.79, 5.72, 6.63, 7.89],
    [5.57, 6.34, 7.34, 5.57, 6.40, 7.51, 3.79, 4.32, 5.01],
    [4.84, 5.57, 6.57, 4.84, 5.48, 6.31, 2.88, 3.24, 3.70],
    [4.37, 5.10, 6.11, 4.37, 4.90, 5.56, 2.35, 2.62, 2.96],
    [4.06, 4.78, 5.80, 4.06, 4.50, 5.04, 2.01, 2.23, 2.50],
    [3.82, 4.54, 5.58, 3.82, 4.21, 4.67, 1.76, 1.95, 2.18],
    [3.65, 4.36, 5.42, 3.65, 3.99, 4.39, 1.58, 1.75, 1.94],
    [3.51, 4.22, 5.30, 3.51, 3.81, 4.16, 1.44, 1.59, 1.77],
    [3.40, 4.12, 5.20, 3.40, 3.67, 3.98, 1.33, 1.47, 1.63],
];

/// Kalker's `[C_11, C_22, C_23]` at Poisson's ratio `nu` and semi-axis ratio `a_over_b`
/// (module docs); `None` outside the table (`min(a/b, b/a) < 0.1`, `nu` outside `[0, 0.5]`
/// or not finite).
pub fn kalker_table(nu: f64, a_over_b: f64) -> Option<[f64; 3]> {
    if !(0.0..=0.5).contains(&nu) || !a_over_b.is_finite() || a_over_b <= 0.0 {
        return None;
    }
    let (tab, g) = if a_over_b <= 1.0 {
        (&A_BELOW_B, a_over_b)
    } else {
        (&A_ABOVE_B, 1.0 / a_over_b)
    };
    if !(0.1 - 1e-12..=1.0).contains(&g) {
        return None;
    }
    let r = (10.0 * g - 1.0).max(0.0);
    let i = ((r + 1e-9).floor() as usize).min(8);
    let f = r - i as f64;
    let mut out = [0.0; 3];
    for (k, c) in out.iter_mut().enumerate() {
        let at = |col: usize| (1.0 - f) * tab[i][3 * k + col] + f * tab[i + 1][3 * k + col];
        let (c0, c1, c2) = (at(0), at(1), at(2));
        let reciprocal = (nu - 0.25) * (nu - 0.5) * 8.0 / c0 - (nu - 0.5) * nu * 16.0 / c1
            + nu * (nu - 0.25) * 8.0 / c2;
        *c = 1.0 / reciprocal;
    }
    Some(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The table's own entries at its nodes, both halves meeting at the circle, and the
    /// parabola in `nu` through the reciprocals: at `nu = 0.28` between rows (the Hertz
    /// ellipse of `scenarios/press-hertz.toml`, `a/b = 1.3294`) the numpy rule of
    /// `validation/halfspace3d` gives 4.5504733, 4.1428317, 1.8689799.
    #[test]
    fn the_table_at_its_entries_and_between() {
        let close = |a: [f64; 3], b: [f64; 3], tol: f64| {
            a.iter().zip(&b).all(|(x, y)| (x - y).abs() <= tol)
        };
        assert!(close(
            kalker_table(0.25, 1.0).unwrap(),
            [4.12, 3.67, 1.47],
            1e-12
        ));
        assert!(close(
            kalker_table(0.25, 0.5).unwrap(),
            [3.62, 3.01, 0.929],
            1e-12
        ));
        assert!(close(
            kalker_table(0.5, 2.0).unwrap(),
            [6.11, 5.56, 2.96],
            1e-12
        ));
        assert!(close(
            kalker_table(0.0, 0.1).unwrap(),
            [2.51, 2.51, 0.334],
            1e-12
        ));
        assert!(close(
            kalker_table(0.28, 1.3294).unwrap(),
            [4.5504733, 4.1428317, 1.8689799],
            1e-6
        ));
        // Just off the circle on either side: continuous.
        let below = kalker_table(0.3, 1.0 - 1e-9).unwrap();
        let above = kalker_table(0.3, 1.0 + 1e-9).unwrap();
        assert!(close(below, above, 1e-6));
        assert!(kalker_table(0.25, 0.05).is_none());
        assert!(kalker_table(0.6, 1.0).is_none());
        assert!(kalker_table(f64::NAN, 1.0).is_none());
    }
}
