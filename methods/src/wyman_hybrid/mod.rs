//! `wyman-hybrid`: Wyman & Ramsey, *Interactive Volumetric Shadows in Participating Media with
//! Single-Scattering* (IEEE Symposium on Interactive Ray Tracing 2008).
//!
//! Algorithm: a shadow map from each light; shadow-volume quads extruded from the casters'
//! silhouette edges (as seen from the light, recomputed on the CPU only when a light or an
//! object moved) are rendered from the eye into the nearest and farthest polygon distance per
//! pixel (min / max blending, one channel per light). A full-screen pass then uses Sun et al.'s
//! airlight model — two lookups in a precomputed F(u, v) table ([`airlight`]) — for rays that
//! meet no shadow polygon, and for the parts of other rays before the first and after the last
//! polygon; between them it marches N equal steps testing the shadow map, and integrates each
//! run of lit steps analytically rather than as a Riemann sum.
//!
//! Faithful: the four passes of §3.1, the F(u,v) airlight in the project's convention (see
//! `airlight.rs` for the constant), marching only between shadow polygons, uniform steps between
//! them (Fig. 4 left), angle-uniform steps for spot lights (Fig. 4 right), three segments
//! (before, between, after the shadow) inside the spot's cone (§3.2).
//! Modernised: float targets; the spot's cone interval along each ray is solved analytically
//! instead of rasterising the light frustum's front and back faces; runs of lit steps are merged
//! before the analytic integral (one table lookup pair per run, not per step).
//! Other phase functions than isotropic, and spot lights, use angle-uniform quadrature (the
//! F table is isotropic-only; knob `airlight=false` forces it everywhere to measure the table's
//! error). §3.3's low-resolution scattering (knob `scale`) with a 3×3 depth-aware (bilateral)
//! upsample: the low-resolution pass stores each sample's ray length beside its radiance and the
//! upsample weights neighbours by depth similarity. §3.4's per-frame F'(cos γ, x) table (knob
//! `fprime`, `fprime.wgsl`): airlight values from the eye to x along the direction at angle γ
//! from the light, so an interval costs two lookups; isotropic point lights only.
//! Limits: visibility between the polygons is a shadow-map test (bias, texels); a thin shadow
//! between two steps is missed; the camera being inside a shadow volume is detected with one
//! shadow-map test at the eye.

pub mod airlight;
mod volumes;

use anyhow::Result;
use bytemuck::{Pod, Zeroable};
use glam::Vec3;
use harness::method::{PrepareContext, ShaderCheck};
use harness::{
    Aov, ConformanceCase, FrameReport, Gpu, Knob, KnobRead, Medium, Method, MethodInfo, Prepared,
    Support, Targets,
};
use scenes::{FrameState, LightState, SceneFeatures};

use crate::common::counters::CounterReadback;
use crate::common::knobs;
use crate::common::renderer::{SceneRenderer, homogeneous_support};
use crate::common::resolve::{self, ResolvePass};
use crate::common::silhouette::EdgeMesh;
use crate::common::tables::r32_table;
use crate::common::wgsl;
use airlight::FTable;

pub const VOLUMES_WGSL: &str = include_str!("volumes.wgsl");
pub const AIRLIGHT_WGSL: &str = include_str!("airlight.wgsl");
pub const HYBRID_WGSL: &str = include_str!("hybrid.wgsl");
pub const FPRIME_WGSL: &str = include_str!("fprime.wgsl");

/// The hybrid resolve's own WGSL: the shared airlight module, then the pass.
pub fn hybrid_wgsl() -> String {
    format!("{AIRLIGHT_WGSL}\n{HYBRID_WGSL}")
}

/// The F' table pass's own WGSL.
pub fn fprime_wgsl() -> String {
    format!("{AIRLIGHT_WGSL}\n{FPRIME_WGSL}")
}

/// F' table samples in cos γ (per light) and in x.
const FPRIME_SIZE: u32 = 256;
pub const UPSAMPLE_WGSL: &str = include_str!("upsample.wgsl");

