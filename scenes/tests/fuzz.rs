//! Fuzzing the scene loader with proptest: arbitrary JSON, and library scenes with fields
//! replaced, removed or added. The properties: `parse_scene` never panics; a refusal is a
//! message that names the file and says something; an accepted scene yields frame states,
//! features and a medium without panicking, with finite cameras, pixel rays and light poses
//! (camera-attached spots resolved through the camera's pose) at its first, middle and last
//! frames.
//!
//! OBJ input goes through the same loader with arbitrary OBJ statements in a file an `obj`
//! shape names. glTF input: the sample level (`scenes::gltf::sample`) mutated as JSON (through
//! a scene file's `import` and as a scene by itself) and as .glb bytes, plus arbitrary bytes.
//!
//! Deterministic by default: every property draws its cases from a fixed seed (`FUZZ_SEED`,
//! default [`DEFAULT_SEED`]), so CI draws the same 2000 cases per property (`FUZZ_CASES`) in every
//! run and a red run is red again. Before its random cases, each property replays the regression
//! corpus (`tests/fuzz-corpus/<kind>/`): every input that ever failed a property, kept as a file.
//! A failing random case is written to `target/fuzz-failures/<kind>/`, to be added to the corpus
//! with its fix. Longer or fresh runs by hand:
//! `FUZZ_CASES=20000 FUZZ_SEED=random cargo test --release -p scenes --test fuzz` (the seed drawn
//! is printed, and `FUZZ_SEED=<that number>` repeats the run).

use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::Path;

use proptest::prelude::*;
use proptest::test_runner::{Config, RngSeed, TestRunner};
use scenes::{library, parse_scene};
use serde_json::{Map, Value};

const FILE: &str = "fuzz.json";

fn cases() -> u32 {
    std::env::var("FUZZ_CASES")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(2000)
}

/// Field names and enum tags of the format, so arbitrary objects often get past the first key.
const WORDS: &[&str] = &[
    "camera",
    "medium",
    "lights",
    "objects",
    "frames",
    "description",
    "position",
    "look_at",
    "up",
    "fov_y_deg",
    "near",
    "far",
    "keyframes",
    "frame",
    "kind",
    "homogeneous",
    "sigma_a",
    "sigma_s",
    "phase",
    "ambient",
    "point",
    "spot",
    "directional",
    "direction",
    "intensity",
    "irradiance",
    "inner_deg",
    "outer_deg",
    "pattern",
    "checker",
    "cells",
    "dark",
    "stained-glass",
    "panes",
    "lead",
    "seed",
    "shape",
    "plane",
    "box",
    "sphere",
    "cylinder",
    "torus",
    "spring",
    "pencil",
    "fence",
    "obj",
    "size",
    "radius",
    "segments",
    "rings",
    "height",
    "transform",
    "translation",
    "rotation_deg",
    "scale",
    "material",
    "albedo",
    "two_sided",
    "phong",
    "ks",
    "shininess",
    "henyey-greenstein",
    "g",
    "isotropic",
    "rayleigh",
    "path",
    "name",
    "casts_volumetric_shadow",
    "indirect_single_scattering",
    "turns",
    "wire_radius",
    "coil_radius",
    "posts",
    "rails",
    "bar",
    "attached_to_camera",
];

/// Numbers at the edges: zero, negatives, f32 overflow (1e39 → inf), denormals, huge counts.
fn number() -> impl Strategy<Value = Value> {
    prop_oneof![
        Just(0.0),
        Just(-1.0),
        Just(1e39),
        Just(-1e39),
        Just(1e-45),
        Just(4096.0),
        Just(4097.0),
        Just(4294967296.0),
        Just(1e300),
        Just(0.5),
        Just(179.999),
        Just(180.0),
        -1e6f64..1e6,
    ]
    .prop_map(|x| serde_json::Number::from_f64(x).map_or(Value::Null, Value::Number))
    .boxed()
    .prop_union(
        prop_oneof![
            Just(0i64),
            Just(-1),
            Just(3),
            Just(4096),
            Just(i64::MAX),
            any::<i32>().prop_map(i64::from)
        ]
        .prop_map(|i| Value::Number(i.into()))
        .boxed(),
    )
}

