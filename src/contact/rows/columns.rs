//! The multipliers' columns added to the solution, `x += sum_t w_t A^{-1} e_{d_t}`: the
//! cached columns of [`super::RowSolver`] four per pass over `x`, on two threads from
//! `SPLIT_ADD_MIN` unknowns.

use crate::linalg::team::Team;
use crate::linalg::with_avx2;
use crate::time::integrator::TimeIntegrator;

use super::NO_SLOT;

/// The column cache: the columns a solve needs, solved or turned into their slots, and a
/// change of load added from them.
impl super::RowSolver {
    /// `x += g sum_d (f_d - f0_d) A^{-1} e_d` from the cached columns, over the dofs where
    /// `f` and `f0` differ: the change of `g A^{-1} f` when a load `f0` becomes `f`, without a
    /// solve. Returns false, `x` untouched, when one of those dofs has no cached column (or
    /// more dofs differ than the solver keeps terms for).
    pub fn add_cached(&mut self, g: f64, f: &[f64], f0: &[f64], x: &mut [f64]) -> bool {
        self.axpy.clear();
        for (d, (&fd, &f0d)) in f.iter().zip(f0).enumerate() {
            if fd.to_bits() == f0d.to_bits() {
                continue;
            }
            let s = self.slot_of_dof[d];
            if s == NO_SLOT || self.axpy.len() == self.axpy.capacity() {
                self.axpy.clear();
                return false;
            }
            self.axpy.push((s, g * (fd - f0d)));
        }
        self.add_terms(x);
        true
    }

    /// Marks `dof`'s column as used by this solve: kept if cached, else given the least
    /// recently used slot (the cache grown when every slot holds a column of this solve)
    /// and queued for [`Self::solve_pending`].
    pub(super) fn reserve(&mut self, dof: usize) {
        let s = self.slot_of_dof[dof];
        if s != NO_SLOT {
            self.last_used[s] = self.clock;
            return;
        }
        // Least recently used slot (empty slots have last_used 0).
        let mut s = 0;
        for i in 0..self.dof_of_slot.len() {
            if self.last_used[i] < self.last_used[s] {
                s = i;
            }
        }
        // Every slot holds a column of this solve: grow (module docs, Memory), past the
        // cache's bound if one solve's rows need more columns than it (they are all needed
        // at once).
        let slots = self.dof_of_slot.len();
        let keep = self.keep && self.dof_of_slot[s] != NO_SLOT && slots < self.max_slots;
        if (self.last_used[s] == self.clock || keep) && slots < self.n {
            let grown = if slots < self.max_slots {
                (2 * slots).min(self.max_slots)
            } else {
                (2 * slots).min(self.n)
            };
            self.dof_of_slot.resize(grown, NO_SLOT);
            self.last_used.resize(grown, 0);
            self.slot_term.resize(grown, NO_SLOT);
            self.cols.resize(grown * self.n, 0.0);
            s = slots;
        }
        assert!(
            self.last_used[s] < self.clock || self.dof_of_slot[s] == NO_SLOT,
            "constraint column cache smaller than the active rows"
        );
        if self.dof_of_slot[s] != NO_SLOT {
            self.slot_of_dof[self.dof_of_slot[s]] = NO_SLOT;
        }
        self.dof_of_slot[s] = dof;
        self.slot_of_dof[dof] = s;
        self.last_used[s] = self.clock;
        self.pending.push(s);
    }

    /// The step matrix's diagonal blocks, as cuts `0 < c_1 < ... < n`
    /// ([`crate::linalg::diagonal_blocks`]): the bodies of a model numbered one after the
    /// other, whose columns `A^{-1} e_d` are zero outside `d`'s body. The columns are then
    /// added to `x` on their blocks alone (a wheel's on the wheel's dofs, its rail's on the
    /// rail's): the same `x`, at half the memory traffic on two bodies of one size. Each
    /// column is checked zero outside its block as it enters the cache; the first that is
    /// not (a coupling the pattern did not show) drops the blocks for good.
    pub fn set_blocks(&mut self, cuts: Vec<usize>) {
        assert!(
            cuts.first() == Some(&0)
                && cuts.last() == Some(&self.n)
                && cuts.windows(2).all(|w| w[0] < w[1] || self.n == 0),
            "blocks are increasing cuts from 0 to n"
        );
        self.blocks = cuts;
    }

    /// The block of `dof`: `blocks[b]..blocks[b + 1]`.
    fn block_of(&self, dof: usize) -> usize {
        self.blocks.partition_point(|&c| c <= dof) - 1
    }

    /// Drops the blocks if the column in slot `s` is not zero outside its dof's block.
    pub(super) fn check_block(&mut self, s: usize) {
        if self.blocks.len() <= 2 {
            return;
        }
        let n = self.n;
        let b = self.block_of(self.dof_of_slot[s]);
        let (lo, hi) = (self.blocks[b], self.blocks[b + 1]);
        let col = &self.cols[s * n..(s + 1) * n];
        if col[..lo].iter().chain(&col[hi..]).any(|&v| v != 0.0) {
            self.blocks = vec![0, n];
        }
    }

