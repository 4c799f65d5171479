//! The wheel pressed on the rail (`kind = "press"`) on a ladder of contact-zone cell sizes,
//! with the Richardson limit of the area, the peak pressure and the approach, beside
//! CONTACT's half-space answer for the Manchester case (S1002 on UIC60 at 1:40, 10 kN,
//! G = 82 GPa, nu = 0.28: `examples/mbench_a22_right.ref_out` case 1 of
//! github.com/eve70a/CONTACT: FN 9997 N, approach 15.96 um, pmax 338.3 MPa, 1291 elements
//! of 0.2 x 0.2 mm = 51.64 mm^2).
//!
//! ```text
//! cargo run --release --example press_ladder -- [SCENARIO] [--sizes 1.2,0.9,0.6] [--count]
//! ```
//!
//! `SCENARIO` defaults to `scenarios/press.toml`; each rung is that scenario with
//! `press.contact_size_mm` set. `--count` prints each rung's meshes' sizes only. The
//! Richardson limit takes the two finest rungs with the observed order of the three
//! finest (clamped to [0.5, 3]; order 1 when it is not defined); where the rungs do not
//! converge monotonically (a patch of a few cells) the range and mean of the rungs say more.

use softway::kinds::press::geometry::{mesh_specs, place, wheel_sector};
use softway::kinds::press::{press, PressScenario, PressSpec};
use softway::mesh::generators::{rail_extruded, wheel_of_revolution};
use softway::scenario::{RunSpec, Scenario};
use std::process::ExitCode;

fn spec_of(path: &str) -> Result<PressSpec, String> {
    let sc: Scenario<RunSpec> =
        Scenario::from_file(std::path::Path::new(path)).map_err(|e| e.to_string())?;
    let m = sc.runs[0]
        .model
        .get::<PressScenario>()
        .ok_or("not a press scenario")?;
    Ok(m.spec)
}

fn count(s: &PressSpec) -> Result<(usize, usize), Box<dyn std::error::Error>> {
    let at = place(
        &s.wheel.profile.profile(),
        s.wheel.nominal_radius,
        s.rail.inclination,
        s.lateral,
    )
    .ok_or("no placement")?;
    let (w, r) = mesh_specs((s.wheel, s.rail), &at, s.size, s.zone, s.growth)?;
    let wheel = wheel_sector(&wheel_of_revolution(&w)?, s.sector, [0.0; 3]);
    let rail = rail_extruded(&r)?;
    Ok((3 * wheel.n_nodes(), 3 * rail.n_nodes()))
}

/// The Richardson limit of `v` on the cell sizes `h` (the three finest).
fn richardson(h: &[f64], v: &[f64]) -> (f64, f64) {
    let n = v.len();
    if n < 2 {
        return (v[n - 1], f64::NAN);
    }
    let (h1, h2) = (h[n - 2], h[n - 1]);
    let mut p = 1.0;
    if n >= 3 {
        let (e1, e2) = (v[n - 2] - v[n - 3], v[n - 1] - v[n - 2]);
        let q = (e1 / e2).abs().ln() / (h[n - 2] / h[n - 1]).ln();
        if q.is_finite() && e1 * e2 > 0.0 {
            p = q.clamp(0.5, 3.0);
        }
    }
    let r = (h1 / h2).powf(p);
    (v[n - 1] + (v[n - 1] - v[n - 2]) / (r - 1.0), p)
}

fn main() -> ExitCode {
    let mut path = "scenarios/press.toml".to_string();
    let mut sizes = vec![1.2, 0.9, 0.6];
    let mut only_count = false;
    let mut it = std::env::args().skip(1);
    while let Some(a) = it.next() {
        match a.as_str() {
            "--sizes" => {
                let v = it.next().unwrap_or_default();
                sizes = v.split(',').filter_map(|s| s.trim().parse().ok()).collect();
            }
            "--count" => only_count = true,
            _ => path = a,
        }
    }
    let base = match spec_of(&path) {
        Ok(s) => s,
        Err(e) => {
            eprintln!("press_ladder: {e}");
            return ExitCode::FAILURE;
        }
    };
    println!("| cell mm | dofs (wheel + rail) | load kN | area mm^2 | a_x mm | a_y mm | peak MPa | approach um | local um | hub descent um | iters | factor s | solve s |");
    println!("|---|---|---|---|---|---|---|---|---|---|---|---|---|");
    let (mut hs, mut area, mut peak, mut appr) = (vec![], vec![], vec![], vec![]);
    for &mm in &sizes {
        let mut s = base;
        s.size = 1e-3 * mm;
        if only_count {
            match count(&s) {
                Ok((w, r)) => println!("| {mm} | {} ({w} + {r}) |", w + r),
                Err(e) => eprintln!("press_ladder: {mm} mm: {e}"),
            }
            continue;
        }
        let p = match press(&s) {
            Ok(p) => p,
            Err(e) => {
                eprintln!("press_ladder: {mm} mm: {e}");
                return ExitCode::FAILURE;
            }
        };
        let w = 3 * p.wheel_nodes;
        println!(
            "| {mm} | {} ({w} + {}) | {:.4} | {:.2} | {:.3} | {:.3} | {:.1} | {:.2} | {:.2} | {:.2} | {} | {:.1} | {:.1} |",
            p.dofs,
            p.dofs - w,
            1e-3 * p.load,
            1e6 * p.area,
            1e3 * p.semi_axes[0],
            1e3 * p.semi_axes[1],
            1e-6 * p.peak_pressure,
            1e6 * p.approach,
            1e6 * p.approach_local,
            1e6 * p.descent,
            p.secant.iter().map(|s| s.iterations).sum::<usize>(),
            p.factor_seconds,
            p.solve_seconds
        );
        if let Some(h) = &p.hertz {
            let (ax, ay) = h.semi_axes_xy();
            println!(
                "|   Hertz | | | {:.2} | {:.3} | {:.3} | {:.1} | {:.2} | | | | | |",
                1e6 * h.area(),
                1e3 * ax,
                1e3 * ay,
                1e-6 * h.peak_pressure,
                1e6 * h.approach
            );
        }
        hs.push(mm);
        area.push(1e6 * p.area);
        peak.push(1e-6 * p.peak_pressure);
        appr.push(1e6 * p.approach);
    }
    if hs.len() >= 2 {
        for (name, v, contact) in [
            ("area mm^2", &area, 51.64),
            ("peak MPa", &peak, 338.3),
            ("approach um", &appr, 15.96),
        ] {
            let (lim, p) = richardson(&hs, v);
            let (lo, hi) = v
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &x| {
                    (a.min(x), b.max(x))
                });
            let mean = v.iter().sum::<f64>() / v.len() as f64;
            println!(
                "{name}: Richardson limit {lim:.3} (order {p:.2}; {:+.1} % of CONTACT's {contact}); rungs {lo:.3} to {hi:.3} ({:+.1} to {:+.1} %), mean {mean:.3} ({:+.1} %)",
                100.0 * (lim / contact - 1.0),
                100.0 * (lo / contact - 1.0),
                100.0 * (hi / contact - 1.0),
                100.0 * (mean / contact - 1.0)
            );
        }
    }
    ExitCode::SUCCESS
}
