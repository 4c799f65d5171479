//! `--set KEY=VALUE` rewriting: arbitrary overrides applied to a shipped scenario's text
//! through the code the command line uses (`Override::parse`, then `overrides::read_with`,
//! then the build stage when it is cheap); never a panic, every error on one line.
//!
//! The input: its first byte picks the scenario, the rest (UTF-8) is one `--set` argument
//! per line.
#![no_main]

use libfuzzer_sys::fuzz_target;
use softway::scenario::{overrides, Model, Override};
use std::path::Path;

/// The shipped scenarios (`scenarios/*.toml`), as the binary would read them.
const SCENARIOS: [&str; 22] = [
    include_str!("../../scenarios/bar-impact-mesh.toml"),
    include_str!("../../scenarios/bar-impact.toml"),
    include_str!("../../scenarios/compare-bar.toml"),
    include_str!("../../scenarios/compare-two-bars.toml"),
    include_str!("../../scenarios/corrugation.toml"),
    include_str!("../../scenarios/creep-curve-carter.toml"),
    include_str!("../../scenarios/creep-curve-coupled.toml"),
    include_str!("../../scenarios/creep-curve.toml"),
    include_str!("../../scenarios/polygon.toml"),
    include_str!("../../scenarios/sdof.toml"),
    include_str!("../../scenarios/track-moving-load.toml"),
    include_str!("../../scenarios/track.toml"),
    include_str!("../../scenarios/wheel-gmsh.toml"),
    include_str!("../../scenarios/wheel-on-block.toml"),
    include_str!("../../scenarios/wheel-paper-mesh.toml"),
    include_str!("../../scenarios/wheel-plastic.toml"),
    include_str!("../../scenarios/wheel-realistic.toml"),
    include_str!("../../scenarios/wheel-sweep-paper-mesh.toml"),
    include_str!("../../scenarios/wheel-sweep.toml"),
    include_str!("../../scenarios/wheel-traction.toml"),
    include_str!("../../scenarios/wheel-zone.toml"),
    include_str!("../../scenarios/wheel.toml"),
];

fuzz_target!(|data: &[u8]| {
    let Some((&pick, rest)) = data.split_first() else {
        return;
    };
    let Ok(args) = std::str::from_utf8(rest) else {
        return;
    };
    let text = SCENARIOS[pick as usize % SCENARIOS.len()];
    let mut sets = Vec::new();
    for arg in args.split('\n') {
        match Override::parse(arg) {
            Ok(o) => sets.push(o),
            Err(m) => {
                assert!(!m.contains('\n'), "multi-line --set error: {m}");
                return;
            }
        }
    }
    match overrides::read_with(text, Path::new("fuzz.toml"), &sets) {
        Ok((sc, run_text)) => {
            // The text as run reads back to the same scenario.
            assert!(
                toml::from_str::<toml::Table>(&run_text).is_ok(),
                "the text as run is not TOML"
            );
            let small = sc.runs.iter().all(|r| match &r.model {
                Model::BarImpact(b) => b.elements <= 200,
                Model::TwoBars(b) => b.elements <= 200,
                _ => true,
            });
            if small {
                if let Err(e) = softway::build::resolve(&sc) {
                    assert!(!e.to_string().contains('\n'), "multi-line error: {e}");
                }
            }
        }
        Err(e) => assert!(!e.to_string().contains('\n'), "multi-line error: {e}"),
    }
});
