//! The built-in scene library: the JSON files of `scenes/library/`, compiled into the binary so
//! `scatterbench` runs from any directory. The list is explicit and ordered.

use std::path::Path;

use crate::load::{SceneError, load_scene, parse_scene};
use crate::scene::Scene;
use crate::variants::{self, MAX_SUB_LEVELS};

/// (name, file text), in the order `list` and `run --scenes all` use.
pub const LIBRARY: &[(&str, &str)] = &[
    ("sphere-point", include_str!("../library/sphere-point.json")),
    ("desk-pencils", include_str!("../library/desk-pencils.json")),
    ("spring-point", include_str!("../library/spring-point.json")),
    ("fence-spot", include_str!("../library/fence-spot.json")),
    ("window-sun", include_str!("../library/window-sun.json")),
    (
        "stained-glass-spot",
        include_str!("../library/stained-glass-spot.json"),
    ),
    ("clear-fog", include_str!("../library/clear-fog.json")),
    ("pen-orbit", include_str!("../library/pen-orbit.json")),
    (
        "overlap-point",
        include_str!("../library/overlap-point.json"),
    ),
    ("cloud-8000", include_str!("../library/cloud-8000.json")),
    ("cloud-plane", include_str!("../library/cloud-plane.json")),
    ("cloud-blocks", include_str!("../library/cloud-blocks.json")),
    ("smoke-point", include_str!("../library/smoke-point.json")),
    (
        "indirect-point",
        include_str!("../library/indirect-point.json"),
    ),
    ("valley-sun", include_str!("../library/valley-sun.json")),
    (
        "corridor-walk",
        include_str!("../library/corridor-walk.json"),
    ),
    (
        "colonnade-flight",
        include_str!("../library/colonnade-flight.json"),
    ),
    ("atrium", include_str!("../library/atrium.json")),
    ("atrium-64", include_str!("../library/atrium-64.json")),
];

pub fn names() -> Vec<&'static str> {
    LIBRARY.iter().map(|(n, _)| *n).collect()
}

/// Loads a library scene by name.
pub fn load(name: &str) -> Option<Result<Scene, SceneError>> {
    LIBRARY
        .iter()
        .find(|(n, _)| *n == name)
        .map(|(n, text)| parse_scene(text, &format!("scenes/library/{n}.json"), n, Path::new(".")))
}

/// A library name, a variant `<library-name>-sub<L>` (every caster subdivided L ≤
/// [`MAX_SUB_LEVELS`] times, [`crate::variants`]) or `<atrium scene>-lights<N>` (N torches),
/// or a path to a scene file (JSON, or a `.gltf`/`.glb` as a scene by itself,
/// [`crate::gltf::scene::load`]). Unknown names are refused with the valid ones.
pub fn resolve(name_or_path: &str) -> Result<Scene, String> {
    if let Some(r) = load(name_or_path) {
        return r.map_err(|e| e.to_string());
    }
    if let Some((base, levels)) = variants::parse_sub(name_or_path)
        && let Some(r) = load(base)
    {
        if levels > MAX_SUB_LEVELS {
            return Err(format!(
                "scene '{name_or_path}': at most {MAX_SUB_LEVELS} subdivision levels (each quadruples the triangles), got {levels}"
            ));
        }
        return r
            .map(|s| variants::subdivided(&s, levels))
            .map_err(|e| e.to_string());
    }
    if let Some((base, n)) = variants::parse_lights(name_or_path)
        && let Some(r) = load(base)
    {
        return r
            .map_err(|e| e.to_string())
            .and_then(|s| variants::with_torches(&s, n));
    }
    let p = Path::new(name_or_path);
    if p.extension().is_some_and(|e| e == "json")
        || crate::gltf::scene::is_gltf_path(p)
        || p.is_file()
    {
        return load_scene(p).map_err(|e| e.to_string());
    }
    Err(format!(
        "unknown scene '{name_or_path}': valid library scenes are {} (or a variant <scene>-sub<L>, L ≤ {MAX_SUB_LEVELS}, atrium-lights<N>, N ≤ 64, or a path to a .json, .gltf or .glb file)",
        names().join(", ")
    ))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::desc::LightDesc;
    use crate::mesh::atrium::layout::torches;

    /// The library's atrium files list the torches the layout places (16 and 62), so the
    /// `-lights<N>` sweep and the library scenes light the same sconces.
    #[test]
    fn atrium_files_light_the_layouts_sconces() {
        for (name, n, spots) in [("atrium", 16, 2), ("atrium-64", 62, 2)] {
            let scene = load(name).unwrap().unwrap();
            let points: Vec<_> = scene
                .desc
                .lights
                .iter()
                .filter_map(|l| match l {
                    LightDesc::Point { position, .. } => Some(*position),
                    _ => None,
                })
                .collect();
            let expected = torches(n);
            assert_eq!(points.len(), n, "{name}");
            for (p, e) in points.iter().zip(&expected) {
                assert!(
                    (*p - *e).length() < 1e-4,
                    "{name}: torch at {p}, layout {e}"
                );
            }
            let spot_count = scene
                .desc
                .lights
                .iter()
                .filter(|l| matches!(l, LightDesc::Spot { .. }))
                .count();
            assert_eq!(spot_count, spots, "{name}");
            assert_eq!(
                scene.features().lights - 1,
                n + spots,
                "{name}: local lights + the sun"
            );
        }
    }

    #[test]
    fn light_variants_resolve_and_bad_counts_are_refused() {
        let s = resolve("atrium-lights4").unwrap();
        assert_eq!(s.name, "atrium-lights4");
        assert_eq!(s.desc.lights.len(), 5, "4 torches + the sun");
        for bad in ["atrium-lights0", "atrium-lights65", "fence-spot-lights4"] {
            let e = resolve(bad).unwrap_err();
            assert!(
                e.contains(bad) && (e.contains("64") || e.contains("atrium")),
                "{e}"
            );
        }
    }
}
