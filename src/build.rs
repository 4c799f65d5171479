//! Stage 3 of reading a scenario, build: what needs a model. The validated
//! [`Scenario<RunSpec>`] ([`crate::scenario`], plain data) becomes the [`Scenario`] of
//! [`Run`]s that the jobs ([`crate::run`](mod@crate::run)) take, each with its time step `h` resolved:
//!
//! - `cfl` (central difference): `h = cfl * 2 / omega_max`, with `omega_max` the largest
//!   natural circular frequency of the lumped contact bar, found by assembling it (and a
//!   penalty spring on the contact node, if any); see [`crate::time::classic::stable_step`].
//! - a fixed `h` with the central difference: a warning when it exceeds `2 / omega_max`.
//! - a penalty with the central difference: a warning when `h sqrt(k / m) >= 2` on the
//!   contact node of lumped mass `m`.
//!
//! The wheel's mesh is read later, by the wheel job ([`crate::kinds::wheel::run::build`]).

use crate::linalg::bandwidth::{memory_bytes_or_default, physical_memory_bytes};
use crate::scenario::{Contact, Run, RunSpec, Scenario, ScenarioError, TimeStep};
use crate::time::SpaceTimeParams;

/// Builds a validated scenario: every run's step resolved, the warnings of the build added
/// to those of the validation.
///
/// # Errors
/// [`ScenarioError::Invalid`] naming the `cfl` key when the model has no finite stable step
/// (not a bar; the validation refuses `cfl` there already).
pub fn resolve(sc: &Scenario<RunSpec>) -> Result<Scenario, ScenarioError> {
    let mut warnings = sc.warnings.clone();
    let mut runs = Vec::with_capacity(sc.runs.len());
    for (i, spec) in sc.runs.iter().enumerate() {
        let h = resolve_time_step(sc, i, &mut warnings)?;
        runs.push(Run {
            label: spec.label_or_default(sc.runs.len(), h),
            params: SpaceTimeParams {
                alpha: spec.alpha,
                gamma: spec.gamma,
                h,
            },
            model: spec.model.clone(),
            integrator: spec.integrator,
            contact: spec.contact,
            friction: spec.friction,
            t_end: spec.t_end,
            step_key: spec.step_key.clone(),
        });
    }
    Ok(Scenario {
        name: sc.name.clone(),
        description: sc.description.clone(),
        path: sc.path.clone(),
        runs,
        history_stride: sc.history_stride,
        plots: sc.plots,
        warnings,
        sweep: sc.sweep.clone(),
        sweep_ladder: sc.sweep_ladder.clone(),
        sweep_ladder_with: sc.sweep_ladder_with.clone(),
        source_sha256: sc.source_sha256.clone(),
        source_text: sc.source_text.clone(),
        overrides: sc.overrides.clone(),
        growth: sc.growth.clone(),
    })
}

/// The step `h` (s) of run `i` of `sc`: the fixed step, or `cfl * 2 / omega_max` of the
/// central difference; pushes the warnings of an explicit run beyond stability.
///
/// # Errors
/// [`ScenarioError::Invalid`] naming the `cfl` key when the stable step is not finite.
pub fn resolve_time_step(
    sc: &Scenario<RunSpec>,
    i: usize,
    warnings: &mut Vec<String>,
) -> Result<f64, ScenarioError> {
    let run = &sc.runs[i];
    let explicit = run.integrator.is_explicit();
    let penalty = match run.contact {
        Contact::Penalty { stiffness } => Some(stiffness),
        _ => None,
    };
    let h = match &run.step {
        TimeStep::Cfl { cfl, key } => {
            let hc = run.model.explicit_stable_step(penalty);
            if !(hc.is_finite() && hc > 0.0) {
                return Err(ScenarioError::Invalid {
                    path: sc.path.clone(),
                    key: key.clone(),
                    value: cfl.to_string(),
                    allowed: format!(
                        "the stable step of this model is {hc}: cfl needs a bar (bar_impact, two_bars)"
                    ),
                });
            }
            // A step beyond the run computes nothing (no contact, its figures empty).
            if cfl * hc > run.t_end {
                return Err(ScenarioError::Invalid {
                    path: sc.path.clone(),
                    key: key.clone(),
                    value: cfl.to_string(),
                    allowed: format!(
                        "the step it gives, {:.4e} s (cfl x the stable step {hc:.4e} s), exceeds the run, time.t_end = {} s: more elements (bar.elements) or a smaller cfl",
                        cfl * hc,
                        run.t_end
                    ),
                });
            }
            cfl * hc
        }
        &TimeStep::Fixed(h) => {
            if explicit {
                let hc = run.model.explicit_stable_step(penalty);
                if h > hc {
                    let with = if penalty.is_some() {
                        " with the penalty spring"
                    } else {
                        ""
                    };
                    warnings.push(format!(
                        "run {i}: h = {h} exceeds the central difference's stable step{with}, {hc:.4e} s (2/omega_max): expect a blow-up (or set cfl)"
                    ));
                }
            }
            h
        }
    };
    if let (Some(stiffness), true) = (penalty, explicit) {
        let m = run.model.explicit_contact_mass();
        if h * (stiffness / m).sqrt() >= 2.0 {
            warnings.push(format!(
                "run {i}: penalty {stiffness:e} N/m on a node of {m:.3e} kg with the central difference: h sqrt(k/m) = {:.2} >= 2, the explicit penalty is unstable (keep k below {:.3e} N/m)",
                h * (stiffness / m).sqrt(),
                4.0 * m / (h * h)
            ));
        }
    }
    Ok(h)
}

