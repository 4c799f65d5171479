//! The machine's memory bandwidth, STREAM-like (McCalpin 1995): the triad `a = b + s c` and
//! a read-only sum over arrays far larger than the caches, best of several rounds.
//!
//! The triad counts 24 bytes an element (two reads, one write; the write's line fill is not
//! counted, as STREAM); the sum 8. A solve streams its factor from memory once forward and
//! once backward, so a step's floor is the bytes it reads over the bandwidth
//! ([`crate::time::step::Stepper::free_step_bytes`]); the floors of the book and of a sweep's
//! `cost.md` take the triad's, the figure STREAM reports, which is the lower of the two on
//! the machines measured (so the floor is the more lenient).

use std::time::Instant;

/// The best triad and read bandwidths of [`measure`], bytes per second.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Bandwidth {
    /// The triad `a = b + s c`, 24 bytes an element.
    pub triad: f64,
    /// A sum over one array, 8 bytes an element.
    pub read: f64,
    /// The arrays' size, MiB each (three arrays).
    pub mib: usize,
    /// Rounds, the best kept.
    pub rounds: usize,
}

/// Measures the bandwidth on three arrays of `mib` MiB each, the best of `rounds` rounds, on
/// the calling thread. Allocates the arrays (`3 mib` MiB) and frees them.
pub fn measure(mib: usize, rounds: usize) -> Bandwidth {
    let n = (mib.max(1) << 20) / 8;
    let mut a = vec![0.0f64; n];
    let b: Vec<f64> = (0..n).map(|i| i as f64).collect();
    let c: Vec<f64> = (0..n).map(|i| (n - i) as f64).collect();
    let s = 3.0;
    let (mut triad, mut read) = (0.0f64, 0.0f64);
    let mut sink = 0.0;
    for _ in 0..rounds.max(1) {
        let t = Instant::now();
        for ((ai, bi), ci) in a.iter_mut().zip(&b).zip(&c) {
            *ai = bi + s * ci;
        }
        let dt = t.elapsed().as_secs_f64();
        triad = triad.max(24.0 * n as f64 / dt);
        let t = Instant::now();
        // Four partial sums: the adds are not one dependent chain.
        let mut p = [0.0f64; 4];
        for ch in a.chunks_exact(4) {
            for k in 0..4 {
                p[k] += ch[k];
            }
        }
        let dt = t.elapsed().as_secs_f64();
        read = read.max(8.0 * n as f64 / dt);
        sink += p.iter().sum::<f64>();
    }
    std::hint::black_box(sink);
    Bandwidth {
        triad,
        read,
        mib,
        rounds: rounds.max(1),
    }
}

#[cfg(test)]
mod tests {
    /// The measure is a rate of these machines' memory: above 0.1 GB/s and below 1 TB/s,
    /// which no memory of theirs reaches (a timer or a byte count gone wrong lands outside).
    #[test]
    fn the_bandwidth_is_a_finite_rate() {
        let b = super::measure(8, 2);
        for r in [b.triad, b.read] {
            assert!(r.is_finite() && r > 1e8 && r < 1e12, "{b:?}");
        }
    }
}
