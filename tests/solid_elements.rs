//! The 3D solid elements (`tet4`, `tet10`, `hex8`) on small models, against numbers from
//! outside the code: rigid-body modes, the patch test (MacNeal and Harder's distorted
//! seven-hexahedron patch, distorted tetrahedral patches), a cantilever against
//! Timoshenko's beam theory and the axial frequency of a free-free bar against
//! `f = c / (2 L)`.
//!
//! Run with `cargo test --release --test solid_elements -- --nocapture` to see the ladders.

use faer::linalg::solvers::Solve;
use faer::sparse::{SparseColMat, Triplet};
use faer::{Mat, Side};
use softway::element::solid::{elasticity_3d, stress_of_strain};
use softway::element::{hex8, tet10, tet4};
use softway::material::Elastic;
use softway::mesh::generators::box3d::{box_hex8, box_tet10, box_tet4, BoxMesh};

const STEEL: Elastic = Elastic {
    young: 210e9,
    poisson: 0.3,
    density: 7850.0,
};

/// A mesh of one element kind, flattened for the generic loops below.
struct Msh {
    coords: Vec<[f64; 3]>,
    cells: Vec<Vec<usize>>,
}

impl<const N: usize> From<BoxMesh<N>> for Msh {
    fn from(b: BoxMesh<N>) -> Self {
        Msh {
            coords: (0..b.n_nodes()).map(|i| b.point(i)).collect(),
            cells: b.cells.iter().map(|c| c.to_vec()).collect(),
        }
    }
}

/// Stiffness and mass (row-major, `3 n` square) of the element with nodes `p` (4: tet4,
/// 10: tet10, 8: hex8).
fn element(p: &[[f64; 3]], d: &[[f64; 6]; 6], rho: f64, lumped: bool) -> (Vec<f64>, Vec<f64>) {
    fn flat<const M: usize>(a: &[[f64; M]; M]) -> Vec<f64> {
        a.iter().flatten().copied().collect()
    }
    match p.len() {
        4 => {
            let g = tet4::geometry(p.try_into().unwrap()).unwrap();
            let (mut k, mut m) = ([[0.0; 12]; 12], [[0.0; 12]; 12]);
            tet4::stiffness_into(&g, d, &mut k);
            tet4::mass_into(&g, rho, lumped, &mut m);
            (flat(&k), flat(&m))
        }
        10 => {
            let g = tet10::geometry(p.try_into().unwrap()).unwrap();
            let (mut k, mut m) = (Box::new([[0.0; 30]; 30]), Box::new([[0.0; 30]; 30]));
            tet10::stiffness_into(&g, d, &mut k);
            tet10::mass_into(&g, rho, lumped, &mut m);
            (flat(&k), flat(&m))
        }
        8 => {
            let g = hex8::geometry(p.try_into().unwrap()).unwrap();
            let (mut k, mut m) = ([[0.0; 24]; 24], [[0.0; 24]; 24]);
            hex8::stiffness_into(&g, d, &mut k);
            hex8::mass_into(&g, rho, lumped, &mut m);
            (flat(&k), flat(&m))
        }
        n => panic!("no element with {n} nodes"),
    }
}

/// The strain at the reference point `xi` (ignored by tet4) of the cell with nodes `p` and
/// displacements `u`.
fn strain(p: &[[f64; 3]], u: &[f64], xi: [f64; 3]) -> [f64; 6] {
    match p.len() {
        4 => tet4::strain(
            &tet4::geometry(p.try_into().unwrap()).unwrap(),
            u.try_into().unwrap(),
        ),
        10 => tet10::strain_at(
            &tet10::geometry(p.try_into().unwrap()).unwrap(),
            xi,
            u.try_into().unwrap(),
        ),
        8 => hex8::strain_at(
            &hex8::geometry(p.try_into().unwrap()).unwrap(),
            xi,
            u.try_into().unwrap(),
        ),
        n => panic!("no element with {n} nodes"),
    }
}

