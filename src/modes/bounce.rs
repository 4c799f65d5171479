//! The bounce of the wheel between its support and the contact held on the base
//! ([`bounce_mode`]), by Rayleigh-Ritz on the lowest modes with the contact nodes held.

use super::*;
/// The bounce of the wheel: the lowest mode with vertical translation, the disk moving
/// between its support (pin or hub) and the contact held on the base.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Bounce {
    /// Frequency, Hz.
    pub frequency_hz: f64,
    /// The mode's effective mass in vertical translation over the total mass (1: a rigid
    /// disk on two springs).
    pub vertical_mass_fraction: f64,
    /// Rim nodes held (their vertical dof) as the static contact patch.
    pub held_nodes: usize,
}

/// The bounce mode of the wheel pressed to the flattening `d` (m) on a base below it: the
/// rim nodes whose undeformed position lies beyond the base line `y = -(R - d)` (at least
/// the lowest one) are held vertically, the support as in the model, and among the lowest
/// modes of `K phi = omega^2 M phi` (elastic stiffness [`WheelModel::k_elastic`], the
/// model's mass) the bounce is the one with the largest effective mass in vertical
/// translation, `(phi^T M e_y)^2 / (phi^T M phi  e_y^T M e_y)`. With a pinned centre it is
/// the lowest mode (the point support is soft); with a clamped hub lower flexural modes
/// come first, so the modes are found by subspace iteration: [`BOUNCE_SUBSPACE`] vectors
/// (vertical and horizontal loads modulated by `cos j theta`, `sin (j+1) theta`), twelve
/// iterations `Phi <- K^{-1} M Phi` with one sparse factorization of `K`, each followed by a
/// Rayleigh-Ritz projection. Sparse: any mesh size.
///
/// # Errors
/// [`ModesError::NotFinite`] when `K` with the held dofs is singular;
/// [`ModesError::MassNotPositive`] or [`ModesError::NoConvergence`] from the projected
/// problem.
pub fn bounce_mode(model: &WheelModel, d: f64) -> Result<Bounce, ModesError> {
    use crate::linalg::{spmv_into, Factor};
    let n = model.mesh.n_dofs();
    let r = model.spec.radius;
    let y = |i: usize| model.mesh.point(i)[1];
    let lowest = model
        .rim
        .iter()
        .copied()
        .min_by(|&a, &b| y(a).total_cmp(&y(b)));
    let mut held: Vec<usize> = model
        .rim
        .iter()
        .copied()
        .filter(|&i| y(i) <= -(r - d))
        .collect();
    if held.is_empty() {
        held.extend(lowest);
    }
    let mut fixed = vec![false; n];
    for &dof in &model.fixed_dofs {
        fixed[dof] = true;
    }
    for &i in &held {
        fixed[2 * i + 1] = true;
    }
    let pattern = model.model.pattern();
    let (m, k) = (&model.model.m, &model.k_elastic);
    let mut kf = k.clone();
    crate::linalg::set_identity_rows(pattern, &mut kf, &fixed);
    let mut lu = Factor::auto(pattern, &kf).map_err(|_| ModesError::NotFinite {
        matrix: "stiffness",
    })?;
    let q = BOUNCE_SUBSPACE
        .min(fixed.iter().filter(|f| !**f).count())
        .max(1);
    // Start: vertical and horizontal loads modulated around the disk.
    let mut phi: Vec<Vec<f64>> = (0..q)
        .map(|c| {
            let (j, comp, sine) = (c / 4, (c / 2) % 2, c % 2 == 1);
            (0..n)
                .map(|dof| {
                    let p = model.mesh.point(dof / 2);
                    let th = p[1].atan2(p[0]);
                    let w = if sine {
                        ((j + 1) as f64 * th).sin()
                    } else {
                        (j as f64 * th).cos()
                    };
                    if dof % 2 == 1 - comp && !fixed[dof] {
                        w
                    } else {
                        0.0
                    }
                })
                .collect()
        })
        .collect();
    let mut tmp = vec![0.0; n];
    let mut ritz = (Vec::new(), Mat::<f64>::zeros(0, 0));
    for _ in 0..12 {
        for v in phi.iter_mut() {
            spmv_into(pattern, m, v, &mut tmp);
            for (t, &fx) in tmp.iter_mut().zip(&fixed) {
                if fx {
                    *t = 0.0;
                }
            }
            lu.solve_in_place(&mut tmp);
            v.copy_from_slice(&tmp);
        }
        ritz = rayleigh_ritz(pattern, m, k, &phi)?;
        // Phi <- Phi Y (the Ritz vectors, M-orthonormal).
        let y = &ritz.1;
        let old = phi.clone();
        for (c, v) in phi.iter_mut().enumerate() {
            for i in 0..n {
                v[i] = (0..q).map(|b| old[b][i] * y[(b, c)]).sum();
            }
        }
    }
    // The Ritz vector with the largest vertical effective mass.
    let ey: Vec<f64> = (0..n).map(|i| (i % 2) as f64).collect();
    let mut mey = vec![0.0; n];
    spmv_into(pattern, m, &ey, &mut mey);
    let mee: f64 = mey.iter().zip(&ey).map(|(a, b)| a * b).sum();
    let (mut best, mut frac) = (0, -1.0);
    for (c, v) in phi.iter().enumerate() {
        // M-orthonormal: phi^T M phi = 1.
        let g: f64 = v.iter().zip(&mey).map(|(a, b)| a * b).sum();
        let f = g * g / mee;
        if f > frac {
            (best, frac) = (c, f);
        }
    }
    let omega2 = ritz.0.get(best).copied().unwrap_or(0.0);
    Ok(Bounce {
        frequency_hz: omega2.max(0.0).sqrt() / (2.0 * std::f64::consts::PI),
        vertical_mass_fraction: frac,
        held_nodes: held.len(),
    })
}

