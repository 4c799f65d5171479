//! Two-node beam element in 2D: Euler-Bernoulli and Timoshenko, with a rotational dof per
//! node (for a rail).
//!
//! # Kinematics and energy
//!
//! The beam lies along its local `x` (length `l`, m); a node carries the axial displacement
//! `u` (m), the deflection `w` (m, along the local `y`, the axis turned +90 degrees from `x`)
//! and the rotation `theta` (rad, counter-clockwise) of the cross-section. With the shear
//! strain `gamma = w' - theta` and the curvature `theta'`, the strain and kinetic energies are
//! $$U = \tfrac12\int_0^l \big(EA\\,u\'^2 + EI\\,\theta\'^2 + \kappa G A\\,(w\'-\theta)^2\big)\\,dx,
//!   \qquad T = \tfrac12\int_0^l \big(\rho A\\,(\dot u^2 + \dot w^2) + \rho I\\,\dot\theta^2\big)\\,dx,$$
//! with `E` Young's modulus (Pa), `G` the shear modulus (Pa), `A` the area (m^2), `I` the
//! second moment of area (m^4), `rho` the density (kg/m^3) and `kappa` the shear coefficient.
//! Euler-Bernoulli is the limit `kappa G A -> infinity` (`theta = w'`) without rotary inertia
//! (`rho I` dropped, the classical theory whose frequencies are
//! `omega_n = (n pi / L)^2 sqrt(EI / rho A)` pinned-pinned); Timoshenko keeps both.
//!
//! # The element
//!
//! **Euler-Bernoulli:** Hermite cubics for `w` (consistent mass and stiffness).
//!
//! **Timoshenko:** the "interdependent interpolation element" (IIE; Friedman and Kosmatka,
//! *Computers & Structures* 47, 1993; Reddy 1997): `w` cubic and `theta` quadratic, the
//! coefficients tied so that the shear strain is constant and the homogeneous static
//! equations `EI theta'' + kappa G A (w' - theta) = 0`, `(kappa G A (w' - theta))' = 0` hold
//! inside the element. With
//! $$\Phi = \frac{12\\,EI}{\kappa G A\\,l^2}$$
//! and `xi = x / l`, the shape functions for `(w1, theta1, w2, theta2)` are
//! $$N_w = \tfrac{1}{1+\Phi}\big[\\,2\xi^3-3\xi^2-\Phi\xi+1+\Phi,\\;
//!   l(\xi^3-(2+\tfrac\Phi2)\xi^2+(1+\tfrac\Phi2)\xi),\\;
//!   -2\xi^3+3\xi^2+\Phi\xi,\\; l(\xi^3-(1-\tfrac\Phi2)\xi^2-\tfrac\Phi2\xi)\big],$$
//! $$N_\theta = \tfrac{1}{1+\Phi}\big[\\,\tfrac6l(\xi^2-\xi),\\; 3\xi^2-(4+\Phi)\xi+1+\Phi,\\;
//!   -\tfrac6l(\xi^2-\xi),\\; 3\xi^2-(2-\Phi)\xi\big].$$
//! It is chosen over the linear element with reduced integration because it is exact for
//! static loads at the nodes (one element gives a cantilever's tip deflection
//! `P L^3 / 3EI + P L / kappa G A`), it is free of shear locking by construction
//! (`Phi -> 0` is the Hermite element exactly, so a slender rail costs nothing), and its
//! bending part is cubic. Its frequencies converge at second order where the shear energy
//! matters (its shear strain is constant per element; `tests/beam.rs`: a stocky beam,
//! `L/h = 5`, orders 2.00-2.09, and the UIC60 rail's pinned-pinned mode) and at the Hermite
//! element's fourth order in the slender limit. Its matrices (the energies above integrated
//! exactly) are
//! $$K_b = \frac{EI}{(1+\Phi)l^3}\begin{bmatrix}12&6l&-12&6l\\\\6l&(4+\Phi)l^2&-6l&(2-\Phi)l^2\\\\
//!   -12&-6l&12&-6l\\\\6l&(2-\Phi)l^2&-6l&(4+\Phi)l^2\end{bmatrix},$$
//! $$M_{\rho A} = \frac{\rho A l}{210(1+\Phi)^2}\begin{bmatrix}m_1&m_2&m_3&m_4\\\\m_2&m_5&-m_4&m_6\\\\
//!   m_3&-m_4&m_1&-m_2\\\\m_4&m_6&-m_2&m_5\end{bmatrix},\quad
//!   M_{\rho I} = \frac{\rho I}{30(1+\Phi)^2 l}\begin{bmatrix}36&m_8&-36&m_8\\\\m_8&m_9&-m_8&m_{10}\\\\
//!   -36&-m_8&36&-m_8\\\\m_8&m_{10}&-m_8&m_9\end{bmatrix},$$
//! with `m1 = 70 Phi^2 + 147 Phi + 78`, `m2 = (35 Phi^2 + 77 Phi + 44) l / 4`,
//! `m3 = 35 Phi^2 + 63 Phi + 27`, `m4 = -(35 Phi^2 + 63 Phi + 26) l / 4`,
//! `m5 = (7 Phi^2 + 14 Phi + 8) l^2 / 4`, `m6 = -(7 Phi^2 + 14 Phi + 6) l^2 / 4`,
//! `m8 = -(15 Phi - 3) l`, `m9 = (10 Phi^2 + 5 Phi + 4) l^2`, `m10 = (5 Phi^2 - 5 Phi - 1) l^2`.
//! `Phi = 0` gives the Hermite matrices (`rho A l / 420 [156, 22 l, 54, -13 l; ...]`); the
//! Euler-Bernoulli element is `Phi = 0` without `M_{rho I}`.
//!
//! **Axial part** (the frame element, [`frame_stiffness_into`]): the linear bar
//! ([`crate::element::bar2`]), `EA / l [1 -1; -1 1]` and `rho A l / 6 [2 1; 1 2]`; the
//! element matrices in local `(u, w, theta)` are turned to global `(u_x, u_y, theta)` by
//! `T^T K T`, `T = diag(R, 1, R, 1)`, `R = [c s; -s c]` with `(c, s)` the direction of the
//! element.
//!
//! The bending-only element ([`Beam2`], dofs `(w, theta)` per node) is the rail of a track
//! along `x`; the frame element ([`Frame2`], dofs `(u_x, u_y, theta)`) is a beam in any
//! direction of the plane.

