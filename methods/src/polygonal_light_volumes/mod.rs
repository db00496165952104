//! `polygonal-light-volumes`: Billeter, Sintorn & Assarsson, *Real time volumetric shadows using
//! polygonal light volumes* (High Performance Graphics 2010, doi:10.2312/EGGH/HPG10/039-045).
//! NVIDIA's GameWorks Volumetric Lighting library (Hoobler, *Fast, Flexible, Physically-Based
//! Volumetric Light Scattering*, GDC 2016; Fallout 4) descends from it.
//!
//! Algorithm: a grid mesh in the light's view, one vertex per `1/mesh` shadow-map texels,
//! displaced to the distance the shadow map stores, encloses the part of the light's frustum the
//! light reaches. Rasterised from the eye, each fragment of that closed mesh adds (leaving the
//! volume) or subtracts (entering it) the unshadowed in-scatter F(d) = ∫_0^d from the eye to the
//! fragment; the sum over a pixel is the in-scatter of the lit stretches of its ray only —
//! exact up to the shadow map's resolution, with no per-pixel loop over the ray. Because the
//! volume comes from a shadow map it needs no silhouettes, works for open meshes (the fence)
//! and its cost does not follow the casters' triangle count.
//!
//! Passes (`volume.wgsl`, `volume.rs`, `faces.rs`, `resolve.wgsl`): the shared shadow maps
//! (`common::shadow_maps`: six cube distance maps per point or spot light, one orthographic depth
//! map per directional light) and surface pass; per light and face one non-indexed draw whose
//! vertex shader pulls the stored distance from the shadow map (no CPU read-back, no vertex
//! buffer), each face's volume closed by walls from the light to the face's boundary (so the six
//! volumes of a cube tile the lit space) and a cap where no caster stops the light (beyond the
//! camera's frustum); float32 additive blending into an accumulation target; a resolve that adds
//! it, the unshadowed integral of lights without a volume, the surface and the ambient fog.
//! Directional light uses the complement — the shadow volume behind the stored depth, walls
//! along the light and a far cap — subtracted from the unshadowed integral (Biri et al.'s
//! front-add / back-subtract rule); a light without a caster in its frustum gets no volume
//! (recorded in `FrameReport::skipped`).
//!
//! The integral (`integral.wgsl`): point lights use Biri et al.'s Γ(λ, γ) table, shared with
//! biri-shadow-volumes (`common::gamma`, `common::wgsl::LDSS`): it holds the scene's phase function, so
//! Henyey–Greenstein, Rayleigh and Mie media are exact up to the table. With a spot's falloff and
//! pattern the integral is not closed-form: it is evaluated per fragment by `panels` two-node
//! Gauss–Legendre panels uniform in the angle seen from the light (dx/r² = dφ/h flattens the
//! 1/r² peak), over the ray's stretch inside the outer cone only; `table = 0` uses the same
//! quadrature for point lights. Directional light is closed-form. The quadrature and the closed
//! form are shared (`common/wgsl/light_segments.wgsl`) and dispatched by the per-interval
//! `lit_between` of `common/wgsl/ldss.wgsl`, which both resolves of biri-shadow-volumes use too.
//!
//! Faithful: the displaced shadow-map grid, the closed light volume, the signed accumulation of
//! the unshadowed integral from the eye, the eye inside a volume needing no special case (F(0) =
//! 0), cost independent of the casters. Modernised: vertex pulling (the paper displaced a base
//! mesh by vertex texture fetch), float32 accumulation, no depth test — each fragment evaluates
//! F(min(d, d_scene)) so crossings behind the visible surface cancel in pairs, robust where the
//! grid lies on the very surfaces it was rendered from — and clip z pinned to w/2 so neither
//! camera plane clips a volume. The integral from a table of Biri's Γ instead of the paper's
//! airlight table (Sun et al.'s F(u, v), point lights with isotropic phase only).
//!
//! Limits: visibility at the shadow map's resolution (thin shafts alias below a texel, the
//! walls at depth discontinuities join neighbouring texel centres); the mesh costs 2(n+1)²
//! triangles per face whatever the scene (n = shadow_map × mesh), so large maps need `mesh` < 1;
//! spot quadrature error (measured in README.md); no unorm8 accumulation (the paper's era).
//!
//! Exponential height fog: refused — F(d) comes from the Γ table and the sun's closed form,
//! both for a constant σ_t.

