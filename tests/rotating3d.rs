//! The rotating frame in 3D ([`softway::frame3d`], [`softway::bodies::spinning`]) against
//! numbers from outside the code: the spinning disk's stresses and rim displacement
//! (Timoshenko and Goodier 1970, §32), the rigid-body resultants of the centrifugal load,
//! the neutral rigid rotation about the axle, the rotating rod's axial frequencies, the
//! energy the Coriolis matrix leaves alone in a free run of the step, and Bryan's
//! splitting of a spinning ring's `n = 2` pair (Bryan 1890).

use softway::assembly::Assembler;
use softway::bodies::solid::SolidSpec;
use softway::bodies::spinning::{spinning_solid, SpinSpec, SpinningError};
use softway::contact::search::Motion;
use softway::element::continuum::{assemble_continuum, SolidHex8, SolidTet10, SolidTet4};
use softway::element::solid::elasticity_3d;
use softway::frame3d::{self, Spin};
use softway::material::{Elastic, PlaneModel};
use softway::mesh::generators::box_mesh;
use softway::mesh::{CellKind, Mesh};
use softway::modes::{natural_modes_sparse_of, Matrices};
use softway::time::step::{FactorChoice, Stepper};
use softway::time::{Coriolis, SpaceTimeParams};
use std::f64::consts::PI;

const STEEL: Elastic = Elastic {
    young: 2.1e11,
    poisson: 0.3,
    density: 7850.0,
};

fn spec(material: Elastic, lumped: bool) -> SolidSpec {
    SolidSpec {
        material,
        plane: PlaneModel::Stress,
        thickness: 1.0,
        lumped,
    }
}

fn z_spin(rate: f64) -> SpinSpec {
    SpinSpec {
        spin: Spin::new([0.0; 3], [0.0, 0.0, 1.0], rate).unwrap(),
        stress_stiffening: true,
    }
}

/// A structured hex8 annulus about the z axis: radii `a..b` in `nr` rings, `nt` sectors,
/// thickness `t` in `nz` layers ([`softway::mesh::generators::annulus_hex8`]).
fn annulus(a: f64, b: f64, t: f64, counts: [usize; 3]) -> Mesh {
    softway::mesh::generators::annulus_hex8(a, b, t, counts).unwrap()
}

/// Timoshenko and Goodier (1970), §32, the rotating disk with a central hole (plane
/// stress): `(sigma_r, sigma_t)` at radius `r` of the annulus `a..b` at `w` rad/s.
fn disk_stresses(m: &Elastic, a: f64, b: f64, w: f64, r: f64) -> (f64, f64) {
    let nu = m.poisson;
    let c = (3.0 + nu) / 8.0 * m.density * w * w;
    let sr = c * (b * b + a * a - a * a * b * b / (r * r) - r * r);
    let st = c * (b * b + a * a + a * a * b * b / (r * r) - (1.0 + 3.0 * nu) / (3.0 + nu) * r * r);
    (sr, st)
}

