//! Counters a shader accumulates with atomics (pixels marched, steps taken), read back without
//! stalling the frame: each frame copies the counters into one of two staging buffers, and the
//! next frame maps it; the values arrive once the harness has waited for that frame. So a report
//! carries the counts of an earlier frame (equal to this frame's for a static scene).

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};

use harness::Gpu;

pub struct CounterReadback {
    slots: u32,
    staging: [wgpu::Buffer; 2],
    /// Which staging buffer this frame copies into.
    next: usize,
    /// Whether each staging buffer holds a copy not yet mapped.
    filled: [bool; 2],
    /// Whether each staging buffer has a map in flight (it cannot be copied into then).
    pending: [bool; 2],
    ready: [Arc<AtomicBool>; 2],
    latest: Arc<Mutex<Option<Vec<u32>>>>,
}

impl CounterReadback {
    pub fn new(gpu: &Gpu, slots: u32) -> CounterReadback {
        let make = || {
            gpu.buffer(&wgpu::BufferDescriptor {
                label: Some("counter staging"),
                size: 4 * slots as u64,
                usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
                mapped_at_creation: false,
            })
        };
        CounterReadback {
            slots,
            staging: [make(), make()],
            next: 0,
            filled: [false; 2],
            pending: [false; 2],
            ready: Default::default(),
            latest: Default::default(),
        }
    }

    /// The most recent counts that have arrived (None before the first).
    pub fn latest(&self) -> Option<Vec<u32>> {
        self.latest.lock().ok().and_then(|l| l.clone())
    }

    /// Call at the start of a frame, before encoding: collects a finished mapping and starts
    /// mapping last frame's copy. Zeroes the GPU counters for this frame.
    pub fn begin_frame(&mut self, gpu: &Gpu, counters: &wgpu::Buffer) {
        for k in 0..2 {
            if self.ready[k].swap(false, Ordering::AcqRel) {
                let slice = self.staging[k].slice(..);
                if let Ok(view) = slice.get_mapped_range() {
                    let v: Vec<u32> = view
                        .chunks_exact(4)
                        .map(|c| u32::from_le_bytes([c[0], c[1], c[2], c[3]]))
                        .collect();
                    if let Ok(mut l) = self.latest.lock() {
                        *l = Some(v);
                    }
                }
                self.staging[k].unmap();
                self.pending[k] = false;
            }
        }
        let prev = 1 - self.next;
        if self.filled[prev] {
            self.filled[prev] = false;
            self.pending[prev] = true;
            let flag = self.ready[prev].clone();
            self.staging[prev]
                .slice(..)
                .map_async(wgpu::MapMode::Read, move |r| {
                    if r.is_ok() {
                        flag.store(true, Ordering::Release);
                    }
                });
        }
        gpu.queue
            .write_buffer(counters, 0, &vec![0u8; 4 * self.slots as usize]);
    }

    /// Call after the passes that count: copies the counters for a later frame to read.
    pub fn end_frame(&mut self, enc: &mut wgpu::CommandEncoder, counters: &wgpu::Buffer) {
        // A buffer still being mapped cannot be copied into; skip this frame's copy then.
        let k = self.next;
        if !self.pending[k] && !self.filled[k] {
            enc.copy_buffer_to_buffer(counters, 0, &self.staging[k], 0, 4 * self.slots as u64);
            self.filled[k] = true;
        }
        self.next = 1 - self.next;
    }
}
