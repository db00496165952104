//! Wavefront OBJ loading into a single [`TriMesh`].
//!
//! Parsing is delegated to `tobj`; this module turns its per-object output into one mesh,
//! validates what `tobj` does not (finite coordinates, index ranges, usable normals) and fills in
//! smooth normals when the file has none. Every failure is an `Err` naming the file, never a
//! panic: scene files are user input and a broken asset must not take down a benchmark sweep.
//!
//! Materials are ignored: the scene description assigns media and surface properties itself, so
//! `mtllib` references are not even opened.

use std::collections::HashMap;
use std::fs::File;
use std::io::{BufRead, BufReader, ErrorKind};
use std::panic::{self, AssertUnwindSafe};
use std::path::{Path, PathBuf};

use glam::Vec3;

use super::TriMesh;

/// Loads an OBJ file, triangulating polygons and merging all objects/groups into one mesh.
///
/// Vertex normals from the file are used when every vertex has one; otherwise smooth
/// area-weighted normals are computed. Errors name the file and the problem (not found,
/// parse error, index out of range, non-finite coordinate, no triangles).
pub fn load_obj(path: &Path) -> Result<TriMesh, String> {
    let name = path.display().to_string();
    let file = File::open(path).map_err(|e| match e.kind() {
        ErrorKind::NotFound => format!("{name}: OBJ file not found"),
        _ => format!("{name}: cannot open OBJ file: {e}"),
    })?;
    parse(&mut BufReader::new(file), &name)
}

/// [`load_obj`] on in-memory text; `name` stands in for the file name in error messages.
pub fn load_obj_str(text: &str, name: &str) -> Result<TriMesh, String> {
    parse(&mut text.as_bytes(), name)
}

fn parse(reader: &mut impl BufRead, name: &str) -> Result<TriMesh, String> {
    // Every field is set today, but tobj's optional features add fields; keep the update.
    #[allow(clippy::needless_update)]
    let options = tobj::LoadOptions {
        triangulate: true,
        single_index: true,
        // With `triangulate`, tobj turns points and lines into degenerate triangles; they are
        // not surfaces, so drop them at the source.
        ignore_points: true,
        ignore_lines: true,
        ..Default::default()
    };
    // tobj does unchecked index arithmetic on hostile input (e.g. huge negative relative
    // indices overflow in debug builds), so contain any panic and report it as a parse error.
    let parsed = panic::catch_unwind(AssertUnwindSafe(|| {
        tobj::load_obj_buf(reader, &options, |_| Ok(Default::default()))
    }))
    .map_err(|_| format!("{name}: OBJ parse error: parser failed on malformed input"))?;
    let (models, _materials) = parsed.map_err(|e| describe(name, &e))?;

    let mut positions = Vec::new();
    let mut normals: Vec<Option<Vec3>> = Vec::new();
    let mut indices = Vec::new();
    for model in &models {
        let mesh = &model.mesh;
        let base = positions.len();
        let count = mesh.positions.len() / 3;
        for (i, p) in mesh.positions.chunks_exact(3).enumerate() {
            let p = Vec3::new(to_f32(p[0]), to_f32(p[1]), to_f32(p[2]));
            if !p.is_finite() {
                return Err(format!(
                    "{name}: non-finite vertex coordinate {p} (vertex {i} of object '{}')",
                    model.name
                ));
            }
            positions.push(p);
        }
        // With single_index tobj only emits a normal for face vertices that reference one, so a
        // partial set is misaligned with the positions and unusable as a whole.
        if mesh.normals.len() == mesh.positions.len() {
            normals.extend(
                mesh.normals
                    .chunks_exact(3)
                    .map(|n| Vec3::new(to_f32(n[0]), to_f32(n[1]), to_f32(n[2])).try_normalize()),
            );
        } else {
            normals.resize(positions.len(), None);
        }
        for t in mesh.indices.chunks_exact(3) {
            let mut tri = [0u32; 3];
            for (slot, &i) in tri.iter_mut().zip(t) {
                if i as usize >= count {
                    return Err(format!(
                        "{name}: vertex index {i} out of range (object '{}' has {count} vertices)",
                        model.name
                    ));
                }
                *slot = u32::try_from(base + i as usize)
                    .map_err(|_| format!("{name}: too many vertices for 32-bit indices"))?;
            }
            // A triangle with two coincident corners has no area and no orientation; its two
            // real edges cancel each other, so dropping it keeps the rest of the surface
            // closed. (Collinear but distinct corners are kept: they may be needed to pair up
            // the edges of a T-junction fix.)
            let [a, b, c] = tri.map(|i| positions[i as usize]);
            if a != b && b != c && c != a {
                indices.push(tri);
            }
        }
    }
    if indices.is_empty() {
        return Err(format!("{name}: OBJ contains no triangles"));
    }

    let normals = fill_normals(&positions, &normals, &indices);
    Ok(TriMesh {
        positions,
        normals,
        indices,
    })
}