/// The free spinning thin annulus (no supports: the body's statically determinate ones
/// carry nothing): its cells' radial and hoop stresses and its rim's radial displacement
/// against the closed form of Timoshenko and Goodier (1970, §32), on two meshes; the error
/// falls with the mesh.
#[test]
fn a_free_spinning_thin_disk_has_timoshenkos_stresses_and_rim_displacement() {
    let (a, b, t, w) = (0.02, 0.1, 0.002, 400.0);
    let mut errors = Vec::new();
    for (nr, nt) in [(8, 32), (16, 64)] {
        let mesh = annulus(a, b, t, [nr, nt, 1]);
        let s = spinning_solid(
            "disk",
            mesh,
            &spec(STEEL, false),
            Motion::Fixed,
            &[],
            z_spin(w),
        )
        .unwrap();
        let body = &s.solid.body;
        let mut stress = vec![0.0; 6 * body.mesh.cells.len()];
        s.solid.stresses.stresses_into(&s.u_spin, &mut stress);
        let (_, st_peak) = disk_stresses(&STEEL, a, b, w, a);
        let conn = body.mesh.cells.connectivity();
        let mut sq = 0.0;
        for (c, sv) in stress.chunks_exact(6).enumerate() {
            let nodes = &conn[8 * c..8 * c + 8];
            let (mut x, mut y) = (0.0, 0.0);
            for &i in nodes {
                x += body.mesh.point(i)[0] / 8.0;
                y += body.mesh.point(i)[1] / 8.0;
            }
            let r = x.hypot(y);
            let (cs, sn) = (x / r, y / r);
            let sr = sv[0] * cs * cs + sv[1] * sn * sn + 2.0 * sv[5] * sn * cs;
            let st = sv[0] * sn * sn + sv[1] * cs * cs - 2.0 * sv[5] * sn * cs;
            let (er, et) = disk_stresses(&STEEL, a, b, w, r);
            sq += (sr - er).powi(2) + (st - et).powi(2);
        }
        let rms = (sq / (2.0 * (stress.len() / 6) as f64)).sqrt() / st_peak;
        // The rim's radial displacement u(b) = b (sigma_t - nu sigma_r)/E with sigma_r = 0.
        let (_, st_b) = disk_stresses(&STEEL, a, b, w, b);
        let u_b = b * st_b / STEEL.young;
        let mut rim = (0.0, 0);
        for i in 0..body.mesh.n_nodes() {
            let p = body.mesh.point(i);
            let r = p[0].hypot(p[1]);
            if (r - b).abs() < 1e-9 {
                let ur = (s.u_spin[3 * i] * p[0] + s.u_spin[3 * i + 1] * p[1]) / r;
                rim = (rim.0 + ur, rim.1 + 1);
            }
        }
        let rim_err = (rim.0 / f64::from(rim.1) / u_b - 1.0).abs();
        println!(
            "disk {nr}x{nt}: rms stress error {rms:.4} of the peak hoop stress {st_peak:.4e} Pa, \
             rim u {:.6e} m vs {u_b:.6e} m ({rim_err:.2e})",
            rim.0 / f64::from(rim.1)
        );
        errors.push((rms, rim_err));
    }
    // The rim: a polygon of nt sides inside the circle (its area short by ~(2 pi/nt)^2/6).
    assert!(errors[0].1 < 0.015 && errors[1].1 < 0.005, "{errors:?}");
    assert!(errors[1].0 < 0.005, "{errors:?}");
    let errors: Vec<f64> = errors.iter().map(|e| e.0).collect();
    assert!(errors[1] < 0.6 * errors[0], "no convergence: {errors:?}");
}

/// The centrifugal load's resultant is Newton's `m Q (X_cm - x0)`: `m r Omega^2` outward for
/// a block of mass `m` whose centre is at the distance `r` from the axle, with consistent and
/// lumped masses on every element; zero for the annulus centred on the axle.
#[test]
fn the_centrifugal_resultant_is_m_r_omega_squared() {
    let (side, r, w) = (0.04, 0.3, 120.0);
    let spin = Spin::new([0.0, 0.0, 0.5], [0.0, 0.0, 1.0], w).unwrap();
    let d = elasticity_3d(&STEEL);
    for kind in [CellKind::Tet4, CellKind::Tet10, CellKind::Hex8] {
        let mut mesh = box_mesh(kind, [side; 3], [2, 2, 2]).unwrap();
        for p in mesh.coords.chunks_exact_mut(3) {
            p[0] += r - side / 2.0;
            p[1] -= side / 2.0;
        }
        for lumped in [false, true] {
            let (asm, m) = match kind {
                CellKind::Tet4 => assembled(&mesh, &SolidTet4 { d }, lumped),
                CellKind::Tet10 => assembled(&mesh, &SolidTet10 { d }, lumped),
                _ => assembled(&mesh, &SolidHex8 { d }, lumped),
            };
            let f = frame3d::centrifugal_load(&asm.pattern, &m, &spin, &mesh.reference_positions());
            let mass = STEEL.density * side.powi(3);
            let exact = mass * r * w * w;
            let sum = |c: usize| f.iter().skip(c).step_by(3).sum::<f64>();
            assert!(
                (sum(0) / exact - 1.0).abs() < 1e-12,
                "{kind:?} {} {exact}",
                sum(0)
            );
            assert!(sum(1).abs() < 1e-12 * exact && sum(2).abs() < 1e-12 * exact);
        }
    }
    let mesh = annulus(0.02, 0.1, 0.01, [3, 24, 2]);
    let (asm, m) = assembled(&mesh, &SolidHex8 { d }, false);
    let f = frame3d::centrifugal_load(&asm.pattern, &m, &spin, &mesh.reference_positions());
    let scale: f64 = f.iter().map(|v| v.abs()).sum();
    for c in 0..3 {
        assert!(f.iter().skip(c).step_by(3).sum::<f64>().abs() < 1e-12 * scale);
    }
}

