//! The leak probes (`scenes/probes/corridor-lamp-fNN.json`, scenes/README.md "corridor-walk")
//! are `corridor-walk` frozen at frame NN and lit by its lamp alone: the same medium, objects and
//! world-space lights, the flashlight removed, the camera at that frame's pose. If the library
//! scene changes, the probes must follow, or the leak table would measure another scene.

use std::path::Path;

use scenes::desc::LightDesc;
use scenes::{library, load_scene};

#[test]
fn each_leak_probe_is_corridor_walk_at_its_frame_without_the_flashlight() {
    let walk = library::load("corridor-walk").unwrap().unwrap();
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("probes");
    for frame in [0u32, 30, 59] {
        let path = dir.join(format!("corridor-lamp-f{frame:02}.json"));
        let probe = load_scene(&path).unwrap_or_else(|e| panic!("{e}"));
        let name = path.display();
        assert_eq!(probe.desc.medium, walk.desc.medium, "{name}");
        assert_eq!(probe.desc.objects, walk.desc.objects, "{name}");
        let lamps: Vec<&LightDesc> = walk
            .desc
            .lights
            .iter()
            .filter(|l| {
                !matches!(
                    l,
                    LightDesc::Spot {
                        attached_to_camera: true,
                        ..
                    }
                )
            })
            .collect();
        assert_eq!(
            lamps.len(),
            1,
            "corridor-walk has one lamp besides the flashlight"
        );
        assert_eq!(
            probe.desc.lights.iter().collect::<Vec<_>>(),
            lamps,
            "{name}"
        );
        assert_eq!(probe.frame_count(), 1, "{name}");
        let (want, got) = (walk.frame(frame).camera, probe.frame(0).camera);
        assert!(
            (want.position - got.position).length() < 1e-4
                && (want.look_at - got.look_at).length() < 1e-4,
            "{name}: camera {got:?}, corridor-walk frame {frame} {want:?}"
        );
        assert_eq!(
            (want.up, want.fov_y_deg, want.near, want.far),
            (got.up, got.fov_y_deg, got.near, got.far),
            "{name}"
        );
    }
}
