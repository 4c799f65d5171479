//! The terminal's report: every line within [`WIDTH`] columns, numbers in readable units.
//!
//! A command's report is its lines of text and, for `sweep`, `converge` and `compare`, a
//! table in markdown (the `.md` file the command writes). [`fit`] lays both out for the
//! terminal:
//!
//! - a table (a run of lines starting with `|`) is printed as aligned columns, its numbers
//!   in units a reader takes in at a glance (forces in kN or MN, lengths in mm or um, times
//!   in ms or us, relative errors in %: the column's name says which) with up to four significant
//!   digits; when its columns are wider than the terminal, the table is printed in blocks of
//!   columns, each repeating the columns that name a row (the run's label, or the swept keys
//!   before `status`), and a cell wider than its room is broken over lines;
//! - any other line longer than [`WIDTH`] is broken at its `; ` (then at its spaces), the
//!   continuation indented.
//!
//! The files keep every digit: the terminal's table is a reading of `sweep.md`,
//! `converge.md` or `compare.md`, never a replacement for it.

/// The width every printed line keeps within, in characters.
pub const WIDTH: usize = 100;

/// The report `lines` laid out for a terminal of `width` columns, each line to be printed
/// after `indent` spaces (the indent counted in the width).
pub fn fit(lines: &[String], indent: usize, width: usize) -> Vec<String> {
    let room = width.saturating_sub(indent).max(20);
    let mut out = Vec::new();
    let mut i = 0;
    while i < lines.len() {
        if is_table_line(&lines[i]) {
            let start = i;
            while i < lines.len() && is_table_line(&lines[i]) {
                i += 1;
            }
            out.extend(table(&lines[start..i], room));
        } else {
            out.extend(wrap(&lines[i], room, 2));
            i += 1;
        }
    }
    out
}

fn is_table_line(line: &str) -> bool {
    line.trim_start().starts_with('|')
}

/// `line` broken into lines of at most `width` characters: at its `; ` first (a clause
/// per line where clauses are long), then at spaces; continuation lines start with `hang`
/// spaces. A word longer than the room is cut.
pub fn wrap(line: &str, width: usize, hang: usize) -> Vec<String> {
    let line = line.trim_end();
    if line.chars().count() <= width {
        return vec![line.to_string()];
    }
    let lead: String = line.chars().take_while(|c| *c == ' ').collect();
    let body = &line[lead.len()..];
    let first_room = width.saturating_sub(lead.len()).max(10);
    let cont_lead = format!("{lead}{}", " ".repeat(hang));
    let cont_room = width.saturating_sub(cont_lead.len()).max(10);
    // Clauses (`a; b; c` -> `a;`, `b;`, `c`), each packed whole when it fits.
    let clauses: Vec<String> = {
        let parts: Vec<&str> = body.split("; ").collect();
        let n = parts.len();
        parts
            .iter()
            .enumerate()
            .map(|(k, p)| {
                if k + 1 < n {
                    format!("{p};")
                } else {
                    (*p).to_string()
                }
            })
            .collect()
    };
    let mut out: Vec<String> = Vec::new();
    let mut cur = String::new();
    let room = |out: &Vec<String>| {
        if out.is_empty() {
            first_room
        } else {
            cont_room
        }
    };
    let flush = |cur: &mut String, out: &mut Vec<String>| {
        if !cur.is_empty() {
            let l = if out.is_empty() { &lead } else { &cont_lead };
            out.push(format!("{l}{cur}"));
            cur.clear();
        }
    };
    for clause in clauses {
        let joined = if cur.is_empty() {
            clause.chars().count()
        } else {
            cur.chars().count() + 1 + clause.chars().count()
        };
        if joined <= room(&out) {
            if !cur.is_empty() {
                cur.push(' ');
            }
            cur.push_str(&clause);
            continue;
        }
        flush(&mut cur, &mut out);
        if clause.chars().count() <= room(&out) {
            cur.push_str(&clause);
            continue;
        }
        // A clause longer than a line: by words.
        for word in clause.split(' ') {
            let mut word = word.to_string();
            loop {
                let r = room(&out);
                let need = if cur.is_empty() {
                    word.chars().count()
                } else {
                    cur.chars().count() + 1 + word.chars().count()
                };
                if need <= r {
                    if !cur.is_empty() {
                        cur.push(' ');
                    }
                    cur.push_str(&word);
                    break;
                }
                if !cur.is_empty() {
                    flush(&mut cur, &mut out);
                    continue;
                }
                // A word longer than the room: cut it.
                let head: String = word.chars().take(r).collect();
                word = word.chars().skip(r).collect();
                cur.push_str(&head);
                flush(&mut cur, &mut out);
                if word.is_empty() {
                    break;
                }
            }
        }
    }
    flush(&mut cur, &mut out);
    out
}

