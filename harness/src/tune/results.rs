//! `tune.json` (ARCHITECTURE §5.1): what a tune found per scene — the configurations it
//! screened, the candidates it timed with their intervals, the verdict per budget, the floor's
//! drift — and the summary counts, written atomically beside the run's results.json.

use std::path::Path;

use serde::{Deserialize, Serialize};

use super::drift::Drift;
use super::verdict::{BudgetVerdict, Count, Timed};
use crate::knobs::Params;
use crate::results::RunInfo;

pub const TUNE_SCHEMA_VERSION: u32 = 1;
/// The file beside results.json.
pub const TUNE_FILE: &str = "tune.json";

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct TuneResults {
    pub schema_version: u32,
    /// The run (adapter, its calibration, resolution, commit); its records are the winners'
    /// full records, in results.json.
    pub run: RunInfo,
    pub budgets: Vec<f64>,
    /// The time limit asked for and the wall time taken, s.
    pub time_limit_s: f64,
    pub wall_s: f64,
    /// How the ratio's interval is computed (`tune::interval`).
    pub interval: String,
    pub scenes: Vec<SceneTune>,
    /// Per budget: within 2× the floor on k of n scenes, with its range.
    pub summary: Vec<Count>,
}

/// One scene's tune.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SceneTune {
    pub scene: String,
    /// The median of the floor's timed frames over the scene's pairs, ms (on the time basis).
    pub floor_ms: Option<f64>,
    /// "gpu" (timestamps) or "wall".
    pub basis: String,
    /// Each method searched: its space and how much of it was evaluated.
    pub methods: Vec<MethodSearch>,
    pub screened: Vec<Screened>,
    pub candidates: Vec<Timed>,
    pub verdicts: Vec<BudgetVerdict>,
    /// The floor's drift over the scene's pairs (None: too few).
    pub drift: Option<Drift>,
    /// Seconds spent screening and timing.
    pub screen_s: f64,
    pub time_s: f64,
    /// The search ran out of its share of the time limit before it ran out of
    /// configurations to expand.
    pub search_stopped: bool,
    /// Of the screened configurations, those the surrogate proposed (`tune::model`).
    #[serde(default)]
    pub surrogate_proposals: usize,
    /// Neighbours the search left out as predicted too costly to win.
    #[serde(default)]
    pub pruned: usize,
    /// Of `screen_s`: preparing, timing and scoring the screened configurations, s.
    #[serde(default)]
    pub screen_phases_s: [f64; 3],
}

/// A method's knob space on a scene.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct MethodSearch {
    pub method: String,
    /// The knobs searched and the number of configurations of their joint space.
    pub knobs: Vec<String>,
    pub joint_size: f64,
    pub evaluated: usize,
    /// Why it was not searched (unsupported scene, a failure at its defaults).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub skipped: Option<String>,
}

/// One screened configuration: its exact error and its cheap cost estimate.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Screened {
    pub method: String,
    pub params: Params,
    /// None where it failed or was left unscored.
    pub error: Option<f64>,
    /// The floor ratio of its screening pair(s).
    pub ratio: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub failed: Option<String>,
    /// Left unscored: its ratio alone was over the search's cost cap (it cannot win).
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub unscored: bool,
}

impl TuneResults {
    pub fn load(path: &Path) -> Result<TuneResults, String> {
        let text = std::fs::read_to_string(path)
            .map_err(|e| format!("{}: cannot read: {e}", path.display()))?;
        serde_json::from_str(&text).map_err(|e| format!("{}: {e}", path.display()))
    }

    /// Written atomically (a temporary file renamed over it).
    pub fn save(&self, path: &Path) -> Result<(), String> {
        let text = serde_json::to_string_pretty(self).map_err(|e| e.to_string())?;
        crate::fsutil::write_atomic(path, text.as_bytes())
    }
}
