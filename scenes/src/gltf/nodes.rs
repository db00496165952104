//! The node hierarchy multiplied out: each node of the imported scene with its world matrix
//! (`world_from_local = parent's world · node's local`), in depth-first order from the
//! scene's roots. A node reached twice (a cycle, or two parents) is refused.

use ::gltf::json;
use glam::{Mat4, Quat, Vec3};

use super::document::{Document, GltfError};

/// A node of the imported scene and where it is.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Placed {
    /// Index into `nodes`.
    pub node: usize,
    pub world_from_local: Mat4,
}

/// The node's own transform: its `matrix` (column-major), or T · R · S from its
/// `translation`, `rotation` (unit quaternion x, y, z, w) and `scale`. Every number finite.
pub fn local_matrix(doc: &Document, index: usize) -> Result<Mat4, GltfError> {
    let path = format!("nodes[{index}]");
    let n = doc.item(&doc.root.nodes, "nodes", index)?;
    let finite = |field: &str, v: &[f32]| {
        if v.iter().all(|x| x.is_finite()) {
            Ok(())
        } else {
            Err(doc.error(
                format!("{path}.{field}"),
                format!("must be finite, got {v:?}"),
            ))
        }
    };
    if let Some(m) = &n.matrix {
        finite("matrix", m)?;
        return Ok(Mat4::from_cols_array(m));
    }
    let t = n.translation.unwrap_or([0.0; 3]);
    let s = n.scale.unwrap_or([1.0; 3]);
    let r = n.rotation.as_ref().map_or([0.0, 0.0, 0.0, 1.0], |q| q.0);
    finite("translation", &t)?;
    finite("scale", &s)?;
    finite("rotation", &r)?;
    let q = Quat::from_array(r);
    let len = q.length();
    if (len - 1.0).abs() > 1e-3 {
        return Err(doc.error(
            format!("{path}.rotation"),
            format!("must be a unit quaternion, got length {len}"),
        ));
    }
    Ok(Mat4::from_scale_rotation_translation(
        Vec3::from_array(s),
        q.normalize(),
        Vec3::from_array(t),
    ))
}

/// The root nodes imported: those of `scene` (else `scenes[0]`), else every node no other
/// node lists as a child.
pub fn roots(doc: &Document) -> Vec<usize> {
    let root = &doc.root;
    let scene = root
        .scene
        .and_then(|s| root.scenes.get(s.value()))
        .or_else(|| root.scenes.first());
    if let Some(s) = scene {
        return s.nodes.iter().map(|n| n.value()).collect();
    }
    let mut is_child = vec![false; root.nodes.len()];
    for n in &root.nodes {
        for c in n.children.iter().flatten() {
            if let Some(slot) = is_child.get_mut(c.value()) {
                *slot = true;
            }
        }
    }
    (0..root.nodes.len()).filter(|&i| !is_child[i]).collect()
}

/// Every node under `roots` with its world matrix, depth-first, parents before children.
pub fn placed_nodes(doc: &Document, roots: &[usize]) -> Result<Vec<Placed>, GltfError> {
    let mut seen = vec![false; doc.root.nodes.len()];
    let mut out = Vec::new();
    // (node, parent's world matrix, how it was reached, for messages)
    let mut stack: Vec<(usize, Mat4, String)> = roots
        .iter()
        .rev()
        .map(|&r| (r, Mat4::IDENTITY, "the scene's nodes".to_string()))
        .collect();
    while let Some((node, parent, via)) = stack.pop() {
        let path = format!("nodes[{node}]");
        let seen_before = seen
            .get_mut(node)
            .ok_or_else(|| doc.error(&path, format!("no such node (listed by {via})")))?;
        if *seen_before {
            return Err(doc.error(
                &path,
                format!("is reached twice (listed by {via}): the hierarchy must be a tree"),
            ));
        }
        *seen_before = true;
        let world_from_local = parent * local_matrix(doc, node)?;
        out.push(Placed {
            node,
            world_from_local,
        });
        let children: &[json::Index<json::Node>] =
            doc.root.nodes[node].children.as_deref().unwrap_or(&[]);
        for (k, c) in children.iter().enumerate().rev() {
            stack.push((c.value(), world_from_local, format!("{path}.children[{k}]")));
        }
    }
    Ok(out)
}

/// The world matrix of one node of the imported scene (the hierarchy is walked from the
/// scene's roots, so a node outside it, or a broken hierarchy, is an error).
pub fn world_matrix(doc: &Document, node: usize) -> Result<Mat4, GltfError> {
    let roots = roots(doc);
    placed_nodes(doc, &roots)?
        .into_iter()
        .find(|p| p.node == node)
        .map(|p| p.world_from_local)
        .ok_or_else(|| {
            doc.error(
                format!("nodes[{node}]"),
                "is not in the imported scene (not reachable from its root nodes)",
            )
        })
}
