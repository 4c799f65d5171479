//! Parallelism as a parameter: [`Par`], how many threads a run may use, and [`Team`], the
//! run's own threads: two closures side by side ([`Team::join`]) for the time loop's
//! two-part work (the split factor's sweeps, the contact rows' columns, the energies' two
//! forms), and a list of independent items in up to `n` groups side by side
//! ([`Team::for_each`]) for the work that divides further (the right-hand side's rows).
//!
//! **Why the parts follow the matrix, not the threads.** The split factor's parts are
//! subtrees of its elimination tree chosen when it is built, from the matrix alone (2, 4 or
//! 8 by its order), and their contributions to each separator are summed in a fixed order:
//! cutting it in more parts when more threads are given would change that order, hence the
//! bits (the promise below). A level of 4 or 8 parts goes to the team's threads through
//! [`Team::for_each`], whatever their number. The contact rows' columns and the
//! energies' forms are each one sum in a fixed order. The right-hand side's rows are each
//! formed whole by one thread, so its parts may follow the threads.
//!
//! A solve on two threads hands work to the second thread three times per step, every few
//! hundred microseconds at most. Through `rayon::join` each hand-off wakes a sleeping worker
//! (a futex wake, then the worker's steal), which the 48-ring step's profile showed as 12-14%
//! of its time in the kernel's scheduler. A [`Team`] built for `Par::Threads(n)` therefore
//! owns `n - 1` helper threads; each waits for its next job spinning for [`HELPER_SPIN`] after its
//! last one, then blocks (`park`), so that a step that hands it work every few tens of
//! microseconds finds it awake, and an idle run (or one whose cores are taken by other
//! processes) does not burn a time slice.
//!
//! **The caller never waits for a helper that has not started.** When the caller has done
//! its own half and the helper has not yet taken the other (it is parked, or waiting for a
//! core that other processes hold), the caller takes the job back and runs it itself, as
//! `rayon::join` pops its own job when no worker stole it. So under a competing load a
//! step costs at most what it costs on one thread plus two atomic operations a hand-off;
//! only a half the helper is already running is waited for: spinning for at most
//! [`CALLER_SPIN`], then blocked until the helper wakes it.
//!
//! **A machine whose cores are taken.** The team's watcher thread reads the run queue
//! (`/proc/loadavg`) every [`LOAD_PERIOD`] and keeps what it read in an atomic; nothing
//! reads the file in the solve loop. Every [`LOAD_CHECK`] joins the caller looks at that
//! value: when other processes' runnable threads are as many as the
//! cores (`others >= cores`: one short-lived process does not count), the next
//! `LOAD_CHECK` joins run on the caller's thread alone, then it looks again (twice as
//! many joins after each look that finds the cores taken, up to 16 times); it goes back to
//! two threads only when a core is free for each (`others + 2 <= cores`), so that two runs
//! side by side, each seeing the other's one thread, keep to one thread each. A helper
//! that would start its half and lose its core in the middle of it (the caller then waits
//! a time slice) is not asked; on an idle machine nothing changes. [`Team::for_each`]
//! uses as many of the team's threads as cores are free of other processes at that look
//! (at least two, at most the machine's cores): `--threads 4` on two cores runs as two.
//!
//! Nothing here is process-wide: the helpers belong to their team, which belongs to a run
//! (created when the run is built, handed to its stepper, row solver and energies as
//! clones), and ends when the last clone is dropped. A team never runs work on the caller's
//! rayon pool, so a run inside a caller's pool takes none of the pool's workers. The default
//! team (`Team::default()`, what a factor or stepper built outside a run uses) is
//! `rayon::join` in whatever pool it is called from.
//!
//! Every computation makes its sums in the same order whatever the team, so the results
//! are the same bits on any number of threads.

use std::any::Any;
use std::cell::UnsafeCell;
use std::num::NonZeroUsize;
use std::sync::atomic::{AtomicBool, AtomicU32, Ordering};
use std::sync::Arc;
use std::thread::{JoinHandle, Thread};
use std::time::{Duration, Instant};

/// How many threads a computation may use (as faer's `Par`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Par {
    /// One thread: the caller's.
    Seq,
    /// Up to this many threads (the caller's and helpers of its own).
    Threads(NonZeroUsize),
}

impl Par {
    /// `n` threads: [`Par::Seq`] for 0 or 1.
    pub fn threads(n: usize) -> Self {
        match NonZeroUsize::new(n) {
            Some(n) if n.get() >= 2 => Par::Threads(n),
            _ => Par::Seq,
        }
    }

    /// The threads of the rayon pool the caller runs in (its global pool outside any): a run
    /// started inside a caller's `ThreadPool::install` follows that pool.
    pub fn current() -> Self {
        Par::threads(rayon::current_num_threads())
    }

    /// The number of threads, at least one.
    pub fn count(self) -> usize {
        match self {
            Par::Seq => 1,
            Par::Threads(n) => n.get(),
        }
    }
}

