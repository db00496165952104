//! GPU tests of `umenhoffer-particle-blocks` and its baseline `particle-splat` (lavapipe in CI):
//! the depth impostor of one sphere against the analytic 1 − e^(−τ·chord), both methods against
//! the reference on a small cloud, the §2.4 depth-interval fix on `cloud-plane` (a measured
//! bound on the error where the aeroplane crosses the cloud, and the plain billboard clipping
//! it removes), and refusals of homogeneous scenes and bad knobs.
//!
//! Without an adapter these tests skip with a message — except when `CI` is set.

use std::path::Path;

use harness::Gpu;
use harness::image::Image;
use harness::image::headline::headline;
use harness::method::{FrameReport, KnobError, Method, ParamValue, Support};
use harness::runner::{AovTargets, render_frame};
use harness::testing::{self, gpu_or_skip as gpu, reference, rel_rmse};
use methods::umenhoffer_particle_blocks::accuracy::{Accuracy, PLAIN, PROFILE};
use methods::umenhoffer_particle_blocks::{ParticleSplat, UmenhofferParticleBlocks, blocks};
use scenes::{Scene, parse_scene};

fn scene(text: &str) -> Scene {
    parse_scene(text, "test.json", "test", Path::new(".")).unwrap_or_else(|e| panic!("{e}"))
}

/// A scene of `methods/tests/fixtures/`.
fn fixture(name: &str) -> Scene {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures");
    let text = std::fs::read_to_string(dir.join(name)).unwrap();
    parse_scene(&text, name, name.trim_end_matches(".json"), &dir).unwrap_or_else(|e| panic!("{e}"))
}

fn method(id: &str) -> &'static dyn Method {
    methods::find(id).expect("registered")
}

/// [inscatter, surface, total] of frame 0.
fn render(gpu: &Gpu, id: &str, scene: &Scene, res: u32, list: &[(&str, ParamValue)]) -> [Image; 3] {
    render_counted(gpu, id, scene, res, list).0
}

/// [inscatter, surface, total] of frame 0 and the frame's report (passes, counters).
fn render_counted(
    gpu: &Gpu,
    id: &str,
    scene: &Scene,
    res: u32,
    list: &[(&str, ParamValue)],
) -> ([Image; 3], FrameReport) {
    let mut m = testing::prepare(gpu, method(id), scene, res, list, false).unwrap();
    let aovs = AovTargets::new(gpu, res, res);
    let timing = render_frame(gpu, m.as_mut(), scene, 0, &aovs, None).unwrap();
    let out = aovs.read(gpu).unwrap();
    for img in &out {
        assert!(
            img.pixels.iter().flatten().all(|v| v.is_finite()),
            "{id}: non-finite pixel"
        );
    }
    (out, timing.report)
}

