//! The large-deformation keys of `[material]` (`geometry`, `law`, `geometry_tolerance`)
//! read into [`super::large::Large`] (apart from the model's code, which the scenario's
//! types depend on).

use super::large::{Large, DEFAULT_TOLERANCE};
use crate::finite::Hyperelastic;
use crate::scenario::raw::RawMaterial;
use crate::scenario::{Ctx, ScenarioError};

/// `material.geometry`, `material.law` and `material.geometry_tolerance`: `None` for the
/// small-strain (linear) wheel, each key refused where it is not used.
///
/// # Errors
/// [`ScenarioError`] naming the key and what is allowed.
pub(crate) fn large_of(cx: &Ctx, m: &RawMaterial) -> Result<Option<Large>, ScenarioError> {
    let geometry = m.geometry.as_deref().unwrap_or("small");
    match geometry {
        "small" => {
            for (key, given) in [
                ("material.law", m.law.is_some()),
                (
                    "material.geometry_tolerance",
                    m.geometry_tolerance.is_some(),
                ),
            ] {
                if given {
                    return Err(cx.invalid(
                        key,
                        "(given)",
                        "used with material.geometry = \"large\" only",
                    ));
                }
            }
            return Ok(None);
        }
        "large" => {}
        o => {
            return Err(cx.invalid(
                "material.geometry",
                format!("\"{o}\""),
                "allowed: \"small\" (linear in the geometry, the default), \"large\" (the geometrically nonlinear force of crate::finite)",
            ))
        }
    }
    // With `material.model = "j2"` the wheel is plastic at finite strain
    // ([`crate::finite::FinitePlastic`]): `material.law` is then the J2 material's elastic
    // part, Saint Venant-Kirchhoff.
    if m.model.as_deref().is_some_and(|s| s != "elastic")
        && m.law
            .as_deref()
            .is_some_and(|l| l != "saint_venant_kirchhoff")
    {
        return Err(cx.invalid(
            "material.law",
            format!("\"{}\"", m.law.as_deref().unwrap_or_default()),
            "the plastic wheel at finite strain (material.model = \"j2\") is Saint Venant-Kirchhoff in its elastic part (S = D (E - E_p)): remove material.law",
        ));
    }
    let law = match m.law.as_deref().unwrap_or("saint_venant_kirchhoff") {
        "saint_venant_kirchhoff" => Hyperelastic::SaintVenantKirchhoff,
        "neo_hookean" => Hyperelastic::NeoHookean,
        o => {
            return Err(cx.invalid(
                "material.law",
                format!("\"{o}\""),
                "allowed: \"saint_venant_kirchhoff\" (default), \"neo_hookean\"",
            ))
        }
    };
    let tolerance = m.geometry_tolerance.unwrap_or(DEFAULT_TOLERANCE);
    if !(tolerance > 0.0 && tolerance < 1.0) {
        return Err(cx.invalid(
            "material.geometry_tolerance",
            tolerance,
            "the residual relative to the internal force, in (0, 1)",
        ));
    }
    Ok(Some(Large { law, tolerance }))
}