use crate::assembly::ElementMatrix;

/// The beam theory of an element.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BeamTheory {
    /// Euler-Bernoulli: no shear deformation, no rotary inertia (Hermite cubics).
    EulerBernoulli,
    /// Timoshenko: shear deformation (`kappa G A`) and rotary inertia (`rho I`), the
    /// interdependent interpolation element.
    Timoshenko,
}

/// Invalid beam data.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum BeamError {
    /// A section property that must be positive and finite is not.
    #[error("beam section: {name} must be positive and finite, got {value}")]
    NotPositive {
        /// The property.
        name: &'static str,
        /// Its value.
        value: f64,
    },
    /// An element of zero, negative or non-finite length.
    #[error("beam element {element}: length {length} m is not positive and finite")]
    BadLength {
        /// The element.
        element: usize,
        /// Its length, m.
        length: f64,
    },
}

/// The cross-section and material of a beam.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BeamSection {
    /// Young's modulus `E`, Pa.
    pub young: f64,
    /// Shear modulus `G`, Pa (Timoshenko only).
    pub shear_modulus: f64,
    /// Shear coefficient `kappa` (5/6 for a rectangle; 0.4 for a rail's web), dimensionless
    /// (Timoshenko only).
    pub shear_coefficient: f64,
    /// Cross-section area `A`, m^2.
    pub area: f64,
    /// Second moment of area `I` about the bending axis, m^4.
    pub inertia: f64,
    /// Density `rho`, kg/m^3.
    pub density: f64,
}

impl BeamSection {
    /// The UIC60 rail in vertical bending: `E = 210 GPa`, `G = 77 GPa`, `kappa = 0.4`,
    /// `A = 7.69e-3 m^2`, `I = 3.055e-5 m^4`, `rho = 7850 kg/m^3`.
    pub const UIC60: BeamSection = BeamSection {
        young: 210.0e9,
        shear_modulus: 77.0e9,
        shear_coefficient: 0.4,
        area: 7.69e-3,
        inertia: 3.055e-5,
        density: 7850.0,
    };

