//! Work counts per frame from pipeline statistics queries (ARCHITECTURE §4.1): how
//! many vertex, fragment and compute shader invocations and clipped primitives a method's frame
//! took, so a reader can tell *why* a method is fast on this adapter and whether the ranking will
//! transfer to another one.
//!
//! Every pass a method begins goes through [`Gpu::render_pass`] / [`Gpu::compute_pass`], which
//! wrap the pass in one pipeline-statistics query; the runner opens a frame
//! ([`Gpu::stats_begin_frame`]), resolves the queries into the frame's encoder
//! ([`Gpu::stats_resolve`]) and reads the sums once the frame has completed
//! ([`Gpu::stats_read`]); those delegate to the device's [`PassCounter`]. Where the device
//! lacks `PIPELINE_STATISTICS_QUERY` the guards are plain passes and nothing is counted.
//!
//! [`Gpu::render_pass`]: crate::Gpu::render_pass
//! [`Gpu::compute_pass`]: crate::Gpu::compute_pass
//! [`Gpu::stats_begin_frame`]: crate::Gpu::stats_begin_frame
//! [`Gpu::stats_resolve`]: crate::Gpu::stats_resolve
//! [`Gpu::stats_read`]: crate::Gpu::stats_read
//!
//! Caveats (documented with the counters): fragment invocations include helper lanes of 2×2
//! quads; lavapipe (llvmpipe) runs fragment shaders on 4×4 blocks and reports invocations per
//! block lane, so its fragment counts are an upper bound on covered pixels; a count is a
//! property of the driver as much as of the method — compare methods within one run.

use std::ops::{Deref, DerefMut};
use std::sync::atomic::{AtomicU32, Ordering};
use std::sync::{Arc, Mutex};

use super::mapping;

/// Passes one frame may count; further passes run uncounted and are reported in
/// [`FrameWork::uncounted_passes`].
const CAPACITY: u32 = 1024;

/// The statistics each query records, in the order the device writes them (bit order).
const TYPES: wgpu::PipelineStatisticsTypes =
    wgpu::PipelineStatisticsTypes::VERTEX_SHADER_INVOCATIONS
        .union(wgpu::PipelineStatisticsTypes::CLIPPER_PRIMITIVES_OUT)
        .union(wgpu::PipelineStatisticsTypes::FRAGMENT_SHADER_INVOCATIONS)
        .union(wgpu::PipelineStatisticsTypes::COMPUTE_SHADER_INVOCATIONS);
const VALUES: u64 = 4;

/// The work of one frame, summed over its counted passes.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct FrameWork {
    pub vertex_invocations: u64,
    pub clipper_primitives: u64,
    pub fragment_invocations: u64,
    pub compute_invocations: u64,
    /// Passes begun after the frame's query capacity was used up (not in the sums).
    pub uncounted_passes: u32,
}

/// The counters a record stores per frame (`counters.pipeline_*` in results.json), in the order
/// of [`FrameWork::counters`].
pub const WORK_COUNTERS: [&str; 4] = [
    "pipeline_vertex_invocations",
    "pipeline_clipper_primitives",
    "pipeline_fragment_invocations",
    "pipeline_compute_invocations",
];

impl FrameWork {
    /// The frame's counts by their results.json names.
    pub fn counters(&self) -> [(&'static str, f64); 4] {
        let n = [
            self.vertex_invocations,
            self.clipper_primitives,
            self.fragment_invocations,
            self.compute_invocations,
        ];
        std::array::from_fn(|i| (WORK_COUNTERS[i], n[i] as f64))
    }
}

/// The query set and buffers of the frame's pipeline statistics.
struct PipelineStats {
    set: wgpu::QuerySet,
    resolve: wgpu::Buffer,
    read: wgpu::Buffer,
    /// Queries begun since the frame was opened.
    begun: AtomicU32,
    /// Queries resolved into `read` by the last [`PassCounter::resolve`] (None: nothing to read).
    resolved: Mutex<Option<u32>>,
}

impl PipelineStats {
    fn new(device: &wgpu::Device) -> PipelineStats {
        let bytes = 8 * VALUES * CAPACITY as u64;
        let buffer = |label, usage| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: bytes,
                usage,
                mapped_at_creation: false,
            })
        };
        PipelineStats {
            set: device.create_query_set(&wgpu::QuerySetDescriptor {
                label: Some("pipeline statistics"),
                ty: wgpu::QueryType::PipelineStatistics(TYPES),
                count: CAPACITY,
            }),
            resolve: buffer(
                "pipeline statistics resolve",
                wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
            ),
            read: buffer(
                "pipeline statistics read",
                wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
            ),
            begun: AtomicU32::new(0),
            resolved: Mutex::new(None),
        }
    }

    /// The next free query index this frame, or None when the capacity is used up.
    fn next(&self) -> Option<u32> {
        let i = self.begun.fetch_add(1, Ordering::Relaxed);
        (i < CAPACITY).then_some(i)
    }
}

/// A pass whose pipeline statistics are counted; ends its query when dropped. Derefs to the
/// wrapped `wgpu::RenderPass` / `wgpu::ComputePass`.
pub struct Counted<P: StatsQuery> {
    /// Always Some until dropped (taken only by `forget_lifetime`).
    pass: Option<P>,
    counting: bool,
}

/// The two kinds of pass a pipeline-statistics query can wrap.
pub trait StatsQuery {
    fn begin_query(&mut self, set: &wgpu::QuerySet, index: u32);
    fn end_query(&mut self);
}

impl StatsQuery for wgpu::RenderPass<'_> {
    fn begin_query(&mut self, set: &wgpu::QuerySet, index: u32) {
        self.begin_pipeline_statistics_query(set, index);
    }
    fn end_query(&mut self) {
        self.end_pipeline_statistics_query();
    }
}

