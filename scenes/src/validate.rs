//! Semantic validation: every problem in a scene description, all at once, each with the
//! field path it is about. Nothing here panics, whatever the numbers.

use std::path::Path;

use glam::Vec3;

use crate::desc::{
    BlockDesc, GeneratorDesc, InstanceDesc, LightDesc, LightKey, MediumDesc, ParticleDesc, Pattern,
    PlacementDesc, SceneDesc, Shape, Transform,
};
use crate::mesh::atrium;
use crate::particles::{block_count, generated_count, instance_count};
use crate::phase::Phase;

/// One thing wrong with a scene: the field path (`objects[2].shape.radius`) and what is wrong.
#[derive(Debug, Clone, PartialEq)]
pub struct Problem {
    pub path: String,
    pub message: String,
}

impl Problem {
    pub fn new(path: impl Into<String>, message: impl Into<String>) -> Self {
        Self {
            path: path.into(),
            message: message.into(),
        }
    }
}

/// The most triangles a procedural parameter may ask for (a typo guard, not a limit on OBJ files).
const MAX_SEGMENTS: u32 = 4096;
const MAX_FRAMES: u32 = 100_000;
/// The most triangles one procedural shape may have: parameters each within range can still
/// multiply to billions (a spring of 1000 turns × 4096 × 4096), which must be refused, not
/// allocated (found by `tests/fuzz.rs`).
const MAX_TRIANGLES: u64 = 1 << 25;

/// The largest far/near ratio a camera may have. The methods project with 32-bit floats: past
/// ~1e7 the projection's depth terms round to those of an infinite far plane (and past ~1e16 even
/// the reference's 64-bit unprojection of a pixel ray divides by zero).
pub const MAX_FAR_OVER_NEAR: f32 = 1e6;

/// The largest magnitude (m) of a position's coordinate (camera, camera keys, lights, light
/// keys, object translations): ±1000 km. f32 leaves 6 cm of precision there, and a camera far
/// beyond it overflows the view and clip matrices to a non-finite pixel ray (found by the
/// loader fuzz test: a camera at x = 9.2e18, a finite f32).
pub const MAX_COORDINATE: f32 = 1e6;

/// An upper bound on the triangles a procedural shape builds (None: an OBJ file).
fn triangle_estimate(s: &Shape) -> Option<u64> {
    let n = |x: u32| x as u64;
    Some(match s {
        Shape::Plane { .. } => 2,
        Shape::Box { .. } => 12,
        Shape::Sphere {
            segments, rings, ..
        } => 2 * n(*segments) * n(*rings),
        Shape::Cylinder { segments, .. } => 4 * n(*segments),
        Shape::Torus {
            segments, sides, ..
        } => 2 * n(*segments) * n(*sides),
        Shape::Spring {
            turns,
            segments_per_turn,
            sides,
            ..
        } => {
            let rows = (turns.clamp(0.0, 1e6) as f64 * *segments_per_turn as f64).ceil() as u64 + 1;
            2 * rows * n(*sides) + 2 * n(*sides)
        }
        Shape::Pencil { .. } => 64,
        Shape::Fence { posts, rails, .. } => 12 * (n(*posts) + n(*rails)),
        Shape::Obj { .. } | Shape::Gltf { .. } => return None,
        Shape::Atrium { detail } | Shape::AtriumBanners { detail } => {
            if !(atrium::MIN_DETAIL..=atrium::MAX_DETAIL).contains(detail) {
                return None;
            }
            atrium::triangle_estimate(*detail)
        }
    })
}

struct Checker {
    out: Vec<Problem>,
}

