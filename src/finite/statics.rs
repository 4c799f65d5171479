//! The tangent stiffness of a [`FiniteBody`] and its static equilibrium under a dead load
//! by Newton's method in load steps ([`solve_static`]).
//!
//! The space-time step solves the nonlinear force on the elastic factor
//! ([`crate::model::internal`]); a static problem at large rotation has no mass to keep
//! that iteration contracting (the elastic `K` and the tangent of a turned cell differ by
//! as much as the turn), so the equilibrium is found with the tangent itself: in each load
//! step `f = (s / n) f_load`, `K_T(u_i) du = f - f_int(u_i)` on the free dofs until the
//! residual is below `tol |f|`.
//!
//! # The tangent
//!
//! Cell by cell, the derivative of `f_a = V P(F) grad N_a` in the direction `dF = e_k
//! grad N_b^T`:
//! - Saint Venant-Kirchhoff, exactly: `dP = dF S + F dS`, `dS = 2 mu dE + lambda' tr(dE) I`,
//!   `dE = sym(F^T dF)` (in plane stress on the in-plane block with `lambda' = 2 lambda mu /
//!   (lambda + 2 mu)`, as [`FiniteBody`]'s force);
//! - neo-Hookean: central differences of the cell's `P` (a step of `1e-6` in the strain),
//!   which turns Newton's quadratic convergence into a linear one with a factor of about
//!   `1e-8`.

use super::{FiniteBody, Hyperelastic, Kind, M3};
use crate::assembly::Assembler;
use crate::linalg::{Factor, LinalgError};
use crate::material::PlaneModel;

/// Counters of a static solve.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct StaticStats {
    /// Newton iterations over the load steps (a factorization each).
    pub iterations: usize,
    /// Most iterations in one load step.
    pub max_in_one_step: usize,
    /// The last residual relative to the load.
    pub residual: f64,
}

/// Why a static solve stopped.
#[derive(Debug, thiserror::Error)]
pub enum StaticError {
    /// A factorization failed.
    #[error("the tangent stiffness could not be factored: {0}")]
    Linalg(#[from] LinalgError),
    /// Newton did not converge within its cap in a load step.
    #[error("Newton did not converge in load step {step} of {steps} (residual {residual:e} of the load after {iterations} iterations): take more load steps")]
    NotConverged {
        /// The load step (1-based).
        step: usize,
        /// Load steps.
        steps: usize,
        /// The residual relative to the load.
        residual: f64,
        /// Iterations taken.
        iterations: usize,
    },
}

/// Newton iterations allowed in one load step.
pub const MAX_NEWTON: usize = 30;

impl FiniteBody {
    /// The derivative of cell `c`'s `P` in the direction `dh` at the gradient `h`.
    fn cell_dp(&self, h: &M3, dh: &M3) -> M3 {
        let (lam, mu) = (self.lam, self.mu);
        let svk = |d: usize, ls: f64| {
            let mut f = *h;
            for (i, row) in f.iter_mut().enumerate().take(d) {
                row[i] += 1.0;
            }
            let mut e = [[0.0; 3]; 3];
            let mut de = [[0.0; 3]; 3];
            for i in 0..d {
                for j in 0..d {
                    let (mut c, mut dc) = (0.0, 0.0);
                    for k in 0..d {
                        c += f[k][i] * f[k][j];
                        dc += f[k][i] * dh[k][j] + dh[k][i] * f[k][j];
                    }
                    e[i][j] = 0.5 * (c - if i == j { 1.0 } else { 0.0 });
                    de[i][j] = 0.5 * dc;
                }
            }
            let (tr, dtr) = (0..d).fold((0.0, 0.0), |(a, b), i| (a + e[i][i], b + de[i][i]));
            let mut s = [[0.0; 3]; 3];
            let mut ds = [[0.0; 3]; 3];
            for i in 0..d {
                for j in 0..d {
                    let id = if i == j { 1.0 } else { 0.0 };
                    s[i][j] = 2.0 * mu * e[i][j] + ls * tr * id;
                    ds[i][j] = 2.0 * mu * de[i][j] + ls * dtr * id;
                }
            }
            let mut dp = [[0.0; 3]; 3];
            for i in 0..d {
                for j in 0..d {
                    dp[i][j] = (0..d)
                        .map(|k| dh[i][k] * s[k][j] + f[i][k] * ds[k][j])
                        .sum();
                }
            }
            dp
        };
        match (self.kind, self.law) {
            (Kind::Plane(PlaneModel::Stress), Hyperelastic::SaintVenantKirchhoff) => {
                svk(2, 2.0 * lam * mu / (lam + 2.0 * mu))
            }
            (Kind::Plane(PlaneModel::Strain), Hyperelastic::SaintVenantKirchhoff) => svk(2, lam),
            (Kind::Solid, Hyperelastic::SaintVenantKirchhoff) => svk(3, lam),
            (_, Hyperelastic::NeoHookean) => {
                let scale = dh.iter().flatten().fold(0.0f64, |m, v| m.max(v.abs()));
                let eps = 1e-6 / scale.max(1e-300);
                let at = |sign: f64| {
                    let mut g = *h;
                    for (row, drow) in g.iter_mut().zip(dh) {
                        for (v, d) in row.iter_mut().zip(drow) {
                            *v += sign * eps * d;
                        }
                    }
                    self.cell_force(&g).p
                };
                let (pp, pm) = (at(1.0), at(-1.0));
                let mut dp = [[0.0; 3]; 3];
                for i in 0..3 {
                    for j in 0..3 {
                        dp[i][j] = (pp[i][j] - pm[i][j]) / (2.0 * eps);
                    }
                }
                dp
            }
        }
    }

