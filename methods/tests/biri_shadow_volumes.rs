//! GPU tests of `biri-shadow-volumes` (lavapipe in CI): eq. 7 from the Γ table against the
//! reference on the unshadowed `clear-fog`, the shadow planes (both resolves, the stencil rules,
//! the unorm8 target) on `sphere-point` and `overlap-point`, and the per-triangle fallback for
//! open and non-manifold casters.
//!
//! Without an adapter these tests skip with a message — except when `CI` is set, where a missing
//! adapter is a failure.

use harness::Gpu;
use harness::image::Image;
use harness::image::metrics::{ToneMap, compare};
use harness::method::{FrameReport, ParamValue};
use harness::reference::{self, Settings};

use harness::testing::{self, gpu_or_skip as gpu};
use methods::biri_shadow_volumes::BiriShadowVolumes;
use scenes::Scene;

/// A scene and its reference in-scatter at `res`².
struct Case {
    name: String,
    scene: Scene,
    res: u32,
    reference: Image,
}

impl Case {
    fn new(scene: Scene, res: u32) -> Case {
        let r = reference::render(&scene, 0, res, res, Settings::default(), &|_| {}).unwrap();
        Case {
            name: scene.name.clone(),
            scene,
            res,
            reference: r.inscatter,
        }
    }

    fn library(name: &str, res: u32) -> Case {
        Case::new(scenes::library::resolve(name).unwrap(), res)
    }

    /// In-scatter rel RMSE of biri-shadow-volumes against the reference, frame 0, and the report
    /// of the last of `frames` frames (counters read back a frame late need two).
    fn error_frames(
        &self,
        gpu: &Gpu,
        list: &[(&str, ParamValue)],
        frames: u32,
    ) -> (f64, FrameReport) {
        let (e, _, report) = self.errors(gpu, list, frames);
        (e, report)
    }

    /// (rel RMSE, 99th percentile of |error| / mean reference, report of the last frame).
    fn errors(
        &self,
        gpu: &Gpu,
        list: &[(&str, ParamValue)],
        frames: u32,
    ) -> (f64, f64, FrameReport) {
        let mut m =
            testing::prepare(gpu, &BiriShadowVolumes, &self.scene, self.res, list, false).unwrap();
        let out =
            testing::render_prepared(gpu, m.as_mut(), &self.scene, self.res, 0, frames).unwrap();
        let (ins, report) = (out.inscatter, out.report);
        // BIRI_DUMP=dir writes the image, the reference and an error map (for debugging, not asserted).
        if let Some(dir) = std::env::var_os("BIRI_DUMP") {
            let dir = std::path::PathBuf::from(dir);
            let tag: String = list
                .iter()
                .map(|(k, v)| format!("-{k}={v:?}"))
                .collect::<String>()
                .replace(['"', '(', ')', ' '], "");
            let t = ToneMap { exposure: 0.0 };
            let stem = format!("{}{tag}", self.name);
            harness::image::io::write_png(&dir.join(format!("{stem}-biri.png")), &ins, &t).unwrap();
            harness::image::io::write_png(
                &dir.join(format!("{}-ref.png", self.name)),
                &self.reference,
                &t,
            )
            .unwrap();
            let em = harness::image::colormap::error_map(&ins, &self.reference, 0.1);
            harness::image::io::write_png_ldr(&dir.join(format!("{stem}-err.png")), &em).unwrap();
        }
        let m = compare(&ins, &self.reference, &ToneMap { exposure: 0.0 }).unwrap();
        let mean = if m.rel_rmse > 0.0 {
            m.rmse / m.rel_rmse
        } else {
            1.0
        };
        (m.rel_rmse, m.p99_abs / mean, report)
    }

    fn error(&self, gpu: &Gpu, list: &[(&str, ParamValue)]) -> f64 {
        self.error_frames(gpu, list, 1).0
    }
}

fn text(s: &str) -> ParamValue {
    ParamValue::Text(s.into())
}

