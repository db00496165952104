//! Eq. 7 (`spot.rs`) against direct quadrature with the reference's exact spot intensity
//! (`LightState::intensity_toward`): the Δ_i tables on interpolated half circles, and whole
//! segments ∫ Λ(θ) I(ω(θ)) dθ. Run with `--nocapture` to see the error per N.

use std::f64::consts::FRAC_PI_2;

use glam::{DVec3, Vec3};
use scenes::Phase;
use scenes::desc::Pattern;
use scenes::light::{LightState, spot_frame};

use super::poly::{chebyshev, taylor};
use super::poly_tests::gauss;
use super::spot::*;

struct Rng(u64);
impl Rng {
    fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
}

fn spot(pattern: Option<Pattern>) -> (LightState, [DVec3; 3], f64) {
    let (inner, outer) = (22f32.to_radians(), 32f32.to_radians());
    let axis = Vec3::new(0.0, -0.25, 1.0).normalize();
    let light = LightState::Spot {
        position: Vec3::new(0.0, 2.2, -3.5),
        direction: axis,
        cos_inner: inner.cos(),
        cos_outer: outer.cos(),
        tan_outer: outer.tan(),
        intensity: Vec3::new(150.0, 140.0, 120.0),
        pattern,
    };
    let a = axis.as_dvec3();
    let (r, u) = spot_frame(a);
    (light, [r, u, a], outer as f64)
}

/// I(ω) for ω in the spot frame, via the reference's world-space evaluation.
fn local_intensity(light: &LightState, frame: [DVec3; 3]) -> impl Fn(DVec3) -> [f64; 3] + '_ {
    move |w: DVec3| {
        let world = frame[0] * w.x + frame[1] * w.y + frame[2] * w.z;
        let p = light.position().unwrap().as_dvec3();
        light.intensity_toward(p + world).to_array()
    }
}

fn tables(
    light: &LightState,
    frame: [DVec3; 3],
    outer: f64,
    order: usize,
    n: usize,
) -> HalfCircles {
    HalfCircles::new(
        order,
        n,
        2 * n,
        256,
        outer,
        8,
        local_intensity(light, frame),
    )
    .unwrap()
}

/// Mean |Δ_i(table) − Δ_i(quadrature)| / mean |Δ_i(quadrature)| over random off-grid circles
/// and γ, for i = 0 and i = order.
fn table_error(t: &HalfCircles, light: &LightState, frame: [DVec3; 3], outer: f64) -> [f64; 2] {
    let f = local_intensity(light, frame);
    let mut rng = Rng(7);
    let (mut err, mut mag) = ([0.0; 2], [0.0; 2]);
    for _ in 0..60 {
        let u = (2.0 * rng.next() - 1.0) * outer.sin() * 0.9;
        let phi = rng.next() * std::f64::consts::TAU;
        let s = (1.0 - u * u).sqrt();
        let m = DVec3::new(s * phi.cos(), s * phi.sin(), u);
        let (c, e) = circle_frame(m).unwrap();
        let gamma = (2.0 * rng.next() - 1.0) * FRAC_PI_2;
        let got = t.delta(m, gamma);
        for (slot, i) in [(0usize, 0usize), (1, t.order)] {
            let exact = gauss(
                |d| d.powi(i as i32) * f(d.cos() * c + d.sin() * e)[0],
                -FRAC_PI_2,
                gamma,
                3000,
            );
            err[slot] += (got[i][0] - exact).abs();
            mag[slot] += exact.abs();
        }
    }
    [err[0] / mag[0], err[1] / mag[1]]
}

#[test]
fn delta_tables_match_direct_quadrature() {
    for (name, pattern) in [
        ("falloff only", None),
        (
            "checker 8",
            Some(Pattern::Checker {
                cells: 8,
                dark: 0.0,
            }),
        ),
    ] {
        let (light, frame, outer) = spot(pattern);
        let mut errs = Vec::new();
        for n in [8, 16, 32, 64] {
            let e = table_error(&tables(&light, frame, outer, 4, n), &light, frame, outer);
            println!(
                "Δ tables, {name}, N_u = {n}, N_φ = {}: rel error Δ_0 {:.2e}, Δ_4 {:.2e}",
                2 * n,
                e[0],
                e[1]
            );
            errs.push(e);
        }
        // Interpolation between half circles converges: ≥ 2× better from N = 8 to 64.
        assert!(errs[3][0] < errs[0][0] / 2.0, "{name}: {errs:?}");
        // Smooth falloff: bilinear interpolation is second order; at N = 64 the table is within 1%.
        if name == "falloff only" {
            assert!(errs[3][0] < 1e-2 && errs[3][1] < 1e-2, "{name}: {errs:?}");
        } else {
            // Piecewise-constant pattern: edges are smeared over one circle spacing; 10% at N = 64.
            assert!(errs[3][0] < 0.1, "{name}: {errs:?}");
        }
    }
}

