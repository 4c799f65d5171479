//! Helpers of the unit tests: output directories, PNG checks, test meshes.

use std::collections::HashSet;
use std::f64::consts::PI;
use std::path::{Path, PathBuf};

/// Output directory of the test figures: `$SOFTWAY_PLOT_SAMPLE_DIR/<test>`
/// if that variable is set (the figures are kept, to look at them), else
/// a fresh directory under the system temporary directory, removed when
/// the test ends.
pub(crate) struct OutDir {
    path: PathBuf,
    keep: bool,
}

impl OutDir {
    pub(crate) fn join(&self, name: impl AsRef<Path>) -> PathBuf {
        self.path.join(name)
    }
    pub(crate) fn path(&self) -> &Path {
        &self.path
    }
}

impl Drop for OutDir {
    fn drop(&mut self) {
        if !self.keep {
            let _ = std::fs::remove_dir_all(&self.path);
        }
    }
}

pub(crate) fn out_dir(test: &str) -> OutDir {
    let (path, keep) = match std::env::var_os("SOFTWAY_PLOT_SAMPLE_DIR") {
        Some(d) => (PathBuf::from(d).join(test), true),
        None => (
            std::env::temp_dir().join(format!("softway-plot-{}-{test}", std::process::id())),
            false,
        ),
    };
    std::fs::create_dir_all(&path).unwrap();
    OutDir { path, keep }
}

/// A decoded 8-bit RGB image.
pub(crate) struct Image {
    pub(crate) width: u32,
    pub(crate) height: u32,
    /// Row-major RGB bytes.
    pub(crate) rgb: Vec<u8>,
}

/// Decodes the PNG at `path` (8-bit RGB, as this crate writes them).
pub(crate) fn decode_png(path: &Path) -> Image {
    let file = std::fs::File::open(path).unwrap();
    let mut reader = png::Decoder::new(std::io::BufReader::new(file))
        .read_info()
        .unwrap();
    let mut buf = vec![0; reader.output_buffer_size()];
    let info = reader.next_frame(&mut buf).unwrap();
    assert_eq!(info.color_type, png::ColorType::Rgb, "{}", path.display());
    assert_eq!(info.bit_depth, png::BitDepth::Eight, "{}", path.display());
    buf.truncate(info.buffer_size());
    Image {
        width: info.width,
        height: info.height,
        rgb: buf,
    }
}

/// Checks that `path` is a PNG of `size` that decodes, that is not blank
/// (more than one colour), and that no temporary file was left behind;
/// returns the decoded image.
pub(crate) fn assert_png(path: &Path, size: (u32, u32)) -> Image {
    let img = decode_png(path);
    assert_eq!((img.width, img.height), size, "{}", path.display());
    assert!(distinct_colors(&img.rgb) > 1, "{} is blank", path.display());
    let mut tmp = path.as_os_str().to_os_string();
    tmp.push(".tmp.png");
    assert!(!Path::new(&tmp).exists(), "temporary file left behind");
    img
}

/// Number of distinct RGB colours in a buffer.
pub(crate) fn distinct_colors(rgb: &[u8]) -> usize {
    rgb.chunks(3)
        .map(|c| (c[0], c[1], c[2]))
        .collect::<HashSet<_>>()
        .len()
}

/// Triangulated disk: centre node plus `rings` rings of 6·i nodes.
pub(crate) fn disk(radius: f64, rings: usize) -> (Vec<[f64; 2]>, Vec<[usize; 3]>) {
    let mut pts = vec![[0.0, 0.0]];
    let mut ring_start = vec![0usize];
    let mut ring_len = vec![1usize];
    for i in 1..=rings {
        ring_start.push(pts.len());
        let m = 6 * i;
        ring_len.push(m);
        let r = radius * i as f64 / rings as f64;
        for j in 0..m {
            let a = 2.0 * PI * j as f64 / m as f64;
            pts.push([r * a.cos(), r * a.sin()]);
        }
    }
    let mut tris = Vec::new();
    for i in 1..=rings {
        let (sa, na) = (ring_start[i - 1], ring_len[i - 1]);
        let (sb, nb) = (ring_start[i], ring_len[i]);
        let (mut a, mut b) = (0usize, 0usize);
        while a < na || b < nb {
            let ta = (a + 1) as f64 / na as f64;
            let tb = (b + 1) as f64 / nb as f64;
            if na > 1 && a < na && (b >= nb || ta < tb) {
                tris.push([sa + a % na, sb + b % nb, sa + (a + 1) % na]);
                a += 1;
            } else {
                tris.push([sa + a % na, sb + b % nb, sb + (b + 1) % nb]);
                b += 1;
                if na == 1 && b >= nb {
                    break;
                }
            }
        }
    }
    (pts, tris)
}

/// Structured triangulation of the rectangle [0, lx] × [0, ly].
pub(crate) fn rectangle(
    lx: f64,
    ly: f64,
    nx: usize,
    ny: usize,
) -> (Vec<[f64; 2]>, Vec<[usize; 3]>) {
    let mut pts = Vec::new();
    for j in 0..=ny {
        for i in 0..=nx {
            pts.push([lx * i as f64 / nx as f64, ly * j as f64 / ny as f64]);
        }
    }
    let id = |i: usize, j: usize| j * (nx + 1) + i;
    let mut tris = Vec::new();
    for j in 0..ny {
        for i in 0..nx {
            tris.push([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
            tris.push([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    (pts, tris)
}

pub(crate) fn centroid(p: &[[f64; 2]], t: &[usize; 3]) -> [f64; 2] {
    [
        (p[t[0]][0] + p[t[1]][0] + p[t[2]][0]) / 3.0,
        (p[t[0]][1] + p[t[1]][1] + p[t[2]][1]) / 3.0,
    ]
}
