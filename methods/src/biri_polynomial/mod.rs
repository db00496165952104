//! `biri-polynomial`: Biri, Michelin & Arquès, *Real-time single scattering with volumetric
//! shadows* (the earlier, software-assisted version of Biri et al. 2006) — the angular RTE with
//! a polynomial kernel.
//!
//! Algorithm: along a camera ray the in-scattered radiance is rewritten in the angle θ between
//! the ray point and the light's foot on the ray (x = t + h tanθ, eq. 3): L_in = σ_s I e^(−σ_t t)/h
//! ∫ Λ(θ) dθ with Λ(θ) = e^(−σ_t h (sinθ+1)/cosθ) p(θ + π/2) (eq. 4). Λ is replaced by a
//! polynomial of order n, so a lit segment costs a constant number of operations (eq. 6). The
//! paper evaluates this per vertex of tessellated surfaces and of meshed shadow planes, and
//! handles volumetric shadows by adding front-facing and subtracting back-facing shadow-plane
//! contributions in a front-to-back order with stencil counting (eq. 11–14, §4.3–4.4).
//!
//! What is here (see README.md for the measurements):
//! - `poly`: Λ, its Taylor coefficients of any order (power-series arithmetic; the annex's
//!   isotropic c0…c4 agree to 1e-12; its hazy and murky c0, c2 agree but its c1 do not — hazy
//!   prints +9/36 for −9/32, murky +c0·k for −c0·k, checked against finite differences — and the
//!   annex's hazy/murky are not normalised: ×8π and ×(4π + 400π/66) of scatterbench's p), the
//!   Chebyshev fit over a segment's own [θ0, θd] (our improvement: Chebyshev interpolation at
//!   n+1 nodes, integrated in closed form — Clenshaw–Curtis), and the lit-segment integral.
//! - `kernel.wgsl`: the same in f32 (checked against `poly` on the GPU in
//!   `tests/biri_polynomial.rs`).
//! - The registered renderer evaluates eq. 3+6 per FRAGMENT over the whole ray [0, d] for point
//!   lights, on scenes WITHOUT volumetric occluders (e.g. `clear-fog`). Surfaces come from the
//!   shared forward pass (shadow maps; the paper's first pass uses stencil shadows and OpenGL fog).
//!
//! Not done (so refused by `support`): shadow planes (eq. 11–14, stencil counting, front-to-back
//! ordering), per-vertex Gouraud evaluation on tessellated surfaces and meshed planes (knobs
//! `eval`, `tessellation`), the `unorm8` accumulation of §5.2, spot lights (eq. 7's Δ_i tables)
//! and directional lights. Limits of the polynomial itself: Taylor around θ = 0 degrades as
//! |θ| → π/2 (rays passing near the light, or long rays far from it: the paper's caveat);
//! Chebyshev stays accurate since it fits the range actually used.

use anyhow::Result;
use bytemuck::{Pod, Zeroable};
use harness::method::PrepareContext;
use harness::{FrameReport, Gpu, Method, MethodInfo, ParamSpec, ParamValue, Support, Targets};
use scenes::{FrameState, SceneFeatures};

use crate::common::renderer::{SceneRenderer, unsupported};
use crate::common::resolve::ResolvePass;

#[cfg(test)]
mod measure_tests;
pub mod poly;
#[cfg(test)]
mod poly_tests;

/// The WGSL kernel library (Λ, Taylor and Chebyshev segment integrals); the including module
/// supplies `biri_phase(cos) -> f32`.
pub const KERNEL_WGSL: &str = include_str!("kernel.wgsl");
const FRAGMENT_WGSL: &str = include_str!("fragment.wgsl");

/// The per-fragment pass's own WGSL (composed after PRELUDE and FULLSCREEN by `ResolvePass`).
pub fn fragment_wgsl() -> String {
    format!("{FRAGMENT_WGSL}\n{KERNEL_WGSL}")
}

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct PolyUniform {
    config: [u32; 4],
    series: [f32; 12],
}

#[derive(Default)]
pub struct BiriPolynomial {
    state: Option<State>,
}

struct State {
    renderer: SceneRenderer,
    pass: ResolvePass,
    uniform: PolyUniform,
}

impl Method for BiriPolynomial {
    fn info(&self) -> MethodInfo {
        MethodInfo {
            id: "biri-polynomial",
            paper: "Biri, Michelin & Arquès, Real-time single scattering with volumetric shadows (software-assisted precursor of Biri et al. 2006)",
            summary: "Angular RTE with a polynomial kernel: constant-time in-scattering per ray (per-fragment; unshadowed scenes only so far)",
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
        if scene.light_kinds.iter().any(|k| *k != "point") {
            return Support::No(
                "only point lights (spots need eq. 7's Δ_i tables, not implemented)".into(),
            );
        }
        if scene.volumetric_occluders {
            return Support::No(
                "volumetric shadows need the shadow planes of §4.2–4.4, not implemented yet".into(),
            );
        }
        let mut ignored = Vec::new();
        if scene.indirect_single_scattering {
            ignored.push("indirect_single_scattering".into());
        }
        if ignored.is_empty() {
            Support::Full
        } else {
            Support::Partial(ignored)
        }
    }

    fn prepare(&mut self, ctx: &PrepareContext) -> Result<()> {
        let order = ctx
            .params
            .get("order")
            .and_then(ParamValue::as_i64)
            .unwrap_or(4);
        if !(2..=poly::MAX_ORDER as i64).contains(&order) {
            anyhow::bail!("order must be 2…{}, not {order}", poly::MAX_ORDER);
        }
        let fit = poly::Fit::parse(
            ctx.params
                .get("fit")
                .and_then(ParamValue::as_str)
                .unwrap_or("taylor"),
        )
        .map_err(anyhow::Error::msg)?;
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
        let renderer = SceneRenderer::new(ctx, 1024, 16)?;
        let pass = ResolvePass::new(
            ctx.gpu,
            &renderer,
            "biri-fragment",
            &fragment_wgsl(),
            Some(std::mem::size_of::<PolyUniform>() as u64),
        );
        let uniform = PolyUniform {
            config: [order as u32, (fit == poly::Fit::Chebyshev) as u32, 0, 0],
            series,
        };
        self.state = Some(State {
            renderer,
            pass,
            uniform,
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
        if let Some(u) = &st.pass.uniform {
            gpu.queue
                .write_buffer(u, 0, bytemuck::bytes_of(&st.uniform));
        }
        st.renderer.encode_shadows(enc, &mut report);
        st.renderer.encode_surface(enc, targets, &mut report);
        st.pass.encode(gpu, enc, &st.renderer, targets);
        report.ran("polynomial-fragment");
        Ok(report)
    }
}
