//! The split factor in 2, 4 and 8 parts on a 3D box: the parts' balance and the factor's
//! and solve's times on one thread and two.
//!
//! ```sh
//! cargo run --release --example split_parts -- [--cells 32] [--depths 1,2,3] [--kind hex8]
//! ```
//!
//! The step matrix `M + c K` of a steel box of cubic hexahedra (as
//! `examples/solver3d_ladder.rs`), Cholesky on nested dissection split into `2^d` parts
//! (`SparseLlt::with_split_depth`). Per depth: the parts' orders (leaves, then separators
//! up to the top), the load balance of the leaves (the largest leaf's entries of `L`, and
//! its factorization flops, over the leaves' mean), the solve's ideal speed-up on `2^d`
//! cores (the entries of `L` over the sum, level by level, of the largest part's: what a
//! machine of that many cores could gain, memory bandwidth aside), the first build
//! (ordering, analysis, factorization), a numeric refactorization (faer's, one thread:
//! the factorization is not split), and a solve on one thread and on two (median of nine).

use std::time::Instant;

use softway::bodies::solid::{solid, SolidSpec};
use softway::contact::search::Motion;
use softway::linalg::team::{Par, Team};
use softway::linalg::{spmv_into, Ordering, Pattern, SparseLlt};
use softway::material::{Elastic, PlaneModel};
use softway::mesh::generators::box_mesh;
use softway::mesh::CellKind;

const STEEL: Elastic = Elastic {
    young: 210e9,
    poisson: 0.3,
    density: 7850.0,
};

/// The step matrix of a cube of `m^3` cells of `kind`, each `1 / m` m.
fn step_matrix(kind: CellKind, m: usize) -> (Pattern, Vec<f64>) {
    let size = 1.0 / m as f64;
    let mesh = box_mesh(kind, [1.0; 3], [m; 3]).expect("a box");
    let spec = SolidSpec {
        material: STEEL,
        plane: PlaneModel::Stress,
        thickness: 1.0,
        lumped: false,
    };
    let body = solid("box", mesh, &spec, Motion::Fixed)
        .expect("a solid")
        .body;
    let wave = (STEEL.young / STEEL.density).sqrt();
    let h = size / wave;
    let c = 0.5 * (0.8 * h) * (0.8 * h);
    let model = &body.model;
    let values = model
        .m
        .iter()
        .zip(&model.k)
        .map(|(a, b)| a + c * b)
        .collect();
    (model.assembler.pattern.clone(), values)
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let value = |key: &str, default: &str| {
        args.iter()
            .position(|a| a == key)
            .and_then(|i| args.get(i + 1))
            .map_or(default.to_string(), String::clone)
    };
    let kind = match value("--kind", "hex8").as_str() {
        "hex8" => CellKind::Hex8,
        "tet10" => CellKind::Tet10,
        other => panic!("unknown kind {other}: hex8 or tet10"),
    };
    let m: usize = value("--cells", "32").parse().expect("a count of cells");
    let depths: Vec<usize> = value("--depths", "1,2,3")
        .split(',')
        .map(|d| d.parse().expect("a depth"))
        .collect();
    let (pattern, values) = step_matrix(kind, m);
    let n = pattern.nrows();
    let b: Vec<f64> = (0..n).map(|i| 1.0 + (i % 7) as f64).collect();
    println!("# {m}^3 cells, {n} unknowns");
    println!(
        "| parts | orders | entries of L | leaf entries max/mean | leaf flops max/mean | ideal solve speed-up | first build s | refactor s | solve 1 thread ms | solve 2 threads ms | residual |"
    );
    for depth in depths {
        let t = Instant::now();
        let mut llt =
            SparseLlt::with_split_depth(&pattern, &values, Ordering::NestedDissection, depth)
                .expect("a factor");
        let t_first = t.elapsed().as_secs_f64();
        let t = Instant::now();
        llt.refactor(&pattern, &values).expect("a factor");
        let t_factor = t.elapsed().as_secs_f64();
        let work = llt.part_work().expect("a split factor");
        let leaves = work.len().div_ceil(2);
        let ratio = |f: &dyn Fn(usize) -> f64| {
            let v: Vec<f64> = (0..leaves).map(f).collect();
            v.iter().copied().fold(0.0, f64::max) * leaves as f64 / v.iter().sum::<f64>()
        };
        let entries_ratio = ratio(&|k| work[k].entries as f64);
        let flops_ratio = ratio(&|k| work[k].factor_flops);
        // Level by level from the leaves: `2^l` parts at level `l`.
        let (mut start, mut size, mut path) = (0, leaves, 0usize);
        while size >= 1 {
            path += work[start..start + size]
                .iter()
                .map(|w| w.entries)
                .max()
                .unwrap();
            start += size;
            size /= 2;
        }
        let total: usize = work.iter().map(|w| w.entries).sum();
        let mut solve = |threads: usize| {
            let team = Team::new(Par::threads(threads));
            let mut x = b.clone();
            let times: Vec<f64> = (0..9)
                .map(|_| {
                    x.copy_from_slice(&b);
                    let t = Instant::now();
                    llt.solve_on(&team, &mut x);
                    t.elapsed().as_secs_f64()
                })
                .collect();
            (median(times), x)
        };
        let (t1, x) = solve(1);
        let (t2, x2) = solve(2);
        assert!(x.iter().zip(&x2).all(|(p, q)| p.to_bits() == q.to_bits()));
        let mut ax = vec![0.0; n];
        spmv_into(&pattern, &values, &x, &mut ax);
        let (num, den) = ax.iter().zip(&b).fold((0.0, 0.0), |(s, d), (a, bi)| {
            (s + (a - bi) * (a - bi), d + bi * bi)
        });
        println!(
            "| {leaves} | {:?} | {total} | {entries_ratio:.3} | {flops_ratio:.3} | {:.2} | {t_first:.2} | {t_factor:.2} | {:.1} | {:.1} | {:.1e} |",
            llt.part_orders().expect("parts"),
            total as f64 / path as f64,
            t1 * 1e3,
            t2 * 1e3,
            (num / den).sqrt(),
        );
    }
}
