//! A rail of the UIC60 (60E1) section over a length ([`rail_extruded`]): the section meshed
//! with quadrilaterals (the head in its published profile, the web and foot simplified to
//! the published area, bending stiffness and neutral axis: [`crate::mesh::profiles::uic60`]),
//! extruded along the rail into hexahedra, graded toward the contact along the rail and in
//! the head, and inclined at 1:40.
//!
//! **Frame.** `x` along the rail, `y` across it (positive toward the field side; the gauge
//! side, which the wheel's flange faces, at negative `y`), `z` up; the origin at the top of
//! the crown in the rail's middle (`x = 0`). The rail runs from `x = -length/2` to
//! `length/2`. The inclination turns the section about the `x` axis through the origin by
//! `atan(inclination)`, the head toward the gauge side (the rail's own vertical axis then
//! points to `(0, -sin a, cos a)`), as rails are laid toward the track's centre.
//!
//! **The section**, before the inclination: the head's surface from one flank to the other
//! with nodes at arc-length steps of [`RailSpec::head_size`] within [`RailSpec::head_band`]
//! of `y = focus_y`, growing by [`RailSpec::growth`] up to [`RailSpec::section_size`]
//! toward the flanks, each exactly on the profile; rows grading from the head's size at the
//! running surface to the section's size at the head's underside; a web and a foot of
//! about the section's size, the web's columns those of the head above it.
//!
//! **Along the rail**: steps of [`RailSpec::fine_size`] within [`RailSpec::fine_half_length`]
//! of `x = 0`, growing by the same factor up to [`RailSpec::coarse_size`].
//!
//! Node sets: `"running"` (the head's surface within the fine length and the fine band,
//! where the wheel touches), `"head"` (the head's whole surface between the flanks),
//! `"foot"` (the foot's underside, where the sleepers hold the rail), `"x0"` and `"x1"`
//! (the rail's ends at `-length/2` and `length/2`) and `"all"`.

use std::collections::BTreeMap;

use super::revolution::{
    check_range, line, on_curve_inverse, rows_to_top, rows_uniform, segments, snap,
};
use super::{check_length, check_nodes, MeshError};
use crate::mesh::profiles::section::{
    arc_lengths, graded_about, on_curve, sweep_hexes, QuadSection,
};
use crate::mesh::profiles::uic60::{self, uic60_head};
use crate::mesh::{Cells, Mesh};

/// A rail of the UIC60 section ([`rail_extruded`]); lengths in m. Every field has a
/// default ([`RailSpec::default`]).
#[derive(Debug, Clone, Copy, PartialEq, serde::Deserialize, serde::Serialize)]
#[serde(deny_unknown_fields, default)]
pub struct RailSpec {
    /// Length of the rail, m. Default 0.4.
    pub length: f64,
    /// The rail's inclination toward the track's centre (dimensionless, tan of the angle).
    /// Default 1/40; 0 for an upright rail.
    pub inclination: f64,
    /// Lateral position of the middle of the fine band on the head, m (before the
    /// inclination). Default 0.
    pub focus_y: f64,
    /// Cell size along the head's surface in the fine band, and of the top row, m.
    /// Default 0.002.
    pub head_size: f64,
    /// Half-width of the fine band on the head, m. Default 0.015.
    pub head_band: f64,
    /// Largest cell size in the section, m. Default 0.01.
    pub section_size: f64,
    /// Cell length along the rail near the contact, m. Default 0.002.
    pub fine_size: f64,
    /// Half-length of the fine zone along the rail, m. Default 0.02.
    pub fine_half_length: f64,
    /// Largest cell length along the rail, m. Default 0.03.
    pub coarse_size: f64,
    /// Ratio of successive cell sizes away from the contact, in `[1, 2]`. Default 1.3.
    pub growth: f64,
}

impl Default for RailSpec {
    fn default() -> Self {
        RailSpec {
            length: 0.4,
            inclination: 1.0 / 40.0,
            focus_y: 0.0,
            head_size: 0.002,
            head_band: 0.015,
            section_size: 0.01,
            fine_size: 0.002,
            fine_half_length: 0.02,
            coarse_size: 0.03,
            growth: 1.3,
        }
    }
}