/// Widens through f64 so the conversion compiles whether tobj stores f32 or (with its
/// `use_f64` feature enabled by some other crate) f64; f32 → f64 → f32 is exact.
fn to_f32(x: impl Into<f64>) -> f32 {
    x.into() as f32
}

fn describe(name: &str, error: &tobj::LoadError) -> String {
    use tobj::LoadError as E;
    match error {
        E::FaceVertexOutOfBounds
        | E::FaceTexCoordOutOfBounds
        | E::FaceNormalOutOfBounds
        | E::FaceColorOutOfBounds => format!("{name}: OBJ index out of range: {error}"),
        E::OpenFileFailed | E::ReadError => format!("{name}: cannot read OBJ: {error}"),
        _ => format!("{name}: OBJ parse error: {error}"),
    }
}

/// Keeps the file's normals where present and usable, and computes smooth area-weighted normals
/// for the rest. Accumulation is keyed by exact position rather than vertex index: tobj splits
/// a vertex wherever its texture coordinates differ, and smoothing per index would turn every
/// UV seam into a visible shading crease.
pub(crate) fn fill_normals(
    positions: &[Vec3],
    given: &[Option<Vec3>],
    indices: &[[u32; 3]],
) -> Vec<Vec3> {
    if given.iter().all(Option::is_some) {
        return given.iter().flatten().copied().collect();
    }
    let key = |p: Vec3| p.to_array().map(f32::to_bits);
    let mut sums: HashMap<[u32; 3], Vec3> = HashMap::new();
    for t in indices {
        let [a, b, c] = t.map(|i| positions[i as usize]);
        // The unnormalised cross product is twice the area times the normal: area weighting
        // for free.
        let weighted = (b - a).cross(c - a);
        for p in [a, b, c] {
            *sums.entry(key(p)).or_insert(Vec3::ZERO) += weighted;
        }
    }
    positions
        .iter()
        .zip(given)
        .map(|(&p, n)| {
            n.or_else(|| sums.get(&key(p)).and_then(|s| s.try_normalize()))
                // Only reachable for vertices whose faces cancel out (e.g. a sheet folded back
                // onto itself); any unit vector is as good as another there.
                .unwrap_or(Vec3::Y)
        })
        .collect()
}

