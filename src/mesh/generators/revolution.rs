//! A wheel of revolution ([`wheel_of_revolution`]): a cross-section of the wheel, the tread
//! profile on top of a rim, a web and a hub (or a solid disk of the tread's width down to
//! the bore), meshed with quadrilaterals and swept about the axle into hexahedra.
//!
//! **Frame.** The axle is the `y` axis through the origin; `y` is the tread profile's
//! lateral coordinate (0 on the running circle, the flange at negative `y`: see
//! [`crate::mesh::profiles`]). A point of the section at radius `r`, turned by `theta`
//! about the axle from the contact (the lowest point of the wheel), lies at
//! `x = r sin(theta)`, `z = -r cos(theta)`: the contact is at `theta = 0`, under the axle.
//!
//! **The section**, in `(y, r)`: the rim between the tread `r = R + p(y)` (`R` the nominal
//! radius, `p` the profile) and `r = R - rim_depth`; below it the web, `web_thickness`
//! wide, down to the hub's outer radius; the hub, `hub_width` wide, down to the bore
//! (`bore_radius`). A simplification of a wheel's section: straight-sided blocks with no
//! fillets, of the usual proportions (defaults: a 920 mm wheel with a 65 mm deep rim, a
//! 30 mm web and a hub of 280 mm over a 200 mm bore). Without a web
//! ([`WheelSpec::web`] = `None`) the section is the rim's full width down to the bore.
//! The tread's nodes are placed along the profile at arc-length steps of
//! [`WheelSpec::tread_size`] within [`WheelSpec::tread_band`] of the running circle, growing
//! by [`WheelSpec::growth`] up to [`WheelSpec::section_size`] away from it, each exactly on
//! the profile; the columns below them are vertical (constant `y`), and the rows grade from
//! the tread's size at the top to the section's size below.
//!
//! **The sweep**: steps of [`WheelSpec::fine_pitch`] over the arc
//! `|theta| <= fine_arc`, growing by the same factor up to [`WheelSpec::coarse_pitch`]
//! around the rest of the wheel; the mesh closes on itself at `theta = pi`.
//!
//! Node sets: `"tread"` (the whole tread surface), `"contact"` (the tread within the fine
//! arc and the fine band, where the rail touches), `"axle"` (the bore, where the axle holds
//! the wheel) and `"all"`.

use std::collections::BTreeMap;
use std::f64::consts::PI;

use super::{check_length, check_nodes, MeshError};
use crate::mesh::profiles::section::{graded, graded_about, on_curve, sweep_hexes, QuadSection};
use crate::mesh::profiles::{self, Profile};
use crate::mesh::{Cells, Mesh};

/// The tread profile of a wheel.
#[derive(Debug, Clone, Copy, PartialEq, serde::Deserialize, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum TreadProfile {
    /// EN 13715 S1002 ([`profiles::s1002()`]), 130 mm wide.
    S1002,
    /// A cone falling 1:40 toward the field side, 130 mm wide centred on the running
    /// circle ([`profiles::conical`]).
    Conical,
}

impl TreadProfile {
    /// The profile.
    pub fn profile(self) -> Profile {
        match self {
            TreadProfile::S1002 => profiles::s1002(),
            TreadProfile::Conical => profiles::conical(1.0 / 40.0, 0.065).expect("valid cone"),
        }
    }
}

/// The web and hub of a wheel's section ([`WheelSpec::web`]); lengths in m.
#[derive(Debug, Clone, Copy, PartialEq, serde::Deserialize, serde::Serialize)]
#[serde(deny_unknown_fields, default)]
pub struct WheelWeb {
    /// Thickness of the web along the axle, m. Default 0.03.
    pub thickness: f64,
    /// Lateral position of the web's (and hub's) middle, m (same `y` as the profile).
    /// Default -0.005 (the middle of S1002's 130 mm).
    pub centre: f64,
    /// Outer radius of the hub, m. Default 0.14.
    pub hub_radius: f64,
    /// Length of the hub along the axle, m. Default 0.16.
    pub hub_width: f64,
}

impl Default for WheelWeb {
    fn default() -> Self {
        WheelWeb {
            thickness: 0.03,
            centre: -0.005,
            hub_radius: 0.14,
            hub_width: 0.16,
        }
    }
}

