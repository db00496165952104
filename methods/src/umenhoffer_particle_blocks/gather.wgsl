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
// is a quadrature (`chord_inscatter`) instead of the closed form. Needs PRELUDE and common.wgsl.

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
    let surf = select(1e30, hit, hit >= 0.0);
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
    if (CHORD_STEPS > 0u) {
        let l = p.albedo.rgb * chord_inscatter(eye, dir, near, far, tau);
        return Gathered(vec4<f32>(l, out_alpha), vec4<f32>(near, -far, 0.0, 0.0));
    }
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
        var shadowed = exp(-ta) * tau;
        if (abs(kk) > 1e-4) { shadowed = exp(-ta) * tau / kk * (1.0 - exp(-kk)); }
        lit += light_radiance_with(k, x, -dir, mean_inv_r2(k, eye, dir, near, far)) * shadowed;
    }
    let l = p.albedo.rgb * lit * transmittance(medium, t_mid);
    return Gathered(vec4<f32>(l, out_alpha), vec4<f32>(near, -far, 0.0, 0.0));
}

// ∫ σ e^(−σ (t − near)) Σ_k L_k(x(t)) e^(−τ_k(x(t))) T_bg(t) dt over [near, far] (σ = τ over
// the interval, uniform), by the midpoint rule with CHORD_STEPS nodes per light: in t for a
// directional light, in Biri's angle variable φ (t = t0 + h tan φ, dt/r² = dφ/h) for a local
// one, which flattens its 1/r² peak. L_k: light_radiance (phase, I, 1/r², visibility).
fn chord_inscatter(eye: vec3<f32>, dir: vec3<f32>, near: f32, far: f32, tau: f32) -> vec3<f32> {
    let sigma = tau / max(far - near, 1e-6);
    // EYE_SLICES: the eye's slices in front of the interval, and across it at least the own τ
    // (as in the closed form above).
    var front = 0.0;
    if (EYE_SLICES) { front = eye_optical_depth(eye + dir * near); }
    var sum = vec3<f32>(0.0);
    for (var k = 0u; k < light_count(); k++) {
        let local = light_kind(k) != LIGHT_DIRECTIONAL;
        let m = angle_march(eye, dir, near, far, CHORD_STEPS, local, lights.lights[k].position.xyz);
        for (var i = 0u; i < CHORD_STEPS; i++) {
            let node = march_node(m, i);
            let t = node.x;
            let x = eye + dir * t;
            var own = sigma * (t - near);
            if (EYE_SLICES) { own = front + max(eye_optical_depth(x) - front, own); }
            let eye_leg = sigma * exp(-own) * transmittance(medium, t);
            let lit = light_radiance(k, x, -dir) * exp(-light_optical_depth(k, x));
            sum += lit * (eye_leg * node.y);
        }
    }
    return sum;
}
