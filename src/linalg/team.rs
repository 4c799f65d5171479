//! `join`: two closures side by side, for the time loop's two-part solves.
//!
//! A solve on two threads hands work to the second thread three times per step (the
//! right-hand side's halves, the forward and the backward sweeps' parts), every few hundred
//! microseconds. Through `rayon::join` each hand-off wakes a sleeping worker (a futex wake,
//! then the worker's steal), which the 48-ring step's profile showed as 12-14% of its time
//! in the kernel's scheduler. Here one helper thread, started on first use, waits for its
//! next job spinning for up to [`SPIN`] after its last one, and only then sleeps; a step
//! that hands it work every few hundred microseconds finds it awake. Measured with
//! `softway matrix` on the 48-ring disk (14,114 dofs, alternated binaries, twice): the free
//! step 655 and 687 us through `rayon::join`, 559 and 528 us here.
//!
//! The helper serves one caller at a time. [`join`] falls back to `rayon::join` when the
//! helper is busy with another caller, when the pool has one thread (then both closures run
//! on the caller's thread, as `rayon::join` does), or while [`Exclusive`] is held (runs in
//! parallel on every core, where a spinning helper would take a core from a run).

use std::any::Any;
use std::cell::UnsafeCell;
use std::sync::atomic::{AtomicBool, AtomicU32, AtomicUsize, Ordering};
use std::sync::OnceLock;
use std::thread::Thread;
use std::time::{Duration, Instant};

/// How long the helper spins for its next job before it sleeps.
const SPIN: Duration = Duration::from_millis(2);

const IDLE: u32 = 0;
const POSTED: u32 = 1;
const DONE: u32 = 2;

/// The job handed to the helper: a closure on the caller's stack, its lifetime erased (the
/// caller waits for `DONE` before the closure's frame ends, unwinding included).
type Job = *const (dyn Fn() + Sync);

struct Helper {
    state: AtomicU32,
    /// Set by the helper before it sleeps; a caller that posts a job then wakes it.
    sleeping: AtomicBool,
    /// The caller's claim (one caller at a time).
    claimed: AtomicBool,
    job: UnsafeCell<Option<Job>>,
    panic: UnsafeCell<Option<Box<dyn Any + Send>>>,
    /// The helper, started on first use (`None` if it could not be).
    thread: OnceLock<Option<Thread>>,
}

// SAFETY: `job` and `panic` are written by the claimant before it posts (Release) and by the
// helper before it reports `DONE` (Release), and read by the other side after it observed
// that state (Acquire): the protocol orders every access.
unsafe impl Sync for Helper {}

static HELPER: Helper = Helper {
    state: AtomicU32::new(IDLE),
    sleeping: AtomicBool::new(false),
    claimed: AtomicBool::new(false),
    job: UnsafeCell::new(None),
    panic: UnsafeCell::new(None),
    thread: OnceLock::new(),
};

/// Holders of an [`Exclusive`] guard.
static EXCLUSIVE: AtomicUsize = AtomicUsize::new(0);

/// While held, [`join`] does not use its helper (runs side by side on every core: sweeps,
/// convergence studies).
#[must_use]
pub struct Exclusive(());

impl Exclusive {
    pub fn hold() -> Self {
        EXCLUSIVE.fetch_add(1, Ordering::SeqCst);
        Exclusive(())
    }
}

impl Drop for Exclusive {
    fn drop(&mut self) {
        EXCLUSIVE.fetch_sub(1, Ordering::SeqCst);
    }
}

fn helper_loop() {
    let h = &HELPER;
    loop {
        let mut since = Instant::now();
        let mut n = 0u32;
        while h.state.load(Ordering::Acquire) != POSTED {
            n = n.wrapping_add(1);
            if n % 64 != 0 {
                std::hint::spin_loop();
                continue;
            }
            if since.elapsed() < SPIN {
                continue;
            }
            h.sleeping.store(true, Ordering::SeqCst);
            if h.state.load(Ordering::SeqCst) != POSTED {
                std::thread::park();
            }
            h.sleeping.store(false, Ordering::SeqCst);
            since = Instant::now();
        }
        // SAFETY: POSTED was observed (Acquire): the claimant wrote the job before it.
        let job = unsafe { (*h.job.get()).take() }.expect("a posted job");
        // SAFETY: the claimant keeps the closure alive until it observes DONE.
        let r = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| unsafe { (*job)() }));
        if let Err(p) = r {
            // SAFETY: the claimant reads it only after DONE (Release below).
            unsafe { *h.panic.get() = Some(p) };
        }
        h.state.store(DONE, Ordering::Release);
    }
}

/// The caller's claim on the helper. [`Claim::finish`] waits for the helper's job and
/// releases the claim; dropping an unfinished claim (the caller's own closure unwinding)
/// does the same, since the helper's job borrows the caller's frame.
struct Claim {
    finished: bool,
}

