//! Linear constraints on nodes imposed by Lagrange multipliers through a factored matrix
//! (DESIGN §2), shared by every stepper.
//!
//! For `A x = b + C^T lambda`, `C x = g` (row `p` of `C`: the unit normal `n_p` on the dofs
//! of node `p`):
//! $$\lambda = (C A^{-1} C^T)^{-1} (g - C A^{-1} b),\qquad x = A^{-1} b + A^{-1} C^T \lambda.$$
//! The columns `A^{-1} e_d` of the constrained nodes' dofs are kept in a cache of fixed size
//! (least recently used slot replaced) while `A` does not change, so a change of the active
//! set costs no factorization, and only the small dense system on the active constraints is
//! solved. All memory is allocated in [`ColumnCache::new`].

use super::step::{dense_solve_in_place, VelocityConstraint};

const NO_SLOT: usize = usize::MAX;

/// The cache of `A^{-1}` columns of constrained nodes and the dense work of the multipliers.
#[derive(Debug, Clone)]
pub struct ColumnCache {
    dim: usize,
    n: usize,
    slot_of_node: Vec<usize>,
    node_of_slot: Vec<usize>,
    last_used: Vec<u64>,
    cols: Vec<f64>,
    clock: u64,
    s_mat: Vec<f64>,
    r_vec: Vec<f64>,
    slots_active: Vec<usize>,
    unit: Vec<f64>,
}

impl ColumnCache {
    /// Room for `max_constraints` simultaneous constraints and the columns of `cache_nodes`
    /// nodes (at least `max_constraints`), for `n` dofs, `dim` per node.
    pub fn new(n: usize, dim: usize, max_constraints: usize, cache_nodes: usize) -> Self {
        let cache_nodes = cache_nodes.max(max_constraints).max(1);
        let mc = max_constraints.max(1);
        Self {
            dim,
            n,
            slot_of_node: vec![NO_SLOT; n / dim.max(1)],
            node_of_slot: vec![NO_SLOT; cache_nodes],
            last_used: vec![0; cache_nodes],
            cols: vec![0.0; cache_nodes * dim * n],
            clock: 0,
            s_mat: vec![0.0; mc * mc],
            r_vec: vec![0.0; mc],
            slots_active: vec![0; mc],
            unit: vec![0.0; n],
        }
    }

    /// Drops every cached column (call after `A` changes).
    pub fn clear(&mut self) {
        self.slot_of_node.fill(NO_SLOT);
        self.node_of_slot.fill(NO_SLOT);
        self.last_used.fill(0);
    }

    /// Given `x = A^{-1} b`, imposes `normal_p . x_{node_p} = rhs_p` for every constraint,
    /// writing the multipliers into `lambda[..len]`. `solve` applies `A^{-1}` in place;
    /// dofs with `is_fixed` get no column (they are Dirichlet rows of `A`).
    ///
    /// # Panics
    /// When more constraints are given than `max_constraints` of [`ColumnCache::new`].
    pub fn apply<F>(
        &mut self,
        x: &mut [f64],
        constraints: &[VelocityConstraint],
        lambda: &mut [f64],
        is_fixed: &[bool],
        mut solve: F,
    ) where
        F: FnMut(&mut [f64]),
    {
        let k = constraints.len();
        if k == 0 {
            return;
        }
        assert!(k <= self.r_vec.len(), "too many simultaneous constraints");
        self.clock += 1;
        for (q, c) in constraints.iter().enumerate() {
            self.slots_active[q] = self.ensure_cached(c.node, is_fixed, &mut solve);
        }
        let (dim, n) = (self.dim, self.n);
        for (p, cp) in constraints.iter().enumerate() {
            let mut xn = 0.0;
            for c in 0..dim {
                xn += cp.normal[c] * x[dim * cp.node + c];
            }
            self.r_vec[p] = cp.rhs - xn;
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
                for (xi, ci) in x.iter_mut().zip(col) {
                    *xi += w * ci;
                }
            }
        }
    }

    fn ensure_cached<F: FnMut(&mut [f64])>(
        &mut self,
        node: usize,
        is_fixed: &[bool],
        solve: &mut F,
    ) -> usize {
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
            if !is_fixed[d] {
                self.unit[d] = 1.0;
                solve(&mut self.unit);
            }
            self.cols[(s * dim + c) * n..(s * dim + c + 1) * n].copy_from_slice(&self.unit);
        }
        self.node_of_slot[s] = node;
        self.slot_of_node[node] = s;
        self.last_used[s] = self.clock;
        s
    }
}
