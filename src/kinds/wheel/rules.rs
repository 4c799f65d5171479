//! The `[block]` under a wheel, and the settings a wheel's run refuses in combination (a
//! moving zone, the uncoupled problem, a block, a plastic wheel, a creepage without
//! friction).

use crate::bodies::wheel::{ContactSurface, Coupling, WheelSpec};
use crate::contact::{FrictionLaw, Treatment};
use crate::material::Elastic;
use crate::scenario::raw::RawBlock;
use crate::scenario::{Contact, Ctx, MeshSource, ScenarioError, WheelScenario};
use crate::time::Integrator;

/// The `[block]` table under a wheel of `spec`: the material (default the wheel's), the
/// depth (default half the wheel's radius), the top column width (default the rim's pitch),
/// the rows' growth (default 1.2), the margins before and after the travel (default the
/// depth: an end nearer than that softens the block under the patch) and the search's reach
/// (default four columns).
pub(crate) fn block_spec(
    cx: &Ctx,
    b: RawBlock,
    spec: &WheelSpec,
) -> Result<crate::bodies::block::BlockSpec, ScenarioError> {
    let mat = spec.material;
    let young = cx.positive("block.young", b.young.unwrap_or(mat.young))?;
    let density = cx.positive("block.density", b.density.unwrap_or(mat.density))?;
    let poisson = b.poisson.unwrap_or(mat.poisson);
    if !(poisson.is_finite() && poisson > -1.0 && poisson < 0.5) {
        return Err(cx.invalid(
            "block.poisson",
            poisson,
            "Poisson's ratio must be in (-1, 0.5)",
        ));
    }
    let grading = b.grading.unwrap_or(1.2);
    if !(1.0..=2.0).contains(&grading) {
        return Err(cx.invalid(
            "block.grading",
            grading,
            "the growth of the rows from the top down, in [1, 2]",
        ));
    }
    let opt = |key: &str, v: Option<f64>| v.map(|x| cx.positive(key, x)).transpose();
    let depth = cx.positive("block.depth", b.depth.unwrap_or(0.5 * spec.radius))?;
    if depth <= 2.0 * spec.flattening.depth {
        return Err(cx.invalid(
            "block.depth",
            depth,
            &format!(
                "the block must be deeper than twice rolling.flattening = {} m",
                spec.flattening.depth
            ),
        ));
    }
    // The block is pressed up from its clamped bottom (the flattening program moves its
    // frame): its top follows once a compression wave has crossed it, and settles onto the
    // wheel only if the settling lasts a period of the block's first mode along its depth,
    // 4 depth / c (c = sqrt(E / rho), the slowest compression wave), as the rigid base must
    // take a period of the wheel's bounce (crate::kinds::wheel::run). A block of 40 m took 7.8 ms
    // to cross against a settling of 5 ms: the wheel ended it at 10 N against the shallow
    // block's 511 kN and rolled unloaded with exit 0 (issue 47).
    let c = (young / density).sqrt();
    let period = 4.0 * depth / c;
    let settle = spec.flattening.settle_time;
    if settle < period {
        let (key, value) = match (b.depth, b.young, b.density) {
            (Some(d), _, _) => ("block.depth", d),
            (None, Some(e), _) => ("block.young", e),
            (None, None, Some(r)) => ("block.density", r),
            _ => ("rolling.settle_time", settle),
        };
        return Err(cx.invalid(
            key,
            value,
            &format!(
                "the block is pressed from its clamped bottom: its first mode along block.depth = {depth} m has a period of 4 depth / sqrt(E / rho) = {:.4e} s ({:.4e} s for a compression wave to cross it), longer than rolling.settle_time = {settle:e} s: the block would not be loaded onto the wheel during the settling; take block.depth <= {:.4e} m or rolling.settle_time >= {period:.4e} s",
                period,
                depth / c,
                settle * c / 4.0
            ),
        ));
    }
    Ok(crate::bodies::block::BlockSpec {
        material: Elastic {
            young,
            poisson,
            density,
        },
        depth,
        dx: opt("block.dx", b.dx)?,
        grading,
        margin: block_margin(cx, b.margin, depth)?,
        reach: opt("block.reach", b.reach)?,
    })
}

/// The block's margin before and after the travel (`block.margin`, default its depth): at
/// most [`MARGIN_DEPTHS`] depths. An edge nearer than the depth softens the block under the
/// patch; one farther than that changes nothing and costs columns of the rim's pitch (a
/// margin of 1 km built a block of 3e5 columns for ever, deaf to its key: issue 47).
fn block_margin(cx: &Ctx, margin: Option<f64>, depth: f64) -> Result<f64, ScenarioError> {
    let m = cx.positive("block.margin", margin.unwrap_or(depth))?;
    if m > MARGIN_DEPTHS * depth {
        return Err(cx.invalid(
            "block.margin",
            m,
            &format!(
                "at most {MARGIN_DEPTHS} block.depth = {:e} m (an edge that far leaves the patch as a half-space does)",
                MARGIN_DEPTHS * depth
            ),
        ));
    }
    Ok(m)
}

/// The largest `block.margin`, in block depths.
const MARGIN_DEPTHS: f64 = 20.0;

