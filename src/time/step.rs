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
    dim: usize,
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
    // Constraint column cache: slot s holds A^{-1} e_{dim*node + c} at
    // cols[(s*dim + c)*n ..][..n].
    slot_of_node: Vec<usize>,
    node_of_slot: Vec<usize>,
    last_used: Vec<u64>,
    cols: Vec<f64>,
    clock: u64,
    // Dense work for the multipliers.
    s_mat: Vec<f64>,
    r_vec: Vec<f64>,
    slots_active: Vec<usize>,
    unit: Vec<f64>,
}

impl std::fmt::Debug for Stepper {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Stepper")
            .field("params", &self.params)
            .field("n", &self.n)
            .finish()
    }
}

const NO_SLOT: usize = usize::MAX;

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
        let cp = pattern.col_ptr();
        let ri = pattern.row_idx();
        for j in 0..n {
            for p in cp[j]..cp[j + 1] {
                let i = ri[p];
                if is_bc[i] || is_bc[j] {
                    a_vals[p] = if i == j { 1.0 } else { 0.0 };
                }
            }
        }
        let lu = SparseLu::new(&pattern, &a_vals)?;
        let cache_nodes = cache_nodes.max(max_constraints).max(1);
        let mc = max_constraints.max(1);
        Ok(Self {
            params,
            dim,
            n,
            pattern,
            bv,
            k: model.k.clone(),
            a_orig,
            lu,
            bc_dofs,
            bc_values,
            is_bc,
            slot_of_node: vec![NO_SLOT; n / dim.max(1)],
            node_of_slot: vec![NO_SLOT; cache_nodes],
            last_used: vec![0; cache_nodes],
            cols: vec![0.0; cache_nodes * dim * n],
            clock: 0,
            s_mat: vec![0.0; mc * mc],
            r_vec: vec![0.0; mc],
            slots_active: vec![0; mc],
            unit: vec![0.0; n],
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
        let k = constraints.len();
        if k == 0 {
            return;
        }
        assert!(k <= self.r_vec.len(), "too many simultaneous constraints");
        self.clock += 1;
        for (q, c) in constraints.iter().enumerate() {
            self.slots_active[q] = self.ensure_cached(c.node);
        }
        let (dim, n) = (self.dim, self.n);
        for (p, cp) in constraints.iter().enumerate() {
            let mut vn = 0.0;
            for c in 0..dim {
                vn += cp.normal[c] * b[dim * cp.node + c];
            }
            self.r_vec[p] = cp.rhs - vn;
            for (q, cq) in constraints.iter().enumerate() {
                let s = self.slots_active[q];
                let mut v = 0.0;
                for c2 in 0..dim {
                    let col = &self.cols[(s * dim + c2) * n..(s * dim + c2 + 1) * n];
                    for c in 0..dim {
                        v += cp.normal[c] * col[dim * cp.node + c] * cq.normal[c2];
                    }
                }
                self.s_mat[p * k + q] = v;
            }
        }
        dense_solve_in_place(&mut self.s_mat[..k * k], &mut self.r_vec[..k], k);
        for (q, cq) in constraints.iter().enumerate() {
            let l = self.r_vec[q];
            lambda[q] = l;
            let s = self.slots_active[q];
            for c2 in 0..dim {
                let w = l * cq.normal[c2];
                if w == 0.0 {
                    continue;
                }
                let col = &self.cols[(s * dim + c2) * n..(s * dim + c2 + 1) * n];
                for (bi, ci) in b.iter_mut().zip(col) {
                    *bi += w * ci;
                }
            }
        }
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

    fn ensure_cached(&mut self, node: usize) -> usize {
        let s = self.slot_of_node[node];
        if s != NO_SLOT {
            self.last_used[s] = self.clock;
            return s;
        }
        // Least recently used slot (empty slots have last_used 0).
        let mut s = 0;
        for i in 0..self.node_of_slot.len() {
            if self.last_used[i] < self.last_used[s] {
                s = i;
            }
        }
        assert!(
            self.last_used[s] < self.clock || self.node_of_slot[s] == NO_SLOT,
            "constraint column cache smaller than the active set"
        );
        if self.node_of_slot[s] != NO_SLOT {
            self.slot_of_node[self.node_of_slot[s]] = NO_SLOT;
        }
        let (dim, n) = (self.dim, self.n);
        for c in 0..dim {
            let d = dim * node + c;
            self.unit.fill(0.0);
            if !self.is_bc[d] {
                self.unit[d] = 1.0;
                self.lu.solve_in_place(&mut self.unit);
            }
            self.cols[(s * dim + c) * n..(s * dim + c + 1) * n].copy_from_slice(&self.unit);
        }
        self.node_of_slot[s] = node;
        self.slot_of_node[node] = s;
        self.last_used[s] = self.clock;
        s
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
