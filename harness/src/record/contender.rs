//! A configuration kept prepared beside its paired floor, for `scatterbench tune`
//! (ARCHITECTURE §4.6): timed in rounds of interleaved pairs (one floor frame, then the method's
//! frame, on the same scene frame and targets, as `paired.rs` does for a record), and scored on
//! the headline alone. Where a record (`run_one`) measures once and scores everything, a
//! contender is timed again and again while the tune's verdict is open, and pays for no image,
//! FLIP or SSIM it would not read.

use std::panic::{AssertUnwindSafe, catch_unwind};

use scenes::Scene;

use super::failure::panic_message;
use super::frame::{AovTargets, render_frame};
use super::paired::PairedFloor;
use super::settings::RecordSettings;
use crate::gpu::{Gpu, GpuTimer};
use crate::image::headline::headline;
use crate::method::{Method, Params, PrepareContext, Prepared};
use crate::reference::ReferenceImages;
use crate::sequence::finite;

/// One timed pair: the floor's frame and the method's frame just after it, ms, on the
/// adapter's GPU timestamps where it has them (both), else wall clock.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pair {
    pub method_ms: f64,
    pub floor_ms: f64,
}

impl Pair {
    /// ln(method / floor): the pair's floor ratio on a log scale.
    pub fn log_ratio(self) -> f64 {
        (self.method_ms / self.floor_ms).ln()
    }
}

/// The headline errors of a contender's scored frames (ARCHITECTURE §4.4), as fractions.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Scored {
    /// In-scatter headline (the verdict metric); for an animated scene the mean over the frames.
    pub inscatter: f64,
    pub total: f64,
    /// mean(in-scatter) / mean(reference in-scatter), averaged likewise; None on a black one.
    pub mean_ratio: Option<f64>,
}

/// A method × params prepared with its paired floor (at the shared knobs' values, §4.5).
pub struct Contender {
    method: Box<dyn Prepared>,
    floor: PairedFloor,
    aovs: AovTargets,
    timer: Option<GpuTimer>,
    /// Frames rendered since prepare: the next pair shows this scene frame.
    next_frame: u32,
    converge: u32,
    pub prepare_ms: f64,
}

impl Contender {
    /// `entry` with `params` and `floor` prepared on `scene` at `settings`' size. Err: why
    /// (a panic, the method's error, a wgpu error, or a floor that cannot run beside it).
    pub fn prepare(
        gpu: &Gpu,
        scene: &Scene,
        (entry, params): (&dyn Method, &Params),
        floor: &dyn Method,
        settings: &RecordSettings,
    ) -> Result<Contender, String> {
        let _ = gpu.take_errors();
        let start = std::time::Instant::now();
        let prepared = catch_unwind(AssertUnwindSafe(|| {
            entry.prepare(&PrepareContext {
                gpu,
                scene,
                params,
                width: settings.width,
                height: settings.height,
                no_skip: settings.no_skip,
            })
        }))
        .map_err(|p| format!("prepare panicked: {}", panic_message(p)))?
        .map_err(|e| format!("prepare failed: {e:#}"))?;
        gpu.wait()?;
        let prepare_ms = start.elapsed().as_secs_f64() * 1e3;
        settled(gpu, "prepare")?;
        let floor = PairedFloor::prepare(gpu, floor, scene, settings, params)
            .ok_or_else(|| format!("the floor ({}) could not be prepared beside it", floor.id()))?;
        Ok(Contender {
            method: prepared,
            floor,
            aovs: AovTargets::new(gpu, settings.width, settings.height),
            timer: GpuTimer::new(gpu),
            next_frame: 0,
            converge: entry.converge_frames(params),
            prepare_ms,
        })
    }

    /// "gpu" where pairs are timed with GPU timestamps, else "wall".
    pub fn basis(&self) -> &'static str {
        if self.timer.is_some() { "gpu" } else { "wall" }
    }

    /// `count` interleaved pairs; `warmup` untimed pairs before them.
    pub fn time(
        &mut self,
        gpu: &Gpu,
        scene: &Scene,
        warmup: u32,
        count: u32,
    ) -> Result<Vec<Pair>, String> {
        let mut out = Vec::with_capacity(count as usize);
        for k in 0..warmup + count {
            let f = self.next_frame;
            let floor = self
                .floor
                .frame_ms(gpu, scene, f, &self.aovs, self.timer.as_ref());
            let t = self.render(gpu, scene, f)?;
            self.next_frame += 1;
            let Some(floor) = floor else {
                return Err("the paired floor failed".into());
            };
            if k >= warmup {
                let both_gpu = t.1.zip(floor.1);
                let (method_ms, floor_ms) = both_gpu.unwrap_or((t.0, floor.0));
                out.push(Pair {
                    method_ms,
                    floor_ms,
                });
            }
        }
        settled(gpu, "the timed frames")?;
        Ok(out)
    }

    /// Renders and scores the scene's frames 0 … references.len() − 1 against their
    /// references (one for a static scene, after the method's convergence frames).
    pub fn score(
        &mut self,
        gpu: &Gpu,
        scene: &Scene,
        references: &[&ReferenceImages],
    ) -> Result<Scored, String> {
        let stat = scene.frame_count() == 1;
        if stat {
            while self.next_frame + 1 < self.converge {
                self.render(gpu, scene, self.next_frame)?;
                self.next_frame += 1;
            }
        }
        // A static scene's last timed frame (the method's, after its floor's) is still in the
        // targets once the method has converged: scored as it is.
        let reuse = stat && self.next_frame > 0 && self.next_frame >= self.converge;
        let (mut inscatter, mut total, mut ratio) = (0.0, 0.0, Some(0.0));
        for (f, r) in references.iter().enumerate() {
            if !reuse {
                self.render(gpu, scene, f as u32)?;
                self.next_frame += 1;
            }
            let [i, _, t] = self.aovs.read(gpu)?;
            let nonfinite = |img: &crate::image::Image| {
                img.pixels.iter().any(|p| p.iter().any(|c| !c.is_finite()))
            };
            if nonfinite(&i) || nonfinite(&t) {
                return Err(format!("non-finite pixels in frame {f}"));
            }
            inscatter += headline(&finite(&i), &r.inscatter);
            total += headline(&finite(&t), &r.total);
            let mean_r = r.inscatter.mean();
            ratio = ratio
                .zip((mean_r > 1e-30).then(|| i.mean() / mean_r))
                .map(|(a, b)| a + b);
        }
        settled(gpu, "the scored frames")?;
        let n = references.len().max(1) as f64;
        Ok(Scored {
            inscatter: inscatter / n,
            total: total / n,
            mean_ratio: ratio.map(|r| r / n),
        })
    }

    /// One frame of the method: (wall ms, GPU ms).
    fn render(&mut self, gpu: &Gpu, scene: &Scene, f: u32) -> Result<(f64, Option<f64>), String> {
        let m = self.method.as_mut();
        let (aovs, timer) = (&self.aovs, self.timer.as_ref());
        let t = catch_unwind(AssertUnwindSafe(|| {
            render_frame(gpu, m, scene, f, aovs, timer)
        }))
        .map_err(|p| format!("render panicked: {}", panic_message(p)))??;
        Ok((t.wall_ms, t.gpu_ms))
    }
}

/// Err naming `when` if wgpu raised errors since they were last taken.
fn settled(gpu: &Gpu, when: &str) -> Result<(), String> {
    let errors = gpu.take_errors();
    if errors.is_empty() {
        Ok(())
    } else {
        Err(format!("wgpu error during {when}: {}", errors.join("; ")))
    }
}
