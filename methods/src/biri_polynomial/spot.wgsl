// biri-polynomial, eq. 7: Γ(M) for a spot light from the Δ_i(γ) tables on half circles
// (`spot.rs` builds them on the CPU; layout [((iu·n_phi + ip)·m + g)·9 + i], rgb = Δ_i of the
// light's falloff × pattern, i = 0…8). Needs PRELUDE, kernel.wgsl and the including module's
// `poly` uniform (spot: [offset, n_u, n_phi, m], spot_f.x = u_max) and `delta` buffer.

fn biri_delta_at(iu: u32, ip: u32, g: u32, i: u32) -> vec3<f32> {
    let s = poly.spot;
    return delta[s.x + ((iu * s.z + ip) * s.w + g) * 9u + i].rgb;
}

// The four tabulated half circles around plane normal m (spot frame) and their bilinear weights.
struct SpotCell {
    iu: u32,
    ip: u32,
    wu: f32,
    wp: f32,
};

fn biri_spot_cell(m: vec3<f32>) -> SpotCell {
    let s = poly.spot;
    let u_max = poly.spot_f.x;
    let fu = (m.z + u_max) / (2.0 * u_max) * f32(s.y - 1u);
    let iu = min(u32(max(floor(fu), 0.0)), s.y - 2u);
    let wu = clamp(fu - f32(iu), 0.0, 1.0);
    var phi = atan2(m.y, m.x);
    if phi < 0.0 {
        phi += 2.0 * BIRI_PI;
    }
    let fp = phi / (2.0 * BIRI_PI) * f32(s.z);
    let ip = min(u32(floor(fp)), s.z - 1u);
    return SpotCell(iu, ip, wu, fp - f32(ip));
}

// Δ_i(γ) on the half circle of `cell`: bilinear between circles, linear in γ.
fn biri_delta(cell: SpotCell, gamma: f32, i: u32) -> vec3<f32> {
    let s = poly.spot;
    let ip1 = (cell.ip + 1u) % s.z;
    let f = (gamma + 0.5 * BIRI_PI) / BIRI_PI * f32(s.w - 1u);
    let ig = min(u32(max(floor(f), 0.0)), s.w - 2u);
    let wg = clamp(f - f32(ig), 0.0, 1.0);
    var v = vec3<f32>(0.0);
    for (var c = 0u; c < 4u; c++) {
        let cu = cell.iu + (c & 1u);
        let cp = select(cell.ip, ip1, (c & 2u) != 0u);
        let w = select(1.0 - cell.wu, cell.wu, (c & 1u) != 0u)
            * select(1.0 - cell.wp, cell.wp, (c & 2u) != 0u);
        v += w * mix(biri_delta_at(cu, cp, ig, i), biri_delta_at(cu, cp, ig + 1u, i), wg);
    }
    return v;
}

