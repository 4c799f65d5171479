//! Constraint rows and their solution through the factored matrix of any integrator
//! (the integrator contract of [`crate::time::integrator`]).
//!
//! # Rows
//!
//! A row `p` acts on a few dofs with the coefficients `c_p` (a contact pair's normal on its
//! node's dofs; for two bodies, `-n` on one node and `+n` on the other). Its reaction enters
//! the step as `c_p^T lambda_p`, and its condition is written on the integrator's unknown `x`
//! (`x = v1` for the space-time scheme, `a1` for the generalized-alpha family):
//! $$y_p = y_{0,p} + \mu_p\\, c_p \cdot x + r_p \lambda_p,$$
//! with one of three kinds:
//! - [`RowKind::Equality`]: `y_p = 0`, `lambda_p` free (a braked or held node);
//! - [`RowKind::Unilateral`]: `y_p >= 0`, `lambda_p >= 0`, `y_p lambda_p = 0` (Signorini,
//!   normal contact);
//! - [`RowKind::Bounded`]: `|lambda_p| <= mu_f lambda_q` with `q` a unilateral or equality
//!   row of the same set: `y_p = 0` inside the bound (stick), and on it `lambda_p =
//!   -sign(y_p) mu_f lambda_q` (slip opposed by the force): Coulomb friction. With a
//!   viscosity `eta > 0` the slip carries an overstress (a viscoplastic friction law of
//!   Perzyna's type: no slip below the bound, a slip rate proportional to the excess over
//!   it): `lambda_p = -sign(y_p) (mu_f lambda_q + eta |y_p|)`, the linear equation
//!   `lambda_p - s mu_f lambda_q + eta y_p = 0` on the slip branch.
//!
//! # Solution
//!
//! With `x = x_free + sum_q z_q lambda_q`, `z_q = A^{-1} c_q^T`, the conditions are a small
//! linear complementarity problem `y = y0' + W lambda`:
//! $$y\'\_{0,p} = y_{0,p} + \mu_p c_p\cdot x_{free},\qquad W_{pq} = \mu_p\\, c_p\cdot z_q +
//!   \delta_{pq} r_p,$$
//! solved exactly by an active set: equality rows always active; a unilateral row enters
//! when violated (`y < -tol`) and leaves when its multiplier turns negative, one change at a
//! time (the most violated first); a bounded row sticks until its multiplier leaves the
//! bound, then slides on it while `y` keeps the sign that the bound opposes. Each active set
//! is one dense solve of its size (from [`crate::linalg::BLOCKED_MIN_ROWS`] rows up by faer's
//! blocked LU, [`DenseLu`]). The columns `A^{-1} e_d` of the constrained dofs are
//! cached (least recently used slot replaced) while `A` does not change, so a change of the
//! active set, a new pair or a turned normal costs no factorization, only column solves the
//! first time a dof is constrained.
//!
//! **Memory.** The rows' buffers are allocated in [`RowSolver::new`]. The column cache
//! (`n` values per slot) starts with [`MAX_TERMS`] slots and grows, by doubling up to the
//! `cache_dofs` given to [`RowSolver::new`] (and past it when the rows of one solve need
//! more columns, all needed at once), only when the rows of one solve need more
//! distinct dofs than it holds: it follows the largest contact patch of the run (a few
//! allocations over a run, none once the patch has been seen), not the number of contact
//! dofs, which on a converged wheel would be hundreds of columns of thousands of values.
//! Under a moving refined zone the columns are kept, not evicted, up to a bound the driver
//! raises to an eighth of the machine's memory ([`RowSolver::raise_column_bound`]): the
//! patch comes back to the same band of dofs after each relocation.
//!
//! **Stick/slip (Coulomb friction).** A bounded row starts a solve sticking (`y_p = 0`) when
//! its normal row starts active, else off (`lambda_p = 0`), and follows the normal row in and
//! out of the active set. After each dense solve, first (before a unilateral row leaves or
//! enters: a sticking row's large multiplier may pull its normal row into tension), all
//! sticking rows with `|lambda_p| > mu_f max(lambda_q, 0) (1 + 1e-12)` slide with `s = sign(lambda_p)` (the
//! equation `lambda_p - s mu_f lambda_q = 0` replaces `y_p = 0`), and all sliding rows whose
//! slip reversed beyond the tolerance, `-s y_p < -tol` (`tol` the solve's tolerance, in the
//! units of `y`: m/s for a velocity row), stick again; the set is then solved again. The
//! relative `1e-12` on the bound and `tol` on the slip keep round-off from flipping a row
//! at the cone's edge. Such a change is a dense re-solve of the active rows on the cached
//! columns, never a factorization; they are counted ([`RowSolver::stick_slip_changes`]).
//! The loop stops after `10 + 4k` changes (k rows) in any case.
//!
//! **Coulomb's cone (3D).** A pair in 3D has two tangential rows `p`, `o` (each naming the
//! other, `with`), and the bound is on their vector: `|(lambda_p, lambda_o)| <= mu_f
//! lambda_q`, isotropic, not a box of two 1D bounds (a box would brake each component
//! alone and bend an oblique slide). Sticking, both rows hold `y = 0`; when the tangential
//! multiplier leaves the disk the pair slides. The law on the slide, `lambda_t = (mu_f
//! lambda_q + eta |y|) d` with `d = -y / |y|` (the force opposing the slip velocity), is
//! nonlinear in the direction; it is solved by the semismooth Newton method of the trial
//! force (Alart and Curnier 1991; Hueeber, Stadler and Wohlmuth 2008)
//! $$\tau = \lambda_t - c\\, y_t,\qquad c = 2 / (W_{pp} + W_{oo}),$$
//! one rule for every change: a pair slides while `|tau| > mu_f lambda_q`, along `d = tau /
//! |tau|`, and sticks again when `tau` falls inside the disk (sticking, `y_t = 0` and `tau` is
//! the force itself). At the iterate `(d, kappa = mu_f lambda_q / |tau|)` each row `c` of a
//! sliding pair carries the linearized law
//! $$\lambda_c - d_c\\,\mu_f \lambda_q - \kappa\\,[P(\lambda_t - c\\, y_t)]_c + \eta\\, y_c = 0,
//! \qquad P = I - d d^T,$$
//! then `d` and `kappa` anew until `d` moves by less than [`CONE_TURN`]. At the solution `P
//! tau = 0`, so `lambda_t = mu_f lambda_q d - eta y` with `y` against `d`: the law. A sliding
//! pair whose normal row pulls (a held pair in tension, released by the treatment after the
//! solve) keeps its direction: on a negative bound the trial force turns round at every
//! re-solve. At most
//! [`CONE_TURNS`] re-solves a solve; they do not count against the `10 + 4k` changes, so a
//! planar model's loop is the one above.
//!
//! The rule of the trial force replaced two separate tests (slide when the sticking force
//! leaves the disk, stick again when the slip turns along the force, the direction
//! `-y / |y|`): on a 3D rolling patch of 40 nodes those two took turns on neighbouring pairs
//! and a pair in tension turned its direction round at every re-solve, so that 366 of a
//! run's solves stopped at their budget after 190,124 dense re-solves in 160 steps; with the
//! trial force and the direction kept in tension, none stopped, in 3,630
//! (docs/src/solids3d.md, "The 3D rolling step's cost").

