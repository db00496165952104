// Depth impostors (Umenhoffer et al. §2.1): the particles of a block rendered orthographically
// into its tile, one pass computing three things with one blend state — front depth (min),
// back depth (min of its negation) and optical depth Σ τ·chord (additive alpha, the
// separate-alpha blend) — and, in a second additive target, the optical depth's first two
// moments in depth (`interval = moments`, a modernisation; blocks.wgsl, prim_interval).
// Instance i draws particle i mod M: groups g = i / M < K into camera tile (its tile + g) — K
// direction bins of the prototype (camera_bins.rs), else 1 — and group K + k into light k's
// tile (the first light's tile index + k·T). Needs PRELUDE and blocks.wgsl.

struct ImpOut {
    @builtin(position) clip: vec4<f32>,
    // quad coordinate in units of the particle radius
    @location(0) q: vec2<f32>,
    // x: radius; y: τ; z: the centre's depth along the tile's forward axis
    @location(1) @interpolate(flat) data: vec3<f32>,
};

@vertex
fn vs_impostor(@builtin(vertex_index) v: u32, @builtin(instance_index) i: u32) -> ImpOut {
    let m = u32(pb.atlas.z);
    let e = imp[i % m];
    let g = i / m;
    // Groups 0 .. K − 1: the camera tiles (K = pb.counts.w, the prototype's direction bins, or
    // 1); then one group per light.
    let k = u32(pb.counts.w);
    let light_tile = e.data.y + f32(g - min(g, k)) * pb.counts.y;
    let tile = u32(select(light_tile, e.data.z + f32(g), g < k));
    let t = tiles[tile];
    let h = t.right.w;
    let corner = quad_corner(v);
    let p = e.pos.xyz;
    let r = e.pos.w;
    let local = (vec2<f32>(dot(p, t.right.xyz), dot(p, t.up.xyz)) + corner * r) / h;
    let cols = u32(pb.atlas.x);
    let res = pb.atlas.y;
    let origin = vec2<f32>(f32(tile % cols), f32(tile / cols)) * res;
    let texel = origin + vec2<f32>(0.5 + 0.5 * local.x, 0.5 - 0.5 * local.y) * res;
    let size = pb.atlas.w;
    let ndc = vec2<f32>(2.0 * texel.x / size - 1.0, 1.0 - 2.0 * texel.y / size);
    var out: ImpOut;
    out.clip = vec4<f32>(ndc, 0.0, 1.0);
    out.q = corner;
    out.data = vec3<f32>(r, e.data.x, dot(p, t.fwd.xyz));
    return out;
}

struct ImpTexel {
    // r: front depth, g: −back depth (min blending); a: τ·chord (additive alpha)
    @location(0) bounds: vec4<f32>,
    // x: τ·chord·z̄, y: τ·chord·(z̄² + h²/3) — the chord's first two depth moments (additive)
    @location(1) moments: vec2<f32>,
};

@fragment
fn fs_impostor(in: ImpOut) -> ImpTexel {
    let rho2 = 1.0 - dot(in.q, in.q);
    if (rho2 <= 0.0) { discard; }
    let hc = in.data.x * sqrt(rho2);
    let z = in.data.z;
    let mass = in.data.y * 2.0 * hc;
    return ImpTexel(
        vec4<f32>(z - hc, -(z + hc), 0.0, mass),
        mass * vec2<f32>(z, z * z + hc * hc / 3.0),
    );
}
