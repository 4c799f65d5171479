//! Observers behind the step loop: the final steps copied into a ring of slots and handed
//! to a second thread, which runs the observers on them while the loop goes on
//! ([`behind`]).
//!
//! A run's observers (tables, statistics, energies, field sums) do not change the state;
//! on the stepping thread they cost what they take (on the paper's wheel about a tenth of
//! the run: the two energies' quadratic forms, the CSV rows' formatting, the turn-averaged
//! stresses), while the machine's second core waits for the figures at the end. Here the
//! loop copies what the observers read (a few vectors of the state) into a free slot and
//! goes on; the observers see the same steps, in the same order, with the same values, so
//! their results are the same bits.
//!
//! **No allocation per step.** The slots are made before the loop (their vectors sized
//! there) and travel between the two threads through two queues of fixed room, the full
//! ones forward and the observed ones back: a step moves a slot's handle, never its
//! vectors. When the observers fall behind by every slot the loop waits for one (the ring
//! bounds the memory); when they are ahead the second thread sleeps.
//!
//! **Few wakes.** Waking a sleeping thread is a system call on each side (a futex), tens of
//! microseconds on a loaded machine: handed over one by one, the paper's wheel's 3,400
//! batches of 16 steps cost 35,000 of them and 0.3 s of system time. The observers' thread
//! therefore takes every full slot at once when it wakes, and the loop wakes it only once
//! half of the slots are full (or at the end, or when it waits for a free one): a wake per
//! half ring.
//!
//! **Errors and stops.** An observer's error (an output file that cannot be written) is
//! kept by the second thread, which observes nothing more and returns the slots at once; the
//! loop sees it at its next step ([`Feed::send`] fails) and stops, and [`behind`] returns
//! the observer's own error. An observer whose error must stop the loop at the very step it
//! sees (a guard) is run on the stepping thread by the caller, not here. A stop of the loop
//! (the end, an interrupt, an error of the driver) lets the second thread observe every
//! step sent so far before [`behind`] returns, so an interrupted run's outputs hold every
//! step it finished.

use std::collections::VecDeque;
use std::sync::{Condvar, Mutex, MutexGuard};

/// The two queues and who sleeps (module docs).
struct Queues<T> {
    full: VecDeque<T>,
    free: Vec<T>,
    /// The observers' thread sleeps on `wake_observers`.
    observers_asleep: bool,
    /// The loop sleeps on `wake_loop`, waiting for a free slot.
    loop_asleep: bool,
    /// No more slots will come (the loop ended).
    done: bool,
    /// The observers stopped (an error): nothing more is observed.
    stopped: bool,
}

struct Shared<T> {
    queues: Mutex<Queues<T>>,
    wake_observers: Condvar,
    wake_loop: Condvar,
    /// Full slots from which a sleeping observers' thread is woken.
    wake_at: usize,
}

impl<T> Shared<T> {
    fn lock(&self) -> MutexGuard<'_, Queues<T>> {
        // A panic of the other thread is propagated by `behind`; the queues stay usable.
        self.queues.lock().unwrap_or_else(|e| e.into_inner())
    }
}

/// The stepping thread's end of the ring: the slot being filled, taken from the free ones,
/// and the way to the observers' thread.
pub struct Feed<'a, T> {
    shared: &'a Shared<T>,
    current: Option<T>,
}

/// The observers' thread stopped (an observer failed): the loop should stop too;
/// [`behind`] returns the cause.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
#[error("the observers behind the step loop stopped")]
pub struct Stopped;

impl<T> Feed<'_, T> {
    /// The slot being filled (a free one taken when there is none: waits when all are in
    /// use).
    ///
    /// # Errors
    /// [`Stopped`] when the observers' thread has stopped (an observer failed): the loop
    /// should stop.
    pub fn current(&mut self) -> Result<&mut T, Stopped> {
        if self.current.is_none() {
            let mut q = self.shared.lock();
            loop {
                if q.stopped {
                    return Err(Stopped);
                }
                if let Some(slot) = q.free.pop() {
                    self.current = Some(slot);
                    break;
                }
                // Every slot is full or being observed: make sure they are.
                if q.observers_asleep {
                    self.shared.wake_observers.notify_one();
                }
                q.loop_asleep = true;
                q = self
                    .shared
                    .wake_loop
                    .wait(q)
                    .unwrap_or_else(|e| e.into_inner());
                q.loop_asleep = false;
            }
        }
        self.current.as_mut().ok_or(Stopped)
    }

    /// Sends the slot being filled to the observers (nothing when there is none). A slot
    /// may hold several steps (a batch); [`behind`] sends the last one after the loop.
    ///
    /// # Errors
    /// [`Stopped`], as [`Feed::current`].
    pub fn send(&mut self) -> Result<(), Stopped> {
        let Some(slot) = self.current.take() else {
            return Ok(());
        };
        let mut q = self.shared.lock();
        if q.stopped {
            return Err(Stopped);
        }
        q.full.push_back(slot);
        if q.observers_asleep && q.full.len() >= self.shared.wake_at {
            self.shared.wake_observers.notify_one();
        }
        Ok(())
    }
}

