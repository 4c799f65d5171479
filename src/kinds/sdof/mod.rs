//! `kind = "sdof"`: the one-degree-of-freedom oscillator `m x'' + k x = 0` of the paper's
//! Eqs. (9)-(10), run by the space-time scheme alone and compared with the exact solution
//! (its `run` module).

use crate::contact::Treatment;
use crate::run::error::RunError;
use crate::run::options::RunOptions;
use crate::run::results::Results;
use crate::scenario::combinations::{Culprit, Family, Refusal};
use crate::scenario::kind::{Kind, KindInput, Model, Size, Spec};
use crate::scenario::raw::RawSdof;
use crate::scenario::{Ctx, Run, Scenario, ScenarioError, Sdof};
use crate::time::Integrator;
use std::path::Path;

pub(crate) mod run;

/// The kind `sdof`.
pub struct SdofKind;

#[derive(serde::Deserialize)]
struct Tables {
    sdof: Option<RawSdof>,
}

impl Kind for SdofKind {
    fn name(&self) -> &'static str {
        "sdof"
    }

    fn tables(&self) -> &'static [&'static str] {
        &["sdof"]
    }

    fn model(&self, input: &KindInput) -> Result<Model, ScenarioError> {
        let cx = input.cx;
        let s = input
            .tables::<Tables>()?
            .sdof
            .ok_or_else(|| cx.missing("sdof", "kind = \"sdof\" needs a [sdof] table"))?;
        Ok(Model::new(Sdof {
            mass: cx.positive("sdof.mass", s.mass)?,
            stiffness: cx.positive("sdof.stiffness", s.stiffness)?,
            x0: cx.finite("sdof.x0", s.x0.unwrap_or(1.0))?,
            v0: cx.finite("sdof.v0", s.v0.unwrap_or(0.0))?,
        }))
    }
}

impl Spec for Sdof {
    crate::spec_plumbing!("sdof");

    fn dim(&self) -> usize {
        1
    }

    fn end_time(&self, cx: &Ctx, given: Option<f64>) -> Result<f64, ScenarioError> {
        given.ok_or_else(|| cx.missing("time.t_end", "the end time of the run, s"))
    }

    fn no_contact(&self) -> Option<&'static str> {
        Some("the oscillator has no contact")
    }

    fn combination(&self, integrator: &Integrator, _: &Treatment) -> Option<Result<(), Refusal>> {
        Some(match Family::of(integrator) {
            Family::SpaceTime => Ok(()),
            _ => Err(Refusal {
                culprit: Culprit::Integrator,
                why: "the one-degree-of-freedom scheme is the space-time scheme's (Eqs. 9-10); use \"space_time\"".into(),
            }),
        })
    }

    fn size(&self, run: &Run, _: Option<usize>) -> Size {
        Size {
            dofs: 1.0,
            duration: run.t_end,
            contact_pairs: 2.0,
            key: None,
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
        run::record(sc, stream, opts)
    }
}