impl Checker {
    fn push(&mut self, path: &str, msg: impl Into<String>) {
        self.out.push(Problem::new(path, msg));
    }
    fn finite3(&mut self, path: &str, v: Vec3) -> bool {
        if !v.is_finite() {
            self.push(path, format!("must be finite, got {v}"));
            return false;
        }
        true
    }
    /// A position: finite, every coordinate within ±MAX_COORDINATE.
    fn point3(&mut self, path: &str, v: Vec3) -> bool {
        if !self.finite3(path, v) {
            return false;
        }
        if v.abs().max_element() > MAX_COORDINATE {
            self.push(
                path,
                format!("must be within ±{MAX_COORDINATE:e} m on every axis, got {v}"),
            );
            return false;
        }
        true
    }
    fn non_negative3(&mut self, path: &str, v: Vec3) {
        if self.finite3(path, v) && v.min_element() < 0.0 {
            self.push(path, format!("must be ≥ 0 in every channel, got {v}"));
        }
    }
    fn nonzero3(&mut self, path: &str, v: Vec3) {
        if self.finite3(path, v) && v.length_squared() < 1e-20 {
            self.push(path, "must not be the zero vector");
        }
    }
    fn positive(&mut self, path: &str, x: f32) {
        if !(x.is_finite() && x > 0.0) {
            self.push(path, format!("must be a finite number > 0, got {x}"));
        }
    }
    fn finite(&mut self, path: &str, x: f32) -> bool {
        if !x.is_finite() {
            self.push(path, format!("must be finite, got {x}"));
            return false;
        }
        true
    }
    fn count(&mut self, path: &str, n: u32, min: u32, max: u32) {
        if n < min || n > max {
            self.push(path, format!("must be in [{min}, {max}], got {n}"));
        }
    }
    fn unit_interval3(&mut self, path: &str, v: Vec3) {
        if self.finite3(path, v) && (v.min_element() < 0.0 || v.max_element() > 1.0) {
            self.push(path, format!("must be in [0, 1] in every channel, got {v}"));
        }
    }
}

/// Every semantic problem of `d`. OBJ paths resolve against `base`.
pub fn validate(d: &SceneDesc, base: &Path) -> Vec<Problem> {
    let mut c = Checker { out: Vec::new() };
    camera(&mut c, d);
    medium(&mut c, &d.medium);
    if d.lights.is_empty() {
        c.push(
            "lights",
            "the scene has no light: there is nothing to render",
        );
    }
    for (i, l) in d.lights.iter().enumerate() {
        light(&mut c, &format!("lights[{i}]"), l);
    }
    for (i, o) in d.objects.iter().enumerate() {
        let p = format!("objects[{i}]");
        shape(&mut c, &format!("{p}.shape"), &o.shape, base);
        transform(&mut c, &format!("{p}.transform"), &o.transform);
        unique_frames(
            &mut c,
            &format!("{p}.keyframes"),
            "",
            o.keyframes.iter().map(|k| k.frame).enumerate(),
        );
        for (k, key) in o.keyframes.iter().enumerate() {
            c.finite(&format!("{p}.keyframes[{k}].frame"), key.frame);
            transform(
                &mut c,
                &format!("{p}.keyframes[{k}].transform"),
                &key.transform,
            );
        }
        let m = &o.material;
        c.unit_interval3(&format!("{p}.material.albedo"), m.albedo);
        if let Some(ph) = &m.phong {
            c.unit_interval3(&format!("{p}.material.phong.ks"), ph.ks);
            if !(ph.shininess.is_finite() && ph.shininess >= 1.0) {
                c.push(
                    &format!("{p}.material.phong.shininess"),
                    format!("must be a finite number ≥ 1, got {}", ph.shininess),
                );
            }
        }
    }
    c.count("frames", d.frames, 1, MAX_FRAMES);
    c.out
}

