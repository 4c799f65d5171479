//! Errors, fonts, the super-sampled canvas and atomic PNG writing.

use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Once;

use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::register_font;

use crate::audit;
use crate::PlotError;

/// Internal error, turned into a [`PlotError`] once the path is known.
#[derive(Debug)]
pub(crate) enum Fail {
    Empty(String),
    Draw(String),
}

impl Fail {
    pub(crate) fn at(self, path: &Path) -> PlotError {
        match self {
            Fail::Empty(why) => PlotError::Empty {
                path: path.to_path_buf(),
                why,
            },
            Fail::Draw(message) => PlotError::Draw {
                path: path.to_path_buf(),
                message,
            },
        }
    }
}

pub(crate) type Res<T> = Result<T, Fail>;
pub(crate) type Area<'a> = DrawingArea<BitMapBackend<'a>, Shift>;

pub(crate) fn de<E: std::fmt::Display>(e: E) -> Fail {
    Fail::Draw(e.to_string())
}

pub(crate) const FONT_FAMILY: &str = "DejaVu Sans";
static FONT_INIT: Once = Once::new();
static FONT_OK: AtomicBool = AtomicBool::new(false);

/// Registers the embedded DejaVu Sans font with plotters (once per process).
fn ensure_fonts() -> Res<()> {
    FONT_INIT.call_once(|| {
        let ok = register_font(FONT_FAMILY, FontStyle::Normal, dejavu::sans::regular()).is_ok()
            && register_font(FONT_FAMILY, FontStyle::Bold, dejavu::sans::bold()).is_ok();
        FONT_OK.store(ok, Ordering::Release);
    });
    if FONT_OK.load(Ordering::Acquire) {
        Ok(())
    } else {
        Err(Fail::Draw(
            "cannot register the embedded DejaVu Sans font".into(),
        ))
    }
}

/// Figure geometry in super-sampled pixels.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Fig {
    /// Super-sampling factor.
    pub(crate) k: f64,
    /// Output size in output pixels.
    pub(crate) out: (f64, f64),
    /// Canvas size in super-sampled pixels.
    pub(crate) w: f64,
    pub(crate) h: f64,
}

/// Whether a figure that paints outside its regions (a label beyond its panel, a title
/// beyond the canvas) is an error rather than written as it is: in this crate's tests, and
/// when the environment variable `SOFTWAY_PLOT_STRICT` is set to anything but `0` (the
/// solver's figure tests).
fn strict() -> bool {
    cfg!(test) || std::env::var_os("SOFTWAY_PLOT_STRICT").is_some_and(|v| !v.is_empty() && v != "0")
}

const MIN_SIZE: (u32, u32) = (120, 90);
const MAX_PIXELS: u64 = 100_000_000;

/// Renders with `draw` on a white, super-sampled canvas and returns the
/// down-sampled RGB buffer of `size`.
pub(crate) fn render<F>(size: (u32, u32), draw: F) -> Res<Vec<u8>>
where
    F: FnOnce(&Area, &Fig) -> Res<()>,
{
    ensure_fonts()?;
    let (w, h) = size;
    if w < MIN_SIZE.0 || h < MIN_SIZE.1 {
        return Err(Fail::Draw(format!(
            "image size {w}x{h} is too small (minimum {}x{})",
            MIN_SIZE.0, MIN_SIZE.1
        )));
    }
    if u64::from(w) * u64::from(h) > MAX_PIXELS {
        return Err(Fail::Draw(format!("image size {w}x{h} is too large")));
    }
    let k: u32 = if u64::from(w) * u64::from(h) <= 4_000_000 {
        2
    } else {
        1
    };
    let (sw, sh) = (w * k, h * k);
    // The thread's canvas of its last figure, refilled: a fresh one of tens of MB would be
    // paged in (and zeroed by the kernel) for every figure.
    let mut big = CANVAS.with(|c| std::mem::take(&mut *c.borrow_mut()));
    big.clear();
    big.resize(sw as usize * sh as usize * 3, 255);
    {
        let area = BitMapBackend::with_buffer(&mut big, (sw, sh)).into_drawing_area();
        let fig = Fig {
            k: f64::from(k),
            out: (f64::from(w), f64::from(h)),
            w: f64::from(sw),
            h: f64::from(sh),
        };
        // Last line of defence: plotting must never bring the solver down.
        audit::begin(fig.w, fig.h);
        let result = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| draw(&area, &fig)));
        let outside = audit::take();
        match result {
            Ok(r) => r?,
            Err(_) => return Err(Fail::Draw("internal error while drawing".into())),
        }
        if strict() && !outside.is_empty() {
            return Err(Fail::Draw(format!(
                "{} defect(s) of the figure (SOFTWAY_PLOT_STRICT: drawings outside their \
                 region, legends hiding data, ranges set by one point): {}",
                outside.len(),
                outside[..outside.len().min(3)].join("; ")
            )));
        }
        area.present().map_err(de)?;
    }
    let out = downsample(&big, (w, h), k);
    if big.capacity() <= CANVAS_KEPT_BYTES {
        CANVAS.with(|c| *c.borrow_mut() = big);
    }
    Ok(out)
}

/// The largest canvas a thread keeps for its next figure (a 2800 x 2000 figure
/// super-sampled), bytes.
const CANVAS_KEPT_BYTES: usize = 5600 * 4000 * 3;

