//! Reading a scene file: syntax errors with file, line, column and field path; then every
//! semantic problem at once (see [`crate::validate`]); then the meshes.

use std::fmt;
use std::path::Path;
use std::sync::Arc;

use crate::desc::{SceneDesc, Shape};
use crate::mesh::{TriMesh, atrium, memo, obj, procedural};
use crate::scene::Scene;
use crate::validate::{Problem, validate};

/// Why a scene could not be loaded. `Display` prints one problem per line, each as
/// `file:line:column: field.path: what is wrong`.
#[derive(Debug, Clone, PartialEq)]
pub enum SceneError {
    Io {
        file: String,
        message: String,
    },
    Syntax {
        file: String,
        line: usize,
        column: usize,
        path: String,
        message: String,
    },
    Invalid {
        file: String,
        problems: Vec<LocatedProblem>,
    },
}

/// A semantic problem with where it is in the file (when the field is present in the text).
#[derive(Debug, Clone, PartialEq)]
pub struct LocatedProblem {
    pub line: Option<usize>,
    pub column: Option<usize>,
    pub problem: Problem,
}

impl fmt::Display for SceneError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            SceneError::Io { file, message } => write!(f, "{file}: {message}"),
            SceneError::Syntax {
                file,
                line,
                column,
                path,
                message,
            } => {
                let at = if path.is_empty() || path == "." || path == "?" {
                    String::new()
                } else {
                    format!("{path}: ")
                };
                write!(f, "{file}:{line}:{column}: {at}{message}")
            }
            SceneError::Invalid { file, problems } => {
                for (i, p) in problems.iter().enumerate() {
                    if i > 0 {
                        writeln!(f)?;
                    }
                    match (p.line, p.column) {
                        (Some(l), Some(c)) => write!(
                            f,
                            "{file}:{l}:{c}: {}: {}",
                            p.problem.path, p.problem.message
                        )?,
                        _ => write!(f, "{file}: {}: {}", p.problem.path, p.problem.message)?,
                    }
                }
                Ok(())
            }
        }
    }
}

impl std::error::Error for SceneError {}

/// Loads and validates a scene file — JSON, or a `.gltf`/`.glb` file as a scene by itself
/// ([`crate::gltf::scene::load`]). The scene's name is the file stem.
pub fn load_scene(path: &Path) -> Result<Scene, SceneError> {
    if crate::gltf::scene::is_gltf_path(path) {
        return crate::gltf::scene::load(path).map_err(|p| gltf_problems(path, p));
    }
    let file = path.display().to_string();
    let text = std::fs::read_to_string(path).map_err(|e| SceneError::Io {
        file: file.clone(),
        message: format!("cannot read: {e}"),
    })?;
    let name = path
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "scene".into());
    let base = path.parent().map(Path::to_path_buf).unwrap_or_default();
    let mut scene = parse_scene(&text, &file, &name, &base)?;
    scene.source = Some(path.to_path_buf());
    Ok(scene)
}

/// Parses and validates scene text. `file` names it in messages; OBJ and glTF paths resolve
/// against `base`. A top-level `"import"` brings in a glTF file's objects, lights and camera
/// ([`crate::gltf::scene`]).
pub fn parse_scene(text: &str, file: &str, name: &str, base: &Path) -> Result<Scene, SceneError> {
    let imported = crate::gltf::scene::import_of(text, base)
        .map_err(|m| invalid(text, file, vec![Problem::new("import", m)]))?;
    let mut desc = match &imported {
        Some(i) => deserialize_value(i.value.clone(), text, file)?,
        None => deserialize(text, file)?,
    };
    let own_objects = desc.objects.len();
    let origins = imported
        .as_ref()
        .map(|i| crate::gltf::scene::splice(&mut desc, &i.level, i.camera_imported));
    let mut problems = validate(&desc, base);
    if let Some(o) = &origins {
        problems = problems.into_iter().map(|p| o.relocate(p)).collect();
    }
    let mut meshes = Vec::with_capacity(desc.objects.len());
    if problems.is_empty() {
        for (i, o) in desc.objects.iter().take(own_objects).enumerate() {
            match shared_mesh(&o.shape, base) {
                Ok(m) if m.indices.is_empty() => problems.push(Problem::new(
                    format!("objects[{i}].shape"),
                    "the mesh has no triangles",
                )),
                Ok(m) => meshes.push(m),
                Err(message) => problems.push(Problem::new(format!("objects[{i}].shape"), message)),
            }
        }
    }
    if !problems.is_empty() {
        return Err(invalid(text, file, problems));
    }
    let (imported_meshes, ignored) = imported.map_or((vec![], vec![]), |i| {
        let meshes = i.level.objects.into_iter().map(|o| Arc::new(o.mesh));
        (meshes.collect(), i.level.ignored)
    });
    meshes.extend(imported_meshes);
    Ok(Scene {
        name: name.to_string(),
        desc,
        meshes,
        source: None,
        ignored,
    })
}