/// Knob overrides of one run.
type Knobs = Vec<(&'static str, ParamValue)>;

fn blocks(n: i64, mode: &str) -> Knobs {
    vec![
        ("blocks", ParamValue::Int(n)),
        ("instancing", ParamValue::Text(mode.into())),
    ]
}

/// One sphere (R = 1, τ = 0.8) in front of a uniform sky: the surface AOV is sky · e^(−τ·chord),
/// so 1 − surface/sky is the impostor's opacity, compared pixel by pixel with the analytic chord
/// of each pixel's ray (computed here, from the camera's own rays).
#[test]
fn impostor_opacity_of_one_sphere_matches_the_analytic_chord() {
    let Some(gpu) = gpu() else { return };
    let (r, tau) = (1.0f64, 0.8f64);
    let s = scene(&format!(
        r#"{{"camera": {{"position": [0, 0, 4], "look_at": [0, 0, 0], "fov_y_deg": 40, "far": 50}},
            "medium": {{"kind": "particles", "particles": [{{"center": [0, 0, 0], "radius": {r}, "density": {tau}}}],
                        "sky": [1, 1, 1]}},
            "lights": [{{"kind": "directional", "direction": [0, -1, 0], "irradiance": [1, 1, 1]}}]}}"#
    ));
    let res = 48;
    let rays = s.frame(0).camera.rays(res, res);
    let cases: [(&str, Knobs, f64, f64); 3] = [
        // One block of one particle: the opacity goes through a 64² depth impostor.
        // (f16 texels: ~1e-3; measured max 1.5e-3, mean 1.2e-3.)
        (
            "umenhoffer-particle-blocks",
            blocks(1, "prototype"),
            5e-3,
            3e-3,
        ),
        (
            "umenhoffer-particle-blocks",
            blocks(1, "clusters"),
            5e-3,
            3e-3,
        ),
        // The analytic splat: exact chord per fragment.
        ("particle-splat", vec![], 1e-4, 1e-5),
    ];
    for (id, list, max_tol, mean_tol) in cases {
        let [_, surface, _] = render(&gpu, id, &s, res, &list);
        let (mut worst, mut sum, mut inside) = (0.0f64, 0.0f64, 0);
        for j in 0..res {
            for i in 0..res {
                let d = rays.direction(i, j).normalize();
                let o = rays.origin;
                let tc = -o.dot(d);
                let perp2 = o.length_squared() - tc * tc;
                let chord = 2.0 * (r * r - perp2).max(0.0).sqrt();
                let want = 1.0 - (-tau * chord).exp();
                let got = 1.0 - surface.get(i, j)[0] as f64;
                let err = (got - want).abs();
                sum += err;
                // Away from the silhouette, where bilinear texels straddle the edge.
                if perp2.sqrt() < 0.9 * r {
                    worst = worst.max(err);
                    inside += 1;
                }
            }
        }
        let mean = sum / (res * res) as f64;
        println!(
            "{id} {list:?}: opacity max |err| inside {worst:.2e} ({inside} px), mean |err| {mean:.2e}"
        );
        assert!(inside > 200, "the sphere covers the view's centre");
        assert!(worst < max_tol, "{id}: max opacity error {worst}");
        assert!(mean < mean_tol, "{id}: mean opacity error {mean}");
    }
}

/// A small cloud over a floor in sunlight, 48², 8 slices: the splat and the blocks against the
/// reference. Bounds are ~1.3× what this machine measures; accuracy orders as expected: exact
/// splats, then cluster impostors (exact geometry, block-level light and depth), then one
/// prototype instanced (the paper's shape approximation).
#[test]
fn small_cloud_against_the_reference() {
    let Some(gpu) = gpu() else { return };
    let s = scene(
        r#"{"camera": {"position": [0, 1.6, 6], "look_at": [0, 1.2, 0], "fov_y_deg": 40, "far": 40},
            "medium": {"kind": "particles",
                       "generators": [{"shape": "cloud", "count": 400, "seed": 5, "center": [0, 1.3, 0],
                                       "radii": [1.5, 0.7, 1.0], "particle_radius": [0.12, 0.25], "density": 0.8,
                                       "albedo": [0.9, 0.9, 0.9]}],
                       "phase": {"kind": "henyey-greenstein", "g": 0.3}, "sky": [0.3, 0.4, 0.6]},
            "lights": [{"kind": "directional", "direction": [-0.3, -1, -0.4], "irradiance": [3, 3, 3]}],
            "objects": [{"name": "floor", "shape": {"kind": "plane", "size": [20, 20]}, "material": {"albedo": [0.5, 0.5, 0.5]}}]}"#,
    );
    let res = 48;
    let r = reference(&s, res);
    let mut errs = Vec::new();
    let eight = ("slices", ParamValue::Int(8));
    for (id, list) in [
        ("particle-splat", vec![eight.clone()]),
        (
            "umenhoffer-particle-blocks",
            [blocks(20, "clusters"), vec![eight.clone()]].concat(),
        ),
        (
            "umenhoffer-particle-blocks",
            [blocks(20, "prototype"), vec![eight.clone()]].concat(),
        ),
    ] {
        let [ins, surf, total] = render(&gpu, id, &s, res, &list);
        let e = (
            rel_rmse(&ins, &r.inscatter),
            rel_rmse(&surf, &r.surface),
            rel_rmse(&total, &r.total),
        );
        println!(
            "{id} {list:?}: rel RMSE inscatter {:.4}, surface {:.4}, total {:.4}",
            e.0, e.1, e.2
        );
        errs.push(e);
    }
    let (splat, clusters, proto) = (errs[0], errs[1], errs[2]);
    // Measured here: splat 0.125 / 0.0047, clusters 0.43 / 0.019, prototype 0.84 / 0.095.
    assert!(splat.0 < 0.17 && splat.2 < 0.01, "splat {splat:?}");
    assert!(
        clusters.0 < 0.55 && clusters.2 < 0.03,
        "clusters {clusters:?}"
    );
    assert!(proto.0 < 1.1 && proto.2 < 0.13, "prototype {proto:?}");
    assert!(splat.0 < clusters.0 && clusters.0 < proto.0, "{errs:?}");
}

