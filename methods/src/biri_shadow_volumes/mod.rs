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
//! constants of eq. 7 (converted to DESIGN §1: p normalised to 1 over the sphere, so the paper's
//! k_t²Ω/4π · 1/(k_t h) becomes σ_s/h). Modernised: float targets; the table's axes are
//! u = λ/(1+λ) and w = tan(γ/2+π/4)/(1+tan(γ/2+π/4)) instead of linear λ and γ (w follows the
//! integrand's e^(−λ tan(γ/2+π/4)) and needs no atan texture), bilinear lookups done in the
//! shader, per-channel σ_t. Surface lighting (step 2) is the shared surface pass, whose shadows
//! come from shadow maps rather than the paper's stencil shadow volumes. Shadow planes
//! (`planes.rs`): silhouettes from `common::silhouette` (recomputed only when a light or caster
//! moved), quads sorted back to front by edge-midpoint distance, the visible point's shadow
//! count by a z-pass stencil count seeded with the eye's count (CPU segment test), the lit
//! surfaces' term where the count is 0, then the planes with signed float accumulation (front
//! faces +, back faces −; the paper's reverse-subtract on 8-bit targets is not needed) and, with
//! `stencil_rules = true`, the step-5 stencil rules. The eye's term is subtracted in the resolve.
//!
//! Status and limits: `stencil_rules = true` is defective (rays ending in shadow find a stencil
//! ≥ 2 and lose their entering term: sphere-point 3.3e-2 vs 2.8e-5 without the rules), so the
//! default counts every crossing, which is exact for non-overlapping volumes only. Not
//! implemented: the per-pixel resolve, the unorm8 knob, indirect single scattering (§III.C;
//! `Partial`), planes clipped by the near plane (a camera within `near` of a plane). Point lights
//! only (the method assumes isotropic point sources); spot and directional lights are declined.

mod gamma;
mod planes;

pub use gamma::{GammaTable, gamma_direct, gamma_of_w, w_of_gamma};

use anyhow::Result;
use bytemuck::{Pod, Zeroable};
use harness::method::PrepareContext;
use harness::{FrameReport, Gpu, Method, MethodInfo, ParamSpec, ParamValue, Support, Targets};
use scenes::{FrameState, SceneFeatures};

use crate::common::renderer::{SceneRenderer, unsupported};
use crate::common::resolve::{self, ResolvePass};

pub const LDSS_WGSL: &str = include_str!("ldss.wgsl");
pub const RESOLVE_WGSL: &str = include_str!("resolve.wgsl");

/// The composed WGSL of the full-screen L_dss pass.
pub fn resolve_source() -> String {
    resolve::source(&format!("{LDSS_WGSL}\n{RESOLVE_WGSL}"))
}

/// The composed WGSL of the shadow-plane passes.
pub fn planes_source() -> String {
    planes::source()
}

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct ConfigUniform {
    flags: [u32; 4],
}

#[derive(Default)]
pub struct BiriShadowVolumes {
    state: Option<State>,
}

struct State {
    renderer: SceneRenderer,
    resolve: ResolvePass,
    planes: planes::Planes,
    _table: wgpu::Texture,
    table_view: wgpu::TextureView,
}

/// Uploads a Γ table as an R32Float texture (w along x, λ along y).
fn upload(gpu: &Gpu, t: &GammaTable) -> wgpu::Texture {
    crate::common::tables::r32_table(gpu, "biri gamma", t.w_res, t.lambda_res, &t.data)
}

impl Method for BiriShadowVolumes {
    fn info(&self) -> MethodInfo {
        MethodInfo {
            id: "biri-shadow-volumes",
            paper: "Biri, Arquès, Michelin, Real time rendering of atmospheric scattering and volumetric shadows, J. WSCG 14, 2006",
            summary: "Precomputed Γ(λ,γ) table: direct single scattering from two lookups per ray (eq. 7)",
        }
    }

    fn params(&self) -> Vec<ParamSpec> {
        vec![
            ParamSpec {
                name: "table",
                default: ParamValue::Int(256),
                sweep: [32, 64, 128, 512].map(ParamValue::Int).to_vec(),
                choices: vec![],
                meaning: "Γ(λ, γ) table size per side (λ rows × γ columns)",
            },
            ParamSpec {
                name: "stencil_rules",
                default: ParamValue::Bool(false),
                sweep: vec![ParamValue::Bool(true)],
                choices: vec![],
                meaning: "step 5's stencil rules (skip crossings inside another shadow; currently defective, see README); false: every crossing counts",
            },
            ParamSpec {
                name: "shadow_map",
                default: ParamValue::Int(1024),
                sweep: vec![],
                choices: vec![],
                meaning: "shadow-map resolution per face, texels (surface shadows of the shared surface pass)",
            },
        ]
    }

    fn support(&self, scene: &SceneFeatures, _device: wgpu::Features) -> Support {
        if let Some(why) = unsupported(scene) {
            return Support::No(why);
        }
        if scene.light_kinds.iter().any(|k| *k != "point") {
            return Support::No("Biri et al.'s Γ table assumes isotropic point lights; spot and directional lights are not implemented".into());
        }
        if scene.indirect_single_scattering {
            return Support::Partial(vec!["indirect_single_scattering".into()]);
        }
        Support::Full
    }

    fn prepare(&mut self, ctx: &PrepareContext) -> Result<()> {
        let get = |k: &str| ctx.params.get(k).and_then(ParamValue::as_i64).unwrap_or(0);
        let res = get("table").clamp(4, 4096) as u32;
        let features = ctx.scene.features();
        if let Support::No(why) = self.support(&features, ctx.gpu.device.features()) {
            anyhow::bail!(why);
        }
        let table = GammaTable::build(&ctx.scene.medium().background().phase, res, res);
        let texture = upload(ctx.gpu, &table);
        let table_view = texture.create_view(&Default::default());
        let renderer = SceneRenderer::new(ctx, get("shadow_map").clamp(16, 8192) as u32, 16)?;
        let resolve = ResolvePass::with_textures(
            ctx.gpu,
            &renderer,
            "biri ldss",
            &format!("{LDSS_WGSL}\n{RESOLVE_WGSL}"),
            Some(std::mem::size_of::<ConfigUniform>() as u64),
            2,
        );
        let rules = ctx
            .params
            .get("stencil_rules")
            .and_then(ParamValue::as_bool)
            .unwrap_or(false);
        let planes = planes::Planes::new(ctx, &renderer, rules);
        self.state = Some(State {
            renderer,
            resolve,
            planes,
            _table: texture,
            table_view,
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
        let shadowed = st.renderer.scene.features().volumetric_occluders;
        let eye_lit = if shadowed {
            st.planes.update(gpu, frame, &mut report)
        } else {
            0
        };
        if let Some(u) = &st.resolve.uniform {
            gpu.queue.write_buffer(
                u,
                0,
                bytemuck::bytes_of(&ConfigUniform {
                    flags: [shadowed as u32, eye_lit, 0, 0],
                }),
            );
        }
        st.renderer.encode_shadows(enc, &mut report);
        st.renderer.encode_surface(enc, targets, &mut report);
        if shadowed {
            st.planes.encode(gpu, enc, &st.renderer, &st.table_view);
            report.ran("shadow-planes");
        } else {
            report.skip("shadow-planes", "no object casts a volumetric shadow");
        }
        st.resolve.encode_with(
            gpu,
            enc,
            &st.renderer,
            targets,
            &[&st.table_view, &st.planes.acc_view],
        );
        report.ran("ldss");
        Ok(report)
    }
}
