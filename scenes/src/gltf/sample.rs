//! A small glTF level built in code, for tests and examples: a floor, a parent node turning
//! and moving two box pillars (its children), a box placed by a `matrix`, a point, a spot and
//! a directional light (`KHR_lights_punctual`) and a perspective camera. The buffer is
//! embedded as a base64 `data:` URI, so the JSON is a complete `.gltf` file on its own;
//! [`to_glb`] repacks it as a `.glb`.

use std::borrow::Cow;

use base64::Engine;
use glam::{Mat4, Quat, Vec3};
use serde_json::{Value, json};

use super::lights::LUMENS_PER_WATT;

/// Radiant intensities and irradiance of the sample's lights (W/sr, W/m²): what an import
/// must give back after the candela/lux conversion.
pub const POINT_W_PER_SR: f32 = 30.0;
pub const SPOT_W_PER_SR: f32 = 150.0;
pub const SUN_W_PER_M2: f32 = 0.4;

/// The parent node's transform (node 1): its pillars' world matrices are this times theirs.
pub fn parent_matrix() -> Mat4 {
    Mat4::from_scale_rotation_translation(
        Vec3::ONE,
        Quat::from_rotation_y(30f32.to_radians()),
        Vec3::new(0.0, 0.0, -2.0),
    )
}

