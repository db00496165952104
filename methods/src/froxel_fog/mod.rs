//! `froxel-fog`: frustum-aligned volumetric fog — a 3-D grid of "froxels" filled by a compute
//! pass, integrated front to back by a second, read once per pixel (what Unreal, Godot and
//! Frostbite ship), for homogeneous and particle media alike.
//!
//! Algorithm: the shared shadow-map and surface passes; `inject` (one dispatch per light that
//! can reach the view frustum, `reach.rs`) evaluates the in-scatter source
//! S = σ_s Σ_lights p(θ) V I(ω) e^(−σ_t r) / r² at one point of every froxel, V from the common
//! shadow maps, I(ω) the spot falloff and pattern, and a point or spot light's 1/r² as its
//! closed-form mean over the slice and the column's footprint (`falloff`) — and where a slice
//! spans more than 0.2 rad seen from the light, the whole slice's in-scatter by Gauss nodes in
//! that angle (`falloff` = quadrature, slice_quadrature.wgsl); `temporal` (with `temporal` N > 0)
//! blends this frame's jittered injection into the previous frames', reprojected through the
//! previous camera, stale history kept, clamped to this frame's 3 × 3 × 3 range, or dropped where
//! the lighting changed (`history`, default range: the unjittered centre sample compared with
//! the history's, under a moving camera the reprojected one with this frame's 3 × 3 × 3 range, or
//! (revisit) at the previous grid's froxel centres re-evaluated this frame; the rejecting modes keep the jittered samples' mean less the centre sample, and show
//! the centre sample plus that residual); `integrate` walks each froxel column from the eye,
//! L += T (S − S e^(−σ_t d)) / σ_t, T *= e^(−σ_t d) per slice of length d, storing L at every
//! slice's far boundary; `apply` reads L at each pixel's ray length (bilinear across columns,
//! linear between slice boundaries). The grid has `columns` columns across the image (or columns
//! of `pixel_size` pixels with `columns` = 0); slice boundary k sits at view depth
//! far · (k / slices)^`depth_exponent`.
//! Particle media (Hillaire's unified volumes): the particles are binned on the CPU into the
//! froxel columns their spheres can reach (`particles.rs`); `voxelise` spreads each sphere's
//! exact chord along 2 × 2 sub-rays of its column over the slices it crosses (each froxel's mean
//! σ_s and τ, and the particles' extinction-weighted mean depth, where that froxel is then
//! sampled); `extinction` builds one light-space extinction grid per light (orthographic along
//! the sun, a perspective cone or a cube of six from a local light: exact chords per column ray,
//! prefix-summed per slab) from which `inject` takes the cloud's self-shadowing and `particle-shadow` its shadow on
//! surfaces (one redraw per light removing that light's blocked share,
//! `common::particles::surface_shadow`);
//! `integrate` adds the froxels' τ to the background's σ_t and stores the particles'
//! transmittance, which attenuates the surfaces and the sky behind the cloud.
//!
//! Papers: Wronski, "Volumetric fog: unified compute shader based solution to atmospheric
//! scattering", SIGGRAPH 2014 Advances in Real-Time Rendering (inject / integrate / apply over a
//! fixed 160×90×64 frustum grid, exponential slices, cost that follows the grid, jitter and
//! temporal reprojection); Hillaire, "Physically based and unified volumetric rendering in
//! Frostbite", SIGGRAPH 2015 (the energy-conserving per-slice integral; participating media from
//! several sources voxelised into the same volume; volumetric shadows from a light-space
//! extinction volume). Knob defaults after Godot 4 (`volumetric_fog.glsl`,
//! `volumetric_fog_process.glsl`: a 64-wide grid, 64 slices, reprojection blend 0.9 ≈ 10 frames)
//! and Unreal's `r.VolumetricFog.GridPixelSize` 8 / `GridSizeZ` 64 / jitter. No code was taken
//! from them.
//!
//! Faithful: the three passes, one injected sample per froxel with shadow-map visibility, the
//! front-to-back column integration, one volume lookup per pixel (cost follows the grid, not
//! the screen), Halton jitter with reprojected history blended as Godot.
//! Modernised: Hillaire's analytic slice integral instead of Wronski's point sample times slice
//! length; a local light's 1/r² averaged over the froxel in closed form (knob `falloff`; `point`
//! is Wronski's sample), and near the light the slice's whole in-scatter by quadrature in the
//! angle seen from the light (`quadrature`, the default); history rejection by a change in
//! lighting, detected on an unjittered centre sample (`history` = reject; range, the default,
//! tests the reprojected centre against this frame's 3 × 3 × 3 centre range while the camera
//! moves; revisit compares at one world point, re-evaluating the previous frame's froxel
//! centres — it crashes lavapipe in prepare about 3 times in 10 on corridor-walk), the history holding only the jitter's residual over the centre sample, or
//! Karis 2014's TAA clamp in 3-D (`clamp`; `none` is the engines' keep-everything); the jitter
//! in depth kept in front of the froxel column's nearest visible surface (`jitter_bound` =
//! surface, the default; `slice` jitters over the whole slice as Wronski and Unreal), so light
//! behind a thin wall does not leak into the wall's pixels more than one centred sample; each
//! frame's jittered sample paired with its mirror image through the froxel's centre (antithetic
//! variates, `jitter_pair`, the default; `false` is the engines' one sample a frame), a history
//! dropped because the lighting changed restarting from that pair, so reuse does not add flicker
//! (pen-orbit, README); float32 volume; the scene's phase function; spot patterns; particles
//! voxelised by exact chords and a froxel with particles sampled at their mean depth.
//! Limits: shafts thinner than a froxel are blurred across it, and light leaks across depth
//! discontinuities within a froxel column (a surface reads the volume interpolated from its
//! neighbours); a spot's cone is point-sampled per froxel (near its apex the froxel is partly
//! lit); temporal accumulation blurs the history a little on every reprojection, and with
//! `history` = none lags behind moving lights and objects (pen-orbit); history revisit crashes
//! lavapipe's shader compiler now and then (heap corruption in prepare, 3 of 10 corridor-walk
//! runs at 64²; reject and range 0 of 10), and evaluates
//! the previous grid's froxels with this frame's particle density of the same index (particle
//! media under a moving camera: a moved cloud reads as changed lighting, its history dropped);
//! with `jitter_bound` = slice the jittered samples leak light through thin walls more than the
//! centre sample (corridor-walk, README); particle media with
//! at most four lights (one extinction grid each: orthographic for the sun, a cone from a local
//! light seeing the cloud within 80°, else — the light inside a particle or the cloud all around
//! it — a cube of six 90° faces, six times the memory).
//!
//! Exponential height fog: integrated (each slice's mean σ_s and σ_t along its ray, the light
//! leg's exact optical depth), homogeneous media only.

