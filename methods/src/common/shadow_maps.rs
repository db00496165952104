//! Shadow maps for every light: six cube faces (perspective, 90°) for point and spot lights,
//! one orthographic face fitted to the casters for directional light. Each face stores, per
//! texel, the distance from the light to the nearest caster (R32Float; depth along the light
//! direction for directional light), and `shadow.wgsl` compares against it.

use bytemuck::{Pod, Zeroable};
use glam::{Mat4, Vec3};
use harness::gpu::{PassCounter, color_attachment, depth_scratch_attachment};
use harness::{FrameReport, Gpu};
use scenes::{FrameState, LightState, Scene};

use super::gpu_scene::{GpuScene, mesh_pipeline};
use super::layouts::{buffer_entry, dynamic_uniform, slot_entry, storage_buffer};
use super::pipeline;
use super::uniforms::ShadowSlot;
use super::wgsl;

/// A local light's cube faces' axes in layer order (+X, −X, +Y, −Y, +Z, −Z), the order every
/// cube of faces around a light uses (shadow maps, polygonal-light-volumes' faces,
/// umenhoffer's light maps).
pub const CUBE_FACE_AXES: [Vec3; 6] = [
    Vec3::X,
    Vec3::NEG_X,
    Vec3::Y,
    Vec3::NEG_Y,
    Vec3::Z,
    Vec3::NEG_Z,
];

/// Each shadow-map face's up vector, beside [`CUBE_FACE_AXES`].
const CUBE_FACE_UPS: [Vec3; 6] = [
    Vec3::NEG_Y,
    Vec3::NEG_Y,
    Vec3::Z,
    Vec3::NEG_Z,
    Vec3::NEG_Y,
    Vec3::NEG_Y,
];

const FACE_STRIDE: u64 = 256;
pub const FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R32Float;
/// What a texel holds where no caster was drawn: a distance beyond everything.
const NO_CASTER: wgpu::Color = wgpu::Color {
    r: 1e30,
    g: 0.0,
    b: 0.0,
    a: 0.0,
};

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct FaceUniform {
    clip_from_world: [[f32; 4]; 4],
    // xyz: light position or direction; w: 1 for directional
    light: [f32; 4],
}

pub struct ShadowMaps {
    pub size: u32,
    pub texture: wgpu::Texture,
    /// All layers, for sampling.
    pub view: wgpu::TextureView,
    layer_views: Vec<wgpu::TextureView>,
    depth_view: wgpu::TextureView,
    faces: wgpu::Buffer,
    pipeline: wgpu::RenderPipeline,
    bind_group: wgpu::BindGroup,
    /// Per light: where its faces are.
    pub slots: Vec<ShadowSlot>,
    passes: PassCounter,
}