impl RailSpec {
    /// Checks the spec.
    ///
    /// # Errors
    /// [`MeshError`] naming the first field that is not a finite positive length, or a
    /// ratio, inclination or position out of its range.
    pub fn validate(&self) -> Result<(), MeshError> {
        for (name, v) in [
            ("length", self.length),
            ("head_size", self.head_size),
            ("head_band", self.head_band),
            ("section_size", self.section_size),
            ("fine_size", self.fine_size),
            ("fine_half_length", self.fine_half_length),
            ("coarse_size", self.coarse_size),
        ] {
            check_length(name, v)?;
        }
        check_range("growth", self.growth, 1.0, 2.0)?;
        check_range("inclination", self.inclination, -0.2, 0.2)?;
        check_range("focus_y", self.focus_y, -0.03, 0.03)?;
        check_range("section_size", self.section_size, self.head_size, 0.05)?;
        check_range("coarse_size", self.coarse_size, self.fine_size, self.length)?;
        check_range("head_size", self.head_size, 1e-5, 0.01)?;
        Ok(())
    }
}

/// The UIC60 section in `(y, z)`, m, before the inclination (module docs): the quads, the
/// indices of the head's surface nodes (left to right) and of the foot's underside.
///
/// # Errors
/// As [`RailSpec::validate`].
pub fn rail_section(spec: &RailSpec) -> Result<(QuadSection, Vec<usize>, Vec<usize>), MeshError> {
    spec.validate()?;
    let mm = 1e-3;
    let head = uic60_head();
    let (ya, yb) = head.domain();
    let polyline = head.polyline(400);
    let cum = arc_lengths(&polyline);
    let total = cum[cum.len() - 1];
    let s0 = on_curve_inverse(&polyline, &cum, spec.focus_y);
    let s = graded_about(
        0.0,
        total,
        s0,
        spec.head_size,
        spec.head_band,
        spec.growth,
        spec.section_size,
    );
    let mut top_pts = on_curve(&polyline, &s, |y| {
        head.height(y.clamp(ya, yb)).unwrap_or(0.0)
    });
    let n = top_pts.len();
    top_pts[0] = polyline[0];
    top_pts[n - 1] = polyline[polyline.len() - 1];
    let g = uic60::head_geometry();
    let depth = uic60::HEAD_DEPTH_MM * mm;
    let flank_top = [g.flank_top[0] * mm, g.flank_top[1] * mm];
    let half_bottom = flank_top[0] + (depth + flank_top[1]) * uic60::FLANK_INCLINATION;
    let mut sec = QuadSection::new();
    let top = sec.add_row(&top_pts);
    let bottom_pts: Vec<[f64; 2]> = top_pts
        .iter()
        .map(|p| [p[0] * half_bottom / flank_top[0], -depth])
        .collect();
    let head_bottom = sec.add_row(&bottom_pts);
    let half_web = 0.5 * uic60::WEB_THICKNESS_MM * mm;
    let il = snap(&mut sec.points, &head_bottom, -half_web);
    let ir = snap(&mut sec.points, &head_bottom, half_web);
    if ir <= il + 1 {
        // Too coarse a head to give the web a column of its own.
        return Err(MeshError::OutOfRange {
            name: "section_size",
            value: spec.section_size,
            min: spec.head_size,
            max: half_web,
        });
    }
    let head_rows = rows_to_top(depth, spec.head_size, spec.growth, spec.section_size);
    sec.ruled_block(&head_bottom, &top, &head_rows);
    // The web, down to the foot's top at the web.
    let foot_at_web = -(uic60::RAIL_HEIGHT_MM - uic60::FOOT_THICKNESS_MM) * mm;
    let web_top = head_bottom[il..=ir].to_vec();
    let web_bottom_pts: Vec<[f64; 2]> = web_top
        .iter()
        .map(|&i| [sec.points[i][0], foot_at_web])
        .collect();
    let web_bottom = sec.add_row(&web_bottom_pts);
    sec.ruled_block(
        &web_bottom,
        &web_top,
        &rows_uniform(foot_at_web.abs() - depth, spec.section_size),
    );
    // The foot: its top falls from the web to the edges; its bottom is flat.
    let base = -uic60::RAIL_HEIGHT_MM * mm;
    let edge = [
        0.5 * uic60::FOOT_WIDTH_MM * mm,
        base + uic60::FOOT_EDGE_MM * mm,
    ];
    let k = segments(edge[0] - half_web, spec.section_size) + 1;
    let left = line([-edge[0], edge[1]], [-half_web, foot_at_web], k);
    let right = line([half_web, foot_at_web], edge, k);
    let mut foot_top = sec.add_row(&left[..k - 1]);
    foot_top.extend_from_slice(&web_bottom);
    foot_top.extend(sec.add_row(&right[1..]));
    let foot_bottom_pts: Vec<[f64; 2]> =
        foot_top.iter().map(|&i| [sec.points[i][0], base]).collect();
    let foot_bottom = sec.add_row(&foot_bottom_pts);
    let t = uic60::FOOT_THICKNESS_MM * mm;
    let foot_rows = rows_uniform(t, spec.section_size.min(0.5 * uic60::FOOT_EDGE_MM * mm));
    sec.ruled_block(&foot_bottom, &foot_top, &foot_rows);
    Ok((sec, top, foot_bottom))
}

