//! Command-line overrides of a scenario's keys (`softway run SCENARIO --set KEY=VALUE`, also
//! `compare`, `modes`, `sweep`): a dotted key as in the file (`rolling.omega`,
//! `contact.method`), its value a TOML value (`300`, `1e-3`, `"exact"`, `true`; a bare word
//! that is not TOML is taken as a string: `contact.method=exact`; nothing after `=` removes
//! the key). The text is then read exactly as the file is: an unknown key or a wrong type
//! is refused with the parser's message, a value out of range with the validator's.
//!
//! The text as run keeps the file's comments where it can: a key of a plain `[table]` (or
//! at the top) is rewritten on its own line, the file's line kept in a comment beside it,
//! and a new key goes under its table's header. Each edit is checked against the same
//! change made on the parsed document; where the two differ (a multi-line value, an inline
//! or dotted table, a key in an array of tables) the text as run is the document written
//! out again, without the comments.

use super::ScenarioError;
use std::path::Path;

/// One `--set KEY=VALUE`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Override {
    /// The dotted key, e.g. `rolling.omega`.
    pub key: String,
    /// The value as given (TOML; empty: remove the key).
    pub value: String,
}

impl Override {
    /// Parses `KEY=VALUE`.
    ///
    /// # Errors
    /// A one-line message naming the argument when there is no `=` or no key, or the key
    /// is not dotted words.
    pub fn parse(s: &str) -> Result<Self, String> {
        let (k, v) = s
            .split_once('=')
            .filter(|(k, _)| !k.trim().is_empty())
            .ok_or_else(|| {
                format!("--set {s}: expected KEY=VALUE (e.g. rolling.omega=250 or contact.method=exact)")
            })?;
        let key = k.trim();
        let word = |p: &str| {
            !p.is_empty()
                && p.chars()
                    .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-')
        };
        if !key.split('.').all(word) {
            return Err(format!(
                "--set {s}: `{key}` is not a key of the scenario (dotted words as in the file, e.g. wheel.rim_nodes)"
            ));
        }
        // The as-run scenario names each `--set` on a comment line of its header: a line
        // break in a value would end the comment and leave a copy that cannot be run again.
        if v.chars().any(char::is_control) {
            return Err(format!(
                "--set {}: the value of `{key}` holds a line break, tab or other control character; give it on one line (a TOML string writes them as \\n, \\t)",
                s.escape_debug()
            ));
        }
        Ok(Self {
            key: key.to_string(),
            value: v.trim().to_string(),
        })
    }

    /// `KEY=VALUE`, as given.
    pub fn to_arg(&self) -> String {
        format!("{}={}", self.key, self.value)
    }

    /// The value as a TOML value (`None`: remove the key): a TOML literal, else the text
    /// as a string.
    fn toml_value(&self) -> Option<toml::Value> {
        if self.value.is_empty() {
            return None;
        }
        Some(
            match toml::from_str::<toml::Table>(&format!("v = {}", self.value)) {
                Ok(mut t) => t.remove("v").unwrap_or(toml::Value::String(String::new())),
                Err(_) => toml::Value::String(self.value.clone()),
            },
        )
    }

    /// The value as written into the text: the TOML literal.
    fn literal(&self) -> Option<String> {
        self.toml_value().map(|v| v.to_string())
    }
}

/// How a sweep combines the values of its keys.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, clap::ValueEnum)]
pub enum Grid {
    /// Every combination of the keys' values (the first key outermost).
    #[default]
    Product,
    /// The keys' values taken together, the i-th of each (the lists of equal length; a key
    /// with a single value is set at every point, as numpy broadcasts a length-1 axis).
    Zip,
}

