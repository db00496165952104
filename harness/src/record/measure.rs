//! One record's measurement: `prepare` timed once, then W warm-up and K timed frames under the
//! time budget, each timed frame read back for the scorer, then the scored frame
//! (ARCHITECTURE §4.1–4.2).

use std::collections::BTreeMap;
use std::time::Instant;

use scenes::Scene;

use super::frame::{AovTargets, FrameTiming, render_frame};
use super::paired::PairedFloor;
use super::phase::{self, Phase};
use super::settings::RecordSettings;
use crate::gpu::{Gpu, GpuTimer, WORK_COUNTERS};
use crate::image::Image;
use crate::method::{FrameReport, Method, Params, PrepareContext, Prepared};
use crate::results::{Passes, Record, Stat, Status, Timing};
use crate::sequence::FrameScorer;

/// Fewest timed frames a record gets under a time budget: one, where that frame alone uses the
/// budget (a frame of seconds varies little; more of them would only multiply the record's cost).
pub const MIN_TIMED_FRAMES: u32 = 1;

/// Under a time budget B: warm-up stops after its first frame once warm-up has used B/4,
/// and timing stops once [`MIN_TIMED_FRAMES`] frames are timed and the timed frames have used
/// B. Fast methods still get the full W + K frames; a 3 s/frame method under 8 s gets 1 + 3
/// instead of 3 + 10 (and see [`first_frame_is_timed`]). Returns whether to render another
/// frame of the phase.
pub fn another_frame(budget_ms: Option<f64>, warmup: bool, done: u32, used_ms: f64) -> bool {
    match budget_ms {
        None => true,
        Some(b) if warmup => done < 1 || used_ms < 0.25 * b,
        Some(b) => done < MIN_TIMED_FRAMES || used_ms < b,
    }
}

/// Under a time budget B, a first warm-up frame that alone took B or more is the record's one
/// timed frame (`warmup_frames` 0, `timed_frames` 1): what a warm-up would spare it (first-use
/// costs) is a small part of a frame that long, and rendering it again would double the
/// record's cost. Not with a paired floor, whose timed frames pair with the method's.
pub fn first_frame_is_timed(budget_ms: Option<f64>, paired_floor: bool, first_ms: f64) -> bool {
    budget_ms.is_some_and(|b| first_ms >= b) && !paired_floor
}

/// What the frames of a record measured.
#[derive(Default)]
struct Frames {
    cpu: Vec<f64>,
    wall: Vec<f64>,
    gpu: Vec<f64>,
    /// The last timed frame's report, with the work counts' medians and the frame counts.
    report: FrameReport,
    /// Frames rendered so far (the next frame's index), and how many of them were warm-up.
    rendered: u32,
    warmed: u32,
}

