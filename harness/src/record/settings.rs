//! How a run measures each of its records: the one settings struct every command fills in
//! (`run`, `stress`, `reproduce`, `scaling`), that the runner and isolation pass on unchanged,
//! and that crosses the pipe to a worker with each job, so an isolated record is measured and
//! scored exactly like one run in process.

use std::path::PathBuf;

use serde::{Deserialize, Serialize};

use crate::reference::Settings;

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RecordSettings {
    /// The run directory: results.json, and each record's images under it.
    pub out_dir: PathBuf,
    pub width: u32,
    pub height: u32,
    /// Timed frames per record (K, ARCHITECTURE §4.1).
    pub frames: u32,
    /// Warm-up frames before them (W).
    pub warmup: u32,
    /// `--no-skip`: every pass runs even where the scene does not need it (ARCHITECTURE §2.4).
    pub no_skip: bool,
    /// Per-record time budget (ms) for warm-up plus timed frames; None: always W + K frames
    /// (the rule: `record::another_frame`, ARCHITECTURE §4.2).
    pub budget_ms: Option<f64>,
    /// Accuracy of the references records are scored against.
    pub reference: Settings,
    /// Where references are cached (None: rendered, not cached), per-frame ones included.
    pub cache_dir: Option<PathBuf>,
    /// `--paired-floor`: the floor method's id (`no-scatter`). Each record of another method
    /// then also times the floor (at the record's shadow-map settings, its defaults
    /// otherwise), one floor frame before each of its own on the same scene frames
    /// (`record::paired`), into `timing.floor` (ARCHITECTURE §4.5). None: off.
    #[serde(default)]
    pub paired_floor: Option<String>,
}

impl RecordSettings {
    /// `width`×`height`, `warmup` + `frames` frames per record, written under `out_dir`: every
    /// pass only where the scene needs it, no time budget, the default reference, no cache.
    pub fn new(
        out_dir: impl Into<PathBuf>,
        (width, height): (u32, u32),
        (frames, warmup): (u32, u32),
    ) -> RecordSettings {
        RecordSettings {
            out_dir: out_dir.into(),
            width,
            height,
            frames,
            warmup,
            no_skip: false,
            budget_ms: None,
            reference: Settings::default(),
            cache_dir: None,
            paired_floor: None,
        }
    }
}