/// The scene description in `text`, or the first syntax or type error with its position.
fn deserialize(text: &str, file: &str) -> Result<SceneDesc, SceneError> {
    let de = &mut serde_json::Deserializer::from_str(text);
    serde_path_to_error::deserialize(de).map_err(|e| {
        let path = e.path().to_string();
        let inner = e.into_inner();
        SceneError::Syntax {
            file: file.to_string(),
            line: inner.line(),
            column: inner.column(),
            path,
            message: strip_position(&inner.to_string()),
        }
    })
}

/// The scene description from a JSON value made from `text` (an import's), or the first type
/// error, positioned at the field in `text` (or its nearest enclosing object).
fn deserialize_value(
    value: serde_json::Value,
    text: &str,
    file: &str,
) -> Result<SceneDesc, SceneError> {
    serde_path_to_error::deserialize(value).map_err(|e| {
        let path = e.path().to_string();
        let (line, column) = crate::locate::locate(text, &path).unwrap_or((1, 1));
        SceneError::Syntax {
            file: file.to_string(),
            line,
            column,
            path,
            message: strip_position(&e.into_inner().to_string()),
        }
    })
}

/// A glTF file's problems (at glTF paths; an empty path is the file as a whole) as the file's
/// scene error.
fn gltf_problems(path: &Path, mut problems: Vec<Problem>) -> SceneError {
    let file = path.display().to_string();
    if let [p] = problems.as_slice()
        && p.path.is_empty()
    {
        return SceneError::Io {
            file,
            message: problems.remove(0).message,
        };
    }
    let problems = problems
        .into_iter()
        .map(|problem| LocatedProblem {
            line: None,
            column: None,
            problem,
        })
        .collect();
    SceneError::Invalid { file, problems }
}

/// The problems, each positioned in `text` where its field is.
fn invalid(text: &str, file: &str, problems: Vec<Problem>) -> SceneError {
    let problems = problems
        .into_iter()
        .map(|problem| {
            let at = crate::locate::locate(text, &problem.path);
            LocatedProblem {
                line: at.map(|a| a.0),
                column: at.map(|a| a.1),
                problem,
            }
        })
        .collect();
    SceneError::Invalid {
        file: file.to_string(),
        problems,
    }
}

/// serde_json appends " at line L column C"; we print the position ourselves.
fn strip_position(msg: &str) -> String {
    match msg.rfind(" at line ") {
        Some(i) => msg[..i].to_string(),
        None => msg.to_string(),
    }
}

/// Builds an object's local-space mesh.
/// [`build_mesh`], with the atrium's large meshes from [`memo`] (built once per process).
fn shared_mesh(shape: &Shape, base: &Path) -> Result<Arc<TriMesh>, String> {
    match shape {
        Shape::Atrium { .. } | Shape::AtriumBanners { .. } => {
            memo::memoized(shape, || build_mesh(shape, base))
        }
        _ => build_mesh(shape, base).map(Arc::new),
    }
}

pub fn build_mesh(shape: &Shape, base: &Path) -> Result<TriMesh, String> {
    Ok(match *shape {
        Shape::Plane { size } => procedural::plane(size[0], size[1]),
        Shape::Box { size } => procedural::cuboid(size),
        Shape::Sphere {
            radius,
            segments,
            rings,
        } => procedural::sphere(radius, segments, rings),
        Shape::Cylinder {
            radius,
            height,
            segments,
        } => procedural::cylinder(radius, height, segments),
        Shape::Torus {
            major_radius,
            minor_radius,
            segments,
            sides,
        } => procedural::torus(major_radius, minor_radius, segments, sides),
        Shape::Spring {
            coil_radius,
            wire_radius,
            turns,
            height,
            segments_per_turn,
            sides,
        } => procedural::spring(
            coil_radius,
            wire_radius,
            turns,
            height,
            segments_per_turn,
            sides,
        ),
        Shape::Pencil {
            radius,
            length,
            tip_length,
        } => procedural::pencil(radius, length, tip_length),
        Shape::Fence {
            width,
            height,
            posts,
            rails,
            bar,
        } => procedural::fence(width, height, posts, rails, bar),
        Shape::Obj { ref path } => obj::load_obj(&obj::resolve_path(base, path))?,
        Shape::Atrium { detail } => atrium::stone(detail),
        Shape::AtriumBanners { detail } => atrium::banners(detail),
        Shape::Gltf {
            ref path,
            node,
            primitive,
        } => crate::gltf::shape_mesh(&obj::resolve_path(base, path), node, primitive)?,
    })
}