fn camera(c: &mut Checker, d: &SceneDesc) {
    let cam = &d.camera;
    let ok = c.point3("camera.position", cam.position) & c.point3("camera.look_at", cam.look_at);
    if ok && (cam.look_at - cam.position).length_squared() < 1e-12 {
        c.push("camera.look_at", "must differ from camera.position");
    }
    c.nonzero3("camera.up", cam.up);
    if ok
        && cam.up.is_finite()
        && cam.up.length_squared() > 1e-20
        && (cam.look_at - cam.position).length_squared() >= 1e-12
    {
        let fwd = (cam.look_at - cam.position).normalize_or_zero();
        if fwd.cross(cam.up.normalize()).length() < 1e-4 {
            c.push("camera.up", "must not be parallel to the view direction");
        }
    }
    if !(cam.fov_y_deg.is_finite() && cam.fov_y_deg > 0.0 && cam.fov_y_deg < 180.0) {
        c.push(
            "camera.fov_y_deg",
            format!("must be in (0, 180) degrees, got {}", cam.fov_y_deg),
        );
    }
    c.positive("camera.near", cam.near);
    if c.finite("camera.far", cam.far) && cam.near.is_finite() && cam.far <= cam.near {
        c.push(
            "camera.far",
            format!("must be greater than near ({}), got {}", cam.near, cam.far),
        );
    } else if cam.near > 0.0 && cam.far / cam.near > MAX_FAR_OVER_NEAR {
        c.push(
            "camera.far",
            format!(
                "must be at most {MAX_FAR_OVER_NEAR:e} × near ({}), got {} ({:e} × near): a 32-bit depth buffer cannot tell such a far plane from infinity",
                cam.near,
                cam.far,
                cam.far / cam.near
            ),
        );
    }
    unique_frames(
        c,
        "camera.keyframes",
        "",
        cam.keyframes.iter().map(|k| k.frame).enumerate(),
    );
    let mut keys_ok = true;
    for (k, key) in cam.keyframes.iter().enumerate() {
        let p = format!("camera.keyframes[{k}]");
        keys_ok &= c.finite(&format!("{p}.frame"), key.frame);
        let finite = c.point3(&format!("{p}.position"), key.position)
            & c.point3(&format!("{p}.look_at"), key.look_at);
        keys_ok &= finite;
        if finite && (key.look_at - key.position).length_squared() < 1e-12 {
            c.push(
                &format!("{p}.look_at"),
                "must differ from the key's position",
            );
            keys_ok = false;
        }
    }
    let up_ok = cam.up.is_finite() && cam.up.length_squared() > 1e-20;
    if keys_ok && up_ok && !cam.keyframes.is_empty() {
        animated_view(c, d);
    }
}

/// Each frame's interpolated camera has a view direction, not parallel to `up`: keys fine on
/// their own can still meet between them (position and look_at swapping places), and the
/// camera's pose there — rays, a camera-attached light — would be undefined.
fn animated_view(c: &mut Checker, d: &SceneDesc) {
    for frame in 0..d.frames.clamp(1, MAX_FRAMES) {
        let pose = crate::scene::camera_at(&d.camera, frame as f32);
        let view = pose.look_at - pose.position;
        let problem = if view.length_squared() < 1e-12 {
            "look_at meets position"
        } else if view.normalize().cross(d.camera.up.normalize()).length() < 1e-4 {
            "the view direction is parallel to camera.up"
        } else {
            continue;
        };
        c.push(
            "camera.keyframes",
            format!(
                "at frame {frame} the interpolated camera has no view: {problem}; every frame in \
                 [0, frames) needs look_at ≠ position and a view direction not parallel to up"
            ),
        );
        return;
    }
}

/// The most particles a medium may have (explicit + generated): a typo guard (1e6 spheres
/// is ~40 MB in the reference's BVH), not a limit of the format.
pub const MAX_PARTICLES: u64 = 1_000_000;

fn phase(c: &mut Checker, ph: &Phase) {
    if let Phase::HenyeyGreenstein { g } = ph
        && !(g.is_finite() && g.abs() < 1.0)
    {
        c.push("medium.phase.g", format!("must be in (-1, 1), got {g}"));
    }
}

fn medium(c: &mut Checker, m: &MediumDesc) {
    match m {
        MediumDesc::Homogeneous {
            sigma_a,
            sigma_s,
            phase: ph,
            ambient,
            height_fog,
        } => {
            c.non_negative3("medium.sigma_a", *sigma_a);
            c.non_negative3("medium.sigma_s", *sigma_s);
            c.non_negative3("medium.ambient", *ambient);
            phase(c, ph);
            if let Some(f) = height_fog {
                c.finite("medium.height_fog.base_height", f.base_height);
                c.positive("medium.height_fog.falloff_height", f.falloff_height);
            }
        }
        MediumDesc::Particles {
            particles,
            generators,
            phase: ph,
            background,
            sky,
        } => {
            phase(c, ph);
            c.non_negative3("medium.sky", *sky);
            if let Some(b) = background {
                c.non_negative3("medium.background.sigma_a", b.sigma_a);
                c.non_negative3("medium.background.sigma_s", b.sigma_s);
            }
            particle_list(c, "medium", particles, generators, true);
            let total = generators
                .iter()
                .map(generated_count)
                .fold(particles.len() as u64, u64::saturating_add);
            if total == 0 {
                c.push(
                    "medium",
                    "a particle medium needs at least one particle (`particles` or `generators`)",
                );
            } else if total > MAX_PARTICLES {
                c.push(
                    "medium",
                    format!("{total} particles; at most {MAX_PARTICLES} are allowed"),
                );
            }
        }
    }
}

