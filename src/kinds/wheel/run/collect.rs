//! A wheel run's [`Results`]: the scenario's first run through [`simulate`], its summary
//! as `summary.json` holds it, its tables, and its fields for ParaView.

use super::{build, simulate, summary_lines, WheelModel, WheelResults, WheelSummary};
use crate::kinds::wheel::run::figures::{self, RimProfile};
use crate::kinds::wheel::run::traction::{self, TractionProfile, TractionSummary};
use crate::output::save::{table, write_fields};
use crate::output::table::Columns;
use crate::run::error::RunError;
use crate::run::options::RunOptions;
use crate::run::results::{Detail, FieldArray, FieldFrame, Fields, OwnFiles, Results};
use crate::scenario::Scenario;
use std::path::{Path, PathBuf};

/// Runs a wheel scenario (its first run; a sweep runs a scenario per value); the history,
/// the contact nodes and the traction history are streamed into the folder `stream` when
/// given, else held. The fields, the profiles and the figures are written by
/// [`Results::save`].
///
/// # Errors
/// [`RunError`].
pub(crate) fn record(
    sc: &Scenario,
    stream: Option<&Path>,
    opts: &RunOptions,
) -> Result<Results, RunError> {
    let run = &sc.runs[0];
    let Some(ws) = run.model.get::<crate::scenario::WheelScenario>() else {
        unreachable!("wheel job on a wheel scenario")
    };
    if ws.block.is_some() {
        return crate::kinds::wheel::on_block::record(sc, stream, opts);
    }
    let wm = build(ws, &sc.path)?;
    let rec = simulate(&wm, ws, run, sc, stream, opts)?;
    let mut json = serde_json::to_value(&rec.summary)
        .map_err(|e| RunError::output(Path::new("summary.json"), e))?;
    if let Some(o) = json.as_object_mut() {
        o.insert("scenario".into(), sc.name.clone().into());
        o.insert("kind".into(), "wheel".into());
        o.insert(
            "units".into(),
            serde_json::json!({"time": "s", "force": "N", "frequency": "Hz", "stress": "MPa", "energy": "J", "omega": "rad/s"}),
        );
    }
    crate::run::provenance::stamp_provenance(&mut json, sc);
    let rim_profile = (!rec.profile.angles_deg.is_empty()).then(|| {
        let p = &rec.profile;
        let mut t = Columns::new(&[
            ("angle_deg", "deg"),
            ("j2_mpa2", "MPa^2"),
            ("von_mises_mpa", "MPa"),
        ]);
        for ((a, j), v) in p.angles_deg.iter().zip(&p.j2_mpa2).zip(&p.von_mises_mpa) {
            t.push(0, &[*a, *j, *v]);
        }
        t
    });
    let plastic_rim = rec.plastic.as_ref().map(|p| {
        let mut t = Columns::new(&[("arc_length_m", "m"), ("radial_displacement_m", "m")]);
        for &(s, d) in &p.rim {
            t.push(0, &[s, d]);
        }
        t
    });
    Ok(Results {
        kind: "wheel",
        summary: json,
        history: rec.history,
        contact_nodes: Some(rec.contact_nodes),
        traction_history: rec.traction_history,
        rim_profile,
        fields: fields_of(&wm, &rec.results, rec.plastic.as_ref()),
        lines: summary_lines(&rec.summary),
        interrupted: rec.summary.interrupted,
        warnings: rec.summary.warnings.clone(),
        plots: sc.plots,
        detail: Detail::Own(Box::new(WheelDetail {
            wm,
            results: rec.results,
            summary: rec.summary,
            profile: rec.profile,
            traction: rec.traction,
            plastic_rim,
        })),
    })
}