/// Dense global stiffness and mass.
fn assemble_dense(msh: &Msh, d: &[[f64; 6]; 6], rho: f64, lumped: bool) -> (Mat<f64>, Mat<f64>) {
    let n = 3 * msh.coords.len();
    let mut k = Mat::<f64>::zeros(n, n);
    let mut m = Mat::<f64>::zeros(n, n);
    for c in &msh.cells {
        let p: Vec<[f64; 3]> = c.iter().map(|&i| msh.coords[i]).collect();
        let (ke, me) = element(&p, d, rho, lumped);
        let nd = 3 * c.len();
        for r in 0..nd {
            for s in 0..nd {
                let (gr, gs) = (3 * c[r / 3] + r % 3, 3 * c[s / 3] + s % 3);
                k[(gr, gs)] += ke[r * nd + s];
                m[(gr, gs)] += me[r * nd + s];
            }
        }
    }
    (k, m)
}

/// The six rigid-body modes (three translations, three rotations) at the points `x`.
fn rigid_modes(x: &[[f64; 3]]) -> Vec<Vec<f64>> {
    let mut modes = Vec::new();
    for a in 0..3 {
        modes.push(
            x.iter()
                .flat_map(|_| [0, 1, 2].map(|b| f64::from(u8::from(a == b))))
                .collect(),
        );
    }
    for a in 0..3 {
        // omega = e_a: u = omega x X.
        modes.push(
            x.iter()
                .flat_map(|p| {
                    let w = [0, 1, 2].map(|b| f64::from(u8::from(a == b)));
                    [
                        w[1] * p[2] - w[2] * p[1],
                        w[2] * p[0] - w[0] * p[2],
                        w[0] * p[1] - w[1] * p[0],
                    ]
                })
                .collect(),
        );
    }
    modes
}

/// A distorted tetrahedron, a straight and a curved ten-node one on it, a distorted hexahedron.
fn distorted_cells() -> Vec<(&'static str, Vec<[f64; 3]>)> {
    let t = [
        [0.1, -0.2, 0.05],
        [1.3, 0.15, -0.1],
        [0.4, 0.95, 0.2],
        [0.35, 0.3, 1.1],
    ];
    let straight = tet10::straight(&t);
    let mut curved = straight;
    curved[4][2] += 0.08;
    curved[5][0] -= 0.06;
    curved[8][1] += 0.05;
    let mut h = hex8::NODES.map(|p| [0.5 * (1.0 + p[0]), 0.5 * (1.0 + p[1]), 0.5 * (1.0 + p[2])]);
    h[6] = [1.15, 0.9, 1.2];
    h[4][0] = -0.12;
    h[1] = [1.05, 0.1, -0.1];
    h[3][2] = 0.07;
    vec![
        ("tet4", t.to_vec()),
        ("tet10 straight", straight.to_vec()),
        ("tet10 curved", curved.to_vec()),
        ("hex8", h.to_vec()),
    ]
}

fn volume(p: &[[f64; 3]]) -> f64 {
    match p.len() {
        4 => tet4::geometry(p.try_into().unwrap()).unwrap().volume,
        10 => tet10::geometry(p.try_into().unwrap()).unwrap().volume,
        _ => hex8::geometry(p.try_into().unwrap()).unwrap().volume,
    }
}

