//! The scene format from the outside: every library scene loads, validates and round-trips;
//! every file in `tests/broken/` is refused with exactly the problems its `.expect` sidecar
//! lists (field path, line and column), all at once, without panicking; keyframes interpolate
//! as documented.
//!
//! Expectations here are written by hand from the files (line and column of each offending
//! value, counted in the text), never copied from the code under test.

use std::collections::BTreeSet;
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::{Path, PathBuf};

use glam::{Mat4, Vec3};
use scenes::desc::{LightDesc, SceneDesc};
use scenes::load::SceneError;
use scenes::{LightState, Scene, library, load_scene, parse_scene};

fn tests_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests")
}

fn lib(name: &str) -> Scene {
    match library::load(name) {
        Some(Ok(s)) => s,
        Some(Err(e)) => panic!("library scene {name} does not load:\n{e}"),
        None => panic!("no library scene {name}"),
    }
}

// ---------------------------------------------------------------------------------------------
// Library
// ---------------------------------------------------------------------------------------------

#[test]
fn every_library_scene_loads_validates_and_renders_a_frame_state() {
    let names = library::names();
    assert_eq!(names.len(), 19, "{names:?}");
    for name in names {
        let s = lib(name);
        assert_eq!(s.name, name);
        assert_eq!(
            s.meshes.len(),
            s.desc.objects.len(),
            "{name}: one mesh per object"
        );
        assert!(
            !s.desc.description.is_empty(),
            "{name}: a library scene has a description for `list`"
        );
        for f in 0..s.frame_count() {
            let st = s.frame(f);
            assert_eq!(st.lights.len(), s.desc.lights.len());
            assert_eq!(st.world_from_local.len(), s.desc.objects.len());
            for l in &st.lights {
                if let LightState::Spot { direction, .. }
                | LightState::Directional { direction, .. } = l
                {
                    assert!(
                        (direction.length() - 1.0).abs() < 1e-6,
                        "{name}: light directions are unit"
                    );
                }
            }
            assert!(st.world_from_local.iter().all(|m| m.is_finite()));
        }
        // The same scene resolves by name.
        assert!(library::resolve(name).is_ok());
    }
}

#[test]
fn library_folder_and_embedded_list_agree() {
    // Every JSON file of scenes/library/ is in the list (and loads from disk to the same
    // description), and every listed scene has its file.
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("library");
    let mut on_disk: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .filter_map(|e| e.ok())
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|x| x == "json"))
        .map(|p| p.file_stem().unwrap().to_string_lossy().into_owned())
        .collect();
    on_disk.sort();
    let mut listed: Vec<String> = library::names().iter().map(|s| s.to_string()).collect();
    listed.sort();
    assert_eq!(on_disk, listed);
    for name in library::names() {
        let from_disk =
            load_scene(&dir.join(format!("{name}.json"))).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(from_disk.desc, lib(name).desc, "{name}");
        assert_eq!(from_disk.name, name);
        assert_eq!(
            from_disk.source.as_deref(),
            Some(dir.join(format!("{name}.json")).as_path())
        );
    }
}

#[test]
fn unknown_scene_names_are_refused_with_the_valid_ones() {
    let err = library::resolve("sphere-pointt").unwrap_err();
    for n in library::names() {
        assert!(err.contains(n), "the message lists {n}: {err}");
    }
    // A .json path that does not exist is an I/O error naming the file.
    let err = library::resolve("no/such/scene.json").unwrap_err();
    assert!(err.contains("no/such/scene.json"), "{err}");
}

