//! Static frictionless contact of nodes against rigid surfaces, by an active-set method, in
//! any dimension: solve `K u = f + sum_r lambda_r c_r` with the gaps of the active rows
//! closed, `g_r = sum_k w_k (c_r . (X_k + u_k) - o_r) = 0` (Lagrange multipliers through the
//! factored `K`, as in the dynamic step), then drop a tensile active row (`lambda_r < 0`) or
//! add a penetrating free one; repeat until the set does not change.
//!
//! Each [`Row`] carries its nodes and weights (summing to 1: one node, or a mortar-weighted
//! gap), its direction `c` (`dim` components: the surface's normal into the admissible side)
//! and its offset `o`, so one solve holds a curved rigid indenter (a row per candidate node,
//! each with the indenter's local height as its offset) as well as a plane
//! ([`solve`], [`solve_rows`], the 2D API).
//!
//! **Two elastic bodies.** A row may tie a slave node of one body to a master facet of the
//! other ([`Row::node_to_facet`], [`pair::facet_rows`]): weights `+1` on the slave node and
//! `-N_i` on the facet's nodes, summing to 0, and the gap
//! `g = c . (x_s - sum_i N_i x_i) - o` (in general `g = sum_k w_k c . (X_k + u_k) - o`,
//! which is the form above when the weights sum to 1). The facet, its parameters and its
//! normal are those of the facet search in the undeformed configuration and stay frozen:
//! small deformation (displacements small beside the facets' size and the surfaces'
//! radii). `K` holds both bodies, block-diagonal, factored once. `K` is factored once ([`Statics::new`]); the
//! columns `K^-1 c_r` are solved only for rows that become active, and kept: a new set of
//! offsets (a deeper indentation) reuses them ([`Statics::solve`]).
//!
//! The rule that changes the set ([`Pivoting`]): one change at a time, the violator of least
//! index (Murty's rule, [`Pivoting::LeastIndex`]): changing every violated row at once can
//! cycle (it did on a coarse graded disk, with an alternating 13 MN / -9 MN pair); the
//! least-index rule terminates on a positive definite `S = C K^-1 C^T`, where choosing the
//! most violated row has no such guarantee. (`S` is positive definite when `K` with the
//! fixed dofs is: a wheel held at its centre node alone, free to turn, is not, and there
//! every rule may cycle.) A patch of hundreds of nodes would take hundreds of single
//! changes; [`Pivoting::Block`] changes every violator at once (the primal-dual active set)
//! and falls back to the least-index rule as soon as a set comes back.
//!
//! A fixed dof takes no contact force: its component of `c_r` is left out of the column (its
//! row of `K` is the identity's and its displacement stays 0).

use std::collections::HashSet;

pub mod indent;
pub mod pair;

use crate::contact::HalfSpace;
use crate::linalg::DenseLu;
use crate::linalg::{Factor, LinalgError, Pattern, SparseLu};

/// The result of a static contact solve.
#[derive(Debug, Clone)]
pub struct StaticContact {
    /// Displacement, m.
    pub u: Vec<f64>,
    /// Active rows, named by their first node, and their contact forces (N, compressive
    /// positive).
    pub active: Vec<(usize, f64)>,
    /// The active rows' indices (in the order of [`StaticContact::active`]).
    pub active_rows: Vec<usize>,
    /// Active-set iterations.
    pub iterations: usize,
    /// Whether the set settled within the iteration limit (`max(100, 4 rows)`).
    pub converged: bool,
}

/// A unilateral row: the gap `g = sum_k w_k c . (X_k + u_k) - o >= 0` (module docs; with
/// weights summing to 1 this is `sum_k w_k (c . (X_k + u_k) - o)`).
#[derive(Debug, Clone, PartialEq)]
pub struct Row {
    /// Nodes and weights (summing to 1 against a rigid surface, to 0 for a slave node
    /// against a master facet: [`Row::node_to_facet`]).
    pub nodes: Vec<(usize, f64)>,
    /// The direction `c`: the surface's unit normal into the admissible side (its first
    /// `dim` components are used).
    pub direction: [f64; 3],
    /// The offset `o`, m.
    pub offset: f64,
}