pub fn volumes_source() -> String {
    wgsl::compose(wgsl::PRELUDE, VOLUMES_WGSL)
}

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct VolumeVertex {
    position: [f32; 3],
    light: u32,
}

/// `upsample` in upsample.wgsl, field for field.
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct UpsampleUniform {
    scale: f32,
    bilateral: u32,
    _pad: [u32; 2],
}

/// `hybrid` in airlight.wgsl, field for field.
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct HybridUniform {
    samples: u32,
    table_nu: u32,
    table_nv: u32,
    _pad0: u32,
    table_u_max: f32,
    scale: f32,
    _pad1: [f32; 2],
    fprime_x_max: f32,
    fprime_ng: f32,
    fprime_nx: f32,
    _pad3: f32,
}

/// The method (a description; [`State`] is the prepared instance).
pub struct WymanHybrid;

/// The prepared method.
pub struct State {
    renderer: SceneRenderer,
    /// (object index, adjacency) of every shadow caster.
    casters: Vec<(usize, EdgeMesh)>,
    volumes: wgpu::RenderPipeline,
    vertex_buffer: Option<wgpu::Buffer>,
    vertex_count: u32,
    /// Lights, transforms and eye position the current quads were built for (the extrusion
    /// length depends on the eye).
    built_for: Option<(Vec<LightState>, Vec<glam::Mat4>, Vec3)>,
    /// `--no-skip`: rebuild silhouettes every frame.
    no_skip: bool,
    front_view: wgpu::TextureView,
    back_view: wgpu::TextureView,
    table_view: wgpu::TextureView,
    resolve: ResolvePass,
    /// §3.3: the low-resolution scattering targets and the upsampling pass (scale > 1).
    low: Option<LowRes>,
    /// §3.4: the per-frame F' table and the pass that fills it (knob `fprime`).
    fprime: Option<FPrime>,
    fprime_view: wgpu::TextureView,
    /// Pixels marched and steps taken, counted by the hybrid pass (one frame late).
    counters: CounterReadback,
    uniform: HybridUniform,
    silhouette_edges: usize,
}

const VOLUME_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Float;

struct FPrime {
    pass: ResolvePass,
    table: wgpu::TextureView,
    unused: wgpu::TextureView,
}

struct LowRes {
    inscatter: wgpu::TextureView,
    total: wgpu::TextureView,
    width: u32,
    height: u32,
    upsample: ResolvePass,
}

impl Method for WymanHybrid {
    fn info(&self) -> MethodInfo {
        MethodInfo {
            id: "wyman-hybrid",
            paper: "Wyman & Ramsey, Interactive Volumetric Shadows in Participating Media with Single-Scattering, IEEE RT 2008",
            summary: "Shadow volumes bound where to march; Sun et al.'s analytic airlight elsewhere",
            baseline: false,
            medium: Medium::Homogeneous,
            readme: include_str!("README.md"),
            source: include_str!("mod.rs"),
        }
    }

    fn knobs(&self) -> Vec<Knob> {
        vec![
            // 4096 steps over the shadowed part of every pixel is far past convergence (Fig. 7).
            Knob::int("samples", 50, 1..=4096)
                .sweep([10, 25, 100, 200])
                .unit("steps")
                .meaning("ray-march steps between the first and last shadow polygon (and per lit segment of a spot)"),
            knobs::shadow_map(1024).sweep([512, 2048]),
            Knob::int("table", 256, 2..=4096)
                .sweep([32, 64])
                .unit("samples per side")
                .meaning("F(u,v) table size per side"),
            Knob::boolean("airlight", true)
                .meaning("use the analytic airlight table for isotropic point lights (false: angle-uniform quadrature everywhere)"),
            Knob::int("scale", 1, 1..=16)
                .sweep([2, 4])
                .unit("pixels per side")
                .meaning("scattering computed at 1/scale of the resolution in each direction (§3.3; 4 = 256² of 1024²), then upsampled"),
            Knob::boolean("bilateral", true)
                .meaning("depth-aware 3×3 upsampling of low-resolution scattering (false: plain 3×3 Gaussian)"),
            Knob::boolean("fprime", false)
                .meaning("§3.4: airlight from a per-frame F'(cos γ, x) table (two lookups per interval) instead of the F(u,v) formula"),
            knobs::pattern_res(512),
        ]
    }

