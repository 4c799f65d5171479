//! Gmsh bytes (ASCII or binary MSH) -> a triangle mesh or an error; never a panic. A mesh
//! that reads also goes through the wheel's disk and support checks.
#![no_main]

use libfuzzer_sys::fuzz_target;
use std::path::Path;

fuzz_target!(|data: &[u8]| {
    match softway::mesh::gmsh::parse_msh_tagged(data, Path::new("fuzz.msh")) {
        Ok((mesh, tags)) => {
            // A mesh that reads is usable: every cell refers to a node, every node has a tag.
            let n = mesh.n_nodes();
            assert_eq!(tags.len(), n);
            for e in 0..mesh.cells.len() {
                assert!(mesh.cell_nodes(e).iter().all(|&i| i < n));
            }
            if let Err(m) = softway::run::wheel::check_disk(&mesh, &tags, 1.0) {
                assert!(!m.contains('\n'), "multi-line message: {m}");
            }
            let spec = softway::wheel::WheelSpec {
                radius: 1.0,
                ..softway::wheel::WheelSpec::paper()
            };
            if let Err(m) = softway::run::wheel::check_supported(&mesh, &tags, &spec) {
                assert!(!m.contains('\n'), "multi-line message: {m}");
            }
        }
        Err(e) => {
            let m = e.to_string();
            assert!(!m.contains('\n'), "multi-line message: {m}");
        }
    }
});
