//! Operations on a matrix given by its sparsity pattern and values: the pattern type, the
//! Dirichlet identity rows, `y = A x` and `y += s A x`, the quadratic form `x^T A x`, the
//! symmetry test, the positions of the transposed entries and a Matrix Market writer. These
//! are also the plain references the tuned kernels are checked against (module
//! [`super::rhs`]).

use faer::sparse::SymbolicSparseColMat;

/// A square sparse pattern in compressed sparse column form (faer's symbolic matrix).
pub type Pattern = SymbolicSparseColMat<usize>;

/// Replaces the rows and columns of the `fixed` dofs by those of the identity (Dirichlet
/// conditions imposed on a matrix sharing `pattern`; the right-hand side is lifted by the
/// caller).
pub fn set_identity_rows(pattern: &Pattern, values: &mut [f64], fixed: &[bool]) {
    let cp = pattern.col_ptr();
    let ri = pattern.row_idx();
    for j in 0..pattern.ncols() {
        for p in cp[j]..cp[j + 1] {
            let i = ri[p];
            if fixed[i] || fixed[j] {
                values[p] = if i == j { 1.0 } else { 0.0 };
            }
        }
    }
}

/// The contiguous diagonal blocks of a square pattern: the cuts `0 = c_0 < c_1 < ... < c_m =
/// n` such that no entry joins a block `c_k..c_{k+1}` to another. A model of several bodies
/// numbered one after the other (a wheel and its rail, a wheel and its twin) has a step
/// matrix block diagonal by body: a column `A^{-1} e_d` is zero outside `d`'s block. One
/// block (`[0, n]`) when the bodies are joined or interleaved.
pub fn diagonal_blocks(pattern: &Pattern) -> Vec<usize> {
    let n = pattern.ncols();
    let (cp, ri) = (pattern.col_ptr(), pattern.row_idx());
    let rows = |j: usize| ri[cp[j]..cp[j + 1]].iter().copied();
    // A cut at `c` needs no entry in a column below `c` at a row at or above it (the
    // largest row of the columns below `c` is below `c`), and none in a column at or
    // above `c` at a row below it (a pattern need not be symmetric): the least row of the
    // columns from `c` on is `c` or more.
    let mut least = vec![usize::MAX; n + 1];
    for j in (0..n).rev() {
        least[j] = rows(j).fold(j, usize::min).min(least[j + 1]);
    }
    let mut cuts = vec![0];
    let mut high = 0;
    for j in 0..n {
        high = rows(j).fold(high.max(j), usize::max);
        if j + 1 < n && high <= j && least[j + 1] > j {
            cuts.push(j + 1);
        }
    }
    cuts.push(n);
    cuts
}

/// `y = A x` for a CSC matrix given by its pattern and values (overwrites `y`).
pub fn spmv_into(pattern: &Pattern, values: &[f64], x: &[f64], y: &mut [f64]) {
    y.fill(0.0);
    spmv_add(pattern, values, 1.0, x, y);
}

/// `y += s A x` for a CSC matrix.
pub fn spmv_add(pattern: &Pattern, values: &[f64], s: f64, x: &[f64], y: &mut [f64]) {
    let col_ptr = pattern.col_ptr();
    let row_idx = pattern.row_idx();
    for (j, &xj) in x.iter().enumerate() {
        if xj == 0.0 {
            continue;
        }
        let sx = s * xj;
        for p in col_ptr[j]..col_ptr[j + 1] {
            y[row_idx[p]] += values[p] * sx;
        }
    }
}

/// `x^T A x` for a CSC matrix.
pub fn quadratic_form(pattern: &Pattern, values: &[f64], x: &[f64]) -> f64 {
    let col_ptr = pattern.col_ptr();
    let row_idx = pattern.row_idx();
    assert!(x.len() == pattern.ncols() && values.len() >= col_ptr[x.len()]);
    let mut s = 0.0;
    for (j, &xj) in x.iter().enumerate() {
        let range = col_ptr[j]..col_ptr[j + 1];
        s += column_dot(&row_idx[range.clone()], &values[range], x) * xj;
    }
    s
}

/// `(x^T A x, y^T B y)` for two CSC matrices on one pattern, in one pass over it: each
/// form summed exactly as [`quadratic_form`] sums it (the same bits), each column's row
/// indices read once from memory.
pub fn quadratic_forms(
    pattern: &Pattern,
    (a, x): (&[f64], &[f64]),
    (b, y): (&[f64], &[f64]),
) -> (f64, f64) {
    let col_ptr = pattern.col_ptr();
    let row_idx = pattern.row_idx();
    let n = pattern.ncols();
    assert!(x.len() == n && y.len() == n);
    assert!(a.len() >= col_ptr[n] && b.len() >= col_ptr[n]);
    let (mut sa, mut sb) = (0.0, 0.0);
    for j in 0..n {
        let range = col_ptr[j]..col_ptr[j + 1];
        let ri = &row_idx[range.clone()];
        sa += column_dot(ri, &a[range.clone()], x) * x[j];
        sb += column_dot(ri, &b[range], y) * y[j];
    }
    (sa, sb)
}