/// The knobs of the stencil resolve with or without the step-5 rules.
fn stencil(rules: bool) -> Vec<(&'static str, ParamValue)> {
    vec![
        ("resolve", text("stencil")),
        ("stencil_rules", ParamValue::Bool(rules)),
    ]
}

/// On clear-fog (a point light, nothing casts a volumetric shadow) every pixel's in-scatter is
/// eq. 7: two Γ lookups per channel. It matches the reference's quadrature of the integral to
/// under 0.5% rel RMSE at 96² (measured: see the eprintln; the rest is the table's bilinear
/// interpolation and f32). The paper's 1/4π left in is 12.6× off; a missing 1/h or e^(−σ_t t)
/// is tens of percents at least; a table of 8² is visibly worse, which the second assertion
/// checks (the table resolution matters, so the lookups are really used).
#[test]
fn ldss_matches_reference_on_clear_fog() {
    let Some(gpu) = gpu() else { return };
    let case = Case::library("clear-fog", 96);
    let e = case.error(&gpu, &[]);
    let coarse = case.error(&gpu, &[("table", ParamValue::Int(8))]);
    eprintln!("clear-fog 96² in-scatter rel RMSE: table 256² {e:.3e}, table 8² {coarse:.3e}");
    assert!(e < 0.005, "in-scatter rel RMSE: {e}");
    assert!(
        coarse > e,
        "an 8² table ({coarse}) should be worse than 256² ({e})"
    );
}

/// Shadow planes on sphere-point (one convex caster, Wyman & Ramsey's sphere) at 64²: one
/// volume, so every resolve is exact up to rasterisation and the table. The per-pixel resolve,
/// the stencil resolve with step 5's rules and the stencil resolve counting every crossing all
/// reproduce the reference to < 1e-3 rel RMSE (measured: see the eprintln); no plane terms at all
/// would be 5.8e-2. The rules' old defect (stencil ops on planes behind the visible point) lost
/// the entering term of rays ending in shadow: 3.3e-2.
#[test]
fn shadow_planes_match_reference_on_sphere_point() {
    let Some(gpu) = gpu() else { return };
    let case = Case::library("sphere-point", 64);
    let pixel = case.error(&gpu, &[("resolve", text("per-pixel"))]);
    let rules = case.error(&gpu, &stencil(true));
    let every = case.error(&gpu, &stencil(false));
    eprintln!(
        "sphere-point 64² in-scatter rel RMSE: per-pixel {pixel:.3e}, stencil rules {rules:.3e}, every crossing {every:.3e}"
    );
    assert!(pixel < 1e-3, "per-pixel: {pixel}");
    assert!(rules < 1e-3, "stencil rules: {rules}");
    assert!(every < 1e-3, "every crossing: {every}");
}

