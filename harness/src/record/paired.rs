//! The paired floor (`run --paired-floor`, ARCHITECTURE §4.5): the floor method, prepared
//! beside the record's method and rendered one frame before each of the method's, warm-up and
//! timed alike, on the same scene frame and AOV targets.
//!
//! The floor takes the record's value of every knob the two share ([`matched_params`]; for
//! no-scatter `shadow_map` and `local_shadow_budget`), its defaults for the rest: it rasterises
//! the scene and its shadow maps as the method does, so the ratio is what the in-scatter costs
//! over them. Against a floor at its defaults, a configuration with coarser shadow maps (whose
//! surfaces are shadowed by them too) read as cheap in-scatter: wyman-hybrid at
//! `shadow_map=512` ran at 0.70–0.72× pen-orbit's floor, whose frame is mostly shadow maps.
//!
//! Interleaved frame by frame, the two see the same state of the machine. Timed one after the
//! other (the method's frames, then the floor's: this module's first form), they did not: on
//! the shared 2-core lavapipe machine a record's own frames agree within 8 % (p90 / median,
//! 10 frames) while the floor timed seconds later moved by a median 18 % between two
//! identical 512² runs, so the ratio moved by 11 %.
//!
//! The floor renders first in each pair so that the method's frame is the last in the AOV
//! targets: the scorer reads it back after it, and the scored frame may reuse it. A floor that
//! fails or panics is dropped, and the record keeps its own measurement without a pairing.

use std::panic::{AssertUnwindSafe, catch_unwind};

use scenes::Scene;

use super::frame::{AovTargets, render_frame};
use super::settings::RecordSettings;
use crate::gpu::{Gpu, GpuTimer};
use crate::method::{Method, Params, PrepareContext, Prepared, resolve_params};
use crate::results::{FloorTiming, Stat};

/// The floor prepared beside a record, and what its timed frames measured.
pub(super) struct PairedFloor {
    prepared: Box<dyn Prepared>,
    params: Params,
    wall: Vec<f64>,
    gpu: Vec<f64>,
    passes: Vec<String>,
    failed: bool,
}

impl PairedFloor {
    /// `floor` with [`matched_params`] prepared for `scene` at the record's size; None where
    /// those are not valid for it, or it cannot be prepared or raises a wgpu error doing it
    /// (taken here, so they are not the record's).
    pub(super) fn prepare(
        gpu: &Gpu,
        floor: &dyn Method,
        scene: &Scene,
        settings: &RecordSettings,
        record_params: &Params,
    ) -> Option<PairedFloor> {
        let params = matched_params(floor, record_params).ok()?;
        let prepared = catch_unwind(AssertUnwindSafe(|| {
            floor.prepare(&PrepareContext {
                gpu,
                scene,
                params: &params,
                width: settings.width,
                height: settings.height,
                no_skip: settings.no_skip,
            })
        }))
        .ok()?
        .ok()?;
        gpu.wait().ok()?;
        gpu.take_errors().is_empty().then(|| PairedFloor {
            prepared,
            params,
            wall: Vec::new(),
            gpu: Vec::new(),
            passes: Vec::new(),
            failed: false,
        })
    }

    /// Renders the floor's frame `index` into `aovs`, kept as a timed frame when `timed`.
    pub(super) fn frame(
        &mut self,
        gpu: &Gpu,
        scene: &Scene,
        index: u32,
        aovs: &AovTargets,
        timer: Option<&GpuTimer>,
        timed: bool,
    ) {
        if self.failed {
            return;
        }
        let prepared = self.prepared.as_mut();
        let rendered = catch_unwind(AssertUnwindSafe(|| {
            render_frame(gpu, prepared, scene, index, aovs, timer)
        }));
        match rendered {
            Ok(Ok(t)) if timed => {
                self.wall.push(t.wall_ms);
                self.gpu.extend(t.gpu_ms);
                self.passes = t.report.run;
            }
            Ok(Ok(_)) => {}
            _ => self.failed = true,
        }
    }

    /// Renders the floor's frame `index` untimed by the record and returns its (wall, GPU)
    /// ms; None once the floor has failed (`record::contender`'s pairs).
    pub(super) fn frame_ms(
        &mut self,
        gpu: &Gpu,
        scene: &Scene,
        index: u32,
        aovs: &AovTargets,
        timer: Option<&GpuTimer>,
    ) -> Option<(f64, Option<f64>)> {
        if self.failed {
            return None;
        }
        let prepared = self.prepared.as_mut();
        match catch_unwind(AssertUnwindSafe(|| {
            render_frame(gpu, prepared, scene, index, aovs, timer)
        })) {
            Ok(Ok(t)) => Some((t.wall_ms, t.gpu_ms)),
            _ => {
                self.failed = true;
                None
            }
        }
    }

    /// What the floor's timed frames measured; None where it failed or timed none.
    pub(super) fn timing(self) -> Option<FloorTiming> {
        (!self.failed && !self.wall.is_empty()).then(|| FloorTiming {
            wall_ms: Stat::of(&self.wall),
            gpu_ms: (self.gpu.len() == self.wall.len()).then(|| Stat::of(&self.gpu)),
            frames: self.wall.len() as u32,
            passes: self.passes,
            interleaved: true,
            params: self.params,
        })
    }
}

/// The floor's parameters beside a record of `record_params`: the record's value of every knob
/// the floor declares too (the scene's rasterisation: shadow-map size and budget), the floor's
/// defaults for the rest; an error where such a value is not valid for the floor.
pub fn matched_params(floor: &dyn Method, record_params: &Params) -> Result<Params, String> {
    let shared: Params = floor
        .knobs()
        .iter()
        .filter_map(|k| Some((k.name.to_string(), record_params.get(k.name)?.clone())))
        .collect();
    resolve_params(floor, &shared).map_err(|e| e.to_string())
}
