//! The CPU reference against things it does not compute itself.
//!
//! Every expected value here comes from code in this file — its own pixel rays, its own
//! quadrature (composite Gauss–Legendre in a sinh substitution, not the reference's adaptive
//! Gauss–Kronrod in Biri's angle), its own ray–sphere and ray–plane geometry, closed forms —
//! or from an independent query (dense point sampling of visibility). Nothing is a recorded
//! output of the code under test.
//!
//! Physics (ARCHITECTURE §1): for a camera ray o + x d, 0 ≤ x ≤ D,
//! L_in = ∫_0^D σ_s p(θ) V(x) I(ω) e^(−σ_t (x + r(x))) / r(x)² dx, r the distance to the light,
//! θ the angle between the light's propagation direction at x (x − L) and the direction toward
//! the eye (−d). A ray that hits nothing ends at the far plane (view depth = far).

use std::f64::consts::PI;
use std::path::Path;
use std::sync::OnceLock;

use glam::{DVec3, Vec3};
use harness::reference::shadow::{Source, shadowed};
use harness::reference::world::World;
use harness::reference::{ReferenceImages, Settings, convergence, render, trace_pixels};
use scenes::{CameraPose, Scene, library, parse_scene};

// ---------------------------------------------------------------------------------------------
// Independent helpers
// ---------------------------------------------------------------------------------------------

fn scene(text: &str) -> Scene {
    parse_scene(text, "test.json", "test", Path::new(".")).unwrap_or_else(|e| panic!("{e}"))
}

fn lib(name: &str) -> Scene {
    library::load(name)
        .unwrap()
        .unwrap_or_else(|e| panic!("{e}"))
}

/// Gauss–Legendre nodes and weights on [-1, 1], by Newton's method on P_n.
fn gauss_legendre(n: usize) -> Vec<(f64, f64)> {
    (0..n)
        .map(|k| {
            let mut x = (PI * (k as f64 + 0.75) / (n as f64 + 0.5)).cos();
            let mut dp = 0.0;
            for _ in 0..100 {
                let (mut p0, mut p1) = (1.0, x);
                for m in 2..=n {
                    let p2 = ((2 * m - 1) as f64 * x * p1 - (m - 1) as f64 * p0) / m as f64;
                    p0 = p1;
                    p1 = p2;
                }
                dp = n as f64 * (x * p1 - p0) / (x * x - 1.0);
                let dx = p1 / dp;
                x -= dx;
                if dx.abs() < 1e-16 {
                    break;
                }
            }
            (x, 2.0 / ((1.0 - x * x) * dp * dp))
        })
        .collect()
}

/// ∫_a^b f(x) dx for an integrand peaked like 1/((x − t0)² + h²): substitute x = t0 + h sinh u
/// (dx = h cosh u du) and use composite 16-point Gauss–Legendre on `panels` equal panels in u.
fn integrate_peaked(
    f: &dyn Fn(f64) -> DVec3,
    a: f64,
    b: f64,
    t0: f64,
    h: f64,
    panels: usize,
) -> DVec3 {
    if b <= a {
        return DVec3::ZERO;
    }
    static GL: OnceLock<Vec<(f64, f64)>> = OnceLock::new();
    let gl = GL.get_or_init(|| gauss_legendre(16));
    let h = h.max(1e-9);
    let (ua, ub) = (((a - t0) / h).asinh(), ((b - t0) / h).asinh());
    let du = (ub - ua) / panels as f64;
    let mut sum = DVec3::ZERO;
    for k in 0..panels {
        let mid = ua + (k as f64 + 0.5) * du;
        for &(x, w) in gl {
            let u = mid + 0.5 * du * x;
            let t = (t0 + h * u.sinh()).clamp(a, b);
            sum += f(t) * (w * 0.5 * du * h * u.cosh());
        }
    }
    sum
}

/// The closest point of the line o + t d (d unit) to `l`: (t0, h).
fn closest(o: DVec3, d: DVec3, l: DVec3) -> (f64, f64) {
    let t0 = (l - o).dot(d);
    (t0, (o + d * t0 - l).length())
}

/// The ray through the centre of pixel (i, j) (j = 0 the top row), from the camera's own
/// definition: forward f, right = f × up, vertical fov, aspect = w/h.
fn pixel_dir(cam: &CameraPose, w: u32, h: u32, i: u32, j: u32) -> DVec3 {
    let f = (cam.look_at.as_dvec3() - cam.position.as_dvec3()).normalize();
    let r = f.cross(cam.up.as_dvec3()).normalize();
    let u = r.cross(f);
    let tan = (0.5 * (cam.fov_y_deg as f64).to_radians()).tan();
    let x = 2.0 * (i as f64 + 0.5) / w as f64 - 1.0;
    let y = 1.0 - 2.0 * (j as f64 + 0.5) / h as f64;
    (f + r * (x * tan * w as f64 / h as f64) + u * (y * tan)).normalize()
}

/// Distance along `d` to the far plane.
fn far_len(cam: &CameraPose, d: DVec3) -> f64 {
    let f = (cam.look_at.as_dvec3() - cam.position.as_dvec3()).normalize();
    cam.far as f64 / d.dot(f)
}

fn hg(g: f64, cos: f64) -> f64 {
    (1.0 - g * g) / (4.0 * PI * (1.0 + g * g - 2.0 * g * cos).powf(1.5))
}

fn exp3(v: DVec3) -> DVec3 {
    DVec3::new(v.x.exp(), v.y.exp(), v.z.exp())
}

fn px(img: &harness::image::Image, i: u32, j: u32) -> DVec3 {
    DVec3::from_array(img.get(i, j).map(f64::from))
}

fn rel_err(got: DVec3, want: DVec3) -> f64 {
    ((got - want).abs() / want.abs().max(DVec3::splat(1e-300))).max_element()
}

/// A light as this file models it.
#[derive(Clone, Copy)]
enum TestLight {
    Point {
        pos: DVec3,
        intensity: DVec3,
    },
    /// Smoothstep in cos between the cones (scenes::light documents this falloff).
    Spot {
        pos: DVec3,
        axis: DVec3,
        cos_inner: f64,
        cos_outer: f64,
        intensity: DVec3,
    },
}

impl TestLight {
    fn pos(&self) -> DVec3 {
        match *self {
            TestLight::Point { pos, .. } | TestLight::Spot { pos, .. } => pos,
        }
    }
    fn intensity(&self, x: DVec3) -> DVec3 {
        match *self {
            TestLight::Point { intensity, .. } => intensity,
            TestLight::Spot {
                pos,
                axis,
                cos_inner,
                cos_outer,
                intensity,
            } => {
                let c = (x - pos).normalize().dot(axis);
                let t = ((c - cos_outer) / (cos_inner - cos_outer)).clamp(0.0, 1.0);
                intensity * (t * t * (3.0 - 2.0 * t))
            }
        }
    }
    /// Where the integrand stops being smooth along the ray (spot cone edges), in (0, len).
    fn breaks(&self, o: DVec3, d: DVec3, len: f64) -> Vec<f64> {
        let TestLight::Spot {
            pos,
            axis,
            cos_inner,
            cos_outer,
            ..
        } = *self
        else {
            return vec![];
        };
        let cos_at = |t: f64| (o + d * t - pos).normalize().dot(axis);
        let (t0, h) = closest(o, d, pos);
        let (ua, ub) = (((0.0 - t0) / h).asinh(), ((len - t0) / h).asinh());
        let n = 4000;
        let ts: Vec<f64> = (0..=n)
            .map(|k| t0 + h * (ua + (ub - ua) * k as f64 / n as f64).sinh())
            .map(|t| t.clamp(0.0, len))
            .collect();
        let mut out = Vec::new();
        for c in [cos_inner, cos_outer] {
            for w in ts.windows(2) {
                let (mut a, mut b) = (w[0], w[1]);
                let (fa, fb) = (cos_at(a) - c, cos_at(b) - c);
                if (fa < 0.0) != (fb < 0.0) {
                    for _ in 0..200 {
                        let m = 0.5 * (a + b);
                        if ((cos_at(m) - c) < 0.0) == (fa < 0.0) {
                            a = m
                        } else {
                            b = m
                        }
                    }
                    out.push(0.5 * (a + b));
                }
            }
        }
        out
    }
}