/// `sum_k va[k] x[ri[k]]` in four partial sums (a dot product with a gather), added as
/// `(s0 + s1) + (s2 + s3)`.
#[inline]
fn column_dot(ri: &[usize], va: &[f64], x: &[f64]) -> f64 {
    let mut acc = [0.0; 4];
    let (ri4, va4) = (ri.chunks_exact(4), va.chunks_exact(4));
    let (ri_rest, va_rest) = (ri4.remainder(), va4.remainder());
    for (ic, vc) in ri4.zip(va4) {
        for k in 0..4 {
            acc[k] += vc[k] * x[ic[k]];
        }
    }
    for (&i, &v) in ri_rest.iter().zip(va_rest) {
        acc[0] += v * x[i];
    }
    (acc[0] + acc[1]) + (acc[2] + acc[3])
}

/// True when the values on `pattern` are symmetric to within `rel_tol` times the largest
/// magnitude (the pattern itself must be structurally symmetric: an entry without its
/// transposed partner makes the matrix unsymmetric).
pub fn is_symmetric(pattern: &Pattern, values: &[f64], rel_tol: f64) -> bool {
    let cp = pattern.col_ptr();
    let ri = pattern.row_idx();
    let scale = values.iter().fold(0.0_f64, |a, v| a.max(v.abs()));
    let tol = rel_tol * scale;
    for j in 0..pattern.ncols() {
        for p in cp[j]..cp[j + 1] {
            let i = ri[p];
            if i <= j {
                continue;
            }
            // Entry (i, j) below the diagonal: find (j, i) in column i.
            let col = &ri[cp[i]..cp[i + 1]];
            match col.binary_search(&j) {
                Ok(q) => {
                    if (values[p] - values[cp[i] + q]).abs() > tol {
                        return false;
                    }
                }
                Err(_) => return false,
            }
        }
    }
    true
}

/// For each stored entry `(i, j)` of `pattern`, the position of `(j, i)`; None when the
/// pattern is not structurally symmetric.
pub fn transpose_positions(pattern: &Pattern) -> Option<Vec<usize>> {
    let (cp, ri) = (pattern.col_ptr(), pattern.row_idx());
    let mut t = vec![0; cp[pattern.ncols()]];
    for j in 0..pattern.ncols() {
        for p in cp[j]..cp[j + 1] {
            let i = ri[p];
            let col = &ri[cp[i]..cp[i + 1]];
            t[p] = cp[i] + col.binary_search(&j).ok()?;
        }
    }
    Some(t)
}

/// Writes the matrix `values` on `pattern` to `out` in Matrix Market coordinate format
/// (`real general`, 1-based indices, every stored entry).
///
/// # Errors
/// I/O errors of `out`.
pub fn write_matrix_market<W: std::io::Write>(
    out: &mut W,
    pattern: &Pattern,
    values: &[f64],
    comment: &str,
) -> std::io::Result<()> {
    let cp = pattern.col_ptr();
    let ri = pattern.row_idx();
    writeln!(out, "%%MatrixMarket matrix coordinate real general")?;
    for line in comment.lines() {
        writeln!(out, "% {line}")?;
    }
    writeln!(
        out,
        "{} {} {}",
        pattern.nrows(),
        pattern.ncols(),
        values.len()
    )?;
    for j in 0..pattern.ncols() {
        for p in cp[j]..cp[j + 1] {
            writeln!(out, "{} {} {:e}", ri[p] + 1, j + 1, values[p])?;
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The pattern of the entries `(i, j)` (rows sorted within each column).
    fn pattern(n: usize, entries: &[(usize, usize)]) -> Pattern {
        let mut cols = vec![Vec::new(); n];
        for &(i, j) in entries {
            cols[j].push(i);
        }
        let mut cp = vec![0];
        let mut ri = Vec::new();
        for mut c in cols {
            c.sort_unstable();
            c.dedup();
            ri.extend(c);
            cp.push(ri.len());
        }
        Pattern::new_checked(n, n, cp, None, ri)
    }

    /// Two bodies one after the other are two blocks, three a chain of three; an entry
    /// joining the first body to the last (either way round: a pattern need not be
    /// symmetric) leaves one block, and a diagonal alone gives a block a dof.
    #[test]
    fn bodies_numbered_in_turn_are_the_blocks() {
        let diag = |n: usize| (0..n).map(|i| (i, i)).collect::<Vec<_>>();
        let mut e = diag(6);
        e.extend([(0, 1), (1, 0), (2, 4), (4, 2), (3, 4), (4, 3), (5, 5)]);
        assert_eq!(diagonal_blocks(&pattern(6, &e)), vec![0, 2, 5, 6]);
        let mut joined = e.clone();
        joined.push((5, 0));
        assert_eq!(diagonal_blocks(&pattern(6, &joined)), vec![0, 6]);
        let mut joined = e.clone();
        joined.push((0, 5));
        assert_eq!(diagonal_blocks(&pattern(6, &joined)), vec![0, 6]);
        let mut bridged = e;
        bridged.push((3, 1));
        assert_eq!(diagonal_blocks(&pattern(6, &bridged)), vec![0, 5, 6]);
        assert_eq!(diagonal_blocks(&pattern(3, &diag(3))), vec![0, 1, 2, 3]);
    }
}