mod faces;
mod shaders;
mod volume;

use anyhow::{Result, bail};
use bytemuck::{Pod, Zeroable};
use harness::gpu::{PhaseTimer, phases};
use harness::method::{PrepareContext, ShaderCheck};
use harness::{
    Aov, ConformanceCase, FrameReport, Gpu, Knob, KnobRead, Medium, Method, MethodInfo, Prepared,
    Support, Targets,
};
use scenes::{FrameState, SceneFeatures};

use crate::common::gamma::GammaTable;
use crate::common::height_fog::constant_sigma_only;
use crate::common::knobs;
use crate::common::renderer::{SceneRenderer, unsupported};
use crate::common::resolve::{self, Bindings, ResolvePass};
use crate::common::shadow_maps::ShadowSettings;
use crate::common::uniforms::LightMask;
pub use shaders::{resolve_wgsl, volume_source};

/// Pattern texture size for spot patterns (texels per side).
const PATTERN_RES: u32 = 512;

/// Mirrors `Config` in resolve.wgsl.
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct ConfigUniform {
    direct: [u32; 4],
}

/// The knobs, read and checked once (`State::new`).
#[derive(Clone, Copy, Debug, PartialEq)]
struct Knobs {
    shadow_map: u32,
    /// Grid samples per face side: shadow_map × mesh.
    samples: u32,
    /// Grid vertices per shadow-map texel along a side (local faces of `local_shadow_map`
    /// texels get that side × mesh samples).
    mesh: f64,
    /// Γ table size per side; 0: per-fragment quadrature for point lights.
    table: u32,
    panels: u32,
}

/// Shadow-map sizes the grid divides evenly at every `mesh`.
const SHADOW_MAPS: &[i64] = &[64, 128, 256, 512, 1024, 2048, 4096, 8192];
const MESHES: [f64; 4] = [1.0, 0.5, 0.25, 0.125];

fn knobs(params: &harness::method::Params) -> Result<Knobs> {
    let shadow_map: u32 = params.knob("shadow_map")?;
    // The declared range is 0.125 ..= 1; the grid needs one of the four steps.
    let mesh: f64 = params.knob("mesh")?;
    if !MESHES.contains(&mesh) {
        bail!("mesh = {mesh}: expected 1, 0.5, 0.25 or 0.125 vertices per texel");
    }
    let table: u32 = params.knob("table")?;
    if (1..16).contains(&table) {
        bail!("table = {table}: expected 0 (per-fragment quadrature) or 16 to 4096");
    }
    Ok(Knobs {
        shadow_map,
        samples: (shadow_map as f64 * mesh) as u32,
        mesh,
        table,
        panels: params.knob("panels")?,
    })
}

/// The method (a description; [`State`] is the prepared instance).
pub struct PolygonalLightVolumes;

/// The prepared method.
pub struct State {
    renderer: SceneRenderer,
    volumes: volume::VolumePass,
    resolve: ResolvePass,
    _table: wgpu::Texture,
    table_view: wgpu::TextureView,
    timer: Option<PhaseTimer>,
}

