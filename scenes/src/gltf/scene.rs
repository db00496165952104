//! glTF files in scenes: a scene file's `"import": "level.glb"` ([`import_of`], [`splice`]),
//! and a `.gltf`/`.glb` given where a scene is expected ([`load`]), a scene by itself with
//! [`default_medium`] (or the medium its own `asset.extras.scatterbench` carries).

use std::path::Path;
use std::sync::Arc;

use glam::Vec3;

use super::{GltfError, Level, import};
use crate::desc::{MediumDesc, SceneDesc};
use crate::mesh::obj::resolve_path;
use crate::phase::Phase;
use crate::scene::Scene;
use crate::validate::{Problem, validate};

/// Whether a path names a glTF file (by its extension, case-insensitive).
pub fn is_gltf_path(path: &Path) -> bool {
    path.extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case("gltf") || e.eq_ignore_ascii_case("glb"))
}

/// The medium of a glTF file used as a scene by itself: homogeneous, σa = 0.002 /m and
/// σs = 0.02 /m in every channel, Henyey–Greenstein g = 0.2, no ambient. σt = 0.022 /m is a
/// mean free path of 45 m: across a 10–50 m level the transmittance is 0.8–0.33, so shafts
/// are plain and the far wall still shows. g = 0.2 is Unreal Engine's default fog anisotropy.
pub fn default_medium() -> MediumDesc {
    MediumDesc::Homogeneous {
        sigma_a: Vec3::splat(0.002),
        sigma_s: Vec3::splat(0.02),
        phase: Phase::HenyeyGreenstein { g: 0.2 },
        ambient: Vec3::ZERO,
        height_fog: None,
    }
}

/// A scene file's import, read: the level and the file's JSON with `import` removed and the
/// level's camera put in when the file gives none.
pub struct Imported {
    pub level: Level,
    pub value: serde_json::Value,
    pub camera_imported: bool,
}

/// The import of a scene file's text, if it has a top-level `"import"`. An error is the
/// message for the scene file's `import` field, naming the glTF file and path.
pub fn import_of(text: &str, base: &Path) -> Result<Option<Imported>, String> {
    if !text.contains("\"import\"") {
        return Ok(None);
    }
    let Ok(serde_json::Value::Object(mut map)) = serde_json::from_str(text) else {
        return Ok(None); // not an object: the ordinary parser reports it with its position
    };
    let Some(field) = map.remove("import") else {
        return Ok(None);
    };
    let serde_json::Value::String(shape_path) = field else {
        return Err(format!(
            "must be the path of a .gltf or .glb file (a string), got {field}"
        ));
    };
    let level = import(&resolve_path(base, &shape_path), &shape_path)
        .map_err(|e: GltfError| e.to_string())?;
    let camera_imported = !map.contains_key("camera");
    if camera_imported {
        let Some((camera, _)) = &level.camera else {
            return Err(format!(
                "{}: the scene file gives no camera and the glTF file has no perspective camera",
                level.file
            ));
        };
        let camera = serde_json::to_value(camera).expect("a camera serialises");
        map.insert("camera".into(), camera);
    }
    map.entry("lights")
        .or_insert(serde_json::Value::Array(vec![]));
    Ok(Some(Imported {
        level,
        value: serde_json::Value::Object(map),
        camera_imported,
    }))
}

/// Where spliced-in content came from, to move a validation problem about it onto the glTF.
pub struct Origins {
    file: String,
    /// Object and light index the imported ones start at.
    first_object: usize,
    first_light: usize,
    objects: Vec<String>,
    lights: Vec<String>,
    camera: Option<String>,
}

/// Appends the level's lights and objects (descriptions only) to `desc`; `camera_imported`:
/// whether `desc.camera` is the level's.
pub fn splice(desc: &mut SceneDesc, level: &Level, camera_imported: bool) -> Origins {
    let origins = Origins {
        file: level.file.clone(),
        first_object: desc.objects.len(),
        first_light: desc.lights.len(),
        objects: level.objects.iter().map(|o| o.origin.clone()).collect(),
        lights: level.lights.iter().map(|l| l.1.clone()).collect(),
        camera: camera_imported
            .then(|| level.camera.as_ref().map(|c| c.1.clone()))
            .flatten(),
    };
    desc.lights.extend(level.lights.iter().map(|l| l.0.clone()));
    desc.objects
        .extend(level.objects.iter().map(|o| o.desc.clone()));
    origins
}

