//! The contact's columns of a model with cyclic symmetry: one sector's columns, the rest
//! turned.
//!
//! A wheel in its rotating frame (the paper's §4) is at rest while the contact runs round
//! its rim: every step new rim nodes enter the patch, and each new constrained dof costs the
//! soft way a column `A^{-1} e_d` of the step matrix ([`crate::contact::rows`]), one read of
//! the whole factor. On a 3D wheel that is most of a rolling step. When the mesh repeats
//! itself round the axle (`count` copies of one sector) and the step matrix does too (the
//! elastic, mass, spin and Coriolis terms are all invariant under a turn about the axle, and
//! so are supports that hold whole nodes), those columns repeat as well.
//!
//! Let `P` turn a nodal field by one sector: the value at node `m` moves to the node one
//! sector on, `sigma(m)`, and is rotated there by `Q`, the rotation by `2 pi / count` about
//! the axle `z`. `A P = P A`, so `A^{-1} P = P A^{-1}`. A node `n = sigma^k(b)`, `b` its
//! orbit's node in the base sector, has the unit vector `e_{n,c} = P^k (e_b (x) Q^{-k}
//! e_c)`, hence
//! $$A^{-1} e_{n,c} = P^k \sum_j (Q^{-k} e_c)_j\\, A^{-1} e_{b,j}:$$
//! the `dim` columns of `b` (solved once for the run, while `A` does not change) give the
//! column of every node of its orbit by a turn and a relabelling, `O(n)` work instead of a
//! solve. The row solver keeps the base columns ([`CyclicColumns`]) beside its cache and
//! derives each new column from them.
//!
//! **A rail closed on itself.** The same algebra holds for any cyclic group of node maps
//! that commutes with `A`. A straight rail whose two ends are joined (its mesh `count`
//! equal stations along it, [`crate::bodies::rolling3d::RailBlock::periodic`]) repeats
//! under a shift by one station: `P` moves each node's value to the next station's node
//! without turning it (`Q = I`, [`Copies::Shift`]). The rail is one body of a model whose
//! other body (the wheel) does not repeat that way; the step matrix is block diagonal by
//! body, so a rail dof's column is zero on the wheel's dofs, and the symmetry covers the
//! rail's nodes alone ([`CyclicSymmetry::partial`]): the wheel's columns are solved.
//!
//! The symmetry is the model's claim; [`crate::simulation::Simulation::set_cyclic_symmetry`]
//! checks it once against a solved column before it is used.

/// How one copy follows from the one before.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Copies {
    /// Turned by `2 pi / count` about the axle `z` (the wheel round its axle).
    Turn,
    /// Shifted, the vectors as they are (a rail closed on itself).
    Shift,
}

/// How a model repeats round the axle `z`: `count` sectors, every node one of an orbit's
/// `count` copies (module docs); or how some of its nodes repeat ([`Self::partial`]), the
/// others outside. Dofs are `dim` per node, node `m`'s at `dim m ..`.
#[derive(Debug, Clone, PartialEq)]
pub struct CyclicSymmetry {
    dim: usize,
    count: usize,
    /// Per node: its orbit ([`OUTSIDE`] for a node the symmetry does not cover).
    orbit: Vec<u32>,
    /// Per node: its copy `k`: the node is `sigma^k` of its orbit's copy 0.
    turn: Vec<u32>,
    /// `node_of[orbit * count + k]`.
    node_of: Vec<u32>,
    /// `(cos, sin)` of `2 pi k / count` ([`Copies::Turn`]), or `(1, 0)` ([`Copies::Shift`]).
    rot: Vec<(f64, f64)>,
    /// The covered nodes, ascending.
    covered: Vec<u32>,
}

/// The orbit of a node outside a partial symmetry.
const OUTSIDE: u32 = u32::MAX;

impl CyclicSymmetry {
    /// The symmetry of `count` sectors from each node's `(orbit, copy)`: node `m` is the
    /// copy `k` of its orbit, turned by `2 pi k / count` about `z` (counter-clockwise) from
    /// copy 0. `dim` is 2 (the plane's rotation) or 3.
    ///
    /// # Errors
    /// A message when `dim` is not 2 or 3, `count < 2`, a copy is out of range or the
    /// labels are not one node per orbit and copy.
    pub fn new(dim: usize, count: usize, labels: &[(usize, usize)]) -> Result<Self, String> {
        let labels: Vec<Option<(usize, usize)>> = labels.iter().copied().map(Some).collect();
        Self::partial(dim, count, &labels, Copies::Turn)
    }