impl Row {
    /// The row of the slave node `slave` against the master facet of nodes and weights
    /// `facet` (`(node, N_i)`, the weights of the closest point, summing to 1), along the
    /// master's outward unit normal `normal`: weights `+1` and `-N_i`, the gap
    /// `g = normal . (x_s - sum_i N_i x_i) - offset` (module docs, Two elastic bodies).
    pub fn node_to_facet(
        slave: usize,
        facet: &[(usize, f64)],
        normal: [f64; 3],
        offset: f64,
    ) -> Row {
        let mut nodes = Vec::with_capacity(1 + facet.len());
        nodes.push((slave, 1.0));
        nodes.extend(facet.iter().map(|&(i, w)| (i, -w)));
        Row {
            nodes,
            direction: normal,
            offset,
        }
    }
}

/// How the active set changes from one iteration to the next (module docs).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Pivoting {
    /// One change at a time, the violator of least index (Murty's rule).
    #[default]
    LeastIndex,
    /// Every violator at once, the least-index rule once a set repeats.
    Block,
}

/// Which factorization of `K`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum FactorChoice {
    /// LU with AMD ordering (the 2D API's).
    #[default]
    Lu,
    /// Cholesky where `K` is symmetric positive definite, else LU ([`Factor::auto`]).
    Auto,
}

/// Input a static contact problem cannot take.
#[derive(Debug, thiserror::Error)]
pub enum StaticsError {
    /// `K` with the fixed dofs is singular (or the analysis failed).
    #[error(transparent)]
    Linalg(#[from] LinalgError),
    /// The dimension is not 1, 2 or 3, or does not divide the dofs.
    #[error("static contact: `dim` must be 1, 2 or 3 and divide the {dofs} dofs, got {dim}")]
    Dimension {
        /// The dimension given.
        dim: usize,
        /// The matrix's dofs.
        dofs: usize,
    },
    /// A vector's length is not the matrix's size.
    #[error("static contact: `{name}` must have {expected} entries (the dofs), got {got}")]
    Length {
        /// The vector's name.
        name: &'static str,
        /// Its length.
        got: usize,
        /// The dofs.
        expected: usize,
    },
    /// A row names a node past the mesh, or a fixed dof past the matrix.
    #[error("static contact: `{name}` {index} is out of range (allowed below {limit})")]
    OutOfRange {
        /// `row node` or `fixed dof`.
        name: &'static str,
        /// The index given.
        index: usize,
        /// The bound.
        limit: usize,
    },
    /// A row has no node, or a weight, direction or offset that is not finite.
    #[error("static contact: row {row} must have nodes and finite weights, direction and offset")]
    BadRow {
        /// The row's index.
        row: usize,
    },
}

/// A factored static contact problem: `K` with its fixed dofs, the load's solution and the
/// rows (module docs).
#[derive(Debug)]
pub struct Statics {
    dim: usize,
    factor: Factor,
    is_fixed: Vec<bool>,
    u0: Vec<f64>,
    rows: Vec<Row>,
    /// `K^-1 c_r`, solved when row `r` first becomes active.
    cols: Vec<Option<Vec<f64>>>,
    /// The rule of the set's changes.
    pub pivoting: Pivoting,
}

impl Statics {
    /// Factors `K` (`k` on `pattern`, `dim` dofs per node) with the dofs `fixed` held at 0
    /// and solves the load `f` (its entries on fixed dofs ignored).
    ///
    /// # Errors
    /// [`StaticsError`] naming a bad dimension, length, index or row, or a singular `K`.
    pub fn new(
        pattern: &Pattern,
        k: &[f64],
        fixed: &[usize],
        f: &[f64],
        dim: usize,
        rows: Vec<Row>,
        factorization: FactorChoice,
    ) -> Result<Self, StaticsError> {
        let n = pattern.nrows();
        if !(1..=3).contains(&dim) || n % dim != 0 {
            return Err(StaticsError::Dimension { dim, dofs: n });
        }
        if f.len() != n {
            return Err(StaticsError::Length {
                name: "f",
                got: f.len(),
                expected: n,
            });
        }
        let mut is_fixed = vec![false; n];
        for &d in fixed {
            *is_fixed.get_mut(d).ok_or(StaticsError::OutOfRange {
                name: "fixed dof",
                index: d,
                limit: n,
            })? = true;
        }
        for (r, row) in rows.iter().enumerate() {
            let finite = row.offset.is_finite()
                && row.direction.iter().all(|c| c.is_finite())
                && row.nodes.iter().all(|(_, w)| w.is_finite());
            if row.nodes.is_empty() || !finite {
                return Err(StaticsError::BadRow { row: r });
            }
            if let Some(&(i, _)) = row.nodes.iter().find(|(i, _)| dim * i >= n) {
                return Err(StaticsError::OutOfRange {
                    name: "row node",
                    index: i,
                    limit: n / dim,
                });
            }
        }
        let mut a = k.to_vec();
        crate::linalg::set_identity_rows(pattern, &mut a, &is_fixed);
        let mut factor = match factorization {
            FactorChoice::Lu => Factor::Lu(SparseLu::new(pattern, &a)?),
            FactorChoice::Auto => Factor::auto(pattern, &a)?,
        };
        let mut u0: Vec<f64> = f
            .iter()
            .zip(&is_fixed)
            .map(|(&v, &fx)| if fx { 0.0 } else { v })
            .collect();
        factor.solve_in_place(&mut u0);
        Ok(Statics {
            dim,
            factor,
            is_fixed,
            u0,
            cols: vec![None; rows.len()],
            rows,
            pivoting: Pivoting::LeastIndex,
        })
    }