fn leaf() -> impl Strategy<Value = Value> {
    prop_oneof![
        Just(Value::Null),
        any::<bool>().prop_map(Value::Bool),
        number(),
        prop::sample::select(WORDS).prop_map(|s| Value::String(s.to_string())),
        ".*".prop_map(Value::String),
        prop::collection::vec(number(), 3).prop_map(Value::Array),
    ]
}

fn json() -> impl Strategy<Value = Value> {
    leaf().prop_recursive(4, 64, 6, |inner| {
        prop_oneof![
            prop::collection::vec(inner.clone(), 0..6).prop_map(Value::Array),
            prop::collection::vec((prop::sample::select(WORDS), inner), 0..6).prop_map(|kv| {
                Value::Object(kv.into_iter().map(|(k, v)| (k.to_string(), v)).collect())
            }),
        ]
    })
}

/// Every path (object keys, array indices) to a value inside `v`.
fn paths(v: &Value, here: &mut Vec<Step>, out: &mut Vec<Vec<Step>>) {
    out.push(here.clone());
    match v {
        Value::Object(m) => {
            for (k, c) in m {
                here.push(Step::Key(k.clone()));
                paths(c, here, out);
                here.pop();
            }
        }
        Value::Array(a) => {
            for (i, c) in a.iter().enumerate() {
                here.push(Step::Index(i));
                paths(c, here, out);
                here.pop();
            }
        }
        _ => {}
    }
}

#[derive(Clone, Debug)]
enum Step {
    Key(String),
    Index(usize),
}

fn at<'a>(v: &'a mut Value, path: &[Step]) -> Option<&'a mut Value> {
    path.iter().try_fold(v, |v, s| match s {
        Step::Key(k) => v.get_mut(k.as_str()),
        Step::Index(i) => v.get_mut(*i),
    })
}

