//! The multi-degree-of-freedom space-time step (paper Eqs. 6-10, 18-24).
//!
//! For `M v' + C v + K u = f(t) + r` with velocity linear over `[t0, t0 + h]` and the
//! virtual velocity a Dirac at `t0 + alpha h` (Eq. 8), the step is
//!
//! $$A v_1 = b,\qquad A = M + \alpha h C + \tfrac{\alpha^2 h^2}{2} K,$$
//! $$b = \big(M - (1-\alpha) h C - (\alpha - \tfrac{\alpha^2}{2}) h^2 K\big) v_0 - h K u_0
//!      + h f(t_0 + \alpha h) + h r,$$
//! $$u_1 = u_0 + h[(1-\beta) v_0 + \beta v_1],\qquad \beta = 1 - \frac{\alpha}{1+\gamma}.$$
//!
//! `A` depends on `alpha` and `h` only, so it is factored once ([`Factor`]); `gamma`
//! (hence `beta`) may change between steps at no cost.
//!
//! **The factor** ([`FactorChoice`]). With the default, [`FactorChoice::Auto`], a symmetric
//! `A` (no Coriolis term: the bars, a wheel without spin) gets a sparse Cholesky factor
//! `L L^T` (AMD ordering), any other `A` (the wheel's Coriolis matrix is skew) an LU with
//! partial pivoting whose columns are ordered by AMD on `A + A^T` (the matrix is structurally
//! symmetric and its pivots stay on the diagonal, where COLAMD, faer's default for LU, orders
//! for the fill of `A^T A`). The LU with COLAMD stays available as the reference
//! ([`FactorChoice::Kind`]); the tests check that the fast paths reproduce it.
//! With the Coriolis term on the right-hand side (below) the spinning wheel's `A` is
//! symmetric and gets the Cholesky factor too: the factor's storage halves, but a solve
//! still reads `L` twice (forward and backward), as many bytes as the LU's `L` and `U`; it
//! pays where `L` then stays in the caches between the two sweeps (measured on the 48-ring
//! disk, 14,114 dofs: 0.6 of the LU step) and not on small meshes (the row solves keep `L`
//! and `L^T` both) nor on the largest (192 rings: `L` of 150 MB streams from memory twice).
//!
//! **The Coriolis term on the right-hand side** ([`Coriolis::Extrapolated`]). `C` splits
//! into its symmetric part `C_s` and its skew part `G` (the Coriolis matrix of a rotating
//! frame). The exact scheme keeps `G` in `A`; the extrapolated one keeps `C_s` only, so that
//! `A_s = M + alpha h C_s + alpha^2 h^2/2 K` is symmetric (a Cholesky factor, half the
//! storage of the LU), and takes the Coriolis force of the step at the extrapolated
//! velocity `v0 + h a0` (`a0 = (v0 - v_-1)/h`, the last step's mean acceleration):
//! $$A_s v_1 = B_s v_0 - h G (v_0 + \alpha h a_0) - h K u_0 + h f,$$
//! with `B_s` the `B` above on `C_s`. The exact scheme's `alpha h G v1 + (1 - alpha) h G v0`
//! becomes `h G (v0 + alpha h a0)`: the same to `O(h^2 G a')`. Its amplification on the
//! spinning oscillator ([`crate::time::sdof::gyroscopic_eigenvalues`]) matches the exact
//! scheme's for every mode well above the spin; the tests assert both.
//!
//! **Dirichlet velocities** are imposed by replacing the rows and columns of `A` by the
//! identity and lifting the prescribed values into `b`.
//!
//! **Velocity constraints** `c_p^T v_1 = g_p` (contact: a node's normal velocity) are imposed
//! by Lagrange multipliers through the factored `A` ([`crate::contact::rows`]):
//! `A v = b + C^T lambda`, `C v = g`, hence
//! $$\lambda = (C A^{-1} C^T)^{-1} (g - C A^{-1} b),\qquad v = A^{-1} b + A^{-1} C^T \lambda.$$
//! The columns `A^{-1} e_d` of the constrained nodes' dofs are computed once and cached while
//! `A` does not change; only the small dense system on the active constraints is solved each
//! step, so a change of the active set costs no factorization. The multiplier `lambda_p` is
//! the impulse of the constraint over the step: the force is `lambda_p / h`.