/// Features, written by hand from the library files.
#[test]
fn library_features_match_what_the_files_say() {
    struct Want {
        name: &'static str,
        kinds: &'static [&'static str],
        lights: usize,
        phase: &'static str,
        textured: bool,
        occluders: bool,
        phong: bool,
        frames: u32,
        animated_lights: bool,
        animated_objects: bool,
        /// "homogeneous", or "particles" with this many particles.
        medium: &'static str,
        particles: usize,
    }
    let table = [
        Want {
            name: "sphere-point",
            kinds: &["point"],
            lights: 1,
            phase: "isotropic",
            textured: false,
            occluders: true,
            phong: false,
            frames: 1,
            animated_lights: false,
            animated_objects: false,
            medium: "homogeneous",
            particles: 0,
        },
        Want {
            name: "desk-pencils",
            kinds: &["point"],
            lights: 1,
            phase: "henyey-greenstein",
            textured: false,
            occluders: true,
            phong: true,
            frames: 1,
            animated_lights: false,
            animated_objects: false,
            medium: "homogeneous",
            particles: 0,
        },
        Want {
            name: "spring-point",
            kinds: &["point"],
            lights: 1,
            phase: "isotropic",
            textured: false,
            occluders: true,
            phong: false,
            frames: 1,
            animated_lights: false,
            animated_objects: false,
            medium: "homogeneous",
            particles: 0,
        },
        Want {
            name: "fence-spot",
            kinds: &["spot"],
            lights: 1,
            phase: "isotropic",
            textured: false,
            occluders: true,
            phong: false,
            frames: 1,
            animated_lights: false,
            animated_objects: false,
            medium: "homogeneous",
            particles: 0,
        },
        Want {
            name: "window-sun",
            kinds: &["directional"],
            lights: 1,
            phase: "rayleigh",
            textured: false,
            occluders: true,
            phong: false,
            frames: 1,
            animated_lights: false,
            animated_objects: false,
            medium: "homogeneous",
            particles: 0,
        },
        Want {
            name: "stained-glass-spot",
            kinds: &["spot"],
            lights: 1,
            phase: "hazy-mie",
            textured: true,
            occluders: true,
            phong: false,
            frames: 1,
            animated_lights: false,
            animated_objects: false,
            medium: "homogeneous",
            particles: 0,
        },
        Want {
            name: "overlap-point",
            kinds: &["point"],
            lights: 1,
            phase: "isotropic",
            textured: false,
            occluders: true,
            phong: false,
            frames: 1,
            animated_lights: false,
            animated_objects: false,
            medium: "homogeneous",
            particles: 0,
        },
        Want {
            name: "clear-fog",
            kinds: &["point"],
            lights: 1,
            phase: "isotropic",
            textured: false,
            occluders: false,
            phong: false,
            frames: 1,
            animated_lights: false,
            animated_objects: false,
            medium: "homogeneous",
            particles: 0,
        },
        Want {
            name: "pen-orbit",
            kinds: &["point"],
            lights: 2,
            phase: "isotropic",
            textured: false,
            occluders: true,
            phong: true,
            frames: 8,
            animated_lights: true,
            animated_objects: true,
            medium: "homogeneous",
            particles: 0,
        },
        Want {
            name: "cloud-8000",
            kinds: &["directional"],
            lights: 1,
            phase: "henyey-greenstein",
            textured: false,
            occluders: true,
            phong: false,
            frames: 1,
            animated_lights: false,
            animated_objects: false,
            medium: "particles",
            particles: 8000,
        },
        Want {
            name: "cloud-plane",
            kinds: &["directional"],
            lights: 1,
            phase: "isotropic",
            textured: false,
            occluders: true,
            phong: false,
            frames: 1,
            animated_lights: false,
            animated_objects: false,
            medium: "particles",
            particles: 3000,
        },
        Want {
            name: "cloud-blocks",
            kinds: &["directional"],
            lights: 1,
            phase: "henyey-greenstein",
            textured: false,
            occluders: true,
            phong: false,
            frames: 1,
            animated_lights: false,
            animated_objects: false,
            medium: "particles",
            particles: 8000,
        },
        Want {
            name: "smoke-point",
            kinds: &["point"],
            lights: 1,
            phase: "henyey-greenstein",
            textured: false,
            occluders: true,
            phong: false,
            frames: 1,
            animated_lights: false,
            animated_objects: false,
            medium: "particles",
            particles: 3000,
        },
        Want {
            name: "indirect-point",
            kinds: &["point"],
            lights: 1,
            phase: "henyey-greenstein",
            textured: false,
            occluders: true,
            phong: true,
            frames: 1,
            animated_lights: false,
            animated_objects: false,
            medium: "homogeneous",
            particles: 0,
        },
        Want {
            name: "valley-sun",
            kinds: &["directional"],
            lights: 1,
            phase: "henyey-greenstein",
            textured: false,
            occluders: true,
            phong: false,
            frames: 1,
            animated_lights: false,
            animated_objects: false,
            medium: "homogeneous",
            particles: 0,
        },
        Want {
            name: "corridor-walk",
            kinds: &["point", "spot"],
            lights: 2,
            phase: "henyey-greenstein",
            textured: false,
            occluders: true,
            phong: false,
            frames: 60,
            // The flashlight rides on the moving camera.
            animated_lights: true,
            animated_objects: false,
            medium: "homogeneous",
            particles: 0,
        },
        Want {
            name: "colonnade-flight",
            kinds: &["directional"],
            lights: 1,
            phase: "henyey-greenstein",
            textured: false,
            occluders: true,
            phong: false,
            frames: 60,
            animated_lights: false,
            animated_objects: false,
            medium: "homogeneous",
            particles: 0,
        },
        Want {
            name: "atrium",
            kinds: &["directional", "point", "spot"],
            lights: 19,
            phase: "henyey-greenstein",
            textured: false,
            occluders: true,
            phong: false,
            frames: 1,
            animated_lights: false,
            animated_objects: false,
            medium: "homogeneous",
            particles: 0,
        },
        Want {
            name: "atrium-64",
            kinds: &["directional", "point", "spot"],
            lights: 65,
            phase: "henyey-greenstein",
            textured: false,
            occluders: true,
            phong: false,
            frames: 1,
            animated_lights: false,
            animated_objects: false,
            medium: "homogeneous",
            particles: 0,
        },
    ];
    assert_eq!(
        table.len(),
        library::names().len(),
        "every library scene is in the table"
    );
    for w in &table {
        let s = lib(w.name);
        let f = s.features();
        let n = w.name;
        assert_eq!(f.medium, w.medium, "{n}");
        assert_eq!(f.particles, w.particles, "{n}");
        // The expanded medium agrees with the feature count.
        match s.medium() {
            scenes::Medium::Homogeneous(_) => assert_eq!(w.medium, "homogeneous", "{n}"),
            scenes::Medium::Particles(p) => assert_eq!(p.particles.len(), w.particles, "{n}"),
        }
        assert_eq!(f.light_kinds, w.kinds, "{n}");
        assert_eq!(f.lights, w.lights, "{n}");
        assert_eq!(f.phase, w.phase, "{n}");
        assert_eq!(f.anisotropic_phase, w.phase != "isotropic", "{n}");
        assert_eq!(f.textured_light, w.textured, "{n}");
        assert_eq!(f.volumetric_occluders, w.occluders, "{n}");
        assert_eq!(f.phong, w.phong, "{n}");
        assert_eq!(f.frames, w.frames, "{n}");
        assert_eq!(f.animated_lights, w.animated_lights, "{n}");
        assert_eq!(f.animated_objects, w.animated_objects, "{n}");
        let moving_camera = matches!(n, "corridor-walk" | "colonnade-flight");
        assert_eq!(
            f.animated_camera, moving_camera,
            "{n}: the walk and the flight move"
        );
        assert_eq!(
            f.animated,
            w.animated_lights || w.animated_objects || moving_camera,
            "{n}"
        );
        assert!(f.scattering, "{n}: every library scene scatters");
        assert!(!f.ambient, "{n}: no library scene has ambient light");
        assert!(f.surfaces, "{n}: every library scene has a floor");
        assert_eq!(f.indirect_single_scattering, n == "indirect-point", "{n}");
        assert_eq!(f.height_fog, n == "valley-sun", "{n}");
        assert_eq!(
            f.triangles,
            s.meshes.iter().map(|m| m.indices.len()).sum::<usize>(),
            "{n}"
        );
    }
    // Triangle counts that follow from the procedural definitions: a plane is 2 triangles, a
    // UV sphere of 48 segments × 24 rings is 2·48·23.
    assert_eq!(lib("sphere-point").features().triangles, 2 + 2 * 48 * 23);
    assert_eq!(lib("clear-fog").features().triangles, 2);
}