impl Claim {
    /// Waits for `DONE`, releases the claim; the helper's panic, if its job panicked.
    fn finish(&mut self) -> Option<Box<dyn Any + Send>> {
        let h = &HELPER;
        while h.state.load(Ordering::Acquire) != DONE {
            std::hint::spin_loop();
        }
        // SAFETY: DONE was observed (Acquire); the helper wrote the slot before it.
        let p = unsafe { (*h.panic.get()).take() };
        h.state.store(IDLE, Ordering::Relaxed);
        self.finished = true;
        h.claimed.store(false, Ordering::Release);
        p
    }
}

impl Drop for Claim {
    fn drop(&mut self) {
        if !self.finished {
            let _ = self.finish();
        }
    }
}

/// Runs `a` on this thread and `b` on the helper (or on rayon's pool, module docs); returns
/// when both have.
pub fn join<A, B>(a: A, b: B)
where
    A: FnOnce() + Send,
    B: FnOnce() + Send,
{
    if rayon::current_num_threads() < 2
        || EXCLUSIVE.load(Ordering::Relaxed) > 0
        || HELPER
            .claimed
            .compare_exchange(false, true, Ordering::Acquire, Ordering::Relaxed)
            .is_err()
    {
        rayon::join(a, b);
        return;
    }
    let h = &HELPER;
    let thread = h.thread.get_or_init(|| {
        std::thread::Builder::new()
            .name("softway-join".into())
            .spawn(helper_loop)
            .ok()
            .map(|j| j.thread().clone())
    });
    let Some(thread) = thread else {
        // No helper thread could be started: the pool's join.
        h.claimed.store(false, Ordering::Release);
        rayon::join(a, b);
        return;
    };
    let b = std::sync::Mutex::new(Some(b));
    let run_b = || {
        if let Some(b) = b.lock().unwrap_or_else(|e| e.into_inner()).take() {
            b()
        }
    };
    let job: &(dyn Fn() + Sync) = &run_b;
    // SAFETY: the helper calls `job` only before it reports DONE, and `Claim`'s drop waits
    // for DONE before this frame (which owns `run_b`) ends.
    let job: Job = unsafe { std::mem::transmute::<&(dyn Fn() + Sync), Job>(job) };
    // SAFETY: the helper is IDLE (claimed, and every claim ends in IDLE): it does not read.
    unsafe { *h.job.get() = Some(job) };
    h.state.store(POSTED, Ordering::SeqCst);
    if h.sleeping.load(Ordering::SeqCst) {
        thread.unpark();
    }
    let mut claim = Claim { finished: false };
    a();
    if let Some(p) = claim.finish() {
        std::panic::resume_unwind(p);
    }
}

/// A slice that the two closures of a [`join`] write at places of their own: each place
/// written by one of them only, none read by the other.
pub(crate) struct Disjoint<'a> {
    ptr: *mut f64,
    len: usize,
    _slice: std::marker::PhantomData<&'a mut [f64]>,
}

// SAFETY: the writes go through `put`, whose callers promise that no place is
// written by two threads (their contract).
unsafe impl Sync for Disjoint<'_> {}

impl<'a> Disjoint<'a> {
    pub(crate) fn new(slice: &'a mut [f64]) -> Self {
        Self {
            ptr: slice.as_mut_ptr(),
            len: slice.len(),
            _slice: std::marker::PhantomData,
        }
    }

    /// `slice[to[k]] = src[k]` for every `k`.
    ///
    /// # Safety
    /// No other thread writes or reads the places `to` while this one does.
    #[inline(always)]
    pub(crate) unsafe fn put(&self, to: &[usize], src: &[f64]) {
        for (&i, &v) in to.iter().zip(src) {
            assert!(i < self.len);
            // SAFETY: in bounds (checked), and this thread's alone (the contract).
            unsafe { *self.ptr.add(i) = v };
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn both_closures_run_and_see_their_borrows() {
        let mut x = vec![0u64; 1000];
        let (lo, hi) = x.split_at_mut(500);
        for _ in 0..200 {
            join(
                || lo.iter_mut().for_each(|v| *v += 1),
                || hi.iter_mut().for_each(|v| *v += 2),
            );
        }
        assert!(x[..500].iter().all(|&v| v == 200));
        assert!(x[500..].iter().all(|&v| v == 400));
    }

    #[test]
    fn a_panic_in_either_closure_reaches_the_caller_and_the_helper_serves_again() {
        let r = std::panic::catch_unwind(|| join(|| (), || panic!("b")));
        assert!(r.is_err());
        let r = std::panic::catch_unwind(|| join(|| panic!("a"), || ()));
        assert!(r.is_err());
        let mut s = [0; 2];
        let (p, q) = s.split_at_mut(1);
        join(|| p[0] = 1, || q[0] = 2);
        assert_eq!(s, [1, 2]);
    }
}
