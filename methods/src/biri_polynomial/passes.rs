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

use super::geometry::{faces_eye, far_grid, mesh_quad, order_key};
use crate::common::gpu_scene::{GpuScene, Vertex};
use crate::common::renderer::SceneRenderer;
use crate::common::shadow_planes::{Order, ShadowCasters};
use crate::common::stencil;
use crate::common::stencil_surfaces::StencilSurfaceShadows;
use crate::common::uniforms::MAX_LIGHTS;
use crate::common::wgsl;

pub use crate::common::stencil::DEPTH_STENCIL as DEPTH;
/// Uniform slot stride (wgpu's guaranteed minimum dynamic-offset alignment).
const SLOT: u64 = 256;

/// The composed WGSL of the passes.
pub fn source() -> String {
    wgsl::compose(
        &[wgsl::PRELUDE, &[wgsl::FULLSCREEN]].concat(),
        &format!(
            "{}\n{}\n{}\n{}",
            super::KERNEL_WGSL,
            include_str!("passes.wgsl"),
            include_str!("spot.wgsl"),
            include_str!("spot_rays.wgsl")
        ),
    )
}

/// Where Γ is evaluated.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Eval {
    /// Per vertex, Gouraud-interpolated (the paper).
    Vertex,
    /// Per fragment (the modern variant).
    Fragment,
}

/// The accumulation target.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Accumulate {
    /// Rgba32Float, signed sums: exact up to f32 rounding.
    Float,
    /// Rgba8Unorm as on the paper's GeForce 2: total radiance clamped to [0, 1] after every
    /// blend and quantised to 1/255 (§5.2's quantization problem).
    Unorm8,
}

/// The knobs the passes depend on.
#[derive(Clone, Copy, Debug)]
pub struct Config {
    pub eval: Eval,
    pub accumulate: Accumulate,
    /// Subdivision levels of the surfaces (vertex evaluation only).
    pub tessellation: u32,
    /// Strips per shadow plane (vertex evaluation only).
    pub plane_segments: u32,
    /// §4.4's stencil rules; false counts every crossing (exact for disjoint shadow volumes).
    pub stencil_rules: bool,
    /// The per-light uniform: [order, fit, _, _] and the phase series.
    pub order: u32,
    pub fit: u32,
    pub series: [f32; 12],
    /// Spots (eq. 7): half circles per unit of the plane-normal grid (n_u = N, n_φ = 2N).
    pub half_circles: u32,
}

/// `poly` in passes.wgsl, field for field (order and fit are the overrides ORDER and FIT).
#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct PolyUniform {
    light: u32,
    signed_output: u32,
    _pad: [u32; 2],
    series: [f32; 12],
    spot: [u32; 4],
    spot_f: [f32; 4],
}

/// eval = fragment with spots: the per-pixel ray part of eq. 7 (`spot_rays.wgsl`), rebuilt before
/// each spot's stages.
struct SpotRays {
    pipeline: wgpu::ComputePipeline,
    bind: wgpu::BindGroup,
    /// Which lights are spots (frame 0; the kinds are fixed per scene).
    is_spot: Vec<bool>,
    width: u32,
    height: u32,
}

/// One light's planes in the vertex buffer: (vertex range, faces the eye), in drawing order.
struct LightDraws {
    eye_count: u32,
    runs: Vec<(Range<u32>, bool)>,
}

pub struct Passes {
    cfg: Config,
    casters: Option<ShadowCasters>,
    /// The tessellated scene (vertex evaluation) — None: draw the renderer's own meshes.
    tess: Option<GpuScene>,
    grid: Option<(wgpu::Buffer, u32)>,
    depth_view: wgpu::TextureView,
    pub acc_view: wgpu::TextureView,
    layout: wgpu::BindGroupLayout,
    uniform: wgpu::Buffer,
    /// eq. 7's Δ_i tables of every spot (`spot_tables`), one dummy entry without spots.
    delta: wgpu::Buffer,
    /// `spot_rays` layers as the fragments read them (1×1 dummy without `spot_rays`).
    spot_rays_view: wgpu::TextureView,
    spot_rays: Option<SpotRays>,
    depth_pipe: wgpu::RenderPipeline,
    count_pipe: wgpu::RenderPipeline,
    first_pipe: wgpu::RenderPipeline,
    surface_pipe: wgpu::RenderPipeline,
    grid_pipe: wgpu::RenderPipeline,
    /// Float: one pipeline (signed output). unorm8: [entering (add), leaving (reverse subtract)].
    plane_pipes: Vec<wgpu::RenderPipeline>,
    vertices: Option<wgpu::Buffer>,
    draws: Vec<LightDraws>,
}