#[derive(Clone, Debug)]
enum Mutation {
    Replace(usize, Value),
    Remove(usize),
    Add(usize, &'static str, Value),
}

fn mutation() -> impl Strategy<Value = Mutation> {
    prop_oneof![
        4 => (any::<usize>(), json()).prop_map(|(i, v)| Mutation::Replace(i, v)),
        1 => any::<usize>().prop_map(Mutation::Remove),
        1 => (any::<usize>(), prop::sample::select(WORDS), leaf()).prop_map(|(i, k, v)| Mutation::Add(i, k, v)),
    ]
}

fn mutate(v: &mut Value, m: &Mutation) {
    let mut all = Vec::new();
    paths(v, &mut Vec::new(), &mut all);
    let pick = |i: usize| all[i % all.len()].clone();
    match m {
        Mutation::Replace(i, x) => {
            if let Some(t) = at(v, &pick(*i)) {
                *t = x.clone();
            }
        }
        Mutation::Remove(i) => {
            let p = pick(*i);
            if let Some((last, parent)) = p.split_last()
                && let Some(t) = at(v, parent)
            {
                match (t, last) {
                    (Value::Object(m), Step::Key(k)) => {
                        m.remove(k);
                    }
                    (Value::Array(a), Step::Index(i)) if *i < a.len() => {
                        a.remove(*i);
                    }
                    _ => {}
                }
            }
        }
        Mutation::Add(i, k, x) => {
            if let Some(Value::Object(m)) = at(v, &pick(*i)) {
                m.insert(k.to_string(), x.clone());
            }
        }
    }
}

/// The loader's contract on one text; Err(description) when violated.
fn check(text: &str) -> Result<(), TestCaseError> {
    // OBJ paths resolve against a directory with no files: a mutated "obj" shape is refused.
    let base = Path::new("/nonexistent-fuzz-dir");
    let out = catch_unwind(AssertUnwindSafe(|| parse_scene(text, FILE, "fuzz", base)));
    let res = out.map_err(|_| TestCaseError::fail(format!("parse_scene panicked on:\n{text}")))?;
    match res {
        Err(e) => {
            let msg = e.to_string();
            prop_assert!(
                msg.starts_with(FILE),
                "refusal does not name the file: {msg}"
            );
            prop_assert!(msg.len() > FILE.len() + 4, "refusal says nothing: {msg}");
        }
        Ok(scene) => {
            let r = catch_unwind(AssertUnwindSafe(|| {
                let _ = scene.features();
                let _ = scene.medium();
                let n = scene.frame_count();
                for i in (0..n.min(3)).chain([n / 2, n - 1]) {
                    let f = scene.frame(i);
                    assert!(f.camera.position.is_finite(), "camera position not finite");
                    let d = f.camera.rays(8, 8).direction(0, 0);
                    assert!(d.is_finite(), "frame {i}: pixel ray not finite");
                    // Every light resolves to a finite pose, camera-attached ones included.
                    for l in &f.lights {
                        assert!(
                            l.position().is_none_or(|p| p.is_finite()),
                            "frame {i}: {l:?}"
                        );
                        if let scenes::LightState::Spot { direction, .. }
                        | scenes::LightState::Directional { direction, .. } = l
                        {
                            assert!((direction.length() - 1.0).abs() < 1e-4, "frame {i}: {l:?}");
                        }
                    }
                }
            }));
            prop_assert!(r.is_ok(), "an accepted scene panicked downstream:\n{text}");
        }
    }
    Ok(())
}

/// The seed CI uses: any fixed number would do; this one is the suite's name in hex speak.
const DEFAULT_SEED: u64 = 0x5CA7_7E2B_E4C4;

/// The run's seed: `FUZZ_SEED` as a number, a fresh one for `FUZZ_SEED=random`, else the default.
fn seed() -> u64 {
    match std::env::var("FUZZ_SEED").ok().as_deref() {
        None | Some("") => DEFAULT_SEED,
        Some("random") => std::time::SystemTime::now()
            .duration_since(std::time::UNIX_EPOCH)
            .map_or(DEFAULT_SEED, |d| d.as_nanos() as u64),
        Some(s) => s
            .parse()
            .unwrap_or_else(|_| panic!("FUZZ_SEED={s}: expected a u64 or `random`")),
    }
}

/// FNV-1a: a stable 64-bit hash (std's hasher may change between releases).
fn fnv1a(bytes: &[u8]) -> u64 {
    bytes
        .iter()
        .fold(0xcbf2_9ce4_8422_2325, |h, &b| (h ^ b as u64).wrapping_mul(0x100_0000_01b3))
}

/// A runner for one property, seeded from the run's seed and the property's name (so properties
/// do not draw correlated cases); prints both so that a failure can be repeated.
fn runner(property: &str) -> TestRunner {
    let run_seed = seed();
    let name_hash = fnv1a(property.as_bytes());
    eprintln!("{property}: FUZZ_SEED={run_seed}, {} cases", cases());
    TestRunner::new(Config {
        cases: cases(),
        failure_persistence: None,
        rng_seed: RngSeed::Fixed(run_seed ^ name_hash),
        ..Config::default()
    })
}

/// The corpus of inputs that once failed, one folder per kind of input (`json`, `obj`, `gltf`,
/// `glb`), sorted by name. A kind with no folder has no entries.
fn corpus(kind: &str) -> Vec<(String, Vec<u8>)> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fuzz-corpus").join(kind);
    let Ok(entries) = std::fs::read_dir(&dir) else {
        return Vec::new();
    };
    let mut files: Vec<_> = entries.map(|e| e.unwrap().path()).collect();
    files.sort();
    files
        .into_iter()
        .map(|p| (p.display().to_string(), std::fs::read(&p).unwrap()))
        .collect()
}

/// Replays the corpus of `kind` through `check` before any random case; returns how many.
fn replay(kind: &str, check: impl Fn(&[u8]) -> Result<(), TestCaseError>) -> usize {
    let entries = corpus(kind);
    for (path, bytes) in &entries {
        if let Err(e) = check(bytes) {
            panic!("regression corpus {path}: {e}");
        }
    }
    entries.len()
}

/// Keeps a failing random input where it can be added to the corpus, and says where.
fn keep_failure(kind: &str, ext: &str, bytes: &[u8], e: TestCaseError) -> TestCaseError {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../target/fuzz-failures").join(kind);
    let path = dir.join(format!("{:016x}.{ext}", fnv1a(bytes)));
    let kept = std::fs::create_dir_all(&dir).and_then(|_| std::fs::write(&path, bytes));
    let whereto = match kept {
        Ok(()) => format!("kept as {} (add it to tests/fuzz-corpus/{kind}/)", path.display()),
        Err(w) => format!("could not keep it at {}: {w}", path.display()),
    };
    TestCaseError::fail(format!("{e}\n{whereto}"))
}