/// A small block-instanced cloud (12 instances of one 40-particle block) in sunlight over a
/// floor: the paper's modelling assumption holds, so its error is the rendering approximation.
const BLOCK_CLOUD: &str = r#"{"camera": {"position": [0, 1.6, 6], "look_at": [0, 1.2, 0], "fov_y_deg": 40, "far": 40},
            "medium": {"kind": "particles",
                       "generators": [{"shape": "blocks",
                                       "block": {"generators": [{"shape": "cloud", "count": 40, "seed": 3, "center": [0, 0, 0],
                                                                 "radii": [0.5, 0.4, 0.5], "particle_radius": [0.1, 0.2], "density": 0.8,
                                                                 "albedo": [0.9, 0.9, 0.9]}]},
                                       "instances": [{"center": [0, 1.3, 0], "scale": 1.2, "density_scale": 0.7}],
                                       "placement": {"count": 11, "seed": 8, "center": [0, 1.3, 0], "radii": [1.4, 0.6, 0.9],
                                                     "scale": [0.8, 1.2]}}],
                       "phase": {"kind": "henyey-greenstein", "g": 0.3}, "sky": [0.3, 0.4, 0.6]},
            "lights": [{"kind": "directional", "direction": [-0.3, -1, -0.4], "irradiance": [3, 3, 3]}],
            "objects": [{"name": "floor", "shape": {"kind": "plane", "size": [20, 20]}, "material": {"albedo": [0.5, 0.5, 0.5]}}]}"#;

/// A small block-instanced cloud (12 instances of one 40-particle block, `blocks` generator),
/// 48², 8 slices: with the declared structure (`from_scene`, default) the prototype IS the
/// block and the instances are the declared ones, so the error is the rendering approximation
/// alone — below clustering the same particles into 12 blocks and instancing the most typical
/// cluster (the shape error), and counted as declared. Bounds ~1.3× what this machine measures.
#[test]
fn block_instanced_cloud_against_the_reference() {
    let Some(gpu) = gpu() else { return };
    let s = scene(BLOCK_CLOUD);
    let res = 48;
    let r = reference(&s, res);
    let eight = ("slices", ParamValue::Int(8));
    let mut errs = Vec::new();
    for (id, list) in [
        ("particle-splat", vec![eight.clone()]),
        ("umenhoffer-particle-blocks", vec![eight.clone()]),
        (
            "umenhoffer-particle-blocks",
            [
                blocks(12, "prototype"),
                vec![eight.clone(), ("from_scene", ParamValue::Bool(false))],
            ]
            .concat(),
        ),
    ] {
        let [ins, _, total] = render(&gpu, id, &s, res, &list);
        let e = (rel_rmse(&ins, &r.inscatter), rel_rmse(&total, &r.total));
        println!(
            "{id} {list:?}: rel RMSE inscatter {:.4}, total {:.4}",
            e.0, e.1
        );
        errs.push(e);
    }
    let (splat, declared, clustered) = (errs[0], errs[1], errs[2]);
    // Measured here: splat 0.117 / 0.0031, declared 0.53 / 0.028 (0.40 / 0.017 with issue 18's
    // moments and camera bins), clustered 0.94 / 0.084 (0.86 / 0.083).
    assert!(
        declared.0 < 0.69 && declared.1 < 0.036,
        "declared {declared:?}"
    );
    assert!(
        declared.0 < clustered.0 && declared.1 < clustered.1,
        "{errs:?}"
    );
    assert!(splat.0 < declared.0, "{errs:?}");
    // The record says which structure it used.
    let mut m = testing::prepare(
        &gpu,
        method("umenhoffer-particle-blocks"),
        &s,
        16,
        &[],
        false,
    )
    .unwrap();
    let aovs = AovTargets::new(&gpu, 16, 16);
    let c = render_frame(&gpu, m.as_mut(), &s, 0, &aovs, None)
        .unwrap()
        .report
        .counters;
    assert_eq!(
        (c["declared_blocks"], c["blocks"], c["particles_per_block"]),
        (1.0, 12.0, 40.0),
        "{c:?}"
    );
}

