use super::kernels::blocks_dot;
#[cfg(target_arch = "x86_64")]
use super::kernels::blocks_dot_avx2;
use super::llt::StoredLower;
use super::lu::column_ordering;
use super::lu::Stored;
use super::solver::Counts;
use super::supernodal::DENSE_SUPERNODAL_MIN_ORDER;
use super::team::{self, Team};
use super::triangle::{Segment, Triangle, MIN_SUPERNODE};
use super::*;
use faer::sparse::linalg::cholesky::SymbolicCholeskyRaw;
use faer::sparse::Triplet;

/// A structurally symmetric, unsymmetric matrix with two unknowns per node (a ring of
/// nodes, each coupled to its neighbours and to a hub), skew terms as a Coriolis matrix
/// makes them; diagonally dominant. Returns the pattern, the values and, if
/// `symmetric`, no skew terms.
fn test_matrix(nodes: usize, symmetric: bool) -> (Pattern, Vec<f64>) {
    let n = 2 * nodes;
    let mut t: Vec<Triplet<usize, usize, f64>> = Vec::new();
    let mut couple = |a: usize, b: usize, w: f64| {
        for (da, db) in [(0, 0), (0, 1), (1, 0), (1, 1)] {
            let (i, j) = (2 * a + da, 2 * b + db);
            let skew = if symmetric || a == b { 0.0 } else { 0.01 * w };
            let v = -w * (1.0 + 0.1 * (da + 2 * db) as f64);
            t.push(Triplet::new(i, j, v + skew));
            t.push(Triplet::new(j, i, v - skew));
        }
    };
    for a in 0..nodes {
        couple(a, (a + 1) % nodes, 1.0 + 0.3 * (a as f64).sin());
        couple(a, (a + 7) % nodes, 0.5);
        if a % 5 == 0 {
            couple(a, 0, 0.2);
        }
    }
    // The diagonal dominates the rows; the skew part of each node's own block.
    let mut row_sum = vec![0.0; n];
    for e in &t {
        row_sum[e.row] += e.val.abs();
    }
    for (i, s) in row_sum.iter().enumerate() {
        t.push(Triplet::new(i, i, 1.0 + s));
    }
    for a in 0..nodes {
        if !symmetric {
            t.push(Triplet::new(2 * a, 2 * a + 1, 0.05));
            t.push(Triplet::new(2 * a + 1, 2 * a, -0.05));
        }
    }
    let m = faer::sparse::SparseColMat::<usize, f64>::try_new_from_triplets(n, n, &t).unwrap();
    (m.symbolic().to_owned().unwrap(), m.val().to_vec())
}

/// The matrix of `test_matrix`'s kind on a grid of `nx` by `ny` nodes (each coupled to
/// its right, upper and upper-right neighbours): a planar graph, whose elimination tree
/// branches as a mesh's does.
fn grid_matrix(nx: usize, ny: usize) -> (Pattern, Vec<f64>) {
    grid_matrix_skew(nx, ny, 0.01)
}

