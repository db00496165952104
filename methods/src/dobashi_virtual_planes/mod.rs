//! `dobashi-virtual-planes`: in-scattering integrated by rasterising virtual planes parallel to
//! the image plane and adding them up (a slice-based volume renderer).
//!
//! Algorithm: after the shared shadow-map and surface passes, a compute reduction finds Z, the
//! view depth of the farthest visible point (the far plane where a ray escapes). n planes at view
//! depths (k + ½)Δz, Δz = Z/n, each an nu×nv lattice mesh covering the frustum, are drawn in one
//! instanced call. At each lattice vertex ξ = σ_s p(α) e^(−σt (t + r)) / r² (σ_s p(α) e^(−σt t) for
//! a parallel light) is evaluated and Gouraud-interpolated; each fragment multiplies in the light
//! map I(θ, φ) (the spot's pattern texture projected from the light, times the cone falloff) and
//! the shadow-map visibility H, scales by its ray-length increment Δs = Δz / cos(angle to the view
//! axis) and is added into an accumulation target. A full-screen pass turns the accumulation into
//! `inscatter` and writes `total` = surface + inscatter + ambient.
//!
//! Paper: Y. Dobashi, T. Yamamoto, T. Nishita, *Interactive rendering method for displaying shafts
//! of light*, Pacific Graphics 2000 (eq. 5, §5.1–5.3).
//!
//! Faithful: screen-parallel planes at a regular spacing, ξ at lattice points interpolated by
//! Gouraud shading (knob `xi=vertex`), light maps for I(θ, φ) by projective texturing, point,
//! spot and parallel lights, additive blending; every phase function of the scene (hazy Mie as in
//! the paper). Modernised: visibility by a shadow-map comparison per plane fragment instead of the
//! per-plane shadow textures read back from the frame buffer (§5.2; the paper's own "future
//! hardware"); a float accumulation target (`accum=unorm8` shows the 8-bit problem of §7);
//! per-pixel jittered plane offsets (`jitter`, the paper's future work); all lights in one set of
//! planes (the paper draws the planes once per light); Δs per pixel (the paper's Δt is exact only
//! on the view axis); the slab a surface cuts is shortened to end at the surface (`clip_last`;
//! the paper drops it); the planes span [0, Z] from the eye, not from the near plane. `xi=fragment`
//! evaluates ξ per fragment (no lattice error). The cone falloff stays analytic — only the
//! pattern is a texture, as in every method here, so the light map's error is the pattern's.
//!
//! Limits: the spacing Δz is uniform, so a scene whose far plane is visible spends most planes
//! where little light is; shadows and thin shafts alias between planes (Fig. 5); the 1/r² peak
//! near a light inside the view is under-sampled by a coarse lattice (Fig. 6a); visibility is as
//! good as the shadow map.
//!
//! Exponential height fog: integrated (ξ carries σ_s(x) and both legs' optical depths; eq. 5 is
//! a quadrature of any smooth ξ).

mod passes;

use anyhow::{Result, bail};
use harness::method::{PrepareContext, ShaderCheck};
use harness::{
    Aov, ConformanceCase, FrameReport, Gpu, Knob, KnobRead, Medium, Method, MethodInfo, Params,
    Prepared, Support, Targets,
};
use scenes::{FrameState, SceneFeatures};

use crate::common::knobs;
use crate::common::renderer::{SceneRenderer, homogeneous_support};
use crate::common::shadow_maps::ShadowSettings;

/// Why a device without FLOAT32_BLENDABLE is refused (accum = float blends Rgba32Float).
const NO_FLOAT_BLEND: &str = "the adapter cannot blend Rgba32Float targets (FLOAT32_BLENDABLE)";
use passes::{FLAG_CLIP_LAST, FLAG_JITTER, Passes, PlanesUniform};
pub use passes::{far_source, planes_source, probe_light_map, probe_source, resolve_source};

/// The method (a description; [`State`] is the prepared instance).
pub struct DobashiVirtualPlanes;