    /// A solid rectangle `b x h` (m) of an isotropic material (`E`, `nu`, `rho`):
    /// `A = b h`, `I = b h^3 / 12`, `G = E / (2 (1 + nu))`, `kappa = 5/6`.
    pub fn rectangle(young: f64, poisson: f64, density: f64, b: f64, h: f64) -> Self {
        BeamSection {
            young,
            shear_modulus: young / (2.0 * (1.0 + poisson)),
            shear_coefficient: 5.0 / 6.0,
            area: b * h,
            inertia: b * h * h * h / 12.0,
            density,
        }
    }

    /// Checks that the properties `theory` uses are positive and finite.
    ///
    /// # Errors
    /// [`BeamError::NotPositive`].
    pub fn validate(&self, theory: BeamTheory) -> Result<(), BeamError> {
        let mut props = vec![
            ("young", self.young),
            ("area", self.area),
            ("inertia", self.inertia),
            ("density", self.density),
        ];
        if theory == BeamTheory::Timoshenko {
            props.push(("shear_modulus", self.shear_modulus));
            props.push(("shear_coefficient", self.shear_coefficient));
        }
        for (name, value) in props {
            if !(value.is_finite() && value > 0.0) {
                return Err(BeamError::NotPositive { name, value });
            }
        }
        Ok(())
    }

    /// Bending stiffness `EI`, N m^2.
    pub fn ei(&self) -> f64 {
        self.young * self.inertia
    }

    /// Mass per unit length `rho A`, kg/m.
    pub fn rho_a(&self) -> f64 {
        self.density * self.area
    }

    /// The shear parameter `Phi = 12 EI / (kappa G A l^2)` of an element of length `l` (m):
    /// 0 for Euler-Bernoulli.
    pub fn phi(&self, theory: BeamTheory, l: f64) -> f64 {
        match theory {
            BeamTheory::EulerBernoulli => 0.0,
            BeamTheory::Timoshenko => {
                12.0 * self.ei() / (self.shear_coefficient * self.shear_modulus * self.area * l * l)
            }
        }
    }
}

/// The lengths of the elements `elements` (node pairs) on the nodes at the flat coordinates
/// `coords`, `dim` per node (m).
///
/// # Errors
/// [`BeamError::BadLength`] for a zero, negative or non-finite length (coincident nodes).
///
/// # Panics
/// If an element refers to a node past `coords`.
pub fn lengths(coords: &[f64], dim: usize, elements: &[[usize; 2]]) -> Result<Vec<f64>, BeamError> {
    let x = |i: usize| &coords[dim * i..dim * (i + 1)];
    elements
        .iter()
        .enumerate()
        .map(|(element, &[a, b])| {
            let (p, q) = (x(a), x(b));
            let length = match dim {
                2 => (q[0] - p[0]).hypot(q[1] - p[1]),
                _ => p
                    .iter()
                    .zip(q)
                    .map(|(u, v)| (v - u).powi(2))
                    .sum::<f64>()
                    .sqrt(),
            };
            if length.is_finite() && length > 0.0 {
                Ok(length)
            } else {
                Err(BeamError::BadLength { element, length })
            }
        })
        .collect()
}

/// The shape functions at `xi = x / l` in `[0, 1]` for `(w1, theta1, w2, theta2)`: the
/// deflection's `N_w` and the rotation's `N_theta` (module docs; `Phi = 0`: Hermite cubics
/// and their derivatives).
pub fn shape_functions(phi: f64, l: f64, xi: f64) -> ([f64; 4], [f64; 4]) {
    let s = 1.0 / (1.0 + phi);
    let (x2, x3) = (xi * xi, xi * xi * xi);
    let nw = [
        s * (2.0 * x3 - 3.0 * x2 - phi * xi + 1.0 + phi),
        s * l * (x3 - (2.0 + 0.5 * phi) * x2 + (1.0 + 0.5 * phi) * xi),
        s * (-2.0 * x3 + 3.0 * x2 + phi * xi),
        s * l * (x3 - (1.0 - 0.5 * phi) * x2 - 0.5 * phi * xi),
    ];
    let nt = [
        s * 6.0 / l * (x2 - xi),
        s * (3.0 * x2 - (4.0 + phi) * xi + 1.0 + phi),
        -s * 6.0 / l * (x2 - xi),
        s * (3.0 * x2 - (2.0 - phi) * xi),
    ];
    (nw, nt)
}