/// Prepares, times and reads back one method × params. Returns the record (without errors
/// and images) and the three AOVs of the scored frame.
pub(super) fn measure(
    gpu: &Gpu,
    scene: &Scene,
    entry: &dyn Method,
    params: &Params,
    settings: &RecordSettings,
    scorer: &mut FrameScorer,
    floor: Option<&dyn Method>,
) -> Result<(Record, [Image; 3]), String> {
    phase::enter(Phase::Prepare);
    gpu.reset_allocated();
    let start = Instant::now();
    let mut method = entry
        .prepare(&PrepareContext {
            gpu,
            scene,
            params,
            width: settings.width,
            height: settings.height,
            no_skip: settings.no_skip,
        })
        .map_err(|e| format!("prepare failed: {e:#}"))?;
    gpu.wait()?;
    let prepare_ms = start.elapsed().as_secs_f64() * 1e3;
    let memory = gpu.allocated_bytes();
    let errors = gpu.take_errors();
    if !errors.is_empty() {
        return Err(format!("wgpu error during prepare: {}", errors.join("; ")));
    }
    let aovs = AovTargets::new(gpu, settings.width, settings.height);
    // The paired floor is prepared after the method's memory is counted, and renders one frame
    // before each of the method's (`paired`).
    let mut floor = floor
        .filter(|f| f.id() != entry.id())
        .and_then(|f| PairedFloor::prepare(gpu, f, scene, settings, params));
    phase::enter(Phase::Render);
    let paired = floor.as_mut();
    let mut frames = timed_frames(
        gpu,
        method.as_mut(),
        scene,
        settings,
        &aovs,
        Some(scorer),
        paired,
    )?;
    // An accumulating method converges over `converge` frames: on a static scene the scored
    // frame is the converge-th rendered since prepare, or later.
    let converge = entry.converge_frames(params);
    if converge > 0 {
        frames.report.count("converge_frames", converge as f64);
        if scene.frame_count() == 1 {
            while frames.rendered < converge {
                render_frame(gpu, method.as_mut(), scene, frames.rendered, &aovs, None)?;
                frames.rendered += 1;
            }
        }
    }
    // The scored frame: frame 0 once more — unless the last timed frame was frame 0 (always,
    // in a static scene): its output is still in the AOVs, the same inputs rendered by the same
    // method, so rendering it again would only cost a frame.
    let (f, warmed) = (frames.rendered, frames.warmed);
    let reuse = f > warmed && (f - 1) % scene.frame_count().max(1) == 0;
    let scored = if reuse {
        None
    } else {
        Some(render_frame(gpu, method.as_mut(), scene, 0, &aovs, None)?.report)
    };
    let images = aovs.read(gpu)?;
    // wgpu errors of the frames are the record's (as `settle` words it), the interleaved
    // floor's among them: the floor is no-scatter, which no run has seen raise one.
    let pending = gpu.take_errors();
    if !pending.is_empty() {
        return Err(format!("wgpu error: {}", pending.join("; ")));
    }
    let floor = floor.and_then(PairedFloor::timing);
    let report = if settings.frames > 0 {
        frames.report
    } else {
        scored.unwrap_or_default()
    };
    let record = Record {
        scene: scene.name.clone(),
        method: entry.id().to_string(),
        params: params.clone(),
        status: Status::Ok,
        reason: None,
        ignored: Vec::new(),
        timing: Some(Timing {
            prepare_ms,
            wall_ms: Stat::of(&frames.wall),
            gpu_ms: (!frames.gpu.is_empty()).then(|| Stat::of(&frames.gpu)),
            cpu_ms: Stat::of(&frames.cpu),
            score_ms: 0.0,
            floor,
        }),
        memory_bytes: Some(memory),
        passes: Some(Passes {
            run: report.run,
            skipped: report.skipped,
        }),
        counters: report.counters,
        errors: Default::default(),
        images: Default::default(),
        errors_per_frame: None,
        validation: Vec::new(),
    };
    Ok((record, images))
}

/// The warm-up and timed frames under the budget, cycling through the scene's frames; with a
/// `scorer`, each timed frame is read back and scored outside its timed region; with a paired
/// `floor`, one frame of it before each of the method's.
fn timed_frames(
    gpu: &Gpu,
    method: &mut dyn Prepared,
    scene: &Scene,
    settings: &RecordSettings,
    aovs: &AovTargets,
    mut scorer: Option<&mut FrameScorer>,
    mut floor: Option<&mut PairedFloor>,
) -> Result<Frames, String> {
    let timer = GpuTimer::new(gpu);
    let budget = settings.budget_ms;
    let mut out = Frames::default();
    let mut work: BTreeMap<&'static str, Vec<f64>> = BTreeMap::new();
    let (mut f, mut warm_ms, mut timed_ms) = (0u32, 0.0, 0.0);
    let mut warmed = None;
    while f < settings.warmup && another_frame(budget, true, f, warm_ms) {
        if let Some(floor) = floor.as_deref_mut() {
            floor.frame(gpu, scene, f, aovs, timer.as_ref(), false);
        }
        let t = render_frame(gpu, method, scene, f, aovs, timer.as_ref())?;
        warm_ms += t.wall_ms;
        f += 1;
        if f == 1 && settings.frames > 0 && first_frame_is_timed(budget, floor.is_some(), t.wall_ms) {
            timed_ms = t.wall_ms;
            keep_timed(gpu, &mut out, &mut work, t, 0, aovs, scorer.as_deref_mut())?;
            warmed = Some(0);
            break;
        }
    }
    let warmed = warmed.unwrap_or(f);
    while f - warmed < settings.frames && another_frame(budget, false, f - warmed, timed_ms) {
        if let Some(floor) = floor.as_deref_mut() {
            floor.frame(gpu, scene, f, aovs, timer.as_ref(), true);
        }
        let t: FrameTiming = render_frame(gpu, method, scene, f, aovs, timer.as_ref())?;
        timed_ms += t.wall_ms;
        keep_timed(gpu, &mut out, &mut work, t, f, aovs, scorer.as_deref_mut())?;
        f += 1;
    }
    // Work counts are per frame, median over the timed frames (an animated scene's frames differ).
    for (name, values) in &work {
        out.report
            .counters
            .insert(name.to_string(), Stat::of(values).median);
    }
    if budget.is_some() {
        out.report.count("warmup_frames", warmed as f64);
        out.report.count("timed_frames", (f - warmed) as f64);
    }
    (out.rendered, out.warmed) = (f, warmed);
    Ok(out)
}