/// The block pixel's interval and the prototype's camera impostors (issue 18) on the
/// block-instanced cloud at 64², 4 slices, against the reference: the defaults (`interval =
/// moments`, `camera_bins = 3`) beat each paper variant alone (`bounds`; one camera impostor)
/// and both together (each by a measured margin), within a bound ~1.2× measured. Measured
/// (headline in-scatter): splat 0.057; defaults 0.134; `bounds` 0.150; one camera impostor
/// 0.158; both (the paper) 0.171. (The issue's 1.5× of the splat is a 256² `cloud-blocks`
/// criterion, measured with the CLI: README; on this 12-block cloud the ratio is 2.4×.)
#[test]
fn block_moments_and_camera_bins_against_the_reference() {
    let Some(gpu) = gpu() else { return };
    let s = scene(BLOCK_CLOUD);
    let res = 64;
    let r = reference(&s, res);
    let bounds = ("interval", ParamValue::Text("bounds".into()));
    let one = ("camera_bins", ParamValue::Int(1));
    let mut errs = Vec::new();
    for (id, list) in [
        ("particle-splat", vec![]),
        ("umenhoffer-particle-blocks", vec![]),
        ("umenhoffer-particle-blocks", vec![bounds.clone()]),
        ("umenhoffer-particle-blocks", vec![one.clone()]),
        ("umenhoffer-particle-blocks", vec![bounds, one]),
    ] {
        let [ins, _, total] = render(&gpu, id, &s, res, &list);
        let e = (headline(&ins, &r.inscatter), headline(&total, &r.total));
        println!(
            "{id} {list:?}: headline inscatter {:.4}, total {:.4}",
            e.0, e.1
        );
        errs.push(e.0);
    }
    let (splat, now, paper) = (errs[0], errs[1], errs[4]);
    assert!(errs[2..].iter().all(|&e| now < e), "{errs:?}");
    assert!(now < 0.16, "{errs:?}");
    assert!(
        paper > now * 1.2,
        "the paper's variant is measurably worse: {errs:?}"
    );
    assert!(
        splat < now,
        "the splat has no block approximation: {errs:?}"
    );
}

/// smoke-point at 48²: a point light beside a smoke column in a thin background haze (the
/// perspective light map, 1/r², the haze marched in the angle variable). Bounds ~1.3× measured.
#[test]
fn point_lit_smoke_against_the_reference() {
    let Some(gpu) = gpu() else { return };
    let s = scenes::library::resolve("smoke-point").unwrap();
    let res = 48;
    let r = reference(&s, res);
    for (id, bound) in [
        ("particle-splat", 0.55),
        ("umenhoffer-particle-blocks", 0.62),
    ] {
        let [ins, _, total] = render(&gpu, id, &s, res, &[]);
        let (ei, et) = (rel_rmse(&ins, &r.inscatter), rel_rmse(&total, &r.total));
        println!("{id}: rel RMSE inscatter {ei:.4}, total {et:.4}");
        assert!(ei < bound, "{id}: inscatter {ei}");
    }
}

