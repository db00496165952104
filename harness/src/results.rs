//! The results schema (ARCHITECTURE §5.1). Field names are a contract scripts rely on; add fields,
//! never rename them, and bump `SCHEMA_VERSION` when a change is incompatible.

use std::collections::BTreeMap;
use std::path::Path;

use serde::{Deserialize, Serialize};

use crate::gpu::{AdapterSummary, Calibration};
use crate::image::metrics::ErrorMetrics;
use crate::method::{Params, SkippedPass};
pub use crate::run_methods::{MethodDescription, RunMethods};

pub const SCHEMA_VERSION: u32 = 1;

#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct Results {
    pub schema_version: u32,
    pub run: RunInfo,
    pub records: Vec<Record>,
}

#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct RunInfo {
    pub id: String,
    pub git_commit: String,
    pub resolution: [u32; 2],
    /// Timed frames per record.
    pub frames: u32,
    pub warmup: u32,
    /// The per-record time budget (`run --time-budget`, ARCHITECTURE §4.2) in seconds, under
    /// which slow records get fewer frames (their counters say how many); absent without one.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub time_budget_s: Option<f64>,
    pub machine: Machine,
    /// Frame whose images are scored against the reference.
    pub scored_frame: u32,
    pub note: String,
    /// What wrote the run: [`STRESS_KIND`] for `scatterbench stress`, absent (`None`) for an
    /// ordinary benchmark run. Optional so results files written before it still load.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub kind: Option<String>,
    /// `run --shard i/n`: which slice of the work list this run holds (absent when whole).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shard: Option<crate::shard::Shard>,
    /// The definition of `errors.<aov>.headline` ([`crate::image::headline::HEADLINE_NAME`]);
    /// absent in results written before the headline existed.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub headline: Option<String>,
    /// Every method of the run, described ([`crate::run_methods`]): readers need no registry.
    /// Empty (and absent) in results written before it.
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub methods: RunMethods,
}

/// `RunInfo::kind` of a `scatterbench stress` run (ARCHITECTURE §6).
pub const STRESS_KIND: &str = "stress";

#[derive(Clone, Debug, Serialize, Deserialize, PartialEq, Default)]
pub struct Machine {
    pub adapter: String,
    pub backend: String,
    pub driver: String,
    #[serde(default)]
    pub driver_info: String,
    #[serde(default)]
    pub device_type: String,
    #[serde(default)]
    pub software: bool,
    pub cpu: String,
    pub cores: usize,
    pub os: String,
    /// The adapter's raster, compute and memory throughput, measured at the start of the run
    /// (`gpu::calibrate`, ARCHITECTURE §7.1); absent in files written before it existed, or
    /// where it failed.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub calibration: Option<Calibration>,
}

#[derive(Clone, Copy, Debug, Serialize, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "lowercase")]
pub enum Status {
    Ok,
    Skipped,
    Failed,
}

#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct Record {
    pub scene: String,
    pub method: String,
    pub params: Params,
    pub status: Status,
    pub reason: Option<String>,
    /// Scene features the method ignored (partial support).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub ignored: Vec<String>,
    pub timing: Option<Timing>,
    pub memory_bytes: Option<u64>,
    pub passes: Option<Passes>,
    #[serde(default)]
    pub counters: BTreeMap<String, f64>,
    /// Per AOV ("inscatter", "total", "surface").
    #[serde(default)]
    pub errors: BTreeMap<String, ErrorMetrics>,
    /// AOV or map name → path relative to the run directory.
    #[serde(default)]
    pub images: BTreeMap<String, String>,
    /// Animated scenes: every timed frame scored against its own frame's reference (absent for
    /// static scenes, whose one scored frame is `errors`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub errors_per_frame: Option<ErrorsPerFrame>,
    /// Under `--validate`: the first messages of the Khronos validation layer while this record
    /// ran (all are counted in counter `validation_messages`); absent when there were none.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub validation: Vec<String>,
}

/// The errors of each scored frame of a sequence, with their mean and worst.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq, Default)]
pub struct ErrorsPerFrame {
    /// In the order rendered (timed frames cycle through the scene's frames).
    pub frames: Vec<FrameErrors>,
    /// Per AOV: the mean over `frames` of each summarised figure.
    pub mean: BTreeMap<String, ErrorSummary>,
    /// Per AOV: the frame of largest headline error, with its figures.
    pub worst: BTreeMap<String, ErrorSummary>,
}

/// One scored frame: the scene's frame index and the metrics of each AOV.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct FrameErrors {
    pub frame: u32,
    pub errors: BTreeMap<String, ErrorMetrics>,
    /// This frame's encode + submit + wait, ms (absent in results written before it).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub wall_ms: Option<f64>,
    /// This frame's GPU time from timestamp queries, ms; absent where the adapter has none.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub gpu_ms: Option<f64>,
}

