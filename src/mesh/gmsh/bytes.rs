//! The bytes of a Gmsh file before and around `mshio`: the `$MeshFormat` header, the
//! sections' counts and physical names, the one repair (a binary section's maximum tag) and
//! the parser's errors in words.

use super::*;

/// The `$MeshFormat` header.
#[derive(Debug, Clone, Copy)]
pub(super) struct Header {
    pub(super) binary: bool,
    /// Size of `size_t` in bytes (4 or 8).
    pub(super) size_t: usize,
    /// Byte order of a binary file (true: little endian).
    pub(super) little_endian: bool,
}

pub(super) enum HeaderError {
    Version(String),
    Invalid(String),
}

/// Reads and checks the `$MeshFormat` header (before mshio, which panics on some bad headers).
pub(super) fn read_header(bytes: &[u8]) -> Result<Header, HeaderError> {
    let invalid = |m: &str| HeaderError::Invalid(m.to_string());
    let start = bytes
        .iter()
        .position(|b| !b.is_ascii_whitespace())
        .unwrap_or(bytes.len());
    let rest = &bytes[start..];
    let Some(rest) = rest.strip_prefix(b"$MeshFormat") else {
        return Err(invalid(
            "not a Gmsh mesh file: it does not start with a $MeshFormat section",
        ));
    };
    let rest = strip_newline(rest).ok_or_else(|| invalid("bad $MeshFormat line"))?;
    let line_end = rest
        .iter()
        .position(|&b| b == b'\n')
        .ok_or_else(|| invalid("truncated $MeshFormat header"))?;
    let line = String::from_utf8_lossy(&rest[..line_end]);
    let tokens: Vec<&str> = line.split_whitespace().collect();
    let [version, file_type, data_size] = tokens[..] else {
        return Err(invalid(
            "the $MeshFormat header must read `version file-type data-size`",
        ));
    };
    if version.parse::<f64>().ok() != Some(4.1) {
        return Err(HeaderError::Version(version.to_string()));
    }
    let binary = match file_type {
        "0" => false,
        "1" => true,
        _ => {
            return Err(HeaderError::Invalid(format!(
                "file type must be 0 (ASCII) or 1 (binary), got {file_type}"
            )))
        }
    };
    let size_t = match data_size {
        "4" => 4,
        "8" => 8,
        _ => {
            return Err(HeaderError::Invalid(format!(
                "data size (size of size_t) must be 4 or 8, got {data_size}"
            )))
        }
    };
    let mut little_endian = true;
    if binary {
        let one = rest
            .get(line_end + 1..line_end + 5)
            .and_then(|b| <[u8; 4]>::try_from(b).ok())
            .ok_or_else(|| invalid("truncated binary $MeshFormat header"))?;
        little_endian = if i32::from_le_bytes(one) == 1 {
            true
        } else if i32::from_be_bytes(one) == 1 {
            false
        } else {
            return Err(invalid(
                "binary $MeshFormat header: the endianness test integer is not 1",
            ));
        };
    }
    Ok(Header {
        binary,
        size_t,
        little_endian,
    })
}

/// Strips one line break (`\n` or `\r\n`) from the start.
pub(super) fn strip_newline(b: &[u8]) -> Option<&[u8]> {
    b.strip_prefix(b"\n").or_else(|| b.strip_prefix(b"\r\n"))
}

/// Offset of the body of section `tag` (just after the line holding `tag`), if present. The
/// tag must start a line and be followed by a line break.
pub(super) fn find_section(bytes: &[u8], tag: &str) -> Option<usize> {
    let tag = tag.as_bytes();
    let mut from = 0;
    while let Some(pos) = find(&bytes[from..], tag).map(|p| p + from) {
        let at_line_start = pos == 0 || bytes[pos - 1] == b'\n';
        let after = &bytes[pos + tag.len()..];
        if at_line_start {
            if let Some(body) = strip_newline(after) {
                return Some(bytes.len() - body.len());
            }
        }
        from = pos + 1;
    }
    None
}

/// First position of `needle` in `hay`.
pub(super) fn find(hay: &[u8], needle: &[u8]) -> Option<usize> {
    if needle.is_empty() || hay.len() < needle.len() {
        return None;
    }
    hay.windows(needle.len()).position(|w| w == needle)
}

