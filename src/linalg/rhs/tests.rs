use super::*;
use crate::bodies::wheel::{WheelModel, WheelSpec};
use crate::linalg::team::{Par, Team};
use crate::mesh::generators::disk_rings;
use crate::time::step::split_skew;

/// `B`, and the right-hand side's rows, of the wheel's `M`, `c` (`C` or its symmetric
/// part) and `K` for `alpha = 0.6`, `h = 2e-6`, with the skew part `g` (or none), their
/// blocks in the most compact form they allow.
fn rows_of(w: &WheelModel, c: &[f64], g: &[f64]) -> (RhsOperator, Vec<f64>) {
    let (m, k, pattern) = (&w.model.m, &w.model.k, w.model.pattern());
    let nnz = m.len();
    let (mut a_orig, mut bv, mut a_work) = (vec![0.0; nnz], vec![0.0; nnz], vec![0.0; nnz]);
    let is_bc = vec![false; w.model.n()];
    let (alpha, h) = (0.6, 2e-6);
    Operators {
        m,
        c,
        k,
        pattern,
        is_bc: &is_bc,
    }
    .fill(alpha, h, &mut a_orig, &mut bv, &mut a_work);
    let values = RhsValues {
        m,
        c,
        k,
        g,
        bv: &bv,
        parts: BParts::new(alpha, h),
    };
    let mut rows = RhsOperator::new(pattern, &values);
    // The paper's disk is small enough for `B`'s four values; its compact form is filled
    // by hand.
    assert_eq!(rows.blk_form, BlockForm::General);
    rows.fill_blocks(rows.compact_form(&values), &values);
    (rows, bv)
}

