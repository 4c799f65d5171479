//! The `softway` command line: parse, validate, call the library, report. A scenario goes
//! through the library's three stages: [`Scenario::from_file`] parses and validates it,
//! [`resolve`] builds what needs a model (the step from `cfl`), the jobs run it.

use clap::{Parser, Subcommand};
use softway::build::resolve;
use softway::run::{run_scenario, RunOptions, INTERRUPT};
use softway::scenario::Scenario;
use softway::time::sdof::analyse;
use std::path::PathBuf;
use std::process::ExitCode;
use std::sync::atomic::Ordering;

/// Dynamic contact by the space-time finite element method (Bajer's soft way).
#[derive(Parser, Debug)]
#[command(name = "softway", version, about, long_about = None)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Run a scenario and write history.csv, summary.json, plots and fields into a folder.
    Run {
        /// The scenario file (TOML).
        scenario: PathBuf,
        /// Output folder [default: out/<scenario name>].
        #[arg(long)]
        out: Option<PathBuf>,
        /// No progress bar.
        #[arg(long)]
        quiet: bool,
    },
    /// Run a scenario over a list of values of one key, in parallel (e.g. the paper's Fig. 15).
    Sweep {
        /// The scenario file (TOML).
        scenario: PathBuf,
        /// KEY=V1,V2,... (a dotted scenario key), e.g. rolling.omega=250,300,350; default:
        /// the scenario's [sweep] table.
        #[arg(long)]
        set: Option<String>,
        /// Output folder [default: out/<scenario name>-sweep].
        #[arg(long)]
        out: Option<PathBuf>,
        /// Runs at once [default: the number of cores].
        #[arg(long)]
        jobs: Option<usize>,
    },
    /// Run a scenario over a refinement ladder of one key (mesh or step) and report the
    /// observed order of every key figure: converge.csv, converge.md, converge.png.
    Converge {
        /// The scenario file (TOML, one run).
        scenario: PathBuf,
        /// KEY=V1,V2,V3,... a geometric ladder of at least three rungs, e.g.
        /// wheel.rings=6,12,24 or time.h=0.1,0.05,0.025.
        #[arg(long)]
        set: String,
        /// Output folder [default: out/<scenario name>-converge].
        #[arg(long)]
        out: Option<PathBuf>,
        /// Runs at once [default: the number of cores].
        #[arg(long)]
        jobs: Option<usize>,
    },
    /// Run the combinations (integrator, contact treatment, time step, mesh) of a bar
    /// scenario side by side against the exact answer: compare.csv, compare.md, force and
    /// energy plots.
    Compare {
        /// The scenario file (TOML, kind = "bar_impact" or "two_bars", one [[runs]] entry
        /// per combination).
        scenario: PathBuf,
        /// Output folder [default: out/<scenario name>].
        #[arg(long)]
        out: Option<PathBuf>,
    },
    /// Natural frequencies (Hz) and periods (us) of a wheel scenario's model, at rest and
    /// spinning (rotating frame), with the mode shapes as VTU.
    Modes {
        /// The scenario file (TOML, kind = "wheel").
        scenario: PathBuf,
        /// Number of elastic modes.
        #[arg(long, default_value_t = 12)]
        count: usize,
        /// Output folder [default: out/<scenario name>-modes].
        #[arg(long)]
        out: Option<PathBuf>,
    },
    /// Write the space-time step's matrices of a wheel or bar scenario (Matrix Market) for
    /// other solvers, with the size of each factor and softway's time for one free step:
    /// A.mtx, B.mtx, K.mtx, u0/v0/f.mtx, fixed.txt, matrix.json (bench/peers/ reads them).
    Matrix {
        /// The scenario file (TOML, kind = "wheel" or "bar_impact"; its first run).
        scenario: PathBuf,
        /// Output folder [default: out/<scenario name>-matrix].
        #[arg(long)]
        out: Option<PathBuf>,
    },
    /// Spectral radius, damping and period error of the scheme against omega*h.
    Stability {
        /// alpha of Eq. (8), in (0, 1].
        #[arg(long, default_value_t = 0.8)]
        alpha: f64,
        /// gamma of Eq. (24), in [0, 1].
        #[arg(long, default_value_t = 0.0)]
        gamma: f64,
        /// Also write stability.csv and stability.png into this folder.
        #[arg(long)]
        out: Option<PathBuf>,
        /// Print one JSON object instead of the table.
        #[arg(long)]
        json: bool,
    },
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let _ = ctrlc::set_handler(|| {
        if INTERRUPT.swap(true, Ordering::SeqCst) {
            std::process::exit(130);
        }
        eprintln!("\ninterrupted: finishing the current step and writing what was computed (Ctrl-C again to abort)");
    });
    match try_main(cli) {
        Ok(code) => code,
        Err(e) => {
            eprintln!("softway: error: {e}");
            ExitCode::from(2)
        }
    }
}

