//! Shadow maps for every light: six cube faces (perspective, 90°) for point and spot lights,
//! one orthographic face fitted to the casters for directional light. Each face stores, per
//! texel, the distance from the light to the nearest caster (R32Float; depth along the light
//! direction for directional light), and `shadow.wgsl` compares against it.
//!
//! The faces live in an atlas, as engines keep dozens of local lights' maps: an R32Float 2-D
//! array of `shadow_map`² layers. A directional face fills a layer; local lights' faces are tiles
//! of `local` texels (`ShadowSettings::local_size`: `shadow_map` halved until every local face
//! fits the `local_shadow_budget`), several to a layer, each layer drawn in one pass with one
//! viewport per face. A light's faces are consecutive tiles (`ShadowSlot::face_tile`).
use bytemuck::{Pod, Zeroable};
use glam::{Mat4, Vec3};
use harness::gpu::{PassCounter, color_attachment, depth_scratch_attachment};
use harness::{FrameReport, Gpu};
use scenes::{FrameState, LightState, Scene};

use super::gpu_scene::{GpuScene, mesh_pipeline};
use super::layered::Layered;
use super::layouts::{buffer_entry, dynamic_uniform, slot_entry, storage_buffer};
use super::pipeline;
use super::uniforms::ShadowSlot;
use super::wgsl;
use harness::method::{KnobRead, Params};

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

/// The shadow-map knobs: `shadow_map` and `local_shadow_budget` (`common::knobs`).
#[derive(Clone, Copy, Debug)]
pub struct ShadowSettings {
    /// Texels per side of a directional light's face, and the atlas's side.
    pub size: u32,
    /// MiB all local lights' faces may take together.
    pub local_budget_mib: u32,
}

impl ShadowSettings {
    /// The method's `shadow_map` and `local_shadow_budget` knobs.
    pub fn from_params(p: &Params) -> anyhow::Result<ShadowSettings> {
        Ok(ShadowSettings {
            size: p.knob("shadow_map")?,
            local_budget_mib: p.knob("local_shadow_budget")?,
        })
    }

    /// log2 of how many times each local light's face side halves `size` for `local_faces`
    /// faces: halved while the faces (R32Float) exceed the budget, while the side stays 16 or
    /// more (`shadow_map`'s least). `size >> shift` is the side; 2^shift tiles fit a row.
    pub fn local_shift(&self, local_faces: u32) -> u32 {
        let budget = self.local_budget_mib as u64 * (1 << 20);
        let bytes = |s: u32| local_faces as u64 * (s as u64).pow(2) * 4;
        let mut shift = 0;
        while self.size >> (shift + 1) >= 16 && bytes(self.size >> shift) > budget {
            shift += 1;
        }
        shift
    }

    /// Texels per side of each local light's face for `local_faces` faces.
    pub fn local_size(&self, local_faces: u32) -> u32 {
        self.size >> self.local_shift(local_faces)
    }
}

