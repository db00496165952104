//! The phase a record is in (start, prepare, render, score), announced by [`super::run_one`]
//! before it enters each one so a watchdog or a crash report can say where a record stopped.
//!
//! The announcement goes to a hook scoped to the current thread ([`with_hook`]): a worker
//! process forwards it to its parent over the protocol pipe; the in-process runner writes it
//! into the in-flight marker. Without a hook, [`enter`] does nothing.

use std::cell::RefCell;

use serde::{Deserialize, Serialize};

/// Where a record is. `Start` covers a worker's start-up (device creation, scene upload).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Phase {
    Start,
    Prepare,
    Render,
    Score,
}

impl Phase {
    pub fn name(self) -> &'static str {
        match self {
            Phase::Start => "start",
            Phase::Prepare => "prepare",
            Phase::Render => "render",
            Phase::Score => "score",
        }
    }
}

impl std::fmt::Display for Phase {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

type Hook<'a> = Box<dyn FnMut(Phase) + 'a>;

thread_local! {
    static HOOK: RefCell<Option<Hook<'static>>> = const { RefCell::new(None) };
}

/// Announces that the current record enters `phase` (no-op without a hook on this thread).
pub fn enter(phase: Phase) {
    HOOK.with(|h| {
        if let Some(f) = h.borrow_mut().as_mut() {
            f(phase);
        }
    });
}

/// Runs `body` with `hook` receiving this thread's phase announcements; the previous hook is
/// restored afterwards (also when `body` panics).
pub fn with_hook<R>(hook: impl FnMut(Phase) + 'static, body: impl FnOnce() -> R) -> R {
    struct Restore(Option<Hook<'static>>);
    impl Drop for Restore {
        fn drop(&mut self) {
            let prev = self.0.take();
            HOOK.with(|h| *h.borrow_mut() = prev);
        }
    }
    let prev = HOOK.with(|h| h.borrow_mut().replace(Box::new(hook)));
    let _restore = Restore(prev);
    body()
}
