//! Global assembly: the sparsity pattern is built once from the mesh connectivity, with a
//! map from every element-matrix entry to its slot in the value array; matrices sharing the
//! pattern (`M`, `K`, `C`, `A`) are then filled by scattering element matrices
//! (fenris `CsrAssembler::assemble_pattern` / `assemble_into_csr`).
//!
//! # The element loop
//!
//! A global matrix is the sum over the elements of their matrices scattered into the
//! pattern, `A = sum_e P_e^T A_e P_e` (`P_e` picks element `e`'s dofs). The element matrix
//! comes from an [`ElementMatrix`] operator, which fills a buffer the loop owns
//! (fenris `assemble_element_matrix_into(element_index, output)`); the loop
//! ([`Assembler::assemble`], [`Assembler::add_assembled`]) evaluates the elements in
//! parallel and scatters them in element order, so the result does not depend on the
//! number of threads.
//!
//! The operators of the 3-node triangle ([`crate::element::tri3`]) over a whole mesh:
//!
//! | operator | element matrix | global matrix |
//! |---|---|---|
//! | [`Tri3Mass`] | `rho t A / 12 (1 + delta_ij) delta_ab` (or lumped `rho t A / 3 I`) | `M` (also the damping `eta_z N^T N` of Eq. 22, with `eta_z` for `rho`) |
//! | [`Tri3Stiffness`] | `t A B^T D B` | `K` |
//! | [`Tri3GeometricStiffness`] | `delta_ab t A grad N_i . S_e grad N_j` | `K_sigma` of the element stresses `S_e` |

use crate::element::tri3::{self, Tri3Geometry};
use crate::linalg::Pattern;
use crate::material::Elastic;
use crate::mesh::Mesh;
use rayon::prelude::*;

/// An element operator: the `N x N` matrix of element `e`, written into the caller's buffer.
///
/// `N` is the number of dofs of an element (`dim * nodes per element`), the
/// [`Assembler::ndof_e`] of the mesh it is assembled on. The buffer is zero on entry;
/// the operator may overwrite it completely.
pub trait ElementMatrix<const N: usize>: Sync {
    /// Fills `out` with the matrix of element `e`.
    fn element_matrix_into(&self, e: usize, out: &mut [[f64; N]; N]);
}

/// Mass matrix of a triangle mesh, consistent or lumped ([`tri3::mass_into`]).
#[derive(Debug, Clone, Copy)]
pub struct Tri3Mass<'a> {
    /// Element geometry, one per triangle.
    pub geometry: &'a [Tri3Geometry],
    /// Mass per unit volume, kg/m^3 (or the damping `eta_z`, N s/m^4, Eq. 22).
    pub density: f64,
    /// Thickness, m.
    pub thickness: f64,
    /// Lumped (`true`) or consistent mass.
    pub lumped: bool,
}

impl ElementMatrix<6> for Tri3Mass<'_> {
    fn element_matrix_into(&self, e: usize, out: &mut [[f64; 6]; 6]) {
        tri3::mass_into(
            &self.geometry[e],
            self.density,
            self.thickness,
            self.lumped,
            out,
        );
    }
}

/// Elastic stiffness of a triangle mesh ([`tri3::stiffness_into`]).
#[derive(Debug, Clone, Copy)]
pub struct Tri3Stiffness<'a> {
    /// Element geometry, one per triangle.
    pub geometry: &'a [Tri3Geometry],
    /// Voigt elasticity matrix `D`, Pa.
    pub d: &'a [[f64; 3]; 3],
    /// Thickness, m.
    pub thickness: f64,
}

impl ElementMatrix<6> for Tri3Stiffness<'_> {
    fn element_matrix_into(&self, e: usize, out: &mut [[f64; 6]; 6]) {
        tri3::stiffness_into(&self.geometry[e], self.d, self.thickness, out);
    }
}

/// Geometric (initial-stress) stiffness of a triangle mesh under the element stresses
/// `stress[e] = [sxx, syy, txy]` (Pa), [`tri3::geometric_stiffness_into`].
#[derive(Debug, Clone, Copy)]
pub struct Tri3GeometricStiffness<'a> {
    /// Element geometry, one per triangle.
    pub geometry: &'a [Tri3Geometry],
    /// The prestress of each element, `[sxx, syy, txy]`, Pa.
    pub stress: &'a [[f64; 3]],
    /// Thickness, m.
    pub thickness: f64,
}

