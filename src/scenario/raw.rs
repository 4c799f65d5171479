//! Stage 1, parse: the TOML text into plain structs that mirror the file, nothing checked
//! but the syntax, the types and the key names (`deny_unknown_fields`: a misspelt key is an
//! error naming the file, the key, its line and the keys allowed there).
//!
//! Every field is what the file says, `None` where a key is absent; defaults, ranges and
//! combinations are the validation's business ([`super::validate`]).

use super::ScenarioError;
use serde::Deserialize;
use std::path::Path;

/// The tables and keys every kind reads (the kinds' own tables are theirs:
/// [`super::kind::Kind::tables`]).
pub(crate) const COMMON: [&str; 10] = [
    "name",
    "kind",
    "description",
    "time",
    "contact",
    "runs",
    "output",
    "sweep",
    "growth",
    "wear",
];

/// The whole file, but for the kinds' own tables (read by each kind,
/// [`super::kind::KindInput::tables`]); a top-level key that neither this nor a kind of
/// the registry reads is refused by [`parse`].
#[derive(Debug, Deserialize)]
pub(super) struct RawScenario {
    pub name: Option<String>,
    pub kind: String,
    pub description: Option<String>,
    pub time: Option<RawTime>,
    pub contact: Option<RawContact>,
    #[serde(default)]
    pub runs: Vec<RawRun>,
    pub output: Option<RawOutput>,
    pub sweep: Option<RawSweep>,
    /// `[growth]` and `[wear]`: validated by [`crate::growth::config`].
    pub growth: Option<toml::Table>,
    pub wear: Option<toml::Table>,
    /// The top-level keys as written, in order.
    #[serde(skip)]
    pub keys: Vec<String>,
}

/// `[sweep]`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawSweep {
    pub key: String,
    pub values: Vec<toml::Value>,
    /// `ladder = { key = "...", values = [...] }`: every value of `key` run on every rung.
    pub ladder: Option<RawLadder>,
}

/// `[sweep] ladder`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawLadder {
    pub key: String,
    pub values: Vec<toml::Value>,
    /// `with = { "other.key" = [v1, v2, ...] }`: keys set with each rung, one value a rung.
    pub with: Option<toml::Table>,
}

/// `[time]`.
#[derive(Debug, Deserialize, Default)]
#[serde(deny_unknown_fields)]
pub(super) struct RawTime {
    pub alpha: Option<f64>,
    pub gamma: Option<f64>,
    pub h: Option<f64>,
    pub t_end: Option<f64>,

    pub integrator: Option<String>,
    pub rho_inf: Option<f64>,
    pub alpha_h: Option<f64>,
    pub gamma_n: Option<f64>,
    pub cfl: Option<f64>,
    pub coriolis: Option<String>,
}

/// `[bar]` and `[two_bars]`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawBar {
    pub length: f64,
    pub ea: f64,
    pub rho_a: f64,
    pub speed: f64,
    pub gap: f64,
    pub elements: Option<i64>,
    pub mass: Option<String>,
    pub damping: Option<f64>,
}

/// `[sdof]`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawSdof {
    pub mass: f64,
    pub stiffness: f64,
    pub x0: Option<f64>,
    pub v0: Option<f64>,
}

/// `[wheel]`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawWheel {
    pub radius: f64,
    pub thickness: f64,
    pub rings: Option<i64>,
    pub rim_nodes: Option<i64>,
    pub grading: Option<f64>,
    pub rim_band: Option<f64>,
    pub mesh: Option<String>,
    pub plane: Option<String>,
    pub mass: Option<String>,
    pub support: Option<String>,
    pub hub_radius: Option<f64>,
    pub damping: Option<f64>,
    pub stress_stiffening: Option<bool>,
    pub contact_surface: Option<String>,
    pub rotating_frame: Option<bool>,
    pub zone_rim_nodes: Option<i64>,
    pub zone_width: Option<f64>,
    pub zone_sectors: Option<i64>,
    pub zone_depth: Option<f64>,
    pub load: Option<f64>,
}

