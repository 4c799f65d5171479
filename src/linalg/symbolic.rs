//! The fill-reducing orderings and the size of a Cholesky factor from the pattern alone
//! (no numeric work): what a cost estimate or a measurement needs before factoring.

use super::{LinalgError, Ordering, Pattern};

/// The permutation `ordering` gives `pattern`: `(fwd, inv)`, `fwd[p]` the unknown at
/// position `p` and `inv` its inverse (AMD and COLAMD are faer's, nested dissection
/// softway's own, module `dissect`).
///
/// # Errors
/// [`LinalgError::Symbolic`] when the ordering fails.
pub fn fill_reducing_ordering(
    pattern: &Pattern,
    ordering: Ordering,
) -> Result<(Vec<usize>, Vec<usize>), LinalgError> {
    super::lu::column_ordering(pattern, ordering)
}

/// Entries of the Cholesky factor `L` of a matrix on `pattern` (structurally symmetric),
/// the diagonal included, in the ordering whose inverse permutation is `inv`: the column
/// counts of the elimination tree's row subtrees, without forming the factor.
pub fn cholesky_factor_nnz(pattern: &Pattern, inv: &[usize]) -> u64 {
    super::split::factor_entries(pattern, inv)
}
