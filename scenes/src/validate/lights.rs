//! Lights: their kind's fields, patterns and animation keys (flashlights included).

use glam::Vec3;

use crate::desc::{
    LightDesc, LightKey, Pattern,
};

use super::checker::*;

pub(super) fn light(c: &mut Checker, p: &str, l: &LightDesc) {
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

/// A spot attached to the camera: it follows the camera's keys, so keys of its own would be
/// ambiguous; and it must not sit at the eye.
pub(super) fn flashlight(c: &mut Checker, p: &str, position: Vec3, keys: &[LightKey]) {
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

pub(super) fn light_keys(c: &mut Checker, p: &str, keys: &[LightKey], has_direction: bool) {
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