#[test]
fn every_library_scene_round_trips_through_json() {
    for name in library::names() {
        let s = lib(name);
        let text = serde_json::to_string_pretty(&s.desc).unwrap();
        let back: SceneDesc =
            serde_json::from_str(&text).unwrap_or_else(|e| panic!("{name}: {e}\n{text}"));
        assert_eq!(back, s.desc, "{name}: serde round trip");
        // And through the full loader (validation, meshes): the same scene.
        let again = parse_scene(&text, "roundtrip.json", name, Path::new("."))
            .unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!(again.desc, s.desc, "{name}: parse_scene round trip");
        assert_eq!(again.meshes.len(), s.meshes.len());
        for (a, b) in again.meshes.iter().zip(&s.meshes) {
            assert_eq!(**a, **b, "{name}: same meshes");
        }
        assert_eq!(again.features(), s.features());
        for f in 0..s.frame_count() {
            assert_eq!(again.frame(f), s.frame(f), "{name} frame {f}");
        }
    }
}

#[test]
fn a_scene_may_use_an_obj_file_next_to_it() {
    let s =
        load_scene(&tests_dir().join("fixtures/obj-scene.json")).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(s.triangle_count(), 4);
    let m = &s.meshes[0];
    assert_eq!(m.positions.len(), m.normals.len());
    // Its bounds are the file's vertices.
    let (lo, hi) = m.bounds(&Mat4::IDENTITY);
    assert_eq!(
        (lo, hi),
        (Vec3::new(0.0, 0.0, -1.0), Vec3::new(1.0, 1.0, 0.0))
    );
}