/// How long the helper spins for its next job before it blocks. The wheel's step hands it
/// work every 10-60 us (`wheel.toml`, 3,432 dofs: five hand-offs in a step of ~110 us),
/// so a spin of this length keeps it awake within a step and lets it block between runs or
/// when its core is wanted elsewhere.
pub const HELPER_SPIN: Duration = Duration::from_micros(250);

/// How long the caller spins for the half the helper is running before it blocks: the
/// halves take tens of microseconds, and a blocked caller woken under a competing load
/// may wait a time slice for its core.
pub const CALLER_SPIN: Duration = Duration::from_micros(200);

/// Spins up to `limit` (checking the clock every 64 turns) for `ready`; true if it came.
fn spin_until(limit: Duration, ready: impl Fn() -> bool) -> bool {
    let since = Instant::now();
    let mut n = 0u32;
    loop {
        if ready() {
            return true;
        }
        n = n.wrapping_add(1);
        if n % 64 == 0 && since.elapsed() >= limit {
            return false;
        }
        std::hint::spin_loop();
    }
}

const IDLE: u32 = 0;
const POSTED: u32 = 1;
const DONE: u32 = 2;
/// The helper took the posted job (and runs it); the caller can no longer take it back.
const RUNNING: u32 = 3;

/// The job handed to the helper: a closure on the caller's stack, its lifetime erased (the
/// caller waits for `DONE` before the closure's frame ends, unwinding included).
type Job = *const (dyn Fn() + Sync);

/// What the caller and the helper share.
struct Shared {
    state: AtomicU32,
    /// Set by the helper before it blocks; a caller that posts a job then wakes it.
    helper_blocked: AtomicBool,
    /// Set by the caller before it blocks; the helper that reports `DONE` then wakes it.
    caller_blocked: AtomicBool,
    /// The caller's claim (one caller at a time).
    claimed: AtomicBool,
    /// Set when the team is dropped: the helper returns.
    stop: AtomicBool,
    job: UnsafeCell<Option<Job>>,
    /// The thread of the caller of the posted job (to wake it).
    caller: UnsafeCell<Option<Thread>>,
    panic: UnsafeCell<Option<Box<dyn Any + Send>>>,
    /// Other processes' runnable threads as the watcher last read them
    /// ([`others_running`]; `u32::MAX`: not known).
    others: AtomicU32,
}

// SAFETY: `job`, `caller` and `panic` are written by the claimant before it posts (Release)
// and by the helper before it reports `DONE` (Release), and read by the other side after it
// observed that state (Acquire): the protocol orders every access. The raw job pointer is
// only dereferenced while the caller's frame that owns the closure waits for `DONE`.
unsafe impl Sync for Shared {}
// SAFETY: as above; the helper thread holds the shared state, not the job's closure.
unsafe impl Send for Shared {}

/// The helper thread and its shared state; dropping it stops and joins the helper.
struct Owner {
    shared: Arc<Shared>,
    thread: Option<JoinHandle<()>>,
    /// The helpers beyond the first (a team of `n` threads has `n - 1`): each its own
    /// shared state and thread, asked only by [`Team::for_each`] under the first's claim.
    more: Vec<(Arc<Shared>, Option<JoinHandle<()>>)>,
    /// The threads [`Team::for_each`] uses now (the caller's included, at least 2): the
    /// team's own at most, the machine's free cores at the last look ([`LOAD_CHECK`]).
    width: AtomicU32,
    /// The watcher of the machine's run queue ([`watcher_loop`]).
    watcher: Option<JoinHandle<()>>,
    /// Joins still to run on the caller's thread alone, after the caller took a job back
    /// ([`MAX_BACKOFF`]).
    skip: AtomicU32,
    /// Take-backs in a row (one more at each, halved at each join the helper served): from
    /// two on, `2^streak` joins (at most [`MAX_BACKOFF`]) run on the caller's thread alone.
    backoff: AtomicU32,
    /// Joins asked of this team, for the machine's check every [`LOAD_CHECK`] joins.
    joins: AtomicU32,
    /// Checks in a row that found the machine's cores taken: the next window is
    /// `LOAD_CHECK` times `2^loaded` joins (at most 16 times).
    loaded: AtomicU32,
    /// The machine's cores (`std::thread::available_parallelism`).
    cores: usize,
}

/// Every this many joins the team looks at the machine's run queue ([`others_running`]):
/// when the threads of other processes that are runnable are as many as the cores (the
/// helper would wait for a core, and so would the caller), the next
/// `LOAD_CHECK` joins run on the caller's thread alone (after each further check that finds
/// the cores taken, twice as many, up to 16 times: the look, a few microseconds on an idle
/// machine, may cost a time slice on a loaded one). About fifty steps of the wheel (five
/// hand-offs a step), some 5 ms.
pub const LOAD_CHECK: u32 = 256;

/// The threads of other processes that are runnable now: the running count of
/// `/proc/loadavg` (its fourth field, `running/total`) less this run's (`ours`); `None`
/// off Linux or when the file cannot be read.
pub fn others_running(ours: usize) -> Option<usize> {
    let text = std::fs::read_to_string("/proc/loadavg").ok()?;
    parse_running(&text).map(|r| r.saturating_sub(ours))
}