/// `check` on a scene text, keeping a failing one.
fn check_kept(text: &str) -> Result<(), TestCaseError> {
    check(text).map_err(|e| keep_failure("json", "json", text.as_bytes(), e))
}

/// `check` on a corpus file's bytes (a scene text).
fn check_bytes(bytes: &[u8]) -> Result<(), TestCaseError> {
    check(&String::from_utf8_lossy(bytes))
}

#[test]
fn arbitrary_json_never_panics_and_refusals_name_the_file() {
    let replayed = replay("json", check_bytes);
    // The corpus holds the loader's past failures (far positions, far planes, huge meshes).
    assert!(replayed >= 3, "the JSON corpus replayed {replayed} files");
    runner("json").run(&json(), |v| check_kept(&v.to_string())).unwrap();
}

#[test]
fn arbitrary_text_never_panics() {
    runner("text").run(&".{0,200}", |t: String| check_kept(&t)).unwrap();
}

#[test]
fn mutated_library_scenes_never_panic_and_refusals_name_the_file() {
    let scenes: Vec<Value> = library::LIBRARY
        .iter()
        .map(|(_, t)| serde_json::from_str(t).unwrap())
        .collect();
    let strategy = (0..scenes.len(), prop::collection::vec(mutation(), 1..4));
    runner("library")
        .run(&strategy, |(k, ms)| {
            let mut v = scenes[k].clone();
            for m in &ms {
                mutate(&mut v, m);
            }
            check_kept(&v.to_string())
        })
        .unwrap();
}

/// Procedural parameters each within their range can still multiply to billions of triangles
/// (a spring of 1000 turns × 4096 segments × 4096 sides): the loader must refuse it with a
/// message, not try to allocate it.
#[test]
fn a_procedural_mesh_too_large_to_build_is_refused() {
    let mut v: Value = serde_json::from_str(library::LIBRARY[0].1).unwrap();
    let mut spring = Map::new();
    for (k, x) in [
        ("kind", Value::from("spring")),
        ("coil_radius", Value::from(1.0)),
        ("wire_radius", Value::from(0.1)),
        ("turns", Value::from(1000.0)),
        ("height", Value::from(2.0)),
        ("segments_per_turn", Value::from(4096)),
        ("sides", Value::from(4096)),
    ] {
        spring.insert(k.into(), x);
    }
    v["objects"][1]["shape"] = Value::Object(spring);
    let text = v.to_string();
    let err = parse_scene(&text, FILE, "fuzz", Path::new("."))
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("objects[1].shape") && err.contains("triangles"),
        "{err}"
    );
}

/// OBJ statements, well-formed and not: vertices with edge-case numbers, faces with absolute,
/// relative (negative), zero, out-of-range and malformed `v/vt/vn` indices, and the statements
/// the loader ignores.
fn obj_line() -> impl Strategy<Value = String> {
    let num = prop_oneof![
        Just("0".to_string()),
        Just("-1".to_string()),
        Just("1e39".to_string()),
        Just("-1e39".to_string()),
        Just("nan".to_string()),
        Just("inf".to_string()),
        Just("1e-45".to_string()),
        Just("x".to_string()),
        Just("".to_string()),
        (-1e3f64..1e3).prop_map(|x| x.to_string()),
    ];
    let index = prop_oneof![
        Just("0".to_string()),
        Just("1".to_string()),
        Just("2".to_string()),
        Just("3".to_string()),
        Just("-1".to_string()),
        Just("-2".to_string()),
        Just("-4294967296".to_string()),
        Just("9223372036854775807".to_string()),
        Just("-9223372036854775808".to_string()),
        Just("".to_string()),
        Just("a".to_string()),
        any::<i32>().prop_map(|i| i.to_string()),
    ];
    let corner = (
        index.clone(),
        prop::option::of(index.clone()),
        prop::option::of(index),
    )
        .prop_map(|(v, t, n)| match (t, n) {
            (None, None) => v,
            (Some(t), None) => format!("{v}/{t}"),
            (None, Some(n)) => format!("{v}//{n}"),
            (Some(t), Some(n)) => format!("{v}/{t}/{n}"),
        });
    prop_oneof![
        4 => prop::collection::vec(num.clone(), 0..5).prop_map(|v| format!("v {}", v.join(" "))),
        4 => prop::collection::vec(-1e3f64..1e3, 3).prop_map(|v| format!("v {} {} {}", v[0], v[1], v[2])),
        1 => prop::collection::vec(num.clone(), 0..4).prop_map(|v| format!("vn {}", v.join(" "))),
        1 => prop::collection::vec(num, 0..3).prop_map(|v| format!("vt {}", v.join(" "))),
        4 => prop::collection::vec(corner, 0..6).prop_map(|c| format!("f {}", c.join(" "))),
        1 => prop::sample::select(&["o a", "g b", "s 1", "usemtl m", "mtllib missing.mtl", "l 1 2", "p 1", "# c", "", "f", "v"][..]).prop_map(str::to_string),
        1 => ".{0,20}",
        2 => Just("f 1 2 3".to_string()),
        2 => Just("f -1 -2 -3".to_string()),
    ]
}

