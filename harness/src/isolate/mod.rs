//! Process isolation for the runner (issue 23): each record runs in a worker process, so a
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
//! - [`Dispatch`]: what the runner calls per record, in process or in a worker.
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

pub mod marker;
pub mod parent;
pub mod phase;
pub mod protocol;
pub mod worker;

use std::ffi::OsString;
use std::path::PathBuf;
use std::time::Duration;

use scenes::Scene;

use crate::gpu::Gpu;
use crate::image::metrics::ToneMap;
use crate::method::{Method, Params};
use crate::reference::ReferenceImages;
use crate::results::{Record, Status};
use crate::runner::RunConfig;

pub use phase::Phase;

/// How to start a worker: a program, its arguments and extra environment. The worker must
/// call [`worker::serve`] with a registry holding every method it will be asked for.
#[derive(Clone, Debug)]
pub struct WorkerCommand {
    pub program: PathBuf,
    pub args: Vec<OsString>,
    pub env: Vec<(OsString, OsString)>,
}

impl WorkerCommand {
    /// This executable with `args` (e.g. the hidden `worker` subcommand).
    pub fn this_executable(args: &[&str]) -> Result<WorkerCommand, String> {
        let program = std::env::current_exe()
            .map_err(|e| format!("cannot find this executable to start workers: {e}"))?;
        Ok(WorkerCommand {
            program,
            args: args.iter().map(OsString::from).collect(),
            env: Vec::new(),
        })
    }
}

/// Which records share a worker.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Reuse {
    /// One worker per record.
    None,
    /// Consecutive records of the same scene and method.
    SceneMethod,
    /// Every record, until one fails.
    #[default]
    Run,
}

/// The runner's isolation settings. The default runs in process (no worker command).
#[derive(Clone, Debug, Default)]
pub struct Isolation {
    /// Where workers come from; None: run records in this process.
    pub worker: Option<WorkerCommand>,
    pub reuse: Reuse,
    /// Per-record limit; None: [`default_timeout`].
    pub record_timeout: Option<Duration>,
    /// With `resume`: run failed records again (their new record replaces the old one).
    pub retry_failed: bool,
}

/// The default record timeout; see the module documentation for the reasoning.
pub fn default_timeout(budget_ms: Option<f64>, warmup: u32, frames: u32) -> Duration {
    let s = match budget_ms {
        Some(b) => 120.0 + 10.0 * b / 1e3,
        None => 120.0 + 30.0 * (warmup + frames + 1) as f64,
    };
    Duration::from_secs_f64(s)
}

/// Runs records for the runner, in process or in workers, keeping the in-flight marker.
pub struct Dispatch<'a> {
    gpu: &'a Gpu,
    cfg: &'a RunConfig,
    pool: Option<parent::Pool>,
}

impl<'a> Dispatch<'a> {
    pub fn new(gpu: &'a Gpu, cfg: &'a RunConfig) -> Dispatch<'a> {
        let iso = &cfg.isolation;
        let pool = iso.worker.clone().map(|cmd| {
            let timeout = iso
                .record_timeout
                .unwrap_or_else(|| default_timeout(cfg.budget_ms, cfg.warmup, cfg.frames));
            parent::Pool::new(cmd, iso.reuse, timeout)
        });
        Dispatch { gpu, cfg, pool }
    }

    /// Workers started so far (0 in process).
    pub fn workers_started(&self) -> u32 {
        self.pool.as_ref().map_or(0, |p| p.spawned)
    }

    /// Runs one record; the in-flight marker names it (and its phase) until the caller has
    /// saved it and called [`marker::clear`].
    #[allow(clippy::too_many_arguments)]
    pub fn run(
        &mut self,
        scene_index: usize,
        scene: &Scene,
        entry: &dyn Method,
        params: &Params,
        reference: &ReferenceImages,
        tone: &ToneMap,
    ) -> Result<Record, String> {
        let out = self.cfg.out_dir.clone();
        let mut flight = marker::InFlight {
            scene: scene.name.clone(),
            method: entry.id().to_string(),
            params: params.clone(),
            phase: Phase::Start,
            pid: None,
        };
        marker::write(&out, &flight)?;
        let Some(pool) = self.pool.as_mut() else {
            let hook = move |p: Phase| {
                flight.phase = p;
                // Best effort: a marker one phase behind only words the reason less precisely.
                let _ = marker::write(&out, &flight);
            };
            return Ok(phase::with_hook(hook, || {
                crate::runner::run_one(self.gpu, scene, entry, params, self.cfg, reference, tone)
            }));
        };
        let c = self.cfg;
        let job = parent::Job {
            scene_index,
            scene,
            reference,
            method: entry.id(),
            params,
            cfg: protocol::JobConfig {
                out_dir: c.out_dir.clone(),
                width: c.width,
                height: c.height,
                frames: c.frames,
                warmup: c.warmup,
                no_skip: c.no_skip,
                budget_ms: c.budget_ms,
            },
        };
        let mut on_phase = |p: Phase, pid: u32| {
            flight.phase = p;
            flight.pid = (pid != 0).then_some(pid);
            let _ = marker::write(&out, &flight);
        };
        Ok(match pool.run(&job, &mut on_phase) {
            Ok(r) => r,
            Err(f) => failed_record(&scene.name, entry.id(), params, f.reason),
        })
    }
}

/// A failed record with nothing measured.
pub(crate) fn failed_record(scene: &str, method: &str, params: &Params, reason: String) -> Record {
    Record::unmeasured(scene, method, params, Status::Failed, reason)
}
