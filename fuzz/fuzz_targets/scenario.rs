//! Scenario text -> parsed and validated `Scenario` or a one-line error; never a panic.
#![no_main]

use libfuzzer_sys::fuzz_target;
use softway::scenario::Scenario;
use std::path::Path;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    match Scenario::from_str(text, Path::new("fuzz.toml")) {
        Ok(sc) => {
            // The build stage too (cfl resolution assembles the bar), when it is cheap.
            let small = sc.runs.iter().all(|r| match &r.model {
                softway::scenario::Model::BarImpact(b) => b.elements <= 200,
                softway::scenario::Model::TwoBars(b) => b.elements <= 200,
                _ => true,
            });
            if small {
                let _ = softway::build::resolve(&sc);
            }
        }
        Err(e) => assert!(!e.to_string().contains('\n'), "multi-line error: {e}"),
    }
});
