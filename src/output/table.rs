//! Tables of results held in memory: named columns of numbers with their units, and an
//! optional key column of text (the run label of a bar's history, the node of a contact
//! row). [`Columns::write_csv`] writes one as the command line's CSV files, byte for byte
//! (through [`CsvWriter`], the same formatting: `{:e}` for numbers, the key's text as is).
//!
//! A run either keeps its rows in memory ([`crate::run::run`]) or streams them to a CSV file
//! as it goes ([`Rows`], for the command line: a long run's memory stays flat); a streamed
//! table keeps its columns' names and units but no rows, and says where the rows went
//! ([`Columns::streamed_to`]).

use super::files::CsvWriter;
use std::path::{Path, PathBuf};

/// One numeric column: its name (the CSV header, e.g. `contact_force_N`), its unit (`N`;
/// `1` for a count or a state) and its values, one per row.
#[derive(Debug, Clone, PartialEq)]
pub struct Column {
    /// Name, as in the CSV header.
    pub name: String,
    /// Unit (SI; `1` for counts and states).
    pub unit: String,
    /// Values, one per row.
    pub values: Vec<f64>,
}

/// A key column of text: row `i` reads `labels[codes[i]]` (a few distinct labels, many rows).
#[derive(Debug, Clone, PartialEq)]
pub struct KeyColumn {
    /// Name, as in the CSV header (e.g. `run`, `node`).
    pub name: String,
    /// The distinct labels.
    pub labels: Vec<String>,
    /// Per row, the index of its label in `labels`.
    pub codes: Vec<u32>,
}

impl KeyColumn {
    /// The text of row `i`.
    pub fn text(&self, i: usize) -> &str {
        &self.labels[self.codes[i] as usize]
    }
}

/// A table: an optional key column, then numeric columns, all of one length.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Columns {
    key: Option<KeyColumn>,
    columns: Vec<Column>,
    rows: usize,
    streamed: Option<PathBuf>,
    /// Per numeric column, whether a NaN is a missing value, written as an empty cell
    /// ([`Columns::empty_when_nan`]).
    empty_nan: Vec<bool>,
}

impl Columns {
    /// An empty table of numeric columns `(name, unit)`.
    pub fn new(spec: &[(&str, &str)]) -> Self {
        Self {
            key: None,
            columns: spec
                .iter()
                .map(|(name, unit)| Column {
                    name: (*name).into(),
                    unit: (*unit).into(),
                    values: Vec::new(),
                })
                .collect(),
            rows: 0,
            streamed: None,
            empty_nan: Vec::new(),
        }
    }

    /// The table with the columns `names` holding NaN where a row has no value: the CSV
    /// writes an empty cell there (`CsvWriter::empty_when_nan`); in memory the value stays
    /// NaN.
    pub fn empty_when_nan(mut self, names: &[&str]) -> Self {
        self.empty_nan = self
            .columns
            .iter()
            .map(|c| names.contains(&c.name.as_str()))
            .collect();
        self
    }

    /// An empty table with a key column `key` of the given labels before the numeric ones.
    pub fn keyed(key: &str, labels: Vec<String>, spec: &[(&str, &str)]) -> Self {
        let mut t = Self::new(spec);
        t.key = Some(KeyColumn {
            name: key.into(),
            labels,
            codes: Vec::new(),
        });
        t
    }

    /// Room for `rows` more rows (so that a run's pushes do not reallocate).
    pub fn reserve(&mut self, rows: usize) {
        if let Some(k) = &mut self.key {
            k.codes.reserve(rows);
        }
        for c in &mut self.columns {
            c.values.reserve(rows);
        }
    }

    /// Appends a row: the key's label index (ignored without a key column) and one value
    /// per numeric column.
    ///
    /// # Panics
    /// If `values` has not one value per column (a programming error).
    pub fn push(&mut self, key: u32, values: &[f64]) {
        assert_eq!(values.len(), self.columns.len(), "one value per column");
        if let Some(k) = &mut self.key {
            k.codes.push(key);
        }
        for (c, &v) in self.columns.iter_mut().zip(values) {
            c.values.push(v);
        }
        self.rows += 1;
    }