/// overlap-point: the lower sphere partly in the upper's shadow (volumes overlap in view) and the
/// eye inside the slab's shadow volume. Counting every crossing double-counts the overlap (the
/// first assertion shows the scene really tests it). The per-pixel resolve sorts each pixel's
/// crossings exactly and starts the walk from the eye's count, so what is left is the Γ table and
/// rasterisation at the volumes' edges, as on sphere-point: bound 2e-3 (measured: eprintln).
/// The stencil rules depend on the CPU's back-to-front order of whole planes (by edge midpoint),
/// which is not every pixel's order where planes of the two spheres interleave: measured, bounded
/// loosely (below counting every crossing), and explained in the README.
#[test]
fn per_pixel_resolve_handles_overlap_and_eye_in_shadow() {
    let Some(gpu) = gpu() else { return };
    let case = Case::library("overlap-point", 64);
    // Three frames: the list counters are read back two frames late.
    let (pixel, pixel99, report) = case.errors(&gpu, &[("resolve", text("per-pixel"))], 3);
    let (rules, rules99, _) = case.errors(&gpu, &stencil(true), 1);
    let (every, every99, _) = case.errors(&gpu, &stencil(false), 1);
    eprintln!(
        "overlap-point 64² in-scatter rel RMSE / p99 |error| over mean: per-pixel {pixel:.3e} / {pixel99:.3e}, stencil rules {rules:.3e} / {rules99:.3e}, every crossing {every:.3e} / {every99:.3e}; counters {:?}",
        report.counters
    );
    // One pixel (at a shaft's corner, where a pixel centre grazes a silhouette vertex's extruded
    // edge) is wrong in every resolve alike and dominates the RMSE (5e-2); the 99th percentile
    // shows the rest.
    assert!(pixel99 < 2e-3, "per-pixel p99: {pixel99}");
    assert!(pixel < 0.08, "per-pixel: {pixel}");
    assert!(
        every99 > 10.0 * pixel99.max(1e-4),
        "every crossing {every99} vs per-pixel {pixel99}"
    );
    assert!(
        rules99 > 10.0 * pixel99.max(1e-4),
        "stencil rules {rules99} vs per-pixel {pixel99}"
    );
    assert_eq!(report.counters.get("crossing_overflows"), Some(&0.0));
    // The Table-1 phases, where the device has timestamps inside encoders (the runner's
    // render_frame stores them from the method's PhaseTimer).
    let stamps = wgpu::Features::TIMESTAMP_QUERY | wgpu::Features::TIMESTAMP_QUERY_INSIDE_ENCODERS;
    if gpu.features().contains(stamps) {
        for phase in [
            "first_pass",
            "second_pass_surfaces",
            "second_pass_volumes",
            "resolve",
        ] {
            let ms = report.counters[&format!("gpu_ms_{phase}")];
            assert!(ms.is_finite() && ms >= 0.0, "{phase}: {ms}");
        }
    }
    assert!(report.counters["max_crossings"] >= 2.0);
}

/// The per-pixel crossing lists cannot overflow: on a point-lit copy of `fence-spot` with 7 posts
/// (4 rails and the floor; per-triangle planes forced with `silhouettes = whole-mesh`, many
/// crossings per pixel) the per-pixel resolve lists every crossing (longest list > 16, the old
/// fixed capacity; none lost) and matches the reference (measured 1.9e-4, bound 1e-3) and is
/// no worse than the stencil rules. With the old 16-entry lists this scene measured 0.98 rel
/// RMSE.
#[test]
fn per_pixel_lists_cannot_overflow() {
    let Some(gpu) = gpu() else { return };
    let case = Case::new(point_fence(7), 64);
    let whole = [("silhouettes", text("whole-mesh"))];
    let (pixel, report) = case.error_frames(&gpu, &whole, 3);
    let rules = case.error(&gpu, &[stencil(true), whole.to_vec()].concat());
    eprintln!(
        "7-post fence, point light, 64²: in-scatter rel RMSE per-pixel {pixel:.3e}, stencil rules {rules:.3e}; counters {:?}",
        report.counters
    );
    assert!(
        report.counters["max_crossings"] > 16.0,
        "{:?}",
        report.counters
    );
    assert_eq!(report.counters["crossing_overflows"], 0.0);
    assert!(report.counters["crossing_pool"] >= report.counters["max_crossings"]);
    assert!(pixel < 1e-3, "per-pixel: {pixel}");
    assert!(pixel <= rules, "per-pixel {pixel} vs stencil rules {rules}");
}

