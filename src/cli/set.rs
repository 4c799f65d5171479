//! `--set KEY=V1,V2,...`: a dotted scenario key and its values.

/// `KEY=V1,V2,...` of `--set` into the key and its values. The values are split at the
/// commas outside brackets, braces and quotes, so that a value may be a TOML array or table
/// (`wheel.mesh=[12,192,1],[24,384,2]`).
pub(super) fn parse_set(s: &str) -> Result<(String, Vec<String>), String> {
    let (k, v) = s
        .split_once('=')
        .filter(|(k, _)| !k.trim().is_empty())
        .ok_or_else(|| format!("--set {s}: expected KEY=V1,V2,... (e.g. rolling.omega=250,300)"))?;
    let mut vals: Vec<String> = Vec::new();
    let (mut depth, mut quote, mut start) = (0i32, None::<char>, 0usize);
    for (i, c) in v.char_indices() {
        match (quote, c) {
            (Some(q), _) if c == q => quote = None,
            (Some(_), _) => {}
            (None, '"' | '\'') => quote = Some(c),
            (None, '[' | '{') => depth += 1,
            (None, ']' | '}') => depth -= 1,
            (None, ',') if depth == 0 => {
                vals.push(v[start..i].trim().to_string());
                start = i + 1;
            }
            _ => {}
        }
    }
    if depth != 0 || quote.is_some() {
        return Err(format!(
            "--set {s}: unbalanced brackets or quotes in the values"
        ));
    }
    vals.push(v[start..].trim().to_string());
    vals.retain(|x| !x.is_empty());
    if vals.is_empty() {
        return Err(format!("--set {s}: no values"));
    }
    Ok((k.trim().to_string(), vals))
}

#[cfg(test)]
mod tests {
    use super::parse_set;

    /// Values split at the top-level commas: a TOML array stays one value, a quoted comma
    /// too; unbalanced brackets are refused.
    #[test]
    fn set_values_split_outside_brackets_and_quotes() {
        let (k, v) = parse_set("wheel.mesh=[12,192,1], [24,384,2]").unwrap();
        assert_eq!(k, "wheel.mesh");
        assert_eq!(v, ["[12,192,1]", "[24,384,2]"]);
        let (_, v) = parse_set("rolling.omega=250, 300,").unwrap();
        assert_eq!(v, ["250", "300"]);
        let (_, v) = parse_set("name=\"a,b\",c").unwrap();
        assert_eq!(v, ["\"a,b\"", "c"]);
        assert!(parse_set("wheel.mesh=[12,192,1").is_err());
        assert!(parse_set("=1").is_err() && parse_set("k=").is_err());
    }
}
