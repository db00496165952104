//! Adapter calibration (ARCHITECTURE §7.1): a micro-benchmark of well under a second, run at the
//! start of every run, that says how the adapter splits its throughput between raster and
//! compute work and how fast it moves memory. A results file then tells its reader what the
//! frame times cannot: on an NVIDIA H100/H200 only 2 TPCs (4 of 132 SMs) run vertex and pixel
//! shaders, so a raster-bound method is there ~30× slower against a compute one than on a
//! graphics GPU.
//!
//! Three passes (`calibrate.wgsl`):
//! - **raster**: full-screen triangles into a [`SIZE`]² `rgba32float` target, every fragment
//!   running `work`;
//! - **compute**: dispatches of [`SIZE`]² invocations of the same `work`, each writing one
//!   texel of a storage texture of the same format;
//! - **memory**: a compute copy of [`COPY_BYTES`] between two storage buffers, counted as read
//!   plus written. A compute copy, not `copy_buffer_to_buffer`: lavapipe's timestamps do not
//!   bracket a transfer (measured: 73–400 GB/s on GPU time for a copy that takes 7–9 ms of
//!   wall clock, 8 GB/s, on the 2-core machine).
//!
//! Each pass is repeated within one submission, ×4 at a time from 1, until it takes
//! [`MIN_PASS_MS`] (a fast GPU finishes one in microseconds, where launch overhead would
//! decide), then timed [`REPEATS`] times; the median is kept. GPU timestamps where the adapter
//! has them inside encoders, else the wall clock from submit to idle (`basis`).

use serde::{Deserialize, Serialize};

use super::device::{Gpu, texture_2d};
use super::timer::GpuTimer;

/// The side of the raster and compute targets, px.
pub const SIZE: u32 = 512;
/// Bytes one memory pass copies.
pub const COPY_BYTES: u64 = 32 << 20;
/// A pass is repeated within its submission until it takes at least this long, ms …
pub const MIN_PASS_MS: f64 = 4.0;
/// … or this many times.
pub const MAX_REPEAT: u32 = 1024;
/// Timed submissions of each pass, once its repeat count is set.
pub const REPEATS: usize = 3;

const FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Float;
const COPY_GROUP: u64 = 64;

/// What the calibration measured, in `run.machine.calibration` (ARCHITECTURE §5.1).
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct Calibration {
    /// Fragments shaded per second by a full-screen pass.
    pub raster_fragments_per_s: f64,
    /// Compute invocations per second, each doing one fragment's work.
    pub compute_invocations_per_s: f64,
    /// Bytes per second of a storage-buffer copy (read plus written).
    pub memory_bytes_per_s: f64,
    /// "gpu" (timestamp queries) or "wall".
    pub basis: String,
    /// Wall time the calibration took, ms.
    pub ms: f64,
}

impl Calibration {
    /// Raster over compute throughput for the same work: near 1 or above on a graphics GPU,
    /// far below where few units run pixel shaders.
    pub fn raster_to_compute(&self) -> f64 {
        self.raster_fragments_per_s / self.compute_invocations_per_s
    }
}

/// Runs the calibration on `gpu`. Err: a wgpu error, or a pass that timed at zero.
pub fn calibrate(gpu: &Gpu) -> Result<Calibration, String> {
    let start = std::time::Instant::now();
    let _ = gpu.take_errors();
    let timer = GpuTimer::new(gpu);
    let passes = Passes::new(gpu);
    let pixels = f64::from(SIZE * SIZE);
    let rate = |encode: &dyn Fn(&mut wgpu::CommandEncoder, u32), per_repeat: f64| {
        let (repeat, ms) = timed(gpu, timer.as_ref(), encode)?;
        Ok::<f64, String>(per_repeat * f64::from(repeat) / (ms * 1e-3))
    };
    let raster = rate(&|enc, n| passes.raster(enc, n), pixels)?;
    let compute = rate(&|enc, n| passes.compute(enc, n), pixels)?;
    let memory = rate(&|enc, n| passes.copy(enc, n), 2.0 * COPY_BYTES as f64)?;
    let errors = gpu.take_errors();
    if !errors.is_empty() {
        return Err(format!("calibration: wgpu error: {}", errors.join("; ")));
    }
    Ok(Calibration {
        raster_fragments_per_s: raster,
        compute_invocations_per_s: compute,
        memory_bytes_per_s: memory,
        basis: if timer.is_some() { "gpu" } else { "wall" }.into(),
        ms: start.elapsed().as_secs_f64() * 1e3,
    })
}

