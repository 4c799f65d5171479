//! The split factor in `2^d` parts: the solves of four and eight parts against two parts'
//! (residuals), the same bits on any number of threads, the parts' independence.

use super::super::llt::{SparseLlt, StoredLower};
use super::super::lu::{Ordering, SparseLu, Stored};
use super::super::team::{Par, Team};
use super::super::{spmv_into, Pattern};
use super::Shape;
use faer::sparse::linalg::cholesky::SymbolicCholeskyRaw;
use faer::sparse::Triplet;

/// A matrix on a box of `m^3` nodes with three unknowns each, every node coupled to its 26
/// neighbours by 3 x 3 blocks of pseudo-random values in `[-1, 0)` (a linear congruential
/// generator, Knuth's MMIX constants), `symmetric` or not (then the two blocks of a pair
/// drawn apart), its diagonal `1 +` the sum of its row's magnitudes: strictly diagonally
/// dominant (positive definite when symmetric).
fn box_matrix(m: usize, symmetric: bool) -> (Pattern, Vec<f64>) {
    let mut state = 0x2545_f491_4f6c_dd1d_u64;
    let mut draw = move || {
        state = state
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        -(((state >> 11) as f64) / (1u64 << 53) as f64) - 1e-3
    };
    let node = |x: usize, y: usize, z: usize| x + m * (y + m * z);
    let n = 3 * m * m * m;
    let mut t: Vec<Triplet<usize, usize, f64>> = Vec::new();
    for z in 0..m {
        for y in 0..m {
            for x in 0..m {
                let a = node(x, y, z);
                // Each pair once: the neighbours after `a` in the node numbering.
                for (dx, dy, dz) in (0..27).map(|k| (k % 3, (k / 3) % 3, k / 9)) {
                    let (xb, yb, zb) = (x + dx, y + dy, z + dz);
                    if xb < 1 || yb < 1 || zb < 1 || xb > m || yb > m || zb > m {
                        continue;
                    }
                    let b = node(xb - 1, yb - 1, zb - 1);
                    if b <= a {
                        continue;
                    }
                    for (da, db) in (0..9).map(|k| (k % 3, k / 3)) {
                        let (i, j) = (3 * a + da, 3 * b + db);
                        let v = draw();
                        let w = if symmetric { v } else { draw() };
                        t.push(Triplet::new(i, j, v));
                        t.push(Triplet::new(j, i, w));
                    }
                }
            }
        }
    }
    let mut row_sum = vec![0.0; n];
    for e in &t {
        row_sum[e.row] += e.val.abs();
    }
    for (i, s) in row_sum.iter().enumerate() {
        t.push(Triplet::new(i, i, 1.0 + s));
    }
    let a = faer::sparse::SparseColMat::<usize, f64>::try_new_from_triplets(n, n, &t).unwrap();
    (a.symbolic().to_owned().unwrap(), a.val().to_vec())
}

fn rhs(n: usize) -> Vec<f64> {
    (0..n)
        .map(|i| ((i * 7919) % 1000) as f64 / 500.0 - 1.0)
        .collect()
}

/// The normwise backward error `|A x - b|_inf / (|A|_inf |x|_inf + |b|_inf)` (Rigal and
/// Gaches, 1967).
fn backward_error(pattern: &Pattern, values: &[f64], x: &[f64], b: &[f64]) -> f64 {
    let mut ax = vec![0.0; b.len()];
    spmv_into(pattern, values, x, &mut ax);
    let inf = |v: &[f64]| v.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    let r: Vec<f64> = ax.iter().zip(b).map(|(p, q)| p - q).collect();
    let (cp, ri) = (pattern.col_ptr(), pattern.row_idx());
    let mut rows = vec![0.0; b.len()];
    for j in 0..pattern.ncols() {
        for p in cp[j]..cp[j + 1] {
            rows[ri[p]] += values[p].abs();
        }
    }
    inf(&r) / (inf(&rows) * inf(x) + inf(b))
}

