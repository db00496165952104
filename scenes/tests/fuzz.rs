//! Fuzzing the scene loader with proptest: arbitrary JSON, and library scenes with fields
//! replaced, removed or added. The properties: `parse_scene` never panics; a refusal is a
//! message that names the file and says something; an accepted scene yields frame states,
//! features and a medium without panicking, with finite cameras.
//!
//! CI runs a fixed number of cases (`FUZZ_CASES`, default 2000 per property, about a second in
//! release). A longer manual run: `FUZZ_CASES=20000 cargo test --release -p scenes --test fuzz`.

use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::Path;

use proptest::prelude::*;
use proptest::test_runner::{Config, TestRunner};
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
                for i in 0..scene.frame_count().min(3) {
                    let f = scene.frame(i);
                    assert!(f.camera.position.is_finite(), "camera position not finite");
                    let _ = f.camera.rays(8, 8).direction(0, 0);
                }
            }));
            prop_assert!(r.is_ok(), "an accepted scene panicked downstream:\n{text}");
        }
    }
    Ok(())
}

fn runner() -> TestRunner {
    TestRunner::new(Config {
        cases: cases(),
        failure_persistence: None,
        ..Config::default()
    })
}

#[test]
fn arbitrary_json_never_panics_and_refusals_name_the_file() {
    runner().run(&json(), |v| check(&v.to_string())).unwrap();
}

#[test]
fn arbitrary_text_never_panics() {
    runner().run(&".{0,200}", |t: String| check(&t)).unwrap();
}

#[test]
fn mutated_library_scenes_never_panic_and_refusals_name_the_file() {
    let scenes: Vec<Value> = library::LIBRARY
        .iter()
        .map(|(_, t)| serde_json::from_str(t).unwrap())
        .collect();
    let strategy = (0..scenes.len(), prop::collection::vec(mutation(), 1..4));
    runner()
        .run(&strategy, |(k, ms)| {
            let mut v = scenes[k].clone();
            for m in &ms {
                mutate(&mut v, m);
            }
            check(&v.to_string())
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