/// Per-piece silhouettes (default) against the per-triangle volumes they replace
/// (`silhouettes = whole-mesh`), both against the reference, on `fence-spot` itself (the spot,
/// the floor, the 9-post fence) at 64²: the fence's 13 bars are closed pieces, so far fewer
/// crossings are stored (measured: see the eprintln), and the in-scatter is as exact as the
/// per-triangle volumes' (measured rel RMSE 5.33e-4 both, pools 39 k vs 290 k crossings;
/// bound: 1e-3 and within 10 % + 1e-5 of the per-triangle error).
#[test]
fn per_piece_silhouettes_match_per_triangle_volumes() {
    let Some(gpu) = gpu() else { return };
    let case = Case::library("fence-spot", 64);
    let (pieces, p_report) = case.error_frames(&gpu, &[], 3);
    let (triangles, t_report) = case.error_frames(&gpu, &[("silhouettes", text("whole-mesh"))], 3);
    let c = |r: &FrameReport, k: &str| r.counters[k];
    eprintln!(
        "fence-spot 64² in-scatter rel RMSE: per-piece {pieces:.3e} (pool {}, longest {}, planes {}), \
         whole-mesh {triangles:.3e} (pool {}, longest {}, planes {})",
        c(&p_report, "crossing_pool"),
        c(&p_report, "max_crossings"),
        c(&p_report, "silhouette_edges"),
        c(&t_report, "crossing_pool"),
        c(&t_report, "max_crossings"),
        c(&t_report, "silhouette_edges"),
    );
    assert_eq!(c(&p_report, "closed_pieces"), 13.0, "9 posts and 4 rails");
    assert_eq!(c(&p_report, "nonmanifold_casters"), 1.0, "the floor");
    assert_eq!(
        c(&t_report, "nonmanifold_casters"),
        2.0,
        "the floor and the fence"
    );
    assert!(
        c(&p_report, "crossing_pool") * 3.0 < c(&t_report, "crossing_pool"),
        "per-piece stores far fewer crossings"
    );
    assert!(pieces < 1e-3, "per-piece: {pieces}");
    assert!(
        pieces <= 1.1 * triangles + 1e-5,
        "per-piece {pieces} vs per-triangle {triangles}"
    );
}

/// Knob `spot_integral` (issue 33). On fence-spot (64², the fence's slits cut each ray into up to
/// ten lit intervals; the spot has no pattern) `per-ray` — the default: one Chebyshev fit per
/// piece of the ray, cut at the inner cone, each lit interval from its antiderivative — is
/// closer to the reference (its own quadrature, independent of both) than `spot_panels` = 8
/// two-node panels per interval: measured rel RMSE 1.40e-5 against 5.32e-4 (at 256² the headline
/// 4.72e-6 against 3.28e-5, README); a fit with too few nodes or a wrong antiderivative
/// constant would not be. A spot with a pattern keeps the per-interval quadrature (not smooth:
/// lead lines), so stained-glass-spot renders identically under both values.
#[test]
fn spot_integral_per_ray_keeps_the_error() {
    let Some(gpu) = gpu() else { return };
    let integral = |v: &str| ("spot_integral", text(v));
    let case = Case::library("fence-spot", 64);
    let per_interval = case.error(&gpu, &[integral("per-interval")]);
    let per_ray = case.error(&gpu, &[integral("per-ray")]);
    let glass = Case::library("stained-glass-spot", 48);
    let glass_interval = glass.error(&gpu, &[integral("per-interval")]);
    let glass_ray = glass.error(&gpu, &[integral("per-ray")]);
    eprintln!(
        "in-scatter rel RMSE per interval / per ray: fence-spot 64² {per_interval:.4e} / \
         {per_ray:.4e}, stained-glass-spot 48² {glass_interval:.4e} / {glass_ray:.4e}"
    );
    assert!(per_interval < 1e-3, "per interval: {per_interval}");
    assert!(
        per_ray < 0.5 * per_interval,
        "per ray {per_ray} vs per interval {per_interval}"
    );
    assert_eq!(
        glass_ray, glass_interval,
        "a patterned spot stays per interval"
    );
}

