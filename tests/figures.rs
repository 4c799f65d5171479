//! No figure draws outside its panels (issue 34): every figure of the shipped scenarios'
//! commands is drawn strictly (`SOFTWAY_PLOT_STRICT=1`: a line, marker, label, legend or
//! title painted outside its axes, its panel or the canvas fails the command, naming what
//! and where; so do a legend over data and an automatic axis range set by one isolated
//! point, issue 48) and is written as a PNG that decodes. The pixels of the data are checked in
//! the plotting crate's own tests (`softway-plot`: no pixel of a series' colour outside its
//! axes on spiky and cut data).

use std::path::{Path, PathBuf};
use std::process::Command;

fn dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("softway-figures-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// Runs `softway ARGS --out OUT` with strict figures; panics with its error output on
/// failure.
fn softway(args: &[&str], out: &Path) {
    let o = Command::new(env!("CARGO_BIN_EXE_softway"))
        .args(args)
        .arg("--out")
        .arg(out)
        .env("SOFTWAY_PLOT_STRICT", "1")
        .output()
        .unwrap();
    assert!(
        o.status.success(),
        "softway {args:?}: {}",
        String::from_utf8_lossy(&o.stderr)
    );
}

/// The PNG decodes, has a size, and is not blank.
fn assert_figure(path: &Path) {
    let file = std::fs::File::open(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let mut reader = png::Decoder::new(std::io::BufReader::new(file))
        .read_info()
        .unwrap();
    let mut buf = vec![0; reader.output_buffer_size()];
    let info = reader.next_frame(&mut buf).unwrap();
    assert!(info.width >= 120 && info.height >= 90, "{}", path.display());
    let first = &buf[..3];
    assert!(
        buf[..info.buffer_size()].chunks(3).any(|p| p != first),
        "{} is blank",
        path.display()
    );
}

fn scenario(name: &str) -> String {
    format!("{}/scenarios/{name}.toml", env!("CARGO_MANIFEST_DIR"))
}

#[test]
fn bar_oscillator_track_and_stability_figures_stay_in_their_panels() {
    let d = dir("small");
    for (name, png) in [
        ("sdof", "sdof.png"),
        ("bar-impact", "bar_head.png"),
        ("bar-impact-mesh", "bar_head.png"),
        ("track", "track.png"),
    ] {
        let out = d.join(name);
        softway(&["run", &scenario(name), "--quiet"], &out);
        assert_figure(&out.join(png));
    }
    let out = d.join("stability");
    softway(&["stability", "--alpha", "0.5", "--gamma", "0.1"], &out);
    assert_figure(&out.join("stability.png"));
}

/// The comparisons' twenty and twelve panels (one legend between them), long titles
/// included.
#[test]
fn comparison_figures_stay_in_their_panels() {
    let d = dir("compare");
    for name in ["compare-bar", "compare-two-bars"] {
        let out = d.join(name);
        softway(&["compare", &scenario(name)], &out);
        for png in ["compare_force.png", "compare_energy.png"] {
            assert_figure(&out.join(png));
        }
    }
}

/// The wheel's figures (the spectrum with its annotations, the zoom, the maps, the rim
/// profile, the velocity fields with the base), with friction (the traction profile), and
/// a sweep's Fig. 15.
#[test]
fn wheel_figures_stay_in_their_panels() {
    let d = dir("wheel");
    let wheel = [
        "contact_force.png",
        "contact_force_zoom.png",
        "spectrum.png",
        "j2_turn_average.png",
        "von_mises_turn_average.png",
        "j2_rim_profile.png",
        "velocity_fields.png",
    ];
    let out = d.join("paper");
    softway(&["run", &scenario("wheel-paper-mesh"), "--quiet"], &out);
    for png in wheel {
        assert_figure(&out.join(png));
    }
    let out = d.join("traction");
    softway(&["run", &scenario("wheel-traction"), "--quiet"], &out);
    for png in wheel
        .iter()
        .chain(&["traction.png", "traction_history.png"])
    {
        assert_figure(&out.join(png));
    }
    // A short sweep of the spin on the paper's mesh: one turn each.
    let text = std::fs::read_to_string(scenario("wheel-paper-mesh"))
        .unwrap()
        .replace("turns = 5", "turns = 1");
    let sc = d.join("sweep.toml");
    std::fs::write(&sc, text).unwrap();
    let out = d.join("sweep");
    softway(
        &[
            "sweep",
            sc.to_str().unwrap(),
            "--set",
            "rolling.omega=250,400",
        ],
        &out,
    );
    assert_figure(&out.join("sweep.png"));
}

/// A refinement ladder's figure, with a series in its asymptotic range (a limit drawn) and
/// others not (a note instead).
#[test]
fn convergence_figure_stays_in_its_panels() {
    let d = dir("converge");
    // The oscillator of `scenarios/sdof.toml` with one run (a ladder needs one per rung).
    let text = std::fs::read_to_string(scenario("sdof")).unwrap();
    let one = text
        .split("[[runs]]")
        .next()
        .unwrap()
        .replace("t_end = 10.0", "t_end = 10.0\nh = 0.05\ngamma = 0.0");
    let sc = d.join("sdof1.toml");
    std::fs::write(&sc, one).unwrap();
    let out = d.join("out");
    softway(
        &[
            "converge",
            sc.to_str().unwrap(),
            "--set",
            "time.h=0.08,0.04,0.02,0.01",
        ],
        &out,
    );
    assert_figure(&out.join("converge.png"));
}

/// `softway modes` on the shipped wheel: `modes.png`, the rest and the spinning rows.
#[test]
fn mode_shapes_figure_stays_in_its_panels() {
    let d = dir("modes");
    let out = d.join("wheel");
    softway(&["modes", &scenario("wheel"), "--count", "6"], &out);
    assert_figure(&out.join("modes.png"));
}

/// The growth studies' figures (issue 48: an empty band at -285 dB set the spectrum's axis,
/// an unreliable 5 m band set the growth rate's, a legend over the data): two passes of the
/// wheel's polygon and one of the rail's corrugation, strictly (a legend over data or an
/// automatic range set by one isolated point fails them).
#[test]
fn growth_figures_stay_in_their_panels_and_show_their_data() {
    let d = dir("grow");
    for (name, passes, pngs) in [
        (
            "polygon",
            "2",
            &[
                "spectrum.png",
                "growth_rate.png",
                "profile.png",
                "orders.png",
            ][..],
        ),
        (
            "corrugation",
            "1",
            &[
                "spectrum.png",
                "growth_rate.png",
                "profile.png",
                "prediction.png",
            ][..],
        ),
    ] {
        let out = d.join(name);
        softway(&["grow", &scenario(name), "--passes", passes], &out);
        for png in pngs {
            assert_figure(&out.join(png));
        }
    }
}
