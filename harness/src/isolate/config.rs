//! The isolation settings (ARCHITECTURE §6): where workers come from, which records share one,
//! the record timeout and `--retry-failed`.

use std::ffi::OsString;
use std::path::PathBuf;
use std::time::Duration;

/// How to start a worker: a program, its arguments and extra environment. The worker must
/// call [`super::worker::serve`] with a registry holding every method it will be asked for.
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

/// The default record timeout; `crate::isolate`'s documentation gives the reasoning.
pub fn default_timeout(budget_ms: Option<f64>, warmup: u32, frames: u32) -> Duration {
    let s = match budget_ms {
        Some(b) => 120.0 + 10.0 * b / 1e3,
        None => 120.0 + 30.0 * (warmup + frames + 1) as f64,
    };
    Duration::from_secs_f64(s)
}
