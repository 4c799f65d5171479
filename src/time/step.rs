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
//! by Lagrange multipliers through the factored `A` (DESIGN §2):
//! `A v = b + C^T lambda`, `C v = g`, hence
//! $$\lambda = (C A^{-1} C^T)^{-1} (g - C A^{-1} b),\qquad v = A^{-1} b + A^{-1} C^T \lambda.$$
//! The columns `A^{-1} e_d` of the constrained nodes' dofs are computed once and cached while
//! `A` does not change; only the small dense system on the active constraints is solved each
//! step, so a change of the active set costs no factorization. The multiplier `lambda_p` is
//! the impulse of the constraint over the step: the force is `lambda_p / h`.

use crate::assembly::Assembler;
use crate::linalg::team::Team;
use crate::linalg::{avx2_method, with_avx2, Factor, FactorKind, HugeBuf, LinalgError, Pattern};
use crate::simulation::LoadFn;
use crate::time::integrator::{Maps, MultiplierUnit, State, TimeIntegrator};
use crate::time::params::beta;
use crate::time::{Coriolis, SpaceTimeParams};

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

/// Bytes of the right-hand side's blocks from which its products prefetch them
/// ([`RhsRows::blocks_ahead`]): below, they stay in the second-level caches (2 MiB a core
/// on the development host). Within a step the sweeps' factors push the blocks out of the
/// caches, and the products waited on them: on the 192-ring disk (40 MB of blocks) the
/// right-hand side took 2.4-3.1 ms of a step without the prefetch, 1.8-2.2 ms with it, the
/// Coriolis term on either side (an in-process probe, alternated binaries, twice). On the
/// 48-ring disk (2.5 MB of blocks, in the last-level cache) it cost: 0.065 -> 0.080 ms with
/// a threshold of 1 MiB.
const RHS_PREFETCH_MIN_BYTES: usize = 4 << 20;

/// How many blocks ahead of the pair being formed the right-hand side prefetches them (24
/// KiB of six-value blocks).
const RHS_AHEAD: usize = 512;

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
    /// `beta` of the step being solved (set by `predict`).
    beta_now: f64,
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
    /// `B` and `K` by rows, for the right-hand side ([`RhsRows`]).
    rhs_rows: RhsRows,
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
    factorizations: usize,
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
        };
        let rhs_rows = RhsRows::new(
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
            beta_now: params.beta(),
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
            factorizations: 1,
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
}

/// The right-hand side's operators `B` and `K` stored by rows (32-bit column indices, the
/// two values of an entry side by side), so that `B v0 - h K u0` is one pass of dot
/// products without stores in the inner loop; refilled when `B` changes with `h`.
///
/// Two consecutive rows with the same columns (a node's two dofs, always on the wheel) are
/// a pair: their columns are stored once, the four values of an entry side by side, and one
/// gather of `v0` and `u0` serves both rows. Other rows are stored alone. A pair's columns
/// that come two by two (`j, j + 1`: a neighbouring node's two dofs) are a block: one
/// index, eight values, `v0[j..j + 2]` and `u0[j..j + 2]` read in one load each, and on AVX2
/// two 256-bit products ([`rhs_blocks_avx2`]). Measured on the paper's wheel: the right-hand
/// side 5.4 -> 4.1 us per step (see `Stepper::rhs_into`).
#[derive(Debug, Clone)]
struct RhsRows {
    /// Rows stored alone: `single[k]` is row `i`, its entries `ptr[k]..ptr[k + 1]`.
    single: Vec<usize>,
    ptr: Vec<usize>,
    idx: Vec<u32>,
    /// `[B_ij, K_ij]` per entry.
    bk: Vec<[f64; 2]>,
    /// For each entry, its position in the pattern (by columns).
    src: Vec<usize>,
    /// Pairs: `pair[k]` is the first row `i` (the second is `i + 1`), its entries
    /// `pair_ptr[k]..pair_ptr[k + 1]`.
    pair: Vec<usize>,
    pair_ptr: Vec<usize>,
    pair_idx: Vec<u32>,
    /// `[B_ij, K_ij, B_(i+1)j, K_(i+1)j]` per entry.
    pair_bk: Vec<[f64; 4]>,
    pair_src: Vec<[usize; 2]>,
    /// The pairs' blocks: pair `k`'s are `blk_ptr[k]..blk_ptr[k + 1]`, block `e` the columns
    /// `j = blk_idx[e]` and `j + 1`, `blk_src[e]` its four positions in the pattern, lanes
    /// `[i j, i j+1, i+1 j, i+1 j+1]`. Its values are held in the form `blk_form`
    /// ([`BlockForm`]): `blk_bk[e]`, `B`'s four values then `K`'s, or `blk_kd[e]`, `K`'s four
    /// and two more from which `B` is formed in the products.
    blk_ptr: Vec<usize>,
    blk_idx: HugeBuf<u32>,
    blk_form: BlockForm,
    blk_bk: HugeBuf<[f64; 8]>,
    blk_kd: HugeBuf<[f64; 6]>,
    blk_src: Vec<[usize; 4]>,
    /// `(alpha - alpha^2/2) h^2`: `B = D - c2 K` with `D = M - (1 - alpha) h C`.
    c2: f64,
    /// `G`'s four values of each block (with the Coriolis term on the right-hand side),
    /// unless every block is `[[0, -g], [g, 0]]` (the wheel's Coriolis term, `2 Omega J
    /// m_ab`): then `blk_gs` holds each block's `g` and `blk_g` is empty ([`ScalarSkew`]).
    /// Both empty in [`BlockForm::Diagonal`], where `g` is in `blk_kd`.
    blk_g: Vec<[f64; 4]>,
    blk_gs: Vec<f64>,
    /// The processor has AVX2: the blocks run on [`rhs_blocks_avx2`] (the bits of
    /// [`rhs_blocks`]).
    avx2: bool,
    /// The products prefetch the blocks ahead of them ([`RhsRows::blocks_ahead`]): set
    /// when they are `RHS_PREFETCH_MIN_BYTES` or more.
    prefetch: bool,
    /// With the Coriolis term on the right-hand side, the skew part `G` by the same rows:
    /// `g[e]` beside `bk[e]`, `pair_g[e] = [G_ij, G_(i+1)j]` beside `pair_bk[e]` (empty
    /// otherwise).
    g: Vec<f64>,
    pair_g: Vec<[f64; 2]>,
    /// For orders from `RHS_SPLIT_MIN_ORDER` on, the first pair of the second half of the
    /// entries: the pairs before it and those from it on are formed on two threads.
    pair_mid: Option<usize>,
}

/// The order from which the right-hand side's pairs of rows are formed in two halves side
/// by side (`Team::join`; one thread runs both with `Par::Seq`): the orders
/// whose factor is split for two threads (`linalg::Factor::parts`).
const RHS_SPLIT_MIN_ORDER: usize = crate::linalg::SPLIT_MIN_ORDER;

