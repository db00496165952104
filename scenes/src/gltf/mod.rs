//! glTF 2.0 levels: import into a scene (`"import": "level.glb"` in a scene file, or a
//! `.gltf`/`.glb` given as a scene by itself) and export of any scene as `.glb`.
//!
//! Imported ([`import`]): every triangle primitive of every mesh node of the default scene,
//! in world space (the node hierarchy multiplied out, [`nodes`]), as one object with a
//! [`crate::desc::Shape::Gltf`] shape naming the file, node and primitive; base-colour factors
//! as Lambert albedo ([`material`]); `KHR_lights_punctual` lights converted to radiometric
//! units ([`lights`]); the first perspective camera ([`camera`]). What is not modelled is
//! recorded ([`ignored`]). Our own `extras` ([`extras`]) restore what glTF cannot say.
//! Errors ([`GltfError`]) name the file and the glTF path.

pub mod accessor;
pub mod camera;
pub mod document;
pub mod export;
pub mod extras;
pub mod ignored;
pub mod lights;
pub mod material;
pub mod nodes;
pub mod primitive;
pub mod sample;
pub mod scene;

use std::path::Path;

use ::gltf::json;

pub use document::GltfError;
use document::{Document, SUPPORTED_EXTENSIONS};
use extras::{AssetExtras, NodeExtras};
use ignored::Ignored;

use crate::desc::{CameraDesc, LightDesc, ObjectDesc, Shape, Transform};
use crate::mesh::TriMesh;

/// One imported mesh primitive as a scene object.
pub struct ImportedObject {
    /// Its shape is [`Shape::Gltf`]; transform identity (the mesh is in world space).
    pub desc: ObjectDesc,
    pub mesh: TriMesh,
    /// Where it came from, for messages: `nodes[3] (meshes[1].primitives[0])`.
    pub origin: String,
}

/// What a glTF file contributes to a scene.
pub struct Level {
    /// The file's name in messages.
    pub file: String,
    pub objects: Vec<ImportedObject>,
    /// Each light with its origin (`extensions.KHR_lights_punctual.lights[2] at nodes[7]`).
    pub lights: Vec<(LightDesc, String)>,
    /// The first perspective camera, with its origin.
    pub camera: Option<(CameraDesc, String)>,
    /// `asset.extras.scatterbench` (default when absent).
    pub extras: AssetExtras,
    /// What was not modelled, one summary line per kind ([`ignored::summarise`]).
    pub ignored: Vec<String>,
}

/// Imports the glTF file at `path`. `shape_path` is how the objects' [`Shape::Gltf`] name
/// the file (as the scene file wrote it, relative to the scene file's folder).
pub fn import(path: &Path, shape_path: &str) -> Result<Level, GltfError> {
    let doc = document::read(path)?;
    let placed = nodes::placed_nodes(&doc, &nodes::roots(&doc))?;
    let mut level = Level {
        file: doc.file.clone(),
        objects: Vec::new(),
        lights: Vec::new(),
        camera: None,
        extras: extras::read(&doc, "asset.extras", &doc.root.asset.extras)?.unwrap_or_default(),
        ignored: Vec::new(),
    };
    let mut skipped = document_level_ignored(&doc);
    for p in &placed {
        import_node(&doc, p, shape_path, &mut level, &mut skipped)?;
    }
    level.ignored = ignored::summarise(&doc.file, &skipped);
    Ok(level)
}

/// What the file holds beyond nodes that is not modelled: animations, other scenes,
/// unsupported extensions in use.
fn document_level_ignored(doc: &Document) -> Vec<Ignored> {
    let root = &doc.root;
    let mut out: Vec<Ignored> = (0..root.animations.len())
        .map(|i| Ignored::new(format!("animations[{i}]"), ignored::ANIMATION))
        .collect();
    let used = root.scene.map_or(0, |s| s.value());
    out.extend(
        (0..root.scenes.len())
            .filter(|&i| i != used)
            .map(|i| Ignored::new(format!("scenes[{i}]"), ignored::OTHER_SCENES)),
    );
    out.extend(
        root.extensions_used
            .iter()
            .enumerate()
            .filter(|(_, e)| !SUPPORTED_EXTENSIONS.contains(&e.as_str()))
            .map(|(i, e)| Ignored::new(format!("extensionsUsed[{i}] ({e})"), ignored::EXTENSION)),
    );
    out
}