/// A wheel's run against what its wheel `w` does not work with: a moving zone, the
/// uncoupled problem and an elastic block each refuse some of friction, creepage, coupling,
/// contact surface, treatment and integrator; a creepage needs friction.
pub(crate) fn check_wheel_run(
    cx: &Ctx,
    w: &WheelScenario,
    friction: Option<FrictionLaw>,
    run_contact: &Contact,
    integrator: &Integrator,
) -> Result<(), ScenarioError> {
    if let MeshSource::Zone(_) = w.mesh {
        let why = if w.spec.coupling == Coupling::Uncoupled {
            Some("rolling.coupling = \"uncoupled\": its twin disk is not relabelled (not yet)")
        } else if w.spec.surface != ContactSurface::Nodes {
            Some("wheel.contact_surface = \"segments\": a moving zone relabels node pairs only")
        } else if !matches!(run_contact, Treatment::SoftWay { .. } | Treatment::Exact)
            || !integrator.is_space_time()
        {
            Some("a moving zone runs with the space-time scheme and the soft way or exact enforcement")
        } else {
            None
        };
        if let Some(why) = why {
            return Err(cx.invalid(
                "wheel.zone_rim_nodes",
                "(given)",
                &format!("a moving refined zone does not work with {why}"),
            ));
        }
    }
    if let Some(g) = w.settle_gamma.filter(|_| !integrator.is_space_time()) {
        return Err(cx.invalid(
            "rolling.settle_gamma",
            g,
            "gamma of the space-time scheme while settling, not used by a classic integrator: remove it",
        ));
    }
    if w.spec.coupling == Coupling::Uncoupled {
        let why = if friction.is_none_or(|law| !law.is_active()) {
            Some("the uncoupled problem differs from the coupled one only through friction: set contact.friction > 0 (or remove rolling.coupling)")
        } else if w.spec.surface != ContactSurface::Nodes {
            Some("the uncoupled problem poses node pairs: remove wheel.contact_surface or set it to \"nodes\"")
        } else {
            None
        };
        if let Some(why) = why {
            return Err(cx.invalid("rolling.coupling", "\"uncoupled\"", why));
        }
    }
    if w.block.is_some() {
        let why = if friction.is_some_and(|law| law.is_active()) {
            Some("contact.friction: the block's tangential rows are searched but not yet verified; remove contact.friction")
        } else if w.spec.creepage != 0.0 {
            Some("rolling.creepage: the block runs under the wheel at the rim's speed; remove rolling.creepage")
        } else if w.spec.coupling == Coupling::Uncoupled {
            Some("rolling.coupling = \"uncoupled\": remove it")
        } else if w.spec.surface != ContactSurface::Nodes {
            Some("wheel.contact_surface = \"segments\": the rim's nodes are searched against the block's segments; remove it")
        } else if matches!(w.mesh, MeshSource::Zone(_)) {
            Some("a moving refined zone (wheel.zone_rim_nodes): remove it")
        } else {
            None
        };
        if let Some(why) = why {
            return Err(cx.invalid(
                "block",
                "(given)",
                &format!("an elastic block does not work with {why}"),
            ));
        }
    }
    // A nonlinear internal force (large deformation, J2): what its states do not travel with.
    let nonlinear = [
        (
            w.large.is_some(),
            (
                "material.geometry",
                "\"large\"",
                "the large-deformation wheel",
            ),
            [
                // Its state is nodal: a moving zone relabels it (crate::simulation).
                None,
                Some("the large-deformation wheel rolls on the rigid base"),
                Some("its twin disk is a second linear body"),
                Some("the snapshots that carry the iteration's state"),
            ],
        ),
        (
            w.plastic.is_some(),
            ("material.model", "\"j2\"", "the plastic wheel"),
            [
                Some("its relabelling carries nodal states, not the elements' plastic states"),
                Some("the plastic wheel rolls on the rigid base"),
                Some("its twin disk would carry half the strain"),
                Some("the snapshots that carry the plastic state"),
            ],
        ),
    ];
    for (on, (key, value, what), [zone, block, twin, snaps]) in nonlinear {
        if !on {
            continue;
        }
        let refused = |on: bool, why: Option<&str>, what: &str| {
            on.then_some(why).flatten().map(|w| format!("{what}: {w}"))
        };
        let why = refused(
            matches!(w.mesh, MeshSource::Zone(_)),
            zone,
            "a moving refined zone (wheel.zone_rim_nodes)",
        )
        .or_else(|| refused(w.block.is_some(), block, "an elastic block ([block])"))
        .or_else(|| {
            refused(
                w.spec.coupling == Coupling::Uncoupled,
                twin,
                "rolling.coupling = \"uncoupled\"",
            )
        })
        .or_else(|| {
            refused(
                matches!(run_contact, Treatment::Subdivision),
                snaps
                    .map(|s| format!("its sub-steps do not start at {s}"))
                    .as_deref(),
                "contact.method = \"subdivision\"",
            )
        });
        if let Some(why) = why {
            return Err(cx.invalid(key, value, &format!("{what} is not built with {why}")));
        }
    }
    if w.spec.creepage != 0.0 && friction.is_none_or(|law| !law.is_active()) {
        return Err(cx.invalid(
            "rolling.creepage",
            w.spec.creepage,
            "a creepage transmits a force only through friction: set contact.friction > 0 \
             (or remove rolling.creepage)",
        ));
    }
    Ok(())
}
