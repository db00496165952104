//! The device: one headless wgpu device with its queue on the adapter a [`DeviceChoice`] names,
//! the adapter summary, the wgpu errors it raised, and the bytes a method allocated through it.

use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Mutex};

use super::adapters::{self, AdapterSummary, DeviceChoice, VALIDATION_HELP};
use super::mapping;
use super::stats::{Counted, FrameWork, PassCounter};
use super::validation;

/// A single-layer, single-mip 2-D texture's descriptor.
pub fn texture_2d<'a>(
    label: &'a str,
    width: u32,
    height: u32,
    format: wgpu::TextureFormat,
    usage: wgpu::TextureUsages,
) -> wgpu::TextureDescriptor<'a> {
    wgpu::TextureDescriptor {
        label: Some(label),
        size: wgpu::Extent3d {
            width,
            height,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage,
        view_formats: &[],
    }
}

pub struct Gpu {
    /// What chose this device: [`Gpu::reopen`] chooses the same after a device loss.
    pub choice: DeviceChoice,
    pub adapter: wgpu::Adapter,
    pub device: wgpu::Device,
    pub queue: wgpu::Queue,
    pub summary: AdapterSummary,
    errors: Arc<Mutex<Vec<String>>>,
    lost: Arc<Mutex<Option<String>>>,
    allocated: AtomicU64,
    /// Pipeline-statistics queries of the current frame (counts nothing without the feature).
    counter: PassCounter,
}

impl Gpu {
    /// Creates the device on the adapter `WGPU_ADAPTER_NAME` names (or the best one), with the
    /// validation layer when `WGPU_VALIDATION=1` ([`DeviceChoice::from_env`]). Errors (never
    /// panics) when no adapter matches.
    pub fn new() -> Result<Gpu, String> {
        Gpu::open(&DeviceChoice::from_env())
    }

