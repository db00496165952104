//! `biri-shadow-volumes`: Biri, Arquès & Michelin, *Real time rendering of atmospheric scattering
//! and volumetric shadows* (J. WSCG 14, 2006).
//!
//! Algorithm: the single-scattering integral of an isotropic point light along a view ray is, after
//! the change of variable x = t + h tan α, a difference of two values of one 2-D function
//! Γ(λ, γ) (eq. 6) that only depends on the phase function; Γ is tabulated once by quadrature and
//! every pixel's direct single scattering L_dss (eq. 7) costs two table lookups per channel. Lit
//! and shadowed parts of a ray split the sum (eq. 14): each shadow-plane crossing adds or
//! subtracts one Γ term, so the paper draws the silhouette shadow planes with the L_dss shader,
//! front faces adding and back faces subtracting, sorted back to front with stencil rules that
//! drop crossings inside another shadow.
//!
//! Faithful: Γ by quadrature per phase function, L_dss from two lookups (the Fig. 7 shader), the
//! constants of eq. 7 (converted to ARCHITECTURE §1: p normalised to 1 over the sphere, so the paper's
//! k_t²Ω/4π · 1/(k_t h) becomes σ_s/h). Modernised: float targets; the table's axes are
//! u = λ/(1+λ) and w = tan(γ/2+π/4)/(1+tan(γ/2+π/4)) instead of linear λ and γ (w follows the
//! integrand's e^(−λ tan(γ/2+π/4)) and needs no atan texture), bilinear lookups done in the
//! shader, per-channel σ_t. Surface lighting (step 2) is the shared surface pass shaded without
//! shadows, then, per light, the stencil count of its shadow volumes (seeded with the eye's count,
//! so correct with the camera in a shadow) removes the light where the count is not zero
//! (`common::shadow_volumes::stencil_surfaces`; knob `surface_shadows = shadow-map` uses shadow
//! maps instead). Shadow planes
//! (`planes.rs`): silhouettes from `common::shadow_volumes::silhouette` (recomputed only when a
//! light or caster
//! moved), one per closed piece of a caster (knob `silhouettes`, default `per-piece`: a union of
//! touching closed solids such as the fence casts one volume per solid; `whole-mesh` keeps the
//! former rule); open or non-manifold pieces fall back to per-triangle planes, counted in
//! `nonmanifold_casters` and recorded as a skipped "silhouette of <name>"), extruded past the far
//! plane. Two resolves (knob `resolve`):
//! - `per-pixel` (default, modern): per light, every plane fragment in front of the visible
//!   surface goes into its pixel's crossing list (signed distance;
//!   `common::shadow_volumes::crossing_lists`: a counting pass and a prefix sum size one pool exactly, so lists cannot overflow), and a
//!   compute pass sorts each list and sums L_dss over the lit intervals only, walking from the
//!   eye's count (`pixel.rs`). Exact shadow in shadow and eye in shadow, no CPU sort.
//! - `stencil` (the paper's steps 4–5): quads sorted back to front by edge-midpoint distance, the
//!   visible point's count by a z-pass stencil count seeded with the eye's count, the lit
//!   surfaces' term where it is 0, then the planes one by one with step 5's rules
//!   (`stencil_rules`, default true): a plane's colour under the stencil test (front = 1, back =
//!   0), then a second draw that steps the stencil only where the plane passes the depth test —
//!   the paper's "own depth test", needed because a stencil op on a failed stencil test also
//!   hits planes behind the visible point. Signed float accumulation by default; `accumulate =
//!   unorm8` reproduces the paper's 8-bit target (each plane writes L_dss from the eye, front
//!   faces add, back faces reverse-subtract; values clamp to [0, 1] and quantise to 1/255).
//!
//! Status and limits: the stencil rules are exact only where the CPU's order of whole planes is
//! every pixel's order along the ray; long extruded planes of different casters interleave (e.g.
//! `overlap-point`, with the eye in a shadow), so there the per-pixel resolve is the exact one.
//! Lights beyond the paper (modernised; the paper's point-light path is unchanged): both
//! resolves evaluate every lit interval through ONE function, `lit_between`
//! (`common/wgsl/ldss.wgsl`, shared with polygonal-light-volumes), dispatched on the light's kind — point lights by eq. 7's Γ lookups; directional light in
//! closed form, σ_s E p(θ) (e^(−σ_t a) − e^(−σ_t b))/σ_t (the scattering angle is constant along
//! the ray; the paper: directional lights "are easier to handle ... and will not be a problem"),
//! its shadow planes extruded along the direction; spot lights (falloff and projected pattern)
//! by `spot_panels` two-node Gauss–Legendre panels in the angle seen from the light over the
//! interval's stretch inside the outer cone (the per-pixel walk, spots without a pattern: an
//! antiderivative fitted once per ray, knob `spot_integral = per-ray`, the default;
//! `spot_fit.wgsl`, README). The closed form and the quadrature are shared with
//! polygonal-light-volumes (`common/wgsl/light_segments.wgsl`). The stencil resolve adds
//! `crossing_term`, an antiderivative of `lit_between` (0 at the eye for the new kinds).
//! GPU time per phase (Table 1) via `harness::gpu::PhaseTimer`: counters
//! `gpu_ms_first_pass`, `gpu_ms_second_pass_surfaces`, `gpu_ms_second_pass_volumes`,
//! `gpu_ms_resolve`, with the CPU's `silhouette_ms` and `sort_ms`.
//!
//! Indirect single scattering (§III.C, Fig. 8; scenes with `indirect_single_scattering`, knob
//! `indirect`): `indirect.rs` tabulates Γ_L(λ, φ_n) (the hemisphere integral, 2-D where the
//! paper's full-sphere version is 1-D) and Γ_P(λ, ψ_s) per shininess, and a second draw of the
//! scene over the surface pass's depth adds the term to the `surface` AOV.
//!
//! Exponential height fog: refused — the Γ table folds a constant σ_t into its arguments.