/// cloud-plane (Fig. 7), 48²: where the aeroplane lies inside the cloud (68 pixels), a measured
/// bound on the total radiance's error with the depth-interval scaling (§2.4); plain billboard
/// clipping (`clip_fix = false`) fades the object by whole blocks in front of or behind each
/// billboard plane — the visible discontinuity — and errs more there.
#[test]
fn cloud_plane_has_no_billboard_clipping_discontinuity() {
    let Some(gpu) = gpu() else { return };
    let s = scenes::library::resolve("cloud-plane").unwrap();
    let res = 48;
    let r = reference(&s, res);
    let rays = s.frame(0).camera.rays(res, res);
    // The band: pixels whose ray hits the aeroplane (above the floor) inside the cloud's
    // ellipsoid (the generator's centre and radii in cloud-plane.json).
    let (c, radii) = (
        glam::DVec3::new(0.0, 2.0, 0.0),
        glam::DVec3::new(2.5, 1.2, 1.8),
    );
    let mut band = Vec::new();
    for j in 0..res {
        for i in 0..res {
            let dist = r.distance[(j * res + i) as usize] as f64;
            let d = rays.direction(i, j).normalize();
            let far = rays.far_distance(rays.direction(i, j));
            if dist >= far * 0.999 {
                continue;
            }
            let p = rays.origin + d * dist;
            if p.y > 0.5 && ((p - c) / radii).length() < 1.0 {
                band.push((i, j));
            }
        }
    }
    assert!(
        band.len() > 30,
        "the aeroplane crosses the cloud in view ({} px)",
        band.len()
    );
    let band_err = |img: &Image| -> f64 {
        let (mut e, mut m) = (0.0, 0.0);
        for &(i, j) in &band {
            let (a, b) = (img.get(i, j), r.total.get(i, j));
            for k in 0..3 {
                e += (a[k] as f64 - b[k] as f64).abs();
                m += b[k] as f64;
            }
        }
        e / m
    };
    let mut out = Vec::new();
    let fix = |on: bool| ("clip_fix", ParamValue::Bool(on));
    for (id, list) in [
        ("particle-splat", vec![fix(true)]),
        ("particle-splat", vec![fix(false)]),
        ("umenhoffer-particle-blocks", vec![fix(true)]),
        ("umenhoffer-particle-blocks", vec![fix(false)]),
        (
            "umenhoffer-particle-blocks",
            [blocks(20, "clusters"), vec![fix(true)]].concat(),
        ),
        (
            "umenhoffer-particle-blocks",
            [blocks(20, "clusters"), vec![fix(false)]].concat(),
        ),
    ] {
        let [_, _, total] = render(&gpu, id, &s, res, &list);
        let e = band_err(&total);
        println!(
            "{id} {list:?}: mean |error| / mean radiance on the {}-pixel band: {e:.4}",
            band.len()
        );
        out.push(e);
    }
    // Measured: splat 0.052 / 0.052, prototype-40 0.196 / 0.205, clusters-20 0.099 / 0.134.
    assert!(out[0] < 0.08, "splat with the fix: {}", out[0]);
    assert!(out[2] < 0.26, "blocks (prototype) with the fix: {}", out[2]);
    assert!(out[4] < 0.13, "blocks (clusters) with the fix: {}", out[4]);
    // Big billboards clip visibly; the depth interval removes it...
    assert!(
        out[4] < 0.85 * out[5],
        "clusters: fix {} vs billboard clipping {}",
        out[4],
        out[5]
    );
    assert!(
        out[2] < out[3],
        "prototype: fix {} vs billboard clipping {}",
        out[2],
        out[3]
    );
    // ...while per-particle billboards are small enough that clipping them barely matters.
    assert!(
        (out[0] - out[1]).abs() < 0.05 * out[0],
        "splat: {} vs {}",
        out[0],
        out[1]
    );
}

#[test]
fn homogeneous_scenes_and_bad_knobs_are_refused() {
    let fog = scenes::library::resolve("sphere-point").unwrap();
    for id in ["umenhoffer-particle-blocks", "particle-splat"] {
        match method(id).support(&fog.features(), wgpu::Features::all()) {
            Support::No(why) => assert!(why.contains("homogeneous"), "{id}: {why}"),
            other => panic!("{id}: {other:?}"),
        }
        let cloud = scenes::library::resolve("cloud-8000").unwrap();
        assert_eq!(
            method(id).support(&cloud.features(), wgpu::Features::all()),
            Support::Full
        );
    }
    let Some(gpu) = gpu() else { return };
    let cloud = scenes::library::resolve("cloud-8000").unwrap();
    for (id, list) in [
        (
            "umenhoffer-particle-blocks",
            vec![("slices", ParamValue::Int(5))],
        ),
        (
            "umenhoffer-particle-blocks",
            vec![("blocks", ParamValue::Int(0))],
        ),
        ("particle-splat", vec![("light_res", ParamValue::Int(1))]),
        // `auto` is a value of the accuracy knobs (accuracy.rs), spelt exactly.
        (
            "particle-splat",
            vec![("eye_slices", ParamValue::from("Auto"))],
        ),
        (
            "particle-splat",
            vec![("chord_steps", ParamValue::from("automatic"))],
        ),
    ] {
        let err = match testing::prepare(&gpu, method(id), &cloud, 16, &list, false) {
            Ok(_) => panic!("{id} {list:?}: accepted"),
            Err(e) => e,
        };
        let knob = err
            .downcast_ref::<KnobError>()
            .unwrap_or_else(|| panic!("{id} {list:?}: not a knob error: {err}"));
        assert_eq!(knob.knob, list[0].0, "{err}");
        println!("{id} {list:?}: {err}");
    }
    let _ = (UmenhofferParticleBlocks, ParticleSplat);
}

