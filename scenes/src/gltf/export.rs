//! Any scene as a binary glTF (`.glb`) that a viewer opens: each object's mesh as the GPU sees
//! it (procedural shapes tessellated, OBJ and glTF meshes as loaded) under a node with its
//! frame-0 `world_from_local` (as translation, rotation and scale); albedo as `baseColorFactor` (metallic 0, roughness 1),
//! `two_sided` as `doubleSided`; lights as `KHR_lights_punctual` with the inverse unit
//! conversion ([`super::lights::photometric`]); the camera as a perspective camera node.
//! What glTF cannot say goes in our extras ([`super::extras`]) so that importing the file
//! gives the same scene back: the medium and scene-wide fields, Phong lobes,
//! `casts_volumetric_shadow`, spot cones in exact degrees and spot patterns, and the exact
//! light and camera values that the glTF fields round. Animation is not
//! exported: the file holds frame 0 (`asset.extras.scatterbench.frames` records the count).
//! Particle media travel in the extras' medium like any other.

use std::borrow::Cow;

use glam::{Mat4, Quat, Vec3};
use serde_json::{Value, json};

use super::extras::{self, AssetExtras, CameraExtras, LightExtras, MaterialExtras, NodeExtras};
use super::lights::photometric;
use crate::desc::{LightDesc, ObjectDesc};
use crate::light::LightState;
use crate::mesh::TriMesh;
use crate::scene::Scene;

/// glTF buffer-view targets.
const ARRAY_BUFFER: u32 = 34962;
const ELEMENT_ARRAY_BUFFER: u32 = 34963;
/// glTF component types.
const FLOAT: u32 = 5126;
const UNSIGNED_INT: u32 = 5125;

/// The scene at frame 0 as `.glb` bytes.
pub fn to_glb(scene: &Scene) -> Result<Vec<u8>, String> {
    let mut out = Builder::default();
    let frame = scene.frame(0);
    let mut scene_nodes = Vec::new();
    for (i, (o, mesh)) in scene.desc.objects.iter().zip(&scene.meshes).enumerate() {
        let node = out.object(i, o, mesh, &frame.world_from_local[i]);
        scene_nodes.push(node);
    }
    for (k, (desc, state)) in scene.desc.lights.iter().zip(&frame.lights).enumerate() {
        scene_nodes.push(out.light(k, desc, state));
    }
    scene_nodes.push(out.camera(&frame.camera));
    let asset_extras = AssetExtras {
        description: scene.desc.description.clone(),
        medium: Some(scene.desc.medium.clone()),
        indirect_single_scattering: scene.desc.indirect_single_scattering,
        frames: Some(scene.frame_count()),
    };
    let root = json!({
        "asset": {
            "version": "2.0",
            "generator": "scatterbench export",
            "extras": extras::wrap(asset_extras),
        },
        "extensionsUsed": ["KHR_lights_punctual"],
        "extensions": { "KHR_lights_punctual": { "lights": out.lights } },
        "scene": 0,
        "scenes": [{ "name": scene.name, "nodes": scene_nodes }],
        "nodes": out.nodes,
        "meshes": out.meshes,
        "materials": out.materials,
        "cameras": out.cameras,
        "accessors": out.accessors,
        "bufferViews": out.views,
        "buffers": [{ "byteLength": out.bin.len() }],
    });
    let json = serde_json::to_vec(&root).map_err(|e| format!("cannot write glTF JSON: {e}"))?;
    let glb = ::gltf::binary::Glb {
        header: ::gltf::binary::Header {
            magic: *b"glTF",
            version: 2,
            length: 0, // computed by to_vec
        },
        json: Cow::Owned(json),
        bin: Some(Cow::Owned(out.bin)),
    };
    glb.to_vec().map_err(|e| format!("cannot write GLB: {e}"))
}

/// The glTF arrays being filled, and the binary chunk.
#[derive(Default)]
struct Builder {
    bin: Vec<u8>,
    views: Vec<Value>,
    accessors: Vec<Value>,
    meshes: Vec<Value>,
    materials: Vec<Value>,
    nodes: Vec<Value>,
    lights: Vec<Value>,
    cameras: Vec<Value>,
}

