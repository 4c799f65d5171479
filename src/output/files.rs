//! Atomic file writing and a streaming CSV writer (its fields through [`super::csv`]).

use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

/// Writes `contents` to `path` atomically (temporary file in the same folder, then rename).
///
/// # Errors
/// The I/O error, with the path in its message.
pub fn write_atomic(path: &Path, contents: &[u8]) -> std::io::Result<()> {
    let tmp = tmp_path(path);
    let res = (|| {
        let mut f = File::create(&tmp)?;
        f.write_all(contents)?;
        f.sync_all()?;
        std::fs::rename(&tmp, path)
    })();
    if res.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    res.map_err(|e| std::io::Error::new(e.kind(), format!("{}: {e}", path.display())))
}

/// Serializes `value` as pretty JSON into `path`, atomically.
///
/// # Errors
/// I/O errors.
pub fn write_json<T: serde::Serialize>(path: &Path, value: &T) -> std::io::Result<()> {
    let mut s = serde_json::to_string_pretty(value).map_err(std::io::Error::other)?;
    s.push('\n');
    write_atomic(path, s.as_bytes())
}

fn tmp_path(path: &Path) -> PathBuf {
    let mut name = path
        .file_name()
        .map(|s| s.to_os_string())
        .unwrap_or_default();
    name.push(".part");
    path.with_file_name(name)
}

/// A CSV file written row by row into `<path>.part`, flushed regularly, and renamed to
/// `path` by [`CsvWriter::finish`]. If the run is interrupted, `finish` still renames what
/// was written (every row complete).
#[derive(Debug)]
pub struct CsvWriter {
    out: BufWriter<File>,
    path: PathBuf,
    tmp: PathBuf,
    rows: usize,
    line: String,
    /// Per value column, whether NaN is written as an empty cell (a value that does not
    /// exist in that row: [`CsvWriter::empty_when_nan`]).
    empty_nan: Vec<bool>,
}

impl CsvWriter {
    /// Writes NaN in the value columns flagged in `mask` (in the order of the values) as an
    /// empty cell: a value that has no meaning in that row (the patch's centre where no rim
    /// node touches), as the sweep's table leaves a point's missing figures empty. Every
    /// other NaN is written `NaN`.
    pub fn empty_when_nan(&mut self, mask: &[bool]) {
        self.empty_nan = mask.to_vec();
    }

    /// Creates the file and writes the header.
    ///
    /// # Errors
    /// I/O errors.
    pub fn create(path: &Path, header: &[&str]) -> std::io::Result<Self> {
        let tmp = tmp_path(path);
        let f = File::create(&tmp)
            .map_err(|e| std::io::Error::new(e.kind(), format!("{}: {e}", tmp.display())))?;
        let mut out = BufWriter::with_capacity(1 << 16, f);
        out.write_all(super::csv::record(header).as_bytes())
            .map_err(|e| std::io::Error::new(e.kind(), format!("{}: {e}", path.display())))?;
        Ok(Self {
            out,
            path: path.to_path_buf(),
            tmp,
            rows: 0,
            line: String::with_capacity(512),
            empty_nan: Vec::new(),
        })
    }

    /// Writes one row: a label (none: no key column; quoted per RFC 4180 when it holds a
    /// comma, a quote or a line break, see [`super::csv`]) and numbers (`{:e}`).
    ///
    /// # Errors
    /// I/O errors.
    pub fn row(&mut self, label: Option<&str>, values: &[f64]) -> std::io::Result<()> {
        use std::fmt::Write as _;
        self.line.clear();
        if let Some(l) = label {
            super::csv::push_field(&mut self.line, l);
        }
        for (i, v) in values.iter().enumerate() {
            if i > 0 || label.is_some() {
                self.line.push(',');
            }
            if v.is_nan() && self.empty_nan.get(i).copied().unwrap_or(false) {
                continue;
            }
            let _ = write!(self.line, "{v:e}");
        }
        self.line.push('\n');
        self.out
            .write_all(self.line.as_bytes())
            .map_err(|e| self.named(e))?;
        self.rows += 1;
        Ok(())
    }

    /// `e` with the file's (final) name in its message.
    fn named(&self, e: std::io::Error) -> std::io::Error {
        std::io::Error::new(e.kind(), format!("{}: {e}", self.path.display()))
    }

    /// Flushes and renames the file into place.
    ///
    /// # Errors
    /// I/O errors.
    pub fn finish(mut self) -> std::io::Result<usize> {
        self.out.flush().map_err(|e| self.named(e))?;
        self.out.get_ref().sync_all().map_err(|e| self.named(e))?;
        std::fs::rename(&self.tmp, &self.path).map_err(|e| self.named(e))?;
        Ok(self.rows)
    }
}
