//! `softway modes` of a wheel: its modes at rest and spinning ([`crate::modes`]), the shapes
//! written as VTU and drawn in `modes.png`, the tables for the screen.

use std::fmt::Write as _;
use std::path::Path;

use super::WheelScenario;
use crate::run::error::RunError;
use crate::scenario::kind::{Study, StudyOptions, StudyReport};
use crate::scenario::Scenario;

/// The wheel's modes study ([`Study`]).
#[derive(Debug, Clone, Copy)]
pub struct WheelModes;

impl Study for WheelModes {
    fn run(
        &self,
        sc: &Scenario<crate::scenario::RunSpec>,
        opts: &StudyOptions,
        dir: &Path,
    ) -> Result<StudyReport, RunError> {
        let Some(ws) = sc.runs[0].model.get::<WheelScenario>() else {
            return Err(RunError::input(
                &sc.path,
                "`softway modes` needs a wheel scenario (kind = \"wheel\")",
            ));
        };
        let input = |e: crate::modes::ModesError| RunError::input(&sc.path, e);
        let wm = super::run::build(ws, &sc.path)?;
        let rep = crate::modes::modes_report(&wm, opts.count.unwrap_or(12)).map_err(input)?;
        let mut files = crate::modes::write_mode_shapes(&wm, &rep.at_rest, dir).map_err(input)?;
        if opts.plots {
            files.extend(crate::modes::write_modes_figure(&wm, &rep, dir).map_err(input)?);
        }
        let text = modes_text(&sc.name, &rep, &wm.spec.support, ws.spec.omega);
        Ok(StudyReport {
            lines: text.lines().map(str::to_string).collect(),
            files,
            // The modes are one solve: a signal during it stops the command after the writing.
            interrupted: opts
                .cancel
                .load(std::sync::atomic::Ordering::Relaxed)
                .then(|| "interrupted: the modes were written".to_string()),
        })
    }
}

/// The tables of `softway modes`: the rest modes, the spinning ones, the notes.
fn modes_text(
    name: &str,
    rep: &crate::modes::ModesReport,
    support: &crate::bodies::wheel::Support,
    omega: f64,
) -> String {
    let mut s = String::new();
    let support = match support {
        crate::bodies::wheel::Support::Hub { radius } => format!("a hub clamped within {radius} m"),
        crate::bodies::wheel::Support::CentrePinned => "the centre node pinned".to_string(),
    };
    let _ = writeln!(
        s,
        "{}: {} dofs ({} free), support: {support}",
        name, rep.dofs, rep.free_dofs
    );
    let _ = writeln!(s, "at rest:");
    let _ = writeln!(
        s,
        "{:>5} {:>14} {:>12} {:>5}  kind",
        "mode", "frequency Hz", "period us", "n"
    );
    for (i, m) in rep.at_rest.iter().enumerate() {
        let _ = writeln!(
            s,
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
        let _ = writeln!(
            s,
            "spinning at omega = {} rad/s (frequencies in the wheel's rotating frame):",
            omega
        );
        let _ = writeln!(
            s,
            "{:>5} {:>14} {:>14} {:>10}  kind",
            "mode", "frequency Hz", "at rest Hz", "whirl"
        );
        for (i, m) in sp.iter().enumerate() {
            let _ = writeln!(
                s,
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
        let _ = writeln!(s, "note: {n}");
    }
    s
}
