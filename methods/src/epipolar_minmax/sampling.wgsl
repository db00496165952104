// Epipolar sampling (Engelhardt & Dachsbacher 2010, §4; Yusov 2013): slice end points on the
// screen border, samples along each slice, and the refinement that marks which samples are
// marched. Needs PRELUDE, EPIPOLAR_SLICES and epipolar.wgsl.

// Slice i of light epi.light (common epipolar_slices.wgsl).
@compute @workgroup_size(64)
fn slice_ends(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if (i >= epi.slices) { return; }
    slices[i] = epipolar_slice(epi.light, i, epi.slices);
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
    if (slice_valid(sl)) { dist = camera_ray(uv).w; }
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
