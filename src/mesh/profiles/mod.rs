//! Wheel and rail profiles: the S1002 wheel tread ([`s1002()`]), the UIC60 (60E1) rail head
//! ([`uic60_head`], [`mod@uic60`]) and the conical tread ([`conical`]), each a [`Profile`]: a height `z(y)` over
//! a lateral coordinate `y`, piece by piece (polynomials, circular arcs, straight lines),
//! in metres. The pieces are stored in the units of their standard (mm) and scaled on
//! evaluation, so the coefficients read as published.
//!
//! Conventions (both in m):
//! - a **wheel** profile gives the radius over the nominal one, `r(y) - r_0`, with `y`
//!   from the taping line (the running circle, 70 mm from the flange's back), positive
//!   toward the field side (the flange at negative `y`);
//! - a **rail** profile gives the height of the head's surface over the top of its crown
//!   (0 at `y = 0`, negative elsewhere), with `y` from the rail's centre line, positive
//!   toward the field side (the gauge side, which the flange faces, at negative `y`).
//!
//! [`section`] meshes cross-sections with quadrilaterals (ruled blocks between node rows,
//! graded spacings) for the generators of solids of revolution and extruded rails.

pub mod s1002;
pub mod section;
pub mod uic60;

pub use s1002::s1002;
pub use uic60::uic60_head;

/// One piece of a profile over `[y0, y1]` (in the profile's own unit, mm for the
/// standards' profiles).
#[derive(Debug, Clone, PartialEq)]
pub enum Piece {
    /// `z = sum_k c[k] y^k` (a polynomial, coefficients from the constant up).
    Polynomial(Vec<f64>),
    /// `z = zc + sign sqrt(R^2 - (y - yc)^2)`: the upper (`sign = +1`) or lower
    /// (`sign = -1`) half of the circle of centre `(yc, zc)` and radius `R`.
    Arc {
        /// Centre's `y`.
        yc: f64,
        /// Centre's `z`.
        zc: f64,
        /// Radius (> 0).
        radius: f64,
        /// `+1` for the upper half (convex seen from above), `-1` for the lower half.
        sign: f64,
    },
}

impl Piece {
    /// The second derivative `d^2 z / dy^2` at `y` (per unit of the piece's length).
    pub fn second_derivative(&self, y: f64) -> f64 {
        match self {
            Piece::Polynomial(c) => c
                .iter()
                .enumerate()
                .skip(2)
                .map(|(k, &ck)| (k * (k - 1)) as f64 * ck * y.powi(k as i32 - 2))
                .sum(),
            Piece::Arc {
                yc, radius, sign, ..
            } => {
                let d = y - yc;
                let s2 = (radius * radius - d * d).max(0.0);
                -sign * radius * radius / (s2 * s2.sqrt())
            }
        }
    }

    /// Height and slope `dz/dy` at `y` (the piece's unit). An arc's slope is infinite where
    /// its tangent is vertical; outside its circle the square root is taken of zero.
    pub fn eval(&self, y: f64) -> (f64, f64) {
        match self {
            Piece::Polynomial(c) => {
                let (mut z, mut dz) = (0.0, 0.0);
                // Horner's scheme for the value and its derivative, highest degree first.
                for &ck in c.iter().rev() {
                    dz = dz * y + z;
                    z = z * y + ck;
                }
                (z, dz)
            }
            Piece::Arc {
                yc,
                zc,
                radius,
                sign,
            } => {
                let d = y - yc;
                let s = (radius * radius - d * d).max(0.0).sqrt();
                (zc + sign * s, -sign * d / s)
            }
        }
    }
}

/// A profile `z(y)`: pieces over consecutive intervals `[joints[i], joints[i + 1]]`.
#[derive(Debug, Clone, PartialEq)]
pub struct Profile {
    /// A short name (`"S1002"`).
    pub name: &'static str,
    /// Where it is defined (the standard and the form of the data).
    pub source: &'static str,
    /// The ends of the pieces, increasing (one more than [`Profile::pieces`]), in the
    /// pieces' unit.
    pub joints: Vec<f64>,
    /// The pieces, left to right.
    pub pieces: Vec<Piece>,
    /// Metres per unit of the pieces (`1e-3` for data in mm).
    pub unit: f64,
}

impl Profile {
    /// The interval `[y_min, y_max]` where the profile is defined, m.
    pub fn domain(&self) -> (f64, f64) {
        (
            self.joints[0] * self.unit,
            self.joints[self.joints.len() - 1] * self.unit,
        )
    }

    /// The joints between the pieces (and the two ends), m.
    pub fn joints_m(&self) -> Vec<f64> {
        self.joints.iter().map(|j| j * self.unit).collect()
    }

    /// Index of the piece holding `y` (in the pieces' unit), `None` outside the domain. A
    /// joint belongs to the piece on its right (the last joint to the last piece).
    fn piece_at(&self, y: f64) -> Option<usize> {
        let n = self.pieces.len();
        if !(y >= self.joints[0] && y <= self.joints[n]) {
            return None;
        }
        Some(
            self.joints[1..n]
                .iter()
                .position(|&j| y < j)
                .unwrap_or(n - 1),
        )
    }

