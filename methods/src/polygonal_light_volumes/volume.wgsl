// Billeter et al.'s polygonal light volume of one shadow-map face, built by vertex pulling:
// vertex_index → a triangle of the face's grid (one vertex per `mesh` texels, displaced to the
// stored distance), of its side walls, or (directional light) of its far cap; the fragment adds
// or subtracts the unshadowed in-scatter from the eye to it (integral.wgsl).
//
// Local lights (point, spot): the face's volume is the pyramid from the light to the displaced
// grid — the lit part of the face's frustum. Its walls would be fans from the light to the
// grid's boundary, closing every face's volume by itself so that the six volumes tile the lit
// space; adjacent faces' walls are coplanar and cancel where they overlap, so each wall starts
// at the seam instead (seam_vertex): the nearer of the two faces' edge distances. Open directions (no caster)
// end at face.cap.x, beyond everything the camera sees. Entering a lit volume (a front face)
// starts a lit stretch of the ray: −F(d); leaving it (a back face) ends one: +F(d), with
// F(d) = ∫_0^d, so F(0) = 0 and a camera inside a volume needs no term of its own.
//
// Directional light: the shadow volume instead (the lit space is everything but it): grid at the
// stored depth, walls along the light to the cap depth, the cap; the resolve adds the whole
// unshadowed integral and the volume the signed corrections, entering +F(d), leaving −F(d) —
// Biri et al.'s front-add / back-subtract rule.
//
// No depth test: each fragment evaluates F(min(d, d_scene)), so crossings behind the visible
// surface cancel in pairs and an unpaired one (the surface inside a volume) counts at the
// surface, robust to the grid lying on the lit surfaces it was rendered from. The clip-space z
// is pinned to w/2: nothing is clipped by the camera's near or far planes (only behind the eye).
//
// Winding (light's NDC, x right, y up): local grids clockwise (outward = away from the light),
// walls (seam, A, B) with A → B counter-clockwise along the face's boundary; the directional
// grid counter-clockwise (outward = toward the light), walls (A, A', B), (B, A', B'), cap
// clockwise. Front-facing from the eye (wgpu's Ccw) then means entering the volume.
// Needs PRELUDE, ldss.wgsl and integral.wgsl.

struct Face {
    world_from_clip: mat4x4<f32>,
    // xyz: light position (local) or unit propagation direction (directional)
    light: vec4<f32>,
    // xyz: spot axis; w: cosine beyond which grid vertices collapse onto the light (−2: never)
    axis: vec4<f32>,
    // x: the light's shadow-map face (its tile: shadow_face_origin); y: the face's size
    // (texels); z: grid samples per side n; w: unused
    grid: vec4<u32>,
    // x: cap distance (local, m from the light) or cap depth (directional, m along the light)
    cap: vec4<f32>,
};
@group(1) @binding(0) var ray_distance: texture_2d<f32>;
@group(1) @binding(1) var volume_maps: texture_2d_array<f32>;
@group(1) @binding(2) var<uniform> face: Face;

// The light this pipeline draws volumes for (one pipeline per light slot).
override LIGHT: u32 = 0u;

// Texture coordinate (0..1) of grid index i ∈ [0, n + 1]: the face's edge at 0 and n + 1, the
// centres of every (size/n)-th texel between.
fn grid_coord(i: u32) -> f32 {
    return clamp((f32(i) - 0.5) / f32(face.grid.z), 0.0, 1.0);
}

// World position of grid vertex (i, j) (i along NDC x, j along NDC y); `cap`: the directional
// shadow volume's far cap instead of the stored depth.
fn grid_vertex(i: u32, j: u32, cap: bool) -> vec3<f32> {
    let uv = vec2<f32>(grid_coord(i), grid_coord(j));
    let ndc = 2.0 * uv - 1.0;
    let size = face.grid.y;
    // Texel rows run down from NDC y = 1 (shadow.wgsl's convention).
    let texel = min(vec2<u32>(vec2<f32>(uv.x, 1.0 - uv.y) * f32(size)), vec2<u32>(size - 1u));
    let o = shadow_face_origin(LIGHT, face.grid.x);
    let stored = textureLoad(volume_maps, o.xy + texel, o.z, 0).r;
    if (light_kind(LIGHT) == LIGHT_DIRECTIONAL) {
        let near = face.world_from_clip * vec4<f32>(ndc, 0.0, 1.0);
        let p0 = near.xyz / near.w;
        let along = face.light.xyz;
        let depth = select(min(stored, face.cap.x), face.cap.x, cap);
        return p0 + along * (depth - dot(p0, along));
    }
    let far = face.world_from_clip * vec4<f32>(ndc, 1.0, 1.0);
    let towards = normalize(far.xyz / far.w - face.light.xyz);
    // Spot: directions well outside the cone (by the margin in faces.rs) carry no light.
    let dark = dot(towards, face.axis.xyz) < face.axis.w;
    return face.light.xyz + towards * select(min(stored, face.cap.x), 0.0, dark);
}

