//! Shared WGSL modules and their composition. A shader is the concatenation of the shared
//! modules it names (in dependency order) and its own source; every composed module is
//! validated by naga in a GPU-less test (`Method::shaders`, `tests/conformance.rs`).

pub const CAMERA: &str = include_str!("wgsl/camera.wgsl");
/// The medium uniform, phase functions and transmittance, with exponential height fog's density
/// and closed-form optical depth (`fog_density`, `fog_length`, `transmittance_along`).
pub const MEDIUM: &str = concat!(
    include_str!("wgsl/medium.wgsl"),
    "\n",
    include_str!("wgsl/height_fog.wgsl")
);
pub const LIGHTS: &str = include_str!("wgsl/lights.wgsl");
pub const SHADOW: &str = include_str!("wgsl/shadow.wgsl");
pub const SCENE: &str = include_str!("wgsl/scene.wgsl");
/// The frame bind group (group 0) every scene pass uses; see `renderer::SceneRenderer`.
pub const FRAME_BINDINGS: &str = include_str!("wgsl/frame_bindings.wgsl");
/// The unshadowed in-scatter over a ray stretch without a table: directional closed form, spot
/// quadrature (`sunlight_between`, `spot_between`, `local_quadrature`); needs PRELUDE.
pub const LIGHT_SEGMENTS: &str = include_str!("wgsl/light_segments.wgsl");
/// Biri et al.'s L_dss from a Γ table (`common::gamma`) and `lit_between`, the unshadowed
/// in-scatter of any light kind over a ray interval, dispatched on its kind (point lights by eq.
/// 7's Γ lookups, the others through LIGHT_SEGMENTS, composed first). Needs PRELUDE. Used by
/// biri-shadow-volumes and polygonal-light-volumes.
pub const LDSS: &str = concat!(
    include_str!("wgsl/light_segments.wgsl"),
    "\n",
    include_str!("wgsl/ldss.wgsl")
);
/// The forward surface pass (`vs`, `fs`, `shade_light…`; needs PRELUDE), also composed by passes
/// that redraw the scene's surfaces per light.
pub const SURFACE_PASS: &str = include_str!("wgsl/surface_pass.wgsl");
/// `vs_fullscreen`: one triangle covering the viewport.
pub const FULLSCREEN: &str = include_str!("wgsl/fullscreen.wgsl");

/// Every shared module in dependency order: what most scene passes include.
pub const PRELUDE: &[&str] = &[CAMERA, MEDIUM, LIGHTS, SHADOW, SCENE, FRAME_BINDINGS];

/// Concatenates shared modules and a method's own source.
pub fn compose(shared: &[&str], own: &str) -> String {
    let mut s =
        String::with_capacity(shared.iter().map(|m| m.len() + 1).sum::<usize>() + own.len());
    for m in shared {
        s.push_str(m);
        s.push('\n');
    }
    s.push_str(own);
    s
}

/// Creates a shader module from composed source.
pub fn module(device: &wgpu::Device, label: &str, source: &str) -> wgpu::ShaderModule {
    device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some(label),
        source: wgpu::ShaderSource::Wgsl(source.into()),
    })
}
