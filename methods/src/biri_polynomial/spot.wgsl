// biri-polynomial, eq. 7: Γ(M) for a spot light from the Δ_i(γ) tables on half circles
// (`spot.rs` builds them on the CPU; layout [((iu·n_phi + ip)·m + g)·9 + i], rgb = Δ_i of the
// light's falloff × pattern, i = 0…8). Needs PRELUDE, kernel.wgsl and the including module's
// `poly` uniform (spot: [offset, n_u, n_phi, m], spot_f.x = u_max) and `delta` buffer.

fn biri_delta_at(iu: u32, ip: u32, g: u32, i: u32) -> vec3<f32> {
    let s = poly.spot;
    return delta[s.x + ((iu * s.z + ip) * s.w + g) * 9u + i].rgb;
}

// Δ_i(γ_b) − Δ_i(γ_a), i = 0…8, on the half circle of plane normal m (spot frame),
// bilinear between circles, linear in γ.
fn biri_delta_diff(m: vec3<f32>, ga: f32, gb: f32) -> array<vec3<f32>, 9> {
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
    let wp = fp - f32(ip);
    let ip1 = (ip + 1u) % s.z;
    let fa = (ga + 0.5 * BIRI_PI) / BIRI_PI * f32(s.w - 1u);
    let fb = (gb + 0.5 * BIRI_PI) / BIRI_PI * f32(s.w - 1u);
    let ia = min(u32(max(floor(fa), 0.0)), s.w - 2u);
    let ib = min(u32(max(floor(fb), 0.0)), s.w - 2u);
    let wa = clamp(fa - f32(ia), 0.0, 1.0);
    let wb = clamp(fb - f32(ib), 0.0, 1.0);
    var out: array<vec3<f32>, 9>;
    for (var i = 0u; i < 9u; i++) {
        var v = vec3<f32>(0.0);
        for (var c = 0u; c < 4u; c++) {
            let cu = iu + (c & 1u);
            let cp = select(ip, ip1, (c & 2u) != 0u);
            let w = select(1.0 - wu, wu, (c & 1u) != 0u) * select(1.0 - wp, wp, (c & 2u) != 0u);
            let db = mix(biri_delta_at(cu, cp, ib, i), biri_delta_at(cu, cp, ib + 1u, i), wb);
            let da = mix(biri_delta_at(cu, cp, ia, i), biri_delta_at(cu, cp, ia + 1u, i), wa);
            v += w * (db - da);
        }
        out[i] = v;
    }
    return out;
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
fn biri_monomials(fit: u32, k: f32, n: u32, lo: f32, hi: f32, e0: f32, ps: array<f32, 9>) -> array<f32, 9> {
    var out = array<f32, 9>(0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
    let nn = min(n, 8u);
    if fit == 0u {
        var g = array<f32, 9>(0.0, 1.0, 0.5, 1.0 / 3.0, 5.0 / 24.0, 2.0 / 15.0, 61.0 / 720.0, 17.0 / 315.0, 277.0 / 8064.0);
        var e = array<f32, 9>(1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
        for (var m = 1u; m <= nn; m++) {
            var s = 0.0;
            for (var j = 1u; j <= m; j++) {
                s += f32(j) * (-k * g[j]) * e[m - j];
            }
            e[m] = s / f32(m);
        }
        let scale = exp(e0 - k);
        for (var i = 0u; i <= nn; i++) {
            var c = 0.0;
            for (var j = 0u; j <= i; j++) {
                c += e[j] * ps[i - j];
            }
            out[i] = scale * c;
        }
        return out;
    }
    let m = nn + 1u;
    let mid = 0.5 * (lo + hi);
    // a wider floor than the segment: 1/half^8 must stay far from f32 overflow
    let half = max(0.5 * (hi - lo), 0.02);
    var f: array<f32, 9>;
    for (var j = 0u; j < m; j++) {
        f[j] = biri_kernel(k, mid + half * cos(BIRI_PI * (f32(j) + 0.5) / f32(m)), e0);
    }
    // Σ a_i T_i(s) as monomials in s: T_i by the recurrence.
    var tp = array<f32, 9>(1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
    var tc = array<f32, 9>(0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
    var q = array<f32, 9>(0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
    for (var i = 0u; i < m; i++) {
        var a = 0.0;
        for (var j = 0u; j < m; j++) {
            a += f[j] * cos(BIRI_PI * f32(i) * (f32(j) + 0.5) / f32(m));
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
    // s = (θ − mid)/half
    var sc = 1.0;
    for (var j = 0u; j < 9u; j++) {
        out[j] = q[j] * sc;
        sc /= half;
    }
    return biri_shift(out, mid);
}

// Γ(M) (per unit σ_s·I) for a spot: eq. 7 with the polynomial re-expanded in δ = θ + β
// (θ = δ − β: biri_shift by β).
fn biri_spot_gamma(dir: vec3<f32>, x: f32) -> vec3<f32> {
    let k = poly.config.z;
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
        return vec3<f32>(0.0);
    }
    let c = normalize(vec3<f32>(0.0, 0.0, 1.0) - m.z * m);
    let e = cross(m, c);
    let beta = atan2(dot(nl, e), dot(nl, c));
    let th0 = atan(-t / h);
    let thm = atan((x - t) / h);
    // the fit's range must contain M (vertices may lie past the far plane or behind the eye)
    let thf = max(atan((camera_far_distance(camera, dir) - t) / h), thm);
    let ga = clamp(th0 + beta, -0.5 * BIRI_PI, 0.5 * BIRI_PI);
    let gb = clamp(thm + beta, -0.5 * BIRI_PI, 0.5 * BIRI_PI);
    if gb <= ga {
        return vec3<f32>(0.0);
    }
    let d = biri_delta_diff(m, ga, gb);
    var ps: array<f32, 9>;
    for (var i = 0u; i < 9u; i++) {
        ps[i] = poly.series[i / 4u][i % 4u];
    }
    let st = medium.sigma_t.rgb;
    let e0 = -st * t;
    let kk = st * h;
    let n = poly.config.x;
    let fit = poly.config.y;
    let cr = biri_shift(biri_monomials(fit, kk.r, n, th0, thf, e0.r, ps), beta);
    let cg = biri_shift(biri_monomials(fit, kk.g, n, th0, thf, e0.g, ps), beta);
    let cb = biri_shift(biri_monomials(fit, kk.b, n, th0, thf, e0.b, ps), beta);
    var out = vec3<f32>(0.0);
    for (var i = 0u; i <= min(n, 8u); i++) {
        out += vec3<f32>(cr[i] * d[i].r, cg[i] * d[i].g, cb[i] * d[i].b);
    }
    return out / h;
}