/// The rungs of a refinement ladder (`softway converge --set KEY=...`, `[sweep] ladder`),
/// TOML literals, as numbers: at least `min` of them, positive, refining (or coarsening)
/// monotonically by one constant ratio, which the observed order of successive differences
/// assumes ([`crate::run::observed_orders`]).
///
/// # Errors
/// A one-line message saying what the rungs must be.
pub fn ladder_rungs(values: &[String], min: usize) -> Result<Vec<f64>, String> {
    let xs: Vec<f64> = values
        .iter()
        .map(|v| v.trim_matches('"').parse::<f64>())
        .collect::<Result<_, _>>()
        .map_err(|_| "a convergence ladder needs numbers".to_string())?;
    if xs.len() < min {
        return Err(if min >= 3 {
            "a convergence ladder needs at least three rungs (an order needs two differences)"
                .into()
        } else {
            "a ladder of at least two rungs (three for an observed order), e.g. [4608, 9216, 18432]"
                .into()
        });
    }
    if xs.iter().any(|&x| !(x.is_finite() && x > 0.0)) {
        return Err("the rungs must be positive".into());
    }
    let ratios: Vec<f64> = xs.windows(2).map(|w| w[1] / w[0]).collect();
    if ratios.contains(&1.0)
        || !(ratios.iter().all(|&r| r > 1.0) || ratios.iter().all(|&r| r < 1.0))
    {
        return Err(
            "the rungs must increase (or decrease) from one to the next, e.g. 8,16,32".into(),
        );
    }
    if let (Some(&r0), Some(&r)) = (
        ratios.first(),
        ratios
            .iter()
            .find(|&&r| (r.ln() / ratios[0].ln() - 1.0).abs() > 0.02),
    ) {
        return Err(format!(
            "the rungs must grow by a constant ratio (the observed order assumes it): {r0:.4} then {r:.4}; e.g. 8,16,32 or 1e-4,5e-5,2.5e-5"
        ));
    }
    Ok(xs)
}

/// The points of a sweep over `keys` (each a dotted key and its values, TOML literals):
/// each point a list of overrides, one per key, in the order of the keys.
///
/// # Errors
/// A one-line message: no keys, a key without values or given twice, lists of different
/// lengths (other than one) for [`Grid::Zip`], more than 10,000 points.
pub fn grid(keys: &[(String, Vec<String>)], how: Grid) -> Result<Vec<Vec<Override>>, String> {
    if keys.is_empty() {
        return Err("no key to sweep: give --set KEY=V1,V2,...".into());
    }
    for (i, (k, vs)) in keys.iter().enumerate() {
        if vs.is_empty() {
            return Err(format!("--set {k}=: no values"));
        }
        if keys[..i].iter().any(|(o, _)| o == k) {
            return Err(format!(
                "--set {k}: given twice; give each key once, with all its values"
            ));
        }
    }
    let point = |pick: &dyn Fn(usize) -> usize| -> Vec<Override> {
        keys.iter()
            .enumerate()
            .map(|(i, (k, vs))| Override {
                key: k.clone(),
                value: vs[pick(i)].clone(),
            })
            .collect()
    };
    match how {
        Grid::Zip => {
            // A key with a single value is broadcast (as numpy broadcasts a length-1 axis):
            // set at every point. The other lists go side by side and share one length.
            let (first, n) = keys
                .iter()
                .find(|(_, vs)| vs.len() > 1)
                .map_or((&keys[0].0, 1), |(k, vs)| (k, vs.len()));
            if let Some((k, vs)) = keys.iter().find(|(_, vs)| vs.len() != 1 && vs.len() != n) {
                return Err(format!(
                    "--grid zip: {first} has {n} values and {k} {}: zip takes the lists side by side, give them the same length (a key with one value is set at every point; or --grid product)",
                    vs.len()
                ));
            }
            Ok((0..n)
                .map(|j| point(&|i| if keys[i].1.len() == 1 { 0 } else { j }))
                .collect())
        }
        Grid::Product => {
            let total = keys
                .iter()
                .try_fold(1usize, |t, (_, vs)| t.checked_mul(vs.len()))
                .filter(|&t| t <= 10_000)
                .ok_or_else(|| {
                    "the grid has more than 10,000 points: sweep fewer values".to_string()
                })?;
            Ok((0..total)
                .map(|mut j| {
                    let mut idx = vec![0; keys.len()];
                    for i in (0..keys.len()).rev() {
                        idx[i] = j % keys[i].1.len();
                        j /= keys[i].1.len();
                    }
                    point(&|i| idx[i])
                })
                .collect())
        }
    }
}

