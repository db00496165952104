//! Content of a glTF file the suite does not model (textures, metallic-roughness, emissive,
//! light ranges, skins, morph targets, animations, …), recorded with its glTF path and never
//! silently dropped. [`summarise`] turns the list into the lines a scene carries in
//! `Scene::ignored` and the runner appends to every record's `ignored`.

/// One piece of unmodelled content: where it is and what kind of thing it is.
#[derive(Clone, Debug, PartialEq)]
pub struct Ignored {
    /// glTF path, e.g. `materials[2].pbrMetallicRoughness.baseColorTexture`.
    pub path: String,
    /// What is not modelled, e.g. "textures (not modelled)"; entries are grouped by it.
    pub what: &'static str,
}

impl Ignored {
    pub fn new(path: impl Into<String>, what: &'static str) -> Self {
        Self {
            path: path.into(),
            what,
        }
    }
}

pub const TEXTURE: &str = "textures are not modelled";
pub const METALLIC_ROUGHNESS: &str = "metallic-roughness is not modelled (Lambert albedo only)";
pub const EMISSIVE: &str = "emission is not modelled";
pub const TRANSPARENCY: &str = "alpha and transparency are not modelled (surfaces are opaque)";
pub const VERTEX_ATTRIBUTE: &str =
    "vertex attributes other than POSITION and NORMAL are not modelled";
pub const NOT_TRIANGLES: &str = "points and lines are not surfaces (not imported)";
pub const SKIN: &str = "skins are not modelled (the bind pose is imported)";
pub const MORPH: &str = "morph targets are not modelled (the base mesh is imported)";
pub const ANIMATION: &str = "animations are not modelled (the static pose is imported)";
pub const LIGHT_RANGE: &str = "light range is not modelled (lights fall off as 1/r² without limit)";
pub const CAMERA: &str =
    "only the first perspective camera is imported (orthographic and later cameras are not)";
pub const ASPECT: &str = "camera aspectRatio is not modelled (the image's width/height sets the horizontal field of view)";
pub const EXTENSION: &str = "extensions other than KHR_lights_punctual are not modelled";
pub const OTHER_SCENES: &str = "only the default scene is imported";

/// How many paths a summary line lists before "… (N in all)".
const SHOWN: usize = 4;

/// One line per kind of ignored content, in first-seen order:
/// `level.glb: textures are not modelled: materials[0]…, materials[2]… (5 in all)`.
pub fn summarise(file: &str, items: &[Ignored]) -> Vec<String> {
    let mut kinds: Vec<&'static str> = Vec::new();
    for i in items {
        if !kinds.contains(&i.what) {
            kinds.push(i.what);
        }
    }
    kinds
        .into_iter()
        .map(|what| {
            let paths: Vec<&str> = items
                .iter()
                .filter(|i| i.what == what)
                .map(|i| i.path.as_str())
                .collect();
            let shown = paths[..paths.len().min(SHOWN)].join(", ");
            let more = if paths.len() > SHOWN {
                format!(", … ({} in all)", paths.len())
            } else {
                String::new()
            };
            format!("{file}: {what}: {shown}{more}")
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn summaries_group_by_kind_and_count_what_they_cut() {
        let items: Vec<Ignored> = (0..6)
            .map(|i| Ignored::new(format!("materials[{i}].emissiveFactor"), EMISSIVE))
            .chain([Ignored::new("animations[0]", ANIMATION)])
            .collect();
        let lines = summarise("l.glb", &items);
        assert_eq!(lines.len(), 2);
        assert!(lines[0].starts_with("l.glb: emission is not modelled: materials[0]"));
        assert!(lines[0].ends_with("(6 in all)"), "{}", lines[0]);
        assert_eq!(lines[1], format!("l.glb: {ANIMATION}: animations[0]"));
    }
}
