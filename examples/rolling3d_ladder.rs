//! The 3D wheel on the rigid base (`softway::bodies::rolling3d`, the book's
//! docs/src/solids3d.md, "Rolling in 3D"): the creep force's mesh ladder. For each mesh of
//! the annulus (rings x sectors x layers) and each longitudinal creepage, the mean normal
//! force and `Q / (mu N)` over the rolling after the flattening has settled.
//!
//! ```sh
//! cargo run --release --example rolling3d_ladder               # 12x192x1, 24x192x1, 24x384x2
//! cargo run --release --example rolling3d_ladder -- 48x384x2   # one mesh
//! ```
//!
//! The 2D plane-stress wheel of the same size for comparison:
//! `softway run scenarios/wheel-traction.toml --set wheel.rim_nodes=192 --set time.h=1e-5
//! --set rolling.turns=0.3 --set rolling.creepage=0` (and `=0.005`).

use std::sync::atomic::AtomicBool;
use std::time::Instant;

use softway::bodies::rolling3d::{PatchForce, RollingSlice, SliceSpec};
use softway::contact::obstacle::Flattening;
use softway::contact::FrictionLaw;
use softway::material::Elastic;
use softway::simulation::Simulation;

const MU: f64 = 0.3;
const SETTLE: f64 = 3e-3;
const H: f64 = 1e-5;
const STEPS: usize = 1000;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let meshes: Vec<[usize; 3]> = if args.is_empty() {
        vec![[12, 192, 1], [24, 192, 1], [24, 384, 2]]
    } else {
        args.iter()
            .map(|a| {
                let v: Vec<usize> = a.split('x').filter_map(|p| p.parse().ok()).collect();
                match v.as_slice() {
                    [r, s, l] => Ok([*r, *s, *l]),
                    _ => Err(format!(
                        "`{a}`: give a mesh as RINGSxSECTORSxLAYERS, e.g. 24x384x2"
                    )),
                }
            })
            .collect::<Result<_, _>>()?
    };
    println!("mesh        xi      N (kN)    Q/(mu N)   Q_lat/(mu N)   s");
    for counts in meshes {
        for xi in [0.0, 0.005] {
            let clock = Instant::now();
            let slice = RollingSlice::new(&SliceSpec {
                radius: 0.1,
                bore: 0.04,
                thickness: 0.01,
                counts,
                material: Elastic {
                    young: 2.05e11,
                    poisson: 0.3,
                    density: 7830.0,
                },
                lumped: false,
                omega: 300.0,
                flattening: Flattening {
                    depth: 1e-3,
                    settle_time: SETTLE,
                },
                creepages: [xi, 0.0, 0.0],
                zone: None,
                crown: None,
                coupling: softway::bodies::wheel::Coupling::Coupled,
                rail: None,
            })?;
            let problem = slice.problem((0.8, 0.2), H, STEPS, FrictionLaw::coulomb(MU));
            let mut sim = Simulation::new(problem)?;
            let (mut sum, mut count) = (PatchForce::default(), 0usize);
            let base = slice.base;
            sim.run(&AtomicBool::new(false), |v| {
                if v.state.t >= 2.0 * SETTLE {
                    let f = PatchForce::of(&base, v.state.t, &v.state.pairs);
                    sum.normal += f.normal;
                    sum.along += f.along;
                    sum.lateral += f.lateral;
                    count += 1;
                }
                Ok(())
            })?;
            let m = count.max(1) as f64;
            let (n, q, ql) = (sum.normal / m, -sum.along / m, sum.lateral / m);
            println!(
                "{:>3}x{:>3}x{}  {xi:<6}  {:9.2}  {:+9.4}  {:+12.2e}  {:5.1}",
                counts[0],
                counts[1],
                counts[2],
                n / 1e3,
                q / (MU * n),
                ql / (MU * n),
                clock.elapsed().as_secs_f64()
            );
        }
    }
    Ok(())
}
