//! Global assembly: the sparsity pattern is built once from the mesh connectivity, with a
//! map from every element-matrix entry to its slot in the value array; matrices sharing the
//! pattern (`M`, `K`, `C`, `A`) are then filled by scattering element matrices
//! (fenris `CsrAssembler::assemble_pattern` / `assemble_into_csr`).

use crate::linalg::Pattern;
use crate::mesh::Mesh;
use rayon::prelude::*;

/// The sparsity pattern of a mesh and the element-to-value map.
#[derive(Debug, Clone)]
pub struct Assembler {
    /// The pattern (square, `n_dofs x n_dofs`, every coupling of two dofs of one element).
    pub pattern: Pattern,
    /// Degrees of freedom per element (`dim * nodes per element`).
    pub ndof_e: usize,
    /// For element `e`, local entry `(a, b)` (row-major) lands at
    /// `values[slots[e * ndof_e^2 + a * ndof_e + b]]`.
    slots: Vec<usize>,
    /// Global dofs of each element, `ndof_e` per element.
    elem_dofs: Vec<usize>,
}

impl Assembler {
    /// Builds the pattern of `mesh`, plus the diagonal of every dof (so that a dof touched by
    /// no element still has a slot for a Dirichlet 1).
    pub fn new(mesh: &Mesh) -> Self {
        let dim = mesh.dim;
        let n = mesh.n_dofs();
        let n_el = mesh.cells.len();
        let npe = if n_el > 0 {
            mesh.cell_nodes(0).len()
        } else {
            0
        };
        let ndof_e = dim * npe;
        let mut elem_dofs = Vec::with_capacity(n_el * ndof_e);
        for e in 0..n_el {
            for &node in mesh.cell_nodes(e) {
                for c in 0..dim {
                    elem_dofs.push(dim * node + c);
                }
            }
        }
        // Column lists of rows.
        let mut cols: Vec<Vec<usize>> = (0..n).map(|j| vec![j]).collect();
        for e in 0..n_el {
            let d = &elem_dofs[e * ndof_e..(e + 1) * ndof_e];
            for &j in d {
                cols[j].extend_from_slice(d);
            }
        }
        let mut col_ptr = Vec::with_capacity(n + 1);
        let mut row_idx = Vec::new();
        col_ptr.push(0);
        for c in &mut cols {
            c.sort_unstable();
            c.dedup();
            row_idx.extend_from_slice(c);
            col_ptr.push(row_idx.len());
        }
        let mut slots = Vec::with_capacity(n_el * ndof_e * ndof_e);
        for e in 0..n_el {
            let d = &elem_dofs[e * ndof_e..(e + 1) * ndof_e];
            for &i in d {
                for &j in d {
                    let rows = &row_idx[col_ptr[j]..col_ptr[j + 1]];
                    let k = rows
                        .binary_search(&i)
                        .expect("pattern holds element entries");
                    slots.push(col_ptr[j] + k);
                }
            }
        }
        // SAFETY of new_checked: indices sorted, in range, no duplicates by construction.
        let pattern = Pattern::new_checked(n, n, col_ptr, None, row_idx);
        Self {
            pattern,
            ndof_e,
            slots,
            elem_dofs,
        }
    }

    /// Number of stored entries.
    pub fn nnz(&self) -> usize {
        self.pattern.row_idx().len()
    }

    /// Global dofs of element `e`.
    pub fn element_dofs(&self, e: usize) -> &[usize] {
        &self.elem_dofs[e * self.ndof_e..(e + 1) * self.ndof_e]
    }

    /// Index in the value array of global entry `(i, j)`, if stored.
    pub fn slot(&self, i: usize, j: usize) -> Option<usize> {
        let cp = self.pattern.col_ptr();
        let rows = &self.pattern.row_idx()[cp[j]..cp[j + 1]];
        rows.binary_search(&i).ok().map(|k| cp[j] + k)
    }

    /// A zero value array for this pattern.
    pub fn zeros(&self) -> Vec<f64> {
        vec![0.0; self.nnz()]
    }

    /// Adds the element matrices produced by `kernel(e, out)` (row-major, `ndof_e^2`, `out`
    /// zeroed before each call) into `values`, one element after another.
    pub fn assemble_serial_into<F>(&self, values: &mut [f64], mut kernel: F)
    where
        F: FnMut(usize, &mut [f64]),
    {
        let m = self.ndof_e * self.ndof_e;
        let mut buf = vec![0.0; m];
        for e in 0..self.elem_dofs.len() / self.ndof_e.max(1) {
            buf.fill(0.0);
            kernel(e, &mut buf);
            for (k, &s) in self.slots[e * m..(e + 1) * m].iter().enumerate() {
                values[s] += buf[k];
            }
        }
    }

    /// As [`Assembler::assemble_serial_into`], with the element kernels evaluated in
    /// parallel (rayon) in chunks, each chunk into its own buffer, then scattered in element
    /// order, so the result is bitwise the serial one.
    pub fn assemble_par_into<F>(&self, values: &mut [f64], kernel: F)
    where
        F: Fn(usize, &mut [f64]) + Sync,
    {
        let m = self.ndof_e * self.ndof_e;
        let n_el = self.elem_dofs.len() / self.ndof_e.max(1);
        const CHUNK: usize = 256;
        let locals: Vec<Vec<f64>> = (0..n_el.div_ceil(CHUNK))
            .into_par_iter()
            .map(|c| {
                let lo = c * CHUNK;
                let hi = (lo + CHUNK).min(n_el);
                let mut buf = vec![0.0; (hi - lo) * m];
                for e in lo..hi {
                    kernel(e, &mut buf[(e - lo) * m..(e - lo + 1) * m]);
                }
                buf
            })
            .collect();
        for (c, buf) in locals.iter().enumerate() {
            let lo = c * CHUNK;
            for (k, v) in buf.iter().enumerate() {
                values[self.slots[lo * m + k]] += v;
            }
        }
    }

    /// Dense copy (tests, small eigenproblems).
    pub fn to_dense(&self, values: &[f64]) -> faer::Mat<f64> {
        let n = self.pattern.nrows();
        let mut a = faer::Mat::zeros(n, n);
        let cp = self.pattern.col_ptr();
        let ri = self.pattern.row_idx();
        for j in 0..n {
            for p in cp[j]..cp[j + 1] {
                a[(ri[p], j)] += values[p];
            }
        }
        a
    }
}
