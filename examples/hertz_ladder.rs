//! Hertz's point contact on graded 3D meshes: a rigid body pressed on a steel block, a mesh
//! ladder per case with its Richardson limit, against Hertz's elliptic solution
//! (`softway::contact::hertz`, Johnson 1985 §4.2) at each rung's load.
//!
//! ```text
//! cargo run --release --example hertz_ladder -- [--case sphere|ellipse|both]
//!     [--rungs 3,4,6,9] [--size-over-a 80] [--ratio 1.3] [--sizes 20,40,80]
//!     [--figure hertz.png]
//! ```
//!
//! Cases: a rigid sphere of R = 0.3 m under 50 kN, and a rigid body of radii 0.46 m (along
//! x, a wheel) and 0.30 m (across, a rail head's crown) under 100 kN, on steel (E = 210 GPa,
//! nu = 0.3; the indenter rigid, so E* = E / (1 - nu^2)). A rung `n` has `b / n` cells in the
//! core (`b` Hertz's smaller semi-axis at the target load); the block is a quarter of side and
//! depth `size-over-a` times `a`, graded by `ratio`. The Richardson limit takes the two
//! finest rungs with the observed order of the three finest (order 2 when it is not
//! defined). `--sizes` runs the coarsest rung on blocks of those sizes instead (the approach's
//! finite-block residual). `--figure` writes, per case, the finest rung's nodal pressures
//! along the two axes against Hertz's semi-ellipses (`hertz-sphere.png`, `hertz-ellipse.png`
//! beside the path given).

use softway::contact::statics::indent::{indent, IndentSpec, Indentation};
use softway::material::Elastic;
use softway::mesh::generators::graded::GradedBlock;
use softway::mesh::CellKind;
use std::process::ExitCode;

const STEEL: Elastic = Elastic {
    young: 210e9,
    poisson: 0.3,
    density: 7850.0,
};

struct Args {
    cases: Vec<&'static str>,
    rungs: Vec<usize>,
    size: f64,
    ratio: f64,
    sizes: Vec<f64>,
    figure: Option<std::path::PathBuf>,
}

fn parse() -> Result<Args, String> {
    let mut a = Args {
        cases: vec!["sphere", "ellipse"],
        rungs: vec![3, 4, 6, 9],
        size: 80.0,
        ratio: 1.3,
        sizes: vec![],
        figure: None,
    };
    let mut it = std::env::args().skip(1);
    while let Some(key) = it.next() {
        let v = it.next().ok_or(format!("{key} needs a value"))?;
        let list = |v: &str| -> Result<Vec<f64>, String> {
            v.split(',')
                .map(|s| {
                    s.trim()
                        .parse::<f64>()
                        .map_err(|_| format!("{key}: bad number {s:?}"))
                })
                .collect()
        };
        match key.as_str() {
            "--case" => {
                a.cases = match v.as_str() {
                    "sphere" => vec!["sphere"],
                    "ellipse" => vec!["ellipse"],
                    "both" => vec!["sphere", "ellipse"],
                    _ => return Err(format!("--case {v:?}: allowed sphere, ellipse, both")),
                }
            }
            "--rungs" => a.rungs = list(&v)?.iter().map(|&x| x as usize).collect(),
            "--size-over-a" => a.size = list(&v)?[0],
            "--ratio" => a.ratio = list(&v)?[0],
            "--sizes" => a.sizes = list(&v)?,
            "--figure" => a.figure = Some(v.into()),
            _ => return Err(format!("unknown option {key}")),
        }
    }
    Ok(a)
}

fn spec(case: &str, n: usize, size: f64, ratio: f64) -> IndentSpec {
    let (rx, ry, load) = match case {
        "sphere" => (0.3, 0.3, 50e3),
        _ => (0.46, 0.30, 100e3),
    };
    let e_star = STEEL.young / (1.0 - STEEL.poisson.powi(2));
    let h = softway::contact::hertz::Hertz::from_radii(rx, ry, e_star, load).unwrap();
    let (ax, ay) = h.semi_axes_xy();
    let l = size * h.a;
    IndentSpec {
        block: GradedBlock {
            kind: CellKind::Hex8,
            extent: [l, l, l],
            core: [1.4 * ax, 1.4 * ay, h.b],
            h: h.b / n as f64,
            ratio,
        },
        material: STEEL,
        radius_x: rx,
        radius_y: ry,
        load,
    }
}

/// `(a_x, a_y, p0, delta)` and Hertz's.
fn values(r: &Indentation) -> ([f64; 4], [f64; 4]) {
    let (hx, hy) = r.hertz.semi_axes_xy();
    (
        [r.semi_axes[0], r.semi_axes[1], r.peak_pressure, r.approach],
        [hx, hy, r.hertz.peak_pressure, r.hertz.approach],
    )
}

fn pct(v: f64, h: f64) -> f64 {
    100.0 * (v / h - 1.0)
}