use crate::linalg::rhs::Operators;
use crate::linalg::team::Team;
use crate::linalg::{
    BParts, Factor, FactorKind, Factorization, LinalgError, Pattern, RhsOperator, RhsValues,
};
pub use crate::model::LinearModel;
use crate::model::{LoadFn, State};
use crate::time::integrator::{FactorCounts, Maps, MultiplierUnit, Step, TimeIntegrator};
use crate::time::params::beta;
use crate::time::{Coriolis, SpaceTimeParams};

/// The order from which [`Stepper::update_displacement`] runs in two halves side by side:
/// on the 48-ring disk (14,114 dofs) 0.0125 -> 0.0100 ms (an in-process probe, alternated
/// binaries, 15 rounds of 1,000 steps, three times), where the threshold had been 50,000.
const UPDATE_SPLIT_MIN_ORDER: usize = 10_000;

/// The space-time stepper: factored `A`, the right-hand-side operators and the Dirichlet
/// velocities. All work memory is allocated in [`Stepper::new`]; it implements the
/// [`TimeIntegrator`] contract (multipliers are impulses).
pub struct Stepper {
    params: SpaceTimeParams,
    /// `gamma` from given instants on: `(t_from, gamma)`, sorted by time.
    schedule: Vec<(f64, f64)>,
    n: usize,
    pattern: Pattern,
    m: Vec<f64>,
    /// `C`, or its symmetric part `C_s` when the skew part is on the right-hand side.
    c: Vec<f64>,
    /// The treatment of `C`'s skew part in force ([`Coriolis::Implicit`] when `C` has none).
    coriolis: Coriolis,
    /// `G`, the skew part of `C`, with [`Coriolis::Extrapolated`] (else empty).
    g: Vec<f64>,
    /// Values of `M - (1-alpha) h C - (alpha - alpha^2/2) h^2 K` for the current `h`.
    bv: Vec<f64>,
    /// Values of `K`.
    k: Vec<f64>,
    /// `B` and `K` by rows, for the right-hand side ([`RhsOperator`]).
    rhs_rows: RhsOperator,
    /// Values of `A` for the current `h` before the Dirichlet rows and columns were replaced
    /// (for lifting).
    a_orig: Vec<f64>,
    a_work: Vec<f64>,
    /// The factor of the run's step `params.h`.
    lu: Factor,
    /// A second numeric factor on the same symbolic analysis, for another step length.
    lu_other: Option<(f64, Factor)>,
    /// The step length in force, s.
    h_now: f64,
    /// The threads of the two-part work: the split factor's sweeps, the right-hand side's
    /// halves, the displacement update (`Team::default()` until [`Stepper::set_team`]).
    team: Team,
    bc_dofs: Vec<usize>,
    bc_values: Vec<f64>,
    is_bc: Vec<bool>,
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
    /// in m/s).
    ///
    /// # Errors
    /// [`LinalgError`] when `A` is singular.
    pub fn new(
        model: &LinearModel,
        params: SpaceTimeParams,
        bcs: &[(usize, f64)],
    ) -> Result<Self, LinalgError> {
        Self::with_options(model, params, bcs, FactorChoice::Auto, Coriolis::Implicit)
    }

    /// The same with the factorization of `A` chosen by `choice` (the exact scheme).
    ///
    /// # Errors
    /// [`LinalgError`] when `A` is singular (or, for a Cholesky factor, not positive
    /// definite).
    pub fn with_factor(
        model: &LinearModel,
        params: SpaceTimeParams,
        bcs: &[(usize, f64)],
        choice: FactorChoice,
    ) -> Result<Self, LinalgError> {
        Self::with_options(model, params, bcs, choice, Coriolis::Implicit)
    }