/// `[block]`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawBlock {
    pub young: Option<f64>,
    pub poisson: Option<f64>,
    pub density: Option<f64>,
    pub depth: Option<f64>,
    pub dx: Option<f64>,
    pub grading: Option<f64>,
    pub margin: Option<f64>,
    pub reach: Option<f64>,
}

/// `[track]`: a parameter set and any of its values overridden.
#[derive(Debug, Deserialize, Default)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawTrack {
    pub set: Option<String>,
    pub theory: Option<String>,
    pub young: Option<f64>,
    pub shear_modulus: Option<f64>,
    pub shear_coefficient: Option<f64>,
    pub area: Option<f64>,
    pub inertia: Option<f64>,
    pub density: Option<f64>,
    pub pad_stiffness: Option<f64>,
    pub pad_damping: Option<f64>,
    pub sleeper_mass: Option<f64>,
    pub ballast_stiffness: Option<f64>,
    pub ballast_damping: Option<f64>,
    pub spacing: Option<f64>,
    pub bays: Option<i64>,
    pub elements_per_bay: Option<i64>,
    pub ends: Option<String>,
    pub end_bays: Option<i64>,
    pub end_damping: Option<f64>,
    pub head_radius: Option<f64>,
    pub poisson: Option<f64>,
}

/// `[vehicle]`: the wheel on the track.
#[derive(Debug, Deserialize, Default)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawVehicle {
    pub model: Option<String>,
    pub unsprung_mass: Option<f64>,
    pub axle_load: Option<f64>,
    pub wheel_radius: Option<f64>,
    pub speed: Option<f64>,
    pub speed_km_h: Option<f64>,
    pub travel_bays: Option<i64>,
    pub settle_bays: Option<i64>,
    pub suspension_stiffness: Option<f64>,
    pub suspension_damping: Option<f64>,
    pub gravity: Option<f64>,
    pub creepage: Option<f64>,
    pub wheelbase: Option<f64>,
    pub wheel_rim_nodes: Option<i64>,
    pub wheel_thickness: Option<f64>,
    pub wheel_hub_radius: Option<f64>,
    pub wheel_grading: Option<f64>,
    pub wheel_rim_band: Option<f64>,
    pub wheel_plane: Option<String>,
}

/// `[irregularity]`: the rail's roughness under the rolling wheel.
#[derive(Debug, Deserialize, Default)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawIrregularity {
    #[serde(rename = "type")]
    pub kind: Option<String>,
    pub amplitude: Option<f64>,
    pub wavelength: Option<f64>,
    pub fade: Option<f64>,
    pub file: Option<String>,
    pub bands: Option<Vec<Vec<f64>>>,
    pub per_band: Option<i64>,
    pub seed: Option<i64>,
}

/// `[receptance]`: the frequencies of `softway receptance`.
#[derive(Debug, Deserialize, Default)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawReceptance {
    pub f_min: Option<f64>,
    pub f_max: Option<f64>,
    pub points: Option<i64>,
}

/// `[material]`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawMaterial {
    pub young: f64,
    pub poisson: f64,
    pub density: f64,
    pub model: Option<String>,
    pub yield_stress: Option<f64>,
    pub hardening: Option<String>,
    pub hardening_modulus: Option<f64>,
    pub voce_q: Option<f64>,
    pub voce_b: Option<f64>,
    pub af_c: Option<f64>,
    pub af_gamma: Option<f64>,
    pub plastic_tolerance: Option<f64>,
    pub geometry: Option<String>,
    pub law: Option<String>,
    pub geometry_tolerance: Option<f64>,
}

/// `[rolling]`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawRolling {
    pub omega: Option<f64>,
    pub speed_km_h: Option<f64>,
    pub flattening: Option<f64>,
    pub settle_time: f64,
    pub turns: f64,
    pub settle_gamma: Option<f64>,
    pub fields_per_turn: Option<i64>,
    pub creepage: Option<f64>,
    pub coupling: Option<String>,
}