/// The figures summarised over a sequence's frames.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq, Default)]
pub struct ErrorSummary {
    pub headline: f64,
    pub rel_rmse: f64,
    pub flip_mean: f64,
    /// Mean over the frames that have a light in view; null when none has.
    pub light_core: Option<f64>,
    /// `worst` only: the scene frame it is.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub frame: Option<u32>,
}

impl ErrorsPerFrame {
    /// Summarises `frames` (mean, and the frame of largest headline per AOV).
    pub fn new(frames: Vec<FrameErrors>) -> ErrorsPerFrame {
        let mut mean = BTreeMap::new();
        let mut worst = BTreeMap::new();
        let aovs: std::collections::BTreeSet<&String> =
            frames.iter().flat_map(|f| f.errors.keys()).collect();
        for aov in aovs {
            let of: Vec<(u32, &ErrorMetrics)> = frames
                .iter()
                .filter_map(|f| f.errors.get(aov).map(|m| (f.frame, m)))
                .collect();
            let n = of.len() as f64;
            let avg =
                |g: &dyn Fn(&ErrorMetrics) -> f64| of.iter().map(|(_, m)| g(m)).sum::<f64>() / n;
            let cores: Vec<f64> = of.iter().filter_map(|(_, m)| m.light_core).collect();
            mean.insert(
                aov.clone(),
                ErrorSummary {
                    headline: avg(&|m| m.headline.unwrap_or(f64::NAN)),
                    rel_rmse: avg(&|m| m.rel_rmse),
                    flip_mean: avg(&|m| m.flip_mean),
                    light_core: (!cores.is_empty())
                        .then(|| cores.iter().sum::<f64>() / cores.len() as f64),
                    frame: None,
                },
            );
            let key = |m: &ErrorMetrics| m.headline.unwrap_or(f64::NAN);
            if let Some((frame, m)) = of.iter().max_by(|a, b| key(a.1).total_cmp(&key(b.1))) {
                worst.insert(
                    aov.clone(),
                    ErrorSummary {
                        headline: key(m),
                        rel_rmse: m.rel_rmse,
                        flip_mean: m.flip_mean,
                        light_core: m.light_core,
                        frame: Some(*frame),
                    },
                );
            }
        }
        ErrorsPerFrame {
            frames,
            mean,
            worst,
        }
    }
}

#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct Passes {
    pub run: Vec<String>,
    pub skipped: Vec<SkippedPass>,
}

#[derive(Clone, Copy, Debug, Serialize, Deserialize, PartialEq, Default)]
pub struct Stat {
    pub median: f64,
    pub p90: f64,
}

impl Stat {
    /// Median and 90th percentile (nearest rank) of the samples; zeros when empty.
    pub fn of(samples: &[f64]) -> Stat {
        if samples.is_empty() {
            return Stat::default();
        }
        let mut s = samples.to_vec();
        s.sort_by(f64::total_cmp);
        let n = s.len();
        let median = if n % 2 == 1 {
            s[n / 2]
        } else {
            0.5 * (s[n / 2 - 1] + s[n / 2])
        };
        let rank = ((0.9 * n as f64).ceil() as usize).clamp(1, n);
        Stat {
            median,
            p90: s[rank - 1],
        }
    }
}

#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct Timing {
    pub prepare_ms: f64,
    /// Encode + submit + wait, per frame.
    pub wall_ms: Stat,
    /// Timestamp queries around the frame; null where the adapter has none.
    pub gpu_ms: Option<Stat>,
    /// The method's `render` call: encoding plus its per-frame CPU work.
    pub cpu_ms: Stat,
    /// The harness's own work on the record after rendering: scoring the AOVs against the
    /// reference and writing images (not the method's cost; 0 in results from before it existed).
    #[serde(default)]
    pub score_ms: f64,
    /// With `--paired-floor`: the floor (no-scatter at its defaults) timed right after this
    /// record's own frames, on the same frames and in the same worker, so that a record's floor
    /// ratio does not depend on where in the run it was measured (ARCHITECTURE §4.5). Absent
    /// otherwise, on the floor's own records, and where the floor could not be prepared.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub floor: Option<FloorTiming>,
}

/// The paired floor's frames ([`Timing::floor`]), timed like the record's own.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct FloorTiming {
    pub wall_ms: Stat,
    pub gpu_ms: Option<Stat>,
    /// Timed frames.
    pub frames: u32,
    /// The passes the floor ran (its last timed frame's): what was timed.
    pub passes: Vec<String>,
    /// Its frames alternated with the record's, one floor frame before each (false: timed
    /// after the record's frames, as results before the interleaving were).
    #[serde(default)]
    pub interleaved: bool,
    /// The floor's parameters: the record's value of each knob the two share (shadow-map
    /// size and budget), the floor's defaults for the rest (`record::paired::matched_params`).
    /// Empty in results written before the floor was matched: it ran at its defaults.
    #[serde(default, skip_serializing_if = "Params::is_empty")]
    pub params: Params,
}