    /// The tangent stiffness `d f_int / d u` at `u`, entry by entry: `add(row, col, value)`
    /// for each cell's pair of dofs (repeated pairs to be summed).
    pub fn tangent_for_each(&self, u: &[f64], mut add: impl FnMut(usize, usize, f64)) {
        let d = self.dim();
        for c in self.points() {
            let nn = c.nodes.len();
            let h = self.gradient(&c, u);
            for b in 0..nn {
                for k in 0..d {
                    let mut dh = [[0.0; 3]; 3];
                    dh[k] = c.grad[b];
                    let dp = self.cell_dp(&h, &dh);
                    let col = d * c.nodes[b] + k;
                    for a in 0..nn {
                        let g = &c.grad[a];
                        for (i, row) in dp.iter().enumerate().take(d) {
                            let v = c.measure * (row[0] * g[0] + row[1] * g[1] + row[2] * g[2]);
                            add(d * c.nodes[a] + i, col, v);
                        }
                    }
                }
            }
        }
    }

    /// The tangent stiffness at `u` added into `values` on `asm`'s pattern.
    ///
    /// # Panics
    /// When the pattern lacks a pair of a cell's dofs.
    pub fn tangent_add(&self, u: &[f64], asm: &Assembler, values: &mut [f64]) {
        self.tangent_for_each(u, |i, j, v| {
            let slot = asm.slot(i, j).expect("the pattern holds the cell's dofs");
            values[slot] += v;
        });
    }
}

/// The static equilibrium `f_int(u) = f_load` of `body` with the dofs `fixed` held at
/// zero, by Newton's method on the tangent in `steps` equal load steps (module docs), each
/// to the residual `tol |f|`. Returns the displacement and the counters.
///
/// # Errors
/// [`StaticError`] when the tangent is singular or a load step does not converge in
/// [`MAX_NEWTON`] iterations.
pub fn solve_static(
    body: &FiniteBody,
    asm: &Assembler,
    fixed: &[usize],
    load: &[f64],
    steps: usize,
    tol: f64,
) -> Result<(Vec<f64>, StaticStats), StaticError> {
    let n = asm.pattern.nrows();
    let mut is_fixed = vec![false; n];
    for &i in fixed {
        is_fixed[i] = true;
    }
    let (mut u, mut f, mut r) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
    let mut stats = StaticStats::default();
    let steps = steps.max(1);
    for s in 1..=steps {
        let frac = s as f64 / steps as f64;
        let mut fnorm = 0.0;
        for (i, (fi, l)) in f.iter_mut().zip(load).enumerate() {
            *fi = if is_fixed[i] { 0.0 } else { frac * l };
            fnorm += *fi * *fi;
        }
        let fnorm = fnorm.sqrt().max(1e-300);
        let mut it = 0;
        loop {
            body.internal_force_into(&u, &mut r);
            let mut rn = 0.0;
            for (i, (ri, fi)) in r.iter_mut().zip(&f).enumerate() {
                *ri = if is_fixed[i] { 0.0 } else { fi - *ri };
                rn += *ri * *ri;
            }
            stats.residual = rn.sqrt() / fnorm;
            if stats.residual <= tol {
                break;
            }
            if it == MAX_NEWTON {
                return Err(StaticError::NotConverged {
                    step: s,
                    steps,
                    residual: stats.residual,
                    iterations: it,
                });
            }
            let mut kt = asm.zeros();
            body.tangent_add(&u, asm, &mut kt);
            crate::linalg::set_identity_rows(&asm.pattern, &mut kt, &is_fixed);
            let mut lu = Factor::auto(&asm.pattern, &kt)?;
            lu.solve_in_place(&mut r);
            for (ui, di) in u.iter_mut().zip(&r) {
                *ui += di;
            }
            it += 1;
            stats.iterations += 1;
        }
        stats.max_in_one_step = stats.max_in_one_step.max(it);
    }
    Ok((u, stats))
}