fn assembled<E: softway::element::Continuum<N>, const N: usize>(
    mesh: &Mesh,
    el: &E,
    lumped: bool,
) -> (Assembler, Vec<f64>) {
    let a = assemble_continuum(mesh, el, STEEL.density, lumped).unwrap();
    (a.assembler, a.m)
}

/// A free block spun about its own axis of symmetry: with the stress stiffening of its
/// spinning equilibrium, `K_eff` leaves the rigid rotation about the axle neutral (a
/// rotated spinning body is still in equilibrium) on every element; without it, the
/// rotation has the spin softening's negative stiffness `-Omega^2 M`. An off-axis free body
/// is refused (its load has a resultant).
#[test]
fn the_rigid_rotation_about_the_axle_is_neutral() {
    let w = 500.0;
    // The lumped hexahedra's nodal masses keep the block's symmetry (the lumped tetrahedra of
    // Kuhn's cut do not: their centrifugal load has a moment about the axle).
    for (kind, lumped) in [
        (CellKind::Tet4, false),
        (CellKind::Tet10, false),
        (CellKind::Hex8, false),
        (CellKind::Hex8, true),
    ] {
        let mesh = box_mesh(kind, [0.2, 0.2, 0.06], [4, 4, 2]).unwrap();
        let spin = Spin::new([0.1, 0.1, 0.0], [0.0, 0.0, 1.0], w).unwrap();
        let x = mesh.reference_positions();
        let rot = spin.rigid_rotation(&x);
        let mut forces = Vec::new();
        for stress_stiffening in [true, false] {
            let s = spinning_solid(
                "block",
                mesh.clone(),
                &spec(STEEL, lumped),
                Motion::Fixed,
                &[],
                SpinSpec {
                    spin,
                    stress_stiffening,
                },
            )
            .unwrap();
            let model = &s.solid.body.model;
            let mut ku = vec![0.0; x.len()];
            softway::linalg::spmv_into(&model.assembler.pattern, &model.k, &rot, &mut ku);
            let mut mu = vec![0.0; x.len()];
            softway::linalg::spmv_into(&model.assembler.pattern, &model.m, &rot, &mut mu);
            let norm = |v: &[f64]| v.iter().map(|a| a * a).sum::<f64>().sqrt();
            forces.push(norm(&ku) / (w * w * norm(&mu)));
        }
        println!("{kind:?} (lumped {lumped}): |K_eff u_rot| / |Omega^2 M u_rot| = {forces:?}");
        assert!(forces[0] < 1e-8, "{kind:?}: {forces:?}");
        assert!((forces[1] - 1.0).abs() < 1e-9, "{kind:?}: {forces:?}");
    }
    let mesh = box_mesh(CellKind::Hex8, [0.1; 3], [1, 1, 1]).unwrap();
    let e = spinning_solid(
        "off",
        mesh,
        &spec(STEEL, false),
        Motion::Fixed,
        &[],
        z_spin(10.0),
    )
    .unwrap_err();
    assert!(matches!(e, SpinningError::Unbalanced { .. }), "{e}");
    assert!(e.to_string().contains("give the body supports"), "{e}");
}