/// A markdown table's lines laid out in `width` columns (see the module's documentation).
pub fn table(lines: &[String], width: usize) -> Vec<String> {
    let mut rows: Vec<Vec<String>> = lines
        .iter()
        .map(|l| cells(l))
        .filter(|c| !is_rule(c))
        .collect();
    if rows.is_empty() {
        return Vec::new();
    }
    let ncol = rows.iter().map(Vec::len).max().unwrap_or(0);
    for r in &mut rows {
        r.resize(ncol, String::new());
    }
    let mut header = rows.remove(0);
    let mut numeric = vec![false; ncol];
    if header.first().map(String::as_str) == Some("figure") {
        // `converge.md`: a figure per row, its unit in its name; the rungs and the limit
        // in its unit, the observed orders as they are.
        let cols: Vec<usize> = (1..ncol)
            .filter(|&c| !header[c].starts_with("order"))
            .collect();
        for r in &mut rows {
            let read = readable(&r[0], cols.iter().map(|&c| r[c].as_str()));
            if let Some((name, values)) = read {
                r[0] = name;
                for (&c, v) in cols.iter().zip(values) {
                    r[c] = v;
                }
            }
        }
        for n in numeric.iter_mut().skip(1) {
            *n = true;
        }
    } else {
        for (c, numeric) in numeric.iter_mut().enumerate() {
            let read = readable(&header[c], rows.iter().map(|r| r[c].as_str()));
            if let Some((name, values)) = read {
                header[c] = name;
                for (r, v) in rows.iter_mut().zip(values) {
                    r[c] = v;
                }
                *numeric = true;
            }
        }
    }
    // The columns that name a row: the swept keys before `status`, else the first.
    let keep = header
        .iter()
        .position(|h| h == "status")
        .filter(|&p| p > 0)
        .unwrap_or(1)
        .min(ncol);
    let gap = 2;
    let natural: Vec<usize> = (0..ncol)
        .map(|c| {
            std::iter::once(&header[c])
                .chain(rows.iter().map(|r| &r[c]))
                .map(|s| s.chars().count())
                .max()
                .unwrap_or(0)
        })
        .collect();
    // The kept columns take at most three fifths of the width between them; every other
    // column at most what is left beside them.
    let mut w = natural.clone();
    let kept: usize = w[..keep].iter().sum::<usize>() + gap * keep.saturating_sub(1);
    if kept > width * 3 / 5 {
        let each = (width * 3 / 5).saturating_sub(gap * keep.saturating_sub(1)) / keep.max(1);
        for x in &mut w[..keep] {
            *x = (*x).min(each.max(4));
        }
    }
    let kept: usize = w[..keep].iter().sum::<usize>() + gap * keep.saturating_sub(1);
    let rest_room = width.saturating_sub(kept + gap).max(4);
    for x in &mut w[keep..] {
        *x = (*x).min(rest_room);
    }
    // Blocks of columns.
    let mut blocks: Vec<Vec<usize>> = Vec::new();
    let mut cur: Vec<usize> = Vec::new();
    let mut used = kept;
    for c in keep..ncol {
        if !cur.is_empty() && used + gap + w[c] > width {
            blocks.push(std::mem::take(&mut cur));
            used = kept;
        }
        cur.push(c);
        used += gap + w[c];
    }
    if !cur.is_empty() || blocks.is_empty() {
        blocks.push(cur);
    }
    let mut out = Vec::new();
    for (b, block) in blocks.iter().enumerate() {
        if b > 0 {
            out.push(String::new());
        }
        let cols: Vec<usize> = (0..keep).chain(block.iter().copied()).collect();
        let render = |row: &[String], out: &mut Vec<String>| {
            let pieces: Vec<Vec<String>> = cols.iter().map(|&c| chop(&row[c], w[c])).collect();
            let height = pieces.iter().map(Vec::len).max().unwrap_or(1);
            for k in 0..height {
                let mut line = String::new();
                for (j, &c) in cols.iter().enumerate() {
                    let text = pieces[j].get(k).map_or("", String::as_str);
                    if j > 0 {
                        line.push_str(&" ".repeat(gap));
                    }
                    let pad = w[c].saturating_sub(text.chars().count());
                    if numeric[c] {
                        line.push_str(&" ".repeat(pad));
                        line.push_str(text);
                    } else {
                        line.push_str(text);
                        line.push_str(&" ".repeat(pad));
                    }
                }
                out.push(line.trim_end().to_string());
            }
        };
        render(&header, &mut out);
        let rule: Vec<String> = cols.iter().map(|&c| "-".repeat(w[c])).collect();
        out.push(rule.join(&" ".repeat(gap)));
        for r in &rows {
            render(r, &mut out);
        }
    }
    out
}