    fn support(&self, scene: &SceneFeatures, device: wgpu::Features) -> Support {
        let why = "needs FLOAT32_BLENDABLE (min/max blending of shadow-polygon distances)";
        homogeneous_support(scene, device, Some(why))
    }

    fn prepare(&self, ctx: &PrepareContext) -> Result<Box<dyn Prepared>> {
        Ok(Box::new(State::new(ctx)?))
    }

    fn shaders(&self) -> Vec<ShaderCheck> {
        let flags: &[f64] = &[0.0, 1.0];
        [
            ShaderCheck::combinations("wyman-hybrid/volumes", &volumes_source(), &[]),
            ShaderCheck::combinations(
                "wyman-hybrid/hybrid",
                &resolve::source(&hybrid_wgsl()),
                &[
                    ("AIRLIGHT", flags),
                    ("FPRIME", flags),
                    ("LIGHT", &[0.0, 3.0]),
                ],
            ),
            ShaderCheck::combinations(
                "wyman-hybrid/fprime",
                &resolve::source(&fprime_wgsl()),
                &[("LIGHT", &[0.0, 3.0])],
            ),
            ShaderCheck::combinations(
                "wyman-hybrid/upsample",
                &resolve::source(UPSAMPLE_WGSL),
                &[],
            ),
        ]
        .concat()
    }

    /// Bounds ≈ 1.5–4× the rel RMSE measured at 48² on lavapipe: sphere-point 5e-4, fence-spot
    /// 0.023, sphere-point at scale 2 with F' 0.37 (24² scattering upsampled).
    fn conformance(&self) -> Vec<ConformanceCase> {
        vec![
            ConformanceCase::new("sphere-point", 48, Aov::Inscatter, 0.002),
            ConformanceCase::new("fence-spot", 48, Aov::Inscatter, 0.035),
            ConformanceCase::new("sphere-point", 48, Aov::Inscatter, 0.55)
                .knob("scale", 2)
                .knob("fprime", true),
        ]
    }
}