mod grid;
mod particle_passes;
mod particles;
mod passes;
mod reach;
mod shaders;
mod state;

use anyhow::Result;
use harness::method::{PrepareContext, ShaderCheck};
use harness::{
    Aov, ConformanceCase, Knob, KnobRead, Medium, Method, MethodInfo, Prepared, Support,
};
use scenes::SceneFeatures;

use crate::common::knobs;
use crate::common::renderer::{homogeneous_support, renderer_limits};
use particle_passes::PARTICLE_GRIDS;
use passes::HISTORY_MODES;
use shaders::{
    apply_source, particle_shadow_source, particle_surface_source, particles_source, volume_source,
};
pub use state::State;

/// The method (a description; [`State`] is the prepared instance).
pub struct FroxelFog;

impl Method for FroxelFog {
    fn info(&self) -> MethodInfo {
        harness::method_info!(
            "froxel-fog",
            Medium::Both,
            "Wronski, Volumetric fog: unified compute shader based solution to atmospheric scattering, SIGGRAPH 2014 Advances; Hillaire, Physically based and unified volumetric rendering in Frostbite, SIGGRAPH 2015",
            "Frustum-aligned froxel grid: inject, integrate front to back (Hillaire's slice integral), one lookup per pixel",
        )
    }

    fn knobs(&self) -> Vec<Knob> {
        let own = vec![
            Knob::int("columns", 64, 0..=1024)
                .sweep([32, 128])
                .unit("froxels")
                .meaning("froxel columns across the image, rows by its aspect: a grid fixed whatever the resolution (Godot's volume_size 64, AC4's 160; 32 / 64 / 128 at 512² are 16 / 8 / 4 px froxels); 0: columns of pixel_size pixels instead"),
            // No sweep: inert at the default columns (the columns sweep is the same response).
            Knob::int("pixel_size", 8, 2..=64)
                .sweep(Vec::<i64>::new())
                .unit("pixels")
                .meaning("with columns = 0: screen pixels per froxel in x and y (Unreal's GridPixelSize; 8 px at 512² is the default 64 columns)"),
            // 1024 slices already make a 1024² volume texture tile at pixel_size 8 and 512².
            Knob::int("slices", 64, 4..=1024)
                .sweep([32, 128, 256])
                .unit("slices")
                .meaning("froxel slices along view depth, eye to far plane"),
            Knob::float("depth_exponent", 2.0, 1.0..=4.0)
                .sweep([1.0, 3.0])
                .meaning("slice boundary k at depth far·(k/slices)^exponent: 1 linear, larger packs slices near the eye"),
            Knob::choice("falloff", "quadrature", &["quadrature", "slice", "point"])
                .sweep(["slice", "point"])
                .meaning("a point or spot light's 1/r² per froxel: its mean over the slice along the sample ray in closed form (slice), or its value at the sample point (point, Wronski); quadrature: as slice, but where the slice spans more than 0.2 rad seen from the light, the whole slice's in-scatter (1/r², phase, visibility, both legs' attenuation) by 8 Gauss nodes in that angle"),
            Knob::choice("shadow_filter", "none", &["none", "pcf"])
                .sweep(["pcf"])
                .meaning("shadow-map visibility per injected sample: one texel (none), or the lit fraction of the 3 × 3 texels around it (pcf); Wronski's blurred exponential shadow map is not built"),
            Knob::int("temporal", 0, 0..=64)
                .sweep([10])
                .unit("frames")
                .meaning("temporal accumulation: 0 off (one sample at each froxel's centre), N > 0 blends N frames of jittered injection, reprojected (history weight 1 − 1/N after a progressive start; Godot's 0.9 ≈ 10)"),
            Knob::choice("jitter", "depth", &["depth", "cell"])
                .sweep(["cell"])
                .meaning("with temporal > 0, where the sample point moves from frame to frame (Halton 2, 3, 5, rotated per froxel): along its column's centre ray (depth) or over the whole froxel (cell, as Unreal)"),
            // No sweep: inert at the default temporal 0 (README: with temporal on).
            Knob::choice("jitter_bound", "surface", &["surface", "slice"])
                .sweep(Vec::<&str>::new())
                .meaning("with temporal > 0, the depth range a froxel's jittered samples cover: its whole slice (slice, as Wronski, Hillaire and Unreal jitter), or only the slice's part in front of the nearest visible surface of its froxel column (surface: a surface inside the slice reads only that part, so light behind a thin wall no longer leaks into it; one pass over the pixels per frame)"),
            // No sweep: inert at the default temporal 0 (README: with temporal on).
            Knob::boolean("jitter_pair", true)
                .sweep(Vec::<bool>::new())
                .meaning("with temporal > 0: each frame injects its jittered sample and its mirror image through the froxel's centre (antithetic variates: the pair's mean has no first-order jitter error), and a history dropped by reject, range or revisit restarts from this frame's pair; false: one jittered sample a frame, as Wronski, Hillaire and Unreal, and a dropped history restarts from the centre sample alone (true costs one more light evaluation per froxel and frame)"),
            // No sweep: inert at the default temporal 0 (README: each mode with temporal on).
            Knob::choice("history", "range", &HISTORY_MODES)
                .sweep(Vec::<&str>::new())
                .meaning("with temporal > 0, what is done with a reprojected history that is no longer true: kept (none, as Godot's and Unreal's volumetric fog, which drop only history from outside the previous frustum), clamped to the range of this frame's source over the 3 × 3 × 3 froxels around (clamp: Karis 2014's TAA neighbourhood clamp), or dropped where the froxel's unjittered centre sample changed by more than reject_change since the history began, the froxel then showing that centre sample (reject; one more light evaluation per froxel; a moving camera moves every froxel's centre, so it drops all history then), or as reject but, where the camera moved, dropped where the reprojected centre sample the history began with lies outside the range of this frame's centre samples over the 3 × 3 × 3 froxels around, widened by reject_change (range), or as reject but, where the camera moved, dropped where this frame's lighting at the previous grid's froxel centres the history is read from changed by more than reject_change since last frame (revisit; one more light evaluation per froxel while the camera moves)"),
            Knob::float("reject_change", 0.001, 0.0..=1.0)
                .sweep(Vec::<f64>::new())
                .meaning("with history = reject, range or revisit: the relative change of a froxel's centre source since its history began beyond which the history is dropped (the centre sample is not jittered, so only a change in the lighting, shadows or medium trips it)"),
            Knob::int("extinction_grid", 64, 4..=256)
                .sweep([32, 128])
                .unit("texels")
                .meaning("particle media: columns per side and slabs of each light's extinction grid (the cloud's self-shadowing and its shadow on surfaces)"),
        ];
        knobs::with_shadow_maps(own, knobs::shadow_map(1024))
    }

