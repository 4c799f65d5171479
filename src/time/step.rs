//! The multi-degree-of-freedom space-time step (DESIGN §1, paper Eqs. 6-10, 18-24).
//!
//! For `M v' + C v + K u = f(t) + r` with velocity linear over `[t0, t0 + h]` and the
//! virtual velocity a Dirac at `t0 + alpha h` (Eq. 8), the step is
//!
//! $$A v_1 = b,\qquad A = M + \alpha h C + \tfrac{\alpha^2 h^2}{2} K,$$
//! $$b = \big(M - (1-\alpha) h C - (\alpha - \tfrac{\alpha^2}{2}) h^2 K\big) v_0 - h K u_0
//!      + h f(t_0 + \alpha h) + h r,$$
//! $$u_1 = u_0 + h[(1-\beta) v_0 + \beta v_1],\qquad \beta = 1 - \frac{\alpha}{1+\gamma}.$$
//!
//! `A` depends on `alpha` and `h` only, so it is factored once ([`SparseLu`]); `gamma`
//! (hence `beta`) may change between steps at no cost.
//!
//! **Dirichlet velocities** are imposed by replacing the rows and columns of `A` by the
//! identity and lifting the prescribed values into `b`.
//!
//! **Velocity constraints** `c_p^T v_1 = g_p` (contact: a node's normal velocity) are imposed
//! by Lagrange multipliers through the factored `A` (DESIGN §2):
//! `A v = b + C^T lambda`, `C v = g`, hence
//! $$\lambda = (C A^{-1} C^T)^{-1} (g - C A^{-1} b),\qquad v = A^{-1} b + A^{-1} C^T \lambda.$$
//! The columns `A^{-1} e_d` of the constrained nodes' dofs are computed once and cached while
//! `A` does not change; only the small dense system on the active constraints is solved each
//! step, so a change of the active set costs no factorization. The multiplier `lambda_p` is
//! the impulse of the constraint over the step: the force is `lambda_p / h`.

use crate::assembly::Assembler;
use crate::linalg::{spmv_add, LinalgError, Pattern, SparseLu};
use crate::time::constraints::ColumnCache;
use crate::time::SpaceTimeParams;

/// The semi-discrete linear model `M v' + C v + K u = f` on one sparsity pattern.
#[derive(Debug, Clone)]
pub struct LinearModel {
    /// Pattern and element map.
    pub assembler: Assembler,
    /// Mass matrix values.
    pub m: Vec<f64>,
    /// Stiffness matrix values (elastic plus, in a rotating frame, spin terms).
    pub k: Vec<f64>,
    /// Damping matrix values (`eta_z` of Eq. 22, Coriolis in a rotating frame).
    pub c: Vec<f64>,
}

impl LinearModel {
    /// Number of degrees of freedom.
    pub fn n(&self) -> usize {
        self.assembler.pattern.nrows()
    }

    /// The pattern.
    pub fn pattern(&self) -> &Pattern {
        &self.assembler.pattern
    }
}

/// A linear velocity constraint on one node: `normal . v_node(t1) = rhs`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct VelocityConstraint {
    /// The node.
    pub node: usize,
    /// Unit direction (only the first `dim` components are used).
    pub normal: [f64; 2],
    /// Prescribed value of `normal . v`, m/s.
    pub rhs: f64,
}

/// The space-time stepper: factored `A`, the right-hand-side operators and the constraint
/// machinery. All work memory is allocated in [`Stepper::new`].
pub struct Stepper {
    params: SpaceTimeParams,
    n: usize,
    pattern: Pattern,
    /// Values of `M - (1-alpha) h C - (alpha - alpha^2/2) h^2 K`.
    bv: Vec<f64>,
    /// Values of `K`.
    k: Vec<f64>,
    /// Values of `A` before the Dirichlet rows and columns were replaced (for lifting).
    a_orig: Vec<f64>,
    lu: SparseLu,
    bc_dofs: Vec<usize>,
    bc_values: Vec<f64>,
    is_bc: Vec<bool>,
    cache: ColumnCache,
}

impl std::fmt::Debug for Stepper {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Stepper")
            .field("params", &self.params)
            .field("n", &self.n)
            .finish()
    }
}

