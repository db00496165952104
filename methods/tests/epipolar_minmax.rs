//! GPU tests of `epipolar-minmax` (lavapipe in CI).
//!
//! Without an adapter these tests skip with a message — except when `CI` is set, where a missing
//! adapter is a failure.

use harness::Aov;
use harness::image::headline::headline;
use harness::method::ParamValue;
use harness::testing::{gpu_or_skip as gpu, library, reference, rel_rmse, render_method};
use methods::epipolar_minmax::EpipolarMinMax;
use methods::raymarch_brute::RaymarchBrute;

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

/// The min-max traversal only settles runs the leaf-by-leaf march would find wholly lit or
/// wholly shadowed, so on a scene with a shadowing caster the two images agree (up to the
/// quadrature of long lit runs), and both are close to the reference.
#[test]
fn sphere_point_tree_traversal_matches_the_leaf_march() {
    let Some(gpu) = gpu() else { return };
    let scene = library("sphere-point");
    let render = |min_max: bool| {
        let knobs = [("min_max", ParamValue::Bool(min_max))];
        render_method(&gpu, &EpipolarMinMax, &scene, RES, &knobs).unwrap()
    };
    let (tree, leaves) = (render(true), render(false));
    let between = rel_rmse(tree.aov(Aov::Inscatter), leaves.aov(Aov::Inscatter));
    let reference = reference(&scene, RES);
    let to_ref = rel_rmse(tree.aov(Aov::Inscatter), &reference.inscatter);
    eprintln!("tree vs leaves {between}, tree vs reference {to_ref}");
    assert!(
        between < 0.01,
        "tree and leaf march differ: rel RMSE {between}"
    );
    assert!(to_ref < 0.1, "tree march vs reference: rel RMSE {to_ref}");
}

/// On sphere-point at 128² the default profile beats raymarch-brute at the step count that
/// costs at least as much frame time. Measured (one run, lavapipe, 5 timed frames after a
/// warm-up): epipolar-minmax 25.1 ms, headline 0.73 %; raymarch-brute at 32 steps 30.6 ms,
/// 3.99 % (`scatterbench run --scenes sphere-point --methods epipolar-minmax,raymarch-brute
/// --param raymarch-brute.steps=32 --res 128 --frames 5 --warmup 1`). Times are not asserted
/// here (the harness measures them); the test asserts the error side of that pair. At 64² the
/// default profile (64 slices × 32 samples) is worse than 64 brute-force steps: epipolar
/// sampling pays with resolution.
#[test]
fn sphere_point_default_beats_brute_force_at_equal_time() {
    let Some(gpu) = gpu() else { return };
    let res = 128;
    let scene = library("sphere-point");
    let reference = reference(&scene, res);
    let epipolar = render_method(&gpu, &EpipolarMinMax, &scene, res, &[]).unwrap();
    let steps = [("steps", ParamValue::Int(32))];
    let brute = render_method(&gpu, &RaymarchBrute, &scene, res, &steps).unwrap();
    let e = headline(epipolar.aov(Aov::Inscatter), &reference.inscatter);
    let b = headline(brute.aov(Aov::Inscatter), &reference.inscatter);
    eprintln!("sphere-point headline: epipolar-minmax {e}, raymarch-brute (32 steps) {b}");
    assert!(
        e < b,
        "epipolar-minmax {e} is not below raymarch-brute's {b}"
    );
}
