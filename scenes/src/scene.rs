//! A loaded, validated scene: its description, its meshes, and its state at any frame.

use std::path::PathBuf;
use std::sync::Arc;

use glam::{EulerRot, Mat4, Quat, Vec3};
use serde::Serialize;

use crate::camera::CameraPose;
use crate::desc::{
    CameraDesc, GeneratorDesc, HeightFog, LightDesc, MediumDesc, SceneDesc, Transform,
};
use crate::light::LightState;
use crate::mesh::TriMesh;
use crate::particles::{BlockInstancing, Particle, expand_with_blocks, generated_count};
use crate::phase::Phase;

/// A validated scene ready to render. Build it with [`crate::load_scene`] or
/// [`crate::library::load`].
#[derive(Clone, Debug)]
pub struct Scene {
    /// Library name, or the file stem of a scene file.
    pub name: String,
    pub desc: SceneDesc,
    /// One mesh per object of `desc.objects`, in local space.
    pub meshes: Vec<Arc<TriMesh>>,
    /// The file it came from (None for the built-in library).
    pub source: Option<PathBuf>,
    /// Content of imported files the suite does not model (glTF textures, light ranges, …),
    /// one line each naming the file and the glTF paths; the runner appends these to every
    /// record's `ignored`. Empty for scenes without an import.
    pub ignored: Vec<String>,
}

/// The homogeneous medium's coefficients in the form integrators want.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Homogeneous {
    pub sigma_a: Vec3,
    pub sigma_s: Vec3,
    pub sigma_t: Vec3,
    pub phase: Phase,
    pub ambient: Vec3,
    /// Exponential height fog: σ_a, σ_s and σ_t above are the values at its base height and
    /// scale with e^(−(y − y₀)/H). None: constant σ.
    pub height_fog: Option<HeightFog>,
}

/// A particle medium in integrator form (ARCHITECTURE §1, "particles").
#[derive(Clone, Debug, PartialEq)]
pub struct Particles {
    /// Explicit particles first, then each generator's, in file order.
    pub particles: Vec<Particle>,
    /// Phase function of the particles and of the background.
    pub phase: Phase,
    /// The background medium (all zero when the file gives none; its phase is `phase`).
    pub background: Homogeneous,
    /// Sky radiance behind the cloud, W/(m² sr), RGB.
    pub sky: Vec3,
    /// One per `blocks` generator, in file order: its block and where each instance's
    /// particles are in `particles` (the declared structure; empty without such generators).
    pub blocks: Vec<BlockInstancing>,
}

/// The scene's medium, whichever kind it is. Methods that handle only homogeneous media use
/// [`Medium::homogeneous`] (None for particles) — or [`Medium::background`] where a uniform is
/// filled regardless and the method has already refused particle scenes.
#[derive(Clone, Debug, PartialEq)]
pub enum Medium {
    Homogeneous(Homogeneous),
    Particles(Particles),
}

impl Medium {
    pub fn homogeneous(&self) -> Option<Homogeneous> {
        match self {
            Medium::Homogeneous(h) => Some(*h),
            Medium::Particles(_) => None,
        }
    }

    pub fn particles(&self) -> Option<&Particles> {
        match self {
            Medium::Homogeneous(_) => None,
            Medium::Particles(p) => Some(p),
        }
    }

    /// The homogeneous part: the whole medium, or a particle scene's background (zero if none).
    pub fn background(&self) -> Homogeneous {
        match self {
            Medium::Homogeneous(h) => *h,
            Medium::Particles(p) => p.background,
        }
    }
}

/// Everything that can change between frames, evaluated at one frame.
#[derive(Clone, Debug, PartialEq)]
pub struct FrameState {
    pub index: u32,
    pub camera: CameraPose,
    pub lights: Vec<LightState>,
    /// One per object, parallel to `Scene::meshes`.
    pub world_from_local: Vec<Mat4>,
}