impl ShadowMaps {
    /// Allocates maps for `lights` (6 layers for local lights, 1 for directional), `size`² each;
    /// `enabled = false` allocates a single 1×1 layer that nothing samples.
    pub fn new(
        gpu: &Gpu,
        lights: &[LightState],
        size: u32,
        enabled: bool,
        scene_gpu: &GpuScene,
    ) -> ShadowMaps {
        let (mut slots, layers) = slots(lights, size);
        let (size, layers) = if enabled && layers > 0 {
            (size, layers)
        } else {
            (1, 1)
        };
        if !enabled {
            slots.clear();
        }
        let (texture, view, layer_views) = layer_textures(gpu, size, layers);
        let depth = gpu.texture_2d(
            "shadow depth",
            size,
            size,
            wgpu::TextureFormat::Depth32Float,
            wgpu::TextureUsages::RENDER_ATTACHMENT,
        );
        let depth_view = depth.create_view(&Default::default());
        let faces = gpu.buffer(&wgpu::BufferDescriptor {
            label: Some("shadow faces"),
            size: FACE_STRIDE * layers as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let (layout, bind_group) = pass_group(gpu, &faces, &scene_gpu.objects);
        let module = wgsl::module(&gpu.device, "shadow map", &shader_source());
        let pl = pipeline::layout(&gpu.device, "shadow map", &[&layout]);
        let pipeline = mesh_pipeline(
            &gpu.device,
            "shadow map",
            &pl,
            &module,
            &[Some(FORMAT.into())],
            &[],
        );
        ShadowMaps {
            size,
            texture,
            view,
            layer_views,
            depth_view,
            faces,
            pipeline,
            bind_group,
            slots,
            passes: gpu.pass_counter(),
        }
    }

    /// Places this frame's faces: cube faces around local lights, an orthographic box around
    /// the casters for directional light.
    pub fn update(&mut self, gpu: &Gpu, scene: &Scene, frame: &FrameState) {
        if self.slots.is_empty() {
            return;
        }
        let (lo, hi) = caster_bounds(scene, frame);
        let centre = 0.5 * (lo + hi);
        let radius = (0.5 * (hi - lo).length()).max(1e-3);
        let mut data = vec![0u8; self.faces.size() as usize];
        for (slot, light) in self.slots.iter_mut().zip(&frame.lights) {
            let (mats, light_v): (Vec<Mat4>, [f32; 4]) = match light {
                LightState::Directional { direction, .. } => {
                    let dir = *direction;
                    let up = if dir.y.abs() > 0.99 { Vec3::Z } else { Vec3::Y };
                    let eye = centre - dir * (2.0 * radius);
                    let view = glam::camera::rh::view::look_to_mat4(eye, dir, up);
                    // Depth is stored as dot(x, dir); the ortho box only selects the texel.
                    let proj = glam::camera::rh::proj::directx::orthographic(
                        -radius,
                        radius,
                        -radius,
                        radius,
                        0.0,
                        4.0 * radius,
                    );
                    slot.bias = 1.5 * 2.0 * radius / slot.size as f32;
                    (vec![proj * view], dir.extend(1.0).to_array())
                }
                _ => {
                    let p = light.position().expect("local light");
                    let far = (p - centre).length() + radius + 1.0;
                    let near = (1e-4 * far).max(1e-4);
                    let proj = glam::camera::rh::proj::directx::perspective(
                        std::f32::consts::FRAC_PI_2,
                        1.0,
                        near,
                        far,
                    );
                    let dirs = CUBE_FACE_AXES.iter().zip(CUBE_FACE_UPS);
                    slot.bias = 1.5;
                    (
                        dirs.map(|(d, u)| proj * glam::camera::rh::view::look_to_mat4(p, *d, u))
                            .collect(),
                        p.extend(0.0).to_array(),
                    )
                }
            };
            for (k, m) in mats.iter().enumerate() {
                slot.clip_from_world[k] = *m;
                let u = FaceUniform {
                    clip_from_world: m.to_cols_array_2d(),
                    light: light_v,
                };
                let off = (slot.layer_base as usize + k) * FACE_STRIDE as usize;
                data[off..off + std::mem::size_of::<FaceUniform>()]
                    .copy_from_slice(bytemuck::bytes_of(&u));
            }
        }
        gpu.queue.write_buffer(&self.faces, 0, &data);
    }

    /// Renders every face (casters only).
    pub fn encode(
        &self,
        enc: &mut wgpu::CommandEncoder,
        scene_gpu: &GpuScene,
        report: &mut FrameReport,
    ) {
        for slot in &self.slots {
            for k in 0..slot.faces {
                let layer = slot.layer_base + k;
                let mut pass = self.passes.render_pass(
                    enc,
                    &wgpu::RenderPassDescriptor {
                        label: Some("shadow face"),
                        color_attachments: &[color_attachment(
                            &self.layer_views[layer as usize],
                            wgpu::LoadOp::Clear(NO_CASTER),
                        )],
                        depth_stencil_attachment: Some(depth_scratch_attachment(
                            &self.depth_view,
                            wgpu::LoadOp::Clear(1.0),
                        )),
                        ..Default::default()
                    },
                );
                pass.set_pipeline(&self.pipeline);
                pass.set_bind_group(0, &self.bind_group, &[(layer as u64 * FACE_STRIDE) as u32]);
                pass.set_vertex_buffer(0, scene_gpu.vertices.slice(..));
                pass.set_index_buffer(scene_gpu.indices.slice(..), wgpu::IndexFormat::Uint32);
                for d in scene_gpu.draws.iter().filter(|d| d.casts_shadow) {
                    pass.draw_indexed(d.first_index..d.first_index + d.index_count, 0, 0..1);
                }
                report.count("shadow_faces", 1.0);
            }
        }
    }
}

/// Each light's slot (6 cube faces for local lights, 1 for directional, `size`² each) and the
/// layers they need in all.
fn slots(lights: &[LightState], size: u32) -> (Vec<ShadowSlot>, u32) {
    let mut slots = Vec::new();
    let mut layers = 0u32;
    for l in lights {
        let faces = if matches!(l, LightState::Directional { .. }) {
            1
        } else {
            6
        };
        slots.push(ShadowSlot {
            layer_base: layers,
            faces,
            size,
            bias: 1.5,
            clip_from_world: [Mat4::IDENTITY; 6],
        });
        layers += faces;
    }
    (slots, layers)
}

/// The `layers`-layer R32Float map texture, its array view (for sampling) and one view per
/// layer (for rendering).
fn layer_textures(
    gpu: &Gpu,
    size: u32,
    layers: u32,
) -> (wgpu::Texture, wgpu::TextureView, Vec<wgpu::TextureView>) {
    let texture = gpu.texture(&wgpu::TextureDescriptor {
        label: Some("shadow maps"),
        size: wgpu::Extent3d {
            width: size,
            height: size,
            depth_or_array_layers: layers,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: FORMAT,
        usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
        view_formats: &[],
    });
    let view = texture.create_view(&wgpu::TextureViewDescriptor {
        dimension: Some(wgpu::TextureViewDimension::D2Array),
        ..Default::default()
    });
    let layer_views = (0..layers)
        .map(|k| {
            texture.create_view(&wgpu::TextureViewDescriptor {
                dimension: Some(wgpu::TextureViewDimension::D2),
                base_array_layer: k,
                array_layer_count: Some(1),
                ..Default::default()
            })
        })
        .collect();
    (texture, view, layer_views)
}

/// The shadow pass's group: each face's uniform (a dynamic-offset slot of `faces`) and the
/// scene's objects.
fn pass_group(
    gpu: &Gpu,
    faces: &wgpu::Buffer,
    objects: &wgpu::Buffer,
) -> (wgpu::BindGroupLayout, wgpu::BindGroup) {
    let face_size = std::mem::size_of::<FaceUniform>() as u64;
    let layout = gpu
        .device
        .create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("shadow pass"),
            entries: &[
                dynamic_uniform(0, wgpu::ShaderStages::VERTEX_FRAGMENT, face_size),
                storage_buffer(1, wgpu::ShaderStages::VERTEX, true),
            ],
        });
    let bind = gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("shadow pass"),
        layout: &layout,
        entries: &[slot_entry(0, faces, face_size), buffer_entry(1, objects)],
    });
    (layout, bind)
}

/// World bounds of the shadow casters at this frame (a unit box at the origin if none).
pub fn caster_bounds(scene: &Scene, frame: &FrameState) -> (Vec3, Vec3) {
    let mut lo = Vec3::splat(f32::INFINITY);
    let mut hi = Vec3::splat(f32::NEG_INFINITY);
    for ((mesh, obj), m) in scene
        .meshes
        .iter()
        .zip(&scene.desc.objects)
        .zip(&frame.world_from_local)
    {
        if obj.casts_volumetric_shadow {
            let (a, b) = mesh.bounds(m);
            lo = lo.min(a);
            hi = hi.max(b);
        }
    }
    if lo.x > hi.x {
        (-Vec3::ONE, Vec3::ONE)
    } else {
        (lo, hi)
    }
}

pub fn shader_source() -> String {
    wgsl::compose(&[wgsl::SCENE], include_str!("wgsl/shadow_pass.wgsl"))
}