/// Keeps timed frame `f`'s times, work counts and report, then reads it back and scores it
/// outside the timed region (the next frame's clock starts after its own clear and wait).
fn keep_timed(
    gpu: &Gpu,
    out: &mut Frames,
    work: &mut BTreeMap<&'static str, Vec<f64>>,
    t: FrameTiming,
    f: u32,
    aovs: &AovTargets,
    scorer: Option<&mut FrameScorer>,
) -> Result<(), String> {
    out.cpu.push(t.cpu_ms);
    out.wall.push(t.wall_ms);
    if let Some(g) = t.gpu_ms {
        out.gpu.push(g);
    }
    for name in WORK_COUNTERS {
        if let Some(n) = t.report.counters.get(name) {
            work.entry(name).or_default().push(*n);
        }
    }
    out.report = t.report;
    if let Some(scorer) = scorer {
        scorer.timed_frame(f, &aovs.read(gpu)?)?;
        scorer.time_last_frame(t.wall_ms, t.gpu_ms);
    }
    Ok(())
}

#[cfg(test)]
mod budget_tests {
    use super::*;

    /// Simulates the frame loop of `measure` for a method taking `frame_ms` a frame.
    fn frames(budget: Option<f64>, warmup: u32, timed: u32, frame_ms: f64) -> (u32, u32) {
        let (mut w, mut used) = (0, 0.0);
        while w < warmup && another_frame(budget, true, w, used) {
            w += 1;
            used += frame_ms;
        }
        let (mut k, mut used) = (0, 0.0);
        while k < timed && another_frame(budget, false, k, used) {
            k += 1;
            used += frame_ms;
        }
        (w, k)
    }

    #[test]
    fn budget_cuts_only_slow_records_and_keeps_the_minimums() {
        // No budget: always W + K.
        assert_eq!(frames(None, 3, 10, 9000.0), (3, 10));
        // Fast methods are untouched by an 8 s budget (10 × 0.5 s = 5 s < 8 s).
        assert_eq!(frames(Some(8000.0), 3, 10, 500.0), (3, 10));
        // 1 s/frame: warm-up stops at 2 s (B/4), timing at 8 s.
        assert_eq!(frames(Some(8000.0), 3, 10, 1000.0), (2, 8));
        // 3 s/frame: one warm-up frame, timing stops once past 8 s.
        assert_eq!(frames(Some(8000.0), 3, 10, 3000.0), (1, 3));
        // 5 s/frame: one warm-up frame, then two timed (10 s ≥ 8 s).
        assert_eq!(frames(Some(8000.0), 3, 10, 5000.0), (1, 2));
        // 9 s/frame: the minimum of timed frames, one (and see the first-frame rule below).
        assert_eq!(frames(Some(8000.0), 3, 10, 9000.0), (1, MIN_TIMED_FRAMES));
        // A budget never asks for more than requested.
        assert_eq!(frames(Some(8000.0), 0, 2, 500.0), (0, 2));
    }

    #[test]
    fn only_a_first_frame_past_the_whole_budget_is_timed_and_never_with_a_paired_floor() {
        assert!(first_frame_is_timed(Some(8000.0), false, 8000.0));
        assert!(first_frame_is_timed(Some(8000.0), false, 35000.0));
        assert!(!first_frame_is_timed(Some(8000.0), false, 7999.0));
        assert!(!first_frame_is_timed(None, false, 35000.0));
        assert!(!first_frame_is_timed(Some(8000.0), true, 35000.0));
    }
}
