//! GPU tests of `epipolar-minmax` (lavapipe in CI).
//!
//! Without an adapter these tests skip with a message — except when `CI` is set, where a missing
//! adapter is a failure.

use harness::Aov;
use harness::method::ParamValue;
use harness::testing::{gpu_or_skip as gpu, library, reference, rel_rmse, render_method};
use methods::epipolar_minmax::EpipolarMinMax;

const RES: u32 = 64;

/// Relative RMSE of the in-scatter AOV on `scene` with `knobs`.
fn error(gpu: &harness::Gpu, scene: &scenes::Scene, knobs: &[(&str, ParamValue)]) -> f64 {
    let r = render_method(gpu, &EpipolarMinMax, scene, RES, knobs).unwrap();
    rel_rmse(r.aov(Aov::Inscatter), &reference(scene, RES).inscatter)
}

#[test]
fn clear_fog_converges_as_slices_and_samples_grow() {
    let Some(gpu) = gpu() else { return };
    let scene = library("clear-fog");
    let errors: Vec<f64> = [(8, 4), (32, 16), (128, 64)]
        .iter()
        .map(|&(n, m)| {
            let knobs = [
                ("slices", ParamValue::Int(n)),
                ("samples", ParamValue::Int(m)),
            ];
            error(&gpu, &scene, &knobs)
        })
        .collect();
    eprintln!("clear-fog: rel RMSE coarse → fine {errors:?}");
    assert!(errors.iter().all(|e| e.is_finite()), "{errors:?}");
    assert!(
        errors[1] < errors[0] && errors[2] < errors[1],
        "error must fall as slices and samples grow: {errors:?}"
    );
}