    /// The symmetry of `count` copies of the nodes labelled `Some((orbit, copy))`, each copy
    /// following from the one before as `copies` says; a node labelled `None` is outside it,
    /// and a covered dof's column must be zero there (module docs, A rail closed on itself).
    ///
    /// # Errors
    /// A message when `dim` is not 2 or 3, `count < 2`, a copy is out of range, no node is
    /// covered or the covered nodes are not one node per orbit and copy.
    pub fn partial(
        dim: usize,
        count: usize,
        labels: &[Option<(usize, usize)>],
        copies: Copies,
    ) -> Result<Self, String> {
        if !(dim == 2 || dim == 3) {
            return Err(format!(
                "a cyclic symmetry needs 2 or 3 dofs per node, not {dim}"
            ));
        }
        if count < 2 {
            return Err(format!(
                "a cyclic symmetry needs 2 sectors or more, not {count}"
            ));
        }
        let covered: Vec<u32> = (0..labels.len())
            .filter(|&m| labels[m].is_some())
            .map(|m| m as u32)
            .collect();
        if covered.is_empty() || covered.len() % count != 0 {
            return Err(format!(
                "{} nodes are not whole orbits of {count} copies",
                covered.len()
            ));
        }
        let orbits = covered.len() / count;
        let mut node_of = vec![u32::MAX; covered.len()];
        let mut orbit = Vec::with_capacity(labels.len());
        let mut turn = Vec::with_capacity(labels.len());
        for (m, label) in labels.iter().enumerate() {
            let Some((o, k)) = *label else {
                orbit.push(OUTSIDE);
                turn.push(0);
                continue;
            };
            if o >= orbits || k >= count {
                return Err(format!(
                    "node {m}: orbit {o} of {orbits}, copy {k} of {count}: out of range"
                ));
            }
            let slot = &mut node_of[o * count + k];
            if *slot != u32::MAX {
                return Err(format!(
                    "nodes {slot} and {m} are both copy {k} of orbit {o}"
                ));
            }
            *slot = m as u32;
            orbit.push(o as u32);
            turn.push(k as u32);
        }
        let rot = (0..count)
            .map(|k| match copies {
                Copies::Turn => {
                    let a = 2.0 * std::f64::consts::PI * k as f64 / count as f64;
                    (a.cos(), a.sin())
                }
                Copies::Shift => (1.0, 0.0),
            })
            .collect();
        Ok(Self {
            dim,
            count,
            orbit,
            turn,
            node_of,
            rot,
            covered,
        })
    }

    /// Dofs per node.
    pub fn dim(&self) -> usize {
        self.dim
    }

    /// Sectors in the full turn.
    pub fn count(&self) -> usize {
        self.count
    }

    /// Orbits (nodes of one sector).
    pub fn orbits(&self) -> usize {
        self.covered.len() / self.count
    }

    /// Whether dof `d`'s node is one the symmetry covers.
    pub fn covers(&self, d: usize) -> bool {
        self.orbit.get(d / self.dim).is_some_and(|&o| o != OUTSIDE)
    }

    /// Dofs of the model.
    pub fn dofs(&self) -> usize {
        self.dim * self.orbit.len()
    }

    /// Dof `d`'s orbit, copy and component (`d` covered: [`Self::covers`]).
    pub fn locate(&self, d: usize) -> (usize, usize, usize) {
        let m = d / self.dim;
        (self.orbit[m] as usize, self.turn[m] as usize, d % self.dim)
    }

    /// The dof of component `c` of orbit `o`'s copy `k`.
    pub fn dof(&self, o: usize, k: usize, c: usize) -> usize {
        self.dim * self.node_of[o * self.count + k % self.count] as usize + c
    }

    /// `Q^k` applied to the in-plane part `(x, y)`.
    fn turn_by(&self, k: usize, x: f64, y: f64) -> (f64, f64) {
        let (c, s) = self.rot[k % self.count];
        (c * x - s * y, s * x + c * y)
    }