impl Scene {
    /// The medium in integrator form. For particle media this expands the generators (cheap:
    /// ~50 ns a particle), so call it once per use, not per pixel.
    pub fn medium(&self) -> Medium {
        match &self.desc.medium {
            MediumDesc::Homogeneous {
                sigma_a,
                sigma_s,
                phase,
                ambient,
                height_fog,
            } => Medium::Homogeneous(Homogeneous {
                sigma_a: *sigma_a,
                sigma_s: *sigma_s,
                sigma_t: *sigma_a + *sigma_s,
                phase: *phase,
                ambient: *ambient,
                height_fog: *height_fog,
            }),
            MediumDesc::Particles {
                particles,
                generators,
                phase,
                background,
                sky,
            } => {
                let (sigma_a, sigma_s) = background
                    .as_ref()
                    .map_or((Vec3::ZERO, Vec3::ZERO), |b| (b.sigma_a, b.sigma_s));
                let (particles, blocks) = expand_with_blocks(particles, generators);
                Medium::Particles(Particles {
                    particles,
                    blocks,
                    phase: *phase,
                    background: Homogeneous {
                        sigma_a,
                        sigma_s,
                        sigma_t: sigma_a + sigma_s,
                        phase: *phase,
                        ambient: Vec3::ZERO,
                        height_fog: None,
                    },
                    sky: *sky,
                })
            }
        }
    }

    pub fn frame_count(&self) -> u32 {
        self.desc.frames.max(1)
    }

    /// The scene at frame `index` (keyframes interpolated linearly, held outside their range).
    /// Lights attached to the camera are resolved to world space from the camera's pose at
    /// that frame.
    pub fn frame(&self, index: u32) -> FrameState {
        let f = index as f32;
        let camera = camera_at(&self.desc.camera, f);
        let lights = self
            .desc
            .lights
            .iter()
            .map(|l| light_at(l, f, &camera))
            .collect();
        let world_from_local = self
            .desc
            .objects
            .iter()
            .map(|o| {
                if o.keyframes.is_empty() {
                    transform_matrix(&o.transform)
                } else {
                    let keys: Vec<(f32, Transform)> = o
                        .keyframes
                        .iter()
                        .map(|k| (k.frame, k.transform.clone()))
                        .collect();
                    transform_matrix(&sample_keys(&keys, f, lerp_transform))
                }
            })
            .collect();
        FrameState {
            index,
            camera,
            lights,
            world_from_local,
        }
    }

    pub fn triangle_count(&self) -> usize {
        self.meshes.iter().map(|m| m.triangle_count()).sum()
    }

    /// What the scene contains, for method support decisions and `list --json`.
    pub fn features(&self) -> SceneFeatures {
        let d = &self.desc;
        // From the description alone: features() must not expand thousands of particles.
        let (medium, phase, scattering, ambient, particles) = match &d.medium {
            MediumDesc::Homogeneous {
                sigma_s,
                phase,
                ambient,
                ..
            } => (
                "homogeneous",
                *phase,
                sigma_s.max_element() > 0.0,
                ambient.max_element() > 0.0,
                0,
            ),
            MediumDesc::Particles {
                particles,
                generators,
                phase,
                background,
                ..
            } => {
                let scattering = any_scatters(particles, generators)
                    || background
                        .as_ref()
                        .is_some_and(|b| b.sigma_s.max_element() > 0.0);
                let n = generators
                    .iter()
                    .map(generated_count)
                    .fold(particles.len() as u64, u64::saturating_add);
                ("particles", *phase, scattering, false, n as usize)
            }
        };
        let mut light_kinds: Vec<&'static str> = d
            .lights
            .iter()
            .map(|l| match l {
                LightDesc::Point { .. } => "point",
                LightDesc::Spot { .. } => "spot",
                LightDesc::Directional { .. } => "directional",
            })
            .collect();
        light_kinds.sort();
        light_kinds.dedup();
        let many = d.frames > 1;
        let animated_camera = many && !d.camera.keyframes.is_empty();
        let animated_lights = many
            && d.lights.iter().any(|l| match l {
                // A flashlight moves when the camera does.
                LightDesc::Spot {
                    attached_to_camera: true,
                    ..
                } => animated_camera,
                LightDesc::Point { keyframes, .. }
                | LightDesc::Spot { keyframes, .. }
                | LightDesc::Directional { keyframes, .. } => !keyframes.is_empty(),
            });
        let animated_objects = many && d.objects.iter().any(|o| !o.keyframes.is_empty());
        SceneFeatures {
            medium,
            phase: phase.name(),
            anisotropic_phase: phase.is_anisotropic(),
            scattering,
            ambient,
            particles,
            lights: d.lights.len(),
            light_kinds,
            textured_light: d.lights.iter().any(|l| {
                matches!(
                    l,
                    LightDesc::Spot {
                        pattern: Some(_),
                        ..
                    }
                )
            }),
            surfaces: !d.objects.is_empty(),
            volumetric_occluders: d.objects.iter().any(|o| o.casts_volumetric_shadow),
            phong: d.objects.iter().any(|o| o.material.phong.is_some()),
            indirect_single_scattering: d.indirect_single_scattering,
            height_fog: matches!(
                d.medium,
                MediumDesc::Homogeneous {
                    height_fog: Some(_),
                    ..
                }
            ),
            frames: d.frames.max(1),
            animated: animated_lights || animated_objects || animated_camera,
            animated_lights,
            animated_objects,
            animated_camera,
            triangles: self.triangle_count(),
        }
    }
}