/// The right-hand side's kernels compiled for AVX2 (and the blocks' AVX2 kernel) give
/// the baseline's bits, the pairs formed in two halves (as from 10,000 dofs on) those
/// formed in one pass, the blocks' compact forms those of `B`'s and `K`'s eight values,
/// and all of them the plain sparse products to round-off.
#[test]
fn right_hand_side_kernels_agree_bit_for_bit() {
    let w = WheelModel::new(disk_rings(0.1, 6).unwrap(), WheelSpec::paper()).unwrap();
    let (n, k, pattern) = (w.model.n(), &w.model.k, w.model.pattern());
    let u: Vec<f64> = (0..n).map(|i| 1e-4 * (0.3 * i as f64).sin()).collect();
    let v: Vec<f64> = (0..n).map(|i| 1e-2 * (0.7 * i as f64).cos()).collect();
    let acc: Vec<f64> = (0..n).map(|i| 3.0 * (0.9 * i as f64).sin()).collect();
    let f: Vec<f64> = (0..n).map(|i| 1e3 * (1.1 * i as f64).cos()).collect();
    let h = 2e-6;
    let c = 0.8 * h;
    let same = |x: &[f64], y: &[f64]| x.iter().zip(y).all(|(p, q)| p.to_bits() == q.to_bits());
    let close = |x: &[f64], reference: &[f64]| {
        let scale = reference.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
        let d = x
            .iter()
            .zip(reference)
            .fold(0.0_f64, |m, (x, y)| m.max((x - y).abs()));
        assert!(
            d <= 1e-13 * scale,
            "against sparse products: {d:e} of {scale:e}"
        );
    };
    // `b` by the portable kernels (or AVX2's), the pairs in one pass or two halves.
    let rhs = |rows: &RhsOperator, g: bool, avx2: bool, halves: bool| {
        let mut rows = rows.clone();
        rows.avx2 = avx2;
        let pairs = rows.pair.len();
        let mid = if halves { pairs / 2 } else { pairs };
        let cut = rows.pair.get(mid).copied().unwrap_or(n);
        let mut b = vec![f64::NAN; n];
        let (lo, hi) = b.split_at_mut(cut);
        for (range, offset, b) in [(0..mid, 0, lo), (mid..pairs, cut, hi)] {
            #[cfg(target_arch = "x86_64")]
            if avx2 {
                // SAFETY: called with `avx2` only where the processor has AVX2.
                unsafe {
                    if g {
                        rows.pairs_g_avx2(range, offset, h, c, [&f, &u, &v, &acc], b);
                    } else {
                        rows.pairs_avx2(range, offset, h, [&f, &u, &v], b);
                    }
                }
                continue;
            }
            if g {
                rows.pairs_g_here(range, offset, h, c, [&f, &u, &v, &acc], b);
            } else {
                rows.pairs_here(range, offset, h, [&f, &u, &v], b);
            }
        }
        rows.singles_here(h, &f, &u, &v, &mut b);
        if g {
            rows.singles_g_into(h, c, &v, &acc, &mut b);
        }
        b
    };
    let avx2 = cfg!(target_arch = "x86_64") && crate::linalg::has_avx2();
    // Each of `rows`' ways to the same bits, and the sparse products to round-off.
    let check = |rows: &RhsOperator, bv: &[f64], g: &[f64]| {
        let with_g = !g.is_empty();
        let whole = rhs(rows, with_g, false, false);
        assert!(whole.iter().all(|x| x.is_finite()), "every row formed");
        assert!(same(&whole, &rhs(rows, with_g, false, true)), "halves");
        // The prefetch (on for large blocks) is a hint: the same bits.
        let mut other = rows.clone();
        other.prefetch = !rows.prefetch;
        assert!(same(&whole, &rhs(&other, with_g, false, true)), "prefetch");
        if avx2 {
            assert!(
                same(&whole, &rhs(&other, with_g, true, false)),
                "AVX2, prefetch"
            );
        }
        if avx2 {
            assert!(same(&whole, &rhs(rows, with_g, true, false)), "AVX2");
            assert!(same(&whole, &rhs(rows, with_g, true, true)), "AVX2, halves");
        }
        // The operator's own entry point: the same bits.
        let mut applied = vec![f64::NAN; n];
        rows.apply(
            &crate::linalg::team::Team::default(),
            h,
            c,
            [&u, &v, &acc],
            &f,
            &mut applied,
        );
        assert!(same(&whole, &applied), "apply");
        // The pairs in parts on teams of one to four threads (more than the machine may
        // have): the parts cover the pairs in order, each with its rows, and the same bits.
        // The halves' cut (as from `RHS_SPLIT_MIN_ORDER` on) is that of two parts.
        let mut parted = rows.clone();
        let pairs = rows.pair.len();
        let mid = rows.first_pair_with(rows.entries_before(pairs) / 2);
        parted.pair_mid = Some(mid.clamp(1, pairs - 1));
        let mut scratch = vec![0.0; n];
        assert_eq!(
            parted.pair_parts(2, &mut scratch)[1].0.start,
            parted.pair_mid.unwrap()
        );
        for threads in 1..=4 {
            let mut scratch = vec![0.0; n];
            let parts = parted.pair_parts(threads, &mut scratch);
            assert_eq!(parts.len(), threads.min(rows.pair.len()));
            let mut next = (0, 0);
            for (range, row, b) in &parts {
                assert_eq!((range.start, *row), next, "{threads} parts");
                assert!(range.start < range.end);
                assert!(range.start == 0 || *row == rows.pair[range.start]);
                next = (range.end, row + b.len());
            }
            assert_eq!(next, (rows.pair.len(), n));
            let team = Team::oversubscribed(Par::threads(threads));
            assert_eq!(team.width(), threads);
            for _ in 0..3 {
                let mut applied = vec![f64::NAN; n];
                parted.apply(&team, h, c, [&u, &v, &acc], &f, &mut applied);
                assert!(same(&whole, &applied), "apply on {threads} threads");
            }
        }
        // The plain sparse products (by columns): the same to round-off.
        let mut reference = vec![f64::NAN; n];
        let values = RhsValues {
            m: &w.model.m,
            c: &w.model.c,
            k,
            g,
            bv,
            parts: BParts::new(0.6, h),
        };
        rhs_plain_into(pattern, &values, h, c, [&u, &v, &acc], &f, &mut reference);
        close(&whole, &reference);
        whole
    };

    // The exact scheme: `D = M - (1 - alpha) h C` is `[[d, s], [-s, d]]` per block.
    let (rows, bv) = rows_of(&w, &w.model.c, &[]);
    assert!(!rows.pair.is_empty() && !rows.blk_idx.is_empty());
    assert_eq!(rows.blk_form, BlockForm::Skew);
    assert!(rows.blk_bk.is_empty() && rows.blk_kd.len() == rows.blk_idx.len());
    let compact = check(&rows, &bv, &[]);
    let mut general = rows.clone();
    let values = |c, g, bv| RhsValues {
        m: &w.model.m,
        c,
        k,
        g,
        bv,
        parts: BParts::new(0.6, 2e-6),
    };
    general.fill_blocks(BlockForm::General, &values(&w.model.c, &[], &bv));
    assert!(general.blk_kd.is_empty() && general.blk_bk.len() == rows.blk_idx.len());
    assert!(
        same(&compact, &check(&general, &bv, &[])),
        "Skew against General"
    );

    // The Coriolis term on the right-hand side: `D` is `d I`, `G` `[[0, -g], [g, 0]]`,
    // both in six values per block.
    let (cs, g) = split_skew(pattern, &w.model.c).unwrap();
    let (rows, bv) = rows_of(&w, &cs, &g);
    assert_eq!(rows.blk_form, BlockForm::Diagonal);
    assert!(rows.blk_g.is_empty() && rows.blk_gs.is_empty());
    let compact = check(&rows, &bv, &g);
    let mut general = rows.clone();
    general.fill_blocks(BlockForm::General, &values(&cs, &g, &bv));
    assert!(general.blk_g.is_empty() && general.blk_gs.len() == rows.blk_idx.len());
    assert!(
        same(&compact, &check(&general, &bv, &g)),
        "Diagonal against General"
    );
    // G's blocks by one value or by four.
    let mut four = general.clone();
    four.blk_g = rows.blk_src.iter().map(|s| s.map(|p| g[p])).collect();
    four.blk_gs = Vec::new();
    assert!(same(&compact, &check(&four, &bv, &g)), "G by four values");

    // A stiffness-proportional damping puts `K`'s coupling of x and y in `D`: the blocks
    // keep `B`'s four values, the same sums.
    let c_k: Vec<f64> = w.model.c.iter().zip(k).map(|(c, k)| c + 1e-5 * k).collect();
    let (rows, bv) = rows_of(&w, &c_k, &[]);
    assert_eq!(rows.blk_form, BlockForm::General);
    assert!(rows.blk_kd.is_empty() && rows.blk_bk.len() == rows.blk_idx.len());
    check(&rows, &bv, &[]);
}