/// The prepared method.
pub struct State {
    renderer: SceneRenderer,
    passes: Passes,
    cfg: Config,
    /// σ_s = 0 and not `--no-skip`: the plane passes are skipped.
    skip_planes: bool,
}

/// The knobs, checked.
#[derive(Clone, Copy, Debug)]
struct Config {
    planes: u32,
    lattice: u32,
    xi_fragment: bool,
    jitter: bool,
    clip_last: bool,
    unorm8: bool,
    /// The accumulation target holds `scale`·L_in.
    scale: f32,
}

impl Config {
    fn from_params(p: &Params) -> Result<Config> {
        let unorm8 = p.knob::<String>("accum")? == "unorm8";
        let scale: f32 = p.knob("unorm8_scale")?;
        Ok(Config {
            planes: p.knob("planes")?,
            lattice: p.knob("lattice")?,
            xi_fragment: p.knob::<String>("xi")? == "fragment",
            jitter: p.knob("jitter")?,
            clip_last: p.knob("clip_last")?,
            unorm8,
            scale: if unorm8 { scale } else { 1.0 },
        })
    }
    fn flags(&self) -> u32 {
        (self.jitter as u32 * FLAG_JITTER) | (self.clip_last as u32 * FLAG_CLIP_LAST)
    }
}

impl State {
    /// The prepared renderer (tests probe the light map through it).
    pub fn renderer(&self) -> &SceneRenderer {
        &self.renderer
    }
    /// Uploads a frame's camera, lights and objects without rendering (for probes).
    pub fn update(&mut self, gpu: &Gpu, frame: &FrameState) {
        self.renderer.update(gpu, frame);
    }
}

impl Method for DobashiVirtualPlanes {
    fn info(&self) -> MethodInfo {
        harness::method_info!(
            "dobashi-virtual-planes",
            Medium::Homogeneous,
            "Dobashi, Yamamoto & Nishita, Interactive Rendering Method for Displaying Shafts of Light, Pacific Graphics 2000",
            "Screen-parallel virtual planes: ξ on a lattice, light maps, shadow maps, additive blending",
        )
    }

    fn knobs(&self) -> Vec<Knob> {
        vec![
            Knob::int("planes", 75, 1..=4096)
                .sweep([15, 30, 150, 300])
                .unit("planes")
                .meaning("virtual planes n, evenly spaced in view depth from the eye to the farthest visible point"),
            // Lattice vertices per plane are lattice²; 1024² is the largest index buffer kept.
            Knob::int("lattice", 20, 2..=1024)
                .sweep([5, 40, 80])
                .unit("points per side")
                .meaning("lattice points per side of each plane (nu = nv) where ξ is evaluated"),
            Knob::choice("xi", "vertex", &["vertex", "fragment"])
                .sweep(["fragment"])
                .meaning("where ξ is evaluated: lattice vertices, Gouraud-interpolated (paper), or per fragment"),
            // The paper's name for the spot pattern texture (`pattern_res` elsewhere).
            Knob::int("light_map", 256, 1..=knobs::MAX_TEXTURE_SIDE)
                .sweep([64, 128, 512])
                .unit("texels")
                .meaning("light-map (spot pattern texture) resolution per side"),
            knobs::shadow_map(1024).sweep([256, 512, 2048]),
            knobs::local_shadow_budget(),
            Knob::boolean("jitter", false)
                .meaning("per-pixel random plane offset within each slab instead of slab midpoints (the paper's future work)"),
            Knob::boolean("clip_last", true)
                .meaning("shorten the slab a surface cuts to end at the surface (false: the paper — planes behind the surface are dropped)"),
            Knob::choice("accum", "float", &["float", "unorm8"])
                .sweep(["unorm8"])
                .meaning("accumulation target: float (Rgba32Float) or the paper's 8-bit frame buffer (Rgba8Unorm)"),
            Knob::float("unorm8_scale", 1.0, 1e-9..=1e9)
                .unit("1/(W/(m² sr))")
                .meaning("accum=unorm8: the target stores scale·L_in, so full scale (255) is L_in = 1/scale W/(m² sr)"),
        ]
    }

