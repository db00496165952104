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
//! upsample weights neighbours by depth similarity. The shadow volumes are rasterised at that
//! low resolution too, each pixel at the very ray the low-resolution pass marches
//! (`volumes.rs`): the same distances for 1/scale² of the fill. §3.4's per-frame F'(cos γ, x)
//! table (knob `fprime`, `fprime.wgsl`): airlight values from the eye to x along the direction
//! at angle γ from the light, so an interval costs two lookups; isotropic point lights only.
//! Limits: visibility between the polygons is a shadow-map test (bias, texels); a thin shadow
//! between two steps is missed; the camera being inside a shadow volume is detected with one
//! shadow-map test at the eye.
//!
//! Exponential height fog: refused — Sun et al.'s airlight F(u, v) assumes a constant σ_t.

pub mod airlight;
mod shaders;
mod volumes;

use anyhow::Result;
use bytemuck::{Pod, Zeroable};
use harness::method::{AOV_FORMAT, PrepareContext, ShaderCheck};
use harness::{
    Aov, ConformanceCase, FrameReport, Gpu, Knob, KnobRead, Medium, Method, MethodInfo, Prepared,
    Support, Targets,
};
use scenes::{FrameState, Scene, SceneFeatures};

use crate::common::counters::CounterReadback;
use crate::common::height_fog::constant_sigma_only;
use crate::common::knobs;
use crate::common::renderer::{SceneRenderer, homogeneous_support};
use crate::common::resolve::{self, Bindings, ResolvePass};
use crate::common::shadow_maps::ShadowSettings;
use crate::common::tables::r32_table;
use airlight::FTable;
use shaders::UPSAMPLE_WGSL;
pub use shaders::{fprime_wgsl, hybrid_wgsl, volumes_source};
use volumes::ShadowVolumes;

/// F' table samples in cos γ (per light) and in x.
const FPRIME_SIZE: u32 = 256;
/// Lights' F' bands per row of the table (airlight.wgsl's `FPRIME_BANDS_PER_ROW`): 4096 texels
/// wide at most, rows added as lights are.
const FPRIME_BANDS_PER_ROW: u32 = 16;

/// The F' table's size for `lights` lights: bands of FPRIME_SIZE², FPRIME_BANDS_PER_ROW a row.
fn fprime_table_size(lights: u32) -> (u32, u32) {
    let lights = lights.max(1);
    let cols = lights.min(FPRIME_BANDS_PER_ROW);
    (
        FPRIME_SIZE * cols,
        FPRIME_SIZE * lights.div_ceil(FPRIME_BANDS_PER_ROW),
    )
}

/// Light k's band of the F' table: x, y, width, height (texels).
fn fprime_band(k: usize) -> [u32; 4] {
    let k = k as u32;
    let (col, row) = (k % FPRIME_BANDS_PER_ROW, k / FPRIME_BANDS_PER_ROW);
    [
        col * FPRIME_SIZE,
        row * FPRIME_SIZE,
        FPRIME_SIZE,
        FPRIME_SIZE,
    ]
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
    /// §3.1's shadow volumes: the quads and the nearest / farthest polygon distances.
    volumes: ShadowVolumes,
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
}

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

/// A `width` × `height` AOV-format target a full-screen pass renders into and a later one reads.
fn render_target(gpu: &Gpu, label: &str, width: u32, height: u32) -> wgpu::TextureView {
    gpu.texture_2d(
        label,
        width,
        height,
        AOV_FORMAT,
        wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
    )
    .create_view(&Default::default())
}

/// The F(u, v) table for `scene`: F's u = σ_t h never exceeds σ_t times a light's distance to
/// the eye (h ≤ that), over every frame.
fn f_table(scene: &Scene, n: u32) -> FTable {
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
    FTable::new(n, n, u_max)
}

impl FPrime {
    /// The F' table as wide as every light's rows, and the pass that fills it.
    fn new(gpu: &Gpu, renderer: &SceneRenderer) -> FPrime {
        let (w, h) = fprime_table_size(renderer.scene.desc.lights.len() as u32);
        let pass = ResolvePass::per_light(
            gpu,
            renderer,
            "F' table",
            &fprime_wgsl(),
            Bindings {
                uniform: Some(std::mem::size_of::<HybridUniform>() as u64),
                textures: 3,
                // The shadow-volume distances (3, 4) are arrays: four lights a layer.
                texture_arrays: 0b11,
                counters: 0,
            },
            &[],
        )
        .with_light_rects(fprime_band);
        FPrime {
            pass,
            table: render_target(gpu, "F' table", w, h),
            unused: render_target(gpu, "F' table (unused)", w, h),
        }
    }
}

