//! Rust mirrors of the WGSL uniform structs (one definition each; the WGSL side documents the
//! field packing).

use bytemuck::{Pod, Zeroable};
use glam::{Mat4, Vec3};
use scenes::light::spot_frame;
use scenes::{CameraPose, Homogeneous, LightState, Phase};

/// Lights the shared renderer holds (the `lights` uniform's array; `lights.wgsl` mirrors it).
/// A uniform rather than a storage buffer: every stage of every pass (vertex stages included)
/// reads it, uniforms are the fastest path on every backend, and 16 B + 128 × 480 B = 61 456 B
/// fits wgpu's default `max_uniform_buffer_binding_size` (64 KiB) on every adapter. 128 covers
/// the atrium's 64-local-light variant (65–67 lights) with room to spare; the light masks below
/// are 128 bits for the same reason.
pub const MAX_LIGHTS: usize = 128;

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
pub struct CameraUniform {
    pub clip_from_world: [[f32; 4]; 4],
    pub world_from_clip: [[f32; 4]; 4],
    pub position: [f32; 4],
    pub forward: [f32; 4],
    pub viewport: [f32; 4],
}

impl CameraUniform {
    pub fn new(cam: &CameraPose, width: u32, height: u32) -> Self {
        let clip_from_world = cam.clip_from_world(width as f32 / height as f32);
        // The inverse in f64: f32 inversion of a perspective matrix with a far/near of 1000
        // loses digits that show up as ray-direction noise.
        let world_from_clip = clip_from_world.as_dmat4().inverse().as_mat4();
        let fwd = cam.forward().as_vec3();
        CameraUniform {
            clip_from_world: clip_from_world.to_cols_array_2d(),
            world_from_clip: world_from_clip.to_cols_array_2d(),
            position: cam.position.extend(cam.near).to_array(),
            forward: fwd.extend(cam.far).to_array(),
            viewport: [
                width as f32,
                height as f32,
                1.0 / width as f32,
                1.0 / height as f32,
            ],
        }
    }
}

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
pub struct MediumUniform {
    pub sigma_a: [f32; 4],
    pub sigma_s: [f32; 4],
    pub sigma_t: [f32; 4],
    pub ambient: [f32; 4],
    /// x: height fog's base height y₀ (m); y: 1/H (1/m), 0 without height fog.
    pub height_fog: [f32; 4],
}

impl MediumUniform {
    pub fn new(m: &Homogeneous) -> Self {
        let (kind, g) = match m.phase {
            Phase::Isotropic => (0.0, 0.0),
            Phase::HenyeyGreenstein { g } => (1.0, g),
            Phase::Rayleigh => (2.0, 0.0),
            Phase::HazyMie => (3.0, 0.0),
            Phase::MurkyMie => (4.0, 0.0),
        };
        MediumUniform {
            sigma_a: m.sigma_a.extend(0.0).to_array(),
            sigma_s: m.sigma_s.extend(kind).to_array(),
            sigma_t: m.sigma_t.extend(g).to_array(),
            ambient: m.ambient.extend(0.0).to_array(),
            height_fog: m.height_fog.map_or([0.0; 4], |f| {
                [f.base_height, 1.0 / f.falloff_height, 0.0, 0.0]
            }),
        }
    }
}

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
pub struct LightUniform {
    pub position: [f32; 4],
    pub direction: [f32; 4],
    pub intensity: [f32; 4],
    pub right: [f32; 4],
    pub up: [f32; 4],
    pub shadow: [f32; 4],
    pub faces: [[[f32; 4]; 4]; 6],
}

/// Shadow-map placement of one light in the atlas (see `shadow_maps`): its faces are the tiles
/// `tile_base …` of side `size` texels, counted in tiles of that side across the atlas's layers,
/// `1 << row_shift` tiles to a row.
#[derive(Clone, Copy, Debug)]
pub struct ShadowSlot {
    pub tile_base: u32,
    pub faces: u32,
    pub size: u32,
    pub row_shift: u32,
    pub bias: f32,
    pub clip_from_world: [Mat4; 6],
}