impl Record {
    /// A record with nothing measured: skipped or failed, and why.
    pub fn unmeasured(
        scene: &str,
        method: &str,
        params: &Params,
        status: Status,
        reason: String,
    ) -> Record {
        Record {
            scene: scene.to_string(),
            method: method.to_string(),
            params: params.clone(),
            status,
            reason: Some(reason),
            ignored: Vec::new(),
            timing: None,
            memory_bytes: None,
            passes: None,
            counters: Default::default(),
            errors: Default::default(),
            images: Default::default(),
            errors_per_frame: None,
            validation: Vec::new(),
        }
    }

    /// Identity of a record for `--resume`: scene, method and the full parameter set.
    pub fn key(&self) -> String {
        record_key(&self.scene, &self.method, &self.params)
    }
}

pub fn record_key(scene: &str, method: &str, params: &Params) -> String {
    format!(
        "{scene}|{method}|{}",
        serde_json::to_string(params).unwrap_or_default()
    )
}

impl Results {
    pub fn load(path: &Path) -> Result<Results, String> {
        let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
        let r: Results = serde_json::from_str(&text)
            .map_err(|e| format!("{}: not a scatterbench results file: {e}", path.display()))?;
        if r.schema_version != SCHEMA_VERSION {
            return Err(format!(
                "{}: schema_version {} (this build reads {SCHEMA_VERSION})",
                path.display(),
                r.schema_version
            ));
        }
        Ok(r)
    }

    /// Writes atomically (temporary file + rename).
    pub fn save(&self, path: &Path) -> Result<(), String> {
        let text = serde_json::to_string_pretty(self).map_err(|e| e.to_string())?;
        crate::fsutil::write_atomic(path, text.as_bytes())
    }
}

impl Machine {
    pub fn detect(adapter: &AdapterSummary) -> Machine {
        let cpu = std::fs::read_to_string("/proc/cpuinfo")
            .ok()
            .and_then(|s| {
                s.lines()
                    .find(|l| l.starts_with("model name"))
                    .and_then(|l| l.split(':').nth(1))
                    .map(|s| s.trim().to_string())
            })
            .unwrap_or_else(|| std::env::consts::ARCH.to_string());
        let os = std::fs::read_to_string("/etc/os-release")
            .ok()
            .and_then(|s| {
                s.lines()
                    .find(|l| l.starts_with("PRETTY_NAME="))
                    .map(|l| l["PRETTY_NAME=".len()..].trim_matches('"').to_string())
            })
            .unwrap_or_else(|| std::env::consts::OS.to_string());
        Machine {
            adapter: adapter.adapter.clone(),
            backend: adapter.backend.clone(),
            driver: adapter.driver.clone(),
            driver_info: adapter.driver_info.clone(),
            device_type: adapter.device_type.clone(),
            software: adapter.software,
            cpu,
            cores: std::thread::available_parallelism()
                .map(|n| n.get())
                .unwrap_or(1),
            os,
            calibration: None,
        }
    }
}

/// The commit `SCATTERBENCH_COMMIT` names, else the working directory's git commit, or "unknown"
/// outside a checkout.
pub fn git_commit() -> String {
    if let Ok(c) = std::env::var(COMMIT_ENV)
        && !c.trim().is_empty()
    {
        return c.trim().to_string();
    }
    std::process::Command::new("git")
        .args(["rev-parse", "--short=12", "HEAD"])
        .output()
        .ok()
        .filter(|o| o.status.success())
        .map(|o| String::from_utf8_lossy(&o.stdout).trim().to_string())
        .unwrap_or_else(|| "unknown".into())
}

/// Names the commit a binary was built from where the working directory cannot (a bundle run
/// elsewhere: its run.sh sets it from the bundle's COMMIT file).
pub const COMMIT_ENV: &str = "SCATTERBENCH_COMMIT";

/// A UTC timestamp usable as a directory name: 2026-11-22T08-30-05Z.
pub fn run_id_now() -> String {
    let secs = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map(|d| d.as_secs())
        .unwrap_or(0);
    let (days, rem) = (secs / 86400, secs % 86400);
    // Civil date from days since 1970-01-01 (Howard Hinnant's algorithm).
    let z = days as i64 + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z - era * 146_097;
    let yoe = (doe - doe / 1460 + doe / 36524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let d = doy - (153 * mp + 2) / 5 + 1;
    let m = if mp < 10 { mp + 3 } else { mp - 9 };
    let y = yoe + era * 400 + i64::from(m <= 2);
    format!(
        "{y:04}-{m:02}-{d:02}T{:02}-{:02}-{:02}Z",
        rem / 3600,
        rem % 3600 / 60,
        rem % 60
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stat_median_and_p90_by_nearest_rank() {
        let s = Stat::of(&[5.0, 1.0, 3.0, 2.0, 4.0, 6.0, 7.0, 8.0, 9.0, 10.0]);
        assert_eq!(s.median, 5.5);
        assert_eq!(s.p90, 9.0);
        assert_eq!(Stat::of(&[2.0]).p90, 2.0);
    }
}