/// `fence-spot` (camera, medium, floor, fence) with its spot replaced by a point light at the
/// same place and `posts` posts.
fn point_fence(posts: u32) -> Scene {
    let text = format!(
        r#"{{
      "description": "fence-spot lit by a point light",
      "camera": {{ "position": [4.5, 2.2, 5.5], "look_at": [0.0, 1.2, -0.5], "fov_y_deg": 45, "near": 0.1, "far": 40 }},
      "medium": {{ "kind": "homogeneous", "sigma_a": [0.01, 0.01, 0.01], "sigma_s": [0.1, 0.1, 0.1] }},
      "lights": [ {{ "kind": "point", "position": [0.0, 2.2, -3.5], "intensity": [150, 140, 120] }} ],
      "objects": [
        {{ "name": "floor", "shape": {{ "kind": "plane", "size": [14, 14] }}, "material": {{ "albedo": [0.7, 0.7, 0.7] }} }},
        {{ "name": "fence", "shape": {{ "kind": "fence", "width": 4.0, "height": 2.4, "posts": {posts}, "rails": 4, "bar": 0.08 }},
          "transform": {{ "translation": [0.0, 1.3, -1.0] }}, "material": {{ "albedo": [0.5, 0.4, 0.3] }} }}
      ] }}"#
    );
    let name = format!("fence-point-{posts}");
    scenes::load::parse_scene(&text, "fence.json", &name, std::path::Path::new(".")).expect("scene")
}

/// `accumulate: unorm8` (the paper's 8-bit target): the in-scatter is quantised to 1/255 and
/// clamped to [0, 1] per blend, so it is measurably worse than float on sphere-point (measured:
/// eprintln) while still the right image (not off by a constant factor: < 0.5).
#[test]
fn unorm8_shows_quantisation() {
    let Some(gpu) = gpu() else { return };
    let case = Case::library("sphere-point", 64);
    let mut list = stencil(true);
    let float = case.error(&gpu, &list);
    list.push(("accumulate", text("unorm8")));
    let unorm8 = case.error(&gpu, &list);
    eprintln!("sphere-point 64² in-scatter rel RMSE: float {float:.3e}, unorm8 {unorm8:.3e}");
    assert!(unorm8 > 10.0 * float, "unorm8 {unorm8} vs float {float}");
    assert!(unorm8 < 1.0, "unorm8 {unorm8}");
}

/// Open and non-manifold casters fall back to per-triangle shadow planes (recorded): a single
/// quad (open: its border edges have one face) and, with `silhouettes = whole-mesh`, the fence
/// (touching bars: edges with four faces) under a point light render within 1e-2 of the
/// reference with the per-pixel resolve (overlapping per-triangle volumes need exact shadow in
/// shadow), no panic. By default the fence splits into closed bars and only the card falls
/// back.
#[test]
fn open_and_nonmanifold_casters_fall_back_to_triangles() {
    let Some(gpu) = gpu() else { return };
    let text_scene = r#"{
      "description": "open and non-manifold casters",
      "camera": { "position": [0.0, 2.0, 7.0], "look_at": [0.0, 1.3, 0.0], "fov_y_deg": 45, "near": 0.1, "far": 40 },
      "medium": { "kind": "homogeneous", "sigma_a": [0.01, 0.01, 0.01], "sigma_s": [0.08, 0.08, 0.08] },
      "lights": [ { "kind": "point", "position": [0.3, 5.0, -2.5], "intensity": [60, 60, 60] } ],
      "objects": [
        { "name": "floor", "shape": { "kind": "plane", "size": [14, 14] }, "casts_volumetric_shadow": false },
        { "name": "card", "shape": { "kind": "plane", "size": [1.2, 0.8] },
          "transform": { "translation": [-1.0, 3.0, -1.5] } },
        { "name": "fence", "shape": { "kind": "fence", "width": 2.0, "height": 1.2, "posts": 4, "rails": 2, "bar": 0.1 },
          "transform": { "translation": [0.8, 2.0, -1.2], "rotation_deg": [90, 0, 0] } }
      ] }"#;
    let scene =
        scenes::load::parse_scene(text_scene, "open.json", "open", std::path::Path::new("."))
            .expect("scene");
    let case = Case::new(scene, 48);
    let whole = [("silhouettes", text("whole-mesh"))];
    let (pixel, report) = case.error_frames(&gpu, &whole, 3);
    let rules = case.error(&gpu, &[stencil(true), whole.to_vec()].concat());
    let (_, pieces) = case.error_frames(&gpu, &[], 1);
    eprintln!(
        "open casters 48² in-scatter rel RMSE: per-pixel {pixel:.3e}, stencil rules {rules:.3e}; counters {:?}",
        report.counters
    );
    assert_eq!(report.counters["nonmanifold_casters"], 2.0);
    assert_eq!(pieces.counters["nonmanifold_casters"], 1.0, "the card");
    assert_eq!(pieces.counters["closed_pieces"], 4.0 + 2.0, "the bars");
    assert!(
        report.skipped.iter().any(|s| s.pass.contains("card")),
        "{:?}",
        report.skipped
    );
    assert_eq!(report.counters["crossing_overflows"], 0.0);
    assert!(
        report.counters["max_crossings"] > 16.0,
        "{:?}",
        report.counters
    );
    assert!(pixel < 1e-2, "per-pixel: {pixel}");
    assert!(rules < 1e-2, "stencil rules: {rules}");
}

