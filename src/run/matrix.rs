//! `softway matrix`: the space-time step's matrices of a scenario's first run, written for
//! other solvers (the peer comparison of `bench/peers/`), with the size of each factor of
//! `A` and softway's own time for one free step.
//!
//! Files (Matrix Market, 1-based, every stored entry, `real general`):
//! - `A.mtx`: `A = M + alpha h C + alpha^2 h^2/2 K` with the Dirichlet rows and columns
//!   replaced by the identity (the matrix softway factors);
//! - `B.mtx`: `B = M - (1-alpha) h C - (alpha - alpha^2/2) h^2 K` and `K.mtx`: the step's
//!   right-hand side is `b = B v0 - h K u0 + h f`, `b_d = 0` on the fixed dofs `d`
//!   ([`crate::time::step`]);
//! - `u0.mtx`, `v0.mtx`, `f.mtx` (Matrix Market arrays): the state and load of the step
//!   timed (a wheel: its spun-up displacement, a velocity `1e-3 sin(i)` m/s, its
//!   centrifugal load; a bar: its initial state, no load);
//! - with `time.coriolis = "extrapolated"` (and a Coriolis term), `A` and `B` are built on
//!   the symmetric part of `C`, and `G.mtx` (the skew part) and `a0.mtx` (the acceleration
//!   of the step, `1e-3 cos(i)` m/s^2) complete the right-hand side:
//!   `b = B v0 - h (K u0 + G (v0 + alpha h a0)) + h f`;
//! - `fixed.txt`: the fixed dofs, 0-based, one a line;
//! - `matrix.json`: `n`, `nnz_a`, `h_s`, `alpha`, `symmetric`, the stored entries of each
//!   factor (`factor_nnz`: LU with COLAMD, LU with AMD, Cholesky when `A` is symmetric
//!   positive definite; a large 3D model's Cholesky factor by nested dissection alone), the
//!   factor softway uses, its ordering and its time (`factor_s`), the peak memory
//!   (`peak_rss_mib`), and `softway_step_us`: the median over
//!   five rounds of the time of one free step (right-hand side and solve, as
//!   `benches/step.rs` times it), measured here; `threads`, the threads it was timed on,
//!   and `factor_parts` (when the factor is split: the orders of its parts, the `2^d` solved
//!   side by side first, then each level of separators up to the top, `[part 0, part 1,
//!   top]` for two parts; otherwise null).

use super::RunError;
use crate::linalg::{write_matrix_market, FactorKind, Ordering};
use crate::model::LinearModel;
use crate::output::files::write_json;
use crate::scenario::kind::FreeStep;
use crate::scenario::Scenario;
use crate::time::step::{FactorChoice, Stepper};
use crate::time::SpaceTimeParams;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// What [`dump`] measured.
#[derive(Debug, Clone, serde::Serialize)]
pub struct MatrixReport {
    /// Dofs.
    pub n: usize,
    /// Stored entries of `A`.
    pub nnz_a: usize,
    /// Time step, s.
    pub h_s: f64,
    /// `alpha`.
    pub alpha: f64,
    /// `A` symmetric (no Coriolis term).
    pub symmetric: bool,
    /// `(factorization, stored entries of its factors)`.
    pub factor_nnz: Vec<(String, usize)>,
    /// The factorization softway uses ([`FactorChoice::Auto`]).
    pub factor: String,
    /// Its analysis and numeric factorization, s (the step matrix's stepper built).
    pub factor_s: f64,
    /// Its fill-reducing ordering ([`Ordering::auto`]).
    pub factor_ordering: String,
    /// The process's peak resident memory at the end, MiB (every factor made included).
    pub peak_rss_mib: Option<f64>,
    /// One free step (right-hand side and solve), microseconds.
    pub softway_step_us: f64,
    /// The orders of the factor's parts when it is split
    /// ([`Stepper::factor_part_orders`]): the leaves, then each level of separators up to
    /// the top.
    pub factor_parts: Option<Vec<usize>>,
    /// Threads of the pool the step was timed on.
    pub threads: usize,
    /// Where the Coriolis term is (`time.coriolis`): "implicit" or "extrapolated".
    pub coriolis: String,
}

/// The name of a factorization; `auto` is the ordering [`Ordering::auto`] gives the
/// matrix (a Cholesky factor's).
fn kind_name(k: FactorKind, auto: Ordering) -> String {
    match k {
        FactorKind::Lu(Ordering::Colamd) => "lu_colamd".into(),
        FactorKind::Lu(Ordering::Amd) => "lu_amd".into(),
        FactorKind::Lu(Ordering::NestedDissection) => "lu_nd".into(),
        FactorKind::Llt if auto == Ordering::NestedDissection => "llt_nd".into(),
        FactorKind::Llt => "llt_amd".into(),
        FactorKind::FaerLu => "faer_lu".into(),
        FactorKind::FaerLlt => "faer_llt".into(),
    }
}

