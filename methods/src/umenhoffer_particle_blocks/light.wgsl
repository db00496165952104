// The light pass (Umenhoffer et al. §2.2): every primitive (block instance or particle) as a
// billboard facing the light, adding its optical depth to each slice it lies before — the
// fraction of its depth interval in front of the slice, assuming uniform density in the
// interval — so slice s holds the optical depth accumulated up to depth d_s. Four slices per
// RGBA target; additive blending, no sorting. Needs PRELUDE and common.wgsl.

struct LightOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) @interpolate(flat) prim: u32,
};

// The billboard facing the light at c.
fn light_basis(c: vec3<f32>) -> Basis {
    if (is_perspective()) { return basis_of(normalize(c - pb.light_p.xyz)); }
    return Basis(pb.light_u.xyz, pb.light_v.xyz);
}

@vertex
fn vs_light(@builtin(vertex_index) v: u32, @builtin(instance_index) i: u32) -> LightOut {
    let p = prims[i];
    let c = p.center.xyz;
    let b = light_basis(c);
    var grow = 1.0;
    if (is_perspective()) { grow = grow_for(p.center.w, length(c - pb.light_p.xyz)); }
    let corner = quad_corner(v) * grow;
    let world = c + (b.right * corner.x + b.up * corner.y) * p.center.w;
    var out: LightOut;
    out.clip = light_clip(world);
    out.world = world;
    out.prim = i;
    return out;
}

// The primitive's optical depth before each slice depth.
struct SliceOut {
    a: vec4<f32>,
    b: vec4<f32>,
};

fn slice_contribution(in: LightOut) -> SliceOut {
    let p = prims[in.prim];
    let iv = prim_interval(p, p.extra.y, light_ray(in.world));
    if (!iv.ok || iv.tau <= 0.0) { discard; }
    let span = max(iv.far - iv.near, 1e-6);
    let n = vec4<f32>(iv.near);
    let fa = clamp((pb.slices_a - n) / span, vec4<f32>(0.0), vec4<f32>(1.0));
    let fb = clamp((pb.slices_b - n) / span, vec4<f32>(0.0), vec4<f32>(1.0));
    return SliceOut(iv.tau * fa, iv.tau * fb);
}

@fragment
fn fs_light4(in: LightOut) -> @location(0) vec4<f32> {
    return slice_contribution(in).a;
}

struct Light8 {
    @location(0) a: vec4<f32>,
    @location(1) b: vec4<f32>,
};

@fragment
fn fs_light8(in: LightOut) -> Light8 {
    let s = slice_contribution(in);
    return Light8(s.a, s.b);
}