/// Explicit particles and generators under `at` (the medium, or a block: `nested_ok` false).
fn particle_list(
    c: &mut Checker,
    at: &str,
    particles: &[ParticleDesc],
    generators: &[GeneratorDesc],
    blocks_ok: bool,
) {
    for (i, p) in particles.iter().enumerate() {
        let at = format!("{at}.particles[{i}]");
        c.finite3(&format!("{at}.center"), p.center);
        c.positive(&format!("{at}.radius"), p.radius);
        non_negative(c, &format!("{at}.density"), p.density);
        c.unit_interval3(&format!("{at}.albedo"), p.albedo);
    }
    for (i, g) in generators.iter().enumerate() {
        let at = format!("{at}.generators[{i}]");
        if !blocks_ok && matches!(g, GeneratorDesc::Blocks { .. }) {
            c.push(
                &format!("{at}.shape"),
                "a block cannot contain a `blocks` generator (one level of instancing)",
            );
            continue;
        }
        generator(c, &at, g);
    }
}

/// A `blocks` generator: its block (≥ 1 particle, no nested blocks), its instances (≥ 1).
fn blocks_generator(
    c: &mut Checker,
    at: &str,
    block: &BlockDesc,
    instances: &[InstanceDesc],
    placement: &Option<PlacementDesc>,
) {
    let b = format!("{at}.block");
    particle_list(c, &b, &block.particles, &block.generators, false);
    if block_count(block) == 0 {
        c.push(
            &b,
            "a block needs at least one particle (`particles` or `generators`)",
        );
    }
    for (i, inst) in instances.iter().enumerate() {
        let p = format!("{at}.instances[{i}]");
        c.finite3(&format!("{p}.center"), inst.center);
        c.positive(&format!("{p}.scale"), inst.scale);
        non_negative(c, &format!("{p}.density_scale"), inst.density_scale);
    }
    if let Some(pl) = placement {
        let p = format!("{at}.placement");
        c.count(&format!("{p}.count"), pl.count, 1, MAX_PARTICLES as u32);
        c.finite3(&format!("{p}.center"), pl.center);
        positive3(c, &format!("{p}.radii"), pl.radii);
        radius_range(c, &format!("{p}.scale"), pl.scale, true);
    }
    if instance_count(instances, placement) == 0 {
        c.push(
            at,
            "a `blocks` generator needs at least one instance (`instances` or `placement`)",
        );
    }
}

fn positive3(c: &mut Checker, path: &str, v: Vec3) {
    if c.finite3(path, v) && v.min_element() <= 0.0 {
        c.push(path, format!("must be > 0 in every axis, got {v}"));
    }
}

fn non_negative(c: &mut Checker, path: &str, x: f32) {
    if !(x.is_finite() && x >= 0.0) {
        c.push(path, format!("must be a finite number ≥ 0, got {x}"));
    }
}

fn radius_range(c: &mut Checker, path: &str, r: [f32; 2], ordered: bool) {
    c.positive(&format!("{path}[0]"), r[0]);
    c.positive(&format!("{path}[1]"), r[1]);
    if ordered && r[0].is_finite() && r[1].is_finite() && r[0] > r[1] {
        c.push(path, format!("min must be ≤ max, got [{}, {}]", r[0], r[1]));
    }
}