/// A factor of `2^depth` parts (Cholesky or LU on nested dissection), by rows
/// or in dense supernodes.
enum Built {
    Llt(SparseLlt),
    Lu(SparseLu),
}

impl Built {
    fn new(pattern: &Pattern, values: &[f64], lu: bool, depth: usize, dense: bool) -> Self {
        if lu {
            let f =
                SparseLu::build_depth(pattern, values, Ordering::NestedDissection, depth).unwrap();
            Built::Lu(f.with_layout(pattern, values, dense))
        } else {
            let o = Ordering::NestedDissection;
            let f = SparseLlt::build_ordered(pattern, values, o, depth, false).unwrap();
            Built::Llt(f.with_layout(pattern, values, dense))
        }
    }

    /// The parts' orders, checking that the factor is stored in them.
    fn part_orders(&self) -> Vec<usize> {
        match self {
            Built::Llt(f) => {
                assert!(matches!(f.stored, Some(StoredLower::Split(_))));
                f.part_orders().unwrap()
            }
            Built::Lu(f) => {
                assert!(matches!(f.stored, Some(Stored::Split(_))));
                f.part_orders().unwrap()
            }
        }
    }

    fn solve(&mut self, team: &Team, b: &[f64]) -> Vec<f64> {
        let mut x = b.to_vec();
        match self {
            Built::Llt(f) => f.solve_on(team, &mut x),
            Built::Lu(f) => f.solve_on(team, &mut x),
        }
        x
    }

    fn factor_nnz(&self) -> usize {
        match self {
            Built::Llt(f) => f.factor_nnz(),
            Built::Lu(f) => f.factor_nnz(),
        }
    }
}

/// On a box of 11^3 nodes (3,993 unknowns), symmetric positive definite (Cholesky on nested
/// dissection) and unsymmetric (LU on nested dissection), by rows and in dense supernodes: the ordering
/// splits into 4 and 8 parts (7 and 15 with the separators, every leaf at least a fifth of
/// the mean leaf), the Cholesky factor has the two parts' entries exactly (a reordering
/// that keeps every column after its descendants keeps the fill), and the solves' backward
/// errors are at round-off and within ten times the two parts' (their solutions within
/// 1e-12 of each other, the matrices being well conditioned by their diagonal dominance).
#[test]
fn four_and_eight_parts_solve_as_two() {
    for lu in [false, true] {
        let (pattern, values) = box_matrix(11, !lu);
        let n = pattern.nrows();
        let b = rhs(n);
        for dense in [false, true] {
            let what = format!("lu {lu}, dense {dense}");
            let mut two = Built::new(&pattern, &values, lu, 1, dense);
            assert_eq!(two.part_orders().len(), 3, "{what}");
            let x2 = two.solve(&Team::new(Par::Seq), &b);
            let e2 = backward_error(&pattern, &values, &x2, &b);
            assert!(e2 < 1e-15, "{what}: two parts' backward error {e2:e}");
            for depth in [2, 3] {
                let mut f = Built::new(&pattern, &values, lu, depth, dense);
                let orders = f.part_orders();
                let leaves = 1 << depth;
                assert_eq!(orders.len(), 2 * leaves - 1, "{what}: {orders:?}");
                assert_eq!(orders.iter().sum::<usize>(), n);
                let mean = orders[..leaves].iter().sum::<usize>() / leaves;
                assert!(
                    orders[..leaves].iter().all(|&o| 5 * o >= mean),
                    "{what}: leaves {orders:?}"
                );
                if !lu {
                    assert_eq!(f.factor_nnz(), two.factor_nnz(), "{what}: the fill");
                }
                let x = f.solve(&Team::new(Par::Seq), &b);
                let e = backward_error(&pattern, &values, &x, &b);
                assert!(
                    e < 1e-15 && e <= 10.0 * e2,
                    "{what}, {leaves} parts: backward error {e:e} against {e2:e}"
                );
                let d = x
                    .iter()
                    .zip(&x2)
                    .fold(0.0f64, |m, (p, q)| m.max((p - q).abs() / q.abs().max(1.0)));
                assert!(d < 1e-12, "{what}, {leaves} parts: {d:e} from two parts'");
            }
        }
    }
}