impl State {
    pub fn new(ctx: &PrepareContext) -> Result<State> {
        let k = knobs(ctx.params)?;
        if let Support::No(why) =
            PolygonalLightVolumes.support(&ctx.scene.features(), ctx.gpu.device.features())
        {
            bail!(why);
        }
        let shadows = ShadowSettings {
            size: k.shadow_map,
            local_budget_mib: ctx.params.knob("local_shadow_budget")?,
        };
        let renderer = SceneRenderer::new(ctx, shadows, PATTERN_RES)?;
        // table = 0 (per-fragment quadrature): a 2×2 stand-in keeps the binding valid.
        let table = if k.table > 0 {
            GammaTable::build(&ctx.scene.medium().background().phase, k.table, k.table)
                .upload(ctx.gpu, "plv gamma")
        } else {
            crate::common::tables::r32_table(ctx.gpu, "plv gamma", 2, 2, &[0.0; 4])
        };
        let table_view = table.create_view(&Default::default());
        let constants = [
            ("QUADRATURE", crate::common::specialize::flag(k.table == 0)),
            ("PANELS", k.panels as f64),
        ];
        let volumes = volume::VolumePass::new(ctx.gpu, &renderer, &table_view, k.mesh, &constants);
        let resolve = ResolvePass::per_light(
            ctx.gpu,
            &renderer,
            "plv resolve",
            &resolve_wgsl(),
            Bindings {
                uniform: Some(std::mem::size_of::<ConfigUniform>() as u64),
                textures: 2,
                texture_arrays: 0,
                counters: 0,
            },
            &constants,
        );
        Ok(State {
            renderer,
            volumes,
            resolve,
            _table: table,
            table_view,
            timer: PhaseTimer::new(ctx.gpu, 4),
        })
    }
}

impl Method for PolygonalLightVolumes {
    fn info(&self) -> MethodInfo {
        harness::method_info!(
            "polygonal-light-volumes",
            Medium::Homogeneous,
            "Billeter, Sintorn, Assarsson, Real time volumetric shadows using polygonal light volumes, HPG 2010",
            "Shadow-map grid displaced into closed light volumes; signed per-fragment unshadowed in-scatter from the eye",
        )
    }

    fn knobs(&self) -> Vec<Knob> {
        vec![
            Knob::int_of("shadow_map", 512, SHADOW_MAPS)
                .sweep([256, 1024, 2048, 4096])
                .unit("texels")
                .meaning("shadow-map resolution per face (a power of two)"),
            knobs::local_shadow_budget(),
            Knob::float("mesh", 0.25, 0.125..=1.0)
                .sweep([1.0, 0.5, 0.125])
                .meaning("light-volume grid vertices per shadow-map texel along each side (1, 0.5, 0.25 or 0.125)"),
            Knob::int("table", 256, 0..=4096)
                .sweep([0, 64, 1024])
                .meaning("point lights: Γ(λ, γ) table size per side (16 to 4096), or 0 for per-fragment quadrature"),
            Knob::int("panels", 8, 1..=128)
                .sweep([2, 4, 16, 32])
                .meaning("spot lights (and table = 0): two-node Gauss-Legendre panels of the per-fragment quadrature"),
        ]
    }

    fn support(&self, scene: &SceneFeatures, _device: wgpu::Features) -> Support {
        let f_of_d = "the unshadowed in-scatter F(d) comes from Biri's Γ table and the sun's closed form, which assume a constant σ_t";
        if let Some(no) = constant_sigma_only(scene, f_of_d) {
            return no;
        }
        match unsupported(scene) {
            Some(why) => Support::No(why),
            None => Support::Full,
        }
    }

    fn prepare(&self, ctx: &PrepareContext) -> Result<Box<dyn Prepared>> {
        Ok(Box::new(State::new(ctx)?))
    }

