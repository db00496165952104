// Epipolar slices and the rectified shadow-map coordinate (Engelhardt & Dachsbacher 2010; Chen,
// Baran, Kavan & Durand 2011; slices on the screen border as Yusov 2013 places them), shared by
// epipolar-minmax and prefiltered-single-scattering (common::epipolar::rectification). Every
// camera ray
// lies in one epipolar plane through the eye and the light; N slices from the epipole to evenly
// spaced points of the screen border stand for N such planes, and in each the light's rays are
// indexed by the rectified coordinate u: the angle about a local light from its axis toward the
// eye, the distance across a directional light's rays from the eye's. Screen positions are in
// uv: [0, 1]², x right, y down. Needs PRELUDE.

// One epipolar slice: a screen segment from the epipole outward, and its epipolar plane.
struct Slice {
    // entry uv (xy), exit uv (zw)
    ends: vec4<f32>,
    // xyz: the plane's first axis (from the light toward the eye; the light direction for
    // directional light); w: 1 valid, 0 the segment misses the screen
    e1: vec4<f32>,
    // xyz: the in-plane axis toward the slice's rays; w: the rectified coordinate's extent u_max
    e2: vec4<f32>,
};

// The light's projection (the epipole) in uv: a finite point of its projective line, also for a
// light behind the camera (then rays through the screen run away from it) or at infinity.
fn epipole_uv(k: u32) -> vec2<f32> {
    var c: vec4<f32>;
    if (light_kind(k) == LIGHT_DIRECTIONAL) {
        c = camera.clip_from_world * vec4<f32>(-lights.lights[k].direction.xyz, 0.0);
    } else {
        c = camera.clip_from_world * vec4<f32>(lights.lights[k].position.xyz, 1.0);
    }
    let floor_w = 1e-6 * max(length(c.xy), 1e-20);
    let w = select(-1.0, 1.0, c.w >= 0.0) * max(abs(c.w), floor_w);
    let ndc = clamp(c.xy / w, vec2<f32>(-1e5), vec2<f32>(1e5));
    return vec2<f32>(0.5 + 0.5 * ndc.x, 0.5 - 0.5 * ndc.y);
}

// The point at perimeter parameter u ∈ [0, 1) of the screen's border, clockwise from the
// top-left corner: top, right, bottom, left edge, a quarter each.
fn border_point(u: f32) -> vec2<f32> {
    let e = fract(u) * 4.0;
    let f = fract(e);
    switch u32(e) {
        case 0u: { return vec2<f32>(f, 0.0); }
        case 1u: { return vec2<f32>(1.0, f); }
        case 2u: { return vec2<f32>(1.0 - f, 1.0); }
        default: { return vec2<f32>(0.0, 1.0 - f); }
    }
}

// Inverse of border_point for a point on the border.
fn border_param(p: vec2<f32>) -> f32 {
    let d = vec4<f32>(p.y, 1.0 - p.x, 1.0 - p.y, p.x);
    let m = min(min(d.x, d.y), min(d.z, d.w));
    if (m == d.x) { return 0.25 * clamp(p.x, 0.0, 1.0); }
    if (m == d.y) { return 0.25 + 0.25 * clamp(p.y, 0.0, 1.0); }
    if (m == d.z) { return 0.5 + 0.25 * clamp(1.0 - p.x, 0.0, 1.0); }
    return 0.75 + 0.25 * clamp(1.0 - p.y, 0.0, 1.0);
}

// Where the line o + s v is inside the screen: (s_in, s_out); s_in > s_out when it misses.
fn screen_span(o: vec2<f32>, v: vec2<f32>) -> vec2<f32> {
    var s = vec2<f32>(-3.0e38, 3.0e38);
    for (var a = 0u; a < 2u; a++) {
        if (abs(v[a]) < 1e-12) {
            if (o[a] < 0.0 || o[a] > 1.0) { s = vec2<f32>(1.0, 0.0); }
        } else {
            let s0 = (0.0 - o[a]) / v[a];
            let s1 = (1.0 - o[a]) / v[a];
            s = vec2<f32>(max(s.x, min(s0, s1)), min(s.y, max(s0, s1)));
        }
    }
    return s;
}