/// The running count of a `/proc/loadavg` text (`0.52 0.58 0.59 3/512 12345`).
fn parse_running(text: &str) -> Option<usize> {
    text.split_whitespace()
        .nth(3)?
        .split('/')
        .next()?
        .parse()
        .ok()
}

/// The longest run of joins done on the caller's thread alone after the caller had to take
/// a job back (the helper was not there to start it): on a machine whose cores other
/// processes hold, the run then keeps to one thread and asks for the helper once in this
/// many hand-offs (about fifty steps of the wheel), instead of at every one.
pub const MAX_BACKOFF: u32 = 256;

impl Drop for Owner {
    fn drop(&mut self) {
        self.shared.stop.store(true, Ordering::SeqCst);
        for (h, _) in &self.more {
            h.stop.store(true, Ordering::SeqCst);
        }
        let more = self.more.iter_mut().map(|(_, t)| t.take());
        for t in [self.thread.take(), self.watcher.take()]
            .into_iter()
            .chain(more)
            .flatten()
        {
            t.thread().unpark();
            let _ = t.join();
        }
    }
}

#[derive(Clone, Default)]
enum Kind {
    /// `rayon::join` in the caller's pool.
    #[default]
    Pool,
    /// Both closures on the caller's thread, one after the other.
    Seq,
    /// A helper thread of the team's own.
    Helper(Arc<Owner>),
}

/// Runs two closures side by side on threads that belong to a run ([module docs](self)).
/// Clones share the same helper; it ends when the last clone is dropped.
#[derive(Clone, Default)]
pub struct Team {
    kind: Kind,
}

impl std::fmt::Debug for Team {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self.kind {
            Kind::Pool => "Team(pool)",
            Kind::Seq => "Team(seq)",
            Kind::Helper(_) => "Team(helper)",
        })
    }
}

impl Team {
    /// A team for `par`: one thread for [`Par::Seq`], the caller's and `n - 1` helper
    /// threads of its own for `Par::Threads(n)` (as many as could be started; one thread
    /// if none could), with the watcher of the machine's load.
    pub fn new(par: Par) -> Self {
        let cores = std::thread::available_parallelism().map_or(1, NonZeroUsize::get);
        Team::build(par, cores, true)
    }

    /// A team of `par`'s threads that uses them all whatever the machine's cores and load
    /// (no watcher): for the tests that check the same bits on more threads than cores.
    #[cfg(test)]
    pub(crate) fn oversubscribed(par: Par) -> Self {
        Team::build(par, par.count(), false)
    }

    fn build(par: Par, cores: usize, watch: bool) -> Self {
        if par == Par::Seq {
            return Team { kind: Kind::Seq };
        }
        let spawn = || {
            let shared = Arc::new(Shared::new());
            let for_helper = Arc::clone(&shared);
            std::thread::Builder::new()
                .name("softway-team".into())
                .spawn(move || helper_loop(&for_helper))
                .ok()
                .map(|t| (shared, t))
        };
        let Some((shared, thread)) = spawn() else {
            return Team { kind: Kind::Seq };
        };
        let more: Vec<_> = (2..par.count())
            .map_while(|_| spawn())
            .map(|(s, t)| (s, Some(t)))
            .collect();
        let mut all = vec![Arc::clone(&shared)];
        all.extend(more.iter().map(|(s, _)| Arc::clone(s)));
        let threads = 1 + all.len();
        // Without a watcher the team never sees the machine's load: it keeps to its
        // take-backs alone.
        let watcher = watch
            .then(|| {
                std::thread::Builder::new()
                    .name("softway-load".into())
                    .spawn(move || watcher_loop(&all))
                    .ok()
            })
            .flatten();
        Team {
            kind: Kind::Helper(Arc::new(Owner {
                shared,
                thread: Some(thread),
                more,
                width: AtomicU32::new(threads.min(cores).max(2) as u32),
                watcher,
                skip: AtomicU32::new(0),
                backoff: AtomicU32::new(0),
                joins: AtomicU32::new(0),
                loaded: AtomicU32::new(0),
                cores,
            })),
        }
    }

    /// The threads this team runs on: [`Par::Seq`], or the caller's and its helpers'; the
    /// default team's are those of the pool it is asked from ([`Par::current`]).
    pub fn par(&self) -> Par {
        match &self.kind {
            Kind::Pool => Par::current(),
            Kind::Seq => Par::Seq,
            Kind::Helper(owner) => Par::threads(owner.threads()),
        }
    }

    /// The parts worth giving [`Team::for_each`] now: the threads it would use (the
    /// team's own, at most the machine's cores not taken by other processes at the last
    /// look, at least two with a helper; one for [`Par::Seq`]). A hint: the results of a
    /// computation must not depend on it.
    pub fn width(&self) -> usize {
        match &self.kind {
            Kind::Pool => rayon::current_num_threads(),
            Kind::Seq => 1,
            Kind::Helper(owner) => owner.width.load(Ordering::Relaxed) as usize,
        }
    }