/// Sets (or with `None` removes) the dotted `key` in the parsed document.
fn set_in(doc: &mut toml::Table, key: &str, value: Option<toml::Value>) -> Result<(), String> {
    let parts: Vec<&str> = key.split('.').collect();
    let mut cur = doc;
    for (i, part) in parts.iter().enumerate() {
        if i + 1 == parts.len() {
            match &value {
                Some(v) => {
                    cur.insert((*part).to_string(), v.clone());
                }
                None => {
                    cur.remove(*part);
                }
            }
        } else {
            cur = cur
                .entry((*part).to_string())
                .or_insert_with(|| toml::Value::Table(toml::Table::new()))
                .as_table_mut()
                .ok_or_else(|| format!("`{}` is not a table", parts[..=i].join(".")))?;
        }
    }
    Ok(())
}

/// The table a header line opens (`[rolling]` -> `rolling`; `[[runs]]` -> `[[runs]]`, which
/// no key of a plain table matches), or `None` for other lines.
fn header(line: &str) -> Option<String> {
    let t = line.trim();
    if let Some(rest) = t.strip_prefix("[[") {
        return Some(format!(
            "[[{}]]",
            rest.split("]]").next().unwrap_or("").trim()
        ));
    }
    let rest = t.strip_prefix('[')?;
    Some(rest.split(']').next().unwrap_or("").trim().to_string())
}

/// The key a line assigns (`omega = 300  # rad/s` -> `omega`), if any.
fn assigned(line: &str) -> Option<&str> {
    let t = line.trim_start();
    if t.starts_with('#') || t.starts_with('[') {
        return None;
    }
    let (k, _) = t.split_once('=')?;
    Some(k.trim())
}

/// The override written into the text line by line (comments kept), or `None` where that
/// cannot be done (a deeper key); the caller checks the result.
fn edit_lines(text: &str, o: &Override) -> Option<String> {
    let (table, leaf) = match o.key.rsplit_once('.') {
        Some((t, l)) if !t.contains('.') => (t, l),
        Some(_) => return None,
        None => ("", o.key.as_str()),
    };
    let lines: Vec<&str> = text.lines().collect();
    let mut current = String::new();
    let mut header_at = None;
    let mut key_at = None;
    for (i, l) in lines.iter().enumerate() {
        if let Some(h) = header(l) {
            current = h;
            if current == table {
                header_at = Some(i);
            }
            continue;
        }
        if current == table && assigned(l) == Some(leaf) {
            key_at = Some(i);
            break;
        }
    }
    let mut out: Vec<String> = lines.iter().map(|l| l.to_string()).collect();
    let note = format!("--set {}", o.to_arg());
    match (key_at, o.literal()) {
        (Some(i), Some(v)) => {
            out[i] = format!(
                "{leaf} = {v}  # {note}; the file's line: {}",
                lines[i].trim()
            );
        }
        (Some(i), None) => out[i] = format!("# removed by {note}: {}", lines[i].trim()),
        (None, None) => {}
        (None, Some(v)) => {
            let line = format!("{leaf} = {v}  # {note}");
            match (table, header_at) {
                ("", _) => out.insert(0, line),
                (_, Some(h)) => out.insert(h + 1, line),
                (_, None) => {
                    out.push(String::new());
                    out.push(format!("[{table}]"));
                    out.push(line);
                }
            }
        }
    }
    let mut s = out.join("\n");
    s.push('\n');
    Some(s)
}

/// The scenario text with the overrides written into it, in order (module docs: comments
/// kept where the edit can be checked, else the document written out again).
///
/// # Errors
/// A one-line message when the text is not TOML or a key's parent is not a table
/// (`--set rolling.omega.x=1`).
pub fn apply(text: &str, sets: &[Override]) -> Result<String, String> {
    let mut doc: toml::Table = toml::from_str(text).map_err(|e| e.message().to_string())?;
    let mut edited = Some(text.to_string());
    for o in sets {
        set_in(&mut doc, &o.key, o.toml_value())
            .map_err(|m| format!("--set {}: {m}", o.to_arg()))?;
        edited = edited
            .and_then(|t| edit_lines(&t, o))
            .filter(|t| toml::from_str::<toml::Table>(t).ok().as_ref() == Some(&doc));
    }
    match edited {
        Some(t) => Ok(t),
        None => toml::to_string(&doc).map_err(|e| e.to_string()),
    }
}

