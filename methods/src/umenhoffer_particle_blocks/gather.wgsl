// Final gathering (Umenhoffer et al. §2.3, §2.4): primitives sorted back to front, each a
// billboard facing the eye. A fragment finds its primitive's interval along the pixel's ray
// (impostor: the block centre's ray parameter plus the stored front/back depths; analytic
// sphere: the exact chord), clips it against the visible surface, and composites
// a·p·I·T_light·(1 − e^(−τ)) over what lies behind it. T_light comes from the slices at both
// ends of the interval (the paper samples one point per block pixel; two and a closed-form
// average is a modernisation). clip_fix (§2.4): a surface inside the interval scales τ by the
// fraction in front of it; without it the billboard plane alone decides (the artefact).
// Every light's contribution is summed per fragment (one set of slices per light). A primitive
// whose bounds hold the eye is drawn as a quad over the whole view (no billboard covers the
// viewer), its interval cut at the eye. The second target keeps the nearest and farthest ray
// parameter where the cloud contributes (min blending), for the background medium's dimming in
// the resolve. With EYE_SLICES (knob `eye_slices`) each primitive's in-scatter is attenuated by
// the eye's slices instead — everything in front, overlapping particles included — and added;
// the opacity is still composited "over". With CHORD_STEPS > 0 the in-scatter over the interval
// is a quadrature (`chord_inscatter`) instead of the closed form. Needs PRELUDE and blocks.wgsl.

struct GatherOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) @interpolate(flat) prim: u32,
};

@vertex
fn vs_gather(@builtin(vertex_index) v: u32, @builtin(instance_index) i: u32) -> GatherOut {
    let p = prims[i];
    let c = p.center.xyz;
    let d = length(c - camera.position.xyz);
    var out: GatherOut;
    out.prim = i;
    if (covers_viewer(p.center.w, d)) {
        out.clip = vec4<f32>(quad_corner(v), 0.0, 1.0);
        return out;
    }
    let b = basis_of(normalize(c - camera.position.xyz));
    let corner = quad_corner(v) * grow_for(p.center.w, d);
    let world = c + (b.right * corner.x + b.up * corner.y) * p.center.w;
    out.clip = camera.clip_from_world * vec4<f32>(world, 1.0);
    return out;
}

struct Gathered {
    // rgb: in-scattered radiance; a: opacity (premultiplied "over")
    @location(0) radiance: vec4<f32>,
    // x: near ray parameter; y: −far (min blending)
    @location(1) extent: vec4<f32>,
};