    /// The rows.
    pub fn rows(&self) -> &[Row] {
        &self.rows
    }

    /// Sets every row's offset (a new indentation: the columns are kept).
    ///
    /// # Errors
    /// [`StaticsError::Length`] unless there is one finite offset per row
    /// ([`StaticsError::BadRow`] for a non-finite one).
    pub fn set_offsets(&mut self, offsets: &[f64]) -> Result<(), StaticsError> {
        if offsets.len() != self.rows.len() {
            return Err(StaticsError::Length {
                name: "offsets",
                got: offsets.len(),
                expected: self.rows.len(),
            });
        }
        if let Some(r) = offsets.iter().position(|o| !o.is_finite()) {
            return Err(StaticsError::BadRow { row: r });
        }
        for (row, &o) in self.rows.iter_mut().zip(offsets) {
            row.offset = o;
        }
        Ok(())
    }

    /// The gap of row `r` under the displacement `u` at the reference positions `x`.
    fn gap(&self, x: &[f64], u: &[f64], r: usize) -> f64 {
        let dim = self.dim;
        let row = &self.rows[r];
        let weights: f64 = row.nodes.iter().map(|&(_, w)| w).sum();
        let moved: f64 = row
            .nodes
            .iter()
            .map(|&(i, w)| {
                let mut dot = 0.0;
                for d in 0..dim {
                    dot += row.direction[d] * (x[dim * i + d] + u[dim * i + d]);
                }
                w * dot
            })
            .sum();
        // Weights summing to 1 (a rigid surface): `sum_k w_k (c . x_k - o)` as before;
        // summing to 0 (two bodies): `sum_k w_k c . x_k - o`.
        if weights.abs() < 0.5 {
            moved - row.offset
        } else {
            moved - weights * row.offset
        }
    }