    /// Creates the device a choice names ([`adapters`]). With validation, the validation
    /// layer must be installed: a run never goes on silently unvalidated.
    pub fn open(choice: &DeviceChoice) -> Result<Gpu, String> {
        if choice.validate {
            validation::install()?;
        }
        let instance = adapters::instance(choice.validate);
        let ranked = adapters::ranked(&instance);
        if choice.validate && validation::layer_missing() {
            return Err(VALIDATION_HELP.to_string());
        }
        let adapter = adapters::choose(ranked, choice.adapter.as_deref())?;
        let info = adapter.get_info();
        let optional = wgpu::Features::TIMESTAMP_QUERY
            | wgpu::Features::TIMESTAMP_QUERY_INSIDE_ENCODERS
            | wgpu::Features::FLOAT32_BLENDABLE
            | wgpu::Features::DEPTH32FLOAT_STENCIL8
            | wgpu::Features::PIPELINE_STATISTICS_QUERY
            // Shadow planes between the eye and the near plane are rasterised (depth clamped)
            // instead of clipped, so z-pass counts from the eye stay exact (Everitt & Kilgard).
            | wgpu::Features::DEPTH_CLIP_CONTROL
            // Per-pixel crossing lists count and store only the plane fragments in front of the
            // visible surface (methods' common::shadow_volumes::crossing_lists::passes_wgsl).
            | wgpu::Features::SHADER_EARLY_DEPTH_TEST;
        let features = adapter.features() & optional;
        let supported = adapter.limits();
        let limits = wgpu::Limits {
            // Per-pixel lists at 1024² (a crossing pool holds 4 bytes per shadow-plane crossing:
            // 370 MB on fence-spot) outgrow wgpu's portable defaults (256 MiB buffers, 128 MiB
            // storage bindings): take what the adapter offers.
            max_buffer_size: supported.max_buffer_size,
            max_storage_buffer_binding_size: supported.max_storage_buffer_binding_size,
            // The shadow atlas of dozens of lights (methods' common::shadow_maps) can outgrow
            // the portable 256 layers; the methods check this limit and name it when exceeded.
            max_texture_array_layers: supported.max_texture_array_layers,
            ..wgpu::Limits::default().using_resolution(supported)
        };
        let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
            label: Some("scatterbench"),
            required_features: features,
            required_limits: limits,
            ..Default::default()
        }))
        .map_err(|e| format!("cannot open a device on '{}': {e}", info.name))?;
        let errors: Arc<Mutex<Vec<String>>> = Arc::default();
        let sink = errors.clone();
        device.on_uncaptured_error(Arc::new(move |e: wgpu::Error| {
            if let Ok(mut v) = sink.lock() {
                v.push(e.to_string());
            }
        }));
        let lost: Arc<Mutex<Option<String>>> = Arc::default();
        let lost_sink = lost.clone();
        device.set_device_lost_callback(move |reason, msg| {
            if let Ok(mut l) = lost_sink.lock() {
                *l = Some(format!("device lost ({reason:?}): {msg}"));
            }
        });
        let summary = AdapterSummary::of(&info);
        let counter = PassCounter::new(&device);
        Ok(Gpu {
            choice: choice.clone(),
            adapter,
            device,
            queue,
            summary,
            errors,
            lost,
            allocated: AtomicU64::new(0),
            counter,
        })
    }

    /// A fresh device on the same adapter, with the same validation (after a device loss).
    pub fn reopen(&self) -> Result<Gpu, String> {
        Gpu::open(&self.choice)
    }

    /// The validation layer's messages since the last call (none without validation).
    pub fn take_validation(&self) -> Vec<validation::Message> {
        if self.choice.validate {
            validation::take()
        } else {
            Vec::new()
        }
    }

    pub fn features(&self) -> wgpu::Features {
        self.device.features()
    }

    /// Errors the device raised since the last call (validation, out of memory, internal),
    /// and device loss.
    pub fn take_errors(&self) -> Vec<String> {
        let mut out: Vec<String> = self
            .errors
            .lock()
            .map(|mut v| std::mem::take(&mut *v))
            .unwrap_or_default();
        if let Ok(l) = self.lost.lock()
            && let Some(m) = l.as_ref()
        {
            out.push(m.clone());
        }
        out
    }

    pub fn is_lost(&self) -> bool {
        self.lost.lock().map(|l| l.is_some()).unwrap_or(true)
    }

    /// Blocks until all submitted work is done.
    pub fn wait(&self) -> Result<(), String> {
        mapping::wait(&self.device)
    }

    /// Creates a buffer and counts its bytes toward the current method's memory.
    pub fn buffer(&self, desc: &wgpu::BufferDescriptor) -> wgpu::Buffer {
        self.allocated.fetch_add(desc.size, Ordering::Relaxed);
        self.device.create_buffer(desc)
    }

    /// Creates a buffer with contents, counted like [`Gpu::buffer`].
    pub fn buffer_init(
        &self,
        label: &str,
        contents: &[u8],
        usage: wgpu::BufferUsages,
    ) -> wgpu::Buffer {
        use wgpu::util::DeviceExt;
        self.allocated
            .fetch_add(contents.len() as u64, Ordering::Relaxed);
        self.device
            .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some(label),
                contents,
                usage,
            })
    }

    /// Creates a texture and counts its bytes (all mips and layers) toward the method's memory.
    pub fn texture(&self, desc: &wgpu::TextureDescriptor) -> wgpu::Texture {
        let block = desc
            .format
            .block_copy_size(Some(wgpu::TextureAspect::All))
            .or_else(|| {
                desc.format
                    .block_copy_size(Some(wgpu::TextureAspect::DepthOnly))
                    .map(|d| d + 1)
            })
            .unwrap_or(4) as u64;
        let mut bytes = 0u64;
        for mip in 0..desc.mip_level_count {
            let s = desc.size.mip_level_size(mip, desc.dimension);
            bytes += s.width as u64 * s.height as u64 * s.depth_or_array_layers as u64 * block;
        }
        self.allocated
            .fetch_add(bytes * desc.sample_count as u64, Ordering::Relaxed);
        self.device.create_texture(desc)
    }

    /// A single-layer, single-mip 2-D texture, counted like [`Gpu::texture`].
    pub fn texture_2d(
        &self,
        label: &str,
        width: u32,
        height: u32,
        format: wgpu::TextureFormat,
        usage: wgpu::TextureUsages,
    ) -> wgpu::Texture {
        self.texture(&texture_2d(label, width, height, format, usage))
    }

    /// Bytes allocated through [`Gpu::buffer`] and [`Gpu::texture`] since the last reset.
    pub fn allocated_bytes(&self) -> u64 {
        self.allocated.load(Ordering::Relaxed)
    }

    pub fn reset_allocated(&self) {
        self.allocated.store(0, Ordering::Relaxed);
    }

    /// Begins a render pass whose work is counted in the frame's pipeline statistics. Every
    /// pass a method encodes in `render` goes through this, [`Gpu::compute_pass`] or a
    /// [`PassCounter`] from [`Gpu::pass_counter`].
    pub fn render_pass<'e>(
        &self,
        enc: &'e mut wgpu::CommandEncoder,
        desc: &wgpu::RenderPassDescriptor<'_>,
    ) -> Counted<wgpu::RenderPass<'e>> {
        self.counter.render_pass(enc, desc)
    }

    /// Begins a compute pass whose work is counted, like [`Gpu::render_pass`].
    pub fn compute_pass<'e>(
        &self,
        enc: &'e mut wgpu::CommandEncoder,
        desc: &wgpu::ComputePassDescriptor<'_>,
    ) -> Counted<wgpu::ComputePass<'e>> {
        self.counter.compute_pass(enc, desc)
    }

    /// A handle that begins counted passes without the [`Gpu`] (see [`PassCounter`]).
    pub fn pass_counter(&self) -> PassCounter {
        self.counter.clone()
    }

    /// True when the device counts pipeline statistics.
    pub fn counts_work(&self) -> bool {
        self.counter.counts_work()
    }

    /// Starts counting a new frame (forgets the passes begun since the last call).
    pub fn stats_begin_frame(&self) {
        self.counter.begin_frame()
    }

    /// Resolves the frame's queries into `enc`, after the frame's last pass.
    pub fn stats_resolve(&self, enc: &mut wgpu::CommandEncoder) {
        self.counter.resolve(enc)
    }

    /// The resolved frame's work, once it has completed on the GPU; None where the device does
    /// not count or no frame was resolved.
    pub fn stats_read(&self) -> Result<Option<FrameWork>, String> {
        self.counter.read(&self.device)
    }
}
