//! A small process-wide memo of large procedural meshes: loading the same atrium scene again
//! (tests that mutate a file thousands of times, variants, every frame-state consumer) would
//! rebuild the same 0.3 M triangles each time. The last few meshes are kept, by shape.

use std::sync::{Arc, Mutex};

use super::TriMesh;
use crate::desc::Shape;

/// Meshes kept: enough for one scene's parts, small enough to bound memory (detail 4 is
/// ~5 M triangles, ~0.3 GB).
const KEPT: usize = 4;

static MEMO: Mutex<Vec<(String, Arc<TriMesh>)>> = Mutex::new(Vec::new());

/// The mesh of `shape`, from the memo or from `build` (whose result is then remembered).
pub fn memoized(
    shape: &Shape,
    build: impl FnOnce() -> Result<TriMesh, String>,
) -> Result<Arc<TriMesh>, String> {
    // Debug prints every f32 exactly (shortest round-trip), so equal keys mean equal shapes.
    let key = format!("{shape:?}");
    let hit = |memo: &Vec<(String, Arc<TriMesh>)>| {
        memo.iter().find(|(k, _)| *k == key).map(|(_, m)| m.clone())
    };
    if let Some(m) = hit(&MEMO.lock().unwrap_or_else(|e| e.into_inner())) {
        return Ok(m);
    }
    let mesh = Arc::new(build()?);
    let mut memo = MEMO.lock().unwrap_or_else(|e| e.into_inner());
    if memo.len() == KEPT {
        memo.remove(0);
    }
    memo.push((key, mesh.clone()));
    Ok(mesh)
}