/// The positions of the rail's node planes along `x`, m (module docs).
pub fn rail_stations(spec: &RailSpec) -> Vec<f64> {
    let h = 0.5 * spec.length;
    graded_about(
        -h,
        h,
        0.0,
        spec.fine_size,
        spec.fine_half_length,
        spec.growth,
        spec.coarse_size,
    )
}

/// A UIC60 rail meshed with hexahedra (module docs).
///
/// # Errors
/// As [`RailSpec::validate`], and [`MeshError::TooLarge`] past [`super::MAX_NODES`] nodes.
pub fn rail_extruded(spec: &RailSpec) -> Result<Mesh, MeshError> {
    let (sec, top, foot) = rail_section(spec)?;
    let xs = rail_stations(spec);
    let (n, m) = (sec.points.len(), xs.len());
    check_nodes("fine_size", m, n.checked_mul(m))?;
    let a = spec.inclination.atan();
    let (sa, ca) = a.sin_cos();
    let mut coords = Vec::with_capacity(3 * n * m);
    for &x in &xs {
        for p in &sec.points {
            coords.extend([x, p[0] * ca - p[1] * sa, p[0] * sa + p[1] * ca]);
        }
    }
    let hexes = sweep_hexes(&sec, m - 1, |k| k + 1, &coords);
    let layers = |ids: &[usize], ks: &mut dyn Iterator<Item = usize>| -> Vec<usize> {
        let mut v: Vec<usize> = ks
            .flat_map(|k| ids.iter().map(move |&i| k * n + i))
            .collect();
        v.sort_unstable();
        v
    };
    let all_sec: Vec<usize> = (0..n).collect();
    let mut sets = BTreeMap::new();
    sets.insert("head".to_string(), layers(&top, &mut (0..m)));
    sets.insert("foot".to_string(), layers(&foot, &mut (0..m)));
    sets.insert("x0".to_string(), layers(&all_sec, &mut (0..1)));
    sets.insert("x1".to_string(), layers(&all_sec, &mut (m - 1..m)));
    let band: Vec<usize> = top
        .iter()
        .copied()
        .filter(|&i| (sec.points[i][0] - spec.focus_y).abs() <= spec.head_band * (1.0 + 1e-9))
        .collect();
    let fine = spec.fine_half_length * (1.0 + 1e-9);
    sets.insert(
        "running".to_string(),
        layers(&band, &mut (0..m).filter(|&k| xs[k].abs() <= fine)),
    );
    sets.insert("all".to_string(), (0..n * m).collect());
    Ok(Mesh::new(3, coords, Cells::Hex8(hexes), sets))
}
