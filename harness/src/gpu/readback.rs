//! Copies float textures (Rgba32Float, R32Float) back to the CPU.

use super::device::Gpu;
use super::mapping;
use crate::image::Image;

/// Reads a 2-D Rgba32Float texture (mip 0, layer 0) into an image, top row first.
pub fn read_rgba32f(gpu: &Gpu, texture: &wgpu::Texture) -> Result<Image, String> {
    let floats = read_floats(gpu, texture, 4)?;
    Ok(Image::from_rgba_f32(
        texture.width(),
        texture.height(),
        &floats,
    ))
}

/// Reads a 2-D R32Float texture (mip 0, layer 0), row-major, top row first.
pub fn read_r32f(gpu: &Gpu, texture: &wgpu::Texture) -> Result<Vec<f32>, String> {
    read_floats(gpu, texture, 1)
}

/// The f32 texels of a texture with `channels` f32 channels, rows unpadded.
fn read_floats(gpu: &Gpu, texture: &wgpu::Texture, channels: u32) -> Result<Vec<f32>, String> {
    let (w, h) = (texture.width(), texture.height());
    let unpadded = w * 4 * channels;
    let align = wgpu::COPY_BYTES_PER_ROW_ALIGNMENT;
    let padded = unpadded.div_ceil(align) * align;
    let buffer = gpu.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("readback"),
        size: padded as u64 * h as u64,
        usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
        mapped_at_creation: false,
    });
    let mut enc = gpu
        .device
        .create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("readback"),
        });
    enc.copy_texture_to_buffer(
        wgpu::TexelCopyTextureInfo {
            texture,
            mip_level: 0,
            origin: wgpu::Origin3d::ZERO,
            aspect: wgpu::TextureAspect::All,
        },
        wgpu::TexelCopyBufferInfo {
            buffer: &buffer,
            layout: wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(padded),
                rows_per_image: Some(h),
            },
        },
        wgpu::Extent3d {
            width: w,
            height: h,
            depth_or_array_layers: 1,
        },
    );
    gpu.queue.submit([enc.finish()]);
    let data = map_read(gpu, &buffer)?;
    let mut floats = Vec::with_capacity((w * h * channels) as usize);
    for row in 0..h as usize {
        let bytes = &data[row * padded as usize..row * padded as usize + unpadded as usize];
        floats.extend(
            bytes
                .chunks_exact(4)
                .map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]])),
        );
    }
    Ok(floats)
}

/// Waits for the queue, maps a MAP_READ buffer and returns a copy of its bytes (unmapped again).
pub fn map_read(gpu: &Gpu, buffer: &wgpu::Buffer) -> Result<Vec<u8>, String> {
    mapping::read_buffer(&gpu.device, buffer)
}