fn main() -> ExitCode {
    let args = match parse() {
        Ok(a) => a,
        Err(e) => {
            eprintln!("hertz_ladder: {e}");
            return ExitCode::FAILURE;
        }
    };
    for case in &args.cases {
        println!("\n## {case}");
        println!(
            "| rung b/h | L/a | dofs | P kN | a_x mm | a_y mm | p0 MPa | delta um | err a_x % | err a_y % | err p0 % | err delta % | delta_block um | active | iters | factor s | solve s |"
        );
        println!("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|");
        let runs: Vec<(usize, f64)> = if args.sizes.is_empty() {
            args.rungs.iter().map(|&n| (n, args.size)).collect()
        } else {
            args.sizes.iter().map(|&s| (args.rungs[0], s)).collect()
        };
        let mut rows = Vec::new();
        let mut last = None;
        for (n, size) in runs {
            let r = match indent(&spec(case, n, size, args.ratio)) {
                Ok(r) => r,
                Err(e) => {
                    eprintln!("hertz_ladder: {case} rung {n}: {e}");
                    return ExitCode::FAILURE;
                }
            };
            let (v, h) = values(&r);
            println!(
                "| {n} | {size} | {} | {:.3} | {:.4} | {:.4} | {:.1} | {:.4} | {:+.2} | {:+.2} | {:+.2} | {:+.2} | {:.4} | {} | {} | {:.1} | {:.1} |{}",
                r.dofs,
                r.load / 1e3,
                v[0] * 1e3,
                v[1] * 1e3,
                v[2] / 1e6,
                v[3] * 1e6,
                pct(v[0], h[0]),
                pct(v[1], h[1]),
                pct(v[2], h[2]),
                pct(v[3], h[3]),
                r.approach_block * 1e6,
                r.active,
                r.iterations,
                r.factor_seconds,
                r.solve_seconds,
                if r.inside { "" } else { " (patch cut)" }
            );
            // Errors relative to Hertz at each rung's load (the loads differ by < 0.1 %).
            rows.push((1.0 / n as f64, [0, 1, 2, 3].map(|k| v[k] / h[k] - 1.0)));
            last = Some((n, r));
        }
        if rows.len() >= 2 && args.sizes.is_empty() {
            let k = rows.len();
            let names = ["a_x", "a_y", "p0", "delta"];
            print!("Richardson limit (error %):");
            for (q, name) in names.iter().enumerate() {
                let (h1, e1) = (rows[k - 2].0, rows[k - 2].1[q]);
                let (h2, e2) = (rows[k - 1].0, rows[k - 1].1[q]);
                let mut p = 2.0;
                if k >= 3 {
                    let (h0, e0) = (rows[k - 3].0, rows[k - 3].1[q]);
                    // Observed order for the ratios h0/h1 and h1/h2 (equal ratios: exact).
                    let ratio = (e0 - e1) / (e1 - e2);
                    let est = ratio.abs().ln() / (h0 / h1).ln();
                    if ratio > 0.0 && est.is_finite() && (0.5..=4.0).contains(&est) {
                        p = est;
                    }
                }
                let r = (h1 / h2).powf(p);
                let limit = (r * e2 - e1) / (r - 1.0);
                print!(" {name} {:+.2} (order {:.2});", 100.0 * limit, p);
            }
            println!();
        }
        if let (Some(path), Some((n, r))) = (&args.figure, &last) {
            let stem = path.file_stem().and_then(|s| s.to_str()).unwrap_or("hertz");
            let out = path.with_file_name(format!("{stem}-{case}.png"));
            if let Err(e) = figure(&out, case, *n, r) {
                eprintln!("hertz_ladder: {e}");
                return ExitCode::FAILURE;
            }
            println!("figure: {}", out.display());
        }
    }
    ExitCode::SUCCESS
}

/// The nodal pressures on the axes `y = 0` and `x = 0` against Hertz's semi-ellipses.
fn figure(
    path: &std::path::Path,
    case: &str,
    n: usize,
    r: &Indentation,
) -> Result<(), softway_plot::PlotError> {
    use softway_plot::{line_plot, Panel, Series, SeriesStyle};
    let on = |axis: usize| {
        let mut pts: Vec<(f64, f64)> = r
            .patch
            .iter()
            .filter(|p| p[1 - axis] == 0.0)
            .map(|p| (p[axis] * 1e3, p[2] / 1e6))
            .collect();
        pts.sort_by(|a, b| a.0.total_cmp(&b.0));
        pts.into_iter().unzip::<f64, f64, Vec<f64>, Vec<f64>>()
    };
    let (hx, hy) = r.hertz.semi_axes_xy();
    let hertz = |semi: f64| {
        let xs: Vec<f64> = (0..=200).map(|k| 1.3 * semi * k as f64 / 200.0).collect();
        let ps = xs
            .iter()
            .map(|&x| r.hertz.peak_pressure / 1e6 * (1.0 - (x / semi).powi(2)).max(0.0).sqrt())
            .collect();
        (xs.iter().map(|x| x * 1e3).collect::<Vec<f64>>(), ps)
    };
    let (fx, px) = on(0);
    let (fy, py) = on(1);
    let (hxs, hxp) = hertz(hx);
    let (hys, hyp) = hertz(hy);
    let mut panel = Panel::new(
        format!(
            "{case}: contact pressure on the axes, P = {:.1} kN, b/h = {n}, {} dofs",
            r.load / 1e3,
            r.dofs
        ),
        "distance from the centre [mm]",
        "p [MPa]",
    );
    panel.series = vec![
        Series::new("nodes on y = 0 (along x)", fx, px, SeriesStyle::Markers),
        Series::new("nodes on x = 0 (along y)", fy, py, SeriesStyle::Markers),
        Series::new("Hertz along x", hxs, hxp, SeriesStyle::Line),
        Series::new("Hertz along y", hys, hyp, SeriesStyle::Dashed),
    ];
    panel.note = format!(
        "Nodal pressure = contact force / consistent nodal area. Hertz (Johnson 1985, Eq. 4.39) at the computed load: a_x = {:.3} mm, a_y = {:.3} mm, p0 = {:.0} MPa; from the forces' second moments a_x = {:.3} mm, a_y = {:.3} mm.",
        hx * 1e3,
        hy * 1e3,
        r.hertz.peak_pressure / 1e6,
        r.semi_axes[0] * 1e3,
        r.semi_axes[1] * 1e3
    );
    line_plot(path, &panel, (1000, 650))
}