// The nearest stored distance of the texels within a quarter texel of texture position uv:
// one texel at a texel centre, the two (or four) sharing a texel border — so two faces that see
// the same edge direction through rounded coordinates still read the same texels.
fn edge_distance(cube_face: u32, uv: vec2<f32>) -> f32 {
    let size = face.grid.y;
    let o = shadow_face_origin(LIGHT, cube_face);
    let layer = o.z;
    let x = clamp(uv, vec2<f32>(0.0), vec2<f32>(1.0)) * f32(size);
    let hi = vec2<f32>(f32(size) - 1.0);
    let lo = vec2<u32>(clamp(floor(x - 0.25), vec2<f32>(0.0), hi));
    let up = vec2<u32>(clamp(floor(x + 0.25), vec2<f32>(0.0), hi));
    return min(
        min(textureLoad(volume_maps, o.xy + lo, layer, 0).r, textureLoad(volume_maps, o.xy + up, layer, 0).r),
        min(textureLoad(volume_maps, o.xy + vec2<u32>(lo.x, up.y), layer, 0).r,
            textureLoad(volume_maps, o.xy + vec2<u32>(up.x, lo.y), layer, 0).r));
}

// Where the walls of this face and its neighbour across `side` (0: −y, 1: +x, 2: +y, 3: −x in
// NDC) part: along boundary vertex (i, j)'s direction, at the nearer of the two faces' stored
// distances. Both faces compute (almost exactly) the same point, so each wall can start there
// instead of at the light: the two walls' common inner parts cancelled anyway, and without them
// a wall covers only the sliver between the two faces' edge profiles, not half the screen.
fn seam_vertex(i: u32, j: u32, side: u32) -> vec3<f32> {
    let uv = vec2<f32>(grid_coord(i), grid_coord(j));
    let ndc = 2.0 * uv - 1.0;
    let own = edge_distance(face.grid.x, vec2<f32>(uv.x, 1.0 - uv.y));
    let far = face.world_from_clip * vec4<f32>(ndc, 1.0, 1.0);
    let towards = normalize(far.xyz / far.w - face.light.xyz);
    // The neighbouring cube face: the one a direction just across the edge falls in.
    var across = ndc;
    switch side {
        case 0u: { across.y = -1.1; }
        case 1u: { across.x = 1.1; }
        case 2u: { across.y = 1.1; }
        default: { across.x = -1.1; }
    }
    let q = face.world_from_clip * vec4<f32>(across, 1.0, 1.0);
    let w = q.xyz / q.w - face.light.xyz;
    let a = abs(w);
    var f = 0u;
    if (a.x >= a.y && a.x >= a.z) { f = select(1u, 0u, w.x > 0.0); }
    else if (a.y >= a.z) { f = select(3u, 2u, w.y > 0.0); }
    else { f = select(5u, 4u, w.z > 0.0); }
    let c = lights.lights[LIGHT].faces[f] * vec4<f32>(face.light.xyz + towards, 1.0);
    let other = edge_distance(f, vec2<f32>(0.5 + 0.5 * c.x / c.w, 0.5 - 0.5 * c.y / c.w));
    let dark = dot(towards, face.axis.xyz) < face.axis.w;
    return face.light.xyz + towards * select(min(min(own, other), face.cap.x), 0.0, dark);
}