/// Vectors of the subspace iteration of [`bounce_mode`].
pub const BOUNCE_SUBSPACE: usize = 16;

/// Rayleigh-Ritz on the columns `phi`: the eigenvalues `omega^2` of the projected problem
/// (increasing) and the coefficients `Y` of its M-orthonormal eigenvectors (`Phi Y`).
fn rayleigh_ritz(
    pattern: &crate::linalg::Pattern,
    m: &[f64],
    k: &[f64],
    phi: &[Vec<f64>],
) -> Result<(Vec<f64>, Mat<f64>), ModesError> {
    use crate::linalg::spmv_into;
    let q = phi.len();
    let n = phi.first().map_or(0, |v| v.len());
    let mut mp = vec![vec![0.0; n]; q];
    let mut kp = vec![vec![0.0; n]; q];
    for c in 0..q {
        spmv_into(pattern, m, &phi[c], &mut mp[c]);
        spmv_into(pattern, k, &phi[c], &mut kp[c]);
    }
    let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>();
    let mut bm = Mat::<f64>::from_fn(q, q, |i, j| dot(&phi[i], &mp[j]));
    let am = Mat::<f64>::from_fn(q, q, |i, j| {
        0.5 * (dot(&phi[i], &kp[j]) + dot(&phi[j], &kp[i]))
    });
    for j in 0..q {
        for i in j + 1..q {
            let s = 0.5 * (bm[(i, j)] + bm[(j, i)]);
            bm[(i, j)] = s;
            bm[(j, i)] = s;
        }
    }
    let l = bm
        .llt(Side::Lower)
        .map_err(|e| match e {
            LltError::NonPositivePivot { index } => ModesError::MassNotPositive { index },
        })?
        .L()
        .to_owned();
    let c = congruence(l.as_ref(), am, Par::Seq, true);
    let evd = c
        .self_adjoint_eigen(Side::Lower)
        .map_err(|_| ModesError::NoConvergence("self-adjoint"))?;
    let vals: Vec<f64> = (0..q).map(|i| evd.S().column_vector()[i]).collect();
    let mut y = evd.U().to_owned();
    solve_upper_triangular_in_place(l.as_ref().transpose(), y.as_mut(), Par::Seq);
    Ok((vals, y))
}
