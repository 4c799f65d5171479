//! `kind = "press"`: the 3D wheel pressed on the 3D rail by a vertical force, frictionless
//! and static ([`solve`]: two elastic bodies on one factorization; [`geometry`]: where the
//! wheel stands on the rail), with the pressure map and Hertz's ellipse ([`files`]).
//!
//! Its tables (lengths as their keys say; every key but `press.load_kN` has a default):
//!
//! ```toml
//! [press]
//! load_kN = 10.0              # the vertical load
//! lateral_mm = 0.0            # the wheel's shift toward the field side
//! shear_modulus_GPa = 82.0    # both bodies (CONTACT's input for the Manchester case)
//! poisson = 0.28
//! contact_size_mm = 1.0       # cells in the contact zone
//! zone_mm = [6.0, 12.0]       # the zone's half-lengths along and across the rail
//! growth = 1.3                # ratio of successive cells away from the zone
//! approach_depth_mm = 15.0    # the local approach's points below the patch
//! [wheel]
//! profile = "s1002"           # or "conical" (1:40)
//! radius_m = 0.46
//! sector_deg = 30.0           # half-angle of the sector kept (its cut faces held)
//! depth_mm = 80.0             # the ring of the tyre kept below the running circle (its
//!                             # inner face, the "hub ring", held and driven down)
//! [rail]
//! profile = "uic60"
//! inclination = 40            # 1:40; 0 for an upright rail
//! length_m = 0.3
//! ```

use crate::contact::Treatment;
use crate::mesh::generators::{RailSpec, TreadProfile, WheelSpec};
use crate::output::table::Columns;
use crate::run::error::RunError;
use crate::run::options::RunOptions;
use crate::run::results::{Detail, Fields, Results};
use crate::scenario::combinations::Refusal;
use crate::scenario::kind::{FreeStep, Kind, KindInput, Model, Size, Spec};
use crate::scenario::{Ctx, Run, Scenario, ScenarioError};
use crate::time::Integrator;
use std::path::Path;

pub mod files;
pub mod geometry;
pub mod solve;

pub use solve::{press, PressError, PressSpec, Pressed};

/// Entries of the Cholesky factor of a press of `dofs` unknowns (nested dissection), an
/// upper estimate for the cost check: `14 n^{4/3}`. The press's bodies are slender (a tyre
/// sector, a rail), with smaller separators than the cube that sets the generic 3D bound's
/// 24 ([`crate::build::factor_entries_3d`]): measured 9.3 `n^{4/3}` at 27,855 unknowns and
/// 10.4 at 233,295 (`softway matrix`; `tests/cli_errors.rs` checks the bound).
pub fn factor_entries(dofs: f64) -> f64 {
    14.0 * dofs.powf(4.0 / 3.0)
}

/// The kind `press`.
pub struct PressKind;

/// `[press]` as written.
#[derive(serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct RawPress {
    #[serde(rename = "load_kN")]
    load_kn: Option<f64>,
    lateral_mm: Option<f64>,
    #[serde(rename = "shear_modulus_GPa")]
    shear_modulus_gpa: Option<f64>,
    poisson: Option<f64>,
    contact_size_mm: Option<f64>,
    zone_mm: Option<[f64; 2]>,
    growth: Option<f64>,
    approach_depth_mm: Option<f64>,
}

/// `[wheel]` as written.
#[derive(serde::Deserialize, Default)]
#[serde(deny_unknown_fields)]
struct RawWheel {
    profile: Option<String>,
    radius_m: Option<f64>,
    sector_deg: Option<f64>,
    depth_mm: Option<f64>,
    mesh: Option<String>,
}

/// `[rail]` as written.
#[derive(serde::Deserialize, Default)]
#[serde(deny_unknown_fields)]
struct RawRail {
    profile: Option<String>,
    inclination: Option<f64>,
    length_m: Option<f64>,
}

#[derive(serde::Deserialize)]
struct Tables {
    press: Option<RawPress>,
    wheel: Option<RawWheel>,
    rail: Option<RawRail>,
}