    /// Runs `a` on this thread and `b` on the team's other thread (both here with
    /// [`Par::Seq`], `a` first, or when the helper is serving another caller of the same
    /// team); returns when both have. A panic in either reaches the caller.
    pub fn join<A, B>(&self, a: A, b: B)
    where
        A: FnOnce() + Send,
        B: FnOnce() + Send,
    {
        match &self.kind {
            Kind::Pool => {
                rayon::join(a, b);
            }
            Kind::Seq => {
                a();
                b();
            }
            Kind::Helper(owner) => {
                if !owner.admit() {
                    a();
                    b();
                    return;
                }
                let thread = owner.thread.as_ref().map(|t| t.thread());
                let taken_back = join_on(&owner.shared, thread, a, b);
                owner.served(taken_back);
            }
        }
    }

    /// Calls `f` once on every item, the items in up to [`Team::width`] contiguous groups
    /// side by side: the first group on this thread, the others on the team's helpers
    /// (all on this thread with [`Par::Seq`], when the machine's cores are taken, or when
    /// another caller of the same team holds its helpers). A helper that has not started
    /// its group when the caller is done with its own is not waited for: the caller runs
    /// that group itself. Returns when every item is done; a panic reaches the caller.
    /// Which thread runs an item never changes what `f` computes: an item's work must not
    /// depend on the others'.
    pub fn for_each<T, F>(&self, items: &mut [T], f: F)
    where
        T: Send,
        F: Fn(&mut T) + Sync,
    {
        match &self.kind {
            Kind::Pool => pool_for_each(items, &f),
            Kind::Seq => items.iter_mut().for_each(f),
            Kind::Helper(owner) => {
                if items.len() < 2 || !owner.admit() {
                    items.iter_mut().for_each(f);
                    return;
                }
                let taken_back = for_each_on(owner, items, &f);
                owner.served(taken_back);
            }
        }
    }

    /// The helper's shared state, for the tests to see the helper end.
    #[cfg(test)]
    fn shared(&self) -> Option<std::sync::Weak<Shared>> {
        match &self.kind {
            Kind::Helper(o) => Some(Arc::downgrade(&o.shared)),
            _ => None,
        }
    }
}

impl Shared {
    fn new() -> Self {
        Shared {
            state: AtomicU32::new(IDLE),
            helper_blocked: AtomicBool::new(false),
            caller_blocked: AtomicBool::new(false),
            claimed: AtomicBool::new(false),
            stop: AtomicBool::new(false),
            job: UnsafeCell::new(None),
            caller: UnsafeCell::new(None),
            panic: UnsafeCell::new(None),
            others: AtomicU32::new(u32::MAX),
        }
    }
}

impl Owner {
    /// The caller's thread and the helpers.
    fn threads(&self) -> usize {
        2 + self.more.len()
    }

    /// Claims the first helper for this caller and decides whether this hand-off goes to
    /// the helpers: false (the claim released, or not got) when another caller holds
    /// them, or when the machine's cores are taken or the helpers were not there to
    /// start the last hand-offs (the caller then runs everything itself).
    fn admit(&self) -> bool {
        let h = &*self.shared;
        if h.claimed
            .compare_exchange(false, true, Ordering::Acquire, Ordering::Relaxed)
            .is_err()
        {
            return false;
        }
        // The claim makes this caller the only one to touch `skip`, `backoff` and `width`.
        let joins = self.joins.load(Ordering::Relaxed).wrapping_add(1);
        self.joins.store(joins, Ordering::Relaxed);
        if joins % LOAD_CHECK == 0 && self.skip.load(Ordering::Relaxed) == 0 {
            self.look();
        }
        let skip = self.skip.load(Ordering::Relaxed);
        if skip > 0 {
            self.skip.store(skip - 1, Ordering::Relaxed);
            h.claimed.store(false, Ordering::Release);
            return false;
        }
        true
    }

    /// The look at the machine every [`LOAD_CHECK`] hand-offs (the watcher's last
    /// reading: an atomic load, no file read here). Enter one thread when the others
    /// fill the cores; leave it only when a core is free for each of this run's first two
    /// threads (between the two, as two runs side by side see each other: stay). Beyond
    /// two, [`Team::for_each`] uses as many threads as cores are free (at least two).
    fn look(&self) {
        let loaded = self.loaded.load(Ordering::Relaxed);
        let others = self.shared.others.load(Ordering::Relaxed);
        let others = (others != u32::MAX).then_some(others as usize);
        match others {
            Some(o) if o >= self.cores || (loaded > 0 && o + 2 > self.cores) => {
                self.loaded.store((loaded + 1).min(4), Ordering::Relaxed);
                self.skip
                    .store(LOAD_CHECK << loaded.min(4), Ordering::Relaxed);
            }
            _ => self.loaded.store(0, Ordering::Relaxed),
        }
        let free = others.map_or(self.cores, |o| self.cores.saturating_sub(o));
        let width = free.min(self.threads()).max(2);
        self.width.store(width as u32, Ordering::Relaxed);
    }

