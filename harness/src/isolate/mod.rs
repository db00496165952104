//! Process isolation for the runner (issue 23, ARCHITECTURE §6): each record runs in a worker process, so a
//! driver crash or hang costs one record, not the run.
//!
//! - [`worker::serve`] is the worker: a hidden subcommand of `scatterbench` (or a test binary
//!   serving a test registry) that runs jobs sent on its stdin and answers with records
//!   ([`protocol`]). It announces each phase ([`phase`]) before entering it.
//! - [`parent::Pool`] is the parent's side: it starts workers, sends them scenes (with their
//!   reference) and jobs, and turns a timeout, a signal, an exit code or a broken protocol
//!   into a failed record ("timed out in render", "crashed in prepare: the worker was killed
//!   by signal 6 (SIGABRT); last stderr lines: …"). The parent alone writes `results.json`.
//! - [`marker`]: the in-flight marker that lets `--resume` record a record that took the
//!   parent down as failed ("interrupted") instead of running it again.
//! - [`Dispatch`]: what the runner calls per record, in process or in a worker; both run
//!   `crate::record::run_one` with the run's `RecordSettings`, which cross the pipe with each job.
//! - `config.rs`: the settings ([`Isolation`], [`WorkerCommand`], [`Reuse`], [`default_timeout`]).
//!
//! Worker reuse ([`Reuse`]): by default one worker runs record after record — scenes and
//! methods included — so device creation and process start are paid once, and a crash still
//! loses only the record in flight; after a failed record the worker is replaced so the next
//! record gets a fresh device. [`Reuse::SceneMethod`] and [`Reuse::None`] trade time for
//! stronger separation.
//!
//! The record timeout ([`default_timeout`]): with a per-record time budget B (s),
//! `120 s + 10·B` (200 s at the default B = 8 s); without one, `120 s + 30 s × (W + K + 1)`
//! for W warm-up and K timed frames. A budgeted record renders at most W + K + 1 frames of
//! which warm-up and timing stop after B/4 and B unless a single frame is slower, and at least
//! 1 + 3 + 1 frames: the 120 s cover preparation (pipeline compilation on a software adapter
//! takes seconds) and scoring, the 10·B five minimum frames of a method slower than the budget.

mod config;
mod dispatch;
pub mod marker;
pub mod parent;
pub mod protocol;
pub mod worker;

pub use crate::record::Phase;
pub use config::{Isolation, Reuse, WorkerCommand, default_timeout};
pub use dispatch::Dispatch;
