//! The verdict metric: the one number every ranking reads (the report's summary matrix,
//! Pareto fronts, budget and equal-error tables, knob plots, `reproduce`), and the light-core
//! pixel set judged beside it.
//!
//! Everything that ranks records calls [`headline`]; switching the verdict metric means
//! changing this function (and `image::headline::HEADLINE_NAME`), nothing else.

use scenes::FrameState;

use crate::image::metrics::ErrorMetrics;
use crate::results::Record;

pub use crate::image::headline::{HEADLINE_NAME, TRIM_FRACTION};

/// The verdict metric of a record's AOV ("inscatter", "total", "surface"), a fraction
/// (0.05 = 5 %): the headline error ([`crate::image::headline`]); for an animated scene the mean
/// over its scored frames (`errors_per_frame.mean`). None when the record was not scored, or
/// was written before the headline existed.
pub fn headline(record: &Record, aov: &str) -> Option<f64> {
    if let Some(seq) = &record.errors_per_frame
        && let Some(m) = seq.mean.get(aov)
        && m.headline.is_finite()
    {
        return Some(m.headline);
    }
    record.errors.get(aov).and_then(|m| m.headline)
}

/// The metrics of a record's AOV that are not the verdict (for tables that show them beside it).
pub fn metrics<'a>(record: &'a Record, aov: &str) -> Option<&'a ErrorMetrics> {
    record.errors.get(aov)
}

/// The method whose time is the floor of a scene (ARCHITECTURE §4.5): it renders the scene
/// without scattering (surfaces and the medium's attenuation only), so its time is what every
/// method pays before any in-scatter. Not a contender: verdicts leave it out (its error is the
/// whole in-scatter) and give each winner's time as a multiple of it.
pub const FLOOR_METHOD: &str = "no-scatter";

/// Radius of the light core around each visible light's projection, as a fraction of the
/// image height: 2 % (5 px at 256², 10 px at 512²), so it covers the same solid angle at any
/// resolution. A disc of it is ≈ 0.12 % of a square image — about the set the headline trims.
pub const LIGHT_CORE_RADIUS: f64 = 0.02;

/// Radius in pixels of the light core at `height` (at least 2 px).
pub fn light_core_radius_px(height: u32) -> f64 {
    (LIGHT_CORE_RADIUS * height as f64).max(2.0)
}