pub mod indirect;
mod pixel;
mod planes;
mod stencil_pipes;
mod types;

use anyhow::Result;
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
use crate::common::resolve::{self, ResolvePass};
use crate::common::shadow_maps::ShadowSettings;
use crate::common::shadow_volumes::shadow_planes::Split;
use crate::common::shadow_volumes::stencil::DEPTH_STENCIL;
use crate::common::shadow_volumes::stencil_surfaces::StencilSurfaceShadows;
use crate::common::uniforms::LightMask;
use crate::common::wgsl;
use types::{Options, Resolve};

pub const RESOLVE_WGSL: &str = include_str!("resolve.wgsl");

/// The full-screen L_dss pass's own WGSL (composed by `common::resolve`).
fn resolve_wgsl() -> String {
    format!("{}\n{RESOLVE_WGSL}", wgsl::LDSS)
}

/// The composed WGSL of the full-screen L_dss pass.
pub fn resolve_source() -> String {
    resolve::source(&resolve_wgsl())
}

/// The composed WGSL of the shadow-plane passes (as on a device without the early depth test).
pub fn planes_source() -> String {
    planes::source(false)
}

/// `config` in resolve.wgsl, field for field.
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct ConfigUniform {
    shadowed: u32,
    spot_panels: u32,
    _pad: [u32; 2],
    eye_lit: LightMask,
}

/// The method (a description; [`State`] is the prepared instance).
pub struct BiriShadowVolumes;

/// The prepared method.
pub struct State {
    renderer: SceneRenderer,
    resolve: ResolvePass,
    planes: planes::Planes,
    indirect: Option<indirect::IndirectPass>,
    /// Step 2's stencil surface shadows (`surface_shadows = stencil`).
    surface_shadows: Option<StencilSurfaceShadows>,
    _table: wgpu::Texture,
    table_view: wgpu::TextureView,
    /// GPU time per phase (Table 1's breakdown), when the device has timestamps in encoders.
    timer: Option<PhaseTimer>,
    /// Knob `spot_panels` (the spot quadrature of `lit_between`).
    spot_panels: u32,
}

impl Method for BiriShadowVolumes {
    fn info(&self) -> MethodInfo {
        harness::method_info!(
            "biri-shadow-volumes",
            Medium::Homogeneous,
            "Biri, Arquès, Michelin, Real time rendering of atmospheric scattering and volumetric shadows, J. WSCG 14, 2006",
            "Precomputed Γ(λ,γ) table: direct single scattering from two lookups per ray (eq. 7)",
        )
    }

