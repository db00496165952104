//! wyman-hybrid's shadow volumes (§3.1): the quads extruded from the casters' silhouettes as
//! seen from each light (rebuilt on the CPU only when a light, an object or the eye moved), and
//! the pass that rasterises them from the eye into the nearest and farthest polygon distance per
//! pixel (min / max blending, one channel per light: lights 4g … 4g + 3 in layer g of two
//! array targets, one pass per layer).
//!
//! At `scale` > 1 (§3.3) the targets have the scattering pass's low resolution, and the
//! viewport is shifted by a fraction of a pixel so that each low-resolution pixel's centre is
//! the full-resolution ray that pass marches ([`low_res_viewport`]): the distances are those
//! a full-resolution target held at those pixels, for 1/scale² of the fill.

use bytemuck::{Pod, Zeroable};
use glam::{Mat4, Vec3};
use harness::gpu::color_attachment;
use harness::{FrameReport, Gpu};
use scenes::{FrameState, LightState};

use super::shaders::volumes_source;
use crate::common::gpu_scene::write_vertices;
use crate::common::layered::Layered;
use crate::common::pipeline::{self, MAX, MIN, Stage, both, target};
use crate::common::renderer::SceneRenderer;
use crate::common::shadow_volumes::shadow_planes::{ShadowCasters, light_pos};
use crate::common::shadow_volumes::silhouette::extrude;
use crate::common::wgsl;

/// The nearest and farthest polygon distance targets.
const VOLUME_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Float;
/// Lights per layer of the targets: one channel each.
const LIGHTS_PER_LAYER: usize = 4;
/// What a target holds where no polygon was drawn: the nearest is "far", the farthest "none".
const NO_NEAREST: f64 = 1e30;
const NO_FARTHEST: f64 = -1.0;

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct VolumeVertex {
    position: [f32; 3],
    light: u32,
}

/// The shadow-volume quads of every caster and light, and the two distance targets.
pub(super) struct ShadowVolumes {
    casters: ShadowCasters,
    pipeline: wgpu::RenderPipeline,
    vertex_buffer: Option<wgpu::Buffer>,
    vertex_count: u32,
    /// Per layer of the targets: its lights' quads' vertex range.
    layer_ranges: Vec<std::ops::Range<u32>>,
    /// Lights, transforms and eye position the current quads were built for (the extrusion
    /// length depends on the eye).
    built_for: Option<(Vec<LightState>, Vec<Mat4>, Vec3)>,
    /// `--no-skip`: rebuild silhouettes every frame.
    no_skip: bool,
    /// x, y, width, height of the pass's viewport ([`low_res_viewport`]).
    viewport: [f32; 4],
    silhouette_edges: usize,
    /// The targets as arrays (for the hybrid pass) and per layer (for drawing).
    pub front_view: wgpu::TextureView,
    pub back_view: wgpu::TextureView,
    layer_views: Vec<[wgpu::TextureView; 2]>,
}

impl ShadowVolumes {
    /// The quads' pass into targets at 1/`scale` of the renderer's resolution.
    pub fn new(gpu: &Gpu, renderer: &SceneRenderer, scale: u32, no_skip: bool) -> ShadowVolumes {
        let layers = renderer
            .scene
            .desc
            .lights
            .len()
            .div_ceil(LIGHTS_PER_LAYER)
            .max(1) as u32;
        let viewport = low_res_viewport(renderer.width, renderer.height, scale);
        let size = low_res_size(renderer, scale);
        let target = |label| Layered::new(gpu, label, size, layers, VOLUME_FORMAT);
        let (front, back) = (target("shadow-volume front"), target("shadow-volume back"));
        ShadowVolumes {
            casters: ShadowCasters::new(&renderer.scene),
            pipeline: volume_pipeline(gpu, renderer),
            vertex_buffer: None,
            vertex_count: 0,
            layer_ranges: Vec::new(),
            built_for: None,
            no_skip,
            viewport,
            silhouette_edges: 0,
            layer_views: (front.layers.into_iter().zip(back.layers))
                .map(|(f, b)| [f, b])
                .collect(),
            front_view: front.array,
            back_view: back.array,
        }
    }

    fn no_casters(&self) -> bool {
        self.casters.casters().is_empty()
    }

    /// Rebuilds the quads when a light, a caster or the eye moved (always with `no_skip`), and
    /// counts `silhouette_edges` and `shadow_polygons`.
    pub fn update(&mut self, gpu: &Gpu, frame: &FrameState, report: &mut FrameReport) {
        let key = (
            frame.lights.clone(),
            frame.world_from_local.clone(),
            frame.camera.position,
        );
        if !self.no_skip && self.built_for.as_ref() == Some(&key) {
            report.skip(
                "silhouettes",
                "lights and occluders unchanged since the last frame",
            );
        } else if !self.no_casters() {
            self.build(gpu, frame);
            self.built_for = Some(key);
            report.ran("silhouettes");
        }
        report.count("silhouette_edges", self.silhouette_edges as f64);
        report.count("shadow_polygons", (self.vertex_count / 6) as f64);
    }

