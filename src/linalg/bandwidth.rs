//! The machine's memory: its size, and its bandwidth, STREAM-like (McCalpin 1995): the triad `a = b + s c` and
//! a read-only sum over arrays far larger than the caches, best of several rounds, on one
//! thread or several (each its own slice of the arrays, as STREAM's OpenMP loops).
//!
//! The triad counts 24 bytes an element (two reads, one write; the write's line fill is not
//! counted, as STREAM); the sum 8. A solve streams its factor from memory once forward and
//! once backward, so a step's floor is the bytes it reads over the bandwidth
//! ([`crate::time::step::Stepper::free_step_bytes`]) on as many threads as the step runs
//! on; the floors of the book and of a sweep's `cost.md` take the triad's, the figure STREAM
//! reports.

use std::time::Instant;

/// The machine's memory (`MemTotal` of `/proc/meminfo`), bytes, where known.
pub fn physical_memory_bytes() -> Option<f64> {
    let info = std::fs::read_to_string("/proc/meminfo").ok()?;
    let line = info.lines().find(|l| l.starts_with("MemTotal:"))?;
    let kb: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb * 1024.0)
}

/// [`physical_memory_bytes`], or 8 GiB where it is not known.
pub fn memory_bytes_or_default() -> f64 {
    physical_memory_bytes().unwrap_or(8.0 * (1u64 << 30) as f64)
}

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
    /// Threads, each on its slice of the arrays.
    pub threads: usize,
}

/// Measures the bandwidth on three arrays of `mib` MiB each, the best of `rounds` rounds, on
/// `threads` threads (the caller's and scoped helpers), each on its own slice. Allocates the
/// arrays (`3 mib` MiB) and frees them.
pub fn measure(mib: usize, rounds: usize, threads: usize) -> Bandwidth {
    let n = (mib.max(1) << 20) / 8;
    let threads = threads.clamp(1, 64);
    let mut a = vec![0.0f64; n];
    let b: Vec<f64> = (0..n).map(|i| i as f64).collect();
    let c: Vec<f64> = (0..n).map(|i| (n - i) as f64).collect();
    let chunk = n.div_ceil(threads).max(4);
    let (mut triad, mut read) = (0.0f64, 0.0f64);
    let mut sink = 0.0;
    for _ in 0..rounds.max(1) {
        let t = Instant::now();
        std::thread::scope(|scope| {
            for ((ai, bi), ci) in a
                .chunks_mut(chunk)
                .zip(b.chunks(chunk))
                .zip(c.chunks(chunk))
            {
                scope.spawn(move || triad_slice(ai, bi, ci));
            }
        });
        let dt = t.elapsed().as_secs_f64();
        triad = triad.max(24.0 * n as f64 / dt);
        let t = Instant::now();
        let sums: Vec<f64> = std::thread::scope(|scope| {
            let parts: Vec<_> = a
                .chunks(chunk)
                .map(|ai| scope.spawn(move || sum_slice(ai)))
                .collect();
            parts.into_iter().map(|p| p.join().unwrap_or(0.0)).collect()
        });
        let dt = t.elapsed().as_secs_f64();
        read = read.max(8.0 * n as f64 / dt);
        sink += sums.iter().sum::<f64>();
    }
    std::hint::black_box(sink);
    Bandwidth {
        triad,
        read,
        mib,
        rounds: rounds.max(1),
        threads,
    }
}

/// `a = b + 3 c` over one slice.
fn triad_slice(a: &mut [f64], b: &[f64], c: &[f64]) {
    for ((ai, bi), ci) in a.iter_mut().zip(b).zip(c) {
        *ai = bi + 3.0 * ci;
    }
}

/// The sum of one slice, four partial sums (the adds are not one dependent chain).
fn sum_slice(a: &[f64]) -> f64 {
    let mut p = [0.0f64; 4];
    let mut ch = a.chunks_exact(4);
    for c in ch.by_ref() {
        for k in 0..4 {
            p[k] += c[k];
        }
    }
    p.iter().sum::<f64>() + ch.remainder().iter().sum::<f64>()
}

#[cfg(test)]
mod tests {
    /// The measure is a rate of these machines' memory: above 0.1 GB/s and below 1 TB/s,
    /// which no memory of theirs reaches (a timer or a byte count gone wrong lands outside),
    /// on one thread and on two.
    #[test]
    fn the_bandwidth_is_a_finite_rate() {
        for threads in [1, 2] {
            let b = super::measure(8, 2, threads);
            assert_eq!(b.threads, threads);
            for r in [b.triad, b.read] {
                assert!(r.is_finite() && r > 1e8 && r < 1e12, "{b:?}");
            }
        }
    }

    /// The slices' sum is the whole sum (a remainder shorter than four included).
    #[test]
    fn the_slices_sum_to_the_whole() {
        let a: Vec<f64> = (0..11).map(f64::from).collect();
        assert_eq!(super::sum_slice(&a), 55.0);
    }
}