    fn knobs(&self) -> Vec<Knob> {
        vec![
            Knob::int("table", 256, 4..=4096)
                .sweep([32, 64, 128, 512])
                .unit("samples per side")
                .meaning("Γ(λ, γ) table size per side (λ rows × γ columns)"),
            Knob::choice("resolve", "per-pixel", &["per-pixel", "stencil"])
                .sweep(["stencil"])
                .meaning("per-pixel: crossing lists sorted and walked on the GPU (exact shadow in shadow); stencil: the paper's steps 4-5 (CPU-sorted planes, stencil counting)"),
            Knob::boolean("stencil_rules", true)
                .meaning("resolve=stencil: step 5's stencil rules (draw only the lit/shadow boundaries, in the CPU order); false: every crossing counts (exact without overlapping volumes)"),
            Knob::choice("accumulate", "float", &["float", "unorm8"])
                .sweep(["unorm8"])
                .requires("unorm8", "resolve", "stencil")
                .meaning("resolve=stencil: crossing accumulation target; unorm8 is the paper's 8-bit target with reverse-subtract blending (clamps and quantises; needs resolve=stencil)"),
            Knob::boolean("indirect", true)
                .meaning("scenes with indirect_single_scattering: add §III.C's term (Γ_L, Γ_P tables, the Fig. 8 pass); false skips it"),
            Knob::int("indirect_table", 64, 4..=1024)
                .sweep([16, 32, 128])
                .unit("samples per side")
                .meaning("Γ_L(λ, φ_n) and Γ_P(λ, ψ_s) table size per side"),
            Knob::choice("surface_shadows", "stencil", &["stencil", "shadow-map"])
                .meaning("surface shadows: the paper's stencil shadow volumes (exact per pixel), or the shared shadow-mapped surface pass"),
            knobs::shadow_map(1024)
                .meaning("shadow-map resolution per face (surface_shadows = shadow-map only)"),
            knobs::local_shadow_budget(),
            Knob::int("spot_panels", 8, 1..=128)
                .sweep([1, 2, 4, 16, 64])
                .unit("panels")
                .meaning("spot lights (modernised): two-node Gauss-Legendre panels of each lit interval's quadrature, in the angle seen from the light, over the stretch inside the cone"),
            // per-ray by default: measured on fence-spot 256² (README, issue 33), faster and
            // more accurate than spot_panels per lit interval.
            Knob::choice("spot_integral", "per-ray", &["per-ray", "per-interval"])
                .sweep(["per-interval"])
                .meaning("resolve=per-pixel, spot lights without a pattern: per-ray fits the ray once (8 Chebyshev nodes per piece, cut at the inner cone) and takes each lit interval from its antiderivative; per-interval integrates each lit interval by spot_panels panels (as the stencil resolve and patterned spots)"),
            knobs::pattern_res(512),
            Knob::choice("silhouettes", "per-piece", &["per-piece", "whole-mesh"])
                .sweep(["whole-mesh"])
                .meaning("per-piece: every closed piece of a caster (a union of touching closed solids such as the fence's bars comes apart into them) casts its silhouette volume, open pieces per-triangle volumes; whole-mesh: a caster that is not a closed 2-manifold as a whole casts per-triangle volumes (3 planes per triangle)"),
        ]
    }

    fn support(&self, scene: &SceneFeatures, device: wgpu::Features) -> Support {
        if let Some(why) = unsupported(scene) {
            return Support::No(why);
        }
        let gamma = "the Γ table of L_dss (eq. 6–7) is tabulated for a constant σ_t";
        if let Some(no) = constant_sigma_only(scene, gamma) {
            return no;
        }
        if scene.indirect_single_scattering && !indirect::device_can(device) {
            return Support::Partial(vec![
                "indirect_single_scattering (needs FLOAT32_BLENDABLE)".into(),
            ]);
        }
        Support::Full
    }

    fn prepare(&self, ctx: &PrepareContext) -> Result<Box<dyn Prepared>> {
        Ok(Box::new(State::new(ctx)?))
    }

    fn shaders(&self) -> Vec<ShaderCheck> {
        [
            ShaderCheck::combinations("biri-shadow-volumes/ldss", &resolve_source(), &[]),
            ShaderCheck::combinations("biri-shadow-volumes/planes", &planes_source(), &[]),
            ShaderCheck::combinations(
                "biri-shadow-volumes/planes (early depth test)",
                &planes::source(true),
                &[],
            ),
            ShaderCheck::combinations("biri-shadow-volumes/indirect", &indirect::source(), &[]),
        ]
        .concat()
    }

    /// The near-plane case: the shadow planes are drawn with depth clamping where the adapter
    /// has `DEPTH_CLIP_CONTROL` (lavapipe does), so crossings between the eye and the near plane
    /// are counted; total rel RMSE 0.051 at 64² (without clamping: 0.51). Bound ≈ 2× that.
    fn stress_bound(&self, case: &str) -> Option<f64> {
        (case == "near-plane-cuts-shadow-plane").then_some(0.10)
    }

    /// Bounds ≈ 1.5–4× the rel RMSE measured at 48² on lavapipe: sphere-point < 5e-5,
    /// overlap-point with the stencil resolve 0.085, indirect-point (total AOV, §III.C) 0.0024,
    /// stained-glass-spot with a reference-quality 64-panel spot quadrature 0.036.
    fn conformance(&self) -> Vec<ConformanceCase> {
        vec![
            ConformanceCase::new("sphere-point", 48, Aov::Inscatter, 0.005),
            ConformanceCase::new("overlap-point", 48, Aov::Inscatter, 0.13)
                .knob("resolve", "stencil"),
            ConformanceCase::new("indirect-point", 48, Aov::Total, 0.01),
            ConformanceCase::new("stained-glass-spot", 48, Aov::Inscatter, 0.06)
                .knob("spot_panels", 64),
        ]
    }
}