impl StatsQuery for wgpu::ComputePass<'_> {
    fn begin_query(&mut self, set: &wgpu::QuerySet, index: u32) {
        self.begin_pipeline_statistics_query(set, index);
    }
    fn end_query(&mut self) {
        self.end_pipeline_statistics_query();
    }
}

impl PassCounter {
    /// Counts on `device` when it has `PIPELINE_STATISTICS_QUERY`; otherwise counts nothing.
    pub(super) fn new(device: &wgpu::Device) -> PassCounter {
        let on = device
            .features()
            .contains(wgpu::Features::PIPELINE_STATISTICS_QUERY);
        PassCounter(on.then(|| Arc::new(PipelineStats::new(device))))
    }
}

impl<P: StatsQuery> Counted<P> {
    fn new(mut pass: P, stats: Option<&PipelineStats>) -> Counted<P> {
        let index = stats.and_then(|s| s.next().map(|i| (s, i)));
        if let Some((s, i)) = index {
            pass.begin_query(&s.set, i);
        }
        Counted {
            pass: Some(pass),
            counting: index.is_some(),
        }
    }
}

impl<P: StatsQuery> Drop for Counted<P> {
    fn drop(&mut self) {
        if let (true, Some(pass)) = (self.counting, self.pass.as_mut()) {
            pass.end_query();
        }
    }
}

impl Counted<wgpu::RenderPass<'_>> {
    /// Like `wgpu::RenderPass::forget_lifetime`: the counted pass no longer borrows its encoder.
    pub fn forget_lifetime(mut self) -> Counted<wgpu::RenderPass<'static>> {
        let pass = self.pass.take().expect("a pass until dropped");
        Counted {
            pass: Some(pass.forget_lifetime()),
            counting: std::mem::take(&mut self.counting),
        }
    }
}

impl<P: StatsQuery> Deref for Counted<P> {
    type Target = P;
    fn deref(&self) -> &P {
        self.pass.as_ref().expect("a pass until dropped")
    }
}

impl<P: StatsQuery> DerefMut for Counted<P> {
    fn deref_mut(&mut self) -> &mut P {
        self.pass.as_mut().expect("a pass until dropped")
    }
}

/// Begins counted passes: a cheap handle on the device's pipeline-statistics queries that a
/// long-lived pass object (a shadow-map or surface renderer) can keep from `prepare`, so it need
/// not be handed the `Gpu` in every `encode`. [`Gpu::render_pass`] uses the same handle, and
/// the frame's statistics are opened, resolved and read through it.
#[derive(Clone, Default)]
pub struct PassCounter(Option<Arc<PipelineStats>>);

impl PassCounter {
    /// Begins a render pass whose work is counted in the frame's pipeline statistics.
    pub fn render_pass<'e>(
        &self,
        enc: &'e mut wgpu::CommandEncoder,
        desc: &wgpu::RenderPassDescriptor<'_>,
    ) -> Counted<wgpu::RenderPass<'e>> {
        Counted::new(enc.begin_render_pass(desc), self.0.as_deref())
    }

    /// Begins a compute pass whose work is counted, like [`PassCounter::render_pass`].
    pub fn compute_pass<'e>(
        &self,
        enc: &'e mut wgpu::CommandEncoder,
        desc: &wgpu::ComputePassDescriptor<'_>,
    ) -> Counted<wgpu::ComputePass<'e>> {
        Counted::new(enc.begin_compute_pass(desc), self.0.as_deref())
    }
}

impl PassCounter {
    /// True when the device counts pipeline statistics.
    pub fn counts_work(&self) -> bool {
        self.0.is_some()
    }

    /// Starts counting a new frame (forgets the passes begun since the last call).
    pub fn begin_frame(&self) {
        if let Some(s) = &self.0 {
            s.begun.store(0, Ordering::Relaxed);
            *s.resolved.lock().unwrap_or_else(|e| e.into_inner()) = None;
        }
    }

    /// Resolves the frame's queries into `enc`, after the frame's last pass.
    pub fn resolve(&self, enc: &mut wgpu::CommandEncoder) {
        let Some(s) = &self.0 else { return };
        let n = s.begun.load(Ordering::Relaxed).min(CAPACITY);
        *s.resolved.lock().unwrap_or_else(|e| e.into_inner()) = Some(n);
        if n == 0 {
            return;
        }
        enc.resolve_query_set(&s.set, 0..n, &s.resolve, 0);
        enc.copy_buffer_to_buffer(&s.resolve, 0, &s.read, 0, 8 * VALUES * n as u64);
    }

    /// The resolved frame's work, once it has completed on `device`; None where the device
    /// does not count or no frame was resolved.
    pub fn read(&self, device: &wgpu::Device) -> Result<Option<FrameWork>, String> {
        let Some(s) = &self.0 else {
            return Ok(None);
        };
        let Some(n) = *s.resolved.lock().unwrap_or_else(|e| e.into_inner()) else {
            return Ok(None);
        };
        let mut work = FrameWork {
            uncounted_passes: s.begun.load(Ordering::Relaxed).saturating_sub(CAPACITY),
            ..FrameWork::default()
        };
        if n == 0 {
            return Ok(Some(work));
        }
        let data = mapping::read_buffer(device, &s.read)?;
        let values: Vec<u64> = data
            .chunks_exact(8)
            .take((VALUES * n as u64) as usize)
            .map(|c| u64::from_le_bytes(c.try_into().expect("8 bytes")))
            .collect();
        for q in values.chunks_exact(VALUES as usize) {
            work.vertex_invocations += q[0];
            work.clipper_primitives += q[1];
            work.fragment_invocations += q[2];
            work.compute_invocations += q[3];
        }
        Ok(Some(work))
    }
}
