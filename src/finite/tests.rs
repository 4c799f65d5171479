//! The finite-deformation cells against invariants and independent computations: a rigid
//! rotation by large angles strains nothing (the linear model does), the force is the
//! gradient of the energy (central differences), small strains agree with the linear model
//! to second order, and the linear part is the assembled `K u` of the linear elements.

use super::*;
use crate::element::{hex8, tet10, tet4, tri3};
use crate::mesh::generators::box_mesh;

const EL: Elastic = Elastic {
    young: 210e9,
    poisson: 0.3,
    density: 7850.0,
};
const LAWS: [Hyperelastic; 2] = [Hyperelastic::SaintVenantKirchhoff, Hyperelastic::NeoHookean];

/// A deterministic sequence in (-1, 1).
fn noise(n: usize, seed: u64) -> Vec<f64> {
    let mut x = seed.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1);
    (0..n)
        .map(|_| {
            x = x
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            ((x >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
        })
        .collect()
}

/// A 3 x 2 grid of squares (0.3 x 0.2 m), each cut into two triangles; the nodes'
/// coordinates.
fn plane_mesh() -> (Vec<[f64; 2]>, Vec<[usize; 3]>) {
    let (nx, ny) = (4, 3);
    let pts: Vec<[f64; 2]> = (0..ny)
        .flat_map(|j| (0..nx).map(move |i| [0.1 * i as f64, 0.1 * j as f64]))
        .collect();
    let mut tris = Vec::new();
    for j in 0..ny - 1 {
        for i in 0..nx - 1 {
            let a = j * nx + i;
            tris.push([a, a + 1, a + nx + 1]);
            tris.push([a, a + nx + 1, a + nx]);
        }
    }
    (pts, tris)
}

fn plane_body(law: Hyperelastic, plane: PlaneModel) -> (FiniteBody, Vec<[f64; 2]>, Vec<f64>) {
    let (pts, tris) = plane_mesh();
    let geo: Vec<_> = tris
        .iter()
        .map(|t| tri3::geometry(&t.map(|i| pts[i])).unwrap())
        .collect();
    // The assembled linear K (dense), an independent computation of K u.
    let n = 2 * pts.len();
    let mut k = vec![0.0; n * n];
    let d = plane.elasticity_matrix(&EL);
    for (t, g) in tris.iter().zip(&geo) {
        let mut ke = [[0.0; 6]; 6];
        tri3::stiffness_into(g, &d, 0.01, &mut ke);
        for r in 0..6 {
            for c in 0..6 {
                k[(2 * t[r / 2] + r % 2) * n + 2 * t[c / 2] + c % 2] += ke[r][c];
            }
        }
    }
    let body = FiniteBody::planar(law, &EL, plane, 0.01, &tris, &geo, n);
    (body, pts, k)
}

/// The unit cube cut into six tetrahedra around its diagonal 0-6, on a 2 x 1 x 1 row of
/// cubes (0.2 x 0.1 x 0.1 m).
fn solid_body(law: Hyperelastic) -> (FiniteBody, Vec<[f64; 3]>, Vec<f64>) {
    let (nx, ny, nz) = (3, 2, 2);
    let id = |i: usize, j: usize, l: usize| (l * ny + j) * nx + i;
    let mut pts = Vec::new();
    for l in 0..nz {
        for j in 0..ny {
            for i in 0..nx {
                pts.push([0.1 * i as f64, 0.1 * j as f64, 0.1 * l as f64]);
            }
        }
    }
    let mut tets = Vec::new();
    for i in 0..nx - 1 {
        let c = [
            id(i, 0, 0),
            id(i + 1, 0, 0),
            id(i + 1, 1, 0),
            id(i, 1, 0),
            id(i, 0, 1),
            id(i + 1, 0, 1),
            id(i + 1, 1, 1),
            id(i, 1, 1),
        ];
        for p in [[1, 2], [2, 3], [3, 7], [7, 4], [4, 5], [5, 1]] {
            let mut t = [c[0], c[p[0]], c[p[1]], c[6]];
            if tet4::geometry(&t.map(|q| pts[q])).is_err() {
                t.swap(1, 2);
            }
            tets.push(t);
        }
    }
    let geo: Vec<_> = tets
        .iter()
        .map(|t| tet4::geometry(&t.map(|q| pts[q])).unwrap())
        .collect();
    let n = 3 * pts.len();
    let mut k = vec![0.0; n * n];
    let d = tet4::elasticity_3d(&EL);
    for (t, g) in tets.iter().zip(&geo) {
        let mut ke = [[0.0; 12]; 12];
        tet4::stiffness_into(g, &d, &mut ke);
        for r in 0..12 {
            for c in 0..12 {
                k[(3 * t[r / 3] + r % 3) * n + 3 * t[c / 3] + c % 3] += ke[r][c];
            }
        }
    }
    (FiniteBody::solid(law, &EL, &tets, &geo, n), pts, k)
}

/// A 2 x 1 x 1 box (0.2 x 0.1 x 0.1 m) of `kind` cells through [`FiniteBody::of_mesh`], its
/// nodes moved by up to `jitter` (m) of noise (curving a ten-node tetrahedron's edges,
/// distorting a hexahedron), and its linear K assembled from the elements' own kernels.
fn mesh_body(
    law: Hyperelastic,
    kind: CellKind,
    jitter: f64,
) -> (FiniteBody, Vec<[f64; 3]>, Vec<f64>) {
    let mut mesh = box_mesh(kind, [0.2, 0.1, 0.1], [2, 1, 1]).unwrap();
    let shake = noise(mesh.coords.len(), 3);
    for (x, z) in mesh.coords.iter_mut().zip(shake) {
        *x += jitter * z;
    }
    let pts: Vec<[f64; 3]> = mesh.points().map(|p| [p[0], p[1], p[2]]).collect();
    let n = 3 * pts.len();
    let d = tet4::elasticity_3d(&EL);
    let mut k = vec![0.0; n * n];
    let nn = kind.nodes();
    let mut curved = false;
    for c in mesh.cells.connectivity().chunks_exact(nn) {
        let mut ke = vec![0.0; 9 * nn * nn];
        match kind {
            CellKind::Hex8 => {
                let g = hex8::geometry(&std::array::from_fn(|i| pts[c[i]])).unwrap();
                let mut m = [[0.0; 24]; 24];
                hex8::stiffness_into(&g, &d, &mut m);
                ke = m.iter().flatten().copied().collect();
            }
            CellKind::Tet10 => {
                let g = tet10::geometry(&std::array::from_fn(|i| pts[c[i]])).unwrap();
                curved |= g.curved;
                let mut m = [[0.0; 30]; 30];
                tet10::stiffness_into(&g, &d, &mut m);
                ke = m.iter().flatten().copied().collect();
            }
            _ => unreachable!(),
        }
        for r in 0..3 * nn {
            for q in 0..3 * nn {
                k[(3 * c[r / 3] + r % 3) * n + 3 * c[q / 3] + q % 3] += ke[r * 3 * nn + q];
            }
        }
    }
    assert_eq!(curved, jitter > 0.0 && kind == CellKind::Tet10);
    let body = FiniteBody::of_mesh(law, &EL, PlaneModel::Strain, 1.0, &mesh, n).unwrap();
    (body, pts, k)
}

fn matvec(k: &[f64], u: &[f64]) -> Vec<f64> {
    let n = u.len();
    (0..n)
        .map(|r| (0..n).map(|c| k[r * n + c] * u[c]).sum())
        .collect()
}

fn norm(x: &[f64]) -> f64 {
    x.iter().map(|v| v * v).sum::<f64>().sqrt()
}

/// A body of the tests: its name, the body, its nodes in 3D and its assembled linear K.
type Case = (String, FiniteBody, Vec<[f64; 3]>, Vec<f64>);

/// Every body of the tests.
fn bodies() -> Vec<Case> {
    let mut out = Vec::new();
    for law in LAWS {
        for plane in [PlaneModel::Stress, PlaneModel::Strain] {
            let (b, p, k) = plane_body(law, plane);
            let p3 = p.iter().map(|q| [q[0], q[1], 0.0]).collect();
            out.push((format!("tri3 {law:?} {plane:?}"), b, p3, k));
        }
        let (b, p, k) = solid_body(law);
        out.push((format!("tet4 {law:?}"), b, p, k));
        for (kind, jitter) in [
            (CellKind::Hex8, 0.0),
            (CellKind::Hex8, 0.01),
            (CellKind::Tet10, 0.0),
            (CellKind::Tet10, 0.005),
        ] {
            let (b, p, k) = mesh_body(law, kind, jitter);
            out.push((format!("{kind:?} {law:?} jitter {jitter}"), b, p, k));
        }
    }
    out
}

/// The rotation by `a` about the axis `n` (unit).
fn rotation(a: f64, n: [f64; 3]) -> M3 {
    let (s, c) = a.sin_cos();
    let mut r = [[0.0; 3]; 3];
    for (i, row) in r.iter_mut().enumerate() {
        for (j, v) in row.iter_mut().enumerate() {
            let cross = match (i, j) {
                (0, 1) => -n[2],
                (1, 0) => n[2],
                (0, 2) => n[1],
                (2, 0) => -n[1],
                (1, 2) => -n[0],
                (2, 1) => n[0],
                _ => 0.0,
            };
            *v = c * f64::from(u8::from(i == j)) + s * cross + (1.0 - c) * n[i] * n[j];
        }
    }
    r
}

fn rigid(pts: &[[f64; 3]], dim: usize, r: &M3, shift: [f64; 3]) -> Vec<f64> {
    let mut u = Vec::new();
    for p in pts {
        for i in 0..dim {
            u.push((0..3).map(|j| r[i][j] * p[j]).sum::<f64>() - p[i] + shift[i]);
        }
    }
    u
}

#[test]
fn rigid_rotation_by_large_angles_strains_nothing_the_linear_model_does() {
    let tau = std::f64::consts::TAU;
    for (name, body, pts, k) in bodies() {
        let dim = if name.starts_with("tri3") { 2 } else { 3 };
        let axis = if dim == 2 {
            [0.0, 0.0, 1.0]
        } else {
            let a = [1.0, 2.0, 2.0f64];
            a.map(|v| v / 3.0)
        };
        for angle in [0.3, 1.0, 2.0, 3.0, 3.0 * tau + 1.0, 5.0 * tau + 2.5] {
            let u = rigid(&pts, dim, &rotation(angle, axis), [0.05, -0.02, 0.01]);
            let mut f = vec![0.0; u.len()];
            body.internal_force_into(&u, &mut f);
            let f_lin = matvec(&k, &u);
            let (w, w_lin) = body.energies(&u);
            let (e, e_lin) = body.max_strains(&u);
            // Round-off: the stresses are E times a strain of order 1e-16.
            assert!(
                norm(&f) <= 1e-12 * norm(&f_lin),
                "{name} {angle}: |f| {:e} vs |Ku| {:e}",
                norm(&f),
                norm(&f_lin)
            );
            assert!(
                w.abs() <= 1e-12 * w_lin,
                "{name} {angle}: W {w:e} vs {w_lin:e}"
            );
            assert!(e < 1e-14, "{name} {angle}: Green strain {e:e}");
            // The linear strain of the rotation is 1 - cos(angle) on the plane of turning.
            // (sym(R - I) = (1 - cos) (n n^T - I), of norm sqrt(2) (1 - cos), in 2D and 3D).
            let expected = (1.0 - angle.cos()) * 2f64.sqrt();
            assert!(
                (e_lin - expected).abs() < 1e-9,
                "{name} {angle}: linear strain {e_lin} vs {expected}"
            );
        }
    }
}

#[test]
fn the_internal_force_is_the_gradient_of_the_energy() {
    for (name, body, pts, _) in bodies() {
        let n = body.dofs;
        // A large displacement: 10 % of the size, a rotation of 1 rad on top.
        let dim = n / pts.len();
        let mut u = rigid(&pts, dim, &rotation(1.0, [0.0, 0.0, 1.0]), [0.0; 3]);
        for (ui, z) in u.iter_mut().zip(noise(n, 7)) {
            *ui += 0.01 * z;
        }
        let mut f = vec![0.0; n];
        body.internal_force_into(&u, &mut f);
        for seed in 1..4 {
            let du = noise(n, seed);
            let h = 1e-6;
            let plus: Vec<f64> = u.iter().zip(&du).map(|(a, b)| a + h * b).collect();
            let minus: Vec<f64> = u.iter().zip(&du).map(|(a, b)| a - h * b).collect();
            let fd = (body.energies(&plus).0 - body.energies(&minus).0) / (2.0 * h);
            let an: f64 = f.iter().zip(&du).map(|(a, b)| a * b).sum();
            assert!(
                (fd - an).abs() <= 1e-6 * an.abs(),
                "{name}: dW {fd:e} vs f.du {an:e}"
            );
        }
    }
}

#[test]
fn small_strains_agree_with_the_linear_model_to_second_order_and_the_contract_adds_up() {
    for (name, body, _, k) in bodies() {
        let n = body.dofs;
        let u0: Vec<f64> = noise(n, 11).iter().map(|v| 3e-4 * v).collect();
        let (mut errs, mut corrs) = (Vec::new(), Vec::new());
        for s in [1.0, 0.5, 0.25] {
            let u: Vec<f64> = u0.iter().map(|v| s * v).collect();
            let mut f = vec![0.0; n];
            body.internal_force_into(&u, &mut f);
            let ku = matvec(&k, &u);
            let d: Vec<f64> = f.iter().zip(&ku).map(|(a, b)| a - b).collect();
            errs.push(norm(&d) / norm(&ku));
            // The contract: f_int + f_nl = K u, the state is f_nl.
            let m = body.state_len();
            let (s0, mut s1) = (vec![0.0; m], vec![0.0; m]);
            let (mut f_nl, mut f_int) = (vec![0.0; n], vec![0.0; n]);
            body.evaluate(&s0, &u, &mut s1, &mut f_nl, &mut f_int);
            for i in 0..n {
                assert!(
                    (f_int[i] + f_nl[i] - ku[i]).abs() <= 1e-9 * norm(&ku),
                    "{name}: K u"
                );
            }
            // The state carries the last two pseudo-loads; the prediction extrapolates.
            let half: Vec<f64> = u.iter().map(|v| 0.5 * v).collect();
            let (mut s2, mut f_half, mut f_i2) = (vec![0.0; m], vec![0.0; n], vec![0.0; n]);
            body.evaluate(&s0, &half, &mut s2, &mut f_half, &mut f_i2);
            let mut s3 = vec![0.0; m];
            body.evaluate(&s2, &u, &mut s3, &mut f_i2, &mut f_int);
            let mut pl = vec![0.0; n];
            body.pseudo_load(&s3, &mut pl);
            for i in 0..n {
                assert_eq!(pl[i], 2.0 * f_nl[i] - f_half[i], "{name}: prediction");
            }
            // Energy: W - u^T K u / 2 is third order.
            let corr = body.energy_correction(&s1, &u);
            let e_lin = 0.5 * u.iter().zip(&ku).map(|(a, b)| a * b).sum::<f64>();
            corrs.push(corr / e_lin);
        }
        // The relative difference is first order in the displacement (the force's is second).
        for w in errs.windows(2) {
            let ratio = w[0] / w[1];
            assert!(
                (ratio - 2.0).abs() < 0.05,
                "{name}: ratio {ratio} ({errs:?})"
            );
        }
        assert!(errs[0] < 3e-2, "{name}: {errs:?}");
        // Energy: W - u^T K u / 2 is third order, its relative size first order.
        for w in corrs.windows(2) {
            let ratio = w[0] / w[1];
            assert!(
                (ratio - 2.0).abs() < 0.1,
                "{name}: energy ratio {ratio} ({corrs:?})"
            );
        }
        assert!(corrs[0].abs() < 3e-2, "{name}: {corrs:?}");
    }
}

#[test]
fn plane_stress_leaves_no_out_of_plane_stress() {
    let (lam, mu) = lame(&EL);
    for law in LAWS {
        let mut f = [[1.2, 0.3, 0.0], [-0.1, 0.9, 0.0], [0.0, 0.0, 1.0]];
        f[2][2] = plane_stress_stretch(law, lam, mu, &f);
        let (_, p) = piola_3d(law, lam, mu, &f);
        assert!(p[2][2].abs() < 1e-12 * mu, "{law:?}: P33 {:e}", p[2][2]);
        assert!(
            f[2][2] < 1.0,
            "{law:?}: the plate thins under in-plane stretch"
        );
    }
}

#[test]
fn the_steps_evaluation_gives_the_cells_forces_at_large_strain() {
    // The step's evaluation (a fast path for Saint Venant-Kirchhoff triangles) against the
    // general cell force, at a displacement of large rotation and strain.
    for (name, body, pts, _) in bodies() {
        let n = body.dofs;
        let dim = n / pts.len();
        let r = rotation(1.3, [0.0, 0.0, 1.0]);
        let mut u = rigid(&pts, dim, &r, [0.1, -0.2, 0.0]);
        u.iter_mut()
            .zip(noise(n, 5))
            .for_each(|(v, e)| *v += 0.01 * e);
        let m = body.state_len();
        let (s0, mut s1) = (vec![0.0; m], vec![0.0; m]);
        let (mut f_nl, mut f_int) = (vec![0.0; n], vec![0.0; n]);
        body.evaluate(&s0, &u, &mut s1, &mut f_nl, &mut f_int);
        let (mut f, mut ku) = (vec![0.0; n], vec![0.0; n]);
        body.internal_force_into(&u, &mut f);
        body.linear_force_into(&u, &mut ku);
        let scale = norm(&f);
        assert!(scale > 0.0, "{name}");
        for i in 0..n {
            assert!(
                (f_int[i] - f[i]).abs() <= 1e-12 * scale,
                "{name}: f_int[{i}]"
            );
            assert!(
                (f_nl[i] - (ku[i] - f[i])).abs() <= 1e-12 * norm(&ku),
                "{name}: f_nl[{i}]"
            );
        }
    }
}

#[test]
fn the_tangent_is_the_derivative_of_the_force() {
    // The tangent against central differences of the force, at a displacement of large
    // rotation and strain; exact for Saint Venant-Kirchhoff, to the differences' error for
    // the neo-Hookean cells (themselves differenced).
    for (name, body, pts, _) in bodies() {
        let n = body.dofs;
        let dim = n / pts.len();
        let r = rotation(0.9, [0.0, 0.0, 1.0]);
        let mut u = rigid(&pts, dim, &r, [0.0; 3]);
        u.iter_mut()
            .zip(noise(n, 9))
            .for_each(|(v, e)| *v += 0.005 * e);
        let mut kt = vec![0.0; n * n];
        body.tangent_for_each(&u, |i, j, v| kt[i * n + j] += v);
        let dir = noise(n, 21);
        let e = 1e-7;
        let (mut fp, mut fm) = (vec![0.0; n], vec![0.0; n]);
        let up: Vec<f64> = u.iter().zip(&dir).map(|(a, d)| a + e * d).collect();
        let um: Vec<f64> = u.iter().zip(&dir).map(|(a, d)| a - e * d).collect();
        body.internal_force_into(&up, &mut fp);
        body.internal_force_into(&um, &mut fm);
        let fd: Vec<f64> = fp
            .iter()
            .zip(&fm)
            .map(|(a, b)| (a - b) / (2.0 * e))
            .collect();
        let kd = matvec(&kt, &dir);
        let err: Vec<f64> = kd.iter().zip(&fd).map(|(a, b)| a - b).collect();
        let rel = norm(&err) / norm(&fd);
        assert!(rel < 1e-6, "{name}: {rel:e}");
        // Symmetric (a hyperelastic tangent).
        let mut asym = 0.0f64;
        for i in 0..n {
            for j in 0..n {
                asym = asym.max((kt[i * n + j] - kt[j * n + i]).abs());
            }
        }
        let big = kt.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        assert!(asym <= 1e-6 * big, "{name}: asymmetry {asym:e} of {big:e}");
    }
}
