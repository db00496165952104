//! The checker: a problem list with its field tests, the limits, and the helpers several
//! parts of a scene use. A leaf: it imports no other part of `validate`.

use glam::Vec3;

use crate::desc::Shape;
use crate::mesh::atrium;

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
pub(super) const MAX_SEGMENTS: u32 = 4096;
pub(super) const MAX_FRAMES: u32 = 100_000;
/// The most triangles one procedural shape may have: parameters each within range can still
/// multiply to billions (a spring of 1000 turns × 4096 × 4096), which must be refused, not
/// allocated (found by `tests/fuzz.rs`).
pub(super) const MAX_TRIANGLES: u64 = 1 << 25;

/// The largest far/near ratio a camera may have. The methods project with 32-bit floats: past
/// ~1e7 the projection's depth terms round to those of an infinite far plane (and past ~1e16 even
/// the reference's 64-bit unprojection of a pixel ray divides by zero).
pub const MAX_FAR_OVER_NEAR: f32 = 1e6;

/// The largest magnitude (m) of a position's coordinate (camera, camera keys, lights, light
/// keys, object translations): ±1000 km. f32 leaves 6 cm of precision there, and a camera far
/// beyond it overflows the view and clip matrices to a non-finite pixel ray (found by the
/// loader fuzz test: a camera at x = 9.2e18, a finite f32).
pub const MAX_COORDINATE: f32 = 1e6;

/// The most particles a medium may have (explicit + generated): a typo guard (1e6 spheres
/// is ~40 MB in the reference's BVH), not a limit of the format.
pub const MAX_PARTICLES: u64 = 1_000_000;

/// The closest a camera-attached spot may be to the eye, m. At the eye itself every pixel's
/// in-scattering integral diverges (the light's 1/r² at r = 0 lies on every eye ray).
pub const MIN_FLASHLIGHT_OFFSET: f32 = 0.01;

/// An upper bound on the triangles a procedural shape builds (None: an OBJ file).
pub(super) fn triangle_estimate(s: &Shape) -> Option<u64> {
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

pub(super) struct Checker {
    pub(super) out: Vec<Problem>,
}

impl Checker {
    pub(super) fn push(&mut self, path: &str, msg: impl Into<String>) {
        self.out.push(Problem::new(path, msg));
    }
    pub(super) fn finite3(&mut self, path: &str, v: Vec3) -> bool {
        if !v.is_finite() {
            self.push(path, format!("must be finite, got {v}"));
            return false;
        }
        true
    }
    /// A position: finite, every coordinate within ±MAX_COORDINATE.
    pub(super) fn point3(&mut self, path: &str, v: Vec3) -> bool {
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
    pub(super) fn non_negative3(&mut self, path: &str, v: Vec3) {
        if self.finite3(path, v) && v.min_element() < 0.0 {
            self.push(path, format!("must be ≥ 0 in every channel, got {v}"));
        }
    }
    pub(super) fn nonzero3(&mut self, path: &str, v: Vec3) {
        if self.finite3(path, v) && v.length_squared() < 1e-20 {
            self.push(path, "must not be the zero vector");
        }
    }
    pub(super) fn positive(&mut self, path: &str, x: f32) {
        if !(x.is_finite() && x > 0.0) {
            self.push(path, format!("must be a finite number > 0, got {x}"));
        }
    }
    pub(super) fn finite(&mut self, path: &str, x: f32) -> bool {
        if !x.is_finite() {
            self.push(path, format!("must be finite, got {x}"));
            return false;
        }
        true
    }
    pub(super) fn count(&mut self, path: &str, n: u32, min: u32, max: u32) {
        if n < min || n > max {
            self.push(path, format!("must be in [{min}, {max}], got {n}"));
        }
    }
    pub(super) fn unit_interval3(&mut self, path: &str, v: Vec3) {
        if self.finite3(path, v) && (v.min_element() < 0.0 || v.max_element() > 1.0) {
            self.push(path, format!("must be in [0, 1] in every channel, got {v}"));
        }
    }
}

/// Two keys at one frame are ambiguous (which value holds there?): each later key whose frame
/// an earlier one already keys is refused at its `frame`, naming the earlier key. `what` names
/// the keyed field for lights, whose keys may set position and direction separately.
pub(super) fn unique_frames(
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