/// Fields for ParaView: the turn averages (`j2_turn_average.vtu`, on the cells) and the
/// velocity snapshots (`velocity_NNN.vtu`: velocity and speed on the points, drawn
/// displaced; listed in `velocity.pvd`) and, for a plastic wheel, the equivalent plastic
/// strain at the end (`plastic_strain.vtu`, on the cells).
fn fields_of(wm: &WheelModel, r: &WheelResults, plastic: Option<&super::PlasticRecord>) -> Fields {
    let array = |name: &str, components: usize, values: Vec<f64>| FieldArray {
        name: name.into(),
        components,
        values,
    };
    let mut frames = Vec::new();
    if !r.fields.j2_mpa2.is_empty() {
        frames.push(FieldFrame {
            file: "j2_turn_average.vtu".into(),
            time: None,
            displacement: None,
            point_data: Vec::new(),
            cell_data: vec![
                array("J2_turn_average_MPa2", 1, r.fields.j2_mpa2.clone()),
                array(
                    "von_mises_turn_average_MPa",
                    1,
                    r.fields.von_mises_mpa.clone(),
                ),
            ],
        });
    }
    if let Some(p) = plastic {
        frames.push(FieldFrame {
            file: "plastic_strain.vtu".into(),
            time: None,
            displacement: None,
            point_data: Vec::new(),
            cell_data: vec![array(
                "equivalent_plastic_strain",
                1,
                p.equivalent_plastic_strain.clone(),
            )],
        });
    }
    let sn = &r.snapshots;
    for (i, ((t, v), u)) in sn.t.iter().zip(&sn.v).zip(&sn.u).enumerate() {
        let speed: Vec<f64> = v
            .chunks(2)
            .map(|c| (c[0] * c[0] + c[1] * c[1]).sqrt())
            .collect();
        frames.push(FieldFrame {
            file: format!("velocity_{i:03}.vtu"),
            time: Some(*t),
            displacement: Some(u.clone()),
            point_data: vec![array("velocity", 2, v.clone()), array("speed", 1, speed)],
            cell_data: Vec::new(),
        });
    }
    Fields {
        mesh: Some(wm.mesh.clone()),
        frames,
    }
}

/// The wheel's model and its observers' results, for the figures and the profiles.
#[derive(Debug)]
pub(crate) struct WheelDetail {
    pub wm: WheelModel,
    pub results: WheelResults,
    pub summary: WheelSummary,
    pub profile: RimProfile,
    pub traction: Option<(TractionSummary, TractionProfile)>,
    /// The plastic wheel's rim permanent radial displacement
    /// (`rim_permanent_displacement.csv`).
    pub plastic_rim: Option<Columns>,
}

impl OwnFiles for WheelDetail {
    /// The wheel's files after `history.csv`: contact nodes, traction, fields, rim profile,
    /// figures. The figures are drawn (on the run's pool) while the tables and fields are
    /// written (on a thread of their own: mostly waiting for the disk), listed in that order.
    fn save(&self, r: &Results, out: &Path) -> Result<Vec<PathBuf>, RunError> {
        let w = self;
        let tables = || -> Result<Vec<PathBuf>, RunError> {
            let mut files = Vec::new();
            if let Some(nodes) = &r.contact_nodes {
                files.push(table(out, "contact_nodes.csv", nodes)?);
            }
            if let (Some((ts, profile)), Some(history)) = (&w.traction, &r.traction_history) {
                files.push(table(out, "traction_history.csv", history)?);
                files.push(traction::write_profile(out, ts, profile)?);
            }
            files.extend(write_fields(out, &r.fields)?);
            files.extend(figures::write_rim_profile(out, &w.profile)?);
            if let Some(rim) = &w.plastic_rim {
                files.push(table(out, "rim_permanent_displacement.csv", rim)?);
            }
            Ok(files)
        };
        let figures = || -> Result<Vec<PathBuf>, RunError> {
            let mut files = Vec::new();
            if !r.plots {
                return Ok(files);
            }
            if let Some((ts, profile)) = &w.traction {
                files.extend(traction::figures(out, ts, profile)?);
            }
            files.extend(figures::write(
                out, &w.wm, &w.summary, &w.results, &w.profile,
            )?);
            Ok(files)
        };
        let (written, drawn) = std::thread::scope(|scope| {
            let written = scope.spawn(tables);
            let drawn = figures();
            let written = written
                .join()
                .unwrap_or_else(|panic| std::panic::resume_unwind(panic));
            (written, drawn)
        });
        let mut files = written?;
        files.extend(drawn?);
        Ok(files)
    }
}