#[test]
fn distorted_elements_have_six_rigid_modes_and_a_consistent_mass() {
    let d = elasticity_3d(&STEEL);
    for (name, p) in distorted_cells() {
        let msh = Msh {
            coords: p.clone(),
            cells: vec![(0..p.len()).collect()],
        };
        let (k, m) = assemble_dense(&msh, &d, STEEL.density, false);
        let n = k.nrows();
        let kmax = (0..n).map(|i| k[(i, i)]).fold(0.0, f64::max);
        // Symmetric.
        for r in 0..n {
            for c in 0..n {
                assert!((k[(r, c)] - k[(c, r)]).abs() < 1e-12 * kmax, "{name}");
            }
        }
        // The rigid modes carry no force...
        for r in rigid_modes(&p) {
            for i in 0..n {
                let f: f64 = (0..n).map(|j| k[(i, j)] * r[j]).sum();
                assert!(f.abs() < 1e-12 * kmax * 2.0, "{name}: {f}");
            }
        }
        // ... and they are the only ones (faer's self-adjoint eigensolver, K scaled to 1).
        let ev = (k.as_ref() * (1.0 / kmax))
            .self_adjoint_eigenvalues(Side::Lower)
            .unwrap();
        assert!(
            ev[..6].iter().all(|e| e.abs() < 1e-12),
            "{name}: {:?}",
            &ev[..7]
        );
        assert!(ev[6] > 1e-4, "{name}: seventh eigenvalue {}", ev[6]);
        eprintln!(
            "{name}: K/kmax eigenvalues 6: {:.1e}, 7: {:.3e}",
            ev[5].abs(),
            ev[6]
        );
        // Mass: total 3 rho V, rho V in each direction, positive definite.
        let rv = STEEL.density * volume(&p);
        for lumped in [false, true] {
            let (_, m) = assemble_dense(&msh, &d, STEEL.density, lumped);
            let total: f64 = (0..n)
                .flat_map(|i| (0..n).map(move |j| (i, j)))
                .map(|(i, j)| m[(i, j)])
                .sum();
            assert!(
                (total - 3.0 * rv).abs() < 1e-12 * rv,
                "{name} lumped={lumped}"
            );
            for a in 0..3 {
                let dir: f64 = (0..n / 3)
                    .flat_map(|i| (0..n / 3).map(move |j| (i, j)))
                    .map(|(i, j)| m[(3 * i + a, 3 * j + a)])
                    .sum();
                assert!((dir - rv).abs() < 1e-12 * rv, "{name} lumped={lumped}");
            }
            let me = (m.as_ref() * (1.0 / rv))
                .self_adjoint_eigenvalues(Side::Lower)
                .unwrap();
            assert!(me[0] > 0.0, "{name} lumped={lumped}: {}", me[0]);
        }
        drop(m);
    }
}

/// The patch test on `msh`: the linear field `u = a + G x` prescribed at the nodes on the
/// boundary `on_boundary` is reproduced at the interior nodes, the interior residual of the
/// exact field is zero, and every element has the strain `sym G` at the points `xis`.
fn patch_test(name: &str, msh: &Msh, on_boundary: impl Fn([f64; 3]) -> bool, xis: &[[f64; 3]]) {
    let d = elasticity_3d(&STEEL);
    let a = [1e-3, -2e-3, 5e-4];
    let gm = [
        [2e-4, -3e-4, 1e-4],
        [5e-4, 1e-4, -2e-4],
        [-1e-4, 3e-4, 4e-4],
    ];
    let field =
        |x: [f64; 3]| [0, 1, 2].map(|r| a[r] + (0..3).map(|c| gm[r][c] * x[c]).sum::<f64>());
    let exact: Vec<f64> = msh.coords.iter().flat_map(|&x| field(x)).collect();
    let (k, _) = assemble_dense(msh, &d, 1.0, false);
    let n = k.nrows();
    let kmax = (0..n).map(|i| k[(i, i)]).fold(0.0, f64::max);
    let interior: Vec<usize> = (0..msh.coords.len())
        .filter(|&i| !on_boundary(msh.coords[i]))
        .flat_map(|i| [3 * i, 3 * i + 1, 3 * i + 2])
        .collect();
    assert!(!interior.is_empty());
    let umax = exact.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    // Zero residual at the interior nodes.
    let mut worst_r: f64 = 0.0;
    for &i in &interior {
        let r: f64 = (0..n).map(|j| k[(i, j)] * exact[j]).sum();
        worst_r = worst_r.max(r.abs() / (kmax * umax));
    }
    assert!(worst_r < 1e-13, "{name}: interior residual {worst_r:e}");
    // Solve K_ii u_i = -K_ib u_b.
    let is_int = {
        let mut v = vec![false; n];
        interior.iter().for_each(|&i| v[i] = true);
        v
    };
    let ni = interior.len();
    let kii = Mat::<f64>::from_fn(ni, ni, |r, c| k[(interior[r], interior[c])]);
    let mut rhs = Mat::<f64>::from_fn(ni, 1, |r, _| {
        -(0..n)
            .filter(|&j| !is_int[j])
            .map(|j| k[(interior[r], j)] * exact[j])
            .sum::<f64>()
    });
    kii.llt(Side::Lower).unwrap().solve_in_place(rhs.as_mut());
    let mut u = exact.clone();
    let mut worst_u: f64 = 0.0;
    for (r, &i) in interior.iter().enumerate() {
        u[i] = rhs[(r, 0)];
        worst_u = worst_u.max((u[i] - exact[i]).abs() / umax);
    }
    assert!(
        worst_u < 1e-11,
        "{name}: interior displacement error {worst_u:e}"
    );
    // The constant strain and stress in every element.
    let eps = [
        gm[0][0],
        gm[1][1],
        gm[2][2],
        gm[1][2] + gm[2][1],
        gm[0][2] + gm[2][0],
        gm[0][1] + gm[1][0],
    ];
    let sig = stress_of_strain(&d, &eps);
    let smax = sig.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let mut worst_e: f64 = 0.0;
    for c in &msh.cells {
        let p: Vec<[f64; 3]> = c.iter().map(|&i| msh.coords[i]).collect();
        let ue: Vec<f64> = c
            .iter()
            .flat_map(|&i| [u[3 * i], u[3 * i + 1], u[3 * i + 2]])
            .collect();
        for &xi in xis {
            let e = strain(&p, &ue, xi);
            let s = stress_of_strain(&d, &e);
            for q in 0..6 {
                worst_e = worst_e.max((e[q] - eps[q]).abs() / 1e-3);
                assert!(
                    (s[q] - sig[q]).abs() < 1e-9 * smax,
                    "{name}: {s:?} vs {sig:?}"
                );
            }
        }
    }
    assert!(worst_e < 1e-10, "{name}: strain error {worst_e:e}");
    eprintln!(
        "{name}: {} cells, interior residual {worst_r:.1e}, displacement {worst_u:.1e}, strain {worst_e:.1e}",
        msh.cells.len()
    );
}