/// What a built scenario will cost, estimated before it runs (rough: within a factor of a
/// few on the machines softway was measured on).
#[derive(Debug, Clone, PartialEq)]
pub struct Estimate {
    /// Time steps over all runs.
    pub steps: f64,
    /// Degrees of freedom of the largest run's model.
    pub dofs: f64,
    /// Run time on one core, s: `steps (2e-7 s dofs + 2e-6 s)` summed over the runs (the
    /// measured cost is about 1.3e-7 s per dof and step on the wheel), for a 3D model plus
    /// [`SOLVE_SECONDS_PER_ENTRY`] per entry of its factor ([`factor_entries_3d`]) a step.
    pub seconds: f64,
    /// Peak memory, bytes: 4 kB per dof (matrices and factors), for a 3D model
    /// [`FACTOR_BYTES_PER_ENTRY`] per entry of its factor ([`factor_entries_3d`]), and 512 bytes per step up to
    /// [`crate::analysis::trace::SPECTRUM_WINDOW_CAP`] steps (the wheel's contact-force window
    /// and its spectral analysis at the end of the run, measured at up to 340 bytes per step;
    /// memory is flat beyond the window, `tests/long_runs.rs`) of the largest run.
    pub memory_bytes: f64,
    /// Bytes of `history.csv` and the other per-step files (300 bytes per written row).
    pub disk_bytes: f64,
    /// The key that sets the step count of the costliest run (`time.h` or `runs[i].h`)
    /// and its value, and the key that sets its model size, for the message.
    pub culprit: String,
}

/// Above these an estimate is refused unless confirmed (`softway run --yes`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Limits {
    /// Run time on one core, s (default 4 h).
    pub seconds: f64,
    /// Memory, bytes (default half the machine's memory, or 4 GiB when unknown).
    pub memory_bytes: f64,
    /// Disk, bytes (default 20 GB).
    pub disk_bytes: f64,
}

impl Default for Limits {
    fn default() -> Self {
        Self {
            seconds: 4.0 * 3600.0,
            memory_bytes: 0.5 * memory_bytes_or_default(),
            disk_bytes: 20e9,
        }
    }
}