// ---------------------------------------------------------------------------------------------
// Broken files
// ---------------------------------------------------------------------------------------------

/// One expected problem: 1-based line and column of the offending value (or, for syntax
/// errors, of where the parser stopped), its field path, and a fragment of the message.
#[derive(Debug, Clone, PartialEq, Eq, PartialOrd, Ord)]
struct Expected {
    line: usize,
    column: usize,
    path: String,
    fragment: String,
}

fn read_expect(path: &Path) -> Vec<Expected> {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    text.lines()
        .filter(|l| !l.trim().is_empty() && !l.trim_start().starts_with('#'))
        .map(|l| {
            let (head, fragment) = l
                .split_once(" | ")
                .unwrap_or_else(|| panic!("{}: bad line {l:?}", path.display()));
            let (pos, field) = head.split_once(' ').unwrap_or((head, ""));
            let (line, column) = pos.split_once(':').unwrap();
            Expected {
                line: line.parse().unwrap(),
                column: column.parse().unwrap(),
                path: field.trim().to_string(),
                fragment: fragment.trim().to_string(),
            }
        })
        .collect()
}

/// Parses one line of `SceneError`'s Display: `file:line:col: path: message` (path may be absent
/// on syntax errors at the document's root).
fn parse_line(file: &str, line: &str) -> (usize, usize, String, String) {
    let rest = line
        .strip_prefix(file)
        .and_then(|r| r.strip_prefix(':'))
        .unwrap_or_else(|| panic!("{line:?} does not start with {file:?}:"));
    let mut it = rest.splitn(3, ':');
    let l = it
        .next()
        .unwrap()
        .parse()
        .unwrap_or_else(|_| panic!("no line number in {line:?}"));
    let c = it
        .next()
        .unwrap()
        .parse()
        .unwrap_or_else(|_| panic!("no column in {line:?}"));
    let rest = it.next().unwrap().strip_prefix(' ').unwrap();
    match rest.split_once(": ") {
        Some((p, m)) if !p.contains(' ') => (l, c, p.to_string(), m.to_string()),
        _ => (l, c, String::new(), rest.to_string()),
    }
}

#[test]
fn broken_scene_files_are_refused_with_every_problem_located() {
    let dir = tests_dir().join("broken");
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    files.sort();
    let jsons: Vec<&PathBuf> = files
        .iter()
        .filter(|p| p.extension().is_some_and(|x| x == "json"))
        .collect();
    let expects: BTreeSet<PathBuf> = files
        .iter()
        .filter(|p| p.extension().is_some_and(|x| x == "expect"))
        .cloned()
        .collect();
    assert!(jsons.len() >= 10, "only {} broken files", jsons.len());
    assert_eq!(
        expects.len(),
        jsons.len(),
        "one .expect per .json: {files:?}"
    );
    let mut failures = Vec::new();
    let mut multi = 0;
    for path in jsons {
        let expect_path = path.with_extension("expect");
        assert!(
            expects.contains(&expect_path),
            "{} has no .expect sidecar",
            path.display()
        );
        let want = read_expect(&expect_path);
        let file = path.display().to_string();
        let got = match catch_unwind(AssertUnwindSafe(|| load_scene(path))) {
            Err(_) => {
                failures.push(format!("{file}: load_scene panicked"));
                continue;
            }
            Ok(Ok(_)) => {
                failures.push(format!("{file}: accepted"));
                continue;
            }
            Ok(Err(e)) => e,
        };
        let shown = got.to_string();
        let lines: Vec<&str> = shown.lines().collect();
        // The structured error and its text agree on the number of problems.
        let count = match &got {
            SceneError::Invalid { problems, .. } => problems.len(),
            SceneError::Syntax { .. } => 1,
            SceneError::Io { .. } => panic!("{file}: unexpected I/O error {shown}"),
        };
        assert_eq!(count, lines.len(), "{file}: {shown}");
        if want.len() > 1 {
            multi += 1;
        }
        let mut got_set: Vec<Expected> = Vec::new();
        for l in &lines {
            let (line, column, p, message) = parse_line(&file, l);
            got_set.push(Expected {
                line,
                column,
                path: p,
                fragment: message,
            });
        }
        let mut unmatched: Vec<Expected> = got_set.clone();
        let mut missing = Vec::new();
        for w in &want {
            match unmatched.iter().position(|g| {
                g.line == w.line
                    && g.column == w.column
                    && g.path == w.path
                    && g.fragment.contains(&w.fragment)
            }) {
                Some(k) => {
                    unmatched.remove(k);
                }
                None => missing.push(w.clone()),
            }
        }
        if !missing.is_empty() || !unmatched.is_empty() {
            failures.push(format!("{file}:\n  missing {missing:#?}\n  unexpected {unmatched:#?}\n  full message:\n{shown}"));
        }
    }
    assert!(multi >= 1, "at least one file has several problems");
    assert!(failures.is_empty(), "{}", failures.join("\n\n"));
}

