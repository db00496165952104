//! A spot attached to the camera (a flashlight, `"attached_to_camera": true`): its file
//! position and direction are in camera space (x right, y up, −z forward) and resolve to world
//! space from the camera's pose at every frame. The expected poses here are built from the
//! camera's basis by hand (forward = look_at − position, right = forward × up, up' = right ×
//! forward), not with the view matrices the scene code uses.

use std::path::Path;

use glam::{DVec3, Vec3};
use scenes::{LightState, Scene, parse_scene};

fn scene(text: &str) -> Scene {
    parse_scene(text, "test.json", "test", Path::new(".")).unwrap_or_else(|e| panic!("{e}"))
}

/// Camera keys (frame, position, look_at) of a walk that turns, climbs and sways.
const KEYS: [(f64, [f64; 3], [f64; 3]); 3] = [
    (0.0, [-1.0, 1.6, 6.0], [0.5, 1.2, -3.0]),
    (4.0, [0.5, 2.1, 3.0], [-2.0, 1.0, -4.0]),
    (9.0, [2.0, 1.4, 0.5], [4.0, 2.5, -6.0]),
];
const UP: [f64; 3] = [0.1, 1.0, 0.2];
const OFFSET: [f64; 3] = [0.3, -0.25, 0.1];
const AIM: [f64; 3] = [-0.1, -0.15, -1.0];

fn vec3(v: [f64; 3]) -> String {
    format!("[{}, {}, {}]", v[0], v[1], v[2])
}

/// A 10-frame scene of one spot `light` (JSON fields after `"kind": "spot"`) on a camera
/// standing at the first of [`KEYS`] with `keys` (JSON, possibly empty).
fn spot_scene(keys: &str, light: &str) -> String {
    format!(
        r#"{{
  "camera": {{ "position": {}, "look_at": {}, "up": {}, "keyframes": [{keys}] }},
  "medium": {{ "kind": "homogeneous", "sigma_a": [0.01, 0.01, 0.01], "sigma_s": [0.1, 0.1, 0.1] }},
  "lights": [ {{ "kind": "spot", {light}, "inner_deg": 10, "outer_deg": 20, "intensity": [10, 10, 10] }} ],
  "frames": 10
}}"#,
        vec3(KEYS[0].1),
        vec3(KEYS[0].2),
        vec3(UP)
    )
}

/// [`KEYS`] as JSON camera keys.
fn keys_json() -> String {
    KEYS.iter()
        .map(|(f, p, l)| {
            format!(
                r#"{{"frame": {f}, "position": {}, "look_at": {}}}"#,
                vec3(*p),
                vec3(*l)
            )
        })
        .collect::<Vec<_>>()
        .join(", ")
}

/// A scene of one flashlight on a camera with [`KEYS`] (or static at the first key).
fn flashlight_scene(animated: bool) -> String {
    let keys = if animated { keys_json() } else { String::new() };
    let light = format!(
        r#""attached_to_camera": true, "position": {}, "direction": {}"#,
        vec3(OFFSET),
        vec3(AIM)
    );
    spot_scene(&keys, &light)
}

/// The camera's (position, look_at) at frame f: linear between [`KEYS`], held outside.
fn pose_at(f: f64) -> (DVec3, DVec3) {
    let d = |v: [f64; 3]| DVec3::from_array(v);
    let k = KEYS.iter().rposition(|k| k.0 <= f).unwrap_or(0);
    if k + 1 == KEYS.len() {
        return (d(KEYS[k].1), d(KEYS[k].2));
    }
    let (a, b) = (&KEYS[k], &KEYS[k + 1]);
    let t = (f - a.0) / (b.0 - a.0);
    (d(a.1).lerp(d(b.1), t), d(a.2).lerp(d(b.2), t))
}

/// The camera-space offset and aim carried to world space by hand.
fn expected(f: f64) -> (DVec3, DVec3) {
    let (eye, target) = pose_at(f);
    let forward = (target - eye).normalize();
    let right = forward.cross(DVec3::from_array(UP)).normalize();
    let up = right.cross(forward);
    // Camera space: x right, y up, and −z forward, so +z points backward.
    let to_world = |v: [f64; 3]| right * v[0] + up * v[1] - forward * v[2];
    (eye + to_world(OFFSET), to_world(AIM).normalize())
}

