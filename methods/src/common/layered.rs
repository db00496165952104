//! Layered render targets: a 2-D array texture with a view of all its layers (for sampling)
//! and one view per layer (for rendering into it) — the shadow atlas, wyman-hybrid's
//! shadow-polygon distances.

use harness::Gpu;

/// A `width` × `height` × `layers` texture of `format` that can be rendered to and sampled.
pub struct Layered {
    pub texture: wgpu::Texture,
    /// Every layer, as a 2-D array (for sampling).
    pub array: wgpu::TextureView,
    /// One 2-D view per layer (render attachments).
    pub layers: Vec<wgpu::TextureView>,
}

impl Layered {
    pub fn new(
        gpu: &Gpu,
        label: &str,
        (width, height): (u32, u32),
        layers: u32,
        format: wgpu::TextureFormat,
    ) -> Layered {
        let texture = gpu.texture(&wgpu::TextureDescriptor {
            label: Some(label),
            size: wgpu::Extent3d {
                width,
                height,
                depth_or_array_layers: layers,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
            view_formats: &[],
        });
        let array = texture.create_view(&wgpu::TextureViewDescriptor {
            dimension: Some(wgpu::TextureViewDimension::D2Array),
            ..Default::default()
        });
        let layers = (0..layers)
            .map(|k| {
                texture.create_view(&wgpu::TextureViewDescriptor {
                    dimension: Some(wgpu::TextureViewDimension::D2),
                    base_array_layer: k,
                    array_layer_count: Some(1),
                    ..Default::default()
                })
            })
            .collect();
        Layered {
            texture,
            array,
            layers,
        }
    }
}
