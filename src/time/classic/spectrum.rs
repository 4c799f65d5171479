//! The family's spectrum on one degree of freedom and on a model (split from the integrators
//! of [`super`]): the largest natural frequency of a model and the central difference's
//! stable step, one step of `m a + c v + k u = f`, the amplification matrix `G(omega h)`, its
//! eigenvalues, spectral radius and `rho_inf`.

use super::ClassicParams;
use crate::linalg::{spmv_add, Pattern};
use crate::model::LinearModel;

/// The largest natural circular frequency `omega_max` (rad/s) of `K phi = omega^2 M phi` for a
/// diagonal (lumped) `M`, the Dirichlet dofs removed, by power iteration on `M^{-1} K` from
/// an alternating start (Rayleigh quotient, relative tolerance 1e-12, at most `max_iter`
/// iterations). A lower bound that converges to `omega_max`; see also
/// [`max_frequency_bound`].
pub fn max_frequency(model: &LinearModel, bc_dofs: &[usize], max_iter: usize) -> f64 {
    let n = model.n();
    let mdiag = diagonal(model.pattern(), &model.m);
    let mut free = vec![true; n];
    for &d in bc_dofs {
        free[d] = false;
    }
    let mut x: Vec<f64> = (0..n)
        .map(|i| {
            if free[i] {
                if i % 2 == 0 {
                    1.0
                } else {
                    -1.0
                }
            } else {
                0.0
            }
        })
        .collect();
    let mut y = vec![0.0; n];
    let mut lam = 0.0;
    for _ in 0..max_iter.max(1) {
        y.fill(0.0);
        spmv_add(model.pattern(), &model.k, 1.0, &x, &mut y);
        // Rayleigh quotient x^T K x / x^T M x.
        let (mut num, mut den) = (0.0, 0.0);
        for i in 0..n {
            if free[i] {
                num += x[i] * y[i];
                den += x[i] * mdiag[i] * x[i];
            }
        }
        let new = num / den;
        let mut norm = 0.0f64;
        for i in 0..n {
            y[i] = if free[i] { y[i] / mdiag[i] } else { 0.0 };
            norm = norm.max(y[i].abs());
        }
        for i in 0..n {
            x[i] = y[i] / norm;
        }
        if (new - lam).abs() <= 1e-12 * new.abs() {
            lam = new;
            break;
        }
        lam = new;
    }
    lam.max(0.0).sqrt()
}

/// Gershgorin upper bound of `omega_max` (rad/s) for a diagonal `M`:
/// `omega_max^2 <= max_i sum_j |K_ij| / M_ii` over the free dofs. Exact for a uniform
/// free-free lumped bar in the limit of many elements.
pub fn max_frequency_bound(model: &LinearModel, bc_dofs: &[usize]) -> f64 {
    let n = model.n();
    let mdiag = diagonal(model.pattern(), &model.m);
    let mut rows = vec![0.0; n];
    let cp = model.pattern().col_ptr();
    let ri = model.pattern().row_idx();
    let mut free = vec![true; n];
    for &d in bc_dofs {
        free[d] = false;
    }
    for j in 0..n {
        for p in cp[j]..cp[j + 1] {
            if free[j] {
                rows[ri[p]] += model.k[p].abs();
            }
        }
    }
    (0..n)
        .filter(|&i| free[i])
        .map(|i| rows[i] / mdiag[i])
        .fold(0.0, f64::max)
        .sqrt()
}

/// The stable step of the central difference, `h_crit = 2 / omega_max` (s), with
/// `omega_max` from [`max_frequency`] (100 000 iterations at most).
pub fn stable_step(model: &LinearModel, bc_dofs: &[usize]) -> f64 {
    2.0 / max_frequency(model, bc_dofs, 100_000)
}

fn diagonal(pattern: &Pattern, values: &[f64]) -> Vec<f64> {
    let n = pattern.nrows();
    let cp = pattern.col_ptr();
    let ri = pattern.row_idx();
    let mut d = vec![0.0; n];
    for j in 0..n {
        for p in cp[j]..cp[j + 1] {
            if ri[p] == j {
                d[j] = values[p];
            }
        }
    }
    d
}

/// One step of the family for one dof `m a + c v + k u = f` (kg, N s/m, N/m; forces `f0`,
/// `f1` in N at `t0`, `t1`), state `(u, v, a)`; the same arithmetic as
/// [`super::ClassicStepper::step`].
#[allow(clippy::too_many_arguments)]
pub fn sdof_step(
    m: f64,
    c: f64,
    k: f64,
    f0: f64,
    f1: f64,
    p: ClassicParams,
    h: f64,
    s0: (f64, f64, f64),
) -> (f64, f64, f64) {
    let (u0, v0, a0) = s0;
    let up = u0 + h * v0 + h * h * (0.5 - p.beta) * a0;
    let vp = v0 + h * (1.0 - p.gamma) * a0;
    let lhs = (1.0 - p.alpha_m) * m + (1.0 - p.alpha_f) * (p.gamma * h * c + p.beta * h * h * k);
    let mut b = (1.0 - p.alpha_f) * f1 + p.alpha_f * f0;
    if p.alpha_m != 0.0 {
        b += m * (-p.alpha_m * a0);
    }
    b += c * -(p.alpha_f * v0 + (1.0 - p.alpha_f) * vp);
    b += k * -(p.alpha_f * u0 + (1.0 - p.alpha_f) * up);
    let a1 = b / lhs;
    (up + p.beta * h * h * a1, vp + p.gamma * h * a1, a1)
}

