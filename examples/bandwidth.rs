//! The machine's memory bandwidth, STREAM-like (McCalpin 1995): the triad `a = b + s c` and
//! a read-only sum over arrays far larger than the caches, best of ten rounds.
//!
//! ```sh
//! cargo run --release --example bandwidth [-- MIB_PER_ARRAY]
//! ```
//!
//! The triad counts 24 bytes an element (two reads, one write; the write's line fill is not
//! counted, as STREAM); the sum 8. A solve with a Cholesky factor reads it twice (forward
//! and backward), so its floor is `16 bytes x nnz(L) / bandwidth`
//! (`examples/solver3d_ladder.rs`).

use std::time::Instant;

fn main() {
    let mib: usize = std::env::args()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(256);
    let n = mib * (1 << 20) / 8;
    let (triad, read) = bandwidth(n, 10);
    println!(
        "arrays of {mib} MiB: triad {:.2} GB/s, read {:.2} GB/s (best of 10)",
        triad / 1e9,
        read / 1e9
    );
}

/// The best triad and read bandwidths, bytes per second, on arrays of `n` values.
fn bandwidth(n: usize, rounds: usize) -> (f64, f64) {
    let mut a = vec![0.0f64; n];
    let b: Vec<f64> = (0..n).map(|i| i as f64).collect();
    let c: Vec<f64> = (0..n).map(|i| (n - i) as f64).collect();
    let s = 3.0;
    let (mut triad, mut read) = (0.0f64, 0.0f64);
    let mut sink = 0.0;
    for _ in 0..rounds {
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
    (triad, read)
}
