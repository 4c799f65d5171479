//! `kind = "wheel"`: the elastic wheel rolling in its rotating frame on a rigid base (the
//! paper's §4, Figs. 10-17), or pressed into an elastic block (`[block]`). Its tables:
//! `[wheel]`, `[material]`, `[rolling]`, `[block]`, `[contact]` (its `validate` module); its run:
//! [`crate::kinds::wheel::run`].

use crate::contact::Treatment;
use crate::growth::GrowOptions;
use crate::growth::{GrowthConfig, GrowthError, PassRunner};
use crate::kinds::wheel::growth::WheelPassRunner;
use crate::run::error::RunError;
use crate::run::options::RunOptions;
use crate::run::results::Results;
use crate::scenario::combinations::{
    constraint_mode_factor, Culprit, Family, Refusal, MAX_CONSTRAINT_MODE_FACTOR,
};
use crate::scenario::kind::{FreeStep, Kind, KindInput, Model, RunView, Size, Spec};
use crate::scenario::raw::{RawBlock, RawMaterial, RawRolling, RawWheel};
use crate::scenario::{Ctx, MeshSource, Run, Scenario, ScenarioError, WheelScenario};
use crate::time::Integrator;
use std::path::Path;

pub mod growth;
pub mod large;
mod large_keys;
pub mod modes;
pub(crate) mod on_block;
pub(crate) mod rules;
pub mod run;
pub(crate) mod validate;

/// The kind `wheel`.
pub struct WheelKind;

#[derive(serde::Deserialize)]
struct Tables {
    wheel: Option<RawWheel>,
    material: Option<RawMaterial>,
    rolling: Option<RawRolling>,
    block: Option<RawBlock>,
}

impl Kind for WheelKind {
    fn name(&self) -> &'static str {
        "wheel"
    }

    fn studies(&self) -> &'static [&'static str] {
        &["modes"]
    }

    fn tables(&self) -> &'static [&'static str] {
        &["wheel", "material", "rolling", "block", "contact"]
    }

    fn model(&self, input: &KindInput) -> Result<Model, ScenarioError> {
        let cx = input.cx;
        let t = input.tables::<Tables>()?;
        let fields_per_turn = t.rolling.as_ref().and_then(|r| r.fields_per_turn);
        let mut w = validate::wheel_model(cx, t.wheel, t.material, t.rolling)?;
        if let Some(b) = t.block {
            if let Some(n) = fields_per_turn {
                return Err(cx.invalid(
                    "rolling.fields_per_turn",
                    n,
                    "the velocity snapshots of the wheel on its rigid base, not written with a [block] (its run writes the last state's fields): remove it",
                ));
            }
            if let Some(p) = w.load {
                return Err(cx.invalid(
                    "wheel.load",
                    p,
                    "not with a [block] (the block is pressed to rolling.flattening): give rolling.flattening",
                ));
            }
            w.block = Some(rules::block_spec(cx, b, &w.spec)?);
        }
        Ok(Model::new(w))
    }
}

/// The rim's nodes of a wheel's mesh (a Gmsh file's from its `file_nodes`, as if uniform).
fn rim_nodes(mesh: &MeshSource, file_nodes: Option<usize>) -> f64 {
    match mesh {
        &MeshSource::Rings(n) => 6.0 * n as f64,
        &MeshSource::Graded { rim_nodes, .. } => rim_nodes as f64,
        MeshSource::Zone(z) => {
            z.rim_nodes as f64
                + z.zone_rim_nodes as f64 * z.zone_width / (2.0 * std::f64::consts::PI)
        }
        MeshSource::Gmsh(_) => (4.0 * std::f64::consts::PI * file_nodes.unwrap_or(0) as f64).sqrt(),
    }
}

/// The nodes of the block under a wheel, without building it
/// ([`crate::bodies::block::WheelOnBlock::new`]): columns of `block.dx` (default the rim's
/// pitch) over the travel of a run of `duration` s and the margins, by rows from `dx` growing
/// by `block.grading` down to the depth.
fn block_nodes(
    b: &crate::bodies::block::BlockSpec,
    w: &crate::bodies::wheel::WheelSpec,
    duration: f64,
    rim: f64,
) -> f64 {
    let pitch = 2.0 * std::f64::consts::PI * w.radius / rim.max(1.0);
    let dx = b.dx.unwrap_or(pitch);
    let length = 2.0 * b.margin + w.omega.abs() * w.radius * duration;
    let columns = (length / dx).min(1e12) + 1.0;
    let (mut rows, mut h, mut depth) = (1.0, dx, 0.0);
    while depth < b.depth && rows < 1e7 {
        depth += h;
        h *= b.grading;
        rows += 1.0;
    }
    columns * rows
}