/// Parses and validates the scenario text with the overrides written into it, as
/// [`super::Scenario::from_str`] reads a file; returns the scenario and the text as run.
/// A key or value the parser refuses is named by its `--set` argument, with the message
/// the same key would get in the file.
///
/// # Errors
/// [`ScenarioError`].
pub fn read_with(
    text: &str,
    path: &Path,
    sets: &[Override],
    kinds: &super::kind::Registry,
) -> Result<(super::Scenario<super::RunSpec>, String), ScenarioError> {
    let parse_error = |message: String| ScenarioError::Parse {
        path: path.to_path_buf(),
        message,
    };
    let run_text = match apply(text, sets) {
        Ok(t) => t,
        Err(m) => {
            // The file's own error first, with its line.
            super::raw::parse(text, path, kinds)?;
            return Err(parse_error(m));
        }
    };
    let mut sc = match super::Scenario::from_str_in(&run_text, path, kinds) {
        Err(e @ ScenarioError::Parse { .. }) => {
            // Which override is at fault: the first one that, alone on the file, the
            // parser refuses (the file itself may be at fault: then its own message).
            if let Err(own @ ScenarioError::Parse { .. }) =
                super::Scenario::from_str_in(text, path, kinds)
            {
                return Err(own);
            }
            for o in sets {
                let one = apply(text, std::slice::from_ref(o)).map_err(parse_error)?;
                if let Some(m) = super::parse_error(&one, kinds) {
                    return Err(parse_error(format!("--set {}: {m}", o.to_arg())));
                }
            }
            return Err(e);
        }
        other => other?,
    };
    sc.overrides = sets.to_vec();
    Ok((sc, run_text))
}

#[cfg(test)]
mod tests {
    use super::*;

    const TEXT: &str = "# a wheel\nkind = \"wheel\"\n\n[rolling]\nomega = 300.0   # rad/s\nturns = 5\n\n[[runs]]\nh = 1e-6\n";

    fn set(s: &str) -> Override {
        Override::parse(s).unwrap()
    }

    fn table(t: &str) -> toml::Table {
        toml::from_str(t).unwrap()
    }

    /// A key of a plain table is rewritten on its line (the file's line kept in a comment),
    /// a new key goes under its table, a new table at the end, a bare word is a string, an
    /// empty value removes the key; the document is the one the parsed edits give.
    #[test]
    fn overrides_are_written_into_the_text_keeping_its_comments() {
        let t = apply(
            TEXT,
            &[
                set("rolling.omega=250"),
                set("rolling.speed_km_h=90"),
                set("contact.method=exact"),
                set("rolling.turns="),
                set("name=\"x\""),
            ],
        )
        .unwrap();
        assert!(t.contains("# a wheel"), "{t}");
        assert!(
            t.contains(
                "omega = 250  # --set rolling.omega=250; the file's line: omega = 300.0   # rad/s"
            ),
            "{t}"
        );
        assert!(
            t.contains("# removed by --set rolling.turns=: turns = 5"),
            "{t}"
        );
        let doc = table(&t);
        assert_eq!(doc["rolling"]["omega"].as_integer(), Some(250));
        assert_eq!(doc["rolling"]["speed_km_h"].as_integer(), Some(90));
        assert!(doc["rolling"].get("turns").is_none());
        assert_eq!(doc["contact"]["method"].as_str(), Some("exact"));
        assert_eq!(doc["name"].as_str(), Some("x"));
        assert_eq!(doc["runs"][0]["h"].as_float(), Some(1e-6));
    }

    /// A value with a line break (or a tab, any control character) is refused on one line:
    /// the as-run scenario's header names each `--set` on a comment line, which a line break
    /// would end, leaving a copy that cannot be run again.
    #[test]
    fn a_value_with_a_line_break_is_refused_on_one_line() {
        for v in ["a\nb", "x\r", "tab\there", "nul\0"] {
            let e = Override::parse(&format!("runs_label={v}")).unwrap_err();
            assert!(
                e.contains("`runs_label`") && e.contains("control character"),
                "{e}"
            );
            assert!(
                !e.contains('\n') && !e.contains('\0'),
                "not one line: {e:?}"
            );
        }
        assert_eq!(Override::parse("rolling.omega=250").unwrap().value, "250");
    }

