//! The scene file format: what a scene JSON file says, field by field.
//!
//! Every struct here is `deny_unknown_fields`, so a misspelt field is an error with its path,
//! not a silently ignored default. Units: metres, radians never (angles are degrees in the file),
//! RGB triples for every spectral quantity. `scenes/README.md` documents every field.

use glam::Vec3;
use serde::{Deserialize, Serialize};

use crate::phase::Phase;

fn one() -> u32 {
    1
}
fn y_up() -> Vec3 {
    Vec3::Y
}
fn default_fov() -> f32 {
    45.0
}
fn default_near() -> f32 {
    0.1
}
fn default_far() -> f32 {
    100.0
}
fn true_() -> bool {
    true
}
fn grey() -> Vec3 {
    Vec3::splat(0.8)
}
fn unit_scale() -> Vec3 {
    Vec3::ONE
}

/// A whole scene file.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct SceneDesc {
    /// One line for `scatterbench list`. Default: empty.
    #[serde(default)]
    pub description: String,
    pub camera: CameraDesc,
    pub medium: MediumDesc,
    pub lights: Vec<LightDesc>,
    /// Opaque surfaces. Default: none (a scene of fog and light only).
    #[serde(default)]
    pub objects: Vec<ObjectDesc>,
    /// Frames to render; keyframes are indexed by frame number. Default: 1.
    #[serde(default = "one")]
    pub frames: u32,
    /// Biri 2006's indirect single scattering term (light scattered by the medium onto
    /// surfaces), added to the `surface` AOV. Default: false.
    #[serde(default)]
    pub indirect_single_scattering: bool,
}

/// A pinhole camera. Pixel centres are sampled (no anti-aliasing).
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct CameraDesc {
    /// Eye position, m.
    pub position: Vec3,
    /// Point the camera looks at, m.
    pub look_at: Vec3,
    /// Up hint. Default: +Y.
    #[serde(default = "y_up")]
    pub up: Vec3,
    /// Vertical field of view, degrees, in (0, 180). Default: 45.
    #[serde(default = "default_fov")]
    pub fov_y_deg: f32,
    /// Near plane distance (view depth), m. Default: 0.1.
    #[serde(default = "default_near")]
    pub near: f32,
    /// Far plane distance (view depth), m. A ray that hits nothing ends here. Default: 100.
    #[serde(default = "default_far")]
    pub far: f32,
    /// Animation; between keys position and look_at are interpolated linearly.
    #[serde(default)]
    pub keyframes: Vec<CameraKey>,
}

#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct CameraKey {
    /// Frame number (may be fractional).
    pub frame: f32,
    pub position: Vec3,
    pub look_at: Vec3,
}

/// The participating medium: homogeneous (fills all space) or particles (spheres of constant
/// extinction, ARCHITECTURE §1). Consumers get it in integrator form from [`crate::Scene::medium`].
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(tag = "kind", rename_all = "kebab-case", deny_unknown_fields)]
pub enum MediumDesc {
    Homogeneous {
        /// Absorption coefficient, 1/m, RGB.
        sigma_a: Vec3,
        /// Scattering coefficient, 1/m, RGB.
        sigma_s: Vec3,
        /// Phase function. Default: isotropic.
        #[serde(default)]
        phase: Phase,
        /// Ambient radiance L_a of the term L_a (1 - e^(-τ)), τ the ray's optical depth (σt d
        /// without height fog), W/(m² sr), RGB. Default: 0.
        #[serde(default)]
        ambient: Vec3,
        /// Exponential height fog: σ(y) = σ · e^(−(y − base_height)/falloff_height), the file's
        /// σ being the values at `base_height`. Default: none (σ constant everywhere). Left out
        /// of the serialised form when absent, so existing scenes keep their reference-cache keys.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        height_fog: Option<HeightFog>,
    },
    /// A particle cloud: explicit spheres plus seeded generators (both optional, at least one
    /// particle in all). Extinction inside a sphere is its `density`, overlaps add.
    Particles {
        /// Explicit particles. Default: none.
        #[serde(default)]
        particles: Vec<ParticleDesc>,
        /// Seeded, reproducible particle generators. Default: none.
        #[serde(default)]
        generators: Vec<GeneratorDesc>,
        /// Phase function of every particle (and of the background medium). Default: isotropic.
        #[serde(default)]
        phase: Phase,
        /// A homogeneous medium filling all space around and inside the particles. Default:
        /// none. Like the homogeneous medium, it does not attenuate directional light on the
        /// light leg; the particles do (that is the cloud's self-shadowing).
        #[serde(default)]
        background: Option<BackgroundDesc>,
        /// Radiance of the sky behind the cloud (rays that hit nothing), W/(m² sr), RGB,
        /// attenuated along the whole ray to the far plane. Default: 0.
        #[serde(default)]
        sky: Vec3,
    },
}