// Boundary vertex k ∈ [0, 4(n + 1)] walking the face's edge counter-clockwise from (0, 0).
fn boundary(k: u32) -> vec2<u32> {
    let e = face.grid.z + 1u;
    let side = min(k / e, 3u);
    let s = k - side * e;
    switch side {
        case 0u: { return vec2<u32>(s, 0u); }
        case 1u: { return vec2<u32>(e, s); }
        case 2u: { return vec2<u32>(e - s, e); }
        default: { return vec2<u32>(0u, e - s); }
    }
}

struct VolumeOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec3<f32>,
};

fn project(p: vec3<f32>) -> VolumeOut {
    var clip = camera.clip_from_world * vec4<f32>(p, 1.0);
    clip.z = 0.5 * clip.w;
    return VolumeOut(clip, p);
}

// The grid (instance 0) or the directional cap (instance 1): cell (ci, cj), two triangles. Its
// own entry point, as are the walls: lavapipe would run both paths under a mask otherwise.
@vertex
fn vs_grid(@builtin(vertex_index) v: u32, @builtin(instance_index) instance: u32) -> VolumeOut {
    let n = face.grid.z;
    let directional = light_kind(LIGHT) == LIGHT_DIRECTIONAL;
    let tri = v / 3u;
    let corner = v - 3u * tri;
    let cell = tri / 2u;
    let ci = cell % (n + 1u);
    let cj = cell / (n + 1u);
    // Counter-clockwise: (a, b, c), (a, c, d) with a = (ci, cj), b = +x, c = +x+y, d = +y.
    var ccw = array<vec2<u32>, 6>(vec2<u32>(0u, 0u), vec2<u32>(1u, 0u), vec2<u32>(1u, 1u),
                                  vec2<u32>(0u, 0u), vec2<u32>(1u, 1u), vec2<u32>(0u, 1u));
    var c = 3u * (tri % 2u) + corner;
    // Clockwise for the local grids and the directional cap: swap the last two corners.
    let clockwise = !directional || instance == 1u;
    if (clockwise && corner != 0u) { c = 3u * (tri % 2u) + 3u - corner; }
    let o = ccw[c];
    return project(grid_vertex(ci + o.x, cj + o.y, instance == 1u));
}

// The walls: a quad per boundary segment w / 2.
@vertex
fn vs_walls(@builtin(vertex_index) v: u32) -> VolumeOut {
    let n = face.grid.z;
    let tri = v / 3u;
    let corner = v - 3u * tri;
    let seg = tri / 2u;
    let second = (tri % 2u) == 1u;
    var end = 0u;
    var inner = false;
    if (light_kind(LIGHT) != LIGHT_DIRECTIONAL) {
        // From the seam (P) out to the grid (A, B), wound like the fan (light, A, B) it
        // replaces: (P_a, A_a, A_b) and (P_a, A_b, P_b).
        if (!second) {
            end = select(0u, 1u, corner == 2u);
            inner = corner == 0u;
        } else {
            end = select(0u, 1u, corner != 0u);
            inner = corner != 1u;
        }
        let b = boundary(seg + end);
        if (inner) {
            return project(seam_vertex(b.x, b.y, min(seg / (n + 1u), 3u)));
        }
        return project(grid_vertex(b.x, b.y, false));
    }
    // Directional: from the grid (A, B) along the light to the cap (A', B'):
    // (A, A', B) and (B, A', B').
    var at_cap = false;
    if (!second) {
        end = select(0u, 1u, corner == 2u);
        at_cap = corner == 1u;
    } else {
        end = select(1u, 0u, corner == 1u);
        at_cap = corner != 0u;
    }
    let b = boundary(seg + end);
    return project(grid_vertex(b.x, b.y, at_cap));
}

@fragment
fn fs_volume(v: VolumeOut, @builtin(front_facing) front: bool) -> @location(0) vec4<f32> {
    let dir = camera_ray_dir(camera, v.clip.xy);
    let scene = camera_ray_length(camera, dir, textureLoad(ray_distance, vec2<i32>(v.clip.xy), 0).r);
    let f = inscatter_between(LIGHT, dir, 0.0, min(length(v.world - camera.position.xyz), scene));
    // Local light volumes: entering −, leaving +; the directional shadow volume the reverse.
    let entering = select(-1.0, 1.0, light_kind(LIGHT) == LIGHT_DIRECTIONAL);
    return vec4<f32>(select(-entering, entering, front) * f, 0.0);
}
