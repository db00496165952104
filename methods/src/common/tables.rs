//! Precomputed tables on the GPU: an f32 grid uploaded as an R32Float texture, read with
//! `textureLoad` (R32Float is not filterable everywhere, so shaders interpolate themselves).

use harness::Gpu;

/// A `width`×`height` R32Float texture holding `data` row-major (row 0 = y 0).
pub fn r32_table(gpu: &Gpu, label: &str, width: u32, height: u32, data: &[f32]) -> wgpu::Texture {
    assert_eq!(data.len(), (width * height) as usize, "{label}: table size");
    let texture = gpu.texture_2d(
        label,
        width,
        height,
        wgpu::TextureFormat::R32Float,
        wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
    );
    gpu.queue.write_texture(
        texture.as_image_copy(),
        bytemuck::cast_slice(data),
        wgpu::TexelCopyBufferLayout {
            offset: 0,
            bytes_per_row: Some(width * 4),
            rows_per_image: Some(height),
        },
        wgpu::Extent3d {
            width,
            height,
            depth_or_array_layers: 1,
        },
    );
    texture
}