/// (repeat count, median ms): `encode(enc, repeat)` with the repeat count grown until one
/// submission takes [`MIN_PASS_MS`], then timed [`REPEATS`] times.
fn timed(
    gpu: &Gpu,
    timer: Option<&GpuTimer>,
    encode: &dyn Fn(&mut wgpu::CommandEncoder, u32),
) -> Result<(u32, f64), String> {
    // The first submission warms the pipeline and the targets; its time is not used.
    submit_ms(gpu, timer, &|enc| encode(enc, 1))?;
    let mut repeat = 1;
    while repeat < MAX_REPEAT && submit_ms(gpu, timer, &|enc| encode(enc, repeat))? < MIN_PASS_MS {
        repeat *= 4;
    }
    let mut times = (0..REPEATS)
        .map(|_| submit_ms(gpu, timer, &|enc| encode(enc, repeat)))
        .collect::<Result<Vec<f64>, String>>()?;
    times.sort_by(f64::total_cmp);
    match times[times.len() / 2] {
        ms if ms > 0.0 => Ok((repeat, ms)),
        _ => Err("calibration: a pass timed at 0 ms".into()),
    }
}

/// One submission of `encode`, ms (GPU timestamps, else wall clock to idle).
fn submit_ms(
    gpu: &Gpu,
    timer: Option<&GpuTimer>,
    encode: &dyn Fn(&mut wgpu::CommandEncoder),
) -> Result<f64, String> {
    let mut enc = gpu.device.create_command_encoder(&Default::default());
    if let Some(t) = timer {
        t.begin(&mut enc);
    }
    encode(&mut enc);
    if let Some(t) = timer {
        t.end(&mut enc);
    }
    let wall = std::time::Instant::now();
    gpu.queue.submit([enc.finish()]);
    gpu.wait()?;
    match timer {
        Some(t) => t.read_ms(gpu),
        None => Ok(wall.elapsed().as_secs_f64() * 1e3),
    }
}

/// The three passes' pipelines and targets.
struct Passes {
    raster: wgpu::RenderPipeline,
    compute: wgpu::ComputePipeline,
    storage: wgpu::BindGroup,
    color: wgpu::Texture,
    /// Bound through `storage`; kept for the test, which reads it back.
    #[cfg_attr(not(test), allow(dead_code))]
    storage_texture: wgpu::Texture,
    copy: wgpu::ComputePipeline,
    buffers: wgpu::BindGroup,
}

impl Passes {
    fn new(gpu: &Gpu) -> Passes {
        let d = &gpu.device;
        let module = d.create_shader_module(wgpu::include_wgsl!("calibrate.wgsl"));
        let raster = d.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("calibration raster"),
            layout: None,
            vertex: wgpu::VertexState {
                module: &module,
                entry_point: Some("full_screen"),
                compilation_options: Default::default(),
                buffers: &[],
            },
            primitive: Default::default(),
            depth_stencil: None,
            multisample: Default::default(),
            fragment: Some(wgpu::FragmentState {
                module: &module,
                entry_point: Some("shade_fragment"),
                compilation_options: Default::default(),
                targets: &[Some(FORMAT.into())],
            }),
            multiview_mask: None,
            cache: None,
        });
        let compute_pipeline = |entry| {
            d.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some(entry),
                layout: None,
                module: &module,
                entry_point: Some(entry),
                compilation_options: Default::default(),
                cache: None,
            })
        };
        let (compute, copy) = (
            compute_pipeline("shade_invocation"),
            compute_pipeline("copy_elements"),
        );
        // COPY_SRC: the test reads both targets back.
        let target = |label, usage| {
            d.create_texture(&texture_2d(
                label,
                SIZE,
                SIZE,
                FORMAT,
                usage | wgpu::TextureUsages::COPY_SRC,
            ))
        };
        let color = target("calibration color", wgpu::TextureUsages::RENDER_ATTACHMENT);
        let storage_texture = target("calibration storage", wgpu::TextureUsages::STORAGE_BINDING);
        let storage_view = storage_texture.create_view(&Default::default());
        let storage = bind(gpu, &compute, &[wgpu::BindingResource::TextureView(&storage_view)]);
        let buffer = |label| {
            d.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: COPY_BYTES,
                usage: wgpu::BufferUsages::STORAGE,
                mapped_at_creation: false,
            })
        };
        let (from, to) = (buffer("calibration copy from"), buffer("calibration copy to"));
        let buffers = bind(
            gpu,
            &copy,
            &[from.as_entire_binding(), to.as_entire_binding()],
        );
        Passes {
            raster,
            compute,
            storage,
            color,
            storage_texture,
            copy,
            buffers,
        }
    }

    fn raster(&self, enc: &mut wgpu::CommandEncoder, repeat: u32) {
        let view = self.color.create_view(&Default::default());
        let mut pass = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("calibration raster"),
            color_attachments: &[super::color_attachment(
                &view,
                wgpu::LoadOp::Clear(wgpu::Color::BLACK),
            )],
            ..Default::default()
        });
        pass.set_pipeline(&self.raster);
        for _ in 0..repeat {
            pass.draw(0..3, 0..1);
        }
    }

    fn compute(&self, enc: &mut wgpu::CommandEncoder, repeat: u32) {
        let mut pass = enc.begin_compute_pass(&Default::default());
        pass.set_pipeline(&self.compute);
        pass.set_bind_group(0, &self.storage, &[]);
        for _ in 0..repeat {
            pass.dispatch_workgroups(SIZE / 8, SIZE / 8, 1);
        }
    }

    fn copy(&self, enc: &mut wgpu::CommandEncoder, repeat: u32) {
        let mut pass = enc.begin_compute_pass(&Default::default());
        pass.set_pipeline(&self.copy);
        pass.set_bind_group(0, &self.buffers, &[]);
        let groups = (COPY_BYTES / 16).div_ceil(COPY_GROUP) as u32;
        for _ in 0..repeat {
            pass.dispatch_workgroups(groups, 1, 1);
        }
    }
}

