//! The comparison as data: what `compare.json` holds (ARCHITECTURE §5.3) and what the page
//! and the text summary are made from. Everything per run is a list in the order of
//! [`Comparison::runs`]; numbers are raw (ms, fractions), the page formats them.

use harness::method::Params;
use harness::results::{Machine, Status};
use serde::Serialize;

use crate::calibration::RasterLimited;
use super::tau::PairCounts;
use super::tolerance::Tolerance;

/// `compare.json`'s `schema`.
pub const SCHEMA: &str = "scatterbench-compare/1";

#[derive(Serialize)]
pub struct Comparison {
    pub schema: &'static str,
    pub runs: Vec<RunSummary>,
    pub resolution: [u32; 2],
    pub frames: u32,
    pub warmup: u32,
    /// The error every verdict and headline column reads (the report's verdict metric).
    pub metric: String,
    /// The same in a word, for the page's table heads (`Metric::short`; not in compare.json).
    #[serde(skip)]
    pub metric_short: &'static str,
    /// The method whose time is each scene's floor; not a contender in the verdicts.
    pub floor_method: &'static str,
    /// The error budgets of the "fastest under" verdicts (fractions).
    pub budgets: Vec<f64>,
    pub tolerance: Tolerance,
    pub scenes: Vec<SceneComparison>,
    /// Per pair of runs: τ over all scenes.
    pub tau: Vec<TauOverall>,
    /// Every record whose headlines differ by more than the tolerance.
    pub headline_flags: Vec<HeadlineFlag>,
    /// Work that some run lacks (left out of ratios, τ and verdicts).
    pub not_in_every_run: Vec<Unmatched>,
    /// Work every run has, but not with the same status (ok / skipped / failed).
    pub status_differs: Vec<StatusDiffers>,
    /// Anything else a reader should know (a run with the same record twice, two runs on
    /// one adapter).
    pub notes: Vec<String>,
}

#[derive(Serialize)]
pub struct RunSummary {
    pub label: String,
    pub dir: String,
    pub id: String,
    pub git_commit: String,
    /// Its adapter's calibration is in `machine.calibration`.
    pub machine: Machine,
    pub records: usize,
    /// Set where its raster-to-compute ratio is far below the other runs' (`calibration`).
    pub raster_limited: Option<RasterLimited>,
}

#[derive(Serialize)]
pub struct SceneComparison {
    pub scene: String,
    /// "gpu" when every ok record of the scene in every run has GPU time, else "wall".
    pub time_basis: &'static str,
    /// Per run: the floor's median time (ms), or null where the run has no timed floor.
    pub floor_ms: Vec<Option<f64>>,
    /// The work every run has, the floor first.
    pub rows: Vec<Row>,
    /// Per pair of runs: τ-b of the times of the rows timed in both.
    pub tau: Vec<PairTau>,
    /// Per run: its verdict on this scene.
    pub verdicts: Vec<Verdict>,
    pub changed: Changed,
}

#[derive(Serialize)]
pub struct Row {
    pub key: String,
    pub method: String,
    pub params: Params,
    /// The floor method's row.
    pub floor: bool,
    /// Per run.
    pub runs: Vec<Cell>,
    /// Whether the headlines agree within the tolerance; null with fewer than two headlines.
    pub headlines_agree: Option<bool>,
}

#[derive(Serialize, Clone)]
pub struct Cell {
    pub status: Status,
    pub reason: Option<String>,
    /// Median time on the scene's basis (ms); ok and timed records only.
    pub time_ms: Option<f64>,
    /// `time_ms` ÷ the run's floor on this scene.
    pub ratio: Option<f64>,
    /// The verdict metric (a fraction); ok and scored records only.
    pub headline: Option<f64>,
}

#[derive(Serialize)]
pub struct PairTau {
    /// Indices into `runs`.
    pub a: usize,
    pub b: usize,
    /// τ-b; null when undefined (fewer than two rows timed in both, or all tied).
    pub tau: Option<f64>,
    pub counts: PairCounts,
}

#[derive(Serialize, Clone, PartialEq)]
pub struct Pick {
    pub key: String,
    pub method: String,
    pub params: Params,
    pub time_ms: f64,
    pub error: f64,
    /// Its time as a multiple of the floor: its paired floor's, else the run's on the scene
    /// (`analysis::Clock::floor_ratio`); None where neither exists.
    pub floor_ratio: Option<f64>,
}

#[derive(Serialize)]
pub struct Verdict {
    /// The time-vs-error Pareto front without the floor, fastest first.
    pub front: Vec<Pick>,
    /// Per budget: the fastest configuration within it, or null.
    pub budgets: Vec<Option<Pick>>,
}

/// Which verdicts of a scene are not the same on every run.
#[derive(Serialize, Default, PartialEq, Debug)]
pub struct Changed {
    /// The fronts hold different configurations.
    pub front: bool,
    /// Per budget: the winners differ (or one run has none).
    pub budgets: Vec<bool>,
}

impl Changed {
    pub fn any(&self) -> bool {
        self.front || self.budgets.iter().any(|&b| b)
    }
}

#[derive(Serialize)]
pub struct TauOverall {
    pub a: usize,
    pub b: usize,
    /// Mean of the scenes' τ where defined.
    pub mean: Option<f64>,
    /// How many scenes have a τ.
    pub scenes: usize,
    /// τ-b of every same-scene pair of every scene, counted together.
    pub pooled: Option<f64>,
    pub counts: PairCounts,
}

#[derive(Serialize)]
pub struct HeadlineFlag {
    pub scene: String,
    pub method: String,
    pub params: Params,
    pub key: String,
    /// Per run (null where not ok and scored).
    pub headlines: Vec<Option<f64>>,
    /// Largest minus smallest.
    pub difference: f64,
    /// What the tolerance allows for the smallest.
    pub allowed: f64,
}

#[derive(Serialize)]
pub struct Unmatched {
    pub key: String,
    pub scene: String,
    pub method: String,
    pub params: Params,
    /// Labels of the runs that have it.
    pub in_runs: Vec<String>,
}

#[derive(Serialize)]
pub struct StatusDiffers {
    pub scene: String,
    pub method: String,
    pub params: Params,
    pub key: String,
    pub statuses: Vec<Status>,
    pub reasons: Vec<Option<String>>,
}
