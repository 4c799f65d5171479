//! `modes.png`: the lowest mode shapes of the wheel, at rest and spinning, each drawn as
//! the deformed mesh over the undeformed outline ([`write_modes_figure`]).

use std::path::{Path, PathBuf};

use super::{Mode, ModesError, ModesReport, SpinMode, Whirl};
use crate::bodies::wheel::WheelModel;
use crate::output::plot::{mode_shapes, ModeShape};

/// At most this many modes per row of `modes.png` (the lowest elastic ones).
pub const FIGURE_MODES: usize = 6;

/// The drawn displacement: the largest nodal displacement of each shape is this fraction of
/// the wheel's radius.
pub const SHAPE_SCALE: f64 = 0.1;

/// A rest mode's kind in words: its circumferential waves `n` as nodal diameters when the
/// rim moves (`"n = 2 nodal diameters"`; `n = 0` as torsion or breathing, whichever of the
/// rim's tangential and radial motion is the larger), else its kind (`"rigid rotation"`).
pub fn mode_label(model: &WheelModel, m: &Mode) -> String {
    match (m.kind.as_str(), m.wavenumber) {
        ("elastic", Some(0)) => {
            // Mean |u_t| against mean |u_r| over the rim.
            let (mut ut, mut ur) = (0.0, 0.0);
            for &k in &model.rim {
                let p = model.mesh.point(k);
                let th = p[1].atan2(p[0]);
                let (ux, uy) = (m.shape[2 * k], m.shape[2 * k + 1]);
                ur += (ux * th.cos() + uy * th.sin()).abs();
                ut += (-ux * th.sin() + uy * th.cos()).abs();
            }
            if ut > ur {
                "n = 0, torsion".to_string()
            } else {
                "n = 0, breathing".to_string()
            }
        }
        ("elastic", Some(1)) => "n = 1 nodal diameter".to_string(),
        ("elastic", Some(n)) => format!("n = {n} nodal diameters"),
        ("elastic", None) => "the rim at rest".to_string(),
        (kind, _) => kind.to_string(),
    }
}

/// Material lines of the wheel drawn deformed: rings at a quarter, half and three quarters
/// of the radius and eight spokes, in undeformed coordinates.
fn rings_and_spokes(radius: f64) -> Vec<Vec<[f64; 2]>> {
    use std::f64::consts::PI;
    let mut lines: Vec<Vec<[f64; 2]>> = [0.25, 0.5, 0.75]
        .iter()
        .map(|f| {
            (0..=180)
                .map(|k| {
                    let a = f64::from(k) * PI / 90.0;
                    [f * radius * a.cos(), f * radius * a.sin()]
                })
                .collect()
        })
        .collect();
    for j in 0..8 {
        let a = f64::from(j) * PI / 4.0 + PI / 8.0;
        lines.push(
            (0..=60)
                .map(|k| {
                    let r = 0.98 * radius * f64::from(k) / 60.0;
                    [r * a.cos(), r * a.sin()]
                })
                .collect(),
        );
    }
    lines
}

/// A frequency in Hz with thousands separated: `11,858.7 Hz`.
fn hz(f: f64) -> String {
    let s = format!("{f:.1}");
    let (int, frac) = s.split_once('.').unwrap_or((&s, "0"));
    let digits: Vec<char> = int.chars().collect();
    let mut out = String::new();
    for (i, c) in digits.iter().enumerate() {
        if i > 0 && (digits.len() - i) % 3 == 0 && c.is_ascii_digit() {
            out.push(',');
        }
        out.push(*c);
    }
    format!("{out}.{frac} Hz")
}

/// The nodal displacements of `shape` (dofs, node-major) scaled so that the largest is
/// `SHAPE_SCALE` times `radius`.
fn scaled(shape: &[f64], radius: f64) -> Vec<[f64; 2]> {
    let d: Vec<[f64; 2]> = shape.chunks(2).map(|c| [c[0], c[1]]).collect();
    let top = d.iter().map(|v| v[0].hypot(v[1])).fold(0.0, f64::max);
    let s = if top > 0.0 {
        SHAPE_SCALE * radius / top
    } else {
        0.0
    };
    d.iter().map(|v| [s * v[0], s * v[1]]).collect()
}