#[test]
fn macneal_harders_seven_hexahedra_pass_the_patch_test() {
    // MacNeal and Harder, "A proposed standard set of problems to test finite element
    // accuracy", Finite Elem. Anal. Des. 1 (1985): the unit cube with the eight interior
    // nodes below, one inner hexahedron and six joining it to the cube's faces.
    let outer = hex8::NODES.map(|p| [0.5 * (1.0 + p[0]), 0.5 * (1.0 + p[1]), 0.5 * (1.0 + p[2])]);
    let inner = [
        [0.249, 0.342, 0.192],
        [0.826, 0.288, 0.288],
        [0.850, 0.649, 0.263],
        [0.273, 0.750, 0.230],
        [0.320, 0.186, 0.643],
        [0.677, 0.305, 0.683],
        [0.788, 0.693, 0.644],
        [0.165, 0.745, 0.702],
    ];
    let coords: Vec<[f64; 3]> = outer.iter().chain(inner.iter()).copied().collect();
    // The cube's faces (outer nodes, hexahedron face order) and the matching inner face.
    let faces = [
        [0, 1, 2, 3],
        [4, 5, 6, 7],
        [0, 1, 5, 4],
        [3, 2, 6, 7],
        [0, 3, 7, 4],
        [1, 2, 6, 5],
    ];
    let mut cells = vec![(8..16).collect::<Vec<usize>>()];
    for f in faces {
        let o: Vec<usize> = f.to_vec();
        let i: Vec<usize> = f.iter().map(|&v| v + 8).collect();
        // Either order of the two faces: the one with a positive Jacobian (the other is
        // inverted).
        let a: Vec<usize> = o.iter().chain(&i).copied().collect();
        let b: Vec<usize> = i.iter().chain(&o).copied().collect();
        let pa: [[f64; 3]; 8] = std::array::from_fn(|k| coords[a[k]]);
        let pb: [[f64; 3]; 8] = std::array::from_fn(|k| coords[b[k]]);
        match (hex8::geometry(&pa), hex8::geometry(&pb)) {
            (Ok(_), Err(hex8::SolidError::Inverted { .. })) => cells.push(a),
            (Err(hex8::SolidError::Inverted { .. }), Ok(_)) => cells.push(b),
            other => panic!("face {f:?}: {other:?}"),
        }
    }
    let msh = Msh { coords, cells };
    let total: f64 = msh
        .cells
        .iter()
        .map(|c| volume(&c.iter().map(|&i| msh.coords[i]).collect::<Vec<_>>()))
        .sum();
    assert!(
        (total - 1.0).abs() < 1e-14,
        "the patch fills the cube: {total}"
    );
    let on_boundary = |x: [f64; 3]| x.iter().any(|&v| v == 0.0 || v == 1.0);
    let g = 0.577_350_269_189_625_8;
    patch_test(
        "hex8 MacNeal-Harder",
        &msh,
        on_boundary,
        &[[0.0; 3], [g, -g, g], [-0.9, 0.3, 0.7]],
    );
}