    /// Rows held (0 for a streamed table).
    pub fn len(&self) -> usize {
        self.rows
    }

    /// True when no row is held.
    pub fn is_empty(&self) -> bool {
        self.rows == 0
    }

    /// The numeric columns.
    pub fn columns(&self) -> &[Column] {
        &self.columns
    }

    /// The values of the numeric column `name`.
    pub fn column(&self, name: &str) -> Option<&[f64]> {
        self.columns
            .iter()
            .find(|c| c.name == name)
            .map(|c| c.values.as_slice())
    }

    /// The key column, if any.
    pub fn key(&self) -> Option<&KeyColumn> {
        self.key.as_ref()
    }

    /// The CSV header: the key's name (if any), then the columns' names.
    pub fn header(&self) -> Vec<&str> {
        self.key
            .iter()
            .map(|k| k.name.as_str())
            .chain(self.columns.iter().map(|c| c.name.as_str()))
            .collect()
    }

    /// The CSV file the rows were streamed to instead of being held (see `Rows`).
    pub fn streamed_to(&self) -> Option<&Path> {
        self.streamed.as_deref()
    }

    /// Writes the table as CSV into `path` (atomically, through `CsvWriter`: the same
    /// bytes as the file streamed during a run). A streamed table is copied from its file.
    ///
    /// # Errors
    /// I/O errors, with the path in the message.
    pub fn write_csv(&self, path: &Path) -> std::io::Result<()> {
        if let Some(src) = &self.streamed {
            if src != path {
                let bytes = std::fs::read(src).map_err(|e| {
                    std::io::Error::new(e.kind(), format!("{}: {e}", src.display()))
                })?;
                super::files::write_atomic(path, &bytes)?;
            }
            return Ok(());
        }
        let mut csv = CsvWriter::create(path, &self.header())?;
        csv.empty_when_nan(&self.empty_nan);
        let mut row = vec![0.0; self.columns.len()];
        for i in 0..self.rows {
            for (x, c) in row.iter_mut().zip(&self.columns) {
                *x = c.values[i];
            }
            csv.row(self.key.as_ref().map(|k| k.text(i)), &row)?;
        }
        csv.finish().map(|_| ())
    }
}

/// Where a run's rows go: into a [`Columns`] in memory, or streamed to a CSV file row by
/// row (the same bytes [`Columns::write_csv`] would write).
#[derive(Debug)]
pub enum Rows {
    /// Held in memory.
    Memory(Columns),
    /// Streamed to a file; `table` keeps the names and units.
    File {
        /// The file being written.
        csv: CsvWriter,
        /// Its final path.
        path: PathBuf,
        /// The table's columns, without rows.
        table: Columns,
    },
}

impl Rows {
    /// Rows for `table`: streamed to `file` when given (created now, header written), else
    /// held in memory with room for `rows` rows.
    ///
    /// # Errors
    /// I/O errors creating the file.
    pub fn open(mut table: Columns, file: Option<&Path>, rows: usize) -> std::io::Result<Self> {
        match file {
            Some(path) => {
                let mut csv = CsvWriter::create(path, &table.header())?;
                csv.empty_when_nan(&table.empty_nan);
                Ok(Rows::File {
                    csv,
                    path: path.to_path_buf(),
                    table,
                })
            }
            None => {
                table.reserve(rows);
                Ok(Rows::Memory(table))
            }
        }
    }

    /// Appends a row (key label index, values).
    ///
    /// # Errors
    /// I/O errors of a streamed file.
    pub fn push(&mut self, key: u32, values: &[f64]) -> std::io::Result<()> {
        match self {
            Rows::Memory(t) => {
                t.push(key, values);
                Ok(())
            }
            Rows::File { csv, table, .. } => {
                csv.row(table.key.as_ref().map(|k| &*k.labels[key as usize]), values)
            }
        }
    }

