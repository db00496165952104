//! One record's frames: the AOV targets, one timed frame (`render_frame`), the warm-up and
//! timed loop under the time budget (`measure`, ARCHITECTURE §4.1–4.2).

use super::*;
use crate::gpu::color_attachment;

/// Fewest timed frames a record gets under a time budget (a median needs a few samples).
pub const MIN_TIMED_FRAMES: u32 = 3;

/// Under a time budget B: warm-up stops after its first frame once warm-up has used B/4,
/// and timing stops once [`MIN_TIMED_FRAMES`] frames are timed and the timed frames have used
/// B. Fast methods still get the full W + K frames; a 9 s/frame method gets 1 + 3 instead of
/// 3 + 10. Returns whether to render another frame of the phase.
pub fn another_frame(budget_ms: Option<f64>, warmup: bool, done: u32, used_ms: f64) -> bool {
    match budget_ms {
        None => true,
        Some(b) if warmup => done < 1 || used_ms < 0.25 * b,
        Some(b) => done < MIN_TIMED_FRAMES || used_ms < b,
    }
}

/// The AOV textures the harness renders into.
pub struct AovTargets {
    pub textures: [wgpu::Texture; 3],
    pub views: [wgpu::TextureView; 3],
    pub width: u32,
    pub height: u32,
}

impl AovTargets {
    pub fn new(gpu: &Gpu, width: u32, height: u32) -> AovTargets {
        let make = |label: &str| {
            gpu.device.create_texture(&wgpu::TextureDescriptor {
                label: Some(label),
                size: wgpu::Extent3d {
                    width,
                    height,
                    depth_or_array_layers: 1,
                },
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format: AOV_FORMAT,
                usage: wgpu::TextureUsages::RENDER_ATTACHMENT
                    | wgpu::TextureUsages::STORAGE_BINDING
                    | wgpu::TextureUsages::TEXTURE_BINDING
                    | wgpu::TextureUsages::COPY_SRC,
                view_formats: &[],
            })
        };
        let textures = [
            make("aov inscatter"),
            make("aov surface"),
            make("aov total"),
        ];
        let views = [0, 1, 2].map(|i| textures[i].create_view(&Default::default()));
        AovTargets {
            textures,
            views,
            width,
            height,
        }
    }

    pub fn targets(&self) -> Targets<'_> {
        Targets {
            inscatter: &self.views[0],
            surface: &self.views[1],
            total: &self.views[2],
            width: self.width,
            height: self.height,
        }
    }

    /// Clears all three to zero (outside any timed region).
    pub fn clear(&self, gpu: &Gpu) {
        let mut enc = gpu.device.create_command_encoder(&Default::default());
        for v in &self.views {
            let _ = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("clear aov"),
                color_attachments: &[color_attachment(
                    v,
                    wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
                )],
                ..Default::default()
            });
        }
        gpu.queue.submit([enc.finish()]);
    }

    pub fn read(&self, gpu: &Gpu) -> Result<[Image; 3], String> {
        Ok([
            read_rgba32f(gpu, &self.textures[0])?,
            read_rgba32f(gpu, &self.textures[1])?,
            read_rgba32f(gpu, &self.textures[2])?,
        ])
    }
}

/// One frame: clear, encode (timed as CPU), submit and wait (timed as wall), GPU timestamps.
pub struct FrameTiming {
    pub cpu_ms: f64,
    pub wall_ms: f64,
    pub gpu_ms: Option<f64>,
    pub report: FrameReport,
}

pub fn render_frame(
    gpu: &Gpu,
    method: &mut dyn Prepared,
    scene: &Scene,
    index: u32,
    aovs: &AovTargets,
    timer: Option<&GpuTimer>,
) -> Result<FrameTiming, String> {
    aovs.clear(gpu);
    gpu.wait()?;
    let frame = scene.frame(index % scene.frame_count());
    let start = Instant::now();
    let mut enc = gpu
        .device
        .create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("frame"),
        });
    if let Some(t) = timer {
        t.begin(&mut enc);
    }
    gpu.stats_begin_frame();
    let cpu_start = Instant::now();
    let report = method
        .render(gpu, &frame, &aovs.targets(), &mut enc)
        .map_err(|e| format!("render failed: {e:#}"))?;
    let cpu_ms = cpu_start.elapsed().as_secs_f64() * 1e3;
    if let Some(t) = timer {
        t.end(&mut enc);
    }
    gpu.stats_resolve(&mut enc);
    gpu.queue.submit([enc.finish()]);
    gpu.wait()?;
    let wall_ms = start.elapsed().as_secs_f64() * 1e3;
    let gpu_ms = match timer {
        Some(t) => Some(t.read_ms(gpu)?),
        None => None,
    };
    let mut report = report;
    if let Some(phases) = method.phase_timer() {
        for (name, ms) in phases.read_ms(gpu)? {
            report.count(&format!("gpu_ms_{name}"), ms);
        }
    }
    if let Some(work) = gpu.stats_read()? {
        for (name, n) in work.counters() {
            report.count(name, n);
        }
    }
    if gpu.is_lost() {
        return Err(gpu.take_errors().join("; "));
    }
    Ok(FrameTiming {
        cpu_ms,
        wall_ms,
        gpu_ms,
        report,
    })
}