/// A deterministic offset in [-0.5, 0.5) per node and direction.
fn jitter(i: usize, q: usize) -> f64 {
    let h = (i as u64 * 2_654_435_761 + q as u64 * 40_503 + 12_345) % 1000;
    h as f64 / 1000.0 - 0.5
}

#[test]
fn distorted_tetrahedral_patches_pass_the_patch_test() {
    let size = [1.0, 0.8, 1.2];
    let on_boundary = |x: [f64; 3]| (0..3).any(|q| x[q] == 0.0 || x[q] == size[q]);
    // tet4: a 3 x 3 x 3 box, its eight interior grid nodes moved by up to 0.3 of a cell.
    let mut m4: Msh = box_tet4(size, [3, 3, 3]).unwrap().into();
    for (i, x) in m4.coords.iter_mut().enumerate() {
        if !on_boundary(*x) {
            for q in 0..3 {
                x[q] += 0.3 * jitter(i, q) * size[q] / 3.0;
            }
        }
    }
    patch_test("tet4", &m4, on_boundary, &[[0.25; 3]]);
    // tet10: a 2 x 2 x 2 box, the interior grid node moved, the mid-edge nodes at the new
    // midpoints (straight-sided) ...
    let mut m10: Msh = box_tet10(size, [2, 2, 2]).unwrap().into();
    let centre = m10
        .coords
        .iter()
        .position(|x| (0..3).all(|q| (x[q] - 0.5 * size[q]).abs() < 1e-12))
        .unwrap();
    m10.coords[centre] = [0.41, 0.47, 0.66];
    for c in m10.cells.clone() {
        for (e, [a, b]) in tet10::EDGES.iter().enumerate() {
            let (pa, pb) = (m10.coords[c[*a]], m10.coords[c[*b]]);
            m10.coords[c[4 + e]] = [0, 1, 2].map(|q| 0.5 * (pa[q] + pb[q]));
        }
    }
    let xis = [[0.25; 3], [0.1, 0.2, 0.6], [0.0, 0.0, 0.0]];
    patch_test("tet10 straight", &m10, on_boundary, &xis);
    // ... and curved: the interior mid-edge nodes moved off their edges too.
    let n_grid = 27;
    for i in n_grid..m10.coords.len() {
        if !on_boundary(m10.coords[i]) {
            for q in 0..3 {
                m10.coords[i][q] += 0.06 * jitter(i, q);
            }
        }
    }
    let curved = m10
        .cells
        .iter()
        .filter(|c| {
            let p: [[f64; 3]; 10] = std::array::from_fn(|k| m10.coords[c[k]]);
            tet10::geometry(&p).unwrap().curved
        })
        .count();
    assert!(curved > 24, "{curved} curved cells");
    patch_test("tet10 curved", &m10, on_boundary, &xis);
}

