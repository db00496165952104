//! The reference on particle media (ARCHITECTURE §1, "particles") against things it does not
//! compute itself: optical depth by dense point sampling of the density, closed forms for a
//! single sphere, an independent midpoint quadrature with its own ray–sphere chords, and its
//! own 4×-tighter convergence report on the library's particle scenes.

use std::f64::consts::PI;
use std::path::Path;

use glam::DVec3;
use harness::reference::particles::ParticleField;
use harness::reference::{Settings, convergence, render, trace_pixels};
use scenes::{Scene, library, parse_scene};

fn scene(text: &str) -> Scene {
    parse_scene(text, "test.json", "test", Path::new(".")).unwrap_or_else(|e| panic!("{e}"))
}

fn lib(name: &str) -> Scene {
    library::load(name)
        .unwrap()
        .unwrap_or_else(|e| panic!("{e}"))
}

/// Density Σ τ_j [|x − c_j| < r_j] at x, by brute force over every particle.
fn density(p: &scenes::Particles, x: DVec3) -> f64 {
    p.particles
        .iter()
        .filter(|q| (x - q.center.as_dvec3()).length() < q.radius as f64)
        .map(|q| q.density as f64)
        .sum()
}

#[test]
fn chord_optical_depth_matches_dense_sampling() {
    let s = lib("cloud-plane");
    let medium = s.medium();
    let p = medium.particles().expect("a particle scene");
    let field = ParticleField::new(p);
    // Segments through the cloud in several directions, from inside and from outside.
    let segs = [
        (
            DVec3::new(-6.0, 2.0, 0.1),
            DVec3::new(1.0, 0.0, 0.0),
            0.0,
            12.0,
        ),
        (
            DVec3::new(0.3, -1.0, -0.2),
            DVec3::new(0.1, 1.0, 0.05),
            1.0,
            6.0,
        ),
        (
            DVec3::new(0.0, 2.0, 0.0),
            DVec3::new(0.3, 0.5, -0.8),
            0.0,
            4.0,
        ),
        (
            DVec3::new(2.0, 3.0, 9.0),
            DVec3::new(-0.2, -0.1, -1.0),
            2.0,
            14.0,
        ),
    ];
    let n = 200_000;
    let mut nonzero = 0;
    for (o, d, a, b) in segs {
        let d = d.normalize();
        let exact = field.optical_depth(o, d, a, b);
        let h = (b - a) / n as f64;
        let sampled: f64 = (0..n)
            .map(|k| density(p, o + d * (a + (k as f64 + 0.5) * h)) * h)
            .sum();
        println!("segment from {o} along {d}: chords {exact:.6}, sampled {sampled:.6}");
        // Midpoint sampling of a step function errs by ≤ τ·h per boundary crossed.
        let tol = 1e-3 * sampled.max(1e-3);
        assert!((exact - sampled).abs() < tol, "{exact} vs {sampled}");
        if exact > 0.5 {
            nonzero += 1;
        }
    }
    assert!(nonzero >= 3, "the segments cross the cloud");
}

