//! Bind-group layout entries the passes share.

/// An unfilterable float 2-D texture read by the fragment stage (`textureLoad`): AOVs, distances,
/// accumulation targets.
pub fn fragment_texture(binding: u32) -> wgpu::BindGroupLayoutEntry {
    float_texture(binding, wgpu::ShaderStages::FRAGMENT)
}

/// An unfilterable float 2-D texture read with `textureLoad` by `visibility`.
pub fn float_texture(binding: u32, visibility: wgpu::ShaderStages) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility,
        ty: wgpu::BindingType::Texture {
            sample_type: wgpu::TextureSampleType::Float { filterable: false },
            view_dimension: wgpu::TextureViewDimension::D2,
            multisampled: false,
        },
        count: None,
    }
}

/// A storage buffer binding of any size.
pub fn storage_buffer(
    binding: u32,
    visibility: wgpu::ShaderStages,
    read_only: bool,
) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility,
        ty: wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Storage { read_only },
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    }
}

/// A uniform buffer binding of any size.
pub fn uniform_buffer(binding: u32, visibility: wgpu::ShaderStages) -> wgpu::BindGroupLayoutEntry {
    uniform(binding, visibility, false, None)
}

/// A uniform buffer bound one slot at a time by a dynamic offset (per light, per face): at
/// least `slot` bytes at each offset. Bind it with [`slot_entry`].
pub fn dynamic_uniform(
    binding: u32,
    visibility: wgpu::ShaderStages,
    slot: u64,
) -> wgpu::BindGroupLayoutEntry {
    uniform(binding, visibility, true, wgpu::BufferSize::new(slot))
}

fn uniform(
    binding: u32,
    visibility: wgpu::ShaderStages,
    has_dynamic_offset: bool,
    min_binding_size: Option<wgpu::BufferSize>,
) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility,
        ty: wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Uniform,
            has_dynamic_offset,
            min_binding_size,
        },
        count: None,
    }
}

/// An unfilterable float 2-D array texture read with `textureLoad` by `visibility` (shadow-map
/// layers, per-light layers).
pub fn float_texture_array(
    binding: u32,
    visibility: wgpu::ShaderStages,
) -> wgpu::BindGroupLayoutEntry {
    texture_array(binding, visibility, false)
}

/// A filterable float 2-D array texture, sampled by `visibility` (spot-pattern layers).
pub fn filterable_texture_array(
    binding: u32,
    visibility: wgpu::ShaderStages,
) -> wgpu::BindGroupLayoutEntry {
    texture_array(binding, visibility, true)
}

fn texture_array(
    binding: u32,
    visibility: wgpu::ShaderStages,
    filterable: bool,
) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility,
        ty: wgpu::BindingType::Texture {
            sample_type: wgpu::TextureSampleType::Float { filterable },
            view_dimension: wgpu::TextureViewDimension::D2Array,
            multisampled: false,
        },
        count: None,
    }
}

/// A write-only Rgba32Float 2-D storage texture (a compute pass's output that a later pass reads
/// as a texture).
pub fn rgba32f_storage_write(
    binding: u32,
    visibility: wgpu::ShaderStages,
) -> wgpu::BindGroupLayoutEntry {
    rgba32f_storage(binding, visibility, wgpu::TextureViewDimension::D2)
}

/// [`rgba32f_storage_write`] of a 2-D array texture (one layer per quantity).
pub fn rgba32f_storage_array_write(
    binding: u32,
    visibility: wgpu::ShaderStages,
) -> wgpu::BindGroupLayoutEntry {
    rgba32f_storage(binding, visibility, wgpu::TextureViewDimension::D2Array)
}

fn rgba32f_storage(
    binding: u32,
    visibility: wgpu::ShaderStages,
    view_dimension: wgpu::TextureViewDimension,
) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility,
        ty: wgpu::BindingType::StorageTexture {
            access: wgpu::StorageTextureAccess::WriteOnly,
            format: wgpu::TextureFormat::Rgba32Float,
            view_dimension,
        },
        count: None,
    }
}

/// A bind-group entry binding a whole buffer.
pub fn buffer_entry(binding: u32, buffer: &wgpu::Buffer) -> wgpu::BindGroupEntry<'_> {
    wgpu::BindGroupEntry {
        binding,
        resource: buffer.as_entire_binding(),
    }
}

/// A bind-group entry binding the `slot`-byte window of `buffer` that a dynamic offset moves
/// ([`dynamic_uniform`]).
pub fn slot_entry(binding: u32, buffer: &wgpu::Buffer, slot: u64) -> wgpu::BindGroupEntry<'_> {
    wgpu::BindGroupEntry {
        binding,
        resource: wgpu::BindingResource::Buffer(wgpu::BufferBinding {
            buffer,
            offset: 0,
            size: wgpu::BufferSize::new(slot),
        }),
    }
}

/// A bind-group entry binding a texture view.
pub fn view_entry(binding: u32, view: &wgpu::TextureView) -> wgpu::BindGroupEntry<'_> {
    wgpu::BindGroupEntry {
        binding,
        resource: wgpu::BindingResource::TextureView(view),
    }
}