fn blend(operation: wgpu::BlendOperation) -> wgpu::BlendState {
    let c = wgpu::BlendComponent {
        src_factor: wgpu::BlendFactor::One,
        dst_factor: wgpu::BlendFactor::One,
        operation,
    };
    wgpu::BlendState { color: c, alpha: c }
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
        let kinds = &ctx.scene.features().light_kinds;
        let flag = crate::common::specialize::flag;
        let spot_constants = renderer.specialization.with(&[
            ("ANY_SPOT", flag(kinds.iter().any(|k| *k == "spot"))),
            (
                "ALL_SPOT",
                flag(!kinds.is_empty() && kinds.iter().all(|k| *k == "spot")),
            ),
            ("ORDER", cfg.order.min(8) as f64),
            ("FIT", cfg.fit as f64),
        ]);
        let options = || crate::common::specialize::compile_options(&spot_constants);
        let shadowed = ctx.scene.features().volumetric_occluders;
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
            DEPTH,
            wgpu::TextureUsages::RENDER_ATTACHMENT,
        );
        let acc = tex(
            "biri-poly accumulation",
            acc_format,
            wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
        );
        let texture_entry = crate::common::layouts::fragment_texture;
        let layout = gpu
            .device
            .create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some("biri-poly passes"),
                entries: &[
                    texture_entry(0),
                    wgpu::BindGroupLayoutEntry {
                        binding: 1,
                        visibility: wgpu::ShaderStages::VERTEX_FRAGMENT,
                        ty: wgpu::BindingType::Buffer {
                            ty: wgpu::BufferBindingType::Uniform,
                            has_dynamic_offset: true,
                            min_binding_size: wgpu::BufferSize::new(
                                std::mem::size_of::<PolyUniform>() as u64,
                            ),
                        },
                        count: None,
                    },
                    texture_entry(2),
                    crate::common::layouts::storage_buffer(
                        3,
                        wgpu::ShaderStages::VERTEX_FRAGMENT,
                        true,
                    ),
                    wgpu::BindGroupLayoutEntry {
                        binding: 4,
                        visibility: wgpu::ShaderStages::FRAGMENT,
                        ty: wgpu::BindingType::Texture {
                            sample_type: wgpu::TextureSampleType::Float { filterable: false },
                            view_dimension: wgpu::TextureViewDimension::D2Array,
                            multisampled: false,
                        },
                        count: None,
                    },
                ],
            });
        let uniform = gpu.buffer(&wgpu::BufferDescriptor {
            label: Some("biri-poly lights"),
            size: SLOT * MAX_LIGHTS as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let signed = (cfg.accumulate == Accumulate::Float) as u32;
        let spots = super::spot_tables::build(ctx.scene, cfg.half_circles);
        let delta = gpu.buffer_init(
            "biri-poly spot tables",
            bytemuck::cast_slice(&spots.data),
            wgpu::BufferUsages::STORAGE,
        );
        let slots: Vec<u8> = (0..MAX_LIGHTS as u32)
            .flat_map(|k| {
                let (spot, spot_f) = spots.slots.get(k as usize).copied().unwrap_or_default();
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

        let module = wgsl::module(&gpu.device, "biri-poly passes", &source());
        let is_spot: Vec<bool> = spots.slots.iter().map(|s| s.1[1] > 0.5).collect();
        let per_pixel_spots = !vertex && is_spot.contains(&true);
        // t h β γ_a, the cell, Σ c_i Δ_i(γ_a), then c_0 … c_n
        let layers = if per_pixel_spots {
            4 + cfg.order.min(8)
        } else {
            1
        };
        let (rays_w, rays_h) = if per_pixel_spots {
            (ctx.width, ctx.height)
        } else {
            (1, 1)
        };
        let rays = gpu.texture(&wgpu::TextureDescriptor {
            label: Some("biri-poly spot rays"),
            size: wgpu::Extent3d {
                width: rays_w,
                height: rays_h,
                depth_or_array_layers: layers,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: wgpu::TextureFormat::Rgba32Float,
            usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::STORAGE_BINDING,
            view_formats: &[],
        });
        let rays_view = rays.create_view(&wgpu::TextureViewDescriptor {
            dimension: Some(wgpu::TextureViewDimension::D2Array),
            ..Default::default()
        });
        let spot_rays = per_pixel_spots.then(|| {
            spot_rays(
                gpu,
                renderer,
                &module,
                &uniform,
                &delta,
                &rays_view,
                is_spot,
                (rays_w, rays_h),
                &spot_constants,
            )
        });
        let pl = gpu
            .device
            .create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some("biri-poly passes"),
                bind_group_layouts: &[Some(&renderer.frame_layout), Some(&layout)],
                immediate_size: 0,
            });
        use wgpu::{CompareFunction as C, StencilOperation as S};
        let ds = stencil::depth_stencil;
        let keep = stencil::face(C::Always, S::Keep, S::Keep);
        let lit = stencil::face(C::Equal, S::Keep, S::Keep);
        let plane_layout = stencil::PLANE_LAYOUT;
        let grid_layout = wgpu::VertexBufferLayout {
            array_stride: 8,
            step_mode: wgpu::VertexStepMode::Vertex,
            attributes: &wgpu::vertex_attr_array![0 => Float32x2],
        };
        let pipe = |label: &str,
                    vs: &str,
                    vbuf: Option<wgpu::VertexBufferLayout>,
                    fs: Option<(&str, wgpu::BlendState)>,
                    depth: wgpu::DepthStencilState| {
            let targets = [fs.map(|(_, b)| wgpu::ColorTargetState {
                format: acc_format,
                blend: Some(b),
                write_mask: wgpu::ColorWrites::ALL,
            })];
            gpu.device
                .create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                    label: Some(label),
                    layout: Some(&pl),
                    vertex: wgpu::VertexState {
                        module: &module,
                        entry_point: Some(vs),
                        compilation_options: options(),
                        buffers: &vbuf.into_iter().map(Some).collect::<Vec<_>>(),
                    },
                    // silhouette::extrude winds quads outward in a right-handed sense, which
                    // wgpu's y-up clip space rasterises clockwise: "front" (entering) is Cw.
                    primitive: wgpu::PrimitiveState {
                        cull_mode: None,
                        front_face: wgpu::FrontFace::Cw,
                        ..Default::default()
                    },
                    depth_stencil: Some(depth),
                    multisample: Default::default(),
                    fragment: fs.map(|(fs, _)| wgpu::FragmentState {
                        module: &module,
                        entry_point: Some(fs),
                        compilation_options: options(),
                        targets: &targets,
                    }),
                    multiview_mask: None,
                    cache: None,
                })
        };
        let add = blend(wgpu::BlendOperation::Add);
        let depth_pipe = pipe(
            "biri-poly depth",
            "vs_scene",
            Some(Vertex::LAYOUT),
            None,
            ds(C::Less, true, keep, keep),
        );
        // z-pass count: entering a volume (front face) +1, leaving (back face) −1.
        let count_pipe = pipe(
            "biri-poly count",
            "vs_plane",
            Some(plane_layout.clone()),
            None,
            ds(
                C::Less,
                false,
                stencil::face(C::Always, S::IncrementWrap, S::IncrementWrap),
                stencil::face(C::Always, S::DecrementWrap, S::DecrementWrap),
            ),
        );
        let first_pipe = pipe(
            "biri-poly first pass",
            "vs_fullscreen",
            None,
            Some(("fs_first_pass", add)),
            ds(C::Always, false, keep, keep),
        );
        // Lit points: stencil == reference 0.
        let surface_pipe = if vertex {
            pipe(
                "biri-poly surfaces (vertex)",
                "vs_scene_gouraud",
                Some(Vertex::LAYOUT),
                Some(("fs_gouraud", add)),
                ds(C::LessEqual, false, lit, lit),
            )
        } else {
            pipe(
                "biri-poly surfaces (fragment)",
                "vs_fullscreen",
                None,
                Some(("fs_surface_frag", add)),
                ds(C::Always, false, lit, lit),
            )
        };
        let grid_pipe = pipe(
            "biri-poly far grid",
            "vs_far_grid",
            Some(grid_layout),
            Some(("fs_gouraud", add)),
            ds(C::LessEqual, false, lit, lit),
        );
        // §4.4 with reference 1, front to back: an entering (front) face counts when the stencil
        // is 0 (1 > s), a leaving (back) face when it is 1; entering always +1, leaving −1.
        let (enter, leave) = if cfg.stencil_rules {
            (
                stencil::face(C::Greater, S::IncrementWrap, S::IncrementWrap),
                stencil::face(C::Equal, S::DecrementWrap, S::DecrementWrap),
            )
        } else {
            (
                stencil::face(C::Always, S::IncrementWrap, S::IncrementWrap),
                stencil::face(C::Always, S::DecrementWrap, S::DecrementWrap),
            )
        };
        let (vs_p, fs_p) = if vertex {
            ("vs_plane_gouraud", "fs_plane_gouraud")
        } else {
            ("vs_plane", "fs_plane_frag")
        };
        let plane_pipes = match cfg.accumulate {
            Accumulate::Float => vec![pipe(
                "biri-poly planes",
                vs_p,
                Some(plane_layout),
                Some((fs_p, add)),
                ds(C::Less, false, enter, leave),
            )],
            // One pipeline per side (the CPU knows each planar quad's side): the blend operation
            // differs, and a unorm target cannot hold a negative output.
            Accumulate::Unorm8 => vec![
                pipe(
                    "biri-poly entering planes",
                    vs_p,
                    Some(plane_layout.clone()),
                    Some((fs_p, add)),
                    ds(C::Less, false, enter, enter),
                ),
                pipe(
                    "biri-poly leaving planes",
                    vs_p,
                    Some(plane_layout),
                    Some((fs_p, blend(wgpu::BlendOperation::ReverseSubtract))),
                    ds(C::Less, false, leave, leave),
                ),
            ],
        };
        Passes {
            cfg,
            casters: shadowed.then(|| ShadowCasters::new(ctx.scene)),
            tess,
            grid,
            depth_view: depth.create_view(&Default::default()),
            acc_view: acc.create_view(&Default::default()),
            layout,
            uniform,
            delta,
            spot_rays_view: rays_view,
            spot_rays,
            depth_pipe,
            count_pipe,
            first_pipe,
            surface_pipe,
            grid_pipe,
            plane_pipes,
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
        let mut verts: Vec<[f32; 3]> = Vec::new();
        for (light, state) in planes.iter().zip(&frame.lights) {
            let lpos = state.position().unwrap_or(Vec3::ZERO);
            let mut keyed: Vec<(f32, &[Vec3; 6])> = light
                .quads
                .iter()
                .map(|q| (order_key(q[0], q[1], lpos, eye), q))
                .collect();
            keyed.sort_by(|a, b| a.0.total_cmp(&b.0));
            let mut runs: Vec<(Range<u32>, bool)> = Vec::new();
            for (_, q) in keyed {
                let start = verts.len() as u32;
                verts.extend(mesh_quad(q, segments).iter().map(|p| p.to_array()));
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
        if self
            .vertices
            .as_ref()
            .is_none_or(|b| b.size() < bytes.len() as u64)
        {
            self.vertices = Some(gpu.buffer(&wgpu::BufferDescriptor {
                label: Some("biri-poly planes"),
                size: bytes.len().next_power_of_two() as u64,
                usage: wgpu::BufferUsages::VERTEX | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            }));
        }
        gpu.queue
            .write_buffer(self.vertices.as_ref().expect("allocated"), 0, bytes);
    }

    /// Every pass of every light into `acc_view`.
    pub fn encode(
        &self,
        gpu: &Gpu,
        enc: &mut wgpu::CommandEncoder,
        renderer: &SceneRenderer,
        surface: &wgpu::TextureView,
        surface_shadows: Option<&StencilSurfaceShadows>,
        report: &mut FrameReport,
    ) {
        let bind = gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("biri-poly passes"),
            layout: &self.layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: wgpu::BindingResource::TextureView(&renderer.distance_view),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: wgpu::BindingResource::Buffer(wgpu::BufferBinding {
                        buffer: &self.uniform,
                        offset: 0,
                        size: wgpu::BufferSize::new(std::mem::size_of::<PolyUniform>() as u64),
                    }),
                },
                wgpu::BindGroupEntry {
                    binding: 2,
                    resource: wgpu::BindingResource::TextureView(surface),
                },
                wgpu::BindGroupEntry {
                    binding: 3,
                    resource: self.delta.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 4,
                    resource: wgpu::BindingResource::TextureView(&self.spot_rays_view),
                },
            ],
        });
        let scene = self.tess.as_ref().unwrap_or(&renderer.gpu_scene);
        let draw_scene = |pass: &mut wgpu::RenderPass| scene.draw(pass);
        let ds = |depth: wgpu::LoadOp<f32>, stencil: wgpu::LoadOp<u32>| {
            wgpu::RenderPassDepthStencilAttachment {
                view: &self.depth_view,
                depth_ops: Some(wgpu::Operations {
                    load: depth,
                    store: wgpu::StoreOp::Store,
                }),
                stencil_ops: Some(wgpu::Operations {
                    load: stencil,
                    store: wgpu::StoreOp::Store,
                }),
            }
        };
        let color = |load| {
            [Some(wgpu::RenderPassColorAttachment {
                view: &self.acc_view,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load,
                    store: wgpu::StoreOp::Store,
                },
            })]
        };
        let clear = wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT);
        // Depth of the (tessellated) scene.
        {
            let mut pass = gpu.render_pass(enc, &wgpu::RenderPassDescriptor {
                label: Some("biri-poly depth"),
                depth_stencil_attachment: Some(ds(
                    wgpu::LoadOp::Clear(1.0),
                    wgpu::LoadOp::Clear(0),
                )),
                ..Default::default()
            });
            pass.set_bind_group(0, &renderer.frame_bind, &[]);
            pass.set_bind_group(1, &bind, &[0]);
            pass.set_pipeline(&self.depth_pipe);
            draw_scene(&mut pass);
        }
        let planes = self.vertices.as_ref();
        // §4.3's surface shadows: per light, the count of its volumes around each visible point,
        // then its light removed from the surfaces where the count is not zero.
        if let Some(shadows) = surface_shadows {
            for (k, light) in self.draws.iter().enumerate().take(MAX_LIGHTS) {
                let offset = [(k as u64 * SLOT) as u32];
                {
                    let mut pass = gpu.render_pass(enc, &wgpu::RenderPassDescriptor {
                        label: Some("biri-poly surface-shadow count"),
                        depth_stencil_attachment: Some(ds(
                            wgpu::LoadOp::Load,
                            wgpu::LoadOp::Clear(light.eye_count),
                        )),
                        ..Default::default()
                    });
                    if let Some(v) = planes.filter(|_| !light.runs.is_empty()) {
                        let whole = light.runs.first().map_or(0, |r| r.0.start)
                            ..light.runs.last().map_or(0, |r| r.0.end);
                        pass.set_pipeline(&self.count_pipe);
                        pass.set_bind_group(0, &renderer.frame_bind, &[]);
                        pass.set_bind_group(1, &bind, &offset);
                        pass.set_vertex_buffer(0, v.slice(..));
                        pass.draw(whole, 0..1);
                    }
                }
                shadows.encode(enc, renderer, surface, &self.depth_view, k);
            }
            report.ran("stencil-surface-shadows");
        }
        // §4.3's first pass (surfaces and ambient fog) into the 8-bit target.
        if self.cfg.accumulate == Accumulate::Unorm8 {
            let attachments = color(clear);
            let mut pass = gpu.render_pass(enc, &wgpu::RenderPassDescriptor {
                label: Some("biri-poly first pass"),
                color_attachments: &attachments,
                depth_stencil_attachment: Some(ds(wgpu::LoadOp::Load, wgpu::LoadOp::Load)),
                ..Default::default()
            });
            pass.set_bind_group(0, &renderer.frame_bind, &[]);
            pass.set_bind_group(1, &bind, &[0]);
            pass.set_pipeline(&self.first_pipe);
            pass.draw(0..3, 0..1);
        }
        let mut first = self.cfg.accumulate == Accumulate::Float;
        for (k, light) in self.draws.iter().enumerate().take(MAX_LIGHTS) {
            let offset = [(k as u64 * SLOT) as u32];
            let has_planes = !light.runs.is_empty() && planes.is_some();
            let whole = light.runs.first().map_or(0, |r| r.0.start)
                ..light.runs.last().map_or(0, |r| r.0.end);
            if let Some(rays) = self
                .spot_rays
                .as_ref()
                .filter(|r| r.is_spot.get(k) == Some(&true))
            {
                let mut pass = gpu.compute_pass(enc, &wgpu::ComputePassDescriptor {
                    label: Some("biri-poly spot rays"),
                    timestamp_writes: None,
                });
                pass.set_pipeline(&rays.pipeline);
                pass.set_bind_group(0, &renderer.frame_bind, &[]);
                pass.set_bind_group(1, &rays.bind, &offset);
                pass.dispatch_workgroups(rays.width.div_ceil(8), rays.height.div_ceil(8), 1);
            }
            // Stencil = shadow volumes around each visible point (z-pass from the eye's count).
            {
                let mut pass = gpu.render_pass(enc, &wgpu::RenderPassDescriptor {
                    label: Some("biri-poly count"),
                    depth_stencil_attachment: Some(ds(
                        wgpu::LoadOp::Load,
                        wgpu::LoadOp::Clear(light.eye_count),
                    )),
                    ..Default::default()
                });
                if has_planes {
                    pass.set_pipeline(&self.count_pipe);
                    pass.set_bind_group(0, &renderer.frame_bind, &[]);
                    pass.set_bind_group(1, &bind, &offset);
                    pass.set_vertex_buffer(0, planes.expect("planes").slice(..));
                    pass.draw(whole.clone(), 0..1);
                }
            }
            // Stage 1 of §4.3.2: +Γ(P) where P is lit.
            {
                let load = if first { clear } else { wgpu::LoadOp::Load };
                first = false;
                let attachments = color(load);
                let mut pass = gpu.render_pass(enc, &wgpu::RenderPassDescriptor {
                    label: Some("biri-poly surfaces"),
                    color_attachments: &attachments,
                    depth_stencil_attachment: Some(ds(wgpu::LoadOp::Load, wgpu::LoadOp::Load)),
                    ..Default::default()
                });
                pass.set_bind_group(0, &renderer.frame_bind, &[]);
                pass.set_bind_group(1, &bind, &offset);
                pass.set_stencil_reference(0);
                pass.set_pipeline(&self.surface_pipe);
                match &self.grid {
                    Some((grid, n)) => {
                        draw_scene(&mut pass);
                        pass.set_pipeline(&self.grid_pipe);
                        pass.set_vertex_buffer(0, grid.slice(..));
                        pass.draw(0..*n, 0..1);
                    }
                    None => pass.draw(0..3, 0..1),
                }
            }
            // Stage 2: the planes front to back, stencil re-seeded with the eye's count.
            if has_planes {
                let attachments = color(wgpu::LoadOp::Load);
                let mut pass = gpu.render_pass(enc, &wgpu::RenderPassDescriptor {
                    label: Some("biri-poly planes"),
                    color_attachments: &attachments,
                    depth_stencil_attachment: Some(ds(
                        wgpu::LoadOp::Load,
                        wgpu::LoadOp::Clear(light.eye_count),
                    )),
                    ..Default::default()
                });
                pass.set_bind_group(0, &renderer.frame_bind, &[]);
                pass.set_bind_group(1, &bind, &offset);
                pass.set_stencil_reference(1);
                pass.set_vertex_buffer(0, planes.expect("planes").slice(..));
                if self.plane_pipes.len() == 1 {
                    pass.set_pipeline(&self.plane_pipes[0]);
                    pass.draw(whole, 0..1);
                } else {
                    for (range, front) in &light.runs {
                        pass.set_pipeline(&self.plane_pipes[if *front { 0 } else { 1 }]);
                        pass.draw(range.clone(), 0..1);
                    }
                }
            }
        }
        report.ran("polynomial-surfaces");
        if self.spot_rays.is_some() {
            report.ran("spot-rays");
        }
        if self.casters.is_some() {
            report.ran("shadow-planes");
        } else {
            report.skip("shadow-planes", "no object casts a volumetric shadow");
        }
    }
}