/// Fills `out` with the bending stiffness `K_b` (module docs) of an element of length `l`
/// (m), dofs `(w1, theta1, w2, theta2)`; units N/m, N/rad, N m/rad.
pub fn bending_stiffness_into(
    section: &BeamSection,
    theory: BeamTheory,
    l: f64,
    out: &mut [[f64; 4]; 4],
) {
    let phi = section.phi(theory, l);
    let c = section.ei() / ((1.0 + phi) * l * l * l);
    let (a, b, d) = (6.0 * l, (4.0 + phi) * l * l, (2.0 - phi) * l * l);
    *out = [
        [12.0 * c, a * c, -12.0 * c, a * c],
        [a * c, b * c, -a * c, d * c],
        [-12.0 * c, -a * c, 12.0 * c, -a * c],
        [a * c, d * c, -a * c, b * c],
    ];
}

/// Fills `out` with the consistent bending mass `M_{rho A}` (+ `M_{rho I}` for Timoshenko)
/// of an element of length `l` (m), dofs `(w1, theta1, w2, theta2)`; units kg, kg m, kg m^2.
pub fn bending_mass_into(
    section: &BeamSection,
    theory: BeamTheory,
    l: f64,
    out: &mut [[f64; 4]; 4],
) {
    let phi = section.phi(theory, l);
    let p2 = phi * phi;
    let t = section.rho_a() * l / (210.0 * (1.0 + phi) * (1.0 + phi));
    let m1 = 70.0 * p2 + 147.0 * phi + 78.0;
    let m2 = (35.0 * p2 + 77.0 * phi + 44.0) * l / 4.0;
    let m3 = 35.0 * p2 + 63.0 * phi + 27.0;
    let m4 = -(35.0 * p2 + 63.0 * phi + 26.0) * l / 4.0;
    let m5 = (7.0 * p2 + 14.0 * phi + 8.0) * l * l / 4.0;
    let m6 = -(7.0 * p2 + 14.0 * phi + 6.0) * l * l / 4.0;
    *out = [
        [t * m1, t * m2, t * m3, t * m4],
        [t * m2, t * m5, -t * m4, t * m6],
        [t * m3, -t * m4, t * m1, -t * m2],
        [t * m4, t * m6, -t * m2, t * m5],
    ];
    if theory == BeamTheory::Timoshenko {
        let r = section.density * section.inertia / (30.0 * (1.0 + phi) * (1.0 + phi) * l);
        let m8 = -(15.0 * phi - 3.0) * l;
        let m9 = (10.0 * p2 + 5.0 * phi + 4.0) * l * l;
        let m10 = (5.0 * p2 - 5.0 * phi - 1.0) * l * l;
        let rot = [
            [36.0, m8, -36.0, m8],
            [m8, m9, -m8, m10],
            [-36.0, -m8, 36.0, -m8],
            [m8, m10, -m8, m9],
        ];
        for i in 0..4 {
            for j in 0..4 {
                out[i][j] += r * rot[i][j];
            }
        }
    }
}

/// The local `(u1, w1, theta1, u2, w2, theta2)` matrix from the axial `2 x 2` and bending
/// `4 x 4` blocks, turned to global `(u_x, u_y, theta)` by the direction `(c, s)`.
fn frame_from_blocks(axial: [[f64; 2]; 2], bend: [[f64; 4]; 4], c: f64, s: f64) -> [[f64; 6]; 6] {
    const AX: [usize; 2] = [0, 3];
    const BE: [usize; 4] = [1, 2, 4, 5];
    let mut local = [[0.0; 6]; 6];
    for i in 0..2 {
        for j in 0..2 {
            local[AX[i]][AX[j]] = axial[i][j];
        }
    }
    for i in 0..4 {
        for j in 0..4 {
            local[BE[i]][BE[j]] = bend[i][j];
        }
    }
    // T: local = T global, per node [[c, s, 0], [-s, c, 0], [0, 0, 1]].
    let mut t = [[0.0; 6]; 6];
    for n in [0, 3] {
        t[n][n] = c;
        t[n][n + 1] = s;
        t[n + 1][n] = -s;
        t[n + 1][n + 1] = c;
        t[n + 2][n + 2] = 1.0;
    }
    let mut out = [[0.0; 6]; 6];
    for i in 0..6 {
        for j in 0..6 {
            let mut sum = 0.0;
            for a in 0..6 {
                for b in 0..6 {
                    sum += t[a][i] * local[a][b] * t[b][j];
                }
            }
            out[i][j] = sum;
        }
    }
    out
}

