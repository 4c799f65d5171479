//! Where each drawing may paint, and a record of what painted elsewhere.
//!
//! A figure is drawn in nested regions: the canvas, a panel's cell (its title, labels,
//! ticks, legend), a panel's plot rectangle (its data). While a region is *clipping*
//! ([`with_clip`]), every polygon and line is cut to it before it reaches plotters, so data
//! cannot leave its axes. While a region is *bounding* ([`with_bounds`]), anything painted
//! outside it (a label, a tick, a marker, a title wider than its cell) is recorded as a
//! violation, with what it was; [`take`] hands the list to the renderer, which turns it
//! into an error when the figure is drawn strictly (the tests, and
//! `SOFTWAY_PLOT_STRICT=1`).
//!
//! The state is per thread: a figure is drawn on one thread from start to end, and figures
//! drawn side by side on other threads keep their own.

use std::cell::RefCell;

use crate::shape::Rect;

/// Slack for rounding to whole pixels, in (super-sampled) pixels.
const SLACK: f64 = 1.5;

#[derive(Default)]
struct State {
    /// Innermost clipping rectangle.
    clip: Option<Rect>,
    /// Innermost bounding region and its name.
    bounds: Option<(Rect, &'static str)>,
    /// The whole canvas.
    canvas: Option<Rect>,
    violations: Vec<String>,
    active: bool,
}

thread_local! {
    static STATE: RefCell<State> = RefCell::new(State::default());
}

/// Starts recording for a figure on a canvas of `w` x `h` pixels.
pub(crate) fn begin(w: f64, h: f64) {
    STATE.with(|s| {
        *s.borrow_mut() = State {
            clip: None,
            bounds: None,
            canvas: Some(Rect::new(0.0, 0.0, w, h)),
            violations: Vec::new(),
            active: true,
        };
    });
}

/// Ends recording; returns the violations.
pub(crate) fn take() -> Vec<String> {
    STATE.with(|s| {
        let mut s = s.borrow_mut();
        s.active = false;
        s.clip = None;
        s.bounds = None;
        s.canvas = None;
        std::mem::take(&mut s.violations)
    })
}

/// Runs `f` with polygons and lines clipped to `r` (within any outer clip).
pub(crate) fn with_clip<R>(r: Rect, f: impl FnOnce() -> R) -> R {
    let old = STATE.with(|s| {
        let mut s = s.borrow_mut();
        let inner = match s.clip {
            Some(c) => c.intersect(&r),
            None => r,
        };
        s.clip.replace(inner)
    });
    let out = f();
    STATE.with(|s| s.borrow_mut().clip = old);
    out
}

/// Runs `f` with everything it paints expected inside `r` (and inside the canvas).
pub(crate) fn with_bounds<R>(r: Rect, name: &'static str, f: impl FnOnce() -> R) -> R {
    let old = STATE.with(|s| s.borrow_mut().bounds.replace((r, name)));
    let out = f();
    STATE.with(|s| s.borrow_mut().bounds = old);
    out
}

/// The current clipping rectangle.
pub(crate) fn clip() -> Option<Rect> {
    STATE.with(|s| s.borrow().clip)
}

/// Records a defect of the figure that is not a place (a legend hiding data, an axis range
/// set by one isolated point), while a figure is being drawn.
pub(crate) fn flag(what: impl FnOnce() -> String) {
    STATE.with(|s| {
        let mut s = s.borrow_mut();
        if s.active {
            s.violations.push(what());
        }
    });
}

/// Records `what` if the box `b` it paints leaves the current bounds or the canvas.
pub(crate) fn check(what: impl FnOnce() -> String, b: Rect) {
    STATE.with(|s| {
        let mut s = s.borrow_mut();
        if !s.active {
            return;
        }
        let regions = [s.bounds, s.canvas.map(|c| (c, "the canvas"))];
        for (r, name) in regions.into_iter().flatten() {
            if !r.grow(SLACK).contains_rect(&b) {
                let msg = format!(
                    "{} spans x {:.0}..{:.0}, y {:.0}..{:.0}: outside {name} (x {:.0}..{:.0}, y {:.0}..{:.0})",
                    what(),
                    b.x0,
                    b.x1,
                    b.y0,
                    b.y1,
                    r.x0,
                    r.x1,
                    r.y0,
                    r.y1
                );
                s.violations.push(msg);
                break;
            }
        }
    });
}