/// `[contact]`.
#[derive(Debug, Deserialize, Default)]
#[serde(deny_unknown_fields)]
pub(super) struct RawContact {
    pub method: Option<String>,
    pub penalty: Option<f64>,
    pub restitution: Option<f64>,
    pub friction: Option<f64>,
    pub friction_kinetic: Option<f64>,
    pub friction_velocity: Option<f64>,
    /// The falling law's memory, a slip distance in micrometres (`FrictionLaw::memory`).
    pub friction_memory_um: Option<f64>,
    pub friction_viscosity: Option<f64>,
    pub tangential_stiffness: Option<f64>,
}

/// One `[[runs]]` entry: overrides of `[time]`, `[contact]` and the bar's `elements`.
#[derive(Debug, Deserialize, Default, Clone)]
#[serde(deny_unknown_fields)]
pub(super) struct RawRun {
    pub label: Option<String>,
    pub h: Option<f64>,
    pub alpha: Option<f64>,
    pub gamma: Option<f64>,
    pub elements: Option<i64>,
    pub method: Option<String>,
    pub penalty: Option<f64>,
    pub restitution: Option<f64>,
    pub integrator: Option<String>,
    pub rho_inf: Option<f64>,
    pub alpha_h: Option<f64>,
    pub gamma_n: Option<f64>,
    pub cfl: Option<f64>,
    pub coriolis: Option<String>,
}

/// `[output]`.
#[derive(Debug, Deserialize, Default)]
#[serde(deny_unknown_fields)]
pub(super) struct RawOutput {
    pub history_stride: Option<i64>,
    pub plots: Option<bool>,
}

/// Parses scenario text; `path` names it in errors; `kinds` lists the kinds whose tables
/// may appear at the top level.
///
/// # Errors
/// [`ScenarioError::Parse`]: TOML syntax, a wrong type or an unknown key, with the parser's
/// message (line, column, the key) on one line.
pub(super) fn parse(
    text: &str,
    path: &Path,
    kinds: &super::kind::Registry,
) -> Result<RawScenario, ScenarioError> {
    parse_at(text, kinds, true).map_err(|message| ScenarioError::Parse {
        path: path.to_path_buf(),
        message,
    })
}

/// [`parse`]'s work, its message with the position (`positions`) or without it.
fn parse_at(
    text: &str,
    kinds: &super::kind::Registry,
    positions: bool,
) -> Result<RawScenario, String> {
    let message =
        |e: toml::de::Error| one_line_message(text, e.message(), e.span().filter(|_| positions));
    let mut raw: RawScenario = toml::from_str(text).map_err(message)?;
    let doc = toml::de::DeTable::parse(text).map_err(message)?;
    // A kind the registry does not know is the validation's refusal (naming `kind`), not
    // its tables'.
    let known = kinds.get(&raw.kind).is_some();
    for (key, _) in doc.get_ref() {
        let name = key.get_ref().as_ref();
        if !known || COMMON.contains(&name) || kinds.kinds().any(|k| k.tables().contains(&name)) {
            raw.keys.push(name.to_string());
            continue;
        }
        let mut tables: Vec<&str> = Vec::new();
        for k in kinds.kinds() {
            for t in k.tables() {
                if !COMMON.contains(t) && !tables.contains(t) {
                    tables.push(t);
                }
            }
        }
        let why = format!(
            "unknown key `{name}`, expected one of `{}` or a kind's table: `{}`",
            COMMON.join("`, `"),
            tables.join("`, `")
        );
        return Err(one_line_message(
            text,
            &why,
            Some(key.span()).filter(|_| positions),
        ));
    }
    Ok(raw)
}

/// A kind's tables `T` deserialized from the whole scenario text (each table's own struct
/// denies unknown keys), the message with the position (`positions`) or without it.
///
/// # Errors
/// The parser's message on one line.
pub(crate) fn parse_tables<T: serde::de::DeserializeOwned>(
    text: &str,
    positions: bool,
) -> Result<T, String> {
    toml::from_str(text)
        .map_err(|e| one_line_message(text, e.message(), e.span().filter(|_| positions)))
}