    /// `out <- A^{-1} e_d` from the columns `base[j] = A^{-1} e_{b,j}` of `d`'s orbit's
    /// copy 0 (module docs); each slice `dofs()` long. The nodes outside a partial symmetry
    /// get zeros.
    pub fn derive(&self, d: usize, base: &[&[f64]], out: &mut [f64]) {
        let dim = self.dim;
        let (_, k, c) = self.locate(d);
        // w = Q^{-k} e_c.
        let mut w = [0.0; 3];
        match c {
            0 => {
                let (x, y) = self.turn_by(self.count - k % self.count, 1.0, 0.0);
                w[0] = x;
                w[1] = y;
            }
            1 => {
                let (x, y) = self.turn_by(self.count - k % self.count, 0.0, 1.0);
                w[0] = x;
                w[1] = y;
            }
            _ => w[2] = 1.0,
        }
        if self.covered.len() < self.orbit.len() {
            out.fill(0.0);
        }
        for &m in &self.covered {
            let m = m as usize;
            let mut v = [0.0; 3];
            for (j, col) in base.iter().enumerate().take(dim) {
                if w[j] != 0.0 {
                    for (vc, &x) in v.iter_mut().zip(&col[dim * m..dim * m + dim]) {
                        *vc += w[j] * x;
                    }
                }
            }
            let (x, y) = self.turn_by(k, v[0], v[1]);
            let target = self.dof(self.orbit[m] as usize, self.turn[m] as usize + k, 0);
            out[target] = x;
            out[target + 1] = y;
            if dim == 3 {
                out[target + 2] = v[2];
            }
        }
    }
}

/// The base sector's columns of a run (module docs), solved as they are first needed and
/// kept while `A` does not change.
#[derive(Debug, Clone)]
pub struct CyclicColumns {
    sym: CyclicSymmetry,
    /// Per base dof (`orbit * dim + c`): its slot in `cols`, or none.
    slot: Vec<usize>,
    cols: Vec<f64>,
    /// Columns derived so far.
    derived: usize,
    /// Base dofs whose columns a solve still needs.
    pending: Vec<usize>,
}

const NONE: usize = usize::MAX;

impl CyclicColumns {
    /// No column yet.
    pub fn new(sym: CyclicSymmetry) -> Self {
        let slots = sym.orbits() * sym.dim();
        Self {
            sym,
            slot: vec![NONE; slots],
            cols: Vec::new(),
            derived: 0,
            pending: Vec::new(),
        }
    }

    /// The base columns of `sym` on `integ`'s step matrix, once the claim is checked: the
    /// column of dof `d` (off the base sector) turned from its orbit's base columns against
    /// the same column solved (`dim + 1` solves; the base columns are kept).
    ///
    /// # Errors
    /// A message when the two differ by more than `1e-9` of the column's largest entry.
    pub fn checked(
        sym: CyclicSymmetry,
        integ: &mut dyn crate::time::integrator::TimeIntegrator,
        d: usize,
    ) -> Result<Self, String> {
        let n = sym.dofs();
        let mut cyc = Self::new(sym);
        cyc.need(d);
        let mut dofs = Vec::new();
        cyc.pending_dofs(&mut dofs);
        let mut base = vec![0.0; dofs.len() * n];
        integ.inverse_columns(&dofs, &mut base);
        cyc.store(&base);
        let mut turned = vec![0.0; n];
        cyc.derive(d, &mut turned);
        let mut solved = vec![0.0; n];
        integ.inverse_column(d, &mut solved);
        let size = solved.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
        let diff = turned
            .iter()
            .zip(&solved)
            .fold(0.0_f64, |m, (a, b)| m.max((a - b).abs()));
        if diff.is_nan() || diff > 1e-9 * size {
            return Err(format!(
                "the model does not repeat round its axle as its cyclic symmetry says: a column turned from the base sector differs from the solved one by {:.2e} of its size",
                diff / size.max(f64::MIN_POSITIVE)
            ));
        }
        Ok(cyc)
    }

    /// The symmetry.
    pub fn symmetry(&self) -> &CyclicSymmetry {
        &self.sym
    }

    /// Forgets every base column (after `A` changes).
    pub fn invalidate(&mut self) {
        self.slot.fill(NONE);
        self.cols.clear();
    }

    /// Columns derived so far (each one a solve saved).
    pub fn derived(&self) -> usize {
        self.derived
    }

    /// Base columns held.
    pub fn held(&self) -> usize {
        self.cols.len() / self.sym.dofs().max(1)
    }

    /// Queues the base dofs that `d`'s column needs and are not held (each once).
    pub fn need(&mut self, d: usize) {
        let (o, _, _) = self.sym.locate(d);
        for j in 0..self.sym.dim() {
            let b = o * self.sym.dim() + j;
            if self.slot[b] == NONE && !self.pending.contains(&b) {
                self.pending.push(b);
            }
        }
    }