    /// The height `z(y)`, m, at `y` (m); `None` outside [`Profile::domain`] or for NaN.
    pub fn height(&self, y: f64) -> Option<f64> {
        let u = y / self.unit;
        self.piece_at(u)
            .map(|i| self.pieces[i].eval(u).0 * self.unit)
    }

    /// The slope `dz/dy` (dimensionless) at `y` (m); `None` outside [`Profile::domain`].
    pub fn slope(&self, y: f64) -> Option<f64> {
        let u = y / self.unit;
        self.piece_at(u).map(|i| self.pieces[i].eval(u).1)
    }

    /// The curvature of the profile's curve at `y` (m), 1/m:
    /// `z'' / (1 + z'^2)^(3/2)`, negative where the curve bends down (a rail's crown: `-1/R`),
    /// positive where it bends up; `None` outside [`Profile::domain`]. For a wheel's
    /// profile (the radius's excess over `y`) this is the transverse curvature of the tread
    /// seen from outside the wheel with the sign flipped: the principal curvature that
    /// Hertz's elliptic contact takes across the rolling direction.
    pub fn curvature(&self, y: f64) -> Option<f64> {
        let u = y / self.unit;
        self.piece_at(u).map(|i| {
            let p = &self.pieces[i];
            let s = p.eval(u).1;
            p.second_derivative(u) / (1.0 + s * s).powf(1.5) / self.unit
        })
    }

    /// The height and slope of the pieces on both sides of each inner joint, m and
    /// dimensionless: `(y, z_left, z_right, slope_left, slope_right)`, for checking the
    /// continuity of the profile.
    pub fn joint_jumps(&self) -> Vec<(f64, f64, f64, f64, f64)> {
        (1..self.pieces.len())
            .map(|i| {
                let y = self.joints[i];
                let (zl, sl) = self.pieces[i - 1].eval(y);
                let (zr, sr) = self.pieces[i].eval(y);
                (y * self.unit, zl * self.unit, zr * self.unit, sl, sr)
            })
            .collect()
    }

    /// Points `(y, z)` on the profile, m, from its left end to its right end: every joint,
    /// and `per_piece` equal steps inside each piece (equal steps of angle along an arc,
    /// of `y` along a polynomial), so that steep arcs are followed closely.
    pub fn polyline(&self, per_piece: usize) -> Vec<[f64; 2]> {
        let per = per_piece.max(1);
        let mut pts = Vec::with_capacity(self.pieces.len() * per + 1);
        for (i, p) in self.pieces.iter().enumerate() {
            let (a, b) = (self.joints[i], self.joints[i + 1]);
            for k in 0..per {
                let f = k as f64 / per as f64;
                let y = match p {
                    Piece::Polynomial(_) => a + f * (b - a),
                    Piece::Arc { yc, radius, .. } => {
                        let ta = ((a - yc) / radius).clamp(-1.0, 1.0).asin();
                        let tb = ((b - yc) / radius).clamp(-1.0, 1.0).asin();
                        yc + radius * (ta + f * (tb - ta)).sin()
                    }
                };
                let y = y.clamp(a, b);
                pts.push([y * self.unit, p.eval(y).0 * self.unit]);
            }
        }
        let n = self.pieces.len();
        let last = self.joints[n];
        pts.push([
            last * self.unit,
            self.pieces[n - 1].eval(last).0 * self.unit,
        ]);
        pts
    }
}

/// A conical tread: `z(y) = -slope y` over `[-half_width, half_width]` (m), the radius
/// falling by `slope` per metre toward the field side (`slope = 1/40` is the classic cone,
/// the "simple case" of the tread profiles). Returns `None` unless `slope` is finite and
/// `half_width` finite and positive.
pub fn conical(slope: f64, half_width: f64) -> Option<Profile> {
    if !(slope.is_finite() && half_width.is_finite() && half_width > 0.0) {
        return None;
    }
    Some(Profile {
        name: "conical",
        source: "a cone: the radius falls linearly toward the field side",
        joints: vec![-half_width, half_width],
        pieces: vec![Piece::Polynomial(vec![0.0, -slope])],
        unit: 1.0,
    })
}

/// Writes a mesh (the generated wheel or rail) as an XML unstructured grid (`.vtu`) for
/// ParaView, through the crate's VTK writer, with no fields.
///
/// # Errors
/// The writer's error (an inconsistent mesh, a file that cannot be written) as an
/// [`std::io::Error`].
pub fn write_mesh_vtu(path: &std::path::Path, mesh: &crate::mesh::Mesh) -> std::io::Result<()> {
    crate::output::vtk::write_vtu(path, mesh, None, &[], &[])
        .map_err(|e| std::io::Error::other(e.to_string()))
}

/// A profile by name: `"s1002"`, `"conical"` (1:40, 65 mm each side) or `"uic60"` (the
/// 60E1 head); `None` for any other.
pub fn by_name(name: &str) -> Option<Profile> {
    match name.to_ascii_lowercase().as_str() {
        "s1002" => Some(s1002()),
        "conical" | "cone" => conical(1.0 / 40.0, 0.065),
        "uic60" | "60e1" => Some(uic60_head()),
        _ => None,
    }
}