    /// Silhouettes of every caster from every light, extruded past everything visible.
    fn build(&mut self, gpu: &Gpu, frame: &FrameState) {
        let cam = frame.camera.position;
        let mut verts: Vec<VolumeVertex> = Vec::new();
        let mut edges = 0;
        self.layer_ranges.clear();
        for (k, light) in frame.lights.iter().enumerate() {
            if k % LIGHTS_PER_LAYER == 0 {
                let start = verts.len() as u32;
                self.layer_ranges.push(start..start);
            }
            let pos = light_pos(light);
            let reach = 2.0
                * (frame.camera.far + light.position().map_or(0.0, |p| (p - cam).length()))
                + 1.0;
            for (obj, mesh) in self.casters.casters() {
                for e in mesh.silhouette(&frame.world_from_local[*obj], pos) {
                    edges += 1;
                    verts.extend(extrude(e, pos, reach).map(|p: Vec3| VolumeVertex {
                        position: p.to_array(),
                        light: k as u32,
                    }));
                }
            }
            if let Some(r) = self.layer_ranges.last_mut() {
                r.end = verts.len() as u32;
            }
        }
        self.silhouette_edges = edges;
        self.vertex_count = verts.len() as u32;
        if verts.is_empty() {
            return;
        }
        let bytes: &[u8] = bytemuck::cast_slice(&verts);
        write_vertices(gpu, &mut self.vertex_buffer, "shadow-volume quads", bytes);
    }

    /// The nearest and farthest polygon distances per pixel (targets cleared even without
    /// quads, so the hybrid pass reads "no shadow polygon" there).
    pub fn encode(
        &self,
        gpu: &Gpu,
        enc: &mut wgpu::CommandEncoder,
        renderer: &SceneRenderer,
        report: &mut FrameReport,
    ) {
        let clear = |v: f64| {
            wgpu::LoadOp::Clear(wgpu::Color {
                r: v,
                g: v,
                b: v,
                a: v,
            })
        };
        for (k, [front, back]) in self.layer_views.iter().enumerate() {
            let mut pass = gpu.render_pass(
                enc,
                &wgpu::RenderPassDescriptor {
                    label: Some("shadow volumes"),
                    color_attachments: &[
                        color_attachment(front, clear(NO_NEAREST)),
                        color_attachment(back, clear(NO_FARTHEST)),
                    ],
                    ..Default::default()
                },
            );
            let range = self.layer_ranges.get(k).filter(|r| !r.is_empty());
            if let (Some(vb), Some(range), true) =
                (&self.vertex_buffer, range, self.vertex_count > 0)
            {
                let [x, y, w, h] = self.viewport;
                pass.set_viewport(x, y, w, h, 0.0, 1.0);
                pass.set_pipeline(&self.pipeline);
                pass.set_bind_group(0, &renderer.frame_bind, &[]);
                pass.set_vertex_buffer(0, vb.slice(..));
                pass.draw(range.clone(), 0..1);
            }
        }
        if self.no_casters() && !self.no_skip {
            report.skip(
                "shadow-volumes",
                "no object casts a volumetric shadow: airlight only",
            );
        } else {
            report.ran("shadow-volumes");
        }
    }
}

/// The scattering pass's resolution at 1/`scale` of the renderer's (rounded up): also the
/// shadow-volume targets', since that pass reads them at its own fragment.
pub(super) fn low_res_size(renderer: &SceneRenderer, scale: u32) -> (u32, u32) {
    (
        renderer.width.div_ceil(scale),
        renderer.height.div_ceil(scale),
    )
}

/// The viewport (x, y, width, height in target pixels) that draws a `width` × `height` view
/// into a target of 1/`scale` its size such that low-resolution pixel i's centre is the ray
/// through full-resolution pixel `scale`·i + ⌊scale/2⌋ — the pixel `hybrid.wgsl` marches for
/// it. A full-resolution x lands at x/scale + the origin; that pixel's centre, offset by half a
/// pixel from the block's centre when `scale` is even, must land at i + ½.
fn low_res_viewport(width: u32, height: u32, scale: u32) -> [f32; 4] {
    let s = scale as f32;
    let origin = ((s * 0.5).floor() + 0.5 - 0.5 * s) / -s;
    [origin, origin, width as f32 / s, height as f32 / s]
}

/// The pipeline that draws the shadow-volume quads from the eye into the nearest (min blending)
/// and farthest (max blending) polygon distance per pixel, one channel per light.
fn volume_pipeline(gpu: &Gpu, renderer: &SceneRenderer) -> wgpu::RenderPipeline {
    let module = wgsl::module(&gpu.device, "shadow volumes", &volumes_source());
    let layout = pipeline::layout(&gpu.device, "shadow volumes", &[&renderer.frame_layout]);
    let targets = [
        target(VOLUME_FORMAT, Some(both(MIN))),
        target(VOLUME_FORMAT, Some(both(MAX))),
    ];
    let vertex_layout = wgpu::VertexBufferLayout {
        array_stride: std::mem::size_of::<VolumeVertex>() as u64,
        step_mode: wgpu::VertexStepMode::Vertex,
        attributes: &wgpu::vertex_attr_array![0 => Float32x3, 1 => Uint32],
    };
    Stage::new("shadow volumes", "vs")
        .vertices(vertex_layout)
        .fragment("fs", &targets)
        .build(&gpu.device, &layout, &module, &[])
}

#[cfg(test)]
mod tests {
    use super::low_res_viewport;

    /// Where the viewport puts full-resolution x: origin + x / scale (the viewport transform
    /// with the view's width scaled by 1/scale).
    fn lands(x: f32, width: u32, scale: u32) -> f32 {
        let [origin, _, w, _] = low_res_viewport(width, width, scale);
        origin + x * w / width as f32
    }

    #[test]
    fn each_low_res_pixel_centre_is_the_full_res_pixel_the_hybrid_pass_marches() {
        for scale in 1..=16u32 {
            for i in [0u32, 1, 7, 31] {
                // hybrid.wgsl: full = floor(frag.xy − 0.5) · scale + floor(0.5 · scale) + 0.5
                let full = (i * scale + scale / 2) as f32 + 0.5;
                let at = lands(full, 512, scale);
                assert!(
                    (at - (i as f32 + 0.5)).abs() < 1e-4,
                    "scale {scale}, pixel {i}: {at}"
                );
            }
        }
    }
}
