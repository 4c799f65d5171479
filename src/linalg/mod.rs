//! Sparse linear algebra on one sparsity pattern.
//!
//! The map of the module, by concern:
//!
//! - [`sparse`]: the pattern ([`Pattern`]) and the plain operations on a matrix given by it
//!   and its values: `y = A x`, `y += s A x`, `x^T A x`, the Dirichlet identity rows, the
//!   symmetry test, the transposed positions, a Matrix Market writer.
//! - [`solver`]: the solver behind one trait, [`Factorization`] (factor on a pattern,
//!   refactor new values on the same symbolic analysis, solve in place without allocating,
//!   the symbolic analyses and numeric factorizations counted by the factorization itself),
//!   the errors ([`LinalgError`]) and the step matrices' factor [`Factor`].
//! - [`reference`](mod@reference): the reference implementation, faer's own LU and Cholesky with their
//!   generic solves ([`FaerLu`], [`FaerLlt`]).
//! - the tuned implementation, checked against the reference (the tests here,
//!   `tests/factor.rs`): [`SparseLu`] (module `lu`: faer's numeric LU on an ordering
//!   computed once) and [`SparseLlt`] (module `llt`: faer's numeric Cholesky on a shared
//!   symbolic analysis), whose factors are copied for the solves into compact rows (module
//!   `triangle`: supernodes, pairs of rows, blocks of two columns), dense supernodes (module
//!   `supernodal`: packed blocks, narrow and wide kernels, prefetch; on huge pages, module
//!   `huge`), or, from `SPLIT_MIN_ORDER` unknowns on, the split (module `split`: two
//!   independent sets of subtrees of the elimination tree, found with module `bisect`, and
//!   a top; from 50,000 unknowns each part split again, 4 parts, from 200,000 8; each
//!   level's parts solved side by side by module `team`; the parts fixed by the matrix,
//!   never by the threads, so the same bits on any number of them);
//!   their small kernels and prefetch hints in module `kernels`.
//! - [`rhs`]: the space-time step's right-hand side `y = B v0 - h K u0 + h f` as an operator
//!   ([`RhsOperator`]) formed by the tuned kernels, with a plain sparse-product reference.
//! - module `dissect`: the nested dissection ordering ([`Ordering::NestedDissection`], chosen
//!   by [`Ordering::auto`] for large 3D meshes); [`symbolic`]: the orderings and the
//!   Cholesky factor's size from the pattern alone ([`fill_reducing_ordering`],
//!   [`cholesky_factor_nnz`]).
//! - [`dense`]: Gaussian elimination on the small dense systems of the contact rows.
//!
//! The kernels of the time loop (the row solves, the right-hand side) are compiled for the
//! baseline processor and for AVX2, chosen at run time (the macro `with_avx2`).

/// Runs `$avx2` (an unsafe call of a function compiled with `#[target_feature(enable =
/// "avx2")]`, the same code as `$generic`) where the processor has AVX2, else `$generic`.
///
/// The kernels of the time loop (the row solves, the right-hand side) are written once,
/// `#[inline(always)]`, and compiled twice: for the baseline x86-64 (SSE2) and for AVX2,
/// chosen at run time, so that one binary runs everywhere and uses the wider instructions
/// where they exist. Measured on the paper's wheel: the free step 26.0 -> 24.x us. The same
/// operations run in the same order (no fused multiply-add: Rust does not contract), so
/// both give the same result bit for bit.
macro_rules! with_avx2 {
    ($generic:expr, $avx2:expr) => {{
        #[cfg(target_arch = "x86_64")]
        {
            if $crate::linalg::has_avx2() {
                // SAFETY: the processor has AVX2 (checked just above).
                #[allow(unused_unsafe)]
                unsafe {
                    $avx2
                }
            } else {
                $generic
            }
        }
        #[cfg(not(target_arch = "x86_64"))]
        {
            $generic
        }
    }};
}
pub(crate) use with_avx2;