    fn shaders(&self) -> Vec<ShaderCheck> {
        let axes: &[(&'static str, &[f64])] =
            &[("QUADRATURE", &[0.0, 1.0]), ("LIGHT", &[0.0, 1.0])];
        [
            ShaderCheck::combinations("polygonal-light-volumes/volume", &volume_source(), axes),
            ShaderCheck::combinations(
                "polygonal-light-volumes/resolve",
                &resolve::source(&resolve_wgsl()),
                axes,
            ),
        ]
        .concat()
    }

    /// Measured at 48², default knobs (`run --res 48 --frames 1 --warmup 0`): sphere-point
    /// 0.19 %, fence-spot 6.5 %, window-sun 15.3 % (the grid's resolution, README); bounds
    /// about 1.6–2.6× that.
    fn conformance(&self) -> Vec<ConformanceCase> {
        vec![
            ConformanceCase::new("sphere-point", 48, Aov::Inscatter, 0.005),
            ConformanceCase::new("fence-spot", 48, Aov::Inscatter, 0.12),
            ConformanceCase::new("window-sun", 48, Aov::Inscatter, 0.25),
        ]
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
        let plans = plan_lights(&self.renderer, frame, self.volumes.mesh, &mut report);
        // Directional light's volume is its shadow volume: its unshadowed integral is always
        // added here; a local light's only when it has no volume.
        let direct = frame
            .lights
            .iter()
            .zip(&plans)
            .enumerate()
            .filter(|(_, (l, p))| {
                p.is_none() || matches!(l, scenes::LightState::Directional { .. })
            })
            .fold(LightMask::default(), |mut bits, (k, _)| {
                bits.set(k);
                bits
            });
        if let Some(u) = &self.resolve.uniform {
            let c = ConfigUniform { direct: direct.0 };
            gpu.queue.write_buffer(u, 0, bytemuck::bytes_of(&c));
        }
        phases::mark(&mut self.timer, enc, "shadow");
        self.renderer.encode_shadows(enc, &mut report);
        phases::mark(&mut self.timer, enc, "surface");
        self.renderer.encode_surface(enc, targets, &mut report);
        phases::mark(&mut self.timer, enc, "volume");
        self.volumes
            .encode(gpu, enc, &self.renderer, &frame.lights, &plans, &mut report);
        report.ran("light-volumes");
        phases::mark(&mut self.timer, enc, "resolve");
        self.resolve.encode_with(
            gpu,
            enc,
            &self.renderer,
            targets,
            &[&self.table_view, &self.volumes.acc_view],
        );
        report.ran("resolve");
        phases::finish(&mut self.timer, enc);
        Ok(report)
    }

    fn phase_timer(&self) -> Option<&PhaseTimer> {
        self.timer.as_ref()
    }
}

/// Every light's volume this frame, or None with its skip recorded.
fn plan_lights(
    renderer: &SceneRenderer,
    frame: &FrameState,
    mesh: f64,
    report: &mut FrameReport,
) -> Vec<Option<faces::LightPlan>> {
    let casters = renderer.shadows_on.then(|| {
        let (lo, hi) = crate::common::shadow_maps::caster_bounds(&renderer.scene, frame);
        (0.5 * (lo + hi), 0.5 * (hi - lo).length())
    });
    let aspect = renderer.width as f32 / renderer.height as f32;
    let corners = faces::frustum_corners(frame, aspect);
    frame
        .lights
        .iter()
        .enumerate()
        .map(|(k, light)| {
            let Some(slot) = renderer.shadows.slots.get(k) else {
                report.skip(&format!("light-volume {k}"), "no shadow map (no caster)");
                return None;
            };
            let samples = volume::samples(slot.size, mesh);
            match faces::plan(light, slot, &corners, casters, samples) {
                Ok(p) => Some(p),
                Err(why) => {
                    report.skip(&format!("light-volume {k}"), why);
                    None
                }
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use harness::method::{ParamValue, resolve_params};

    fn params(pairs: &[(&str, ParamValue)]) -> Result<harness::method::Params> {
        let o = harness::testing::knobs(pairs);
        Ok(resolve_params(&PolygonalLightVolumes, &o)?)
    }

    #[test]
    fn knobs_out_of_range_are_refused_not_clamped() {
        assert!(knobs(&params(&[]).unwrap()).is_ok());
        for bad in [
            ("shadow_map", ParamValue::Int(1000)),
            ("shadow_map", ParamValue::Int(32)),
            ("mesh", ParamValue::Float(0.3)),
            ("mesh", ParamValue::Float(2.0)),
            ("table", ParamValue::Int(8)),
            ("panels", ParamValue::Int(0)),
        ] {
            let refused = params(std::slice::from_ref(&bad)).and_then(|p| knobs(&p).map(|_| ()));
            let e = refused.expect_err(bad.0).to_string();
            assert!(e.contains(bad.0), "{e}");
        }
        let p = params(&[
            ("shadow_map", ParamValue::Int(1024)),
            ("mesh", ParamValue::Float(0.25)),
        ]);
        assert_eq!(knobs(&p.unwrap()).unwrap().samples, 256);
    }
}