#[derive(Clone, Copy)]
struct Medium {
    sigma_s: DVec3,
    sigma_t: DVec3,
    /// Henyey–Greenstein g; 0 is isotropic.
    g: f64,
}

/// The unshadowed in-scatter integrand at ray parameter t.
fn integrand(m: Medium, light: TestLight, o: DVec3, d: DVec3, t: f64) -> DVec3 {
    let x = o + d * t;
    let w = x - light.pos();
    let r = w.length();
    let cos = w.dot(-d) / r;
    m.sigma_s * hg(m.g, cos) * light.intensity(x) * exp3(-m.sigma_t * (t + r)) / (r * r)
}

/// ∫ over [a, b] of the unshadowed integrand, split at the light's breaks.
fn inscatter(
    m: Medium,
    light: TestLight,
    o: DVec3,
    d: DVec3,
    a: f64,
    b: f64,
    panels: usize,
) -> DVec3 {
    let (t0, h) = closest(o, d, light.pos());
    let mut cuts = vec![a, b];
    cuts.extend(
        light
            .breaks(o, d, b)
            .into_iter()
            .filter(|&t| t > a && t < b),
    );
    cuts.sort_by(f64::total_cmp);
    let f = |t: f64| integrand(m, light, o, d, t);
    cuts.windows(2)
        .map(|w| integrate_peaked(&f, w[0], w[1], t0, h, panels))
        .sum()
}

// ---------------------------------------------------------------------------------------------
// 1. Unshadowed lights in an infinite medium vs independent quadrature
// ---------------------------------------------------------------------------------------------

const CAMERA: &str = r#""camera": { "position": [0.0, 1.0, 5.0], "look_at": [0.2, 1.1, 0.0], "fov_y_deg": 60, "near": 0.1, "far": 20 }"#;

fn infinite_medium(phase: &str, light: &str) -> Scene {
    scene(&format!(
        r#"{{ {CAMERA},
            "medium": {{ "kind": "homogeneous", "sigma_a": [0.02, 0.03, 0.05], "sigma_s": [0.1, 0.2, 0.3], "phase": {phase} }},
            "lights": [ {light} ] }}"#
    ))
}

/// Sample pixels: corners, centre, a few others, and the pixel whose ray passes closest to
/// `light` (the sharpest 1/r² peak).
fn sample_pixels(cam: &CameraPose, w: u32, h: u32, light: DVec3) -> Vec<(u32, u32)> {
    let o = cam.position.as_dvec3();
    let mut best = (f64::INFINITY, (0, 0));
    for j in 0..h {
        for i in 0..w {
            let (_, dist) = closest(o, pixel_dir(cam, w, h, i, j), light);
            if dist < best.0 {
                best = (dist, (i, j));
            }
        }
    }
    vec![
        (0, 0),
        (w - 1, 0),
        (0, h - 1),
        (w - 1, h - 1),
        (w / 2, h / 2),
        (5, h - 9),
        (w - 5, 9),
        best.1,
    ]
}

/// Checks the reference's in-scatter at the sample pixels against this file's quadrature;
/// returns the largest relative error seen.
fn check_unshadowed(s: &Scene, m: Medium, light: TestLight, tol: f64, min_lit: usize) -> f64 {
    let (w, h) = (32, 32);
    let img = render(s, 0, w, h, Settings::default(), &|_| {}).unwrap();
    let cam = s.frame(0).camera;
    let rays = cam.rays(w, h);
    let o = cam.position.as_dvec3();
    let mut worst: f64 = 0.0;
    let mut nonzero = 0;
    for (i, j) in sample_pixels(&cam, w, h, light.pos()) {
        let d = pixel_dir(&cam, w, h, i, j);
        // The shared camera code agrees with this file's ray (the contract is tested elsewhere).
        assert!(
            (rays.direction(i, j) - d).length() < 1e-9,
            "pixel ({i},{j})"
        );
        let len = far_len(&cam, d);
        // Nothing to hit: the ray ends at the far plane.
        assert!(
            (img.distance[(j * w + i) as usize] as f64 / len - 1.0).abs() < 1e-6,
            "distance at ({i},{j})"
        );
        let want = inscatter(m, light, o, d, 0.0, len, 400);
        // Our own quadrature has converged far below the tolerance.
        let finer = inscatter(m, light, o, d, 0.0, len, 800);
        assert!(
            rel_err(want, finer) < 1e-11,
            "test quadrature not converged at ({i},{j}): {want} vs {finer}"
        );
        let got = px(&img.inscatter, i, j);
        if want.max_element() > 0.0 {
            nonzero += 1;
            let e = rel_err(got, want);
            worst = worst.max(e);
            assert!(
                e < tol,
                "pixel ({i},{j}): reference {got} vs quadrature {want}: relative error {e:e}"
            );
        } else {
            assert_eq!(got, DVec3::ZERO, "pixel ({i},{j}) sees no light");
        }
        assert_eq!(px(&img.surface, i, j), DVec3::ZERO);
        assert_eq!(
            px(&img.total, i, j),
            got,
            "total = in-scatter with no surfaces and no ambient"
        );
    }
    assert!(nonzero >= min_lit, "only {nonzero} sample pixels see light");
    worst
}

/// The medium of `infinite_medium`. A scene file's numbers are single precision (the format
/// stores f32, and σ_t = σ_a + σ_s is formed in f32), so the test takes them through f32 exactly
/// as the file does; with the f64 decimals instead, the difference is ~1e-7 relative.
fn medium(g: f64) -> Medium {
    let (a, s) = (Vec3::new(0.02, 0.03, 0.05), Vec3::new(0.1, 0.2, 0.3));
    Medium {
        sigma_s: s.as_dvec3(),
        sigma_t: (a + s).as_dvec3(),
        g,
    }
}

#[test]
fn point_light_in_infinite_medium_matches_independent_quadrature() {
    let pos = DVec3::new(0.5, 1.5, -1.0);
    let light = TestLight::Point {
        pos,
        intensity: DVec3::new(10.0, 20.0, 30.0),
    };
    let s = infinite_medium(
        r#"{ "kind": "isotropic" }"#,
        r#"{ "kind": "point", "position": [0.5, 1.5, -1.0], "intensity": [10, 20, 30] }"#,
    );
    let worst = check_unshadowed(&s, medium(0.0), light, 1e-6, 8);
    println!("point, isotropic: worst relative error {worst:e}");
}

