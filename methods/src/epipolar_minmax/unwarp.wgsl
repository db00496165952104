// From samples to pixels (Engelhardt & Dachsbacher 2010, §4.3; Yusov 2013): unmarched samples
// interpolate their two sources along the slice; each pixel then interpolates the two nearest
// slices' two nearest samples, weighting out samples across a depth break; a pixel left without
// weight is queued for a direct march (Yusov's fix-up). Needs PRELUDE and epipolar.wgsl.

// Unmarched sample: linear between its sources along the slice.
@compute @workgroup_size(64)
fn interpolate(@builtin(global_invocation_id) id: vec3<u32>) {
    let m = id.x;
    let i = id.y;
    if (m >= epi.samples || i >= epi.slices) { return; }
    let s = i * epi.samples + m;
    let src = samples[s].src;
    if (samples[s].dist < 0.0 || (src >> 31u) != 0u) { return; }
    let a = src & 0x7fffu;
    let b = (src >> 15u) & 0x7fffu;
    let f = select(0.0, f32(m - a) / f32(b - a), b > a);
    let base = i * epi.samples;
    samples[s].value = mix(samples[base + a].value, samples[base + b].value, f);
}

// Slice i's in-scatter at screen point q, and the weight behind it: bilinear along the slice,
// zero for samples whose ray length breaks with the pixel's `dist`.
fn slice_value(i: u32, q: vec2<f32>, dist: f32, w_slice: f32) -> vec4<f32> {
    let sl = slices[i];
    if (sl.e1.w < 0.5 || w_slice <= 0.0) { return vec4<f32>(0.0); }
    let v = sl.ends.zw - sl.ends.xy;
    let tau = clamp(dot(q - sl.ends.xy, v) / max(dot(v, v), 1e-20), 0.0, 1.0);
    let m = tau * f32(epi.samples - 1u);
    let m0 = min(u32(m), epi.samples - 2u);
    let f = m - f32(m0);
    var sum = vec4<f32>(0.0);
    for (var e = 0u; e < 2u; e++) {
        let s = i * epi.samples + m0 + e;
        let w = w_slice * select(1.0 - f, f, e == 1u) * select(1.0, 0.0, depth_break(samples[s].dist, dist));
        sum += vec4<f32>(samples[s].value.rgb * w, w);
    }
    return sum;
}

@compute @workgroup_size(8, 8)
fn unwarp(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = vec2<u32>(camera.viewport.xy);
    if (id.x >= size.x || id.y >= size.y) { return; }
    let p = id.y * size.x + id.x;
    let q = (vec2<f32>(id.xy) + 0.5) * camera.viewport.zw;
    let ray = camera_ray(q);
    let dist = ray.w;
    let c = slice_coordinate(epipole_uv(epi.light), q, epi.slices);
    let n = epi.slices;
    let c0 = floor(c);
    let f = c - c0;
    let i0 = u32(i32(c0) + i32(n)) % n;
    let sum = slice_value(i0, q, dist, 1.0 - f) + slice_value((i0 + 1u) % n, q, dist, f);
    let prev = select(accum[p], vec4<f32>(0.0), epi.first != 0u);
    if (sum.w > 1e-3) {
        accum[p] = prev + vec4<f32>(sum.rgb / (sum.w * interpolation_scale(epi.light, ray.xyz)), 0.0);
    } else {
        accum[p] = prev;
        work[atomicAdd(&header[1], 1u)] = p;
    }
}

// The indirect dispatch of the fix-up march: one thread per queued pixel.
@compute @workgroup_size(1)
fn fixup_args() {
    let n = atomicLoad(&header[1]);
    atomicStore(&header[5], (n + 63u) / 64u);
    atomicStore(&header[6], 1u);
    atomicStore(&header[7], 1u);
    atomicAdd(&counters[COUNT_FIXUP], n);
}

// The summed in-scatter into the texture the resolve pass reads.
@compute @workgroup_size(8, 8)
fn publish(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = vec2<u32>(camera.viewport.xy);
    if (id.x >= size.x || id.y >= size.y) { return; }
    textureStore(published, id.xy, accum[id.y * size.x + id.x]);
}