impl Stepper {
    /// Builds and factors `A` for `params`, with the Dirichlet velocities `bcs` (dof, value
    /// in m/s) and room for `max_constraints` simultaneous velocity constraints, caching the
    /// columns of at most `cache_nodes` constrained nodes.
    ///
    /// # Errors
    /// [`LinalgError`] when `A` is singular.
    pub fn new(
        model: &LinearModel,
        dim: usize,
        params: SpaceTimeParams,
        bcs: &[(usize, f64)],
        max_constraints: usize,
        cache_nodes: usize,
    ) -> Result<Self, LinalgError> {
        let n = model.n();
        let (a, h) = (params.alpha, params.h);
        let pattern = model.pattern().clone();
        let nnz = model.m.len();
        let mut a_vals = vec![0.0; nnz];
        let mut bv = vec![0.0; nnz];
        for p in 0..nnz {
            a_vals[p] = model.m[p] + a * h * model.c[p] + 0.5 * a * a * h * h * model.k[p];
            bv[p] =
                model.m[p] - (1.0 - a) * h * model.c[p] - (a - 0.5 * a * a) * h * h * model.k[p];
        }
        let a_orig = a_vals.clone();
        let mut is_bc = vec![false; n];
        let mut bc_dofs = Vec::with_capacity(bcs.len());
        let mut bc_values = Vec::with_capacity(bcs.len());
        for &(d, v) in bcs {
            if !is_bc[d] {
                is_bc[d] = true;
                bc_dofs.push(d);
                bc_values.push(v);
            }
        }
        crate::linalg::set_identity_rows(&pattern, &mut a_vals, &is_bc);
        let lu = SparseLu::new(&pattern, &a_vals)?;
        Ok(Self {
            params,
            n,
            pattern,
            bv,
            k: model.k.clone(),
            a_orig,
            lu,
            bc_dofs,
            bc_values,
            is_bc,
            cache: ColumnCache::new(n, dim, max_constraints, cache_nodes),
        })
    }

    /// The scheme's parameters.
    pub fn params(&self) -> SpaceTimeParams {
        self.params
    }

    /// Number of degrees of freedom.
    pub fn n(&self) -> usize {
        self.n
    }

    /// True when the dof has a prescribed velocity.
    pub fn is_dirichlet(&self, dof: usize) -> bool {
        self.is_bc[dof]
    }

    /// `b = (M - (1-alpha) h C - (alpha - alpha^2/2) h^2 K) v0 - h K u0 + h f`, where `f` is
    /// the external force at `t0 + alpha h` (N per dof).
    pub fn rhs_into(&self, u0: &[f64], v0: &[f64], f: &[f64], b: &mut [f64]) {
        let h = self.params.h;
        for (bi, fi) in b.iter_mut().zip(f) {
            *bi = h * fi;
        }
        spmv_add(&self.pattern, &self.bv, 1.0, v0, b);
        spmv_add(&self.pattern, &self.k, -h, u0, b);
    }

    /// Solves `A v1 = b` in place (`b` becomes `v1`) with the Dirichlet velocities and the
    /// velocity constraints; writes the multipliers (impulses, N s) into `lambda[..len]`.
    ///
    /// # Panics
    /// When more constraints are given than `max_constraints` of [`Stepper::new`].
    pub fn solve(&mut self, b: &mut [f64], constraints: &[VelocityConstraint], lambda: &mut [f64]) {
        self.apply_dirichlet(b);
        self.lu.solve_in_place(b);
        let lu = &mut self.lu;
        self.cache.apply(b, constraints, lambda, &self.is_bc, |r| {
            lu.solve_in_place(r)
        });
    }

    /// `r <- A^{-1} r` with the Dirichlet rows of `r` set to zero first: the velocity
    /// response to an impulse `r` (N s) added to `b`.
    pub fn apply_inverse(&mut self, r: &mut [f64]) {
        for (ri, &bc) in r.iter_mut().zip(&self.is_bc) {
            if bc {
                *ri = 0.0;
            }
        }
        self.lu.solve_in_place(r);
    }

    /// `u1 = u0 + h [(1 - beta) v0 + beta v1]`, Eq. (10).
    pub fn update_displacement(
        &self,
        beta: f64,
        u0: &[f64],
        v0: &[f64],
        v1: &[f64],
        u1: &mut [f64],
    ) {
        let h = self.params.h;
        for i in 0..self.n {
            u1[i] = u0[i] + h * ((1.0 - beta) * v0[i] + beta * v1[i]);
        }
    }

    fn apply_dirichlet(&self, b: &mut [f64]) {
        let cp = self.pattern.col_ptr();
        let ri = self.pattern.row_idx();
        for (&j, &g) in self.bc_dofs.iter().zip(&self.bc_values) {
            if g != 0.0 {
                for p in cp[j]..cp[j + 1] {
                    let i = ri[p];
                    if !self.is_bc[i] {
                        b[i] -= self.a_orig[p] * g;
                    }
                }
            }
        }
        for (&j, &g) in self.bc_dofs.iter().zip(&self.bc_values) {
            b[j] = g;
        }
    }
}

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