/// Same with a strongly forward-scattering phase: checks the orientation of θ (light's
/// propagation direction vs the direction toward the eye).
#[test]
fn anisotropic_phase_uses_the_documented_scattering_angle() {
    let pos = DVec3::new(0.5, 1.5, -1.0);
    let light = TestLight::Point {
        pos,
        intensity: DVec3::new(10.0, 20.0, 30.0),
    };
    let s = infinite_medium(
        r#"{ "kind": "henyey-greenstein", "g": 0.7 }"#,
        r#"{ "kind": "point", "position": [0.5, 1.5, -1.0], "intensity": [10, 20, 30] }"#,
    );
    let worst = check_unshadowed(&s, medium(0.7), light, 1e-6, 8);
    println!("point, HG 0.7: worst relative error {worst:e}");
    // The wrong orientation (θ measured from the light toward x vs the eye direction d) would
    // differ by orders of magnitude: make sure the test can tell.
    let cam = s.frame(0).camera;
    let (i, j) = *sample_pixels(&cam, 32, 32, pos).last().unwrap();
    let d = pixel_dir(&cam, 32, 32, i, j);
    let o = cam.position.as_dvec3();
    let len = far_len(&cam, d);
    let right = inscatter(medium(0.7), light, o, d, 0.0, len, 400);
    let flipped = inscatter(medium(-0.7), light, o, d, 0.0, len, 400);
    assert!(rel_err(flipped, right) > 0.1);
}

#[test]
fn spot_light_in_infinite_medium_matches_independent_quadrature() {
    // The light as the scene hands it to every renderer: position from the file's f32s, and
    // — a precision choice of `scenes::LightState`, which GPU methods share — the axis
    // normalised and the cone cosines computed in f32. (With f64 cosines of the file's 15° and
    // 25°, the smoothstep tail differs enough to move pixel (31,31) by 3.4e-6 relative.)
    let pos = Vec3::new(-0.6, 2.4, -1.5).as_dvec3();
    let axis = Vec3::new(0.3, -1.0, 0.4).normalize().as_dvec3();
    let light = TestLight::Spot {
        pos,
        axis,
        cos_inner: 15f32.to_radians().cos() as f64,
        cos_outer: 25f32.to_radians().cos() as f64,
        intensity: DVec3::new(50.0, 40.0, 30.0),
    };
    let s = infinite_medium(
        r#"{ "kind": "isotropic" }"#,
        r#"{ "kind": "spot", "position": [-0.6, 2.4, -1.5], "direction": [0.3, -1.0, 0.4], "inner_deg": 15, "outer_deg": 25, "intensity": [50, 40, 30] }"#,
    );
    // The sample pixels plus a row across the image, which crosses the cone.
    let m = medium(0.0);
    let worst = check_unshadowed(&s, m, light, 1e-6, 2);
    let cam = s.frame(0).camera;
    let img = trace_pixels(
        &s,
        0,
        32,
        32,
        Settings::default(),
        &(0..32).map(|i| (i, 20)).collect::<Vec<_>>(),
        &|_| {},
    )
    .unwrap();
    let o = cam.position.as_dvec3();
    let mut lit = 0;
    let mut worst_row: f64 = 0.0;
    for (i, r) in img.iter().enumerate() {
        let d = pixel_dir(&cam, 32, 32, i as u32, 20);
        let want = inscatter(m, light, o, d, 0.0, far_len(&cam, d), 400);
        if want.max_element() > 0.0 {
            lit += 1;
            let e = rel_err(r.inscatter, want);
            worst_row = worst_row.max(e);
            assert!(e < 1e-6, "row pixel {i}: {} vs {want}", r.inscatter);
        } else {
            assert_eq!(r.inscatter, DVec3::ZERO);
        }
    }
    assert!(
        (8..32).contains(&lit),
        "the row crosses the cone ({lit} of 32 pixels lit)"
    );
    println!("spot: worst relative error {worst:e} (samples), {worst_row:e} (row)");
}

/// Directional light in an infinite medium: σ_s p(θ) E ∫_0^D e^(−σ_t x) dx in closed form
/// (irradiance not attenuated on the light leg).
#[test]
fn directional_light_in_infinite_medium_matches_closed_form() {
    let s = infinite_medium(
        r#"{ "kind": "rayleigh" }"#,
        r#"{ "kind": "directional", "direction": [1.0, -0.7, 0.35], "irradiance": [4.0, 3.8, 3.4] }"#,
    );
    let (w, h) = (16, 16);
    let img = render(&s, 0, w, h, Settings::default(), &|_| {}).unwrap();
    let cam = s.frame(0).camera;
    let dir = Vec3::new(1.0, -0.7, 0.35).as_dvec3().normalize();
    let e = Vec3::new(4.0, 3.8, 3.4).as_dvec3();
    let mut worst: f64 = 0.0;
    for j in 0..h {
        for i in 0..w {
            let d = pixel_dir(&cam, w, h, i, j);
            let len = far_len(&cam, d);
            let cos = dir.dot(-d);
            let p = 3.0 / (16.0 * PI) * (1.0 + cos * cos);
            let m = medium(0.0);
            let want = m.sigma_s * p * e * (DVec3::ONE - exp3(-m.sigma_t * len)) / m.sigma_t;
            let err = rel_err(px(&img.inscatter, i, j), want);
            worst = worst.max(err);
            assert!(
                err < 1e-6,
                "({i},{j}): {:?} vs {want}",
                img.inscatter.get(i, j)
            );
        }
    }
    println!("directional: worst relative error {worst:e}");
}

// ---------------------------------------------------------------------------------------------
// 2. σ_t → 0: the vacuum closed form
// ---------------------------------------------------------------------------------------------

/// With σ_a = 0 and σ_s → 0, L_in / σ_s → ∫_0^D p I / r² dx = (p I / h)(atan((D − t0)/h) − atan(−t0/h)).
/// The attenuation factor e^(−σ_t (x + r)) lies in [1 − σ_t max(x + r), 1], so the ratio to the
/// vacuum form deviates by at most σ_t max(x + r) (< 5e-6 for σ_s = 1e-7 here), and that
/// deviation must shrink in proportion to σ_t.
#[test]
fn thin_medium_tends_to_the_vacuum_closed_form() {
    let pos = DVec3::new(0.5, 1.5, -1.0);
    let intensity = DVec3::new(10.0, 20.0, 30.0);
    let (w, h) = (32u32, 32u32);
    let mut prev_worst = f64::INFINITY;
    for sigma in [1e-3, 1e-5, 1e-7] {
        let s = scene(&format!(
            r#"{{ {CAMERA}, "medium": {{ "kind": "homogeneous", "sigma_a": [0, 0, 0], "sigma_s": [{sigma:e}, {sigma:e}, {sigma:e}] }},
                "lights": [ {{ "kind": "point", "position": [0.5, 1.5, -1.0], "intensity": [10, 20, 30] }} ] }}"#
        ));
        let cam = s.frame(0).camera;
        let pixels = sample_pixels(&cam, w, h, pos);
        let got = trace_pixels(&s, 0, w, h, Settings::default(), &pixels, &|_| {}).unwrap();
        let o = cam.position.as_dvec3();
        let mut worst: f64 = 0.0;
        for (&(i, j), r) in pixels.iter().zip(&got) {
            let d = pixel_dir(&cam, w, h, i, j);
            let len = far_len(&cam, d);
            let (t0, hh) = closest(o, d, pos);
            let vacuum =
                intensity / (4.0 * PI * hh) * (((len - t0) / hh).atan() - (-t0 / hh).atan());
            let ratio = r.inscatter / sigma / vacuum;
            let max_path = len + (o - pos).length().max((o + d * len - pos).length());
            for c in 0..3 {
                let dev = 1.0 - ratio[c];
                // Attenuation only ever removes light, by at most σ_t max(x + r).
                assert!(
                    dev > -1e-6 && dev < sigma * max_path + 1e-6,
                    "σ={sigma:e} ({i},{j}) channel {c}: ratio {}",
                    ratio[c]
                );
                worst = worst.max(dev.abs());
            }
        }
        println!("σ_s = {sigma:e}: worst |ratio − 1| = {worst:e}");
        if sigma <= 1e-7 {
            assert!(worst < 1e-5, "σ_s = {sigma:e}: {worst:e}");
        }
        assert!(worst < prev_worst, "the deviation shrinks with σ_t");
        prev_worst = worst;
    }
}