use crate::contact::cyclic::CyclicColumns;
use crate::linalg::team::Team;
use crate::linalg::DenseLu;
use crate::time::integrator::TimeIntegrator;

mod columns;
mod cone;

pub use crate::model::{Terms, MAX_TERMS};

/// The kind of a row (module docs).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum RowKind {
    /// `y = 0`.
    Equality,
    /// `y >= 0`, `lambda >= 0`, `y lambda = 0`.
    Unilateral,
    /// `|lambda| <= mu_f lambda_normal`, stick (`y = 0`) or slip.
    Bounded {
        /// Index of the normal row in the same set.
        normal: usize,
        /// Friction coefficient.
        mu_f: f64,
        /// Viscoplastic overstress (module docs), in multiplier units per unit of `y`; 0:
        /// Coulomb.
        eta: f64,
        /// The other tangential row of the same pair in 3D (module docs, Coulomb's cone):
        /// the bound is then on the pair's tangential vector, `|(lambda_p, lambda_with)| <=
        /// mu_f lambda_normal`, both rows with the same `normal`, `mu_f` and `eta`. `None`:
        /// a planar pair's one tangent.
        with: Option<usize>,
    },
}

/// One row: `y = y0 + mu c.x + reg lambda` with its kind.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Row {
    /// The owner (a contact pair's index), for the caller.
    pub pair: usize,
    /// `c`.
    pub terms: Terms,
    /// The kind.
    pub kind: RowKind,
    /// `y0`.
    pub y0: f64,
    /// `mu`.
    pub mu: f64,
    /// `reg` (a penalty's compliance; 0 for a hard condition).
    pub reg: f64,
}

const NO_SLOT: usize = usize::MAX;

/// A sliding 3D pair's direction has converged when it moves by less than this (the sum of
/// its components' changes; module docs, Coulomb's cone).
pub const CONE_TURN: f64 = 1e-10;

/// At most this many turns of the sliding directions in one solve (module docs).
pub const CONE_TURNS: usize = 200;

/// What one pass of the cone's rules did to a 3D pair.
#[derive(Debug, Clone, Copy, PartialEq)]
enum ConeMove {
    None,
    /// Entered, left, stuck or started sliding.
    State,
    /// Turned its sliding direction.
    Turn,
}

/// The rows of one solve, the column cache and the dense work (module docs).
#[derive(Debug, Clone)]
pub struct RowSolver {
    n: usize,
    rows: Vec<Row>,
    lambda: Vec<f64>,
    slot_of_dof: Vec<usize>,
    /// Most slots the cache may grow to.
    max_slots: usize,
    /// Grow the cache (up to `max_slots`) rather than evict a column
    /// ([`RowSolver::set_keep_columns`]).
    keep: bool,
    dof_of_slot: Vec<usize>,
    last_used: Vec<u64>,
    cols: Vec<f64>,
    clock: u64,
    solves: usize,
    stick_slip: usize,
    /// Dense solves of the active rows so far.
    dense: usize,
    /// Solves that stopped at their budget of changes or turns.
    capped: usize,
    y0: Vec<f64>,
    w: Vec<f64>,
    state: Vec<Activity>,
    /// Per sliding row of a 3D pair, the Newton term `kappa = mu_f lambda_q / |y|` of its
    /// direction (module docs, Coulomb's cone; 0 on the first slide).
    kappa: Vec<f64>,
    idx: Vec<usize>,
    m: Vec<f64>,
    r: Vec<f64>,
    /// The multipliers' terms of one solve: `(slot, weight)` of each cached column added
    /// to `x`.
    axpy: Vec<(usize, f64)>,
    /// Per slot, its place in `axpy` during one solve's gathering (`NO_SLOT`: not listed):
    /// the terms of one column, from several rows, are summed into one.
    slot_term: Vec<usize>,
    /// The threads of [`columns::add_columns`] (`Team::default()` until [`RowSolver::set_team`]).
    team: Team,
    /// The step matrix's diagonal blocks (cuts, [`crate::linalg::diagonal_blocks`]; `[0,
    /// n]` until [`RowSolver::set_blocks`]): a column is added on its dof's block alone.
    blocks: Vec<usize>,
    /// One block's terms of `axpy` during [`RowSolver::add_terms`].
    block_terms: Vec<(usize, f64)>,
    /// The slots one [`RowSolver::solve_pending`] writes, checked against their blocks.
    written: Vec<usize>,
    /// The slots whose columns one solve still needs, and their dofs.
    pending: Vec<usize>,
    pending_dofs: Vec<usize>,
    /// Their columns, solved together (`TimeIntegrator::inverse_columns`), before they go
    /// to their slots; grown to the most columns one solve has needed.
    fresh: Vec<f64>,
    /// A model with cyclic symmetry: its base sector's columns, from which every new
    /// column is turned instead of solved ([`crate::contact::cyclic`]).
    cyclic: Option<CyclicColumns>,
    /// Counts the times the cache was dropped ([`RowSolver::epoch`]).
    epoch: u64,
    /// The dense solves' workspace: faer's blocked LU on a large active set
    /// ([`DenseLu`]).
    lu: DenseLu,
    /// Per dof, its place among the distinct dofs of one solve's rows (`NO_SLOT`: none);
    /// reset after each gathering.
    local_of_dof: Vec<usize>,
    /// The distinct dofs of one solve's rows, in order of first appearance.
    local_dofs: Vec<usize>,
    /// Each row's terms on those places.
    local_terms: Vec<Terms>,
    /// The cached columns at those dofs, column after column (`gathered[j * D + i]` the
    /// column of dof `j` at dof `i`, `D` of them): the rows' matrix `W` reads each column
    /// once per distinct dof from here, not once per term pair across the `n` values.
    gathered: Vec<f64>,
}

