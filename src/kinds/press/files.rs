//! What a press writes: `pressure.png` (the patch's pressure map with Hertz's ellipse),
//! `pressure.csv` (the rail's nodes in the zone and their pressures), `fields.vtu` (both
//! bodies: the displacement, the pressure, the von Mises stress, for ParaView), and the
//! summary's key figures.

use super::solve::{PressSpec, Pressed};
use crate::output::plot::{mesh_color_map_overlay, sig, EdgeMode, MeshColorMap, MeshOptions};
use crate::output::vtk::{write_vtu, Field};
use crate::run::error::RunError;
use crate::run::results::{OwnFiles, Results};
use crate::scenario::Scenario;
use std::path::{Path, PathBuf};

/// The press's own files (module docs).
#[derive(Debug)]
pub(crate) struct PressFiles {
    /// The solved press.
    pub(crate) pressed: Pressed,
}

impl OwnFiles for PressFiles {
    fn save(&self, results: &Results, out: &Path) -> Result<Vec<PathBuf>, RunError> {
        let p = &self.pressed;
        let mut files = Vec::new();
        let csv = out.join("pressure.csv");
        let mut text = String::from("x_mm,y_mm,pressure_MPa\n");
        for n in &p.patch {
            text.push_str(&format!(
                "{:.6},{:.6},{:.6}\n",
                1e3 * n.x,
                1e3 * n.y,
                1e-6 * n.pressure
            ));
        }
        crate::output::files::write_atomic(&csv, text.as_bytes())
            .map_err(|e| RunError::output(&csv, e))?;
        files.push(csv);
        let vtu = out.join("fields.vtu");
        let mut pressure = vec![0.0; p.mesh.n_nodes()];
        let off = p.wheel_nodes;
        for n in &p.patch {
            pressure[off + n.node] = 1e-6 * n.pressure;
        }
        let body: Vec<f64> = (0..p.mesh.n_nodes())
            .map(|i| if i < off { 0.0 } else { 1.0 })
            .collect();
        let vm: Vec<f64> = p.von_mises.iter().map(|v| 1e-6 * v).collect();
        write_vtu(
            &vtu,
            &p.mesh,
            Some(&p.u),
            &[
                Field {
                    name: "contact_pressure_MPa",
                    components: 1,
                    values: &pressure,
                },
                Field {
                    name: "body_wheel0_rail1",
                    components: 1,
                    values: &body,
                },
            ],
            &[Field {
                name: "von_mises_MPa",
                components: 1,
                values: &vm,
            }],
        )
        .map_err(|e| RunError::output(&vtu, e))?;
        files.push(vtu);
        if results.plots {
            let png = out.join("pressure.png");
            pressure_map(&png, p).map_err(|e| RunError::output(&png, e))?;
            files.push(png);
        }
        Ok(files)
    }
}

/// The pressure map: the zone's rail facets split into triangles, coloured by their
/// nodes' mean pressure, in mm along and across the rail, with Hertz's ellipse (module
/// docs).
fn pressure_map(path: &Path, p: &Pressed) -> Result<(), crate::output::plot::PlotError> {
    let points: Vec<[f64; 2]> = p.patch.iter().map(|n| [n.x, n.y]).collect();
    let triangles = &p.patch_triangles;
    let values: Vec<f64> = triangles
        .iter()
        .map(|t| 1e-6 * t.iter().map(|&i| p.patch[i].pressure).sum::<f64>() / 3.0)
        .collect();
    let mut overlay = Vec::new();
    let note = match &p.hertz {
        Some(h) => {
            let (ax, ay) = h.semi_axes_xy();
            let k = 120;
            let at = |j: usize| {
                let t = 2.0 * std::f64::consts::PI * j as f64 / k as f64;
                [p.centre[0] + ax * t.cos(), p.centre[1] + ay * t.sin()]
            };
            overlay.extend((0..k).map(|j| [at(j), at(j + 1)]));
            format!(
                "Red: Hertz's ellipse for the same load ({} kN) and the local curvatures (A = {} /m along, B = {} /m across), centred on the pressure's centre: axes {} x {} mm, p0 = {} MPa. FE (triangles coloured by their nodes' mean): area {} mm², peak nodal pressure {} MPa.",
                sig(1e-3 * h.load, 4),
                sig(p.placement.curvatures[0], 3),
                sig(p.placement.curvatures[1], 3),
                sig(2e3 * ax, 3),
                sig(2e3 * ay, 3),
                sig(1e-6 * h.peak_pressure, 4),
                sig(1e6 * p.area, 4),
                sig(1e-6 * p.peak_pressure, 4),
            )
        }
        None => format!(
            "No Hertz ellipse: the profiles conform across the rail at the contact (B = {} /m). FE: area {} mm², peak {} MPa.",
            sig(p.placement.curvatures[1], 3),
            sig(1e6 * p.area, 4),
            sig(1e-6 * p.peak_pressure, 4),
        ),
    };
    let map = MeshColorMap {
        points: &points,
        triangles,
        cell_values: &values,
        title: format!(
            "Contact pressure of the wheel pressed on the rail, {} kN",
            sig(1e-3 * p.load, 4)
        ),
        colorbar_label: "pressure [MPa]".into(),
        length_unit_scale: 1e3,
        length_unit: "mm".into(),
        note,
    };
    mesh_color_map_overlay(
        path,
        &map,
        &overlay,
        (1000, 1100),
        &MeshOptions {
            edges: EdgeMode::Always,
            value_range: None,
        },
    )
}