// ---------------------------------------------------------------------------------------------
// 3. Shadows on sphere-point vs the analytic sphere
// ---------------------------------------------------------------------------------------------

fn sphere_point_64() -> &'static ReferenceImages {
    static IMG: OnceLock<ReferenceImages> = OnceLock::new();
    IMG.get_or_init(|| {
        render(
            &lib("sphere-point"),
            0,
            64,
            64,
            Settings::default(),
            &|_| {},
        )
        .unwrap()
    })
}

/// Entry distance of the ray into the ball (c, rho), if it enters it ahead of the origin.
fn ball_entry(o: DVec3, d: DVec3, c: DVec3, rho: f64) -> Option<f64> {
    let (t0, h) = closest(o, d, c);
    if h >= rho {
        return None;
    }
    let t = t0 - (rho * rho - h * h).sqrt();
    (t > 0.0).then_some(t)
}

/// Distance from `c` to the segment [a, b].
fn segment_distance(c: DVec3, a: DVec3, b: DVec3) -> f64 {
    let ab = b - a;
    let s = ((c - a).dot(ab) / ab.length_squared()).clamp(0.0, 1.0);
    (a + ab * s - c).length()
}

/// The interval of [0, len] whose points cannot see `l` past the ball (c, rho): convex (the
/// shadow of a convex body from a point is convex), found by dense sampling + bisection on
/// the exact segment–ball distance. None when the ray never enters the shadow.
fn ball_shadow(o: DVec3, d: DVec3, len: f64, l: DVec3, c: DVec3, rho: f64) -> Option<(f64, f64)> {
    let f = |t: f64| segment_distance(c, o + d * t, l) - rho;
    let n = 4000;
    let inside: Vec<f64> = (0..=n)
        .map(|k| len * k as f64 / n as f64)
        .filter(|&t| f(t) < 0.0)
        .collect();
    let (first, last) = (*inside.first()?, *inside.last()?);
    let bisect = |mut a: f64, mut b: f64| {
        // f(a) ≥ 0 > f(b) or the reverse; find the sign change.
        let sa = f(a) < 0.0;
        for _ in 0..200 {
            let m = 0.5 * (a + b);
            if (f(m) < 0.0) == sa { a = m } else { b = m }
        }
        0.5 * (a + b)
    };
    let step = len / n as f64;
    let a = if first <= 0.0 {
        0.0
    } else {
        bisect(first - step, first)
    };
    let b = if last >= len {
        len
    } else {
        bisect(last, last + step)
    };
    Some((a, b))
}

/// The sphere of sphere-point as the mesh approximates it: every vertex on the sphere of
/// radius `outer` (≈ R), every face at least `inner` from the centre. The mesh is convex
/// (checked), so the ball of radius `inner` ⊆ the polyhedron ⊆ the ball of radius `outer`.
struct SphereBounds {
    c: DVec3,
    inner: f64,
    outer: f64,
}

fn sphere_bounds(s: &Scene) -> SphereBounds {
    let c = DVec3::new(0.0, 2.0, 0.0);
    let r = 0.9;
    let world = World::new(s, &s.frame(0));
    let tris: Vec<[DVec3; 3]> = world
        .bvh
        .tris
        .iter()
        .map(|t| t.p)
        .filter(|p| p.iter().all(|v| ((*v - c).length() - r).abs() < 1e-3))
        .collect();
    assert_eq!(tris.len(), 2 * 48 * 23, "the UV sphere's triangles");
    let verts: Vec<DVec3> = tris.iter().flatten().copied().collect();
    let outer = verts.iter().map(|v| (*v - c).length()).fold(0.0, f64::max);
    let mut inner = f64::INFINITY;
    for t in &tris {
        let n = (t[1] - t[0]).cross(t[2] - t[0]);
        if n.length() < 1e-12 {
            continue; // degenerate sliver at a pole: no area, no effect
        }
        let n = n.normalize();
        let dist = n.dot(t[0] - c);
        assert!(dist > 0.0, "faces point outward");
        inner = inner.min(dist);
        // Convex: every vertex lies on the inner side of every face's plane.
        for v in &verts {
            assert!(n.dot(*v - t[0]) < 1e-6, "the sphere mesh is not convex");
        }
    }
    SphereBounds {
        c,
        inner,
        outer: outer + 1e-7,
    }
}

