//! GPU tests of `froxel-fog` (lavapipe in CI): the in-scatter error against the reference
//! renderer falls as the froxel grid refines.
//!
//! Without an adapter these tests skip with a message — except when `CI` is set, where a missing
//! adapter is a failure.

use harness::Aov;
use harness::method::ParamValue;
use harness::testing::{gpu_or_skip as gpu, library, reference, rel_rmse, render_method};
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
