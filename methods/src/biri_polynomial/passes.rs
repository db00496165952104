//! biri-polynomial's GPU passes (§4.3–4.5), per light: a stencil count of the shadow volumes at
//! each visible point (z-pass, seeded with the eye's count), the lit surfaces' Γ(P) where the count
//! is 0 (per fragment, or per vertex of the tessellated surfaces and a far-plane grid), then the
//! shadow planes front to back (eq. 13/14 order) adding (front faces) or subtracting (back faces)
//! Γ under §4.4's stencil rules — all blended into one accumulation target, float or unorm8.

use std::ops::Range;

use glam::Vec3;
use harness::method::PrepareContext;
use harness::{FrameReport, Gpu};
use scenes::{FrameState, Scene};

use super::geometry::{faces_eye, far_grid, light_order_key, mesh_quad};
use super::pipelines::Pipelines;
use super::pixel::{Inputs as PixelInputs, PixelPass};
use super::shaders::passes_source;
use super::spot_rays::{self, SpotRays};
use super::types::{Accumulate, Config, Eval, PolyUniform, Resolve, SLOT};
use crate::common::gpu_scene::{GpuScene, write_vertices};
use crate::common::layouts::{dynamic_uniform, float_texture, float_texture_array, storage_buffer};
use crate::common::renderer::SceneRenderer;
use crate::common::shadow_volumes::shadow_planes::{Order, ShadowCasters};
use crate::common::shadow_volumes::stencil::{DEPTH_STENCIL, PlaneVertex};
use crate::common::wgsl;

/// One light's planes in the vertex buffer: (vertex range, faces the eye), in drawing order.
pub(super) struct LightDraws {
    pub(super) eye_count: u32,
    pub(super) runs: Vec<(Range<u32>, bool)>,
}

pub struct Passes {
    pub(super) cfg: Config,
    pub(super) casters: Option<ShadowCasters>,
    /// The tessellated scene (vertex evaluation) — None: draw the renderer's own meshes.
    pub(super) tess: Option<GpuScene>,
    pub(super) grid: Option<(wgpu::Buffer, u32)>,
    pub(super) depth_view: wgpu::TextureView,
    pub acc_view: wgpu::TextureView,
    pub(super) layout: wgpu::BindGroupLayout,
    pub(super) uniform: wgpu::Buffer,
    /// eq. 7's Δ_i tables of every spot (`spot_tables`), one dummy entry without spots.
    pub(super) delta: wgpu::Buffer,
    /// `spot_rays` layers as the fragments read them (1×1 dummy without `spot_rays`).
    pub(super) spot_rays_view: wgpu::TextureView,
    pub(super) spot_rays: Option<SpotRays>,
    pub(super) pipes: Pipelines,
    /// `resolve = per-pixel`: the crossing lists and their passes.
    pub(super) pixel: Option<PixelPass>,
    pub(super) vertices: Option<wgpu::Buffer>,
    pub(super) draws: Vec<LightDraws>,
}

/// A copy of `scene` with every mesh subdivided `levels` times.
fn tessellated(scene: &Scene, levels: u32) -> Scene {
    let mut s = scene.clone();
    s.meshes = scene
        .meshes
        .iter()
        .map(|m| std::sync::Arc::new(scenes::mesh::subdivide::subdivide(m, levels)))
        .collect();
    s
}