@fragment
fn fs_gather(in: GatherOut) -> Gathered {
    let eye = camera.position.xyz;
    let dir = camera_ray_dir(camera, in.clip.xy);
    let p = prims[in.prim];
    let iv = prim_interval(p, p.extra.z, Ray(eye, dir));
    if (!iv.ok || iv.far <= 0.0) { discard; }
    let hit = textureLoad(ray_distance, vec2<i32>(in.clip.xy), 0).r;
    // The ray ends at the visible surface or, like the reference's, at the far plane: a particle
    // (a part of one) beyond it is not on the ray (a 1 km sphere around the scene: its far side).
    let surf = camera_ray_length(camera, dir, hit);
    var near = iv.near;
    var far = iv.far;
    var tau = iv.tau;
    let span = max(far - near, 1e-6);
    if (pb.flags.x > 0.5) {
        if (surf <= near) { discard; }
        // Uniform density in the interval: the optical depth of the part before the surface
        // (and after the eye).
        let a = max(near, 0.0);
        let b = min(far, surf);
        tau *= max(b - a, 0.0) / span;
        near = a;
        far = b;
    } else {
        if (surf <= iv.plane) { discard; }
        if (near < 0.0) {
            // The eye inside the interval: only the part in front of it is seen.
            tau *= far / span;
            near = 0.0;
        }
    }
    if (tau <= 0.0) { discard; }
    let alpha = 1.0 - exp(-tau);
    // EYE_SLICES: the in-scatter added, each primitive attenuated by the eye's slices; the
    // opacity composited "over" either way (Π(1 − α) needs no order, and the exact chords
    // keep the silhouettes the slices' texels would blur).
    let out_alpha = alpha;
    // A dominant sphere leaves the extents alone: the resolve dims the haze by it exactly.
    let dominant = is_dominant(in.prim);
    let extent = select(vec2<f32>(near, -far), vec2<f32>(NO_EXTENT), dominant);
    if (CHORD_STEPS > 0u) {
        let l = p.albedo.rgb * chord_inscatter(eye, dir, near, far, tau, CHORD_STEPS, in.prim, surf);
        return Gathered(vec4<f32>(l, out_alpha), vec4<f32>(extent, 0.0, 0.0));
    }
    // A dominant sphere's own in-scatter: the quadrature (a loop of no nodes elsewhere, so the
    // closed form's fragments pay nothing for it).
    let nodes = select(0u, DOMINANT_NODES, dominant);
    let quad = p.albedo.rgb * chord_inscatter(eye, dir, near, far, tau, nodes, in.prim, surf);
    let t_mid = 0.5 * (near + far);
    let x = eye + dir * t_mid;
    // Each light's optical depth at both ends of the interval (slices), taken as linear in
    // between: with uniform extinction τ over the interval, ∫ σ e^(−σ s) e^(−(τa + Δ s/L)) ds
    // = e^(−τa) · τ/(τ+Δ) · (1 − e^(−(τ+Δ))). light_radiance() supplies phase, I
    // and visibility at the midpoint.
    // EYE_SLICES: the eye leg's optical depth at both ends from the eye's slices (everything in
    // front, this primitive and its overlaps included), taken as linear in between like the
    // light's, and growing across the interval by at least the primitive's own exact τ (the
    // slices' texels blur it near its silhouette); else this primitive's own τ over the
    // interval, what lies in front applied by the "over" compositing.
    var ea = 0.0;
    var grow = tau;
    if (EYE_SLICES) {
        ea = eye_optical_depth(eye + dir * near);
        grow = max(eye_optical_depth(eye + dir * far) - ea, tau);
    }
    var lit = vec3<f32>(0.0);
    for (var k = 0u; k < light_count(); k++) {
        let ta = light_optical_depth(k, eye + dir * near) + ea;
        let tb = light_optical_depth(k, eye + dir * far);
        let kk = grow + (tb - (ta - ea));
        let shadowed = pieces_integral(in.prim, eye, dir, near, far, surf, tau, ta, ta + kk);
        lit += light_radiance_with(k, x, -dir, mean_inv_r2(k, eye, dir, near, far)) * shadowed;
    }
    let closed = p.albedo.rgb * lit * transmittance(medium, t_mid);
    let l = select(closed, quad, nodes > 0u);
    return Gathered(vec4<f32>(l, out_alpha), vec4<f32>(extent, 0.0, 0.0));
}

// An extents texel's value where no primitive contributes (passes.rs `NO_EXTENT`).
const NO_EXTENT: f32 = 1e9;

// Nodes of a dominant sphere's own in-scatter quadrature (dominant.rs): across a thick sphere
// the light's optical depth is far from linear, as the closed form takes it.
const DOMINANT_NODES: u32 = 8u;

// Whether gathered primitive i is a dominant sphere.
fn is_dominant(i: u32) -> bool {
    var yes = false;
    for (var j = 0u; j < dominant_count(); j++) {
        yes = yes || u32(pb.dominant[2u * j + 1u].y) == i;
    }
    return yes;
}

// The dominant spheres' eye leg for gathered primitive i at ray parameter t < surf: their exact
// optical depth between the eye and t, less the whole of each one's τ on this ray that the
// "over" compositing already applies to i (those composited after it, clipped as their own
// fragments clip it). Zero with EYE_SLICES, whose slices hold them.
fn dominant_eye_depth(i: u32, eye: vec3<f32>, dir: vec3<f32>, t: f32, surf: f32) -> f32 {
    if (EYE_SLICES) { return 0.0; }
    var tau = 0.0;
    for (var j = 0u; j < dominant_count(); j++) {
        let row = pb.dominant[2u * j + 1u];
        let c = dominant_chord(j, eye, dir);
        let a = max(c.x, 0.0);
        let seen = max(min(c.y, surf) - a, 0.0);
        // Its fragment's τ: clip_fix cuts it at the surface; billboard clipping keeps it whole
        // while the surface lies beyond its centre.
        let whole = select(select(0.0, max(c.y - a, 0.0), surf > 0.5 * (c.x + c.y)), seen, pb.flags.x > 0.5);
        let over = select(0.0, whole, u32(row.y) > i);
        tau += select(row.x * (clamp(t - a, 0.0, seen) - over), 0.0, u32(row.y) == i);
    }
    return tau;
}

