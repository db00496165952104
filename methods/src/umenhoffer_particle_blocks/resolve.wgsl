// The last pass: the surface (the shared surface pass, every light's cloud shadow already
// removed by the surface-shadow pass, surface_shadow.wgsl) or the sky, both seen through the
// gathered opacity; the cloud's in-scatter plus, where the scene has a background medium, its
// in-scatter marched along the ray (32 steps, in Biri's angle variable for a local light; shadow
// maps and slices for visibility toward every light), dimmed by the cloud on the eye leg:
// transmittance 1 before the nearest depth where the cloud contributes, the gathered 1 − α
// beyond the farthest, and in between the optical depth −ln(1 − α) growing linearly with depth
// (uniform density across the cloud's span on that ray), the dominant spheres' share exactly
// along their chords (dominant.rs) — or, with EYE_SLICES, the eye's slices at each step. Needs PRELUDE, FULLSCREEN and blocks.wgsl.

// The index of the first light that is not directional (light_count() if none).
fn first_local_light() -> u32 {
    for (var k = 0u; k < light_count(); k++) {
        if (light_kind(k) != LIGHT_DIRECTIONAL) { return k; }
    }
    return light_count();
}

// `total` is their sum, written by a second pass from these two targets (total.wgsl).
struct Resolved {
    inscatter: vec3<f32>,
    surface: vec3<f32>,
};

fn resolve(frag: vec4<f32>) -> Resolved {
    let px = vec2<i32>(frag.xy);
    let eye = camera.position.xyz;
    let dir = camera_ray_dir(camera, frag.xy);
    let hit = textureLoad(ray_distance, px, 0).r;
    let d = camera_ray_length(camera, dir, hit);
    let g = textureLoad(gathered, px, 0);
    var surf = pb.sky.rgb * transmittance(medium, d);
    if (hit >= 0.0) {
        surf = textureLoad(surface_in, px, 0).rgb;
    }
    surf *= 1.0 - g.a;
    var l_in = g.rgb;
    let n = u32(pb.flags.y);
    if (n > 0u) {
        // Equal steps in t for the sun; for a local light equal steps in Biri's angle φ, which
        // flattens the 1/r² peak near the light (angle_march). The angle variable follows the
        // first local light, whichever its index (a sun alone: equal steps in t). Formerly only
        // light 0 was looked at, so a point light after a sun had its 1/r² peak sampled at 32
        // equal steps in t.
        let local = first_local_light();
        var lp = vec3<f32>(0.0);
        if (local < light_count()) { lp = lights.lights[local].position.xyz; }
        let m = angle_march(eye, dir, 0.0, d, n, local < light_count(), lp);
        let e = textureLoad(extents, px, 0);
        // The dominant spheres dim it exactly (their chords; dominant.rs); the linear model
        // spreads the rest of the gathered optical depth over the span of the other primitives.
        let dims = pb.flags.z;
        let dom_tau = select(dominant_depth(eye, dir, 0.0, d), 0.0, EYE_SLICES);
        let cloud_tau = max(-log(max(1.0 - g.a, 1e-30)) - dom_tau, 0.0) * dims;
        let cloud_span = max(-e.y - e.x, 1e-6);
        var acc = vec3<f32>(0.0);
        for (var k = 0u; k < n; k++) {
            let node = march_node(m, k);
            let t = node.x;
            let dom = select(dominant_depth(eye, dir, 0.0, t), 0.0, EYE_SLICES) * dims;
            var cloud = exp(-cloud_tau * clamp((t - e.x) / cloud_span, 0.0, 1.0) - dom);
            if (EYE_SLICES && pb.flags.z > 0.5) { cloud = exp(-eye_optical_depth(eye + dir * t)); }
            acc += incident(eye + dir * t, -dir) * (transmittance(medium, t) * cloud * node.y);
        }
        l_in += medium.sigma_s.rgb * acc;
    }
    return Resolved(l_in, surf);
}

struct ResolveOut {
    @location(0) inscatter: vec4<f32>,
    @location(1) surface: vec4<f32>,
};

@fragment
fn fs_resolve(@builtin(position) frag: vec4<f32>) -> ResolveOut {
    let r = resolve(frag);
    return ResolveOut(vec4<f32>(r.inscatter, 1.0), vec4<f32>(r.surface, 1.0));
}