/// How the right-hand side's blocks hold their values ([`RhsRows`]). In the wheel, `M` and
/// the mass-proportional damping are `m_ab I` per pair of nodes and the Coriolis term `2
/// Omega m_ab J`, so that `D = M - (1 - alpha) h C` has two values per block, or one, and
/// `B = D - c2 K` need not be stored: a block is read as six values instead of eight
/// (nine with the Coriolis term on the right-hand side, seven when `G` is by one value).
/// `B`'s four values are formed lane by lane by the operations `Operators::fill` forms
/// them with ([`BParts`]), from `D`'s values checked equal to `D`'s
/// ([`RhsRows::compact_form`]), so every form gives the same bits.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum BlockForm {
    /// `blk_bk`: `B`'s four values, then `K`'s.
    General,
    /// `blk_kd = [K's four, d, s]`, `D = [[d, s], [-s, d]]`.
    Skew,
    /// `blk_kd = [K's four, d, g]`, `D = [[d, 0], [0, d]]` and `G = [[0, -g], [g, 0]]`
    /// (`g` zero without the Coriolis term on the right-hand side).
    Diagonal,
}

/// The size of the blocks' eight values from which they are held in a compact form
/// ([`BlockForm`]): below, they stay in the second-level cache between steps, where forming
/// `B` costs more than reading it (the paper's wheel, 0.2 MB: 18.8 -> 21.1 us a free step;
/// `wheel.toml`'s, 0.8 MB: 49.9 and 50.2 us; graded 576 rim nodes, 1.7 MB: 154 -> 150 us;
/// 48 rings, 3.2 MB: 400-417 -> 380-394 us with the Coriolis term on the right-hand side;
/// `softway matrix`, alternated binaries).
const COMPACT_MIN_BYTES: usize = 1 << 20;

/// `B = D - c2 K` with `D = M - k1 C`, `k1 = (1 - alpha) h`, `c2 = (alpha - alpha^2/2) h^2`:
/// the one place `B`'s values are formed ([`Operators::fill`]), and `D`'s of the right-hand
/// side's compact blocks, which form `B` from `D` and `K` with these very operations
/// ([`BlockForm`]), so that both round alike.
#[derive(Debug, Clone, Copy)]
struct BParts {
    k1: f64,
    c2: f64,
}

impl BParts {
    fn new(alpha: f64, h: f64) -> Self {
        Self {
            k1: (1.0 - alpha) * h,
            c2: (alpha - 0.5 * alpha * alpha) * h * h,
        }
    }

    /// `D`'s value of an entry from `M`'s and `C`'s.
    #[inline(always)]
    fn d(&self, m: f64, c: f64) -> f64 {
        m - self.k1 * c
    }

    /// `B`'s value of an entry from `M`'s, `C`'s and `K`'s.
    #[inline(always)]
    fn b(&self, m: f64, c: f64, k: f64) -> f64 {
        self.d(m, c) - self.c2 * k
    }
}

/// The values the right-hand side's rows are filled from, for one step: `B`
/// ([`BParts::b`]) and its parts `M`, `C` (the symmetric part with the Coriolis term on the
/// right-hand side) and `K`, and `G` (empty unless on the right-hand side).
struct RhsValues<'a> {
    m: &'a [f64],
    c: &'a [f64],
    k: &'a [f64],
    g: &'a [f64],
    bv: &'a [f64],
    parts: BParts,
}

impl RhsRows {
    fn new(pattern: &Pattern, values: &RhsValues) -> Self {
        let g = values.g;
        let n = pattern.nrows();
        assert!(n <= u32::MAX as usize, "too many dofs for 32-bit indices");
        let (cp, ri) = (pattern.col_ptr(), pattern.row_idx());
        let nnz = cp[pattern.ncols()];
        // The pattern by rows: (column, position by columns).
        let mut ptr = vec![0usize; n + 1];
        for &i in &ri[..nnz] {
            ptr[i + 1] += 1;
        }
        for i in 0..n {
            ptr[i + 1] += ptr[i];
        }
        let mut next = ptr[..n].to_vec();
        let mut by_rows = vec![(0u32, 0usize); nnz];
        for j in 0..pattern.ncols() {
            for p in cp[j]..cp[j + 1] {
                by_rows[next[ri[p]]] = (j as u32, p);
                next[ri[p]] += 1;
            }
        }
        let row = |i: usize| &by_rows[ptr[i]..ptr[i + 1]];
        let mut rows = Self {
            single: Vec::new(),
            ptr: vec![0],
            idx: Vec::new(),
            bk: Vec::new(),
            src: Vec::new(),
            pair: Vec::new(),
            pair_ptr: vec![0],
            pair_idx: Vec::new(),
            pair_bk: Vec::new(),
            pair_src: Vec::new(),
            blk_ptr: vec![0],
            blk_idx: HugeBuf::default(),
            blk_form: BlockForm::General,
            blk_bk: HugeBuf::default(),
            blk_kd: HugeBuf::default(),
            blk_src: Vec::new(),
            c2: 0.0,
            blk_g: Vec::new(),
            blk_gs: Vec::new(),
            avx2: crate::linalg::has_avx2(),
            prefetch: false,
            g: Vec::new(),
            pair_g: Vec::new(),
            pair_mid: None,
        };
        let (mut i, mut blk_idx) = (0, Vec::new());
        while i < n {
            let same = i + 1 < n
                && row(i).len() == row(i + 1).len()
                && row(i).iter().zip(row(i + 1)).all(|(a, b)| a.0 == b.0);
            if same {
                rows.pair.push(i);
                let (a, b) = (row(i), row(i + 1));
                let mut e = 0;
                while e < a.len() {
                    if e + 1 < a.len() && a[e + 1].0 == a[e].0 + 1 {
                        blk_idx.push(a[e].0);
                        rows.blk_src.push([a[e].1, a[e + 1].1, b[e].1, b[e + 1].1]);
                        e += 2;
                    } else {
                        rows.pair_idx.push(a[e].0);
                        rows.pair_src.push([a[e].1, b[e].1]);
                        e += 1;
                    }
                }
                rows.pair_ptr.push(rows.pair_idx.len());
                rows.blk_ptr.push(blk_idx.len());
                i += 2;
            } else {
                rows.single.push(i);
                for a in row(i) {
                    rows.idx.push(a.0);
                    rows.src.push(a.1);
                }
                rows.ptr.push(rows.idx.len());
                i += 1;
            }
        }
        rows.blk_idx = blk_idx.into();
        if n >= RHS_SPLIT_MIN_ORDER && rows.pair.len() >= 2 {
            // Entries before pair `k` (a block is two columns).
            let before = |k: usize| rows.pair_ptr[k] + 2 * rows.blk_ptr[k];
            let half = before(rows.pair.len()) / 2;
            let mid = (0..rows.pair.len())
                .find(|&k| before(k) >= half)
                .unwrap_or(1);
            rows.pair_mid = Some(mid.clamp(1, rows.pair.len() - 1));
        }
        rows.bk = vec![[0.0; 2]; rows.idx.len()];
        rows.pair_bk = vec![[0.0; 4]; rows.pair_idx.len()];
        if !g.is_empty() {
            rows.g = rows.src.iter().map(|&p| g[p]).collect();
            rows.pair_g = rows.pair_src.iter().map(|&[p, q]| [g[p], g[q]]).collect();
        }
        rows.refill(values);
        rows
    }

    /// The form the blocks' values are held in for `values`: [`BlockForm::General`] below
    /// `COMPACT_MIN_BYTES`, else the most compact one they allow
    /// ([`RhsRows::compact_form`]).
    fn block_form(&self, values: &RhsValues) -> BlockForm {
        if std::mem::size_of::<[f64; 8]>() * self.blk_src.len() < COMPACT_MIN_BYTES {
            BlockForm::General
        } else {
            self.compact_form(values)
        }
    }