/// The per-pixel spot-ray pass (`cs_spot_rays`): its own group 1 (the light's uniform slot, the
/// Δ tables, the layers it writes).
#[allow(clippy::too_many_arguments)]
fn spot_rays(
    gpu: &Gpu,
    renderer: &SceneRenderer,
    module: &wgpu::ShaderModule,
    uniform: &wgpu::Buffer,
    delta: &wgpu::Buffer,
    rays: &wgpu::TextureView,
    is_spot: Vec<bool>,
    (width, height): (u32, u32),
    constants: &[(&str, f64)],
) -> SpotRays {
    let compute = wgpu::ShaderStages::COMPUTE;
    let layout = gpu
        .device
        .create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("biri-poly spot rays"),
            entries: &[
                wgpu::BindGroupLayoutEntry {
                    binding: 1,
                    visibility: compute,
                    ty: wgpu::BindingType::Buffer {
                        ty: wgpu::BufferBindingType::Uniform,
                        has_dynamic_offset: true,
                        min_binding_size: wgpu::BufferSize::new(
                            std::mem::size_of::<PolyUniform>() as u64
                        ),
                    },
                    count: None,
                },
                crate::common::layouts::storage_buffer(3, compute, true),
                wgpu::BindGroupLayoutEntry {
                    binding: 5,
                    visibility: compute,
                    ty: wgpu::BindingType::StorageTexture {
                        access: wgpu::StorageTextureAccess::WriteOnly,
                        format: wgpu::TextureFormat::Rgba32Float,
                        view_dimension: wgpu::TextureViewDimension::D2Array,
                    },
                    count: None,
                },
            ],
        });
    let bind = gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("biri-poly spot rays"),
        layout: &layout,
        entries: &[
            wgpu::BindGroupEntry {
                binding: 1,
                resource: wgpu::BindingResource::Buffer(wgpu::BufferBinding {
                    buffer: uniform,
                    offset: 0,
                    size: wgpu::BufferSize::new(std::mem::size_of::<PolyUniform>() as u64),
                }),
            },
            wgpu::BindGroupEntry {
                binding: 3,
                resource: delta.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 5,
                resource: wgpu::BindingResource::TextureView(rays),
            },
        ],
    });
    let pl = gpu
        .device
        .create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("biri-poly spot rays"),
            bind_group_layouts: &[Some(&renderer.frame_layout), Some(&layout)],
            immediate_size: 0,
        });
    let pipeline = gpu
        .device
        .create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some("biri-poly spot rays"),
            layout: Some(&pl),
            module,
            entry_point: Some("cs_spot_rays"),
            compilation_options: crate::common::specialize::compile_options(constants),
            cache: None,
        });
    SpotRays {
        pipeline,
        bind,
        is_spot,
        width,
        height,
    }
}
