//! GPU time per phase of a frame (the breakdown of Biri et al.'s Table 1: first pass, second
//! pass surfaces, second pass volumes): a method marks where each phase starts with encoder
//! timestamps, and the runner reads the phases back after the frame and stores them as counters
//! `gpu_ms_<phase>` (see `Method::phase_timer`). Optional: None without timestamp queries inside
//! encoders, and methods that do not offer a timer need no change.

use super::device::Gpu;
use super::readback::map_read;

/// Phase marks of one frame: phase `names[i]` runs from timestamp i to timestamp i + 1.
pub struct PhaseTimer {
    set: wgpu::QuerySet,
    resolve: wgpu::Buffer,
    read: wgpu::Buffer,
    period_ns: f32,
    capacity: u32,
    names: Vec<&'static str>,
    /// Timestamps written this frame (marks plus the final one).
    written: u32,
}

impl PhaseTimer {
    /// Room for `phases` marks per frame; None when the device lacks timestamp queries inside
    /// encoders.
    pub fn new(gpu: &Gpu, phases: u32) -> Option<PhaseTimer> {
        let need =
            wgpu::Features::TIMESTAMP_QUERY | wgpu::Features::TIMESTAMP_QUERY_INSIDE_ENCODERS;
        if !gpu.features().contains(need) {
            return None;
        }
        let capacity = phases + 1;
        let bytes = 8 * capacity as u64;
        let set = gpu.device.create_query_set(&wgpu::QuerySetDescriptor {
            label: Some("phase timer"),
            ty: wgpu::QueryType::Timestamp,
            count: capacity,
        });
        let buffer = |label, usage| {
            gpu.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: bytes,
                usage,
                mapped_at_creation: false,
            })
        };
        Some(PhaseTimer {
            set,
            resolve: buffer(
                "phase timer resolve",
                wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
            ),
            read: buffer(
                "phase timer read",
                wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
            ),
            period_ns: gpu.queue.get_timestamp_period(),
            capacity,
            names: Vec::new(),
            written: 0,
        })
    }

    /// Starts phase `name` here (ending the previous one). The first mark of a frame starts a
    /// new frame. Marks beyond the capacity are ignored (their time joins the previous phase).
    pub fn mark(&mut self, enc: &mut wgpu::CommandEncoder, name: &'static str) {
        if self.written == 0 {
            self.names.clear();
        }
        if self.written + 1 >= self.capacity {
            return;
        }
        enc.write_timestamp(&self.set, self.written);
        self.names.push(name);
        self.written += 1;
    }

    /// Ends the last phase and copies the timestamps for [`PhaseTimer::read_ms`]; the next mark
    /// starts a new frame.
    pub fn finish(&mut self, enc: &mut wgpu::CommandEncoder) {
        if self.written == 0 {
            return;
        }
        enc.write_timestamp(&self.set, self.written);
        let n = self.written + 1;
        enc.resolve_query_set(&self.set, 0..n, &self.resolve, 0);
        enc.copy_buffer_to_buffer(&self.resolve, 0, &self.read, 0, 8 * n as u64);
        self.written = 0;
    }

    /// Milliseconds per phase name (summed over its marks) of the last finished frame, once it
    /// has completed on the GPU; empty before any.
    pub fn read_ms(&self, gpu: &Gpu) -> Result<Vec<(String, f64)>, String> {
        let names = &self.names;
        if names.is_empty() || self.written != 0 {
            return Ok(Vec::new());
        }
        let data = map_read(gpu, &self.read)?;
        let t: Vec<u64> = data
            .chunks_exact(8)
            .take(names.len() + 1)
            .map(|c| u64::from_le_bytes(c.try_into().expect("8 bytes")))
            .collect();
        let mut out: Vec<(String, f64)> = Vec::new();
        for (i, name) in names.iter().enumerate() {
            let ms = t[i + 1].saturating_sub(t[i]) as f64 * self.period_ns as f64 * 1e-6;
            match out.iter_mut().find(|(n, _)| n == name) {
                Some((_, v)) => *v += ms,
                None => out.push((name.to_string(), ms)),
            }
        }
        Ok(out)
    }
}

/// [`PhaseTimer::mark`] on a method's optional timer (None without timestamp queries).
pub fn mark(timer: &mut Option<PhaseTimer>, enc: &mut wgpu::CommandEncoder, name: &'static str) {
    if let Some(t) = timer.as_mut() {
        t.mark(enc, name);
    }
}

/// [`PhaseTimer::finish`] on a method's optional timer.
pub fn finish(timer: &mut Option<PhaseTimer>, enc: &mut wgpu::CommandEncoder) {
    if let Some(t) = timer.as_mut() {
        t.finish(enc);
    }
}
