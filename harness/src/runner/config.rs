//! What a run is told ([`RunConfig`]) and what it tells its caller ([`Event`]).

use crate::isolate::Isolation;
use crate::method::Params;
use crate::record::RecordSettings;
use crate::results::Record;

pub struct RunConfig {
    /// How every record is measured: output directory, resolution, frames, time budget,
    /// `no_skip`, reference settings and cache (shared with the worker protocol).
    pub record: RecordSettings,
    pub run_id: String,
    /// Continue the run in `record.out_dir` (ARCHITECTURE §9.2).
    pub resume: bool,
    /// Run every declared sweep value of every knob (`crate::method::param_sets`).
    pub sweep: bool,
    /// Per method id: knob overrides applied to every parameter set of that method.
    pub overrides: std::collections::BTreeMap<String, Params>,
    /// Records in worker processes with a watchdog, or in process (the default); with
    /// `resume`, whether failed records run again. See [`crate::isolate`].
    pub isolation: Isolation,
}

impl RunConfig {
    /// A fresh run `run_id` of `record`: no resume, no sweep, no overrides, in process.
    pub fn new(record: RecordSettings, run_id: &str) -> RunConfig {
        RunConfig {
            record,
            run_id: run_id.to_string(),
            resume: false,
            sweep: false,
            overrides: Default::default(),
            isolation: Isolation::default(),
        }
    }
}

/// Events the caller may show (progress bars, log lines).
pub enum Event<'a> {
    /// A work list is built: this many records follow, resumed ones included. A command that
    /// runs several work lists (`scaling`) sends one per list.
    Planned(usize),
    /// A record is about to be measured (or skipped by its support); not sent for resumed ones.
    Starting {
        scene: &'a str,
        method: &'a str,
        params: &'a Params,
    },
    Reference {
        scene: &'a str,
        cached: bool,
        seconds: f64,
    },
    Record(&'a Record),
    Resumed(&'a str),
}
