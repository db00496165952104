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
//! (`plane_segments`); silhouettes (cached per light, `common::shadow_planes`), the eq. 13/14 sort
//! keys (`geometry.rs`), the stencil rules, and the paper's 8-bit frame buffer with additive and
//! reverse-subtractive blending and its §5.2 clamping problem (`accumulate: unorm8`). Modernised:
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
//! Limits: directional lights have no foot distance h and are refused; spot cones ≥ 90° do not
//! fit one hemisphere (refused at prepare); spot tables come from frame 0 (a keyframed cone or
//! pattern would need a rebuild). Taylor degrades as |θ| → π/2
//! (rays passing near the light or far from it: the paper's caveat); per-vertex evaluation cannot
//! follow Γ's 1/h peak around the light's image (README: error vs tessellation). The front-to-back
//! order is per plane, not per pixel, so intersecting or nested volumes seen at grazing angles can
//! be mis-ordered; planes clipped by the near plane break the z-pass count (the eye's count is
//! exact, but a plane crossing the near plane is not drawn in front of the eye), and per-vertex
//! values of vertices behind the eye are meaningless. Indirect single scattering is ignored
//! (`Partial`).

use anyhow::Result;
use harness::method::PrepareContext;
use harness::{FrameReport, Gpu, Method, MethodInfo, ParamSpec, ParamValue, Support, Targets};
use scenes::{FrameState, SceneFeatures};

use crate::common::renderer::{SceneRenderer, unsupported};
use crate::common::resolve::{self, ResolvePass};
use crate::common::stencil_surfaces::StencilSurfaceShadows;

pub mod geometry;
#[cfg(test)]
mod measure_tests;
mod passes;
pub mod poly;
#[cfg(test)]
mod poly_tests;
pub mod spot;
mod spot_tables;
#[cfg(test)]
mod spot_tests;

pub use passes::{Accumulate, Eval};

/// The WGSL kernel library (Λ, Taylor and Chebyshev segment integrals); the including module
/// supplies `biri_phase(cos) -> f32`.
pub const KERNEL_WGSL: &str = include_str!("kernel.wgsl");
const RESOLVE_WGSL: &str = include_str!("resolve.wgsl");

/// The composed WGSL of the surface and shadow-plane passes.
pub fn passes_source() -> String {
    passes::source()
}

/// The composed WGSL of the last (resolve) pass.
pub fn resolve_source() -> String {
    resolve::source(RESOLVE_WGSL)
}

#[derive(Default)]
pub struct BiriPolynomial {
    state: Option<State>,
}

struct State {
    renderer: SceneRenderer,
    passes: passes::Passes,
    resolve: ResolvePass,
    /// §4.3's stencil surface shadows (`surface_shadows = stencil`).
    surface_shadows: Option<StencilSurfaceShadows>,
}

/// The knobs, parsed and checked.
fn config(ctx: &PrepareContext) -> Result<passes::Config> {
    let p = ctx.params;
    let int = |k: &str, d: i64| p.get(k).and_then(ParamValue::as_i64).unwrap_or(d);
    let text = |k: &str, d: &'static str| {
        p.get(k)
            .and_then(ParamValue::as_str)
            .unwrap_or(d)
            .to_string()
    };
    let order = int("order", 4);
    if !(2..=poly::MAX_ORDER as i64).contains(&order) {
        anyhow::bail!("order must be 2…{}, not {order}", poly::MAX_ORDER);
    }
    let fit = poly::Fit::parse(&text("fit", "taylor")).map_err(anyhow::Error::msg)?;
    let eval = match text("eval", "fragment").as_str() {
        "vertex" => Eval::Vertex,
        "fragment" => Eval::Fragment,
        e => anyhow::bail!("eval must be `vertex` or `fragment`, not `{e}`"),
    };
    let accumulate = match text("accumulate", "float").as_str() {
        "float" => Accumulate::Float,
        "unorm8" => Accumulate::Unorm8,
        e => anyhow::bail!("accumulate must be `float` or `unorm8`, not `{e}`"),
    };
    let tessellation = int("tessellation", 3);
    if !(0..=6).contains(&tessellation) {
        anyhow::bail!("tessellation must be 0…6 subdivision levels, not {tessellation}");
    }
    let plane_segments = int("plane_segments", 16);
    if !(1..=256).contains(&plane_segments) {
        anyhow::bail!("plane_segments must be 1…256, not {plane_segments}");
    }
    let half_circles = int("half_circles", 32);
    if !(2..=48).contains(&half_circles) {
        anyhow::bail!("half_circles must be 2…48, not {half_circles}");
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
    Ok(passes::Config {
        eval,
        accumulate,
        tessellation: tessellation as u32,
        plane_segments: plane_segments as u32,
        stencil_rules: p
            .get("stencil_rules")
            .and_then(ParamValue::as_bool)
            .unwrap_or(true),
        order: order as u32,
        fit: (fit == poly::Fit::Chebyshev) as u32,
        series,
        half_circles: half_circles as u32,
    })
}

impl Method for BiriPolynomial {
    fn info(&self) -> MethodInfo {
        MethodInfo {
            id: "biri-polynomial",
            paper: "Biri, Michelin & Arquès, Real-time single scattering with volumetric shadows (software-assisted precursor of Biri et al. 2006)",
            summary: "Angular RTE with a polynomial kernel: constant-time Γ per vertex or fragment, shadow planes front to back with stencil counting",
        }
    }