/// The displacement of the cantilever `[0, l] x [0, b] x [0, h]` clamped at `x = 0` under
/// the shear load `p` (in `z`) spread uniformly over the end `x = l`: the work-conjugate
/// tip deflection `f . u / p` (the mean deflection of the end section).
fn cantilever_deflection(msh: &Msh, size: [f64; 3], p: f64) -> f64 {
    let d = elasticity_3d(&STEEL);
    let nn = msh.coords.len();
    // Free dofs: every node off x = 0.
    let mut index = vec![usize::MAX; 3 * nn];
    let mut nf = 0;
    for (i, x) in msh.coords.iter().enumerate() {
        if x[0] != 0.0 {
            for q in 0..3 {
                index[3 * i + q] = nf;
                nf += 1;
            }
        }
    }
    // Consistent end load of the uniform traction t = p / (b h): per end facet, the
    // integral of each node's shape function over the facet.
    let traction = p / (size[1] * size[2]);
    let mut f = vec![0.0; 3 * nn];
    let at_end = |i: usize| msh.coords[i][0] == size[0];
    let tri_area = |a: [f64; 3], b: [f64; 3], c: [f64; 3]| {
        let (u, v) = (
            [0, 1, 2].map(|q| b[q] - a[q]),
            [0, 1, 2].map(|q| c[q] - a[q]),
        );
        let w = [
            u[1] * v[2] - u[2] * v[1],
            u[2] * v[0] - u[0] * v[2],
            u[0] * v[1] - u[1] * v[0],
        ];
        0.5 * (w[0] * w[0] + w[1] * w[1] + w[2] * w[2]).sqrt()
    };
    let mut triplets = Vec::new();
    for c in &msh.cells {
        match c.len() {
            8 => {
                // The face x = l of a box cell is the rectangle of nodes 1, 2, 6, 5.
                let face = [1, 2, 6, 5].map(|k| c[k]);
                if face.iter().all(|&i| at_end(i)) {
                    let (a, b) = (msh.coords[face[0]], msh.coords[face[2]]);
                    let area = (b[1] - a[1]).abs() * (b[2] - a[2]).abs();
                    face.iter()
                        .for_each(|&i| f[3 * i + 2] += traction * area / 4.0);
                }
            }
            _ => {
                for skip in 0..4 {
                    let corners: Vec<usize> = (0..4).filter(|&k| k != skip).collect();
                    if corners.iter().all(|&k| at_end(c[k])) {
                        let [a, b, cc] = [0, 1, 2].map(|k| msh.coords[c[corners[k]]]);
                        let area = tri_area(a, b, cc);
                        if c.len() == 4 {
                            // Linear triangle: a third at each corner.
                            corners
                                .iter()
                                .for_each(|&k| f[3 * c[k] + 2] += traction * area / 3.0);
                        } else {
                            // Quadratic triangle: nothing at the corners, a third at each
                            // mid-edge node of the face.
                            for (e, [ea, eb]) in tet10::EDGES.iter().enumerate() {
                                if *ea != skip && *eb != skip {
                                    f[3 * c[4 + e] + 2] += traction * area / 3.0;
                                }
                            }
                        }
                    }
                }
            }
        }
        let p: Vec<[f64; 3]> = c.iter().map(|&i| msh.coords[i]).collect();
        let (ke, _) = element(&p, &d, 1.0, true);
        let nd = 3 * c.len();
        for r in 0..nd {
            let gr = index[3 * c[r / 3] + r % 3];
            if gr == usize::MAX {
                continue;
            }
            for s in 0..nd {
                let gs = index[3 * c[s / 3] + s % 3];
                if gs != usize::MAX && gs <= gr {
                    triplets.push(Triplet::new(gr, gs, ke[r * nd + s]));
                }
            }
        }
    }
    let total: f64 = f.iter().sum();
    assert!((total - p).abs() < 1e-12 * p, "load {total} vs {p}");
    let k = SparseColMat::<usize, f64>::try_new_from_triplets(nf, nf, &triplets).unwrap();
    let llt = k.sp_cholesky(Side::Lower).unwrap();
    let mut rhs = Mat::<f64>::zeros(nf, 1);
    for (i, &g) in index.iter().enumerate() {
        if g != usize::MAX {
            rhs[(g, 0)] = f[i];
        }
    }
    llt.solve_in_place(rhs.as_mut());
    let work: f64 = index
        .iter()
        .enumerate()
        .filter(|(_, &g)| g != usize::MAX)
        .map(|(i, &g)| f[i] * rhs[(g, 0)])
        .sum();
    work / p
}