    /// After a hand-off the helpers served (`taken_back`: the caller had to run a part
    /// itself, its helper not there to start it): a take-back after a pause (the helper
    /// had parked) wakes the helper for the next one; take-backs in a row mean its core
    /// is held elsewhere, and the next hand-offs run on the caller's thread alone.
    fn served(&self, taken_back: bool) {
        let last = self.backoff.load(Ordering::Relaxed);
        let streak = if taken_back { last + 1 } else { last / 2 };
        self.backoff.store(streak.min(16), Ordering::Relaxed);
        let skip = if taken_back && streak >= 2 {
            (1u32 << streak.min(16)).min(MAX_BACKOFF)
        } else {
            0
        };
        self.skip.store(skip, Ordering::Relaxed);
    }
}

/// [`Team::for_each`] in the caller's rayon pool: halves by `rayon::join`.
fn pool_for_each<T: Send, F: Fn(&mut T) + Sync>(items: &mut [T], f: &F) {
    match items.len() {
        0 => {}
        1 => f(&mut items[0]),
        n => {
            let (lo, hi) = items.split_at_mut(n / 2);
            rayon::join(|| pool_for_each(lo, f), || pool_for_each(hi, f));
        }
    }
}

/// How often the watcher reads the machine's run queue: about [`LOAD_CHECK`] joins of the
/// wheel's step.
pub const LOAD_PERIOD: Duration = Duration::from_millis(5);

/// The watcher: every [`LOAD_PERIOD`], the other processes' runnable threads
/// ([`others_running`], less this run's: the watcher, the caller and the helpers that are
/// not blocked) into the first helper's `others`, until the team is dropped. `all`: the
/// helpers' shared states, the first's first.
fn watcher_loop(all: &[Arc<Shared>]) {
    let h = &*all[0];
    while !h.stop.load(Ordering::Acquire) {
        let awake = all
            .iter()
            .filter(|s| !s.helper_blocked.load(Ordering::Relaxed))
            .count();
        let others =
            others_running(2 + awake).map_or(u32::MAX, |o| o.min(u32::MAX as usize - 1) as u32);
        h.others.store(others, Ordering::Relaxed);
        std::thread::park_timeout(LOAD_PERIOD);
    }
}

fn helper_loop(h: &Shared) {
    loop {
        let posted = || h.state.load(Ordering::Acquire) == POSTED || h.stop.load(Ordering::Acquire);
        while !spin_until(HELPER_SPIN, posted) {
            h.helper_blocked.store(true, Ordering::SeqCst);
            if h.state.load(Ordering::SeqCst) != POSTED && !h.stop.load(Ordering::SeqCst) {
                std::thread::park();
            }
            h.helper_blocked.store(false, Ordering::SeqCst);
        }
        if h.stop.load(Ordering::Acquire) && h.state.load(Ordering::Acquire) != POSTED {
            return;
        }
        // Take the job, unless the caller took it back first (it runs it itself when the
        // helper was not there to start it: a helper that waits for a time slice of its
        // own under a competing load never delays the caller).
        if h.state
            .compare_exchange(POSTED, RUNNING, Ordering::SeqCst, Ordering::SeqCst)
            .is_err()
        {
            continue;
        }
        // SAFETY: the helper moved POSTED to RUNNING: the claimant wrote the job and its
        // thread before posting, and does not touch them until DONE.
        let (job, caller) = unsafe { ((*h.job.get()).take(), (*h.caller.get()).take()) };
        let job = job.expect("a posted job");
        // SAFETY: the claimant keeps the closure alive until it observes DONE.
        let r = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| unsafe { (*job)() }));
        if let Err(p) = r {
            // SAFETY: the claimant reads it only after DONE (SeqCst, below).
            unsafe { *h.panic.get() = Some(p) };
        }
        h.state.store(DONE, Ordering::SeqCst);
        if h.caller_blocked.load(Ordering::SeqCst) {
            if let Some(c) = caller {
                c.unpark();
            }
        }
    }
}

/// The caller's claim on the helper. [`Claim::finish`] waits for the helper's job and
/// releases the claim; dropping an unfinished claim (the caller's own closure unwinding)
/// does the same, since the helper's job borrows the caller's frame.
struct Claim<'a> {
    h: &'a Shared,
    finished: bool,
}

impl Claim<'_> {
    /// Takes the posted job back if the helper has not started it (`POSTED -> IDLE`):
    /// true if it did (the caller then runs it, or drops it when unwinding), with the job
    /// slots cleared and the claim released.
    fn take_back(&mut self) -> bool {
        let h = self.h;
        if h.state
            .compare_exchange(POSTED, IDLE, Ordering::SeqCst, Ordering::SeqCst)
            .is_err()
        {
            return false;
        }
        // SAFETY: the helper did not move POSTED to RUNNING, so it never reads the slots
        // of this job; the claim is still held, so no other caller writes them.
        unsafe {
            *h.job.get() = None;
            *h.caller.get() = None;
        }
        self.finished = true;
        h.claimed.store(false, Ordering::Release);
        true
    }

    /// Waits for `DONE` (spinning up to [`CALLER_SPIN`], then blocked), releases the
    /// claim; the helper's panic, if its job panicked. The helper is running the job:
    /// [`Claim::take_back`] failed.
    fn finish(&mut self) -> Option<Box<dyn Any + Send>> {
        let h = self.h;
        let done = || h.state.load(Ordering::Acquire) == DONE;
        if !spin_until(CALLER_SPIN, done) {
            h.caller_blocked.store(true, Ordering::SeqCst);
            while h.state.load(Ordering::SeqCst) != DONE {
                std::thread::park();
            }
            h.caller_blocked.store(false, Ordering::SeqCst);
        }
        // SAFETY: DONE was observed (Acquire); the helper wrote the slot before it.
        let p = unsafe { (*h.panic.get()).take() };
        h.state.store(IDLE, Ordering::Relaxed);
        self.finished = true;
        h.claimed.store(false, Ordering::Release);
        p
    }
}