/// Fills `out` with the frame stiffness (axial bar + bending, module docs) of the element
/// from `p0` to `p1` (m), global dofs `(u_x, u_y, theta)` per node.
pub fn frame_stiffness_into(
    section: &BeamSection,
    theory: BeamTheory,
    p0: [f64; 2],
    p1: [f64; 2],
    out: &mut [[f64; 6]; 6],
) {
    let (dx, dy) = (p1[0] - p0[0], p1[1] - p0[1]);
    let l = dx.hypot(dy);
    let mut axial = [[0.0; 2]; 2];
    super::bar2::stiffness_into(l, section.young * section.area, &mut axial);
    let mut bend = [[0.0; 4]; 4];
    bending_stiffness_into(section, theory, l, &mut bend);
    *out = frame_from_blocks(axial, bend, dx / l, dy / l);
}

/// Fills `out` with the frame's consistent mass (axial bar + bending, module docs) of the
/// element from `p0` to `p1` (m), global dofs `(u_x, u_y, theta)` per node.
pub fn frame_mass_into(
    section: &BeamSection,
    theory: BeamTheory,
    p0: [f64; 2],
    p1: [f64; 2],
    out: &mut [[f64; 6]; 6],
) {
    let (dx, dy) = (p1[0] - p0[0], p1[1] - p0[1]);
    let l = dx.hypot(dy);
    let mut axial = [[0.0; 2]; 2];
    super::bar2::mass_into(l, section.rho_a(), false, &mut axial);
    let mut bend = [[0.0; 4]; 4];
    bending_mass_into(section, theory, l, &mut bend);
    *out = frame_from_blocks(axial, bend, dx / l, dy / l);
}

/// Which matrix an element operator assembles.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BeamMatrix {
    /// The consistent mass.
    Mass,
    /// The elastic stiffness.
    Stiffness,
}

/// The bending-only beam along `x` over a family of elements with dofs `(w, theta)` per node
/// ([`bending_mass_into`], [`bending_stiffness_into`]).
#[derive(Debug, Clone, Copy)]
pub struct Beam2<'a> {
    /// Element lengths, m ([`lengths`]).
    pub lengths: &'a [f64],
    /// Section and material.
    pub section: &'a BeamSection,
    /// Euler-Bernoulli or Timoshenko.
    pub theory: BeamTheory,
    /// Mass or stiffness.
    pub matrix: BeamMatrix,
}

impl ElementMatrix<4> for Beam2<'_> {
    fn element_matrix_into(&self, e: usize, out: &mut [[f64; 4]; 4]) {
        let l = self.lengths[e];
        match self.matrix {
            BeamMatrix::Mass => bending_mass_into(self.section, self.theory, l, out),
            BeamMatrix::Stiffness => bending_stiffness_into(self.section, self.theory, l, out),
        }
    }
}

/// The frame element (axial + bending) in any direction of the plane over a family of
/// elements with dofs `(u_x, u_y, theta)` per node ([`frame_mass_into`],
/// [`frame_stiffness_into`]).
#[derive(Debug, Clone, Copy)]
pub struct Frame2<'a> {
    /// End points of each element, m.
    pub ends: &'a [[[f64; 2]; 2]],
    /// Section and material.
    pub section: &'a BeamSection,
    /// Euler-Bernoulli or Timoshenko.
    pub theory: BeamTheory,
    /// Mass or stiffness.
    pub matrix: BeamMatrix,
}