pub struct ShadowMaps {
    /// The atlas's side (texels): a directional face's size.
    pub size: u32,
    /// Texels per side of each local light's face.
    pub local_size: u32,
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
    /// Allocates the atlas for `lights` (6 tiles for local lights, a layer for directional);
    /// `enabled = false` allocates a single 1×1 layer that nothing samples. Fails, naming the
    /// device limit, where the atlas needs more layers than the device has.
    pub fn new(
        gpu: &Gpu,
        lights: &[LightState],
        settings: ShadowSettings,
        enabled: bool,
        scene_gpu: &GpuScene,
    ) -> anyhow::Result<ShadowMaps> {
        let local_faces = 6 * lights.iter().filter(|l| l.position().is_some()).count() as u32;
        let local_shift = settings.local_shift(local_faces);
        let local_size = settings.size >> local_shift;
        let (mut slots, layers) = slots(lights, settings.size, local_shift);
        let (size, layers) = if enabled && layers > 0 {
            (settings.size, layers)
        } else {
            (1, 1)
        };
        if !enabled {
            slots.clear();
        }
        let most = gpu.device.limits().max_texture_array_layers;
        if layers > most {
            anyhow::bail!(
                "the shadow atlas needs {layers} layers of {size}² texels ({} lights, local faces \
                 {local_size}²) but the device's max_texture_array_layers is {most}: lower \
                 shadow_map or local_shadow_budget",
                lights.len()
            );
        }
        let Layered {
            texture,
            array: view,
            layers: layer_views,
        } = Layered::new(gpu, "shadow maps", (size, size), layers, FORMAT);
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
            size: FACE_STRIDE * slots.iter().map(|s| s.faces as u64).sum::<u64>().max(1),
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
        Ok(ShadowMaps {
            size,
            local_size,
            texture,
            view,
            layer_views,
            depth_view,
            faces,
            pipeline,
            bind_group,
            slots,
            passes: gpu.pass_counter(),
        })
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
        let mut uniform_slot = 0usize;
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
                let off = uniform_slot * FACE_STRIDE as usize;
                uniform_slot += 1;
                data[off..off + std::mem::size_of::<FaceUniform>()]
                    .copy_from_slice(bytemuck::bytes_of(&u));
            }
        }
        gpu.queue.write_buffer(&self.faces, 0, &data);
    }

    /// Renders every face (casters only): one pass per atlas layer, one viewport per face.
    pub fn encode(
        &self,
        enc: &mut wgpu::CommandEncoder,
        scene_gpu: &GpuScene,
        report: &mut FrameReport,
    ) {
        // (layer, tile origin x, y, side, uniform slot): the uniform slots in `update`'s order.
        let mut faces: Vec<(u32, u32, u32, u32, u64)> = Vec::new();
        for slot in &self.slots {
            for k in 0..slot.faces {
                let (layer, x, y) = slot.face_tile(k);
                faces.push((layer, x, y, slot.size, faces.len() as u64));
            }
        }
        for layer in 0..self.layer_views.len() as u32 {
            let in_layer: Vec<_> = faces.iter().filter(|f| f.0 == layer).collect();
            if in_layer.is_empty() {
                continue;
            }
            let mut pass = self.passes.render_pass(
                enc,
                &wgpu::RenderPassDescriptor {
                    label: Some("shadow layer"),
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
            pass.set_vertex_buffer(0, scene_gpu.vertices.slice(..));
            pass.set_index_buffer(scene_gpu.indices.slice(..), wgpu::IndexFormat::Uint32);
            for &&(_, x, y, side, uniform_slot) in &in_layer {
                pass.set_viewport(x as f32, y as f32, side as f32, side as f32, 0.0, 1.0);
                pass.set_scissor_rect(x, y, side, side);
                let offset = (uniform_slot * FACE_STRIDE) as u32;
                pass.set_bind_group(0, &self.bind_group, &[offset]);
                for d in scene_gpu.draws.iter().filter(|d| d.casts_shadow) {
                    pass.draw_indexed(d.first_index..d.first_index + d.index_count, 0, 0..1);
                }
                report.count("shadow_faces", 1.0);
            }
        }
        report.count("shadow_map_local", self.local_size as f64);
    }
}

/// Each light's slot in an atlas of `side`² layers (a directional light: one `side`² face;
/// a local light: 6 tiles of `side >> local_shift` texels, consecutive, 2^local_shift to a
/// row) and the layers they take in all. A light whose tile side differs from the previous
/// light's starts a fresh layer, so every slot's tiles count from layer 0 in its own tile side
/// (`ShadowSlot::face_tile`).
fn slots(lights: &[LightState], side: u32, local_shift: u32) -> (Vec<ShadowSlot>, u32) {
    let mut slots = Vec::new();
    // The next free tile, counted in tiles of side `side >> shift`, 4^shift to a layer.
    let (mut shift, mut next) = (0u32, 0u32);
    let per_layer = |s: u32| 1u32 << (2 * s);
    for l in lights {
        let (faces, row_shift) = match l {
            LightState::Directional { .. } => (1, 0),
            _ => (6, local_shift),
        };
        if row_shift != shift {
            let layers_used = next.div_ceil(per_layer(shift));
            (shift, next) = (row_shift, layers_used * per_layer(row_shift));
        }
        slots.push(ShadowSlot {
            tile_base: next,
            faces,
            size: side >> row_shift,
            row_shift,
            bias: 1.5,
            clip_from_world: [Mat4::IDENTITY; 6],
        });
        next += faces;
    }
    (slots, next.div_ceil(per_layer(shift)))
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

#[cfg(test)]
mod tests {
    use super::*;

    fn point() -> LightState {
        LightState::Point {
            position: Vec3::ONE,
            intensity: Vec3::ONE,
        }
    }

    fn sun() -> LightState {
        LightState::Directional {
            direction: Vec3::NEG_Y,
            irradiance: Vec3::ONE,
        }
    }

    /// Every face of every light gets its own tile inside the atlas: no two faces overlap, each
    /// lies within its layer, and the layer count covers them all.
    #[test]
    fn atlas_tiles_are_disjoint_and_inside() {
        let lights = [sun(), point(), point(), sun(), point(), point(), point()];
        // 64² layers, local faces of 16²: 16 to a layer.
        let side = 64;
        let (slots, layers) = slots(&lights, side, 2);
        let mut rects = Vec::new();
        for s in &slots {
            for k in 0..s.faces {
                let (layer, x, y) = s.face_tile(k);
                assert!(layer < layers && x + s.size <= side && y + s.size <= side);
                rects.push((layer, x, y, s.size));
            }
        }
        for (i, a) in rects.iter().enumerate() {
            for b in &rects[i + 1..] {
                let apart = a.0 != b.0
                    || a.1 + a.3 <= b.1
                    || b.1 + b.3 <= a.1
                    || a.2 + a.3 <= b.2
                    || b.2 + b.3 <= a.2;
                assert!(apart, "tiles {a:?} and {b:?} overlap");
            }
        }
        // sun | 12 local tiles (16 per layer) | sun | 18 local tiles: 1 + 1 + 1 + 2 layers.
        assert_eq!(layers, 5);
    }

    /// The local face side halves until the faces fit the budget, and stays at `shadow_map`
    /// where they already fit.
    #[test]
    fn local_size_fits_the_budget() {
        let s = ShadowSettings {
            size: 1024,
            local_budget_mib: 256,
        };
        // 4 MiB a face at 1024²: 64 faces fit; 1 MiB at 512²: 256 faces; 64 lights' 384 faces
        // take 256² (0.25 MiB each).
        assert_eq!(s.local_size(64), 1024);
        assert_eq!(s.local_size(65), 512);
        assert_eq!(s.local_size(256), 512);
        assert_eq!(s.local_size(257), 256);
        assert_eq!(s.local_size(384), 256);
        let tiny = ShadowSettings {
            size: 1024,
            local_budget_mib: 1,
        };
        assert_eq!(tiny.local_size(100_000), 16);
        // Not a power of two: the side halves with rounding down, 2^shift tiles still fit a row.
        let odd = ShadowSettings {
            size: 1000,
            local_budget_mib: 1,
        };
        let shift = odd.local_shift(100_000);
        assert_eq!((shift, odd.local_size(100_000)), (5, 31));
        assert!(odd.local_size(100_000) << shift <= odd.size);
    }
}
