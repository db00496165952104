// Epipolar sampling (Engelhardt & Dachsbacher 2010, §4; Yusov 2013): slice end points on the
// screen border, samples along each slice, and the refinement that marks which samples are
// marched. Needs PRELUDE and epipolar.wgsl.

// A ray's far-plane point's rectified coordinate in the plane (o, e1, e2): the angle about the
// light (local light), or the distance across the light direction (directional).
fn far_coordinate(o: vec3<f32>, e1: vec3<f32>, e2: vec3<f32>, uv: vec2<f32>, directional: bool) -> f32 {
    let dir = camera_ray_dir(camera, uv * camera.viewport.xy);
    let x = camera.position.xyz + dir * camera_far_distance(camera, dir) - o;
    if (directional) { return max(dot(x, e2), 0.0); }
    return atan2(max(dot(x, e2), 0.0), dot(x, e1));
}

// Slice i: its exit at perimeter parameter (i + 0.5) / N, its entry where the line from the
// epipole enters the screen (the epipole itself when it is on screen); invalid when the exit is
// not where that line leaves the screen. Then the epipolar plane through the eye and the light.
@compute @workgroup_size(64)
fn slice_ends(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if (i >= epi.slices) { return; }
    let k = epi.light;
    let ep = epipole_uv(k);
    let exit = border_point((f32(i) + 0.5) / f32(epi.slices));
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
    slices[i] = Slice(
        vec4<f32>(entry, exit),
        vec4<f32>(e1, select(0.0, 1.0, valid)),
        vec4<f32>(e2, max(u_max * 1.001, 1e-6)),
    );
}

// Sample m of slice i, evenly spaced from entry to exit, with its camera ray's length.
@compute @workgroup_size(64)
fn place_samples(@builtin(global_invocation_id) id: vec3<u32>) {
    let m = id.x;
    let i = id.y;
    if (m >= epi.samples || i >= epi.slices) { return; }
    let sl = slices[i];
    let uv = mix(sl.ends.xy, sl.ends.zw, f32(m) / f32(epi.samples - 1u));
    var dist = -1.0;
    if (sl.e1.w > 0.5) { dist = camera_ray(uv).w; }
    samples[i * epi.samples + m] = Sample(uv, dist, 0u, vec4<f32>(0.0));
}

// Whether the samples base + a … base + b (inclusive) contain a depth break.
fn breaks_between(base: u32, a: u32, b: u32) -> bool {
    for (var k = a; k < b; k++) {
        if (depth_break(samples[base + k].dist, samples[base + k + 1u].dist)) { return true; }
    }
    return false;
}

// Sample m's interpolation sources (Yusov's refinement): the segment of the coarse grid
// (initial_step) around it, halved until it holds no depth break or is one step long.
fn sources(base: u32, m: u32) -> vec2<u32> {
    let last = epi.samples - 1u;
    var step = epi.initial_step;
    loop {
        let a = (m / step) * step;
        let b = min(a + step, last);
        if (step == 1u || !breaks_between(base, a, b)) { return vec2<u32>(a, b); }
        step = step / 2u;
    }
    return vec2<u32>(m, m);
}

// Marks each sample's sources and appends the marched samples (every segment's ends) to `work`.
@compute @workgroup_size(64)
fn refine(@builtin(global_invocation_id) id: vec3<u32>) {
    let m = id.x;
    let i = id.y;
    if (m >= epi.samples || i >= epi.slices) { return; }
    let base = i * epi.samples;
    if (samples[base].dist < 0.0) { return; }
    let src = sources(base, m);
    var marched = src.x == m;
    if (m > 0u) { marched = marched || sources(base, m - 1u).y == m; }
    samples[base + m].src = src.x | (src.y << 15u) | select(0u, 1u << 31u, marched);
    if (marched) {
        work[atomicAdd(&header[0], 1u)] = base + m;
    } else {
        atomicAdd(&counters[COUNT_INTERPOLATED], 1u);
    }
}

// The indirect dispatch of the march: one thread per marched sample.
@compute @workgroup_size(1)
fn march_args() {
    let n = atomicLoad(&header[0]);
    atomicStore(&header[2], (n + 63u) / 64u);
    atomicStore(&header[3], 1u);
    atomicStore(&header[4], 1u);
    atomicAdd(&counters[COUNT_MARCHED], n);
}
