//! Per-pixel crossing lists that cannot overflow: every pixel's shadow-plane crossings (signed
//! distances along its view ray) for each light, stored back to back in one pool sized exactly
//! for the frame. Used by the per-pixel resolves of biri-shadow-volumes and biri-polynomial.
//!
//! Algorithm (`wgsl/crossing_lists.wgsl`, group 2 of the passes that use it):
//! 1. count: the method draws its shadow planes once per light with a fragment stage that calls
//!    `crossing_count_fragment` (depth-tested against the scene, no colour);
//! 2. scan: one workgroup turns the counts into per-list offsets (exclusive prefix sum) and
//!    records the total and the longest list;
//! 3. [`CrossingLists::size_pool`] submits 1–2, waits for the GPU and reads the total back (a
//!    mid-frame CPU–GPU sync, 16 bytes), then grows the pool if it is too small — so the pool
//!    always holds every crossing of this frame;
//! 4. gather: the method draws the same planes with the same pipeline state calling
//!    `crossing_append` into the harness's encoder;
//! 5. walk: `crossing_sorted` sorts one list by distance (an insertion sort where the list has
//!    at most 2 descents — nearly sorted, as planes drawn near to far leave it — else a merge
//!    sort in private memory up to 64 crossings, an insertion sort in the pool beyond;
//!    tests/crossing_sort.rs), `crossing_walk` (`wgsl/crossing_passes.wgsl`) walks it from the
//!    eye's shadow count, writing where the lit state toggles, and sums the method's
//!    `crossing_lit(px, a, b)` over the lit intervals in a second loop.
//!
//! Why a sync rather than "grow and redraw" from the last frame's size: a frame is then never
//! wrong (the first frame, a camera cut, a new caster), at the cost of one submit-and-wait per
//! frame (the scene depth and the count passes run before the rest of the frame is encoded).
//! Cost: per frame 2 × planes rasterised (count + gather), 8 bytes per pixel and light for
//! counts and offsets, 4 bytes per crossing; the sort n − 1 + inversions steps per nearly
//! sorted list of n, n·⌈log₂ n⌉ otherwise. The walk calls the method's `crossing_lit` once per
//! lit interval of the SIMD group's busiest pixel (lavapipe runs a branch for a group of pixels
//! whenever one of them takes it, hence the separate loop over the intervals).
//!
//! Counters: `max_crossings` (longest list, this frame), `crossing_pool` (crossings stored, this
//! frame), `crossing_count_ms` (the submit-and-wait: GPU work outside the harness's timestamps),
//! `crossing_overflows` (lists whose gather did not fill exactly their counted size; a
//! frame late through [`CounterReadback`]) — 0 by construction, kept as a check.

use harness::{FrameReport, Gpu};

use crate::common::counters::CounterReadback;
use crate::common::layouts::{buffer_entry, dynamic_uniform, slot_entry, storage_buffer};
use crate::common::pipeline::ComputeStage;

/// The shared WGSL: bindings, count, append, scan, sort.
pub const WGSL: &str = include_str!("crossing_lists.wgsl");
/// The count and gather fragment entries and the walk (after PRELUDE and [`WGSL`]); the
/// including module supplies `crossing_lit(px, a, b) -> vec3<f32>`. Compose it through
/// [`passes_wgsl`].
const PASSES_WGSL: &str = include_str!("crossing_passes.wgsl");
/// Where the count and gather entries take the early depth test.
const EARLY_DEPTH_MARK: &str = "/* early depth test */";

/// [`PASSES_WGSL`], with the count and gather fragment entries' depth test forced before the
/// shader where `early_depth_test` (the device has `Features::SHADER_EARLY_DEPTH_TEST`; see
/// [`early_depth_test`]). A fragment shader with side effects (the counts' atomics, the
/// gathered crossings) otherwise runs for the plane fragments behind the visible surface too,
/// and lavapipe does run it: on fence-spot at 256², 0.17 M of 0.62 M crossings, counted,
/// stored and sorted though the walk stops at the surface (−20 % GPU time, same image).
pub fn passes_wgsl(early_depth_test: bool) -> String {
    let attribute = if early_depth_test {
        "@early_depth_test(force)"
    } else {
        ""
    };
    PASSES_WGSL.replace(EARLY_DEPTH_MARK, attribute)
}

/// Whether `device` forces fragment tests early (for [`passes_wgsl`]).
pub fn early_depth_test(device: &wgpu::Device) -> bool {
    device
        .features()
        .contains(wgpu::Features::SHADER_EARLY_DEPTH_TEST)
}
/// The bind group index the WGSL uses.
pub const GROUP: u32 = 2;
/// Uniform slot stride (wgpu's guaranteed minimum dynamic-offset alignment).
const SLOT: u64 = 256;
const UNIFORM_SIZE: u64 = std::mem::size_of::<CrossingUniform>() as u64;

