//! The S1002 wheel tread (EN 13715, the UIC/ORE S1002 profile), in its published
//! piecewise definition: eight sections A to H over `y` in mm from the taping line
//! (positive toward the field side), polynomials on the tread and the flange root, circular
//! arcs and a straight line on the flange, the height being the radius over the nominal one
//! (mm). The coefficients are those of the standard's definition as distributed by
//! H. Netter (DLR Oberpfaffenhofen) with the wheelset test problem of Hairer and Wanner
//! (Solving Ordinary Differential Equations II, 1996, section VII.7; the "wheelset" problem
//! of the CWI/Bari test set for IVP solvers, Mazzia and Magherini).
//!
//! ```text
//!  Section A:  F =  AA - BA y                                  32.15796 <= y <= 60
//!  Section B:  F =  AB - BB y + CB y^2 - DB y^3 + EB y^4
//!                      - FB y^5 + GB y^6 - HB y^7 + IB y^8    -26 <= y <= 32.15796
//!  Section C:  F = -AC - BC y - CC y^2 - ... - HC y^7          -35 <= y <= -26
//!  Section D:  F =  AD - sqrt(BD^2 - (y + CD)^2)               -38.426669071 <= y <= -35
//!  Section E:  F = -AE - BE y                                  -39.764473993 <= y <= -38.426669071
//!  Section F:  F =  AF + sqrt(BF^2 - (y + CF)^2)               -49.662510381 <= y <= -39.764473993
//!  Section G:  F =  AG + sqrt(BG^2 - (y + CG)^2)               -62.764705882 <= y <= -49.662510381
//!  Section H:  F =  AH + sqrt(BH^2 - (y + CH)^2)               -70 <= y <= -62.764705882
//! ```
//!
//! The flange is 28 mm high (section G's top at `y = -55`), 32.5 mm thick 10 mm above the
//! taping line, and its back is vertical at `y = -70` (section H's end); the tread falls
//! 1:15 on the chamfer (section A).

use super::{Piece, Profile};

/// Section A: `AA`, `BA`.
const A: [f64; 2] = [1.364_323_640, 0.066_666_667];
/// Section B: `AB` to `IB`.
const B: [f64; 9] = [
    0.0,
    3.358_537_058e-02,
    1.565_681_624e-03,
    2.810_427_944e-05,
    5.844_240_864e-08,
    1.562_379_023e-08,
    5.309_217_349e-15,
    5.957_839_843e-12,
    2.646_656_573e-13,
];
/// Section C: `AC` to `HC`.
const C: [f64; 8] = [
    4.320_221_063e+03,
    1.038_384_026e+03,
    1.065_501_873e+02,
    6.051_367_875,
    2.054_332_446e-01,
    4.169_739_389e-03,
    4.687_195_829e-05,
    2.252_755_540e-07,
];
/// Sections D to H: `(A, B, C)` of each (the arcs' `A + sqrt(B^2 - (y + C)^2)`, the line's
/// `-A - B y`).
const D: [f64; 3] = [16.446, 13.0, 26.210_665];
const E: [f64; 2] = [93.576_667_419, 2.747_477_419];
const F: [f64; 3] = [8.834_924_130, 20.0, 58.558_326_413];
const G: [f64; 3] = [16.0, 12.0, 55.0];
const H: [f64; 3] = [9.519_259_302, 20.5, 49.5];

/// The section bounds, mm, from the flange's back (H) to the field side (A).
pub const JOINTS_MM: [f64; 9] = [
    -70.0,
    -62.764_705_882,
    -49.662_510_381,
    -39.764_473_993,
    -38.426_669_071,
    -35.0,
    -26.0,
    32.157_96,
    60.0,
];

/// The S1002 tread as a [`Profile`] (module docs), over `y` from -70 mm (the flange's
/// back) to +60 mm (the field side), heights in m over the nominal radius.
pub fn s1002() -> Profile {
    let arc = |[a, b, c]: [f64; 3], sign: f64| Piece::Arc {
        yc: -c,
        zc: a,
        radius: b,
        sign,
    };
    // Sections B and C alternate their signs as published.
    let b: Vec<f64> = B
        .iter()
        .enumerate()
        .map(|(k, &v)| if k % 2 == 1 { -v } else { v })
        .collect();
    let c: Vec<f64> = C.iter().map(|&v| -v).collect();
    Profile {
        name: "S1002",
        source: "EN 13715 S1002, the published piecewise definition (sections A-H)",
        joints: JOINTS_MM.to_vec(),
        pieces: vec![
            arc(H, 1.0),
            arc(G, 1.0),
            arc(F, 1.0),
            Piece::Polynomial(vec![-E[0], -E[1]]),
            arc(D, -1.0),
            Piece::Polynomial(c),
            Piece::Polynomial(b),
            Piece::Polynomial(vec![A[0], -A[1]]),
        ],
        unit: 1e-3,
    }
}