impl State {
    pub fn new(ctx: &PrepareContext) -> Result<State> {
        let gpu = ctx.gpu;
        let p = ctx.params;
        let samples: u32 = p.knob("samples")?;
        let table_n: u32 = p.knob("table")?;
        let analytic: bool = p.knob("airlight")?;
        let use_fprime: bool = p.knob("fprime")?;
        let scale: u32 = p.knob("scale")?;
        let bilateral: bool = p.knob("bilateral")?;
        let renderer = SceneRenderer::new(ctx, p.knob("shadow_map")?, p.knob("pattern_res")?)?;
        let scene = ctx.scene;
        let casters = scene
            .desc
            .objects
            .iter()
            .enumerate()
            .filter(|(_, o)| o.casts_volumetric_shadow)
            .map(|(k, _)| (k, EdgeMesh::new(&scene.meshes[k])))
            .collect();

        // F's u = σ_t h never exceeds σ_t times the light's distance to the eye (h ≤ that).
        let sigma_t = scene.medium().background().sigma_t.max_element();
        let mut reach = 0.0f32;
        for f in 0..scene.frame_count() {
            let fs = scene.frame(f);
            for l in &fs.lights {
                if let Some(p) = l.position() {
                    reach = reach.max((p - fs.camera.position).length());
                }
            }
        }
        let u_max = (sigma_t * reach * 1.05).max(1e-3);
        let table = FTable::new(table_n, table_n, u_max);
        let table_tex = r32_table(gpu, "F(u,v)", table.nu, table.nv, &table.data);
        let target = |label| {
            gpu.texture_2d(
                label,
                ctx.width,
                ctx.height,
                VOLUME_FORMAT,
                wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
            )
        };
        let (front, back) = (target("shadow-volume front"), target("shadow-volume back"));
        let volumes = volumes::pipeline(gpu, &renderer);
        let flag = crate::common::specialize::flag;
        let resolve = ResolvePass::per_light(
            gpu,
            &renderer,
            "hybrid",
            &hybrid_wgsl(),
            Some(std::mem::size_of::<HybridUniform>() as u64),
            4,
            2,
            &[("AIRLIGHT", flag(analytic)), ("FPRIME", flag(use_fprime))],
        );
        let counters = CounterReadback::new(gpu, 2);
        let render_target = |label, w, h| {
            gpu.texture_2d(
                label,
                w,
                h,
                harness::method::AOV_FORMAT,
                wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
            )
            .create_view(&Default::default())
        };
        let (fprime, fprime_view) = if use_fprime {
            let (w, h) = (
                FPRIME_SIZE * crate::common::uniforms::MAX_LIGHTS as u32,
                FPRIME_SIZE,
            );
            let pass = ResolvePass::per_light(
                gpu,
                &renderer,
                "F' table",
                &fprime_wgsl(),
                Some(std::mem::size_of::<HybridUniform>() as u64),
                3,
                0,
                &[],
            );
            let table = render_target("F' table", w, h);
            (
                Some(FPrime {
                    pass,
                    table: table.clone(),
                    unused: render_target("F' table (unused)", w, h),
                }),
                table,
            )
        } else {
            (None, render_target("F' table (off)", 1, 1))
        };
        let low = (scale > 1).then(|| {
            let (width, height) = (ctx.width.div_ceil(scale), ctx.height.div_ceil(scale));
            let size = std::mem::size_of::<UpsampleUniform>() as u64;
            let upsample = ResolvePass::with_textures(
                gpu,
                &renderer,
                "upsample",
                UPSAMPLE_WGSL,
                Some(size),
                1,
            );
            if let Some(u) = &upsample.uniform {
                let uniform = UpsampleUniform {
                    scale: scale as f32,
                    bilateral: bilateral as u32,
                    _pad: [0; 2],
                };
                gpu.queue.write_buffer(u, 0, bytemuck::bytes_of(&uniform));
            }
            LowRes {
                inscatter: render_target("low-res inscatter", width, height),
                total: render_target("low-res total (unused)", width, height),
                width,
                height,
                upsample,
            }
        });
        let uniform = HybridUniform {
            samples,
            table_nu: table.nu,
            table_nv: table.nv,
            _pad0: 0,
            table_u_max: table.u_max,
            scale: scale as f32,
            _pad1: [0.0; 2],
            fprime_x_max: 1.0, // set per frame
            fprime_ng: FPRIME_SIZE as f32,
            fprime_nx: FPRIME_SIZE as f32,
            _pad3: 0.0,
        };
        Ok(State {
            renderer,
            casters,
            volumes,
            vertex_buffer: None,
            vertex_count: 0,
            built_for: None,
            front_view: front.create_view(&Default::default()),
            back_view: back.create_view(&Default::default()),
            table_view: table_tex.create_view(&Default::default()),
            no_skip: ctx.no_skip,
            resolve,
            low,
            fprime,
            fprime_view,
            counters,
            uniform,
            silhouette_edges: 0,
        })
    }
}