/// A spinning steel box of hexahedra (consistent mass): `M`, `K` (with the spin
/// softening) and `C` the Coriolis term of a spin about `axis`, on one pattern.
fn spinning_box(axis: [f64; 3]) -> (Pattern, Vec<f64>, Vec<f64>, Vec<f64>) {
    use crate::element::continuum::{assemble_continuum, SolidHex8};
    use crate::element::solid::elasticity_3d;
    use crate::frame3d::{add_coriolis, add_spin_softening, Spin};
    let steel = crate::material::Elastic {
        young: 2.1e11,
        poisson: 0.3,
        density: 7850.0,
    };
    let mesh =
        crate::mesh::generators::box_mesh(crate::mesh::CellKind::Hex8, [0.3, 0.2, 0.1], [4, 3, 2])
            .unwrap();
    let el = SolidHex8 {
        d: elasticity_3d(&steel),
    };
    let a = assemble_continuum(&mesh, &el, steel.density, false).unwrap();
    let spin = Spin::new([0.1, 0.0, 0.0], axis, 300.0).unwrap();
    let mut c = a.assembler.zeros();
    add_coriolis(&a.assembler, &a.m, &spin, &mut c);
    let mut k = a.k.clone();
    add_spin_softening(&a.assembler, &a.m, &spin, &mut k);
    (a.assembler.pattern.clone(), a.m, k, c)
}