/// Step 2's stencil surface shadows decide each pixel's visibility at its centre from the same
/// triangles the reference ray-casts (z-pass count seeded with the eye's count), so the surface
/// AOV matches the reference up to f32 shading (~1e-6 relative) except at pixels whose centre lies
/// within rasterisation rounding of a shadow edge — none or a handful at 64². The bound 1e-3 rel
/// RMSE allows a few such pixels; the shadow-mapped surface pass (texel- and bias-limited) is
/// measured alongside and must not be better.
#[test]
fn stencil_surface_shadows_match_the_reference() {
    let Some(gpu) = gpu() else { return };
    let res = 64;
    for name in ["sphere-point", "desk-pencils"] {
        let scene = scenes::library::resolve(name).unwrap();
        let r = reference::render(&scene, 0, res, res, Settings::default(), &|_| {}).unwrap();
        let surface_error = |mode: &str| {
            let list = [("surface_shadows", text(mode))];
            let out = testing::render_method(&gpu, &BiriShadowVolumes, &scene, res, &list).unwrap();
            let e = compare(&out.surface, &r.surface, &ToneMap { exposure: 0.0 }).unwrap();
            (e, out.report)
        };
        let (stencil, report) = surface_error("stencil");
        let (map, _) = surface_error("shadow-map");
        eprintln!(
            "{name} {res}²: surface rel RMSE stencil {:.3e} (p99 {:.1e}), shadow map {:.3e}",
            stencil.rel_rmse, stencil.p99_abs, map.rel_rmse
        );
        assert!(report.run.iter().any(|p| p == "stencil-surface-shadows"));
        assert!(report.skipped.iter().any(|p| p.pass == "shadow-maps"));
        assert!(stencil.rel_rmse < 1e-3, "{name}: {}", stencil.rel_rmse);
        assert!(
            stencil.rel_rmse <= map.rel_rmse,
            "{name}: {} vs {}",
            stencil.rel_rmse,
            map.rel_rmse
        );
    }
}

/// `tests/scenes/sun-shafts.json` (a sun, a floating box and a sphere casting shafts, the eye
/// outside them); `sun_in_eye` moves the camera two metres down the light from the box's centre,
/// inside its shadow volume.
fn sun_scene(sun_in_eye: bool) -> Scene {
    let mut scene = testing::scene_text(include_str!("scenes/sun-shafts.json"), "sun-shafts");
    if sun_in_eye {
        scene.desc.camera.position = glam::Vec3::new(0.4, 0.6, 0.0);
        scene.desc.camera.look_at = glam::Vec3::new(3.0, 1.2, -2.5);
    }
    scene
}