impl State {
    pub fn new(ctx: &PrepareContext) -> Result<State> {
        let p = ctx.params;
        let res: u32 = p.knob("table")?;
        let features = ctx.scene.features();
        if let Support::No(why) = BiriShadowVolumes.support(&features, ctx.gpu.device.features()) {
            anyhow::bail!(why);
        }
        let table = GammaTable::build(&ctx.scene.medium().background().phase, res, res);
        let texture = table.upload(ctx.gpu, "biri gamma");
        let table_view = texture.create_view(&Default::default());
        let stencil_shadows = p.knob::<String>("surface_shadows")? == "stencil";
        let renderer = SceneRenderer::with_shadow_maps(
            ctx,
            ShadowSettings::from_params(p)?,
            p.knob("pattern_res")?,
            !stencil_shadows,
        )?;
        let surface_shadows = stencil_shadows.then(|| {
            StencilSurfaceShadows::new(ctx.gpu, &renderer, DEPTH_STENCIL, features.lights)
        });
        let resolve = ResolvePass::with_textures(
            ctx.gpu,
            &renderer,
            "biri ldss",
            &resolve_wgsl(),
            Some(std::mem::size_of::<ConfigUniform>() as u64),
            2,
        );
        let mode = match p.knob::<String>("resolve")?.as_str() {
            "stencil" => Resolve::Stencil,
            _ => Resolve::PerPixel,
        };
        let unorm8 = p.knob::<String>("accumulate")? == "unorm8";
        if unorm8 && mode != Resolve::Stencil {
            anyhow::bail!(
                "accumulate = unorm8 is the paper's blended stencil target: it needs resolve = stencil"
            );
        }
        let options = Options {
            resolve: mode,
            rules: p.knob("stencil_rules")?,
            unorm8,
            spot_panels: p.knob("spot_panels")?,
            spot_per_ray: p.knob::<String>("spot_integral")? == "per-ray",
            split: match p.knob::<String>("silhouettes")?.as_str() {
                "whole-mesh" => Split::WholeMesh,
                _ => Split::Components,
            },
        };
        let planes = planes::Planes::new(ctx, &renderer, options);
        let want_iss: bool = p.knob("indirect")?;
        let iss_res: u32 = p.knob("indirect_table")?;
        let indirect = (features.indirect_single_scattering && want_iss)
            .then(|| indirect::IndirectPass::new(ctx, &renderer, iss_res))
            .transpose()?;
        Ok(State {
            renderer,
            resolve,
            planes,
            indirect,
            surface_shadows,
            _table: texture,
            table_view,
            timer: PhaseTimer::new(ctx.gpu, 5 + 3 * features.lights as u32),
            spot_panels: p.knob("spot_panels")?,
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
        let shadowed = self.renderer.scene.features().volumetric_occluders;
        let eye_lit = if shadowed {
            let lit = self.planes.update(gpu, frame, &mut report);
            if self.planes.eye_term() {
                lit
            } else {
                LightMask::default()
            }
        } else {
            LightMask::default()
        };
        if let Some(u) = &self.resolve.uniform {
            gpu.queue.write_buffer(
                u,
                0,
                bytemuck::bytes_of(&ConfigUniform {
                    shadowed: shadowed as u32,
                    spot_panels: self.spot_panels,
                    _pad: [0; 2],
                    eye_lit,
                }),
            );
        }
        phases::mark(&mut self.timer, enc, "first_pass");
        self.renderer.encode_shadows_and_surface(enc, targets, &mut report);
        match &self.indirect {
            Some(pass) => {
                pass.encode(enc, &self.renderer, targets);
                report.ran("indirect");
            }
            None if self.renderer.scene.desc.indirect_single_scattering => {
                report.skip("indirect", "knob indirect = false")
            }
            None => {}
        }
        if shadowed {
            self.planes.encode(
                gpu,
                enc,
                &self.renderer,
                &self.table_view,
                &mut report,
                &mut self.timer,
            )?;
            report.ran("shadow-planes");
            if let Some(shadows) = &self.surface_shadows {
                phases::mark(&mut self.timer, enc, "first_pass");
                self.planes.encode_surface_shadows(
                    gpu,
                    enc,
                    &self.renderer,
                    &self.table_view,
                    targets.surface,
                    shadows,
                );
                report.ran("stencil-surface-shadows");
            }
        } else {
            report.skip("shadow-planes", "no object casts a volumetric shadow");
        }
        phases::mark(&mut self.timer, enc, "resolve");
        self.resolve.encode_with(
            gpu,
            enc,
            &self.renderer,
            targets,
            &[&self.table_view, &self.planes.acc_view],
        );
        phases::finish(&mut self.timer, enc);
        report.ran("ldss");
        Ok(report)
    }

    fn phase_timer(&self) -> Option<&PhaseTimer> {
        self.timer.as_ref()
    }
}
