//! `biri-polynomial`: Biri, Michelin & Arquès, *Real-time single scattering with volumetric
//! shadows* (the earlier, software-assisted version of Biri et al. 2006) — the angular RTE with
//! a polynomial kernel.
//!
//! Algorithm: along a camera ray the in-scattered radiance is rewritten in the angle θ between
//! the ray point and the light's foot on the ray (x = t + h tanθ, eq. 3): L_in = σ_s I e^(−σ_t t)/h
//! ∫ Λ(θ) dθ with Λ(θ) = e^(−σ_t h (sinθ+1)/cosθ) p(θ + π/2) (eq. 4). Λ is replaced by a
//! polynomial of order n, so Γ(M), the contribution from the eye to a point M (eq. 11), costs a
//! constant number of operations (eq. 6). A ray's lit parts are a signed sum of Γ values (eq. 12):
//! +Γ at a lit surface point, +Γ where it enters a shadow (front-facing shadow plane), −Γ where it
//! leaves one (back-facing plane). So, per light (§4.3–4.5): a z-pass stencil count of the
//! silhouette shadow planes (seeded with the eye's count) marks the lit surfaces, which get +Γ(P);
//! then the planes are drawn front to back in the order of eq. 13/14's distances, adding or
//! subtracting Γ under §4.4's stencil rules (an entering plane counts where the stencil is 0, a
//! leaving one where it is 1; entering +1, leaving −1), so planes inside another shadow drop out.
//!
//! Faithful: Γ by the Taylor polynomial of the annex (any order; `fit: taylor`), evaluated per
//! VERTEX with Gouraud interpolation on subdivided surfaces (`eval: vertex`, `tessellation`) and on
//! shadow planes meshed into strips at (i/n)² of their length, finer near the light
//! (`plane_segments`); silhouettes (cached per light, `common::shadow_volumes::shadow_planes`),
//! the eq. 13/14 sort
//! keys (`geometry.rs`), the stencil rules, and the paper's 8-bit frame buffer with additive and
//! reverse-subtractive blending and its §5.2 clamping problem (`accumulate: unorm8`) — all of it
//! under `resolve: planes`. Modernised: `resolve: per-pixel` (the default; `pixel.rs`): each
//! pixel's crossings go into a crossing list (`common::shadow_volumes::crossing_lists`, cannot
//! overflow), sorted
//! and walked from the eye's count, adding Γ(b) − Γ(a) over the lit intervals only — the paper's
//! whole-plane order has no answer where shadow wedges cross, and §4.4's rules then drop crossings
//! (the fence-spot band, README); this resolve is per fragment, so `eval: vertex` and
//! `accumulate: unorm8` need `resolve: planes`;
//! `eval: fragment` (Γ per pixel, the paper's "fragment shaders if possible"), `fit: chebyshev`
//! (interpolation over the segment's own θ range, 4–16× more accurate at equal order), signed
//! float accumulation (`accumulate: float`, the default: no clamping, no reverse subtract), the
//! surface term from the shared forward pass with shadow maps instead of stencil shadows and
//! OpenGL's fog/lighting approximations (eq. 15, 16), per-channel σ_t. Scatterbench's phase is
//! normalised to ∫p dω = 1 (the annex's hazy/murky coefficients are ×8π and ×(4π + 400π/66), and
//! its c1 lines are typos: README).
//!
//! Spots (falloff and projected pattern) follow eq. 7 (`spot.rs`, `spot_tables.rs`,
//! `spot.wgsl`): Δ_i(γ) = ∫_{−π/2}^{γ} δ^i I(δ) dδ tabulated at prepare on a grid of half circles
//! of the emission hemisphere (plane normals: `half_circles` = N values of the axis component ×
//! 2N azimuths, 128 γ each), the ray's polynomial re-expanded in δ = θ + β, so a segment stays
//! O(n²) plus 2×4 table fetches per coefficient. Approximated: Δ between half circles
//! (bilinear) and between γ samples (linear) — a pattern edge is smeared over one circle
//! spacing (README: error vs N); for spots `fit: chebyshev` fits Λ once over the ray's whole
//! eye-to-far-plane range (so every Γ on a ray uses one polynomial), not per segment. With
//! `eval: fragment` all of eq. 7 but θ_M and the Δ lookups at γ_M depends on the pixel's ray
//! alone: a compute pass per spot (`spot_rays.wgsl`) stores it per pixel (t, h, β, γ_0, the
//! half-circle cell, the scaled coefficients and Σ c'_i Δ_i(γ_0)), and the plane and surface
//! fragments only finish the sum.
//!
//! Directional light (modernised; the paper treats point lights): no foot distance h, but the
//! scattering angle is constant along a ray, so Γ(M) = σ_s E p(θ) (1 − e^(−σ_t x))/σ_t in closed
//! form (`passes.wgsl` → `sunlight_between` of `common/wgsl/light_segments.wgsl`, shared with
//! biri-shadow-volumes and polygonal-light-volumes; no polynomial), shadow planes extruded along
//! the direction, and eq. 13/14's order replaced by its limit for a light receding to infinity:
//! the squared distance from the eye to the plane's infinite strip (`geometry::light_order_key`).
//!
//! Limits: spot cones ≥ 90° do not
//! fit one hemisphere (refused at prepare); spot tables come from frame 0 (a keyframed cone or
//! pattern would need a rebuild). Taylor degrades as |θ| → π/2
//! (rays passing near the light or far from it: the paper's caveat); per-vertex evaluation cannot
//! follow Γ's 1/h peak around the light's image (README: error vs tessellation). With `resolve:
//! planes` the front-to-back order is per plane, not per pixel, so crossing, intersecting or
//! nested volumes can be mis-ordered (fence-spot: 0.23 rel RMSE vs 0.022 per pixel). Without
//! the adapter's DEPTH_CLIP_CONTROL, planes clipped by the near plane break the z-pass count
//! (README: near plane). Per-vertex values of vertices behind the eye are meaningless. Indirect single scattering is ignored
//! (`Partial`).
//!
//! Exponential height fog: refused — the kernel Λ(θ) and Γ(M) assume a constant σ_t.