/// The validated press: its [`PressSpec`] and the values as the scenario gave them.
#[derive(Debug, Clone, PartialEq)]
pub struct PressScenario {
    /// The press to solve.
    pub spec: PressSpec,
}

impl Kind for PressKind {
    fn name(&self) -> &'static str {
        "press"
    }

    fn tables(&self) -> &'static [&'static str] {
        &["press", "wheel", "rail"]
    }

    fn model(&self, input: &KindInput) -> Result<Model, ScenarioError> {
        let cx = input.cx;
        let t = input.tables::<Tables>()?;
        let p = t
            .press
            .ok_or_else(|| cx.missing("press", "kind = \"press\" needs a [press] table"))?;
        let w = t.wheel.unwrap_or_default();
        let r = t.rail.unwrap_or_default();
        let load = p
            .load_kn
            .ok_or_else(|| cx.missing("press.load_kN", "the vertical load, kN"))?;
        let load = cx.within("press.load_kN", load, 1e-3, 1e3)?;
        let lateral = cx.within("press.lateral_mm", p.lateral_mm.unwrap_or(0.0), -15.0, 15.0)?;
        let g = cx.within(
            "press.shear_modulus_GPa",
            p.shear_modulus_gpa.unwrap_or(82.0),
            1.0,
            1e3,
        )?;
        let nu = cx.within("press.poisson", p.poisson.unwrap_or(0.28), 0.0, 0.49)?;
        let size = cx.within(
            "press.contact_size_mm",
            p.contact_size_mm.unwrap_or(1.0),
            0.05,
            5.0,
        )?;
        let zone = p.zone_mm.unwrap_or([6.0, 12.0]);
        for (k, z) in zone.iter().enumerate() {
            let key = format!("press.zone_mm[{k}]");
            cx.within(&key, *z, 2.0 * size, 30.0)?;
        }
        let growth = cx.within("press.growth", p.growth.unwrap_or(1.3), 1.05, 2.0)?;
        let depth = cx.within(
            "press.approach_depth_mm",
            p.approach_depth_mm.unwrap_or(15.0),
            1.0,
            40.0,
        )?;
        if let Some(m) = &w.mesh {
            return Err(cx.invalid(
                "wheel.mesh",
                format!("\"{m}\""),
                "a Gmsh wheel is not taken by kind = \"press\" (its wheel is generated): remove wheel.mesh",
            ));
        }
        let profile = match w.profile.as_deref().unwrap_or("s1002") {
            "s1002" => TreadProfile::S1002,
            "conical" => TreadProfile::Conical,
            other => {
                return Err(cx.invalid(
                    "wheel.profile",
                    format!("\"{other}\""),
                    "allowed: \"s1002\", \"conical\"",
                ))
            }
        };
        let radius = cx.within("wheel.radius_m", w.radius_m.unwrap_or(0.46), 0.25, 0.7)?;
        let sector = cx.within("wheel.sector_deg", w.sector_deg.unwrap_or(30.0), 5.0, 90.0)?;
        let ring = cx.within(
            "wheel.depth_mm",
            w.depth_mm.unwrap_or(80.0),
            20.0,
            1e3 * radius - 60.0,
        )?;
        match r.profile.as_deref().unwrap_or("uic60") {
            "uic60" => {}
            other => {
                return Err(cx.invalid(
                    "rail.profile",
                    format!("\"{other}\""),
                    "allowed: \"uic60\"",
                ))
            }
        }
        let incl = r.inclination.unwrap_or(40.0);
        if !(incl == 0.0 || (incl.is_finite() && (5.0..=1000.0).contains(&incl))) {
            return Err(cx.invalid(
                "rail.inclination",
                incl,
                "must be 0 (upright) or n of 1:n within [5, 1000]",
            ));
        }
        let length = cx.within("rail.length_m", r.length_m.unwrap_or(0.3), 0.05, 2.0)?;
        let e = 2.0 * g * 1e9 * (1.0 + nu);
        let spec = PressSpec {
            wheel: WheelSpec {
                profile,
                nominal_radius: radius,
                web: None,
                rim_depth: 0.5e-3 * ring,
                bore_radius: radius - 1e-3 * ring,
                ..WheelSpec::default()
            },
            rail: RailSpec {
                length,
                inclination: if incl == 0.0 { 0.0 } else { 1.0 / incl },
                ..RailSpec::default()
            },
            sector: sector.to_radians(),
            material: crate::material::Elastic {
                young: e,
                poisson: nu,
                density: 7850.0,
            },
            load: 1e3 * load,
            lateral: 1e-3 * lateral,
            size: 1e-3 * size,
            zone: (1e-3 * zone[0], 1e-3 * zone[1]),
            growth,
            depth: 1e-3 * depth,
        };
        Ok(Model::new(PressScenario { spec }))
    }
}