/// A method `$name` that runs the `#[inline(always)]` method `$here` through [`with_avx2`],
/// and `$twin`, the same body compiled for AVX2 (unsafe: the processor must have AVX2).
macro_rules! avx2_method {
    ($(#[$doc:meta])* $vis:vis fn $name:ident / $twin:ident
        (&mut self $(, $a:ident: $t:ty)*) => $here:ident) => {
        $(#[$doc])*
        $vis fn $name(&mut self $(, $a: $t)*) {
            with_avx2!(self.$here($($a),*), self.$twin($($a),*))
        }

        #[doc = concat!("`", stringify!($here), "` compiled for AVX2.")]
        ///
        /// # Safety
        /// The processor must have AVX2.
        #[cfg(target_arch = "x86_64")]
        #[target_feature(enable = "avx2")]
        pub(super) unsafe fn $twin(&mut self $(, $a: $t)*) {
            self.$here($($a),*)
        }
    };
    ($(#[$doc:meta])* $vis:vis fn $name:ident / $twin:ident
        (&self $(, $a:ident: $t:ty)*) => $here:ident) => {
        $(#[$doc])*
        $vis fn $name(&self $(, $a: $t)*) {
            with_avx2!(self.$here($($a),*), self.$twin($($a),*))
        }

        #[doc = concat!("`", stringify!($here), "` compiled for AVX2.")]
        ///
        /// # Safety
        /// The processor must have AVX2.
        #[cfg(target_arch = "x86_64")]
        #[target_feature(enable = "avx2")]
        pub(super) unsafe fn $twin(&self $(, $a: $t)*) {
            self.$here($($a),*)
        }
    };
}

pub mod bandwidth;
mod bisect;
pub mod dense;
mod dissect;
mod huge;
mod kernels;
mod llt;
mod lu;
pub mod reference;
pub mod rhs;
pub mod solver;
pub mod sparse;
mod split;
mod supernodal;
pub mod symbolic;
pub mod team;
mod triangle;

pub use dense::{dense_solve_in_place, DenseLu, BLOCKED_MIN_ROWS};
pub use huge::{HugeBuf, HUGE_MIN_BYTES};
pub(crate) use kernels::{broadcast2, has_avx2, prefetch_span};
pub use llt::SparseLlt;
pub use llt::BLOCK_MIN_RHS;
pub use lu::{Ordering, SparseLu, DISSECTION_MIN_ORDER};
pub use reference::{FaerLlt, FaerLu};
pub use rhs::{rhs_plain_into, BParts, RhsOperator, RhsValues};
pub use solver::{Backend, Factor, FactorKind, Factorization, LinalgError};
pub use sparse::{
    diagonal_blocks, is_symmetric, quadratic_form, quadratic_forms, set_identity_rows, spmv_add,
    spmv_into, transpose_positions, write_matrix_market, Pattern,
};
pub use split::PartWork;
use supernodal::Supernodal;
pub use supernodal::BLOCK_RHS;
pub use symbolic::{cholesky_factor_nnz, fill_reducing_ordering};
use triangle::Triangle;

/// The order from which the column ordering is split into two independent parts and a top
/// (`split::two_subtrees`) for solves on two threads (by rows below
/// `DENSE_SUPERNODAL_MIN_ORDER`, in dense supernodes from it on). The split is made whatever
/// the thread count, so that a run's result does not depend on it. Measured with
/// `softway matrix` (median of five rounds, alternated binaries, twice), the free step by
/// rows, whole against split, on two threads: 2,054 dofs (18 rings) 57 -> 37 us, 3,432
/// (`wheel.toml`) 108 -> 55 us, 7,948 (576 rim nodes) 335 -> 180 us; on one thread the
/// split costs 10-20% (57 -> 62-67, 100 -> 118, 330 -> 338-367 us). On the paper's wheel
/// (938 dofs) it gave 18 against 20 us per free step and nothing in the run's loop.
///
/// From the same order the time loop's other work on whole vectors runs on two threads as
/// well (the right-hand side's halves, the held nodes' columns, the energies): the steps
/// there already hand work to the second thread.
pub(crate) const SPLIT_MIN_ORDER: usize = 1_500;

#[cfg(test)]
mod tests;