use anyhow::Result;
use harness::method::{PrepareContext, ShaderCheck};
use harness::{
    Aov, ConformanceCase, FrameReport, Gpu, Knob, KnobRead, Medium, Method, MethodInfo, Prepared,
    Support, Targets,
};
use scenes::{FrameState, SceneFeatures};

use crate::common::height_fog::constant_sigma_only;
use crate::common::knobs;
use crate::common::renderer::{SceneRenderer, unsupported};
use crate::common::resolve::ResolvePass;
use crate::common::shadow_maps::ShadowSettings;
use crate::common::shadow_volumes::stencil_surfaces::StencilSurfaceShadows;

mod encode;
pub mod geometry;
#[cfg(test)]
mod measure_tests;
mod passes;
mod pipelines;
mod pixel;
pub mod poly;
#[cfg(test)]
mod poly_tests;
mod shaders;
pub mod spot;
mod spot_rays;
mod spot_tables;
#[cfg(test)]
mod spot_tests;
mod types;

pub use shaders::{KERNEL_WGSL, passes_source, resolve_source};
use types::Config;
pub use types::{Accumulate, Eval, Resolve, Walk};

/// `mode` in resolve.wgsl, field for field.
#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct ResolveUniform {
    unorm8: u32,
    _pad: [u32; 3],
}

/// The method (a description; [`State`] is the prepared instance).
pub struct BiriPolynomial;

/// The prepared method.
pub struct State {
    renderer: SceneRenderer,
    passes: passes::Passes,
    resolve: ResolvePass,
    /// §4.3's stencil surface shadows (`surface_shadows = stencil`).
    surface_shadows: Option<StencilSurfaceShadows>,
}

