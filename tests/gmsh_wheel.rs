//! A wheel of the user's own mesh: a Gmsh 4.1 file (written here from the generator's disk,
//! with physical groups "rim" and "centre"), rolled through the CLI.

use softway::mesh::generators::disk_rings;
use softway::mesh::Cells;
use std::fmt::Write as _;
use std::process::Command;

/// Writes `mesh` as an ASCII MSH 4.1 file: one surface entity with all triangles, one curve
/// entity carrying the rim nodes (physical "rim"), one point entity at the centre (physical
/// "centre").
fn write_msh(path: &std::path::Path, rings: usize) {
    let mesh = disk_rings(0.1, rings).unwrap();
    let Cells::Tri3(tris) = &mesh.cells else {
        unreachable!()
    };
    let rim = mesh.node_set("rim").unwrap().to_vec();
    let mut s = String::new();
    s.push_str("$MeshFormat\n4.1 0 8\n$EndMeshFormat\n");
    s.push_str("$PhysicalNames\n3\n0 1 \"centre\"\n1 2 \"rim\"\n2 3 \"body\"\n$EndPhysicalNames\n");
    s.push_str("$Entities\n1 1 1 0\n1 0 0 0 1 1\n1 -0.1 -0.1 0 0.1 0.1 0 1 2 0\n1 -0.1 -0.1 0 0.1 0.1 0 1 3 0\n$EndEntities\n");
    let n = mesh.n_nodes();
    let _ = writeln!(s, "$Nodes\n3 {n} 1 {n}");
    // Point entity: node 1 (the centre); curve entity: the rim; surface: the rest.
    let others: Vec<usize> = (1..n).filter(|i| !rim.contains(i)).collect();
    let _ = writeln!(s, "0 1 0 1\n1\n0 0 0");
    let _ = writeln!(s, "1 1 0 {}", rim.len());
    for &i in &rim {
        let _ = writeln!(s, "{}", i + 1);
    }
    for &i in &rim {
        let _ = writeln!(s, "{} {} 0", mesh.points[i][0], mesh.points[i][1]);
    }
    let _ = writeln!(s, "2 1 0 {}", others.len());
    for &i in &others {
        let _ = writeln!(s, "{}", i + 1);
    }
    for &i in &others {
        let _ = writeln!(s, "{} {} 0", mesh.points[i][0], mesh.points[i][1]);
    }
    s.push_str("$EndNodes\n");
    let m = tris.len();
    let _ = writeln!(
        s,
        "$Elements\n3 {} 1 {}",
        m + rim.len() + 1,
        m + rim.len() + 1
    );
    let _ = writeln!(s, "0 1 15 1\n1 1");
    let _ = writeln!(s, "1 1 1 {}", rim.len());
    for k in 0..rim.len() {
        let _ = writeln!(
            s,
            "{} {} {}",
            2 + k,
            rim[k] + 1,
            rim[(k + 1) % rim.len()] + 1
        );
    }
    let _ = writeln!(s, "2 1 2 {m}");
    for (e, t) in tris.iter().enumerate() {
        let _ = writeln!(
            s,
            "{} {} {} {}",
            2 + rim.len() + e,
            t[0] + 1,
            t[1] + 1,
            t[2] + 1
        );
    }
    s.push_str("$EndElements\n");
    std::fs::write(path, s).unwrap();
}

#[test]
fn wheel_from_a_gmsh_file_rolls_like_the_generated_one() {
    let dir = std::env::temp_dir().join(format!("softway-gmsh-wheel-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    write_msh(&dir.join("disk.msh"), 6);
    let base = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/scenarios/wheel-paper-mesh.toml"
    ))
    .unwrap()
    .replace("turns = 5", "turns = 0.1")
    .replace("settle_time = 5e-3", "settle_time = 1e-3")
    .replace("h = 2e-6", "h = 4e-6")
    .replace("plots = true", "plots = false");
    let mut results = Vec::new();
    for (name, text) in [
        ("gmsh", base.replace("rings = 12", "mesh = \"disk.msh\"")),
        ("rings", base.replace("rings = 12", "rings = 6")),
    ] {
        let sc = dir.join(format!("{name}.toml"));
        std::fs::write(&sc, text).unwrap();
        let out = dir.join(format!("out-{name}"));
        let o = Command::new(env!("CARGO_BIN_EXE_softway"))
            .args([
                "run",
                sc.to_str().unwrap(),
                "--quiet",
                "--out",
                out.to_str().unwrap(),
            ])
            .output()
            .unwrap();
        assert!(
            o.status.success(),
            "{name}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
        let s: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap())
                .unwrap();
        results.push((
            s["nodes"].as_u64().unwrap(),
            s["mean_contact_force"].as_f64().unwrap(),
        ));
    }
    // The same mesh read from the file: the same model, the same contact force.
    assert_eq!(results[0].0, results[1].0);
    assert!(
        (results[0].1 / results[1].1 - 1.0).abs() < 1e-9,
        "{results:?}"
    );
}
