//! Spot-light patterns as a texture array (one layer per patterned light), sampled by the
//! methods — the approximation the reference does not make (it evaluates the pattern exactly).

use harness::Gpu;
use scenes::desc::LightDesc;
use scenes::light::pattern_value;

pub struct PatternTextures {
    pub texture: wgpu::Texture,
    pub view: wgpu::TextureView,
    /// Layer of each light's pattern (None: no pattern).
    pub layers: Vec<Option<u32>>,
}

impl PatternTextures {
    /// `size`: texels per side of each layer.
    pub fn new(gpu: &Gpu, lights: &[LightDesc], size: u32) -> PatternTextures {
        let mut layers = Vec::new();
        let mut data: Vec<half::f16> = Vec::new();
        let mut n = 0;
        for l in lights {
            match l {
                LightDesc::Spot {
                    pattern: Some(p), ..
                } => {
                    layers.push(Some(n));
                    n += 1;
                    for y in 0..size {
                        for x in 0..size {
                            let v = pattern_value(
                                p,
                                (x as f64 + 0.5) / size as f64,
                                (y as f64 + 0.5) / size as f64,
                            );
                            data.extend([v.x, v.y, v.z, 1.0].map(half::f16::from_f64));
                        }
                    }
                }
                _ => layers.push(None),
            }
        }
        let (size, count) = if n == 0 { (1, 1) } else { (size, n) };
        if n == 0 {
            data = vec![half::f16::ONE; 4];
        }
        let texture = gpu.texture(&wgpu::TextureDescriptor {
            label: Some("light patterns"),
            size: wgpu::Extent3d {
                width: size,
                height: size,
                depth_or_array_layers: count,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: wgpu::TextureFormat::Rgba16Float,
            usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
            view_formats: &[],
        });
        gpu.queue.write_texture(
            texture.as_image_copy(),
            bytemuck::cast_slice(&data),
            wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(size * 8),
                rows_per_image: Some(size),
            },
            wgpu::Extent3d {
                width: size,
                height: size,
                depth_or_array_layers: count,
            },
        );
        let view = texture.create_view(&wgpu::TextureViewDescriptor {
            dimension: Some(wgpu::TextureViewDimension::D2Array),
            ..Default::default()
        });
        PatternTextures {
            texture,
            view,
            layers,
        }
    }
}
