//! `prefiltered-single-scattering`: in-scatter with volumetric shadows at a cost per pixel that
//! does not grow with the shadows' frequency — the visibility along each epipolar plane is
//! prefiltered once per frame (a rectified shadow map expanded in a basis and prefix-summed
//! along its rows), and each pixel reads its ray's mean visibility in a few lookups.
//!
//! Algorithm, per light: (1) `slice_rows`: N epipolar slices (common::epipolar::rectification, as
//! in
//! epipolar-minmax) and the range of eye angles α of each slice's camera rays (α: the angle at
//! the eye between the ray and the direction toward the light). (2) `rectify`: K texels per
//! slice over its rectified coordinate u ∈ [0, u_max] (the angle about a local light from its
//! axis toward the eye; the distance across a directional light's rays); at each, the caster of
//! the shadow map's stored depth is turned into the eye angle θ_c at which the eye sees it. Along
//! one light ray, away from the light, the eye angle grows, so a camera ray of the plane at eye
//! angle α is lit where it crosses light ray u iff α < θ_c(u): V(u, α) = H(θ_c(u) − α), a step
//! in a value (θ_c) that does not depend on the camera ray. θ_c is mapped to z_c ∈ [0, 1] over
//! the slice's α range and expanded in the basis (basis.wgsl): Fourier, cos and sin of
//! π(2k − 1) z_c (Annen et al. 2007, Klehm et al. 2014), or the moments z_c … z_c⁴ (Peters et
//! al. 2016). (3) `prefix`: the coefficients summed along each row. (4) `shade`: a pixel's ray
//! lies in its own epipolar plane, between two slices (weighted by its slice coordinate); its
//! u runs from 0 at the eye to u_end; `segments` equal pieces in u each add the piece's
//! unshadowed in-scatter (common LIGHT_SEGMENTS: closed form for a directional light, Gauss–
//! Legendre in the angle about a point or spot light) times its mean visibility over the piece,
//! reconstructed from the mean coefficients (two prefix-sum lookups per channel). In the angle
//! about a local light the integrand I p e^(−σt(t + r)) / h dφ is constant for isotropic phase
//! without extinction, so uniform weighting in u is exact there; elsewhere `segments` refines it.
//! (5) `publish` the summed in-scatter for the resolve. Several lights run in turn and add.
//!
//! Papers: Klehm, Seidel & Eisemann, "Prefiltered Single Scattering", I3D 2014 (read: the
//! authors' slides and abstract — a rectified shadow map, visibility in the convolution-shadow-
//! map Fourier basis, prefix-sum-like filtering along camera rays, "almost independent of the
//! screen resolution"); Annen, Mertens, Bekaert, Seidel & Kautz, "Convolution Shadow Maps",
//! EGSR 2007 (the Fourier expansion of the shadow test); Peters, Münstermann, Wetzstein & Klein,
//! "Beyond Hard Shadows: Moment Shadow Maps for Single Scattering, Soft Shadows and Translucent
//! Occluders", I3D 2016, and "Improved Moment Shadow Maps for Translucent Occluders, Soft Shadows
//! and Single Scattering", JCGT 6(1) 2017 (read: the JCGT abstract — "one lookup per pixel in a
//! prefiltered moment shadow map with six channels"); Peters & Klein, "Moment Shadow Mapping",
//! I3D 2015 (the 4-moment Hamburger reconstruction; its public-domain shader code was read, not
//! copied). The full papers were not reachable here.
//!
//! My reading, not read from the papers: which value the rows store — the caster's eye angle
//! θ_c, so that the shadow test of every camera ray of the plane is a step in one variable and
//! the filtering is independent of the ray; the per-slice mapping of θ_c to [0, 1] over the
//! slice's ray angles (values outside clamp without changing any of its rays' tests); the
//! double-float prefix sums of the moments; the lookups at fractional texel positions.
//!
//! Faithful: rectified rows per epipolar slice, the Fourier basis of convolution shadow maps
//! with a truncation knob, the four moments with Peters & Klein's bias and reconstruction,
//! prefix sums along the rows, one filtered visibility per camera ray (`segments = 1`).
//! Modernised: `segments > 1` pieces per ray, each weighted by its unshadowed in-scatter (the
//! papers' one lookup assumes the in-scatter uniform along the ray in u); Lanczos σ factors
//! against the Fourier series' ringing (`lanczos`); point and spot lights besides directional;
//! the pixel's visibility interpolated between the two nearest slices.
//! Limits: hard shadow-map casters only (a translucent caster's coloured transmittance is not
//! filtered: the stained-glass pattern is the spot's emission, which the unshadowed quadrature
//! carries); a texel point-samples the shadow map at its centre; the Fourier series rings and the
//! moment bound leaks light where an interval holds several caster angles (README); homogeneous
//! media without height fog (its σ varies along the ray).