/// The summary's object.
pub(crate) fn summary(sc: &Scenario, spec: &PressSpec, p: &Pressed) -> serde_json::Value {
    let hertz = p.hertz.map(|h| {
        let (ax, ay) = h.semi_axes_xy();
        serde_json::json!({
            "semi_axis_along_mm": 1e3 * ax, "semi_axis_across_mm": 1e3 * ay,
            "area_mm2": 1e6 * h.area(), "peak_pressure_MPa": 1e-6 * h.peak_pressure,
            "approach_um": 1e6 * h.approach,
        })
    });
    let at = &p.placement;
    serde_json::json!({
        "scenario": sc.name, "kind": "press", "interrupted": false,
        "units": {"length": "mm", "force": "kN", "pressure": "MPa", "approach": "um"},
        "load_target_kN": 1e-3 * spec.load,
        "load_kN": 1e-3 * p.load,
        "foot_reaction_kN": 1e-3 * p.foot_reaction,
        "contact_area_mm2": 1e6 * p.area,
        "semi_axis_along_mm": 1e3 * p.semi_axes[0],
        "semi_axis_across_mm": 1e3 * p.semi_axes[1],
        "extent_mm": p.extent.map(|v| 1e3 * v),
        "centre_mm": p.centre.map(|v| 1e3 * v),
        "peak_pressure_MPa": 1e-6 * p.peak_pressure,
        "approach_um": 1e6 * p.approach,
        "approach_local_um": 1e6 * p.approach_local,
        "approach_depths_mm": p.depths.map(|v| 1e3 * v),
        "descent_um": 1e6 * p.descent,
        "active_set_iterations": p.secant.iter().map(|s| s.iterations).sum::<usize>(),
        "secant_steps": p.secant.len(),
        "dofs": p.dofs,
        "contact_rows": p.rows,
        "active_rows": p.secant.last().map(|s| s.active).unwrap_or(0),
        "contact_size_mm": 1e3 * spec.size,
        "placement": {
            "contact_y_mm": 1e3 * at.contact[1], "rail_profile_y_mm": 1e3 * at.rail_y,
            "wheel_profile_y_mm": 1e3 * at.wheel_y, "rolling_radius_mm": 1e3 * at.rolling_radius,
            "curvature_along_per_m": at.curvatures[0], "curvature_across_per_m": at.curvatures[1],
        },
        "hertz": hertz,
        "factor_seconds": p.factor_seconds,
        "solve_seconds": p.solve_seconds,
    })
}

/// The screen lines.
pub(crate) fn lines(p: &Pressed) -> Vec<String> {
    let mut l = vec![format!(
        "press: {} dofs, {} rows; load {:.4} kN (foot {:.4} kN); area {:.2} mm^2, semi-axes {:.3} x {:.3} mm, peak {:.1} MPa; approach {:.2} um (local {:.2} um at {:.1}/{:.1} mm, hub {:.2} um); {} active-set iterations",
        p.dofs,
        p.rows,
        1e-3 * p.load,
        1e-3 * p.foot_reaction,
        1e6 * p.area,
        1e3 * p.semi_axes[0],
        1e3 * p.semi_axes[1],
        1e-6 * p.peak_pressure,
        1e6 * p.approach,
        1e6 * p.approach_local,
        1e3 * p.depths[0],
        1e3 * p.depths[1],
        1e6 * p.descent,
        p.secant.iter().map(|s| s.iterations).sum::<usize>(),
    )];
    if let Some(h) = &p.hertz {
        let (ax, ay) = h.semi_axes_xy();
        l.push(format!(
            "Hertz (local curvatures): area {:.2} mm^2, semi-axes {:.3} x {:.3} mm, p0 {:.1} MPa, approach {:.2} um",
            1e6 * h.area(),
            1e3 * ax,
            1e3 * ay,
            1e-6 * h.peak_pressure,
            1e6 * h.approach
        ));
    }
    l
}
