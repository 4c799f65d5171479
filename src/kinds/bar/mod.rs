//! `kind = "bar_impact"` (the elastic bar striking a rigid wall, the paper's Fig. 8) and
//! `kind = "two_bars"` (two equal bars colliding, node to node), both against d'Alembert's
//! exact answer ([`run`]).

use crate::bodies::bar::{BarImpact, TwoBars};
use crate::run::error::RunError;
use crate::run::options::RunOptions;
use crate::run::results::Results;
use crate::scenario::kind::{FreeStep, Kind, KindInput, Model, Size, Spec};
use crate::scenario::raw::RawBar;
use crate::scenario::{Ctx, Run, Scenario, ScenarioError};
use std::path::Path;

pub mod run;

/// The kind `bar_impact`.
pub struct BarImpactKind;

/// The kind `two_bars`.
pub struct TwoBarsKind;

#[derive(serde::Deserialize)]
struct BarTables {
    bar: Option<RawBar>,
}

#[derive(serde::Deserialize)]
struct TwoBarsTables {
    two_bars: Option<RawBar>,
}

/// Whether `model` is a bar (`bar_impact` or `two_bars`): what `softway compare` runs.
pub fn is_bar(model: &Model) -> bool {
    model.get::<BarImpact>().is_some() || model.get::<TwoBars>().is_some()
}

/// `bar.mass` (or `two_bars.mass`): lumped or consistent (the default); a consistent mass
/// is refused when every run is explicit (the central difference runs lumped).
fn lumped(input: &KindInput, key: &str, v: Option<&str>) -> Result<bool, ScenarioError> {
    let cx = input.cx;
    match v {
        None => Ok(false),
        Some("lumped") => Ok(true),
        Some("consistent") if input.every_run_explicit => Err(cx.invalid(
            key,
            "\"consistent\"",
            "every run's integrator = \"central_difference\" runs with the lumped mass: remove it (or set it to \"lumped\")",
        )),
        Some("consistent") => Ok(false),
        Some(other) => Err(cx.invalid(
            key,
            format!("\"{other}\""),
            "allowed: \"consistent\", \"lumped\"",
        )),
    }
}

/// The bar's `elements` (key `key`), 0 when not given: then every run must give its own.
fn elements(cx: &Ctx, key: &str, v: Option<i64>) -> Result<usize, ScenarioError> {
    v.map_or(Ok(0), |e| cx.count(key, e, 1_000_000))
}

/// The bar of table `table` (`[bar]` or `[two_bars]`), each value checked under its key
/// (`damping` 0 when not given).
fn bar_of(input: &KindInput, table: &str, b: &RawBar) -> Result<BarImpact, ScenarioError> {
    let cx = input.cx;
    let key = |k: &str| format!("{table}.{k}");
    Ok(BarImpact {
        lumped: lumped(input, &key("mass"), b.mass.as_deref())?,
        length: cx.positive(&key("length"), b.length)?,
        ea: cx.positive(&key("ea"), b.ea)?,
        rho_a: cx.positive(&key("rho_a"), b.rho_a)?,
        speed: cx.positive(&key("speed"), b.speed)?,
        gap: cx.non_negative(&key("gap"), b.gap)?,
        elements: elements(cx, &key("elements"), b.elements)?,
        damping: cx.non_negative(&key("damping"), b.damping.unwrap_or(0.0))?,
    })
}

impl Kind for BarImpactKind {
    fn name(&self) -> &'static str {
        "bar_impact"
    }

    fn tables(&self) -> &'static [&'static str] {
        &["bar", "contact"]
    }

    fn model(&self, input: &KindInput) -> Result<Model, ScenarioError> {
        let cx = input.cx;
        let b = input
            .tables::<BarTables>()?
            .bar
            .ok_or_else(|| cx.missing("bar", "kind = \"bar_impact\" needs a [bar] table"))?;
        Ok(Model::new(bar_of(input, "bar", &b)?))
    }
}

impl Kind for TwoBarsKind {
    fn name(&self) -> &'static str {
        "two_bars"
    }

    fn tables(&self) -> &'static [&'static str] {
        &["two_bars", "contact"]
    }

    fn model(&self, input: &KindInput) -> Result<Model, ScenarioError> {
        let cx = input.cx;
        let b = input.tables::<TwoBarsTables>()?.two_bars.ok_or_else(|| {
            cx.missing("two_bars", "kind = \"two_bars\" needs a [two_bars] table")
        })?;
        if let Some(d) = b.damping {
            return Err(cx.invalid(
                "two_bars.damping",
                d,
                "the two-bars case has no external damping",
            ));
        }
        let a = bar_of(input, "two_bars", &b)?;
        Ok(Model::new(TwoBars {
            length: a.length,
            ea: a.ea,
            rho_a: a.rho_a,
            speed: a.speed,
            gap: a.gap,
            elements: a.elements,
            lumped: a.lumped,
        }))
    }
}