/// Prepares, times and reads back one method × params. Returns the record (without errors
/// and images) and the three AOVs of the scored frame.
pub(super) fn measure(
    gpu: &Gpu,
    scene: &Scene,
    entry: &dyn Method,
    params: &Params,
    cfg: &RunConfig,
    scorer: &mut FrameScorer,
) -> Result<(Record, [Image; 3]), String> {
    crate::isolate::phase::enter(crate::isolate::Phase::Prepare);
    gpu.reset_allocated();
    let start = Instant::now();
    let mut method = entry
        .prepare(&PrepareContext {
            gpu,
            scene,
            params,
            width: cfg.width,
            height: cfg.height,
            no_skip: cfg.no_skip,
        })
        .map_err(|e| format!("prepare failed: {e:#}"))?;
    gpu.wait()?;
    let prepare_ms = start.elapsed().as_secs_f64() * 1e3;
    let memory = gpu.allocated_bytes();
    let errors = gpu.take_errors();
    if !errors.is_empty() {
        return Err(format!("wgpu error during prepare: {}", errors.join("; ")));
    }
    let aovs = AovTargets::new(gpu, cfg.width, cfg.height);
    let timer = GpuTimer::new(gpu);
    let (mut cpu, mut wall, mut gpu_ms) = (Vec::new(), Vec::new(), Vec::new());
    let mut last = FrameReport::default();
    let mut work: BTreeMap<&'static str, Vec<f64>> = BTreeMap::new();
    crate::isolate::phase::enter(crate::isolate::Phase::Render);
    // Frames cycle through the scene's frames: warm-up first, then the timed ones.
    let (mut f, mut warm_ms, mut timed_ms) = (0u32, 0.0, 0.0);
    while f < cfg.warmup && another_frame(cfg.budget_ms, true, f, warm_ms) {
        warm_ms += render_frame(gpu, method.as_mut(), scene, f, &aovs, timer.as_ref())?.wall_ms;
        f += 1;
    }
    let warmed = f;
    while f - warmed < cfg.frames && another_frame(cfg.budget_ms, false, f - warmed, timed_ms) {
        let t = render_frame(gpu, method.as_mut(), scene, f, &aovs, timer.as_ref())?;
        timed_ms += t.wall_ms;
        cpu.push(t.cpu_ms);
        wall.push(t.wall_ms);
        if let Some(g) = t.gpu_ms {
            gpu_ms.push(g);
        }
        for name in WORK_COUNTERS {
            if let Some(n) = t.report.counters.get(name) {
                work.entry(name).or_default().push(*n);
            }
        }
        last = t.report;
        // Read back and score outside the timed region (the next frame's clock starts after
        // its own clear and wait).
        scorer.timed_frame(f, &aovs.read(gpu)?)?;
        f += 1;
    }
    // Work counts are per frame, median over the timed frames (an animated scene's frames differ).
    for (name, values) in &work {
        last.counters
            .insert(name.to_string(), Stat::of(values).median);
    }
    if cfg.budget_ms.is_some() {
        last.count("warmup_frames", warmed as f64);
        last.count("timed_frames", (f - warmed) as f64);
    }
    // An accumulating method converges over `converge` frames: on a static scene the scored
    // frame is the converge-th rendered since prepare, or later.
    let converge = entry.converge_frames(params);
    if converge > 0 {
        last.count("converge_frames", converge as f64);
        if scene.frame_count() == 1 {
            while f < converge {
                render_frame(gpu, method.as_mut(), scene, f, &aovs, None)?;
                f += 1;
            }
        }
    }
    // The scored frame: frame 0 once more — unless the last timed frame was frame 0 (always,
    // in a static scene): its output is still in the AOVs, the same inputs rendered by the same
    // method, so rendering it again would only cost a frame.
    let reuse = f > warmed && (f - 1) % scene.frame_count().max(1) == 0;
    let scored = if reuse {
        None
    } else {
        Some(render_frame(gpu, method.as_mut(), scene, 0, &aovs, None)?.report)
    };
    let images = aovs.read(gpu)?;
    let report = if cfg.frames > 0 {
        last
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
            wall_ms: Stat::of(&wall),
            gpu_ms: (!gpu_ms.is_empty()).then(|| Stat::of(&gpu_ms)),
            cpu_ms: Stat::of(&cpu),
            score_ms: 0.0,
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
        // 9 s/frame: one warm-up frame, the minimum of timed frames.
        assert_eq!(frames(Some(8000.0), 3, 10, 9000.0), (1, MIN_TIMED_FRAMES));
        // A budget never asks for more than requested.
        assert_eq!(frames(Some(8000.0), 0, 2, 9000.0), (0, 2));
    }
}