/// One sphere of radius R, τ, albedo a at the origin; the camera on +z looks through its centre
/// and the sun shines from behind the camera along the view direction, so the light comes
/// back toward the eye (θ = π). At depth s into the chord both legs cross the same sphere
/// depth s: L_in = a τ p(π) E ∫_0^{2R} e^(−2τ s) ds = a p(π) E (1 − e^(−4τR)) / 2, and the sky
/// behind is seen through e^(−2τR).
#[test]
fn single_sphere_backscattered_sun_matches_closed_form() {
    let (r, tau, a, e, sky) = (1.0f64, 0.7f64, 0.8f64, 2.0f64, 0.3f64);
    let s = scene(&format!(
        r#"{{"camera": {{"position": [0, 0, 5], "look_at": [0, 0, 0], "far": 50}},
            "medium": {{"kind": "particles", "particles": [{{"center": [0, 0, 0], "radius": {r}, "density": {tau}, "albedo": [{a}, {a}, {a}]}}],
                        "phase": {{"kind": "henyey-greenstein", "g": 0.5}}, "sky": [{sky}, {sky}, {sky}]}},
            "lights": [{{"kind": "directional", "direction": [0, 0, -1], "irradiance": [{e}, {e}, {e}]}}]}}"#
    ));
    // Henyey–Greenstein g = 0.5 at cos θ = −1: (1 − g²) / (4π (1 + g)³).
    let p0 = (1.0 - 0.25) / (4.0 * PI * (1.0f64 + 0.5).powi(3));
    let want_in = a * p0 * e * (1.0 - (-4.0 * tau * r).exp()) / 2.0;
    let want_sky = sky * (-2.0 * tau * r).exp();
    let got = trace_pixels(&s, 0, 1, 1, Settings::default(), &[(0, 0)], &|_| {}).unwrap()[0];
    println!(
        "in-scatter {} vs {want_in}, sky {} vs {want_sky}",
        got.inscatter.x, got.surface.x
    );
    assert!((got.inscatter.x / want_in - 1.0).abs() < 1e-6, "{got:?}");
    // τ, R and the sky are f32 in the scene file: agreement to f32 precision.
    assert!((got.surface.x / want_sky - 1.0).abs() < 1e-6, "{got:?}");
    assert!(!got.hit);
}

/// Two overlapping spheres and a point light beside the ray, with a background medium: the
/// reference against a midpoint quadrature written here (its own chords, its own sums).
#[test]
fn point_light_through_overlapping_spheres_matches_dense_quadrature() {
    let spheres = [
        (DVec3::new(0.0, 0.0, 0.0), 1.0, 0.9, 0.8),
        (DVec3::new(0.3, 0.5, -0.8), 0.7, 1.5, 0.6),
        // Off the camera ray, it shadows part of it from the light.
        (DVec3::new(1.2, 0.6, -0.3), 0.5, 3.0, 0.5),
    ];
    let parts: Vec<String> = spheres
        .iter()
        .map(|(c, r, t, a)| {
            format!(r#"{{"center": [{}, {}, {}], "radius": {r}, "density": {t}, "albedo": [{a}, {a}, {a}]}}"#, c.x, c.y, c.z)
        })
        .collect();
    let (bs, ba) = (0.05, 0.01);
    let lp = DVec3::new(2.5, 1.0, 0.0);
    let s = scene(&format!(
        r#"{{"camera": {{"position": [0.1, 0.2, 6], "look_at": [0, 0, 0], "far": 12}},
            "medium": {{"kind": "particles", "particles": [{}],
                        "background": {{"sigma_a": [{ba}, {ba}, {ba}], "sigma_s": [{bs}, {bs}, {bs}]}}}},
            "lights": [{{"kind": "point", "position": [{}, {}, {}], "intensity": [5, 5, 5]}}]}}"#,
        parts.join(","),
        lp.x,
        lp.y,
        lp.z
    ));
    let cam = s.frame(0).camera;
    let rays = cam.rays(1, 1);
    let d = rays.direction(0, 0).normalize();
    let o = rays.origin;
    let len = rays.far_distance(rays.direction(0, 0));
    // Independent optical depth along a segment: chords by the quadratic formula.
    let depth = |x: DVec3, u: DVec3, tmax: f64| -> f64 {
        spheres
            .iter()
            .map(|&(c, r, t, _)| {
                let b = (x - c).dot(u);
                let cc = (x - c).length_squared() - r * r;
                let disc = b * b - cc;
                if disc <= 0.0 {
                    return 0.0;
                }
                let (t0, t1) = (-b - disc.sqrt(), -b + disc.sqrt());
                t * (t1.min(tmax) - t0.max(0.0)).max(0.0)
            })
            .sum()
    };
    let n = 400_000;
    let h = len / n as f64;
    let mut sum = 0.0;
    for k in 0..n {
        let t = (k as f64 + 0.5) * h;
        let x = o + d * t;
        let sig_s: f64 = bs
            + spheres
                .iter()
                .filter(|(c, r, _, _)| (x - *c).length() < *r)
                .map(|(_, _, tau, a)| a * tau)
                .sum::<f64>();
        let w = lp - x;
        let r = w.length();
        let tr = (-(ba + bs) * (t + r) - depth(o, d, t) - depth(x, w / r, r)).exp();
        sum += sig_s / (4.0 * PI) * 5.0 / (r * r) * tr * h;
    }
    let got = trace_pixels(&s, 0, 1, 1, Settings::default(), &[(0, 0)], &|_| {}).unwrap()[0];
    println!(
        "in-scatter: reference {}, dense quadrature {sum}",
        got.inscatter.x
    );
    assert!(
        (got.inscatter.x / sum - 1.0).abs() < 1e-4,
        "{} vs {sum}",
        got.inscatter.x
    );
}

