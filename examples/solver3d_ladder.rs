//! The sparse Cholesky solver at 3D size: AMD against nested dissection on boxes of
//! hexahedra or 10-node tetrahedra, the step matrix `M + c K` of a steel box of cubic cells
//! (`c = (alpha h)^2 / 2`, `alpha = 0.8`, `h` an element's wave transit time, no supports).
//!
//! ```sh
//! cargo run --release --example solver3d_ladder -- [--kind hex8|tet10] [--cells 18,24,31]
//!     [--orderings amd,nd] [--mtx DIR]
//! ```
//!
//! `--cells` lists cubes (`24`: 24^3 cells of 1/24 m) or boxes of cubic cells (`12x12x400`:
//! a bar of 12 by 12 by 400 cells, the shape of a rail's length).
//!
//! Each (size, ordering) runs in a process of its own (this program again, `--one`), so
//! that its peak memory (`VmHWM`) is its own. The columns: the ordering's time, the entries
//! of `L` (diagonal included) and the symbolic count of them ([`cholesky_factor_nnz`], what
//! the cost estimate may use), the analysis and first factorization (`SparseLlt::with_ordering`,
//! the ordering included), a numeric refactorization (one thread: faer's kernels with
//! `Par::Seq`), the peak resident memory, a solve on one thread and on two (the split's
//! parts side by side, median of five), the floor `16 bytes x nnz(L) / triad bandwidth`
//! (`examples/bandwidth.rs`), and the solve's relative residual. `--mtx DIR` writes each
//! matrix (`A_<kind>_<cells>.mtx`) for `bench/peers/solver3d.py`.

use std::time::Instant;

use softway::bodies::solid::{solid, SolidSpec};
use softway::contact::search::Motion;
use softway::linalg::team::{Par, Team};
use softway::linalg::{
    cholesky_factor_nnz, fill_reducing_ordering, spmv_into, write_matrix_market, Ordering, Pattern,
    SparseLlt,
};
use softway::material::{Elastic, PlaneModel};
use softway::mesh::generators::box_mesh;
use softway::mesh::CellKind;

const STEEL: Elastic = Elastic {
    young: 210e9,
    poisson: 0.3,
    density: 7850.0,
};

fn kind_of(name: &str) -> CellKind {
    match name {
        "hex8" => CellKind::Hex8,
        "tet10" => CellKind::Tet10,
        "tet4" => CellKind::Tet4,
        other => panic!("unknown kind {other}: hex8, tet10 or tet4"),
    }
}

fn ordering_of(name: &str) -> Ordering {
    match name {
        "amd" => Ordering::Amd,
        "nd" => Ordering::NestedDissection,
        other => panic!("unknown ordering {other}: amd or nd"),
    }
}

/// The counts of cells of `spec`: `m` (a cube, `m^3`) or `nx x ny x nz` (`16x16x256`).
fn counts_of(spec: &str) -> [usize; 3] {
    let v: Vec<usize> = spec
        .split('x')
        .map(|c| c.parse().expect("a count"))
        .collect();
    match v[..] {
        [m] => [m; 3],
        [x, y, z] => [x, y, z],
        _ => panic!("cells {spec}: m or nx x ny x nz"),
    }
}

/// The step matrix of a box of `counts` cells of `kind`, cubes of `1 / counts[0]` m.
fn step_matrix(kind: CellKind, counts: [usize; 3]) -> (Pattern, Vec<f64>) {
    let size = 1.0 / counts[0] as f64;
    let lengths = counts.map(|c| c as f64 * size);
    let mesh = box_mesh(kind, lengths, counts).expect("a box");
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
    let m = &body.model;
    let values: Vec<f64> = m.m.iter().zip(&m.k).map(|(mi, ki)| mi + c * ki).collect();
    (m.assembler.pattern.clone(), values)
}

