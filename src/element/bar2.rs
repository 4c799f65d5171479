//! Two-node axial bar element (1D), linear shape functions.
//!
//! With length `l`, axial stiffness `EA` (N) and mass per unit length `rho A` (kg/m):
//!
//! $$K_e = \frac{EA}{l}\begin{bmatrix}1&-1\\\\-1&1\end{bmatrix},\quad
//!   M_e = \frac{\rho A l}{6}\begin{bmatrix}2&1\\\\1&2\end{bmatrix}\ \text{(consistent)},\quad
//!   M_e = \frac{\rho A l}{2} I\ \text{(lumped)}.$$

/// Fills `out` with the bar stiffness matrix.
pub fn stiffness_into(length: f64, ea: f64, out: &mut [[f64; 2]; 2]) {
    let k = ea / length;
    *out = [[k, -k], [-k, k]];
}

/// Fills `out` with the bar mass matrix, consistent or lumped.
pub fn mass_into(length: f64, rho_a: f64, lumped: bool, out: &mut [[f64; 2]; 2]) {
    let m = rho_a * length;
    *out = if lumped {
        [[m / 2.0, 0.0], [0.0, m / 2.0]]
    } else {
        [[m / 3.0, m / 6.0], [m / 6.0, m / 3.0]]
    };
}

/// Axial strain of the element from the end displacements.
pub fn strain(length: f64, u: [f64; 2]) -> f64 {
    (u[1] - u[0]) / length
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mass_sums_to_the_element_mass_both_ways() {
        for lumped in [false, true] {
            let mut m = [[0.0; 2]; 2];
            mass_into(0.25, 3.0, lumped, &mut m);
            let s: f64 = m.iter().flatten().sum();
            assert!((s - 0.75).abs() < 1e-15);
        }
    }

    #[test]
    fn rigid_translation_gives_no_force() {
        let mut k = [[0.0; 2]; 2];
        stiffness_into(0.3, 7.0, &mut k);
        for row in k {
            assert!((row[0] + row[1]).abs() < 1e-12);
        }
    }
}