    /// The most compact form the blocks' values allow for `values` ([`BlockForm`]): each of
    /// `D`'s values it holds equal to `D`'s (`==`: a zero's sign aside, which no sum that
    /// starts at `+0` can tell), so that `B`'s formed from them are `B`'s ([`BParts`]).
    fn compact_form(&self, values: &RhsValues) -> BlockForm {
        let RhsValues { m, c, g, parts, .. } = *values;
        let d = |p: usize| parts.d(m[p], c[p]);
        let same = |p: usize, q: usize| d(p).to_bits() == d(q).to_bits();
        let diagonal = (g.is_empty()
            || self
                .blk_src
                .iter()
                .all(|s| ScalarSkew::holds(&s.map(|p| g[p]))))
            && self
                .blk_src
                .iter()
                .all(|s| same(s[0], s[3]) && d(s[1]) == 0.0 && d(s[2]) == 0.0);
        if diagonal {
            return BlockForm::Diagonal;
        }
        let skew = self
            .blk_src
            .iter()
            .all(|s| same(s[0], s[3]) && d(s[2]) == -d(s[1]));
        if skew {
            BlockForm::Skew
        } else {
            BlockForm::General
        }
    }

    avx2_method! {
        /// `b[i] = h f[i] + (B v0 - h K u0)[i]` for the rows `i` stored alone, on AVX2's
        /// instructions where the processor has them (`linalg::with_avx2`).
        fn singles_into / singles_avx2(
            &self,
            h: f64,
            f: &[f64],
            u0: &[f64],
            v0: &[f64],
            b: &mut [f64]
        ) => singles_here
    }

    #[inline(always)]
    fn singles_here(&self, h: f64, f: &[f64], u0: &[f64], v0: &[f64], b: &mut [f64]) {
        let n = v0.len();
        assert!(u0.len() == n && f.len() == n);
        for (k, &i) in self.single.iter().enumerate() {
            let range = self.ptr[k]..self.ptr[k + 1];
            let (idx, bk) = (&self.idx[range.clone()], &self.bk[range]);
            let (mut sb, mut sk) = ([0.0; 2], [0.0; 2]);
            let (idx2, bk2) = (idx.chunks_exact(2), bk.chunks_exact(2));
            let (idx_rest, bk_rest) = (idx2.remainder(), bk2.remainder());
            for (ic, vc) in idx2.zip(bk2) {
                for k in 0..2 {
                    let j = ic[k] as usize;
                    debug_assert!(j < n);
                    // SAFETY: the column indices are < n (built from the pattern in
                    // `RhsRows::new`) and `v0.len() == u0.len() == n` (asserted above).
                    let (vj, uj) = unsafe { (*v0.get_unchecked(j), *u0.get_unchecked(j)) };
                    sb[k] += vc[k][0] * vj;
                    sk[k] += vc[k][1] * uj;
                }
            }
            for (&j, v) in idx_rest.iter().zip(bk_rest) {
                sb[0] += v[0] * v0[j as usize];
                sk[0] += v[1] * u0[j as usize];
            }
            b[i] = h * f[i] + ((sb[0] + sb[1]) - h * (sk[0] + sk[1]));
        }
    }

    avx2_method! {
        /// `b[i - offset] = h f[i] + (B v0 - h K u0)[i]` for the rows `i` of the pairs `pairs`
        /// (`fuv = [f, u0, v0]`), on AVX2's instructions where the processor has them
        /// (`linalg::with_avx2`).
        fn pairs_into / pairs_avx2(
            &self,
            pairs: std::ops::Range<usize>,
            offset: usize,
            h: f64,
            fuv: [&[f64]; 3],
            b: &mut [f64]
        ) => pairs_here
    }

    #[inline(always)]
    fn pairs_here(
        &self,
        pairs: std::ops::Range<usize>,
        offset: usize,
        h: f64,
        [f, u0, v0]: [&[f64]; 3],
        b: &mut [f64],
    ) {
        let n = v0.len();
        assert!(u0.len() == n && f.len() == n);
        let mut ahead = self.blocks_ahead(pairs.start);
        for k in pairs {
            ahead(self.blk_ptr[k]);
            let i = self.pair[k] - offset;
            let range = self.pair_ptr[k]..self.pair_ptr[k + 1];
            let (idx, bk) = (&self.pair_idx[range.clone()], &self.pair_bk[range]);
            // [B v of row i, K u of row i, B v of row i + 1, K u of row i + 1].
            let mut s = [0.0; 4];
            for (&j, v) in idx.iter().zip(bk) {
                let j = j as usize;
                debug_assert!(j < n);
                // SAFETY: the column indices are < n (built from the pattern in
                // `RhsRows::new`) and `v0.len() == u0.len() == n` (asserted above).
                let (vj, uj) = unsafe { (*v0.get_unchecked(j), *u0.get_unchecked(j)) };
                s[0] += v[0] * vj;
                s[1] += v[1] * uj;
                s[2] += v[2] * vj;
                s[3] += v[3] * uj;
            }
            let range = self.blk_ptr[k]..self.blk_ptr[k + 1];
            let idx = &self.blk_idx[range.clone()];
            let (no_g, uva): (&[[f64; 4]], _) = (&[], [u0, v0, &[][..]]);
            let (sb, sk) = match self.blk_form {
                BlockForm::General => {
                    self.blocks::<false, _, _>(idx, &self.blk_bk[range], no_g, 0.0, uva)
                }
                BlockForm::Skew => {
                    let kd = SkewD {
                        kd: &self.blk_kd[range],
                        c2: self.c2,
                    };
                    self.blocks::<false, _, _>(idx, kd, no_g, 0.0, uva)
                }
                BlockForm::Diagonal => {
                    let kd = DiagD {
                        kd: &self.blk_kd[range],
                        c2: self.c2,
                    };
                    self.blocks::<false, _, _>(idx, kd, no_g, 0.0, uva)
                }
            };
            let r = self.pair[k];
            b[i] = h * f[r] + ((s[0] + (sb[0] + sb[1])) - h * (s[1] + (sk[0] + sk[1])));
            b[i + 1] = h * f[r + 1] + ((s[2] + (sb[2] + sb[3])) - h * (s[3] + (sk[2] + sk[3])));
        }
    }

    avx2_method! {
        /// The same as `pairs_into` with the skew part: `b[i - offset] = h f[i] + (B v0 - h (K
        /// u0 + G (v0 + c a0)))[i]` (`fuva = [f, u0, v0, a0]`).
        fn pairs_g_into / pairs_g_avx2(
            &self,
            pairs: std::ops::Range<usize>,
            offset: usize,
            h: f64,
            c: f64,
            fuva: [&[f64]; 4],
            b: &mut [f64]
        ) => pairs_g_here
    }