/// Every located position points at the start of a JSON value in the file (an independent
/// check of the locator: the character before it, ignoring spaces, is `:` `[` or `,`).
#[test]
fn semantic_problem_positions_point_at_values() {
    let dir = tests_dir().join("broken");
    for e in std::fs::read_dir(&dir).unwrap() {
        let path = e.unwrap().path();
        if path.extension().is_none_or(|x| x != "json") {
            continue;
        }
        let text = std::fs::read_to_string(&path).unwrap();
        let Err(SceneError::Invalid { problems, .. }) = load_scene(&path) else {
            continue;
        };
        for p in problems {
            let (Some(l), Some(c)) = (p.line, p.column) else {
                panic!("{}: {} has no position", path.display(), p.problem.path)
            };
            let line: Vec<char> = text.lines().nth(l - 1).unwrap().chars().collect();
            let ch = line[c - 1];
            assert!(
                matches!(ch, '[' | '{' | '"' | '-' | '0'..='9' | 't' | 'f' | 'n'),
                "{}:{l}:{c}: {ch:?} starts no value",
                path.display()
            );
            let before: String = line[..c - 1].iter().collect();
            let prev = before.trim_end().chars().last();
            // A value at the start of a line follows the previous line's `[` or `,`.
            assert!(
                matches!(prev, Some(':' | '[' | ',') | None),
                "{}:{l}:{c}: preceded by {prev:?}",
                path.display()
            );
        }
    }
}

/// Mutates every number of every library scene to hostile values; loading must return Ok or a
/// located error, never panic, and a scene that loads must give finite frame states.
#[test]
fn hostile_numbers_never_panic() {
    let hostile = [
        "-1",
        "0",
        "1e39",
        "-1e39",
        "1e-39",
        "4294967296",
        "0.5",
        "1000000",
    ];
    let mut refused = 0;
    let mut accepted = 0;
    for (name, text) in library::LIBRARY {
        let spans = number_spans(text);
        assert!(spans.len() > 10, "{name}");
        for &(a, b) in &spans {
            for h in hostile {
                let mutated = format!("{}{}{}", &text[..a], h, &text[b..]);
                let r = catch_unwind(AssertUnwindSafe(|| {
                    parse_scene(&mutated, "m.json", name, Path::new(".")).map(|s| {
                        let st = s.frame(0);
                        let _ = s.features();
                        st.lights.iter().all(|l| match l {
                            LightState::Point { position, .. } => position.is_finite(),
                            LightState::Spot {
                                position,
                                direction,
                                ..
                            } => position.is_finite() && direction.is_finite(),
                            LightState::Directional { direction, .. } => direction.is_finite(),
                        })
                    })
                }));
                match r {
                    Err(_) => panic!(
                        "{name}: panicked with {h} at byte {a}: ...{}...",
                        &mutated[a.saturating_sub(40)..(a + 40).min(mutated.len())]
                    ),
                    Ok(Ok(finite)) => {
                        assert!(finite, "{name}: {h} at byte {a} gives a non-finite light");
                        accepted += 1;
                    }
                    Ok(Err(e)) => {
                        let s = e.to_string();
                        assert!(s.starts_with("m.json"), "{s}");
                        refused += 1;
                    }
                }
            }
        }
    }
    assert!(
        refused > 100 && accepted > 100,
        "refused {refused}, accepted {accepted}"
    );
}