    /// The same with the factorization of `A` chosen by `choice` and the skew part of `C`
    /// treated by `coriolis` (module docs). [`Coriolis::Extrapolated`] on a `C` without skew
    /// part, or on a pattern that is not structurally symmetric, is the exact scheme
    /// ([`Stepper::coriolis`] tells which is in force).
    ///
    /// # Errors
    /// [`LinalgError`] when `A` is singular (or, for a Cholesky factor, not positive
    /// definite).
    pub fn with_options(
        model: &LinearModel,
        params: SpaceTimeParams,
        bcs: &[(usize, f64)],
        choice: FactorChoice,
        coriolis: Coriolis,
    ) -> Result<Self, LinalgError> {
        let n = model.n();
        let pattern = model.pattern().clone();
        let (c, g) = match coriolis {
            Coriolis::Extrapolated => split_skew(&pattern, &model.c),
            Coriolis::Implicit => None,
        }
        .unwrap_or_else(|| (model.c.clone(), Vec::new()));
        let coriolis = if g.is_empty() {
            Coriolis::Implicit
        } else {
            Coriolis::Extrapolated
        };
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
        let nnz = model.m.len();
        let (mut a_orig, mut bv, mut a_work) = (vec![0.0; nnz], vec![0.0; nnz], vec![0.0; nnz]);
        Operators {
            m: &model.m,
            c: &c,
            k: &model.k,
            pattern: &pattern,
            is_bc: &is_bc,
        }
        .fill(params.alpha, params.h, &mut a_orig, &mut bv, &mut a_work);
        let lu = match choice {
            FactorChoice::Kind(kind) => Factor::new(&pattern, &a_work, kind)?,
            // A symmetric matrix that is not positive definite keeps the LU.
            FactorChoice::Auto => Factor::auto(&pattern, &a_work)?,
            FactorChoice::On(backend) => Factor::auto_on(backend, &pattern, &a_work)?,
        };
        let rhs_rows = RhsOperator::new(
            &pattern,
            &RhsValues {
                m: &model.m,
                c: &c,
                k: &model.k,
                g: &g,
                bv: &bv,
                parts: BParts::new(params.alpha, params.h),
            },
        );
        Ok(Self {
            params,
            rhs_rows,
            schedule: Vec::new(),
            n,
            m: model.m.clone(),
            c,
            coriolis,
            g,
            bv,
            k: model.k.clone(),
            a_orig,
            a_work,
            lu,
            lu_other: None,
            h_now: params.h,
            team: Team::default(),
            pattern,
            bc_dofs,
            bc_values,
            is_bc,
        })
    }

    /// The same with `gamma` changing at given instants: `(t_from, gamma)`, sorted by time;
    /// before the first, `params.gamma`.
    pub fn with_schedule(mut self, schedule: Vec<(f64, f64)>) -> Self {
        self.schedule = schedule;
        self
    }

    /// `gamma` in force for the step starting at `t`.
    pub fn gamma_at(&self, t: f64) -> f64 {
        let mut g = self.params.gamma;
        for &(t_from, gm) in &self.schedule {
            if t + 1e-12 * self.params.h >= t_from {
                g = gm;
            }
        }
        g
    }

    /// `beta` in force for the step starting at `t` (Eq. 24).
    pub fn beta_at(&self, t: f64) -> f64 {
        beta(self.params.alpha, self.gamma_at(t))
    }

    /// `bv`, `a_orig` and `a_work` (with the Dirichlet identity rows) for the step `h`.
    fn operators(&mut self, h: f64) {
        let ops = Operators {
            m: &self.m,
            c: &self.c,
            k: &self.k,
            pattern: &self.pattern,
            is_bc: &self.is_bc,
        };
        ops.fill(
            self.params.alpha,
            h,
            &mut self.a_orig,
            &mut self.bv,
            &mut self.a_work,
        );
        self.rhs_rows.refill(&RhsValues {
            m: &self.m,
            c: &self.c,
            k: &self.k,
            g: &self.g,
            bv: &self.bv,
            parts: BParts::new(self.params.alpha, h),
        });
        self.h_now = h;
    }
}

/// How [`Stepper`] factors `A` (module docs).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FactorChoice {
    /// Cholesky when `A` is symmetric (to 1e-14 of its largest entry) and positive definite,
    /// else LU with AMD column ordering.
    Auto,
    /// This factorization (an LU works for every `A`; Cholesky fails on an unsymmetric or
    /// indefinite one).
    Kind(FactorKind),
    /// As [`FactorChoice::Auto`] by these factorizations ([`crate::linalg::Backend`]).
    On(crate::linalg::Backend),
}

impl Stepper {
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
    /// the external force at `t0 + alpha h` (N per dof); with the Coriolis term on the
    /// right-hand side, `C` is its symmetric part and `- h G (v0 + alpha h a0)` is added
    /// (module docs; `a0` is read only then).
    pub fn rhs_into(&self, u0: &[f64], v0: &[f64], a0: &[f64], f: &[f64], b: &mut [f64]) {
        let h = self.h_now;
        assert!(b.len() == self.n);
        debug_assert_eq!(self.coriolis == Coriolis::Extrapolated, !self.g.is_empty());
        self.rhs_rows
            .apply(&self.team, h, self.params.alpha * h, [u0, v0, a0], f, b);
    }