/// Whether some particle of these (explicit or generated) scatters: albedo · τ > 0.
fn any_scatters(particles: &[crate::desc::ParticleDesc], generators: &[GeneratorDesc]) -> bool {
    let scatters = |albedo: Vec3, density: f32| albedo.max_element() * density > 0.0;
    particles.iter().any(|p| scatters(p.albedo, p.density))
        || generators.iter().any(|g| match g {
            GeneratorDesc::Cloud {
                count,
                density,
                albedo,
                ..
            }
            | GeneratorDesc::SmokeColumn {
                count,
                density,
                albedo,
                ..
            } => *count > 0 && scatters(*albedo, *density),
            GeneratorDesc::Blocks {
                block,
                instances,
                placement,
            } => {
                // Placed instances have density_scale 1.
                (placement.as_ref().is_some_and(|p| p.count > 0)
                    || instances.iter().any(|i| i.density_scale > 0.0))
                    && any_scatters(&block.particles, &block.generators)
            }
        })
}

/// What a scene needs from a method. Methods decide their support from this alone.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct SceneFeatures {
    /// "homogeneous" or "particles".
    pub medium: &'static str,
    /// Number of particles (0 for homogeneous media).
    pub particles: usize,
    pub phase: &'static str,
    pub anisotropic_phase: bool,
    /// σ_s > 0 in some channel: there is in-scattering to compute.
    pub scattering: bool,
    pub ambient: bool,
    pub lights: usize,
    /// Sorted, unique: "directional", "point", "spot".
    pub light_kinds: Vec<&'static str>,
    /// Some spot light projects a pattern.
    pub textured_light: bool,
    pub surfaces: bool,
    /// Some object casts volumetric shadows.
    pub volumetric_occluders: bool,
    pub phong: bool,
    pub indirect_single_scattering: bool,
    /// The homogeneous medium has exponential height fog (σ varies with height).
    pub height_fog: bool,
    pub frames: u32,
    pub animated: bool,
    pub animated_lights: bool,
    pub animated_objects: bool,
    pub animated_camera: bool,
    pub triangles: usize,
}

/// The camera at (possibly fractional) frame `f`: its keys' position and look_at interpolated
/// linearly, held outside their range; the static pose when it has no keys.
pub(crate) fn camera_at(c: &CameraDesc, f: f32) -> CameraPose {
    let (position, look_at) = if c.keyframes.is_empty() {
        (c.position, c.look_at)
    } else {
        let keys: Vec<(f32, (Vec3, Vec3))> = c
            .keyframes
            .iter()
            .map(|k| (k.frame, (k.position, k.look_at)))
            .collect();
        sample_keys(&keys, f, |a, b, t| (a.0.lerp(b.0, t), a.1.lerp(b.1, t)))
    };
    CameraPose {
        position,
        look_at,
        up: c.up,
        fov_y_deg: c.fov_y_deg,
        near: c.near,
        far: c.far,
    }
}