/// The light-core pixels of a frame: those whose centre lies within
/// [`light_core_radius_px`] of the projection of a point or spot light that is in view — in
/// front of the camera, projecting inside the image, and not hidden (the reference's ray
/// through the projected pixel, `distance`, reaches at least the light). Directional lights
/// have no position and no core. Row-major, top row first; None when no light is in view.
pub fn light_core_mask(
    frame: &FrameState,
    width: u32,
    height: u32,
    distance: &[f32],
) -> Option<Vec<bool>> {
    let clip_from_world = frame.camera.clip_from_world(width as f32 / height as f32);
    let eye = frame.camera.position;
    let radius = light_core_radius_px(height);
    let mut mask = vec![false; width as usize * height as usize];
    let mut any = false;
    for light in &frame.lights {
        let Some(p) = light.position() else { continue };
        let clip = clip_from_world * p.extend(1.0);
        if clip.w <= 0.0 {
            continue;
        }
        let (x, y) = (clip.x / clip.w, clip.y / clip.w);
        // NDC → continuous pixel coordinates (pixel (i, j)'s centre is at i + ½, j + ½).
        let (px, py) = (
            (x as f64 + 1.0) * 0.5 * width as f64,
            (1.0 - y as f64) * 0.5 * height as f64,
        );
        if !(0.0..width as f64).contains(&px) || !(0.0..height as f64).contains(&py) {
            continue;
        }
        let centre = py as usize * width as usize + px as usize;
        let to_light = (p - eye).length();
        if distance.get(centre).is_none_or(|&d| d < to_light) {
            continue; // a surface in front of the light
        }
        any = true;
        let (j0, j1) = (
            (py - radius).floor().max(0.0) as u32,
            (py + radius).ceil() as u32,
        );
        let (i0, i1) = (
            (px - radius).floor().max(0.0) as u32,
            (px + radius).ceil() as u32,
        );
        for j in j0..j1.min(height) {
            for i in i0..i1.min(width) {
                let (dx, dy) = (i as f64 + 0.5 - px, j as f64 + 0.5 - py);
                if dx * dx + dy * dy <= radius * radius {
                    mask[j as usize * width as usize + i as usize] = true;
                }
            }
        }
    }
    any.then_some(mask)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::image::Image;
    use crate::image::headline::masked_relative;
    use glam::{Mat4, Vec3};
    use scenes::{CameraPose, LightState};

    fn frame_with_light(at: Vec3) -> FrameState {
        FrameState {
            index: 0,
            camera: CameraPose {
                position: Vec3::new(0.0, 0.0, 5.0),
                look_at: Vec3::ZERO,
                up: Vec3::Y,
                fov_y_deg: 45.0,
                near: 0.1,
                far: 50.0,
            },
            lights: vec![LightState::Point {
                position: at,
                intensity: Vec3::ONE,
            }],
            world_from_local: vec![Mat4::IDENTITY],
        }
    }

    /// A reference with a bright 1/d peak at the centre (a light's glow over a dim medium) and
    /// a test that is right everywhere except that it misses the peak: the headline must call it
    /// nearly right, the light-core figure very wrong.
    #[test]
    fn missing_only_the_peak_is_a_small_headline_and_a_large_light_core() {
        let (w, h) = (128u32, 128u32);
        let (cx, cy) = (64.0f32, 64.0f32);
        let mut reference = Image::new(w, h);
        let mut test = Image::new(w, h);
        for j in 0..h {
            for i in 0..w {
                let d = ((i as f32 + 0.5 - cx).powi(2) + (j as f32 + 0.5 - cy).powi(2)).sqrt();
                let base = 0.2 + 0.1 * (i as f32 / w as f32);
                // The peak: a Gaussian of σ = 0.7 px, negligible beyond ≈ 2.5 px.
                let peak = 50.0 * (-d * d / (2.0 * 0.49)).exp();
                reference.set(i, j, [base + peak; 3]);
                test.set(i, j, [base; 3]);
            }
        }
        let head = crate::image::headline::headline(&test, &reference);
        // Nothing is decided by the light at the image's centre: the far field is exact.
        let frame = frame_with_light(Vec3::ZERO);
        let mask = light_core_mask(&frame, w, h, &vec![100.0; (w * h) as usize]).expect("in view");
        let core = masked_relative(&test, &reference, &mask).unwrap();
        assert!(head < 0.05, "headline {head}");
        assert!(core > 0.5, "light core {core}");
        // The mask is the disc of radius 2.56 px around the centre pixel corner (64, 64).
        let count = mask.iter().filter(|&&m| m).count();
        assert!((16..=32).contains(&count), "{count} pixels");
        assert!(mask[64 * w as usize + 64] && !mask[0]);
    }

    #[test]
    fn lights_behind_the_camera_outside_the_frame_or_hidden_have_no_core() {
        let far = vec![100.0f32; 64 * 64];
        assert!(
            light_core_mask(&frame_with_light(Vec3::new(0.0, 0.0, 9.0)), 64, 64, &far).is_none()
        );
        assert!(
            light_core_mask(&frame_with_light(Vec3::new(30.0, 0.0, 0.0)), 64, 64, &far).is_none()
        );
        // A wall 2 m from the eye hides a light 5 m away.
        let near = vec![2.0f32; 64 * 64];
        assert!(light_core_mask(&frame_with_light(Vec3::ZERO), 64, 64, &near).is_none());
        assert!(light_core_mask(&frame_with_light(Vec3::ZERO), 64, 64, &far).is_some());
    }
}