// Continuous slice coordinate of screen point q: its ray from the epipole leaves the screen at
// perimeter parameter u, and slice i of n exits at (i + 0.5) / n.
fn slice_coordinate(ep: vec2<f32>, q: vec2<f32>, n: u32) -> f32 {
    let v = q - ep;
    if (dot(v, v) < 1e-14) { return 0.0; }
    let s = screen_span(ep, v);
    return border_param(ep + s.y * v) * f32(n) - 0.5;
}

// From the eye to local light k; a light at the eye (closer than 0.1 mm) is taken 0.1 mm ahead
// of it, where the epipolar frame is defined (the in-scatter there is unbounded anyway).
fn eye_to_light(k: u32) -> vec3<f32> {
    let v = lights.lights[k].position.xyz - camera.position.xyz;
    return select(v, camera.forward.xyz * 1e-4, dot(v, v) < 1e-8);
}

// A ray's far-plane point's rectified coordinate in the plane (o, e1, e2): the angle about the
// light (local light), or the distance across the light direction (directional).
fn far_coordinate(o: vec3<f32>, e1: vec3<f32>, e2: vec3<f32>, uv: vec2<f32>, directional: bool) -> f32 {
    let dir = camera_ray_dir(camera, uv * camera.viewport.xy);
    let x = camera.position.xyz + dir * camera_far_distance(camera, dir) - o;
    if (directional) { return max(dot(x, e2), 0.0); }
    return atan2(max(dot(x, e2), 0.0), dot(x, e1));
}

// Slice i of n for light k: its exit at perimeter parameter (i + 0.5) / n, its entry where the
// line from the epipole enters the screen (the epipole itself when it is on screen); invalid when
// the exit is not where that line leaves the screen. Then the epipolar plane through the eye and
// the light, and u_max: the largest rectified coordinate of the slice's rays at the far plane.
fn epipolar_slice(k: u32, i: u32, n: u32) -> Slice {
    let ep = epipole_uv(k);
    let exit = border_point((f32(i) + 0.5) / f32(n));
    let v = exit - ep;
    let s = screen_span(ep, v);
    var valid = dot(v, v) > 1e-12 && s.x < s.y - 1e-4 && abs(s.y - 1.0) < 1e-3;
    let entry = ep + max(s.x, 0.0) * v;
    let directional = light_kind(k) == LIGHT_DIRECTIONAL;
    let eye = camera.position.xyz;
    var o = lights.lights[k].position.xyz;
    var e1 = -normalize(eye_to_light(k));
    if (directional) {
        o = eye;
        e1 = lights.lights[k].direction.xyz;
    }
    let d = camera_ray_dir(camera, exit * camera.viewport.xy);
    let perp = d - e1 * dot(d, e1);
    valid = valid && dot(perp, perp) > 1e-12;
    let e2 = perp * inverseSqrt(max(dot(perp, perp), 1e-30));
    let mid = 0.5 * (entry + exit);
    let u_max = max(
        far_coordinate(o, e1, e2, entry, directional),
        max(far_coordinate(o, e1, e2, mid, directional), far_coordinate(o, e1, e2, exit, directional)),
    );
    return Slice(
        vec4<f32>(entry, exit),
        vec4<f32>(e1, select(0.0, 1.0, valid)),
        vec4<f32>(e2, max(u_max * 1.001, 1e-6)),
    );
}

// World point on the light ray of slice sl at rectified coordinate u (any point of that ray
// projects to the same shadow-map texel).
fn rectified_point(k: u32, sl: Slice, u: f32) -> vec3<f32> {
    if (light_kind(k) == LIGHT_DIRECTIONAL) {
        return camera.position.xyz + u * sl.e2.xyz;
    }
    return lights.lights[k].position.xyz + cos(u) * sl.e1.xyz + sin(u) * sl.e2.xyz;
}

// The slice's segment meets the screen (e1.w: 1 valid, 0 not).
fn slice_valid(sl: Slice) -> bool {
    return sl.e1.w > 0.5;
}

// The width in the rectified coordinate of one texel of a row of n texels over [0, u_max].
fn texel_width(sl: Slice, n: u32) -> f32 {
    return sl.e2.w / f32(n);
}

// The rectified coordinate of texel j's centre in a row of n texels over [0, u_max].
fn texel_centre(sl: Slice, j: u32, n: u32) -> f32 {
    return (f32(j) + 0.5) * sl.e2.w / f32(n);
}