/// Panics anywhere in the process since the last call (a panic contained by the loader's own
/// `catch_unwind` still counts: the property is zero panics, not zero escaped panics).
fn panics_since_last_call() -> usize {
    use std::sync::Once;
    use std::sync::atomic::{AtomicUsize, Ordering};
    static COUNT: AtomicUsize = AtomicUsize::new(0);
    static HOOK: Once = Once::new();
    HOOK.call_once(|| {
        let default = std::panic::take_hook();
        std::panic::set_hook(Box::new(move |info| {
            COUNT.fetch_add(1, Ordering::SeqCst);
            default(info);
        }));
    });
    COUNT.swap(0, Ordering::SeqCst)
}

/// A scene file whose first object is the mesh `fuzz.obj` in its directory.
fn obj_scene_text() -> String {
    let mut v: Value = serde_json::from_str(library::LIBRARY[0].1).unwrap();
    let mut shape = Map::new();
    shape.insert("kind".into(), Value::from("obj"));
    shape.insert("path".into(), Value::from("fuzz.obj"));
    v["objects"][0]["shape"] = Value::Object(shape);
    v.to_string()
}

/// The `obj` mesh path's contract on one OBJ file, loaded from `dir` through `parse_scene`:
/// never a panic (counted, contained or not); a refusal names the scene file and the object; an
/// accepted mesh has finite positions and normals and in-range indices. Ok(true) if accepted.
fn check_obj(dir: &Path, scene_text: &str, obj: &str) -> Result<bool, TestCaseError> {
    std::fs::write(dir.join("fuzz.obj"), obj).unwrap();
    let out = catch_unwind(AssertUnwindSafe(|| parse_scene(scene_text, FILE, "fuzz", dir)));
    let res =
        out.map_err(|_| TestCaseError::fail(format!("parse_scene panicked on OBJ:\n{obj}")))?;
    prop_assert_eq!(panics_since_last_call(), 0, "a panic (contained) on OBJ:\n{}", obj);
    let scene = match res {
        Err(e) => {
            let msg = e.to_string();
            prop_assert!(msg.starts_with(FILE), "refusal does not name the file: {msg}");
            prop_assert!(
                msg.contains("objects[0].shape"),
                "refusal does not name the object: {msg}"
            );
            return Ok(false);
        }
        Ok(scene) => scene,
    };
    let m = &scene.meshes[0];
    prop_assert!(!m.indices.is_empty());
    prop_assert!(m.positions.iter().all(|p| p.is_finite()), "non-finite position from:\n{obj}");
    prop_assert!(m.normals.iter().all(|n| n.is_finite()), "non-finite normal from:\n{obj}");
    let n = m.positions.len() as u32;
    prop_assert!(
        m.indices.iter().flatten().all(|&i| i < n),
        "index out of range from:\n{obj}"
    );
    Ok(true)
}