/// Directional light (modernised: `lit_between`'s closed form σ_s E p(θ) (e^(−σ_t a) −
/// e^(−σ_t b))/σ_t, the shadow planes extruded along the light's direction). Without casters the
/// closed form alone matches the reference's quadrature (measured: eprintln); with the box's and
/// the sphere's shafts both resolves match it, with the eye outside and inside a shadow volume
/// (the eye's count seeds the walk), bound 5e-3 (rasterised shadow edges; measured < 1e-6). An irradiance
/// attenuated on the light leg, a missing phase, or shafts left unshadowed are ≥ 10 % off; the
/// last assertion checks the shafts are really in the image (the unshadowed closed form alone is
/// > 10× worse).
#[test]
fn directional_light_matches_reference() {
    let Some(gpu) = gpu() else { return };
    let mut clear = sun_scene(false);
    for o in &mut clear.desc.objects {
        o.casts_volumetric_shadow = false;
    }
    let open = Case::new(clear, 64);
    let unshadowed = open.error(&gpu, &[]);
    eprintln!("sun without casters 64²: in-scatter rel RMSE {unshadowed:.3e}");
    assert!(unshadowed < 1e-3, "closed form: {unshadowed}");
    for inside in [false, true] {
        let case = Case::new(sun_scene(inside), 64);
        let (pixel, pixel99, _) = case.errors(&gpu, &[], 1);
        let (rules, rules99, _) = case.errors(&gpu, &stencil(true), 1);
        let (every, every99, _) = case.errors(&gpu, &stencil(false), 1);
        let no_planes = compare_unshadowed(&gpu, &case);
        eprintln!(
            "sun shafts 64², eye in shadow {inside}: in-scatter rel RMSE / p99 per-pixel {pixel:.3e} / {pixel99:.3e}, stencil rules {rules:.3e} / {rules99:.3e}, every crossing {every:.3e} / {every99:.3e}, no shadow planes {no_planes:.3e}"
        );
        assert!(no_planes > 10.0 * pixel, "shafts missing? {no_planes}");
        if !inside {
            assert!(pixel < 5e-3, "per-pixel: {pixel}");
            assert!(rules < 5e-3, "stencil rules: {rules}");
            assert!(every < 5e-3, "every crossing: {every}");
            continue;
        }
        // Eye in the box's shaft: one pixel (a ray grazing a silhouette vertex's extruded edge,
        // as on overlap-point) dominates the RMSE; the 99th percentile shows the rest. The two
        // volumes never overlap along a ray, so counting every crossing is exact too. The
        // stencil rules are not (their CPU plane order, with the eye inside a volume; a point
        // light in the same place measures the same: README), so they are only measured.
        assert!(pixel99 < 1e-4, "per-pixel p99: {pixel99}");
        assert!(every99 < 1e-4, "every crossing p99: {every99}");
        assert!(pixel < 0.02, "per-pixel: {pixel}");
    }
}

/// The error of the method's in-scatter with no volumetric caster (the same scene's objects
/// flagged not to cast) against `case`'s reference, which has shafts.
fn compare_unshadowed(gpu: &Gpu, case: &Case) -> f64 {
    let mut scene = case.scene.clone();
    for o in &mut scene.desc.objects {
        o.casts_volumetric_shadow = false;
    }
    let out = testing::render_method(gpu, &BiriShadowVolumes, &scene, case.res, &[]).unwrap();
    compare(&out.inscatter, &case.reference, &ToneMap { exposure: 0.0 })
        .unwrap()
        .rel_rmse
}

