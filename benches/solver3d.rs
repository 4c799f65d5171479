//! The Cholesky factor of a 3D step matrix at one mid size: a steel cube of 18^3 hexahedra
//! (20,577 unknowns, `M + c K` as in `examples/solver3d_ladder.rs`), AMD against nested
//! dissection: `order/*` the ordering alone, `factor/*` a numeric refactorization on the
//! ordering's analysis, `solve/*` one solve on one thread (`Team` of one). The entries of each
//! factor are printed on stderr. The full ladder, with memory and a peer, is the example.
//! `columns/*`: the contact's cached columns `A^-1 e_d` for 64 surface dofs (the top face's
//! vertical dofs), one solve each against `Factor::solve_many_on`'s blocks of eight.

use criterion::{criterion_group, criterion_main, Criterion};

use softway::bodies::solid::{solid, SolidSpec};
use softway::contact::search::Motion;
use softway::linalg::team::{Par, Team};
use softway::linalg::{fill_reducing_ordering, Ordering, Pattern, SparseLlt};
use softway::material::{Elastic, PlaneModel};
use softway::mesh::generators::box_mesh;
use softway::mesh::CellKind;

fn cube(cells: usize) -> (Pattern, Vec<f64>) {
    let steel = Elastic {
        young: 210e9,
        poisson: 0.3,
        density: 7850.0,
    };
    let spec = SolidSpec {
        material: steel,
        plane: PlaneModel::Stress,
        thickness: 1.0,
        lumped: false,
    };
    let mesh = box_mesh(CellKind::Hex8, [1.0; 3], [cells; 3]).unwrap();
    let body = solid("cube", mesh, &spec, Motion::Fixed).unwrap().body;
    let h = 1.0 / cells as f64 / (steel.young / steel.density).sqrt();
    let c = 0.5 * (0.8 * h) * (0.8 * h);
    let m = &body.model;
    let values = m.m.iter().zip(&m.k).map(|(a, k)| a + c * k).collect();
    (m.assembler.pattern.clone(), values)
}

fn bench(c: &mut Criterion) {
    let (pattern, values) = cube(18);
    let team = Team::new(Par::threads(1));
    let b: Vec<f64> = (0..pattern.nrows()).map(|i| 1.0 + (i % 7) as f64).collect();
    for (name, ordering) in [("amd", Ordering::Amd), ("nd", Ordering::NestedDissection)] {
        let mut g = c.benchmark_group("solver3d_hex8_18");
        g.sample_size(10);
        g.bench_function(format!("order/{name}"), |bch| {
            bch.iter(|| fill_reducing_ordering(&pattern, ordering).unwrap())
        });
        let mut llt = SparseLlt::with_ordering(&pattern, &values, ordering).unwrap();
        eprintln!("{name}: nnz(L) = {}", llt.factor_nnz());
        g.bench_function(format!("factor/{name}"), |bch| {
            bch.iter(|| llt.refactor(&pattern, &values).unwrap())
        });
        let mut x = b.clone();
        g.bench_function(format!("solve/{name}"), |bch| {
            bch.iter(|| {
                x.copy_from_slice(&b);
                llt.solve_on(&team, &mut x);
            })
        });
        g.finish();
    }
    // The contact's columns: 64 unit right-hand sides on the top face.
    let n = pattern.nrows();
    let top: Vec<usize> = (0..n / 3).rev().take(64).map(|i| 3 * i + 2).collect();
    let mut llt = softway::linalg::Factor::Llt(
        SparseLlt::with_ordering(&pattern, &values, Ordering::NestedDissection).unwrap(),
    );
    let mut cols = vec![0.0; n * top.len()];
    let unit = |cols: &mut [f64]| {
        cols.fill(0.0);
        for (c, &d) in top.iter().enumerate() {
            cols[c * n + d] = 1.0;
        }
    };
    let mut g = c.benchmark_group("solver3d_hex8_18");
    g.sample_size(10);
    g.bench_function("columns/64_single", |bch| {
        bch.iter(|| {
            unit(&mut cols);
            for col in cols.chunks_exact_mut(n) {
                llt.solve_on(&team, col);
            }
        })
    });
    g.bench_function("columns/64_block", |bch| {
        bch.iter(|| {
            unit(&mut cols);
            llt.solve_many_on(&team, &mut cols, top.len());
        })
    });
    g.finish();
}

/// The step's right-hand side `b = h f + B v0 - h K u0 - h G (v0 + c a0)` of a steel bar of
/// 12 x 12 x 100 hexahedra spinning about its long axis (the rolling wheel's Coriolis term
/// on the right-hand side, 51,207 unknowns, some 4.1M entries): by 3D node blocks (`K`'s
/// nine values, `d` and `g` a block) against the rows by pairs (`B`'s and `K`'s values an
/// entry and `G`'s beside them), one thread, beyond the caches as in a run.
fn bench_rhs(c: &mut Criterion) {
    use softway::element::continuum::{assemble_continuum, SolidHex8};
    use softway::element::solid::elasticity_3d;
    use softway::frame3d::{add_coriolis, Spin};
    use softway::linalg::{BParts, RhsOperator, RhsValues};
    let steel = Elastic {
        young: 210e9,
        poisson: 0.3,
        density: 7850.0,
    };
    let mesh = box_mesh(CellKind::Hex8, [0.1, 0.1, 1.0], [12, 12, 100]).unwrap();
    let el = SolidHex8 {
        d: elasticity_3d(&steel),
    };
    let a = assemble_continuum(&mesh, &el, steel.density, false).unwrap();
    let spin = Spin::new([0.05, 0.05, 0.0], [0.0, 0.0, 1.0], 300.0).unwrap();
    let mut g = a.assembler.zeros();
    add_coriolis(&a.assembler, &a.m, &spin, &mut g);
    let pattern = a.assembler.pattern.clone();
    let (alpha, h) = (0.8, 2.5e-6);
    let parts = BParts::new(alpha, h);
    let cs = vec![0.0; a.m.len()];
    let bv: Vec<f64> = (0..a.m.len())
        .map(|p| parts.b(a.m[p], 0.0, a.k[p]))
        .collect();
    let values = RhsValues {
        m: &a.m,
        c: &cs,
        k: &a.k,
        g: &g,
        bv: &bv,
        parts,
    };
    let n = pattern.nrows();
    let u: Vec<f64> = (0..n).map(|i| 1e-4 * (0.3 * i as f64).sin()).collect();
    let v: Vec<f64> = (0..n).map(|i| 1e-2 * (0.7 * i as f64).cos()).collect();
    let acc: Vec<f64> = (0..n).map(|i| 3.0 * (0.9 * i as f64).sin()).collect();
    let f = vec![0.0; n];
    let team = Team::new(Par::threads(1));
    let mut grp = c.benchmark_group("rhs3d_bar_12x12x100");
    grp.sample_size(20);
    for (name, rows) in [
        ("pairs", RhsOperator::by_pairs(&pattern, &values)),
        ("node_blocks", RhsOperator::new(&pattern, &values)),
    ] {
        eprintln!("{name}: {} bytes", rows.bytes());
        let mut b = vec![0.0; n];
        grp.bench_function(name, |bch| {
            bch.iter(|| rows.apply(&team, h, alpha * h, [&u, &v, &acc], &f, &mut b))
        });
    }
    grp.finish();
}

criterion_group!(benches, bench, bench_rhs);
criterion_main!(benches);
