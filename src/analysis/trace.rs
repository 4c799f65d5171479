//! Series of bounded size for runs of any length.
//!
//! A run observes one value per step; keeping every one makes memory grow with the run. Two
//! bounded stores replace the full series:
//! - [`Envelope`] for plots: up to its capacity it keeps every sample; beyond, each kept point
//!   stands for a bucket of consecutive samples with their minimum and maximum, so a plot of
//!   it shows the true envelope of a fast ripple (no aliasing into a false slow wave, which
//!   plain decimation would draw).
//! - [`LatestWindow`] for spectra: the latest samples up to its capacity, oldest first.
//!
//! Both take their room once, up front (no allocation in the time loop).

/// Buckets an [`Envelope`] keeps before it merges them pairwise.
pub const ENVELOPE_CAP: usize = 1 << 17;

/// Samples a [`LatestWindow`] of the wheel's contact force keeps for its spectrum: at
/// `h = 2 us`, 0.52 s (25 turns at 300 rad/s), a frequency resolution of 1.9 Hz.
pub const SPECTRUM_WINDOW_CAP: usize = 1 << 18;

/// A min-max envelope of a series, of at most `cap` buckets (module docs).
#[derive(Debug, Clone)]
pub struct Envelope {
    cap: usize,
    /// Samples per bucket (a power of two; 1 until the envelope first fills).
    per: usize,
    /// Samples in the last bucket.
    filled: usize,
    /// Time of each bucket's first sample.
    t: Vec<f64>,
    lo: Vec<f64>,
    hi: Vec<f64>,
}

impl Envelope {
    /// An empty envelope of at most `cap` buckets (rounded up to an even number >= 2), with
    /// room for `expected` samples (or `cap`, the smaller).
    pub fn new(cap: usize, expected: usize) -> Self {
        let cap = cap.max(2).next_multiple_of(2);
        let room = expected.min(cap);
        Self {
            cap,
            per: 1,
            filled: 0,
            t: Vec::with_capacity(room),
            lo: Vec::with_capacity(room),
            hi: Vec::with_capacity(room),
        }
    }

    /// Adds the sample `y` at time `t`.
    pub fn push(&mut self, t: f64, y: f64) {
        if !self.t.is_empty() && self.filled < self.per {
            let k = self.t.len() - 1;
            self.lo[k] = self.lo[k].min(y);
            self.hi[k] = self.hi[k].max(y);
            self.filled += 1;
            return;
        }
        if self.t.len() == self.cap {
            self.merge_pairs();
        }
        self.t.push(t);
        self.lo.push(y);
        self.hi.push(y);
        self.filled = 1;
    }

    /// Merges buckets `2i` and `2i + 1` (all full: `cap` is even), doubling the samples per
    /// bucket.
    fn merge_pairs(&mut self) {
        let n = self.t.len() / 2;
        for i in 0..n {
            self.t[i] = self.t[2 * i];
            self.lo[i] = self.lo[2 * i].min(self.lo[2 * i + 1]);
            self.hi[i] = self.hi[2 * i].max(self.hi[2 * i + 1]);
        }
        self.t.truncate(n);
        self.lo.truncate(n);
        self.hi.truncate(n);
        self.per *= 2;
    }

    /// Samples per bucket: 1 while every sample is kept.
    pub fn samples_per_bucket(&self) -> usize {
        self.per
    }

    /// Buckets held.
    pub fn len(&self) -> usize {
        self.t.len()
    }

    /// Buckets there is room for without allocating.
    pub fn capacity(&self) -> usize {
        self.t
            .capacity()
            .min(self.lo.capacity())
            .min(self.hi.capacity())
    }

    /// Whether nothing was pushed.
    pub fn is_empty(&self) -> bool {
        self.t.is_empty()
    }

    /// The points to draw, `(t, y)`: every sample while each is kept; beyond, each bucket's
    /// minimum then maximum at its first time, so a line through them fills the envelope.
    pub fn points(&self) -> (Vec<f64>, Vec<f64>) {
        if self.per == 1 {
            return (self.t.clone(), self.lo.clone());
        }
        let mut t = Vec::with_capacity(2 * self.t.len());
        let mut y = Vec::with_capacity(2 * self.t.len());
        for ((&ti, &lo), &hi) in self.t.iter().zip(&self.lo).zip(&self.hi) {
            t.extend([ti, ti]);
            y.extend([lo, hi]);
        }
        (t, y)
    }
}

/// The latest samples of a series, at most `cap` of them (module docs).
#[derive(Debug, Clone)]
pub struct LatestWindow {
    cap: usize,
    /// Index of the oldest sample once the window is full.
    start: usize,
    t: Vec<f64>,
    y: Vec<f64>,
    /// Samples pushed in all.
    seen: usize,
}