/// Byte spans of the numeric literals of a JSON text (outside strings).
fn number_spans(text: &str) -> Vec<(usize, usize)> {
    let b = text.as_bytes();
    let mut out = Vec::new();
    let mut i = 0;
    let mut in_str = false;
    while i < b.len() {
        let c = b[i];
        if in_str {
            if c == b'\\' {
                i += 1;
            } else if c == b'"' {
                in_str = false;
            }
            i += 1;
            continue;
        }
        if c == b'"' {
            in_str = true;
            i += 1;
            continue;
        }
        if c == b'-' || c.is_ascii_digit() {
            let s = i;
            i += 1;
            while i < b.len()
                && (b[i].is_ascii_digit() || matches!(b[i], b'.' | b'e' | b'E' | b'+' | b'-'))
            {
                i += 1;
            }
            out.push((s, i));
            continue;
        }
        i += 1;
    }
    out
}

// ---------------------------------------------------------------------------------------------
// Keyframes
// ---------------------------------------------------------------------------------------------

fn point_position(l: &LightState) -> Vec3 {
    match l {
        LightState::Point { position, .. } => *position,
        other => panic!("not a point light: {other:?}"),
    }
}

/// T · Rz · Ry · Rx · S, composed from single-axis rotations (not the Euler helper the crate uses).
fn trs(t: Vec3, deg: Vec3, s: Vec3) -> Mat4 {
    Mat4::from_translation(t)
        * Mat4::from_rotation_z(deg.z.to_radians())
        * Mat4::from_rotation_y(deg.y.to_radians())
        * Mat4::from_rotation_x(deg.x.to_radians())
        * Mat4::from_scale(s)
}

#[test]
fn pen_orbit_keyframes_interpolate_linearly() {
    let s = lib("pen-orbit");
    assert_eq!(s.frame_count(), 8);
    let (a, b) = (Vec3::new(2.2, 2.8, -1.0), Vec3::new(2.2, 2.8, 1.0));
    // The keyed positions at the keyed frames.
    assert!((point_position(&s.frame(0).lights[1]) - a).length() < 1e-6);
    assert!((point_position(&s.frame(7).lights[1]) - b).length() < 1e-6);
    for k in 0..8u32 {
        let st = s.frame(k);
        // The static light does not move; the keyed one moves along the straight line.
        assert_eq!(point_position(&st.lights[0]), Vec3::new(-2.2, 2.8, 0.0));
        let want = a + (b - a) * (k as f32 / 7.0);
        assert!(
            (point_position(&st.lights[1]) - want).length() < 1e-6,
            "frame {k}"
        );
        // The pen turns about Y from 90° to 405° (45° per frame), still tipped 90° about X.
        let m = trs(
            Vec3::new(0.0, 1.6, -0.8),
            Vec3::new(90.0, 90.0 + 45.0 * k as f32, 0.0),
            Vec3::ONE,
        );
        let got = st.world_from_local[1];
        assert!(got.abs_diff_eq(m, 1e-5), "frame {k}: {got:?} vs {m:?}");
        assert_eq!(
            st.world_from_local[0],
            Mat4::IDENTITY,
            "the floor does not move"
        );
        assert_eq!(st.camera, s.frame(0).camera);
    }
    // Frame 3.5 is halfway: frames are integers, so it is the mean of frames 3 and 4 (the
    // motion is linear), and exactly frame 7 of the same animation stretched over 15 frames.
    let mid = 0.5 * (point_position(&s.frame(3).lights[1]) + point_position(&s.frame(4).lights[1]));
    assert!((mid - 0.5 * (a + b)).length() < 1e-6, "{mid}");
    let mut stretched = s.desc.clone();
    stretched.frames = 15;
    if let LightDesc::Point { keyframes, .. } = &mut stretched.lights[1] {
        for k in keyframes.iter_mut() {
            k.frame *= 2.0;
        }
    }
    for k in &mut stretched.objects[1].keyframes {
        k.frame *= 2.0;
    }
    let text = serde_json::to_string(&stretched).unwrap();
    let st = parse_scene(&text, "stretched.json", "stretched", Path::new("."))
        .unwrap()
        .frame(7);
    assert!((point_position(&st.lights[1]) - 0.5 * (a + b)).length() < 1e-6);
    let m = trs(
        Vec3::new(0.0, 1.6, -0.8),
        Vec3::new(90.0, 247.5, 0.0),
        Vec3::ONE,
    );
    assert!(st.world_from_local[1].abs_diff_eq(m, 1e-5));
    // Outside the keys the last key holds.
    assert!((point_position(&s.frame(20).lights[1]) - b).length() < 1e-6);
}