    /// The table: the rows held, or (streamed) the file closed and named in the table.
    ///
    /// # Errors
    /// I/O errors closing the file.
    pub fn finish(self) -> std::io::Result<Columns> {
        match self {
            Rows::Memory(t) => Ok(t),
            Rows::File {
                csv,
                path,
                mut table,
            } => {
                csv.finish()?;
                table.streamed = Some(path);
                Ok(table)
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A table written from memory and the same rows streamed give the same bytes, and the
    /// columns read back as pushed.
    #[test]
    fn memory_and_streamed_tables_write_the_same_bytes() {
        let dir = std::env::temp_dir().join(format!("softway-table-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let spec = [("t_s", "s"), ("force_N", "N")];
        let table = || Columns::keyed("run", vec!["a".into(), "b".into()], &spec);
        let rows = [(0, [0.0, 1.5]), (1, [1e-3, -2.25e7]), (0, [f64::NAN, 0.1])];
        let mut mem = Rows::open(table(), None, 3).unwrap();
        let streamed_path = dir.join("streamed.csv");
        let mut file = Rows::open(table(), Some(&streamed_path), 0).unwrap();
        for (k, v) in &rows {
            mem.push(*k, v).unwrap();
            file.push(*k, v).unwrap();
        }
        let mem = mem.finish().unwrap();
        let file = file.finish().unwrap();
        assert_eq!(file.streamed_to(), Some(streamed_path.as_path()));
        assert_eq!((mem.len(), file.len()), (3, 0));
        assert_eq!(mem.column("force_N").unwrap()[1], -2.25e7);
        assert_eq!(mem.key().unwrap().text(1), "b");
        assert_eq!(mem.header(), ["run", "t_s", "force_N"]);
        let from_memory = dir.join("memory.csv");
        mem.write_csv(&from_memory).unwrap();
        let text = std::fs::read_to_string(&from_memory).unwrap();
        assert_eq!(
            text,
            "run,t_s,force_N\na,0e0,1.5e0\nb,1e-3,-2.25e7\na,NaN,1e-1\n"
        );
        assert_eq!(std::fs::read(&streamed_path).unwrap(), text.as_bytes());
        // A streamed table saved elsewhere is a copy of its file.
        let copy = dir.join("copy.csv");
        file.write_csv(&copy).unwrap();
        assert_eq!(std::fs::read(&copy).unwrap(), text.as_bytes());
        let _ = std::fs::remove_dir_all(&dir);
    }

    /// A column whose NaN is a missing value is written with an empty cell there, in memory
    /// and streamed alike; NaN elsewhere stays `NaN`.
    #[test]
    fn a_missing_value_is_an_empty_cell() {
        let dir = std::env::temp_dir().join(format!("softway-missing-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let spec = [("t_s", "s"), ("centre_m", "m")];
        let rows = [[0.0, f64::NAN], [f64::NAN, 2e-3]];
        let mut mem = Columns::new(&spec).empty_when_nan(&["centre_m"]);
        let path = dir.join("streamed.csv");
        let mut file = Rows::open(
            Columns::new(&spec).empty_when_nan(&["centre_m"]),
            Some(&path),
            0,
        )
        .unwrap();
        for r in &rows {
            mem.push(0, r);
            file.push(0, r).unwrap();
        }
        file.finish().unwrap();
        assert!(mem.column("centre_m").unwrap()[0].is_nan());
        let from_memory = dir.join("memory.csv");
        mem.write_csv(&from_memory).unwrap();
        let text = std::fs::read_to_string(&from_memory).unwrap();
        assert_eq!(text, "t_s,centre_m\n0e0,\nNaN,2e-3\n");
        assert_eq!(std::fs::read_to_string(&path).unwrap(), text);
        let _ = std::fs::remove_dir_all(&dir);
    }
}