    fn params(&self) -> Vec<ParamSpec> {
        vec![
            ParamSpec {
                name: "order",
                default: ParamValue::Int(4),
                sweep: [2, 3, 5, 6, 7, 8].map(ParamValue::Int).to_vec(),
                choices: vec![],
                meaning: "polynomial order n of the kernel Λ(θ), 2…8",
            },
            ParamSpec {
                name: "fit",
                default: ParamValue::Text("taylor".into()),
                sweep: vec![ParamValue::Text("chebyshev".into())],
                choices: vec!["taylor", "chebyshev"],
                meaning: "taylor: the paper's expansion around θ = 0; chebyshev: interpolation over the segment's own θ range",
            },
            ParamSpec {
                name: "eval",
                default: ParamValue::Text("fragment".into()),
                sweep: vec![ParamValue::Text("vertex".into())],
                choices: vec!["fragment", "vertex"],
                meaning: "where Γ is evaluated: per fragment (modern), or per vertex with Gouraud interpolation (the paper)",
            },
            ParamSpec {
                name: "tessellation",
                default: ParamValue::Int(3),
                sweep: [0, 1, 2, 4, 5].map(ParamValue::Int).to_vec(),
                choices: vec![],
                meaning: "eval = vertex: midpoint-subdivision levels of every surface (×4 triangles each), 0…6; the far-plane grid has 2^(levels+1) cells per side",
            },
            ParamSpec {
                name: "plane_segments",
                default: ParamValue::Int(16),
                sweep: [2, 4, 8, 32, 64].map(ParamValue::Int).to_vec(),
                choices: vec![],
                meaning: "eval = vertex: strips per shadow plane, at (i/n)² of its length (finer near the light), 1…256",
            },
            ParamSpec {
                name: "surface_shadows",
                default: ParamValue::Text("stencil".into()),
                sweep: vec![],
                choices: vec!["stencil", "shadow-map"],
                meaning: "surface shadows: §4.3's stencil shadow volumes (exact per pixel), or the shared shadow-mapped surface pass",
            },
            ParamSpec {
                name: "accumulate",
                default: ParamValue::Text("float".into()),
                sweep: vec![ParamValue::Text("unorm8".into())],
                choices: vec!["float", "unorm8"],
                meaning: "float: signed Rgba32Float sums; unorm8: the paper's 8-bit frame buffer, clamped after each blend (§5.2's quantization problem)",
            },
            ParamSpec {
                name: "half_circles",
                default: ParamValue::Int(32),
                sweep: [4, 8, 16, 48].map(ParamValue::Int).to_vec(),
                choices: vec![],
                meaning: "spots (eq. 7): Δ_i tables on N×2N half circles (plane normal: N values of its axis component, 2N azimuths), 128 γ samples each, 2…48",
            },
            ParamSpec {
                name: "stencil_rules",
                default: ParamValue::Bool(true),
                sweep: vec![ParamValue::Bool(false)],
                choices: vec![],
                meaning: "§4.4: count a plane only where it is lit (stencil 0 entering, 1 leaving); false: every crossing counts (exact for disjoint shadow volumes only)",
            },
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
        if scene.light_kinds.contains(&"directional") {
            return Support::No(
                "point and spot lights only (a directional light has no foot distance h)".into(),
            );
        }
        if scene.indirect_single_scattering {
            return Support::Partial(vec!["indirect_single_scattering".into()]);
        }
        Support::Full
    }

    fn prepare(&mut self, ctx: &PrepareContext) -> Result<()> {
        if let Support::No(why) = self.support(&ctx.scene.features(), ctx.gpu.device.features()) {
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
        let stencil_shadows = match ctx
            .params
            .get("surface_shadows")
            .and_then(ParamValue::as_str)
            .unwrap_or("stencil")
        {
            "stencil" => true,
            "shadow-map" => false,
            e => anyhow::bail!("surface_shadows must be `stencil` or `shadow-map`, not `{e}`"),
        };
        let renderer = SceneRenderer::with_shadow_maps(ctx, 1024, 16, !stencil_shadows)?;
        let passes = passes::Passes::new(ctx, &renderer, cfg);
        let surface_shadows = stencil_shadows.then(|| {
            StencilSurfaceShadows::new(
                ctx.gpu,
                &renderer,
                passes::DEPTH,
                ctx.scene.features().lights,
            )
        });
        let resolve = ResolvePass::with_textures(
            ctx.gpu,
            &renderer,
            "biri-poly resolve",
            RESOLVE_WGSL,
            Some(16),
            1,
        );
        let mode = [(cfg.accumulate == Accumulate::Unorm8) as u32, 0, 0, 0];
        ctx.gpu.queue.write_buffer(
            resolve.uniform.as_ref().expect("uniform"),
            0,
            bytemuck::cast_slice(&mode),
        );
        self.state = Some(State {
            renderer,
            passes,
            resolve,
            surface_shadows,
        });
        Ok(())
    }

    fn render(
        &mut self,
        gpu: &Gpu,
        frame: &FrameState,
        targets: &Targets,
        enc: &mut wgpu::CommandEncoder,
    ) -> Result<FrameReport> {
        let st = self
            .state
            .as_mut()
            .ok_or_else(|| anyhow::anyhow!("render before prepare"))?;
        let mut report = FrameReport::default();
        st.renderer.update(gpu, frame);
        st.passes.update(gpu, frame, &mut report);
        st.renderer.encode_shadows(enc, &mut report);
        st.renderer.encode_surface(enc, targets, &mut report);
        st.passes.encode(
            gpu,
            enc,
            &st.renderer,
            targets.surface,
            st.surface_shadows.as_ref(),
            &mut report,
        );
        st.resolve
            .encode_with(gpu, enc, &st.renderer, targets, &[&st.passes.acc_view]);
        report.ran("resolve");
        Ok(report)
    }
}