/// Spin softening: a rod along `x`, clamped at `x = 0`, held to axial motion, spinning about
/// `z` through the clamp. Its axial motion obeys `rho u'' = E u_xx + rho Omega^2 u` (the
/// centrifugal load of the displacement), so the fixed-free rod's frequencies fall to
/// `sqrt(((2n - 1) pi c / 2L)^2 - Omega^2)`, `c = sqrt(E / rho)`; spun about its own axis,
/// they stay.
#[test]
fn spin_softening_lowers_the_rotating_rods_axial_frequencies() {
    let material = Elastic {
        poisson: 0.0,
        ..STEEL
    };
    let len = 1.0;
    let mesh = box_mesh(CellKind::Hex8, [len, 0.04, 0.04], [60, 1, 1]).unwrap();
    let c = (material.young / material.density).sqrt();
    let w1 = PI * c / (2.0 * len);
    let held: Vec<usize> = (0..mesh.n_nodes())
        .flat_map(|i| {
            let clamp = mesh.point(i)[0] < 1e-12;
            [3 * i, 3 * i + 1, 3 * i + 2]
                .into_iter()
                .filter(move |&d| clamp || d % 3 != 0)
        })
        .collect();
    for (axis, softened) in [([0.0, 0.0, 1.0], true), ([1.0, 0.0, 0.0], false)] {
        let omega = 0.6 * w1;
        let s = spinning_solid(
            "rod",
            mesh.clone(),
            &spec(material, false),
            Motion::Fixed,
            &held,
            SpinSpec {
                spin: Spin::new([0.0; 3], axis, omega).unwrap(),
                stress_stiffening: false,
            },
        )
        .unwrap();
        let model = &s.solid.body.model;
        let modes = natural_modes_sparse_of(
            &Matrices {
                mesh: &s.solid.body.mesh,
                assembler: &model.assembler,
                m: &model.m,
                k: &model.k,
                fixed_dofs: &held,
            },
            3,
        )
        .unwrap();
        let f: Vec<f64> = modes.iter().map(|m| m.frequency_hz * 2.0 * PI).collect();
        for (n, got) in f.iter().enumerate() {
            let w0 = (2 * n + 1) as f64 * w1;
            let exact = if softened {
                (w0 * w0 - omega * omega).sqrt()
            } else {
                w0
            };
            println!(
                "axis {axis:?}: mode {}: {got:.2} rad/s vs {exact:.2}",
                n + 1
            );
            assert!(
                (got / exact - 1.0).abs() < 2e-3,
                "mode {}: {got} vs {exact}",
                n + 1
            );
        }
    }
}