/// Estimates the cost of a built scenario; `mesh_nodes` gives the nodes of a wheel whose
/// mesh is a file (read by the caller).
pub fn estimate(sc: &Scenario, mesh_nodes: Option<usize>) -> Estimate {
    let mut e = Estimate {
        steps: 0.0,
        dofs: 0.0,
        seconds: 0.0,
        memory_bytes: 0.0,
        disk_bytes: 0.0,
        culprit: String::new(),
    };
    let mut worst = -1.0;
    for run in &sc.runs {
        let h = run.params.h;
        // The contact solver's dense blocks grow with the square of the rows it may hold
        // (`crate::contact::rows::RowSolver`: two of `rows^2` values): one row a contact
        // pair, two with friction.
        let per_pair = if run.friction.is_some() { 2.0 } else { 1.0 };
        let crate::scenario::kind::Size {
            dofs,
            duration,
            contact_pairs,
            key: size_key,
            factor_entries,
            kept_columns,
        } = run.model.size(run, mesh_nodes);
        let rows = per_pair * contact_pairs;
        let steps = (duration / h).ceil().max(1.0);
        // A 3D model's factor grows faster than its unknowns (2D: within the 4 kB a dof).
        let factor = match factor_entries {
            Some(f) => f,
            None if run.model.dim() == 3 => factor_entries_3d(dofs),
            None => 0.0,
        };
        let seconds = steps * (2e-7 * dofs + 2e-6 + SOLVE_SECONDS_PER_ENTRY * factor);
        e.steps += steps;
        e.seconds += seconds;
        e.dofs = e.dofs.max(dofs);
        let windowed = steps.min(crate::analysis::trace::SPECTRUM_WINDOW_CAP as f64);
        // A moving zone's kept columns, up to their share of the machine's memory.
        let kept = (8.0 * dofs * kept_columns).min(crate::simulation::kept_columns_bytes());
        e.memory_bytes = e.memory_bytes.max(
            4096.0 * dofs
                + FACTOR_BYTES_PER_ENTRY * factor
                + 512.0 * windowed
                + 16.0 * rows * rows
                + kept,
        );
        e.disk_bytes += 300.0 * steps / sc.history_stride as f64;
        if seconds > worst {
            worst = seconds;
            e.culprit = format!("`{}` = {h:e} s over {duration:e} s", run.step_key);
            if let Some(k) = size_key {
                e.culprit.push_str(&format!(", `{k}` ({dofs:.0} dofs)"));
            }
        }
    }
    e
}

/// Entries of the Cholesky factor `L` of a 3D model of `dofs` unknowns, an upper estimate:
/// `24 n^{4/3}`, nested dissection's growth on a 3D mesh (George 1973; Lipton, Rose and
/// Tarjan 1979), its constant above the cubes of hexahedra and 10-node tetrahedra measured
/// (`examples/solver3d_ladder.rs`: 13.7 to 21.2 `n^{4/3}` for hexahedra from 3,993 to 98,304
/// unknowns). A cube is the worst shape for a number of unknowns; a long body (a rail, a
/// wheel's rim) has smaller separators and fewer entries. `tests/solver3d.rs` checks the
/// bound against the symbolic count on cubes and bars: within a factor of 6 above it.
pub fn factor_entries_3d(dofs: f64) -> f64 {
    24.0 * dofs.powf(4.0 / 3.0)
}

/// Peak bytes of a factorization per entry of `L` (faer's numeric factor, its columns, the
/// solve's dense supernodes, the previous factor while refactoring): measured 59 to 67 on
/// the cubes of `examples/solver3d_ladder.rs` (the process's peak over the factor's
/// entries).
pub const FACTOR_BYTES_PER_ENTRY: f64 = 64.0;

/// Seconds of one solve per entry of `L` on one core: both sweeps read `L` (16 bytes an
/// entry) at about 4 GB/s, the memory bandwidth of the machines measured.
pub const SOLVE_SECONDS_PER_ENTRY: f64 = 4e-9;

/// The most steps a run may take, confirmed or not: at a microsecond a step, eleven days.
pub const MAX_STEPS: f64 = 1e12;

impl Estimate {
    /// The runs repeated `times` times in turn (a growth study's passes): the steps and the
    /// time scale, the memory is the one run's (a pass's model is built once), and no
    /// per-step file is written (a pass keeps its profile's samples, not its history).
    pub fn repeated(&self, times: f64) -> Estimate {
        Estimate {
            steps: self.steps * times,
            seconds: self.seconds * times,
            disk_bytes: 0.0,
            ..self.clone()
        }
    }

    /// `None` when the run can be carried out at all, else why not, whatever the user
    /// confirms: more steps than [`MAX_STEPS`] (or not a number), or more memory than this
    /// machine has.
    pub fn impossible(&self) -> Option<String> {
        if self.steps.is_nan() || self.steps > MAX_STEPS {
            return Some(format!(
                "this run would take {:.3e} steps (at most {MAX_STEPS:e} can be run, with or without --yes); check {}",
                self.steps, self.culprit
            ));
        }
        match physical_memory_bytes() {
            Some(total) if self.memory_bytes > total => Some(format!(
                "this run would need about {} of memory, more than this machine's {} (with or without --yes); check {}",
                human_bytes(self.memory_bytes),
                human_bytes(total),
                self.culprit
            )),
            _ => None,
        }
    }

