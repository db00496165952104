//! What glTF cannot say about a scatterbench scene, carried in glTF `extras` under the key
//! `scatterbench` so that importing an exported file restores the scene: the medium and other
//! scene-wide fields (`asset.extras`), Phong lobes (`materials[i].extras`), whether an object
//! casts volumetric shadows (`nodes[i].extras`), and a spot's exact cone in degrees and its
//! pattern (`KHR_lights_punctual.lights[i].extras`). Other applications' extras are left alone.

use ::gltf::json::extras::RawValue;
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

/// `KHR_lights_punctual.lights[i].extras.scatterbench` of a spot light: its cone in degrees
/// (glTF's radians in f32 lose the last bit) and its pattern.
#[derive(Clone, Debug, Default, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct LightExtras {
    #[serde(default)]
    pub inner_deg: Option<f32>,
    #[serde(default)]
    pub outer_deg: Option<f32>,
    #[serde(default)]
    pub pattern: Option<Pattern>,
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
