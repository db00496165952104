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

mod passes;

use anyhow::{Result, bail};
use harness::method::PrepareContext;
use harness::{
    FrameReport, Gpu, Method, MethodInfo, ParamSpec, ParamValue, Params, Support, Targets,
};
use scenes::{FrameState, SceneFeatures};

use crate::common::renderer::{SceneRenderer, unsupported};
use passes::{FLAG_CLIP_LAST, FLAG_JITTER, Passes, PlanesUniform};
pub use passes::{far_source, planes_source, probe_light_map, probe_source, resolve_source};

#[derive(Default)]
pub struct DobashiVirtualPlanes {
    state: Option<State>,
}

struct State {
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

fn int(p: &Params, k: &str, lo: i64, hi: i64) -> Result<u32> {
    let v = p
        .get(k)
        .and_then(ParamValue::as_i64)
        .ok_or_else(|| anyhow::anyhow!("knob '{k}' missing or not an integer"))?;
    if !(lo..=hi).contains(&v) {
        bail!("knob '{k}' = {v} is outside {lo}..={hi}");
    }
    Ok(v as u32)
}

fn flag(p: &Params, k: &str) -> bool {
    p.get(k).and_then(ParamValue::as_bool).unwrap_or(false)
}

fn choice<'a>(p: &'a Params, k: &str, default: &'a str) -> &'a str {
    p.get(k).and_then(ParamValue::as_str).unwrap_or(default)
}

impl Config {
    fn from_params(p: &Params) -> Result<Config> {
        let unorm8 = match choice(p, "accum", "float") {
            "float" => false,
            "unorm8" => true,
            other => bail!("knob 'accum' = '{other}': expected float or unorm8"),
        };
        let xi_fragment = match choice(p, "xi", "vertex") {
            "vertex" => false,
            "fragment" => true,
            other => bail!("knob 'xi' = '{other}': expected vertex or fragment"),
        };
        let scale = p
            .get("unorm8_scale")
            .and_then(ParamValue::as_f64)
            .unwrap_or(1.0);
        if !(scale.is_finite() && scale > 0.0) {
            bail!("knob 'unorm8_scale' = {scale} must be a positive number");
        }
        Ok(Config {
            planes: int(p, "planes", 1, 4096)?,
            lattice: int(p, "lattice", 2, 1024)?,
            xi_fragment,
            jitter: flag(p, "jitter"),
            clip_last: flag(p, "clip_last"),
            unorm8,
            scale: if unorm8 { scale as f32 } else { 1.0 },
        })
    }
    fn flags(&self) -> u32 {
        (self.jitter as u32 * FLAG_JITTER)
            | (self.clip_last as u32 * FLAG_CLIP_LAST)
    }
}

impl DobashiVirtualPlanes {
    /// The prepared renderer (tests probe the light map through it).
    pub fn renderer(&self) -> Option<&SceneRenderer> {
        self.state.as_ref().map(|s| &s.renderer)
    }
    /// Uploads a frame's camera, lights and objects without rendering (for probes).
    pub fn update(&mut self, gpu: &Gpu, frame: &FrameState) -> Result<()> {
        let st = self
            .state
            .as_mut()
            .ok_or_else(|| anyhow::anyhow!("update before prepare"))?;
        st.renderer.update(gpu, frame);
        Ok(())
    }
}

impl Method for DobashiVirtualPlanes {
    fn info(&self) -> MethodInfo {
        MethodInfo {
            id: "dobashi-virtual-planes",
            paper: "Dobashi, Yamamoto & Nishita, Interactive Rendering Method for Displaying Shafts of Light, Pacific Graphics 2000",
            summary: "Screen-parallel virtual planes: ξ on a lattice, light maps, shadow maps, additive blending",
        }
    }