impl Origins {
    /// For a problem about spliced-in content: its glTF origin (`nodes[3] (meshes[1]…)`) and
    /// the message with the field it is about.
    pub fn origin_of(&self, p: &Problem) -> Option<(String, String)> {
        let indexed = |prefix: &str, first: usize, names: &[String]| {
            let rest = p.path.strip_prefix(prefix)?;
            let (i, tail) = rest.split_once(']')?;
            let k = i.parse::<usize>().ok()?.checked_sub(first)?;
            Some((
                names.get(k)?.clone(),
                tail.trim_start_matches('.').to_string(),
            ))
        };
        let (origin, tail) = indexed("objects[", self.first_object, &self.objects)
            .or_else(|| indexed("lights[", self.first_light, &self.lights))
            .or_else(|| {
                let tail = p.path.strip_prefix("camera")?;
                Some((
                    self.camera.clone()?,
                    tail.trim_start_matches('.').to_string(),
                ))
            })?;
        let message = if tail.is_empty() {
            p.message.clone()
        } else {
            format!("{tail}: {}", p.message)
        };
        Some((origin, message))
    }

    /// A problem about imported content, re-pathed to the scene file's `import` with the glTF
    /// file and origin in its message; others unchanged.
    pub fn relocate(&self, p: Problem) -> Problem {
        match self.origin_of(&p) {
            Some((origin, message)) => {
                Problem::new("import", format!("{}: {origin}: {message}", self.file))
            }
            None => p,
        }
    }
}

/// A `.gltf`/`.glb` file as a scene by itself: its objects, lights and first perspective
/// camera, the medium of its `asset.extras.scatterbench` (an exported scene's) or
/// [`default_medium`]. Without a camera or a light it is refused. Problems are at glTF paths
/// (an empty path: the file as a whole); `crate::load::load_scene` names the file.
pub fn load(path: &Path) -> Result<Scene, Vec<Problem>> {
    let shape_path = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let base = path.parent().unwrap_or(Path::new(""));
    let level = import(path, &shape_path).map_err(|e| vec![Problem::new(e.path, e.message)])?;
    let refuse = |path: &str, message: &str| vec![Problem::new(path, message)];
    let Some((camera, _)) = level.camera.clone() else {
        return Err(refuse(
            "cameras",
            "a glTF file used as a scene needs a perspective camera on a node of its scene \
             (or import it from a scene file that gives the camera)",
        ));
    };
    if level.lights.is_empty() {
        return Err(refuse(
            "extensions.KHR_lights_punctual",
            "a glTF file used as a scene needs at least one KHR_lights_punctual light on a node \
             of its scene (or import it from a scene file that adds lights)",
        ));
    }
    let extras = level.extras.clone();
    let mut desc = SceneDesc {
        description: if extras.description.is_empty() {
            format!("glTF level {shape_path}")
        } else {
            extras.description.clone()
        },
        camera,
        medium: extras.medium.clone().unwrap_or_else(default_medium),
        lights: Vec::new(),
        objects: Vec::new(),
        frames: 1,
        indirect_single_scattering: extras.indirect_single_scattering,
    };
    let origins = splice(&mut desc, &level, true);
    let problems: Vec<Problem> = validate(&desc, base)
        .into_iter()
        // Inside the glTF file itself, a problem is at its glTF path.
        .map(|p| match origins.origin_of(&p) {
            Some((origin, message)) => Problem::new(origin, message),
            None => p,
        })
        .collect();
    if !problems.is_empty() {
        return Err(problems);
    }
    Ok(Scene {
        name: path
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_else(|| "scene".into()),
        desc,
        meshes: level
            .objects
            .into_iter()
            .map(|o| Arc::new(o.mesh))
            .collect(),
        source: Some(path.to_path_buf()),
        ignored: level.ignored,
    })
}