fn generator(c: &mut Checker, at: &str, g: &GeneratorDesc) {
    match g {
        GeneratorDesc::Blocks {
            block,
            instances,
            placement,
        } => blocks_generator(c, at, block, instances, placement),
        GeneratorDesc::Cloud {
            count,
            center,
            radii,
            particle_radius,
            density,
            albedo,
            ..
        } => {
            c.count(&format!("{at}.count"), *count, 1, MAX_PARTICLES as u32);
            c.finite3(&format!("{at}.center"), *center);
            positive3(c, &format!("{at}.radii"), *radii);
            radius_range(c, &format!("{at}.particle_radius"), *particle_radius, true);
            non_negative(c, &format!("{at}.density"), *density);
            c.unit_interval3(&format!("{at}.albedo"), *albedo);
        }
        GeneratorDesc::SmokeColumn {
            count,
            base,
            height,
            radius_bottom,
            radius_top,
            particle_radius,
            density,
            albedo,
            ..
        } => {
            c.count(&format!("{at}.count"), *count, 1, MAX_PARTICLES as u32);
            c.finite3(&format!("{at}.base"), *base);
            c.positive(&format!("{at}.height"), *height);
            non_negative(c, &format!("{at}.radius_bottom"), *radius_bottom);
            non_negative(c, &format!("{at}.radius_top"), *radius_top);
            radius_range(c, &format!("{at}.particle_radius"), *particle_radius, false);
            non_negative(c, &format!("{at}.density"), *density);
            c.unit_interval3(&format!("{at}.albedo"), *albedo);
        }
    }
}

fn light(c: &mut Checker, p: &str, l: &LightDesc) {
    match l {
        LightDesc::Point {
            position,
            intensity,
            keyframes,
        } => {
            c.point3(&format!("{p}.position"), *position);
            c.non_negative3(&format!("{p}.intensity"), *intensity);
            light_keys(c, p, keyframes, false);
        }
        LightDesc::Spot {
            position,
            direction,
            inner_deg,
            outer_deg,
            intensity,
            pattern,
            keyframes,
            attached_to_camera,
        } => {
            c.point3(&format!("{p}.position"), *position);
            c.nonzero3(&format!("{p}.direction"), *direction);
            if *attached_to_camera {
                flashlight(c, p, *position, keyframes);
            }
            c.non_negative3(&format!("{p}.intensity"), *intensity);
            if !(inner_deg.is_finite() && *inner_deg >= 0.0) {
                c.push(
                    &format!("{p}.inner_deg"),
                    format!("must be ≥ 0 degrees, got {inner_deg}"),
                );
            }
            if !(outer_deg.is_finite() && *outer_deg > 0.0 && *outer_deg < 90.0) {
                c.push(
                    &format!("{p}.outer_deg"),
                    format!("must be in (0, 90) degrees, got {outer_deg}"),
                );
            } else if inner_deg.is_finite() && inner_deg >= outer_deg {
                c.push(
                    &format!("{p}.inner_deg"),
                    format!("must be less than outer_deg ({outer_deg}), got {inner_deg}"),
                );
            }
            if let Some(pat) = pattern {
                let pp = format!("{p}.pattern");
                match pat {
                    Pattern::Checker { cells, dark } => {
                        c.count(&format!("{pp}.cells"), *cells, 1, 1024);
                        if !(dark.is_finite() && (0.0..=1.0).contains(dark)) {
                            c.push(
                                &format!("{pp}.dark"),
                                format!("must be in [0, 1], got {dark}"),
                            );
                        }
                    }
                    Pattern::StainedGlass { panes, lead, .. } => {
                        c.count(&format!("{pp}.panes"), *panes, 1, 256);
                        if !(lead.is_finite() && (0.0..1.0).contains(lead)) {
                            c.push(
                                &format!("{pp}.lead"),
                                format!("must be in [0, 1), got {lead}"),
                            );
                        }
                    }
                }
            }
            light_keys(c, p, keyframes, true);
        }
        LightDesc::Directional {
            direction,
            irradiance,
            keyframes,
        } => {
            c.nonzero3(&format!("{p}.direction"), *direction);
            c.non_negative3(&format!("{p}.irradiance"), *irradiance);
            for (k, key) in keyframes.iter().enumerate() {
                if key.position.is_some() {
                    c.push(
                        &format!("{p}.keyframes[{k}].position"),
                        "a directional light has no position",
                    );
                }
            }
            light_keys(c, p, keyframes, true);
        }
    }
}