/// Writes `modes.png` into `dir`: the lowest [`FIGURE_MODES`] elastic rest modes of
/// `report` (first row) and, when the spinning analysis ran, its lowest elastic modes
/// (second row), each panel titled with its frequency and kind. A spinning mode is drawn
/// with the shape of the rest mode it comes from ([`SpinMode::rest_index`]): to first order
/// in the spin a whirling mode is that shape travelling round the wheel (forward or
/// backward), so any instant of it is the rest shape turned. Returns the file, or `None`
/// for a model that is not plane or has no elastic mode.
///
/// # Errors
/// [`ModesError::Plot`] if the figure cannot be drawn or written.
pub fn write_modes_figure(
    model: &WheelModel,
    report: &ModesReport,
    dir: &Path,
) -> Result<Option<PathBuf>, ModesError> {
    let mesh = &model.mesh;
    if mesh.dim != 2 {
        return Ok(None);
    }
    let radius = model.spec.radius;
    let points: Vec<[f64; 2]> = mesh.points().map(|p| [p[0], p[1]]).collect();
    let elastic: Vec<(usize, &Mode)> = report
        .at_rest
        .iter()
        .enumerate()
        .filter(|(_, m)| m.kind == "elastic" && m.frequency_hz > 0.0)
        .take(FIGURE_MODES)
        .collect();
    if elastic.is_empty() {
        return Ok(None);
    }
    let mut panels: Vec<(String, Vec<[f64; 2]>)> = elastic
        .iter()
        .map(|(i, m)| {
            (
                format!(
                    "mode {}: {}\n{}",
                    i + 1,
                    hz(m.frequency_hz),
                    mode_label(model, m)
                ),
                scaled(&m.shape, radius),
            )
        })
        .collect();
    // One row of rest modes; the spinning ones in a second row of at most as many.
    let cols = panels.len();
    if let Some(spin) = &report.spinning {
        panels.extend(
            spin.iter()
                .filter(|m| m.kind == "elastic")
                .filter_map(|m: &SpinMode| {
                    let k = m.rest_index?;
                    let rest = report.at_rest.get(k)?;
                    let whirl = match m.whirl {
                        Whirl::Forward => "forward whirl",
                        Whirl::Backward => "backward whirl",
                        Whirl::Standing => "standing",
                    };
                    Some((
                        format!(
                            "spinning: {}\n{whirl}, shape of mode {}",
                            hz(m.frequency_hz),
                            k + 1
                        ),
                        scaled(&rest.shape, radius),
                    ))
                })
                .take(cols),
        );
    }
    let mut note = format!(
        "Each shape is scaled so that its largest displacement is {:.0} % of the radius \
         ({} m); grey dashed: the undeformed outline; thin lines: rings and spokes carried \
         by the shape; colour: the displacement over its largest. n: waves around the rim \
         (nodal diameters).",
        100.0 * SHAPE_SCALE,
        radius
    );
    if panels.len() > cols {
        note.push_str(
            " Second row, the spinning wheel: frequencies in its rotating frame, drawn with \
             the shape of the rest mode each comes from (a whirling mode is that shape \
             travelling round the wheel).",
        );
    }
    let lines = rings_and_spokes(radius);
    let shapes: Vec<ModeShape> = panels
        .iter()
        .map(|(title, d)| ModeShape {
            points: &points,
            triangles: &model.triangles,
            displacement: d,
            lines: lines.clone(),
            title: title.clone(),
            length_unit_scale: 100.0,
            length_unit: "cm".into(),
            colorbar_label: "|u| / max |u|".into(),
            note: note.clone(),
        })
        .collect();
    let rows = shapes.len().div_ceil(cols);
    let png = dir.join("modes.png");
    // Square panels about 330 px wide, two lines of title over each.
    let width = 330 * cols as u32 + 260;
    let panel = (width - 230 - 35 * (cols as u32 - 1)) / cols as u32;
    let size = (width.max(900), (rows as u32 * (panel + 62) + 175).max(500));
    mode_shapes(&png, &shapes, cols, size)?;
    Ok(Some(png))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frequencies_are_printed_with_separators() {
        assert_eq!(hz(11858.66), "11,858.7 Hz");
        assert_eq!(hz(812.04), "812.0 Hz");
        assert_eq!(hz(1486.8), "1,486.8 Hz");
    }

    #[test]
    fn the_scaled_shape_peaks_at_the_stated_fraction_of_the_radius() {
        let d = scaled(&[3.0, 4.0, -1.0, 0.0, 0.0, 0.0], 0.5);
        assert!((d[0][0].hypot(d[0][1]) - SHAPE_SCALE * 0.5).abs() < 1e-15);
        assert!((d[1][0] + 0.2 * SHAPE_SCALE * 0.5).abs() < 1e-15);
        assert!(scaled(&[0.0, 0.0], 1.0).iter().all(|v| v == &[0.0, 0.0]));
    }
}