    #[inline(always)]
    fn pairs_g_here(
        &self,
        pairs: std::ops::Range<usize>,
        offset: usize,
        h: f64,
        c: f64,
        [f, u0, v0, a0]: [&[f64]; 4],
        b: &mut [f64],
    ) {
        let n = v0.len();
        assert!(u0.len() == n && a0.len() == n && f.len() == n);
        let mut ahead = self.blocks_ahead(pairs.start);
        for k in pairs {
            ahead(self.blk_ptr[k]);
            let i = self.pair[k] - offset;
            let range = self.pair_ptr[k]..self.pair_ptr[k + 1];
            let (idx, bk, g) = (
                &self.pair_idx[range.clone()],
                &self.pair_bk[range.clone()],
                &self.pair_g[range],
            );
            // [B v, K u + G w of row i, the same of row i + 1], w = v0 + c a0.
            let mut s = [0.0; 4];
            for ((&j, v), gj) in idx.iter().zip(bk).zip(g) {
                let j = j as usize;
                debug_assert!(j < n);
                // SAFETY: the column indices are < n (built from the pattern in
                // `RhsRows::new`) and the three vectors have length n (asserted above).
                let (vj, uj, aj) = unsafe {
                    (
                        *v0.get_unchecked(j),
                        *u0.get_unchecked(j),
                        *a0.get_unchecked(j),
                    )
                };
                let wj = vj + c * aj;
                s[0] += v[0] * vj;
                s[1] += v[1] * uj + gj[0] * wj;
                s[2] += v[2] * vj;
                s[3] += v[3] * uj + gj[1] * wj;
            }
            // The blocks: lanes `[i j, i j+1, i+1 j, i+1 j+1]`.
            let range = self.blk_ptr[k]..self.blk_ptr[k + 1];
            let idx = &self.blk_idx[range.clone()];
            let uva = [u0, v0, a0];
            let (sb, sk) = match self.blk_form {
                BlockForm::Diagonal => {
                    let kd = &self.blk_kd[range];
                    let vals = DiagD { kd, c2: self.c2 };
                    self.blocks::<true, _, _>(idx, vals, SlotSkew(kd), c, uva)
                }
                BlockForm::General => {
                    self.blocks_g(idx, &self.blk_bk[range.clone()], range, c, uva)
                }
                BlockForm::Skew => {
                    let vals = SkewD {
                        kd: &self.blk_kd[range.clone()],
                        c2: self.c2,
                    };
                    self.blocks_g(idx, vals, range, c, uva)
                }
            };
            let r = self.pair[k];
            b[i] = h * f[r] + ((s[0] + (sb[0] + sb[1])) - h * (s[1] + (sk[0] + sk[1])));
            b[i + 1] = h * f[r + 1] + ((s[2] + (sb[2] + sb[3])) - h * (s[3] + (sk[2] + sk[3])));
        }
    }

    /// A prefetch of the blocks for the pairs from `first` on: called with the first block
    /// of each pair in turn, it asks for the lines of the blocks' values, column indices and
    /// skew values `RHS_AHEAD` blocks after it that it has not asked for yet (a pair's few
    /// lines at a time), with [`RhsRows::prefetch`]; nothing otherwise.
    #[inline(always)]
    fn blocks_ahead(&self, first: usize) -> impl FnMut(usize) + '_ {
        let on = self.prefetch;
        let mut done = self.blk_ptr.get(first).map_or(0, |&e| e + RHS_AHEAD);
        move |e: usize| {
            let want = e + RHS_AHEAD;
            if on && want > done {
                use crate::linalg::prefetch_span as span;
                span(&self.blk_idx, done..want);
                span(&self.blk_bk, done..want);
                span(&self.blk_kd, done..want);
                span(&self.blk_g, done..want);
                span(&self.blk_gs, done..want);
                done = want;
            }
        }
    }

    /// Bytes of the blocks' arrays.
    fn blk_bytes(&self) -> usize {
        use std::mem::size_of_val as b;
        b(&self.blk_idx[..])
            + b(&self.blk_bk[..])
            + b(&self.blk_kd[..])
            + b(&self.blk_g[..])
            + b(&self.blk_gs[..])
    }

    /// [`RhsRows::blocks`] with the skew part held apart from the values (`blk_g` or
    /// `blk_gs`, the blocks `range`).
    #[inline(always)]
    fn blocks_g<V: BlockValues>(
        &self,
        idx: &[u32],
        vals: V,
        range: std::ops::Range<usize>,
        c: f64,
        uva: [&[f64]; 3],
    ) -> ([f64; 4], [f64; 4]) {
        if self.blk_g.is_empty() {
            self.blocks::<true, _, _>(idx, vals, ScalarSkew(&self.blk_gs[range]), c, uva)
        } else {
            self.blocks::<true, _, _>(idx, vals, &self.blk_g[range], c, uva)
        }
    }

    /// [`rhs_blocks`], on AVX2 where the processor has it.
    #[inline(always)]
    fn blocks<const G: bool, V: BlockValues, S: SkewBlocks>(
        &self,
        idx: &[u32],
        vals: V,
        g: S,
        c: f64,
        uva: [&[f64]; 3],
    ) -> ([f64; 4], [f64; 4]) {
        if self.avx2 {
            // SAFETY: `avx2` is set only where the processor has AVX2 (`new`); the block
            // columns `j, j + 1` are < n and the vectors read have length n (asserted by
            // the callers); `vals` (and with `G`, `g`) have a block for each of `idx`.
            #[cfg(target_arch = "x86_64")]
            unsafe {
                rhs_blocks_avx2::<G, V, S>(idx, vals, g, c, uva)
            }
            #[cfg(not(target_arch = "x86_64"))]
            rhs_blocks::<G, V, S>(idx, vals, g, c, uva)
        } else {
            rhs_blocks::<G, V, S>(idx, vals, g, c, uva)
        }
    }

    /// `b[i] -= h (G (v0 + c a0))[i]` for the rows `i` stored alone (the skew part's share
    /// of `singles_into`).
    fn singles_g_into(&self, h: f64, c: f64, v0: &[f64], a0: &[f64], b: &mut [f64]) {
        for (k, &i) in self.single.iter().enumerate() {
            let range = self.ptr[k]..self.ptr[k + 1];
            let s: f64 = self.idx[range.clone()]
                .iter()
                .zip(&self.g[range])
                .map(|(&j, gj)| gj * (v0[j as usize] + c * a0[j as usize]))
                .sum();
            b[i] -= h * s;
        }
    }

    /// Bytes of the arrays a right-hand side reads (the positions in the pattern, read only
    /// when the values change, left out).
    fn bytes(&self) -> usize {
        use std::mem::size_of_val as b;
        b(&self.single[..])
            + b(&self.ptr[..])
            + b(&self.idx[..])
            + b(&self.bk[..])
            + b(&self.g[..])
            + b(&self.pair[..])
            + b(&self.pair_ptr[..])
            + b(&self.pair_idx[..])
            + b(&self.pair_bk[..])
            + b(&self.pair_g[..])
            + b(&self.blk_ptr[..])
            + self.blk_bytes()
    }

    /// Fills the values for `values`' step (the blocks' arrays are allocated again only
    /// when their form changes).
    fn refill(&mut self, values: &RhsValues) {
        let (k, bv) = (values.k, values.bv);
        for (e, &p) in self.bk.iter_mut().zip(&self.src) {
            *e = [bv[p], k[p]];
        }
        for (e, &[p, q]) in self.pair_bk.iter_mut().zip(&self.pair_src) {
            *e = [bv[p], k[p], bv[q], k[q]];
        }
        self.fill_blocks(self.block_form(values), values);
    }

    /// Fills the blocks' values in the form `form` (which must hold for `values`:
    /// [`RhsRows::block_form`]), allocating their arrays when the form changes.
    fn fill_blocks(&mut self, form: BlockForm, values: &RhsValues) {
        let RhsValues {
            m,
            c,
            k,
            g,
            bv,
            parts,
        } = *values;
        let nb = self.blk_src.len();
        let allocated = match form {
            BlockForm::General => self.blk_bk.len() == nb,
            BlockForm::Skew | BlockForm::Diagonal => self.blk_kd.len() == nb,
        };
        if form != self.blk_form || !allocated {
            self.blk_form = form;
            (self.blk_bk, self.blk_kd, self.blk_g, self.blk_gs) = Default::default();
            match form {
                BlockForm::General => self.blk_bk = vec![[0.0; 8]; nb].into(),
                BlockForm::Skew | BlockForm::Diagonal => {
                    self.blk_kd = vec![[0.0; 6]; nb].into();
                }
            }
            if !g.is_empty() && form != BlockForm::Diagonal {
                let four: Vec<[f64; 4]> = self.blk_src.iter().map(|s| s.map(|p| g[p])).collect();
                if four.iter().all(ScalarSkew::holds) {
                    // A quarter of the bytes, the same values (and bits) in the products.
                    self.blk_gs = four.iter().map(|g| g[2]).collect();
                } else {
                    self.blk_g = four;
                }
            }
        }
        self.c2 = parts.c2;
        let d = |p: usize| parts.d(m[p], c[p]);
        let ks = |s: &[usize; 4]| s.map(|p| k[p]);
        match form {
            BlockForm::General => {
                for (e, s) in self.blk_bk.iter_mut().zip(&self.blk_src) {
                    let kk = ks(s);
                    *e = [
                        bv[s[0]], bv[s[1]], bv[s[2]], bv[s[3]], kk[0], kk[1], kk[2], kk[3],
                    ];
                }
            }
            BlockForm::Skew => {
                for (e, s) in self.blk_kd.iter_mut().zip(&self.blk_src) {
                    let kk = ks(s);
                    *e = [kk[0], kk[1], kk[2], kk[3], d(s[0]), d(s[1])];
                }
            }
            BlockForm::Diagonal => {
                for (e, s) in self.blk_kd.iter_mut().zip(&self.blk_src) {
                    let kk = ks(s);
                    let gs = if g.is_empty() { 0.0 } else { g[s[2]] };
                    *e = [kk[0], kk[1], kk[2], kk[3], d(s[0]), gs];
                }
            }
        }
        self.prefetch = self.blk_bytes() >= RHS_PREFETCH_MIN_BYTES;
    }
}

