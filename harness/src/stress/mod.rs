//! `scatterbench stress` (ARCHITECTURE §6): extreme but valid scenes × every method, each judged by
//! four criteria — no panic, no wgpu error, zero non-finite pixels, and an error within the
//! bound the method declares for the case ([`crate::method::Method::stress_bound`]) — or a clean
//! "unsupported" with the method's reason.
//!
//! Each case × method goes through the ordinary runner (one frame, no warm-up), so its record
//! lands in `results.json` like any other (scene name = case name) and is written atomically
//! the moment it finishes; an interrupted stress run resumes like `run --resume`. Faults are
//! contained per record: a panic or wgpu error inside a method is the runner's business; a
//! panic or error in the reference, or in building the case, becomes a failed record here; and
//! a method that loses the device gets a fresh device for the records after it.

mod cases;
pub mod meshes;
mod particle_cases;

use std::panic::AssertUnwindSafe;
use std::path::PathBuf;

pub use cases::{BuildContext, CASES, Case, find, names};

use crate::gpu::Gpu;
use crate::isolate::Isolation;
use crate::method::{Method, Params, resolve_params};
use crate::record::{RecordSettings, panic_message};
use crate::results::{Record, Results, STRESS_KIND, Status, record_key};
use crate::runner::{self, Event, RunConfig};

/// Counter name under which a record carries the bound it was judged against.
pub const BOUND_COUNTER: &str = "stress_bound_total_rel_rmse";

pub struct StressConfig {
    /// How each case × method is measured: made by [`one_frame`] (the output directory, the
    /// resolution, and the reference cache where one is set).
    pub record: RecordSettings,
    /// Cases to run (all when empty).
    pub cases: Vec<&'static Case>,
    /// Triangle count of `many-triangles`.
    pub triangles: usize,
    /// Particle count of `particle-million`.
    pub particles: usize,
    pub resume: bool,
    pub run_id: String,
    /// Worker processes and the watchdog for every record; `retry_failed` (with `resume`)
    /// runs failed records again.
    pub isolation: Isolation,
}

/// The stress protocol's record settings: one frame per case × method, no warm-up, no time
/// budget, at `width`×`height`, written under `out_dir`.
pub fn one_frame(out_dir: impl Into<PathBuf>, (width, height): (u32, u32)) -> RecordSettings {
    RecordSettings::new(out_dir, (width, height), (1, 0))
}

/// How one case × method came out.
#[derive(Clone, Debug, PartialEq)]
pub enum Verdict {
    Pass,
    /// The method declined the scene, with its reason (a pass: a clean refusal).
    Unsupported(String),
    Fail(String),
}

/// Judges a runner record against the four criteria; `bound` is what the method declared for
/// the case. The runner has already turned panics, wgpu errors and non-finite pixels into
/// failed records; this checks non-finite counts again (in every AOV) and the error bound.
pub fn judge(rec: &Record, bound: Option<f64>) -> Verdict {
    match rec.status {
        Status::Skipped => {
            return Verdict::Unsupported(rec.reason.clone().unwrap_or_default());
        }
        Status::Failed => return Verdict::Fail(rec.reason.clone().unwrap_or_default()),
        Status::Ok => {}
    }
    let nonfinite: u64 = rec.errors.values().map(|m| m.nonfinite).sum();
    if nonfinite > 0 {
        return Verdict::Fail(format!("{nonfinite} non-finite pixels"));
    }
    let Some(total) = rec.errors.get("total") else {
        return Verdict::Fail("no error metrics for the total AOV".into());
    };
    if !total.rel_rmse.is_finite() {
        return Verdict::Fail(format!("total rel RMSE is {}", total.rel_rmse));
    }
    if let Some(b) = bound
        && total.rel_rmse > b
    {
        return Verdict::Fail(format!(
            "total rel RMSE {:.4} exceeds the bound {b} the method declares for this case",
            total.rel_rmse
        ));
    }
    Verdict::Pass
}

/// Applies a verdict to the record: a failed criterion turns an ok record into a failed one
/// with the reason; the bound is kept as a counter.
fn apply(rec: &mut Record, bound: Option<f64>) {
    if let Some(b) = bound {
        rec.counters.insert(BOUND_COUNTER.into(), b);
    }
    if let Verdict::Fail(why) = judge(rec, bound)
        && rec.status == Status::Ok
    {
        rec.status = Status::Failed;
        rec.reason = Some(why);
    }
}

