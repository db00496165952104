// Knob `spot_integral = per-ray` (issue 33): a spot light's in-scatter along ONE view ray as an
// antiderivative, fitted once per ray, so that each lit interval [a, b] of the per-pixel walk
// costs G(φ(b)) − G(φ(a)) (two atans and two Clenshaw sums, no light evaluation) instead of
// `spot_panels` Gauss–Legendre panels (2 × `spot_panels` evaluations of falloff, phase and three
// exponentials per interval). Composed after light_segments.wgsl (`angular_sample`,
// `cone_stretch_at`).
//
// The integrand g(φ) = I(ω) p(θ) e^(−σ_t (x + r)) in the angle φ seen from the light
// (dx/r² = dφ/h) is smooth except where the ray crosses the inner cone: there the falloff's
// smoothstep has a jump in its second derivative, which would hold a single polynomial fit to
// algebraic convergence. So the ray's lit span inside the outer cone is cut at the inner cone
// into three pieces (rim, core, rim; some empty), and each piece gets a Chebyshev fit at
// SPOT_FIT_NODES = 8 Chebyshev nodes (Trefethen, *Approximation Theory and Approximation
// Practice*, ch. 3 and 19) whose antiderivative is a Chebyshev series in closed form:
// C_j = (c_{j−1} − c_{j+1}) / 2j. Outside the span G is constant (φ is clamped), so the cone clip
// costs nothing per interval. Measured (README): 8 nodes per piece are 5e-6 of the ray's total
// (6 nodes: 1e-3 on rays that only graze the rim), where one fit over the whole span would need
// 32 nodes for 2e-5. Not for patterned spots (a pattern edge is not smooth): `spot_fit_applies`.
//
// Written out for 8 nodes, with no array: the coefficients live in struct fields (measured on
// lavapipe: with them in private arrays indexed in loops the walk was no faster than the
// panels; such arrays presumably live in per-lane memory rather than registers).

// Knob `spot_integral` (baked): true per ray, false per interval (`spot_panels` each).
override SPOT_INTEGRAL_PER_RAY: bool = false;
const SPOT_FIT_NODES: u32 = 8u;

// The antiderivative of one piece, C_0 .. C_8 of its Chebyshev series in u ∈ [−1, 1] (0 at −1).
struct SpotPiece {
    c0: vec3<f32>, c1: vec3<f32>, c2: vec3<f32>, c3: vec3<f32>, c4: vec3<f32>,
    c5: vec3<f32>, c6: vec3<f32>, c7: vec3<f32>, c8: vec3<f32>,
};

// One ray's fit: φ at the piece bounds, the integral before each piece, the pieces.
struct SpotFit {
    cut: vec4<f32>,        // φ of the span's start, the inner-cone entry and exit, its end
    core_base: vec3<f32>,  // the integral over the first piece
    rim_base: vec3<f32>,   // ... over the first two
    rim_in: SpotPiece,
    core: SpotPiece,
    rim_out: SpotPiece,
    x0: f32,               // the ray's closest approach to the light (distance from the eye)
    h: f32,                // the light's distance from the ray there
};

// Whether light k's intervals go through the per-ray fit: the knob is on and k is a spot
// without a pattern (uniform across invocations: k is).
fn spot_fit_applies(k: u32) -> bool {
    return SPOT_INTEGRAL_PER_RAY && scene_has_light_kind(LIGHT_SPOT) && light_kind(k) == LIGHT_SPOT
        && lights.lights[k].up.w < 0.0;
}

// The fit of spot k along view ray `dir` over the distances [first, last] (the ray's first and
// last lit bound).
fn spot_fit(k: u32, dir: vec3<f32>, first: f32, last: f32) -> SpotFit {
    let to_light = lights.lights[k].position.xyz - camera.position.xyz;
    let x0 = dot(to_light, dir);
    let h = max(length(to_light - dir * x0), 1e-6);
    let outer = cone_stretch(k, dir);
    let inner = cone_stretch_at(k, dir, lights.lights[k].direction.w);
    let lo = max(first, outer.x);
    let hi = max(lo, min(last, outer.y));
    // The core inside [lo, hi]; none: all of the span is the first piece.
    let has_core = inner.x < inner.y;
    let core_in = select(hi, clamp(inner.x, lo, hi), has_core);
    let core_out = select(hi, clamp(inner.y, core_in, hi), has_core);
    let cut = atan((vec4<f32>(lo, core_in, core_out, hi) - vec4<f32>(x0)) / h);
    let none = SpotPiece(vec3<f32>(0.0), vec3<f32>(0.0), vec3<f32>(0.0), vec3<f32>(0.0), vec3<f32>(0.0),
        vec3<f32>(0.0), vec3<f32>(0.0), vec3<f32>(0.0), vec3<f32>(0.0));
    var fit = SpotFit(cut, vec3<f32>(0.0), vec3<f32>(0.0), none, none, none, x0, h);
    // Empty pieces are skipped (a ray outside the cone, or one that misses the core): their
    // integral is 0 and `spot_fit_at` never reads them (it stays in the first piece where all
    // cuts are equal).
    if (cut.y > cut.x) {
        fit.rim_in = spot_fit_piece(k, dir, x0, h, cut.x, cut.y);
        fit.core_base = spot_piece_at(fit.rim_in, 1.0);
    }
    fit.rim_base = fit.core_base;
    if (cut.z > cut.y) {
        fit.core = spot_fit_piece(k, dir, x0, h, cut.y, cut.z);
        fit.rim_base += spot_piece_at(fit.core, 1.0);
    }
    if (cut.w > cut.z) {
        fit.rim_out = spot_fit_piece(k, dir, x0, h, cut.z, cut.w);
    }
    return fit;
}