    /// The model dofs of the queued base columns, in the order [`Self::store`] takes them.
    pub fn pending_dofs(&self, out: &mut Vec<usize>) {
        out.clear();
        let dim = self.sym.dim();
        out.extend(
            self.pending
                .iter()
                .map(|&b| self.sym.dof(b / dim, 0, b % dim)),
        );
    }

    /// Keeps the solved queued columns `cols` (each `dofs()` long, in the queue's order).
    pub fn store(&mut self, cols: &[f64]) {
        let n = self.sym.dofs();
        for (i, &b) in self.pending.iter().enumerate() {
            self.slot[b] = self.cols.len() / n;
            self.cols.extend_from_slice(&cols[i * n..(i + 1) * n]);
        }
        self.pending.clear();
    }

    /// `out <- A^{-1} e_d` from the held base columns ([`Self::need`] and [`Self::store`]
    /// first).
    ///
    /// # Panics
    /// When a base column `d` needs is not held.
    pub fn derive(&mut self, d: usize, out: &mut [f64]) {
        let n = self.sym.dofs();
        let dim = self.sym.dim();
        let (o, _, _) = self.sym.locate(d);
        let mut base: [&[f64]; 3] = [&[], &[], &[]];
        for (j, b) in base.iter_mut().enumerate().take(dim) {
            let s = self.slot[o * dim + j];
            assert!(s != NONE, "a base column of the cyclic symmetry is missing");
            *b = &self.cols[s * n..(s + 1) * n];
        }
        self.sym.derive(d, &base[..dim], out);
        self.derived += 1;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The columns of `dofs` derived from the base columns of the dense matrix `a` (row
    /// major) against the same columns solved: the largest difference, and the count
    /// derived; `check` sees each derived column.
    fn derived_against_solved(
        sym: CyclicSymmetry,
        a: &[f64],
        dofs: std::ops::Range<usize>,
        check: impl Fn(&[f64]),
    ) -> (f64, usize) {
        let n = sym.dofs();
        let solve = |d: usize| {
            let mut m = a.to_vec();
            let mut r = vec![0.0; n];
            r[d] = 1.0;
            crate::linalg::dense_solve_in_place(&mut m, &mut r, n);
            r
        };
        let mut cc = CyclicColumns::new(sym);
        for d in dofs.clone() {
            cc.need(d);
        }
        let mut base = Vec::new();
        cc.pending_dofs(&mut base);
        assert_eq!(base.len(), 6, "two orbits, three components");
        let solved: Vec<f64> = base.iter().flat_map(|&d| solve(d)).collect();
        cc.store(&solved);
        let mut out = vec![f64::NAN; n];
        let mut worst: f64 = 0.0;
        for d in dofs {
            cc.derive(d, &mut out);
            check(&out);
            for (x, y) in out.iter().zip(&solve(d)) {
                worst = worst.max((x - y).abs());
            }
        }
        (worst, cc.derived())
    }

    /// A ring of `count` nodes round the axle (2 orbits: radius 1 and 2) with a dense
    /// symmetric "matrix" built to commute with the turn: `A = I + sum` of spring pairs
    /// between neighbours, their stiffness along the line between them. The derived columns
    /// equal the solved ones.
    #[test]
    fn derived_columns_equal_solved_ones() {
        let count = 7;
        let dim = 3;
        let labels: Vec<(usize, usize)> = (0..2)
            .flat_map(|o| (0..count).map(move |k| (o, k)))
            .collect();
        let sym = CyclicSymmetry::new(dim, count, &labels).unwrap();
        let nodes = labels.len();
        let pos: Vec<[f64; 3]> = labels
            .iter()
            .map(|&(o, k)| {
                let a = 2.0 * std::f64::consts::PI * k as f64 / count as f64 + 0.3;
                let r = 1.0 + o as f64;
                [r * a.cos(), r * a.sin(), 0.2 * o as f64]
            })
            .collect();
        let n = dim * nodes;
        let mut a = vec![0.0; n * n];
        for i in 0..n {
            a[i * n + i] = 3.0;
        }
        let mut spring = |p: usize, q: usize, kf: f64| {
            let d: Vec<f64> = (0..3).map(|c| pos[q][c] - pos[p][c]).collect();
            let l = d.iter().map(|x| x * x).sum::<f64>().sqrt();
            for i in 0..3 {
                for j in 0..3 {
                    let v = kf * d[i] * d[j] / (l * l);
                    a[(3 * p + i) * n + 3 * p + j] += v;
                    a[(3 * q + i) * n + 3 * q + j] += v;
                    a[(3 * p + i) * n + 3 * q + j] -= v;
                    a[(3 * q + i) * n + 3 * p + j] -= v;
                }
            }
        };
        for k in 0..count {
            let (i0, i1) = (k, (k + 1) % count);
            spring(i0, i1, 2.0);
            spring(count + i0, count + i1, 1.0);
            spring(i0, count + i0, 5.0);
            spring(i0, count + i1, 0.7);
        }
        // A skew term (a Coriolis-like coupling, invariant under turns about z).
        for m in 0..nodes {
            a[(3 * m) * n + 3 * m + 1] += 0.4;
            a[(3 * m + 1) * n + 3 * m] -= 0.4;
        }
        let (worst, derived) = derived_against_solved(sym, &a, 0..n, |_| {});
        assert!(worst < 1e-13, "derived against solved: {worst:e}");
        assert_eq!(derived, n);
    }

    /// A partial symmetry: a ring of `count` nodes closed on itself under a shift (springs
    /// between neighbours along a line, the last joined to the first, no turn) beside two
    /// nodes outside it, in a block of their own. The shifted columns equal the solved
    /// ones, zero on the outside nodes; the outside dofs are not covered.
    #[test]
    fn shifted_columns_of_a_closed_ring_equal_solved_ones() {
        let count = 6;
        let dim = 3;
        let outside = 2;
        let mut labels: Vec<Option<(usize, usize)>> = vec![None; outside];
        labels.extend((0..2).flat_map(|o| (0..count).map(move |k| Some((o, k)))));
        let sym = CyclicSymmetry::partial(dim, count, &labels, Copies::Shift).unwrap();
        let nodes = labels.len();
        let n = dim * nodes;
        let mut a = vec![0.0; n * n];
        for i in 0..n {
            a[i * n + i] = 3.0;
        }
        // The outside block: its own coupling.
        a[1] = 0.5;
        a[n] = 0.5;
        let node = |o: usize, k: usize| outside + o * count + k % count;
        let mut spring = |p: usize, q: usize, d: [f64; 3], kf: f64| {
            let l2: f64 = d.iter().map(|x| x * x).sum();
            for i in 0..3 {
                for j in 0..3 {
                    let v = kf * d[i] * d[j] / l2;
                    a[(3 * p + i) * n + 3 * p + j] += v;
                    a[(3 * q + i) * n + 3 * q + j] += v;
                    a[(3 * p + i) * n + 3 * q + j] -= v;
                    a[(3 * q + i) * n + 3 * p + j] -= v;
                }
            }
        };
        for k in 0..count {
            spring(node(0, k), node(0, k + 1), [1.0, 0.0, 0.0], 2.0);
            spring(node(1, k), node(1, k + 1), [1.0, 0.0, 0.0], 1.0);
            spring(node(0, k), node(1, k), [0.0, 1.0, 0.0], 5.0);
            spring(node(0, k), node(1, k + 1), [1.0, 1.0, 0.3], 0.7);
        }
        assert!(!sym.covers(0) && !sym.covers(dim * outside - 1) && sym.covers(dim * outside));
        assert_eq!(sym.orbits(), 2);
        let (worst, _) = derived_against_solved(sym, &a, dim * outside..n, |out| {
            assert!(out[..dim * outside].iter().all(|&x| x == 0.0));
        });
        assert!(worst < 1e-13, "shifted against solved: {worst:e}");
        // Not a symmetry of a ring whose copies are not whole.
        assert!(
            CyclicSymmetry::partial(dim, count, &labels[..outside + 3], Copies::Shift).is_err()
        );
        assert!(CyclicSymmetry::partial(dim, count, &[None, None], Copies::Shift).is_err());
    }

    #[test]
    fn bad_labels_are_refused() {
        assert!(CyclicSymmetry::new(3, 1, &[(0, 0)]).is_err());
        assert!(CyclicSymmetry::new(4, 2, &[(0, 0), (0, 1)]).is_err());
        assert!(CyclicSymmetry::new(3, 2, &[(0, 0), (0, 0)]).is_err());
        assert!(CyclicSymmetry::new(3, 2, &[(0, 0), (0, 2)]).is_err());
        assert!(CyclicSymmetry::new(3, 2, &[(0, 0), (0, 1), (1, 0)]).is_err());
        assert!(CyclicSymmetry::new(3, 2, &[(0, 0), (0, 1)]).is_ok());
    }
}
