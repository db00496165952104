//! Process isolation on the command line: the flags every command that runs records shares
//! (`--isolate`, `--record-timeout`, `--retry-failed`, and the device's `--adapter`,
//! `--validate`, which workers inherit), and the worker command they start
//! (`cmd::worker`, `harness::isolate`).

use std::time::Duration;

use anyhow::Result;
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
    #[arg(long, value_name = "SECONDS", value_parser = parse_timeout)]
    pub record_timeout: Option<Duration>,
    /// With --resume: run the failed records again (including one interrupted by a crash of
    /// the run itself); the new record replaces the old.
    #[arg(long)]
    pub retry_failed: bool,
    /// The adapter and validation layer, shared with the workers.
    #[command(flatten)]
    pub device: super::device::DeviceArgs,
}

impl IsolateArgs {
    pub fn isolation(&self) -> Result<Isolation> {
        let record_timeout = self.record_timeout;
        let (mut worker, reuse) = match self.isolate {
            IsolateMode::Off => (None, Reuse::Run),
            IsolateMode::On => (Some(this_worker()?), Reuse::Run),
            IsolateMode::PerRecord => (Some(this_worker()?), Reuse::None),
        };
        if let Some(w) = &mut worker {
            w.env.extend(self.device.choice().worker_env());
        }
        Ok(Isolation {
            worker,
            reuse,
            record_timeout,
            retry_failed: self.retry_failed,
        })
    }
}

/// Seconds in (0, 1e6]; refused by clap (exit 2) otherwise.
fn parse_timeout(s: &str) -> std::result::Result<Duration, String> {
    match s.trim().parse::<f64>() {
        Ok(v) if v.is_finite() && v > 0.0 && v <= 1e6 => Ok(Duration::from_secs_f64(v)),
        _ => Err(format!("'{s}' is not a number of seconds in (0, 1e6]")),
    }
}

fn this_worker() -> Result<WorkerCommand> {
    WorkerCommand::this_executable(&[SUBCOMMAND]).map_err(anyhow::Error::msg)
}