/// Writes the matrices of the first run of `sc` (a wheel or a bar, space-time scheme) into
/// `out` (module docs) and times softway's free step: `steps` free steps in each of five
/// rounds (default `2,000,000 / nnz(A)`, between 20 and 20,000), the median round reported.
///
/// # Errors
/// [`RunError`] for another kind of scenario, a singular matrix or an output error.
pub fn dump(
    sc: &Scenario,
    out: &Path,
    steps: Option<usize>,
    interrupt: &std::sync::atomic::AtomicBool,
) -> Result<(MatrixReport, Vec<PathBuf>), RunError> {
    let run = &sc.runs[0];
    let FreeStep {
        model,
        fixed,
        u0,
        v0,
        f,
    } = step_inputs(sc)?;
    std::fs::create_dir_all(out).map_err(|e| RunError::output(out, e))?;
    let bcs: Vec<(usize, f64)> = fixed.iter().map(|&d| (d, 0.0)).collect();
    let sim_err = |e| RunError::Simulation {
        run: run.label.clone(),
        source: crate::simulation::SimError::Linalg(e),
    };
    let coriolis = match run.integrator {
        crate::time::Integrator::SpaceTime { coriolis, .. } => coriolis,
        _ => crate::time::Coriolis::Implicit,
    };
    let built = Instant::now();
    let mut st = Stepper::with_options(&model, run.params, &bcs, FactorChoice::Auto, coriolis)
        .map_err(sim_err)?;
    let factor_s = built.elapsed().as_secs_f64();
    let ordering = Ordering::auto(model.pattern());
    let factor_nnz = factor_sizes(&model, run.params, &bcs, (&st, ordering));
    let n = model.n();
    let a0: Vec<f64> = match st.skew() {
        Some(_) => (0..n).map(|i| 1e-3 * (i as f64).cos()).collect(),
        None => vec![0.0; n],
    };
    let (pattern, a, _, _) = st.matrices();
    let symmetric = crate::linalg::is_symmetric(pattern, a, 1e-14);
    let nnz_a = a.len();
    let header = format!(
        "softway: {} ({}), space-time step, alpha = {}, h = {:e} s",
        sc.name, run.label, run.params.alpha, run.params.h
    );
    let mut files = write_matrices(out, &st, &header)?;
    let with_a0 = st.skew().map(|_| ("a0.mtx", &a0));
    for (name, values) in [("u0.mtx", &u0), ("v0.mtx", &v0), ("f.mtx", &f)]
        .into_iter()
        .chain(with_a0)
    {
        let path = out.join(name);
        let mut s = format!(
            "%%MatrixMarket matrix array real general\n% {header}\n{} 1\n",
            values.len()
        );
        for v in values.iter() {
            s.push_str(&format!("{v:e}\n"));
        }
        std::fs::write(&path, s).map_err(|e| RunError::output(&path, e))?;
        files.push(path);
    }
    let path = out.join("fixed.txt");
    let s: String = fixed.iter().map(|d| format!("{d}\n")).collect();
    std::fs::write(&path, s).map_err(|e| RunError::output(&path, e))?;
    files.push(path);
    // softway's free step, timed as benches/step.rs does: median of five rounds.
    let reps = steps
        .unwrap_or((2_000_000 / (nnz_a + 1)).clamp(20, 20_000))
        .max(1);
    // On the threads of a run (`Simulation::set_par`): a team of the caller's pool's size.
    let team = crate::linalg::team::Team::new(crate::linalg::team::Par::current());
    st.set_team(&team);
    let rounds = time_free_step(&mut st, [&u0, &v0, &a0, &f], n, reps, interrupt);
    let report = MatrixReport {
        n,
        nnz_a,
        h_s: run.params.h,
        alpha: run.params.alpha,
        symmetric,
        factor_nnz,
        factor: match st.skew() {
            Some(_) => format!(
                "{} (coriolis extrapolated)",
                kind_name(st.factor_kind(), ordering)
            ),
            None => kind_name(st.factor_kind(), ordering),
        },
        factor_s,
        factor_ordering: format!("{ordering:?}"),
        peak_rss_mib: crate::run::provenance::peak_rss_mib(),
        softway_step_us: rounds[rounds.len() / 2],
        factor_parts: st.factor_part_orders(),
        threads: team.par().count(),
        coriolis: st.coriolis().name().to_string(),
    };
    let path = out.join("matrix.json");
    write_json(&path, &report).map_err(|e| RunError::output(&path, e))?;
    files.push(path);
    Ok((report, files))
}

/// The step's inputs of the first run of `sc` (its kind's [`crate::kinds::Spec::free_step`]:
/// a wheel's spun-up model with a velocity `1e-3 sin(i)`, a bar's initial state without
/// load).
fn step_inputs(sc: &Scenario) -> Result<FreeStep, RunError> {
    let run = &sc.runs[0];
    run.model.free_step(run, &sc.path).unwrap_or_else(|| {
        Err(RunError::input(
            &sc.path,
            format!(
                "`softway matrix` takes a wheel, bar_impact, press or rolling3d scenario, not kind = \"{}\"",
                run.model.kind()
            ),
        ))
    })
}

