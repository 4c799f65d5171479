//! The S1002 wheel of revolution and the UIC60 rail at 1:40 with their default specs,
//! written for ParaView (`wheel.vtu`, `rail.vtu`) with their cross-sections' quadrilaterals
//! (`wheel_section.csv`, `rail_section.csv`: one row per quadrilateral, its four corners
//! `u0,v0,...,u3,v3` in m), and their counts printed.
//!
//! ```text
//! cargo run --release --example wheel_rail_meshes -- [OUT_DIR]   # default: wheel_rail_meshes
//! python validation/plot_sections.py OUT_DIR                     # the sections as PNG
//! ```

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use softway::mesh::generators::rail3d::rail_section;
use softway::mesh::generators::revolution::wheel_section;
use softway::mesh::generators::{rail_extruded, wheel_of_revolution, RailSpec, WheelSpec};
use softway::mesh::profiles::section::QuadSection;
use softway::mesh::profiles::write_mesh_vtu;
use softway::mesh::{quality, Mesh};

fn write_section(path: &Path, sec: &QuadSection) -> std::io::Result<()> {
    let mut text = String::from("u0,v0,u1,v1,u2,v2,u3,v3\n");
    for q in &sec.quads {
        let row: Vec<String> = q
            .iter()
            .flat_map(|&i| sec.points[i].map(|c| format!("{c:.9e}")))
            .collect();
        text.push_str(&row.join(","));
        text.push('\n');
    }
    std::fs::write(path, text)
}

fn report(name: &str, mesh: &Mesh, sec: &QuadSection) {
    let q = quality(mesh);
    let sets: Vec<String> = mesh
        .node_sets
        .iter()
        .filter(|(k, _)| k.as_str() != "all")
        .map(|(k, v)| format!("{k} {}", v.len()))
        .collect();
    println!(
        "{name}: {} nodes, {} hexahedra ({} inverted, {} degenerate), volume {:.6e} m^3; \
         section {} quadrilaterals, {} nodes, area {:.4e} m^2; node sets: {}",
        mesh.n_nodes(),
        q.solids,
        q.inverted,
        q.degenerate,
        q.volume,
        sec.quads.len(),
        sec.points.len(),
        sec.area(),
        sets.join(", ")
    );
}

fn run(out: &Path) -> Result<(), Box<dyn std::error::Error>> {
    std::fs::create_dir_all(out)?;
    let wheel_spec = WheelSpec::default();
    let rail_spec = RailSpec::default();
    let wheel = wheel_of_revolution(&wheel_spec)?;
    let rail = rail_extruded(&rail_spec)?;
    let (wsec, _, _) = wheel_section(&wheel_spec)?;
    let (rsec, _, _) = rail_section(&rail_spec)?;
    write_mesh_vtu(&out.join("wheel.vtu"), &wheel)?;
    write_mesh_vtu(&out.join("rail.vtu"), &rail)?;
    write_section(&out.join("wheel_section.csv"), &wsec)?;
    write_section(&out.join("rail_section.csv"), &rsec)?;
    report("wheel (S1002, R = 0.46 m)", &wheel, &wsec);
    report("rail (UIC60 at 1:40)", &rail, &rsec);
    println!("written to {}", out.display());
    Ok(())
}

fn main() -> ExitCode {
    let out: PathBuf = std::env::args()
        .nth(1)
        .map_or_else(|| PathBuf::from("wheel_rail_meshes"), PathBuf::from);
    match run(&out) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("wheel_rail_meshes: {e}");
            ExitCode::FAILURE
        }
    }
}