/// Exponential height fog of a homogeneous medium (ARCHITECTURE §1): every coefficient is
/// scaled by e^(−(y − base_height)/falloff_height); albedo and phase do not change with height.
#[derive(Clone, Copy, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct HeightFog {
    /// Height y₀ where σ has the file's values, m; finite.
    pub base_height: f32,
    /// Height H over which σ falls by a factor e, m; finite, > 0.
    pub falloff_height: f32,
}

fn white() -> Vec3 {
    Vec3::ONE
}

/// One sphere particle.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct ParticleDesc {
    /// m.
    pub center: Vec3,
    /// m, > 0.
    pub radius: f32,
    /// Extinction coefficient τ inside the sphere, 1/m, ≥ 0 (grey).
    pub density: f32,
    /// Single-scattering albedo a (σ_s = a τ), RGB in [0,1]. Default: 1.
    #[serde(default = "white")]
    pub albedo: Vec3,
}

/// The background medium of a particle scene (its phase is the particles' phase).
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct BackgroundDesc {
    /// Absorption coefficient, 1/m, RGB.
    pub sigma_a: Vec3,
    /// Scattering coefficient, 1/m, RGB.
    pub sigma_s: Vec3,
}

/// A seeded particle generator: the same fields always give the same particles (its own
/// SplitMix64 stream, no platform randomness). See `scenes::particles`.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(tag = "shape", rename_all = "kebab-case", deny_unknown_fields)]
pub enum GeneratorDesc {
    /// Particle centres uniform in an ellipsoid (a cumulus-like puff), radii uniform in a range.
    Cloud {
        /// Number of particles, ≥ 1.
        count: u32,
        #[serde(default)]
        seed: u64,
        /// Ellipsoid centre, m.
        center: Vec3,
        /// Ellipsoid semi-axes, m, > 0.
        radii: Vec3,
        /// Particle radius range [min, max], m, 0 < min ≤ max; uniform in between.
        particle_radius: [f32; 2],
        /// Extinction τ of each particle, 1/m.
        density: f32,
        /// Albedo of each particle, RGB in [0,1]. Default: 1.
        #[serde(default = "white")]
        albedo: Vec3,
    },
    /// A rising smoke column: centres at uniform heights over [0, height] above `base`, spread
    /// over a disc whose radius grows linearly from `radius_bottom` to `radius_top`, the column
    /// swaying sideways; particles grow from particle_radius[0] at the base to [1] at the top.
    SmokeColumn {
        count: u32,
        #[serde(default)]
        seed: u64,
        /// Centre of the column's base, m.
        base: Vec3,
        /// Column height along +Y, m, > 0.
        height: f32,
        /// Spread radius at the base and at the top, m, ≥ 0.
        radius_bottom: f32,
        radius_top: f32,
        /// Particle radius at the base and at the top, m, > 0.
        particle_radius: [f32; 2],
        /// Extinction τ of each particle, 1/m.
        density: f32,
        #[serde(default = "white")]
        albedo: Vec3,
    },
    /// Instances of ONE particle block (Umenhoffer et al. 2006: "build a block of b particles
    /// and instance it N/b times"): the explicit `instances`, then `placement`'s, each a copy
    /// of `block` moved, uniformly scaled and with its τ scaled. At least one instance.
    Blocks {
        block: BlockDesc,
        /// Explicit instances. Default: none.
        #[serde(default)]
        instances: Vec<InstanceDesc>,
        /// Seeded instances, after the explicit ones. Default: none.
        #[serde(default)]
        placement: Option<PlacementDesc>,
    },
}

/// The one particle block a `blocks` generator instances: explicit particles and/or generators,
/// in block-local metres about the block's origin (which each instance places at its centre).
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct BlockDesc {
    /// Explicit particles (block-local). Default: none.
    #[serde(default)]
    pub particles: Vec<ParticleDesc>,
    /// Seeded generators (block-local), not themselves `blocks`. Default: none.
    #[serde(default)]
    pub generators: Vec<GeneratorDesc>,
}

fn one_f() -> f32 {
    1.0
}
fn unit_range() -> [f32; 2] {
    [1.0, 1.0]
}

