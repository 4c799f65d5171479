//! The sparse Cholesky solver on 3D meshes: nested dissection against AMD on a steel cube of
//! hexahedra (the step matrix `M + c K`), and the 2D models' ordering unchanged.
//!
//! What must hold, whatever the numbers: an ordering is a permutation; the factor solves
//! `A x = b` to round-off; nested dissection fills less than AMD on a 3D mesh (George 1973:
//! `O(n^{4/3})` entries on a 3D grid, the least any ordering reaches, where minimum degree
//! orderings are not bounded so); the symbolic count of `L`'s entries bounds the factor's
//! (the factor leaves out entries that are exactly zero); and a 2D model (two unknowns a
//! node) keeps AMD, the same factor bit for bit as before nested dissection existed.

use softway::bodies::solid::{solid, SolidSpec};
use softway::contact::search::Motion;
use softway::linalg::{
    cholesky_factor_nnz, fill_reducing_ordering, spmv_into, Ordering, Pattern, SparseLlt,
    DISSECTION_MIN_ORDER,
};
use softway::material::{Elastic, PlaneModel};
use softway::mesh::generators::{box_mesh, rectangle};
use softway::mesh::{CellKind, Mesh};

const STEEL: Elastic = Elastic {
    young: 210e9,
    poisson: 0.3,
    density: 7850.0,
};

/// The step matrix `M + c K` of `mesh` (`c = (0.8 h)^2 / 2`, `h = 1e-6` s).
fn step_matrix(mesh: Mesh) -> (Pattern, Vec<f64>) {
    let spec = SolidSpec {
        material: STEEL,
        plane: PlaneModel::Stress,
        thickness: 1.0,
        lumped: false,
    };
    let body = solid("body", mesh, &spec, Motion::Fixed).unwrap().body;
    let c = 0.5 * (0.8e-6f64).powi(2);
    let m = &body.model;
    let values = m.m.iter().zip(&m.k).map(|(a, k)| a + c * k).collect();
    (m.assembler.pattern.clone(), values)
}

fn residual(pattern: &Pattern, values: &[f64], llt: &mut SparseLlt) -> f64 {
    let n = pattern.nrows();
    let b: Vec<f64> = (0..n).map(|i| 1.0 + (i % 7) as f64).collect();
    let mut x = b.clone();
    llt.solve_in_place(&mut x);
    let mut ax = vec![0.0; n];
    spmv_into(pattern, values, &x, &mut ax);
    let num: f64 = ax.iter().zip(&b).map(|(a, b)| (a - b) * (a - b)).sum();
    let den: f64 = b.iter().map(|b| b * b).sum();
    (num / den).sqrt()
}

/// On a cube of 10^3 hexahedra (3,993 unknowns): both orderings are permutations, nested
/// dissection's factor has fewer entries than AMD's, both solve to round-off, and the
/// symbolic counts bound the factors' entries.
#[test]
fn nested_dissection_fills_less_than_amd_on_a_cube_and_solves() {
    let (pattern, values) = step_matrix(box_mesh(CellKind::Hex8, [1.0; 3], [10; 3]).unwrap());
    let n = pattern.nrows();
    let mut counts = Vec::new();
    for ordering in [Ordering::Amd, Ordering::NestedDissection] {
        let (fwd, inv) = fill_reducing_ordering(&pattern, ordering).unwrap();
        let mut seen = vec![false; n];
        for (p, &i) in fwd.iter().enumerate() {
            assert!(!seen[i], "{ordering:?}: {i} twice");
            seen[i] = true;
            assert_eq!(inv[i], p);
        }
        let symbolic = cholesky_factor_nnz(&pattern, &inv);
        let mut llt = SparseLlt::with_ordering(&pattern, &values, ordering).unwrap();
        assert_eq!(llt.ordering(), ordering);
        let r = residual(&pattern, &values, &mut llt);
        assert!(r < 1e-12, "{ordering:?}: residual {r:e}");
        counts.push(symbolic);
    }
    let (amd, nd) = (counts[0], counts[1]);
    assert!(nd < amd, "nested dissection {nd} against AMD {amd}");
}

/// `Ordering::auto` takes nested dissection on a 3D mesh from `DISSECTION_MIN_ORDER`
/// unknowns on and AMD below it; a 2D mesh of as many unknowns keeps AMD, and
/// `SparseLlt::new` gives it the very factor of `Ordering::Amd`: the same solution bit for
/// bit.
#[test]
fn three_dimensional_meshes_get_nested_dissection_and_plane_ones_keep_amd() {
    let (big, _) = step_matrix(box_mesh(CellKind::Hex8, [1.0; 3], [12; 3]).unwrap());
    assert!(big.nrows() >= DISSECTION_MIN_ORDER);
    assert_eq!(Ordering::auto(&big), Ordering::NestedDissection);
    let (small, _) = step_matrix(box_mesh(CellKind::Hex8, [1.0; 3], [4; 3]).unwrap());
    assert!(small.nrows() < DISSECTION_MIN_ORDER);
    assert_eq!(Ordering::auto(&small), Ordering::Amd);

    let (plane, values) = step_matrix(rectangle(1.0, 1.0, 60, 50).unwrap());
    assert!(plane.nrows() >= DISSECTION_MIN_ORDER);
    assert_eq!(Ordering::auto(&plane), Ordering::Amd);
    let mut auto = SparseLlt::new(&plane, &values).unwrap();
    let mut amd = SparseLlt::with_ordering(&plane, &values, Ordering::Amd).unwrap();
    assert_eq!(auto.ordering(), Ordering::Amd);
    assert_eq!(auto.factor_nnz(), amd.factor_nnz());
    let b: Vec<f64> = (0..plane.nrows()).map(|i| (i % 5) as f64 - 2.0).collect();
    let (mut x, mut y) = (b.clone(), b);
    auto.solve_in_place(&mut x);
    amd.solve_in_place(&mut y);
    assert!(x.iter().zip(&y).all(|(p, q)| p.to_bits() == q.to_bits()));
}

/// The cost estimate's 3D factor (`softway::build::factor_entries_3d`) bounds the symbolic
/// count of nested dissection's factor on cubes and bars of hexahedra and 10-node
/// tetrahedra, within a factor of 6 above it (the bars, long bodies, are the loosest).
#[test]
fn the_estimate_bounds_the_factor_of_3d_boxes() {
    let cases = [
        (CellKind::Hex8, [1.0, 1.0, 1.0], [10, 10, 10]),
        (CellKind::Hex8, [0.1, 0.1, 1.0], [4, 4, 40]),
        (CellKind::Tet10, [1.0, 1.0, 1.0], [5, 5, 5]),
        (CellKind::Tet10, [0.1, 0.1, 1.0], [2, 2, 20]),
    ];
    for (kind, lengths, counts) in cases {
        let (pattern, _) = step_matrix(box_mesh(kind, lengths, counts).unwrap());
        let (_, inv) = fill_reducing_ordering(&pattern, Ordering::NestedDissection).unwrap();
        let actual = cholesky_factor_nnz(&pattern, &inv) as f64;
        let estimate = softway::build::factor_entries_3d(pattern.nrows() as f64);
        let ratio = estimate / actual;
        println!("{kind:?} {counts:?}: {} unknowns, nnz(L) {actual}, estimate {estimate:.0}, ratio {ratio:.2}", pattern.nrows());
        assert!(
            (1.0..=6.0).contains(&ratio),
            "{kind:?} {counts:?}: estimate {estimate:.0} against {actual}"
        );
    }
}