/// The same with the skew part `skew` (0: symmetric positive definite).
fn grid_matrix_skew(nx: usize, ny: usize, skew: f64) -> (Pattern, Vec<f64>) {
    let n = 2 * nx * ny;
    let mut t: Vec<Triplet<usize, usize, f64>> = Vec::new();
    let node = |x: usize, y: usize| x + nx * y;
    for y in 0..ny {
        for x in 0..nx {
            for (dx, dy, w) in [(1, 0, 1.0), (0, 1, 0.8), (1, 1, 0.3)] {
                if x + dx >= nx || y + dy >= ny {
                    continue;
                }
                let (a, b) = (node(x, y), node(x + dx, y + dy));
                for (da, db) in [(0, 0), (0, 1), (1, 0), (1, 1)] {
                    let (i, j) = (2 * a + da, 2 * b + db);
                    let v = -w * (1.0 + 0.1 * (da + 2 * db) as f64);
                    t.push(Triplet::new(i, j, v + skew * w));
                    t.push(Triplet::new(j, i, v - skew * w));
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
    let m = faer::sparse::SparseColMat::<usize, f64>::try_new_from_triplets(n, n, &t).unwrap();
    (m.symbolic().to_owned().unwrap(), m.val().to_vec())
}

/// The factor `build(split)` with and without the split into two
/// independent parts and a top: the parts are balanced, the fill is that of AMD or,
/// when the split took the graph's bisection, within 5% of it, the solve reproduces
/// faer's LU to 1e-13, and its result is the same, bit for bit, on one thread and on two.
fn split_solves_alike(pattern: &Pattern, values: &[f64], build: impl Fn(bool) -> Factor) {
    let n = pattern.nrows();
    let b = rhs(n);
    let x_ref = faer_solve(pattern, values, &b);
    let whole = build(false);
    assert!(whole.parts().is_none());
    let mut split = build(true);
    let kind = split.kind();
    let (p0, p1, top) = split.parts().expect("a split ordering");
    assert_eq!(p0 + p1 + top, n);
    assert!(
        p0.min(p1) * 3 > p0.max(p1) && top * 10 < n,
        "{kind:?}: parts of {p0} and {p1} unknowns, top {top}"
    );
    let (fill, amd) = (split.factor_nnz(), whole.factor_nnz());
    assert!(
        20 * fill <= 21 * amd,
        "{kind:?}: fill {fill} against AMD's {amd}"
    );
    let mut on = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        let mut x = b.clone();
        pool.install(|| split.solve_in_place(&mut x));
        x
    };
    let (x1, x2) = (on(1), on(2));
    assert!(x1.iter().zip(&x2).all(|(p, q)| p.to_bits() == q.to_bits()));
    // On a team of the caller's thread and its own helper.
    let mut x3 = b.clone();
    split.solve_on(&Team::new(team::Par::threads(2)), &mut x3);
    assert!(x1.iter().zip(&x3).all(|(p, q)| p.to_bits() == q.to_bits()));
    let d = max_rel_diff(&x1, &x_ref);
    assert!(d < 1e-13, "{kind:?} split against faer's LU: {d:e}");
}

/// Two disconnected copies of a grid: their elimination trees are two equal subtrees, so
/// the split puts one copy in each part and leaves no top.
#[test]
fn two_disconnected_grids_split_into_the_two_without_a_top() {
    let (p1, v1) = grid_matrix(12, 9);
    let m = p1.nrows();
    let mut t: Vec<Triplet<usize, usize, f64>> = Vec::new();
    for copy in 0..2 {
        for j in 0..m {
            for q in p1.col_ptr()[j]..p1.col_ptr()[j + 1] {
                let i = p1.row_idx()[q];
                t.push(Triplet::new(copy * m + i, copy * m + j, v1[q]));
            }
        }
    }
    let mat =
        faer::sparse::SparseColMat::<usize, f64>::try_new_from_triplets(2 * m, 2 * m, &t).unwrap();
    let pattern = mat.symbolic().to_owned().unwrap();
    let (fwd, inv) = column_ordering(&pattern, Ordering::Amd).unwrap();
    let split::Split {
        fwd: new_fwd,
        bounds,
        ..
    } = split::two_subtrees(&pattern, &fwd, &inv).expect("a split");
    assert_eq!(
        bounds,
        [0, m, 2 * m, 2 * m],
        "the parts of {} unknowns",
        2 * m
    );
    let copy_of = |k: usize| new_fwd[k] / m;
    assert!((1..m).all(|k| copy_of(k) == copy_of(0)));
    assert!((m + 1..2 * m).all(|k| copy_of(k) == copy_of(m)));
    assert_ne!(copy_of(0), copy_of(m));
}

/// On the hexagonal disk of 48 rings (14,114 unknowns) AMD's split has a top of 456
/// unknowns, the chain of its last eliminations. The split taken is the bisection's,
/// whose top is about the separator across a diameter, `2 (2 r + 1)` unknowns: a
/// shorter critical path for a fill within 2% of AMD's.
#[test]
fn the_disk_is_split_across_a_diameter() {
    use crate::bodies::wheel::{Support, WheelModel, WheelSpec};
    use crate::mesh::generators::disk_rings;
    let rings = 48;
    let spec = WheelSpec {
        support: Support::CentrePinned,
        ..WheelSpec::paper()
    };
    let w = WheelModel::new(disk_rings(0.1, rings).unwrap(), spec).unwrap();
    let pattern = w.model.pattern();
    let n = pattern.ncols();
    let (fwd, inv) = column_ordering(pattern, Ordering::Amd).unwrap();
    let own = split::two_subtrees(pattern, &fwd, &inv).expect("AMD's split");
    let best = split::best_split(pattern, &fwd, &inv).expect("a split");
    let diameter = 2 * (2 * rings + 1);
    let (top, own_top) = (n - best.bounds[2], n - own.bounds[2]);
    assert!(
        best.critical < own.critical && 2 * top <= 3 * diameter,
        "top {top} (AMD's {own_top}), critical path {} (AMD's {})",
        best.critical,
        own.critical
    );
    assert!(50 * best.entries <= 51 * own.entries);
}

/// By rows and in dense supernodes.
#[test]
fn split_factor_solves_alike_on_one_thread_and_two() {
    let (pattern, values) = grid_matrix(60, 50);
    for dense in [false, true] {
        split_solves_alike(&pattern, &values, |split| {
            Factor::Lu(
                SparseLu::build(&pattern, &values, Ordering::Amd, split)
                    .unwrap()
                    .with_layout(&pattern, &values, dense),
            )
        });
    }
}

/// The same for the Cholesky factor of a symmetric matrix.
#[test]
fn split_cholesky_solves_alike_on_one_thread_and_two() {
    let (pattern, values) = grid_matrix_skew(60, 50, 0.0);
    for dense in [false, true] {
        split_solves_alike(&pattern, &values, |split| {
            Factor::Llt(
                SparseLlt::build(&pattern, &values, split)
                    .unwrap()
                    .with_layout(&pattern, &values, dense),
            )
        });
    }
}

/// The same for a system large enough for dense supernodes, LU and Cholesky.
#[test]
fn large_split_solves_alike_on_one_thread_and_two() {
    let (pattern, values) = grid_matrix_skew(160, 160, 0.0);
    assert!(pattern.nrows() >= DENSE_SUPERNODAL_MIN_ORDER);
    split_solves_alike(&pattern, &values, |split| {
        Factor::Llt(SparseLlt::build(&pattern, &values, split).unwrap())
    });
    let (pattern, values) = grid_matrix_skew(160, 160, 0.01);
    split_solves_alike(&pattern, &values, |split| {
        Factor::Lu(SparseLu::build(&pattern, &values, Ordering::Amd, split).unwrap())
    });
}

/// The solves compiled for AVX2 (chosen at run time) give the baseline's result bit for
/// bit: the same operations in the same order, by rows and in dense supernodes, LU and
/// Cholesky.
#[test]
fn avx2_solves_match_the_baseline_bit_for_bit() {
    #[cfg(target_arch = "x86_64")]
    if std::is_x86_feature_detected!("avx2") {
        for symmetric in [false, true] {
            let (pattern, values) = test_matrix(300, symmetric);
            let b = rhs(pattern.nrows());
            let same =
                |x: &[f64], y: &[f64]| x.iter().zip(y).all(|(p, q)| p.to_bits() == q.to_bits());
            for dense in [false, true] {
                let mut lu = SparseLu::new(&pattern, &values)
                    .unwrap()
                    .with_layout(&pattern, &values, dense);
                let (mut x, mut y) = (b.clone(), b.clone());
                // The baseline without the AVX2 block kernel (`blocks_dot`).
                (lu.l.avx2, lu.u.avx2) = (false, false);
                lu.solve_here(&Team::default(), &mut x);
                (lu.l.avx2, lu.u.avx2) = (true, true);
                // SAFETY: the processor has AVX2 (checked above).
                unsafe { lu.solve_avx2(&Team::default(), &mut y) };
                assert!(same(&x, &y), "LU, dense {dense}");
                if symmetric {
                    let mut llt = SparseLlt::new(&pattern, &values)
                        .unwrap()
                        .with_layout(&pattern, &values, dense);
                    let (mut x, mut y) = (b.clone(), b.clone());
                    (llt.l.avx2, llt.lt.avx2) = (false, false);
                    llt.solve_here(&Team::default(), &mut x);
                    (llt.l.avx2, llt.lt.avx2) = (true, true);
                    // SAFETY: as above.
                    unsafe { llt.solve_avx2(&Team::default(), &mut y) };
                    assert!(same(&x, &y), "Cholesky, dense {dense}");
                }
            }
        }
    }
}

/// The AVX2 block kernel gives the bits of the portable one, for every number of
/// blocks (odd counts take its remainder path), and the dot products they stand for.
#[test]
fn block_kernel_matches_the_portable_one_bit_for_bit() {
    let n = 40;
    let x: Vec<f64> = (0..n).map(|i| (0.7 * i as f64).cos() * 1e3).collect();
    for len in 0..12 {
        let idx: Vec<u32> = (0..len).map(|k| ((7 * k + 3) % (n - 1)) as u32).collect();
        let val: Vec<[f64; 4]> = (0..len)
            .map(|k| {
                let f = |l: usize| ((k * 4 + l) as f64 * 0.91).sin() / 3.0;
                [f(0), f(1), f(2), f(3)]
            })
            .collect();
        let s = blocks_dot(&idx, &val, &x);
        // Row r0's dot product is s[0] + s[1], row r0 + 1's s[2] + s[3].
        let (mut r0, mut r1) = (0.0, 0.0);
        for (&c, v) in idx.iter().zip(&val) {
            let c = c as usize;
            r0 += v[0] * x[c] + v[1] * x[c + 1];
            r1 += v[2] * x[c] + v[3] * x[c + 1];
        }
        let scale = x.iter().map(|v| v.abs()).sum::<f64>();
        assert!(((s[0] + s[1]) - r0).abs() <= 1e-14 * scale, "{len} blocks");
        assert!(((s[2] + s[3]) - r1).abs() <= 1e-14 * scale, "{len} blocks");
        #[cfg(target_arch = "x86_64")]
        if std::is_x86_feature_detected!("avx2") {
            // SAFETY: the processor has AVX2 and every `c + 1 < n`.
            let t = unsafe { blocks_dot_avx2(&idx, &val, &x) };
            let bits = |a: [f64; 4]| a.map(f64::to_bits);
            assert_eq!(bits(s), bits(t), "{len} blocks");
        }
    }
}

fn rhs(n: usize) -> Vec<f64> {
    (0..n).map(|i| (0.37 * i as f64).sin() + 0.1).collect()
}

fn max_rel_diff(x: &[f64], y: &[f64]) -> f64 {
    let scale = y.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    x.iter()
        .zip(y)
        .fold(0.0_f64, |m, (a, b)| m.max((a - b).abs()))
        / scale
}

/// faer's own LU and solve: the reference ([`FaerLu`]).
/// The dense supernodal layout on a mesh-like grid solves as faer's LU does (1e-13)
/// through supernodes of every narrow width (the one-pass kernels, `W < 8`) and wide
/// ones (four columns per pass, with a remainder), for the LU and the Cholesky factor;
/// the AVX2 copies of the sweeps give the baseline's bits.
#[test]
fn narrow_and_wide_supernodes_solve_alike() {
    for symmetric in [false, true] {
        let (pattern, values) = grid_matrix_skew(14, 14, if symmetric { 0.0 } else { 0.01 });
        let n = pattern.nrows();
        let b = rhs(n);
        let x_ref = faer_solve(&pattern, &values, &b);
        let kind = if symmetric {
            FactorKind::Llt
        } else {
            FactorKind::Lu(Ordering::Amd)
        };
        let f = match Factor::new(&pattern, &values, kind).unwrap() {
            Factor::Lu(lu) => Factor::Lu(lu.with_layout(&pattern, &values, true)),
            Factor::Llt(l) => Factor::Llt(l.with_layout(&pattern, &values, true)),
            _ => unreachable!("softway's kinds"),
        };
        let sn = match &f {
            Factor::Lu(SparseLu {
                stored: Some(Stored::Supernodes(lu)),
                ..
            }) => lu.0.clone(),
            Factor::Llt(SparseLlt {
                stored: Some(StoredLower::Supernodes(l)),
                ..
            }) => l.clone(),
            _ => panic!("no dense layout"),
        };
        let mut widths: Vec<usize> = sn.bounds.windows(2).map(|w| w[1] - w[0]).collect();
        widths.sort_unstable();
        widths.dedup();
        assert!(
            widths.iter().filter(|&&w| w < 8).count() >= 3
                && widths.iter().any(|&w| w >= 8 && w % 4 != 0),
            "widths {widths:?}"
        );
        // Packed blocks hold the factor's entries and nothing else (no zeros above the
        // diagonals), and a solve reads them twice for Cholesky, once each for LU.
        assert_eq!(sn.blk.len(), sn.nnz);
        let sn_bytes = sn.bytes();
        assert!(
            sn_bytes > 8 * sn.nnz && sn_bytes < 10 * sn.nnz,
            "{sn_bytes}"
        );
        match &f {
            Factor::Llt(_) => assert_eq!(f.solve_bytes(), 2 * sn_bytes),
            Factor::Lu(SparseLu {
                stored: Some(Stored::Supernodes(lu)),
                ..
            }) => assert_eq!(f.solve_bytes(), sn_bytes + lu.1.bytes()),
            Factor::Lu(_) => unreachable!("dense layout above"),
            _ => unreachable!("softway's kinds"),
        }
        // The prefetch (on for factors that stream from memory) is a hint: the same bits.
        let (mut x, mut y) = (b.clone(), b.clone());
        let mut with = sn.clone();
        with.prefetch = true;
        let mut without = sn.clone();
        without.prefetch = false;
        with.forward(&mut x);
        with.backward(&mut x);
        without.forward(&mut y);
        without.backward(&mut y);
        assert!(x.iter().zip(&y).all(|(p, q)| p.to_bits() == q.to_bits()));
        #[cfg(target_arch = "x86_64")]
        if std::is_x86_feature_detected!("avx2") {
            let mut sn = sn;
            let (mut x, mut y) = (b.clone(), b.clone());
            sn.forward_here(&mut x);
            sn.backward_here(&mut x);
            // SAFETY: the processor has AVX2 (checked above).
            unsafe {
                sn.forward_avx2(&mut y);
                sn.backward_avx2(&mut y);
            }
            assert!(x.iter().zip(&y).all(|(p, q)| p.to_bits() == q.to_bits()));
        }
        let mut f = f;
        let mut x = b.clone();
        f.solve_in_place(&mut x);
        let d = max_rel_diff(&x, &x_ref);
        assert!(d < 1e-13, "symmetric {symmetric}: {d:e}");
    }
}

/// faer's supernodal Cholesky (used from 10,000 dofs on), converted to columns, gives
/// the simplicial factor's columns (the relaxed supernodes' zeros left out: the same
/// stored entries) and solves as faer's LU does, by rows, in dense supernodes and split.
#[test]
fn supernodal_cholesky_gives_the_simplicial_columns() {
    let (pattern, values) = grid_matrix_skew(16, 15, 0.0);
    let b = rhs(pattern.nrows());
    let x_ref = faer_solve(&pattern, &values, &b);
    for split in [false, true] {
        let simplicial = SparseLlt::build_with(&pattern, &values, split, false).unwrap();
        for dense in [false, true] {
            let mut f = SparseLlt::build_with(&pattern, &values, split, true)
                .unwrap()
                .with_layout(&pattern, &values, dense);
            assert!(matches!(
                f.symbolic.raw(),
                SymbolicCholeskyRaw::Supernodal(_)
            ));
            assert_eq!(f.factor_nnz(), simplicial.factor_nnz(), "split {split}");
            let mut x = b.clone();
            f.solve_in_place(&mut x);
            let d = max_rel_diff(&x, &x_ref);
            assert!(d < 1e-13, "split {split}, dense {dense}: {d:e}");
        }
    }
}

/// `Factor::auto`: a Cholesky on a symmetric positive definite matrix, an LU on an
/// unsymmetric one and on a symmetric indefinite one, each solving as faer's LU does.
#[test]
fn auto_factor_chooses_by_symmetry_and_definiteness() {
    let (pattern, spd) = test_matrix(60, true);
    let (unsym_pattern, unsym) = test_matrix(60, false);
    // Indefinite: the diagonal of one node's dofs negated (still regular).
    let mut indef = spd.clone();
    let (cp, ri) = (pattern.col_ptr(), pattern.row_idx());
    for j in [10, 11] {
        for p in cp[j]..cp[j + 1] {
            if ri[p] == j {
                indef[p] = -indef[p];
            }
        }
    }
    let b = rhs(pattern.nrows());
    for (pattern, values, cholesky) in [
        (&pattern, &spd, true),
        (&unsym_pattern, &unsym, false),
        (&pattern, &indef, false),
    ] {
        let mut f = Factor::auto(pattern, values).unwrap();
        assert_eq!(f.kind() == FactorKind::Llt, cholesky, "{:?}", f.kind());
        let mut x = b.clone();
        f.solve_in_place(&mut x);
        let d = max_rel_diff(&x, &faer_solve(pattern, values, &b));
        assert!(d < 1e-12, "{:?}: {d:e}", f.kind());
    }
}

fn faer_solve(pattern: &Pattern, values: &[f64], b: &[f64]) -> Vec<f64> {
    let mut x = b.to_vec();
    FaerLu::new(pattern, values).unwrap().solve_in_place(&mut x);
    x
}

use SparseLlt as LltLayout;
use SparseLu as LuLayout;

fn widest_rows(t: &Triangle) -> usize {
    t.segments
        .iter()
        .filter(|s| matches!(s.2, Segment::Super(_)))
        .map(|s| s.1 - s.0)
        .max()
        .unwrap_or(0)
}

/// The supernodal row solves (LU with either ordering, Cholesky) reproduce faer's LU
/// and its solve to 1e-13 relative, and their factors have supernodes of several rows
/// and, by rows, pairs of rows solved together.
#[test]
fn supernodal_solves_reproduce_faers_lu() {
    for (nodes, symmetric) in [(40, false), (300, false), (300, true)] {
        let (pattern, values) = test_matrix(nodes, symmetric);
        let n = 2 * nodes;
        let b = rhs(n);
        let x_ref = faer_solve(&pattern, &values, &b);
        let mut kinds = vec![
            FactorKind::Lu(Ordering::Amd),
            FactorKind::Lu(Ordering::Colamd),
        ];
        if symmetric {
            kinds.push(FactorKind::Llt);
        }
        for kind in kinds {
            for dense in [false, true] {
                let f = Factor::new(&pattern, &values, kind).unwrap();
                let mut f = match f {
                    Factor::Lu(lu) => Factor::Lu(lu.with_layout(&pattern, &values, dense)),
                    Factor::Llt(l) => Factor::Llt(l.with_layout(&pattern, &values, dense)),
                    _ => unreachable!("softway's kinds"),
                };
                let mut x = b.clone();
                f.solve_in_place(&mut x);
                let d = max_rel_diff(&x, &x_ref);
                assert!(d < 1e-13, "{nodes} nodes, {kind:?}, dense {dense}: {d:e}");
                // The supernodes of the elimination: several columns of `L` (rows of
                // `U`) that share their rows.
                let widest = match &f {
                    Factor::Lu(LuLayout {
                        stored: Some(Stored::Supernodes(lu)),
                        ..
                    }) => lu.1.bounds.windows(2).map(|w| w[1] - w[0]).max().unwrap(),
                    Factor::Llt(LltLayout {
                        stored: Some(StoredLower::Supernodes(ut)),
                        ..
                    }) => ut.bounds.windows(2).map(|w| w[1] - w[0]).max().unwrap(),
                    Factor::Lu(lu) => widest_rows(&lu.u),
                    Factor::Llt(llt) => widest_rows(&llt.lt),
                    _ => unreachable!("softway's kinds"),
                };
                assert!(
                    widest >= MIN_SUPERNODE,
                    "{nodes} nodes, {kind:?}: no supernode"
                );
                // The row layout also solves pairs of rows (a node's two dofs) together.
                let pairs = |t: &Triangle| {
                    t.segments
                        .iter()
                        .filter(|s| matches!(s.2, Segment::Pair(_)))
                        .count()
                };
                let pairs = match &f {
                    Factor::Lu(lu) if !dense => pairs(&lu.l) + pairs(&lu.u),
                    Factor::Llt(llt) if !dense => pairs(&llt.l) + pairs(&llt.lt),
                    _ => 1,
                };
                assert!(pairs > 0, "{nodes} nodes, {kind:?}: no pair of rows");
                // And, in pairs, blocks of two columns (a neighbouring node's dofs).
                let blocks = match &f {
                    Factor::Lu(lu) if !dense => lu.l.blk_idx.len() + lu.u.blk_idx.len(),
                    Factor::Llt(llt) if !dense => llt.l.blk_idx.len() + llt.lt.blk_idx.len(),
                    _ => 1,
                };
                assert!(blocks > 0, "{nodes} nodes, {kind:?}: no block of columns");
            }
        }
    }
}

/// A second factorization of other values on the same pattern shares the Cholesky's
/// symbolic analysis (the same `Arc`: no ordering or elimination tree made again, none
/// counted) and the LU's column ordering, split alike (1,800 unknowns: the two-part split),
/// and solves its own matrix as faer's LU does; a refactor counts a numeric factorization
/// and no analysis.
#[test]
fn with_values_shares_the_symbolic_analysis() {
    let (pattern, values) = grid_matrix_skew(30, 30, 0.0);
    assert!(pattern.nrows() >= SPLIT_MIN_ORDER);
    let (cp, ri) = (pattern.col_ptr(), pattern.row_idx());
    let mut other = values.clone();
    for j in 0..pattern.ncols() {
        for p in cp[j]..cp[j + 1] {
            if ri[p] == j {
                other[p] *= 2.0;
            }
        }
    }
    let b = rhs(pattern.nrows());
    let x_ref = faer_solve(&pattern, &other, &b);
    let close = |x: &[f64]| max_rel_diff(x, &x_ref) < 1e-13;

    let mut llt = SparseLlt::new(&pattern, &values).unwrap();
    let mut second = llt.with_values(&pattern, &other).unwrap();
    assert!(std::sync::Arc::ptr_eq(&llt.symbolic, &second.symbolic));
    assert_eq!(std::sync::Arc::strong_count(&llt.symbolic), 2);
    assert!(llt.parts.is_some() && second.parts == llt.parts);
    assert_eq!(second.perm_fwd, llt.perm_fwd);
    assert_eq!(
        second.counts,
        Counts {
            analyses: 0,
            factorizations: 1
        }
    );
    let mut x = b.clone();
    second.solve_in_place(&mut x);
    assert!(close(&x), "Cholesky with_values");
    llt.refactor(&pattern, &other).unwrap();
    assert_eq!(
        llt.counts,
        Counts {
            analyses: 1,
            factorizations: 2
        }
    );
    let mut y = b.clone();
    llt.solve_in_place(&mut y);
    assert!(x.iter().zip(&y).all(|(p, q)| p.to_bits() == q.to_bits()));

    let lu = SparseLu::new(&pattern, &values).unwrap();
    let mut second = lu.with_values(&pattern, &other).unwrap();
    assert_eq!(second.col_fwd, lu.col_fwd);
    assert!(lu.parts.is_some() && second.parts == lu.parts);
    assert_eq!(
        second.counts,
        Counts {
            analyses: 0,
            factorizations: 1
        }
    );
    assert_eq!(
        lu.counts,
        Counts {
            analyses: 1,
            factorizations: 1
        }
    );
    let mut x = b.clone();
    second.solve_in_place(&mut x);
    assert!(close(&x), "LU with_values");
}

/// The two forms in one pass are each the bits of [`quadratic_form`], and a form is its
/// definition `sum_ij x_i A_ij x_j` summed entry by entry (to round-off).
#[test]
fn two_quadratic_forms_in_one_pass_are_each_the_single_forms_bits() {
    let (pattern, a) = test_matrix(57, false);
    let b: Vec<f64> = a
        .iter()
        .enumerate()
        .map(|(i, v)| v * (1.0 + 0.01 * (i % 7) as f64))
        .collect();
    let n = pattern.ncols();
    let x: Vec<f64> = (0..n).map(|i| (i as f64 * 0.37).sin()).collect();
    let y: Vec<f64> = (0..n).map(|i| (i as f64 * 0.11).cos() - 0.2).collect();
    let (fa, fb) = quadratic_forms(&pattern, (&a, &x), (&b, &y));
    assert_eq!(fa.to_bits(), quadratic_form(&pattern, &a, &x).to_bits());
    assert_eq!(fb.to_bits(), quadratic_form(&pattern, &b, &y).to_bits());
    let (cp, ri) = (pattern.col_ptr(), pattern.row_idx());
    let mut direct = 0.0;
    for j in 0..n {
        for p in cp[j]..cp[j + 1] {
            direct += x[ri[p]] * a[p] * x[j];
        }
    }
    assert!((fa - direct).abs() <= 1e-12 * direct.abs().max(1.0));
}

/// A block of right-hand sides (`Factor::solve_many_on`) solves each column as the single
/// solve does, to round-off, on a Cholesky factor in dense supernodes (narrow and wide, one
/// whole block and two single solves: 10 columns, and 11: a padded block) and against
/// faer's answer; on a factor by rows
/// and on an LU it is the single solve itself, bit for bit.
#[test]
fn a_block_of_right_hand_sides_solves_each_column() {
    let (pattern, values) = grid_matrix_skew(14, 14, 0.0);
    let n = pattern.nrows();
    for k in [10, 11] {
        let b: Vec<f64> = (0..n * k)
            .map(|i| ((i * 7919) % 1013) as f64 / 1013.0 - 0.4)
            .collect();
        let dense = match Factor::new(&pattern, &values, FactorKind::Llt).unwrap() {
            Factor::Llt(l) => Factor::Llt(l.with_layout(&pattern, &values, true)),
            _ => unreachable!(),
        };
        assert!(matches!(
            &dense,
            Factor::Llt(SparseLlt {
                stored: Some(StoredLower::Supernodes(_)),
                ..
            })
        ));
        let by_rows = Factor::new(&pattern, &values, FactorKind::Llt).unwrap();
        let split = Factor::Llt(
            SparseLlt::build(&pattern, &values, true)
                .unwrap()
                .with_layout(&pattern, &values, true),
        );
        assert!(matches!(
            &split,
            Factor::Llt(SparseLlt {
                stored: Some(StoredLower::Split(l)),
                ..
            }) if l.is_dense()
        ));
        let lu = Factor::new(&pattern, &values, FactorKind::Lu(Ordering::Amd)).unwrap();
        let team = Team::default();
        for (name, mut f, bitwise) in [
            ("dense", dense, false),
            ("rows", by_rows, true),
            ("lu", lu, true),
        ] {
            let mut x = b.clone();
            f.solve_many_on(&team, &mut x, k);
            for c in 0..k {
                let col = &b[c * n..(c + 1) * n];
                let mut y = col.to_vec();
                f.solve_on(&team, &mut y);
                let got = &x[c * n..(c + 1) * n];
                if bitwise {
                    assert!(
                        got.iter().zip(&y).all(|(p, q)| p.to_bits() == q.to_bits()),
                        "{name} {c}"
                    );
                } else {
                    let d = max_rel_diff(got, &y);
                    assert!(d < 1e-13, "{name} column {c}: {d:e}");
                    let d = max_rel_diff(got, &faer_solve(&pattern, &values, col));
                    assert!(d < 1e-12, "{name} column {c} against faer: {d:e}");
                }
            }
        }
    }
}