fn light_at(l: &LightDesc, f: f32, camera: &CameraPose) -> LightState {
    match l {
        LightDesc::Point {
            position,
            intensity,
            keyframes,
        } => LightState::Point {
            position: animate(*position, keyframes, f, |k| k.position),
            intensity: *intensity,
        },
        LightDesc::Spot {
            position,
            direction,
            inner_deg,
            outer_deg,
            intensity,
            pattern,
            keyframes,
            attached_to_camera,
        } => LightState::Spot {
            position: if *attached_to_camera {
                camera.world_point(*position)
            } else {
                animate(*position, keyframes, f, |k| k.position)
            },
            direction: if *attached_to_camera {
                camera.world_direction(*direction)
            } else {
                animate_direction(*direction, keyframes, f)
            },
            cos_inner: inner_deg.to_radians().cos(),
            cos_outer: outer_deg.to_radians().cos(),
            tan_outer: outer_deg.to_radians().tan(),
            intensity: *intensity,
            pattern: pattern.clone(),
        },
        LightDesc::Directional {
            direction,
            irradiance,
            keyframes,
        } => LightState::Directional {
            direction: animate_direction(*direction, keyframes, f),
            irradiance: *irradiance,
        },
    }
}

/// A light's direction at frame f: every key's direction normalised *before* the component-wise
/// interpolation (so a key's length never weighs it), the result normalised again (scenes/README
/// "Keyframes").
fn animate_direction(base: Vec3, keys: &[crate::desc::LightKey], f: f32) -> Vec3 {
    animate(base, keys, f, |k| k.direction.map(Vec3::normalize)).normalize()
}

/// Interpolates the light keys that set a field, falling back to the static value.
fn animate(
    base: Vec3,
    keys: &[crate::desc::LightKey],
    f: f32,
    field: impl Fn(&crate::desc::LightKey) -> Option<Vec3>,
) -> Vec3 {
    let keyed: Vec<(f32, Vec3)> = keys
        .iter()
        .filter_map(|k| field(k).map(|v| (k.frame, v)))
        .collect();
    if keyed.is_empty() {
        base
    } else {
        sample_keys(&keyed, f, |a, b, t| a.lerp(*b, t))
    }
}

/// Piecewise-linear sampling of keys (sorted by frame here, so file order does not matter).
fn sample_keys<T: Clone>(keys: &[(f32, T)], f: f32, lerp: impl Fn(&T, &T, f32) -> T) -> T {
    let mut sorted: Vec<&(f32, T)> = keys.iter().collect();
    sorted.sort_by(|a, b| a.0.total_cmp(&b.0));
    let first = sorted[0];
    if f <= first.0 {
        return first.1.clone();
    }
    for w in sorted.windows(2) {
        let (a, b) = (w[0], w[1]);
        if f <= b.0 {
            let span = b.0 - a.0;
            let t = if span > 0.0 { (f - a.0) / span } else { 1.0 };
            return lerp(&a.1, &b.1, t);
        }
    }
    sorted[sorted.len() - 1].1.clone()
}

fn lerp_transform(a: &Transform, b: &Transform, t: f32) -> Transform {
    Transform {
        translation: a.translation.lerp(b.translation, t),
        rotation_deg: a.rotation_deg.lerp(b.rotation_deg, t),
        scale: a.scale.lerp(b.scale, t),
    }
}

/// world_from_local = T · Rz · Ry · Rx · S.
pub fn transform_matrix(t: &Transform) -> Mat4 {
    let r = t.rotation_deg * (std::f32::consts::PI / 180.0);
    let rot = Quat::from_euler(EulerRot::ZYX, r.z, r.y, r.x);
    Mat4::from_scale_rotation_translation(t.scale, rot, t.translation)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rotation_order_is_x_then_y_then_z() {
        let t = Transform {
            translation: Vec3::ZERO,
            rotation_deg: Vec3::new(90.0, 90.0, 0.0),
            scale: Vec3::ONE,
        };
        // Rx(90) takes +Y to +Z; then Ry(90) takes +Z to +X.
        let v = transform_matrix(&t).transform_vector3(Vec3::Y);
        assert!((v - Vec3::X).length() < 1e-6, "{v}");
    }

    #[test]
    fn keys_interpolate_linearly_and_hold_outside() {
        let keys = vec![(4.0, 10.0f32), (0.0, 2.0)];
        let lerp = |a: &f32, b: &f32, t: f32| a + (b - a) * t;
        assert_eq!(sample_keys(&keys, -1.0, lerp), 2.0);
        assert_eq!(sample_keys(&keys, 1.0, lerp), 4.0);
        assert_eq!(sample_keys(&keys, 9.0, lerp), 10.0);
    }
}