#[derive(Debug, Clone, Copy, PartialEq)]
enum Activity {
    Off,
    On,
    /// A bounded row on its bound: `lambda_p = s mu_f lambda_normal`.
    Slip(f64),
}

impl RowSolver {
    /// Room for `max_rows` rows at once and the columns of at most `cache_dofs` dofs (at
    /// least [`MAX_TERMS`], at most `n`), for `n` dofs. The cache must be able to hold the
    /// distinct dofs of the rows of one solve (a panic says so otherwise): the caller sizes
    /// it, e.g. every contact dof; it is filled only as far as needed (module docs, Memory).
    pub fn new(n: usize, max_rows: usize, cache_dofs: usize) -> Self {
        let mr = max_rows.max(1);
        let max_slots = cache_dofs.max(MAX_TERMS).min(n.max(1));
        let slots = MAX_TERMS.min(max_slots);
        Self {
            n,
            rows: Vec::with_capacity(mr),
            lambda: vec![0.0; mr],
            slot_of_dof: vec![NO_SLOT; n],
            max_slots,
            keep: false,
            dof_of_slot: vec![NO_SLOT; slots],
            last_used: vec![0; slots],
            cols: vec![0.0; slots * n],
            clock: 0,
            solves: 0,
            stick_slip: 0,
            dense: 0,
            capped: 0,
            y0: vec![0.0; mr],
            w: vec![0.0; mr * mr],
            state: vec![Activity::Off; mr],
            kappa: vec![0.0; mr],
            idx: Vec::with_capacity(mr),
            m: vec![0.0; mr * mr],
            r: vec![0.0; mr],
            axpy: Vec::with_capacity(mr * MAX_TERMS),
            slot_term: vec![NO_SLOT; slots],
            team: Team::default(),
            blocks: vec![0, n],
            block_terms: Vec::with_capacity(mr * MAX_TERMS),
            written: Vec::with_capacity(MAX_TERMS),
            pending: Vec::with_capacity(MAX_TERMS),
            pending_dofs: Vec::with_capacity(MAX_TERMS),
            fresh: Vec::new(),
            cyclic: None,
            epoch: 0,
            lu: DenseLu::new(),
            local_of_dof: vec![NO_SLOT; n],
            local_dofs: Vec::with_capacity(mr),
            local_terms: vec![Terms::default(); mr],
            gathered: Vec::new(),
        }
    }

    /// Keeps every column solved (`true`), the cache growing up to its bound rather than
    /// evicting the least recently used column: for a contact that comes back to the same
    /// dofs, as under a moving refined zone ([`crate::simulation::Relocation`]), where the
    /// patch stays on the zone's nodes. Default `false`: the cache follows the largest patch.
    pub fn set_keep_columns(&mut self, keep: bool) {
        self.keep = keep;
    }

    /// Lets the cache grow to `slots` columns (at most `n`) where its bound was lower: the
    /// kept columns of a moving zone's band ([`RowSolver::set_keep_columns`]), which the
    /// patch sweeps between two relocations and comes back to after each.
    pub fn raise_column_bound(&mut self, slots: usize) {
        self.max_slots = self.max_slots.max(slots.min(self.n.max(1)));
    }

    /// Derives new columns from the base sector's of `cyclic` instead of solving them
    /// ([`crate::contact::cyclic`]); `None`: each column solved. The cache is dropped; the
    /// base columns `cyclic` holds are kept (they must be of the current `A`).
    ///
    /// # Panics
    /// When the symmetry is not on this solver's dofs.
    pub fn set_cyclic(&mut self, cyclic: Option<CyclicColumns>) {
        if let Some(c) = &cyclic {
            assert_eq!(
                c.symmetry().dofs(),
                self.n,
                "a cyclic symmetry on other dofs"
            );
        }
        self.cyclic = cyclic;
        self.slot_of_dof.fill(NO_SLOT);
        self.dof_of_slot.fill(NO_SLOT);
        self.last_used.fill(0);
        self.epoch += 1;
    }

    /// The cyclic symmetry's base columns, if one is set.
    pub fn cyclic(&self) -> Option<&CyclicColumns> {
        self.cyclic.as_ref()
    }

    /// Adds the columns of a solve in two halves on `team`'s threads (the same bits on any
    /// team).
    pub fn set_team(&mut self, team: &Team) {
        self.team = team.clone();
    }