/// The knobs, parsed and checked.
fn config(ctx: &PrepareContext) -> Result<Config> {
    let p = ctx.params;
    let order: u32 = p.knob("order")?;
    let fit = poly::Fit::parse(&p.knob::<String>("fit")?).map_err(anyhow::Error::msg)?;
    let eval = match p.knob::<String>("eval")?.as_str() {
        "vertex" => Eval::Vertex,
        _ => Eval::Fragment,
    };
    let accumulate = match p.knob::<String>("accumulate")?.as_str() {
        "unorm8" => Accumulate::Unorm8,
        _ => Accumulate::Float,
    };
    let resolve = match p.knob::<String>("resolve")?.as_str() {
        "planes" => Resolve::Planes,
        _ => Resolve::PerPixel,
    };
    let walk = match p.knob::<String>("walk")?.as_str() {
        "compute" => Walk::Compute,
        _ => Walk::Fragment,
    };
    if resolve == Resolve::PerPixel && eval == Eval::Vertex {
        anyhow::bail!(
            "eval = vertex is the paper's per-vertex Γ on its plane draws: it needs resolve = planes (resolve = per-pixel evaluates Γ per pixel)"
        );
    }
    if resolve == Resolve::PerPixel && accumulate == Accumulate::Unorm8 {
        anyhow::bail!(
            "accumulate = unorm8 is the paper's blended 8-bit frame buffer: it needs resolve = planes"
        );
    }
    let phase = ctx
        .scene
        .medium()
        .homogeneous()
        .ok_or_else(|| anyhow::anyhow!("biri-polynomial needs a homogeneous medium"))?
        .phase;
    let mut series = [0.0f32; 12];
    for (s, v) in series
        .iter_mut()
        .zip(poly::phase_series(&phase, poly::MAX_ORDER))
    {
        *s = v as f32;
    }
    Ok(Config {
        resolve,
        walk,
        eval,
        accumulate,
        tessellation: p.knob("tessellation")?,
        plane_segments: p.knob("plane_segments")?,
        stencil_rules: p.knob("stencil_rules")?,
        order,
        fit: (fit == poly::Fit::Chebyshev) as u32,
        series,
        half_circles: p.knob("half_circles")?,
    })
}

impl Method for BiriPolynomial {
    fn info(&self) -> MethodInfo {
        harness::method_info!(
            "biri-polynomial",
            Medium::Homogeneous,
            "Biri, Michelin & Arquès, Real-time single scattering with volumetric shadows (software-assisted precursor of Biri et al. 2006)",
            "Angular RTE with a polynomial kernel: constant-time Γ per vertex or fragment, shadow planes front to back with stencil counting",
        )
    }