impl ElementMatrix<6> for Tri3GeometricStiffness<'_> {
    fn element_matrix_into(&self, e: usize, out: &mut [[f64; 6]; 6]) {
        tri3::geometric_stiffness_into(&self.geometry[e], self.stress[e], self.thickness, out);
    }
}

/// Assembles `M` (consistent or lumped) and `K` of a triangle mesh with the elasticity
/// matrix `d` and thickness `thickness` (m).
pub fn assemble_mass_stiffness(
    asm: &Assembler,
    geom: &[Tri3Geometry],
    d: &[[f64; 3]; 3],
    material: &Elastic,
    thickness: f64,
    lumped: bool,
) -> (Vec<f64>, Vec<f64>) {
    let m = asm.assemble(&Tri3Mass {
        geometry: geom,
        density: material.density,
        thickness,
        lumped,
    });
    let k = asm.assemble(&Tri3Stiffness {
        geometry: geom,
        d,
        thickness,
    });
    (m, k)
}

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

    /// The global matrix of the operator `op` (values on this pattern).
    ///
    /// # Panics
    /// If `N` is not this mesh's [`Assembler::ndof_e`].
    pub fn assemble<const N: usize>(&self, op: &impl ElementMatrix<N>) -> Vec<f64> {
        let mut values = self.zeros();
        self.add_assembled(op, &mut values);
        values
    }

    /// Adds the global matrix of the operator `op` into `values`: the element loop of the
    /// module docs, in parallel, scattered in element order (bitwise the serial sum).
    ///
    /// # Panics
    /// If `N` is not this mesh's [`Assembler::ndof_e`].
    pub fn add_assembled<const N: usize>(&self, op: &impl ElementMatrix<N>, values: &mut [f64]) {
        if self.elem_dofs.is_empty() {
            return;
        }
        assert_eq!(N, self.ndof_e, "element operator of the wrong size");
        self.assemble_par_into(values, |e, out| {
            let mut b = [[0.0; N]; N];
            op.element_matrix_into(e, &mut b);
            out.copy_from_slice(b.as_flattened());
        });
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::generators::disk_rings;

    #[test]
    fn operator_loop_is_bitwise_the_serial_sum_and_mass_sums_to_the_mass() {
        let mesh = disk_rings(0.1, 6).unwrap();
        let crate::mesh::Cells::Tri3(tris) = &mesh.cells else {
            panic!("disk of triangles")
        };
        let geom: Vec<Tri3Geometry> = tris
            .iter()
            .map(|t| {
                tri3::geometry(&[mesh.points[t[0]], mesh.points[t[1]], mesh.points[t[2]]]).unwrap()
            })
            .collect();
        let asm = Assembler::new(&mesh);
        let mat = Elastic {
            young: 2.05e11,
            poisson: 0.3,
            density: 7830.0,
        };
        let d = crate::material::PlaneModel::Stress.elasticity_matrix(&mat);
        let (m, k) = assemble_mass_stiffness(&asm, &geom, &d, &mat, 0.01, false);
        let mut k_ser = asm.zeros();
        asm.assemble_serial_into(&mut k_ser, |e, out| {
            let mut b = [[0.0; 6]; 6];
            tri3::stiffness_into(&geom[e], &d, 0.01, &mut b);
            out.copy_from_slice(b.as_flattened());
        });
        assert_eq!(k, k_ser);
        // Mass: 1^T M 1 over both components is twice the mass rho t A.
        let area: f64 = geom.iter().map(|g| g.area).sum();
        let total: f64 = m.iter().sum::<f64>() / 2.0;
        let exact = 7830.0 * 0.01 * area;
        assert!((total - exact).abs() < 1e-12 * exact, "{total} vs {exact}");
        // Geometric stiffness of a uniform hydrostatic stress p: u^T K_sigma u = p t
        // sum_a int |grad u_a|^2, which is p t |Omega| for u = (x, 0).
        let p = 3.0e6;
        let stress = vec![[p, p, 0.0]; geom.len()];
        let ks = asm.assemble(&Tri3GeometricStiffness {
            geometry: &geom,
            stress: &stress,
            thickness: 0.01,
        });
        let u: Vec<f64> = mesh.points.iter().flat_map(|q| [q[0], 0.0]).collect();
        let mut ku = vec![0.0; u.len()];
        crate::linalg::spmv_into(&asm.pattern, &ks, &u, &mut ku);
        let q: f64 = ku.iter().zip(&u).map(|(a, b)| a * b).sum();
        assert!((q - p * 0.01 * area).abs() < 1e-10 * p * 0.01 * area, "{q}");
    }
}
