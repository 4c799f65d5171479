//! The UIC60 (60E1) rail: the head's running surface in its published geometry and a
//! simplified section below it of the published area, second moment and neutral axis.
//!
//! **The head** (EN 13674-1, the 60E1 profile drawing): a crown of radius 300 mm over a
//! width of 20.456 mm, arcs of 80 mm out to a width of 52.053 mm, then gauge-corner arcs of
//! 13 mm down to the head's flanks, inclined 1:20. Each arc is tangent to the next, so the
//! radii, the two widths and the flank's inclination fix every centre; the head then comes
//! out 72.0 mm wide where the 13 mm arcs meet the flanks, 14.3 mm below the crown (both the
//! drawing's own dimensions: checked in the tests, not imposed).
//!
//! **The section below the head** is simplified (the drawing's fishing surfaces, fillets
//! and curved web are not modelled): the flanks continue at 1:20 down to a flat underside
//! [`HEAD_DEPTH_MM`] below the crown, a straight web of [`WEB_THICKNESS_MM`], and a foot
//! of the published width (150 mm) whose upper face falls linearly from
//! [`FOOT_THICKNESS_MM`] at the web to the published 11.5 mm at its edges; the rail is
//! 172 mm high. The three free dimensions are fitted (validation/uic60_section_fit.py) so
//! that the section has the published area 76.70 cm^2, second moment about the horizontal
//! axis 3038.3 cm^4 and neutral axis 80.9 mm above the foot (EN 13674-1, 60E1: section
//! moduli 333.6 cm^3 at the head and 375.5 cm^3 at the foot): the vertical bending
//! stiffness, the mass and the head's height over the neutral axis are the real rail's.
//! The lateral second moment comes out 551 cm^4 against the published 512.3 cm^4 (+7.6 %,
//! the real foot being thinner toward its edges and the web thinner than the fitted one).

use super::{Piece, Profile};

/// Radius of the crown, mm (EN 13674-1, 60E1).
pub const CROWN_RADIUS_MM: f64 = 300.0;
/// Radius of the arcs beside the crown, mm.
pub const SIDE_RADIUS_MM: f64 = 80.0;
/// Radius of the gauge corners, mm.
pub const CORNER_RADIUS_MM: f64 = 13.0;
/// Width over which the crown's 300 mm arc runs, mm.
pub const CROWN_WIDTH_MM: f64 = 20.456;
/// Width over which the 300 mm and 80 mm arcs run, mm.
pub const SIDE_WIDTH_MM: f64 = 52.053;
/// Inclination of the head's flanks (dimensionless run per fall): 1:20.
pub const FLANK_INCLINATION: f64 = 1.0 / 20.0;
/// Published width of the head, mm.
pub const HEAD_WIDTH_MM: f64 = 72.0;
/// Published height of the rail, mm.
pub const RAIL_HEIGHT_MM: f64 = 172.0;
/// Published width of the foot, mm.
pub const FOOT_WIDTH_MM: f64 = 150.0;
/// Published thickness of the foot at its edges, mm.
pub const FOOT_EDGE_MM: f64 = 11.5;
/// Published area of the section, m^2 (76.70 cm^2).
pub const AREA_M2: f64 = 76.70e-4;
/// Published second moment of area about the horizontal axis, m^4 (3038.3 cm^4).
pub const SECOND_MOMENT_M4: f64 = 3038.3e-8;
/// Published height of the neutral axis over the foot, m (3038.3 / 375.5 cm).
pub const NEUTRAL_AXIS_M: f64 = 0.0809;
/// Published lateral second moment of area (about the vertical axis), m^4 (512.3 cm^4).
pub const LATERAL_SECOND_MOMENT_M4: f64 = 512.3e-8;

/// Depth of the simplified head's flat underside below the crown, mm (fitted: module docs).
pub const HEAD_DEPTH_MM: f64 = 42.783_984_49;
/// Thickness of the simplified foot at the web, mm (fitted).
pub const FOOT_THICKNESS_MM: f64 = 23.597_307_83;
/// Thickness of the simplified straight web, mm (fitted; the drawing's web is 16.5 mm at
/// its thinnest and widens in fillets toward the head and the foot).
pub const WEB_THICKNESS_MM: f64 = 18.437_407_32;

/// The arcs' centres `(y, z)`, mm, on the right half (the crown's, the 80 mm arc's, the
/// 13 mm arc's), the normal angles from the vertical where they meet (rad), and the point
/// where the 13 mm arc meets the flank.
pub struct HeadGeometry {
    /// Centres of the 300, 80 and 13 mm arcs, mm.
    pub centres: [[f64; 2]; 3],
    /// `y` of the joints 300/80, 80/13 and 13/flank, mm.
    pub joints: [f64; 3],
    /// The point where the 13 mm arc meets the flank, mm.
    pub flank_top: [f64; 2],
}

/// The right half of the head's arcs by tangency from the published radii, widths and
/// flank inclination (module docs).
pub fn head_geometry() -> HeadGeometry {
    let (r1, r2, r3) = (CROWN_RADIUS_MM, SIDE_RADIUS_MM, CORNER_RADIUS_MM);
    let (y1, y2) = (0.5 * CROWN_WIDTH_MM, 0.5 * SIDE_WIDTH_MM);
    let c1 = [0.0, -r1];
    let p1 = (y1 / r1).asin();
    let c2 = [c1[0] + (r1 - r2) * p1.sin(), c1[1] + (r1 - r2) * p1.cos()];
    let p2 = ((y2 - c2[0]) / r2).asin();
    let c3 = [c2[0] + (r2 - r3) * p2.sin(), c2[1] + (r2 - r3) * p2.cos()];
    // The flank widens downward by 1:20: its outward normal is turned from the
    // horizontal up by atan(1/20).
    let p3 = std::f64::consts::FRAC_PI_2 - FLANK_INCLINATION.atan();
    let flank_top = [c3[0] + r3 * p3.sin(), c3[1] + r3 * p3.cos()];
    HeadGeometry {
        centres: [c1, c2, c3],
        joints: [y1, y2, flank_top[0]],
        flank_top,
    }
}

/// The 60E1 head's running surface as a [`Profile`]: the 13, 80, 300, 80 and 13 mm arcs
/// from one flank to the other (heights in m below the crown, 0 at its top).
pub fn uic60_head() -> Profile {
    let g = head_geometry();
    let arc = |c: [f64; 2], r: f64| Piece::Arc {
        yc: c[0],
        zc: c[1],
        radius: r,
        sign: 1.0,
    };
    let mirror = |c: [f64; 2]| [-c[0], c[1]];
    let [c1, c2, c3] = g.centres;
    let [j1, j2, j3] = g.joints;
    Profile {
        name: "UIC60",
        source:
            "EN 13674-1 60E1 head: R300 over 20.456 mm, R80 to 52.053 mm, R13 to the 1:20 flanks",
        joints: vec![-j3, -j2, -j1, j1, j2, j3],
        pieces: vec![
            arc(mirror(c3), CORNER_RADIUS_MM),
            arc(mirror(c2), SIDE_RADIUS_MM),
            arc(c1, CROWN_RADIUS_MM),
            arc(c2, SIDE_RADIUS_MM),
            arc(c3, CORNER_RADIUS_MM),
        ],
        unit: 1e-3,
    }
}