    /// `x += sum w_t cols[s_t]` for the terms `(s_t, w_t)` of `axpy`: each column on its
    /// dof's block ([`RowSolver::set_blocks`]), the terms of a block in their order (each
    /// `x_i` receives them as one pass over every column would give it: the other blocks'
    /// columns are zero there).
    pub(super) fn add_terms(&mut self, x: &mut [f64]) {
        if self.blocks.len() <= 2 {
            add_columns(&self.team, &self.cols, &self.axpy, x);
            return;
        }
        let n = self.n;
        for b in 0..self.blocks.len() - 1 {
            let (lo, hi) = (self.blocks[b], self.blocks[b + 1]);
            self.block_terms.clear();
            for &(s, w) in &self.axpy {
                let d = self.dof_of_slot[s];
                if (lo..hi).contains(&d) {
                    self.block_terms.push((s, w));
                }
            }
            if !self.block_terms.is_empty() {
                add_columns_on(
                    &self.team,
                    &self.cols,
                    n,
                    &self.block_terms,
                    lo,
                    &mut x[lo..hi],
                );
            }
        }
    }

    /// Solves the queued columns `A^{-1} e_d` together (one block of right-hand sides: a
    /// factor in dense supernodes is read once for eight of them) into their slots.
    pub(super) fn solve_pending(&mut self, integ: &mut dyn TimeIntegrator) {
        if self.blocks.len() <= 2 {
            self.fill_pending(integ);
            return;
        }
        let mut written = std::mem::take(&mut self.written);
        written.clear();
        written.extend_from_slice(&self.pending);
        self.fill_pending(integ);
        for &s in &written {
            self.check_block(s);
        }
        self.written = written;
    }

    /// [`Self::solve_pending`]'s columns, solved or derived into their slots.
    fn fill_pending(&mut self, integ: &mut dyn TimeIntegrator) {
        let m = self.pending.len();
        if m == 0 {
            return;
        }
        let n = self.n;
        if let Some(cyc) = self.cyclic.as_mut() {
            // The base columns that are missing, solved together; then each queued column
            // the symmetry covers turned (or shifted) from them. The others (the dofs
            // outside a partial symmetry) are solved below.
            for &s in &self.pending {
                let d = self.dof_of_slot[s];
                if cyc.symmetry().covers(d) {
                    cyc.need(d);
                }
            }
            cyc.pending_dofs(&mut self.pending_dofs);
            let b = self.pending_dofs.len();
            if b > 0 {
                if self.fresh.len() < b * n {
                    self.fresh.resize(b * n, 0.0);
                }
                let fresh = &mut self.fresh[..b * n];
                self.solves += integ.inverse_columns(&self.pending_dofs, fresh);
                cyc.store(fresh);
            }
            let dof_of_slot = &self.dof_of_slot;
            let cols = &mut self.cols;
            self.pending.retain(|&s| {
                let d = dof_of_slot[s];
                if !cyc.symmetry().covers(d) {
                    return true;
                }
                cyc.derive(d, &mut cols[s * n..(s + 1) * n]);
                false
            });
            if self.pending.is_empty() {
                return;
            }
        }
        let m = self.pending.len();
        self.pending_dofs.clear();
        self.pending_dofs
            .extend(self.pending.iter().map(|&s| self.dof_of_slot[s]));
        if self.fresh.len() < m * n {
            self.fresh.resize(m * n, 0.0);
        }
        let fresh = &mut self.fresh[..m * n];
        self.solves += integ.inverse_columns(&self.pending_dofs, fresh);
        for (&s, col) in self.pending.iter().zip(fresh.chunks_exact(n)) {
            self.cols[s * n..(s + 1) * n].copy_from_slice(col);
        }
    }
}

/// `x += sum_t w_t cols[s_t]` for the terms `(s_t, w_t)` (each column `x.len()` long in
/// `cols`), four columns per pass over `x`, on AVX2's instructions where the processor has
/// them (`linalg::with_avx2`). Each `x_i` receives the terms one after the other in their
/// order, as one pass per column would give it, bit for bit. From `SPLIT_ADD_MIN` unknowns
/// on, the two halves of `x` side by side on `team`'s threads.
pub(super) fn add_columns(team: &Team, cols: &[f64], terms: &[(usize, f64)], x: &mut [f64]) {
    add_columns_on(team, cols, x.len(), terms, 0, x);
}

/// [`add_columns`] on the rows `i0..i0 + x.len()` of columns `n` long: a block of the
/// unknowns ([`super::RowSolver::set_blocks`]).
pub(super) fn add_columns_on(
    team: &Team,
    cols: &[f64],
    n: usize,
    terms: &[(usize, f64)],
    i0: usize,
    x: &mut [f64],
) {
    let len = x.len();
    if len < SPLIT_ADD_MIN || terms.is_empty() {
        add_columns_range(cols, n, terms, i0, x);
        return;
    }
    let (lo, hi) = x.split_at_mut(len / 2);
    team.join(
        || add_columns_range(cols, n, terms, i0, lo),
        || add_columns_range(cols, n, terms, i0 + len / 2, hi),
    );
}