impl Prepared for State {
    fn render(
        &mut self,
        gpu: &Gpu,
        frame: &FrameState,
        targets: &Targets,
        enc: &mut wgpu::CommandEncoder,
    ) -> Result<FrameReport> {
        let mut report = self.renderer.start_frame(gpu, frame);
        // F' spans x up to the longest camera ray (a corner ray to the far plane).
        let rays = frame.camera.rays(targets.width, targets.height);
        let corner = rays.direction(0, 0);
        self.uniform.fprime_x_max = (rays.far_distance(corner) * 1.001) as f32;
        for u in self
            .resolve
            .uniform
            .iter()
            .chain(self.fprime.as_ref().and_then(|f| f.pass.uniform.as_ref()))
        {
            gpu.queue
                .write_buffer(u, 0, bytemuck::bytes_of(&self.uniform));
        }
        let counter_buf = self.resolve.counters.clone().expect("hybrid pass counts");
        self.counters.begin_frame(gpu, &counter_buf);
        if let Some(c) = self.counters.latest() {
            report.count("pixels_marched", c[0] as f64);
            report.count("steps", c[1] as f64);
        }
        self.renderer.encode_shadows(enc, &mut report);
        self.renderer.encode_surface(enc, targets, &mut report);

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
        } else if !self.casters.is_empty() {
            volumes::build(gpu, self, frame);
            self.built_for = Some(key);
            report.ran("silhouettes");
        }
        report.count("silhouette_edges", self.silhouette_edges as f64);
        report.count("shadow_polygons", (self.vertex_count / 6) as f64);
        {
            let clear = |v: f64| wgpu::Operations {
                load: wgpu::LoadOp::Clear(wgpu::Color {
                    r: v,
                    g: v,
                    b: v,
                    a: v,
                }),
                store: wgpu::StoreOp::Store,
            };
            let mut pass = gpu.render_pass(
                enc,
                &wgpu::RenderPassDescriptor {
                    label: Some("shadow volumes"),
                    color_attachments: &[
                        Some(wgpu::RenderPassColorAttachment {
                            view: &self.front_view,
                            depth_slice: None,
                            resolve_target: None,
                            ops: clear(1e30),
                        }),
                        Some(wgpu::RenderPassColorAttachment {
                            view: &self.back_view,
                            depth_slice: None,
                            resolve_target: None,
                            ops: clear(-1.0),
                        }),
                    ],
                    ..Default::default()
                },
            );
            if let (Some(vb), true) = (&self.vertex_buffer, self.vertex_count > 0) {
                pass.set_pipeline(&self.volumes);
                pass.set_bind_group(0, &self.renderer.frame_bind, &[]);
                pass.set_vertex_buffer(0, vb.slice(..));
                pass.draw(0..self.vertex_count, 0..1);
            }
        }
        if self.casters.is_empty() && !self.no_skip {
            report.skip(
                "shadow-volumes",
                "no object casts a volumetric shadow: airlight only",
            );
        } else {
            report.ran("shadow-volumes");
        }
        if let Some(fp) = &self.fprime {
            let t = Targets {
                inscatter: &fp.table,
                surface: targets.surface,
                total: &fp.unused,
                width: FPRIME_SIZE * crate::common::uniforms::MAX_LIGHTS as u32,
                height: FPRIME_SIZE,
            };
            fp.pass.encode_with(
                gpu,
                enc,
                &self.renderer,
                &t,
                &[&self.front_view, &self.back_view, &self.table_view],
            );
            report.ran("fprime-table");
        }
        let extra = [
            &self.front_view,
            &self.back_view,
            &self.table_view,
            &self.fprime_view,
        ];
        match &self.low {
            None => self
                .resolve
                .encode_with(gpu, enc, &self.renderer, targets, &extra),
            Some(low) => {
                let low_targets = Targets {
                    inscatter: &low.inscatter,
                    surface: targets.surface,
                    total: &low.total,
                    width: low.width,
                    height: low.height,
                };
                self.resolve
                    .encode_with(gpu, enc, &self.renderer, &low_targets, &extra);
                low.upsample
                    .encode_with(gpu, enc, &self.renderer, targets, &[&low.inscatter]);
                report.ran("upsample");
            }
        }
        self.counters.end_frame(enc, &counter_buf);
        report.ran("hybrid");
        report.count(
            "scattering_pixels",
            self.low
                .as_ref()
                .map_or(targets.width * targets.height, |l| l.width * l.height) as f64,
        );
        Ok(report)
    }
}