impl Passes {
    pub fn new(ctx: &PrepareContext, renderer: &SceneRenderer, cfg: Config) -> Passes {
        let gpu = ctx.gpu;
        let constants = specialization(ctx, renderer, &cfg);
        let vertex = cfg.eval == Eval::Vertex;
        let tess = vertex.then(|| GpuScene::new(gpu, &tessellated(ctx.scene, cfg.tessellation)));
        let grid = vertex.then(|| {
            let g = far_grid(1 << (cfg.tessellation + 1));
            let buf = gpu.buffer_init(
                "biri-poly far grid",
                bytemuck::cast_slice(&g),
                wgpu::BufferUsages::VERTEX,
            );
            (buf, g.len() as u32)
        });
        let acc_format = match cfg.accumulate {
            Accumulate::Float => wgpu::TextureFormat::Rgba32Float,
            Accumulate::Unorm8 => wgpu::TextureFormat::Rgba8Unorm,
        };
        let tex =
            |label, format, usage| gpu.texture_2d(label, ctx.width, ctx.height, format, usage);
        let depth = tex(
            "biri-poly depth-stencil",
            DEPTH_STENCIL,
            wgpu::TextureUsages::RENDER_ATTACHMENT,
        );
        let acc = tex(
            "biri-poly accumulation",
            acc_format,
            wgpu::TextureUsages::RENDER_ATTACHMENT
                | wgpu::TextureUsages::TEXTURE_BINDING
                // The compute walk (`walk = compute`) stores into it.
                | wgpu::TextureUsages::STORAGE_BINDING,
        );
        let layout = bind_group_layout(&gpu.device);
        let spots = super::spot_tables::build(ctx.scene, cfg.half_circles);
        let uniform = light_slots(gpu, &cfg, ctx.scene.desc.lights.len(), &spots.slots);
        let delta = gpu.buffer_init(
            "biri-poly spot tables",
            bytemuck::cast_slice(&spots.data),
            wgpu::BufferUsages::STORAGE,
        );
        let early_depth_test = crate::common::shadow_volumes::crossing_lists::early_depth_test(&gpu.device);
        let module = wgsl::module(
            &gpu.device,
            "biri-poly passes",
            &passes_source(early_depth_test),
        );
        let is_spot: Vec<bool> = match cfg.eval {
            Eval::Vertex => vec![],
            Eval::Fragment => spots.slots.iter().map(|s| s.1[1] > 0.5).collect(),
        };
        let inputs = spot_rays::Inputs {
            module: &module,
            uniform: &uniform,
            delta: &delta,
            constants: &constants,
        };
        let size = (ctx.width, ctx.height);
        let (spot_rays_view, spot_rays) =
            spot_rays::build(gpu, renderer, inputs, is_spot, size, cfg.order);
        let pipes = Pipelines::new(
            &gpu.device,
            [&renderer.frame_layout, &layout],
            &module,
            &constants,
            acc_format,
            &cfg,
        );
        // Without volumetric shadow casters both resolves are the one +Γ(P) pass of the lit
        // surfaces: the lists (and their mid-frame sync) are not built.
        let shadowed = ctx.scene.features().volumetric_occluders;
        let acc_view = acc.create_view(&Default::default());
        let pixel = (cfg.resolve == Resolve::PerPixel && shadowed).then(|| {
            let inputs = PixelInputs {
                layouts: [&renderer.frame_layout, &layout],
                module: &module,
                constants: &constants,
                acc: &acc_view,
                size,
            };
            PixelPass::new(gpu, inputs, ctx.scene.features().lights as u32, cfg.walk)
        });
        Passes {
            cfg,
            casters: shadowed.then(|| ShadowCasters::new(ctx.scene)),
            tess,
            grid,
            depth_view: depth.create_view(&Default::default()),
            acc_view,
            layout,
            uniform,
            delta,
            spot_rays_view,
            spot_rays,
            pipes,
            pixel,
            vertices: None,
            draws: Vec::new(),
        }
    }