#[test]
fn a_cantilever_converges_to_timoshenkos_deflection() {
    // Timoshenko's beam: delta = P L^3 / (3 E I) + P L / (kappa G A), with Cowper's shear
    // coefficient of a rectangle kappa = 10 (1 + nu) / (12 + 11 nu).
    let (l, b, h): (f64, f64, f64) = (10.0, 1.0, 1.0);
    let size = [l, b, h];
    let p = 1e6;
    let (e, nu) = (STEEL.young, STEEL.poisson);
    let g = e / (2.0 * (1.0 + nu));
    let kappa = 10.0 * (1.0 + nu) / (12.0 + 11.0 * nu);
    let inertia = b * h * h * h / 12.0;
    let bending = p * l.powi(3) / (3.0 * e * inertia);
    let shear = p * l / (kappa * g * b * h);
    let exact = bending + shear;
    eprintln!(
        "Timoshenko: {exact:.6e} m (bending {bending:.6e}, shear {shear:.3e}, {:.2}%)",
        100.0 * shear / exact
    );
    let ladder = |name: &str, rungs: &[[usize; 3]], mesh: &dyn Fn([usize; 3]) -> Msh| {
        let mut errs = Vec::new();
        for &n in rungs {
            let msh = mesh(n);
            let delta = cantilever_deflection(&msh, size, p);
            let err = delta / exact - 1.0;
            eprintln!(
                "{name} {n:?}: {} dofs, deflection {delta:.6e} m, error {:+.3}%",
                3 * msh.coords.len(),
                100.0 * err
            );
            errs.push(err);
        }
        errs
    };
    let hex = ladder(
        "hex8",
        &[[10, 1, 1], [20, 2, 2], [40, 4, 4], [80, 8, 8]],
        &|n| box_hex8(size, n).unwrap().into(),
    );
    let t10 = ladder(
        "tet10",
        &[[5, 1, 1], [10, 1, 1], [20, 2, 2], [40, 4, 4]],
        &|n| box_tet10(size, n).unwrap().into(),
    );
    let t4 = ladder(
        "tet4",
        &[[10, 1, 1], [20, 2, 2], [40, 4, 4], [80, 8, 8]],
        &|n| box_tet4(size, n).unwrap().into(),
    );
    // Converging: the error shrinks at every rung, within 2% on the finest.
    for (name, errs) in [("hex8", &hex), ("tet10", &t10), ("tet4", &t4)] {
        for w in errs.windows(2) {
            assert!(w[1].abs() < w[0].abs(), "{name}: {errs:?}");
        }
    }
    assert!(hex.last().unwrap().abs() < 0.02, "hex8 {hex:?}");
    assert!(t10.last().unwrap().abs() < 0.02, "tet10 {t10:?}");
    // The linear tetrahedron locks: stiffer than the beam at every rung, and much
    // stiffer than the hexahedra on the same grid.
    for (e4, eh) in t4.iter().zip(&hex) {
        assert!(*e4 < 0.0 && e4 < eh, "tet4 {t4:?} hex8 {hex:?}");
    }
    assert!(t4[0] < -0.5, "tet4 coarse {t4:?}");
}

/// The lowest frequencies (Hz) of the free bar `msh` and the fraction of each mode's kinetic
/// energy in the `x` motion.
fn free_modes(msh: &Msh, lumped: bool) -> Vec<(f64, f64)> {
    let d = elasticity_3d(&STEEL);
    let (k, m) = assemble_dense(msh, &d, STEEL.density, lumped);
    let n = k.nrows();
    // K phi = w^2 M phi by Cholesky of M: (L^-1 K L^-T) y = w^2 y, phi = L^-T y.
    let mscale = (0..n).map(|i| m[(i, i)]).fold(0.0, f64::max);
    let kscale = (0..n).map(|i| k[(i, i)]).fold(0.0, f64::max);
    let llt = (m.as_ref() * (1.0 / mscale)).llt(Side::Lower).unwrap();
    let l = llt.L().to_owned();
    let mut a = k.as_ref() * (1.0 / kscale);
    faer::linalg::triangular_solve::solve_lower_triangular_in_place(
        l.as_ref(),
        a.as_mut(),
        faer::Par::Seq,
    );
    let mut at = a.transpose().to_owned();
    faer::linalg::triangular_solve::solve_lower_triangular_in_place(
        l.as_ref(),
        at.as_mut(),
        faer::Par::Seq,
    );
    let sym = Mat::<f64>::from_fn(n, n, |i, j| 0.5 * (at[(i, j)] + at[(j, i)]));
    let evd = sym.self_adjoint_eigen(Side::Lower).unwrap();
    let mut y = evd.U().to_owned();
    faer::linalg::triangular_solve::solve_upper_triangular_in_place(
        l.as_ref().transpose(),
        y.as_mut(),
        faer::Par::Seq,
    );
    (0..n.min(40))
        .map(|c| {
            let w2 = evd.S().column_vector()[c] * kscale / mscale;
            let energy = |dirs: &[usize]| {
                let mut s = 0.0;
                for i in 0..n {
                    if !dirs.contains(&(i % 3)) {
                        continue;
                    }
                    for j in 0..n {
                        if j % 3 == i % 3 {
                            s += y[(i, c)] * m[(i, j)] * y[(j, c)];
                        }
                    }
                }
                s
            };
            let fx = energy(&[0]) / energy(&[0, 1, 2]);
            (w2.max(0.0).sqrt() / std::f64::consts::TAU, fx)
        })
        .collect()
}