    /// Where the line edit cannot reach (a key inside an array of tables' entry, a dotted
    /// table) the document is written out again: the same values, the comments lost.
    #[test]
    fn an_edit_the_lines_cannot_make_falls_back_to_the_document() {
        let t = apply(TEXT, &[set("runs=[{h = 2e-6}]")]).unwrap();
        let doc = table(&t);
        assert_eq!(doc["runs"][0]["h"].as_float(), Some(2e-6));
        assert_eq!(doc["rolling"]["omega"].as_float(), Some(300.0));
        let t = apply(TEXT, &[set("a.b.c=1")]).unwrap();
        assert_eq!(table(&t)["a"]["b"]["c"].as_integer(), Some(1));
        let e = apply(TEXT, &[set("rolling.omega.x=1")]).unwrap_err();
        assert_eq!(e, "--set rolling.omega.x=1: `rolling.omega` is not a table");
    }

    /// The product's points in order (the first key outermost), the zip's side by side;
    /// zip broadcasts a single value and refuses other lists of different lengths, both a
    /// key given twice.
    #[test]
    fn sweep_grids_by_product_and_zip() {
        let keys = vec![
            ("a".to_string(), vec!["1".to_string(), "2".to_string()]),
            ("b".to_string(), vec!["x".into(), "y".into(), "z".into()]),
        ];
        let args = |g: &[Vec<Override>]| -> Vec<String> {
            g.iter()
                .map(|p| p.iter().map(Override::to_arg).collect::<Vec<_>>().join(" "))
                .collect()
        };
        assert_eq!(
            args(&grid(&keys, Grid::Product).unwrap()),
            ["a=1 b=x", "a=1 b=y", "a=1 b=z", "a=2 b=x", "a=2 b=y", "a=2 b=z"]
        );
        let e = grid(&keys, Grid::Zip).unwrap_err();
        assert!(e.contains("a has 2 values and b 3"), "{e}");
        let zipped = vec![keys[0].clone(), ("b".into(), vec!["x".into(), "y".into()])];
        assert_eq!(
            args(&grid(&zipped, Grid::Zip).unwrap()),
            ["a=1 b=x", "a=2 b=y"]
        );
        // A single value is broadcast over the zip, in any position; lengths 2 and 3 are
        // still refused when a third key has one value.
        let one = ("c".to_string(), vec!["7".to_string()]);
        assert_eq!(
            args(
                &grid(
                    &[one.clone(), zipped[0].clone(), zipped[1].clone()],
                    Grid::Zip
                )
                .unwrap()
            ),
            ["c=7 a=1 b=x", "c=7 a=2 b=y"]
        );
        assert_eq!(
            args(&grid(&[keys[1].clone(), one.clone()], Grid::Zip).unwrap()),
            ["b=x c=7", "b=y c=7", "b=z c=7"]
        );
        assert_eq!(
            args(&grid(std::slice::from_ref(&one), Grid::Zip).unwrap()),
            ["c=7"]
        );
        let e = grid(&[one, keys[0].clone(), keys[1].clone()], Grid::Zip).unwrap_err();
        assert!(e.contains("a has 2 values and b 3"), "{e}");
        let twice = vec![keys[0].clone(), keys[0].clone()];
        assert!(grid(&twice, Grid::Product)
            .unwrap_err()
            .contains("given twice"));
    }

    #[test]
    fn malformed_arguments_are_refused_on_one_line() {
        for bad in ["omega", "=3", "a..b=1", "a b=1"] {
            let e = Override::parse(bad).unwrap_err();
            assert!(
                e.starts_with(&format!("--set {bad}: ")) && !e.contains('\n'),
                "{e}"
            );
        }
        assert_eq!(set(" rolling.omega = 3 ").to_arg(), "rolling.omega=3");
    }
}