#[test]
fn sphere_point_surfaces_shadows_and_depth_match_analytic_geometry() {
    let s = lib("sphere-point");
    let img = sphere_point_64();
    let (w, h) = (64u32, 64u32);
    let cam = s.frame(0).camera;
    let o = cam.position.as_dvec3();
    let l = DVec3::new(0.6, 4.6, -0.4);
    let b = sphere_bounds(&s);
    // R(1 − cos 7.5°) = 0.0077 would be a crude bound on the faces' depth; the real one is smaller.
    println!(
        "sphere mesh between radii {:.6} and {:.6} (depth {:.2e} m)",
        b.inner,
        b.outer,
        b.outer - b.inner
    );
    assert!(b.outer - b.inner < 0.9 * (1.0 - 7.5f64.to_radians().cos()) && b.outer < 0.9 + 1e-6);
    let sigma_t = 0.09;
    let (intensity, albedo) = (60.0, 0.7);
    let (mut sphere_px, mut lit_px, mut shadow_px, mut sky_px, mut skipped) = (0, 0, 0, 0, 0);
    let mut worst_surface: f64 = 0.0;
    for j in 0..h {
        for i in 0..w {
            let d = pixel_dir(&cam, w, h, i, j);
            let k = (j * w + i) as usize;
            let dist = img.distance[k] as f64;
            let surface = px(&img.surface, i, j);
            let floor = (d.y < 0.0).then(|| -o.y / d.y).filter(|&t| {
                let p = o + d * t;
                p.x.abs() < 7.0 && p.z.abs() < 7.0
            });
            let floor_edge = (d.y < 0.0) && {
                let p = o + d * (-o.y / d.y);
                (p.x.abs() - 7.0).abs() < 1e-4 || (p.z.abs() - 7.0).abs() < 1e-4
            };
            if let Some(t_in) = ball_entry(o, d, b.c, b.inner) {
                // Certainly the sphere: the mesh surface lies between the two balls.
                let t_out = ball_entry(o, d, b.c, b.outer).unwrap();
                assert!(
                    dist >= t_out * (1.0 - 1e-6) && dist <= t_in * (1.0 + 1e-6),
                    "({i},{j}): sphere at {dist}, expected in [{t_out}, {t_in}]"
                );
                assert!(surface.is_finite() && surface.min_element() >= 0.0);
                sphere_px += 1;
            } else if ball_entry(o, d, b.c, b.outer).is_some() || floor_edge {
                skipped += 1; // silhouette of the polyhedron, or the floor's edge
            } else if let Some(t) = floor {
                assert!(
                    (dist / t - 1.0).abs() < 1e-6,
                    "({i},{j}): floor at {t}, reference {dist}"
                );
                let p = o + d * t;
                let gap = segment_distance(b.c, p, l);
                if gap > b.outer + 1e-6 {
                    // Lit floor: Lambert, (albedo/π) I cos e^(−σt r)/r², attenuated over t.
                    let to = l - p;
                    let r = to.length();
                    let want = albedo / PI * intensity * (to.y / r) * (-sigma_t * r).exp()
                        / (r * r)
                        * (-sigma_t * t).exp();
                    let e = rel_err(surface, DVec3::splat(want));
                    worst_surface = worst_surface.max(e);
                    assert!(e < 1e-5, "({i},{j}): lit floor {surface} vs {want}");
                    lit_px += 1;
                } else if gap < b.inner - 1e-6 {
                    assert_eq!(
                        surface,
                        DVec3::ZERO,
                        "({i},{j}): floor in the sphere's shadow must be black"
                    );
                    shadow_px += 1;
                } else {
                    skipped += 1; // penumbra of mesh vs sphere
                }
            } else {
                let far = far_len(&cam, d);
                assert!(
                    (dist / far - 1.0).abs() < 1e-6,
                    "({i},{j}): no hit must end at the far plane {far}, got {dist}"
                );
                assert_eq!(surface, DVec3::ZERO);
                sky_px += 1;
            }
        }
    }
    println!(
        "sphere {sphere_px}, lit floor {lit_px}, shadowed floor {shadow_px}, far plane {sky_px}, skipped {skipped}; worst lit-floor error {worst_surface:e}"
    );
    assert!(
        sphere_px > 200 && lit_px > 1000 && shadow_px > 50 && sky_px > 100,
        "every category is exercised"
    );
    assert!(skipped < 200, "the margins skip few pixels");
}

/// In-scatter through the sphere's volumetric shadow. The mesh is a convex polyhedron between
/// the balls B(inner) and B(outer), so the set of ray points it shadows lies between the sets
/// those two balls shadow; the integrand is non-negative, so the reference's in-scatter must
/// lie between our quadratures with the two analytic balls (up to the reference's own 1e-6
/// tolerance and f32 storage). That bracket is the mesh tolerance — no fudge factor — and the
/// test checks it is much narrower than the shadow's effect, so it has teeth.
#[test]
fn sphere_point_volumetric_shadow_is_bracketed_by_analytic_spheres() {
    let s = lib("sphere-point");
    let img = sphere_point_64();
    let (w, h) = (64u32, 64u32);
    let cam = s.frame(0).camera;
    let o = cam.position.as_dvec3();
    let l = DVec3::new(0.6, 4.6, -0.4);
    let b = sphere_bounds(&s);
    let m = Medium {
        sigma_s: DVec3::splat(0.08),
        sigma_t: DVec3::splat(0.09),
        g: 0.0,
    };
    let light = TestLight::Point {
        pos: l,
        intensity: DVec3::splat(60.0),
    };
    let (t0_of, f_of) = (
        |d: DVec3| closest(o, d, l),
        |d: DVec3| move |t: f64| integrand(m, light, o, d, t),
    );
    let mut through = 0;
    let mut clear = 0;
    let (mut bracket_sum, mut deficit_sum, mut deepest) = (0.0, 0.0, 0.0f64);
    let mut worst_clear: f64 = 0.0;
    for j in (0..h).step_by(2) {
        for i in (0..w).step_by(2) {
            let d = pixel_dir(&cam, w, h, i, j);
            // Rays that end on the floor without touching the sphere (their length is exact,
            // and every point is above the floor, which therefore shadows nothing).
            if d.y >= 0.0 || ball_entry(o, d, b.c, b.outer).is_some() {
                continue;
            }
            let len = -o.y / d.y;
            let p = o + d * len;
            if p.x.abs() > 6.99 || p.z.abs() > 6.99 {
                continue;
            }
            let (t0, hh) = t0_of(d);
            let f = f_of(d);
            let got = px(&img.inscatter, i, j);
            let full = integrate_peaked(&f, 0.0, len, t0, hh, 400);
            let lit_with = |rho: f64| match ball_shadow(o, d, len, l, b.c, rho) {
                None => full,
                Some((a, bb)) => {
                    integrate_peaked(&f, 0.0, a, t0, hh, 400)
                        + integrate_peaked(&f, bb, len, t0, hh, 400)
                }
            };
            let (lo, hi) = (lit_with(b.outer), lit_with(b.inner));
            if ball_shadow(o, d, len, l, b.c, b.outer).is_none() {
                // No shadow at all: the unshadowed integral.
                let e = rel_err(got, full);
                worst_clear = worst_clear.max(e);
                assert!(e < 1e-6, "({i},{j}) unshadowed: {got} vs {full}");
                clear += 1;
                continue;
            }
            for c in 0..3 {
                assert!(
                    got[c] >= lo[c] * (1.0 - 2e-6) && got[c] <= hi[c] * (1.0 + 2e-6),
                    "({i},{j}): reference {} outside [{}, {}]",
                    got[c],
                    lo[c],
                    hi[c]
                );
            }
            // How much the shadow removes, and how much room the mesh leaves.
            through += 1;
            bracket_sum += hi.x - lo.x;
            deficit_sum += full.x - lo.x;
            deepest = deepest.max((full.x - lo.x) / full.x);
        }
    }
    let ratio = bracket_sum / deficit_sum;
    println!(
        "{through} rays through the shadow (deepest removes {:.0}% of the light; mesh bracket = {:.2}% of the shadow's effect), {clear} unshadowed rays (worst error {worst_clear:e})",
        100.0 * deepest,
        100.0 * ratio
    );
    assert!(
        through >= 50 && clear >= 100,
        "through {through}, clear {clear}"
    );
    // Teeth: a reference that ignored the shadow, or misplaced it by more than the mesh does,
    // would leave the bracket, which is a few % of the shadow's effect.
    assert!(
        deepest > 0.15 && ratio < 0.05,
        "the mesh bracket is too wide to test anything: {ratio}"
    );
}

// ---------------------------------------------------------------------------------------------
// 4. The reference's own convergence
// ---------------------------------------------------------------------------------------------