#[test]
fn reference_converges_on_particle_scenes() {
    for (name, res) in [("cloud-8000", 16), ("cloud-plane", 24), ("smoke-point", 24)] {
        let s = lib(name);
        let img = render(&s, 0, res, res, Settings::default(), &|_| {}).unwrap();
        let c = convergence(&s, 0, &img, Settings::default(), 2).unwrap();
        println!(
            "{name} {res}²: {:.2} s, rel RMSE inscatter {:e}, total {:e} ({} pixels, {:.2} s)",
            img.stats.seconds, c.rel_rmse_inscatter, c.rel_rmse_total, c.pixels, c.seconds
        );
        assert!(
            c.rel_rmse_total < 1e-4 && c.rel_rmse_inscatter < 1e-4,
            "{name}: {c:?}"
        );
        assert!(
            img.inscatter.mean() > 0.0,
            "{name}: the cloud scatters light"
        );
        assert!(img.inscatter.pixels.iter().flatten().all(|v| v.is_finite()));
    }
}

/// Not a check: times the reference on `SB_PROFILE_SCENES` (comma-separated, default the
/// particle scenes) at `SB_PROFILE_RES` (default 32) and, with `SB_PROFILE_COMPARE=DIR`,
/// reports the relative RMSE and largest relative difference against DIR/<scene>/*.exr
/// (e.g. what `scatterbench reference --out DIR/<scene>` wrote with an older build).
/// `cargo test --release -p harness --test particle_reference profile -- --ignored --nocapture`
#[test]
#[ignore]
fn profile_reference() {
    let names = std::env::var("SB_PROFILE_SCENES")
        .unwrap_or_else(|_| "cloud-8000,cloud-plane,smoke-point".into());
    let res: u32 = std::env::var("SB_PROFILE_RES")
        .ok()
        .and_then(|r| r.parse().ok())
        .unwrap_or(32);
    let compare = std::env::var("SB_PROFILE_COMPARE").ok();
    let mut total = 0.0;
    for name in names.split(',') {
        let s = lib(name);
        let img = render(&s, 0, res, res, Settings::default(), &|_| {}).unwrap();
        total += img.stats.seconds;
        let mut line = format!("{name} {res}²: {:.3} s", img.stats.seconds);
        if let Some(dir) = &compare {
            for (aov, got) in [("inscatter", &img.inscatter), ("total", &img.total)] {
                let path = Path::new(dir).join(name).join(format!("{aov}.exr"));
                let Ok(want) = harness::image::io::read_exr(&path) else {
                    continue;
                };
                let (mut se, mut mean, mut worst) = (0.0f64, 0.0f64, 0.0f64);
                for (a, b) in got.pixels.iter().zip(&want.pixels) {
                    for c in 0..3 {
                        let (a, b) = (a[c] as f64, b[c] as f64);
                        se += (a - b).powi(2);
                        mean += b;
                        worst = worst.max((a - b).abs() / b.abs().max(1e-6));
                    }
                }
                let n = 3.0 * got.pixels.len() as f64;
                line += &format!(
                    ", {aov} rel RMSE {:.2e} max rel {:.2e}",
                    (se / n).sqrt() / (mean / n).max(1e-300),
                    worst
                );
            }
        }
        println!("{line}");
    }
    println!("total {total:.3} s");
}