/// A wheel of revolution ([`wheel_of_revolution`]); lengths in m, angles in rad. Every field
/// has a default ([`WheelSpec::default`]): an S1002 wheel of 0.46 m nominal radius.
#[derive(Debug, Clone, Copy, PartialEq, serde::Deserialize, serde::Serialize)]
#[serde(deny_unknown_fields, default)]
pub struct WheelSpec {
    /// The tread. Default [`TreadProfile::S1002`].
    pub profile: TreadProfile,
    /// Radius of the running circle (`y = 0`), m. Default 0.46.
    pub nominal_radius: f64,
    /// Radial depth of the rim below the nominal radius, m. Default 0.065.
    pub rim_depth: f64,
    /// The web and hub; `None` for a solid disk of the rim's width down to the bore.
    /// Default `Some(WheelWeb::default())`.
    pub web: Option<WheelWeb>,
    /// Radius of the bore (the axle's seat), m. Default 0.1.
    pub bore_radius: f64,
    /// Cell size along the tread near the running circle (arc length), and of the top row,
    /// m. Default 0.002.
    pub tread_size: f64,
    /// Half-width of the band about the running circle where the tread's cells have
    /// [`WheelSpec::tread_size`], m. Default 0.015.
    pub tread_band: f64,
    /// Largest cell size in the section, m. Default 0.012.
    pub section_size: f64,
    /// Ratio of successive cell sizes away from the contact (in the section and around the
    /// wheel), in `[1, 2]`. Default 1.3.
    pub growth: f64,
    /// Half-angle of the fine arc about the contact, rad. Default 0.04 (18 mm of tread).
    pub fine_arc: f64,
    /// Angular pitch over the fine arc, rad. Default 0.004 (1.8 mm of tread).
    pub fine_pitch: f64,
    /// Largest angular pitch, rad. Default `2 pi / 48`.
    pub coarse_pitch: f64,
}

impl Default for WheelSpec {
    fn default() -> Self {
        WheelSpec {
            profile: TreadProfile::S1002,
            nominal_radius: 0.46,
            rim_depth: 0.065,
            web: Some(WheelWeb::default()),
            bore_radius: 0.1,
            tread_size: 0.002,
            tread_band: 0.015,
            section_size: 0.012,
            growth: 1.3,
            fine_arc: 0.04,
            fine_pitch: 0.004,
            coarse_pitch: 2.0 * PI / 48.0,
        }
    }
}

pub(super) fn out_of_range(name: &'static str, value: f64, min: f64, max: f64) -> MeshError {
    MeshError::OutOfRange {
        name,
        value,
        min,
        max,
    }
}

/// `Ok` when `min <= value <= max` (not NaN).
pub(super) fn check_range(
    name: &'static str,
    value: f64,
    min: f64,
    max: f64,
) -> Result<(), MeshError> {
    if value >= min && value <= max {
        Ok(())
    } else {
        Err(out_of_range(name, value, min, max))
    }
}

impl WheelSpec {
    /// Checks the spec.
    ///
    /// # Errors
    /// [`MeshError`] naming the first field that is not a finite positive length, a ratio
    /// or angle out of its range, or radii out of order (the bore inside the hub inside the
    /// rim).
    pub fn validate(&self) -> Result<(), MeshError> {
        for (name, v) in [
            ("nominal_radius", self.nominal_radius),
            ("rim_depth", self.rim_depth),
            ("bore_radius", self.bore_radius),
            ("tread_size", self.tread_size),
            ("tread_band", self.tread_band),
            ("section_size", self.section_size),
            ("fine_arc", self.fine_arc),
            ("fine_pitch", self.fine_pitch),
            ("coarse_pitch", self.coarse_pitch),
        ] {
            check_length(name, v)?;
        }
        check_range("growth", self.growth, 1.0, 2.0)?;
        check_range("section_size", self.section_size, self.tread_size, 1.0)?;
        check_range("coarse_pitch", self.coarse_pitch, self.fine_pitch, PI / 3.0)?;
        check_range("fine_arc", self.fine_arc, self.fine_pitch, PI / 2.0)?;
        let rim_in = self.nominal_radius - self.rim_depth;
        check_range("rim_depth", rim_in, self.bore_radius, self.nominal_radius)?;
        if let Some(w) = self.web {
            check_length("web.thickness", w.thickness)?;
            check_length("web.hub_width", w.hub_width)?;
            let (a, b) = self.profile.profile().domain();
            check_range("web.centre", w.centre - 0.5 * w.thickness, a, b)?;
            check_range("web.centre", w.centre + 0.5 * w.thickness, a, b)?;
            check_range("web.hub_width", w.hub_width, w.thickness, 1.0)?;
            if !(w.hub_radius > self.bore_radius && w.hub_radius < rim_in) {
                return Err(out_of_range(
                    "web.hub_radius",
                    w.hub_radius,
                    self.bore_radius,
                    rim_in,
                ));
            }
        }
        Ok(())
    }
}