#[test]
fn reference_converges_on_sphere_point_and_fence_spot() {
    let sp = lib("sphere-point");
    let c = convergence(&sp, 0, sphere_point_64(), Settings::default(), 1).unwrap();
    println!(
        "sphere-point 64²: rel RMSE inscatter {:e}, total {:e} ({} pixels)",
        c.rel_rmse_inscatter, c.rel_rmse_total, c.pixels
    );
    assert_eq!(c.pixels, 64 * 64);
    assert!(
        c.rel_rmse_total < 1e-4 && c.rel_rmse_inscatter < 1e-4,
        "{c:?}"
    );
    let fs = lib("fence-spot");
    let img = render(&fs, 0, 64, 64, Settings::default(), &|_| {}).unwrap();
    let c = convergence(&fs, 0, &img, Settings::default(), 1).unwrap();
    println!(
        "fence-spot 64²: rel RMSE inscatter {:e}, total {:e}",
        c.rel_rmse_inscatter, c.rel_rmse_total
    );
    assert!(
        c.rel_rmse_total < 1e-4 && c.rel_rmse_inscatter < 1e-4,
        "{c:?}"
    );
    // Not vacuous: the images have light in them.
    assert!(img.inscatter.mean() > 0.0 && img.total.mean() > img.inscatter.mean());
}

/// Many lights on a level: the atrium with 64 local lights (0.3 M triangles) converges like the
/// toy scenes, and the reference is linear in its lights — the image of five lights equals the
/// sum of five one-light images (each light's integration sees only its own intervals; a light
/// dropped, doubled or mixed up with another's shadows breaks the sum).
#[test]
fn reference_converges_on_the_atrium_and_its_lights_superpose() {
    let (w, h) = (32, 24);
    let many = scenes::library::resolve("atrium-64").unwrap();
    let img = render(&many, 0, w, h, Settings::default(), &|_| {}).unwrap();
    let c = convergence(&many, 0, &img, Settings::default(), 1).unwrap();
    println!(
        "atrium-64 {w}x{h}: rel RMSE inscatter {:e}, total {:e}",
        c.rel_rmse_inscatter, c.rel_rmse_total
    );
    assert!(
        c.rel_rmse_total < 1e-4 && c.rel_rmse_inscatter < 1e-4,
        "{c:?}"
    );
    assert!(img.inscatter.mean() > 0.0);

    let four = scenes::library::resolve("atrium-lights4").unwrap();
    let all = render(&four, 0, w, h, Settings::default(), &|_| {}).unwrap();
    let mut sum = vec![[0.0f64; 3]; (w * h) as usize];
    for light in &four.desc.lights {
        let mut alone = four.clone();
        alone.desc.lights = vec![light.clone()];
        let one = render(&alone, 0, w, h, Settings::default(), &|_| {}).unwrap();
        for (s, p) in sum.iter_mut().zip(&one.total.pixels) {
            for k in 0..3 {
                s[k] += f64::from(p[k]);
            }
        }
    }
    let (mut se, mut peak) = (0.0f64, 0.0f64);
    for (s, p) in sum.iter().zip(&all.total.pixels) {
        for k in 0..3 {
            se += (s[k] - f64::from(p[k])).powi(2);
            peak = peak.max(f64::from(p[k]));
        }
    }
    let rms = (se / (3 * w * h) as f64).sqrt();
    assert!(
        rms < 1e-5 * peak,
        "sum of one-light images vs all lights: rms {rms:e}, peak {peak}"
    );
}

// ---------------------------------------------------------------------------------------------
// 5. Exact shadow intervals vs dense visibility sampling
// ---------------------------------------------------------------------------------------------

struct Lcg(u64);
impl Lcg {
    fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((self.0 >> 11) as f64) / (1u64 << 53) as f64
    }
    fn in_box(&mut self, lo: DVec3, hi: DVec3) -> DVec3 {
        lo + (hi - lo) * DVec3::new(self.next(), self.next(), self.next())
    }
}

/// For each ray, samples visibility at `n` points with a shadow ray each and checks it agrees
/// with membership in `shadowed`'s intervals, except within 1e-6 m of an interval end.
/// Returns (rays whose samples are both lit and shadowed, total sampled visibility changes).
fn check_intervals(
    world: &World,
    rays: &[(DVec3, DVec3, f64)],
    src: Source,
    n: usize,
) -> (usize, usize) {
    let eps = 1e-9;
    let (mut shadowed_rays, mut changes, mut degenerate) = (0, 0, 0);
    for (k, &(o, d, len)) in rays.iter().enumerate() {
        let Some(iv) = shadowed(&world.bvh, o, d, len, src) else {
            degenerate += 1;
            continue;
        };
        for w in iv.windows(2) {
            assert!(
                w[0].1 < w[1].0,
                "ray {k}: intervals sorted and disjoint: {iv:?}"
            );
        }
        assert!(
            iv.iter().all(|&(a, b)| 0.0 <= a && a < b && b <= len),
            "ray {k}: {iv:?} outside [0, {len}]"
        );
        let mut prev = None;
        let mut mixed = false;
        for s in 0..n {
            let t = len * (s as f64 + 0.5) / n as f64;
            let x = o + d * t;
            let blocked = match src {
                Source::Point(lp) => {
                    let to = lp - x;
                    let r = to.length();
                    world.bvh.occluded(x, to / r, eps, r - eps)
                }
                Source::Direction(sun, reach) => world.bvh.occluded(x, sun, eps, reach),
            };
            let inside = iv.iter().any(|&(a, b)| t > a && t < b);
            let near_end = iv
                .iter()
                .any(|&(a, b)| (t - a).abs() < 1e-6 || (t - b).abs() < 1e-6);
            assert!(
                blocked == inside || near_end,
                "ray {k} (o {o}, d {d}, len {len}) at t = {t}: sampled {}, intervals {iv:?}",
                if blocked { "shadowed" } else { "lit" }
            );
            if prev.is_some_and(|p| p != blocked) {
                changes += 1;
                mixed = true;
            }
            prev = Some(blocked);
        }
        if mixed {
            shadowed_rays += 1;
        }
    }
    assert_eq!(degenerate, 0, "random rays never give a degenerate fan");
    (shadowed_rays, changes)
}

/// Camera rays through random pixels of a 48×48 image, to their first hit or the far plane.
fn camera_rays(
    world: &World,
    st: &scenes::FrameState,
    rng: &mut Lcg,
    n: usize,
) -> Vec<(DVec3, DVec3, f64)> {
    let rays_of = st.camera.rays(48, 48);
    (0..n)
        .map(|_| {
            let (i, j) = ((rng.next() * 48.0) as u32, (rng.next() * 48.0) as u32);
            let d = rays_of.direction(i, j);
            let far = rays_of.far_distance(d);
            let len = world
                .bvh
                .intersect(rays_of.origin, d, rays_of.near_distance(d), far)
                .map_or(far, |h| h.t);
            (rays_of.origin, d, len)
        })
        .collect()
}

#[test]
fn exact_shadow_intervals_agree_with_dense_sampling_fence_spot() {
    let s = lib("fence-spot");
    let st = s.frame(0);
    let world = World::new(&s, &st);
    let l = st.lights[0].position().unwrap().as_dvec3();
    let mut rng = Lcg(0x5eed);
    let (lo, hi) = (DVec3::new(-4.0, 0.05, -3.0), DVec3::new(4.0, 4.0, 5.0));
    let mut rays = Vec::new();
    // Random segments through the fence's region.
    for _ in 0..150 {
        let (a, b) = (rng.in_box(lo, hi), rng.in_box(lo, hi));
        rays.push((a, (b - a).normalize(), (b - a).length()));
    }
    rays.extend(camera_rays(&world, &st, &mut rng, 50));
    let (with_shadow, changes) = check_intervals(&world, &rays, Source::Point(l), 20_000);
    println!(
        "fence-spot: {with_shadow} of {} rays cross a shadow boundary, {changes} sampled lit/shadow changes",
        rays.len()
    );
    assert!(
        with_shadow >= 60 && changes >= 500,
        "the rays must actually cross the fence's shadows"
    );
}

