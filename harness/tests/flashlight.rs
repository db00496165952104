//! The CPU reference on a camera-attached spot (a flashlight): on a static camera it renders
//! exactly what the equivalent world-space spot renders. The world-space spot is placed by this
//! file from the camera's basis (forward = look_at − eye, right = forward × up, up' = right ×
//! forward; camera space x right, y up, −z forward), not by the scene code under test.

use std::path::Path;

use glam::DVec3;
use harness::reference::{ReferenceImages, Settings, render};
use scenes::{Scene, parse_scene};

fn scene(text: &str) -> Scene {
    parse_scene(text, "test.json", "test", Path::new(".")).unwrap_or_else(|e| panic!("{e}"))
}

const EYE: [f64; 3] = [0.4, 1.7, 5.0];
const TARGET: [f64; 3] = [-0.3, 1.0, -1.0];
const OFFSET: [f64; 3] = [0.25, -0.3, 0.05];
const AIM: [f64; 3] = [0.05, -0.2, -1.0];

fn vec3(v: DVec3) -> String {
    format!("[{}, {}, {}]", v.x, v.y, v.z)
}

/// A floor, a box in the beam (a volumetric shadow inside the cone) and `light`.
fn with_light(light: &str) -> Scene {
    scene(&format!(
        r#"{{
  "camera": {{ "position": {}, "look_at": {}, "fov_y_deg": 50, "near": 0.05, "far": 20 }},
  "medium": {{ "kind": "homogeneous", "sigma_a": [0.02, 0.02, 0.02], "sigma_s": [0.15, 0.12, 0.1],
              "phase": {{ "kind": "henyey-greenstein", "g": 0.3 }} }},
  "lights": [ {light} ],
  "objects": [
    {{ "shape": {{ "kind": "plane", "size": [12, 16] }} }},
    {{ "shape": {{ "kind": "box", "size": [0.6, 0.6, 0.6] }}, "transform": {{ "translation": [0.0, 0.9, 1.5] }} }}
  ]
}}"#,
        vec3(DVec3::from_array(EYE)),
        vec3(DVec3::from_array(TARGET))
    ))
}

fn spot(attached: bool, position: DVec3, direction: DVec3) -> String {
    format!(
        r#"{{ "kind": "spot", "attached_to_camera": {attached}, "position": {}, "direction": {},
             "inner_deg": 14, "outer_deg": 24, "intensity": [30, 28, 25] }}"#,
        vec3(position),
        vec3(direction)
    )
}

fn reference(s: &Scene) -> ReferenceImages {
    render(s, 0, 24, 18, Settings::default(), &|_| {}).unwrap_or_else(|e| panic!("{e}"))
}

#[test]
fn a_flashlight_on_a_static_camera_renders_as_the_equivalent_world_spot() {
    let (eye, target) = (DVec3::from_array(EYE), DVec3::from_array(TARGET));
    let forward = (target - eye).normalize();
    let right = forward.cross(DVec3::Y).normalize();
    let up = right.cross(forward);
    let to_world = |v: [f64; 3]| right * v[0] + up * v[1] - forward * v[2];
    let attached = with_light(&spot(
        true,
        DVec3::from_array(OFFSET),
        DVec3::from_array(AIM),
    ));
    let world = with_light(&spot(
        false,
        eye + to_world(OFFSET),
        to_world(AIM).normalize(),
    ));
    let (a, w) = (reference(&attached), reference(&world));
    let mut lit = 0;
    for (name, ia, iw) in [
        ("inscatter", &a.inscatter, &w.inscatter),
        ("surface", &a.surface, &w.surface),
    ] {
        let peak = iw
            .pixels
            .iter()
            .flat_map(|p| p.iter().copied())
            .fold(0.0f32, f32::max);
        assert!(peak > 0.0, "{name}: the beam lights something");
        for (k, (pa, pw)) in ia.pixels.iter().zip(&iw.pixels).enumerate() {
            for c in 0..3 {
                // Within f32 rounding of the light's pose and the quadrature tolerance.
                assert!(
                    (pa[c] - pw[c]).abs() <= 1e-4 * peak,
                    "{name} pixel {k} channel {c}: attached {} vs world {}",
                    pa[c],
                    pw[c]
                );
            }
            lit += (pw[0] > 0.01 * peak) as usize;
        }
    }
    // The beam fills part of the frame, not all of it and not none of it.
    assert!(lit > 20 && lit < 2 * 24 * 18 - 20, "{lit} lit pixels");
}