/// Parses scenario text as [`parse`] does; the error is the parser's message alone, on one
/// line, without the position (a `--set` override is named by its argument instead).
pub(super) fn parse_message(
    text: &str,
    kinds: &super::kind::Registry,
) -> Result<RawScenario, String> {
    parse_at(text, kinds, false)
}

/// The parser's message on one line, after `line L, column C (`the line`)` of the byte span
/// where the parser stopped (the line shortened to 60 characters, its control characters
/// escaped).
fn one_line_message(text: &str, message: &str, span: Option<std::ops::Range<usize>>) -> String {
    let mut message = message.split_whitespace().collect::<Vec<_>>().join(" ");
    // serde names the structs of this module ("expected struct RawContact"): a table.
    while let Some(at) = message.find("struct Raw") {
        let name = at + "struct ".len();
        let end = message[name..]
            .find(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
            .map_or(message.len(), |k| name + k);
        message.replace_range(at..end, "a table");
    }
    let Some(before) = span.and_then(|s| text.get(..s.start)) else {
        return message;
    };
    let line = before.matches('\n').count() + 1;
    let column = before.len() - before.rfind('\n').map_or(0, |i| i + 1) + 1;
    let source: String = text
        .lines()
        .nth(line - 1)
        .unwrap_or("")
        .trim()
        .chars()
        .take(60)
        .flat_map(|c| {
            if c.is_control() {
                c.escape_default().collect::<Vec<_>>()
            } else {
                vec![c]
            }
        })
        .collect();
    if source.is_empty() {
        format!("line {line}: {message}")
    } else {
        format!("line {line}, column {column} (`{source}`): {message}")
    }
}

/// Sets a dotted key (e.g. `rolling.omega`) in TOML text to a value, for sweeps and
/// command-line overrides; the result is validated as usual.
///
/// # Errors
/// A message naming the key when the text is not TOML or the key cannot be set.
pub fn set_key(text: &str, key: &str, value: &str) -> Result<String, String> {
    let mut doc: toml::Table = toml::from_str(text).map_err(|e| e.to_string())?;
    let parsed: toml::Value = match toml::from_str::<toml::Table>(&format!("v = {value}")) {
        Ok(t) => t["v"].clone(),
        Err(_) => toml::Value::String(value.to_string()),
    };
    let parts: Vec<&str> = key.split('.').collect();
    let mut cur = &mut doc;
    for (i, part) in parts.iter().enumerate() {
        if i + 1 == parts.len() {
            cur.insert((*part).to_string(), parsed.clone());
        } else {
            cur = cur
                .entry((*part).to_string())
                .or_insert_with(|| toml::Value::Table(toml::Table::new()))
                .as_table_mut()
                .ok_or_else(|| format!("`{}` is not a table", parts[..=i].join(".")))?;
        }
    }
    toml::to_string(&doc).map_err(|e| e.to_string())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The line, column and text of the parser's stop, on one line; no span, no prefix; a
    /// span past a multi-byte character or the end of the text is no panic.
    #[test]
    fn parse_errors_name_the_line_and_column_on_one_line() {
        let e = parse(
            "kind = \"x\"\n[time]\nh = \"0.1\"\n",
            Path::new("a.toml"),
            &crate::scenario::kind::Registry::new(Vec::new()),
        )
        .unwrap_err()
        .to_string();
        assert_eq!(
            e,
            "a.toml: line 3, column 5 (`h = \"0.1\"`): invalid type: string \"0.1\", expected f64"
        );
        assert_eq!(one_line_message("x", "two\n  lines", None), "two lines");
        assert_eq!(
            one_line_message(
                "x",
                "invalid type: integer `3`, expected struct RawContact",
                None
            ),
            "invalid type: integer `3`, expected a table"
        );
        let text = "é = \u{1}\n";
        assert_eq!(
            one_line_message(text, "m", Some(2..3)),
            "line 1, column 3 (`é = \\u{1}`): m"
        );
        assert_eq!(one_line_message(text, "m", Some(1..2)), "m");
        assert_eq!(one_line_message(text, "m", Some(99..100)), "m");
    }
}
