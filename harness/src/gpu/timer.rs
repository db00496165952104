//! GPU frame time from timestamp queries written at the start and end of a frame's encoder.

use super::device::Gpu;
use super::readback::map_read;

pub struct GpuTimer {
    set: wgpu::QuerySet,
    resolve: wgpu::Buffer,
    read: wgpu::Buffer,
    period_ns: f32,
}

impl GpuTimer {
    /// None when the device lacks timestamp queries inside encoders.
    pub fn new(gpu: &Gpu) -> Option<GpuTimer> {
        let need =
            wgpu::Features::TIMESTAMP_QUERY | wgpu::Features::TIMESTAMP_QUERY_INSIDE_ENCODERS;
        if !gpu.features().contains(need) {
            return None;
        }
        let set = gpu.device.create_query_set(&wgpu::QuerySetDescriptor {
            label: Some("frame timer"),
            ty: wgpu::QueryType::Timestamp,
            count: 2,
        });
        let resolve = gpu.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("timer resolve"),
            size: 16,
            usage: wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let read = gpu.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("timer read"),
            size: 16,
            usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
            mapped_at_creation: false,
        });
        Some(GpuTimer {
            set,
            resolve,
            read,
            period_ns: gpu.queue.get_timestamp_period(),
        })
    }

    pub fn begin(&self, enc: &mut wgpu::CommandEncoder) {
        enc.write_timestamp(&self.set, 0);
    }

    pub fn end(&self, enc: &mut wgpu::CommandEncoder) {
        enc.write_timestamp(&self.set, 1);
        enc.resolve_query_set(&self.set, 0..2, &self.resolve, 0);
        enc.copy_buffer_to_buffer(&self.resolve, 0, &self.read, 0, 16);
    }

    /// Milliseconds between begin and end of the last submitted frame (call after it finished).
    pub fn read_ms(&self, gpu: &Gpu) -> Result<f64, String> {
        let data = map_read(gpu, &self.read)?;
        let t0 = u64::from_le_bytes(data[0..8].try_into().expect("16-byte buffer"));
        let t1 = u64::from_le_bytes(data[8..16].try_into().expect("16-byte buffer"));
        Ok(t1.saturating_sub(t0) as f64 * self.period_ns as f64 * 1e-6)
    }
}
