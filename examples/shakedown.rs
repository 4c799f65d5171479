//! Johnson's rolling shakedown: the Hertz pressure moved over an elastic-perfectly-plastic
//! half-space pass after pass (`softway::plasticity::shakedown`), a table per pass.
//!
//! ```text
//! cargo run --release --example shakedown -- --p0-over-k 4.6 --passes 15 [--h-over-a 0.125]
//!     [--path-over-a 4] [--step-over-a 0.1] [--far-over-a 30] [--tol 1e-9] [--profile]
//! ```

use softway::plasticity::shakedown::{first_yield, Shakedown, ShakedownConfig};
use std::process::ExitCode;

const USAGE: &str = "usage: shakedown [--p0-over-k X] [--passes N] [--h-over-a X] [--path-over-a X] [--step-over-a X] [--far-over-a X] [--tol X] [--profile]";

fn parse() -> Result<(ShakedownConfig, usize, bool), String> {
    let mut c = ShakedownConfig::default();
    let (mut passes, mut profile) = (10, false);
    let mut args = std::env::args().skip(1);
    while let Some(key) = args.next() {
        if key == "--profile" {
            profile = true;
            continue;
        }
        let value = args
            .next()
            .ok_or_else(|| format!("shakedown: {key} needs a value; {USAGE}"))?;
        let num = || {
            value
                .parse::<f64>()
                .map_err(|_| format!("shakedown: {key} = {value:?} is not a number; {USAGE}"))
        };
        match key.as_str() {
            "--p0-over-k" => c.p0_over_k = num()?,
            "--h-over-a" => c.h_over_a = num()?,
            "--path-over-a" => c.path_over_a = num()?,
            "--step-over-a" => c.step_over_a = num()?,
            "--far-over-a" => c.far_over_a = num()?,
            "--tol" => c.tol = num()?,
            "--passes" => {
                passes = value
                    .parse()
                    .ok()
                    .filter(|&n: &usize| n >= 1)
                    .ok_or_else(|| {
                        format!("shakedown: --passes = {value:?} is not allowed; allowed: a whole number >= 1")
                    })?
            }
            _ => return Err(format!("shakedown: unknown option {key:?}; {USAGE}")),
        }
    }
    Ok((c, passes, profile))
}

fn run() -> Result<(), String> {
    let (c, passes, profile) = parse()?;
    let fy = first_yield(c.elastic.poisson);
    let t = std::time::Instant::now();
    let mut s = Shakedown::new(c).map_err(|e| e.to_string())?;
    println!(
        "p0/k = {}, first yield (exact field) at p0/k = {:.4}, depth {:.4} a; {} triangles, {} dofs, h = a/{:.0}, path +-{} a, {} increments per pass ({} moves of {} a, {} on, {} off), central region |x| <= {} a",
        c.p0_over_k,
        fy.p0_over_k,
        fy.depth_over_a,
        s.space.triangles.len(),
        s.space.n_dofs(),
        1.0 / c.h_over_a,
        c.path_over_a,
        c.increments_per_pass(),
        c.moves(),
        c.step_over_a,
        c.ramp,
        c.ramp,
        c.path_over_a - 2.0,
    );
    println!("pass  d_eq_max    d_eq_int/a^2  net_max     net_int/a^2  eq_max      flowed  d_ux_surf/a  iters(max)");
    let mut ux_prev = 0.0;
    let mut last = None;
    for _ in 0..passes {
        let r = s.run_pass().map_err(|e| e.to_string())?;
        let a2 = c.a * c.a;
        println!(
            "{:4}  {:.3e}   {:.3e}     {:.3e}   {:.3e}    {:.3e}   {:6}  {:+.3e}   {}({})",
            r.pass,
            r.d_eq_max,
            r.d_eq_integral / a2,
            r.net_max,
            r.net_integral / a2,
            r.eq_max,
            r.flowed,
            (r.surface_ux - ux_prev) / c.a,
            r.iterations,
            r.max_iterations
        );
        ux_prev = r.surface_ux;
        last = Some(r);
    }
    if let (true, Some(r)) = (profile, last) {
        println!("residual sigma_xx / k at x = 0 after the last pass:");
        for (z, sxx) in r.residual_sxx.iter().filter(|(z, _)| *z <= 3.0 * c.a) {
            println!("  z/a = {:.4}  {:+.4}", z / c.a, sxx / c.k());
        }
    }
    eprintln!("{:.1} s", t.elapsed().as_secs_f64());
    Ok(())
}

fn main() -> ExitCode {
    match run() {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("{e}");
            ExitCode::FAILURE
        }
    }
}
