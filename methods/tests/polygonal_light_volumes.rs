//! GPU tests of `polygonal-light-volumes` (lavapipe in CI) against the reference renderer: a
//! shadowed scene per light kind, the error falling as the shadow map grows, the table against
//! per-fragment quadrature, and the skip of a light without casters.
//!
//! Without an adapter these tests skip with a message — except when `CI` is set, where a missing
//! adapter is a failure.

use harness::testing::{gpu_or_skip as gpu, rel_rmse, render_method};

use harness::Gpu;
use harness::image::Image;
use harness::method::{FrameReport, ParamValue};
use harness::reference::{self, Settings};
use methods::polygonal_light_volumes::PolygonalLightVolumes;
use scenes::Scene;

fn scene(name: &str) -> Scene {
    scenes::library::resolve(name).unwrap()
}

/// The in-scatter AOV of frame 0 of `scene` at `res`² with `list` over the defaults, and the report.
fn render(gpu: &Gpu, scene: &Scene, res: u32, list: &[(&str, ParamValue)]) -> (Image, FrameReport) {
    let r = render_method(gpu, &PolygonalLightVolumes, scene, res, list).unwrap();
    (r.inscatter, r.report)
}

fn reference_inscatter(s: &Scene, res: u32) -> Image {
    reference::render(s, 0, res, res, Settings::default(), &|_| {})
        .unwrap()
        .inscatter
}

fn map(size: i64, mesh: f64) -> Vec<(&'static str, ParamValue)> {
    vec![
        ("shadow_map", ParamValue::Int(size)),
        ("mesh", ParamValue::Float(mesh)),
    ]
}

/// Sphere-point (a point light, a sphere's shaft of shadow, the camera outside it) at 128²,
/// shadow map 1024 with one vertex per texel: the light volumes' signed sum is the reference's
/// in-scatter up to the shadow map (the shaft's edge is a staircase of 1024-texel cube faces)
/// and the Γ table. Bound 1 %: a wrong sign rule or an unclosed volume (walls or cap missing)
/// leaves whole faces' in-scatter out (tens of percents); a wrong constant is ≥ 100 % off.
#[test]
fn matches_reference_on_sphere_point() {
    let Some(gpu) = gpu() else { return };
    let s = scene("sphere-point");
    let refimg = reference_inscatter(&s, 128);
    let (ins, report) = render(&gpu, &s, 128, &map(1024, 1.0));
    let e = rel_rmse(&ins, &refimg);
    eprintln!(
        "sphere-point 128², map 1024, mesh 1: in-scatter rel RMSE {e}, {:?}",
        report.counters
    );
    assert!(e < 0.01, "in-scatter rel RMSE {e}");
}

/// The three light kinds through their volumes: fence-spot (a spot's cone faces and quadrature,
/// an open mesh), window-sun (the directional shadow volume, the camera inside a room lit
/// through windows) and overlap-point (the camera in a shadow, overlapping shadows), at 96²,
/// map 1024, one vertex per texel. What remains is the volumes' resolution: a depth
/// discontinuity becomes a wall slanted across one texel along the whole shaft, and
/// window-sun's orthographic map spans the whole room, so its thin mullions' shafts carry the
/// largest error (measured 6.1 %; bound 8 %); fence-spot and overlap-point within 3 %. A wrong
/// sign rule for the shadow volume or a missing cap or wall is ≥ 30 % off.
#[test]
fn matches_reference_for_spot_directional_and_camera_in_shadow() {
    let Some(gpu) = gpu() else { return };
    for (name, bound) in [
        ("fence-spot", 0.03),
        ("window-sun", 0.08),
        ("overlap-point", 0.03),
    ] {
        let s = scene(name);
        let refimg = reference_inscatter(&s, 96);
        let (ins, _) = render(&gpu, &s, 96, &map(1024, 1.0));
        let e = rel_rmse(&ins, &refimg);
        eprintln!("{name} 96², map 1024: in-scatter rel RMSE {e}");
        assert!(e < bound, "{name}: in-scatter rel RMSE {e}");
    }
}

/// Visibility comes from the shadow map, so the error falls as it grows: on sphere-point at
/// 96², maps 64 → 128 → 512 with one vertex per texel (the shaft's edge is a staircase of
/// texels, its area error ∝ 1/size). Each step must cut the error by a fifth at least; a grid
/// that ignored the map's size (or a fixed-resolution volume) would be flat.
#[test]
fn error_falls_as_the_shadow_map_grows() {
    let Some(gpu) = gpu() else { return };
    let s = scene("sphere-point");
    let refimg = reference_inscatter(&s, 96);
    let e: Vec<f64> = [(64, 1.0), (128, 1.0), (512, 1.0)]
        .iter()
        .map(|(n, m)| rel_rmse(&render(&gpu, &s, 96, &map(*n, *m)).0, &refimg))
        .collect();
    eprintln!("sphere-point 96², maps 64/128/512: in-scatter rel RMSE {e:?}");
    assert!(
        e.windows(2).all(|p| p[1] < 0.8 * p[0]),
        "error does not fall: {e:?}"
    );
}

/// `table = 0` evaluates every point-light fragment by quadrature instead of the Γ table: an
/// independent evaluation of the same integral. On desk-pencils (Henyey–Greenstein haze, so
/// the table's phase matters) both agree with each other to 0.5 %.
#[test]
fn gamma_table_agrees_with_quadrature_on_desk_pencils() {
    let Some(gpu) = gpu() else { return };
    let s = scene("desk-pencils");
    let (table, _) = render(&gpu, &s, 64, &[]);
    let (quad, _) = render(
        &gpu,
        &s,
        64,
        &[
            ("table", ParamValue::Int(0)),
            ("panels", ParamValue::Int(64)),
        ],
    );
    let e = rel_rmse(&table, &quad);
    eprintln!("desk-pencils 64²: table vs quadrature rel RMSE {e}");
    assert!(e < 0.005, "table vs quadrature: {e}");
}

/// Clear-fog has no volumetric shadow caster: no volume is drawn (recorded as skipped) and the
/// in-scatter is the unshadowed integral, within 0.5 % of the reference.
#[test]
fn light_without_casters_gets_no_volume() {
    let Some(gpu) = gpu() else { return };
    let s = scene("clear-fog");
    let refimg = reference_inscatter(&s, 64);
    let (ins, report) = render(&gpu, &s, 64, &[]);
    assert!(
        report
            .skipped
            .iter()
            .any(|p| p.pass.starts_with("light-volume")),
        "{report:?}"
    );
    assert_eq!(report.counters.get("volume_triangles"), Some(&0.0));
    let e = rel_rmse(&ins, &refimg);
    eprintln!("clear-fog 64²: in-scatter rel RMSE {e}");
    assert!(e < 0.005, "clear-fog rel RMSE {e}");
}