/// The closest a camera-attached spot may be to the eye, m. At the eye itself every pixel's
/// in-scattering integral diverges (the light's 1/r² at r = 0 lies on every eye ray).
pub const MIN_FLASHLIGHT_OFFSET: f32 = 0.01;

/// A spot attached to the camera: it follows the camera's keys, so keys of its own would be
/// ambiguous; and it must not sit at the eye.
fn flashlight(c: &mut Checker, p: &str, position: Vec3, keys: &[LightKey]) {
    if !keys.is_empty() {
        c.push(
            &format!("{p}.keyframes"),
            "a spot attached to the camera follows the camera's keyframes and cannot have its \
             own: remove `keyframes` or `attached_to_camera`",
        );
    }
    if position.is_finite() && position.length() < MIN_FLASHLIGHT_OFFSET {
        c.push(
            &format!("{p}.position"),
            format!(
                "a spot attached to the camera must be at least {MIN_FLASHLIGHT_OFFSET} m from the \
                 eye (camera-space [0, 0, 0]): at the eye every pixel's in-scattering diverges; \
                 got {position} ({} m)",
                position.length()
            ),
        );
    }
}

/// Two keys at one frame are ambiguous (which value holds there?): each later key whose frame
/// an earlier one already keys is refused at its `frame`, naming the earlier key. `what` names
/// the keyed field for lights, whose keys may set position and direction separately.
fn unique_frames(
    c: &mut Checker,
    keys_path: &str,
    what: &str,
    frames: impl Iterator<Item = (usize, f32)>,
) {
    let mut seen: Vec<(usize, f32)> = Vec::new();
    for (k, frame) in frames {
        if let Some((first, _)) = seen.iter().find(|(_, f)| *f == frame) {
            c.push(
                &format!("{keys_path}[{k}].frame"),
                format!(
                    "frame {frame} already has a key{what} ({keys_path}[{first}]): two keys at one \
                     frame are ambiguous; give each key its own frame"
                ),
            );
        } else if frame.is_finite() {
            seen.push((k, frame));
        }
    }
}

fn light_keys(c: &mut Checker, p: &str, keys: &[LightKey], has_direction: bool) {
    let keys_path = format!("{p}.keyframes");
    let keyed = |field: fn(&LightKey) -> bool| {
        keys.iter()
            .enumerate()
            .filter(move |(_, k)| field(k))
            .map(|(i, k)| (i, k.frame))
    };
    unique_frames(
        c,
        &keys_path,
        " setting position",
        keyed(|k| k.position.is_some()),
    );
    unique_frames(
        c,
        &keys_path,
        " setting direction",
        keyed(|k| k.direction.is_some()),
    );
    for (k, key) in keys.iter().enumerate() {
        let kp = format!("{p}.keyframes[{k}]");
        c.finite(&format!("{kp}.frame"), key.frame);
        if let Some(pos) = key.position {
            c.point3(&format!("{kp}.position"), pos);
        }
        match (key.direction, has_direction) {
            (Some(d), true) => c.nonzero3(&format!("{kp}.direction"), d),
            (Some(_), false) => {
                c.push(&format!("{kp}.direction"), "a point light has no direction")
            }
            _ => {}
        }
        if key.position.is_none() && key.direction.is_none() {
            c.push(&kp, "a key must set position or direction");
        }
    }
}

fn transform(c: &mut Checker, p: &str, t: &Transform) {
    c.point3(&format!("{p}.translation"), t.translation);
    c.finite3(&format!("{p}.rotation_deg"), t.rotation_deg);
    if c.finite3(&format!("{p}.scale"), t.scale) && t.scale.min_element() <= 0.0 {
        c.push(
            &format!("{p}.scale"),
            format!("must be > 0 on every axis, got {}", t.scale),
        );
    }
}

