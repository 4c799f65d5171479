//! The one CSV record writer of the crate: every CSV file softway writes (`history.csv`,
//! `contact_nodes.csv`, `sweep.csv`, `compare.csv`, `converge.csv`, `creep_curve.csv`,
//! `creep_ladder.csv`, `passes.csv`, `modes.csv`, ...) builds its lines here, the streamed
//! tables through [`crate::output::files::CsvWriter`], which calls [`push_field`] too.
//!
//! A field is quoted per RFC 4180 when it needs to be: when it holds a comma, a double quote,
//! a carriage return or a line feed, it is written between double quotes with its inner
//! quotes doubled; any other field is written as is. Run labels, sweep values, treatment
//! names and mode kinds are the text that can need it (`"h = 0.1, soft way"`); numbers never
//! do, so a table of numbers is written byte for byte as before.
//!
//! Why not the `csv` crate: the writers stream rows of numbers whose columns each keep their
//! own formatting (`{:e}` in the histories, `{:.4}` or `{:.6e}` in the reports, integers,
//! empty cells for a missing value), formatted into one reused line buffer per row. The crate
//! would take those same strings and add only this quoting rule, a dependency and a second
//! buffering layer under the atomic `.part` file; the rule itself is the few lines below, and
//! the tests read the files back with the `csv` crate's parser (a dev-dependency), which is
//! the independent check that they are valid CSV.

use std::borrow::Cow;

/// True when `field` must be quoted: it holds a comma, a double quote, CR or LF.
pub fn needs_quotes(field: &str) -> bool {
    field.contains([',', '"', '\r', '\n'])
}

/// `field` as it is written into a CSV line: between double quotes with its quotes doubled
/// when [`needs_quotes`], else unchanged.
pub fn field(field: &str) -> Cow<'_, str> {
    if needs_quotes(field) {
        Cow::Owned(format!("\"{}\"", field.replace('"', "\"\"")))
    } else {
        Cow::Borrowed(field)
    }
}

/// Appends `f` to `line` as one CSV field (see [`field`]); no separator.
pub fn push_field(line: &mut String, f: &str) {
    line.push_str(&field(f));
}

/// Appends one record to `out`: the cells through [`field`], separated by commas, then `\n`.
pub fn push_record<I, S>(out: &mut String, cells: I)
where
    I: IntoIterator<Item = S>,
    S: AsRef<str>,
{
    for (i, c) in cells.into_iter().enumerate() {
        if i > 0 {
            out.push(',');
        }
        push_field(out, c.as_ref());
    }
    out.push('\n');
}

/// One record as a line of its own (with its `\n`), see [`push_record`].
pub fn record<I, S>(cells: I) -> String
where
    I: IntoIterator<Item = S>,
    S: AsRef<str>,
{
    let mut s = String::new();
    push_record(&mut s, cells);
    s
}

/// The cells of one line of a CSV file of numbers (a measured profile's `x_m,z_m` rows):
/// split at the commas, since no number holds one, each with its surrounding blanks and the
/// RFC 4180 quotes of a quoted cell (`"1.5e-3"`, as some spreadsheets write every field)
/// taken off. The readers of the crate's input files of numbers (`growth.file`,
/// `irregularity.file`) read their rows through it.
pub fn number_cells(line: &str) -> impl Iterator<Item = &str> {
    line.split(',').map(|c| {
        let c = c.trim();
        c.strip_prefix('"')
            .and_then(|c| c.strip_suffix('"'))
            .unwrap_or(c)
            .trim()
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fields_are_quoted_only_when_needed() {
        assert_eq!(field("h = 0.1"), "h = 0.1");
        assert_eq!(field("1.5e-3"), "1.5e-3");
        assert_eq!(field(""), "");
        assert_eq!(field("h = 0.1, soft way"), "\"h = 0.1, soft way\"");
        assert_eq!(field("the \"soft\" way"), "\"the \"\"soft\"\" way\"");
        assert_eq!(field("two\nlines"), "\"two\nlines\"");
        assert_eq!(field("cr\r"), "\"cr\r\"");
        assert_eq!(record(["a,b", "2", "", "c\"d"]), "\"a,b\",2,,\"c\"\"d\"\n");
    }

    #[test]
    fn number_cells_take_off_blanks_and_quotes() {
        let c: Vec<&str> = number_cells(" 1.5e-3 ,\"2\", \" -3 \",").collect();
        assert_eq!(c, ["1.5e-3", "2", "-3", ""]);
        let c: Vec<&str> = number_cells("\"x_m\",\"z_m\"").collect();
        assert_eq!(c, ["x_m", "z_m"]);
    }
}