/// The order from which [`add_columns`] runs on two threads: that of the split factors.
/// With the energies' two quadratic forms side by side too (`StepView::energies`),
/// `wheel.toml`'s run (3,432 dofs) went from 124.8 and 122.4 to 108.0 and 110.3 us per
/// step of its loop (alternated binaries, twice).
const SPLIT_ADD_MIN: usize = crate::linalg::SPLIT_MIN_ORDER;

/// [`add_columns`] on the rows `i0..i0 + x.len()` of the columns (each `n` long).
fn add_columns_range(cols: &[f64], n: usize, terms: &[(usize, f64)], i0: usize, x: &mut [f64]) {
    with_avx2!(
        add_columns_here(cols, n, terms, i0, x),
        add_columns_avx2(cols, n, terms, i0, x)
    );
}

/// [`add_columns_here`] compiled for AVX2.
///
/// # Safety
/// The processor must have AVX2.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn add_columns_avx2(
    cols: &[f64],
    n: usize,
    terms: &[(usize, f64)],
    i0: usize,
    x: &mut [f64],
) {
    add_columns_here(cols, n, terms, i0, x);
}

/// `x` is the rows `i0..i0 + x.len()` of the columns, each `n` long.
#[inline(always)]
fn add_columns_here(cols: &[f64], n: usize, terms: &[(usize, f64)], i0: usize, x: &mut [f64]) {
    let len = x.len();
    let col = |s: usize| &cols[s * n + i0..s * n + i0 + len];
    for chunk in terms.chunks(4) {
        match *chunk {
            [(a, wa)] => add_k(x, [col(a)], [wa]),
            [(a, wa), (b, wb)] => add_k(x, [col(a), col(b)], [wa, wb]),
            [(a, wa), (b, wb), (c, wc)] => add_k(x, [col(a), col(b), col(c)], [wa, wb, wc]),
            [(a, wa), (b, wb), (c, wc), (d, wd)] => {
                add_k(x, [col(a), col(b), col(c), col(d)], [wa, wb, wc, wd])
            }
            _ => unreachable!("chunks of one to four terms"),
        }
    }
}

/// `x_i += w_0 c_0[i]`, then `+= w_1 c_1[i]`, ... in one pass.
#[inline(always)]
fn add_k<const K: usize>(x: &mut [f64], c: [&[f64]; K], w: [f64; K]) {
    let n = x.len();
    assert!(c.iter().all(|ct| ct.len() == n));
    for i in 0..n {
        let mut xi = x[i];
        for t in 0..K {
            xi += w[t] * c[t][i];
        }
        x[i] = xi;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The columns added four per pass (baseline and AVX2, whole and in two halves on two
    /// threads) give what one pass per column gives, bit for bit, for every count of terms
    /// up to nine.
    #[test]
    fn columns_added_together_match_one_pass_each() {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(2)
            .build()
            .unwrap();
        let helper = Team::new(crate::linalg::team::Par::threads(2));
        for n in [37, SPLIT_ADD_MIN + 1] {
            let cols: Vec<f64> = (0..9 * n).map(|i| (0.7 * i as f64).sin()).collect();
            for count in 0..=9 {
                let terms: Vec<(usize, f64)> = (0..count)
                    .map(|t| ((t * 4) % 9, 1.0 / (t as f64 + 0.3)))
                    .collect();
                let x0: Vec<f64> = (0..n).map(|i| (1.3 * i as f64).cos()).collect();
                let mut want = x0.clone();
                for &(s, w) in &terms {
                    for (xi, ci) in want.iter_mut().zip(&cols[s * n..(s + 1) * n]) {
                        *xi += w * ci;
                    }
                }
                let same = |x: &[f64]| x.iter().zip(&want).all(|(p, q)| p.to_bits() == q.to_bits());
                let mut x = x0.clone();
                add_columns_here(&cols, n, &terms, 0, &mut x);
                assert!(same(&x), "{count} terms");
                let mut x = x0.clone();
                pool.install(|| add_columns(&Team::default(), &cols, &terms, &mut x));
                assert!(same(&x), "{count} terms, n = {n}, two threads of a pool");
                let mut x = x0.clone();
                add_columns(&helper, &cols, &terms, &mut x);
                assert!(same(&x), "{count} terms, n = {n}, two threads");
                #[cfg(target_arch = "x86_64")]
                if std::is_x86_feature_detected!("avx2") {
                    let mut x = x0.clone();
                    // SAFETY: the processor has AVX2 (checked just above).
                    unsafe { add_columns_avx2(&cols, n, &terms, 0, &mut x) };
                    assert!(same(&x), "{count} terms, AVX2");
                }
            }
        }
    }
}
