//! glTF materials as the suite's: `pbrMetallicRoughness.baseColorFactor` (RGB) is the Lambert
//! albedo, `doubleSided` is `two_sided`, a Phong lobe comes from our extras. Everything else
//! that changes a surface's look (textures, metallic-roughness, emission, transparency) is
//! recorded as ignored. A primitive without a material gets the suite's default (albedo 0.8),
//! not glTF's white default material: a perfect reflector would be unlike any real level.

use ::gltf::json::material::AlphaMode;
use ::gltf::json::validation::Checked;

use super::document::{Document, GltfError};
use super::extras::{self, MaterialExtras};
use super::ignored::{self, Ignored};
use crate::desc::Material;

/// The suite's material for `materials[index]` (the default without one), and what of it was
/// not modelled.
pub fn import(doc: &Document, index: Option<usize>) -> Result<(Material, Vec<Ignored>), GltfError> {
    let Some(index) = index else {
        return Ok((Material::default(), vec![]));
    };
    let path = format!("materials[{index}]");
    let m = doc.item(&doc.root.materials, "materials", index)?;
    let pbr = &m.pbr_metallic_roughness;
    let [r, g, b, a] = pbr.base_color_factor.0;
    if ![r, g, b, a]
        .iter()
        .all(|c| c.is_finite() && (0.0..=1.0).contains(c))
    {
        return Err(doc.error(
            format!("{path}.pbrMetallicRoughness.baseColorFactor"),
            format!("must be in [0, 1] per channel, got {:?}", [r, g, b, a]),
        ));
    }
    let ours: MaterialExtras =
        extras::read(doc, &format!("{path}.extras"), &m.extras)?.unwrap_or_default();
    let mut ignored = Vec::new();
    let mut note = |present: bool, field: &str, what| {
        if present {
            ignored.push(Ignored::new(format!("{path}.{field}"), what));
        }
    };
    let pbr_path = "pbrMetallicRoughness";
    note(
        pbr.base_color_texture.is_some(),
        &format!("{pbr_path}.baseColorTexture"),
        ignored::TEXTURE,
    );
    note(
        pbr.metallic_roughness_texture.is_some(),
        &format!("{pbr_path}.metallicRoughnessTexture"),
        ignored::TEXTURE,
    );
    note(
        m.normal_texture.is_some(),
        "normalTexture",
        ignored::TEXTURE,
    );
    note(
        m.occlusion_texture.is_some(),
        "occlusionTexture",
        ignored::TEXTURE,
    );
    note(
        m.emissive_texture.is_some(),
        "emissiveTexture",
        ignored::TEXTURE,
    );
    note(
        pbr.metallic_factor.0 != 0.0,
        &format!("{pbr_path}.metallicFactor"),
        ignored::METALLIC_ROUGHNESS,
    );
    note(
        m.emissive_factor.0 != [0.0; 3],
        "emissiveFactor",
        ignored::EMISSIVE,
    );
    note(
        a < 1.0 || !matches!(m.alpha_mode, Checked::Valid(AlphaMode::Opaque)),
        "alphaMode",
        ignored::TRANSPARENCY,
    );
    Ok((
        Material {
            albedo: glam::Vec3::new(r, g, b),
            phong: ours.phong,
            two_sided: m.double_sided,
        },
        ignored,
    ))
}
