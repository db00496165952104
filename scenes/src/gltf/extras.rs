//! What glTF cannot say about a scatterbench scene, carried in glTF `extras` under the key
//! `scatterbench` so that importing an exported file restores the scene: the medium and other
//! scene-wide fields (`asset.extras`), Phong lobes (`materials[i].extras`), whether an object
//! casts volumetric shadows (`nodes[i].extras`), a light's exact placement, intensity, cone in
//! degrees and pattern (`KHR_lights_punctual.lights[i].extras`), the camera's exact pose
//! (`cameras[i].extras`). Exact values restore what the glTF fields round (radians, the
//! quaternion of a direction, candela) and are used only while they agree with those fields
//! ([`agreeing`]): an edit in another tool changes the glTF fields, and then they win. Other
//! applications' extras are left alone.

use ::gltf::json::extras::RawValue;
use glam::Vec3;
use serde::de::DeserializeOwned;
use serde::{Deserialize, Serialize};

use super::document::{Document, GltfError};
use crate::desc::{MediumDesc, Pattern, Phong};

/// The key inside an `extras` object.
pub const KEY: &str = "scatterbench";

/// `asset.extras.scatterbench`: the scene-wide fields of the exported scene.
#[derive(Clone, Debug, Default, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct AssetExtras {
    /// The scene's description. Default: empty.
    #[serde(default)]
    pub description: String,
    /// The medium; a glTF file imported as a scene by itself uses it instead of the default.
    #[serde(default)]
    pub medium: Option<MediumDesc>,
    /// Biri 2006's indirect single scattering. Default: false.
    #[serde(default)]
    pub indirect_single_scattering: bool,
    /// The exported scene's frame count (export writes frame 0; an import is one frame).
    #[serde(default)]
    pub frames: Option<u32>,
}

/// `materials[i].extras.scatterbench`.
#[derive(Clone, Debug, Default, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct MaterialExtras {
    #[serde(default)]
    pub phong: Option<Phong>,
}

/// `nodes[i].extras.scatterbench` of a mesh node.
#[derive(Clone, Debug, Default, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct NodeExtras {
    /// Default: true.
    #[serde(default)]
    pub casts_volumetric_shadow: Option<bool>,
}

/// `KHR_lights_punctual.lights[i].extras.scatterbench`: the light as the scene gave it
/// (position in m, direction as written, intensity in W/sr or irradiance in W/m²) and a spot's
/// cone in degrees and its pattern.
#[derive(Clone, Debug, Default, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct LightExtras {
    #[serde(default)]
    pub position: Option<Vec3>,
    #[serde(default)]
    pub direction: Option<Vec3>,
    #[serde(default)]
    pub intensity: Option<Vec3>,
    #[serde(default)]
    pub inner_deg: Option<f32>,
    #[serde(default)]
    pub outer_deg: Option<f32>,
    #[serde(default)]
    pub pattern: Option<Pattern>,
}

/// `cameras[i].extras.scatterbench`: the camera as the scene gave it.
#[derive(Clone, Debug, Default, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct CameraExtras {
    #[serde(default)]
    pub position: Option<Vec3>,
    #[serde(default)]
    pub look_at: Option<Vec3>,
    #[serde(default)]
    pub up: Option<Vec3>,
    #[serde(default)]
    pub fov_y_deg: Option<f32>,
}

/// How close (relative to 1 + the value's size) an exact value must be to the one derived
/// from the glTF fields to be used: f32 rounding of a round trip is ~1e-7.
pub const AGREEMENT: f32 = 1e-5;

/// `exact` (from our extras) when `agree(exact)` holds against the glTF-derived value, else
/// `derived`.
pub fn agreeing<T: Copy>(exact: Option<T>, derived: T, agree: impl Fn(T, T) -> bool) -> T {
    exact.filter(|&e| agree(e, derived)).unwrap_or(derived)
}

/// Whether two vectors agree within [`AGREEMENT`].
pub fn near3(a: Vec3, b: Vec3) -> bool {
    (a - b).length() <= AGREEMENT * (1.0 + b.length())
}

/// Whether two numbers agree within [`AGREEMENT`].
pub fn near(a: f32, b: f32) -> bool {
    (a - b).abs() <= AGREEMENT * (1.0 + b.abs())
}

/// Whether two directions agree within [`AGREEMENT`] once normalised.
pub fn same_direction(a: Vec3, b: Vec3) -> bool {
    match (a.try_normalize(), b.try_normalize()) {
        (Some(a), Some(b)) => near3(a, b),
        _ => false,
    }
}

/// Our part of an `extras` value at `path` (e.g. `nodes[3].extras`): None when the extras are
/// absent, not an object, or have no `scatterbench` key; an error naming the field when ours
/// is malformed.
pub fn read<T: DeserializeOwned>(
    doc: &Document,
    path: &str,
    extras: &Option<Box<RawValue>>,
) -> Result<Option<T>, GltfError> {
    let Some(raw) = extras else { return Ok(None) };
    let Ok(serde_json::Value::Object(mut map)) = serde_json::from_str(raw.get()) else {
        return Ok(None);
    };
    let Some(ours) = map.remove(KEY) else {
        return Ok(None);
    };
    serde_path_to_error::deserialize(ours)
        .map(Some)
        .map_err(|e| {
            let inner = e.path().to_string();
            let at = if inner == "." || inner.is_empty() {
                format!("{path}.{KEY}")
            } else {
                format!("{path}.{KEY}.{inner}")
            };
            doc.error(at, e.into_inner().to_string())
        })
}

/// `{"scatterbench": value}`, for export.
pub fn wrap(value: impl Serialize) -> serde_json::Value {
    serde_json::json!({ KEY: value })
}