    fn knobs(&self) -> Vec<Knob> {
        vec![
            Knob::int("order", 4, 2..=poly::MAX_ORDER as i64)
                .sweep([2, 3, 5, 6, 7, 8])
                .meaning("polynomial order n of the kernel Λ(θ)"),
            Knob::choice("fit", "taylor", &["taylor", "chebyshev"])
                .sweep(["chebyshev"])
                .meaning("taylor: the paper's expansion around θ = 0; chebyshev: interpolation over the segment's own θ range"),
            Knob::choice("resolve", "per-pixel", &["per-pixel", "planes"])
                .sweep(["planes"])
                .meaning("per-pixel: crossing lists sorted and walked per pixel, Γ over the lit intervals (modern, exact shadow in shadow); planes: the paper's eq. 13/14 front-to-back plane order under §4.4's stencil rules"),
            Knob::choice("walk", "fragment", &["fragment", "compute"])
                .sweep(["compute"])
                .meaning("resolve=per-pixel: the walk of the crossing lists as a compute pass over 8×8 tiles writing the sum over lights, or a full-screen fragment pass blended into the accumulation target (same image)"),
            Knob::choice("eval", "fragment", &["fragment", "vertex"])
                .requires("vertex", "resolve", "planes")
                .meaning("where Γ is evaluated: per fragment (modern), or per vertex with Gouraud interpolation (the paper; needs resolve = planes)"),
            // Each level multiplies the triangles by 4: 6 levels is 4096× the scene's.
            Knob::int("tessellation", 3, 0..=6)
                .sweep([0, 1, 2, 4, 5])
                .unit("subdivision levels")
                .meaning("eval = vertex: midpoint-subdivision levels of every surface (×4 triangles each); the far-plane grid has 2^(levels+1) cells per side"),
            Knob::int("plane_segments", 16, 1..=256)
                .sweep([2, 4, 8, 32, 64])
                .unit("strips")
                .meaning("eval = vertex: strips per shadow plane, at (i/n)² of its length (finer near the light)"),
            Knob::choice("surface_shadows", "stencil", &["stencil", "shadow-map"])
                .meaning("surface shadows: §4.3's stencil shadow volumes (exact per pixel), or the shared shadow-mapped surface pass"),
            knobs::shadow_map(1024)
                .meaning("shadow-map resolution per face (surface_shadows = shadow-map only)"),
            knobs::local_shadow_budget(),
            knobs::pattern_res(512),
            Knob::choice("accumulate", "float", &["float", "unorm8"])
                .requires("unorm8", "resolve", "planes")
                .meaning("float: signed Rgba32Float sums; unorm8: the paper's 8-bit frame buffer, clamped after each blend (§5.2's quantization problem; needs resolve = planes)"),
            // 48 × 96 half circles × 128 γ samples is the largest table the uniforms index.
            Knob::int("half_circles", 32, 2..=48)
                .sweep([4, 8, 16, 48])
                .unit("half circles")
                .meaning("spots (eq. 7): Δ_i tables on N×2N half circles (plane normal: N values of its axis component, 2N azimuths), 128 γ samples each"),
            Knob::boolean("stencil_rules", true)
                .meaning("resolve = planes: §4.4, count a plane only where it is lit (stencil 0 entering, 1 leaving); false: every crossing counts (exact for disjoint shadow volumes only)"),
        ]
    }

    fn support(&self, scene: &SceneFeatures, _device: wgpu::Features) -> Support {
        if let Some(why) = unsupported(scene) {
            return Support::No(why);
        }
        if scene.medium != "homogeneous" {
            return Support::No(
                "needs a homogeneous medium (the angular RTE assumes constant σ_t)".into(),
            );
        }
        let kernel = "the angular RTE's kernel Λ(θ) and its polynomial Γ(M) assume a constant σ_t";
        if let Some(no) = constant_sigma_only(scene, kernel) {
            return no;
        }
        if scene.indirect_single_scattering {
            return Support::Partial(vec!["indirect_single_scattering".into()]);
        }
        Support::Full
    }

    fn prepare(&self, ctx: &PrepareContext) -> Result<Box<dyn Prepared>> {
        Ok(Box::new(State::new(ctx)?))
    }

    fn shaders(&self) -> Vec<ShaderCheck> {
        let orders: Vec<f64> = (2..=poly::MAX_ORDER).map(|n| n as f64).collect();
        let flags: &[f64] = &[0.0, 1.0];
        [
            ShaderCheck::combinations(
                "biri-polynomial/passes",
                &passes_source(false),
                &[
                    ("ORDER", &orders),
                    ("FIT", flags),
                    ("ANY_SPOT", flags),
                    ("ALL_SPOT", flags),
                ],
            ),
            ShaderCheck::combinations(
                "biri-polynomial/passes (early depth test)",
                &passes_source(true),
                &[],
            ),
            ShaderCheck::combinations("biri-polynomial/resolve", &resolve_source(), &[]),
        ]
        .concat()
    }