    /// CPU side of a frame: silhouettes (cached by `ShadowCasters`), planes re-sorted by the
    /// eq. 13/14 keys, meshed (vertex evaluation), uploaded; the eye's count per light.
    pub fn update(&mut self, gpu: &Gpu, frame: &FrameState, report: &mut FrameReport) {
        self.draws.clear();
        let Some(casters) = self.casters.as_mut() else {
            self.draws = frame
                .lights
                .iter()
                .map(|_| LightDraws {
                    eye_count: 0,
                    runs: vec![],
                })
                .collect();
            return;
        };
        let eye = frame.camera.position;
        let far = frame.camera.far;
        let planes = casters.planes(
            frame,
            Order::FrontToBack,
            |l| 2.0 * (far + (l.position().unwrap_or(eye) - eye).length()) + 1.0,
            report,
        );
        let t0 = std::time::Instant::now();
        let segments = match self.cfg.eval {
            Eval::Vertex => self.cfg.plane_segments.max(1),
            Eval::Fragment => 1,
        };
        let mut verts: Vec<PlaneVertex> = Vec::new();
        for (light, state) in planes.iter().zip(&frame.lights) {
            let lpos = crate::common::shadow_volumes::shadow_planes::light_pos(state);
            let mut keyed: Vec<(f32, &[Vec3; 6])> = light
                .quads
                .iter()
                .map(|q| (light_order_key(q[0], q[1], lpos, eye), q))
                .collect();
            keyed.sort_by(|a, b| a.0.total_cmp(&b.0));
            let mut runs: Vec<(Range<u32>, bool)> = Vec::new();
            for (_, q) in keyed {
                let start = verts.len() as u32;
                verts.extend(PlaneVertex::on_quad(q, mesh_quad(q, segments)));
                let end = verts.len() as u32;
                let front = faces_eye(q, eye);
                match runs.last_mut() {
                    Some((r, f)) if *f == front && r.end == start => r.end = end,
                    _ => runs.push((start..end, front)),
                }
            }
            self.draws.push(LightDraws {
                eye_count: light.eye_count,
                runs,
            });
        }
        report.count("sort_ms", t0.elapsed().as_secs_f64() * 1e3);
        report.count("plane_triangles", (verts.len() / 3) as f64);
        if verts.is_empty() {
            return;
        }
        let bytes: &[u8] = bytemuck::cast_slice(&verts);
        write_vertices(gpu, &mut self.vertices, "biri-poly planes", bytes);
    }
}

/// The scene's overrides plus the passes' own: which lights are spots, the order and the fit.
fn specialization(
    ctx: &PrepareContext,
    renderer: &SceneRenderer,
    cfg: &Config,
) -> Vec<(&'static str, f64)> {
    let kinds = &ctx.scene.features().light_kinds;
    let flag = crate::common::specialize::flag;
    renderer.specialization.with(&[
        ("ANY_SPOT", flag(kinds.contains(&"spot"))),
        (
            "ALL_SPOT",
            flag(!kinds.is_empty() && kinds.iter().all(|k| *k == "spot")),
        ),
        ("ORDER", cfg.order.min(8) as f64),
        ("FIT", cfg.fit as f64),
    ])
}

/// Group 1's layout (see `Passes::bind_group`).
fn bind_group_layout(device: &wgpu::Device) -> wgpu::BindGroupLayout {
    // COMPUTE: the per-pixel resolve's compute walk (`walk = compute`) reads them too.
    let all = wgpu::ShaderStages::VERTEX_FRAGMENT | wgpu::ShaderStages::COMPUTE;
    let pixel = wgpu::ShaderStages::FRAGMENT | wgpu::ShaderStages::COMPUTE;
    let slot = std::mem::size_of::<PolyUniform>() as u64;
    device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("biri-poly passes"),
        entries: &[
            float_texture(0, pixel),
            dynamic_uniform(1, all, slot),
            float_texture(2, pixel),
            storage_buffer(3, all, true),
            float_texture_array(4, pixel),
        ],
    })
}

/// One uniform slot per light of the scene's `lights` (dynamic offsets): its index, the output
/// sign, the phase series and its spot table's header.
fn light_slots(
    gpu: &Gpu,
    cfg: &Config,
    lights: usize,
    spots: &[([u32; 4], [f32; 4])],
) -> wgpu::Buffer {
    let lights = lights.max(1);
    let uniform = gpu.buffer(&wgpu::BufferDescriptor {
        label: Some("biri-poly lights"),
        size: SLOT * lights as u64,
        usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    let signed = (cfg.accumulate == Accumulate::Float) as u32;
    let slots: Vec<u8> = (0..lights as u32)
        .flat_map(|k| {
            let (spot, spot_f) = spots.get(k as usize).copied().unwrap_or_default();
            let u = PolyUniform {
                light: k,
                signed_output: signed,
                _pad: [0; 2],
                series: cfg.series,
                spot,
                spot_f,
            };
            let mut v = vec![0u8; SLOT as usize];
            v[..std::mem::size_of::<PolyUniform>()].copy_from_slice(bytemuck::bytes_of(&u));
            v
        })
        .collect();
    gpu.queue.write_buffer(&uniform, 0, &slots);
    uniform
}