// Coefficients in δ of Σ c_j (δ − s)^j.
fn biri_shift(c: array<f32, 9>, s: f32) -> array<f32, 9> {
    var out = array<f32, 9>(0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
    for (var j = 0u; j < 9u; j++) {
        var binom = 1.0;
        var pw = 1.0; // (−s)^(j−i), built from i = j downwards
        for (var q = 0u; q <= j; q++) {
            let i = j - q;
            out[i] += c[j] * binom * pw;
            // next: i−1, C(j, i−1) = C(j, i) · i / (j − i + 1)
            binom = binom * f32(i) / f32(j - i + 1u);
            pw *= -s;
        }
    }
    return out;
}

// Monomial coefficients in θ (times e^(e0)) of Λ's order-n polynomial for k: the paper's Taylor
// series (fit 0), or the Chebyshev interpolant on the ray's whole range [lo, hi] (fit 1) — the
// same polynomial for every Γ on the ray, so eq. 12's differences stay consistent.
// Constant trip counts (orders past n are masked): lavapipe then unrolls the loops and keeps the
// private arrays in registers instead of scratch memory.
fn biri_monomials(fit: u32, k: f32, n: u32, lo: f32, hi: f32, e0: f32, ps: array<f32, 9>) -> array<f32, 9> {
    var out = array<f32, 9>(0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
    let nn = min(n, 8u);
    if fit == 0u {
        var g = array<f32, 9>(0.0, 1.0, 0.5, 1.0 / 3.0, 5.0 / 24.0, 2.0 / 15.0, 61.0 / 720.0, 17.0 / 315.0, 277.0 / 8064.0);
        var e = array<f32, 9>(1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
        for (var m = 1u; m <= 8u; m++) {
            var s = 0.0;
            for (var j = 1u; j <= m; j++) {
                s += f32(j) * (-k * g[j]) * e[m - j];
            }
            e[m] = s / f32(m);
        }
        let scale = exp(e0 - k);
        for (var i = 0u; i < 9u; i++) {
            var c = 0.0;
            for (var j = 0u; j <= i; j++) {
                c += e[j] * ps[i - j];
            }
            out[i] = select(0.0, scale * c, i <= nn);
        }
        return out;
    }
    let m = nn + 1u;
    let mid = 0.5 * (lo + hi);
    // a wider floor than the segment: 1/half^8 must stay far from f32 overflow
    let half = max(0.5 * (hi - lo), 0.02);
    var f = array<f32, 9>(0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
    for (var j = 0u; j < 9u; j++) {
        if j < m {
            f[j] = biri_kernel(k, mid + half * cos(BIRI_PI * (f32(j) + 0.5) / f32(m)), e0);
        }
    }
    // Σ a_i T_i(s) as monomials in s: T_i by the recurrence.
    var tp = array<f32, 9>(1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
    var tc = array<f32, 9>(0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
    var q = array<f32, 9>(0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
    for (var i = 0u; i < 9u; i++) {
        if i < m {
            var a = 0.0;
            for (var j = 0u; j < 9u; j++) {
                if j < m {
                    a += f[j] * cos(BIRI_PI * f32(i) * (f32(j) + 0.5) / f32(m));
                }
            }
            a *= select(2.0, 1.0, i == 0u) / f32(m);
            if i == 0u {
                for (var j = 0u; j < 9u; j++) {
                    q[j] += a * tp[j];
                }
            } else {
                for (var j = 0u; j < 9u; j++) {
                    q[j] += a * tc[j];
                }
                var nx = array<f32, 9>(0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
                for (var j = 0u; j < 8u; j++) {
                    nx[j + 1u] = 2.0 * tc[j];
                }
                for (var j = 0u; j < 9u; j++) {
                    nx[j] -= tp[j];
                }
                tp = tc;
                tc = nx;
            }
        }
    }
    // s = (θ − mid)/half
    var sc = 1.0;
    for (var j = 0u; j < 9u; j++) {
        out[j] = q[j] * sc;
        sc /= half;
    }
    return biri_shift(out, mid);
}

// Eq. 7 on one eye ray (unit `dir`), everything that does not depend on M: the light's foot
// t and distance h, the ray plane's normal m in the spot frame, β (δ = θ + β), θ_0 at the eye and
// γ_a = θ_0 + β. `lit` is false when m's half circle lies outside the tables (Γ = 0 on the ray).
struct SpotGeometry {
    t: f32,
    h: f32,
    m: vec3<f32>,
    beta: f32,
    th0: f32,
    ga: f32,
    lit: bool,
};

fn biri_spot_geometry(dir: vec3<f32>) -> SpotGeometry {
    let k = poly.light;
    // Field by field: copying a whole `Light` (480 bytes) per call is slow on lavapipe.
    let v = lights.lights[k].position.xyz - camera.position.xyz;
    let t = dot(v, dir);
    let foot = t * dir - v;
    let h = max(length(foot), 1e-6);
    let nh = foot / h;
    let fr = lights.lights[k].right.xyz;
    let fu = lights.lights[k].up.xyz;
    let fa = lights.lights[k].direction.xyz;
    let nl = vec3<f32>(dot(nh, fr), dot(nh, fu), dot(nh, fa));
    let ul = vec3<f32>(dot(dir, fr), dot(dir, fu), dot(dir, fa));
    // cross in the spot frame itself: (right, up, axis) is left-handed
    let m = normalize(cross(nl, ul));
    if abs(m.z) >= poly.spot_f.x {
        return SpotGeometry(t, h, m, 0.0, 0.0, 0.0, false);
    }
    let c = normalize(vec3<f32>(0.0, 0.0, 1.0) - m.z * m);
    let e = cross(m, c);
    let beta = atan2(dot(nl, e), dot(nl, c));
    let th0 = atan(-t / h);
    let ga = clamp(th0 + beta, -0.5 * BIRI_PI, 0.5 * BIRI_PI);
    return SpotGeometry(t, h, m, beta, th0, ga, true);
}

// θ where the ray through the far plane along `dir` ends.
fn biri_spot_far_theta(g: SpotGeometry, dir: vec3<f32>) -> f32 {
    return atan((camera_far_distance(camera, dir) - g.t) / g.h);
}

// The ray's polynomial in δ (eq. 7), per channel: Λ's order-n fit on [θ_0, thf] (Chebyshev) or
// around θ = 0 (Taylor), shifted by β. Entries past the order are 0.
fn biri_spot_coefficients(g: SpotGeometry, thf: f32) -> array<vec3<f32>, 9> {
    var ps: array<f32, 9>;
    for (var i = 0u; i < 9u; i++) {
        ps[i] = poly.series[i / 4u][i % 4u];
    }
    let st = medium.sigma_t.rgb;
    let e0 = -st * g.t;
    let kk = st * g.h;
    let n = ORDER;
    let fit = FIT;
    let cr = biri_shift(biri_monomials(fit, kk.r, n, g.th0, thf, e0.r, ps), g.beta);
    let cg = biri_shift(biri_monomials(fit, kk.g, n, g.th0, thf, e0.g, ps), g.beta);
    let cb = biri_shift(biri_monomials(fit, kk.b, n, g.th0, thf, e0.b, ps), g.beta);
    var out: array<vec3<f32>, 9>;
    for (var i = 0u; i < 9u; i++) {
        out[i] = vec3<f32>(cr[i], cg[i], cb[i]);
    }
    return out;
}

// Γ(M) (per unit σ_s·I) for a spot: eq. 7 with the polynomial re-expanded in δ = θ + β
// (θ = δ − β: biri_shift by β). Everything at once, for per-vertex evaluation; per fragment,
// `biri_spot_gamma_pixel` reads the ray's part from the per-light pass instead.
fn biri_spot_gamma(dir: vec3<f32>, x: f32) -> vec3<f32> {
    let g = biri_spot_geometry(dir);
    if !g.lit {
        return vec3<f32>(0.0);
    }
    let thm = atan((x - g.t) / g.h);
    let gb = clamp(thm + g.beta, -0.5 * BIRI_PI, 0.5 * BIRI_PI);
    if gb <= g.ga {
        return vec3<f32>(0.0);
    }
    // the fit's range must contain M (vertices may lie past the far plane or behind the eye)
    let c = biri_spot_coefficients(g, max(biri_spot_far_theta(g, dir), thm));
    let cell = biri_spot_cell(g.m);
    var out = vec3<f32>(0.0);
    for (var i = 0u; i <= ORDER; i++) {
        out += c[i] * (biri_delta(cell, gb, i) - biri_delta(cell, g.ga, i));
    }
    return out / g.h;
}