/// The Coriolis matrix does no work: a free spinning disk, started from its spinning
/// equilibrium with a velocity out of it, run by the step with `alpha = 1/2`, `gamma = 0`
/// (`beta = 1/2`) and `G` in `A`. Then the step is `(M - h^2 K/8)(v1 - v0) = -h G vm -
/// h K (u0 + u1)/2` with `vm = (v0 + v1)/2 = (u1 - u0)/h` (`K = K_eff`, `u` from `u_c`), and
/// `vm^T` times it gives, since `vm^T G vm = 0` for a skew `G`, the exact invariant
/// `E_h = v^T (M - h^2 K/8) v / 2 + u^T K u / 2`. The same run without `G` ends elsewhere:
/// the Coriolis force is not negligible in it.
#[test]
fn the_coriolis_term_keeps_the_energy_of_a_free_spinning_disk() {
    let (b, w) = (0.1, 2000.0);
    let mesh = annulus(0.02, b, 0.01, [3, 16, 1]);
    let s = spinning_solid(
        "disk",
        mesh,
        &spec(STEEL, false),
        Motion::Fixed,
        &[],
        z_spin(w),
    )
    .unwrap();
    let body = &s.solid.body;
    let n = body.mesh.n_dofs();
    // A velocity with a drift across the axle (which the Coriolis force turns), an n = 2
    // ovalisation and a dish.
    let v0: Vec<f64> = (0..body.mesh.n_nodes())
        .flat_map(|i| {
            let p = body.mesh.point(i);
            let (r, th) = (p[0].hypot(p[1]), p[1].atan2(p[0]));
            let vr = 0.1 * (2.0 * th).cos() * r / b;
            [0.1 + vr * th.cos(), vr * th.sin(), 0.05 * (r / b).powi(2)]
        })
        .collect();
    let params = SpaceTimeParams {
        alpha: 0.5,
        gamma: 0.0,
        // Stable and E_h positive while h^2 omega_max^2 / 8 < 1 (omega_max ~ 3e6 rad/s here).
        h: 2e-7,
    };
    let mut ends = Vec::new();
    for with_coriolis in [true, false] {
        let mut model = body.model.clone();
        if !with_coriolis {
            model.c.iter_mut().for_each(|x| *x = 0.0);
        }
        let pat = &model.assembler.pattern;
        let energy = |u: &[f64], v: &[f64]| {
            let du: Vec<f64> = u.iter().zip(&s.u_spin).map(|(a, b)| a - b).collect();
            let (mut mv, mut kv, mut kd) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
            softway::linalg::spmv_into(pat, &model.m, v, &mut mv);
            softway::linalg::spmv_into(pat, &model.k, v, &mut kv);
            softway::linalg::spmv_into(pat, &model.k, &du, &mut kd);
            let dot = |x: &[f64], y: &[f64]| x.iter().zip(y).map(|(a, b)| a * b).sum::<f64>();
            0.5 * (dot(v, &mv) - params.h * params.h / 8.0 * dot(v, &kv)) + 0.5 * dot(&du, &kd)
        };
        let mut st = Stepper::new(&model, params, &[]).unwrap();
        let (mut u, mut v) = (s.u_spin.clone(), v0.clone());
        let (mut b1, mut u1) = (vec![0.0; n], vec![0.0; n]);
        let e0 = energy(&u, &v);
        let mut drift = 0.0f64;
        for _ in 0..1000 {
            st.rhs_into(&u, &v, &[], &body.load, &mut b1);
            st.solve(&mut b1);
            st.update_displacement(params.beta(), &u, &v, &b1, &mut u1);
            std::mem::swap(&mut u, &mut u1);
            v.copy_from_slice(&b1);
            drift = drift.max((energy(&u, &v) / e0 - 1.0).abs());
        }
        println!("coriolis {with_coriolis}: E_h drift {drift:.3e} over 1000 steps (E0 {e0:.4e} J)");
        assert!(drift < 1e-9, "energy drift {drift}");
        ends.push(u);
    }
    let motion: f64 = ends[0]
        .iter()
        .zip(&s.u_spin)
        .map(|(a, b)| (a - b).powi(2))
        .sum::<f64>()
        .sqrt();
    let apart: f64 = ends[0]
        .iter()
        .zip(&ends[1])
        .map(|(a, b)| (a - b).powi(2))
        .sum::<f64>()
        .sqrt();
    println!("with and without G: |u_G - u_0| = {apart:.3e} m, |u_G - u_c| = {motion:.3e} m");
    assert!(apart > 0.1 * motion, "{apart} vs {motion}");
    // The Coriolis term on the right-hand side (time.coriolis = "extrapolated"): the step
    // takes the 3D G's skew part out of A, and rolls the same run to O(h^2 G a').
    let mut st = Stepper::with_options(
        &body.model,
        params,
        &[],
        FactorChoice::Auto,
        Coriolis::Extrapolated,
    )
    .unwrap();
    assert_eq!(st.coriolis(), Coriolis::Extrapolated);
    let (mut u, mut v, mut v_prev) = (s.u_spin.clone(), v0.clone(), v0.clone());
    let (mut b1, mut u1, mut a0) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
    for _ in 0..1000 {
        for ((a, x), y) in a0.iter_mut().zip(&v).zip(&v_prev) {
            *a = (x - y) / params.h;
        }
        st.rhs_into(&u, &v, &a0, &body.load, &mut b1);
        st.solve(&mut b1);
        st.update_displacement(params.beta(), &u, &v, &b1, &mut u1);
        std::mem::swap(&mut u, &mut u1);
        v_prev.copy_from_slice(&v);
        v.copy_from_slice(&b1);
    }
    let off: f64 = u
        .iter()
        .zip(&ends[0])
        .map(|(a, b)| (a - b).powi(2))
        .sum::<f64>()
        .sqrt();
    println!(
        "extrapolated Coriolis: |u_ex - u_G| = {off:.3e} m ({:.2e} of the motion)",
        off / motion
    );
    assert!(off < 1e-3 * motion, "{off} vs {motion}");
}