/// The amplification matrix `G(Omega)`, `Omega = omega h`, of `u'' + omega^2 u = 0` on the
/// scaled state `(u, h v, h^2 a)`: built column by column from [`sdof_step`].
pub fn amplification_matrix(p: ClassicParams, omega_h: f64) -> [[f64; 3]; 3] {
    let mut g = [[0.0; 3]; 3];
    for (j, e) in [(1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0)]
        .into_iter()
        .enumerate()
    {
        let (u, v, a) = sdof_step(1.0, 0.0, omega_h * omega_h, 0.0, 0.0, p, 1.0, e);
        g[0][j] = u;
        g[1][j] = v;
        g[2][j] = a;
    }
    g
}

/// Spectral properties at one `omega h` (the same record as the space-time scheme's; the
/// spectral radius is over all three eigenvalues, clusters averaged, see
/// [`clustered_spectral_radius`]; damping and period error are those of the principal pair).
pub use crate::time::sdof::Amplification;

/// The three eigenvalues `[re, im]` of `G(omega h)` (faer's dense eigensolver).
pub fn eigenvalues(p: ClassicParams, omega_h: f64) -> [[f64; 2]; 3] {
    let g = amplification_matrix(p, omega_h);
    let mat = faer::Mat::<f64>::from_fn(3, 3, |i, j| g[i][j]);
    let mut out = [[0.0; 2]; 3];
    match mat.eigen() {
        Ok(evd) => {
            let s = evd.S().column_vector();
            for (i, o) in out.iter_mut().enumerate() {
                *o = [s[i].re, s[i].im];
            }
        }
        Err(_) => out = [[f64::NAN; 2]; 3],
    }
    out
}

/// Spectral radius of three eigenvalues, robust to multiple eigenvalues: eigenvalues closer
/// than `1e-4 max(1, |lambda|_max)` form a cluster and are replaced by its mean. A multiple
/// eigenvalue of a defective `G` (the double root `-1` of average acceleration, the triple
/// root `-rho_inf` of generalized-alpha) is computed only to `eps^(1/2)`..`eps^(1/3)`
/// (1e-8..6e-6), but the sum of a cluster, hence its mean, to round-off.
pub fn clustered_spectral_radius(ev: &[[f64; 2]; 3]) -> f64 {
    let mag = |l: [f64; 2]| l[0].hypot(l[1]);
    let big = ev.iter().map(|&l| mag(l)).fold(1.0, f64::max);
    let tol = 1e-4 * big;
    let close = |a: [f64; 2], b: [f64; 2]| (a[0] - b[0]).hypot(a[1] - b[1]) < tol;
    let mut rho = 0.0f64;
    for i in 0..3 {
        // The cluster of i: every eigenvalue linked to i directly or through a third one.
        let mut member = [false; 3];
        member[i] = true;
        for _ in 0..2 {
            for j in 0..3 {
                for k in 0..3 {
                    if member[k] && close(ev[j], ev[k]) {
                        member[j] = true;
                    }
                }
            }
        }
        let (mut re, mut im, mut cnt) = (0.0, 0.0, 0.0);
        for j in 0..3 {
            if member[j] {
                re += ev[j][0];
                im += ev[j][1];
                cnt += 1.0;
            }
        }
        rho = rho.max((re / cnt).hypot(im / cnt));
    }
    rho
}

/// Eigen-analysis of `G(omega h)`.
pub fn amplification(p: ClassicParams, omega_h: f64) -> Amplification {
    let ev = eigenvalues(p, omega_h);
    let rho = clustered_spectral_radius(&ev);
    // Principal pair: the complex eigenvalue with positive imaginary part.
    let pair = ev
        .iter()
        .filter(|l| l[1] > 0.0)
        .max_by(|a, b| a[0].hypot(a[1]).total_cmp(&b[0].hypot(b[1])));
    let (xi, pe) = match pair {
        Some(l) => {
            let phase = l[1].atan2(l[0]);
            (-(l[0].hypot(l[1])).ln() / phase, omega_h / phase - 1.0)
        }
        None => (f64::NAN, f64::NAN),
    };
    Amplification {
        omega_h,
        spectral_radius: rho,
        damping_ratio: xi,
        period_error: pe,
    }
}

/// High-frequency spectral radius: the spectral radius at `omega h = 1e8`.
pub fn rho_inf(p: ClassicParams) -> f64 {
    amplification(p, 1e8).spectral_radius
}