impl Drop for Claim<'_> {
    fn drop(&mut self) {
        if !self.finished && !self.take_back() {
            let _ = self.finish();
        }
    }
}

/// `a` here, `b` on the claimed helper `thread` of `h`; true when the helper had not
/// started `b` by the time `a` was done, so that the caller took it back and ran it.
fn join_on<A, B>(h: &Shared, thread: Option<&Thread>, a: A, b: B) -> bool
where
    A: FnOnce() + Send,
    B: FnOnce() + Send,
{
    let Some(thread) = thread else {
        h.claimed.store(false, Ordering::Release);
        a();
        b();
        return false;
    };
    let b = std::sync::Mutex::new(Some(b));
    let run_b = || {
        if let Some(b) = b.lock().unwrap_or_else(|e| e.into_inner()).take() {
            b()
        }
    };
    let mut claim = post(h, thread, &run_b);
    a();
    if claim.take_back() {
        // The helper had not started `b` (asleep, or waiting for a core): run it here
        // rather than wait for it.
        run_b();
        return true;
    }
    if let Some(p) = claim.finish() {
        std::panic::resume_unwind(p);
    }
    false
}

/// [`Team::for_each`] on the claimed first helper of `owner` and as many more as its
/// width allows: the items in contiguous groups, the first here, each other one posted to
/// a helper of its own; true when a helper had not started its group by the time the
/// caller was done with its own (the caller then took it back and ran it). The first
/// helper's claim, the team's, is released last.
fn for_each_on<T, F>(owner: &Owner, items: &mut [T], f: &F) -> bool
where
    T: Send,
    F: Fn(&mut T) + Sync,
{
    let width = (owner.width.load(Ordering::Relaxed) as usize)
        .min(owner.threads())
        .min(items.len());
    // Contiguous groups as even as the count allows, the first `items % width` one longer.
    let (per, extra) = (items.len() / width, items.len() % width);
    let mut groups = Vec::with_capacity(width);
    let mut rest = items;
    for g in 0..width {
        let (head, tail) = rest.split_at_mut(per + usize::from(g < extra));
        groups.push(head);
        rest = tail;
    }
    let mut groups = groups.into_iter();
    let mine = groups.next().expect("a group for the caller");
    // The helpers' groups, each behind a lock that the one who runs it (the helper, or
    // the caller taking it back) empties.
    let slots: Vec<_> = groups.map(|g| std::sync::Mutex::new(Some(g))).collect();
    let runs: Vec<_> = slots
        .iter()
        .map(|slot| {
            move || {
                if let Some(g) = slot.lock().unwrap_or_else(|e| e.into_inner()).take() {
                    g.iter_mut().for_each(f);
                }
            }
        })
        .collect();
    let helpers = std::iter::once((&owner.shared, owner.thread.as_ref()))
        .chain(owner.more.iter().map(|(s, t)| (s, t.as_ref())));
    let mut claims = Vec::with_capacity(runs.len());
    let mut here = Vec::new();
    for (k, (h, t)) in helpers.take(runs.len()).enumerate() {
        // The first helper is claimed (`Owner::admit`); the others are asked only under
        // its claim, but a helper without a thread runs nothing.
        let claimed = k == 0
            || h.claimed
                .compare_exchange(false, true, Ordering::Acquire, Ordering::Relaxed)
                .is_ok();
        match (claimed, t) {
            (true, Some(t)) => claims.push((k, post(h, t.thread(), &runs[k]))),
            (true, None) => {
                h.claimed.store(false, Ordering::Release);
                here.push(k);
            }
            (false, _) => here.push(k),
        }
    }
    mine.iter_mut().for_each(f);
    for &k in &here {
        runs[k]();
    }
    let mut taken_back = false;
    let mut panic = None;
    // The first helper's claim (the team's) last.
    while let Some((k, mut claim)) = claims.pop() {
        if claim.take_back() {
            runs[k]();
            taken_back = true;
        } else if let Some(p) = claim.finish() {
            panic.get_or_insert(p);
        }
    }
    if let Some(p) = panic {
        std::panic::resume_unwind(p);
    }
    taken_back
}