    /// Drops every cached column (call after `A` changes).
    pub fn invalidate(&mut self) {
        if let Some(c) = self.cyclic.as_mut() {
            c.invalidate();
        }
        self.slot_of_dof.fill(NO_SLOT);
        self.dof_of_slot.fill(NO_SLOT);
        self.last_used.fill(0);
        self.epoch += 1;
    }

    /// How many times the cache has been dropped ([`RowSolver::invalidate`],
    /// [`RowSolver::set_cyclic`]): the columns of two equal epochs are of the same `A`.
    pub fn epoch(&self) -> u64 {
        self.epoch
    }

    /// Removes all rows.
    pub fn clear(&mut self) {
        self.rows.clear();
    }

    /// Adds a row; returns its index.
    ///
    /// # Panics
    /// Beyond `max_rows` of [`RowSolver::new`].
    pub fn push(&mut self, row: Row) -> usize {
        assert!(
            self.rows.len() < self.lambda.len(),
            "too many simultaneous constraint rows"
        );
        self.rows.push(row);
        self.rows.len() - 1
    }

    /// The rows.
    pub fn rows(&self) -> &[Row] {
        &self.rows
    }

    /// The multipliers of the last solve, one per row.
    pub fn lambda(&self) -> &[f64] {
        &self.lambda[..self.rows.len()]
    }

    /// Columns the cache holds room for now (it grows as the rows need, module docs).
    pub fn cached_columns(&self) -> usize {
        self.dof_of_slot.len()
    }

    /// Column solves done so far (`A^{-1} e_d` for a newly constrained dof).
    pub fn column_solves(&self) -> usize {
        self.solves
    }

    /// Dense solves of the active rows so far (one per active set, stick/slip change and
    /// turn of a sliding cone's direction).
    pub fn dense_solves(&self) -> usize {
        self.dense
    }

    /// Solves that stopped at their budget of changes (`10 + 4k`) or of a cone's turns
    /// ([`CONE_TURNS`]) before their active set held.
    pub fn capped_solves(&self) -> usize {
        self.capped
    }

    /// Columns turned from the base sector's instead of solved ([`Self::set_cyclic`]).
    pub fn columns_turned(&self) -> usize {
        self.cyclic.as_ref().map_or(0, CyclicColumns::derived)
    }

    /// Stick/slip changes of bounded rows so far (each one a dense re-solve of the active
    /// rows, never a factorization).
    pub fn stick_slip_changes(&self) -> usize {
        self.stick_slip
    }

    /// True when row `p` of the last solve is a bounded row on its bound (sliding).
    pub fn is_sliding(&self, p: usize) -> bool {
        p < self.rows.len() && matches!(self.state[p], Activity::Slip(_))
    }

    /// Solves the rows: `x` holds `x_free` on entry and `x_free + sum z_q lambda_q` on exit;
    /// `tol` is the violation tolerance of unilateral rows (in the units of `y`). Returns the
    /// number of active-set changes.
    pub fn solve(&mut self, integ: &mut dyn TimeIntegrator, x: &mut [f64], tol: f64) -> usize {
        let changes = self.solve_multipliers(integ, x, tol);
        self.add_solution(x);
        changes
    }

    /// [`RowSolver::solve`]'s multipliers alone ([`RowSolver::lambda`]), from `x_free`, without
    /// forming `x` (`n` values a column the rows touch): for a solve whose multipliers alone
    /// are read (the soft way's stopping impulses). The same multipliers, bit for bit.
    pub fn solve_multipliers(
        &mut self,
        integ: &mut dyn TimeIntegrator,
        xfree: &[f64],
        tol: f64,
    ) -> usize {
        let k = self.rows.len();
        if k == 0 {
            return 0;
        }
        self.clock += 1;
        self.pending.clear();
        for p in 0..k {
            let t = self.rows[p].terms;
            for (d, _) in t.iter() {
                self.reserve(d);
            }
        }
        self.solve_pending(integ);
        self.gather(k);
        let nd = self.local_dofs.len();
        for p in 0..k {
            let rp = self.rows[p];
            let lp = self.local_terms[p];
            self.y0[p] = rp.y0 + rp.mu * rp.terms.dot(xfree);
            for q in 0..k {
                // The same products in the same order as over the columns themselves.
                let mut v = 0.0;
                for (jq, cq) in self.local_terms[q].iter() {
                    let col = &self.gathered[jq * nd..(jq + 1) * nd];
                    for (ip, cp) in lp.iter() {
                        v += cp * col[ip] * cq;
                    }
                }
                self.w[p * k + q] = rp.mu * v + if p == q { rp.reg } else { 0.0 };
            }
        }
        self.active_set(k, tol)
    }

    /// The rows' distinct dofs, their terms on them and the cached columns at them
    /// (`local_dofs`, `local_terms`, `gathered`) for the first `k` rows.
    fn gather(&mut self, k: usize) {
        self.local_dofs.clear();
        for p in 0..k {
            let mut local = Terms::default();
            for (d, c) in self.rows[p].terms.iter() {
                let j = match self.local_of_dof[d] {
                    NO_SLOT => {
                        self.local_of_dof[d] = self.local_dofs.len();
                        self.local_dofs.push(d);
                        self.local_dofs.len() - 1
                    }
                    j => j,
                };
                local.push(j, c);
            }
            self.local_terms[p] = local;
        }
        let (n, nd) = (self.n, self.local_dofs.len());
        if self.gathered.len() < nd * nd {
            self.gathered.resize(nd * nd, 0.0);
        }
        for (j, &dj) in self.local_dofs.iter().enumerate() {
            let s = self.slot_of_dof[dj];
            let col = &self.cols[s * n..(s + 1) * n];
            let out = &mut self.gathered[j * nd..(j + 1) * nd];
            for (g, &di) in out.iter_mut().zip(&self.local_dofs) {
                *g = col[di];
            }
        }
        for &d in &self.local_dofs {
            self.local_of_dof[d] = NO_SLOT;
        }
    }