#[cfg(target_arch = "x86_64")]
use crate::linalg::broadcast2;
#[cfg(target_arch = "x86_64")]
use std::arch::x86_64::{
    __m256d, _mm256_add_pd, _mm256_blend_pd, _mm256_loadu_pd, _mm256_mul_pd, _mm256_permute_pd,
    _mm256_set1_pd, _mm256_set_pd, _mm256_setzero_pd, _mm256_storeu_pd, _mm256_sub_pd,
    _mm256_xor_pd,
};

/// The blocks of a pair of rows `i, i + 1` of [`RhsRows`]: `(sb, sk)`, the lane sums of
/// `B`'s and `K`'s four values of each block times `[v0[j], v0[j + 1], v0[j], v0[j + 1]]`
/// and the same of `u0` (row `i`'s `(B v0)_i` share is `sb[0] + sb[1]`, row `i + 1`'s
/// `sb[2] + sb[3]`). With the skew part (`G`), `sk` also holds `G`'s four values `g` times
/// the lanes of `w = v0 + c a0` (each lane `K u + G w` summed as `K_l u_l + G_l w_l`);
/// without it `g` and `a0` are not read. The order of [`rhs_blocks_avx2`]'s lanes, so that
/// both give the same bits.
///
/// # Panics
/// When `j + 1` is out of range of a vector for a block (debug builds; the indices come
/// from the pattern), or with `G` when `g` is shorter than `idx`.
#[inline(always)]
fn rhs_blocks<const G: bool, V: BlockValues, S: SkewBlocks>(
    idx: &[u32],
    vals: V,
    g: S,
    c: f64,
    [u0, v0, a0]: [&[f64]; 3],
) -> ([f64; 4], [f64; 4]) {
    assert!(vals.len() >= idx.len() && (!G || g.len() >= idx.len()));
    let (mut sb, mut sk) = ([0.0; 4], [0.0; 4]);
    for (e, &j) in idx.iter().enumerate() {
        let j = j as usize;
        debug_assert!(j + 1 < v0.len() && j + 1 < u0.len() && (!G || j + 1 < a0.len()));
        // SAFETY: a block's columns `j, j + 1` are < n (`RhsRows::new`) and the vectors
        // have length n (asserted by the callers).
        let (vl, ul) = unsafe {
            (
                [*v0.get_unchecked(j), *v0.get_unchecked(j + 1)],
                [*u0.get_unchecked(j), *u0.get_unchecked(j + 1)],
            )
        };
        // SAFETY: `e < vals.len()` (asserted above).
        let (bl, kl) = unsafe { vals.lanes(e) };
        for l in 0..4 {
            sb[l] += bl[l] * vl[l % 2];
        }
        if G {
            // SAFETY: as above; `e < g.len()` (asserted above).
            let (al, gj) =
                unsafe { ([*a0.get_unchecked(j), *a0.get_unchecked(j + 1)], g.block(e)) };
            for l in 0..4 {
                let w = vl[l % 2] + c * al[l % 2];
                sk[l] += kl[l] * ul[l % 2] + gj[l] * w;
            }
        } else {
            for l in 0..4 {
                sk[l] += kl[l] * ul[l % 2];
            }
        }
    }
    (sb, sk)
}

/// [`rhs_blocks`] on 256-bit registers, the same operations lane by lane: per block one
/// broadcast of `v0[j..j + 2]` and one of `u0[j..j + 2]` (and of `a0[j..j + 2]`) to both
/// halves, two products (four) and their sums.
///
/// # Safety
/// The processor must have AVX2, `j + 1` must be below the length of the vectors read for
/// every block column `j`, and with `G`, `g.len() >= idx.len()`.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
#[inline]
unsafe fn rhs_blocks_avx2<const G: bool, V: BlockValues, S: SkewBlocks>(
    idx: &[u32],
    vals: V,
    g: S,
    c: f64,
    [u0, v0, a0]: [&[f64]; 3],
) -> ([f64; 4], [f64; 4]) {
    debug_assert!(vals.len() >= idx.len() && (!G || g.len() >= idx.len()));
    let (mut sb, mut sk) = (_mm256_setzero_pd(), _mm256_setzero_pd());
    let cc = _mm256_set1_pd(c);
    for (e, &j) in idx.iter().enumerate() {
        let j = j as usize;
        debug_assert!(j + 1 < v0.len() && j + 1 < u0.len() && (!G || j + 1 < a0.len()));
        let vl = broadcast2(v0.as_ptr().add(j));
        let ul = broadcast2(u0.as_ptr().add(j));
        let (bl, kl) = vals.lanes_avx2(e);
        sb = _mm256_add_pd(sb, _mm256_mul_pd(bl, vl));
        let ku = _mm256_mul_pd(kl, ul);
        if G {
            let al = broadcast2(a0.as_ptr().add(j));
            let w = _mm256_add_pd(vl, _mm256_mul_pd(cc, al));
            let gw = _mm256_mul_pd(_mm256_loadu_pd(g.block(e).as_ptr()), w);
            sk = _mm256_add_pd(sk, _mm256_add_pd(ku, gw));
        } else {
            sk = _mm256_add_pd(sk, ku);
        }
    }
    let (mut b, mut k) = ([0.0; 4], [0.0; 4]);
    _mm256_storeu_pd(b.as_mut_ptr(), sb);
    _mm256_storeu_pd(k.as_mut_ptr(), sk);
    (b, k)
}

