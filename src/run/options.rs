//! What a job is run with: the options, the cancellation token, the progress.

use crate::guard::GuardMode;
use crate::linalg::team::Par;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

/// A cancellation token: the caller keeps a clone and calls [`Cancel::cancel`] (the CLI
/// from its Ctrl-C handler); a job stops at its next step and keeps what it has. Clones
/// share one flag; a fresh token is not cancelled.
#[derive(Debug, Clone, Default)]
pub struct Cancel(Arc<AtomicBool>);

impl Cancel {
    /// A token not cancelled.
    pub fn new() -> Self {
        Self::default()
    }

    /// Cancels every job that holds a clone of this token; returns true if it already was.
    pub fn cancel(&self) -> bool {
        self.0.swap(true, Ordering::SeqCst)
    }

    /// True once [`Cancel::cancel`] was called on a clone.
    pub fn is_cancelled(&self) -> bool {
        self.0.load(Ordering::Relaxed)
    }

    /// The flag itself, as `Simulation::run` reads it.
    pub fn flag(&self) -> &AtomicBool {
        &self.0
    }
}

/// Options of a job.
#[derive(Debug, Clone, Default)]
pub struct RunOptions {
    /// Show a progress bar (on a terminal).
    pub progress: bool,
    /// The threads of each run; `None` (the default): [`Par::current`] when the run starts,
    /// i.e. the rayon pool it is called in. Sweeps run their runs side by side, each on its
    /// share of the cores (one thread when as many run at once as there are cores).
    pub par: Option<Par>,
    /// Stops the job at its next step (it then keeps what it has, `interrupted` set).
    pub cancel: Cancel,
    /// What the divergence guard does ([`crate::guard`]): stop the run (the default), or
    /// record where it diverged and go on (the comparison lab's rows).
    pub guard: GuardMode,
    /// A caller's view of the run's progress (steps done of the current run), for a caller
    /// that draws its own bar (the Python package's); `None` (the default): none kept.
    pub progress_watch: Option<ProgressWatch>,
    /// Whose factorizations and solves the runs' step matrices get: softway's tuned kernels
    /// (the default) or faer's own, the reference (`--solver faer`).
    pub solver: crate::linalg::Backend,
}

/// The progress of a job as another thread sees it: the current run's label, its steps
/// done and its steps in all, updated as the run goes (every 256 steps or so). Clones share
/// one view; a fresh one has seen no run.
#[derive(Debug, Clone, Default)]
pub struct ProgressWatch(Arc<std::sync::Mutex<Option<indicatif::ProgressBar>>>);

impl ProgressWatch {
    /// A view that has seen no run yet.
    pub fn new() -> Self {
        Self::default()
    }

    /// The current run's `(label, steps done, steps)`; `None` before the first run starts.
    pub fn get(&self) -> Option<(String, u64, u64)> {
        let bar = self.0.lock().ok()?.clone()?;
        Some((bar.prefix(), bar.position(), bar.length().unwrap_or(0)))
    }

    /// Watches `bar` from now on (each run of a scenario starts its own).
    fn watch(&self, bar: &indicatif::ProgressBar) {
        if let Ok(mut b) = self.0.lock() {
            *b = Some(bar.clone());
        }
    }
}

impl RunOptions {
    /// What every run's simulation is set up with ([`crate::simulation::Settings`]): the
    /// threads ([`RunOptions::par`]) and the guard's mode.
    pub fn settings(&self) -> crate::simulation::Settings {
        crate::simulation::Settings {
            par: self.par(),
            guard: self.guard,
            solver: self.solver,
        }
    }

    /// The threads of a run: [`RunOptions::par`], or those of the caller's pool.
    pub fn par(&self) -> Par {
        self.par.unwrap_or_else(Par::current)
    }
}

/// A progress bar over `len` steps (hidden when not on a terminal or not asked for by
/// [`RunOptions::progress`]), handed to [`RunOptions::progress_watch`] when there is one.
pub(crate) fn progress_bar(len: u64, label: &str, opts: &RunOptions) -> indicatif::ProgressBar {
    use std::io::IsTerminal;
    if !opts.progress || !std::io::stderr().is_terminal() {
        let pb = indicatif::ProgressBar::with_draw_target(
            Some(len),
            indicatif::ProgressDrawTarget::hidden(),
        );
        if let Some(w) = &opts.progress_watch {
            pb.set_prefix(label.to_string());
            w.watch(&pb);
        }
        return pb;
    }
    let pb = indicatif::ProgressBar::new(len);
    // Within 100 columns; the time per step and the time left from the mean rate since the
    // start (stable, where indicatif's own estimate follows the last steps' rate and jumps
    // between the settling and the rolling).
    pb.set_style(
        indicatif::ProgressStyle::with_template(
            "{prefix:>12} [{bar:20}] {steps} steps, {per_step}, {left} {msg}",
        )
        .map(|s| {
            s.with_key(
                "steps",
                |st: &indicatif::ProgressState, w: &mut dyn std::fmt::Write| {
                    let _ = write!(
                        w,
                        "{}/{}",
                        crate::output::terminal::grouped(st.pos() as f64),
                        crate::output::terminal::grouped(st.len().unwrap_or(0) as f64)
                    );
                },
            )
            .with_key(
                "per_step",
                |st: &indicatif::ProgressState, w: &mut dyn std::fmt::Write| {
                    let per = st.elapsed().as_secs_f64() / st.pos().max(1) as f64;
                    let _ = write!(w, "{}/step", crate::output::terminal::quantity(per, "s"));
                },
            )
            .with_key(
                "left",
                |st: &indicatif::ProgressState, w: &mut dyn std::fmt::Write| {
                    let _ = write!(
                        w,
                        "{}",
                        crate::output::terminal::time_left(
                            st.elapsed().as_secs_f64(),
                            st.pos(),
                            st.len().unwrap_or(0)
                        )
                    );
                },
            )
        })
        .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar())
        .progress_chars("=> "),
    );
    pb.set_prefix(label.to_string());
    if let Some(w) = &opts.progress_watch {
        w.watch(&pb);
    }
    pb
}