/// The nodes of a wheel's generated mesh, without building it (`None` for a file): the
/// hexagonal disk's `1 + 3 n (n + 1)`, the graded disk's `rim^2 / (4 pi)` when uniform
/// (grading below 1.05), else `1.2 rim ln(rim)` (above the measured 1,715 nodes at 288 rim
/// nodes and 10,811 at 1,440; [`crate::mesh::generators::disk_graded`]).
pub fn wheel_nodes(mesh: &MeshSource) -> Option<f64> {
    match mesh {
        &MeshSource::Rings(n) => Some(1.0 + 3.0 * n as f64 * (n as f64 + 1.0)),
        &MeshSource::Graded {
            rim_nodes,
            grading,
            band,
        } => {
            let r = rim_nodes as f64;
            // The symmetric band's rings: ln(R / (R - band)) / ln(1 + pi sqrt(3) / n) of
            // the rim's count each (a band of depth d under a rim of radius R holds about
            // n^2 d / (pi sqrt(3) R) nodes; the estimate takes d / R from the count alone,
            // at its largest, 0.9).
            let banded = band.map_or(0.0, |_| r * r * 0.9 / (std::f64::consts::PI * 3f64.sqrt()));
            Some(
                banded
                    + if grading < 1.05 {
                        r * r / (4.0 * std::f64::consts::PI)
                    } else {
                        1.2 * r * r.ln()
                    },
            )
        }
        MeshSource::Gmsh(_) => None,
        // The coarse disk's nodes, plus the zone's square cells at the fine pitch down to
        // its depth (about the zone's width).
        MeshSource::Zone(z) => {
            let r = z.rim_nodes as f64;
            let zone = z.zone_rim_nodes as f64 * z.zone_width / (2.0 * std::f64::consts::PI);
            Some(1.2 * r * r.ln() + zone * zone / 4.0)
        }
    }
}

impl Spec for WheelScenario {
    crate::spec_plumbing!("wheel");

    fn dim(&self) -> usize {
        2
    }

    fn end_time(&self, cx: &Ctx, given: Option<f64>) -> Result<f64, ScenarioError> {
        if let Some(t) = given {
            return Err(cx.invalid(
                "time.t_end",
                t,
                "a wheel run lasts rolling.settle_time + rolling.turns turns: remove time.t_end",
            ));
        }
        Ok(self.duration())
    }

    fn end_phrase(&self, t_end: f64) -> String {
        format!(
            "the step must not exceed the run, rolling.settle_time + rolling.turns turns = {t_end} s"
        )
    }

    fn check_scenario(&self, cx: &Ctx, runs: usize, _: bool) -> Result<(), ScenarioError> {
        if runs > 1 {
            return Err(cx.invalid(
                "runs[1]",
                "(a second run)",
                "a wheel scenario runs one run (runs[0]); the others would be dropped: give one [[runs]] entry, or vary a key with `softway sweep --set KEY=V1,V2,...`",
            ));
        }
        Ok(())
    }

    fn coriolis(&self) -> Option<String> {
        (!self.spec.rotating_frame)
            .then(|| "wheel.rotating_frame = false: the wheel's model has no Coriolis term".into())
    }

    fn combination(
        &self,
        integrator: &Integrator,
        contact: &Treatment,
    ) -> Option<Result<(), Refusal>> {
        let refuse = |why: String| {
            Some(Err(Refusal {
                culprit: Culprit::Integrator,
                why,
            }))
        };
        match (Family::of(integrator), integrator) {
            (Family::Explicit, _) => refuse(
                "the wheel's stable explicit step is about 1e-8 s (hundreds of millions of steps a turn); use \"space_time\", \"newmark\", \"newmark_dissipative\", \"hht\" or \"generalized_alpha\"".into(),
            ),
            (Family::Implicit, Integrator::Classic { params, .. })
                if matches!(contact, Treatment::Exact)
                    && constraint_mode_factor(*params) > MAX_CONSTRAINT_MODE_FACTOR =>
            {
                refuse(format!(
                    "with method = \"exact\" on the rolling wheel this integrator leaves the contact multipliers' period-2h mode undamped (displacement-level constraints under a trapezoidal rule without numerical dissipation: it carries {:.1}% of the mode to the next step) and the active set, changing at every node passing, feeds it (the paper's wheel: energy 327 J -> 2.1e10 J); use \"newmark_dissipative\", \"hht\" or \"generalized_alpha\" with their default damping, or \"space_time\", or method = \"mass_redistribution\", \"moreau_jean\" or \"penalty\"",
                    100.0 * constraint_mode_factor(*params)
                ))
            }
            _ => None,
        }
    }