thread_local! {
    /// The super-sampled canvas of the thread's last figure ([`render`]).
    static CANVAS: std::cell::RefCell<Vec<u8>> = const { std::cell::RefCell::new(Vec::new()) };
}

/// Box-filter down-sampling of an RGB buffer by the integer factor `k`.
fn downsample(big: &[u8], (w, h): (u32, u32), k: u32) -> Vec<u8> {
    if k == 1 {
        return big.to_vec();
    }
    if k == 2 {
        return downsample_by_two(big, (w, h));
    }
    let (w, h, k) = (w as usize, h as usize, k as usize);
    let n = (k * k) as u32;
    let row_len = w * k * 3;
    let mut out = vec![0u8; w * h * 3];
    // One output row at a time: the sums of its `k x k` blocks, channel by channel, in one
    // pass over each of its `k` source rows.
    let mut acc = vec![0u32; w * 3];
    for (y, out_row) in out.chunks_exact_mut(w * 3).enumerate() {
        acc.fill(0);
        for dy in 0..k {
            let src = &big[(y * k + dy) * row_len..][..row_len];
            for (a, block) in acc.chunks_exact_mut(3).zip(src.chunks_exact(k * 3)) {
                for px in block.chunks_exact(3) {
                    a[0] += u32::from(px[0]);
                    a[1] += u32::from(px[1]);
                    a[2] += u32::from(px[2]);
                }
            }
        }
        for (o, &s) in out_row.iter_mut().zip(&acc) {
            *o = ((s + n / 2) / n) as u8;
        }
    }
    out
}

/// [`downsample`] by 2 (every figure up to 4 megapixels): the same rounded means of each
/// 2 x 2 block, two source rows read side by side.
fn downsample_by_two(big: &[u8], (w, h): (u32, u32)) -> Vec<u8> {
    let (w, h) = (w as usize, h as usize);
    let row_len = w * 6;
    let mut out = vec![0u8; w * h * 3];
    for (y, out_row) in out.chunks_exact_mut(w * 3).enumerate() {
        let (r0, r1) = (
            &big[2 * y * row_len..][..row_len],
            &big[(2 * y + 1) * row_len..][..row_len],
        );
        for ((o, a), b) in out_row
            .chunks_exact_mut(3)
            .zip(r0.chunks_exact(6))
            .zip(r1.chunks_exact(6))
        {
            for c in 0..3 {
                let s =
                    u32::from(a[c]) + u32::from(a[c + 3]) + u32::from(b[c]) + u32::from(b[c + 3]);
                o[c] = ((s + 2) / 4) as u8;
            }
        }
    }
    out
}

/// Writes the RGB buffer as PNG to `<path>.tmp.png`, then renames it to
/// `path`.
pub(crate) fn save_png(path: &Path, size: (u32, u32), rgb: &[u8]) -> Result<(), PlotError> {
    let fail = |message: String| PlotError::Draw {
        path: path.to_path_buf(),
        message,
    };
    let name = path
        .file_name()
        .ok_or_else(|| fail("the path has no file name".into()))?;
    if let Some(parent) = path.parent() {
        if !parent.as_os_str().is_empty() {
            std::fs::create_dir_all(parent)
                .map_err(|e| fail(format!("cannot create {}: {e}", parent.display())))?;
        }
    }
    let mut tmp_name = name.to_os_string();
    tmp_name.push(".tmp.png");
    let tmp = path.with_file_name(tmp_name);
    let written = (|| -> Result<(), String> {
        let mut backend = BitMapBackend::new(&tmp, size);
        backend
            .blit_bitmap((0, 0), size, rgb)
            .map_err(|e| e.to_string())?;
        backend.present().map_err(|e| e.to_string())?;
        Ok(())
    })();
    let result = written.and_then(|()| {
        std::fs::rename(&tmp, path).map_err(|e| format!("cannot rename {}: {e}", tmp.display()))
    });
    if let Err(message) = result {
        let _ = std::fs::remove_file(&tmp);
        return Err(fail(message));
    }
    Ok(())
}

#[cfg(test)]
mod downsample_tests {
    use super::downsample;

    /// The box filter by rows equals the mean of each `k x k` block computed pixel by pixel
    /// (rounded to nearest), on a buffer of varied bytes.
    #[test]
    fn downsample_is_the_rounded_block_mean() {
        let (w, h) = (7u32, 5u32);
        for k in [1u32, 2, 3] {
            let (bw, bh) = ((w * k) as usize, (h * k) as usize);
            let big: Vec<u8> = (0..bw * bh * 3)
                .map(|i| ((i * 37 + i / 5) % 256) as u8)
                .collect();
            let out = downsample(&big, (w, h), k);
            let k = k as usize;
            for y in 0..h as usize {
                for x in 0..w as usize {
                    for c in 0..3 {
                        let mut s = 0u32;
                        for dy in 0..k {
                            for dx in 0..k {
                                s += u32::from(big[((y * k + dy) * bw + x * k + dx) * 3 + c]);
                            }
                        }
                        let n = (k * k) as u32;
                        assert_eq!(out[(y * w as usize + x) * 3 + c], ((s + n / 2) / n) as u8);
                    }
                }
            }
        }
    }
}