    fn support(&self, scene: &SceneFeatures, device: wgpu::Features) -> Support {
        homogeneous_support(scene, device, Some(NO_FLOAT_BLEND))
    }

    fn prepare(&self, ctx: &PrepareContext) -> Result<Box<dyn Prepared>> {
        Ok(Box::new(State::new(ctx)?))
    }

    fn shaders(&self) -> Vec<ShaderCheck> {
        [
            ShaderCheck::combinations(
                "dobashi-virtual-planes/planes",
                &planes_source(),
                &[("XI_PER_FRAGMENT", &[0.0, 1.0])],
            ),
            ShaderCheck::combinations("dobashi-virtual-planes/far", &far_source(), &[]),
            ShaderCheck::combinations("dobashi-virtual-planes/resolve", &resolve_source(), &[]),
            ShaderCheck::combinations("dobashi-virtual-planes/probe", &probe_source(), &[]),
        ]
        .concat()
    }

    /// Bounds ≈ 1.5× the rel RMSE measured at 48² on lavapipe: sphere-point 0.20; fence-spot
    /// with ξ per fragment 3.4 (the spot is in view: its 1/r² peak falls between planes).
    fn conformance(&self) -> Vec<ConformanceCase> {
        vec![
            ConformanceCase::new("sphere-point", 48, Aov::Inscatter, 0.3),
            ConformanceCase::new("fence-spot", 48, Aov::Inscatter, 5.0).knob("xi", "fragment"),
        ]
    }
}

impl State {
    pub fn new(ctx: &PrepareContext) -> Result<State> {
        let cfg = Config::from_params(ctx.params)?;
        let renderer = SceneRenderer::new(
            ctx,
            ShadowSettings::from_params(ctx.params)?,
            ctx.params.knob("light_map")?,
        )?;
        let format = if cfg.unorm8 {
            wgpu::TextureFormat::Rgba8Unorm
        } else {
            if !ctx
                .gpu
                .features()
                .contains(wgpu::Features::FLOAT32_BLENDABLE)
            {
                bail!(NO_FLOAT_BLEND);
            }
            wgpu::TextureFormat::Rgba32Float
        };
        let passes = Passes::new(
            ctx.gpu,
            &renderer,
            (cfg.lattice, cfg.lattice),
            format,
            cfg.xi_fragment,
        );
        let skip_planes = !ctx.no_skip && !ctx.scene.features().scattering;
        Ok(State {
            renderer,
            passes,
            cfg,
            skip_planes,
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
        let cfg = self.cfg;
        let mut report = self.renderer.begin_frame(gpu, frame, enc, targets);
        self.passes.write_uniform(
            gpu,
            &PlanesUniform {
                count: cfg.planes,
                nu: cfg.lattice,
                nv: cfg.lattice,
                flags: cfg.flags(),
                frame: frame.index,
                _pad0: [0; 3],
                scale: cfg.scale,
                _pad1: [0.0; 3],
            },
        );
        if self.skip_planes {
            report.skip("far-extent", "σ_s = 0: no in-scattering");
            report.skip("planes", "σ_s = 0: no in-scattering");
            self.passes.encode_planes(enc, &self.renderer, 0);
        } else {
            self.passes.encode_far(enc, &self.renderer);
            report.ran("far-extent");
            self.passes.encode_planes(enc, &self.renderer, cfg.planes);
            report.ran("planes");
            let lattice = (cfg.lattice as u64).pow(2);
            let pixels = targets.width as u64 * targets.height as u64;
            report.count("planes", cfg.planes as f64);
            // ξ per lattice vertex (each vertex once: the lattice is indexed), or per fragment.
            report.count(
                "lattice_vertices",
                if cfg.xi_fragment {
                    0
                } else {
                    cfg.planes as u64 * lattice
                } as f64,
            );
            // Rasterised: every plane covers the screen; the surface test then discards some.
            report.count("fragments", (cfg.planes as u64 * pixels) as f64);
        }
        self.passes
            .encode_resolve(gpu, enc, &self.renderer, targets);
        report.ran("resolve");
        Ok(report)
    }
}
