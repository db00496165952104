//! Scene-baked pipeline constants. A scene's light count, light kinds and phase function are
//! fixed for a run (lights move, they do not change kind), so the hot passes compile them in as
//! WGSL `override`s (`LIGHT_COUNT`, `LIGHT_KIND_0..3`, `LIGHT_KINDS_REST` in `lights.wgsl`,
//! `PHASE_KIND` and `GREY_SIGMA_T` in `medium.wgsl`, `HEIGHT_FOG` in `height_fog.wgsl`, so
//! constant-σ scenes pay nothing for it): the per-light loops get a constant trip count and the kind and phase
//! branches fold away. The first four lights' kinds are baked per light; beyond them (up to
//! `MAX_LIGHTS`) `light_kind` reads the uniform and `LIGHT_KINDS_REST` (the set of kinds that
//! occur there) keeps `scene_has_light_kind` folding. A pass without them reads the same values
//! from the uniforms, so leaving
//! them out is only slower, never wrong. lavapipe runs both sides of a branch on a uniform value
//! under a mask and indexes the light array per lane, so this matters there: with the light
//! loop's divergent `continue` removed as well, raymarch-brute's 512² frame on sphere-point went
//! from 2.9 s to 0.46 s (methods/src/raymarch_brute/README.md). Method knobs tested in hot loops
//! are baked the same way by their methods (dobashi's `XI_PER_FRAGMENT`, the particle methods'
//! `FORWARD_SCATTERING`, `SLICE_GROUPS`, `BLOCKS`).

use scenes::Scene;
use scenes::desc::LightDesc;

use super::uniforms::{MAX_LIGHTS, MediumUniform};

/// Lights whose kind is baked one by one (`LIGHT_KIND_0..3`).
const BAKED_KINDS: usize = 4;

/// The constants of one scene, for `wgpu::PipelineCompilationOptions::constants`.
#[derive(Clone, Debug, PartialEq)]
pub struct Specialization {
    constants: Vec<(&'static str, f64)>,
}

const KIND_KEYS: [&str; BAKED_KINDS] = [
    "LIGHT_KIND_0",
    "LIGHT_KIND_1",
    "LIGHT_KIND_2",
    "LIGHT_KIND_3",
];

impl Specialization {
    pub fn of(scene: &Scene) -> Specialization {
        let lights = &scene.desc.lights;
        let mut constants = vec![("LIGHT_COUNT", lights.len().min(MAX_LIGHTS) as f64)];
        for (key, l) in KIND_KEYS.iter().zip(lights) {
            constants.push((key, kind_code(l) as f64));
        }
        let rest = lights.iter().skip(BAKED_KINDS);
        let rest_kinds = rest.fold(0u32, |bits, l| bits | 1 << kind_code(l));
        constants.push(("LIGHT_KINDS_REST", rest_kinds as f64));
        // The code of MediumUniform (sigma_s.w), for the medium the renderer uploads.
        let medium = MediumUniform::new(&scene.medium().background());
        constants.push(("PHASE_KIND", medium.sigma_s[3] as f64));
        let [r, g, b, _] = medium.sigma_t;
        constants.push(("GREY_SIGMA_T", flag(r == g && g == b)));
        let fog = scene.medium().background().height_fog.is_some();
        constants.push(("HEIGHT_FOG", flag(fog)));
        Specialization { constants }
    }

    pub fn constants(&self) -> &[(&'static str, f64)] {
        &self.constants
    }

    /// These constants plus a pass's own.
    pub fn with(&self, own: &[(&'static str, f64)]) -> Vec<(&'static str, f64)> {
        [&self.constants[..], own].concat()
    }

    /// Compilation options carrying these constants, for a stage whose module composes
    /// `lights.wgsl` and `medium.wgsl` (which declare them).
    pub fn options(&self) -> wgpu::PipelineCompilationOptions<'_> {
        compile_options(&self.constants)
    }
}

/// A light's kind code: common::uniforms::LightUniform's `position.w`.
fn kind_code(l: &LightDesc) -> u32 {
    match l {
        LightDesc::Point { .. } => 0,
        LightDesc::Spot { .. } => 1,
        LightDesc::Directional { .. } => 2,
    }
}

/// Compilation options with these pipeline-overridable constants (and zeroed workgroup memory,
/// wgpu's default): what every pass that sets overrides passes to its stages.
pub fn compile_options<'a>(
    constants: &'a [(&'a str, f64)],
) -> wgpu::PipelineCompilationOptions<'a> {
    wgpu::PipelineCompilationOptions {
        constants,
        zero_initialize_workgroup_memory: true,
    }
}

/// A `bool` override's value as `PipelineCompilationOptions::constants` takes it.
pub fn flag(b: bool) -> f64 {
    if b { 1.0 } else { 0.0 }
}

#[cfg(test)]
mod tests {
    use super::*;
    use scenes::desc::MediumDesc;

    fn constant(s: &Specialization, key: &str) -> f64 {
        let found = s.constants().iter().find(|(k, _)| *k == key);
        found.unwrap_or_else(|| panic!("{key} not baked")).1
    }

    /// GREY_SIGMA_T is baked exactly where the scene file gives σ_a and σ_s the same value in
    /// every channel (then σ_t is grey): a coloured medium must keep its three lookups. The
    /// library has both kinds, so the test sees each.
    #[test]
    fn grey_sigma_t_is_baked_for_grey_media_only() {
        let mut seen = [false, false];
        for name in scenes::library::names() {
            let scene = scenes::library::load(name)
                .expect("in the library")
                .expect("loads");
            let MediumDesc::Homogeneous {
                sigma_a, sigma_s, ..
            } = &scene.desc.medium
            else {
                continue;
            };
            let flat = |v: &glam::Vec3| v.x == v.y && v.y == v.z;
            let grey = flat(sigma_a) && flat(sigma_s);
            let baked = constant(&Specialization::of(&scene), "GREY_SIGMA_T");
            assert_eq!(baked, flag(grey), "{name}");
            seen[grey as usize] = true;
        }
        assert_eq!(
            seen,
            [true, true],
            "the library has grey and coloured media"
        );
    }
}