/// The values of the blocks of a pair of rows for [`rhs_blocks`]: `B`'s four and `K`'s
/// four, lanes `[i j, i j+1, i+1 j, i+1 j+1]` ([`BlockForm`]).
trait BlockValues: Copy {
    /// Blocks held.
    fn len(&self) -> usize;
    /// Block `e`'s values of `B` and of `K`.
    ///
    /// # Safety
    /// `e < self.len()`.
    unsafe fn lanes(&self, e: usize) -> ([f64; 4], [f64; 4]);
    /// The same in two registers, by the same operations.
    ///
    /// # Safety
    /// `e < self.len()`, and the processor has AVX2 (called from AVX2 code, into which it
    /// is inlined).
    #[cfg(target_arch = "x86_64")]
    unsafe fn lanes_avx2(&self, e: usize) -> (__m256d, __m256d);
}

/// [`BlockForm::General`]: `B`'s four values, then `K`'s.
impl BlockValues for &[[f64; 8]] {
    fn len(&self) -> usize {
        <[[f64; 8]]>::len(self)
    }
    #[inline(always)]
    unsafe fn lanes(&self, e: usize) -> ([f64; 4], [f64; 4]) {
        // SAFETY: `e < len` (the caller's contract).
        let v = unsafe { self.get_unchecked(e) };
        ([v[0], v[1], v[2], v[3]], [v[4], v[5], v[6], v[7]])
    }
    #[cfg(target_arch = "x86_64")]
    #[inline(always)]
    unsafe fn lanes_avx2(&self, e: usize) -> (__m256d, __m256d) {
        // SAFETY: `e < len` and AVX2 (the caller's contract).
        unsafe {
            let v = self.get_unchecked(e).as_ptr();
            (_mm256_loadu_pd(v), _mm256_loadu_pd(v.add(4)))
        }
    }
}

/// [`BlockForm::Skew`] (`DIAGONAL` false): `[K's four, d, s]`, `B = [[d, s], [-s, d]] - c2
/// K`; [`BlockForm::Diagonal`] (`DIAGONAL` true): `[K's four, d, g]`, `B = [[d, 0], [0, d]] -
/// c2 K` (`g` is [`SlotSkew`]'s).
#[derive(Clone, Copy)]
struct CompactD<'a, const DIAGONAL: bool> {
    kd: &'a [[f64; 6]],
    c2: f64,
}

/// [`BlockForm::Skew`]'s values.
type SkewD<'a> = CompactD<'a, false>;
/// [`BlockForm::Diagonal`]'s values.
type DiagD<'a> = CompactD<'a, true>;

impl<const DIAGONAL: bool> BlockValues for CompactD<'_, DIAGONAL> {
    fn len(&self) -> usize {
        self.kd.len()
    }
    #[inline(always)]
    unsafe fn lanes(&self, e: usize) -> ([f64; 4], [f64; 4]) {
        // SAFETY: `e < len` (the caller's contract).
        let v = unsafe { self.kd.get_unchecked(e) };
        let (c2, d) = (self.c2, v[4]);
        // `D`'s off-diagonal pair.
        let (s1, s2) = if DIAGONAL { (0.0, 0.0) } else { (v[5], -v[5]) };
        (
            [d - c2 * v[0], s1 - c2 * v[1], s2 - c2 * v[2], d - c2 * v[3]],
            [v[0], v[1], v[2], v[3]],
        )
    }
    #[cfg(target_arch = "x86_64")]
    #[inline(always)]
    unsafe fn lanes_avx2(&self, e: usize) -> (__m256d, __m256d) {
        // SAFETY: `e < len` and AVX2 (the caller's contract).
        unsafe {
            let v = self.kd.get_unchecked(e).as_ptr();
            let k = _mm256_loadu_pd(v);
            let d = if DIAGONAL {
                // [d, +0, +0, d].
                _mm256_blend_pd::<0b1001>(_mm256_setzero_pd(), _mm256_set1_pd(*v.add(4)))
            } else {
                // [d, s, d, s] -> [d, s, s, d] -> [d, s, -s, d] (a sign flip, exact).
                let ds = _mm256_permute_pd::<0b0110>(broadcast2(v.add(4)));
                _mm256_xor_pd(ds, _mm256_set_pd(0.0, -0.0, 0.0, 0.0))
            };
            (
                _mm256_sub_pd(d, _mm256_mul_pd(_mm256_set1_pd(self.c2), k)),
                k,
            )
        }
    }
}

/// The skew part's blocks of a pair of rows for [`rhs_blocks`]: four values each, lanes
/// `[i j, i j+1, i+1 j, i+1 j+1]`.
trait SkewBlocks: Copy {
    /// Blocks held.
    fn len(&self) -> usize;
    /// Block `e`'s four values.
    ///
    /// # Safety
    /// `e < self.len()`.
    unsafe fn block(&self, e: usize) -> [f64; 4];
}

impl SkewBlocks for &[[f64; 4]] {
    fn len(&self) -> usize {
        <[[f64; 4]]>::len(self)
    }
    #[inline(always)]
    unsafe fn block(&self, e: usize) -> [f64; 4] {
        // SAFETY: `e < len` (the caller's contract).
        unsafe { *self.get_unchecked(e) }
    }
}

/// Skew blocks `[[0, -g], [g, 0]]` held by their one value `g`: the wheel's Coriolis term
/// (`2 Omega J m_ab`, `crate::frame::add_coriolis`), a quarter of the bytes of four values.
/// Block `e` is `[+0, -g, g, +0]`, the four values it was made from, bit for bit
/// ([`ScalarSkew::holds`]).
#[derive(Clone, Copy)]
struct ScalarSkew<'a>(&'a [f64]);

impl ScalarSkew<'_> {
    /// The four values `g` are `[+0, -x, x, +0]` for some `x`, bit for bit.
    fn holds(g: &[f64; 4]) -> bool {
        g[0].to_bits() == 0 && g[3].to_bits() == 0 && g[1].to_bits() == (-g[2]).to_bits()
    }
}

impl SkewBlocks for ScalarSkew<'_> {
    fn len(&self) -> usize {
        self.0.len()
    }
    #[inline(always)]
    unsafe fn block(&self, e: usize) -> [f64; 4] {
        // SAFETY: `e < len` (the caller's contract).
        let g = unsafe { *self.0.get_unchecked(e) };
        [0.0, -g, g, 0.0]
    }
}

/// [`BlockForm::Diagonal`]'s skew blocks `[[0, -g], [g, 0]]`, `g` the sixth value of each
/// block (as [`ScalarSkew`]).
#[derive(Clone, Copy)]
struct SlotSkew<'a>(&'a [[f64; 6]]);

impl SkewBlocks for SlotSkew<'_> {
    fn len(&self) -> usize {
        self.0.len()
    }
    #[inline(always)]
    unsafe fn block(&self, e: usize) -> [f64; 4] {
        // SAFETY: `e < len` (the caller's contract).
        let g = unsafe { self.0.get_unchecked(e)[5] };
        [0.0, -g, g, 0.0]
    }
}