    fn converge_frames(&self, params: &harness::Params) -> u32 {
        params.knob::<u32>("temporal").unwrap_or(0)
    }

    fn support(&self, scene: &SceneFeatures, device: wgpu::Features) -> Support {
        if scene.medium != "particles" {
            return homogeneous_support(scene, device, None);
        }
        if let Some(why) = renderer_limits(scene) {
            return Support::No(why);
        }
        if scene.lights > PARTICLE_GRIDS {
            return Support::No(format!(
                "particle media with {} lights: one light-space extinction grid per light (extinction_grid³ optical depths each, 64 MiB at 256), at most {PARTICLE_GRIDS}",
                scene.lights
            ));
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
        [
            ShaderCheck::combinations(
                "froxel-fog/volume",
                &volume_source(),
                &[
                    ("LIGHT", &[0.0, 1.0, 2.0, 3.0]),
                    ("FIRST", &[0.0, 1.0]),
                    ("TEMPORAL", &[0.0, 1.0]),
                    ("SLICE_FALLOFF", &[0.0, 1.0]),
                    ("SHADOW_PCF", &[0.0, 1.0]),
                    ("PARTICLES", &[0.0, 1.0]),
                ],
            ),
            // The slice quadrature near local lights (SLICE_QUADRATURE 0 is in the product above).
            ShaderCheck::combinations(
                "froxel-fog/volume",
                &volume_source(),
                &[
                    ("LIGHT", &[0.0, 1.0]),
                    ("SLICE_FALLOFF", &[1.0]),
                    ("SLICE_QUADRATURE", &[1.0]),
                    ("SHADOW_PCF", &[0.0, 1.0]),
                    ("PARTICLES", &[0.0, 1.0]),
                ],
            ),
            // The history modes of the temporal pass (HISTORY 0 is in the product above).
            ShaderCheck::combinations(
                "froxel-fog/volume",
                &volume_source(),
                &[
                    ("TEMPORAL", &[1.0]),
                    ("HISTORY", &[1.0, 2.0, 3.0, 4.0]),
                    ("JITTER_PAIR", &[0.0, 1.0]),
                ],
            ),
            // The jitter bounded in front of the nearest surface (jitter_bound = surface).
            ShaderCheck::combinations(
                "froxel-fog/volume",
                &volume_source(),
                &[("TEMPORAL", &[1.0]), ("SURFACE_BOUND", &[1.0])],
            ),
            ShaderCheck::combinations("froxel-fog/apply", &apply_source(), &[]),
            ShaderCheck::combinations("froxel-fog/particles", &particles_source(), &[]),
            ShaderCheck::combinations(
                "froxel-fog/particle-surface",
                &particle_surface_source(),
                &[],
            ),
            ShaderCheck::combinations(
                "froxel-fog/particle-shadow",
                &particle_shadow_source(),
                &[("SURFACE_LIGHT", &[0.0, 3.0])],
            ),
        ]
        .concat()
    }

    /// Particle stress cases: about 2× the total's rel RMSE `scatterbench stress --res 64`
    /// measured on lavapipe (noted; `particle-million` at 1M and at CI's 20k particles, the
    /// larger), 1e-3 where the exact answer is the surfaces alone (zero density).
    fn stress_bound(&self, case: &str) -> Option<f64> {
        match case {
            "particle-fills-view" => Some(0.02),        // 0.0047
            "particle-million" => Some(0.1),            // 0.046 at 1M, 0.037 at 20k
            "particles-same-centre" => Some(0.04),      // 0.019
            "particles-zero-density" => Some(1e-3),     // 3.9e-8
            "camera-in-dense-particle" => Some(0.03),   // 0.013
            "light-in-particle" => Some(0.06),          // 0.030 (a cube extinction grid)
            "particle-radii-1e-4-to-1e3" => Some(0.09), // 0.042
            _ => None,
        }
    }

    fn conformance(&self) -> Vec<ConformanceCase> {
        // A fine grid (2 px froxels, 256 slices): at 8 px a 48² image is 6×6 froxels.
        vec![
            ConformanceCase::new("sphere-point", 48, Aov::Inscatter, 0.3)
                .knob("columns", 24i64)
                .knob("slices", 256i64),
            // Particle media: the sunlit cloud's total (sky and floor behind it); 0.0545 measured.
            ConformanceCase::new("cloud-8000", 48, Aov::Total, 0.1).knob("columns", 24i64),
        ]
    }
}