/// `CrossingCfg` in crossing_lists.wgsl, field for field.
#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct CrossingUniform {
    list: u32,
    width: u32,
    height: u32,
    lists: u32,
    /// The eye's shadow count for this light (this frame).
    eye_count: u32,
    _pad: [u32; 3],
}

pub struct CrossingLists {
    /// Group 2's layout, for the pipelines of the count, gather and walk passes.
    pub layout: wgpu::BindGroupLayout,
    uniform: wgpu::Buffer,
    counts: wgpu::Buffer,
    offsets: wgpu::Buffer,
    pool: wgpu::Buffer,
    stats: wgpu::Buffer,
    summary: wgpu::Buffer,
    scan: wgpu::ComputePipeline,
    bind: wgpu::BindGroup,
    readback: CounterReadback,
    lists: u32,
    /// Pool capacity in crossings.
    capacity: u64,
}

fn storage(gpu: &Gpu, label: &str, bytes: u64) -> wgpu::Buffer {
    gpu.buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size: bytes.max(16),
        usage: wgpu::BufferUsages::STORAGE
            | wgpu::BufferUsages::COPY_DST
            | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    })
}

/// Crossings the pool makes room for when `total` do not fit: a quarter of headroom, so a
/// slowly growing count does not reallocate every frame, within `largest` bytes (the device's
/// largest storage binding); an error naming both sizes when even `total` does not fit.
fn pool_capacity(total: u64, largest: u64) -> Result<u64, String> {
    let fits = largest / 4;
    if total > fits {
        return Err(format!(
            "the crossing pool needs {} MB ({total} shadow-plane crossings × 4 bytes), above this \
             device's largest storage buffer binding ({} MB): lower the resolution",
            (4 * total).div_ceil(1 << 20),
            largest >> 20
        ));
    }
    Ok((total + total / 4).min(fits))
}