    /// The near-plane case: the shadow planes are drawn with depth clamping where the adapter
    /// has `DEPTH_CLIP_CONTROL` (lavapipe does), so crossings between the eye and the near plane
    /// are counted; total rel RMSE 0.060 at 64² (without clamping: 0.71). Bound ≈ 2× that.
    fn stress_bound(&self, case: &str) -> Option<f64> {
        (case == "near-plane-cuts-shadow-plane").then_some(0.12)
    }

    /// Bounds ≈ 1.5× the rel RMSE measured at 48² on lavapipe: sphere-point 0.055, fence-spot
    /// 0.0208 (per-pixel resolve, default knobs), fence-spot with the paper's plane order and
    /// the Chebyshev fit 0.24, sphere-point per vertex at 2 subdivision levels 0.44.
    fn conformance(&self) -> Vec<ConformanceCase> {
        vec![
            ConformanceCase::new("sphere-point", 48, Aov::Inscatter, 0.08),
            ConformanceCase::new("fence-spot", 48, Aov::Inscatter, 0.032),
            ConformanceCase::new("fence-spot", 48, Aov::Inscatter, 0.36)
                .knob("resolve", "planes")
                .knob("fit", "chebyshev"),
            ConformanceCase::new("sphere-point", 48, Aov::Inscatter, 0.65)
                .knob("resolve", "planes")
                .knob("eval", "vertex")
                .knob("tessellation", 2),
        ]
    }
}

impl State {
    pub fn new(ctx: &PrepareContext) -> Result<State> {
        let features = ctx.scene.features();
        if let Support::No(why) = BiriPolynomial.support(&features, ctx.gpu.device.features()) {
            anyhow::bail!(why);
        }
        let cfg = config(ctx)?;
        for light in &ctx.scene.frame(0).lights {
            if let scenes::LightState::Spot { cos_outer, .. } = light
                && *cos_outer <= 0.0
            {
                anyhow::bail!(
                    "biri-polynomial: a spot cone of 90° or more does not fit eq. 7's half circles on one hemisphere"
                );
            }
        }
        let stencil_shadows = ctx.params.knob::<String>("surface_shadows")? == "stencil";
        let renderer = SceneRenderer::with_shadow_maps(
            ctx,
            ShadowSettings::from_params(ctx.params)?,
            ctx.params.knob("pattern_res")?,
            !stencil_shadows,
        )?;
        let passes = passes::Passes::new(ctx, &renderer, cfg);
        let surface_shadows = stencil_shadows.then(|| {
            StencilSurfaceShadows::new(
                ctx.gpu,
                &renderer,
                crate::common::shadow_volumes::stencil::DEPTH_STENCIL,
                ctx.scene.features().lights,
            )
        });
        let resolve = ResolvePass::with_textures(
            ctx.gpu,
            &renderer,
            "biri-poly resolve",
            shaders::RESOLVE_WGSL,
            Some(std::mem::size_of::<ResolveUniform>() as u64),
            1,
        );
        let mode = ResolveUniform {
            unorm8: (cfg.accumulate == Accumulate::Unorm8) as u32,
            _pad: [0; 3],
        };
        ctx.gpu.queue.write_buffer(
            resolve.uniform.as_ref().expect("uniform"),
            0,
            bytemuck::bytes_of(&mode),
        );
        Ok(State {
            renderer,
            passes,
            resolve,
            surface_shadows,
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
        self.passes.update(gpu, frame, &mut report);
        self.renderer.encode_shadows_and_surface(enc, targets, &mut report);
        self.passes.encode(
            gpu,
            enc,
            &self.renderer,
            targets.surface,
            self.surface_shadows.as_ref(),
            &mut report,
        )?;
        self.resolve
            .encode_with(gpu, enc, &self.renderer, targets, &[&self.passes.acc_view]);
        report.ran("resolve");
        Ok(report)
    }
}