/// Adds a placed node's primitives, light and camera to `level`.
fn import_node(
    doc: &Document,
    placed: &nodes::Placed,
    shape_path: &str,
    level: &mut Level,
    skipped: &mut Vec<Ignored>,
) -> Result<(), GltfError> {
    let index = placed.node;
    let node: &json::Node = &doc.root.nodes[index];
    let path = format!("nodes[{index}]");
    let world = &placed.world_from_local;
    if node.skin.is_some() {
        skipped.push(Ignored::new(format!("{path}.skin"), ignored::SKIN));
    }
    if node.weights.is_some() {
        skipped.push(Ignored::new(format!("{path}.weights"), ignored::MORPH));
    }
    if let Some(mesh) = node.mesh {
        let ours: NodeExtras =
            extras::read(doc, &format!("{path}.extras"), &node.extras)?.unwrap_or_default();
        add_mesh(doc, placed, mesh.value(), &ours, shape_path, level, skipped)?;
    }
    if let Some(c) = node.camera {
        let at = format!("cameras[{}] at {path}", c.value());
        match (&level.camera, camera::import(doc, c.value(), world)?) {
            (None, Some(cam)) => level.camera = Some((cam, at)),
            _ => skipped.push(Ignored::new(at, ignored::CAMERA)),
        }
        let aspect = doc.root.cameras[c.value()]
            .perspective
            .as_ref()
            .and_then(|p| p.aspect_ratio);
        if aspect.is_some() {
            skipped.push(Ignored::new(
                format!("cameras[{}].perspective.aspectRatio", c.value()),
                ignored::ASPECT,
            ));
        }
    }
    let light = node
        .extensions
        .as_ref()
        .and_then(|e| e.khr_lights_punctual.as_ref());
    if let Some(l) = light {
        let imported = lights::import(doc, l.light.value(), world)?;
        let at = format!(
            "extensions.KHR_lights_punctual.lights[{}] at {path}",
            l.light.value()
        );
        skipped.extend(imported.ignored);
        level.lights.push((imported.light, at));
    }
    Ok(())
}

/// One object per triangle primitive of `meshes[mesh]` at a placed node.
fn add_mesh(
    doc: &Document,
    placed: &nodes::Placed,
    mesh: usize,
    ours: &NodeExtras,
    shape_path: &str,
    level: &mut Level,
    skipped: &mut Vec<Ignored>,
) -> Result<(), GltfError> {
    let node = &doc.root.nodes[placed.node];
    let count = doc
        .item(&doc.root.meshes, "meshes", mesh)
        .map_err(|e| doc.error(format!("nodes[{}].mesh", placed.node), e.located_message()))?
        .primitives
        .len();
    for k in 0..count {
        let prim_path = format!("meshes[{mesh}].primitives[{k}]");
        let p = primitive::get(doc, mesh, k)?;
        skipped.extend(primitive::ignored_parts(p, &prim_path));
        if p.mode == json::validation::Checked::Invalid {
            return Err(doc.error(
                format!("{prim_path}.mode"),
                "unknown mode: allowed are 0 to 6 (POINTS … TRIANGLE_FAN)",
            ));
        }
        if !primitive::is_triangles(p) {
            skipped.push(Ignored::new(
                format!("{prim_path}.mode"),
                ignored::NOT_TRIANGLES,
            ));
            continue;
        }
        let (material, unmodelled) = material::import(doc, p.material.map(|m| m.value()))?;
        skipped.extend(unmodelled);
        let m = primitive::world_mesh(doc, mesh, k, &placed.world_from_local)?;
        let base = node
            .name
            .clone()
            .or_else(|| doc.root.meshes[mesh].name.clone())
            .unwrap_or_else(|| format!("node {}", placed.node));
        let name = if count > 1 {
            format!("{base} #{k}")
        } else {
            base
        };
        level.objects.push(ImportedObject {
            desc: ObjectDesc {
                name,
                shape: Shape::Gltf {
                    path: shape_path.to_string(),
                    node: placed.node as u32,
                    primitive: k as u32,
                },
                transform: Transform::default(),
                material,
                casts_volumetric_shadow: ours.casts_volumetric_shadow.unwrap_or(true),
                keyframes: vec![],
            },
            mesh: m,
            origin: format!("nodes[{}] ({prim_path})", placed.node),
        });
    }
    Ok(())
}

/// The world-space mesh of a [`Shape::Gltf`]: primitive `primitive` of node `node`'s mesh in
/// the file at `path` (for scene files that name a glTF primitive directly).
pub fn shape_mesh(path: &Path, node: u32, primitive: u32) -> Result<TriMesh, String> {
    let doc = document::read(path).map_err(|e| e.to_string())?;
    let at = format!("nodes[{node}]");
    let mesh = doc
        .item(&doc.root.nodes, "nodes", node as usize)
        .and_then(|n| {
            n.mesh
                .ok_or_else(|| doc.error(format!("{at}.mesh"), "the node has no mesh"))
        })
        .map_err(|e| e.to_string())?;
    let world = nodes::world_matrix(&doc, node as usize).map_err(|e| e.to_string())?;
    primitive::world_mesh(&doc, mesh.value(), primitive as usize, &world).map_err(|e| e.to_string())
}
