//! Gmsh bytes (ASCII or binary MSH) -> a triangle mesh or an error; never a panic.
#![no_main]

use libfuzzer_sys::fuzz_target;
use std::path::Path;

fuzz_target!(|data: &[u8]| {
    if let Ok(mesh) = softway::mesh::gmsh::parse_msh(data, Path::new("fuzz.msh")) {
        // A mesh that reads is usable: every cell refers to a node.
        let n = mesh.n_nodes();
        for e in 0..mesh.cells.len() {
            assert!(mesh.cell_nodes(e).iter().all(|&i| i < n));
        }
    }
});