fn try_main(cli: Cli) -> Result<ExitCode, Box<dyn std::error::Error>> {
    match cli.command {
        Command::Run {
            scenario,
            out,
            quiet,
        } => {
            let sc = resolve(&Scenario::from_file(&scenario)?)?;
            for w in &sc.warnings {
                eprintln!("softway: warning: {w}");
            }
            let out = out.unwrap_or_else(|| PathBuf::from("out").join(&sc.name));
            let report = run_scenario(&sc, &out, &RunOptions { progress: !quiet })?;
            println!("{} ({})", sc.name, scenario.display());
            for l in &report.lines {
                println!("  {l}");
            }
            println!("  wrote:");
            for f in &report.files {
                println!("    {}", f.display());
            }
            if report.interrupted {
                eprintln!("softway: interrupted; the files above hold the steps computed so far");
                return Ok(ExitCode::from(130));
            }
            Ok(ExitCode::SUCCESS)
        }
        Command::Sweep {
            scenario,
            set,
            out,
            jobs,
        } => {
            let text = std::fs::read_to_string(&scenario)
                .map_err(|e| format!("{}: cannot read the scenario: {e}", scenario.display()))?;
            let sc = Scenario::from_file(&scenario)?;
            let (key, values) = match set {
                Some(s) => parse_set(&s)?,
                None => sc.sweep.clone().ok_or_else(|| {
                    format!(
                        "{}: no [sweep] table and no --set KEY=V1,V2,...",
                        scenario.display()
                    )
                })?,
            };
            let out =
                out.unwrap_or_else(|| PathBuf::from("out").join(format!("{}-sweep", sc.name)));
            set_jobs(jobs);
            println!("{}: sweeping {key} over {} values", sc.name, values.len());
            let (points, files) =
                softway::run::sweep::sweep(&scenario, &text, &key, &values, &out)?;
            print_table(&out.join("sweep.md"), &files);
            for p in points {
                println!("    {}/", p.dir.display());
            }
            if INTERRUPT.load(Ordering::Relaxed) {
                return Ok(ExitCode::from(130));
            }
            Ok(ExitCode::SUCCESS)
        }
        Command::Converge {
            scenario,
            set,
            out,
            jobs,
        } => {
            let text = std::fs::read_to_string(&scenario)
                .map_err(|e| format!("{}: cannot read the scenario: {e}", scenario.display()))?;
            let sc = Scenario::from_file(&scenario)?;
            let (key, values) = parse_set(&set)?;
            let out =
                out.unwrap_or_else(|| PathBuf::from("out").join(format!("{}-converge", sc.name)));
            set_jobs(jobs);
            println!(
                "{}: convergence of {key} over {} rungs",
                sc.name,
                values.len()
            );
            let (_, files) =
                softway::run::converge::converge(&scenario, &text, &key, &values, &out)?;
            print_table(&out.join("converge.md"), &files);
            if INTERRUPT.load(Ordering::Relaxed) {
                return Ok(ExitCode::from(130));
            }
            Ok(ExitCode::SUCCESS)
        }
        Command::Compare { scenario, out } => {
            let sc = resolve(&Scenario::from_file(&scenario)?)?;
            for w in &sc.warnings {
                eprintln!("softway: warning: {w}");
            }
            let out = out.unwrap_or_else(|| PathBuf::from("out").join(&sc.name));
            let report =
                softway::run::compare::compare(&sc, &out, &RunOptions { progress: false })?;
            for l in &report.lines {
                println!("{l}");
            }
            println!("wrote:");
            for f in &report.files {
                println!("  {}", f.display());
            }
            if report.interrupted {
                eprintln!("softway: interrupted: the table holds the runs finished before");
                return Ok(ExitCode::from(130));
            }
            Ok(ExitCode::SUCCESS)
        }
        Command::Modes {
            scenario,
            count,
            out,
        } => {
            let sc = Scenario::from_file(&scenario)?;
            let softway::scenario::Model::Wheel(ws) = &sc.runs[0].model else {
                return Err(format!(
                    "{}: `softway modes` needs a wheel scenario (kind = \"wheel\")",
                    scenario.display()
                )
                .into());
            };
            if count == 0 {
                return Err("--count 0: ask for at least one mode".into());
            }
            let wm = softway::run::wheel::build(ws, &sc.path)?;
            let rep = softway::modes::modes_report(&wm, count)?;
            println!(
                "{}: {} dofs ({} free), support {:?}",
                sc.name, rep.dofs, rep.free_dofs, wm.spec.support
            );
            println!("at rest:");
            println!(
                "{:>5} {:>14} {:>12} {:>5}  kind",
                "mode", "frequency Hz", "period us", "n"
            );
            for (i, m) in rep.at_rest.iter().enumerate() {
                println!(
                    "{:>5} {:>14.2} {:>12.3} {:>5}  {}",
                    i + 1,
                    m.frequency_hz,
                    m.period_us,
                    m.wavenumber
                        .map(|n| n.to_string())
                        .unwrap_or_else(|| "-".into()),
                    m.kind
                );
            }
            if let Some(sp) = &rep.spinning {
                println!(
                    "spinning at omega = {} rad/s (frequencies in the wheel's rotating frame):",
                    ws.spec.omega
                );
                println!(
                    "{:>5} {:>14} {:>14} {:>10}  kind",
                    "mode", "frequency Hz", "at rest Hz", "whirl"
                );
                for (i, m) in sp.iter().enumerate() {
                    println!(
                        "{:>5} {:>14.2} {:>14.2} {:>10}  {}",
                        i + 1,
                        m.frequency_hz,
                        m.rest_frequency_hz,
                        m.whirl.to_string(),
                        m.kind
                    );
                }
            }
            for n in &rep.notes {
                println!("note: {n}");
            }
            let out =
                out.unwrap_or_else(|| PathBuf::from("out").join(format!("{}-modes", sc.name)));
            let files = softway::modes::write_mode_shapes(&wm, &rep.at_rest, &out)?;
            println!("wrote {} files into {}", files.len(), out.display());
            Ok(ExitCode::SUCCESS)
        }
        Command::Matrix { scenario, out } => {
            let sc = resolve(&Scenario::from_file(&scenario)?)?;
            let out =
                out.unwrap_or_else(|| PathBuf::from("out").join(format!("{}-matrix", sc.name)));
            let (rep, files) = softway::run::matrix::dump(&sc, &out)?;
            println!(
                "{}: {} dofs, nnz(A) = {}, symmetric: {}; softway factors it as {}",
                sc.name, rep.n, rep.nnz_a, rep.symmetric, rep.factor
            );
            for (name, nnz) in &rep.factor_nnz {
                println!("  nnz of the factors, {name}: {nnz}");
            }
            println!("  softway free step: {:.1} us", rep.softway_step_us);
            println!("  wrote:");
            for f in &files {
                println!("    {}", f.display());
            }
            Ok(ExitCode::SUCCESS)
        }
        Command::Stability {
            alpha,
            gamma,
            out,
            json,
        } => {
            if !(alpha.is_finite() && alpha > 0.0 && alpha <= 1.0) {
                return Err(format!("--alpha {alpha}: alpha must be in (0, 1] (Eq. 8)").into());
            }
            if !(gamma.is_finite() && (0.0..=1.0).contains(&gamma)) {
                return Err(format!("--gamma {gamma}: gamma must be in [0, 1] (Eq. 24)").into());
            }
            let rep = analyse(alpha, gamma, 5);
            if json {
                let j = serde_json::json!({
                    "alpha": rep.alpha, "gamma": rep.gamma, "beta": rep.beta,
                    "rho_inf": rep.rho_inf,
                    "unconditionally_stable": rep.unconditionally_stable,
                    "stability_limit_omega_h": rep.stability_limit_omega_h,
                    "table": rep.table,
                });
                println!("{}", serde_json::to_string_pretty(&j)?);
            } else {
                print!("{}", softway::output::stability::table_text(&rep));
            }
            if let Some(dir) = out {
                let files = softway::output::stability::write(&rep, &dir)?;
                if !json {
                    for f in files {
                        println!("wrote {}", f.display());
                    }
                }
            }
            Ok(ExitCode::SUCCESS)
        }
    }
}

/// `KEY=V1,V2,...` of `--set` into the key and its values.
fn parse_set(s: &str) -> Result<(String, Vec<String>), String> {
    let (k, v) = s
        .split_once('=')
        .ok_or_else(|| format!("--set {s}: expected KEY=V1,V2,... (e.g. rolling.omega=250,300)"))?;
    let vals: Vec<String> = v
        .split(',')
        .map(|x| x.trim().to_string())
        .filter(|x| !x.is_empty())
        .collect();
    if vals.is_empty() {
        return Err(format!("--set {s}: no values"));
    }
    Ok((k.trim().to_string(), vals))
}

/// Runs at once for `sweep` and `converge` (default: the number of cores).
fn set_jobs(jobs: Option<usize>) {
    if let Some(j) = jobs {
        rayon::ThreadPoolBuilder::new()
            .num_threads(j.max(1))
            .build_global()
            .ok();
    }
}

/// Prints a markdown table written by a study and the files it wrote.
fn print_table(md: &std::path::Path, files: &[PathBuf]) {
    print!("{}", std::fs::read_to_string(md).unwrap_or_default());
    println!("  wrote:");
    for f in files {
        println!("    {}", f.display());
    }
}