/// The sample level as glTF JSON with its buffer embedded.
pub fn level() -> Value {
    let mut bin = Vec::new();
    let mut views = Vec::new();
    let mut accessors = Vec::new();
    let mut push = |bytes: Vec<u8>, accessor: Value| {
        views.push(json!({"buffer": 0, "byteOffset": bin.len(), "byteLength": bytes.len()}));
        bin.extend(bytes);
        let mut a = accessor;
        a["bufferView"] = json!(views.len() - 1);
        accessors.push(a);
        accessors.len() - 1
    };
    let (qp, qn, qi) = quad();
    let (cp, cn, ci) = cube();
    let mut mesh = |p: &[Vec3], n: &[Vec3], i: &[u16], material: usize| {
        let (lo, hi) = p
            .iter()
            .fold((Vec3::MAX, Vec3::MIN), |(l, h), v| (l.min(*v), h.max(*v)));
        let pa = push(
            floats(p),
            json!({"componentType": 5126, "count": p.len(), "type": "VEC3", "min": lo.to_array(), "max": hi.to_array()}),
        );
        let na = push(
            floats(n),
            json!({"componentType": 5126, "count": n.len(), "type": "VEC3"}),
        );
        let ia = push(
            shorts(i),
            json!({"componentType": 5123, "count": i.len(), "type": "SCALAR"}),
        );
        json!({"primitives": [{"attributes": {"POSITION": pa, "NORMAL": na}, "indices": ia, "material": material}]})
    };
    let meshes = vec![mesh(&qp, &qn, &qi, 0), mesh(&cp, &cn, &ci, 1)];
    let cd = |w: f32| w * LUMENS_PER_WATT;
    let boxed = Mat4::from_scale_rotation_translation(
        Vec3::new(0.6, 1.2, 0.6),
        Quat::from_rotation_x(0.3),
        Vec3::new(3.0, 0.8, 1.0),
    );
    json!({
        "asset": {"version": "2.0", "generator": "scatterbench sample level"},
        "extensionsUsed": ["KHR_lights_punctual"],
        "extensions": {"KHR_lights_punctual": {"lights": [
            {"type": "point", "color": [1.0, 0.9, 0.8], "intensity": cd(POINT_W_PER_SR)},
            {"type": "spot", "color": [1.0, 1.0, 1.0], "intensity": cd(SPOT_W_PER_SR),
             "spot": {"innerConeAngle": 0.3, "outerConeAngle": 0.5}},
            {"type": "directional", "color": [1.0, 1.0, 1.0], "intensity": cd(SUN_W_PER_M2)}
        ]}},
        "scene": 0,
        "scenes": [{"nodes": [0, 1, 4, 5, 6, 7, 8]}],
        "nodes": [
            {"name": "floor", "mesh": 0},
            {"name": "pillars", "translation": [0.0, 0.0, -2.0],
             "rotation": Quat::from_rotation_y(30f32.to_radians()).to_array(), "children": [2, 3]},
            {"name": "left pillar", "mesh": 1, "translation": [-1.5, 1.0, 0.0], "scale": [0.5, 2.0, 0.5]},
            {"name": "right pillar", "mesh": 1, "translation": [1.5, 1.2, 0.0], "scale": [0.4, 2.4, 0.4]},
            {"name": "tilted box", "mesh": 1, "matrix": boxed.to_cols_array()},
            {"name": "lamp", "translation": [2.0, 3.5, 1.5],
             "extensions": {"KHR_lights_punctual": {"light": 0}}},
            {"name": "spot", "translation": [-1.0, 5.0, -1.0],
             "rotation": Quat::from_rotation_arc(Vec3::NEG_Z, Vec3::new(0.2, -1.0, -0.3).normalize()).to_array(),
             "extensions": {"KHR_lights_punctual": {"light": 1}}},
            {"name": "sun", "rotation": Quat::from_rotation_arc(Vec3::NEG_Z, Vec3::new(0.6, -0.7, 0.3).normalize()).to_array(),
             "extensions": {"KHR_lights_punctual": {"light": 2}}},
            {"name": "camera", "camera": 0,
             "matrix": camera_matrix().to_cols_array()}
        ],
        "cameras": [{"type": "perspective", "perspective": {"yfov": 0.8, "znear": 0.1, "zfar": 60.0}}],
        "meshes": meshes,
        "materials": [
            {"pbrMetallicRoughness": {"baseColorFactor": [0.7, 0.7, 0.7, 1.0], "metallicFactor": 0.0}},
            {"pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.4, 0.3, 1.0], "metallicFactor": 0.0}, "doubleSided": true}
        ],
        "accessors": accessors,
        "bufferViews": views,
        "buffers": [{"byteLength": bin.len(), "uri": format!(
            "data:application/octet-stream;base64,{}",
            base64::engine::general_purpose::STANDARD.encode(&bin)
        )}]
    })
}

/// A `.gltf` JSON value with one embedded buffer as `.glb` bytes (the buffer becomes the
/// binary chunk). None when the value has no decodable `data:` buffer.
pub fn to_glb(gltf: &Value) -> Option<Vec<u8>> {
    let mut root = gltf.clone();
    let uri = root["buffers"][0]["uri"].as_str()?.to_string();
    let bin = base64::engine::general_purpose::STANDARD
        .decode(uri.split_once(";base64,")?.1)
        .ok()?;
    root["buffers"][0].as_object_mut()?.remove("uri");
    let glb = ::gltf::binary::Glb {
        header: ::gltf::binary::Header {
            magic: *b"glTF",
            version: 2,
            length: 0,
        },
        json: Cow::Owned(serde_json::to_vec(&root).ok()?),
        bin: Some(Cow::Owned(bin)),
    };
    glb.to_vec().ok()
}

/// The camera node's matrix: at (0, 3, 9) looking at (0, 1, −1), +Y up (columns: right, up,
/// backward, position — a glTF camera looks down its −Z).
fn camera_matrix() -> Mat4 {
    let eye = Vec3::new(0.0, 3.0, 9.0);
    let forward = (Vec3::new(0.0, 1.0, -1.0) - eye).normalize();
    let right = forward.cross(Vec3::Y).normalize();
    let up = right.cross(forward);
    Mat4::from_cols(
        right.extend(0.0),
        up.extend(0.0),
        (-forward).extend(0.0),
        eye.extend(1.0),
    )
}

fn floats(v: &[Vec3]) -> Vec<u8> {
    v.iter()
        .flat_map(|p| p.to_array())
        .flat_map(f32::to_le_bytes)
        .collect()
}

/// u16 indices, padded to 4 bytes so the next view stays aligned.
fn shorts(v: &[u16]) -> Vec<u8> {
    let mut b: Vec<u8> = v.iter().flat_map(|i| i.to_le_bytes()).collect();
    b.resize(b.len().next_multiple_of(4), 0);
    b
}

/// A 16 m square floor in the XZ plane facing +Y.
fn quad() -> (Vec<Vec3>, Vec<Vec3>, Vec<u16>) {
    let s = 8.0;
    let p = vec![
        Vec3::new(-s, 0.0, -s),
        Vec3::new(-s, 0.0, s),
        Vec3::new(s, 0.0, s),
        Vec3::new(s, 0.0, -s),
    ];
    (p, vec![Vec3::Y; 4], vec![0, 1, 2, 0, 2, 3])
}

/// A unit cube centred on the origin, counter-clockwise from outside, flat normals.
fn cube() -> (Vec<Vec3>, Vec<Vec3>, Vec<u16>) {
    let (mut p, mut n, mut idx) = (Vec::new(), Vec::new(), Vec::new());
    for axis in [
        Vec3::X,
        Vec3::Y,
        Vec3::Z,
        Vec3::NEG_X,
        Vec3::NEG_Y,
        Vec3::NEG_Z,
    ] {
        let u = axis.any_orthonormal_vector();
        let v = axis.cross(u);
        let base = p.len() as u16;
        for (a, b) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
            p.push((axis + u * a + v * b) * 0.5);
            n.push(axis);
        }
        idx.extend([base, base + 1, base + 2, base, base + 2, base + 3]);
    }
    (p, n, idx)
}
