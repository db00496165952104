// The virtual planes (Dobashi et al. 2000, §5.1–5.2): n planes parallel to the image plane at
// view depths (k + ½)Δz, Δz = Z/n with Z the view depth of the farthest visible point; each an
// nu×nv lattice (instanced: one instance per plane). ξ is evaluated at the lattice vertices and
// Gouraud-interpolated (or per fragment); the fragment multiplies in the light map and the
// shadow-map visibility and the pixel's ray-length increment Δs, and is added into the
// accumulation target. Needs PRELUDE and dobashi.wgsl.

// ξ per fragment (knob xi = fragment) instead of per lattice vertex; baked (passes.rs) because
// lavapipe evaluates both sides of a branch on a uniform flag, ξ included.
override XI_PER_FRAGMENT: bool = false;

@group(1) @binding(0) var ray_distance: texture_2d<f32>;
@group(1) @binding(1) var<uniform> planes: Planes;
// bits of the farthest visible view depth, from far.wgsl
@group(1) @binding(2) var<storage, read> far_bits: array<u32>;

// Z: the view depth the planes span, [0, Z] (the camera's far plane if the reduction found none).
fn far_extent() -> f32 {
    let z = bitcast<f32>(far_bits[0]);
    return select(camera.forward.w, min(z, camera.forward.w), z > 0.0);
}

// Interleaved gradient noise (Jimenez 2014) in [0, 1), shifted per frame: the per-pixel plane
// offset of the jittered variant (the paper's future work).
fn jitter_offset(px: vec2<f32>, frame: u32) -> f32 {
    let p = px + 5.588238 * f32(frame % 64u);
    return fract(52.9829189 * fract(dot(p, vec2<f32>(0.06711056, 0.00583715))));
}

struct VsOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) @interpolate(flat) plane: u32,
    @location(1) xi0: vec3<f32>,
    @location(2) xi1: vec3<f32>,
    @location(3) xi2: vec3<f32>,
    @location(4) xi3: vec3<f32>,
};

@vertex
fn vs(@builtin(vertex_index) v: u32, @builtin(instance_index) k: u32) -> VsOut {
    let nu = planes.nu;
    let nv = planes.nv;
    let ndc = vec2<f32>(
        -1.0 + 2.0 * f32(v % nu) / f32(nu - 1u),
        -1.0 + 2.0 * f32(v / nu) / f32(nv - 1u),
    );
    let p = camera.world_from_clip * vec4<f32>(ndc, 1.0, 1.0);
    let dir = normalize(p.xyz / p.w - camera.position.xyz);
    let cos_v = dot(dir, camera.forward.xyz);
    let z = (f32(k) + 0.5) * far_extent() / f32(planes.count);
    let t = z / cos_v;
    var o: VsOut;
    // The plane is drawn inside the depth range (its depth decides only coverage: every plane
    // covers the screen; the fragment places its sample itself). Parallel to the image plane,
    // so w is constant and the interpolation of ξ is linear in screen space (Gouraud).
    let z_draw = clamp(z, camera.position.w * 1.001, camera.forward.w * 0.999);
    o.clip = camera.clip_from_world * vec4<f32>(camera.position.xyz + dir * (z_draw / cos_v), 1.0);
    o.plane = k;
    o.xi0 = vec3<f32>(0.0);
    o.xi1 = vec3<f32>(0.0);
    o.xi2 = vec3<f32>(0.0);
    o.xi3 = vec3<f32>(0.0);
    if (!XI_PER_FRAGMENT) {
        let x = camera.position.xyz + dir * t;
        let n = light_count();
        if (n > 0u) { o.xi0 = xi(0u, x, dir, t); }
        if (n > 1u) { o.xi1 = xi(1u, x, dir, t); }
        if (n > 2u) { o.xi2 = xi(2u, x, dir, t); }
        if (n > 3u) { o.xi3 = xi(3u, x, dir, t); }
    }
    return o;
}

@fragment
fn fs(in: VsOut) -> @location(0) vec4<f32> {
    let flags = planes.flags;
    let px = vec2<i32>(in.clip.xy);
    let dir = camera_ray_dir(camera, in.clip.xy);
    let cos_v = dot(dir, camera.forward.xyz);
    let z_surf = camera_ray_length(camera, dir, textureLoad(ray_distance, px, 0).r) * cos_v;
    let dz = far_extent() / f32(planes.count);
    // This plane's slab of view depth, [z_lo, z_lo + Δz]; with FLAG_CLIP_LAST the slab the surface
    // cuts is shortened to end there (otherwise the paper's rule: a plane behind the surface is
    // rejected, the piece before the surface is lost).
    let z_lo = f32(in.plane) * dz;
    let z_end = select(z_lo + dz, min(z_lo + dz, z_surf), (flags & FLAG_CLIP_LAST) != 0u);
    if (z_end <= z_lo) { discard; }
    let u = select(0.5, jitter_offset(in.clip.xy, planes.frame), (flags & FLAG_JITTER) != 0u);
    let z = z_lo + u * (z_end - z_lo);
    if (z >= z_surf) { discard; }
    let t = z / cos_v;
    let x = camera.position.xyz + dir * t;
    var sum = vec3<f32>(0.0);
    // The first four lights' ξ come interpolated from the vertices (four interpolators); a
    // fifth light on has none left, so its ξ is evaluated here, per fragment.
    let n = light_count();
    for (var k = 0u; k < n; k++) {
        var f: vec3<f32>;
        if (XI_PER_FRAGMENT || k >= 4u) {
            f = xi(k, x, dir, t);
        } else {
            switch k {
                case 0u: { f = in.xi0; }
                case 1u: { f = in.xi1; }
                case 2u: { f = in.xi2; }
                default: { f = in.xi3; }
            }
        }
        // No early `continue` where i = 0: a divergent continue in a light loop is ~5× slower
        // on lavapipe (see raymarch_brute/march.wgsl); the product is 0 there anyway.
        let i = light_map(k, x);
        sum += f * i * shadow_visibility(k, x);
    }
    // Δs: the ray length between the slab's bounds for this pixel, Δz / cos(angle to the view axis).
    let ds = (z_end - z_lo) / cos_v;
    return vec4<f32>(sum * ds * planes.scale, 0.0);
}