    fn check_run(&self, cx: &Ctx, run: &RunView) -> Result<(), ScenarioError> {
        rules::check_wheel_run(cx, self, run.friction, run.contact, run.integrator.0)
    }

    fn size(&self, _: &Run, mesh_nodes: Option<usize>) -> Size {
        let nodes = wheel_nodes(&self.mesh)
            .or(mesh_nodes.map(|n| n as f64))
            .unwrap_or(0.0);
        let mut key = match self.mesh {
            MeshSource::Rings(_) => "wheel.rings",
            MeshSource::Graded { .. } => "wheel.rim_nodes",
            MeshSource::Gmsh(_) => "wheel.mesh",
            MeshSource::Zone(_) => "wheel.zone_rim_nodes",
        };
        // The block's nodes count with the wheel's (a block.dx of 1 um built a block of
        // millions of nodes, the run deaf to its keys and to SIGTERM: issue 47).
        let block = self.block.as_ref().map_or(0.0, |b| {
            block_nodes(
                b,
                &self.spec,
                self.duration(),
                rim_nodes(&self.mesh, mesh_nodes),
            )
        });
        if block > nodes {
            key = if self.block.as_ref().is_some_and(|b| b.dx.is_some()) {
                "block.dx"
            } else {
                "block.margin"
            };
        }
        let nodes = nodes + block;
        Size {
            dofs: 2.0 * nodes,
            duration: self.duration(),
            contact_pairs: rim_nodes(&self.mesh, mesh_nodes),
            key: Some(key),
            factor_entries: None,
            // The zone's rows touch the rim nodes' two dofs.
            kept_columns: match self.mesh {
                MeshSource::Zone(_) => 2.0 * rim_nodes(&self.mesh, mesh_nodes),
                _ => 0.0,
            },
        }
    }

    fn mesh_nodes(&self, scenario: &Path) -> Result<Option<usize>, RunError> {
        match &self.mesh {
            MeshSource::Gmsh(p) => Ok(Some(
                crate::kinds::wheel::run::read_mesh_file(p, &self.spec, scenario)?.n_nodes(),
            )),
            _ => Ok(None),
        }
    }

    /// The spun-up wheel with a velocity `1e-3 sin(i)` and its load.
    fn free_step(&self, _: &Run, scenario: &Path) -> Option<Result<FreeStep, RunError>> {
        Some(run::build(self, scenario).map(|wm| {
            let n = wm.model.n();
            FreeStep {
                v0: (0..n).map(|i| 1e-3 * (i as f64).sin()).collect(),
                model: wm.model.clone(),
                fixed: wm.fixed_dofs.clone(),
                u0: wm.u_spin.clone(),
                f: wm.load.clone(),
            }
        }))
    }

    fn study(&self, command: &str) -> Option<&dyn crate::scenario::kind::Study> {
        (command == "modes").then_some(&modes::WheelModes as &dyn crate::scenario::kind::Study)
    }

    fn growth_runner(
        &self,
        sc: &Scenario,
        config: &GrowthConfig,
        opts: &GrowOptions,
    ) -> Result<Box<dyn PassRunner>, GrowthError> {
        // Every rim point passes the contact as often in a pass: whole turns (a part of a
        // turn wore part of the rim and grew a polygon of its own, +10,000 dB).
        if !(self.turns >= 1.0 && self.turns.fract() == 0.0) {
            return Err(GrowthError::Run(RunError::input(
                &sc.path,
                format!("`rolling.turns` = {}: a growth study rolls whole turns, at least one (each rim point then passes the contact as often)", self.turns),
            )));
        }
        if let Some(k) = config.rail.given().first() {
            return Err(GrowthError::Run(RunError::input(
                &sc.path,
                format!("{k} is a rail's key (kind = \"track\"): the wheel on its rigid base slides by rolling.creepage under contact.friction; remove it"),
            )));
        }
        Ok(Box::new(WheelPassRunner::new(
            sc,
            config.wear,
            config.wear_density,
            opts.par,
        )?))
    }

    fn record(
        &self,
        sc: &Scenario,
        stream: Option<&Path>,
        opts: &RunOptions,
    ) -> Result<Results, RunError> {
        crate::kinds::wheel::run::record(sc, stream, opts)
    }
}
