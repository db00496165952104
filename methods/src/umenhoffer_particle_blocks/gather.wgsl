// Final gathering (Umenhoffer et al. §2.3, §2.4): primitives sorted back to front, each a
// billboard facing the eye. A fragment finds its primitive's interval along the pixel's ray
// (impostor: the block centre's ray parameter plus the stored front/back depths; analytic
// sphere: the exact chord), clips it against the visible surface, and composites
// a·p·I·T_light·(1 − e^(−τ)) over what lies behind it. T_light comes from the slices at both
// ends of the interval (the paper samples one point per block pixel; two and a closed-form
// average is a modernisation). clip_fix (§2.4): a surface inside the interval scales τ by the
// fraction in front of it; without it the billboard plane alone decides (the artefact).
// Needs PRELUDE and common.wgsl.

struct GatherOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) @interpolate(flat) prim: u32,
};

@vertex
fn vs_gather(@builtin(vertex_index) v: u32, @builtin(instance_index) i: u32) -> GatherOut {
    let p = prims[i];
    let c = p.center.xyz;
    let b = basis_of(normalize(c - camera.position.xyz));
    let corner = quad_corner(v) * grow_for(p.center.w, length(c - camera.position.xyz));
    let world = c + (b.right * corner.x + b.up * corner.y) * p.center.w;
    var out: GatherOut;
    out.clip = camera.clip_from_world * vec4<f32>(world, 1.0);
    out.world = world;
    out.prim = i;
    return out;
}

@fragment
fn fs_gather(in: GatherOut) -> @location(0) vec4<f32> {
    let eye = camera.position.xyz;
    let dir = normalize(in.world - eye);
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
        near = max(near, 0.0);
    }
    if (tau <= 0.0) { discard; }
    let alpha = 1.0 - exp(-tau);
    let t_mid = 0.5 * (near + far);
    let x = eye + dir * t_mid;
    // The light's optical depth at both ends of the interval (slices), taken as linear in
    // between: with uniform extinction τ over the interval, ∫ σ e^(−σ s) e^(−(τa + Δ s/L)) ds
    // = e^(−τa) · τ/(τ+Δ) · (1 − e^(−(τ+Δ))). light_radiance() supplies phase, I
    // and visibility at the midpoint.
    let ta = light_optical_depth(eye + dir * near);
    let tb = light_optical_depth(eye + dir * far);
    let k = tau + (tb - ta);
    var shadowed = exp(-ta) * alpha;
    if (abs(k) > 1e-4) { shadowed = exp(-ta) * tau / k * (1.0 - exp(-k)); }
    let l = p.albedo.rgb * light_radiance(x, -dir) * shadowed * transmittance(medium, t_mid);
    return vec4<f32>(l, alpha);
}
