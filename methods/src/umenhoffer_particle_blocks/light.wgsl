// The light pass (Umenhoffer et al. §2.2): every primitive (block instance or particle) as a
// billboard facing the light, adding its optical depth to each slice it lies before — the
// fraction of its depth interval in front of the slice, assuming uniform density in the
// interval — so slice s holds the optical depth accumulated up to depth d_s. Four slices per
// RGBA target, two targets (eight slices) per render pass; additive blending, no sorting.
// slice_passes() = max(S/8, 1) render passes per light map ("view": one map, or each face of a
// cube around a local light, or — with EYE_SLICES — the eye's view, drawing the gathering's
// list); instance i draws entry i mod C of light k's primitive list into pass
// (i / C) mod slice_passes() of view i / C / slice_passes() (k = view / 6; blocks holding the
// light are replaced there by their particles, held.rs). Each pass skips (a degenerate quad)
// every primitive whose bounds begin beyond its last slice: it adds nothing there. A primitive
// still holding the light (a sphere) is drawn over the
// whole face instead of as a billboard (no billboard can pass through the light), each fragment
// finding its interval along its own light ray, the part behind the light cut off. Needs
// PRELUDE and blocks.wgsl.

struct LightOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) @interpolate(flat) prim: u32,
    @location(2) @interpolate(flat) view: u32,
    // which eight slices (8·pair … 8·pair + 7) this render pass writes
    @location(3) @interpolate(flat) pair: u32,
};

// The billboard facing the light at c.
fn light_basis(vi: u32, c: vec3<f32>) -> Basis {
    if (is_perspective(vi)) { return basis_of(normalize(c - pb.views[vi].p.xyz)); }
    return Basis(pb.views[vi].u.xyz, pb.views[vi].v.xyz);
}

@vertex
fn vs_light(@builtin(vertex_index) v: u32, @builtin(instance_index) i: u32) -> LightOut {
    let stride = u32(pb.counts.x);
    let slot = i / stride;
    let vi = slot / slice_passes();
    let pair = slot % slice_passes();
    // Light k's list is k + 1; the eye's view draws the gathering's list (0).
    let list = select(vi / FACES + 1u, 0u, vi == camera_view());
    let pi = list * stride + i % stride;
    let p = prims[pi];
    let c = p.center.xyz;
    let view = pb.views[vi];
    var out: LightOut;
    out.prim = pi;
    out.view = vi;
    out.pair = pair;
    var nearest = dot(c, view.w.xyz);
    if (is_perspective(vi)) { nearest = length(c - view.p.xyz); }
    let last = min(8.0 * f32(pair) + 7.0, view.range.z - 1.0);
    if (nearest - BOUNDS_MARGIN * p.center.w > slice_depth(vi, last)) {
        // Entirely behind this pass's slices: a degenerate quad outside the view.
        out.clip = vec4<f32>(2.0, 2.0, 2.0, 1.0);
        out.world = c;
        return out;
    }
    var world: vec3<f32>;
    if (is_perspective(vi) && covers_viewer(p.center.w, length(c - view.p.xyz))) {
        // The whole face: the point at unit depth along the axis under each corner.
        let q = quad_corner(v) * view.p.w;
        world = view.p.xyz + view.w.xyz + view.u.xyz * q.x + view.v.xyz * q.y;
    } else {
        let b = light_basis(vi, c);
        var grow = 1.0;
        if (is_perspective(vi)) { grow = grow_for(p.center.w, length(c - view.p.xyz)); }
        let corner = quad_corner(v) * grow;
        world = c + (b.right * corner.x + b.up * corner.y) * p.center.w;
    }
    out.clip = light_clip(vi, world);
    out.world = world;
    return out;
}

// A primitive's extent about its centre, in billboard half-sizes, for the pass culling above
// (the light maps' bounds, light_maps.rs `BOUNDS`).
const BOUNDS_MARGIN: f32 = 1.2;

// The primitive's optical depth before each slice depth.
struct SliceOut {
    a: vec4<f32>,
    b: vec4<f32>,
};

fn slice_contribution(in: LightOut) -> SliceOut {
    let p = prims[in.prim];
    let vi = in.view;
    // Light k's impostor tiles follow the first light's, k·T further on; the eye's view reads
    // the camera tile.
    let tile = select(p.extra.y + f32(vi / FACES) * pb.counts.y, p.extra.z, vi == camera_view());
    let iv = prim_interval(p, tile, light_ray(vi, in.world));
    if (!iv.ok || iv.tau <= 0.0) { discard; }
    var near = iv.near;
    var tau = iv.tau;
    let span = max(iv.far - near, 1e-6);
    if (is_perspective(vi) && near < 0.0) {
        // The light is inside the interval: only the part in front of it is on this ray.
        if (iv.far <= 0.0) { discard; }
        tau *= iv.far / span;
        near = 0.0;
    }
    let rest = max(iv.far - near, 1e-6);
    let n = vec4<f32>(near);
    let s0 = 8.0 * f32(in.pair);
    let da = vec4<f32>(
        slice_depth(vi, s0), slice_depth(vi, s0 + 1.0), slice_depth(vi, s0 + 2.0), slice_depth(vi, s0 + 3.0)
    );
    let db = vec4<f32>(
        slice_depth(vi, s0 + 4.0), slice_depth(vi, s0 + 5.0), slice_depth(vi, s0 + 6.0), slice_depth(vi, s0 + 7.0)
    );
    let fa = clamp((da - n) / rest, vec4<f32>(0.0), vec4<f32>(1.0));
    let fb = clamp((db - n) / rest, vec4<f32>(0.0), vec4<f32>(1.0));
    return SliceOut(tau * fa, tau * fb);
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
