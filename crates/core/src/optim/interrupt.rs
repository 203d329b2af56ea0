//! A host's request that every run end now: Ctrl-C in Python.
//!
//! A host that can be interrupted while a run is in progress (the Python
//! package: `KeyboardInterrupt` is raised on its main thread, not where the
//! optimiser runs) opens a [`Watch`] for the time of a call and, on the
//! interrupt, calls [`request`]. Every [`Evaluator`](super::Evaluator) polls
//! [`requested`] every [`POLL_EVALUATIONS`] evaluations and then ends its
//! budget there, so that every optimiser stops at its next check of the
//! budget, as if it were spent; Levenberg–Marquardt polls once an
//! iteration. A run that ended this way is not a result: the host discards
//! it (a campaign keeps its finished runs and resumes the others).
//!
//! The request is lowered when the last watch ends, and when the first one
//! begins, so a run in a process without a watch (the command line, where
//! SIGINT ends the process and the journal keeps the finished runs) is
//! never affected. No seed, value or count depends on the flag while it is
//! down.

use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};

/// Whether an interrupt was requested during the open watches.
static REQUESTED: AtomicBool = AtomicBool::new(false);

/// How many watches are open.
static WATCHES: AtomicUsize = AtomicUsize::new(0);

/// Evaluations between two polls of the request by an evaluator: a power of
/// two, so that a poll costs a mask and a branch; 256 evaluations of even a
/// 10 µs objective end within 3 ms of the request.
pub const POLL_EVALUATIONS: u64 = 256;

/// Asks every run in the process to end now.
pub fn request() {
    REQUESTED.store(true, Ordering::Relaxed);
}

/// Whether an end was asked for ([`request`]) since the watches opened.
#[inline]
pub fn requested() -> bool {
    REQUESTED.load(Ordering::Relaxed)
}

/// An interruptible call in progress: while one is open, [`request`] ends
/// every run; when the last one closes the request is lowered.
#[derive(Debug)]
pub struct Watch(());

impl Watch {
    /// Opens a watch; the first one lowers a stale request.
    pub fn begin() -> Watch {
        if WATCHES.fetch_add(1, Ordering::SeqCst) == 0 {
            REQUESTED.store(false, Ordering::SeqCst);
        }
        Watch(())
    }
}

impl Drop for Watch {
    fn drop(&mut self) {
        if WATCHES.fetch_sub(1, Ordering::SeqCst) == 1 {
            REQUESTED.store(false, Ordering::SeqCst);
        }
    }
}