impl Spec for PressScenario {
    crate::spec_plumbing!("press");

    fn dim(&self) -> usize {
        3
    }

    fn end_time(&self, cx: &Ctx, given: Option<f64>) -> Result<f64, ScenarioError> {
        match given {
            Some(t) => Err(cx.invalid(
                "time.t_end",
                t,
                "a static press has no time: remove time.t_end",
            )),
            None => Ok(1.0),
        }
    }

    fn no_contact(&self) -> Option<&'static str> {
        Some("the press's contact is static and frictionless, set by its [press] table")
    }

    fn combination(&self, _: &Integrator, _: &Treatment) -> Option<Result<(), Refusal>> {
        Some(Ok(()))
    }

    fn default_step(&self) -> Option<f64> {
        Some(1.0)
    }

    fn check_step(&self, cx: &Ctx, key: &str, h: f64) -> Result<(), ScenarioError> {
        if h == 1.0 {
            Ok(())
        } else {
            Err(cx.invalid(key, h, "a static press has no time step: remove it"))
        }
    }

    fn size(&self, _run: &Run, _: Option<usize>) -> Size {
        let s = &self.spec;
        let dofs = solve::press_dofs(s).unwrap_or(0) as f64;
        let rows = (2.0 * s.zone.0 / s.size + 1.0) * (2.0 * s.zone.1 / s.size + 1.0);
        Size {
            dofs,
            // One solve a row that becomes active, at most.
            duration: rows,
            contact_pairs: rows,
            key: Some("press.contact_size_mm"),
            factor_entries: Some(factor_entries(dofs)),
            kept_columns: 0.0,
        }
    }

    fn free_step(&self, _: &Run, scenario: &Path) -> Option<Result<FreeStep, RunError>> {
        Some(
            solve::free_model(&self.spec)
                .map(|(model, fixed)| {
                    let n = model.assembler.pattern.nrows();
                    FreeStep {
                        v0: (0..n).map(|i| 1e-3 * (i as f64).sin()).collect(),
                        u0: vec![0.0; n],
                        f: vec![0.0; n],
                        model,
                        fixed,
                    }
                })
                .map_err(|e| RunError::input(scenario, e.to_string())),
        )
    }

    fn record(
        &self,
        sc: &Scenario,
        _stream: Option<&Path>,
        opts: &RunOptions,
    ) -> Result<Results, RunError> {
        let _ = opts;
        let run = &sc.runs[0];
        let Some(m) = run.model.get::<PressScenario>() else {
            unreachable!("a press run of a press scenario")
        };
        let p = press(&m.spec).map_err(|e| RunError::input(&sc.path, e.to_string()))?;
        let mut history = Columns::new(&[
            ("descent_um", "um"),
            ("load_kN", "kN"),
            ("active", "-"),
            ("iterations", "-"),
        ]);
        for s in &p.secant {
            history.push(
                0,
                &[
                    1e6 * s.descent,
                    1e-3 * s.load,
                    s.active as f64,
                    s.iterations as f64,
                ],
            );
        }
        let mut summary = files::summary(sc, &m.spec, &p);
        crate::run::provenance::stamp_provenance(&mut summary, sc);
        let lines = files::lines(&p);
        Ok(Results {
            kind: "press",
            summary,
            history,
            contact_nodes: None,
            traction_history: None,
            rim_profile: None,
            fields: Fields::default(),
            lines,
            interrupted: false,
            warnings: Vec::new(),
            plots: sc.plots,
            detail: Detail::Own(Box::new(files::PressFiles { pressed: p })),
        })
    }
}
