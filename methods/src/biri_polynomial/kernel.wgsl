// biri-polynomial: the kernel Λ(θ) = e^(−k (sinθ+1)/cosθ) p(θ + π/2) of eq. 4 and the medium
// contribution of a lit segment in constant time (eq. 3 and 6), in f32. The including module
// supplies `fn biri_phase(cos_theta: f32) -> f32` (∫p dω = 1); the phase's Taylor series in θ
// (independent of k) comes from the CPU (`poly::phase_series`) because it differs per phase.

const BIRI_PI: f32 = 3.14159265358979;

// Λ(θ) e^(e0): e0 carries −σ_t t so that e^(−σ_t t) never overflows on its own.
fn biri_kernel(k: f32, th: f32, e0: f32) -> f32 {
    let s = sin(th);
    let c = max(cos(th), 1e-7);
    return exp(e0 - k * (s + 1.0) / c) * biri_phase(-s);
}

// e^(e0) ∫_a^b of the order-n Taylor polynomial of Λ around θ = 0 (annex): exp(−k(g−1)) by the
// power-series recurrence, times the phase series `ps`, integrated term by term (eq. 6).
fn biri_taylor_integral(k: f32, n: u32, a: f32, b: f32, e0: f32, ps: array<f32, 9>) -> f32 {
    // g(θ) − 1 = secθ + tanθ − 1 = θ + θ²/2 + θ³/3 + 5θ⁴/24 + 2θ⁵/15 + 61θ⁶/720 + 17θ⁷/315 + 277θ⁸/8064
    var g = array<f32, 9>(0.0, 1.0, 0.5, 1.0 / 3.0, 5.0 / 24.0, 2.0 / 15.0, 61.0 / 720.0, 17.0 / 315.0, 277.0 / 8064.0);
    var p = ps;
    var e = array<f32, 9>(1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
    let nn = min(n, 8u);
    for (var m = 1u; m <= nn; m++) {
        var s = 0.0;
        for (var j = 1u; j <= m; j++) {
            s += f32(j) * (-k * g[j]) * e[m - j];
        }
        e[m] = s / f32(m);
    }
    var total = 0.0;
    var pa = a;
    var pb = b;
    for (var i = 0u; i <= nn; i++) {
        var c = 0.0;
        for (var j = 0u; j <= i; j++) {
            c += e[j] * p[i - j];
        }
        total += c * (pb - pa) / f32(i + 1u);
        pa *= a;
        pb *= b;
    }
    return exp(e0 - k) * total;
}

// e^(e0) ∫_a^b of the degree-n Chebyshev interpolant of Λ on [a, b] (n+1 first-kind nodes):
// (b−a)/2 Σ_{i even} c_i 2/(1 − i²).
fn biri_chebyshev_integral(k: f32, n: u32, a: f32, b: f32, e0: f32) -> f32 {
    let m = min(n, 8u) + 1u;
    let mid = 0.5 * (a + b);
    let half = 0.5 * (b - a);
    var f: array<f32, 9>;
    for (var j = 0u; j < m; j++) {
        f[j] = biri_kernel(k, mid + half * cos(BIRI_PI * (f32(j) + 0.5) / f32(m)), e0);
    }
    var total = 0.0;
    for (var i = 0u; i < m; i += 2u) {
        var c = 0.0;
        for (var j = 0u; j < m; j++) {
            c += f[j] * cos(BIRI_PI * f32(i) * (f32(j) + 0.5) / f32(m));
        }
        let w = select(2.0, 1.0, i == 0u) / f32(m);
        total += c * w * 2.0 / (1.0 - f32(i * i));
    }
    return half * total;
}

// In-scattered radiance per unit σ_s·I of the lit segment [x0, x1] of a ray whose light foot is
// at t with distance h (eq. 3): e^(−σ_t t)/h · ∫ Λ over [atan((x0−t)/h), atan((x1−t)/h)].
// fit: 0 Taylor, 1 Chebyshev.
fn biri_segment(fit: u32, sigma_t: f32, n: u32, t: f32, h_in: f32, x0: f32, x1: f32, ps: array<f32, 9>) -> f32 {
    let h = max(h_in, 1e-6);
    let a = atan((x0 - t) / h);
    let b = atan((x1 - t) / h);
    let k = sigma_t * h;
    let e0 = -sigma_t * t;
    var v: f32;
    if fit == 0u {
        v = biri_taylor_integral(k, n, a, b, e0, ps);
    } else {
        v = biri_chebyshev_integral(k, n, a, b, e0);
    }
    return v / h;
}