/// The cells of a markdown table's line.
fn cells(line: &str) -> Vec<String> {
    let t = line.trim();
    let t = t.strip_prefix('|').unwrap_or(t);
    let t = t.strip_suffix('|').unwrap_or(t);
    t.split('|').map(|c| c.trim().to_string()).collect()
}

/// Whether a row is the header's rule (`---`, `:--:`).
fn is_rule(cells: &[String]) -> bool {
    cells
        .iter()
        .all(|c| !c.is_empty() && c.chars().all(|ch| matches!(ch, '-' | ':')))
}

/// `text` cut into pieces of at most `w` characters, at spaces where it can.
fn chop(text: &str, w: usize) -> Vec<String> {
    if text.chars().count() <= w || w == 0 {
        return vec![text.to_string()];
    }
    wrap(text, w, 0)
}

/// A column's name and cells in readable units, when every cell is a number (or empty, or
/// `-`): `None` for a column of text. The unit is read off the name's end (`_N`, `_m`,
/// `_s`, `_Pa`), relative errors (`..._error`, `energy_change`) are given in percent.
fn readable<'a>(name: &str, cells: impl Iterator<Item = &'a str>) -> Option<(String, Vec<String>)> {
    let raw: Vec<&str> = cells.collect();
    let values: Vec<Option<f64>> = raw
        .iter()
        .map(|c| match *c {
            "" | "-" => Ok(None),
            s => s.parse::<f64>().map(Some),
        })
        .collect::<Result<_, _>>()
        .ok()?;
    let finite: Vec<f64> = values.iter().flatten().copied().collect();
    if finite.is_empty() {
        return None;
    }
    let largest = finite
        .iter()
        .filter(|v| v.is_finite())
        .fold(0.0_f64, |m, v| m.max(v.abs()));
    let (stem, unit) = split_unit(name);
    let (scale, shown, signed) = match unit {
        "N" => prefixed(largest, &[(1e6, "MN"), (1e3, "kN")], "N"),
        "Pa" => prefixed(largest, &[(1e9, "GPa"), (1e6, "MPa"), (1e3, "kPa")], "Pa"),
        "m" if largest > 0.0 && largest < 1e-3 => (1e6, "um", false),
        "m" if largest > 0.0 && largest < 1.0 => (1e3, "mm", false),
        "s" if largest > 0.0 && largest < 1e-3 => (1e6, "us", false),
        "s" if largest > 0.0 && largest < 1.0 => (1e3, "ms", false),
        "" if stem.ends_with("_error") || stem == "energy_change" => (100.0, "%", true),
        u => (1.0, u, false),
    };
    let shown_name = if shown.is_empty() {
        stem.to_string()
    } else if shown == "%" {
        format!("{stem} %")
    } else {
        format!("{stem}_{shown}")
    };
    let integers = scale == 1.0 && finite.iter().all(|v| v.fract() == 0.0 && v.abs() < 1e15);
    let cells = raw
        .iter()
        .zip(&values)
        .map(|(c, v)| match v {
            None => (*c).to_string(),
            Some(v) if integers => grouped(*v),
            // A short number keeps its text (an observed order, `0.63`).
            Some(_) if scale == 1.0 && !signed && significant(c) <= 4 => (*c).to_string(),
            Some(v) => {
                // No more digits than the file gives (`0.0009` s: `0.9` ms, not `0.9000`).
                let s = number_to(v * scale, significant(c).clamp(1, 4));
                if (signed || c.starts_with('+')) && *v > 0.0 && v.is_finite() {
                    format!("+{s}")
                } else {
                    s
                }
            }
        })
        .collect();
    Some((shown_name, cells))
}

/// The significant digits a number's text shows (`0.63`: 2, `90.00000`: 7, `6.40e-3`: 3).
fn significant(text: &str) -> usize {
    let mantissa = text.split(['e', 'E']).next().unwrap_or(text);
    mantissa
        .chars()
        .filter(char::is_ascii_digit)
        .skip_while(|c| *c == '0')
        .count()
}

/// A column name's stem and unit: `mean_contact_force_N` -> (`mean_contact_force`, `N`);
/// a name without one of the units read here -> (name, "").
fn split_unit(name: &str) -> (&str, &str) {
    for unit in ["N", "Pa", "m", "s"] {
        if let Some(stem) = name.strip_suffix(unit).and_then(|s| s.strip_suffix('_')) {
            if !stem.is_empty() {
                return (stem, unit);
            }
        }
    }
    (name, "")
}

