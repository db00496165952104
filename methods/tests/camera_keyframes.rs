//! Camera keyframes reach every method and the reference alike (issue 34): sphere-point with its
//! camera keyed to swing from the front to the side between frames 0 and 1. Each method that
//! renders the scene draws frame 1; its image must match frame 1's reference much better than
//! frame 0's — a method that ignored the keys (or read them a frame late) would match frame 0.

use harness::image::Image;
use harness::method::Support;
use harness::reference::{self, Settings};
use harness::testing::{gpu_or_skip, prepare, rel_rmse, render_prepared, scene_text};

const RES: u32 = 32;

/// sphere-point (scenes/library/sphere-point.json) with two camera keys: from the front at
/// frame 0 to the side at frame 1 (the static camera is ignored once keys exist).
const MOVING_CAMERA: &str = r#"{
  "frames": 2,
  "camera": { "position": [0.0, 2.6, 8.0], "look_at": [0.0, 1.2, 0.0], "fov_y_deg": 45, "near": 0.1, "far": 40,
              "keyframes": [ { "frame": 0, "position": [0.0, 2.6, 8.0], "look_at": [0.0, 1.2, 0.0] },
                             { "frame": 1, "position": [8.0, 2.6, 0.0], "look_at": [0.0, 1.2, 0.0] } ] },
  "medium": { "kind": "homogeneous", "sigma_a": [0.01, 0.01, 0.01], "sigma_s": [0.08, 0.08, 0.08] },
  "lights": [ { "kind": "point", "position": [0.6, 4.6, -0.4], "intensity": [60, 60, 60] } ],
  "objects": [
    { "name": "floor", "shape": { "kind": "plane", "size": [14, 14] }, "material": { "albedo": [0.7, 0.7, 0.7] } },
    { "name": "sphere", "shape": { "kind": "sphere", "radius": 0.9 },
      "transform": { "translation": [0.0, 2.0, 0.0] }, "material": { "albedo": [0.8, 0.3, 0.2] } }
  ]
}"#;

fn moving_camera_scene() -> scenes::Scene {
    scene_text(MOVING_CAMERA, "sphere-point-moving-camera")
}

#[test]
fn every_method_renders_the_keyed_camera_of_the_frame_it_is_asked_for() {
    let Some(gpu) = gpu_or_skip() else { return };
    let scene = moving_camera_scene();
    assert!(scene.features().animated_camera);
    let refs: Vec<_> = (0..2)
        .map(|f| reference::render(&scene, f, RES, RES, Settings::default(), &|_| {}).unwrap())
        .collect();
    // The two frames really differ (otherwise the test proves nothing).
    let apart = rel_rmse(&refs[1].total, &refs[0].total);
    assert!(apart > 0.2, "frames 0 and 1 differ by only {apart}");
    let mut rendered = 0;
    for method in methods::REGISTRY {
        if let Support::No(_) = method.support(&scene.features(), gpu.device.features()) {
            continue;
        }
        let mut p = prepare(&gpu, *method, &scene, RES, &[], false)
            .unwrap_or_else(|e| panic!("{}: {e}", method.id()));
        let img = render_prepared(&gpu, p.as_mut(), &scene, RES, 1, 1)
            .unwrap_or_else(|e| panic!("{}: {e}", method.id()));
        // The total, but the floor's surface: it has no in-scatter, so its total is ~100 % off
        // against any frame.
        let floor = method.id() == harness::verdict::FLOOR_METHOD;
        let pick = |total: &'_ Image, surface: &'_ Image| -> Image {
            if floor {
                surface.clone()
            } else {
                total.clone()
            }
        };
        let shown = pick(&img.total, &img.surface);
        let (own, other) = (
            rel_rmse(&shown, &pick(&refs[1].total, &refs[1].surface)),
            rel_rmse(&shown, &pick(&refs[0].total, &refs[0].surface)),
        );
        assert!(
            own < 0.5 * other,
            "{}: frame 1 matches its own reference at {own:.3} and frame 0's at {other:.3}",
            method.id()
        );
        rendered += 1;
    }
    assert!(rendered >= 8, "only {rendered} methods render sphere-point");
}