fn shape(c: &mut Checker, p: &str, s: &Shape, base: &Path) {
    let f = |name: &str| format!("{p}.{name}");
    if let Some(t) = triangle_estimate(s)
        && t > MAX_TRIANGLES
    {
        c.push(
            p,
            format!("would have about {t} triangles; a procedural shape may have at most {MAX_TRIANGLES}"),
        );
    }
    match s {
        Shape::Plane { size } => {
            c.positive(&f("size[0]"), size[0]);
            c.positive(&f("size[1]"), size[1]);
        }
        Shape::Box { size } => {
            if c.finite3(&f("size"), *size) && size.min_element() <= 0.0 {
                c.push(&f("size"), format!("must be > 0 on every axis, got {size}"));
            }
        }
        Shape::Sphere {
            radius,
            segments,
            rings,
        } => {
            c.positive(&f("radius"), *radius);
            c.count(&f("segments"), *segments, 3, MAX_SEGMENTS);
            c.count(&f("rings"), *rings, 2, MAX_SEGMENTS);
        }
        Shape::Cylinder {
            radius,
            height,
            segments,
        } => {
            c.positive(&f("radius"), *radius);
            c.positive(&f("height"), *height);
            c.count(&f("segments"), *segments, 3, MAX_SEGMENTS);
        }
        Shape::Torus {
            major_radius,
            minor_radius,
            segments,
            sides,
        } => {
            c.positive(&f("major_radius"), *major_radius);
            c.positive(&f("minor_radius"), *minor_radius);
            if minor_radius >= major_radius {
                c.push(
                    &f("minor_radius"),
                    format!("must be less than major_radius ({major_radius}), got {minor_radius}"),
                );
            }
            c.count(&f("segments"), *segments, 3, MAX_SEGMENTS);
            c.count(&f("sides"), *sides, 3, MAX_SEGMENTS);
        }
        Shape::Spring {
            coil_radius,
            wire_radius,
            turns,
            height,
            segments_per_turn,
            sides,
        } => {
            c.positive(&f("coil_radius"), *coil_radius);
            c.positive(&f("wire_radius"), *wire_radius);
            c.positive(&f("height"), *height);
            if !(turns.is_finite() && *turns > 0.0 && *turns <= 1000.0) {
                c.push(&f("turns"), format!("must be in (0, 1000], got {turns}"));
            }
            if wire_radius >= coil_radius {
                c.push(
                    &f("wire_radius"),
                    format!("must be less than coil_radius ({coil_radius}), got {wire_radius}"),
                );
            }
            c.count(&f("segments_per_turn"), *segments_per_turn, 3, MAX_SEGMENTS);
            c.count(&f("sides"), *sides, 3, MAX_SEGMENTS);
        }
        Shape::Pencil {
            radius,
            length,
            tip_length,
        } => {
            c.positive(&f("radius"), *radius);
            c.positive(&f("length"), *length);
            c.positive(&f("tip_length"), *tip_length);
        }
        Shape::Fence {
            width,
            height,
            posts,
            rails,
            bar,
        } => {
            c.positive(&f("width"), *width);
            c.positive(&f("height"), *height);
            c.positive(&f("bar"), *bar);
            c.count(&f("posts"), *posts, 1, MAX_SEGMENTS);
            c.count(&f("rails"), *rails, 0, MAX_SEGMENTS);
            if bar >= width || bar >= height {
                c.push(
                    &f("bar"),
                    format!("must be smaller than the fence ({width} × {height}), got {bar}"),
                );
            }
        }
        Shape::Atrium { detail } | Shape::AtriumBanners { detail } => {
            if !(detail.is_finite() && (atrium::MIN_DETAIL..=atrium::MAX_DETAIL).contains(detail)) {
                c.push(
                    &f("detail"),
                    format!(
                        "must be in [{}, {}], got {detail}",
                        atrium::MIN_DETAIL,
                        atrium::MAX_DETAIL
                    ),
                );
            }
        }
        Shape::Obj { path } => {
            let full = crate::mesh::obj::resolve_path(base, path);
            if !full.is_file() {
                c.push(
                    &f("path"),
                    format!("OBJ file not found: {}", full.display()),
                );
            }
        }
        Shape::Gltf { path, .. } => {
            let full = crate::mesh::obj::resolve_path(base, path);
            if !full.is_file() {
                c.push(
                    &f("path"),
                    format!("glTF file not found: {}", full.display()),
                );
            }
        }
    }
}