    /// The treatment of `C`'s skew part in force (module docs).
    pub fn coriolis(&self) -> Coriolis {
        self.coriolis
    }

    /// `G`, the skew part of `C` on the right-hand side (on the pattern of
    /// [`Stepper::matrices`]), with [`Coriolis::Extrapolated`].
    pub fn skew(&self) -> Option<&[f64]> {
        (self.coriolis == Coriolis::Extrapolated).then_some(&self.g[..])
    }

    /// Solves `A v1 = b` in place (`b` becomes `v1`) with the Dirichlet velocities.
    pub fn solve(&mut self, b: &mut [f64]) {
        self.apply_dirichlet(b);
        let (lu, team) = self.factor();
        lu.solve_on(team, b);
    }

    /// The factorization of `A` in use.
    pub fn factor_kind(&self) -> FactorKind {
        self.lu.kind()
    }

    /// Stored entries of the factors of `A` (`L + U`, or `L` for Cholesky).
    pub fn factor_nnz(&self) -> usize {
        self.lu.factor_nnz()
    }

    /// Bytes a free step reads (its floor is these over the read bandwidth of the memory
    /// they live in): the factors as a solve reads them
    /// ([`crate::linalg::Factor::solve_bytes`]), the right-hand side's rows and ten passes
    /// over vectors of `n` values (the state, the load and `b` in the right-hand side, the
    /// solve's gather, two sweeps and read-out, the update of `u`), eleven with the Coriolis
    /// term on the right-hand side (`a0`).
    pub fn free_step_bytes(&self) -> usize {
        let passes = if self.coriolis == Coriolis::Extrapolated {
            11
        } else {
            10
        };
        self.lu.solve_bytes() + self.rhs_rows.bytes() + passes * self.n * std::mem::size_of::<f64>()
    }

    /// The orders of the factor's two parts solved side by side and of the top after them,
    /// when the factor is split for two threads ([`crate::linalg::Factor::parts`]).
    pub fn factor_parts(&self) -> Option<(usize, usize, usize)> {
        self.lu.parts()
    }

    /// The orders of all the factor's parts when it is split
    /// ([`crate::linalg::Factor::part_orders`]): the leaves, then each level of separators up
    /// to the top.
    pub fn factor_part_orders(&self) -> Option<Vec<usize>> {
        self.lu.part_orders()
    }

    /// The step's matrices for the current `h` on their pattern: `A` with the Dirichlet
    /// identity rows and columns (the matrix factored), the right-hand-side operator
    /// `B = M - (1-alpha) h C - (alpha - alpha^2/2) h^2 K` and `K` (module docs): `(pattern,
    /// A, B, K)`. With [`Coriolis::Extrapolated`], `C` in `A` and `B` is its symmetric part
    /// (and [`Stepper::skew`] the rest).
    pub fn matrices(&self) -> (&Pattern, &[f64], &[f64], &[f64]) {
        (&self.pattern, &self.a_work, &self.bv, &self.k)
    }

    /// The run's factor and, once made, the other step length's.
    fn factors(&self) -> impl Iterator<Item = &Factor> {
        std::iter::once(&self.lu).chain(self.lu_other.as_ref().map(|(_, lu)| lu))
    }

    /// The factor in use and the team its solves run on.
    fn factor(&mut self) -> (&mut Factor, &Team) {
        let lu = match &mut self.lu_other {
            Some((h, lu)) if *h == self.h_now => lu,
            _ => &mut self.lu,
        };
        (lu, &self.team)
    }

    /// Runs the two-part work on `team`'s threads (the same bits on any team).
    pub fn set_team(&mut self, team: &Team) {
        self.team = team.clone();
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
        let n = self.n;
        assert!(u0.len() == n && v0.len() == n && v1.len() == n && u1.len() == n);
        let (h, b0) = (self.h_now, 1.0 - beta);
        let update = |range: std::ops::Range<usize>, u1: &mut [f64]| {
            let (u0, v0, v1) = (&u0[range.clone()], &v0[range.clone()], &v1[range]);
            for (((u1i, &u0i), &v0i), &v1i) in u1.iter_mut().zip(u0).zip(v0).zip(v1) {
                *u1i = u0i + h * (b0 * v0i + beta * v1i);
            }
        };
        if n >= UPDATE_SPLIT_MIN_ORDER {
            let (lo, hi) = u1.split_at_mut(n / 2);
            self.team
                .join(|| update(0..n / 2, lo), || update(n / 2..n, hi));
        } else {
            update(0..n, u1);
        }
    }