impl LatestWindow {
    /// An empty window of at most `cap` (>= 1) samples, with room for `expected` samples
    /// (or `cap`, the smaller).
    pub fn new(cap: usize, expected: usize) -> Self {
        let cap = cap.max(1);
        let room = expected.min(cap);
        Self {
            cap,
            start: 0,
            t: Vec::with_capacity(room),
            y: Vec::with_capacity(room),
            seen: 0,
        }
    }

    /// Adds the sample `y` at time `t`, dropping the oldest when full.
    pub fn push(&mut self, t: f64, y: f64) {
        self.seen += 1;
        if self.t.len() < self.cap {
            self.t.push(t);
            self.y.push(y);
        } else {
            self.t[self.start] = t;
            self.y[self.start] = y;
            self.start = (self.start + 1) % self.cap;
        }
    }

    /// Samples pushed in all (kept or dropped).
    pub fn seen(&self) -> usize {
        self.seen
    }

    /// Samples held.
    pub fn len(&self) -> usize {
        self.t.len()
    }

    /// Samples there is room for without allocating.
    pub fn capacity(&self) -> usize {
        self.t.capacity().min(self.y.capacity())
    }

    /// Whether nothing was pushed.
    pub fn is_empty(&self) -> bool {
        self.t.is_empty()
    }

    /// The held samples `(t, y)`, oldest first.
    pub fn into_ordered(mut self) -> (Vec<f64>, Vec<f64>) {
        self.t.rotate_left(self.start);
        self.y.rotate_left(self.start);
        (self.t, self.y)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_envelope_keeps_every_sample_below_its_capacity() {
        let mut e = Envelope::new(8, 100);
        for k in 0..8 {
            e.push(k as f64, (k * k) as f64);
        }
        assert_eq!(e.samples_per_bucket(), 1);
        let (t, y) = e.points();
        assert_eq!(t, (0..8).map(|k| k as f64).collect::<Vec<_>>());
        assert_eq!(y, (0..8).map(|k| (k * k) as f64).collect::<Vec<_>>());
    }

    #[test]
    fn a_full_envelope_holds_the_extremes_of_a_fast_ripple_in_bounded_room() {
        // A ripple of period 3 samples, far above what 16 buckets can draw: plain decimation
        // would alias it; the envelope keeps its extremes in every bucket.
        let (cap, n) = (16, 10_000);
        let mut e = Envelope::new(cap, n);
        let room = (e.t.capacity(), e.lo.capacity(), e.hi.capacity());
        let ripple = [-1.0, 0.5, 1.0];
        for k in 0..n {
            e.push(k as f64, 10.0 + ripple[k % 3]);
        }
        assert!(e.len() <= cap && e.len() > cap / 2, "{}", e.len());
        assert_eq!(room, (e.t.capacity(), e.lo.capacity(), e.hi.capacity()));
        let per = e.samples_per_bucket();
        assert!(
            per.is_power_of_two() && per * cap >= n && per * cap / 2 < n,
            "{per}"
        );
        // Every bucket spans >= 3 samples: its extremes are the ripple's.
        for k in 0..e.len() {
            assert_eq!((e.lo[k], e.hi[k]), (9.0, 11.0), "bucket {k}");
            assert_eq!(e.t[k], (k * per) as f64);
        }
        let (t, y) = e.points();
        assert_eq!((t.len(), y.len()), (2 * e.len(), 2 * e.len()));
    }

    #[test]
    fn the_envelope_of_a_ramp_brackets_each_bucket() {
        let mut e = Envelope::new(4, 0);
        for k in 0..20 {
            e.push(k as f64, k as f64);
        }
        // 4 buckets of 4 samples, then a fifth begun after the merge to 8 per bucket.
        assert_eq!(e.samples_per_bucket(), 8);
        assert_eq!(e.lo, vec![0.0, 8.0, 16.0]);
        assert_eq!(e.hi, vec![7.0, 15.0, 19.0]);
    }

    #[test]
    fn a_window_keeps_the_latest_samples_in_order() {
        let mut w = LatestWindow::new(5, 1000);
        for k in 0..3 {
            w.push(k as f64, -(k as f64));
        }
        assert_eq!(w.clone().into_ordered().0, vec![0.0, 1.0, 2.0]);
        let room = w.t.capacity();
        for k in 3..1000 {
            w.push(k as f64, -(k as f64));
        }
        assert_eq!((w.len(), w.seen(), w.t.capacity()), (5, 1000, room));
        let (t, y) = w.into_ordered();
        assert_eq!(t, vec![995.0, 996.0, 997.0, 998.0, 999.0]);
        assert_eq!(y, vec![-995.0, -996.0, -997.0, -998.0, -999.0]);
    }
}
