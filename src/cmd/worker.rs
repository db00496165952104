//! Process isolation on the command line: the flags every command that runs records shares
//! (`--isolate`, `--record-timeout`, `--retry-failed`) and the hidden worker subcommand the
//! runner starts (`harness::isolate`).

use std::time::Duration;

use anyhow::{Result, bail};
use clap::{Args, ValueEnum};
use harness::isolate::{Isolation, Reuse, WorkerCommand};

/// The hidden subcommand that makes this binary a worker.
pub const SUBCOMMAND: &str = "__worker";

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum IsolateMode {
    /// Each record in a worker process (reused from record to record until one fails).
    On,
    /// Every record in this process (debugging, profiling): a driver crash ends the run.
    Off,
    /// A fresh worker for every record (measures the cost of worker start-up).
    #[value(hide = true)]
    PerRecord,
}

#[derive(Args, Clone, Debug)]
pub struct IsolateArgs {
    /// Run each record in a worker process with a watchdog, so a driver crash or hang fails
    /// one record instead of ending the run.
    #[arg(long, value_enum, default_value = "on")]
    pub isolate: IsolateMode,
    /// Seconds after which a record is killed and recorded as failed ("timed out in
    /// <phase>"). Default: 120 + 10 × the time budget, or 120 + 30 × (warm-up + frames + 1)
    /// without a budget.
    #[arg(long, value_name = "SECONDS")]
    pub record_timeout: Option<f64>,
    /// With --resume: run the failed records again (including one interrupted by a crash of
    /// the run itself); the new record replaces the old.
    #[arg(long)]
    pub retry_failed: bool,
}

impl IsolateArgs {
    pub fn isolation(&self) -> Result<Isolation> {
        let record_timeout = match self.record_timeout {
            None => None,
            Some(s) if s.is_finite() && s > 0.0 && s <= 1e6 => Some(Duration::from_secs_f64(s)),
            Some(s) => bail!("--record-timeout: {s} is not a number of seconds in (0, 1e6]"),
        };
        let (worker, reuse) = match self.isolate {
            IsolateMode::Off => (None, Reuse::Run),
            IsolateMode::On => (Some(this_worker()?), Reuse::Run),
            IsolateMode::PerRecord => (Some(this_worker()?), Reuse::None),
        };
        Ok(Isolation {
            worker,
            reuse,
            record_timeout,
            retry_failed: self.retry_failed,
        })
    }
}

fn this_worker() -> Result<WorkerCommand> {
    WorkerCommand::this_executable(&[SUBCOMMAND]).map_err(anyhow::Error::msg)
}

/// The worker subcommand: serves the parent over the method registry, then exits.
pub fn serve() -> ! {
    harness::isolate::worker::serve(methods::REGISTRY)
}