impl ElementMatrix<6> for Frame2<'_> {
    fn element_matrix_into(&self, e: usize, out: &mut [[f64; 6]; 6]) {
        let [p0, p1] = self.ends[e];
        match self.matrix {
            BeamMatrix::Mass => frame_mass_into(self.section, self.theory, p0, p1, out),
            BeamMatrix::Stiffness => frame_stiffness_into(self.section, self.theory, p0, p1, out),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn section() -> BeamSection {
        BeamSection::rectangle(2.1e11, 0.3, 7850.0, 0.05, 0.2)
    }

    /// Gauss-Legendre, 5 points on [0, 1] (exact to degree 9).
    fn gauss5() -> [(f64, f64); 5] {
        let a = (5.0f64 - 2.0 * (10.0f64 / 7.0).sqrt()).sqrt() / 3.0;
        let b = (5.0f64 + 2.0 * (10.0f64 / 7.0).sqrt()).sqrt() / 3.0;
        let wa = (322.0 + 13.0 * 70.0f64.sqrt()) / 900.0;
        let wb = (322.0 - 13.0 * 70.0f64.sqrt()) / 900.0;
        [
            (0.5, 64.0 / 225.0),
            (0.5 * (1.0 - a), 0.5 * wa),
            (0.5 * (1.0 + a), 0.5 * wa),
            (0.5 * (1.0 - b), 0.5 * wb),
            (0.5 * (1.0 + b), 0.5 * wb),
        ]
    }

    #[test]
    fn closed_forms_are_the_energies_of_the_shape_functions_integrated() {
        let s = section();
        let l = 0.37;
        for theory in [BeamTheory::EulerBernoulli, BeamTheory::Timoshenko] {
            let phi = s.phi(theory, l);
            let kga = if phi > 0.0 {
                s.shear_coefficient * s.shear_modulus * s.area
            } else {
                0.0
            };
            let (mut kq, mut mq) = ([[0.0; 4]; 4], [[0.0; 4]; 4]);
            let dxi = 1e-6;
            for (xi, wq) in gauss5() {
                let (nw, nt) = shape_functions(phi, l, xi);
                // Derivatives by central differences of the cubic (exact to rounding, h^2
                // times the third derivative of a quadratic/cubic: checked at 1e-7).
                let (wp, _) = shape_functions(phi, l, xi + dxi);
                let (wm, _) = shape_functions(phi, l, xi - dxi);
                let (_, tp) = shape_functions(phi, l, xi + dxi);
                let (_, tm) = shape_functions(phi, l, xi - dxi);
                let dw: Vec<f64> = (0..4).map(|i| (wp[i] - wm[i]) / (2.0 * dxi * l)).collect();
                let dt: Vec<f64> = (0..4).map(|i| (tp[i] - tm[i]) / (2.0 * dxi * l)).collect();
                for i in 0..4 {
                    for j in 0..4 {
                        let gi = dw[i] - nt[i];
                        let gj = dw[j] - nt[j];
                        kq[i][j] += wq * l * (s.ei() * dt[i] * dt[j] + kga * gi * gj);
                        let rot = if theory == BeamTheory::Timoshenko {
                            s.density * s.inertia * nt[i] * nt[j]
                        } else {
                            0.0
                        };
                        mq[i][j] += wq * l * (s.rho_a() * nw[i] * nw[j] + rot);
                    }
                }
            }
            let (mut k, mut m) = ([[0.0; 4]; 4], [[0.0; 4]; 4]);
            bending_stiffness_into(&s, theory, l, &mut k);
            bending_mass_into(&s, theory, l, &mut m);
            let kmax = k.iter().flatten().fold(0.0f64, |a, b| a.max(b.abs()));
            let mmax = m.iter().flatten().fold(0.0f64, |a, b| a.max(b.abs()));
            for i in 0..4 {
                for j in 0..4 {
                    assert!(
                        (k[i][j] - kq[i][j]).abs() < 1e-6 * kmax,
                        "{theory:?} K {i}{j}"
                    );
                    assert!(
                        (m[i][j] - mq[i][j]).abs() < 1e-12 * mmax,
                        "{theory:?} M {i}{j}"
                    );
                    assert_eq!(k[i][j], k[j][i]);
                    assert_eq!(m[i][j], m[j][i]);
                }
            }
            // Shear constant along the element (the interdependent interpolation).
            let g = |xi: f64| {
                let (_, nt) = shape_functions(phi, l, xi);
                let (wp, _) = shape_functions(phi, l, xi + dxi);
                let (wm, _) = shape_functions(phi, l, xi - dxi);
                (wp[1] - wm[1]) / (2.0 * dxi * l) - nt[1]
            };
            assert!((g(0.1) - g(0.8)).abs() < 1e-8);
        }
    }

    #[test]
    fn shape_functions_interpolate_the_nodal_values() {
        for phi in [0.0, 0.4, 3.0] {
            let (w0, t0) = shape_functions(phi, 0.6, 0.0);
            let (w1, t1) = shape_functions(phi, 0.6, 1.0);
            let close =
                |a: [f64; 4], b: [f64; 4]| a.iter().zip(&b).all(|(x, y)| (x - y).abs() < 1e-15);
            assert!(close(w0, [1.0, 0.0, 0.0, 0.0]) && close(t0, [0.0, 1.0, 0.0, 0.0]));
            assert!(close(w1, [0.0, 0.0, 1.0, 0.0]) && close(t1, [0.0, 0.0, 0.0, 1.0]));
        }
    }

    #[test]
    fn one_element_cantilever_tip_deflection_is_exact() {
        // Clamped at node 1 (w1 = theta1 = 0), tip load P at node 2: the exact Timoshenko
        // deflection P L^3 / (3 EI) + P L / (kappa G A) (Euler-Bernoulli: the first term).
        let s = section();
        let (l, p) = (0.9, 1.0e4);
        for theory in [BeamTheory::EulerBernoulli, BeamTheory::Timoshenko] {
            let mut k = [[0.0; 4]; 4];
            bending_stiffness_into(&s, theory, l, &mut k);
            let det = k[2][2] * k[3][3] - k[2][3] * k[3][2];
            let w = p * k[3][3] / det;
            let mut exact = p * l * l * l / (3.0 * s.ei());
            if theory == BeamTheory::Timoshenko {
                exact += p * l / (s.shear_coefficient * s.shear_modulus * s.area);
            }
            assert!(
                (w - exact).abs() < 1e-12 * exact,
                "{theory:?}: {w} vs {exact}"
            );
        }
    }

    #[test]
    fn frame_in_any_direction_has_rigid_motions_and_its_mass() {
        let s = section();
        for angle in [0.0f64, 0.3, 2.0, -1.1] {
            let (c, sn) = (angle.cos(), angle.sin());
            let p0 = [0.2, -0.1];
            let l = 0.45;
            let p1 = [p0[0] + l * c, p0[1] + l * sn];
            let (mut k, mut m) = ([[0.0; 6]; 6], [[0.0; 6]; 6]);
            frame_stiffness_into(&s, BeamTheory::Timoshenko, p0, p1, &mut k);
            frame_mass_into(&s, BeamTheory::Timoshenko, p0, p1, &mut m);
            let kmax = k.iter().flatten().fold(0.0f64, |a, b| a.max(b.abs()));
            // Rigid motions: two translations and a rotation about p0
            // (u = omega x (x - p0): u_x = -omega dy, u_y = omega dx, theta = omega).
            let rigid = [
                [1.0, 0.0, 0.0, 1.0, 0.0, 0.0],
                [0.0, 1.0, 0.0, 0.0, 1.0, 0.0],
                [0.0, 0.0, 1.0, -(p1[1] - p0[1]), p1[0] - p0[0], 1.0],
            ];
            for d in rigid {
                for row in &k {
                    let f: f64 = row.iter().zip(&d).map(|(a, b)| a * b).sum();
                    assert!(f.abs() < 1e-9 * kmax, "angle {angle}: {f}");
                }
            }
            // A unit translation in any direction carries the element's mass rho A l.
            for dir in [0.0f64, 1.0, 2.5] {
                let d = [dir.cos(), dir.sin(), 0.0, dir.cos(), dir.sin(), 0.0];
                let q: f64 = (0..6)
                    .map(|i| (0..6).map(|j| d[i] * m[i][j] * d[j]).sum::<f64>())
                    .sum();
                let exact = s.rho_a() * l;
                assert!((q - exact).abs() < 1e-12 * exact, "angle {angle}: {q}");
            }
        }
    }

    #[test]
    fn bad_sections_and_lengths_are_errors() {
        let mut s = section();
        assert!(s.validate(BeamTheory::Timoshenko).is_ok());
        s.shear_modulus = 0.0;
        assert!(s.validate(BeamTheory::EulerBernoulli).is_ok());
        assert_eq!(
            s.validate(BeamTheory::Timoshenko),
            Err(BeamError::NotPositive {
                name: "shear_modulus",
                value: 0.0
            })
        );
        s.inertia = f64::NAN;
        assert!(s.validate(BeamTheory::EulerBernoulli).is_err());
        let pts = [0.0, 0.0, 1.0, 0.0, 1.0, 0.0];
        assert_eq!(lengths(&pts, 2, &[[0, 1]]), Ok(vec![1.0]));
        assert_eq!(
            lengths(&[0.0, 1.0, 3.0], 1, &[[0, 1], [1, 2]]),
            Ok(vec![1.0, 2.0])
        );
        assert_eq!(
            lengths(&pts, 2, &[[0, 1], [1, 2]]),
            Err(BeamError::BadLength {
                element: 1,
                length: 0.0
            })
        );
    }
}