mod passes;

use anyhow::Result;
use harness::method::{PrepareContext, ShaderCheck};
use harness::{
    Aov, ConformanceCase, FrameReport, Gpu, Knob, KnobRead, Medium, Method, MethodInfo, Prepared,
    Support, Targets,
};
use scenes::{FrameState, SceneFeatures};

use crate::common::height_fog::constant_sigma_only;
use crate::common::knobs;
use crate::common::epipolar::published::PUBLISHED_RESOLVE;
use crate::common::epipolar::skeleton;
use crate::common::renderer::{SceneRenderer, homogeneous_support};
use crate::common::shadow_maps::ShadowSettings;
use passes::Passes;
pub use passes::{BASIS_WGSL, Basis, Sizes, compute_source};

/// The method (a description; [`State`] is the prepared instance).
pub struct PrefilteredSingleScattering;

/// The prepared method.
pub struct State {
    pub renderer: SceneRenderer,
    passes: Passes,
    frame: skeleton::Frame,
}

/// The basis the knobs name.
fn basis(ctx: &PrepareContext) -> Result<Basis> {
    let p = ctx.params;
    Ok(match p.knob::<String>("basis")?.as_str() {
        "fourier" => Basis::Fourier {
            terms: p.knob("terms")?,
            lanczos: p.knob("lanczos")?,
        },
        _ => Basis::Moments,
    })
}