impl LowRes {
    /// Scattering at 1/`scale` of `width` × `height` and its depth-aware (`bilateral`) upsample.
    fn new(gpu: &Gpu, renderer: &SceneRenderer, scale: u32, bilateral: bool) -> LowRes {
        let (width, height) = volumes::low_res_size(renderer, scale);
        let size = std::mem::size_of::<UpsampleUniform>() as u64;
        let upsample =
            ResolvePass::with_textures(gpu, renderer, "upsample", UPSAMPLE_WGSL, Some(size), 1);
        if let Some(u) = &upsample.uniform {
            let uniform = UpsampleUniform {
                scale: scale as f32,
                bilateral: bilateral as u32,
                _pad: [0; 2],
            };
            gpu.queue.write_buffer(u, 0, bytemuck::bytes_of(&uniform));
        }
        LowRes {
            inscatter: render_target(gpu, "low-res inscatter", width, height),
            total: render_target(gpu, "low-res total (unused)", width, height),
            width,
            height,
            upsample,
        }
    }
}

impl Method for WymanHybrid {
    fn info(&self) -> MethodInfo {
        harness::method_info!(
            "wyman-hybrid",
            Medium::Homogeneous,
            "Wyman & Ramsey, Interactive Volumetric Shadows in Participating Media with Single-Scattering, IEEE RT 2008",
            "Shadow volumes bound where to march; Sun et al.'s analytic airlight elsewhere",
        )
    }

    fn knobs(&self) -> Vec<Knob> {
        vec![
            // 4096 steps over the shadowed part of every pixel is far past convergence (Fig. 7).
            Knob::int("samples", 50, 1..=4096)
                .sweep([10, 25, 100, 200])
                .unit("steps")
                .meaning("ray-march steps between the first and last shadow polygon (and per lit segment of a spot)"),
            knobs::shadow_map(1024).sweep([512, 2048]),
            knobs::local_shadow_budget(),
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
        let airlight =
            "Sun et al.'s airlight F(u, v) and the sun's closed form assume a constant σ_t";
        if let Some(no) = constant_sigma_only(scene, airlight) {
            return no;
        }
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
        let analytic: bool = p.knob("airlight")?;
        let use_fprime: bool = p.knob("fprime")?;
        let scale: u32 = p.knob("scale")?;
        let bilateral: bool = p.knob("bilateral")?;
        let renderer =
            SceneRenderer::new(ctx, ShadowSettings::from_params(p)?, p.knob("pattern_res")?)?;
        let table = f_table(ctx.scene, p.knob("table")?);
        let table_tex = r32_table(gpu, "F(u,v)", table.nu, table.nv, &table.data);
        let volumes = ShadowVolumes::new(gpu, &renderer, scale, ctx.no_skip);
        let flag = crate::common::specialize::flag;
        let resolve = ResolvePass::per_light(
            gpu,
            &renderer,
            "hybrid",
            &hybrid_wgsl(),
            Bindings {
                uniform: Some(std::mem::size_of::<HybridUniform>() as u64),
                textures: 4,
                texture_arrays: 0b11,
                counters: 2,
            },
            &[("AIRLIGHT", flag(analytic)), ("FPRIME", flag(use_fprime))],
        );
        let fprime = use_fprime.then(|| FPrime::new(gpu, &renderer));
        let fprime_view = match &fprime {
            Some(f) => f.table.clone(),
            None => render_target(gpu, "F' table (off)", 1, 1),
        };
        let low = (scale > 1).then(|| LowRes::new(gpu, &renderer, scale, bilateral));
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
            volumes,
            table_view: table_tex.create_view(&Default::default()),
            resolve,
            low,
            fprime,
            fprime_view,
            counters: CounterReadback::new(gpu, 2),
            uniform,
        })
    }

    /// This frame's uniform of the hybrid and F' passes: F' spans x up to the longest camera
    /// ray (a corner ray to the far plane).
    fn write_uniform(&mut self, gpu: &Gpu, frame: &FrameState, targets: &Targets) {
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
    }

    /// §3.4's F' table (if on), then the hybrid pass per light — at full resolution, or at
    /// 1/scale and upsampled (§3.3).
    fn encode_scattering(
        &self,
        gpu: &Gpu,
        enc: &mut wgpu::CommandEncoder,
        targets: &Targets,
        report: &mut FrameReport,
    ) {
        let volumes = [&self.volumes.front_view, &self.volumes.back_view];
        if let Some(fp) = &self.fprime {
            let (width, height) = fprime_table_size(self.renderer.scene.desc.lights.len() as u32);
            let t = Targets {
                inscatter: &fp.table,
                surface: targets.surface,
                total: &fp.unused,
                width,
                height,
            };
            let extra = [volumes[0], volumes[1], &self.table_view];
            fp.pass.encode_with(gpu, enc, &self.renderer, &t, &extra);
            report.ran("fprime-table");
        }
        let extra = [volumes[0], volumes[1], &self.table_view, &self.fprime_view];
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
        self.write_uniform(gpu, frame, targets);
        let counter_buf = self.resolve.counters.clone().expect("hybrid pass counts");
        self.counters.begin_frame(gpu, &counter_buf);
        if let Some(c) = self.counters.latest() {
            report.count("pixels_marched", c[0] as f64);
            report.count("steps", c[1] as f64);
        }
        self.renderer.encode_shadows_and_surface(enc, targets, &mut report);
        self.volumes.update(gpu, frame, &mut report);
        self.volumes.encode(gpu, enc, &self.renderer, &mut report);
        self.encode_scattering(gpu, enc, targets, &mut report);
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
