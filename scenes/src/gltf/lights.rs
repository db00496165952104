//! `KHR_lights_punctual` lights ↔ the suite's lights, with the unit conversion.
//!
//! glTF is photometric: point and spot `intensity` in candela (lm/sr), directional in lux
//! (lm/m²), times a linear RGB `color`. The suite is radiometric: W/sr and W/m². We assume
//! the luminous efficacy of the photometric definition, 683 lm/W (the candela's definition
//! at 555 nm), so `color × intensity / 683` is RGB W/sr (point, spot) or W/m² (directional).
//! glTF's spot falloff is t² with t = (cos α − cos outer) / (cos inner − cos outer) clamped;
//! the suite's is the smoothstep t²(3 − 2t) of the same t: the same cone edges, brighter in
//! between. Cones are imported as their angles. `range` is not modelled (the suite's lights
//! fall off as 1/r² to infinity): it is recorded as ignored.

use ::gltf::json::extensions::scene::khr_lights_punctual::{Light, Type};
use ::gltf::json::validation::Checked;
use glam::{Mat4, Vec3};

use super::document::{Document, GltfError};
use super::extras::{self, LightExtras, agreeing, near, near3, same_direction};
use super::ignored::{self, Ignored};
use crate::desc::LightDesc;

/// Assumed luminous efficacy, lm/W: the photometric definition (683 lm/W at 555 nm).
pub const LUMENS_PER_WATT: f32 = 683.0;

/// glTF `color × intensity` (cd or lx) as radiometric RGB (W/sr or W/m²).
pub fn radiometric(color: [f32; 3], intensity: f32) -> Vec3 {
    Vec3::from_array(color) * (intensity / LUMENS_PER_WATT)
}

/// The inverse of [`radiometric`]: (color in [0, 1] with its largest channel 1, intensity in
/// cd or lx). Black gives white at intensity 0.
pub fn photometric(rgb: Vec3) -> ([f32; 3], f32) {
    let peak = rgb.max_element();
    if peak > 0.0 {
        ((rgb / peak).to_array(), peak * LUMENS_PER_WATT)
    } else {
        ([1.0; 3], 0.0)
    }
}

/// One imported light and what of it was not modelled.
pub struct ImportedLight {
    pub light: LightDesc,
    pub ignored: Vec<Ignored>,
}

/// Light `index` placed by a node's world matrix (a glTF light shines down its node's −Z).
pub fn import(doc: &Document, index: usize, world: &Mat4) -> Result<ImportedLight, GltfError> {
    let path = format!("extensions.KHR_lights_punctual.lights[{index}]");
    let l: &Light = doc
        .root
        .extensions
        .as_ref()
        .and_then(|e| e.khr_lights_punctual.as_ref())
        .and_then(|k| k.lights.get(index))
        .ok_or_else(|| doc.error(&path, "no such light"))?;
    check_color_and_intensity(doc, &path, l)?;
    let ours: LightExtras =
        extras::read(doc, &format!("{path}.extras"), &l.extras)?.unwrap_or_default();
    let rgb = agreeing(ours.intensity, radiometric(l.color, l.intensity), near3);
    let position = agreeing(ours.position, world.transform_point3(Vec3::ZERO), near3);
    let derived = world.transform_vector3(Vec3::NEG_Z);
    let direction = agreeing(ours.direction, derived, same_direction);
    let mut ignored = Vec::new();
    if l.range.is_some() {
        ignored.push(Ignored::new(format!("{path}.range"), ignored::LIGHT_RANGE));
    }
    let light = match l.type_ {
        Checked::Valid(Type::Point) => LightDesc::Point {
            position,
            intensity: rgb,
            keyframes: vec![],
        },
        Checked::Valid(Type::Directional) => LightDesc::Directional {
            direction: unit_direction(doc, &path, direction)?,
            irradiance: rgb,
            keyframes: vec![],
        },
        Checked::Valid(Type::Spot) => {
            let (inner_deg, outer_deg) = spot_cone(doc, &path, l, &ours)?;
            LightDesc::Spot {
                position,
                direction: unit_direction(doc, &path, direction)?,
                inner_deg,
                outer_deg,
                intensity: rgb,
                pattern: ours.pattern,
                keyframes: vec![],
                attached_to_camera: false,
            }
        }
        Checked::Invalid => return Err(doc.error(format!("{path}.type"), "unknown light type")),
    };
    Ok(ImportedLight { light, ignored })
}