/// Runs `produce` (the step loop) on this thread with a [`Feed`] of `slots`, and `observe`
/// on a second thread over every slot sent, in order (module docs); `observe` may reset a
/// slot before it goes back to the free ones. Returns `produce`'s result and the
/// observers' (the first error of `observe`, after which it is not called again).
///
/// # Panics
/// Propagates a panic of `observe`.
pub fn behind<T, R, E>(
    slots: Vec<T>,
    mut observe: impl FnMut(&mut T) -> Result<(), E> + Send,
    produce: impl FnOnce(&mut Feed<T>) -> R,
) -> (R, Result<(), E>)
where
    T: Send,
    E: Send,
{
    let n = slots.len();
    let shared = Shared {
        queues: Mutex::new(Queues {
            full: VecDeque::with_capacity(n),
            free: slots,
            observers_asleep: false,
            loop_asleep: false,
            done: false,
            stopped: false,
        }),
        wake_observers: Condvar::new(),
        wake_loop: Condvar::new(),
        wake_at: (n / 2).max(1),
    };
    let shared = &shared;
    std::thread::scope(|scope| {
        let worker = scope.spawn(move || {
            let mut taken: Vec<T> = Vec::with_capacity(n);
            loop {
                {
                    let mut q = shared.lock();
                    while q.full.is_empty() && !q.done {
                        q.observers_asleep = true;
                        q = shared
                            .wake_observers
                            .wait(q)
                            .unwrap_or_else(|e| e.into_inner());
                        q.observers_asleep = false;
                    }
                    if q.full.is_empty() {
                        return Ok(());
                    }
                    taken.extend(q.full.drain(..));
                }
                let mut result = Ok(());
                for slot in taken.iter_mut() {
                    if result.is_ok() {
                        result = observe(slot);
                    }
                }
                let mut q = shared.lock();
                q.free.append(&mut taken);
                if result.is_err() {
                    q.stopped = true;
                }
                if q.loop_asleep {
                    shared.wake_loop.notify_one();
                }
                drop(q);
                result?;
            }
        });
        let mut feed = Feed {
            shared,
            current: None,
        };
        let r = produce(&mut feed);
        // The end of the steps: the last slot sent, the observers finish, then return
        // (after an observer's error the slot has nowhere to go: dropped).
        let _ = feed.send();
        {
            let mut q = shared.lock();
            q.done = true;
            shared.wake_observers.notify_one();
        }
        let observed = match worker.join() {
            Ok(o) => o,
            Err(panic) => std::panic::resume_unwind(panic),
        };
        (r, observed)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_step_is_observed_in_order_with_its_values() {
        let mut seen = Vec::new();
        let (sent, observed) = behind(
            vec![vec![0.0; 3]; 2],
            |s: &mut Vec<f64>| -> Result<(), ()> {
                seen.push(s.clone());
                Ok(())
            },
            |feed| {
                for k in 0..100 {
                    let s = feed.current().unwrap();
                    s.iter_mut().for_each(|x| *x = k as f64);
                    feed.send().unwrap();
                }
                100
            },
        );
        assert_eq!(sent, 100);
        assert!(observed.is_ok());
        assert_eq!(seen.len(), 100);
        for (k, s) in seen.iter().enumerate() {
            assert_eq!(s, &vec![k as f64; 3]);
        }
    }

    #[test]
    fn an_observer_error_stops_the_loop_and_is_returned() {
        let (steps, observed) = behind(
            vec![0usize; 4],
            |k: &mut usize| if *k == 10 { Err(*k) } else { Ok(()) },
            |feed| {
                let mut k = 0;
                while let Ok(s) = feed.current() {
                    *s = k;
                    if feed.send().is_err() {
                        break;
                    }
                    k += 1;
                    assert!(k < 10_000, "the loop was not stopped");
                }
                k
            },
        );
        assert_eq!(observed, Err(10));
        // Stopped within the ring's slots after the failing step.
        assert!((10..=16).contains(&steps), "{steps}");
    }
}