    fn params(&self) -> Vec<ParamSpec> {
        let int = |name, default, sweep: &[i64], meaning| ParamSpec {
            name,
            default: ParamValue::Int(default),
            sweep: sweep.iter().copied().map(ParamValue::Int).collect(),
            choices: vec![],
            meaning,
        };
        let text = |name, default: &str, choices: Vec<&'static str>, meaning| ParamSpec {
            name,
            default: ParamValue::Text(default.into()),
            sweep: choices
                .iter()
                .filter(|c| **c != default)
                .map(|c| ParamValue::Text(c.to_string()))
                .collect(),
            choices,
            meaning,
        };
        let boolean = |name, default: bool, meaning| ParamSpec {
            name,
            default: ParamValue::Bool(default),
            sweep: vec![ParamValue::Bool(!default)],
            choices: vec![],
            meaning,
        };
        vec![
            int(
                "planes",
                75,
                &[15, 30, 150, 300],
                "virtual planes n, evenly spaced in view depth from the eye to the farthest visible point",
            ),
            int(
                "lattice",
                20,
                &[5, 40, 80],
                "lattice points per side of each plane (nu = nv) where ξ is evaluated",
            ),
            text(
                "xi",
                "vertex",
                vec!["vertex", "fragment"],
                "where ξ is evaluated: lattice vertices, Gouraud-interpolated (paper), or per fragment",
            ),
            int(
                "light_map",
                256,
                &[64, 128, 512],
                "light-map (spot pattern texture) resolution, texels per side",
            ),
            int(
                "shadow_map",
                1024,
                &[256, 512, 2048],
                "shadow-map resolution per face, texels",
            ),
            boolean(
                "jitter",
                false,
                "per-pixel random plane offset within each slab instead of slab midpoints (the paper's future work)",
            ),
            boolean(
                "clip_last",
                true,
                "shorten the slab a surface cuts to end at the surface (false: the paper — planes behind the surface are dropped)",
            ),
            text(
                "accum",
                "float",
                vec!["float", "unorm8"],
                "accumulation target: float (Rgba32Float) or the paper's 8-bit frame buffer (Rgba8Unorm)",
            ),
            ParamSpec {
                name: "unorm8_scale",
                default: ParamValue::Float(1.0),
                sweep: vec![],
                choices: vec![],
                meaning: "accum=unorm8: the target stores scale·L_in, so full scale (255) is L_in = 1/scale W/(m² sr)",
            },
        ]
    }

    fn support(&self, scene: &SceneFeatures, device: wgpu::Features) -> Support {
        if let Some(why) = unsupported(scene) {
            return Support::No(why);
        }
        if !device.contains(wgpu::Features::FLOAT32_BLENDABLE) {
            return Support::No(
                "the adapter cannot blend Rgba32Float targets (FLOAT32_BLENDABLE)".into(),
            );
        }
        if scene.indirect_single_scattering {
            return Support::Partial(vec!["indirect_single_scattering".into()]);
        }
        Support::Full
    }

    fn prepare(&mut self, ctx: &PrepareContext) -> Result<()> {
        let cfg = Config::from_params(ctx.params)?;
        let renderer = SceneRenderer::new(
            ctx,
            int(ctx.params, "shadow_map", 16, 8192)?,
            int(ctx.params, "light_map", 1, 8192)?,
        )?;
        let format = if cfg.unorm8 {
            wgpu::TextureFormat::Rgba8Unorm
        } else {
            if !ctx
                .gpu
                .features()
                .contains(wgpu::Features::FLOAT32_BLENDABLE)
            {
                bail!("the adapter cannot blend Rgba32Float targets (FLOAT32_BLENDABLE)");
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
        self.state = Some(State {
            renderer,
            passes,
            cfg,
            skip_planes,
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
        let cfg = st.cfg;
        let mut report = FrameReport::default();
        st.renderer.update(gpu, frame);
        st.passes.write_uniform(
            gpu,
            &PlanesUniform {
                config: [cfg.planes, cfg.lattice, cfg.lattice, cfg.flags()],
                frame: [frame.index, 0, 0, 0],
                scale: [cfg.scale, 0.0, 0.0, 0.0],
            },
        );
        st.renderer.encode_shadows(enc, &mut report);
        st.renderer.encode_surface(enc, targets, &mut report);
        if st.skip_planes {
            report.skip("far-extent", "σ_s = 0: no in-scattering");
            report.skip("planes", "σ_s = 0: no in-scattering");
            st.passes.encode_planes(enc, &st.renderer, 0);
        } else {
            st.passes.encode_far(enc, &st.renderer);
            report.ran("far-extent");
            st.passes.encode_planes(enc, &st.renderer, cfg.planes);
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
        st.passes.encode_resolve(gpu, enc, &st.renderer, targets);
        report.ran("resolve");
        Ok(report)
    }
}