/// Rays through the beam: eq. 7 (Chebyshev order 8 of Λ, tables at N) against a Gauss–Legendre
/// quadrature in θ of Λ(θ) I(ω(θ)) with the exact intensity.
#[test]
fn eq7_segments_match_quadrature() {
    let phase = Phase::Isotropic;
    for (name, pattern) in [
        ("falloff only", None),
        (
            "checker 8",
            Some(Pattern::Checker {
                cells: 8,
                dark: 0.0,
            }),
        ),
    ] {
        let (light, frame, outer) = spot(pattern);
        let lp = light.position().unwrap().as_dvec3();
        let mut rel = Vec::new();
        for n in [8, 32] {
            let t = tables(&light, frame, outer, 8, n);
            let mut rng = Rng(11);
            let (mut err, mut mag, mut err_taylor) = (0.0, 0.0, 0.0);
            for _ in 0..80 {
                // A ray from a point near the camera of fence-spot through a point in the beam.
                let o = DVec3::new(4.5, 2.2, 5.5) + DVec3::new(rng.next(), rng.next(), rng.next())
                    - 0.5;
                let target = lp
                    + frame[2] * (1.0 + 5.0 * rng.next())
                    + (frame[0] * (rng.next() - 0.5) + frame[1] * (rng.next() - 0.5)) * 2.0;
                let dir = (target - o).normalize();
                let Some(rc) = ray_circle(o, dir, lp, frame) else {
                    continue;
                };
                let sigma_t = 0.11;
                let k = sigma_t * rc.h;
                let (x0, x1) = (0.0, (target - o).length() + 4.0 * rng.next());
                let (a, b) = (((x0 - rc.t) / rc.h).atan(), ((x1 - rc.t) / rc.h).atan());
                let exact = gauss(
                    |th| {
                        let x = rc.t + rc.h * th.tan();
                        super::poly::kernel(k, &phase, th) * light.intensity_toward(o + x * dir).x
                    },
                    a,
                    b,
                    4000,
                );
                let c = chebyshev_to_monomial(&chebyshev(k, &phase, 8, a, b), a, b);
                let got = eq7(&t, &rc, &c, a, b)[0];
                let got_taylor = eq7(&t, &rc, &taylor(k, &phase, 8), a, b)[0];
                err += (got - exact).abs();
                err_taylor += (got_taylor - exact).abs();
                mag += exact.abs();
            }
            println!(
                "eq. 7 segments, {name}, N_u = {n}: rel error (Chebyshev 8) {:.2e}, (Taylor 8) {:.2e}",
                err / mag,
                err_taylor / mag
            );
            rel.push(err / mag);
        }
        assert!(rel[1] < rel[0] || rel[1] < 1e-3, "{name}: {rel:?}");
        let bound = if name == "falloff only" { 2e-2 } else { 0.1 };
        assert!(rel[1] < bound, "{name}: {rel:?}");
    }
}

#[test]
fn chebyshev_to_monomial_is_the_same_polynomial() {
    let phase = Phase::Isotropic;
    let (a, b) = (-0.7, 0.4);
    let cheb = chebyshev(0.3, &phase, 8, a, b);
    let mono = chebyshev_to_monomial(&cheb, a, b);
    for j in 0..=10 {
        let th = a + (b - a) * j as f64 / 10.0;
        let s = (th - 0.5 * (a + b)) / (0.5 * (b - a));
        let via_cheb: f64 = cheb
            .iter()
            .enumerate()
            .map(|(i, c)| c * (i as f64 * s.acos()).cos())
            .sum();
        let via_mono: f64 = mono
            .iter()
            .enumerate()
            .map(|(i, c)| c * th.powi(i as i32))
            .sum();
        assert!(
            (via_cheb - via_mono).abs() < 1e-9,
            "θ {th}: {via_cheb} vs {via_mono}"
        );
    }
}