#[test]
fn keys_may_come_in_any_order_and_animate_direction_and_camera() {
    let text = r#"{
      "camera": { "position": [0, 1, 5], "look_at": [0, 1, 0],
                  "keyframes": [ { "frame": 4, "position": [4, 1, 5], "look_at": [0, 1, 0] },
                                 { "frame": 0, "position": [0, 1, 5], "look_at": [0, 1, 0] } ] },
      "medium": { "kind": "homogeneous", "sigma_a": [0, 0, 0], "sigma_s": [0.1, 0.1, 0.1] },
      "lights": [ { "kind": "directional", "direction": [0, -1, 0], "irradiance": [1, 1, 1],
                    "keyframes": [ { "frame": 4, "direction": [1, -1, 0] }, { "frame": 0, "direction": [-1, -1, 0] } ] } ],
      "frames": 5
    }"#;
    let s =
        parse_scene(text, "keys.json", "keys", Path::new(".")).unwrap_or_else(|e| panic!("{e}"));
    let f = s.features();
    assert!(f.animated && f.animated_camera && f.animated_lights && !f.animated_objects);
    let st = s.frame(2);
    assert!((st.camera.position - Vec3::new(2.0, 1.0, 5.0)).length() < 1e-6);
    match st.lights[0] {
        // Halfway between (-1,-1,0) and (1,-1,0) is straight down, normalised.
        LightState::Directional { direction, .. } => {
            assert!((direction - Vec3::NEG_Y).length() < 1e-6, "{direction}")
        }
        ref o => panic!("{o:?}"),
    }
}

/// Direction keys are normalised before they are interpolated (scenes/README "Keyframes"): a
/// long key does not pull the halfway direction toward itself.
#[test]
fn direction_keys_are_normalised_before_interpolation() {
    let text = r#"{
      "camera": { "position": [0, 1, 5], "look_at": [0, 1, 0] },
      "medium": { "kind": "homogeneous", "sigma_a": [0, 0, 0], "sigma_s": [0.1, 0.1, 0.1] },
      "lights": [ { "kind": "spot", "position": [0, 3, 0], "direction": [0, -1, 0],
                    "inner_deg": 10, "outer_deg": 20, "intensity": [1, 1, 1],
                    "keyframes": [ { "frame": 0, "direction": [0, -10, 0] }, { "frame": 2, "direction": [1, 0, 0] } ] } ],
      "frames": 3
    }"#;
    let s =
        parse_scene(text, "keys.json", "keys", Path::new(".")).unwrap_or_else(|e| panic!("{e}"));
    match s.frame(1).lights[0] {
        // Halfway between the unit keys (0,−1,0) and (1,0,0): (1,−1,0)/√2. Interpolating the
        // raw keys would give (0.5,−5,0)/|…|, 5.7° from straight down.
        LightState::Spot { direction, .. } => {
            let want = Vec3::new(1.0, -1.0, 0.0).normalize();
            assert!((direction - want).length() < 1e-6, "{direction}")
        }
        ref o => panic!("{o:?}"),
    }
}

// ---------------------------------------------------------------------------------------------
// The documentation's example
// ---------------------------------------------------------------------------------------------

/// The complete example of `scenes/README.md` (its first ```json block) is a valid scene that
/// uses what it claims to.
#[test]
fn readme_example_is_a_valid_scene() {
    let readme =
        std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("README.md")).unwrap();
    let start = readme
        .find("```json\n")
        .expect("README has a ```json block")
        + "```json\n".len();
    let end = start + readme[start..].find("\n```").unwrap();
    let s = parse_scene(&readme[start..end], "README.md", "example", Path::new("."))
        .unwrap_or_else(|e| panic!("{e}"));
    let f = s.features();
    assert_eq!(f.light_kinds, ["directional", "point", "spot"]);
    assert!(f.textured_light && f.phong && f.anisotropic_phase && f.volumetric_occluders);
    assert!(f.animated_camera && f.animated_lights && f.animated_objects);
    assert_eq!(f.frames, 4);
    assert!(
        s.desc
            .objects
            .iter()
            .any(|o| !o.casts_volumetric_shadow && o.material.two_sided)
    );
    // Every field the format has appears in the example (so it is "complete"): the JSON keys of
    // the re-serialised description, all of which must occur in the example's text.
    let v = serde_json::to_value(&s.desc).unwrap();
    let mut keys = BTreeSet::new();
    collect_keys(&v, &mut keys);
    for k in keys {
        assert!(
            readme[start..end].contains(&format!("\"{k}\"")),
            "the README example lacks the field {k:?}"
        );
    }
}