/// Peak resident memory of this process, bytes (`VmHWM`).
fn peak_rss() -> f64 {
    let s = std::fs::read_to_string("/proc/self/status").unwrap_or_default();
    s.lines()
        .find(|l| l.starts_with("VmHWM:"))
        .and_then(|l| l.split_whitespace().nth(1))
        .and_then(|v| v.parse::<f64>().ok())
        .map_or(f64::NAN, |kb| kb * 1024.0)
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

/// One row of the table: `kind cells ordering bandwidth [mtx dir]`.
fn one(args: &[String]) {
    let kind = kind_of(&args[0]);
    let cells = &args[1];
    let ordering = ordering_of(&args[2]);
    let bw: f64 = args[3].parse().expect("bandwidth");
    let (pattern, values) = step_matrix(kind, counts_of(cells));
    let n = pattern.nrows();
    if let Some(dir) = args.get(4) {
        let path = format!("{dir}/A_{}_{cells}.mtx", args[0]);
        if !std::path::Path::new(&path).exists() {
            let mut f = std::io::BufWriter::new(std::fs::File::create(&path).expect("mtx"));
            write_matrix_market(&mut f, &pattern, &values, "softway step matrix M + c K")
                .expect("written");
        }
    }
    let t = Instant::now();
    let (_, inv) = fill_reducing_ordering(&pattern, ordering).expect("an ordering");
    let t_order = t.elapsed().as_secs_f64();
    let t = Instant::now();
    let symbolic = cholesky_factor_nnz(&pattern, &inv);
    let t_count = t.elapsed().as_secs_f64();
    let t = Instant::now();
    let mut llt = SparseLlt::with_ordering(&pattern, &values, ordering).expect("a factor");
    let t_first = t.elapsed().as_secs_f64();
    let t = Instant::now();
    llt.refactor(&pattern, &values).expect("a factor");
    let t_factor = t.elapsed().as_secs_f64();
    let rss = peak_rss();
    let b: Vec<f64> = (0..n).map(|i| 1.0 + (i % 7) as f64).collect();
    let mut solve = |threads: usize| {
        let team = Team::new(Par::threads(threads));
        let mut x = b.clone();
        let times: Vec<f64> = (0..5)
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
    let (t2, _) = solve(2);
    let mut ax = vec![0.0; n];
    spmv_into(&pattern, &values, &x, &mut ax);
    let (num, den) = ax.iter().zip(&b).fold((0.0, 0.0), |(s, d), (a, bi)| {
        (s + (a - bi) * (a - bi), d + bi * bi)
    });
    let nnz = llt.factor_nnz();
    let floor = 16.0 * nnz as f64 / bw;
    println!(
        "| {} | {cells} | {n} | {} | {} | {t_order:.2} | {nnz} | {symbolic} ({t_count:.2} s) | {t_first:.2} | {t_factor:.2} | {:.0} | {:.1} | {:.1} | {:.1} | {:.1e} | {:?} |",
        args[0],
        pattern.compute_nnz(),
        args[2],
        rss / 1e6,
        t1 * 1e3,
        t2 * 1e3,
        floor * 1e3,
        (num / den).sqrt(),
        llt.parts(),
    );
}

/// The triad bandwidth, bytes per second, best of five rounds on arrays of 256 MiB.
fn triad_bandwidth() -> f64 {
    let n = 32 << 20;
    let mut a = vec![0.0f64; n];
    let b: Vec<f64> = (0..n).map(|i| i as f64).collect();
    let c: Vec<f64> = (0..n).map(|i| (n - i) as f64).collect();
    let mut best = 0.0f64;
    for _ in 0..5 {
        let t = Instant::now();
        for ((ai, bi), ci) in a.iter_mut().zip(&b).zip(&c) {
            *ai = bi + 3.0 * ci;
        }
        best = best.max(24.0 * n as f64 / t.elapsed().as_secs_f64());
        std::hint::black_box(&a);
    }
    best
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if args.first().map(String::as_str) == Some("--one") {
        one(&args[1..]);
        return;
    }
    let value = |key: &str, default: &str| {
        args.iter()
            .position(|a| a == key)
            .and_then(|i| args.get(i + 1).cloned())
            .unwrap_or_else(|| default.to_string())
    };
    let kind = value("--kind", "hex8");
    let cells = value("--cells", "18,24,31");
    let orderings = value("--orderings", "amd,nd");
    let mtx = args
        .iter()
        .position(|a| a == "--mtx")
        .and_then(|i| args.get(i + 1).cloned());
    let bw = triad_bandwidth();
    let load = std::fs::read_to_string("/proc/loadavg").unwrap_or_default();
    println!(
        "triad bandwidth {:.2} GB/s; load average {}",
        bw / 1e9,
        load.split_whitespace()
            .take(3)
            .collect::<Vec<_>>()
            .join(" ")
    );
    println!("| kind | cells | dofs | nnz(A) | ordering | order s | nnz(L) | symbolic nnz(L) | analyse+factor s | refactor s | peak MB | solve 1 thr ms | solve 2 thr ms | floor ms | residual | parts |");
    println!("|---|---:|---:|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|");
    let exe = std::env::current_exe().expect("this program");
    for c in cells.split(',') {
        for o in orderings.split(',') {
            let mut cmd = std::process::Command::new(&exe);
            cmd.args(["--one", &kind, c, o, &bw.to_string()]);
            if let Some(dir) = &mtx {
                cmd.arg(dir);
            }
            let status = cmd.status().expect("a child");
            if !status.success() {
                println!("| {kind} | {c} | | | {o} | failed: {status} |");
            }
        }
    }
}