impl State {
    pub fn new(ctx: &PrepareContext) -> Result<State> {
        let p = ctx.params;
        let gpu = ctx.gpu;
        let renderer =
            SceneRenderer::new(ctx, ShadowSettings::from_params(p)?, p.knob("pattern_res")?)?;
        let slices_knob: u32 = p.knob("slices")?;
        let sizes = Sizes {
            // 0: one slice per two pixels of the screen's border (its perimeter is 2 (W + H)).
            slices: if slices_knob == 0 {
                (renderer.width + renderer.height).max(1)
            } else {
                slices_knob
            },
            texels: p.knob("texels")?,
            segments: p.knob("segments")?,
            panels: p.knob("panels")?,
            basis: basis(ctx)?,
            moment_bias: p.knob("moment_bias")?,
            width: renderer.width,
            height: renderer.height,
        };
        let passes = Passes::new(gpu, &renderer, sizes);
        Ok(State {
            // Two phases per light: rows, shade.
            frame: skeleton::Frame::new(gpu, &renderer, "prefiltered resolve", 2),
            renderer,
            passes,
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
        self.passes.write_uniforms(gpu);
        let mut report = self.frame.open(&mut self.renderer, gpu, frame, targets, enc);
        let encoding = self.frame.encoding(gpu, &self.renderer);
        self.passes.encode(enc, encoding);
        report.ran("shade");
        if self.renderer.shadows_on {
            report.ran("rows");
        } else {
            report.skip("rows", "no object casts a volumetric shadow");
        }
        let published = &self.passes.published;
        (self.frame).close(&self.renderer, published, gpu, targets, enc, &mut report);
        let s = self.passes.sizes;
        report.count("slices", s.slices as f64);
        report.count("texels_per_row", s.texels as f64);
        report.count("channels", s.basis.channels() as f64);
        report.count("row_bytes", passes::rows_bytes(&s) as f64);
        Ok(report)
    }

    fn phase_timer(&self) -> Option<&harness::gpu::PhaseTimer> {
        self.frame.timer.as_ref()
    }
}

/// Fourier terms (even: two per vec4 channel; 32 fills basis.wgsl's MAX_CHANNELS).
const TERMS: &[i64] = &[2, 4, 8, 16, 32];

impl Method for PrefilteredSingleScattering {
    fn info(&self) -> MethodInfo {
        harness::method_info!(
            "prefiltered-single-scattering",
            Medium::Homogeneous,
            "Klehm, Seidel & Eisemann, Prefiltered Single Scattering, I3D 2014; Peters, Münstermann, Wetzstein & Klein, Beyond Hard Shadows: Moment Shadow Maps for Single Scattering, Soft Shadows and Translucent Occluders, I3D 2016 (JCGT 2017)",
            "Rectified shadow-map rows per epipolar slice in a Fourier or moment basis, prefix-summed: each pixel's filtered visibility in a few lookups",
        )
    }

    fn knobs(&self) -> Vec<Knob> {
        let own = vec![
            Knob::choice("basis", "moments", &["moments", "fourier"])
                .sweep(["fourier"])
                .meaning("visibility basis of the rectified rows: Peters et al.'s four moments or Klehm et al.'s Fourier series"),
            Knob::int_of("terms", 16, TERMS)
                .sweep([4, 8, 32])
                .unit("terms")
                .meaning("basis = fourier: terms of the truncated series (Klehm et al.'s slides show 16)"),
            Knob::boolean("lanczos", false)
                .sweep([true])
                .meaning("basis = fourier: damp term k by Lanczos' σ factor sinc(k / (terms + 1)) against ringing (modernised; false = the papers' plain truncation)"),
            Knob::float("moment_bias", 3e-5, 0.0..=0.1)
                .sweep([3e-7, 3e-4])
                .meaning("basis = moments: weight of a uniform distribution's moments mixed into the mean moments (Peters & Klein 2015: 3e-5 for [0, 1] depths)"),
            Knob::int("slices", 0, 0..=8192)
                .sweep([64, 256, 1024])
                .unit("slices")
                .meaning("epipolar slices (rectified rows) per light; 0 = width + height, one per two pixels of the screen border"),
            Knob::int("texels", 512, 16..=4096)
                .sweep([128, 256, 1024])
                .unit("texels")
                .meaning("texels of a rectified row"),
            Knob::int("segments", 16, 1..=64)
                .sweep([1, 4, 8, 32])
                .unit("pieces")
                .meaning("pieces of a camera ray in the rectified coordinate, each its own filtered visibility times its unshadowed in-scatter; 1 = the papers' one lookup per ray"),
            Knob::int("panels", 2, 1..=64)
                .sweep([1, 4])
                .unit("panels")
                .meaning("two-node Gauss–Legendre panels per piece for a point or spot light's unshadowed in-scatter"),
        ];
        knobs::with_shadow_maps(own, knobs::shadow_map(1024))
    }

    fn support(&self, scene: &SceneFeatures, device: wgpu::Features) -> Support {
        if let Some(no) = constant_sigma_only(
            scene,
            "the unshadowed in-scatter of a piece (common LIGHT_SEGMENTS) assumes a constant σ",
        ) {
            return no;
        }
        homogeneous_support(scene, device, None)
    }

    fn prepare(&self, ctx: &PrepareContext) -> Result<Box<dyn Prepared>> {
        Ok(Box::new(State::new(ctx)?))
    }

    fn shaders(&self) -> Vec<ShaderCheck> {
        let on_off: &[f64] = &[0.0, 1.0];
        let axes = [("BASIS", on_off), ("LANCZOS", on_off), ("SHADOWED", on_off)];
        let id = "prefiltered-single-scattering";
        skeleton::shader_checks(id, &compute_source(), &axes, PUBLISHED_RESOLVE)
    }

    fn conformance(&self) -> Vec<ConformanceCase> {
        // Measured in-scatter rel RMSE at 48²: 0.0023 moments, 0.0054 Fourier; bounds ~2×.
        vec![
            ConformanceCase::new("sphere-point", 48, Aov::Inscatter, 0.005),
            ConformanceCase::new("sphere-point", 48, Aov::Inscatter, 0.01).knob("basis", "fourier"),
        ]
    }
}