/// The `obj` mesh path end to end: a scene whose object is an OBJ file of arbitrary statements
/// (`check_obj`), after the OBJ corpus.
#[test]
fn arbitrary_obj_files_never_panic_and_refusals_name_the_object() {
    let dir = std::env::temp_dir().join(format!("scatterbench-fuzz-obj-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let scene_text = obj_scene_text();
    panics_since_last_call();
    replay("obj", |b| check_obj(&dir, &scene_text, &String::from_utf8_lossy(b)).map(drop));
    let accepted = std::cell::Cell::new(0u32);
    runner("obj")
        .run(
            &(any::<bool>(), prop::collection::vec(obj_line(), 0..24)),
            |(seed, lines)| {
                // Half the files start from a valid triangle, so the accepting path is reached too.
                let seed = if seed {
                    "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"
                } else {
                    ""
                };
                let obj = format!("{seed}{}", lines.join("\n"));
                let ok = check_obj(&dir, &scene_text, &obj)
                    .map_err(|e| keep_failure("obj", "obj", obj.as_bytes(), e))?;
                accepted.set(accepted.get() + ok as u32);
                Ok(())
            },
        )
        .unwrap();
    let _ = std::fs::remove_dir_all(&dir);
    eprintln!("{} of {} OBJ files accepted", accepted.get(), cases());
    // The generator must reach the accepting path too, or the checks above never run.
    assert!(accepted.get() > 0, "no generated OBJ file was accepted");
}

/// The contract for a loaded glTF level: never a panic (counted, contained or not); a refusal
/// names `file`; an accepted scene has finite geometry, in-range indices and frame states.
fn check_gltf(
    res: std::thread::Result<Result<scenes::Scene, scenes::SceneError>>,
    file: &str,
    what: &dyn Fn() -> String,
) -> Result<bool, TestCaseError> {
    let res = res.map_err(|_| TestCaseError::fail(format!("the loader panicked on {}", what())))?;
    prop_assert_eq!(
        panics_since_last_call(),
        0,
        "a panic (contained) on {}",
        what()
    );
    match res {
        Err(e) => {
            let msg = e.to_string();
            prop_assert!(msg.starts_with(file), "refusal does not name {file}: {msg}");
            prop_assert!(msg.len() > file.len() + 4, "refusal says nothing: {msg}");
            Ok(false)
        }
        Ok(scene) => {
            for m in &scene.meshes {
                let n = m.positions.len() as u32;
                prop_assert!(m.positions.iter().chain(&m.normals).all(|p| p.is_finite()));
                prop_assert!(m.indices.iter().flatten().all(|&i| i < n));
            }
            let f = scene.frame(0);
            prop_assert!(f.camera.position.is_finite());
            let _ = scene.features();
            Ok(true)
        }
    }
}

/// One glTF level's text, written as `level.gltf` in `dir` and loaded both through a scene
/// file's `import` and as a scene by itself (`check_gltf`). Ok(true) if the import accepted it.
fn check_gltf_text(dir: &Path, text: &str) -> Result<bool, TestCaseError> {
    let scene_text = r#"{"import": "level.gltf", "medium": {"kind": "homogeneous", "sigma_a": [0.01, 0.01, 0.01], "sigma_s": [0.05, 0.05, 0.05]}}"#;
    let standalone = dir.join("level.gltf");
    std::fs::write(&standalone, text).unwrap();
    let what = || format!("glTF:\n{text}");
    let imported = catch_unwind(AssertUnwindSafe(|| parse_scene(scene_text, FILE, "fuzz", dir)));
    let ok = check_gltf(imported, FILE, &what)?;
    let alone = catch_unwind(AssertUnwindSafe(|| scenes::load_scene(&standalone)));
    check_gltf(alone, &standalone.display().to_string(), &what)?;
    Ok(ok)
}

/// glTF input: the sample level's JSON (`scenes::gltf::sample`, buffer embedded) with fields
/// replaced, removed or added (`check_gltf_text`), after the glTF corpus. Same number of cases
/// as the JSON and OBJ properties.
#[test]
fn mutated_gltf_levels_never_panic_and_refusals_name_the_file() {
    let dir = std::env::temp_dir().join(format!("scatterbench-fuzz-gltf-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let level = scenes::gltf::sample::level();
    panics_since_last_call();
    let replayed = replay("gltf", |b| check_gltf_text(&dir, &String::from_utf8_lossy(b)).map(drop));
    // The corpus holds gltf-json's unchecked POSITION index (a panic before 54af581).
    assert!(replayed >= 1, "the glTF corpus replayed {replayed} files");
    let accepted = std::cell::Cell::new(0u32);
    runner("gltf")
        .run(&prop::collection::vec(mutation(), 1..4), |ms| {
            let mut v = level.clone();
            for m in &ms {
                mutate(&mut v, m);
            }
            let text = v.to_string();
            let ok = check_gltf_text(&dir, &text)
                .map_err(|e| keep_failure("gltf", "gltf", text.as_bytes(), e))?;
            accepted.set(accepted.get() + ok as u32);
            Ok(())
        })
        .unwrap();
    let _ = std::fs::remove_dir_all(&dir);
    eprintln!(
        "{} of {} mutated glTF levels accepted",
        accepted.get(),
        cases()
    );
    assert!(accepted.get() > 0, "no mutated level was accepted");
}

/// A byte-level edit of a .glb file.
#[derive(Clone, Debug)]
enum ByteEdit {
    Set(usize, u8),
    Truncate(usize),
    Insert(usize, Vec<u8>),
}

fn byte_edit() -> impl Strategy<Value = ByteEdit> {
    prop_oneof![
        4 => (any::<usize>(), any::<u8>()).prop_map(|(i, b)| ByteEdit::Set(i, b)),
        1 => any::<usize>().prop_map(ByteEdit::Truncate),
        1 => (any::<usize>(), prop::collection::vec(any::<u8>(), 1..16))
            .prop_map(|(i, b)| ByteEdit::Insert(i, b)),
    ]
}

/// `glb` with the edits applied in order.
fn edited(glb: &[u8], edits: &[ByteEdit]) -> Vec<u8> {
    let mut b = glb.to_vec();
    for e in edits {
        match e {
            ByteEdit::Set(i, x) => {
                let n = b.len().max(1);
                if let Some(t) = b.get_mut(i % n) {
                    *t = *x;
                }
            }
            ByteEdit::Truncate(i) => b.truncate(i % (b.len() + 1)),
            ByteEdit::Insert(i, x) => {
                let at = i % (b.len() + 1);
                b.splice(at..at, x.iter().copied());
            }
        }
    }
    b
}

/// One .glb file's bytes, written as `level.glb` in `dir` and loaded as a scene by itself
/// (`check_gltf`). Ok(true) if accepted.
fn check_glb(dir: &Path, bytes: &[u8]) -> Result<bool, TestCaseError> {
    let path = dir.join("level.glb");
    std::fs::write(&path, bytes).unwrap();
    let what = || format!("GLB bytes {:?}", &bytes[..bytes.len().min(64)]);
    let res = catch_unwind(AssertUnwindSafe(|| scenes::load_scene(&path)));
    check_gltf(res, &path.display().to_string(), &what)
}

/// .glb input: the sample level as GLB with bytes changed, cut or inserted (header, chunk
/// lengths, JSON and binary chunk alike), or arbitrary bytes after the magic; loaded as a
/// scene by itself, after the GLB corpus. Same number of cases as the JSON and OBJ properties.
#[test]
fn mutated_and_arbitrary_glb_bytes_never_panic_and_refusals_name_the_file() {
    let dir = std::env::temp_dir().join(format!("scatterbench-fuzz-glb-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let glb = scenes::gltf::sample::to_glb(&scenes::gltf::sample::level()).unwrap();
    panics_since_last_call();
    replay("glb", |b| check_glb(&dir, b).map(drop));
    let accepted = std::cell::Cell::new(0u32);
    let strategy = (
        any::<bool>(),
        prop::collection::vec(byte_edit(), 1..6),
        prop::collection::vec(any::<u8>(), 0..256),
    );
    runner("glb")
        .run(&strategy, |(arbitrary, edits, noise)| {
            let bytes = if arbitrary {
                [b"glTF".as_slice(), &noise].concat()
            } else {
                edited(&glb, &edits)
            };
            let ok = check_glb(&dir, &bytes).map_err(|e| keep_failure("glb", "glb", &bytes, e))?;
            accepted.set(accepted.get() + ok as u32);
            Ok(())
        })
        .unwrap();
    let _ = std::fs::remove_dir_all(&dir);
    eprintln!("{} of {} GLB files accepted", accepted.get(), cases());
    assert!(accepted.get() > 0, "no GLB file was accepted");
}
