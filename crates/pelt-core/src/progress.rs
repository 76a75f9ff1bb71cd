//! Progress reporting and cancellation for long stages (volume bake, transfer bake, patches).
//!
//! A stage announces how many units of work it has, and its workers call [`Progress::advance`]
//! as units finish, from any thread. The user's callback receives the finished fraction and
//! returns `false` to cancel; the stage then stops at its next check and returns
//! [`PeltError::Cancelled`] without partial output. Reports are thinned to whole percents so a
//! callback that takes the Python GIL is called at most ~100 times per stage.

use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::{Mutex, PoisonError};

use crate::error::{PeltError, Result};

/// A progress callback: receives the finished fraction in [0, 1], returns `false` to cancel.
pub type ProgressCallback<'a> = &'a (dyn Fn(f64) -> bool + Sync);

/// Shared progress state of one stage.
pub struct Progress<'a> {
    callback: Option<ProgressCallback<'a>>,
    total: usize,
    done: AtomicUsize,
    last_percent: AtomicUsize,
    /// The last percent handed to the callback; held while the callback runs, so reports arrive
    /// in order even when a thread that moved the percent forward is overtaken before it calls.
    reported: Mutex<usize>,
    cancelled: AtomicBool,
}

impl<'a> Progress<'a> {
    /// Progress over `total` units reported to `callback` (if any).
    pub fn new(total: usize, callback: Option<ProgressCallback<'a>>) -> Self {
        Progress {
            callback,
            total: total.max(1),
            done: AtomicUsize::new(0),
            last_percent: AtomicUsize::new(0),
            reported: Mutex::new(0),
            cancelled: AtomicBool::new(false),
        }
    }

    /// No reporting, never cancelled.
    pub fn none() -> Progress<'static> {
        Progress::new(1, None)
    }

    /// Records `units` finished units, reports when a new whole percent is reached, and returns
    /// [`PeltError::Cancelled`] once the callback has asked to stop.
    ///
    /// # Errors
    /// [`PeltError::Cancelled`] after the callback returned `false` (from this or another thread).
    pub fn advance(&self, units: usize) -> Result<()> {
        let done = self.done.fetch_add(units, Ordering::Relaxed) + units;
        if let Some(callback) = self.callback {
            let percent = (done.min(self.total) * 100) / self.total;
            // Only the thread that moves the percent forward reports it, and only if no thread
            // has reported a higher one meanwhile: a progress bar never goes back.
            if self.last_percent.fetch_max(percent, Ordering::Relaxed) < percent {
                let mut reported = self.reported.lock().unwrap_or_else(PoisonError::into_inner);
                if percent > *reported {
                    *reported = percent;
                    if !callback(percent as f64 / 100.0) {
                        self.cancelled.store(true, Ordering::Relaxed);
                    }
                }
            }
        }
        self.check()
    }

    /// Returns [`PeltError::Cancelled`] if the stage was cancelled.
    ///
    /// # Errors
    /// [`PeltError::Cancelled`] after the callback returned `false`.
    pub fn check(&self) -> Result<()> {
        if self.cancelled.load(Ordering::Relaxed) {
            Err(PeltError::Cancelled)
        } else {
            Ok(())
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::Mutex;

    #[test]
    fn reports_each_percent_once_and_cancels_on_false() {
        let seen = Mutex::new(Vec::new());
        let callback = |f: f64| {
            let mut seen = seen.lock().unwrap_or_else(|e| e.into_inner());
            seen.push(f);
            f < 0.5
        };
        let progress = Progress::new(1000, Some(&callback));
        let mut outcome = Ok(());
        for _ in 0..1000 {
            outcome = progress.advance(1);
            if outcome.is_err() {
                break;
            }
        }
        assert!(matches!(outcome, Err(PeltError::Cancelled)));
        let seen = seen.into_inner().unwrap_or_else(|e| e.into_inner());
        assert_eq!(seen.len(), 50, "one report per percent up to the cancel");
        assert_eq!(seen.last().copied(), Some(0.5));
        assert!(Progress::none().advance(10).is_ok());
    }

    #[test]
    fn reports_arrive_in_order_when_a_reporting_thread_is_overtaken() {
        // The first report is slow (a callback waiting for Python's GIL): the other threads move
        // on meanwhile, and their later percents must not be handed over before it.
        let seen = Mutex::new(Vec::new());
        let callback = |f: f64| {
            if f <= 0.01 {
                std::thread::sleep(std::time::Duration::from_millis(100));
            }
            seen.lock().unwrap_or_else(|e| e.into_inner()).push(f);
            true
        };
        let progress = Progress::new(100, Some(&callback));
        let pool = rayon::ThreadPoolBuilder::new().num_threads(4).build().unwrap();
        pool.install(|| {
            use rayon::prelude::*;
            (0..100)
                .into_par_iter()
                .for_each(|_| progress.advance(1).unwrap());
        });
        let seen = seen.into_inner().unwrap_or_else(|e| e.into_inner());
        assert!(seen.windows(2).all(|w| w[0] < w[1]), "out of order: {seen:?}");
        assert_eq!(seen.last().copied(), Some(1.0));
    }
}