    /// Solves `K^-1 c_r` for the rows `rows` not done yet, in one block of right-hand sides
    /// (`Factor::solve_many_on`: a Cholesky factor in dense supernodes is read once for
    /// eight of them).
    fn columns(&mut self, rows: &[usize]) {
        let todo: Vec<usize> = rows
            .iter()
            .copied()
            .filter(|&r| self.cols[r].is_none())
            .collect();
        if todo.is_empty() {
            return;
        }
        let (dim, n) = (self.dim, self.u0.len());
        let mut e = vec![0.0; n * todo.len()];
        for (col, &r) in e.chunks_exact_mut(n).zip(&todo) {
            for &(i, w) in &self.rows[r].nodes {
                for d in 0..dim {
                    if !self.is_fixed[dim * i + d] {
                        col[dim * i + d] += w * self.rows[r].direction[d];
                    }
                }
            }
        }
        self.factor
            .solve_many_on(&crate::linalg::team::Team::default(), &mut e, todo.len());
        for (col, &r) in e.chunks_exact(n).zip(&todo) {
            self.cols[r] = Some(col.to_vec());
        }
    }

    /// `c_p . K^-1 c_q` (the columns of `q` solved).
    fn coupling(&self, p: usize, q: usize) -> f64 {
        let dim = self.dim;
        let col = self.cols[q].as_deref().unwrap_or(&[]);
        let row = &self.rows[p];
        row.nodes
            .iter()
            .map(|&(i, w)| {
                let mut dot = 0.0;
                for d in 0..dim {
                    dot += row.direction[d] * col[dim * i + d];
                }
                w * dot
            })
            .sum()
    }

    /// The static contact at the reference positions `x` (module docs): the active set from
    /// the rows that penetrate under the load alone, changed by [`Statics::pivoting`]'s rule
    /// until it settles (at most `max(100, 4 rows)` iterations).
    ///
    /// # Errors
    /// [`StaticsError::Length`] unless `x` has one entry per dof.
    pub fn solve(&mut self, x: &[f64]) -> Result<StaticContact, StaticsError> {
        let n = self.u0.len();
        if x.len() != n {
            return Err(StaticsError::Length {
                name: "x",
                got: x.len(),
                expected: n,
            });
        }
        let n_rows = self.rows.len();
        let mut active: Vec<usize> = (0..n_rows)
            .filter(|&c| self.gap(x, &self.u0, c) < 0.0)
            .collect();
        let mut u = self.u0.clone();
        let mut lam = Vec::new();
        let mut rule = self.pivoting;
        let mut seen: HashSet<Vec<usize>> = HashSet::new();
        let limit = 100.max(4 * n_rows);
        let mut is_active = vec![false; n_rows];
        let mut lu = DenseLu::new();
        for it in 1..=limit {
            self.columns(&active);
            let m = active.len();
            let mut s = vec![0.0; m * m];
            let mut r = vec![0.0; m];
            for (p, &cp) in active.iter().enumerate() {
                r[p] = -self.gap(x, &self.u0, cp);
                for (q, &cq) in active.iter().enumerate() {
                    s[p * m + q] = self.coupling(cp, cq);
                }
            }
            lu.solve_in_place(&mut s, &mut r, m);
            u.copy_from_slice(&self.u0);
            for (q, &cq) in active.iter().enumerate() {
                let col = self.cols[cq].as_deref().unwrap_or(&[]);
                for (ui, ci) in u.iter_mut().zip(col) {
                    *ui += r[q] * ci;
                }
            }
            lam = r;
            is_active.iter_mut().for_each(|a| *a = false);
            for &c in &active {
                is_active[c] = true;
            }
            let lam_tol = -1e-10 * lam.iter().fold(0.0f64, |m, l| m.max(l.abs()));
            let penetrates = |c: usize| {
                let tol = -1e-12 * self.rows[c].offset.abs().max(1.0);
                self.gap(x, &u, c) < tol
            };
            let mut next = active.clone();
            match rule {
                // One change at a time, the violator of least index (Murty's rule: it cannot
                // cycle on the symmetric positive definite `S`): a tensile active row is
                // dropped, a penetrating free one added.
                Pivoting::LeastIndex => {
                    let tensile = active
                        .iter()
                        .zip(&lam)
                        .find(|(_, &l)| l < lam_tol)
                        .map(|(&c, _)| c);
                    let penetrating = (0..n_rows).find(|&c| !is_active[c] && penetrates(c));
                    match (tensile, penetrating) {
                        (Some(t), Some(p)) if p < t => next.push(p),
                        (Some(t), _) => next.retain(|&a| a != t),
                        (None, Some(p)) => next.push(p),
                        (None, None) => {}
                    }
                }
                Pivoting::Block => {
                    next = active
                        .iter()
                        .zip(&lam)
                        .filter(|(_, &l)| l >= lam_tol)
                        .map(|(&c, _)| c)
                        .collect();
                    next.extend((0..n_rows).filter(|&c| !is_active[c] && penetrates(c)));
                }
            }
            next.sort_unstable();
            if next == active {
                return Ok(self.result(u, &active, &lam, it, true));
            }
            if rule == Pivoting::Block && !seen.insert(next.clone()) {
                rule = Pivoting::LeastIndex;
            }
            active = next;
        }
        Ok(self.result(u, &active, &lam, limit, false))
    }