impl ShadowSlot {
    /// Face `face`'s tile: (atlas layer, texel origin x, y). Mirrors `shadow_face_origin` in
    /// shadow.wgsl.
    pub fn face_tile(&self, face: u32) -> (u32, u32, u32) {
        let per_row = 1 << self.row_shift;
        let per_layer = per_row * per_row;
        let tile = self.tile_base + face;
        let r = tile % per_layer;
        (
            tile / per_layer,
            r % per_row * self.size,
            r / per_row * self.size,
        )
    }
}

/// One bit per light slot (128 bits, `vec4<u32>` in WGSL; `light_bit` in lights.wgsl reads it).
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
#[repr(C)]
pub struct LightMask(pub [u32; 4]);

impl LightMask {
    /// Sets light `k`'s bit (`k` < [`MAX_LIGHTS`]).
    pub fn set(&mut self, k: usize) {
        self.0[k / 32] |= 1 << (k % 32);
    }

    pub fn get(&self, k: usize) -> bool {
        self.0[k / 32] >> (k % 32) & 1 != 0
    }
}

impl LightUniform {
    /// `pattern_layer`: the light's layer in the pattern texture, if it has a pattern.
    pub fn new(l: &LightState, pattern_layer: Option<u32>, shadow: Option<&ShadowSlot>) -> Self {
        let (kind, pos, dir, ci, co, tan_o, intensity) = match l {
            LightState::Point {
                position,
                intensity,
            } => (0.0, *position, Vec3::Z, 1.0, 1.0, 0.0, *intensity),
            LightState::Spot {
                position,
                direction,
                cos_inner,
                cos_outer,
                tan_outer,
                intensity,
                ..
            } => (
                1.0, *position, *direction, *cos_inner, *cos_outer, *tan_outer, *intensity,
            ),
            LightState::Directional {
                direction,
                irradiance,
            } => (2.0, Vec3::ZERO, *direction, 1.0, 1.0, 0.0, *irradiance),
        };
        let (right, up) = spot_frame(dir.as_dvec3());
        let mut faces = [[[0.0; 4]; 4]; 6];
        let shadow_v = match shadow {
            Some(s) => {
                for (k, m) in s.clip_from_world.iter().enumerate() {
                    faces[k] = m.to_cols_array_2d();
                }
                [
                    s.tile_base as f32,
                    s.row_shift as f32,
                    s.size as f32,
                    s.bias,
                ]
            }
            None => [-1.0, 0.0, 1.0, 0.0],
        };
        LightUniform {
            position: pos.extend(kind).to_array(),
            direction: dir.extend(ci).to_array(),
            intensity: intensity.extend(co).to_array(),
            right: right.as_vec3().extend(tan_o).to_array(),
            up: up
                .as_vec3()
                .extend(pattern_layer.map_or(-1.0, |p| p as f32))
                .to_array(),
            shadow: shadow_v,
            faces,
        }
    }
}

/// The `lights` uniform: a header, then [`MAX_LIGHTS`] slots of which the first `count[0]` are
/// the scene's (only those are written each frame: [`lights_bytes`]).
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
pub struct LightsUniform {
    /// x: number of lights; yzw: unused.
    pub count: [u32; 4],
    pub lights: [LightUniform; MAX_LIGHTS],
}

/// The header and the first `lights.len()` slots of [`LightsUniform`], as uploaded.
pub fn lights_bytes(count: [u32; 4], lights: &[LightUniform]) -> Vec<u8> {
    assert!(lights.len() <= MAX_LIGHTS, "{} lights", lights.len());
    let mut bytes = bytemuck::bytes_of(&count).to_vec();
    bytes.extend_from_slice(bytemuck::cast_slice(lights));
    bytes
}