/// One placed copy of a block: every block particle's centre p becomes `center + scale·p`,
/// its radius `scale·r`, its density `density_scale·τ` (albedo unchanged).
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct InstanceDesc {
    /// Where the block's origin goes, m.
    pub center: Vec3,
    /// Uniform scale of positions and radii, > 0. Default: 1.
    #[serde(default = "one_f")]
    pub scale: f32,
    /// Multiplier of every particle's τ, ≥ 0. Default: 1.
    #[serde(default = "one_f")]
    pub density_scale: f32,
}

/// A seeded placement rule: `count` instance centres uniform in an ellipsoid, scales uniform in
/// a range (the same SplitMix64 stream as the generators).
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct PlacementDesc {
    /// Number of instances, ≥ 1.
    pub count: u32,
    #[serde(default)]
    pub seed: u64,
    /// Ellipsoid centre, m.
    pub center: Vec3,
    /// Ellipsoid semi-axes, m, > 0.
    pub radii: Vec3,
    /// Instance scale range [min, max], 0 < min ≤ max; uniform in between. Default: [1, 1].
    #[serde(default = "unit_range")]
    pub scale: [f32; 2],
}

/// A light. Intensities are radiant intensity I in W/sr; irradiance E in W/m².
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(tag = "kind", rename_all = "kebab-case", deny_unknown_fields)]
pub enum LightDesc {
    Point {
        /// m.
        position: Vec3,
        /// W/sr, RGB.
        intensity: Vec3,
        #[serde(default)]
        keyframes: Vec<LightKey>,
    },
    Spot {
        /// m.
        position: Vec3,
        /// Cone axis (propagation direction); need not be normalised.
        direction: Vec3,
        /// Full intensity inside this half-angle, degrees.
        inner_deg: f32,
        /// Zero intensity outside this half-angle, degrees; smoothstep in between. < 90.
        outer_deg: f32,
        /// W/sr on the axis, RGB.
        intensity: Vec3,
        /// Analytic pattern projected by the spot (a slide in front of the light).
        #[serde(default)]
        pattern: Option<Pattern>,
        #[serde(default)]
        keyframes: Vec<LightKey>,
        /// A flashlight: `position` (m) and `direction` are in camera space (x right, y up,
        /// −z forward, the camera looking down −z) and follow the camera's pose at every frame
        /// ([`crate::scene::Scene::frame`]). Such a spot has no keyframes of its own. Default:
        /// false. Left out of the serialised form when false, so existing scenes keep their
        /// reference-cache keys.
        #[serde(default, skip_serializing_if = "std::ops::Not::not")]
        attached_to_camera: bool,
    },
    Directional {
        /// Propagation direction of the light (from the sun toward the scene).
        direction: Vec3,
        /// Irradiance on a surface facing the light, W/m², RGB. Not attenuated on the light leg.
        irradiance: Vec3,
        #[serde(default)]
        keyframes: Vec<LightKey>,
    },
}

/// Light animation key: whichever of position / direction is given is interpolated linearly.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct LightKey {
    pub frame: f32,
    #[serde(default)]
    pub position: Option<Vec3>,
    #[serde(default)]
    pub direction: Option<Vec3>,
}

/// A spot light's projected pattern, an analytic function of the slide coordinates (u, v) in
/// [0,1]² (see [`crate::light::spot_uv`]). Every discontinuity lies on a line u = const or
/// v = const, i.e. on a plane through the light, which the reference splits at exactly.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(tag = "kind", rename_all = "kebab-case", deny_unknown_fields)]
pub enum Pattern {
    /// `cells`×`cells` checkerboard of 1 and `dark`.
    Checker {
        cells: u32,
        /// Transmission of the dark cells, [0,1]. Default: 0.
        #[serde(default)]
        dark: f32,
    },
    /// `panes`×`panes` coloured panes (colours from `seed`) separated by opaque lead lines of
    /// `lead` width (fraction of a pane).
    StainedGlass {
        panes: u32,
        #[serde(default)]
        seed: u32,
        #[serde(default = "default_lead")]
        lead: f32,
    },
}

fn default_lead() -> f32 {
    0.08
}

/// An opaque object.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct ObjectDesc {
    /// Name used in messages. Default: "object N".
    #[serde(default)]
    pub name: String,
    pub shape: Shape,
    #[serde(default)]
    pub transform: Transform,
    #[serde(default)]
    pub material: Material,
    /// Whether the object blocks light in the medium (volumetric shadow) and on surfaces.
    /// Default: true.
    #[serde(default = "true_")]
    pub casts_volumetric_shadow: bool,
    /// Animation of the transform; linear between keys, held outside them.
    #[serde(default)]
    pub keyframes: Vec<TransformKey>,
}

#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct TransformKey {
    pub frame: f32,
    pub transform: Transform,
}