/// The matrices the step's operators are made of.
struct Operators<'a> {
    m: &'a [f64],
    c: &'a [f64],
    k: &'a [f64],
    pattern: &'a Pattern,
    is_bc: &'a [bool],
}

impl Operators<'_> {
    /// `A = M + alpha h C + alpha^2 h^2/2 K`, `B = M - (1-alpha) h C - (alpha - alpha^2/2)
    /// h^2 K` and `A` with the Dirichlet identity rows, for the step `h`.
    fn fill(&self, a: f64, h: f64, a_orig: &mut [f64], bv: &mut [f64], a_work: &mut [f64]) {
        let (m, c, k) = (self.m, self.c, self.k);
        let parts = BParts::new(a, h);
        for p in 0..m.len() {
            a_orig[p] = m[p] + a * h * c[p] + 0.5 * a * a * h * h * k[p];
            bv[p] = parts.b(m[p], c[p], k[p]);
        }
        a_work.copy_from_slice(a_orig);
        crate::linalg::set_identity_rows(self.pattern, a_work, self.is_bc);
    }
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
        // `b = h f + (B v0 - h K u0)`, one row (or pair of rows) at a time: `h f` is formed
        // row by row with the rest, on the thread that forms the row.
        let r = &self.rhs_rows;
        let n = self.n;
        assert!(b.len() == n && v0.len() == n && u0.len() == n && f.len() == n);
        let pairs = r.pair.len();
        let skew = self.coriolis == Coriolis::Extrapolated;
        assert!(!skew || a0.len() == n);
        let c = self.params.alpha * h;
        let part = |range: std::ops::Range<usize>, offset: usize, b: &mut [f64]| {
            if skew {
                r.pairs_g_into(range, offset, h, c, [f, u0, v0, a0], b);
            } else {
                r.pairs_into(range, offset, h, [f, u0, v0], b);
            }
        };
        match r.pair_mid {
            Some(mid) => {
                // The second half's rows start at its first pair's row.
                let cut = r.pair[mid];
                let (lo, hi) = b.split_at_mut(cut);
                self.team
                    .join(|| part(0..mid, 0, lo), || part(mid..pairs, cut, hi));
            }
            None => part(0..pairs, 0, b),
        }
        r.singles_into(h, f, u0, v0, b);
        if skew {
            r.singles_g_into(h, c, v0, a0, b);
        }
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

    /// The step's matrices for the current `h` on their pattern: `A` with the Dirichlet
    /// identity rows and columns (the matrix factored), the right-hand-side operator
    /// `B = M - (1-alpha) h C - (alpha - alpha^2/2) h^2 K` and `K` (module docs): `(pattern,
    /// A, B, K)`. With [`Coriolis::Extrapolated`], `C` in `A` and `B` is its symmetric part
    /// (and [`Stepper::skew`] the rest).
    pub fn matrices(&self) -> (&Pattern, &[f64], &[f64], &[f64]) {
        (&self.pattern, &self.a_work, &self.bv, &self.k)
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
    fn n(&self) -> usize {
        self.n
    }
    fn h(&self) -> f64 {
        self.h_now
    }
    fn unit(&self) -> MultiplierUnit {
        MultiplierUnit::Impulse
    }
    fn maps(&self) -> Maps {
        Maps {
            mu_u: self.h_now * self.beta_now,
            mu_v: 1.0,
            force: 1.0 / self.h_now,
        }
    }
    fn displacement_weight(&self, t0: f64) -> f64 {
        self.beta_at(t0)
    }
    fn is_fixed(&self, dof: usize) -> bool {
        self.is_bc[dof]
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
    ) {
        let h = self.h_now;
        self.beta_now = self.beta_at(t0);
        load(t0 + self.params.alpha * h, f);
        for (fi, ei) in f.iter_mut().zip(extra) {
            *fi += ei;
        }
        self.rhs_into(&s0.u, &s0.v, &s0.a, f, x);
        self.solve(x);
        let bt = self.beta_now;
        for i in 0..self.n {
            pred.u[i] = s0.u[i] + h * (1.0 - bt) * s0.v[i];
            pred.v[i] = 0.0;
        }
    }
    fn apply_inverse(&mut self, r: &mut [f64]) {
        for (ri, &bc) in r.iter_mut().zip(&self.is_bc) {
            if bc {
                *ri = 0.0;
            }
        }
        let (lu, team) = self.factor();
        lu.solve_on(team, r);
    }
    fn finish(&self, s0: &State, _pred: &State, x: &[f64], s1: &mut State) {
        s1.v.copy_from_slice(x);
        self.update_displacement(self.beta_now, &s0.u, &s0.v, x, &mut s1.u);
        let h = self.h_now;
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
                self.factorizations += 1;
            }
            None => {
                let lu = self.lu.with_values(&self.pattern, &self.a_work)?;
                self.lu_other = Some((h, lu));
                self.factorizations += 1;
            }
        }
        Ok(())
    }
    fn factorizations(&self) -> usize {
        self.factorizations
    }
    fn set_team(&mut self, team: &Team) {
        Stepper::set_team(self, team);
    }
    fn symbolic_analyses(&self) -> usize {
        1
    }
}

