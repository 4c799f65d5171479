//! The machine's memory bandwidth, STREAM-like (McCalpin 1995): the triad `a = b + s c` and
//! a read-only sum over arrays far larger than the caches, best of ten rounds, on one thread
//! and on every core ([`softway::linalg::bandwidth`]).
//!
//! ```sh
//! cargo run --release --example bandwidth [-- MIB_PER_ARRAY]
//! ```
//!
//! The triad counts 24 bytes an element (two reads, one write; the write's line fill is not
//! counted, as STREAM); the sum 8. A solve with a Cholesky factor reads it twice (forward
//! and backward), so its floor is `16 bytes x nnz(L) / bandwidth`
//! (`examples/solver3d_ladder.rs`).

fn main() {
    let mib: usize = std::env::args()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(256);
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    for threads in [1, cores] {
        let b = softway::linalg::bandwidth::measure(mib, 10, threads);
        println!(
            "arrays of {mib} MiB on {threads} thread(s): triad {:.2} GB/s, read {:.2} GB/s (best of 10)",
            b.triad / 1e9,
            b.read / 1e9
        );
        if cores == 1 {
            break;
        }
    }
}