/// The fixture `two-lights.json` (a sun and a point light) at 48²: both methods against the
/// reference (headline, total and in-scatter). The bounds are ~1.3× what this machine measures
/// (splat 0.0057 / 0.071, 20 clusters 0.013 / 0.145, 40 prototype blocks 0.038 / 0.376) and
/// the test shows they mean something: the reference of either light alone is further from
/// the two-light reference than the bound, so a method that lost one light pass would fail.
#[test]
fn two_lights_add_up_against_the_reference() {
    let Some(gpu) = gpu() else { return };
    let s = fixture("two-lights.json");
    assert_eq!(s.desc.lights.len(), 2);
    let res = 48;
    let r = reference(&s, res);
    // (id, knobs, bound on the total's headline, on the in-scatter's)
    let cases = [
        ("particle-splat", vec![], 0.0075, 0.092),
        (
            "umenhoffer-particle-blocks",
            blocks(20, "clusters"),
            0.017,
            0.19,
        ),
        ("umenhoffer-particle-blocks", vec![], 0.05, 0.49),
    ];
    for k in 0..2 {
        let mut alone = s.clone();
        alone.desc.lights = vec![s.desc.lights[k].clone()];
        let ra = reference(&alone, res);
        let (et, ei) = (
            headline(&ra.total, &r.total),
            headline(&ra.inscatter, &r.inscatter),
        );
        println!("light {k} alone vs both: headline total {et:.4}, inscatter {ei:.4}");
        for (id, list, bt, bi) in &cases {
            assert!(
                et > *bt && ei > *bi,
                "{id} {list:?}: light {k} alone ({et}, {ei}) passes"
            );
        }
    }
    // One light map per light.
    headlines_within(&gpu, &s, &r, &cases, 2.0);
}

/// (method, knobs, bound on the total's headline error, on the in-scatter's).
type Case = (&'static str, Vec<(&'static str, ParamValue)>, f64, f64);

/// Every case rendered at the reference's resolution within its bounds, its frame reporting
/// `faces` light maps.
fn headlines_within(
    gpu: &Gpu,
    s: &Scene,
    r: &harness::reference::ReferenceImages,
    cases: &[Case],
    faces: f64,
) {
    for (id, list, bt, bi) in cases {
        let ([ins, _, total], report) = render_counted(gpu, id, s, r.total.width, list);
        let (et, ei) = (headline(&total, &r.total), headline(&ins, &r.inscatter));
        let c = &report.counters;
        println!(
            "{id} {list:?}: headline total {et:.4}, inscatter {ei:.4} (slices {}, chord_steps {}, eye_slices {})",
            c["slices"], c["chord_steps"], c["eye_slices"]
        );
        assert_eq!(report.counters["light_faces"], faces, "{id}: light maps");
        assert!(
            et < *bt && ei < *bi,
            "{id} {list:?}: total {et}, inscatter {ei}"
        );
    }
}

/// Whether `x` lies inside the bounds of one of the scene's particles' 20 cluster blocks.
fn inside_a_block(s: &Scene, x: glam::Vec3) -> bool {
    let medium = s.medium();
    let particles = &medium.particles().unwrap().particles;
    let set = blocks::blocked(particles, 20, blocks::Instancing::Clusters);
    set.prims
        .iter()
        .any(|p| (glam::Vec3::from_slice(&p.center[..3]) - x).length() < p.center[3])
}

/// The accuracy knobs at the plain values `auto` takes where no viewer is inside a particle (8
/// slices, the closed form, "over"), plus `more`.
fn plain(more: Knobs) -> Knobs {
    let mut v = vec![
        ("slices", ParamValue::Int(8)),
        ("chord_steps", ParamValue::Int(0)),
        ("eye_slices", ParamValue::Bool(false)),
    ];
    v.extend(more);
    v
}