/// `t_end` when the bar (table `table`, moving at `speed` towards `what` across `gap`)
/// touches it before the end of the run, else the refusal naming `time.t_end`.
fn reached(
    cx: &Ctx,
    (table, what): (&str, &str),
    (gap, speed): (f64, f64),
    given: Option<f64>,
) -> Result<f64, ScenarioError> {
    let t_end = given.ok_or_else(|| cx.missing("time.t_end", "the end time of the run, s"))?;
    let t_touch = gap / speed;
    if t_touch < t_end {
        return Ok(t_end);
    }
    Err(cx.invalid(
        "time.t_end",
        t_end,
        &format!(
            "the bar reaches the {what} at {table}.gap / {table}.speed = {gap} m / {speed} m/s = {t_touch:e} s, not before the run ends: nothing would touch; take time.t_end > {t_touch:e} s or a smaller {table}.gap"
        ),
    ))
}

/// The stable step `2 / omega_max` (s) of the central difference on the contact bar
/// (lumped), with a penalty spring `k` (N/m) on the contact dof.
fn stable_step(mut bar: BarImpact, k: f64) -> f64 {
    bar.lumped = true;
    let mut m = bar.model(&bar.mesh());
    let pattern = m.pattern().clone();
    let (cp, ri) = (pattern.col_ptr(), pattern.row_idx());
    let d = bar.elements;
    for p in cp[d]..cp[d + 1] {
        if ri[p] == d {
            m.k[p] += k;
        }
    }
    crate::time::classic::stable_step(&m, &[])
}

/// The lumped mass of the bar's contact node, kg.
fn node_mass(b: &BarImpact) -> f64 {
    b.rho_a * b.length / (2.0 * b.elements as f64)
}

fn record(sc: &Scenario, stream: Option<&Path>, opts: &RunOptions) -> Result<Results, RunError> {
    run::record(sc, stream, opts)
}

impl Spec for BarImpact {
    crate::spec_plumbing!("bar_impact");

    /// The bar's initial state, without load.
    fn free_step(&self, run: &Run, _: &Path) -> Option<Result<FreeStep, RunError>> {
        let (_, p) = self.problem(run.integrator, run.contact, run.params.h, run.t_end);
        let n = p.model.n();
        Some(Ok(FreeStep {
            model: p.model,
            fixed: vec![],
            u0: p.u0,
            v0: p.v0,
            f: vec![0.0; n],
        }))
    }

    fn dim(&self) -> usize {
        1
    }

    fn end_time(&self, cx: &Ctx, given: Option<f64>) -> Result<f64, ScenarioError> {
        reached(cx, ("bar", "obstacle"), (self.gap, self.speed), given)
    }

    fn elements_mut(&mut self) -> Option<(&'static str, &mut usize)> {
        Some(("bar", &mut self.elements))
    }

    fn make_explicit(&mut self) {
        self.lumped = true;
    }

    fn explicit_stable_step(&self, penalty: Option<f64>) -> f64 {
        stable_step(*self, penalty.unwrap_or(0.0))
    }

    fn explicit_contact_mass(&self) -> f64 {
        node_mass(self)
    }

    fn size(&self, run: &Run, _: Option<usize>) -> Size {
        Size {
            dofs: self.elements as f64 + 1.0,
            duration: run.t_end,
            contact_pairs: 2.0,
            key: Some("bar.elements"),
            factor_entries: None,
            kept_columns: 0.0,
        }
    }

    fn record(
        &self,
        sc: &Scenario,
        stream: Option<&Path>,
        opts: &RunOptions,
    ) -> Result<Results, RunError> {
        record(sc, stream, opts)
    }
}

impl Spec for TwoBars {
    crate::spec_plumbing!("two_bars");

    fn dim(&self) -> usize {
        1
    }

    fn end_time(&self, cx: &Ctx, given: Option<f64>) -> Result<f64, ScenarioError> {
        reached(cx, ("two_bars", "other bar"), (self.gap, self.speed), given)
    }

    fn default_method(&self) -> &'static str {
        "exact"
    }

    fn elements_mut(&mut self) -> Option<(&'static str, &mut usize)> {
        Some(("two_bars", &mut self.elements))
    }

    fn make_explicit(&mut self) {
        self.lumped = true;
    }

    /// Bar A's step, with the spring `2 k` between two equal facing nodes (it acts on their
    /// relative motion at twice the rate).
    fn explicit_stable_step(&self, penalty: Option<f64>) -> f64 {
        stable_step(self.bar_a(), 2.0 * penalty.unwrap_or(0.0))
    }

    fn explicit_contact_mass(&self) -> f64 {
        node_mass(&self.bar_a())
    }

    fn size(&self, run: &Run, _: Option<usize>) -> Size {
        Size {
            dofs: 2.0 * (self.elements as f64 + 1.0),
            duration: run.t_end,
            contact_pairs: 2.0,
            key: Some("two_bars.elements"),
            factor_entries: None,
            kept_columns: 0.0,
        }
    }

    fn record(
        &self,
        sc: &Scenario,
        stream: Option<&Path>,
        opts: &RunOptions,
    ) -> Result<Results, RunError> {
        record(sc, stream, opts)
    }
}
