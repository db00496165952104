//! The stress cases' broken-but-loadable meshes, as OBJ text. They are written to disk so they
//! go through the same OBJ loader as a user's asset.

use std::path::Path;

/// A unit box with its bottom and front (+Z) faces missing: an open surface whose inside is
/// visible and lit.
pub const OPEN_BOX: &str = "\
o open-box
v -0.5 -0.5 -0.5
v  0.5 -0.5 -0.5
v  0.5  0.5 -0.5
v -0.5  0.5 -0.5
v -0.5 -0.5  0.5
v  0.5 -0.5  0.5
v  0.5  0.5  0.5
v -0.5  0.5  0.5
f 1 4 3 2
f 4 8 7 3
f 1 5 8 4
f 2 3 7 6
";

/// Non-manifold: three quads share the edge x = 0, z = 0 (a 'book' of fins), and one of them
/// is doubled with the opposite winding (two coincident faces facing away from each other).
pub const NON_MANIFOLD: &str = "\
o fins
v 0 -0.5 0
v 0  0.5 0
v 1  0.5 0
v 1 -0.5 0
v -0.5  0.5 0.866
v -0.5 -0.5 0.866
v -0.5  0.5 -0.866
v -0.5 -0.5 -0.866
f 1 4 3 2
f 1 2 5 6
f 1 2 7 8
f 1 8 7 2
";

/// Degenerate: zero-area triangles with three distinct collinear corners (which the loader
/// keeps), needle slivers 1e-7 wide, and one ordinary triangle.
pub const DEGENERATE: &str = "\
o degenerate
v -1 0 0
v  0 0 0
v  1 0 0
v -1 0 1e-7
v  1 1 0
v -1 1 0
v  0 0.5 0
v  0 0.5 1e-7
f 1 2 3
f 3 2 1
f 1 3 4
f 1 5 6
f 2 7 8
f 7 2 8
";

/// Writes `text` to `dir/file` (creating `dir`).
pub fn write(dir: &Path, file: &str, text: &str) -> Result<(), String> {
    std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    let path = dir.join(file);
    std::fs::write(&path, text).map_err(|e| format!("{}: {e}", path.display()))
}
