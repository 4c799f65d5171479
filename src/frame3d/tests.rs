use super::*;
use crate::element::continuum::assemble_continuum;
use crate::element::solid::elasticity_3d;
use crate::material::Elastic;
use crate::mesh::generators::box_mesh;
use crate::mesh::CellKind;

const STEEL: Elastic = Elastic {
    young: 2.1e11,
    poisson: 0.3,
    density: 7850.0,
};

#[test]
fn bad_spins_are_refused_by_name() {
    let e = Spin::new([0.0; 3], [0.0; 3], 1.0).unwrap_err();
    assert!(e.to_string().contains("finite non-zero"), "{e}");
    let e = Spin::new([0.0; 3], [0.0, 0.0, 1.0], f64::NAN).unwrap_err();
    assert!(e.to_string().contains("rate"), "{e}");
    let e = Spin::new([f64::INFINITY, 0.0, 0.0], [0.0, 0.0, 1.0], 1.0).unwrap_err();
    assert!(e.to_string().contains("point"), "{e}");
    // The axis is normalised: Omega = rate e.
    let s = Spin::new([0.0; 3], [0.0, 3.0, 4.0], 10.0).unwrap();
    assert_eq!(s.omega(), [0.0, 6.0, 8.0]);
}

/// `[Omega]_x w = Omega x w` and `Q = [Omega]_x^T [Omega]_x`, the centrifugal acceleration
/// `-Omega x (Omega x r)` (vector identities, computed here independently).
#[test]
fn the_spin_matrices_are_the_cross_products() {
    let s = Spin::new([0.1, -0.2, 0.3], [1.0, 2.0, -2.0], 7.0).unwrap();
    let w = s.omega();
    let cross = |u: [f64; 3], v: [f64; 3]| {
        [
            u[1] * v[2] - u[2] * v[1],
            u[2] * v[0] - u[0] * v[2],
            u[0] * v[1] - u[1] * v[0],
        ]
    };
    let v = [0.3, -1.1, 0.7];
    let c = s.cross_matrix();
    let cv: [f64; 3] = std::array::from_fn(|a| (0..3).map(|b| c[a][b] * v[b]).sum());
    let ex = cross(w, v);
    for a in 0..3 {
        assert!((cv[a] - ex[a]).abs() < 1e-12);
    }
    let x = [1.0, 0.5, -0.25];
    let r = [x[0] - 0.1, x[1] + 0.2, x[2] - 0.3];
    let acc = s.centrifugal_acceleration(x);
    let ex = cross(w, cross(w, r)).map(|a| -a);
    let q = s.centrifugal_matrix();
    for a in 0..3 {
        assert!((acc[a] - ex[a]).abs() < 1e-10);
        for b in 0..3 {
            let ctc: f64 = (0..3).map(|k| c[k][a] * c[k][b]).sum();
            assert!((q[a][b] - ctc).abs() < 1e-10);
        }
    }
}

/// On every solid element, consistent and lumped: `M = M_s (x) I_3`; `G` skew, and its
/// force on a uniform velocity `v` is `2 m Omega x v`; `K_s` symmetric, its force on a
/// uniform displacement `u` is `-m Q u` (Newton's rigid-body values, `m` the volume times
/// the density).
#[test]
fn coriolis_is_skew_and_softening_symmetric_with_the_rigid_body_resultants() {
    let spin = Spin::new([0.2, 0.1, 0.0], [0.3, -0.4, 1.0], 250.0).unwrap();
    let w = spin.omega();
    let q = spin.centrifugal_matrix();
    for kind in [CellKind::Tet4, CellKind::Tet10, CellKind::Hex8] {
        let mesh = box_mesh(kind, [0.3, 0.2, 0.1], [3, 2, 2]).unwrap();
        let mass = STEEL.density * 0.3 * 0.2 * 0.1;
        for lumped in [false, true] {
            let d = elasticity_3d(&STEEL);
            let a = match kind {
                CellKind::Tet4 => {
                    let el = SolidTet4 { d };
                    let a = assemble_continuum(&mesh, &el, STEEL.density, lumped).unwrap();
                    (a.assembler, a.m)
                }
                CellKind::Tet10 => {
                    let el = SolidTet10 { d };
                    let a = assemble_continuum(&mesh, &el, STEEL.density, lumped).unwrap();
                    (a.assembler, a.m)
                }
                _ => {
                    let el = SolidHex8 { d };
                    let a = assemble_continuum(&mesh, &el, STEEL.density, lumped).unwrap();
                    (a.assembler, a.m)
                }
            };
            let (asm, m) = a;
            scalar_mass(&asm, &m).unwrap();
            let mut g = asm.zeros();
            add_coriolis(&asm, &m, &spin, &mut g);
            let mut ks = asm.zeros();
            add_spin_softening(&asm, &m, &spin, &mut ks);
            let n = asm.pattern.nrows();
            let (cp, ri) = (asm.pattern.col_ptr(), asm.pattern.row_idx());
            let scale = g.iter().fold(0.0f64, |x, y| x.max(y.abs()));
            for j in 0..n {
                for p in cp[j]..cp[j + 1] {
                    let i = ri[p];
                    let t = asm.slot(j, i).unwrap();
                    assert!((g[p] + g[t]).abs() <= 1e-14 * scale, "{kind:?} G skew");
                    assert!((ks[p] - ks[t]).abs() <= 1e-14 * scale * 250.0, "K_s sym");
                }
            }
            let v = [0.7, -0.2, 0.4];
            let uni: Vec<f64> = (0..n).map(|i| v[i % 3]).collect();
            let mut f = vec![0.0; n];
            crate::linalg::spmv_into(&asm.pattern, &g, &uni, &mut f);
            let mut fs = vec![0.0; n];
            crate::linalg::spmv_into(&asm.pattern, &ks, &uni, &mut fs);
            let wxv = [
                w[1] * v[2] - w[2] * v[1],
                w[2] * v[0] - w[0] * v[2],
                w[0] * v[1] - w[1] * v[0],
            ];
            for a in 0..3 {
                let total: f64 = f.iter().skip(a).step_by(3).sum();
                let exact = 2.0 * mass * wxv[a];
                assert!(
                    (total - exact).abs() < 1e-10 * mass * 250.0,
                    "{total} {exact}"
                );
                let total: f64 = fs.iter().skip(a).step_by(3).sum();
                let exact: f64 = -mass * (0..3).map(|b| q[a][b] * v[b]).sum::<f64>();
                assert!(
                    (total - exact).abs() < 1e-10 * mass * 62500.0,
                    "{total} {exact}"
                );
            }
        }
    }
}

/// A mass matrix that couples components is refused.
#[test]
fn a_non_scalar_mass_is_refused() {
    let mesh = box_mesh(CellKind::Hex8, [1.0; 3], [1, 1, 1]).unwrap();
    let el = SolidHex8 {
        d: elasticity_3d(&STEEL),
    };
    let a = assemble_continuum(&mesh, &el, STEEL.density, false).unwrap();
    let mut m = a.m.clone();
    let s = a.assembler.slot(0, 1).unwrap();
    m[s] = 1.0;
    let e = scalar_mass(&a.assembler, &m).unwrap_err();
    assert!(e.to_string().contains("M = M_s (x) I_3"), "{e}");
}
