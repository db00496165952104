//! The resolve of methods whose compute passes sum each light's in-scatter into a buffer and
//! publish it to an rgba32float texture (epipolar-minmax, prefiltered-single-scattering): a
//! [`crate::common::resolve::ResolvePass`] with that texture at binding 3.

/// The resolve's fragment shader (an `fs` entry; composed by `common::resolve::source`).
pub const PUBLISHED_RESOLVE: &str = include_str!("published_resolve.wgsl");

use harness::Gpu;

/// A buffer of `size` bytes (at least 16: a binding may not be empty), counted by the harness.
pub fn scratch_buffer(
    gpu: &Gpu,
    label: &str,
    size: u64,
    usage: wgpu::BufferUsages,
) -> wgpu::Buffer {
    gpu.buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size: size.max(16),
        usage,
        mapped_at_creation: false,
    })
}

/// The published in-scatter: an rgba32float texture the compute passes write (storage) and the
/// resolve reads (binding 3), `width` × `height`.
pub fn published_texture(gpu: &Gpu, label: &str, width: u32, height: u32) -> wgpu::TextureView {
    gpu.texture_2d(
        label,
        width,
        height,
        wgpu::TextureFormat::Rgba32Float,
        wgpu::TextureUsages::STORAGE_BINDING | wgpu::TextureUsages::TEXTURE_BINDING,
    )
    .create_view(&Default::default())
}
