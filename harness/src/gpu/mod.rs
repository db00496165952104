//! The GPU context: one headless wgpu device on the adapter a [`DeviceChoice`] names (`--adapter`,
//! `WGPU_ADAPTER_NAME`, or the best available: [`adapters`]), optionally under the Khronos
//! validation layer ([`validation`]), with the optional features the methods can use (timestamp
//! queries, float32 blending, …) requested when the adapter has them. Every wgpu error the
//! device raises is collected, so the runner can record a method that caused one as failed.

pub mod adapters;
mod attachments;
pub mod calibrate;
mod device;
mod mapping;
pub mod phases;
mod readback;
mod stats;
mod timer;
pub mod validation;

pub use adapters::{
    AdapterReport, AdapterSummary, DeviceChoice, NO_ADAPTER_HELP, SuiteFeatures, VALIDATION_HELP,
};
pub use attachments::{
    color_attachment, depth_attachment, depth_scratch_attachment, depth_stencil_attachment,
};
pub use calibrate::{Calibration, calibrate};
pub use device::{Gpu, texture_2d};
pub use phases::PhaseTimer;
pub use readback::{map_read, read_r32f, read_rgba32f};
pub use stats::{Counted, FrameWork, PassCounter, StatsQuery, WORK_COUNTERS};
pub use timer::GpuTimer;