/// A 3D solid's rows by node blocks: `M = M_s (x) I_3` and `G` about a coordinate axis
/// give [`Nodes3`]; its right-hand side is the plain sparse products' to round-off, with
/// and without `G` on the right-hand side, on one thread as on two or three (the same bits), for
/// a spin about each axis; a spin off the axes, or a mass that is not `M_s (x) I_3`, keep
/// the rows by pairs, with the same answer.
#[test]
fn node_blocks_of_a_solid_give_the_plain_products() {
    let teams = [
        Team::oversubscribed(Par::threads(2)),
        Team::oversubscribed(Par::threads(3)),
    ];
    for (axis, blocks) in [
        ([1.0, 0.0, 0.0], true),
        ([0.0, 1.0, 0.0], true),
        ([0.0, 0.0, 1.0], true),
        ([0.0, 0.6, 0.8], false),
    ] {
        let (pattern, m, k, c_full) = spinning_box(axis);
        let n = pattern.nrows();
        let (cs, g) = split_skew(&pattern, &c_full).unwrap();
        let u: Vec<f64> = (0..n).map(|i| 1e-4 * (0.3 * i as f64).sin()).collect();
        let v: Vec<f64> = (0..n).map(|i| 1e-2 * (0.7 * i as f64).cos()).collect();
        let acc: Vec<f64> = (0..n).map(|i| 3.0 * (0.9 * i as f64).sin()).collect();
        let f: Vec<f64> = (0..n).map(|i| 1e3 * (1.1 * i as f64).cos()).collect();
        let (alpha, h) = (0.6, 2e-6);
        let c = alpha * h;
        for (cc, gg) in [(&cs, &g[..]), (&c_full, &[][..])] {
            let nnz = m.len();
            let (mut a_orig, mut bv, mut a_work) = (vec![0.0; nnz], vec![0.0; nnz], vec![0.0; nnz]);
            Operators {
                m: &m,
                c: cc,
                k: &k,
                pattern: &pattern,
                is_bc: &vec![false; n],
            }
            .fill(alpha, h, &mut a_orig, &mut bv, &mut a_work);
            let values = RhsValues {
                m: &m,
                c: cc,
                k: &k,
                g: gg,
                bv: &bv,
                parts: BParts::new(alpha, h),
            };
            let rows = RhsOperator::new(&pattern, &values);
            // Without `G` on the right-hand side, `C` is the whole skew term: no block
            // form.
            let expect = blocks && !gg.is_empty();
            assert_eq!(
                rows.nodes3.is_some(),
                expect,
                "axis {axis:?}, G {}",
                gg.len()
            );
            let mut reference = vec![0.0; n];
            rhs_plain_into(&pattern, &values, h, c, [&u, &v, &acc], &f, &mut reference);
            let scale = reference.iter().fold(0.0_f64, |a, x| a.max(x.abs()));
            let mut one = vec![f64::NAN; n];
            rows.apply(&Team::new(Par::Seq), h, c, [&u, &v, &acc], &f, &mut one);
            let d = one
                .iter()
                .zip(&reference)
                .fold(0.0_f64, |a, (x, y)| a.max((x - y).abs()));
            assert!(d <= 1e-13 * scale, "axis {axis:?}: {d:e} of {scale:e}");
            for team in &teams {
                let mut more = vec![f64::NAN; n];
                rows.apply(team, h, c, [&u, &v, &acc], &f, &mut more);
                assert!(one
                    .iter()
                    .zip(&more)
                    .all(|(x, y)| x.to_bits() == y.to_bits()));
            }
        }
    }
    // A mass that couples a node's components: the rows by pairs.
    let (pattern, mut m, k, c_full) = spinning_box([0.0, 0.0, 1.0]);
    let (cs, g) = split_skew(&pattern, &c_full).unwrap();
    let t = crate::linalg::transpose_positions(&pattern).unwrap();
    let (cp, ri) = (pattern.col_ptr(), pattern.row_idx());
    let p = (cp[0]..cp[1]).find(|&p| ri[p] == 1).unwrap();
    m[p] = 1e-3;
    m[t[p]] = 1e-3;
    let bv = vec![0.0; m.len()];
    let values = RhsValues {
        m: &m,
        c: &cs,
        k: &k,
        g: &g,
        bv: &bv,
        parts: BParts::new(0.6, 2e-6),
    };
    assert!(RhsOperator::new(&pattern, &values).nodes3.is_none());
}