    fn result(
        &self,
        u: Vec<f64>,
        active: &[usize],
        lam: &[f64],
        iterations: usize,
        converged: bool,
    ) -> StaticContact {
        StaticContact {
            u,
            active: active
                .iter()
                .zip(lam)
                .map(|(&c, &l)| (self.rows[c].nodes[0].0, l))
                .collect(),
            active_rows: active.to_vec(),
            iterations,
            converged,
        }
    }
}

/// Solves the static contact of the `candidates` (2D nodes) against `plane`, with `K` on
/// `pattern`, fixed dofs `fixed`, load `f` and reference positions `x`.
///
/// # Errors
/// [`LinalgError`] when `K` with the fixed dofs is singular.
pub fn solve(
    pattern: &Pattern,
    k: &[f64],
    fixed: &[usize],
    f: &[f64],
    x: &[f64],
    candidates: &[usize],
    plane: HalfSpace,
) -> Result<StaticContact, LinalgError> {
    let rows: Vec<Vec<(usize, f64)>> = candidates.iter().map(|&i| vec![(i, 1.0)]).collect();
    solve_rows(pattern, k, fixed, f, x, &rows, plane)
}

/// As [`solve`], with each candidate a weighted gap: `candidates[c]` lists nodes and weights
/// (summing to 1), the gap is that of the weighted position `sum_k w_k (X_k + u_k)` and the
/// multiplier reaches the nodes in the same proportions (the mortar-weighted gap of
/// [`crate::contact::Pair::Weighted`]). The active list names each row by its first node.
/// The least-index rule ([`Pivoting::LeastIndex`]) and the LU of [`Statics`] in 2D.
///
/// # Errors
/// [`LinalgError`] when `K` with the fixed dofs is singular; inputs [`Statics::new`] refuses
/// (a candidate past the mesh, a fixed dof past the matrix, lengths that are not the dofs')
/// as [`LinalgError::Symbolic`] with [`StaticsError`]'s message.
pub fn solve_rows(
    pattern: &Pattern,
    k: &[f64],
    fixed: &[usize],
    f: &[f64],
    x: &[f64],
    candidates: &[Vec<(usize, f64)>],
    plane: HalfSpace,
) -> Result<StaticContact, LinalgError> {
    let rows = candidates
        .iter()
        .map(|nodes| Row {
            nodes: nodes.clone(),
            direction: plane.normal,
            offset: plane.offset,
        })
        .collect();
    let solved =
        Statics::new(pattern, k, fixed, f, 2, rows, FactorChoice::Lu).and_then(|mut s| s.solve(x));
    match solved {
        Ok(sol) => Ok(sol),
        Err(StaticsError::Linalg(e)) => Err(e),
        Err(e) => Err(LinalgError::Symbolic(e.to_string())),
    }
}

#[cfg(test)]
mod tests;
