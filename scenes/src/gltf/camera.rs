//! glTF perspective cameras ↔ the suite's pinhole camera. A glTF camera looks down its node's
//! −Z with +Y up; `yfov` (radians) is the vertical field of view, `znear`/`zfar` the clip
//! depths (an infinite projection, no `zfar`, gets the suite's default far plane of 100 m).
//! `aspectRatio` is not modelled: the image's width/height sets the horizontal field of view.
//! An exported camera's exact position, look-at point, up hint and field of view travel in
//! `cameras[i].extras.scatterbench` and are used while they agree with the node.

use glam::{Mat4, Vec3};

use super::document::{Document, GltfError};
use super::extras::{self, CameraExtras, agreeing, near, near3, same_direction};
use crate::desc::CameraDesc;
use crate::validate::MAX_FAR_OVER_NEAR;

/// Far plane for a camera without `zfar`, m (the scene format's default).
pub const DEFAULT_FAR: f32 = 100.0;

/// `cameras[index]` placed by its node's world matrix; None for an orthographic camera.
pub fn import(doc: &Document, index: usize, world: &Mat4) -> Result<Option<CameraDesc>, GltfError> {
    let path = format!("cameras[{index}]");
    let c = doc.item(&doc.root.cameras, "cameras", index)?;
    let Some(p) = &c.perspective else {
        return Ok(None);
    };
    let fov_y_deg = p.yfov.to_degrees();
    if !(fov_y_deg.is_finite() && fov_y_deg > 0.0 && fov_y_deg < 180.0) {
        return Err(doc.error(
            format!("{path}.perspective.yfov"),
            format!("must be in (0, π) radians, got {}", p.yfov),
        ));
    }
    if !(p.znear.is_finite() && p.znear > 0.0) {
        return Err(doc.error(
            format!("{path}.perspective.znear"),
            format!("must be a finite number > 0, got {}", p.znear),
        ));
    }
    let far = p.zfar.unwrap_or(DEFAULT_FAR.max(p.znear * 2.0));
    if !(far.is_finite() && far > p.znear && far / p.znear <= MAX_FAR_OVER_NEAR) {
        return Err(doc.error(
            format!("{path}.perspective.zfar"),
            format!(
                "must be finite, > znear = {} and ≤ {MAX_FAR_OVER_NEAR:e} × znear (without zfar: {DEFAULT_FAR} m), got {far}",
                p.znear
            ),
        ));
    }
    let position = world.transform_point3(Vec3::ZERO);
    let forward = world.transform_vector3(Vec3::NEG_Z).try_normalize();
    let up = world.transform_vector3(Vec3::Y).try_normalize();
    let (Some(forward), Some(up)) = (forward, up) else {
        return Err(doc.error(
            &path,
            "its node's transform is singular: the camera has no view direction",
        ));
    };
    if forward.cross(up).length() < 1e-3 {
        return Err(doc.error(
            &path,
            "its node's transform makes the up direction parallel to the view direction",
        ));
    }
    let ours: CameraExtras =
        extras::read(doc, &format!("{path}.extras"), &c.extras)?.unwrap_or_default();
    let exact = exact_pose(&ours).filter(|&(p, l, u)| {
        near3(p, position)
            && same_direction(l - p, forward)
            && same_direction(true_up(l - p, u), up)
    });
    let (position, look_at, up) = exact.unwrap_or((position, position + forward, up));
    Ok(Some(CameraDesc {
        position,
        look_at,
        up,
        fov_y_deg: agreeing(ours.fov_y_deg, fov_y_deg, near),
        near: p.znear,
        far,
        keyframes: vec![],
    }))
}

/// (position, look_at, up) from our extras, when all three are there.
fn exact_pose(e: &CameraExtras) -> Option<(Vec3, Vec3, Vec3)> {
    Some((e.position?, e.look_at?, e.up?))
}

/// The up direction of a camera looking along `forward` with the `up` hint.
fn true_up(forward: Vec3, up: Vec3) -> Vec3 {
    forward.cross(up).cross(forward)
}