#[test]
fn a_free_bars_first_axial_frequency_converges_to_c_over_2l() {
    // The free-free rod: f1 = c / (2 L), c = sqrt(E / rho). Love's lateral-inertia
    // correction (Rayleigh and Love; Graff, Wave Motion in Elastic Solids, 1975, sec. 8.2),
    // f / f1 - 1 = -nu^2 pi^2 r_p^2 / (2 L^2) with the polar radius of gyration
    // r_p^2 = (b^2 + h^2) / 12, is -0.074% here: the consistent mass of the finest rung is
    // already below c / (2 L). The bounds are asserted against Love's value; the errors
    // printed against both. The lumped mass of a section one hexahedron wide puts the
    // section's lateral mass at its edges, three times the true section's lateral inertia
    // (b^2/4 against b^2/12 per unit mass): the finer rungs are two hexahedra wide.
    let (l, b): (f64, f64) = (1.0, 0.1);
    let size = [l, b, b];
    let rod = STEEL.bar_wave_speed() / (2.0 * l);
    let nu = STEEL.poisson;
    let r2 = (b * b + b * b) / 12.0;
    let love = rod * (1.0 - nu * nu * std::f64::consts::PI.powi(2) * r2 / (2.0 * l * l));
    let axial = |name: &str, msh: Msh, lumped: bool| {
        let modes = free_modes(&msh, lumped);
        // Six rigid-body modes at zero frequency.
        let f7 = modes[6].0;
        assert!(
            modes[..6].iter().all(|m| m.0 < 1e-4 * f7),
            "{name}: {:?}",
            &modes[..7]
        );
        let (f, share) = *modes[6..]
            .iter()
            .find(|m| m.1 > 0.9)
            .unwrap_or_else(|| panic!("{name}: no axial mode in {modes:?}"));
        let err = f / love - 1.0;
        eprintln!(
            "{name}: {} dofs, axial {f:.2} Hz ({:.1}% of its energy in x), error {:+.4}% against Love's {love:.2} Hz, {:+.4}% against c/2L = {rod:.2} Hz",
            3 * msh.coords.len(),
            100.0 * share,
            100.0 * err,
            100.0 * (f / rod - 1.0)
        );
        err
    };
    let mut last = [f64::INFINITY; 4];
    for n in [[4, 1, 1], [8, 1, 1], [16, 2, 2], [32, 2, 2]] {
        let cons = axial(
            &format!("hex8 consistent {n:?}"),
            box_hex8(size, n).unwrap().into(),
            false,
        );
        let lump = axial(
            &format!("hex8 lumped {n:?}"),
            box_hex8(size, n).unwrap().into(),
            true,
        );
        // Linear elements: the consistent mass bounds the frequency from above, the lumped
        // one from below.
        assert!(cons > 0.0 && lump < 0.0, "{cons} {lump}");
        assert!(cons < last[0] && lump.abs() < last[1]);
        last[0] = cons;
        last[1] = lump.abs();
    }
    assert!(last[0] < 1e-3 && last[1] < 1e-3, "{last:?}");
    for n in [[2, 1, 1], [4, 1, 1], [8, 2, 2]] {
        let cons = axial(
            &format!("tet10 consistent {n:?}"),
            box_tet10(size, n).unwrap().into(),
            false,
        );
        let lump = axial(
            &format!("tet10 HRZ {n:?}"),
            box_tet10(size, n).unwrap().into(),
            true,
        );
        assert!(
            cons.abs() < last[2] && lump.abs() < last[3],
            "{cons} {lump} {last:?}"
        );
        last[2] = cons.abs();
        last[3] = lump.abs();
    }
    // Quadratic elements: the consistent mass within 0.01% of Love's value (a check of the
    // correction itself); HRZ's diagonal slower, its lateral inertia on a section two
    // elements wide still too large.
    assert!(last[2] < 1e-4 && last[3] < 2e-3, "{last:?}");
}