    /// The predictors of `step` from `s0`: `U = u0 + h (1 - beta) v0`, `V = 0`.
    fn predictors(&self, step: &Step, s0: &State, pred: &mut State) {
        let (h, bt) = (step.h, step.weight);
        for i in 0..self.n {
            pred.u[i] = s0.u[i] + h * (1.0 - bt) * s0.v[i];
            pred.v[i] = 0.0;
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

impl TimeIntegrator for Stepper {
    fn name(&self) -> String {
        format!(
            "space_time(alpha={} gamma={})",
            self.params.alpha, self.params.gamma
        )
    }
    fn h(&self) -> f64 {
        self.h_now
    }
    fn step_at(&self, t0: f64) -> Step {
        let (h, beta) = (self.h_now, self.beta_at(t0));
        Step {
            t0,
            h,
            maps: Maps {
                mu_u: h * beta,
                mu_v: 1.0,
                force: 1.0 / h,
            },
            weight: beta,
            unit: MultiplierUnit::Impulse,
            explicit: false,
        }
    }
    #[allow(clippy::too_many_arguments)]
    fn predict(
        &mut self,
        t0: f64,
        s0: &State,
        load: &LoadFn,
        extra: &[f64],
        f: &mut [f64],
        pred: &mut State,
        x: &mut [f64],
    ) -> Step {
        let step = self.step_at(t0);
        let h = step.h;
        load(t0 + self.params.alpha * h, f);
        for (fi, ei) in f.iter_mut().zip(extra) {
            *fi += ei;
        }
        self.rhs_into(&s0.u, &s0.v, &s0.a, f, x);
        self.solve(x);
        self.predictors(&step, s0, pred);
        step
    }
    /// `b = h f + ...` ([`crate::linalg::rhs::RhsOperator::apply`]): the gain is `h`.
    fn repredict(&self, t0: f64, s0: &State, pred: &mut State) -> Option<(Step, f64)> {
        let step = self.step_at(t0);
        self.predictors(&step, s0, pred);
        Some((step, step.h))
    }
    fn inverse_column(&mut self, dof: usize, col: &mut [f64]) -> bool {
        col.fill(0.0);
        if self.is_bc[dof] {
            return false;
        }
        col[dof] = 1.0;
        let (lu, team) = self.factor();
        lu.solve_on(team, col);
        true
    }
    /// The columns as one block of right-hand sides (`Factor::solve_many_on`); a prescribed
    /// dof's column is zero (its right-hand side is, and so its solution, exactly).
    fn inverse_columns(&mut self, dofs: &[usize], cols: &mut [f64]) -> usize {
        let n = self.n;
        cols.fill(0.0);
        let mut made = 0;
        for (c, &d) in dofs.iter().enumerate() {
            if !self.is_bc[d] {
                cols[c * n + d] = 1.0;
                made += 1;
            }
        }
        let (lu, team) = self.factor();
        lu.solve_many_on(team, cols, dofs.len());
        made
    }
    fn finish(&self, step: &Step, s0: &State, _pred: &State, x: &[f64], s1: &mut State) {
        s1.v.copy_from_slice(x);
        self.update_displacement(step.weight, &s0.u, &s0.v, x, &mut s1.u);
        let h = step.h;
        for i in 0..self.n {
            s1.a[i] = (s1.v[i] - s0.v[i]) / h;
        }
    }
    fn stiffness_point(&self, s0: &State, _pred: &State, p: &mut [f64]) -> f64 {
        let (a, h) = (self.params.alpha, self.h_now);
        for i in 0..self.n {
            p[i] = s0.u[i] + h * (a - 0.5 * a * a) * s0.v[i];
        }
        0.5 * h * a * a
    }
    fn set_step(&mut self, h: f64) -> Result<(), LinalgError> {
        if h == self.h_now {
            return Ok(());
        }
        self.operators(h);
        if h == self.params.h {
            return Ok(());
        }
        match &mut self.lu_other {
            Some((ho, _)) if *ho == h => {}
            Some((ho, lu)) => {
                lu.refactor(&self.pattern, &self.a_work)?;
                *ho = h;
            }
            None => {
                // On the run's factor's symbolic analysis (shared, not made again).
                let lu = self.lu.with_values(&self.pattern, &self.a_work)?;
                self.lu_other = Some((h, lu));
            }
        }
        Ok(())
    }
    /// The numeric factorizations and symbolic analyses made by the run's factor and the
    /// other step length's, as they count them ([`Factorization::numeric_factorizations`],
    /// [`Factorization::symbolic_analyses`]): one analysis while the second shares the
    /// first's.
    fn factor_size(&self) -> Option<super::integrator::FactorSize> {
        Some(super::integrator::FactorSize {
            kind: self.factor_kind(),
            nnz: self.factor_nnz(),
            free_step_bytes: self.free_step_bytes(),
        })
    }
    fn counts(&self) -> FactorCounts {
        FactorCounts {
            numeric: self
                .factors()
                .map(Factorization::numeric_factorizations)
                .sum(),
            symbolic: self.factors().map(Factorization::symbolic_analyses).sum(),
        }
    }
    fn set_team(&mut self, team: &Team) {
        Stepper::set_team(self, team);
    }
}

/// `(C_s, G)`: the symmetric and skew parts of `C` on `pattern`; None when `C` has no skew
/// part (to 1e-14 of its largest entry) or the pattern is not structurally symmetric.
pub(crate) fn split_skew(pattern: &Pattern, c: &[f64]) -> Option<(Vec<f64>, Vec<f64>)> {
    let t = crate::linalg::transpose_positions(pattern)?;
    let scale = c.iter().fold(0.0_f64, |a, v| a.max(v.abs()));
    let g: Vec<f64> = (0..c.len()).map(|p| 0.5 * (c[p] - c[t[p]])).collect();
    if g.iter().all(|x| x.abs() <= 1e-14 * scale) {
        return None;
    }
    let cs = (0..c.len()).map(|p| 0.5 * (c[p] + c[t[p]])).collect();
    Some((cs, g))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bodies::wheel::{WheelModel, WheelSpec};
    use crate::mesh::generators::disk_rings;

    /// `set_step` factors another step length on the run's one symbolic analysis, for the
    /// Cholesky factor (the Coriolis term on the right-hand side makes `A` symmetric) as for
    /// the LU (the exact scheme): after two other step lengths and the run's again, one
    /// analysis and three numeric factorizations, as the factors count them. A `set_step`
    /// that analysed the pattern again would count two.
    #[test]
    fn set_step_reuses_the_symbolic_analysis() {
        let w = WheelModel::new(disk_rings(0.1, 6).unwrap(), WheelSpec::paper()).unwrap();
        let h = 2e-6;
        let params = SpaceTimeParams {
            alpha: 0.6,
            gamma: 0.0,
            h,
        };
        for (coriolis, kind) in [
            (Coriolis::Extrapolated, FactorKind::Llt),
            (
                Coriolis::Implicit,
                FactorKind::Lu(crate::linalg::Ordering::Amd),
            ),
        ] {
            let mut s =
                Stepper::with_options(&w.model, params, &[], FactorChoice::Kind(kind), coriolis)
                    .unwrap();
            assert_eq!(s.factor_kind(), kind);
            assert_eq!(
                {
                    let c = s.counts();
                    (c.symbolic, c.numeric)
                },
                (1, 1)
            );
            // A factor made afresh counts its own analysis: the count can tell.
            let fresh = Factor::new(&s.pattern, &s.a_work, kind).unwrap();
            assert_eq!(fresh.symbolic_analyses(), 1);
            s.set_step(0.5 * h).unwrap();
            s.set_step(0.25 * h).unwrap();
            s.set_step(h).unwrap();
            assert_eq!(s.h(), h);
            assert_eq!(
                {
                    let c = s.counts();
                    (c.symbolic, c.numeric)
                },
                (1, 3),
                "{kind:?}"
            );
            // The other step length's factor solves its own matrix: `A(h/4) x = b`.
            s.set_step(0.25 * h).unwrap();
            let n = s.n();
            let x0: Vec<f64> = (0..n).map(|i| (0.3 * i as f64).sin()).collect();
            let mut b = vec![0.0; n];
            crate::linalg::spmv_into(&s.pattern, &s.a_work, &x0, &mut b);
            s.factor().0.solve_in_place(&mut b);
            let err = b
                .iter()
                .zip(&x0)
                .fold(0.0_f64, |m, (p, q)| m.max((p - q).abs()));
            assert!(err < 1e-10, "{kind:?}: {err:e}");
            assert_eq!(
                {
                    let c = s.counts();
                    (c.symbolic, c.numeric)
                },
                (1, 3)
            );
        }
    }
}