/// The stored entries of the factors of `A` by each factorization that factors it (a
/// Cholesky factor only when softway's is one, `st`), and of softway's own with an
/// extrapolated Coriolis term.
fn factor_sizes(
    model: &LinearModel,
    params: SpaceTimeParams,
    bcs: &[(usize, f64)],
    (st, ordering): (&Stepper, Ordering),
) -> Vec<(String, usize)> {
    let mut factor_nnz = Vec::new();
    // A large 3D model's own factor (nested dissection: a Cholesky factor, or the LU of
    // the 3D rolling's unsymmetric matrix) alone: other factors of it would hold many
    // times its entries (an LU with COLAMD took minutes and gigabytes at 1e5 unknowns, and
    // more than 13 minutes at 2.3e5); AMD against nested dissection at 3D size is
    // `examples/solver3d_ladder.rs`'s.
    if ordering == Ordering::NestedDissection {
        let name = match st.skew() {
            Some(_) => format!(
                "{} (coriolis extrapolated)",
                kind_name(st.factor_kind(), ordering)
            ),
            None => kind_name(st.factor_kind(), ordering),
        };
        return vec![(name, st.factor_nnz())];
    }
    for kind in [
        FactorKind::Lu(Ordering::Colamd),
        FactorKind::Lu(Ordering::Amd),
        FactorKind::Llt,
    ] {
        if let Ok(s) = Stepper::with_factor(model, params, bcs, FactorChoice::Kind(kind)) {
            // A Cholesky factor of an unsymmetric matrix is not a factor of it.
            if kind != FactorKind::Llt
                || (st.factor_kind() == FactorKind::Llt && st.skew().is_none())
            {
                factor_nnz.push((kind_name(kind, ordering), s.factor_nnz()));
            }
        }
    }
    if st.skew().is_some() {
        factor_nnz.push((
            format!(
                "{} (coriolis extrapolated)",
                kind_name(st.factor_kind(), ordering)
            ),
            st.factor_nnz(),
        ));
    }
    factor_nnz
}

/// Writes `A.mtx`, `B.mtx`, `K.mtx` and with an extrapolated Coriolis term `G.mtx` into
/// `out`, each under `header`; returns their paths.
fn write_matrices(out: &Path, st: &Stepper, header: &str) -> Result<Vec<PathBuf>, RunError> {
    let (pattern, a, b, k) = st.matrices();
    let mut files = Vec::new();
    for (name, values, what) in [
        (
            "A.mtx",
            a,
            "A = M + alpha h C + alpha^2 h^2/2 K, Dirichlet rows and columns identity",
        ),
        (
            "B.mtx",
            b,
            "B = M - (1-alpha) h C - (alpha - alpha^2/2) h^2 K",
        ),
        ("K.mtx", k, "K"),
    ]
    .into_iter()
    .chain(
        st.skew()
            .map(|g| ("G.mtx", g, "G = (C - C^T)/2, the Coriolis term")),
    ) {
        let path = out.join(name);
        let mut w = std::io::BufWriter::new(
            std::fs::File::create(&path).map_err(|e| RunError::output(&path, e))?,
        );
        write_matrix_market(&mut w, pattern, values, &format!("{header}\n{what}"))
            .and_then(|_| w.flush())
            .map_err(|e| RunError::output(&path, e))?;
        files.push(path);
    }
    Ok(files)
}

/// The time of one free step of `n` dofs (right-hand side and solve from
/// `[u0, v0, a0, f]`) in each of five rounds of `reps` steps, microseconds, sorted.
///
/// Stops at the next step once `interrupt` is set: the rounds finished, and the one under
/// way when it has at least one step (so never none).
fn time_free_step(
    st: &mut Stepper,
    [u0, v0, a0, f]: [&[f64]; 4],
    n: usize,
    reps: usize,
    interrupt: &std::sync::atomic::AtomicBool,
) -> Vec<f64> {
    use std::sync::atomic::Ordering;
    let mut rhs = vec![0.0; n];
    let mut rounds = Vec::with_capacity(5);
    'rounds: for _ in 0..5 {
        let t = Instant::now();
        for k in 0..reps {
            if interrupt.load(Ordering::Relaxed) {
                if k > 0 || rounds.is_empty() {
                    rounds.push(t.elapsed().as_secs_f64() / k.max(1) as f64 * 1e6);
                }
                break 'rounds;
            }
            st.rhs_into(u0, v0, a0, f, &mut rhs);
            st.solve(&mut rhs);
        }
        rounds.push(t.elapsed().as_secs_f64() / reps as f64 * 1e6);
        std::hint::black_box(&rhs);
    }
    rounds.sort_by(f64::total_cmp);
    rounds
}