impl CrossingLists {
    /// Lists for `lists` lights of a `width` × `height` target; `visibility`: the stages of the
    /// method's passes that bind group 2 (the scan adds COMPUTE).
    pub fn new(
        gpu: &Gpu,
        width: u32,
        height: u32,
        lists: u32,
        visibility: wgpu::ShaderStages,
    ) -> CrossingLists {
        let vis = visibility | wgpu::ShaderStages::COMPUTE;
        let layout = gpu
            .device
            .create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some("crossing lists"),
                entries: &[
                    dynamic_uniform(0, vis, UNIFORM_SIZE),
                    storage_buffer(1, vis, false),
                    storage_buffer(2, vis, false),
                    storage_buffer(3, vis, false),
                    storage_buffer(4, vis, false),
                ],
            });
        let lists = lists.max(1);
        let slots: Vec<u8> = (0..lists)
            .flat_map(|k| {
                let u = CrossingUniform {
                    list: k,
                    width,
                    height,
                    lists,
                    eye_count: 0,
                    _pad: [0; 3],
                };
                let mut v = vec![0u8; SLOT as usize];
                v[..UNIFORM_SIZE as usize].copy_from_slice(bytemuck::bytes_of(&u));
                v
            })
            .collect();
        let uniform = gpu.buffer_init(
            "crossing lists",
            &slots,
            wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        );
        let n = lists as u64 * width as u64 * height as u64;
        let counts = storage(gpu, "crossing counts", 4 * n);
        let offsets = storage(gpu, "crossing offsets", 4 * (n + 1));
        let capacity = n.max(4);
        let pool = storage(gpu, "crossing pool", 4 * capacity);
        let stats = storage(gpu, "crossing stats", 16);
        let summary = gpu.buffer(&wgpu::BufferDescriptor {
            label: Some("crossing summary"),
            size: 16,
            usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
            mapped_at_creation: false,
        });
        let module = crate::common::wgsl::module(&gpu.device, "crossing scan", WGSL);
        let empty = gpu
            .device
            .create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some("empty"),
                entries: &[],
            });
        let pl = crate::common::pipeline::layout(&gpu.device, "crossing scan", &[&empty, &empty, &layout]);
        let scan = ComputeStage::new("crossing scan", "cs_crossing_scan").build(
            &gpu.device,
            &pl,
            &module,
            &[],
        );
        let bind = bind_group(gpu, &layout, [&uniform, &counts, &offsets, &pool, &stats]);
        CrossingLists {
            layout,
            uniform,
            counts,
            offsets,
            pool,
            stats,
            summary,
            scan,
            bind,
            readback: CounterReadback::new(gpu, 4),
            lists,
            capacity,
        }
    }

    /// Group 2 of every pass that uses the lists.
    pub fn bind_group(&self) -> &wgpu::BindGroup {
        &self.bind
    }

    /// Light k's dynamic offset for group 2.
    pub fn slot(&self, k: usize) -> [u32; 1] {
        [(k.min(self.lists as usize - 1) as u64 * SLOT) as u32]
    }

    /// Starts a frame: the encoder the method records its scene depth and count passes into
    /// (submitted by [`CrossingLists::size_pool`]), with the counts cleared. `eye_counts`: per
    /// light, the number of shadow volumes around the eye (where each walk starts).
    pub fn begin_count(
        &mut self,
        gpu: &Gpu,
        eye_counts: &[u32],
        report: &mut FrameReport,
    ) -> wgpu::CommandEncoder {
        for (k, c) in eye_counts.iter().take(self.lists as usize).enumerate() {
            let at = k as u64 * SLOT + std::mem::offset_of!(CrossingUniform, eye_count) as u64;
            gpu.queue
                .write_buffer(&self.uniform, at, bytemuck::bytes_of(c));
        }
        self.readback.begin_frame(gpu, &self.stats);
        if let Some(v) = self.readback.latest() {
            report.count("crossing_overflows", v[2] as f64);
        }
        let mut enc = gpu
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("crossing count"),
            });
        enc.clear_buffer(&self.counts, 0, None);
        enc
    }

    /// Scans the counts, submits `enc` and waits for the total, grows the pool to hold it, and
    /// clears the counts again for the gather (they become its cursors).
    pub fn size_pool(
        &mut self,
        gpu: &Gpu,
        mut enc: wgpu::CommandEncoder,
        report: &mut FrameReport,
    ) -> anyhow::Result<()> {
        {
            let mut pass = gpu.compute_pass(
                &mut enc,
                &wgpu::ComputePassDescriptor {
                    label: Some("crossing scan"),
                    timestamp_writes: None,
                },
            );
            pass.set_pipeline(&self.scan);
            pass.set_bind_group(GROUP, &self.bind, &self.slot(0));
            pass.dispatch_workgroups(1, 1, 1);
        }
        enc.copy_buffer_to_buffer(&self.stats, 0, &self.summary, 0, 16);
        enc.clear_buffer(&self.counts, 0, None);
        let t0 = std::time::Instant::now();
        gpu.queue.submit([enc.finish()]);
        let bytes = harness::gpu::map_read(gpu, &self.summary).map_err(anyhow::Error::msg)?;
        report.count("crossing_count_ms", t0.elapsed().as_secs_f64() * 1e3);
        let word = |i: usize| {
            u32::from_le_bytes([
                bytes[4 * i],
                bytes[4 * i + 1],
                bytes[4 * i + 2],
                bytes[4 * i + 3],
            ])
        };
        let (total, longest) = (word(0) as u64, word(1));
        report.count("max_crossings", longest as f64);
        report.count("crossing_pool", total as f64);
        if total > self.capacity {
            let limits = gpu.device.limits();
            let largest = limits
                .max_buffer_size
                .min(limits.max_storage_buffer_binding_size);
            self.capacity = pool_capacity(total, largest).map_err(anyhow::Error::msg)?;
            self.pool = storage(gpu, "crossing pool", 4 * self.capacity);
            self.bind = bind_group(
                gpu,
                &self.layout,
                [
                    &self.uniform,
                    &self.counts,
                    &self.offsets,
                    &self.pool,
                    &self.stats,
                ],
            );
        }
        Ok(())
    }

    /// After the walks: copies the mismatch counter for a later frame's report.
    pub fn end_frame(&mut self, enc: &mut wgpu::CommandEncoder) {
        self.readback.end_frame(enc, &self.stats);
    }
}

/// Group 2: the uniform slot (0) and the four storage buffers (1–4).
fn bind_group(gpu: &Gpu, layout: &wgpu::BindGroupLayout, b: [&wgpu::Buffer; 5]) -> wgpu::BindGroup {
    let [uniform, storage @ ..] = b;
    let mut entries = vec![slot_entry(0, uniform, UNIFORM_SIZE)];
    entries.extend(
        storage
            .iter()
            .enumerate()
            .map(|(i, buf)| buffer_entry(1 + i as u32, buf)),
    );
    gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("crossing lists"),
        layout,
        entries: &entries,
    })
}

#[cfg(test)]
mod tests {
    use super::pool_capacity;

    #[test]
    fn the_pool_holds_every_crossing_within_the_binding_or_says_why_not() {
        let largest = 256u64 << 20;
        for total in [1, 1000, (largest / 4) * 3 / 4, largest / 4 - 1, largest / 4] {
            let capacity = pool_capacity(total, largest).unwrap();
            assert!(
                capacity >= total && 4 * capacity <= largest,
                "{total} → {capacity}"
            );
        }
        assert_eq!(
            pool_capacity(1000, largest).unwrap(),
            1250,
            "a quarter of headroom"
        );
        let why = pool_capacity(92_650_441, largest).unwrap_err();
        assert!(why.contains("354 MB") && why.contains("256 MB"), "{why}");
    }
}