fn spot(s: &Scene, frame: u32) -> (Vec3, Vec3) {
    match &s.frame(frame).lights[0] {
        LightState::Spot {
            position,
            direction,
            ..
        } => (*position, *direction),
        other => panic!("expected a spot, got {other:?}"),
    }
}

#[test]
fn a_flashlight_follows_the_moving_camera_with_its_camera_space_offset() {
    let s = scene(&flashlight_scene(true));
    let mut seen = Vec::new();
    for frame in [0u32, 2, 4, 7, 9] {
        let (p, d) = spot(&s, frame);
        let (want_p, want_d) = expected(frame as f64);
        assert!(
            (p.as_dvec3() - want_p).length() < 1e-5,
            "frame {frame}: position {p}, expected {want_p}"
        );
        assert!(
            (d.as_dvec3() - want_d).length() < 1e-5,
            "frame {frame}: direction {d}, expected {want_d}"
        );
        seen.push(p);
    }
    // The light really moves with the camera (the check above is not met by a fixed pose).
    assert!((seen[0] - seen[2]).length() > 1.0 && (seen[2] - seen[4]).length() > 1.0);
    let f = s.features();
    assert!(f.animated_camera && f.animated_lights && f.animated);
}

#[test]
fn a_flashlight_on_a_static_camera_is_the_equivalent_world_space_spot() {
    let attached = scene(&flashlight_scene(false));
    let (want_p, want_d) = expected(0.0);
    let world = scene(&spot_scene(
        "",
        &format!(
            r#""position": {}, "direction": {}"#,
            vec3(want_p.to_array()),
            vec3(want_d.to_array())
        ),
    ));
    for frame in [0, 5, 9] {
        let (a, b) = (spot(&attached, frame), spot(&world, frame));
        assert!((a.0 - b.0).length() < 1e-5, "frame {frame}: {a:?} vs {b:?}");
        assert!((a.1 - b.1).length() < 1e-5, "frame {frame}: {a:?} vs {b:?}");
    }
    // A static camera: nothing moves.
    assert!(!attached.features().animated_lights);
}

#[test]
fn the_corridor_walks_flashlight_lights_ahead_of_the_camera_every_frame() {
    let s = scenes::library::load("corridor-walk").unwrap().unwrap();
    for frame in 0..s.frame_count() {
        let st = s.frame(frame);
        let (p, d) = spot(&s, frame);
        let eye = st.camera.position;
        let forward = st.camera.forward().as_vec3();
        // Within arm's reach of the eye, and aimed within 10° of the view direction.
        assert!((p - eye).length() < 0.5, "frame {frame}: {p} vs eye {eye}");
        assert!(d.dot(forward) > 10f32.to_radians().cos(), "frame {frame}");
    }
}

#[test]
fn flashlight_mistakes_are_refused_with_the_field_and_the_rule() {
    let base = flashlight_scene(true);
    let refuse = |text: String| match parse_scene(&text, "f.json", "f", Path::new(".")) {
        Ok(_) => panic!("accepted:\n{text}"),
        Err(e) => e.to_string(),
    };
    let keyed = base.replace(
        r#""intensity": [10, 10, 10] }"#,
        r#""intensity": [10, 10, 10], "keyframes": [{"frame": 0, "position": [0, 1, 0]}] }"#,
    );
    let e = refuse(keyed);
    assert!(
        e.contains("lights[0].keyframes") && e.contains("follows the camera's keyframes"),
        "{e}"
    );
    let at_eye = base.replace(&vec3(OFFSET), "[0, 0.001, 0]");
    let e = refuse(at_eye);
    assert!(
        e.contains("lights[0].position") && e.contains("at least 0.01 m from the eye"),
        "{e}"
    );
    let no_aim = base.replace(&vec3(AIM), "[0, 0, 0]");
    let e = refuse(no_aim);
    assert!(
        e.contains("lights[0].direction") && e.contains("zero vector"),
        "{e}"
    );
    // Keys that are fine alone but swap position and look_at meet half way: frame 2 of 4.
    let swap = base.replace(
        &keys_json(),
        r#"{"frame": 0, "position": [0, 1, 4], "look_at": [0, 1, 0]},
            {"frame": 4, "position": [0, 1, 0], "look_at": [0, 1, 4]}"#,
    );
    let e = refuse(swap);
    assert!(
        e.contains("camera.keyframes") && e.contains("at frame 2") && e.contains("look_at meets"),
        "{e}"
    );
}