// g over [pa, pb] at the 8 Chebyshev nodes u_n = cos θ_n, θ_n = π (n + ½)/8, into
// c_j = (2/8) Σ_n g(u_n) T_j(u_n) (T_j by T_{j+1} = 2u T_j − T_{j−1}), then the antiderivative's
// C_j = half (c_{j−1} − c_{j+1}) / 2j (c_8 = c_9 = 0) and C_0 = −Σ_{j≥1} (−1)^j C_j (0 at pa).
fn spot_fit_piece(k: u32, dir: vec3<f32>, x0: f32, h: f32, pa: f32, pb: f32) -> SpotPiece {
    let mid = 0.5 * (pa + pb);
    let half = 0.5 * (pb - pa);
    var c0 = vec3<f32>(0.0);
    var c1 = vec3<f32>(0.0);
    var c2 = vec3<f32>(0.0);
    var c3 = vec3<f32>(0.0);
    var c4 = vec3<f32>(0.0);
    var c5 = vec3<f32>(0.0);
    var c6 = vec3<f32>(0.0);
    var c7 = vec3<f32>(0.0);
    for (var n = 0u; n < SPOT_FIT_NODES; n++) {
        let u = cos(PI * (f32(n) + 0.5) / f32(SPOT_FIT_NODES));
        let g = angular_sample(k, dir, x0, h, mid + half * u);
        let t2 = 2.0 * u * u - 1.0;
        let t3 = 2.0 * u * t2 - u;
        let t4 = 2.0 * u * t3 - t2;
        let t5 = 2.0 * u * t4 - t3;
        let t6 = 2.0 * u * t5 - t4;
        let t7 = 2.0 * u * t6 - t5;
        c0 += g;
        c1 += g * u;
        c2 += g * t2;
        c3 += g * t3;
        c4 += g * t4;
        c5 += g * t5;
        c6 += g * t6;
        c7 += g * t7;
    }
    let s = half * 2.0 / f32(SPOT_FIT_NODES);
    var p = SpotPiece(vec3<f32>(0.0), s * (c0 - c2) / 2.0, s * (c1 - c3) / 4.0, s * (c2 - c4) / 6.0,
        s * (c3 - c5) / 8.0, s * (c4 - c6) / 10.0, s * (c5 - c7) / 12.0, s * c6 / 14.0, s * c7 / 16.0);
    p.c0 = p.c1 - p.c2 + p.c3 - p.c4 + p.c5 - p.c6 + p.c7 - p.c8;
    return p;
}

// One piece's antiderivative at u ∈ [−1, 1], Clenshaw: b_j = C_j + 2u b_{j+1} − b_{j+2},
// G = C_0 + u b_1 − b_2.
fn spot_piece_at(p: SpotPiece, u: f32) -> vec3<f32> {
    let u2 = 2.0 * u;
    let b8 = p.c8;
    let b7 = p.c7 + u2 * b8;
    let b6 = p.c6 + u2 * b7 - b8;
    let b5 = p.c5 + u2 * b6 - b7;
    let b4 = p.c4 + u2 * b5 - b6;
    let b3 = p.c3 + u2 * b4 - b5;
    let b2 = p.c2 + u2 * b3 - b4;
    let b1 = p.c1 + u2 * b2 - b3;
    return p.c0 + u * b1 - b2;
}

// ∫ g dφ from the span's start to φ (clamped to the span): the piece's base plus its
// antiderivative.
fn spot_fit_at(fit: SpotFit, phi: f32) -> vec3<f32> {
    let p = select(0u, 1u, phi > fit.cut.y) + select(0u, 1u, phi > fit.cut.z);
    let pa = fit.cut[p];
    let width = fit.cut[p + 1u] - pa;
    let u = clamp(2.0 * (phi - pa) / max(width, 1e-30) - 1.0, -1.0, 1.0);
    var piece = fit.rim_in;
    var base = vec3<f32>(0.0);
    if (p == 1u) {
        piece = fit.core;
        base = fit.core_base;
    }
    if (p == 2u) {
        piece = fit.rim_out;
        base = fit.rim_base;
    }
    return base + spot_piece_at(piece, u);
}

// σ_s ∫_a^b of the fitted spot over [a, b] of the ray (distances from the eye).
fn spot_fit_between(fit: SpotFit, a: f32, b: f32) -> vec3<f32> {
    if (fit.cut.w <= fit.cut.x) {
        return vec3<f32>(0.0);
    }
    let phi = atan((vec2<f32>(a, b) - vec2<f32>(fit.x0)) / fit.h);
    return medium.sigma_s.rgb * (spot_fit_at(fit, phi.y) - spot_fit_at(fit, phi.x)) / fit.h;
}