/// `(C_s, G)`: the symmetric and skew parts of `C` on `pattern`; None when `C` has no skew
/// part (to 1e-14 of its largest entry) or the pattern is not structurally symmetric.
fn split_skew(pattern: &Pattern, c: &[f64]) -> Option<(Vec<f64>, Vec<f64>)> {
    let t = crate::linalg::transpose_positions(pattern)?;
    let scale = c.iter().fold(0.0_f64, |a, v| a.max(v.abs()));
    let g: Vec<f64> = (0..c.len()).map(|p| 0.5 * (c[p] - c[t[p]])).collect();
    if g.iter().all(|x| x.abs() <= 1e-14 * scale) {
        return None;
    }
    let cs = (0..c.len()).map(|p| 0.5 * (c[p] + c[t[p]])).collect();
    Some((cs, g))
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::generators::disk_rings;
    use crate::wheel::{WheelModel, WheelSpec};

    /// `B`, and the right-hand side's rows, of the wheel's `M`, `c` (`C` or its symmetric
    /// part) and `K` for `alpha = 0.6`, `h = 2e-6`, with the skew part `g` (or none), their
    /// blocks in the most compact form they allow.
    fn rows_of(w: &WheelModel, c: &[f64], g: &[f64]) -> (RhsRows, Vec<f64>) {
        let (m, k, pattern) = (&w.model.m, &w.model.k, w.model.pattern());
        let nnz = m.len();
        let (mut a_orig, mut bv, mut a_work) = (vec![0.0; nnz], vec![0.0; nnz], vec![0.0; nnz]);
        let is_bc = vec![false; w.model.n()];
        let (alpha, h) = (0.6, 2e-6);
        Operators {
            m,
            c,
            k,
            pattern,
            is_bc: &is_bc,
        }
        .fill(alpha, h, &mut a_orig, &mut bv, &mut a_work);
        let values = RhsValues {
            m,
            c,
            k,
            g,
            bv: &bv,
            parts: BParts::new(alpha, h),
        };
        let mut rows = RhsRows::new(pattern, &values);
        // The paper's disk is small enough for `B`'s four values; its compact form is filled
        // by hand.
        assert_eq!(rows.blk_form, BlockForm::General);
        rows.fill_blocks(rows.compact_form(&values), &values);
        (rows, bv)
    }

    /// The right-hand side's kernels compiled for AVX2 (and the blocks' AVX2 kernel) give
    /// the baseline's bits, the pairs formed in two halves (as from 10,000 dofs on) those
    /// formed in one pass, the blocks' compact forms those of `B`'s and `K`'s eight values,
    /// and all of them the plain sparse products to round-off.
    #[test]
    fn right_hand_side_kernels_agree_bit_for_bit() {
        let w = WheelModel::new(disk_rings(0.1, 6).unwrap(), WheelSpec::paper()).unwrap();
        let (n, k, pattern) = (w.model.n(), &w.model.k, w.model.pattern());
        let u: Vec<f64> = (0..n).map(|i| 1e-4 * (0.3 * i as f64).sin()).collect();
        let v: Vec<f64> = (0..n).map(|i| 1e-2 * (0.7 * i as f64).cos()).collect();
        let acc: Vec<f64> = (0..n).map(|i| 3.0 * (0.9 * i as f64).sin()).collect();
        let f: Vec<f64> = (0..n).map(|i| 1e3 * (1.1 * i as f64).cos()).collect();
        let h = 2e-6;
        let c = 0.8 * h;
        let same = |x: &[f64], y: &[f64]| x.iter().zip(y).all(|(p, q)| p.to_bits() == q.to_bits());
        let close = |x: &[f64], reference: &[f64]| {
            let scale = reference.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
            let d = x
                .iter()
                .zip(reference)
                .fold(0.0_f64, |m, (x, y)| m.max((x - y).abs()));
            assert!(
                d <= 1e-13 * scale,
                "against sparse products: {d:e} of {scale:e}"
            );
        };
        // `b` by the portable kernels (or AVX2's), the pairs in one pass or two halves.
        let rhs = |rows: &RhsRows, g: bool, avx2: bool, halves: bool| {
            let mut rows = rows.clone();
            rows.avx2 = avx2;
            let pairs = rows.pair.len();
            let mid = if halves { pairs / 2 } else { pairs };
            let cut = rows.pair.get(mid).copied().unwrap_or(n);
            let mut b = vec![f64::NAN; n];
            let (lo, hi) = b.split_at_mut(cut);
            for (range, offset, b) in [(0..mid, 0, lo), (mid..pairs, cut, hi)] {
                #[cfg(target_arch = "x86_64")]
                if avx2 {
                    // SAFETY: called with `avx2` only where the processor has AVX2.
                    unsafe {
                        if g {
                            rows.pairs_g_avx2(range, offset, h, c, [&f, &u, &v, &acc], b);
                        } else {
                            rows.pairs_avx2(range, offset, h, [&f, &u, &v], b);
                        }
                    }
                    continue;
                }
                if g {
                    rows.pairs_g_here(range, offset, h, c, [&f, &u, &v, &acc], b);
                } else {
                    rows.pairs_here(range, offset, h, [&f, &u, &v], b);
                }
            }
            rows.singles_here(h, &f, &u, &v, &mut b);
            if g {
                rows.singles_g_into(h, c, &v, &acc, &mut b);
            }
            b
        };
        let avx2 = cfg!(target_arch = "x86_64") && crate::linalg::has_avx2();
        // Each of `rows`' ways to the same bits, and the sparse products to round-off.
        let check = |rows: &RhsRows, bv: &[f64], g: &[f64]| {
            let with_g = !g.is_empty();
            let whole = rhs(rows, with_g, false, false);
            assert!(whole.iter().all(|x| x.is_finite()), "every row formed");
            assert!(same(&whole, &rhs(rows, with_g, false, true)), "halves");
            // The prefetch (on for large blocks) is a hint: the same bits.
            let mut other = rows.clone();
            other.prefetch = !rows.prefetch;
            assert!(same(&whole, &rhs(&other, with_g, false, true)), "prefetch");
            if avx2 {
                assert!(
                    same(&whole, &rhs(&other, with_g, true, false)),
                    "AVX2, prefetch"
                );
            }
            if avx2 {
                assert!(same(&whole, &rhs(rows, with_g, true, false)), "AVX2");
                assert!(same(&whole, &rhs(rows, with_g, true, true)), "AVX2, halves");
            }
            let mut reference: Vec<f64> = f.iter().map(|fi| h * fi).collect();
            crate::linalg::spmv_add(pattern, bv, 1.0, &v, &mut reference);
            crate::linalg::spmv_add(pattern, k, -h, &u, &mut reference);
            if with_g {
                let wv: Vec<f64> = v.iter().zip(&acc).map(|(x, y)| x + c * y).collect();
                crate::linalg::spmv_add(pattern, g, -h, &wv, &mut reference);
            }
            close(&whole, &reference);
            whole
        };

        // The exact scheme: `D = M - (1 - alpha) h C` is `[[d, s], [-s, d]]` per block.
        let (rows, bv) = rows_of(&w, &w.model.c, &[]);
        assert!(!rows.pair.is_empty() && !rows.blk_idx.is_empty());
        assert_eq!(rows.blk_form, BlockForm::Skew);
        assert!(rows.blk_bk.is_empty() && rows.blk_kd.len() == rows.blk_idx.len());
        let compact = check(&rows, &bv, &[]);
        let mut general = rows.clone();
        let values = |c, g, bv| RhsValues {
            m: &w.model.m,
            c,
            k,
            g,
            bv,
            parts: BParts::new(0.6, 2e-6),
        };
        general.fill_blocks(BlockForm::General, &values(&w.model.c, &[], &bv));
        assert!(general.blk_kd.is_empty() && general.blk_bk.len() == rows.blk_idx.len());
        assert!(
            same(&compact, &check(&general, &bv, &[])),
            "Skew against General"
        );

        // The Coriolis term on the right-hand side: `D` is `d I`, `G` `[[0, -g], [g, 0]]`,
        // both in six values per block.
        let (cs, g) = split_skew(pattern, &w.model.c).unwrap();
        let (rows, bv) = rows_of(&w, &cs, &g);
        assert_eq!(rows.blk_form, BlockForm::Diagonal);
        assert!(rows.blk_g.is_empty() && rows.blk_gs.is_empty());
        let compact = check(&rows, &bv, &g);
        let mut general = rows.clone();
        general.fill_blocks(BlockForm::General, &values(&cs, &g, &bv));
        assert!(general.blk_g.is_empty() && general.blk_gs.len() == rows.blk_idx.len());
        assert!(
            same(&compact, &check(&general, &bv, &g)),
            "Diagonal against General"
        );
        // G's blocks by one value or by four.
        let mut four = general.clone();
        four.blk_g = rows.blk_src.iter().map(|s| s.map(|p| g[p])).collect();
        four.blk_gs = Vec::new();
        assert!(same(&compact, &check(&four, &bv, &g)), "G by four values");

        // A stiffness-proportional damping puts `K`'s coupling of x and y in `D`: the blocks
        // keep `B`'s four values, the same sums.
        let c_k: Vec<f64> = w.model.c.iter().zip(k).map(|(c, k)| c + 1e-5 * k).collect();
        let (rows, bv) = rows_of(&w, &c_k, &[]);
        assert_eq!(rows.blk_form, BlockForm::General);
        assert!(rows.blk_kd.is_empty() && rows.blk_bk.len() == rows.blk_idx.len());
        check(&rows, &bv, &[]);
    }
}