/// The scale and unit of a quantity of largest magnitude `largest`: the first prefix it
/// reaches, else the base unit.
fn prefixed(
    largest: f64,
    prefixes: &[(f64, &'static str)],
    base: &'static str,
) -> (f64, &'static str, bool) {
    prefixes
        .iter()
        .find(|(p, _)| largest >= *p)
        .map_or((1.0, base, false), |(p, u)| (1.0 / p, *u, false))
}

/// A whole number with its thousands grouped by commas (`54,860`).
pub fn grouped(v: f64) -> String {
    let digits = format!("{}", v.abs() as u64);
    let mut s = String::new();
    for (i, ch) in digits.chars().enumerate() {
        if i > 0 && (digits.len() - i) % 3 == 0 {
            s.push(',');
        }
        s.push(ch);
    }
    if v < 0.0 {
        format!("-{s}")
    } else {
        s
    }
}

/// A count: whole and below 1e9 with its thousands grouped (`2,000`), else as `1.500e9`.
pub fn grouped_or_sci(v: f64) -> String {
    if v.fract() == 0.0 && v.abs() < 1e9 {
        grouped(v)
    } else {
        format!("{v:.3e}")
    }
}

/// `v` with `sig` significant digits (1 to 17), in plain notation from 1e-3 to 1e6 and as
/// `1.234e-5` outside; 0 as `0`.
pub fn number_to(v: f64, sig: usize) -> String {
    let sig = sig.clamp(1, 17) as i32;
    if !v.is_finite() {
        return format!("{v}");
    }
    if v == 0.0 {
        return "0".into();
    }
    let a = v.abs();
    if (1e-3..1e6).contains(&a) {
        // The decimals of four significant digits, after rounding (999.96 -> 1000).
        let d = a.log10().floor() as i32;
        let unit = 10f64.powi(d - (sig - 1));
        let d = ((a / unit).round() * unit).log10().floor() as i32;
        let decimals = (sig - 1 - d).max(0) as usize;
        format!("{v:.decimals$}")
    } else {
        format!("{v:.prec$e}", prec = (sig - 1) as usize)
    }
}

/// A quantity in the SI prefix that puts it between 1 and 1000, four significant digits:
/// `quantity(839_750.0, "N")` = `839.8 kN`, `quantity(2e-6, "s")` = `2.000 us`.
pub fn quantity(v: f64, unit: &str) -> String {
    if !v.is_finite() {
        return format!("{v} {unit}");
    }
    if v == 0.0 {
        return format!("0 {unit}");
    }
    const PREFIXES: [(f64, &str); 7] = [
        (1e9, "G"),
        (1e6, "M"),
        (1e3, "k"),
        (1.0, ""),
        (1e-3, "m"),
        (1e-6, "u"),
        (1e-9, "n"),
    ];
    let a = v.abs();
    if !(1e-9 * (1.0 - 5e-5)..1e12).contains(&a) {
        return format!("{v:.3e} {unit}");
    }
    let (p, name) = PREFIXES
        .iter()
        .find(|(p, _)| a >= *p * (1.0 - 5e-5))
        .copied()
        .unwrap_or((1e-9, "n"));
    let x = v / p;
    let digits = x.abs().log10().floor().max(0.0) as usize;
    let decimals = 3usize.saturating_sub(digits);
    format!("{x:.decimals$} {name}{unit}")
}

/// The time left of a job `pos` of `len` steps into it after `elapsed` seconds, at the mean
/// rate since its start: `about 3 min 05 s left`, rounded to 5 s from a minute on and to a
/// minute from an hour on (a reading that does not flicker); `estimating` before a
/// hundredth of the steps.
pub fn time_left(elapsed: f64, pos: u64, len: u64) -> String {
    if len == 0 || pos * 100 < len || pos == 0 {
        return "estimating time left".into();
    }
    let left = elapsed * (len.saturating_sub(pos)) as f64 / pos as f64;
    let rounded = if left >= 3600.0 {
        (left / 60.0).round() * 60.0
    } else if left >= 60.0 {
        (left / 5.0).round() * 5.0
    } else {
        left.round()
    };
    format!("about {} left", duration(rounded))
}

/// A duration for a person: `42 s`, `3 min 05 s`, `1 h 02 min`.
pub fn duration(seconds: f64) -> String {
    if !seconds.is_finite() || seconds < 0.0 {
        return "-".into();
    }
    let s = seconds.round() as u64;
    if s < 60 {
        format!("{s} s")
    } else if s < 3600 {
        format!("{} min {:02} s", s / 60, s % 60)
    } else {
        format!("{} h {:02} min", s / 3600, (s % 3600) / 60)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_keep_four_significant_digits() {
        assert_eq!(number_to(839_750.946_28, 4), "839751");
        assert_eq!(number_to(839.75, 4), "839.8");
        assert_eq!(number_to(0.012346, 4), "0.01235");
        assert_eq!(number_to(0.9, 1), "0.9");
        assert_eq!(number_to(0.0009, 1), "9e-4");
        assert_eq!(number_to(999.96, 4), "1000");
        assert_eq!(number_to(2.2e-16, 4), "2.200e-16");
        assert_eq!(grouped(54860.0), "54,860");
        assert_eq!(grouped(400.0), "400");
        assert_eq!(quantity(839_750.0, "N"), "839.8 kN");
        assert_eq!(quantity(2e-6, "s"), "2.000 us");
        assert_eq!(quantity(1e-3, "m"), "1.000 mm");
        assert_eq!(quantity(7301.2, "Hz"), "7.301 kHz");
        assert_eq!(duration(185.0), "3 min 05 s");
    }

    #[test]
    fn a_wide_table_is_printed_in_blocks_that_fit() {
        let mut lines = vec![
            "| run | a_N | b_m | c_s | d_error | e | f | g | h |".to_string(),
            "|---|---|---|---|---|---|---|---|---|".to_string(),
        ];
        for i in 0..3 {
            lines.push(format!(
                "| a run with a long label {i} | 854120.9{i} | 0.00{i}1 | 0.0{i}1 | 0.1 | {} | {} | {} | text of a fair length that goes on |",
                "x".repeat(30),
                "y".repeat(30),
                "z".repeat(30)
            ));
        }
        let out = table(&lines, 60);
        assert!(out.iter().all(|l| l.chars().count() <= 60), "{out:#?}");
        // Every block repeats the label; the forces are in kN, the errors in percent.
        let blocks = out.iter().filter(|l| l.starts_with("run")).count();
        assert!(blocks >= 3, "{out:#?}");
        assert!(out[0].contains("a_kN") && out[0].contains("b_mm") && out[0].contains("c_ms"));
        assert!(out.iter().any(|l| l.contains("854.1")), "{out:#?}");
        assert!(out.iter().any(|l| l.contains("+10")), "{out:#?}");
    }

    #[test]
    fn long_lines_break_at_their_clauses() {
        let line = format!(
            "  {}; {}; {}",
            "a".repeat(40),
            "b".repeat(40),
            "c ".repeat(60)
        );
        let out = wrap(&line, 50, 2);
        assert!(out.iter().all(|l| l.chars().count() <= 50), "{out:#?}");
        assert_eq!(out[0], format!("  {};", "a".repeat(40)));
        assert!(out[1].starts_with("    b"));
        let words: Vec<&str> = out.iter().flat_map(|l| l.split_whitespace()).collect();
        let orig: Vec<String> = line.split_whitespace().map(String::from).collect();
        assert_eq!(words.len(), orig.len());
    }

    /// The time left, from the mean rate since the start: with every step's time drawn at
    /// random between 0.5 and 1.5 ms, the reading taken every 1 % of the run never goes up by
    /// more than its rounding, and it falls to zero at the end.
    #[test]
    fn the_time_left_does_not_jump() {
        let len = 200_000u64;
        let mut seed = 12345u64;
        let mut elapsed = 0.0;
        let mut last: Option<f64> = None;
        let seconds = |s: &str| -> f64 {
            // "about 3 min 05 s left", "about 42 s left", "about 1 h 02 min left"
            let words: Vec<&str> = s.split_whitespace().collect();
            let mut t = 0.0;
            for w in words.windows(2) {
                if let Ok(v) = w[0].parse::<f64>() {
                    t += v * match w[1] {
                        "h" => 3600.0,
                        "min" => 60.0,
                        _ => 1.0,
                    };
                }
            }
            t
        };
        for pos in 1..=len {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            let u = (seed >> 11) as f64 / (1u64 << 53) as f64;
            elapsed += 1e-3 * (0.5 + u);
            if pos % (len / 100) == 0 {
                let text = time_left(elapsed, pos, len);
                let t = seconds(&text);
                if let Some(prev) = last {
                    assert!(t <= prev + 5.0, "{text} after {prev} s at step {pos}");
                }
                last = Some(t);
            }
        }
        assert_eq!(time_left(elapsed, len, len), "about 0 s left");
        assert_eq!(time_left(1.0, 10, len), "estimating time left");
    }
}
