//! One glTF mesh primitive as a [`TriMesh`] in world space: its node's world matrix applied
//! to the positions and (inverse-transpose) to the normals, triangle strips and fans unrolled,
//! the winding flipped under a mirroring matrix so that counter-clockwise still faces out.

use ::gltf::json::mesh::{Mode, Primitive, Semantic};
use ::gltf::json::validation::Checked;
use glam::{Mat3, Mat4, Vec3};

use super::accessor::{read_indices, read_vec3};
use super::document::{Document, GltfError};
use super::ignored::{self, Ignored};
use crate::mesh::TriMesh;
use crate::mesh::obj::fill_normals;

/// The primitive `meshes[mesh].primitives[primitive]`, if it exists.
pub fn get(doc: &Document, mesh: usize, primitive: usize) -> Result<&Primitive, GltfError> {
    doc.root
        .meshes
        .get(mesh)
        .and_then(|m| m.primitives.get(primitive))
        .ok_or_else(|| {
            doc.error(
                format!("meshes[{mesh}].primitives[{primitive}]"),
                "no such mesh primitive",
            )
        })
}

/// Whether the primitive is made of triangles (TRIANGLES, TRIANGLE_STRIP, TRIANGLE_FAN).
pub fn is_triangles(p: &Primitive) -> bool {
    matches!(
        p.mode,
        Checked::Valid(Mode::Triangles | Mode::TriangleStrip | Mode::TriangleFan)
    )
}

/// The attributes and morph targets the import leaves out, as ignored content.
pub fn ignored_parts(p: &Primitive, path: &str) -> Vec<Ignored> {
    let mut out: Vec<Ignored> = p
        .attributes
        .keys()
        .filter_map(|k| match k {
            Checked::Valid(Semantic::Positions | Semantic::Normals) => None,
            k => Some(Ignored::new(
                format!("{path}.attributes.{}", semantic_name(k)),
                ignored::VERTEX_ATTRIBUTE,
            )),
        })
        .collect();
    if p.targets.as_ref().is_some_and(|t| !t.is_empty()) {
        out.push(Ignored::new(format!("{path}.targets"), ignored::MORPH));
    }
    out
}

fn semantic_name(s: &Checked<Semantic>) -> String {
    match s {
        Checked::Valid(Semantic::Positions) => "POSITION".into(),
        Checked::Valid(Semantic::Normals) => "NORMAL".into(),
        Checked::Valid(Semantic::Tangents) => "TANGENT".into(),
        Checked::Valid(Semantic::Colors(n)) => format!("COLOR_{n}"),
        Checked::Valid(Semantic::TexCoords(n)) => format!("TEXCOORD_{n}"),
        Checked::Valid(Semantic::Joints(n)) => format!("JOINTS_{n}"),
        Checked::Valid(Semantic::Weights(n)) => format!("WEIGHTS_{n}"),
        Checked::Valid(Semantic::Extras(n)) => format!("_{n}"),
        Checked::Invalid => "(invalid)".into(),
    }
}

/// The triangles of `meshes[mesh].primitives[primitive]` placed by `world_from_local`.
pub fn world_mesh(
    doc: &Document,
    mesh: usize,
    primitive: usize,
    world_from_local: &Mat4,
) -> Result<TriMesh, GltfError> {
    let path = format!("meshes[{mesh}].primitives[{primitive}]");
    let p = get(doc, mesh, primitive)?;
    let attribute = |s: Semantic| p.attributes.get(&Checked::Valid(s)).map(|a| a.value());
    let position = attribute(Semantic::Positions).ok_or_else(|| {
        doc.error(
            format!("{path}.attributes"),
            "POSITION is missing (it is required)",
        )
    })?;
    let local = read_vec3(doc, position)?;
    let n = local.len();
    let order: Vec<u32> = match p.indices {
        Some(i) => read_indices(doc, i.value(), n)?,
        None => (0..n as u32).collect(),
    };
    let corners = triangles(doc, &path, p, &order)?;
    let det = world_from_local.determinant();
    if !(det.is_finite() && det != 0.0) {
        return Err(doc.error(
            &path,
            format!(
                "its node's world matrix is singular (determinant {det}): the mesh would be flat"
            ),
        ));
    }
    let positions: Vec<Vec3> = local
        .iter()
        .map(|&q| world_from_local.transform_point3(q))
        .collect();
    if !positions.iter().all(|q| q.is_finite()) {
        return Err(doc.error(
            &path,
            "a vertex is not finite once placed by its node's transform",
        ));
    }
    // A mirroring matrix turns counter-clockwise into clockwise: swap two corners back.
    let indices: Vec<[u32; 3]> = corners
        .into_iter()
        .map(|[a, b, c]| if det < 0.0 { [a, c, b] } else { [a, b, c] })
        .filter(|t| {
            let [a, b, c] = t.map(|i| positions[i as usize]);
            a != b && b != c && c != a
        })
        .collect();
    if !indices.iter().any(|t| {
        let [a, b, c] = t.map(|i| positions[i as usize]);
        (b - a).cross(c - a) != Vec3::ZERO
    }) {
        return Err(doc.error(
            &path,
            "every triangle is degenerate (no triangle has an area)",
        ));
    }
    let given = match attribute(Semantic::Normals) {
        Some(a) => world_normals(doc, a, n, world_from_local)?,
        None => vec![None; n],
    };
    let normals = fill_normals(&positions, &given, &indices);
    Ok(TriMesh {
        positions,
        normals,
        indices,
    })
}

/// The NORMAL accessor's normals in world space; None where one is zero.
fn world_normals(
    doc: &Document,
    accessor: usize,
    vertices: usize,
    world_from_local: &Mat4,
) -> Result<Vec<Option<Vec3>>, GltfError> {
    let local = read_vec3(doc, accessor)?;
    if local.len() != vertices {
        return Err(doc.error(
            format!("accessors[{accessor}]"),
            format!("NORMAL has {} elements, POSITION {vertices}", local.len()),
        ));
    }
    let normal_from_local = Mat3::from_mat4(*world_from_local).inverse().transpose();
    Ok(local
        .iter()
        .map(|&v| (normal_from_local * v).try_normalize())
        .collect())
}

/// The vertex order as triangles, by the primitive's mode (strips alternate their winding so
/// every triangle keeps the first one's orientation).
fn triangles(
    doc: &Document,
    path: &str,
    p: &Primitive,
    order: &[u32],
) -> Result<Vec<[u32; 3]>, GltfError> {
    let n = order.len();
    Ok(match p.mode {
        Checked::Valid(Mode::Triangles) => {
            if !n.is_multiple_of(3) {
                return Err(doc.error(
                    path,
                    format!("TRIANGLES needs a multiple of 3 vertices, got {n}"),
                ));
            }
            order.chunks_exact(3).map(|t| [t[0], t[1], t[2]]).collect()
        }
        Checked::Valid(Mode::TriangleStrip) => (2..n)
            .map(|i| {
                let (a, b, c) = (order[i - 2], order[i - 1], order[i]);
                if i % 2 == 0 { [a, b, c] } else { [b, a, c] }
            })
            .collect(),
        Checked::Valid(Mode::TriangleFan) => {
            (2..n).map(|i| [order[0], order[i - 1], order[i]]).collect()
        }
        _ => {
            return Err(doc.error(
                format!("{path}.mode"),
                "must be TRIANGLES (4), TRIANGLE_STRIP (5) or TRIANGLE_FAN (6)",
            ));
        }
    })
}
