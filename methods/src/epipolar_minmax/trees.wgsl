// Rectified shadow-map rows and their 1-D min-max trees (Chen, Baran, Kavan & Durand 2011).
// Every camera ray of slice i lies in its epipolar plane, so the part of the shadow map it
// meets is one row: the stored caster distance along the light rays of that plane, indexed by
// the rectified coordinate u (the angle about a local light, the distance across a directional
// light's rays) in K leaves over [0, u_max]. Needs PRELUDE and epipolar.wgsl.

// Tree node index of node n of level l (level 0: the leaves) of slice i.
fn tree_node(i: u32, l: u32, n: u32) -> u32 {
    let two_k = 2u * epi.leaves;
    return i * two_k + two_k - (two_k >> l) + n;
}

// Leaf j of slice i: the shadow map's stored depth at the leaf's centre.
@compute @workgroup_size(64)
fn rectify(@builtin(global_invocation_id) id: vec3<u32>) {
    let j = id.x;
    let i = id.y;
    if (j >= epi.leaves || i >= epi.slices) { return; }
    let sl = slices[i];
    var stored = SHADOW_NONE;
    if (slice_valid(sl)) {
        let u = texel_centre(sl, j, epi.leaves);
        stored = shadow_stored(epi.light, rectified_point(epi.light, sl, u));
    }
    tree[tree_node(i, 0u, j)] = vec2<f32>(stored);
}

// The levels above the leaves of slice i's tree, bottom up.
@compute @workgroup_size(64)
fn build_tree(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if (i >= epi.slices) { return; }
    for (var l = 1u; l <= epi.levels; l++) {
        for (var n = 0u; n < (epi.leaves >> l); n++) {
            let a = tree[tree_node(i, l - 1u, 2u * n)];
            let b = tree[tree_node(i, l - 1u, 2u * n + 1u)];
            tree[tree_node(i, l, n)] = vec2<f32>(min(a.x, b.x), max(a.y, b.y));
        }
    }
}