/// world_from_local = translate · Rz · Ry · Rx · scale (rotations about the world axes, X first).
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Transform {
    /// m. Default: 0.
    #[serde(default)]
    pub translation: Vec3,
    /// Degrees about X, Y, Z. Default: 0.
    #[serde(default)]
    pub rotation_deg: Vec3,
    /// Per-axis scale, > 0. Default: 1.
    #[serde(default = "unit_scale")]
    pub scale: Vec3,
}

impl Default for Transform {
    fn default() -> Self {
        Self {
            translation: Vec3::ZERO,
            rotation_deg: Vec3::ZERO,
            scale: Vec3::ONE,
        }
    }
}

/// Lambert + optional Phong.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Material {
    /// Lambert albedo, RGB in [0,1]. Default: 0.8.
    #[serde(default = "grey")]
    pub albedo: Vec3,
    /// Optional normalised Phong lobe.
    #[serde(default)]
    pub phong: Option<Phong>,
    /// Lit on both sides (for quads and planes seen from below). Default: false.
    #[serde(default)]
    pub two_sided: bool,
}

impl Default for Material {
    fn default() -> Self {
        Self {
            albedo: grey(),
            phong: None,
            two_sided: false,
        }
    }
}

/// Phong lobe: f_s = ks (n+2)/(2π) max(0, r·v)^n, r the mirrored light direction.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Phong {
    /// Specular reflectance, RGB.
    pub ks: Vec3,
    /// Exponent n ≥ 1.
    pub shininess: f32,
}

/// Procedural shapes (local space, Y up) and OBJ files.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(tag = "kind", rename_all = "kebab-case", deny_unknown_fields)]
pub enum Shape {
    /// Quad in the XZ plane, centred, facing +Y; `size` = [x, z] extents, m.
    Plane { size: [f32; 2] },
    /// Axis-aligned box centred on the origin; full extents, m.
    Box { size: Vec3 },
    /// UV sphere centred on the origin.
    Sphere {
        radius: f32,
        #[serde(default = "default_segments")]
        segments: u32,
        #[serde(default = "default_rings")]
        rings: u32,
    },
    /// Capped cylinder, axis Y, from y = 0 to y = height.
    Cylinder {
        radius: f32,
        height: f32,
        #[serde(default = "default_segments")]
        segments: u32,
    },
    /// Torus in the XZ plane.
    Torus {
        major_radius: f32,
        minor_radius: f32,
        #[serde(default = "default_segments")]
        segments: u32,
        #[serde(default = "default_sides")]
        sides: u32,
    },
    /// Helix spring along Y from y = 0 to y = height: a tube of `wire_radius` around a helix
    /// of `coil_radius`, with capped ends.
    Spring {
        coil_radius: f32,
        wire_radius: f32,
        turns: f32,
        height: f32,
        #[serde(default = "default_segments")]
        segments_per_turn: u32,
        #[serde(default = "default_sides")]
        sides: u32,
    },
    /// Hexagonal prism (across-corners radius) along Y from 0 to `length`, topped by a cone
    /// of `tip_length` (so the total length is length + tip_length).
    Pencil {
        radius: f32,
        length: f32,
        tip_length: f32,
    },
    /// A fence in the XY plane, centred, facing +Z: `posts` vertical bars and `rails`
    /// horizontal bars of square section `bar`, spanning `width` × `height`.
    Fence {
        width: f32,
        height: f32,
        posts: u32,
        rails: u32,
        bar: f32,
    },
    /// A Wavefront OBJ file, path relative to the scene file.
    Obj { path: String },
    /// The `atrium` library scene's stonework, built in world metres (`scenes::mesh::atrium`):
    /// two storeys of arcades around a 20 × 44 m courtyard, walls, a roof with an opening.
    /// `detail` in [0.25, 4] scales every tessellation count (triangles ∝ detail², ≈ 0.3 M at
    /// 1). Default: 1.
    Atrium {
        #[serde(default = "one_f")]
        detail: f32,
    },
    /// The atrium's twelve hanging banners (1.5 cm cloth slabs), in world metres. `detail` as
    /// for `atrium`. Default: 1.
    AtriumBanners {
        #[serde(default = "one_f")]
        detail: f32,
    },
    /// One triangle primitive of a glTF 2.0 file (path relative to the scene file): primitive
    /// `primitive` of the mesh of node `node`, in the file's world space (the node hierarchy
    /// multiplied out; `transform` then applies on top). What an `import` makes.
    Gltf {
        path: String,
        node: u32,
        primitive: u32,
    },
}

fn default_segments() -> u32 {
    48
}
fn default_rings() -> u32 {
    24
}
fn default_sides() -> u32 {
    16
}