    /// `None` within `limits`, else the one-line reason (what would be exceeded, by how
    /// much, and the keys that set it).
    pub fn check(&self, limits: &Limits) -> Option<String> {
        let over = self.seconds > limits.seconds
            || self.memory_bytes > limits.memory_bytes
            || self.disk_bytes > limits.disk_bytes;
        over.then(|| {
            format!(
                "this run would take about {:.3e} steps of {:.0} dofs: {} on one core, {} of memory and {} of per-step files (limits {}, {}, {}); check {}, or pass --yes to run it anyway",
                self.steps,
                self.dofs,
                human_seconds(self.seconds),
                human_bytes(self.memory_bytes),
                human_bytes(self.disk_bytes),
                human_seconds(limits.seconds),
                human_bytes(limits.memory_bytes),
                human_bytes(limits.disk_bytes),
                self.culprit
            )
        })
    }
}

fn human_seconds(s: f64) -> String {
    if s < 120.0 {
        format!("{s:.0} s")
    } else if s < 7200.0 {
        format!("{:.0} min", s / 60.0)
    } else if s < 3.0 * 86400.0 {
        format!("{:.1} h", s / 3600.0)
    } else if s < 1e4 * 86400.0 {
        format!("{:.0} days", s / 86400.0)
    } else {
        format!("{:.3e} days", s / 86400.0)
    }
}

fn human_bytes(b: f64) -> String {
    const UNITS: [&str; 5] = ["B", "kB", "MB", "GB", "TB"];
    let mut x = b;
    for u in UNITS {
        if x < 1000.0 {
            return format!("{x:.0} {u}");
        }
        x /= 1000.0;
    }
    format!("{:.3e} TB", b / 1e12)
}

#[cfg(test)]
mod tests {

    /// The documented defaults: 4 h, 20 GB, at most half the machine's memory.
    #[test]
    fn the_default_limits_are_the_documented_ones() {
        let l = Limits::default();
        assert_eq!(l.seconds, 4.0 * 3600.0);
        assert_eq!(l.disk_bytes, 20e9);
        let half = 0.5 * memory_bytes_or_default();
        assert_eq!(l.memory_bytes, half);
        assert!(l.memory_bytes > 1e8);
    }

    /// Every scenario shipped is within the default limits of a machine of 16 GB (none
    /// needs --yes); a step of 1e-12 s on the paper's bar is refused with the step count
    /// and the key.
    #[test]
    fn the_estimate_passes_the_shipped_scenarios_and_refuses_a_tiny_step() {
        let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenarios");
        let limits = Limits {
            memory_bytes: 8e9,
            ..Limits::default()
        };
        let mut n = 0;
        for f in std::fs::read_dir(&dir).unwrap() {
            let p = f.unwrap().path();
            let sc = resolve(&Scenario::from_file(&p).unwrap()).unwrap();
            let e = estimate(&sc, None);
            assert!(e.check(&limits).is_none(), "{}: {e:?}", p.display());
            n += 1;
        }
        assert!(n >= 9);
        let text = std::fs::read_to_string(dir.join("bar-impact.toml")).unwrap();
        let sc = Scenario::from_str(&text, Path::new("bar.toml")).unwrap();
        let mut sc = resolve(&sc).unwrap();
        sc.runs.truncate(1);
        sc.runs[0].params.h = 1e-12;
        let e = estimate(&sc, None);
        assert!(e.steps > 1e12, "{e:?}");
        let why = e.check(&limits).unwrap();
        assert!(
            // bar-impact.toml's runs set their own step: the key is the run's.
            why.contains("`runs[0].h` = 1e-12 s") && why.contains("--yes"),
            "{why}"
        );
    }
    use super::*;
    use std::path::Path;

    /// The bar with `time.h = 0.1` unless `integrator_and_step` sets a `cfl` (a step
    /// setting that no run uses is refused).
    fn bar(integrator_and_step: &str, contact: &str) -> String {
        let h = if integrator_and_step.contains("cfl") {
            ""
        } else {
            "h = 0.1"
        };
        format!(
            r#"
kind = "bar_impact"
[time]
{h}
t_end = 4.0
{integrator_and_step}
[bar]
length = 2.0
ea = 3.0
rho_a = 0.5
speed = 1.0
gap = 0.5
elements = 10
mass = "lumped"
[contact]
{contact}
"#
        )
    }

    fn validated(text: &str) -> Scenario<RunSpec> {
        Scenario::from_str(text, Path::new("b.toml")).unwrap()
    }