/// Fractions `0..=1` of a block's height `depth` (m) with rows of `fine` at the top (1),
/// growing by `growth` up to `coarse` toward the bottom (0).
pub(super) fn rows_to_top(depth: f64, fine: f64, growth: f64, coarse: f64) -> Vec<f64> {
    let x = graded(depth, fine, fine, growth, coarse);
    x.iter().rev().map(|d| 1.0 - d / depth).collect()
}

/// Uniform fractions `0..=1` with steps of about `size` over `depth`.
pub(super) fn rows_uniform(depth: f64, size: f64) -> Vec<f64> {
    let n = ((depth / size).ceil() as usize).max(1);
    (0..=n).map(|j| j as f64 / n as f64).collect()
}

/// Moves the `y` (component 0) of the point of `row` nearest to `y` onto `y`, and returns
/// its index in the row (ends excluded).
pub(super) fn snap(points: &mut [[f64; 2]], row: &[usize], y: f64) -> usize {
    let k = (1..row.len() - 1)
        .min_by(|&a, &b| {
            (points[row[a]][0] - y)
                .abs()
                .total_cmp(&(points[row[b]][0] - y).abs())
        })
        .unwrap_or(1);
    points[row[k]][0] = y;
    k
}

/// `n` points evenly from `a` to `b`, both included (`n >= 2`).
pub(super) fn line(a: [f64; 2], b: [f64; 2], n: usize) -> Vec<[f64; 2]> {
    (0..n)
        .map(|k| {
            let f = k as f64 / (n - 1) as f64;
            [a[0] + f * (b[0] - a[0]), a[1] + f * (b[1] - a[1])]
        })
        .collect()
}

/// Number of segments of about `size` over `len` (at least 1).
pub(super) fn segments(len: f64, size: f64) -> usize {
    ((len / size).ceil() as usize).max(1)
}

/// The wheel's cross-section in `(y, r)`, m (module docs), the indices of its tread nodes
/// (left to right) and of its bore nodes.
///
/// # Errors
/// As [`WheelSpec::validate`].
pub fn wheel_section(spec: &WheelSpec) -> Result<(QuadSection, Vec<usize>, Vec<usize>), MeshError> {
    spec.validate()?;
    let profile = spec.profile.profile();
    let (ya, yb) = profile.domain();
    let r0 = spec.nominal_radius;
    let rim_in = r0 - spec.rim_depth;
    let polyline = profile.polyline(400);
    let cum = profiles::section::arc_lengths(&polyline);
    let total = cum[cum.len() - 1];
    // The running circle's arc-length position.
    let s0 = on_curve_inverse(&polyline, &cum, 0.0);
    let s = graded_about(
        0.0,
        total,
        s0,
        spec.tread_size,
        spec.tread_band,
        spec.growth,
        spec.section_size,
    );
    let mut tread_pts = on_curve(&polyline, &s, |y| {
        r0 + profile.height(y.clamp(ya, yb)).unwrap_or(0.0)
    });
    tread_pts[0][0] = ya;
    let n = tread_pts.len();
    tread_pts[n - 1][0] = yb;
    let mut sec = QuadSection::new();
    let tread = sec.add_row(&tread_pts);
    let bottom_r = if spec.web.is_some() {
        rim_in
    } else {
        spec.bore_radius
    };
    let bottom_pts: Vec<[f64; 2]> = tread_pts.iter().map(|p| [p[0], bottom_r]).collect();
    let rim_bottom = sec.add_row(&bottom_pts);
    let rim_rows = rows_to_top(
        r0 - bottom_r,
        spec.tread_size,
        spec.growth,
        spec.section_size,
    );
    let Some(web) = spec.web else {
        sec.ruled_block(&rim_bottom, &tread, &rim_rows);
        return Ok((sec, tread, rim_bottom));
    };
    let (wl, wr) = (
        web.centre - 0.5 * web.thickness,
        web.centre + 0.5 * web.thickness,
    );
    let il = snap(&mut sec.points, &rim_bottom, wl);
    let ir = snap(&mut sec.points, &rim_bottom, wr);
    if ir <= il {
        return Err(out_of_range(
            "web.thickness",
            web.thickness,
            spec.tread_size,
            yb - ya,
        ));
    }
    sec.ruled_block(&rim_bottom, &tread, &rim_rows);
    // The web: the rim's bottom nodes il..=ir down to the hub.
    let web_top = rim_bottom[il..=ir].to_vec();
    let web_bottom_pts: Vec<[f64; 2]> = web_top
        .iter()
        .map(|&i| [sec.points[i][0], web.hub_radius])
        .collect();
    let web_bottom = sec.add_row(&web_bottom_pts);
    let web_rows = rows_uniform(rim_in - web.hub_radius, spec.section_size);
    sec.ruled_block(&web_bottom, &web_top, &web_rows);
    // The hub: its top is the web's bottom and the hub's shoulders either side.
    let (hl, hr) = (
        web.centre - 0.5 * web.hub_width,
        web.centre + 0.5 * web.hub_width,
    );
    let left = line(
        [hl, web.hub_radius],
        [wl, web.hub_radius],
        segments(wl - hl, spec.section_size) + 1,
    );
    let right = line(
        [wr, web.hub_radius],
        [hr, web.hub_radius],
        segments(hr - wr, spec.section_size) + 1,
    );
    let mut hub_top = sec.add_row(&left[..left.len() - 1]);
    hub_top.extend_from_slice(&web_bottom);
    hub_top.extend(sec.add_row(&right[1..]));
    let hub_bottom_pts: Vec<[f64; 2]> = hub_top
        .iter()
        .map(|&i| [sec.points[i][0], spec.bore_radius])
        .collect();
    let hub_bottom = sec.add_row(&hub_bottom_pts);
    let hub_rows = rows_uniform(web.hub_radius - spec.bore_radius, spec.section_size);
    sec.ruled_block(&hub_bottom, &hub_top, &hub_rows);
    Ok((sec, tread, hub_bottom))
}