/// Bryan's effect (Bryan 1890, "On the beats in the vibrations of a revolving cylinder or
/// bell", Proc. Camb. Phil. Soc. 7): the in-plane flexural modes of a thin ring with `n`
/// waves, in the frame turning with it at `Omega`, split into a forward and a backward wave
/// whose frequencies differ by `4 n Omega / (n^2 + 1)` (the pattern turns against the ring at
/// `2 Omega / (n^2 + 1)`). To first order in `Omega` the split of an `M`-orthonormal pair
/// `phi_1, phi_2` of rest frequency `omega_0` is `|phi_1^T G phi_2|` (the pair's `2 x 2`
/// gyroscopic problem `omega^2 - omega_0^2 = +- omega g`): the free 3D ring's `n = 2` pair,
/// found by subspace iteration from purely radial `cos 2 theta`, `sin 2 theta` fields,
/// against `8 Omega / 5`.
#[test]
fn a_spinning_rings_n2_pair_splits_by_bryans_factor() {
    let (rm, t, width) = (0.1, 0.004, 0.012);
    let mesh = annulus(rm - t / 2.0, rm + t / 2.0, width, [2, 96, 2]);
    let d = elasticity_3d(&STEEL);
    let a = assemble_continuum(&mesh, &SolidHex8 { d }, STEEL.density, false).unwrap();
    let pat = &a.assembler.pattern;
    let n = mesh.n_dofs();
    let mdot = |x: &[f64], y: &[f64]| {
        let mut my = vec![0.0; n];
        softway::linalg::spmv_into(pat, &a.m, y, &mut my);
        x.iter().zip(&my).map(|(p, q)| p * q).sum::<f64>()
    };
    let kdot = |x: &[f64], y: &[f64]| {
        let mut ky = vec![0.0; n];
        softway::linalg::spmv_into(pat, &a.k, y, &mut ky);
        x.iter().zip(&ky).map(|(p, q)| p * q).sum::<f64>()
    };
    // The shift: 0.8 of the thin ring's omega_2^2 = (E I / rho A R^4) n^2 (n^2 - 1)^2 /
    // (n^2 + 1) (Love's inextensional ring), between the rigid modes and the n = 2 pair.
    let ei_rho_a = STEEL.young * t * t / 12.0 / STEEL.density;
    let shift = 0.8 * ei_rho_a / rm.powi(4) * 4.0 * 9.0 / 5.0;
    let factor_at = |shift: f64| {
        let mut shifted = a.k.clone();
        for (x, m) in shifted.iter_mut().zip(&a.m) {
            *x -= shift * m;
        }
        softway::linalg::Factor::auto(pat, &shifted).unwrap()
    };
    let mut factor = factor_at(shift);
    let mut pair: [Vec<f64>; 2] = std::array::from_fn(|q| {
        (0..mesh.n_nodes())
            .flat_map(|i| {
                let p = mesh.point(i);
                let th = p[1].atan2(p[0]);
                let vr = if q == 0 {
                    (2.0 * th).cos()
                } else {
                    (2.0 * th).sin()
                };
                [vr * th.cos(), vr * th.sin(), 0.0]
            })
            .collect()
    });
    for it in 0..40 {
        if it == 5 {
            // Closer to the pair than to the rigid modes: 0.9 of its Rayleigh quotient.
            factor = factor_at(0.9 * kdot(&pair[0], &pair[0]) / mdot(&pair[0], &pair[0]));
        }
        for x in pair.iter_mut() {
            let mut y = vec![0.0; n];
            softway::linalg::spmv_into(pat, &a.m, x, &mut y);
            factor.solve_in_place(&mut y);
            *x = y;
        }
        // M-orthonormalise (Gram-Schmidt).
        let s1 = mdot(&pair[0], &pair[0]).sqrt();
        pair[0].iter_mut().for_each(|x| *x /= s1);
        let c12 = mdot(&pair[0], &pair[1]);
        let p0 = pair[0].clone();
        pair[1].iter_mut().zip(&p0).for_each(|(x, y)| *x -= c12 * y);
        let s2 = mdot(&pair[1], &pair[1]).sqrt();
        pair[1].iter_mut().for_each(|x| *x /= s2);
    }
    let w2 = [kdot(&pair[0], &pair[0]), kdot(&pair[1], &pair[1])];
    assert!((w2[0] / w2[1] - 1.0).abs() < 1e-6, "not a pair: {w2:?}");
    let axial: f64 = pair[0]
        .iter()
        .skip(2)
        .step_by(3)
        .map(|x| x * x)
        .sum::<f64>()
        / pair[0].iter().map(|x| x * x).sum::<f64>();
    assert!(axial < 1e-6, "the pair is not in-plane: {axial}");
    let omega = 10.0;
    let spin = Spin::new([0.0; 3], [0.0, 0.0, 1.0], omega).unwrap();
    let mut g = a.assembler.zeros();
    frame3d::add_coriolis(&a.assembler, &a.m, &spin, &mut g);
    let mut gp = vec![0.0; n];
    softway::linalg::spmv_into(pat, &g, &pair[1], &mut gp);
    let split = pair[0]
        .iter()
        .zip(&gp)
        .map(|(x, y)| x * y)
        .sum::<f64>()
        .abs();
    let bryan = 4.0 * 2.0 * omega / 5.0;
    println!(
        "ring n = 2 pair at {:.2} Hz (thin ring {:.2} Hz): split {split:.5} rad/s vs Bryan's \
         {bryan:.5} ({:+.3e})",
        w2[0].sqrt() / (2.0 * PI),
        (shift / 0.8).sqrt() / (2.0 * PI),
        split / bryan - 1.0
    );
    assert!((split / bryan - 1.0).abs() < 0.01, "{split} vs {bryan}");
}

