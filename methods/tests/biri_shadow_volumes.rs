//! GPU tests of `biri-shadow-volumes` (lavapipe in CI): eq. 7 from the Γ table against the
//! reference on the unshadowed `clear-fog`, and the shadow planes on `sphere-point`.
//!
//! Without an adapter these tests skip with a message — except when `CI` is set, where a missing
//! adapter is a failure.

use harness::Gpu;
use harness::image::metrics::{ToneMap, compare};
use harness::method::{Method, ParamValue, PrepareContext, resolve_params};
use harness::reference::{self, Settings};
use harness::runner::{AovTargets, render_frame};
use harness::testing::{gpu_or_skip as gpu, knobs};
use methods::biri_shadow_volumes::BiriShadowVolumes;

/// In-scatter rel RMSE of biri-shadow-volumes against the reference on `scene`, frame 0.
fn error(gpu: &Gpu, scene: &str, res: u32, list: &[(&str, ParamValue)]) -> f64 {
    let s = scenes::library::resolve(scene).unwrap();
    let mut m = BiriShadowVolumes::default();
    let params = resolve_params(&m.params(), &knobs(list)).unwrap();
    m.prepare(&PrepareContext {
        gpu,
        scene: &s,
        params: &params,
        width: res,
        height: res,
        no_skip: false,
    })
    .unwrap();
    let aovs = AovTargets::new(gpu, res, res);
    render_frame(gpu, &mut m, &s, 0, &aovs, None).unwrap();
    let [ins, _, _] = aovs.read(gpu).unwrap();
    let refimg = reference::render(&s, 0, res, res, Settings::default(), &|_| {}).unwrap();
    // BIRI_DUMP=dir writes the image, the reference and an error map (for debugging, not asserted).
    if let Some(dir) = std::env::var_os("BIRI_DUMP") {
        let dir = std::path::PathBuf::from(dir);
        let t = ToneMap { exposure: 0.0 };
        harness::image::io::write_png(&dir.join(format!("{scene}-biri.png")), &ins, &t).unwrap();
        harness::image::io::write_png(&dir.join(format!("{scene}-ref.png")), &refimg.inscatter, &t)
            .unwrap();
        let em = harness::image::colormap::error_map(&ins, &refimg.inscatter, 0.1);
        harness::image::io::write_png_ldr(&dir.join(format!("{scene}-err.png")), &em).unwrap();
    }
    compare(&ins, &refimg.inscatter, &ToneMap { exposure: 0.0 })
        .unwrap()
        .rel_rmse
}

/// On clear-fog (a point light, nothing casts a volumetric shadow) every pixel's in-scatter is
/// eq. 7: two Γ lookups per channel. It matches the reference's quadrature of the integral to
/// under 0.5% rel RMSE at 96² (measured: see the eprintln; the rest is the table's bilinear
/// interpolation and f32). The paper's 1/4π left in is 12.6× off; a missing 1/h or e^(−σ_t t)
/// is tens of percents at least; a table of 16² is visibly worse, which the second assertion
/// checks (the table resolution matters, so the lookups are really used).
#[test]
fn ldss_matches_reference_on_clear_fog() {
    let Some(gpu) = gpu() else { return };
    let e = error(&gpu, "clear-fog", 96, &[]);
    let coarse = error(&gpu, "clear-fog", 96, &[("table", ParamValue::Int(8))]);
    eprintln!("clear-fog 96² in-scatter rel RMSE: table 256² {e:.3e}, table 8² {coarse:.3e}");
    assert!(e < 0.005, "in-scatter rel RMSE: {e}");
    assert!(
        coarse > e,
        "an 8² table ({coarse}) should be worse than 256² ({e})"
    );
}

/// Shadow planes on sphere-point (one convex caster, Wyman & Ramsey's sphere) at 64². With every
/// crossing counted (`stencil_rules = false`, exact for one convex volume) the z-pass count,
/// lit-surface term and signed plane terms reproduce the reference to < 1e-3 rel RMSE (measured
/// 2.8e-5): the Γ terms, signs, facing and eye term are right. With the paper's step-5 rules
/// (`stencil_rules = true`) the measured error is 3.3e-2: rays ending in shadow lose their entering plane's
/// term because the stencil there is ≥ 2, not 1 (an open defect, see the README); the bound 0.05
/// is below the 5.8e-2 of no plane terms at all.
#[test]
fn shadow_planes_match_reference_on_sphere_point() {
    let Some(gpu) = gpu() else { return };
    let every = error(
        &gpu,
        "sphere-point",
        64,
        &[("stencil_rules", ParamValue::Bool(false))],
    );
    let rules = error(
        &gpu,
        "sphere-point",
        64,
        &[("stencil_rules", ParamValue::Bool(true))],
    );
    eprintln!(
        "sphere-point 64² in-scatter rel RMSE: every crossing {every:.3e}, paper stencil rules {rules:.3e}"
    );
    assert!(every < 1e-3, "every crossing: {every}");
    assert!(rules < 0.05, "stencil rules: {rules}");
}