// The mean of e^(−x) for x linear from a to b.
fn exp_mean(a: f32, b: f32) -> f32 {
    let d = b - a;
    return select(exp(-a) * (1.0 - exp(-d)) / d, exp(-a), abs(d) < 1e-4);
}

// ∫ σ e^(−G(t)) dt over [near, far], σ = tau / (far − near): G linear from g0 to g1 (the closed
// form's own, light and eye-slice depths) plus the dominant spheres' eye leg for primitive i,
// which is piecewise linear — so the interval is cut at their chord ends and each piece is
// integrated exactly. Without dominant spheres one piece: τ (e^(−g0) − e^(−g1)) / (g1 − g0).
fn pieces_integral(i: u32, eye: vec3<f32>, dir: vec3<f32>, near: f32, far: f32, surf: f32, tau: f32, g0: f32, g1: f32) -> f32 {
    let span = max(far - near, 1e-6);
    let slope = (g1 - g0) / span;
    var t0 = near;
    var e0 = g0 + dominant_eye_depth(i, eye, dir, near, surf);
    var sum = 0.0;
    for (var piece = 0u; piece <= 2u * dominant_count(); piece++) {
        var t1 = far;
        for (var j = 0u; j < dominant_count(); j++) {
            let c = dominant_chord(j, eye, dir);
            let b = min(c.y, surf);
            t1 = select(t1, c.x, c.x > t0 && c.x < t1);
            t1 = select(t1, b, b > t0 && b < t1);
        }
        let e1 = g0 + slope * (t1 - near) + dominant_eye_depth(i, eye, dir, t1, surf);
        sum += (t1 - t0) * exp_mean(e0, e1);
        t0 = t1;
        e0 = e1;
        if (t1 >= far) { break; }
    }
    return tau / span * sum;
}

// ∫ σ e^(−σ (t − near)) Σ_k L_k(x(t)) e^(−τ_k(x(t))) T_bg(t) dt over [near, far] (σ = τ over
// the interval, uniform; the dominant spheres' eye leg for primitive `prim` in the exponent too),
// by the midpoint rule with n nodes per light (CHORD_STEPS, or a dominant sphere's own): in t for a
// directional light, in Biri's angle variable φ (t = t0 + h tan φ, dt/r² = dφ/h) for a local
// one, which flattens its 1/r² peak. L_k: light_radiance (phase, I, 1/r², visibility).
fn chord_inscatter(eye: vec3<f32>, dir: vec3<f32>, near: f32, far: f32, tau: f32, n: u32, prim: u32, surf: f32) -> vec3<f32> {
    let sigma = tau / max(far - near, 1e-6);
    // EYE_SLICES: the eye's slices in front of the interval, and across it at least the own τ
    // (as in the closed form above).
    var front = 0.0;
    if (EYE_SLICES) { front = eye_optical_depth(eye + dir * near); }
    var sum = vec3<f32>(0.0);
    for (var k = 0u; k < light_count(); k++) {
        let local = light_kind(k) != LIGHT_DIRECTIONAL;
        let m = angle_march(eye, dir, near, far, max(n, 1u), local, lights.lights[k].position.xyz);
        for (var i = 0u; i < n; i++) {
            let node = march_node(m, i);
            let t = node.x;
            let x = eye + dir * t;
            var own = sigma * (t - near) + dominant_eye_depth(prim, eye, dir, t, surf);
            if (EYE_SLICES) { own = front + max(eye_optical_depth(x) - front, own); }
            let eye_leg = sigma * exp(-own) * transmittance(medium, t);
            let lit = light_radiance(k, x, -dir) * exp(-light_optical_depth(k, x));
            sum += lit * (eye_leg * node.y);
        }
    }
    return sum;
}