fn collect_keys(v: &serde_json::Value, out: &mut BTreeSet<String>) {
    match v {
        serde_json::Value::Object(m) => {
            for (k, x) in m {
                out.insert(k.clone());
                collect_keys(x, out);
            }
        }
        serde_json::Value::Array(a) => a.iter().for_each(|x| collect_keys(x, out)),
        _ => {}
    }
}

/// A particle medium with a problem in every field is refused with each field's path, at once.
#[test]
fn particle_media_problems_are_listed_with_their_paths() {
    let text = r#"{"camera": {"position": [0, 0, 5], "look_at": [0, 0, 0]},
        "medium": {"kind": "particles",
            "particles": [{"center": [0, 0, 0], "radius": -1, "density": -2, "albedo": [1.5, 0, 0]}],
            "generators": [{"shape": "cloud", "count": 0, "center": [0, 0, 0], "radii": [1, 0, 1],
                            "particle_radius": [0.3, 0.1], "density": 1}],
            "background": {"sigma_a": [-1, 0, 0], "sigma_s": [0, 0, 0]},
            "sky": [0, -1, 0]},
        "lights": [{"kind": "point", "position": [0, 3, 0], "intensity": [1, 1, 1]}]}"#;
    let err = parse_scene(text, "p.json", "p", Path::new("."))
        .expect_err("refused")
        .to_string();
    for path in [
        "medium.particles[0].radius",
        "medium.particles[0].density",
        "medium.particles[0].albedo",
        "medium.generators[0].count",
        "medium.generators[0].radii",
        "medium.generators[0].particle_radius",
        "medium.background.sigma_a",
        "medium.sky",
    ] {
        assert!(err.contains(path), "{path} missing from:\n{err}");
    }
    // No particles at all is refused too; a misspelt generator field is a parse error.
    let empty = text.replace(
        r#""particles": [{"center": [0, 0, 0], "radius": -1, "density": -2, "albedo": [1.5, 0, 0]}],
            "generators": [{"shape": "cloud", "count": 0, "center": [0, 0, 0], "radii": [1, 0, 1],
                            "particle_radius": [0.3, 0.1], "density": 1}],"#,
        "",
    );
    assert_ne!(empty, text);
    let err = parse_scene(&empty, "p.json", "p", Path::new("."))
        .err()
        .unwrap()
        .to_string();
    assert!(err.contains("at least one particle"), "{err}");
    let typo = text.replace("\"radii\"", "\"radius\"");
    assert!(parse_scene(&typo, "p.json", "p", Path::new(".")).is_err());
}

/// cloud-blocks declares its structure: one block of 200 particles instanced 40 times, and the
/// medium's particles are exactly those instances' copies of the block, instance after instance.
#[test]
fn cloud_blocks_exposes_its_block_and_instances() {
    let s = lib("cloud-blocks");
    let m = s.medium();
    let p = m.particles().expect("a particle medium");
    assert_eq!(p.blocks.len(), 1);
    let b = &p.blocks[0];
    assert_eq!((b.block.len(), b.instances.len()), (200, 40));
    assert_eq!(p.particles.len(), 200 * 40);
    for (k, i) in b.instances.iter().enumerate() {
        assert_eq!(i.first, 200 * k);
        assert!((0.8..=1.25).contains(&i.scale), "{}", i.scale);
        for (j, q) in b.block.iter().enumerate() {
            assert_eq!(p.particles[i.first + j], i.place(q));
        }
    }
    // A misspelt field inside a block or the placement is a parse error naming it (serde
    // reports tagged generators at the end of the buffered value, so the line is not checked).
    let (_, text) = library::LIBRARY
        .iter()
        .find(|(n, _)| *n == "cloud-blocks")
        .unwrap();
    for (from, to) in [
        ("\"radii\": [0.75", "\"radius\": [0.75"),
        ("\"count\": 40", "\"cuont\": 40"),
    ] {
        let bad = text.replace(from, to);
        assert_ne!(&bad, text);
        let err = parse_scene(&bad, "c.json", "c", Path::new("."))
            .err()
            .unwrap()
            .to_string();
        let field = to.split('"').nth(1).unwrap();
        assert!(err.contains(&format!("unknown field `{field}`")), "{err}");
    }
}
