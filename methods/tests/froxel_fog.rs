//! GPU tests of `froxel-fog` (lavapipe in CI): the in-scatter error against the reference
//! renderer falls as the froxel grid refines; a spot light that cannot reach the view is not
//! injected, and the reference confirms it adds nothing.
//!
//! Without an adapter these tests skip with a message — except when `CI` is set, where a missing
//! adapter is a failure.

use harness::Aov;
use harness::method::ParamValue;
use harness::testing::{
    gpu_or_skip as gpu, library, max_rel_diff, prepare, reference, rel_rmse, render_method,
    render_prepared,
};
use methods::froxel_fog::FroxelFog;

const RES: u32 = 64;

/// Relative RMSE of the in-scatter AOV on `scene` at `pixel_size` and `slices`.
fn error(gpu: &harness::Gpu, scene: &scenes::Scene, pixel_size: i64, slices: i64) -> f64 {
    let knobs = [
        ("pixel_size", ParamValue::Int(pixel_size)),
        ("slices", ParamValue::Int(slices)),
    ];
    let r = render_method(gpu, &FroxelFog, scene, RES, &knobs).unwrap();
    let reference = reference(scene, RES);
    rel_rmse(r.aov(Aov::Inscatter), &reference.inscatter)
}

/// Coarse → medium → fine grid (pixel size 16 → 8 → 2, slices 16 → 64 → 256): each refinement
/// lowers the in-scatter error against the reference renderer.
fn error_falls_with_grid(name: &str) {
    let Some(gpu) = gpu() else { return };
    let scene = library(name);
    let errors: Vec<f64> = [(16, 16), (8, 64), (2, 256)]
        .iter()
        .map(|&(p, s)| error(&gpu, &scene, p, s))
        .collect();
    eprintln!("{name}: rel RMSE coarse → fine {errors:?}");
    assert!(errors.iter().all(|e| e.is_finite()), "{errors:?}");
    assert!(
        errors[1] < errors[0] && errors[2] < errors[1],
        "{name}: error must fall as the grid refines: {errors:?}"
    );
}

#[test]
fn clear_fog_error_falls_as_grid_refines() {
    error_falls_with_grid("clear-fog");
}

#[test]
fn sphere_point_error_falls_as_grid_refines() {
    error_falls_with_grid("sphere-point");
}

/// fence-spot with its spot turned to face away from the camera's frustum: the method skips its
/// injection (counter `lights_injected` 0, against 1 with `no_skip`), the image is the one
/// `no_skip` renders, and the reference renderer's in-scatter is zero — so the light the cull
/// dropped could indeed not reach the view.
#[test]
fn a_spot_facing_away_from_the_view_is_not_injected() {
    let Some(gpu) = gpu() else { return };
    let mut scene = library("fence-spot");
    let cam = scene.desc.camera.position;
    let scenes::desc::LightDesc::Spot {
        position,
        direction,
        ..
    } = &mut scene.desc.lights[0]
    else {
        panic!("fence-spot has a spot light")
    };
    // Behind the camera, pointing further away from the scene.
    *position = cam + (cam - glam::Vec3::new(0.0, 1.2, -0.5)).normalize();
    *direction = cam - glam::Vec3::new(0.0, 1.2, -0.5);
    const R: u32 = 32;
    let run = |no_skip| {
        let mut p = prepare(&gpu, &FroxelFog, &scene, R, &[], no_skip).unwrap();
        render_prepared(&gpu, p.as_mut(), &scene, R, 0, 1).unwrap()
    };
    let (skipped, forced) = (run(false), run(true));
    assert_eq!(skipped.report.counters["lights_injected"], 0.0);
    assert_eq!(forced.report.counters["lights_injected"], 1.0);
    assert!(skipped.report.skipped.iter().any(|s| s.pass == "inject"));
    for aov in [Aov::Inscatter, Aov::Total] {
        let d = max_rel_diff(skipped.aov(aov), forced.aov(aov));
        assert!(d < 1e-5, "{aov:?}: skipping changed the image by {d}");
    }
    let peak =
        |img: &harness::image::Image| img.pixels.iter().flatten().fold(0.0f32, |m, &v| m.max(v));
    let r = reference(&scene, R);
    assert_eq!(
        peak(&r.inscatter),
        0.0,
        "the reference sees the spot's light in view"
    );
    assert!(
        peak(&forced.inscatter) == 0.0,
        "the forced injection lit the view"
    );
}