impl Builder {
    /// Appends bytes (4-byte aligned) as a buffer view; its index.
    fn view(&mut self, bytes: &[u8], target: u32) -> usize {
        while !self.bin.len().is_multiple_of(4) {
            self.bin.push(0);
        }
        self.views.push(json!({
            "buffer": 0, "byteOffset": self.bin.len(), "byteLength": bytes.len(), "target": target
        }));
        self.bin.extend_from_slice(bytes);
        self.views.len() - 1
    }

    fn accessor(&mut self, value: Value) -> usize {
        self.accessors.push(value);
        self.accessors.len() - 1
    }

    /// The object's mesh, material and node; the node's index.
    fn object(&mut self, i: usize, o: &ObjectDesc, mesh: &TriMesh, world: &Mat4) -> usize {
        let (lo, hi) = mesh.bounds(&Mat4::IDENTITY);
        let n = mesh.positions.len();
        let view = self.view(&vec3_bytes(&mesh.positions), ARRAY_BUFFER);
        let position = self.accessor(json!({
            "bufferView": view, "componentType": FLOAT, "count": n, "type": "VEC3",
            "min": lo.to_array(), "max": hi.to_array()
        }));
        let view = self.view(&vec3_bytes(&mesh.normals), ARRAY_BUFFER);
        let normal = self.accessor(json!({
            "bufferView": view, "componentType": FLOAT, "count": mesh.normals.len(), "type": "VEC3"
        }));
        let indices: Vec<u8> = mesh
            .indices
            .iter()
            .flatten()
            .flat_map(|i| i.to_le_bytes())
            .collect();
        let view = self.view(&indices, ELEMENT_ARRAY_BUFFER);
        let index = self.accessor(json!({
            "bufferView": view, "componentType": UNSIGNED_INT,
            "count": mesh.indices.len() * 3, "type": "SCALAR"
        }));
        let m = &o.material;
        let mut material = json!({
            "name": object_name(i, o),
            "pbrMetallicRoughness": {
                "baseColorFactor": [m.albedo.x, m.albedo.y, m.albedo.z, 1.0],
                "metallicFactor": 0.0,
                "roughnessFactor": 1.0
            },
            "doubleSided": m.two_sided
        });
        if m.phong.is_some() {
            let ours = MaterialExtras {
                phong: m.phong.clone(),
            };
            material["extras"] = extras::wrap(ours);
        }
        self.materials.push(material);
        self.meshes.push(json!({
            "name": object_name(i, o),
            "primitives": [{
                "attributes": { "POSITION": position, "NORMAL": normal },
                "indices": index,
                "material": self.materials.len() - 1,
                "mode": 4
            }]
        }));
        let mut node = json!({ "name": object_name(i, o), "mesh": self.meshes.len() - 1 });
        set_trs(&mut node, world);
        if !o.casts_volumetric_shadow {
            let ours = NodeExtras {
                casts_volumetric_shadow: Some(false),
            };
            node["extras"] = extras::wrap(ours);
        }
        self.nodes.push(node);
        self.nodes.len() - 1
    }