/// A point light inside the small cloud, within a block's bounds: the single perspective map
/// cannot see every block, so the light pass renders a cube of six maps (`light_faces` = 6) and
/// the blocks holding or near the light are drawn as their particles. Headline errors against
/// the reference (total, in-scatter), bounds ~1.3× measured, with the plain accuracy values
/// ([`plain`]): splat 0.040 / 0.081, 20 clusters 0.053 / 0.102, 40 prototype blocks 0.082 /
/// 0.131 (with issue 18's moments, camera bins and `near_light` 2: clusters 0.049 / 0.098,
/// prototype 0.051 / 0.098; since issue 32's dominant spheres: splat 0.032 / 0.064, clusters
/// 0.034 / 0.069, prototype 0.038 / 0.072). The light is inside a particle too, so the defaults (`auto`) are
/// the accurate profile; bounds ~1.5× measured: splat 0.0056 / 0.0111, clusters 0.0057 /
/// 0.0112, prototype 0.0103 / 0.0145.
#[test]
fn a_light_inside_the_cloud_renders_against_the_reference() {
    let Some(gpu) = gpu() else { return };
    let mut s = fixture("two-lights.json");
    let centre = glam::Vec3::new(0.1, 1.35, 0.05);
    s.desc.lights = vec![scenes::desc::LightDesc::Point {
        position: centre,
        intensity: glam::Vec3::new(3.0, 3.0, 3.0),
        keyframes: Vec::new(),
    }];
    assert!(
        inside_a_block(&s, centre),
        "the light lies inside a block's bounds"
    );
    let clusters = || blocks(20, "clusters");
    let cases = [
        ("particle-splat", plain(vec![]), 0.052, 0.106),
        ("umenhoffer-particle-blocks", plain(clusters()), 0.07, 0.135),
        ("umenhoffer-particle-blocks", plain(vec![]), 0.11, 0.17),
        ("particle-splat", vec![], 0.0085, 0.017),
        ("umenhoffer-particle-blocks", clusters(), 0.0086, 0.017),
        ("umenhoffer-particle-blocks", vec![], 0.016, 0.022),
    ];
    // A cube of six light maps.
    headlines_within(&gpu, &s, &reference(&s, 48), &cases, 6.0);
}

/// The camera inside the small cloud, within a block's bounds: that block is drawn over the
/// whole view (a billboard cannot cover its viewer), its interval cut at the eye. Headline
/// errors against the reference (total, in-scatter), bounds ~1.3× measured with the plain
/// accuracy values: splat 0.032 / 0.064, 20 clusters 0.098 / 0.055 (since issue 32's dominant
/// spheres: splat 0.026 / 0.051, clusters 0.104 / 0.059). The eye is inside a
/// particle too, so the defaults (`auto`) are the accurate profile; bounds ~1.5× measured:
/// splat 0.0012 / 0.0023, clusters 0.0817 / 0.0388.
#[test]
fn a_camera_inside_the_cloud_renders_against_the_reference() {
    let Some(gpu) = gpu() else { return };
    let mut s = fixture("two-lights.json");
    let eye = glam::Vec3::new(-0.4, 1.3, 0.3);
    s.desc.camera.position = eye;
    s.desc.camera.look_at = glam::Vec3::new(1.5, 1.1, -0.5);
    s.desc.lights.truncate(1);
    assert!(
        inside_a_block(&s, eye),
        "the eye lies inside a block's bounds"
    );
    let clusters = || blocks(20, "clusters");
    let cases = [
        ("particle-splat", plain(vec![]), 0.042, 0.083),
        (
            "umenhoffer-particle-blocks",
            plain(clusters()),
            0.127,
            0.071,
        ),
        ("particle-splat", vec![], 0.002, 0.0035),
        ("umenhoffer-particle-blocks", clusters(), 0.12, 0.058),
    ];
    headlines_within(&gpu, &s, &reference(&s, 48), &cases, 1.0);
}

/// `smoke-absorber.json`: smoke-point with black particles, so the only in-scatter is the
/// background haze's and the column only dims it. Dimming by the gathered opacity must bring
/// the haze behind the column closer to the reference than leaving it undimmed (48²; measured
/// in-scatter headline dimmed / undimmed: splat 0.0025 / 0.0133, blocks 0.0059 / 0.0148).
#[test]
fn the_cloud_dims_the_background_haze() {
    let Some(gpu) = gpu() else { return };
    let s = fixture("smoke-absorber.json");
    let res = 48;
    let r = reference(&s, res);
    for id in ["particle-splat", "umenhoffer-particle-blocks"] {
        let dim = |on: bool| {
            let list = [("background_dimming", ParamValue::Bool(on))];
            let [ins, _, _] = render(&gpu, id, &s, res, &list);
            headline(&ins, &r.inscatter)
        };
        let (on, off) = (dim(true), dim(false));
        println!("{id}: in-scatter headline dimmed {on:.4}, undimmed {off:.4}");
        assert!(on < 0.7 * off, "{id}: dimmed {on} vs undimmed {off}");
    }
}