/// Posts `job` to the claimed helper `h` (its thread `thread`) and wakes it if it is
/// blocked; the claim that waits for it.
fn post<'a>(h: &'a Shared, thread: &Thread, job: &'a (dyn Fn() + Sync + 'a)) -> Claim<'a> {
    // SAFETY: the helper calls `job` only before it reports DONE, and the returned
    // `Claim` (whose drop waits for DONE) lives no longer than `job`'s borrow.
    let job: Job = unsafe { std::mem::transmute::<&(dyn Fn() + Sync), Job>(job) };
    // SAFETY: the helper is IDLE (claimed, and every claim ends in IDLE): it does not read.
    unsafe {
        *h.job.get() = Some(job);
        *h.caller.get() = Some(std::thread::current());
    }
    h.state.store(POSTED, Ordering::SeqCst);
    if h.helper_blocked.load(Ordering::SeqCst) {
        thread.unpark();
    }
    Claim { h, finished: false }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn teams() -> [Team; 3] {
        [
            Team::new(Par::Seq),
            Team::new(Par::threads(2)),
            Team::default(),
        ]
    }

    #[test]
    fn both_closures_run_and_see_their_borrows() {
        for team in teams() {
            let mut x = vec![0u64; 1000];
            let (lo, hi) = x.split_at_mut(500);
            for _ in 0..200 {
                team.join(
                    || lo.iter_mut().for_each(|v| *v += 1),
                    || hi.iter_mut().for_each(|v| *v += 2),
                );
            }
            assert!(x[..500].iter().all(|&v| v == 200), "{team:?}");
            assert!(x[500..].iter().all(|&v| v == 400), "{team:?}");
        }
    }

    /// With [`Par::Seq`] both closures run on the caller's thread, `a` first.
    #[test]
    fn a_sequential_team_runs_both_on_the_callers_thread_in_order() {
        let team = Team::new(Par::Seq);
        assert_eq!(team.par(), Par::Seq);
        let me = std::thread::current().id();
        let order = std::sync::Mutex::new(Vec::new());
        team.join(
            || {
                order
                    .lock()
                    .unwrap()
                    .push(("a", std::thread::current().id()))
            },
            || {
                order
                    .lock()
                    .unwrap()
                    .push(("b", std::thread::current().id()))
            },
        );
        assert_eq!(order.into_inner().unwrap(), [("a", me), ("b", me)]);
    }

    /// With a helper, `b` runs on another thread, the helper's, when `a` lasts until the
    /// helper has started it; when `a` is done first and the helper has not started `b`,
    /// the caller takes `b` back: either way both run once.
    #[test]
    fn a_team_of_two_runs_the_second_closure_on_its_helper() {
        let team = Team::new(Par::threads(2));
        assert_eq!(team.par(), Par::threads(2));
        let me = std::thread::current().id();
        let (mut ta, mut tb) = (None, None);
        let started = AtomicBool::new(false);
        team.join(
            || {
                ta = Some(std::thread::current().id());
                let since = Instant::now();
                while !started.load(Ordering::SeqCst) && since.elapsed() < Duration::from_secs(10) {
                    std::hint::spin_loop();
                }
            },
            || {
                started.store(true, Ordering::SeqCst);
                tb = Some(std::thread::current().id());
            },
        );
        assert_eq!(ta, Some(me));
        assert!(tb.is_some() && tb != Some(me));
        let mut runs = [0u32; 2];
        let (ra, rb) = runs.split_at_mut(1);
        for _ in 0..1000 {
            team.join(|| ra[0] += 1, || rb[0] += 1);
        }
        assert_eq!(runs, [1000, 1000]);
    }

    #[test]
    fn a_panic_in_either_closure_reaches_the_caller_and_the_helper_serves_again() {
        let team = Team::new(Par::threads(2));
        let r = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
            team.join(|| (), || panic!("b"))
        }));
        assert!(r.is_err());
        let r = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
            team.join(|| panic!("a"), || ())
        }));
        assert!(r.is_err());
        let mut s = [0; 2];
        let (p, q) = s.split_at_mut(1);
        team.join(|| p[0] = 1, || q[0] = 2);
        assert_eq!(s, [1, 2]);
    }

    /// The helper blocks when idle (after [`HELPER_SPIN`]), still serves after it was
    /// woken, and ends (its thread joined, the shared state freed) when the last clone of
    /// its team is dropped.
    #[test]
    fn the_helper_blocks_when_idle_and_ends_with_its_team() {
        let team = Team::new(Par::threads(2));
        let shared = team.shared().expect("a helper");
        let mut s = [0; 2];
        let (p, q) = s.split_at_mut(1);
        team.join(|| p[0] = 1, || q[0] = 2);
        let since = Instant::now();
        let blocked = || {
            shared
                .upgrade()
                .unwrap()
                .helper_blocked
                .load(Ordering::SeqCst)
        };
        while !blocked() && since.elapsed() < Duration::from_secs(5) {
            std::thread::sleep(Duration::from_millis(1));
        }
        assert!(
            blocked(),
            "the helper still spins after {:?}",
            since.elapsed()
        );
        team.join(|| p[0] = 3, || q[0] = 4);
        assert_eq!(s, [3, 4]);
        let clone = team.clone();
        drop(team);
        assert!(shared.upgrade().is_some(), "a clone keeps the helper");
        clone.join(|| (), || ());
        drop(clone);
        assert!(shared.upgrade().is_none(), "the helper outlived its team");
    }

    /// [`Par::current`] follows the pool it is asked from.
    #[test]
    fn the_run_queue_is_read_from_loadavg() {
        assert_eq!(parse_running("0.52 0.58 0.59 3/512 12345\n"), Some(3));
        assert_eq!(parse_running("0.52 0.58"), None);
        assert_eq!(parse_running("a b c x/9 1"), None);
        if std::path::Path::new("/proc/loadavg").exists() {
            // This thread runs while it reads.
            assert!(others_running(0).is_some_and(|n| n >= 1));
        }
    }

    /// The watcher, not the solve loop, reads the run queue: a team's `others` is filled
    /// within a few periods on Linux, and the watcher ends with the team.
    #[test]
    fn the_watcher_reads_the_run_queue_for_the_team() {
        let team = Team::new(Par::threads(2));
        let shared = team.shared().expect("a helper team");
        if std::path::Path::new("/proc/loadavg").exists() {
            let t0 = std::time::Instant::now();
            let seen = loop {
                let o = shared.upgrade().unwrap().others.load(Ordering::Relaxed);
                if o != u32::MAX || t0.elapsed() > Duration::from_secs(2) {
                    break o;
                }
                std::thread::sleep(LOAD_PERIOD);
            };
            assert_ne!(seen, u32::MAX, "no reading in 2 s");
        }
        drop(team);
        assert!(shared.upgrade().is_none(), "the watcher outlived its team");
    }

    #[test]
    fn par_follows_the_callers_pool() {
        let pool = |n| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(n)
                .build()
                .unwrap()
        };
        assert_eq!(pool(1).install(Par::current), Par::Seq);
        assert_eq!(pool(3).install(Par::current), Par::threads(3));
        assert_eq!(Par::threads(0), Par::Seq);
        assert_eq!(Par::threads(3).count(), 3);
        assert_eq!(pool(1).install(|| Team::default().par()), Par::Seq);
    }

    /// Two callers of one team at once: one gets the helper, the other runs both of its
    /// closures itself; every result is right.
    #[test]
    fn two_callers_of_one_team_share_it() {
        let team = Team::new(Par::threads(2));
        std::thread::scope(|s| {
            for k in 0..2u64 {
                let team = &team;
                s.spawn(move || {
                    for i in 0..500u64 {
                        let (mut x, mut y) = (0, 0);
                        team.join(|| x = i + k, || y = 2 * i + k);
                        assert_eq!((x, y), (i + k, 2 * i + k));
                    }
                });
            }
        });
    }

    /// `for_each` on teams of one to four threads (more than the machine may have): every
    /// item once per call, whatever the thread that runs it; with four threads and four
    /// items that each wait for all four to have started, four distinct threads ran them
    /// (no group waits for a helper that another group holds).
    #[test]
    fn for_each_runs_every_item_once_on_up_to_n_threads() {
        for threads in 1..=4 {
            let team = Team::oversubscribed(Par::threads(threads));
            assert_eq!(team.par(), Par::threads(threads));
            assert_eq!(team.width(), threads);
            for len in [0, 1, 2, 3, 4, 7] {
                let mut items = vec![0u32; len];
                for _ in 0..200 {
                    team.for_each(&mut items, |x| *x += 1);
                }
                assert!(
                    items.iter().all(|&x| x == 200),
                    "{threads} threads, {len} items"
                );
            }
        }
        let team = Team::oversubscribed(Par::threads(4));
        let started = std::sync::atomic::AtomicUsize::new(0);
        let mut items: Vec<Option<std::thread::ThreadId>> = vec![None; 4];
        team.for_each(&mut items, |t| {
            started.fetch_add(1, Ordering::SeqCst);
            let since = Instant::now();
            while started.load(Ordering::SeqCst) < 4 && since.elapsed() < Duration::from_secs(10) {
                std::hint::spin_loop();
            }
            *t = Some(std::thread::current().id());
        });
        let ids: std::collections::BTreeSet<_> = items
            .iter()
            .map(|t| format!("{:?}", t.expect("ran")))
            .collect();
        assert_eq!(ids.len(), 4, "four threads ran the four items");
        // The watched team of four reports its four threads.
        assert_eq!(Team::new(Par::threads(4)).par(), Par::threads(4));
    }

    /// A panic in any group of `for_each` reaches the caller once every helper is done,
    /// and the team serves again.
    #[test]
    fn a_panic_in_for_each_reaches_the_caller_and_the_team_serves_again() {
        let team = Team::oversubscribed(Par::threads(3));
        for bad in 0..3 {
            let mut items = [0usize, 1, 2];
            let r = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
                team.for_each(&mut items, |x| {
                    if *x == bad {
                        panic!("item {bad}")
                    }
                })
            }));
            assert!(r.is_err(), "item {bad}");
        }
        let mut items = [1u32; 3];
        team.for_each(&mut items, |x| *x *= 5);
        assert_eq!(items, [5; 3]);
        let mut s = [0; 2];
        let (p, q) = s.split_at_mut(1);
        team.join(|| p[0] = 1, || q[0] = 2);
        assert_eq!(s, [1, 2]);
    }
}