    /// The light (at frame 0) and its node; the node's index.
    fn light(&mut self, k: usize, desc: &LightDesc, state: &LightState) -> usize {
        let (kind, rgb, position, direction) = match *state {
            LightState::Point {
                position,
                intensity,
            } => ("point", intensity, position, Vec3::NEG_Z),
            LightState::Spot {
                position,
                direction,
                intensity,
                ..
            } => ("spot", intensity, position, direction),
            LightState::Directional {
                direction,
                irradiance,
            } => ("directional", irradiance, Vec3::ZERO, direction),
        };
        let (color, intensity) = photometric(rgb);
        let mut light = json!({
            "name": format!("light {k}"), "type": kind, "color": color, "intensity": intensity
        });
        let (given_position, given_direction) = as_given(desc);
        let mut ours = LightExtras {
            position: (kind != "directional").then_some(given_position.unwrap_or(position)),
            direction: (kind != "point").then_some(given_direction.unwrap_or(direction)),
            intensity: Some(rgb),
            ..LightExtras::default()
        };
        if let LightDesc::Spot {
            inner_deg,
            outer_deg,
            pattern,
            ..
        } = desc
        {
            light["spot"] = json!({
                "innerConeAngle": inner_deg.to_radians(),
                "outerConeAngle": outer_deg.to_radians()
            });
            (ours.inner_deg, ours.outer_deg) = (Some(*inner_deg), Some(*outer_deg));
            ours.pattern = pattern.clone();
        }
        light["extras"] = extras::wrap(ours);
        self.lights.push(light);
        // A glTF light shines down its node's −Z.
        let rotation = Quat::from_rotation_arc(Vec3::NEG_Z, direction.normalize());
        self.nodes.push(json!({
            "name": format!("light {k}"),
            "translation": position.to_array(),
            "rotation": rotation.to_array(),
            "extensions": { "KHR_lights_punctual": { "light": self.lights.len() - 1 } }
        }));
        self.nodes.len() - 1
    }

    /// The camera at frame 0 and its node (looking down −Z, +Y up); the node's index.
    fn camera(&mut self, pose: &crate::CameraPose) -> usize {
        let ours = CameraExtras {
            position: Some(pose.position),
            look_at: Some(pose.look_at),
            up: Some(pose.up),
            fov_y_deg: Some(pose.fov_y_deg),
        };
        self.cameras.push(json!({
            "extras": extras::wrap(ours),
            "name": "camera",
            "type": "perspective",
            "perspective": {
                "yfov": pose.fov_y_deg.to_radians(),
                "znear": pose.near,
                "zfar": pose.far
            }
        }));
        let mut node = json!({ "name": "camera", "camera": self.cameras.len() - 1 });
        set_trs(&mut node, &pose.view_from_world().inverse());
        self.nodes.push(node);
        self.nodes.len() - 1
    }
}

/// A static light's position and direction as the scene file wrote them (the direction not
/// normalised, so that the import's frame state normalises the same numbers); None for an
/// animated one or one attached to the camera, whose frame-0 state is exported.
fn as_given(desc: &LightDesc) -> (Option<Vec3>, Option<Vec3>) {
    match desc {
        LightDesc::Point {
            position,
            keyframes,
            ..
        } if keyframes.is_empty() => (Some(*position), None),
        // A flashlight's file values are in camera space: its frame-0 world state is exported.
        LightDesc::Spot {
            position,
            direction,
            keyframes,
            attached_to_camera: false,
            ..
        } if keyframes.is_empty() => (Some(*position), Some(*direction)),
        LightDesc::Directional {
            direction,
            keyframes,
            ..
        } if keyframes.is_empty() => (None, Some(*direction)),
        _ => (None, None),
    }
}

/// A node's `translation`, `rotation` and `scale` (each only where not the identity): glTF
/// wants TRS that recompose to the matrix, and an object's `world_from_local` is T · R · S
/// with positive scales, so it decomposes exactly up to rounding.
fn set_trs(node: &mut Value, world: &Mat4) {
    let (scale, rotation, translation) = world.to_scale_rotation_translation();
    if translation != Vec3::ZERO {
        node["translation"] = json!(translation.to_array());
    }
    if rotation != Quat::IDENTITY {
        node["rotation"] = json!(rotation.normalize().to_array());
    }
    if scale != Vec3::ONE {
        node["scale"] = json!(scale.to_array());
    }
}

fn object_name(i: usize, o: &ObjectDesc) -> String {
    if o.name.is_empty() {
        format!("object {i}")
    } else {
        o.name.clone()
    }
}

/// Little-endian f32 triples.
fn vec3_bytes(v: &[Vec3]) -> Vec<u8> {
    v.iter()
        .flat_map(|p| p.to_array())
        .flat_map(f32::to_le_bytes)
        .collect()
}