    /// The uniform free-free lumped bar of `N` elements of length `dx`: `omega_k =
    /// (2 c / dx) sin(k pi / (2 N))`, `k = 0..N`, so `omega_max = 2 c / dx` (k = N, the
    /// nodes alternating) and `h = cfl * 2 / omega_max = cfl * dx / c`.
    #[test]
    fn cfl_gives_the_analytic_step_of_the_lumped_bar() {
        let (length, ea, rho_a, n) = (2.0_f64, 3.0_f64, 0.5_f64, 10.0_f64);
        let c = (ea / rho_a).sqrt();
        let dx = length / n;
        let omega_max = 2.0 * c / dx;
        for cfl in [0.9, 0.5, 1.0] {
            let sc = validated(&bar(
                &format!("integrator = \"central_difference\"\ncfl = {cfl}"),
                "method = \"exact\"",
            ));
            let built = resolve(&sc).unwrap();
            let h = built.runs[0].params.h;
            let exact = cfl * 2.0 / omega_max;
            assert!(
                ((h - exact) / exact).abs() < 1e-9,
                "cfl {cfl}: h = {h:e}, analytic {exact:e}"
            );
            assert!(built.warnings.is_empty(), "{:?}", built.warnings);
        }
    }

    /// Two bars: the step of bar A alone (the contact bar), here with the same data.
    #[test]
    fn two_bars_take_the_step_of_bar_a() {
        let text = bar(
            "integrator = \"central_difference\"\ncfl = 0.8",
            "method = \"exact\"",
        )
        .replace("kind = \"bar_impact\"", "kind = \"two_bars\"")
        .replace("[bar]", "[two_bars]");
        let h = resolve(&validated(&text)).unwrap().runs[0].params.h;
        let b = validated(&text).runs[0]
            .model
            .get::<crate::bodies::bar::TwoBars>()
            .expect("two bars")
            .bar_a();
        let exact = 0.8 * (b.length / b.elements as f64) / b.wave_speed();
        assert!(((h - exact) / exact).abs() < 1e-9, "{h:e} vs {exact:e}");
    }

    /// A penalty spring on the contact node raises `omega_max`: a smaller step; one end
    /// spring `k` on the lumped end mass `m = rho A dx / 2` bounds `omega_max^2` by
    /// Gershgorin, `(2 EA / dx + k) / m`.
    #[test]
    fn cfl_with_a_penalty_spring_shrinks_the_step_within_gershgorin() {
        let free = resolve(&validated(&bar(
            "integrator = \"central_difference\"\ncfl = 1.0",
            "method = \"exact\"",
        )))
        .unwrap()
        .runs[0]
            .params
            .h;
        let k = 400.0;
        let sc = validated(&bar(
            "integrator = \"central_difference\"\ncfl = 1.0",
            &format!("method = \"penalty\"\npenalty = {k}"),
        ));
        let built = resolve(&sc).unwrap();
        let h = built.runs[0].params.h;
        let (ea, rho_a, dx) = (3.0_f64, 0.5_f64, 0.2_f64);
        let m = rho_a * dx / 2.0;
        let gershgorin = 2.0 / ((2.0 * ea / dx + k) / m).sqrt();
        assert!(
            h < free && h >= gershgorin * (1.0 - 1e-12),
            "{h} {free} {gershgorin}"
        );
        // cfl = 1 with the spring included: h sqrt(k/m) < 2, no penalty warning.
        assert!(built.warnings.is_empty(), "{:?}", built.warnings);
    }

    #[test]
    fn a_fixed_explicit_step_beyond_stability_warns_at_build_only() {
        // dx / c = 0.2 / sqrt(6) = 0.0816 s < h = 0.1 s.
        let sc = validated(&bar(
            "integrator = \"central_difference\"",
            "method = \"exact\"",
        ));
        assert!(
            sc.warnings.is_empty(),
            "validation warned: {:?}",
            sc.warnings
        );
        let built = resolve(&sc).unwrap();
        assert_eq!(built.runs[0].params.h, 0.1);
        assert_eq!(built.warnings.len(), 1, "{:?}", built.warnings);
        assert!(
            built.warnings[0].contains("stable step"),
            "{:?}",
            built.warnings
        );
    }

    #[test]
    fn labels_default_to_the_resolved_step() {
        // Both runs set their own step: no time.h.
        let text = bar("integrator = \"central_difference\"", "method = \"exact\"")
            .replace("h = 0.1\n", "")
            + "[[runs]]\ncfl = 0.5\n[[runs]]\nh = 0.01\nlabel = \"given\"\n";
        let built = resolve(&validated(&text)).unwrap();
        let h0 = built.runs[0].params.h;
        assert_eq!(built.runs[0].label, format!("h = {h0}"));
        assert_eq!(built.runs[1].label, "given");
    }
}