/// A bind group of `resources` at bindings 0, 1, … of `pipeline`'s group 0.
fn bind(
    gpu: &Gpu,
    pipeline: &wgpu::ComputePipeline,
    resources: &[wgpu::BindingResource],
) -> wgpu::BindGroup {
    let entries: Vec<wgpu::BindGroupEntry> = resources
        .iter()
        .enumerate()
        .map(|(i, r)| wgpu::BindGroupEntry {
            binding: i as u32,
            resource: r.clone(),
        })
        .collect();
    gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("calibration"),
        layout: &pipeline.get_bind_group_layout(0),
        entries: &entries,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `work` of calibrate.wgsl on the CPU, in f32 (fma as the shader's).
    fn work(x: u32, y: u32) -> [f32; 4] {
        let mut v = [x as f32 * 1e-3, y as f32 * 1e-3, 0.25, 0.5];
        for _ in 0..16 {
            v = v.map(|c| c.mul_add(0.999, 1e-4));
        }
        v
    }

    /// The figures are finite and positive on the basis the adapter allows, and the two
    /// shading passes did the same work: every texel of the raster target and of the compute
    /// target equals `work` computed here (to f32 rounding), so their rates compare like for like.
    #[test]
    fn raster_and_compute_shade_the_same_work_and_the_figures_are_positive() {
        let Some(gpu) = crate::testing::gpu_or_skip() else {
            return;
        };
        let c = calibrate(&gpu).unwrap();
        for x in [
            c.raster_fragments_per_s,
            c.compute_invocations_per_s,
            c.memory_bytes_per_s,
            c.ms,
        ] {
            assert!(x.is_finite() && x > 0.0, "{c:?}");
        }
        assert_eq!(c.basis == "gpu", GpuTimer::new(&gpu).is_some());
        let passes = Passes::new(&gpu);
        submit_ms(&gpu, None, &|enc| {
            passes.raster(enc, 1);
            passes.compute(enc, 1);
        })
        .unwrap();
        let raster = super::super::read_rgba32f(&gpu, &passes.color).unwrap();
        let compute = super::super::read_rgba32f(&gpu, &passes.storage_texture).unwrap();
        for (name, image) in [("raster", &raster), ("compute", &compute)] {
            for (i, p) in image.pixels.iter().enumerate() {
                let (x, y) = (i as u32 % SIZE, i as u32 / SIZE);
                let want = work(x, y);
                // The image keeps rgb; alpha is the constant channel.
                for (got, want) in p.iter().zip(want) {
                    let close = (got - want).abs() <= 1e-5 * want.abs().max(1e-3);
                    assert!(close, "{name} ({x}, {y}): {p:?} vs {want:?}");
                }
            }
        }
    }
}