/// Spot lights (modernised: `lit_between` integrates each lit interval by `spot_panels` two-node
/// Gauss–Legendre panels in the angle seen from the light, over the stretch inside the outer
/// cone, with the falloff and the projected pattern at every node). On stained-glass-spot at 64²
/// (a torus in the beam): with a reference-quality 64 panels both resolves match the reference
/// to the pattern texture's sampling (measured 0.051 both; bound 0.1); the default 8 panels
/// alias the pattern's lead lines on the brightest rays (measured 0.26, bound 0.5; the trimmed
/// headline is 0.057 at 128²: README); a single panel is worse (2.5: the quadrature is really
/// used). The pattern and the cone are really applied: the same image is
/// ≥ 5× further from the reference of the scene without its pattern, and a cone ignored or a
/// wrong constant factor would be ≥ 100 % off.
#[test]
fn spot_light_matches_reference() {
    let Some(gpu) = gpu() else { return };
    let case = Case::library("stained-glass-spot", 64);
    let panels = |n| ("spot_panels", ParamValue::Int(n));
    let fine = case.error(&gpu, &[panels(64)]);
    let mut list = stencil(true);
    list.push(panels(64));
    let rules = case.error(&gpu, &list);
    let default = case.error(&gpu, &[]);
    let coarse = case.error(&gpu, &[panels(1)]);
    let mut plain = case.scene.clone();
    for l in &mut plain.desc.lights {
        if let scenes::desc::LightDesc::Spot { pattern, .. } = l {
            *pattern = None;
        }
    }
    let plain_ref = reference::render(&plain, 0, 64, 64, Settings::default(), &|_| {}).unwrap();
    let out =
        testing::render_method(&gpu, &BiriShadowVolumes, &case.scene, 64, &[panels(64)]).unwrap();
    let t = ToneMap { exposure: 0.0 };
    let vs_plain = compare(&out.inscatter, &plain_ref.inscatter, &t)
        .unwrap()
        .rel_rmse;
    eprintln!(
        "stained-glass-spot 64² in-scatter rel RMSE: per-pixel 64 panels {fine:.3e}, stencil rules 64 panels {rules:.3e}, 8 panels {default:.3e}, 1 panel {coarse:.3e}; against the reference without the pattern {vs_plain:.3e}"
    );
    assert!(fine < 0.1, "64 panels: {fine}");
    assert!(rules < 0.1, "stencil, 64 panels: {rules}");
    assert!(default < 0.5, "8 panels: {default}");
    assert!(coarse > default, "1 panel {coarse} vs 8 {default}");
    assert!(
        vs_plain > 5.0 * fine,
        "pattern missing? {vs_plain} vs {fine}"
    );
}

/// One light of each kind in one scene (`tests/scenes/mixed-lights.json`: the sun of
/// sun-shafts.json plus a point light and a patterned spot, all shadowed by the box and the
/// sphere): `lit_between` dispatches per light, the point light's eye term is the only one, and
/// the baked kinds (`scene_has_light_kind`) keep every branch. Both resolves with a 64-panel spot
/// quadrature match the reference at 48² (measured 1.5e-3 both), bound 5e-3; dropping any one
/// light moves the reference by > 5 % (asserted), and a misdispatched kind is far worse.
#[test]
fn mixed_light_kinds_match_reference() {
    let Some(gpu) = gpu() else { return };
    let scene = testing::scene_text(include_str!("scenes/mixed-lights.json"), "mixed-lights");
    let case = Case::new(scene, 48);
    let panels = ("spot_panels", ParamValue::Int(64));
    let pixel = case.error(&gpu, std::slice::from_ref(&panels));
    let mut list = stencil(true);
    list.push(panels);
    let rules = case.error(&gpu, &list);
    eprintln!(
        "mixed lights 48² in-scatter rel RMSE: per-pixel {pixel:.3e}, stencil rules {rules:.3e}"
    );
    assert!(pixel < 5e-3, "per-pixel: {pixel}");
    assert!(rules < 5e-3, "stencil rules: {rules}");
    // Every light matters: the reference without it is ≥ 10× the bound away.
    for k in 0..case.scene.desc.lights.len() {
        let mut less = case.scene.clone();
        less.desc.lights.remove(k);
        let r = reference::render(&less, 0, 48, 48, Settings::default(), &|_| {}).unwrap();
        let e = compare(&r.inscatter, &case.reference, &ToneMap { exposure: 0.0 })
            .unwrap()
            .rel_rmse;
        eprintln!("without light {k}: {e:.3e}");
        assert!(e > 0.05, "light {k} hardly matters: {e}");
    }
}