/// Centrifugal stiffening: a uniform cantilever blade clamped on the axle (zero hub radius)
/// and spinning about `z`. Its first flapwise (out of the plane of rotation) frequency rises
/// as `omega^2 = omega_0^2 + K1 Omega^2` with Southwell's coefficient `K1 = 1.1933` (Wright,
/// Smith, Thresher and Wang 1982, J. Appl. Mech. 49, first mode at zero hub radius;
/// `validation/southwell.py` recomputes it with an independent beam model: 1.19334), its
/// first lagwise (in the plane) frequency as `omega_0^2 + (K1 - 1) Omega^2` (the spin
/// softening takes `Omega^2` off). The slopes at `Omega -> 0` are the rest modes' Rayleigh
/// quotients of `K_eff - K = K_sigma + K_s` over `Omega^2 M`.
#[test]
fn a_spinning_blade_stiffens_by_southwells_coefficient() {
    let (len, wy, wz) = (1.0, 0.04, 0.03);
    let mut mesh = box_mesh(CellKind::Hex8, [len, wy, wz], [50, 2, 2]).unwrap();
    for p in mesh.coords.chunks_exact_mut(3) {
        p[1] -= wy / 2.0;
        p[2] -= wz / 2.0;
    }
    let root: Vec<usize> = mesh.node_sets["x0"]
        .iter()
        .flat_map(|&i| [3 * i, 3 * i + 1, 3 * i + 2])
        .collect();
    let omega = 50.0;
    let s = spinning_solid(
        "blade",
        mesh,
        &spec(STEEL, false),
        Motion::Fixed,
        &root,
        z_spin(omega),
    )
    .unwrap();
    let body = &s.solid.body;
    let model = &body.model;
    let modes = natural_modes_sparse_of(
        &Matrices {
            mesh: &body.mesh,
            assembler: &model.assembler,
            m: &model.m,
            k: &body.elastic,
            fixed_dofs: &root,
        },
        2,
    )
    .unwrap();
    let pat = &model.assembler.pattern;
    let n = body.mesh.n_dofs();
    let quad = |v: &[f64], a: &[f64]| {
        let mut y = vec![0.0; n];
        softway::linalg::spmv_into(pat, a, v, &mut y);
        v.iter().zip(&y).map(|(p, q)| p * q).sum::<f64>()
    };
    let delta: Vec<f64> = model
        .k
        .iter()
        .zip(&body.elastic)
        .map(|(a, b)| a - b)
        .collect();
    let mut found = Vec::new();
    for m in modes.iter().filter(|m| m.kind == "elastic") {
        let share = |c: usize| {
            m.shape
                .iter()
                .skip(c)
                .step_by(3)
                .map(|x| x * x)
                .sum::<f64>()
        };
        let flap = share(2) > share(1);
        let slope = quad(&m.shape, &delta) / (omega * omega * quad(&m.shape, &model.m));
        let exact = if flap { 1.1933 } else { 0.1933 };
        println!(
            "blade {} mode at {:.2} Hz: d(omega^2)/d(Omega^2) = {slope:.4} vs {exact}",
            if flap { "flap" } else { "lag" },
            m.frequency_hz
        );
        found.push((flap, slope, exact));
    }
    assert_eq!(found.iter().map(|f| f.0).collect::<Vec<_>>(), [true, false]);
    for (_, slope, exact) in found {
        assert!((slope - exact).abs() < 0.01 * 1.1933, "{slope} vs {exact}");
    }
}