/// The arc length along `polyline` (cumulative lengths `cum`) where its `y` first reaches
/// `y` (the polyline's `y` increasing).
pub(super) fn on_curve_inverse(polyline: &[[f64; 2]], cum: &[f64], y: f64) -> f64 {
    for (k, w) in polyline.windows(2).enumerate() {
        if w[1][0] >= y && w[0][0] <= y {
            let d = w[1][0] - w[0][0];
            let f = if d > 0.0 { (y - w[0][0]) / d } else { 0.0 };
            return cum[k] + f * (cum[k + 1] - cum[k]);
        }
    }
    0.0
}

/// The angles of the sweep's node planes, rad, from `-pi` (included) to `pi` (excluded,
/// the same plane as `-pi`), graded about 0 (module docs).
pub fn sweep_angles(spec: &WheelSpec) -> Vec<f64> {
    let mut t = graded_about(
        -PI,
        PI,
        0.0,
        spec.fine_pitch,
        spec.fine_arc,
        spec.growth,
        spec.coarse_pitch,
    );
    t.pop();
    t
}

/// A wheel of revolution meshed with hexahedra (module docs).
///
/// # Errors
/// As [`WheelSpec::validate`], and [`MeshError::TooLarge`] past
/// [`super::MAX_NODES`] nodes.
pub fn wheel_of_revolution(spec: &WheelSpec) -> Result<Mesh, MeshError> {
    let (sec, tread, bore) = wheel_section(spec)?;
    let angles = sweep_angles(spec);
    let (n, m) = (sec.points.len(), angles.len());
    check_nodes("fine_pitch", m, n.checked_mul(m))?;
    let mut coords = Vec::with_capacity(3 * n * m);
    for &t in &angles {
        let (s, c) = t.sin_cos();
        for p in &sec.points {
            coords.extend([p[1] * s, p[0], -p[1] * c]);
        }
    }
    let hexes = sweep_hexes(&sec, m, |k| (k + 1) % m, &coords);
    let (y_band, t_band) = (spec.tread_band * (1.0 + 1e-9), spec.fine_arc * (1.0 + 1e-9));
    let mut sets = BTreeMap::new();
    let all_layers = |ids: &[usize]| -> Vec<usize> {
        let mut v: Vec<usize> = (0..m)
            .flat_map(|k| ids.iter().map(move |&i| k * n + i))
            .collect();
        v.sort_unstable();
        v
    };
    sets.insert("tread".to_string(), all_layers(&tread));
    sets.insert("axle".to_string(), all_layers(&bore));
    let mut contact: Vec<usize> = angles
        .iter()
        .enumerate()
        .filter(|(_, t)| t.abs() <= t_band)
        .flat_map(|(k, _)| {
            tread
                .iter()
                .filter(|&&i| sec.points[i][0].abs() <= y_band)
                .map(move |&i| k * n + i)
        })
        .collect();
    contact.sort_unstable();
    sets.insert("contact".to_string(), contact);
    sets.insert("all".to_string(), (0..n * m).collect());
    Ok(Mesh::new(3, coords, Cells::Hex8(hexes), sets))
}
