//! The light-volume pass: per light, one pipeline (the light index and kind baked); per face, a
//! non-indexed draw whose vertices are pulled from the shadow map (`volume.wgsl`), blended
//! additively into a float accumulation target the resolve reads.

use bytemuck::{Pod, Zeroable};
use harness::gpu::color_attachment;
use harness::{FrameReport, Gpu};

use super::faces::{self, LightPlan};
use super::shaders::volume_source;
use crate::common::layouts::{
    dynamic_uniform, float_texture_array, fragment_texture, slot_entry, view_entry,
};
use crate::common::pipeline::{self, Stage};
use crate::common::renderer::SceneRenderer;
use crate::common::wgsl;

const FACE_STRIDE: u64 = 256;
pub const ACC_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Float;

/// Mirrors `Face` in volume.wgsl.
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct FaceUniform {
    world_from_clip: [[f32; 4]; 4],
    light: [f32; 4],
    axis: [f32; 4],
    grid: [u32; 4],
    cap: [f32; 4],
}

pub struct VolumePass {
    /// Per light: (grid, walls).
    pipelines: Vec<(wgpu::RenderPipeline, wgpu::RenderPipeline)>,
    bind: wgpu::BindGroup,
    faces: wgpu::Buffer,
    pub acc_view: wgpu::TextureView,
    /// Grid vertices per shadow-map texel along a side (the `mesh` knob).
    pub mesh: f64,
}

/// Grid samples per side of a face of `size` texels: `size` × `mesh`.
pub fn samples(size: u32, mesh: f64) -> u32 {
    (size as f64 * mesh) as u32
}

/// One queued draw: light, face slot in the uniform buffer, directional?, grid samples per side.
struct Draw {
    light: usize,
    slot: u64,
    directional: bool,
    samples: u32,
}

impl VolumePass {
    /// `constants`: the pass's own overrides (QUADRATURE, PANELS) beside LIGHT and the scene's.
    pub fn new(
        gpu: &Gpu,
        renderer: &SceneRenderer,
        gamma_view: &wgpu::TextureView,
        mesh: f64,
        constants: &[(&'static str, f64)],
    ) -> VolumePass {
        let acc = gpu.texture_2d(
            "light-volume accumulation",
            renderer.width,
            renderer.height,
            ACC_FORMAT,
            wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
        );
        let acc_view = acc.create_view(&Default::default());
        let face_size = std::mem::size_of::<FaceUniform>() as u64;
        let layout = gpu
            .device
            .create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some("light volumes"),
                entries: &[
                    fragment_texture(0),
                    float_texture_array(1, wgpu::ShaderStages::VERTEX),
                    dynamic_uniform(2, wgpu::ShaderStages::VERTEX_FRAGMENT, face_size),
                    fragment_texture(3),
                ],
            });
        let faces = gpu.buffer(&wgpu::BufferDescriptor {
            label: Some("light-volume faces"),
            // Six cube faces per light at most.
            size: FACE_STRIDE * 6 * renderer.scene.desc.lights.len().max(1) as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let bind = gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("light volumes"),
            layout: &layout,
            entries: &[
                view_entry(0, &renderer.distance_view),
                view_entry(1, &renderer.shadows.view),
                slot_entry(2, &faces, face_size),
                view_entry(3, gamma_view),
            ],
        });
        let module = wgsl::module(&gpu.device, "light volumes", &volume_source());
        let pl = pipeline::layout(
            &gpu.device,
            "light volumes",
            &[&renderer.frame_layout, &layout],
        );
        let targets = [pipeline::target(ACC_FORMAT, Some(pipeline::ADDITIVE))];
        let pipelines = (0..renderer.scene.desc.lights.len())
            .map(|k| {
                let own = [&[("LIGHT", k as f64)][..], constants].concat();
                let all = renderer.specialization.with(&own);
                // Both facings drawn; the fragment takes its sign from front_facing
                // (volume.wgsl winds every face outward).
                let pipeline = |vs: &str| {
                    Stage::new("light volume", vs)
                        .fragment("fs_volume", &targets)
                        .build(&gpu.device, &pl, &module, &all)
                };
                (pipeline("vs_grid"), pipeline("vs_walls"))
            })
            .collect();
        VolumePass {
            pipelines,
            bind,
            faces,
            acc_view,
            mesh,
        }
    }

    /// Uploads this frame's faces and draws them (`plans[k]`: light k's volume, if any), into
    /// the cleared accumulation target.
    pub fn encode(
        &self,
        gpu: &Gpu,
        enc: &mut wgpu::CommandEncoder,
        renderer: &SceneRenderer,
        lights: &[scenes::LightState],
        plans: &[Option<LightPlan>],
        report: &mut FrameReport,
    ) {
        let mut data = vec![0u8; self.faces.size() as usize];
        let mut draws = Vec::new();
        for (k, (light, plan)) in lights.iter().zip(plans).enumerate() {
            let Some(plan) = plan else { continue };
            let directional = matches!(light, scenes::LightState::Directional { .. });
            let origin = match light {
                scenes::LightState::Directional { direction, .. } => *direction,
                _ => light.position().unwrap_or_default(),
            };
            let size = renderer.shadows.slots[k].size;
            let samples = samples(size, self.mesh);
            for f in &plan.faces {
                let slot = draws.len() as u64;
                let u = FaceUniform {
                    world_from_clip: f.world_from_clip.to_cols_array_2d(),
                    light: origin.extend(0.0).to_array(),
                    axis: plan.axis.extend(plan.collapse_cos).to_array(),
                    grid: [f.face, size, samples, 0],
                    cap: [plan.cap, 0.0, 0.0, 0.0],
                };
                let off = (slot * FACE_STRIDE) as usize;
                data[off..off + std::mem::size_of::<FaceUniform>()]
                    .copy_from_slice(bytemuck::bytes_of(&u));
                draws.push(Draw {
                    light: k,
                    slot,
                    directional,
                    samples,
                });
            }
        }
        gpu.queue.write_buffer(&self.faces, 0, &data);
        // Counted (harness::gpu pipeline statistics): the volumes' vertex and fragment work.
        let mut pass = gpu.render_pass(
            enc,
            &wgpu::RenderPassDescriptor {
                label: Some("light volumes"),
                color_attachments: &[color_attachment(
                    &self.acc_view,
                    wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
                )],
                ..Default::default()
            },
        );
        pass.set_bind_group(0, &renderer.frame_bind, &[]);
        let mut triangles = 0u64;
        for d in &draws {
            let (grid, walls) = &self.pipelines[d.light];
            pass.set_bind_group(1, &self.bind, &[(d.slot * FACE_STRIDE) as u32]);
            let t = faces::triangles(d.directional, d.samples);
            pass.set_pipeline(grid);
            pass.draw(0..(3 * t.grid) as u32, 0..1);
            if d.directional {
                pass.draw(0..(3 * t.grid) as u32, 1..2);
            }
            pass.set_pipeline(walls);
            pass.draw(0..(3 * t.walls) as u32, 0..1);
            triangles += t.total();
        }
        report.count("volume_faces", draws.len() as f64);
        report.count("volume_triangles", triangles as f64);
    }
}