fn fresh(gpu: &Gpu, cfg: &StressConfig) -> Results {
    let mut r = runner::fresh_results(gpu, &cfg.record, &cfg.run_id, None);
    r.run.note = "stress run: one frame per case × method; timings are not meaningful".into();
    r.run.kind = Some(STRESS_KIND.into());
    r
}

/// Runs every case × method. `gpu` is replaced by a fresh device when a method loses it.
/// Returns the results (also in `out_dir/results.json`). Errs only when results cannot be
/// written or a lost device cannot be reopened.
pub fn run(
    gpu: &mut Gpu,
    methods: &[&dyn Method],
    cfg: &StressConfig,
    on_event: &mut dyn FnMut(Event),
) -> Result<Results, String> {
    let out = &cfg.record.out_dir;
    std::fs::create_dir_all(out)
        .map_err(|e| format!("{}: cannot create the output directory: {e}", out.display()))?;
    let path = out.join("results.json");
    let mut start = if cfg.resume && path.exists() {
        Results::load(&path)?
    } else {
        fresh(gpu, cfg)
    };
    crate::run_methods::describe(&mut start.run.methods, methods.iter().copied());
    start.save(&path)?;
    let mesh_dir = out.join("stress-meshes");
    let ctx = BuildContext {
        width: cfg.record.width,
        height: cfg.record.height,
        mesh_dir: &mesh_dir,
        triangles: cfg.triangles,
        particles: cfg.particles,
    };
    let cases: Vec<&Case> = if cfg.cases.is_empty() {
        CASES.iter().collect()
    } else {
        cfg.cases.clone()
    };
    on_event(Event::Planned(cases.len() * methods.len()));
    for case in cases {
        let scene = std::panic::catch_unwind(|| case.scene(&ctx))
            .unwrap_or_else(|p| Err(format!("panicked: {}", panic_message(p))));
        for entry in methods {
            let bound = entry.stress_bound(case.name);
            let params = resolve_params(*entry, &Params::new()).map_err(|e| e.to_string())?;
            let key = record_key(case.name, entry.id(), &params);
            let mut results = Results::load(&path)?;
            let retry = |r: &Record| cfg.isolation.retry_failed && r.status == Status::Failed;
            if results.records.iter().any(|r| r.key() == key && !retry(r)) {
                on_event(Event::Resumed(&key));
                continue;
            }
            on_event(Event::Starting {
                scene: case.name,
                method: entry.id(),
                params: &params,
            });
            let outcome = match &scene {
                Err(e) => Err(format!("the case could not be built: {e}")),
                Ok(scene) => {
                    let rc = RunConfig {
                        resume: true,
                        isolation: cfg.isolation.clone(),
                        ..RunConfig::new(cfg.record.clone(), &cfg.run_id)
                    };
                    let g: &Gpu = gpu;
                    // Swallow the runner's own record events: the judged record is reported below.
                    let mut inner = |e: Event| {
                        if let Event::Reference { .. } = e {
                            on_event(e)
                        }
                    };
                    std::panic::catch_unwind(AssertUnwindSafe(|| {
                        runner::run(g, std::slice::from_ref(scene), &[*entry], &rc, &mut inner)
                    }))
                    .unwrap_or_else(|p| Err(format!("panicked: {}", panic_message(p))))
                    .map_err(|e| format!("no record (reference or harness): {e}"))
                }
            };
            match outcome {
                Ok(r) => results = r,
                Err(why) => {
                    results = Results::load(&path)?;
                    results.records.push(Record::unmeasured(
                        case.name,
                        entry.id(),
                        &params,
                        Status::Failed,
                        why,
                    ));
                }
            }
            if let Some(rec) = results.records.iter_mut().find(|r| r.key() == key) {
                apply(rec, bound);
                on_event(Event::Record(rec));
            }
            results.save(&path)?;
            if gpu.is_lost() {
                *gpu = gpu
                    .reopen()
                    .map_err(|e| format!("the device was lost and cannot be reopened: {e}"))?;
            }
        }
    }
    Results::load(&path)
}

/// Verdict counts of a stress run's records: (pass, unsupported, fail).
pub fn tally(results: &Results) -> (usize, usize, usize) {
    let mut t = (0, 0, 0);
    for r in &results.records {
        match r.status {
            Status::Ok => t.0 += 1,
            Status::Skipped => t.1 += 1,
            Status::Failed => t.2 += 1,
        }
    }
    t
}