/// An OBJ path as a scene file gives it: absolute, or relative to the scene file's directory
/// `base`.
pub fn resolve_path(base: &Path, path: &str) -> PathBuf {
    let p = Path::new(path);
    if p.is_absolute() {
        p.to_path_buf()
    } else {
        base.join(p)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const CUBE: &str = "\
# unit cube, quads, no normals
o cube
v -0.5 -0.5 -0.5
v  0.5 -0.5 -0.5
v  0.5  0.5 -0.5
v -0.5  0.5 -0.5
v -0.5 -0.5  0.5
v  0.5 -0.5  0.5
v  0.5  0.5  0.5
v -0.5  0.5  0.5
f 1 4 3 2
f 5 6 7 8
f 1 2 6 5
f 4 8 7 3
f 1 5 8 4
f 2 3 7 6
";

    fn volume(mesh: &TriMesh) -> f32 {
        mesh.indices
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|i| mesh.positions[i as usize]);
                a.dot(b.cross(c)) / 6.0
            })
            .sum()
    }

    #[test]
    fn cube_round_trips() {
        let m = load_obj_str(CUBE, "cube.obj").unwrap();
        assert_eq!(m.positions.len(), 8);
        assert_eq!(m.triangle_count(), 12);
        assert_eq!(m.normals.len(), 8);
        assert!((volume(&m) - 1.0).abs() < 1e-6, "volume {}", volume(&m));
        // Computed smooth normals are unit and point away from the centre at every corner.
        for (p, n) in m.positions.iter().zip(&m.normals) {
            assert!((n.length() - 1.0).abs() < 1e-5);
            assert!(n.dot(*p) > 0.5, "normal {n} at {p}");
        }
    }

    #[test]
    fn file_normals_are_kept() {
        let text = "\
v 0 0 0
v 1 0 0
v 0 0 1
vn 0 2 0
f 1//1 3//1 2//1
";
        let m = load_obj_str(text, "tri.obj").unwrap();
        assert_eq!(m.triangle_count(), 1);
        // Renormalised, not recomputed.
        assert!(m.normals.iter().all(|&n| n == Vec3::Y));
    }

    #[test]
    fn objects_are_merged() {
        let text = format!("{CUBE}o second\nv 2 0 0\nv 3 0 0\nv 2 1 0\nf 9 10 11\n");
        let m = load_obj_str(&text, "two.obj").unwrap();
        assert_eq!(m.positions.len(), 11);
        assert_eq!(m.triangle_count(), 13);
        let last = m.indices[12].map(|i| m.positions[i as usize]);
        assert_eq!(
            last,
            [
                Vec3::new(2.0, 0.0, 0.0),
                Vec3::new(3.0, 0.0, 0.0),
                Vec3::new(2.0, 1.0, 0.0)
            ]
        );
    }

    #[test]
    fn degenerate_faces_are_dropped() {
        let text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 1 2\nl 1 2\np 3\n";
        let m = load_obj_str(text, "degenerate.obj").unwrap();
        assert_eq!(m.triangle_count(), 1);
    }

    #[test]
    fn load_from_file() {
        let dir = std::env::temp_dir().join(format!("scatterbench-obj-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("cube.obj");
        std::fs::write(&path, CUBE).unwrap();
        let m = load_obj(&path);
        std::fs::remove_dir_all(&dir).unwrap();
        assert_eq!(m.unwrap(), load_obj_str(CUBE, "x").unwrap());
    }

    #[test]
    fn missing_file_names_the_path() {
        let path = Path::new("/definitely/not/here/missing-mesh.obj");
        let err = load_obj(path).unwrap_err();
        assert!(err.contains("missing-mesh.obj"), "{err}");
        assert!(err.contains("not found"), "{err}");
    }

    #[test]
    fn bad_input_is_an_error_not_a_panic() {
        let cases = [
            ("garbage", "this is not\nan obj file \u{1F600}\n\0\0\0"),
            ("empty", ""),
            ("no faces", "v 0 0 0\nv 1 0 0\nv 0 1 0\n"),
            ("bad position", "v 0 zero 0\nf 1 1 1\n"),
            ("short position", "v 0 0\n"),
            ("bad face", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 two 3\n"),
            ("index out of range", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n"),
            ("zero index", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n"),
            (
                "relative out of range",
                "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -1 -2 -9\n",
            ),
            (
                "huge relative texcoord",
                "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/-9223372036854775807 2/1 3/1\n",
            ),
            ("non-finite", "v 0 0 0\nv inf 0 0\nv 0 1 0\nf 1 2 3\n"),
            ("nan", "v 0 0 0\nv 1 NaN 0\nv 0 1 0\nf 1 2 3\n"),
            ("mtllib only", "mtllib nothing.mtl\nusemtl nothing\n"),
        ];
        for (what, text) in cases {
            let result = load_obj_str(text, "bad.obj");
            let err = result.expect_err(what);
            assert!(err.starts_with("bad.obj: "), "{what}: {err}");
        }
        let err = load_obj_str("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n", "x.obj").unwrap_err();
        assert!(err.contains("out of range"), "{err}");
        let err = load_obj_str("v 0 0 0\nv inf 0 0\nv 0 1 0\nf 1 2 3\n", "x.obj").unwrap_err();
        assert!(err.contains("non-finite"), "{err}");
        let err = load_obj_str("v 0 0 0\n", "x.obj").unwrap_err();
        assert!(err.contains("no triangles"), "{err}");
    }
}