/// Reads `$PhysicalNames` (always ASCII, also in binary files): `(dim, tag) -> name`.
pub(super) fn read_physical_names(bytes: &[u8]) -> Result<BTreeMap<(i32, i32), String>, String> {
    let mut names = BTreeMap::new();
    let Some(start) = find_section(bytes, "$PhysicalNames") else {
        return Ok(names);
    };
    let len = find(&bytes[start..], b"$EndPhysicalNames")
        .ok_or("the $PhysicalNames section has no $EndPhysicalNames")?;
    let text = String::from_utf8_lossy(&bytes[start..start + len]);
    let mut lines = text.lines().map(str::trim).filter(|l| !l.is_empty());
    let count: usize = lines
        .next()
        .and_then(|l| l.parse().ok())
        .ok_or("$PhysicalNames: the first line must be the number of names")?;
    for k in 0..count {
        let line = lines
            .next()
            .ok_or_else(|| format!("$PhysicalNames: {count} names announced, {k} found"))?;
        let bad = || format!("$PhysicalNames: bad entry `{line}` (expected `dim tag \"name\"`)");
        let mut parts = line.splitn(3, char::is_whitespace);
        let dim: i32 = parts.next().and_then(|s| s.parse().ok()).ok_or_else(bad)?;
        let tag: i32 = parts.next().and_then(|s| s.parse().ok()).ok_or_else(bad)?;
        let name = parts
            .next()
            .map(str::trim)
            .and_then(|s| s.strip_prefix('"'))
            .and_then(|s| s.strip_suffix('"'))
            .ok_or_else(bad)?;
        names.insert((dim, tag), name.to_string());
    }
    Ok(names)
}

/// The header of a `$Nodes` or `$Elements` section.
#[derive(Debug, Clone, Copy)]
pub(super) struct SectionCounts {
    /// Number of nodes or elements.
    pub(super) count: u64,
    /// Byte range of the maximum tag in the file.
    pub(super) max_tag: (usize, usize),
}

/// Reads `numEntityBlocks numX minTag maxTag` at the start of section `tag`. `None` if the
/// section is absent or its header unreadable (mshio then reports the problem).
pub(super) fn section_counts(bytes: &[u8], tag: &str, header: &Header) -> Option<SectionCounts> {
    let start = find_section(bytes, tag)?;
    if header.binary {
        let n = header.size_t;
        let read = |k: usize| -> Option<u64> {
            let b = bytes.get(start + k * n..start + (k + 1) * n)?;
            Some(match (n, header.little_endian) {
                (4, true) => u64::from(u32::from_le_bytes(b.try_into().ok()?)),
                (4, false) => u64::from(u32::from_be_bytes(b.try_into().ok()?)),
                (_, true) => u64::from_le_bytes(b.try_into().ok()?),
                (_, false) => u64::from_be_bytes(b.try_into().ok()?),
            })
        };
        let count = read(1)?;
        read(3)?;
        Some(SectionCounts {
            count,
            max_tag: (start + 3 * n, start + 4 * n),
        })
    } else {
        // Four whitespace-separated integers.
        let mut spans = Vec::with_capacity(4);
        let mut i = start;
        while spans.len() < 4 {
            while i < bytes.len() && bytes[i].is_ascii_whitespace() {
                i += 1;
            }
            let s = i;
            while i < bytes.len() && bytes[i].is_ascii_digit() {
                i += 1;
            }
            if s == i {
                return None;
            }
            spans.push((s, i));
        }
        let num = |k: usize| -> Option<u64> {
            let (s, e) = spans[k];
            std::str::from_utf8(&bytes[s..e]).ok()?.parse().ok()
        };
        let count = num(1)?;
        num(3)?;
        Some(SectionCounts {
            count,
            max_tag: spans[3],
        })
    }
}

/// Replaces the maximum node tag in the `$Nodes` header by the largest value, so that mshio
/// treats the tags as sparse and keeps them. Returns false if nothing was changed.
pub(super) fn patch_max_tag(bytes: &mut Vec<u8>, counts: &SectionCounts, header: &Header) -> bool {
    let (s, e) = counts.max_tag;
    if e > bytes.len() || s > e {
        return false;
    }
    if header.binary {
        bytes[s..e].fill(0xff);
    } else {
        let max = if header.size_t == 4 {
            u64::from(u32::MAX)
        } else {
            u64::MAX
        };
        bytes.splice(s..e, max.to_string().into_bytes());
    }
    true
}

/// A readable message from an mshio error: what went wrong, in which section, and where
/// (line for ASCII files, byte offset for binary ones). mshio's own `Display` appends a hex
/// dump of the whole rest of the file, which is not wanted here.
pub(super) fn describe_parse_error(
    err: &MshParserError<&[u8]>,
    input: &[u8],
    binary: bool,
) -> String {
    let trace = err.filtered_backtrace();
    let Some((rest, _)) = trace.first() else {
        return "unknown parse error".to_string();
    };
    // The innermost error kind that is not a context note, then the contexts from the
    // outermost (section) to the innermost (value).
    let kind = trace
        .iter()
        .find(|(_, k)| k.context().is_none())
        .map_or_else(|| "parse error".to_string(), |(_, k)| k.to_string());
    let context: Vec<&str> = trace
        .iter()
        .rev()
        .filter_map(|(_, k)| k.context())
        .collect();
    let mut message = kind.trim_end().to_string();
    if !context.is_empty() {
        message = format!("{message} (in {})", context.join(" > "));
    }
    let base = input.as_ptr() as usize;
    let at = rest.as_ptr() as usize;
    if at >= base && at - base <= input.len() {
        let offset = at - base;
        if binary {
            message.push_str(&format!(", at byte {offset}"));
        } else {
            let line = input[..offset].iter().filter(|&&b| b == b'\n').count() + 1;
            message.push_str(&format!(", near line {line}"));
        }
    }
    message
}