fn check_color_and_intensity(doc: &Document, path: &str, l: &Light) -> Result<(), GltfError> {
    if !l
        .color
        .iter()
        .all(|c| c.is_finite() && (0.0..=1.0).contains(c))
    {
        return Err(doc.error(
            format!("{path}.color"),
            format!("must be linear RGB in [0, 1], got {:?}", l.color),
        ));
    }
    if !(l.intensity.is_finite() && l.intensity >= 0.0) {
        return Err(doc.error(
            format!("{path}.intensity"),
            format!(
                "must be a finite number ≥ 0 (cd or lx), got {}",
                l.intensity
            ),
        ));
    }
    Ok(())
}

/// A node's −Z as a light direction; a singular node matrix can squash it to nothing.
fn unit_direction(doc: &Document, path: &str, d: Vec3) -> Result<Vec3, GltfError> {
    d.try_normalize().ok_or_else(|| {
        doc.error(
            path,
            "its node's transform maps −Z to zero: the light has no direction",
        )
    })
}

/// (inner_deg, outer_deg): glTF's cone angles in radians, 0 ≤ inner < outer < π/2, or the
/// exported exact degrees where they agree.
fn spot_cone(
    doc: &Document,
    path: &str,
    l: &Light,
    ours: &LightExtras,
) -> Result<(f32, f32), GltfError> {
    let spot = l
        .spot
        .as_ref()
        .ok_or_else(|| doc.error(format!("{path}.spot"), "a spot light needs its spot cone"))?;
    let (inner, outer) = (spot.inner_cone_angle, spot.outer_cone_angle);
    let half_pi = std::f32::consts::FRAC_PI_2;
    if !(outer.is_finite() && outer > 0.0 && outer.to_degrees() < 90.0 && outer < half_pi) {
        return Err(doc.error(
            format!("{path}.spot.outerConeAngle"),
            format!("must be in (0, π/2) radians (the suite's spots are under 90°), got {outer}"),
        ));
    }
    if !(inner.is_finite() && inner >= 0.0 && inner < outer) {
        return Err(doc.error(
            format!("{path}.spot.innerConeAngle"),
            format!("must be in [0, outerConeAngle = {outer}) radians, got {inner}"),
        ));
    }
    Ok((
        agreeing(ours.inner_deg, inner.to_degrees(), near),
        agreeing(ours.outer_deg, outer.to_degrees(), near),
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// 1 W of 555 nm light is 683 lm by definition: a source of 683 cd emits 1 W/sr, a
    /// surface under 683 lx receives 1 W/m².
    #[test]
    fn candela_and_lux_convert_by_the_photometric_definition() {
        assert_eq!(radiometric([1.0, 1.0, 1.0], 683.0), Vec3::ONE);
        let w = radiometric([1.0, 0.5, 0.25], 1366.0);
        assert!((w - Vec3::new(2.0, 1.0, 0.5)).length() < 1e-6, "{w}");
        // An isotropic 1 cd point source emits 4π lm in all: 4π/683 W.
        let total_watts = 4.0 * std::f32::consts::PI * radiometric([1.0; 3], 1.0).x;
        assert!((total_watts - 4.0 * std::f32::consts::PI / 683.0).abs() < 1e-9);
    }

    #[test]
    fn photometric_inverts_radiometric() {
        for rgb in [
            Vec3::new(200.0, 190.0, 170.0),
            Vec3::new(0.5, 0.5, 0.45),
            Vec3::ZERO,
        ] {
            let (color, cd) = photometric(rgb);
            assert!(color.iter().all(|c| (0.0..=1.0).contains(c)));
            let back = radiometric(color, cd);
            assert!((back - rgb).abs().max_element() <= 1e-5 * rgb.max_element().max(1.0));
        }
    }
}
