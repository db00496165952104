//! glTF 2.0 from the outside: the sample level (`scenes::gltf::sample`) imported by a scene
//! file and as a scene by itself, its node hierarchy against an independent matrix product,
//! its lights against the photometric definition, errors naming the glTF path, ignored
//! content recorded, and every library scene exported and imported back unchanged.

use std::path::{Path, PathBuf};

use glam::{Mat4, Quat, Vec3};
use scenes::gltf::export::to_glb;
use scenes::gltf::lights::LUMENS_PER_WATT;
use scenes::gltf::sample;
use scenes::{LightState, Scene, library, load_scene, parse_scene};
use serde_json::{Value, json};

/// A fresh folder for one test's files.
fn scratch(test: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("scatterbench-gltf-{test}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn write(dir: &Path, name: &str, bytes: &[u8]) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, bytes).unwrap();
    p
}

const MEDIUM: &str = r#""medium": {"kind": "homogeneous", "sigma_a": [0.01, 0.01, 0.01], "sigma_s": [0.05, 0.05, 0.05]}"#;

/// A scene file importing `level.gltf` (written from `level`) with `extra` fields.
fn import_scene(test: &str, level: &Value, extra: &str) -> Result<Scene, String> {
    let dir = scratch(test);
    write(&dir, "level.gltf", level.to_string().as_bytes());
    let text = format!(r#"{{"import": "level.gltf", {MEDIUM}{extra}}}"#);
    parse_scene(&text, "scene.json", "scene", &dir).map_err(|e| e.to_string())
}

fn standalone(test: &str, level: &Value) -> Result<Scene, String> {
    let p = write(&scratch(test), "level.gltf", level.to_string().as_bytes());
    library::resolve(p.to_str().unwrap())
}

#[test]
fn the_sample_level_imports_its_nodes_lights_and_camera() {
    let s = import_scene("sample", &sample::level(), "").unwrap_or_else(|e| panic!("{e}"));
    let names: Vec<&str> = s.desc.objects.iter().map(|o| o.name.as_str()).collect();
    assert_eq!(
        names,
        ["floor", "left pillar", "right pillar", "tilted box"]
    );
    assert_eq!(s.meshes.len(), 4);
    assert_eq!(s.triangle_count(), 2 + 3 * 12);
    assert!(
        s.desc.objects[1].material.two_sided,
        "doubleSided → two_sided"
    );
    assert_eq!(s.desc.objects[0].material.albedo, Vec3::splat(0.7));
    assert_eq!(s.desc.lights.len(), 3);
    assert!(s.ignored.is_empty(), "{:?}", s.ignored);
    let f = s.frame(0);
    // Camera: node matrix = inverse look-at from (0, 3, 9) toward (0, 1, -1).
    let forward = (Vec3::new(0.0, 1.0, -1.0) - Vec3::new(0.0, 3.0, 9.0)).normalize();
    assert!((f.camera.position - Vec3::new(0.0, 3.0, 9.0)).length() < 1e-5);
    assert!(((f.camera.look_at - f.camera.position).normalize() - forward).length() < 1e-5);
    assert!((f.camera.fov_y_deg - 0.8f32.to_degrees()).abs() < 1e-4);
    assert_eq!((f.camera.near, f.camera.far), (0.1, 60.0));
}

/// 683 lm = 1 W (the photometric definition at 555 nm): the sample's candela and lux, written
/// as W × 683, come back as the W/sr and W/m² they were made from, times the colour.
#[test]
fn lights_convert_candela_and_lux_to_radiometric_units() {
    let s = import_scene("units", &sample::level(), "").unwrap();
    let f = s.frame(0);
    let close = |a: Vec3, b: Vec3| (a - b).abs().max_element() <= 1e-5 * b.max_element();
    match f.lights[0] {
        LightState::Point {
            position,
            intensity,
        } => {
            assert!(close(
                intensity,
                Vec3::new(1.0, 0.9, 0.8) * sample::POINT_W_PER_SR
            ));
            assert!((position - Vec3::new(2.0, 3.5, 1.5)).length() < 1e-6);
        }
        ref l => panic!("light 0 should be a point light: {l:?}"),
    }
    match f.lights[1] {
        LightState::Spot {
            direction,
            intensity,
            cos_inner,
            cos_outer,
            ..
        } => {
            assert!(close(intensity, Vec3::splat(sample::SPOT_W_PER_SR)));
            let want = Vec3::new(0.2, -1.0, -0.3).normalize();
            assert!((direction - want).length() < 1e-5, "{direction} vs {want}");
            assert!((cos_inner - 0.3f32.cos()).abs() < 1e-6);
            assert!((cos_outer - 0.5f32.cos()).abs() < 1e-6);
        }
        ref l => panic!("light 1 should be a spot: {l:?}"),
    }
    match f.lights[2] {
        LightState::Directional {
            irradiance,
            direction,
        } => {
            assert!(close(irradiance, Vec3::splat(sample::SUN_W_PER_M2)));
            assert!((direction - Vec3::new(0.6, -0.7, 0.3).normalize()).length() < 1e-5);
        }
        ref l => panic!("light 2 should be directional: {l:?}"),
    }
    assert_eq!(LUMENS_PER_WATT, 683.0);
}

/// The right pillar is node 3, a child of node 1: its world matrix is the parent's times its
/// own, built here from separate translation, rotation and scale matrices.
#[test]
fn a_child_node_is_placed_by_the_product_of_its_ancestors() {
    let s = import_scene("hierarchy", &sample::level(), "").unwrap();
    let parent = Mat4::from_translation(Vec3::new(0.0, 0.0, -2.0))
        * Mat4::from_quat(Quat::from_rotation_y(30f32.to_radians()));
    let child = Mat4::from_translation(Vec3::new(1.5, 1.2, 0.0))
        * Mat4::from_scale(Vec3::new(0.4, 2.4, 0.4));
    assert!(parent.abs_diff_eq(sample::parent_matrix(), 1e-6));
    let world = parent * child;
    let mesh = &s.meshes[2];
    // The unit cube's corner (+½, +½, +½) must be among the imported world-space vertices.
    let corner = world.transform_point3(Vec3::splat(0.5));
    assert!(
        mesh.positions.iter().any(|p| (*p - corner).length() < 1e-5),
        "{corner} not among {:?}",
        &mesh.positions[..4]
    );
    let (lo, hi) = mesh.bounds(&Mat4::IDENTITY);
    let centre = world.transform_point3(Vec3::ZERO);
    assert!(((lo + hi) * 0.5 - centre).length() < 1e-5);
    // Normals are unit and the +X face's normal is the parent's rotation of +X.
    let nx = Quat::from_rotation_y(30f32.to_radians()) * Vec3::X;
    assert!(mesh.normals.iter().any(|n| (*n - nx).length() < 1e-5));
}

/// A change to the sample level's JSON.
type Mutation = Box<dyn Fn(&mut Value)>;

/// Each mutation of the sample must be refused with the glTF path it breaks.
#[test]
fn errors_name_the_file_and_the_gltf_path() {
    let cases: Vec<(&str, Mutation)> = vec![
        (
            "nodes[2].mesh",
            Box::new(|v| v["nodes"][2]["mesh"] = json!(99)),
        ),
        (
            "meshes[0].primitives[0].attributes",
            Box::new(|v| {
                v["meshes"][0]["primitives"][0]["attributes"]
                    .as_object_mut()
                    .unwrap()
                    .remove("POSITION");
            }),
        ),
        (
            "accessors[0]",
            Box::new(|v| v["accessors"][0]["count"] = json!(1_000_000)),
        ),
        (
            "accessors[2]",
            Box::new(|v| {
                // Two vertices left: the floor's indices reach past them.
                v["accessors"][0]["count"] = json!(2);
                v["accessors"][1]["count"] = json!(2);
            }),
        ),
        (
            "extensions.KHR_lights_punctual.lights[1].spot.outerConeAngle",
            Box::new(|v| {
                v["extensions"]["KHR_lights_punctual"]["lights"][1]["spot"]["outerConeAngle"] =
                    json!(std::f64::consts::FRAC_PI_2)
            }),
        ),
        (
            "extensions.KHR_lights_punctual.lights[0].intensity",
            Box::new(|v| {
                v["extensions"]["KHR_lights_punctual"]["lights"][0]["intensity"] = json!(-1.0)
            }),
        ),
        (
            "nodes[5].translation",
            Box::new(|v| v["nodes"][5]["translation"] = json!([0.0, 1e39, 0.0])),
        ),
        ("accessors[0]", Box::new(|v| set_buffer_f32(v, 1, f32::NAN))),
        (
            "nodes[1].rotation",
            Box::new(|v| v["nodes"][1]["rotation"] = json!([0.0, 0.0, 0.0, 2.0])),
        ),
        (
            "buffers[0]",
            Box::new(|v| v["buffers"][0]["uri"] = json!("no-such-file.bin")),
        ),
        (
            "meshes[1].primitives[0]",
            Box::new(|v| v["nodes"][2]["scale"] = json!([0.0, 1.0, 1.0])),
        ),
        (
            "nodes[2]",
            Box::new(|v| v["nodes"][2]["children"] = json!([1])),
        ),
        (
            "materials[1].pbrMetallicRoughness.baseColorFactor",
            Box::new(|v| {
                v["materials"][1]["pbrMetallicRoughness"]["baseColorFactor"] =
                    json!([2.0, 0.0, 0.0, 1.0])
            }),
        ),
    ];
    for (i, (path, mutate)) in cases.iter().enumerate() {
        let mut level = sample::level();
        mutate(&mut level);
        let err = import_scene(&format!("err{i}"), &level, "").expect_err(path);
        assert!(
            err.starts_with("scene.json:1:") && err.contains("level.gltf: ") && err.contains(path),
            "case {path}: the message must name the scene file, the glTF file and {path}:\n{err}"
        );
        let err = standalone(&format!("err-standalone{i}"), &level).expect_err(path);
        assert!(
            err.contains("level.gltf: ") && err.contains(path),
            "{path}:\n{err}"
        );
    }
}

/// Sets the `k`-th f32 of the embedded buffer (the floor's POSITION data comes first).
fn set_buffer_f32(level: &mut Value, k: usize, x: f32) {
    use base64::Engine;
    let engine = base64::engine::general_purpose::STANDARD;
    let uri = level["buffers"][0]["uri"].as_str().unwrap().to_string();
    let (head, data) = uri.split_once(";base64,").unwrap();
    let mut bin = engine.decode(data).unwrap();
    bin[4 * k..4 * k + 4].copy_from_slice(&x.to_le_bytes());
    level["buffers"][0]["uri"] = json!(format!("{head};base64,{}", engine.encode(bin)));
}

#[test]
fn the_scene_file_camera_wins_and_a_missing_camera_is_refused() {
    let cam = r#", "camera": {"position": [1, 2, 3], "look_at": [0, 0, 0]}"#;
    let s = import_scene("own-camera", &sample::level(), cam).unwrap();
    assert_eq!(s.desc.camera.position, Vec3::new(1.0, 2.0, 3.0));
    let mut level = sample::level();
    level["nodes"][8].as_object_mut().unwrap().remove("camera");
    assert!(import_scene("own-camera2", &level, cam).is_ok());
    let err = import_scene("no-camera", &level, "").unwrap_err();
    assert!(
        err.contains("scene.json") && err.contains("no perspective camera"),
        "{err}"
    );
    let err = standalone("no-camera-standalone", &level).unwrap_err();
    assert!(
        err.contains("level.gltf") && err.contains("perspective camera"),
        "{err}"
    );
}

#[test]
fn scene_file_lights_add_to_the_imported_ones() {
    let extra = r#", "lights": [{"kind": "point", "position": [0, 9, 0], "intensity": [5, 5, 5]}]"#;
    let s = import_scene("extra-light", &sample::level(), extra).unwrap();
    assert_eq!(s.desc.lights.len(), 4);
    let bad = r#", "lights": [{"kind": "point", "position": [0, 9, 0], "intensity": [-5, 5, 5]}]"#;
    let err = import_scene("bad-light", &sample::level(), bad).unwrap_err();
    assert!(err.contains("lights[0].intensity"), "{err}");
}

#[test]
fn a_gltf_file_alone_is_a_scene_with_the_documented_default_medium() {
    let s = standalone("alone", &sample::level()).unwrap();
    assert_eq!(s.name, "level");
    assert_eq!(s.desc.medium, scenes::gltf::scene::default_medium());
    let h = s.medium().homogeneous().unwrap();
    assert_eq!(h.sigma_t, Vec3::splat(0.022));
    let mut dark = sample::level();
    dark.as_object_mut().unwrap().remove("extensions");
    for n in dark["nodes"].as_array_mut().unwrap() {
        n.as_object_mut().unwrap().remove("extensions");
    }
    let err = standalone("dark", &dark).unwrap_err();
    assert!(err.contains("KHR_lights_punctual light"), "{err}");
}

#[test]
fn unmodelled_content_is_listed_with_its_gltf_path() {
    let mut level = sample::level();
    level["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"] = json!({"index": 0});
    level["materials"][1]["emissiveFactor"] = json!([1.0, 0.0, 0.0]);
    level["textures"] = json!([{"source": 0}]);
    level["images"] = json!([{"uri": "wood.png"}]);
    level["extensions"]["KHR_lights_punctual"]["lights"][0]["range"] = json!(10.0);
    level["meshes"][0]["primitives"][0]["mode"] = json!(4);
    let s = import_scene("ignored", &level, "").unwrap();
    let all = s.ignored.join("\n");
    for want in [
        "materials[0].pbrMetallicRoughness.baseColorTexture",
        "materials[1].emissiveFactor",
        "extensions.KHR_lights_punctual.lights[0].range",
    ] {
        assert!(all.contains(want), "{want} missing from:\n{all}");
    }
    assert!(s.ignored.iter().all(|l| l.contains("level.gltf")), "{all}");
    // Lines are never dropped silently: a points primitive is listed, not imported.
    level["meshes"][0]["primitives"][0]["mode"] = json!(0);
    let s = import_scene("ignored-points", &level, "").unwrap();
    assert_eq!(s.desc.objects.len(), 3);
    assert!(
        s.ignored
            .join("\n")
            .contains("meshes[0].primitives[0].mode")
    );
}

#[test]
fn a_glb_and_a_gltf_with_an_external_buffer_load_the_same_level() {
    let dir = scratch("forms");
    let level = sample::level();
    let glb = write(&dir, "level.glb", &sample::to_glb(&level).unwrap());
    let from_glb = load_scene(&glb).unwrap_or_else(|e| panic!("{e}"));
    let mut external = level.clone();
    let uri = level["buffers"][0]["uri"].as_str().unwrap();
    use base64::Engine;
    let bin = base64::engine::general_purpose::STANDARD
        .decode(uri.split_once(";base64,").unwrap().1)
        .unwrap();
    write(&dir, "level data.bin", &bin);
    external["buffers"][0]["uri"] = json!("level%20data.bin");
    let path = write(&dir, "external.gltf", external.to_string().as_bytes());
    let from_gltf = load_scene(&path).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(from_glb.meshes, from_gltf.meshes);
    assert_eq!(from_glb.desc.lights, from_gltf.desc.lights);
}

/// World-space triangles of a scene at frame 0, object by object.
fn world_triangles(s: &Scene) -> Vec<Vec<[Vec3; 3]>> {
    let f = s.frame(0);
    s.meshes
        .iter()
        .zip(&f.world_from_local)
        .map(|(m, w)| {
            m.indices
                .iter()
                .map(|t| t.map(|i| w.transform_point3(m.positions[i as usize])))
                .collect()
        })
        .collect()
}

/// Every library scene, exported and imported back as a scene by itself, has the same
/// triangles, lights, camera (within f32) and exactly the same medium and spot cones.
#[test]
fn every_library_scene_survives_export_and_import() {
    let dir = scratch("roundtrip");
    for name in library::names() {
        let original = library::resolve(name).unwrap();
        let path = write(&dir, &format!("{name}.glb"), &to_glb(&original).unwrap());
        let back = load_scene(&path).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!(back.desc.medium, original.desc.medium, "{name}: medium");
        assert_eq!(back.desc.description, original.desc.description, "{name}");
        let (a, b) = (world_triangles(&original), world_triangles(&back));
        assert_eq!(a.len(), b.len(), "{name}: objects");
        for (oa, ob) in a.iter().zip(&b) {
            assert_eq!(oa.len(), ob.len(), "{name}: triangles");
            for (ta, tb) in oa.iter().zip(ob) {
                for (pa, pb) in ta.iter().zip(tb) {
                    assert!(
                        (*pa - *pb).length() <= 1e-5 * (1.0 + pa.length()),
                        "{name}: {pa} vs {pb}"
                    );
                }
            }
        }
        for (oa, ob) in original.desc.objects.iter().zip(&back.desc.objects) {
            assert_eq!(oa.material, ob.material, "{name}: material");
            assert_eq!(
                oa.casts_volumetric_shadow, ob.casts_volumetric_shadow,
                "{name}"
            );
        }
        let (fa, fb) = (original.frame(0), back.frame(0));
        assert_eq!(fa.lights.len(), fb.lights.len(), "{name}: lights");
        for (la, lb) in fa.lights.iter().zip(&fb.lights) {
            assert_lights_match(name, la, lb);
        }
        let (ca, cb) = (fa.camera, fb.camera);
        assert!(
            (ca.position - cb.position).length() < 1e-5,
            "{name}: camera position"
        );
        let dir = |c: &scenes::CameraPose| (c.look_at - c.position).normalize();
        assert!(
            (dir(&ca) - dir(&cb)).length() < 1e-5,
            "{name}: camera direction"
        );
        assert!(
            ca.view_from_world().abs_diff_eq(cb.view_from_world(), 1e-4),
            "{name}: camera"
        );
        assert!((ca.fov_y_deg - cb.fov_y_deg).abs() < 1e-4);
        assert_eq!((ca.near, ca.far), (cb.near, cb.far), "{name}");
    }
}

fn assert_lights_match(name: &str, a: &LightState, b: &LightState) {
    let close =
        |x: Vec3, y: Vec3| (x - y).abs().max_element() <= 1e-5 * (1.0 + x.abs().max_element());
    match (a, b) {
        (
            LightState::Point {
                position: p,
                intensity: i,
            },
            LightState::Point {
                position: q,
                intensity: j,
            },
        ) => assert!(close(*p, *q) && close(*i, *j), "{name}: {a:?} vs {b:?}"),
        (
            LightState::Spot {
                position: p,
                direction: d,
                intensity: i,
                cos_inner: ci,
                cos_outer: co,
                pattern: pa,
                ..
            },
            LightState::Spot {
                position: q,
                direction: e,
                intensity: j,
                cos_inner: cj,
                cos_outer: cp,
                pattern: pb,
                ..
            },
        ) => {
            assert!(
                close(*p, *q) && close(*d, *e) && close(*i, *j),
                "{name}: {a:?} vs {b:?}"
            );
            assert_eq!(
                (ci, co, pa),
                (cj, cp, pb),
                "{name}: exact cones and pattern"
            );
        }
        (
            LightState::Directional {
                direction: d,
                irradiance: i,
            },
            LightState::Directional {
                direction: e,
                irradiance: j,
            },
        ) => assert!(close(*d, *e) && close(*i, *j), "{name}: {a:?} vs {b:?}"),
        _ => panic!("{name}: light kinds differ: {a:?} vs {b:?}"),
    }
}

/// Our exact values in extras are used only while they agree with the glTF fields: a spot
/// moved in another tool (its node) keeps the node's position, while a cone angle that still
/// agrees keeps its exact degrees.
#[test]
fn extras_yield_to_edited_gltf_fields() {
    let mut level = sample::level();
    let exact_inner: f32 = 17.188_734; // 0.3 rad in degrees, rounded to f32
    level["extensions"]["KHR_lights_punctual"]["lights"][1]["extras"] = json!({"scatterbench": {
        "position": [9.0, 9.0, 9.0], "inner_deg": exact_inner, "outer_deg": 45.0
    }});
    let s = import_scene("agree", &level, "").unwrap();
    let scenes::desc::LightDesc::Spot {
        position,
        inner_deg,
        outer_deg,
        ..
    } = &s.desc.lights[1]
    else {
        panic!("light 1 is the spot")
    };
    assert_eq!(
        *position,
        Vec3::new(-1.0, 5.0, -1.0),
        "the node wins over a stale extra"
    );
    assert_eq!(*inner_deg, exact_inner, "an agreeing extra is used exactly");
    assert!(
        (*outer_deg - 0.5f32.to_degrees()).abs() < 1e-4,
        "45° ≠ 0.5 rad: the glTF wins"
    );
}

/// An imported scene's description is self-contained: written out as JSON (its objects are
/// `gltf` shapes naming file, node and primitive) and parsed again, it builds the same meshes.
#[test]
fn an_imported_description_parses_back_to_the_same_scene() {
    let dir = scratch("described");
    write(&dir, "level.gltf", sample::level().to_string().as_bytes());
    let text = format!(r#"{{"import": "level.gltf", {MEDIUM}}}"#);
    let s = parse_scene(&text, "scene.json", "scene", &dir).unwrap();
    let again = serde_json::to_string(&s.desc).unwrap();
    assert!(again.contains(r#""kind":"gltf""#), "{again}");
    let back = parse_scene(&again, "again.json", "scene", &dir).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(back.desc, s.desc);
    assert_eq!(back.meshes, s.meshes);
    // The left pillar (node 2) shows mesh 1, which has one primitive.
    let mut missing = s.desc.clone();
    if let scenes::desc::Shape::Gltf { primitive, .. } = &mut missing.objects[1].shape {
        *primitive = 3;
    }
    let err = parse_scene(
        &serde_json::to_string(&missing).unwrap(),
        "m.json",
        "m",
        &dir,
    )
    .unwrap_err()
    .to_string();
    assert!(
        err.contains("objects[1].shape") && err.contains("meshes[1].primitives[3]"),
        "{err}"
    );
}