    /// `x += sum_q z_q lambda_q` with the last solve's multipliers: after
    /// [`RowSolver::solve_multipliers`] from `x_free`, what [`RowSolver::solve`] gives, bit for
    /// bit.
    pub fn add_solution(&mut self, x: &mut [f64]) {
        if self.rows.is_empty() {
            return;
        }
        let k = self.rows.len();
        // One term per column: a node's dof is in its normal and tangential rows, so the
        // rows' terms name each column up to three times.
        self.axpy.clear();
        for q in 0..k {
            let l = self.lambda[q];
            if l == 0.0 {
                continue;
            }
            for (d, c) in self.rows[q].terms.iter() {
                let wgt = l * c;
                if wgt != 0.0 {
                    let s = self.slot_of_dof[d];
                    match self.slot_term[s] {
                        NO_SLOT => {
                            self.slot_term[s] = self.axpy.len();
                            self.axpy.push((s, wgt));
                        }
                        t => self.axpy[t].1 += wgt,
                    }
                }
            }
        }
        for &(s, _) in &self.axpy {
            self.slot_term[s] = NO_SLOT;
        }
        self.add_terms(x);
    }

    /// `y_p` of the current multipliers.
    fn y(&self, p: usize, k: usize) -> f64 {
        let mut y = self.y0[p];
        for q in 0..k {
            y += self.w[p * k + q] * self.lambda[q];
        }
        y
    }

    fn active_set(&mut self, k: usize, tol: f64) -> usize {
        for p in 0..k {
            self.state[p] = match self.rows[p].kind {
                RowKind::Equality | RowKind::Bounded { .. } => Activity::On,
                RowKind::Unilateral if self.y0[p] < -tol => Activity::On,
                RowKind::Unilateral => Activity::Off,
            };
        }
        // A friction row starts sticking when its normal row starts active, else off.
        for p in 0..k {
            if let RowKind::Bounded { normal, .. } = self.rows[p].kind {
                if self.state[normal] == Activity::Off {
                    self.state[p] = Activity::Off;
                }
            }
        }
        let mut changes = 0;
        let mut turns = 0;
        let mut budget = 10 + 4 * k;
        while budget > 0 {
            self.solve_set(k);
            // Friction first (module docs): a friction row follows its normal row in and out
            // of the active set (off while the pair carries no normal reaction, sticking when
            // it enters); a sticking row beyond its bound slides; a sliding row whose `y` no
            // longer has the sign its force opposes sticks.
            let mut moved = false;
            let mut turned = false;
            for p in 0..k {
                if let RowKind::Bounded {
                    normal,
                    mu_f,
                    with: Some(o),
                    ..
                } = self.rows[p].kind
                {
                    if o > p {
                        match self.cone(p, o, (normal, mu_f), k, turns < CONE_TURNS) {
                            ConeMove::State => moved = true,
                            ConeMove::Turn => turned = true,
                            ConeMove::None => {}
                        }
                    }
                    continue;
                }
                if let RowKind::Bounded { normal, mu_f, .. } = self.rows[p].kind {
                    let bound = mu_f * self.lambda[normal].max(0.0);
                    let normal_on = self.state[normal] != Activity::Off;
                    match self.state[p] {
                        Activity::Off if normal_on => {
                            self.state[p] = Activity::On;
                            moved = true;
                        }
                        Activity::On | Activity::Slip(_) if !normal_on => {
                            self.state[p] = Activity::Off;
                            moved = true;
                        }
                        Activity::On if self.lambda[p].abs() > bound * (1.0 + 1e-12) => {
                            self.state[p] = Activity::Slip(self.lambda[p].signum());
                            self.stick_slip += 1;
                            moved = true;
                        }
                        Activity::Slip(s) if -s * self.y(p, k) < -tol => {
                            self.state[p] = Activity::On;
                            self.stick_slip += 1;
                            moved = true;
                        }
                        _ => {}
                    }
                }
            }
            if moved {
                changes += 1;
                budget -= 1;
                continue;
            }
            if turned {
                // A turn of a sliding direction: re-solved outside the budget (module docs).
                turns += 1;
                changes += 1;
                continue;
            }
            // Leave: the most negative unilateral multiplier.
            let mut worst: Option<(usize, f64)> = None;
            for &p in &self.idx {
                let l = self.lambda[p];
                if self.rows[p].kind == RowKind::Unilateral
                    && l < 0.0
                    && worst.is_none_or(|(_, v)| l < v)
                {
                    worst = Some((p, l));
                }
            }
            if let Some((p, _)) = worst {
                self.state[p] = Activity::Off;
                changes += 1;
                budget -= 1;
                continue;
            }
            // Enter: the most violated inactive unilateral row.
            let mut viol: Option<(usize, f64)> = None;
            for p in 0..k {
                if self.rows[p].kind != RowKind::Unilateral || self.state[p] != Activity::Off {
                    continue;
                }
                let y = self.y(p, k);
                if y < -tol && viol.is_none_or(|(_, v)| y < v) {
                    viol = Some((p, y));
                }
            }
            match viol {
                Some((p, _)) => {
                    self.state[p] = Activity::On;
                    changes += 1;
                    budget -= 1;
                }
                None => break,
            }
        }
        if budget == 0 || turns >= CONE_TURNS {
            self.capped += 1;
        }
        changes
    }

