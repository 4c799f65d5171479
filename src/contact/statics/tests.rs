use super::*;
use crate::element::continuum::{assemble_continuum, SolidHex8};
use crate::material::Elastic;
use crate::mesh::generators::box_mesh;
use crate::mesh::CellKind;

const STEEL: Elastic = Elastic {
    young: 210e9,
    poisson: 0.3,
    density: 7850.0,
};

/// A box on rollers (`u_z = 0` at the bottom, symmetry planes `x = 0`, `y = 0`) pressed
/// down by a rigid flat through `d`: every top node in contact, the uniaxial stress
/// `E d / H` (the hexahedra hold the linear field exactly), the force `E A d / H`.
#[test]
fn a_flat_punch_on_a_box_on_rollers_gives_the_uniaxial_force() {
    let (l, hgt, d) = (0.02, 0.03, 1e-5);
    let mesh = box_mesh(CellKind::Hex8, [l, l, hgt], [3, 3, 4]).unwrap();
    let el = SolidHex8 {
        d: crate::element::solid::elasticity_3d(&STEEL),
    };
    let a = assemble_continuum(&mesh, &el, STEEL.density, true).unwrap();
    let set = |s: &str| mesh.node_set(s).unwrap().to_vec();
    let mut fixed: Vec<usize> = set("x0").iter().map(|&i| 3 * i).collect();
    fixed.extend(set("y0").iter().map(|&i| 3 * i + 1));
    fixed.extend(set("z0").iter().map(|&i| 3 * i + 2));
    // The flat at z = H - d: gap -(z + u_z) - (d - H) >= 0.
    let rows: Vec<Row> = set("z1")
        .iter()
        .map(|&i| Row {
            nodes: vec![(i, 1.0)],
            direction: [0.0, 0.0, -1.0],
            offset: d - hgt,
        })
        .collect();
    let n = mesh.n_dofs();
    let x = mesh.reference_positions();
    for (pivoting, factor) in [
        (Pivoting::Block, FactorChoice::Auto),
        (Pivoting::LeastIndex, FactorChoice::Lu),
    ] {
        let mut s = Statics::new(
            &a.assembler.pattern,
            &a.k,
            &fixed,
            &vec![0.0; n],
            3,
            rows.clone(),
            factor,
        )
        .unwrap();
        s.pivoting = pivoting;
        let sol = s.solve(&x).unwrap();
        assert!(sol.converged);
        assert_eq!(sol.active.len(), rows.len(), "{pivoting:?}");
        let force: f64 = sol.active.iter().map(|a| a.1).sum();
        let exact = STEEL.young * l * l * d / hgt;
        assert!(
            (force / exact - 1.0).abs() < 1e-9,
            "{pivoting:?}: {force} {exact}"
        );
        for &i in &set("z1") {
            assert!((sol.u[3 * i + 2] + d).abs() < 1e-15);
        }
        // Half the indentation by new offsets on the kept columns: half the force.
        let half: Vec<f64> = rows.iter().map(|_| 0.5 * d - hgt).collect();
        s.set_offsets(&half).unwrap();
        let sol = s.solve(&x).unwrap();
        let force: f64 = sol.active.iter().map(|a| a.1).sum();
        assert!((force / (0.5 * exact) - 1.0).abs() < 1e-9);
    }
}

/// A rigid sphere on a coarse block: the two rules settle on the same set and forces (the
/// solution of the linear complementarity problem is unique for a positive definite `S`),
/// the block rule in fewer iterations.
#[test]
fn the_block_rule_and_the_least_index_rule_agree() {
    let mesh = box_mesh(CellKind::Hex8, [0.01, 0.01, 0.01], [12, 12, 4]).unwrap();
    let el = SolidHex8 {
        d: crate::element::solid::elasticity_3d(&STEEL),
    };
    let a = assemble_continuum(&mesh, &el, STEEL.density, true).unwrap();
    let set = |s: &str| mesh.node_set(s).unwrap().to_vec();
    let mut fixed: Vec<usize> = set("x0").iter().map(|&i| 3 * i).collect();
    fixed.extend(set("y0").iter().map(|&i| 3 * i + 1));
    fixed.extend(
        set("z0")
            .iter()
            .flat_map(|&i| [3 * i, 3 * i + 1, 3 * i + 2]),
    );
    let r = 0.01;
    let d = 4e-4;
    let rows: Vec<Row> = set("z1")
        .iter()
        .map(|&i| {
            let p = mesh.point(i);
            Row {
                nodes: vec![(i, 1.0)],
                direction: [0.0, 0.0, -1.0],
                offset: d - 0.01 - (p[0] * p[0] + p[1] * p[1]) / (2.0 * r),
            }
        })
        .collect();
    let n = mesh.n_dofs();
    let x = mesh.reference_positions();
    let mut out = Vec::new();
    for pivoting in [Pivoting::Block, Pivoting::LeastIndex] {
        let mut s = Statics::new(
            &a.assembler.pattern,
            &a.k,
            &fixed,
            &vec![0.0; n],
            3,
            rows.clone(),
            FactorChoice::Auto,
        )
        .unwrap();
        s.pivoting = pivoting;
        out.push(s.solve(&x).unwrap());
    }
    assert!(out[0].converged && out[1].converged);
    assert_eq!(out[0].active_rows, out[1].active_rows);
    assert!(out[0].active.len() > 3 && out[0].active.len() < rows.len());
    for (p, q) in out[0].active.iter().zip(&out[1].active) {
        assert!((p.1 - q.1).abs() < 1e-8 * p.1.abs().max(1.0), "{p:?} {q:?}");
        assert!(p.1 > 0.0);
    }
    assert!(out[0].iterations <= out[1].iterations);
}

#[test]
fn bad_input_is_named() {
    let mesh = box_mesh(CellKind::Hex8, [1.0; 3], [1, 1, 1]).unwrap();
    let el = SolidHex8 {
        d: crate::element::solid::elasticity_3d(&STEEL),
    };
    let a = assemble_continuum(&mesh, &el, STEEL.density, true).unwrap();
    let p = &a.assembler.pattern;
    let row = |i: usize| Row {
        nodes: vec![(i, 1.0)],
        direction: [0.0, 0.0, 1.0],
        offset: 0.0,
    };
    let f = vec![0.0; 24];
    let e = Statics::new(p, &a.k, &[], &f, 5, vec![], FactorChoice::Lu).unwrap_err();
    assert!(matches!(e, StaticsError::Dimension { dim: 5, .. }), "{e}");
    let e = Statics::new(p, &a.k, &[], &f[..3], 3, vec![], FactorChoice::Lu).unwrap_err();
    assert!(e.to_string().contains("`f`"), "{e}");
    let e = Statics::new(p, &a.k, &[99], &f, 3, vec![], FactorChoice::Lu).unwrap_err();
    assert!(e.to_string().contains("fixed dof"), "{e}");
    let e = Statics::new(p, &a.k, &[], &f, 3, vec![row(8)], FactorChoice::Lu).unwrap_err();
    assert!(e.to_string().contains("row node"), "{e}");
    let mut bad = row(0);
    bad.offset = f64::NAN;
    let e = Statics::new(p, &a.k, &[], &f, 3, vec![bad], FactorChoice::Lu).unwrap_err();
    assert!(matches!(e, StaticsError::BadRow { row: 0 }), "{e}");
}