#[test]
fn exact_shadow_intervals_agree_with_dense_sampling_window_sun() {
    let s = lib("window-sun");
    let st = s.frame(0);
    let world = World::new(&s, &st);
    let sun = match st.lights[0] {
        scenes::LightState::Directional { direction, .. } => -direction.as_dvec3(),
        ref o => panic!("{o:?}"),
    };
    let reach = 10.0 * world.scale().max(st.camera.far as f64);
    let mut rng = Lcg(0xface);
    // Inside the room (walls at x = -3.1 (windows), z = ±4.1, floor y = 0, ceiling y = 4).
    let (lo, hi) = (DVec3::new(-2.9, 0.05, -3.9), DVec3::new(3.9, 3.9, 3.9));
    let mut rays = Vec::new();
    for _ in 0..150 {
        let (a, b) = (rng.in_box(lo, hi), rng.in_box(lo, hi));
        rays.push((a, (b - a).normalize(), (b - a).length()));
    }
    rays.extend(camera_rays(&world, &st, &mut rng, 50));
    let (with_shadow, changes) =
        check_intervals(&world, &rays, Source::Direction(sun, reach), 20_000);
    println!(
        "window-sun: {with_shadow} of {} rays cross a shadow boundary, {changes} sampled lit/shadow changes",
        rays.len()
    );
    assert!(
        with_shadow >= 60 && changes >= 150,
        "the rays must cross the window's light and shadows"
    );
}

// ---------------------------------------------------------------------------------------------
// Scenes of fog and light only
// ---------------------------------------------------------------------------------------------

/// `objects` defaults to none ("a scene of fog and light only"): the reference must render it.
#[test]
fn a_scene_without_objects_renders() {
    let s = infinite_medium(
        r#"{ "kind": "isotropic" }"#,
        r#"{ "kind": "point", "position": [0.5, 1.5, -1.0], "intensity": [10, 20, 30] }"#,
    );
    assert_eq!(s.triangle_count(), 0);
    let img = std::panic::catch_unwind(|| render(&s, 0, 4, 4, Settings::default(), &|_| {}));
    let img = img
        .expect("the reference panics on a scene without triangles (empty BVH)")
        .unwrap();
    assert!(
        img.inscatter
            .pixels
            .iter()
            .flatten()
            .all(|v| v.is_finite() && *v > 0.0)
    );
}

// ---------------------------------------------------------------------------------------------
// Exponential height fog vs quadrature written here
// ---------------------------------------------------------------------------------------------

/// The fog of `fog_scene`: σ(y) = σ · e^(−(y − FOG_BASE)/FOG_FALLOFF).
const FOG_BASE: f64 = 0.5;
const FOG_FALLOFF: f64 = 2.5;

fn fog_density(y: f64) -> f64 {
    (-(y - FOG_BASE) / FOG_FALLOFF).exp()
}

/// ∫_0^s fog_density along a + t d, by composite 16-point Gauss–Legendre on `panels` panels.
fn numeric_fog_length(a: DVec3, d: DVec3, s: f64, panels: usize) -> f64 {
    static GL: OnceLock<Vec<(f64, f64)>> = OnceLock::new();
    let gl = GL.get_or_init(|| gauss_legendre(16));
    let dt = s / panels as f64;
    let mut sum = 0.0;
    for k in 0..panels {
        let mid = (k as f64 + 0.5) * dt;
        for &(x, w) in gl {
            sum += w * 0.5 * dt * fog_density(a.y + d.y * (mid + 0.5 * dt * x));
        }
    }
    sum
}

/// The closed-form fog length against the numeric integral, for segments going up, down,
/// level, nearly level and steeply through many falloff heights.
#[test]
fn height_fog_optical_depth_matches_numeric_integral() {
    use harness::reference::height_fog::Fog;
    let fog = Fog {
        base: FOG_BASE,
        falloff: FOG_FALLOFF,
    };
    let cases = [
        (
            "up",
            DVec3::new(0.0, 1.0, 5.0),
            DVec3::new(1.0, 0.5, 0.0),
            30.0,
        ),
        (
            "down",
            DVec3::new(0.0, 9.0, 5.0),
            DVec3::new(1.0, -0.4, 0.3),
            25.0,
        ),
        (
            "level",
            DVec3::new(2.0, 1.3, 0.0),
            DVec3::new(0.0, 0.0, -1.0),
            200.0,
        ),
        (
            "near-level up",
            DVec3::new(2.0, 1.3, 0.0),
            DVec3::new(1.0, 1e-9, 0.0),
            300.0,
        ),
        (
            "near-level down",
            DVec3::new(2.0, 1.3, 0.0),
            DVec3::new(1.0, -1e-6, 0.0),
            300.0,
        ),
        (
            "steep up",
            DVec3::new(0.0, -20.0, 0.0),
            DVec3::new(0.1, 1.0, 0.0),
            150.0,
        ),
        (
            "steep down",
            DVec3::new(0.0, 100.0, 0.0),
            DVec3::new(0.0, -1.0, 0.1),
            110.0,
        ),
    ];
    for (name, a, d, s) in cases {
        let d = d.normalize();
        let got = fog.length(a, d, s);
        let want = numeric_fog_length(a, d, s, 256);
        let finer = numeric_fog_length(a, d, s, 512);
        assert!(
            (want - finer).abs() <= 1e-13 * finer,
            "{name}: test quadrature"
        );
        let e = (got - want).abs() / want;
        println!("fog length {name}: {got} vs {want} (relative error {e:e})");
        assert!(e < 1e-12, "{name}: closed form {got} vs quadrature {want}");
    }
}

/// A floor and a point light in height fog with an ambient term.
fn fog_scene(light: &str) -> Scene {
    scene(&format!(
        r#"{{ "camera": {{ "position": [0.0, 2.0, 9.0], "look_at": [0.3, 1.0, 0.0], "fov_y_deg": 60, "near": 0.1, "far": 30 }},
            "medium": {{ "kind": "homogeneous", "sigma_a": [0.02, 0.03, 0.05], "sigma_s": [0.1, 0.2, 0.3],
                         "phase": {{ "kind": "henyey-greenstein", "g": 0.4 }}, "ambient": [0.05, 0.04, 0.03],
                         "height_fog": {{ "base_height": {FOG_BASE}, "falloff_height": {FOG_FALLOFF} }} }},
            "lights": [ {light} ],
            "objects": [ {{ "shape": {{ "kind": "plane", "size": [60, 60] }}, "material": {{ "albedo": [0.6, 0.5, 0.4] }} }} ] }}"#
    ))
}

