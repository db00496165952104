//! One frame of a record: the AOV targets the harness renders into, and one timed frame
//! (clear, encode, submit, wait; CPU, wall and GPU time, the phase timers and work counts;
//! ARCHITECTURE §4.1).

use std::time::Instant;

use scenes::Scene;

use crate::gpu::{Gpu, GpuTimer, color_attachment, read_rgba32f, texture_2d};
use crate::image::Image;
use crate::method::{AOV_FORMAT, FrameReport, Prepared, Targets};

/// The AOV textures the harness renders into.
pub struct AovTargets {
    pub textures: [wgpu::Texture; 3],
    pub views: [wgpu::TextureView; 3],
    pub width: u32,
    pub height: u32,
}

impl AovTargets {
    pub fn new(gpu: &Gpu, width: u32, height: u32) -> AovTargets {
        // The harness's own targets: created on the device, not counted as the method's memory.
        let usage = wgpu::TextureUsages::RENDER_ATTACHMENT
            | wgpu::TextureUsages::STORAGE_BINDING
            | wgpu::TextureUsages::TEXTURE_BINDING
            | wgpu::TextureUsages::COPY_SRC;
        let make = |label: &str| {
            gpu.device
                .create_texture(&texture_2d(label, width, height, AOV_FORMAT, usage))
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