/// Viewers inside particles (issue 32): the eye inside one particle and a point light inside
/// another (`particles-inside-201.json`; `particles-inside-dense-eye.json`, the eye inside a
/// particle of optical depth ≈ 5 to its surface, isotropic phase; `particles-inside-deep-light.json`,
/// the light inside a particle of optical depth 3 to its surface in a denser cloud, HG 0.5).
/// Both methods at their defaults against the reference at 48²: the mean in-scatter within 10 %
/// of the reference's (issue 32's criterion, results.json `mean_ratio`) and the in-scatter
/// headline within 3× the method's own headline on `cloud-8000` at the same resolution and
/// defaults (README.md "Viewers inside particles"). The accuracy knobs' default `auto`
/// (accuracy.rs) resolves to the accurate profile (32 slices, 8 quadrature nodes, the eye's
/// slices) on the three fixtures and to the plain values (8, 0, false) on `cloud-8000`, checked
/// in the frames' counters. Explicit values are kept: the plain values on deep-light report
/// 8 / 0 / false, and there the splat's headline is 0.196 (printed), far past its 3 × 0.025 —
/// so the test fails if `auto` stops resolving per scene.
#[test]
fn viewers_inside_particles_against_the_reference() {
    let Some(gpu) = gpu() else { return };
    let res = 48;
    let cloud = scenes::library::resolve("cloud-8000").unwrap();
    let cloud_ref = reference(&cloud, res);
    let fixtures: Vec<_> = [
        "particles-inside-201.json",
        "particles-inside-dense-eye.json",
        "particles-inside-deep-light.json",
    ]
    .into_iter()
    .map(|name| {
        let s = fixture(name);
        let r = reference(&s, res);
        (name, s, r)
    })
    .collect();
    for id in ["particle-splat", "umenhoffer-particle-blocks"] {
        let ([ins, _, _], report) = render_counted(&gpu, id, &cloud, res, &[]);
        assert_accuracy(&report, PLAIN, &format!("{id} cloud-8000"));
        let own = headline(&ins, &cloud_ref.inscatter);
        println!("{id}: cloud-8000 in-scatter headline {own:.4}");
        for (name, s, r) in &fixtures {
            let ([ins, _, _], report) = render_counted(&gpu, id, s, res, &[]);
            assert_accuracy(&report, PROFILE, &format!("{id} {name}"));
            let (h, ratio) = (
                headline(&ins, &r.inscatter),
                ins.mean() / r.inscatter.mean(),
            );
            println!("{id} {name}: in-scatter headline {h:.4}, mean ratio {ratio:.3}");
            assert!(
                (0.9..=1.1).contains(&ratio),
                "{id} {name}: mean in-scatter {ratio:.3}× the reference's"
            );
            assert!(
                h <= 3.0 * own,
                "{id} {name}: headline {h:.4} > 3 × its cloud-8000 headline {own:.4}"
            );
        }
        let (name, s, r) = &fixtures[2];
        let ([ins, _, _], report) = render_counted(&gpu, id, s, res, &plain(vec![]));
        assert_accuracy(&report, PLAIN, &format!("{id} {name}, explicit values"));
        let h = headline(&ins, &r.inscatter);
        println!("{id} {name}, explicit 8 slices, closed form, over: in-scatter headline {h:.4}");
    }
}

/// The frame's counters `slices`, `chord_steps`, `eye_slices` (the accuracy knobs as used) are
/// `want`'s.
fn assert_accuracy(report: &FrameReport, want: Accuracy, what: &str) {
    let c = &report.counters;
    let got = (c["slices"], c["chord_steps"], c["eye_slices"]);
    let expected = (
        want.slices as f64,
        want.chord_steps as f64,
        want.eye_slices as u32 as f64,
    );
    assert_eq!(
        got, expected,
        "{what}: (slices, chord_steps, eye_slices) used"
    );
}