    /// Solves the equations of the active rows (`y_p = 0`, or the slip relation), the others
    /// getting `lambda = 0`.
    fn solve_set(&mut self, k: usize) {
        self.idx.clear();
        for p in 0..k {
            if self.state[p] != Activity::Off {
                self.idx.push(p);
            }
        }
        let m = self.idx.len();
        for a in 0..m {
            let p = self.idx[a];
            match (self.state[p], self.rows[p].kind) {
                (
                    Activity::Slip(dp),
                    RowKind::Bounded {
                        normal,
                        mu_f,
                        eta,
                        with: Some(o),
                    },
                ) => {
                    // The linearized law of a sliding 3D pair (module docs, Coulomb's cone):
                    // lambda_p - d_p mu_f lambda_q + c_pp y_p + c_po y_o = 0.
                    let d_o = match self.state[o] {
                        Activity::Slip(d) => d,
                        _ => 0.0,
                    };
                    // lambda_p - d_p mu_f lambda_q - kappa [P (lambda_t - c y)]_p + eta y_p = 0,
                    // P = I - d d^T (module docs, Coulomb's cone).
                    let kappa = self.kappa[p];
                    let c = self.trial_weight(p, o, k);
                    let (pp, po) = (1.0 - dp * dp, -dp * d_o);
                    let (c_pp, c_po) = (kappa * c * pp + eta, kappa * c * po);
                    self.r[a] = -(c_pp * self.y0[p] + c_po * self.y0[o]);
                    for b in 0..m {
                        let q = self.idx[b];
                        let mut v = c_pp * self.w[p * k + q] + c_po * self.w[o * k + q];
                        if q == p {
                            v += 1.0 - kappa * pp;
                        }
                        if q == o {
                            v -= kappa * po;
                        }
                        if q == normal {
                            v -= dp * mu_f;
                        }
                        self.m[a * m + b] = v;
                    }
                }
                (
                    Activity::Slip(s),
                    RowKind::Bounded {
                        normal, mu_f, eta, ..
                    },
                ) => {
                    // lambda_p - s mu_f lambda_q + eta (y0_p + sum_b W_pb lambda_b) = 0.
                    self.r[a] = -eta * self.y0[p];
                    for b in 0..m {
                        let q = self.idx[b];
                        let mut v = eta * self.w[p * k + q];
                        if q == p {
                            v += 1.0;
                        }
                        if q == normal {
                            v -= s * mu_f;
                        }
                        self.m[a * m + b] = v;
                    }
                }
                _ => {
                    self.r[a] = -self.y0[p];
                    for b in 0..m {
                        self.m[a * m + b] = self.w[p * k + self.idx[b]];
                    }
                }
            }
        }
        self.lu
            .solve_in_place(&mut self.m[..m * m], &mut self.r[..m], m);
        self.dense += 1;
        self.lambda[..k].fill(0.0);
        for a in 0..m {
            self.lambda[self.idx[a]] = self.r[a];
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::linalg::LinalgError;

    use crate::model::{LoadFn, State};
    use crate::time::integrator::{FactorCounts, Maps, MultiplierUnit, Step};

    /// `A = diag(d)`: the rows' solution is checkable by hand.
    fn diagonal(d: Vec<f64>) -> Inverse {
        let n = d.len();
        let mut inv = vec![0.0; n * n];
        for (i, di) in d.iter().enumerate() {
            inv[i * n + i] = 1.0 / di;
        }
        Inverse(inv, n)
    }

    /// `A^{-1}` given whole (`inv[i * n + j]`, symmetric): columns of any coupling.
    struct Inverse(Vec<f64>, usize);

    impl TimeIntegrator for Inverse {
        fn name(&self) -> String {
            "inverse".into()
        }
        fn h(&self) -> f64 {
            1.0
        }
        fn step_at(&self, t0: f64) -> Step {
            Step {
                t0,
                h: 1.0,
                maps: Maps {
                    mu_u: 1.0,
                    mu_v: 1.0,
                    force: 1.0,
                },
                weight: 1.0,
                unit: MultiplierUnit::Impulse,
                explicit: false,
            }
        }
        fn predict(
            &mut self,
            t0: f64,
            _s0: &State,
            _load: &LoadFn,
            _extra: &[f64],
            _f: &mut [f64],
            _pred: &mut State,
            _x: &mut [f64],
        ) -> Step {
            self.step_at(t0)
        }
        fn inverse_column(&mut self, dof: usize, col: &mut [f64]) -> bool {
            let n = self.1;
            col.copy_from_slice(&self.0[dof * n..(dof + 1) * n]);
            true
        }
        fn finish(&self, _: &Step, _s0: &State, _pred: &State, _x: &[f64], _s1: &mut State) {}
        fn stiffness_point(&self, _s0: &State, _pred: &State, _p: &mut [f64]) -> f64 {
            0.0
        }
        fn set_step(&mut self, _h: f64) -> Result<(), LinalgError> {
            Ok(())
        }
        fn counts(&self) -> FactorCounts {
            FactorCounts::default()
        }
    }

    /// Two bodies in turn (dofs 0..5 and 5..12, `A^{-1}` block diagonal) and rows joining
    /// them, as a wheel's node and its rail's facet: the columns added on their blocks give
    /// the same multipliers and `x` as over the whole, bit for bit. Blocks the matrix does
    /// not have (an entry joining the two) are dropped at the first column that shows it,
    /// and the answer is again the whole's.
    #[test]
    fn columns_added_on_their_bodies_blocks_give_the_same_x() {
        let n = 12;
        let entry = |i: usize, j: usize| {
            let same = (i < 5) == (j < 5);
            if i == j {
                2.0 + 0.1 * i as f64
            } else if same {
                0.3 / (1.0 + (i + j) as f64)
            } else {
                0.0
            }
        };
        let solve = |inv: &[f64], blocks: Option<Vec<usize>>| {
            let mut integ = Inverse(inv.to_vec(), n);
            let mut rows = RowSolver::new(n, 4, n);
            let blocked = blocks.is_some();
            if let Some(b) = blocks {
                rows.set_blocks(b);
            }
            for (k, (a, b, y0)) in [(1, 7, -1.0), (3, 9, -0.5), (4, 5, -0.25)]
                .into_iter()
                .enumerate()
            {
                let mut terms = Terms::default();
                terms.push(a, 1.0);
                terms.push(b, -0.7);
                rows.push(Row {
                    pair: k,
                    terms,
                    kind: RowKind::Equality,
                    y0,
                    mu: 1.0,
                    reg: 0.0,
                });
            }
            let mut x: Vec<f64> = (0..n).map(|i| (0.9 * i as f64).sin()).collect();
            rows.solve(&mut integ, &mut x, 1e-12);
            (
                x,
                rows.lambda()[..3].to_vec(),
                blocked && rows.blocks.len() > 2,
            )
        };
        let inv: Vec<f64> = (0..n * n).map(|k| entry(k / n, k % n)).collect();
        let (whole, lw, _) = solve(&inv, None);
        let (parts, lp, kept) = solve(
            &inv,
            Some(crate::linalg::diagonal_blocks(&{
                let mut cp = vec![0];
                let mut ri = Vec::new();
                for j in 0..n {
                    ri.extend((0..n).filter(|&i| entry(i, j) != 0.0));
                    cp.push(ri.len());
                }
                crate::linalg::Pattern::new_checked(n, n, cp, None, ri)
            })),
        );
        assert!(kept, "the blocks stand");
        let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(&parts), bits(&whole));
        assert_eq!(bits(&lp), bits(&lw));
        let y = |x: &[f64], a: usize, b: usize| x[a] - 0.7 * x[b];
        // Each equality row holds: `y0 + c . x = 0`.
        assert!((y(&whole, 1, 7) - 1.0).abs() < 1e-12 && (y(&whole, 4, 5) - 0.25).abs() < 1e-12);
        // Coupled: an entry joins dof 3 to dof 9 (both in the rows).
        let mut coupled = inv.clone();
        coupled[3 * n + 9] = 0.05;
        coupled[9 * n + 3] = 0.05;
        let (whole, lw, _) = solve(&coupled, None);
        let (parts, lp, kept) = solve(&coupled, Some(vec![0, 5, n]));
        assert!(!kept, "a column outside its block drops the blocks");
        assert_eq!(bits(&parts), bits(&whole));
        assert_eq!(bits(&lp), bits(&lw));
    }

    fn row(dof: usize, kind: RowKind) -> Row {
        let mut terms = Terms::default();
        terms.push(dof, 1.0);
        Row {
            pair: dof,
            terms,
            kind,
            y0: 0.0,
            mu: 1.0,
            reg: 0.0,
        }
    }

    /// A node approaching a plane (normal velocity -1, unit mass) with a tangential velocity
    /// `vt`, friction coefficient 0.5: the normal impulse stops it (1 N s); the tangential
    /// impulse stops the sliding when it can (`|vt| <= 0.5`: stick) and is `-0.5 sign(vt)`
    /// otherwise (slip, the velocity keeping its sign).
    #[test]
    fn coulomb_rows_stick_inside_the_cone_and_slide_on_it() {
        for (vt, lt, xt) in [(2.0, -0.5, 1.5), (0.3, -0.3, 0.0), (-4.0, 0.5, -3.5)] {
            let (l, x) = node_on_plane(vt, 0.0);
            assert!((l[0] - 1.0).abs() < 1e-14, "{vt}: {l:?}");
            assert!((l[1] - lt).abs() < 1e-14, "{vt}: {l:?}");
            assert!(
                x[0].abs() < 1e-14 && (x[1] - xt).abs() < 1e-14,
                "{vt}: {x:?}"
            );
        }
    }

    /// One solve whose rows need more columns than the cache's bound (40 nodes, each of unit
    /// mass approaching its plane at -1, against a bound of `MAX_TERMS` = 15 columns): the
    /// cache grows past its bound, as the columns are all needed at once, and each node is
    /// stopped by its unit impulse.
    #[test]
    fn one_solve_needing_more_columns_than_the_cache_holds_grows_it() {
        let n = 40;
        let mut integ = diagonal(vec![1.0; n]);
        let mut rows = RowSolver::new(n, n, 1);
        for d in 0..n {
            rows.push(row(d, RowKind::Unilateral));
        }
        let mut x = vec![-1.0; n];
        rows.solve(&mut integ, &mut x, 1e-12);
        assert!(rows.lambda().iter().all(|l| (l - 1.0).abs() < 1e-14));
        assert!(x.iter().all(|v| v.abs() < 1e-14), "{x:?}");
    }

    /// The node of the Coulomb and viscoplastic tests: unit mass, normal velocity -1,
    /// tangential `vt`, friction 0.5 with the viscosity `eta`; its multipliers and velocity.
    fn node_on_plane(vt: f64, eta: f64) -> (Vec<f64>, Vec<f64>) {
        let mut integ = diagonal(vec![1.0, 1.0]);
        let mut rows = RowSolver::new(2, 2, 2);
        let n = rows.push(row(0, RowKind::Unilateral));
        rows.push(row(
            1,
            RowKind::Bounded {
                normal: n,
                mu_f: 0.5,
                eta,
                with: None,
            },
        ));
        let mut x = vec![-1.0, vt];
        rows.solve(&mut integ, &mut x, 1e-12);
        (rows.lambda().to_vec(), x)
    }

    /// A node of masses `m = (m_n, m_1, m_2)` approaching a plane at normal velocity -1 with
    /// the tangential velocity `vt`, under Coulomb's cone of coefficient 0.5 with the
    /// viscosity `eta`: the multipliers and the velocity.
    fn node_on_plane_3d(m: [f64; 3], vt: [f64; 2], eta: f64) -> (Vec<f64>, Vec<f64>) {
        let mut integ = diagonal(m.to_vec());
        let mut rows = RowSolver::new(3, 3, 3);
        let n = rows.push(row(0, RowKind::Unilateral));
        for (dof, other) in [(1, 2), (2, 1)] {
            rows.push(row(
                dof,
                RowKind::Bounded {
                    normal: n,
                    mu_f: 0.5,
                    eta,
                    with: Some(other),
                },
            ));
        }
        let mut x = vec![-1.0, vt[0], vt[1]];
        rows.solve(&mut integ, &mut x, 1e-12);
        (rows.lambda().to_vec(), x)
    }

    /// Coulomb's cone on a node of unit masses: inside the disk (`|vt| = 0.36 < 0.5`) the
    /// node sticks, its tangential impulse `-vt`; outside (`|vt| = sqrt 5`) it slides with
    /// the impulse `-0.5 vt / |vt|`, the velocity keeping its direction (a box of two 1D
    /// bounds would brake each component by 0.5 and turn it: `(1.5, 0.5)`).
    #[test]
    fn a_3d_pair_sticks_inside_coulombs_disk_and_slides_against_its_velocity() {
        let (l, x) = node_on_plane_3d([1.0; 3], [0.3, 0.2], 0.0);
        assert!((l[0] - 1.0).abs() < 1e-14, "{l:?}");
        assert!(
            (l[1] + 0.3).abs() < 1e-14 && (l[2] + 0.2).abs() < 1e-14,
            "{l:?}"
        );
        assert!(x[1].abs() < 1e-14 && x[2].abs() < 1e-14, "{x:?}");
        let (l, x) = node_on_plane_3d([1.0; 3], [2.0, 1.0], 0.0);
        let r5 = 5.0_f64.sqrt();
        assert!((l[1] + 1.0 / r5).abs() < 1e-14 && (l[2] + 0.5 / r5).abs() < 1e-14);
        assert!((x[1] - (2.0 - 1.0 / r5)).abs() < 1e-14, "{x:?}");
        assert!((x[2] - (1.0 - 0.5 / r5)).abs() < 1e-14, "{x:?}");
    }

    /// Unequal tangential masses (1 and 4) make the sliding direction a fixed point that
    /// the first guess misses: at the solution the force lies on the disk's edge, `|lambda_t|
    /// = mu lambda_n (+ eta |y|)`, opposes the slip velocity exactly (their cross product
    /// zero, their dot product negative), and the velocity obeys the momentum balance
    /// `y = vt + lambda_t / m`, for Coulomb and with a viscosity.
    #[test]
    fn a_3d_pairs_sliding_direction_is_the_fixed_point_of_the_law() {
        for eta in [0.0, 0.25] {
            for vt in [[2.0, 1.0], [-0.4, 3.0], [0.45, -0.35]] {
                let m = [1.0, 1.0, 4.0];
                let (l, x) = node_on_plane_3d(m, vt, eta);
                let (lt, y) = ([l[1], l[2]], [x[1], x[2]]);
                let speed = y[0].hypot(y[1]);
                assert!(speed > 1e-3, "{vt:?}: slides");
                let f = lt[0].hypot(lt[1]);
                assert!(
                    (f - (0.5 * l[0] + eta * speed)).abs() < 1e-9,
                    "{vt:?}: {l:?}"
                );
                let cross = (lt[0] * y[1] - lt[1] * y[0]) / (f * speed);
                assert!(cross.abs() < 1e-9, "{vt:?}: force along the slip");
                assert!(lt[0] * y[0] + lt[1] * y[1] < 0.0, "{vt:?}: opposes it");
                for c in 0..2 {
                    assert!((y[c] - (vt[c] + lt[c] / m[c + 1])).abs() < 1e-12);
                }
            }
        }
    }

    /// The viscoplastic slip: the node of the Coulomb test sliding at `vt = 2` with
    /// `eta = 0.25` keeps the slip `y` with `|lambda_t| = mu_f lambda_n + eta |y|`: by hand,
    /// `lambda_t = -0.5 - 0.25 (2 + lambda_t)`, so `lambda_t = -0.8`, `y = 1.2`; inside the
    /// bound (`vt = 0.3`) it sticks as without viscosity.
    #[test]
    fn viscoplastic_rows_slide_with_the_overstress() {
        for (vt, lt, xt) in [(2.0, -0.8, 1.2), (0.3, -0.3, 0.0), (-4.0, 1.2, -2.8)] {
            let (l, x) = node_on_plane(vt, 0.25);
            assert!((l[1] - lt).abs() < 1e-14, "{vt}: {l:?}");
            assert!((x[1] - xt).abs() < 1e-14, "{vt}: {x:?}");
            if vt.abs() > 0.5 {
                assert!((l[1].abs() - (0.5 * l[0] + 0.25 * x[1].abs())).abs() < 1e-14);
            }
        }
    }

    /// A unilateral row that is not violated carries nothing; a separating node is let go;
    /// an equality row is imposed whatever its sign; a penalty row (`reg > 0`) gives
    /// `lambda = -y0 / (W + reg)`.
    #[test]
    fn unilateral_equality_and_compliant_rows() {
        let mut integ = diagonal(vec![2.0, 4.0]);
        let mut rows = RowSolver::new(2, 2, 2);
        rows.push(row(0, RowKind::Unilateral));
        rows.push(row(1, RowKind::Equality));
        let mut x = vec![0.5, 1.0];
        rows.solve(&mut integ, &mut x, 1e-12);
        assert_eq!(rows.lambda()[0], 0.0);
        assert!((rows.lambda()[1] + 4.0).abs() < 1e-14 && x[1].abs() < 1e-14);
        rows.clear();
        let mut r = row(0, RowKind::Unilateral);
        r.reg = 0.5;
        rows.push(r);
        let mut x = vec![-1.0, 0.0];
        rows.solve(&mut integ, &mut x, 1e-12);
        // y = x0 + lambda/2 + 0.5 lambda = -1 + lambda = 0.
        assert!(
            (rows.lambda()[0] - 1.0).abs() < 1e-14,
            "{:?}",
            rows.lambda()
        );
    }
}
