//! The camera, and an animated view's keys.

use crate::desc::SceneDesc;

use super::checker::*;

pub(super) fn camera(c: &mut Checker, d: &SceneDesc) {
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
pub(super) fn animated_view(c: &mut Checker, d: &SceneDesc) {
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