/// Every pixel term of `fog_scene` with a point light against brute-force quadrature: the
/// in-scatter ∫ σ_s(x) p I e^(−τ(eye→x) − τ(x→light)) / r² dx with both optical depths
/// integrated numerically, the floor's attenuated Lambert term, the ambient L_a (1 − e^(−τ)).
#[test]
fn height_fog_pixels_match_brute_force_quadrature() {
    let lp = DVec3::new(1.0, 3.0, 0.0);
    let intensity = DVec3::new(30.0, 40.0, 50.0);
    let s =
        fog_scene(r#"{ "kind": "point", "position": [1.0, 3.0, 0.0], "intensity": [30, 40, 50] }"#);
    let (w, h) = (16, 16);
    let img = render(&s, 0, w, h, Settings::default(), &|_| {}).unwrap();
    let cam = s.frame(0).camera;
    let o = cam.position.as_dvec3();
    let m = medium(0.4);
    let albedo = Vec3::new(0.6, 0.5, 0.4).as_dvec3();
    let ambient = Vec3::new(0.05, 0.04, 0.03).as_dvec3();
    let tau = |a: DVec3, d: DVec3, len: f64| m.sigma_t * numeric_fog_length(a, d, len, 8);
    let (mut floor, mut sky) = (0, 0);
    for (i, j) in sample_pixels(&cam, w, h, lp) {
        let d = pixel_dir(&cam, w, h, i, j);
        // The floor is y = 0; the ray ends there or at the far plane.
        let t_floor = -o.y / d.y;
        let hits = d.y < 0.0 && t_floor < far_len(&cam, d);
        let len = if hits { t_floor } else { far_len(&cam, d) };
        let f = |t: f64| {
            let x = o + d * t;
            let to = lp - x;
            let r = to.length();
            let cos = (x - lp).dot(-d) / r;
            m.sigma_s
                * fog_density(x.y)
                * hg(m.g, cos)
                * intensity
                * exp3(-tau(o, d, t) - tau(x, to / r, r))
                / (r * r)
        };
        let (t0, hh) = closest(o, d, lp);
        let want_in = integrate_peaked(&f, 0.0, len, t0, hh, 200);
        let finer = integrate_peaked(&f, 0.0, len, t0, hh, 400);
        assert!(rel_err(want_in, finer) < 1e-9, "({i},{j}): test quadrature");
        let eye = exp3(-tau(o, d, len));
        let want_surf = if hits {
            floor += 1;
            let p = o + d * len;
            let to = lp - p;
            let r = to.length();
            albedo / PI * intensity * (to.y / r) / (r * r) * exp3(-tau(p, to / r, r)) * eye
        } else {
            sky += 1;
            DVec3::ZERO
        };
        let want_total = want_in + want_surf + ambient * (DVec3::ONE - eye);
        for (what, got, want) in [
            ("in-scatter", px(&img.inscatter, i, j), want_in),
            ("surface", px(&img.surface, i, j), want_surf),
            ("total", px(&img.total, i, j), want_total),
        ] {
            let e = if want == DVec3::ZERO {
                got.max_element()
            } else {
                rel_err(got, want)
            };
            println!("({i},{j}) {what}: {got} vs {want} ({e:e})");
            // f32 images: ~1e-7; the reference's own tolerance 1e-6.
            assert!(
                e < 3e-6,
                "({i},{j}) {what}: reference {got} vs quadrature {want}"
            );
        }
    }
    assert!(
        floor >= 3 && sky >= 2,
        "the sample pixels must see the floor and the sky"
    );
}

/// A directional light in height fog: the in-scatter (unattenuated light leg) against
/// brute-force quadrature of ∫ σ_s(x) p E e^(−τ(eye→x)) dx.
#[test]
fn height_fog_directional_light_matches_brute_force_quadrature() {
    let dir = DVec3::new(0.5, -0.3, -0.8).normalize();
    let e = DVec3::new(2.0, 2.5, 3.0);
    let s = fog_scene(
        r#"{ "kind": "directional", "direction": [0.5, -0.3, -0.8], "irradiance": [2.0, 2.5, 3.0] }"#,
    );
    let (w, h) = (8, 8);
    let img = render(&s, 0, w, h, Settings::default(), &|_| {}).unwrap();
    let cam = s.frame(0).camera;
    let o = cam.position.as_dvec3();
    let m = medium(0.4);
    for j in 0..h {
        for i in 0..w {
            let d = pixel_dir(&cam, w, h, i, j);
            let t_floor = -o.y / d.y;
            let len = if d.y < 0.0 && t_floor < far_len(&cam, d) {
                t_floor
            } else {
                far_len(&cam, d)
            };
            let p = hg(m.g, dir.dot(-d));
            let f = |t: f64| {
                let x = o + d * t;
                m.sigma_s
                    * fog_density(x.y)
                    * p
                    * e
                    * exp3(-m.sigma_t * numeric_fog_length(o, d, t, 8))
            };
            // No peak: a wide "peak" makes the substitution nearly linear.
            let want = integrate_peaked(&f, 0.0, len, 0.0, 1e3, 64);
            let got = px(&img.inscatter, i, j);
            assert!(
                rel_err(got, want) < 3e-6,
                "({i},{j}): reference {got} vs quadrature {want}"
            );
        }
    }
}

/// The reference agrees with its 4×-tighter self on a height-fog scene with a shadow caster
/// (a box between the light and the floor).
#[test]
fn reference_converges_with_height_fog() {
    let s = scene(&format!(
        r#"{{ "camera": {{ "position": [0.0, 2.0, 9.0], "look_at": [0.3, 1.0, 0.0], "fov_y_deg": 60, "far": 30 }},
            "medium": {{ "kind": "homogeneous", "sigma_a": [0.02, 0.02, 0.02], "sigma_s": [0.1, 0.2, 0.3],
                         "height_fog": {{ "base_height": {FOG_BASE}, "falloff_height": {FOG_FALLOFF} }} }},
            "lights": [ {{ "kind": "point", "position": [1.0, 4.0, 0.0], "intensity": [30, 40, 50] }},
                        {{ "kind": "directional", "direction": [0.5, -0.6, -0.8], "irradiance": [1, 1, 1] }} ],
            "objects": [ {{ "shape": {{ "kind": "plane", "size": [60, 60] }} }},
                         {{ "shape": {{ "kind": "box", "size": [1, 1, 1] }}, "transform": {{ "translation": [0.8, 2.0, 0.0] }} }} ] }}"#
    ));
    let img = render(&s, 0, 32, 32, Settings::default(), &|_| {}).unwrap();
    let c = convergence(&s, 0, &img, Settings::default(), 1).unwrap();
    println!(
        "height fog 32²: rel RMSE inscatter {:e}, total {:e}",
        c.rel_rmse_inscatter, c.rel_rmse_total
    );
    assert!(
        c.rel_rmse_total < 1e-4 && c.rel_rmse_inscatter < 1e-4,
        "{c:?}"
    );
    assert!(img.inscatter.mean() > 0.0 && img.surface.mean() > 0.0);
}

/// Indirect single scattering is not computed with height fog: a clear error, not an image.
#[test]
fn height_fog_with_indirect_scattering_is_refused() {
    let mut s =
        fog_scene(r#"{ "kind": "point", "position": [1.0, 3.0, 0.0], "intensity": [30, 40, 50] }"#);
    s.desc.indirect_single_scattering = true;
    let err = render(&s, 0, 4, 4, Settings::default(), &|_| {}).unwrap_err();
    assert!(
        err.contains("height_fog") && err.contains("indirect"),
        "{err}"
    );
}