/// With 4 and 8 parts the solution is the same bits on 1, 2, 3 and 4 threads (a team of
/// that many, used whatever the machine's cores), by rows and in dense supernodes, for
/// Cholesky and LU, solved three times each.
#[test]
fn the_parts_give_the_same_bits_on_any_number_of_threads() {
    for lu in [false, true] {
        let (pattern, values) = box_matrix(10, !lu);
        let b = rhs(pattern.nrows());
        for dense in [false, true] {
            for depth in [2, 3] {
                let mut f = Built::new(&pattern, &values, lu, depth, dense);
                assert_eq!(f.part_orders().len(), (2 << depth) - 1);
                let one = f.solve(&Team::new(Par::Seq), &b);
                for threads in 2..=4 {
                    let team = Team::oversubscribed(Par::threads(threads));
                    for _ in 0..3 {
                        let x = f.solve(&team, &b);
                        assert!(
                            x.iter().zip(&one).all(|(p, q)| p.to_bits() == q.to_bits()),
                            "lu {lu}, dense {dense}, depth {depth}: {threads} threads"
                        );
                    }
                }
            }
        }
    }
}

/// In the Cholesky factor's structure (faer's simplicial analysis on the split ordering),
/// every column of a part has its rows in that part and its ancestors only: no entry of one
/// leaf's columns lies in another leaf's rows or in a separator above another branch. The
/// LU's factors are stored in the parts too (their storage refuses a row outside them).
#[test]
fn the_parts_are_independent() {
    let (pattern, values) = box_matrix(10, true);
    for depth in [1, 2, 3] {
        let o = Ordering::NestedDissection;
        let llt = SparseLlt::build_ordered(&pattern, &values, o, depth, false).unwrap();
        let bounds = llt.parts.clone().expect("a split");
        let shape = Shape::of(bounds.len() - 1);
        assert_eq!(shape.depth, depth);
        let part_of = |i: usize| bounds.partition_point(|&e| e <= i) - 1;
        let SymbolicCholeskyRaw::Simplicial(simp) = llt.symbolic.raw() else {
            panic!("a simplicial analysis");
        };
        let (cp, ri) = (simp.col_ptr(), simp.row_idx());
        let mut foreign = 0;
        for j in 0..pattern.ncols() {
            let k = part_of(j);
            for &i in &ri[cp[j]..cp[j + 1]] {
                let p = part_of(i);
                if p != k && !shape.ancestors(k).any(|a| a == p) {
                    foreign += 1;
                }
            }
        }
        assert_eq!(
            foreign, 0,
            "depth {depth}: entries outside a part's ancestors"
        );
        let lu =
            SparseLu::build_depth(&pattern, &values, Ordering::NestedDissection, depth).unwrap();
        assert!(
            matches!(lu.stored, Some(Stored::Split(_))),
            "LU at depth {depth}"
        );
        assert_eq!(lu.part_orders().unwrap().len(), (2 << depth) - 1);
    }
}

/// The shape of a tree of depth 2 in the split's order `[l0 l1 l2 l3 s0 s1 r]`.
#[test]
fn the_tree_of_seven_parts_is_numbered_level_by_level() {
    let s = Shape::of(7);
    assert_eq!(s.depth, 2);
    assert_eq!((0..7).map(|k| s.parent(k)).collect::<Vec<_>>(), {
        let p = |k| Some(k);
        vec![p(4), p(4), p(5), p(5), p(6), p(6), None]
    });
    assert_eq!(s.children(6), Some([4, 5]));
    assert_eq!(s.children(5), Some([2, 3]));
    assert_eq!(s.children(1), None);
    assert_eq!(s.ancestors(2).collect::<Vec<_>>(), [5, 6]);
    assert_eq!(
        (0..6).map(|k| s.half(k)).collect::<Vec<_>>(),
        [0, 0, 1, 1, 0, 1]
    );
}
