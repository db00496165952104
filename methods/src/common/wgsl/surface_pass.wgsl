// The forward surface pass: Lambert + Phong with shadow-mapped visibility, attenuated toward the
// eye (ARCHITECTURE §1's e^(−σt d) L_surf; e^(−τ) of each leg with height fog), and the distance
// along each pixel's ray. Needs PRELUDE.

struct VsOut {
    // Invariant: passes that redraw the surfaces over this depth (depth test Equal) get the
    // very same depths.
    @builtin(position) @invariant clip: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) @interpolate(flat) object: u32,
};

@vertex
fn vs(v: VertexIn) -> VsOut {
    let o = objects[v.object];
    let world = o.world_from_local * vec4<f32>(v.position, 1.0);
    let n = (o.normal_from_local * vec4<f32>(v.normal, 0.0)).xyz;
    return VsOut(camera.clip_from_world * world, world.xyz, n, v.object);
}

struct FsOut {
    @location(0) surface: vec4<f32>,
    @location(1) distance: vec4<f32>,
};

// Light k's unshadowed reflected radiance toward v at x, with n facing the viewer.
fn shade_light(k: u32, x: vec3<f32>, n: vec3<f32>, v: vec3<f32>, o: ObjectData) -> vec3<f32> {
    var to_light: vec3<f32>;
    var incident: vec3<f32>;
    if (light_kind(k) == LIGHT_DIRECTIONAL) {
        to_light = -lights.lights[k].direction.xyz;
        incident = lights.lights[k].intensity.rgb;
    } else {
        let w = x - lights.lights[k].position.xyz;
        let r = length(w);
        to_light = -w / r;
        incident = light_intensity(k, w) * transmittance_along(medium, x, to_light, r) / (r * r);
    }
    let cos_l = dot(n, to_light);
    if (cos_l <= 0.0) { return vec3<f32>(0.0); }
    var brdf = o.albedo.rgb / PI;
    if (o.phong.w > 0.0) {
        let refl = 2.0 * cos_l * n - to_light;
        brdf += o.phong.rgb * (o.phong.w + 2.0) / (2.0 * PI) * pow(max(dot(refl, v), 0.0), o.phong.w);
    }
    return brdf * incident * cos_l;
}

// Light k's reflected radiance toward v at x with its shadow-map visibility.
fn shade_light_shadowed(k: u32, x: vec3<f32>, n: vec3<f32>, v: vec3<f32>, o: ObjectData) -> vec3<f32> {
    let directional = light_kind(k) == LIGHT_DIRECTIONAL;
    let r = length(x - lights.lights[k].position.xyz);
    // Offset along the normal so a surface does not shadow itself.
    let offset = 2.0 * select(r, 1.0, directional) / max(lights.lights[k].shadow.z, 1.0);
    return shade_light(k, x, n, v, o) * shadow_visibility(k, x + n * offset);
}

// The normal facing the viewer, or zero for the back of a one-sided surface.
fn facing_normal(n_in: vec3<f32>, front: bool, o: ObjectData) -> vec3<f32> {
    let n = normalize(n_in);
    if (front) { return n; }
    return select(-n, vec3<f32>(0.0), o.albedo.w < 0.5);
}

// Reflected radiance toward the eye at x (not attenuated on the eye leg), shadow-mapped.
fn shade(x: vec3<f32>, n_in: vec3<f32>, front: bool, o: ObjectData) -> vec3<f32> {
    let n = facing_normal(n_in, front, o);
    if (all(n == vec3<f32>(0.0))) { return vec3<f32>(0.0); }
    let v = normalize(camera.position.xyz - x);
    var out = vec3<f32>(0.0);
    for (var k = 0u; k < light_count(); k++) {
        out += shade_light_shadowed(k, x, n, v, o);
    }
    return out;
}

// e^(−τ) from the eye to the surface point x at distance d along the pixel's ray.
fn eye_transmittance(x: vec3<f32>, d: f32) -> vec3<f32> {
    return transmittance_along(medium, camera.position.xyz, normalize(x - camera.position.xyz), d);
}

// Stencil surface shadows (methods that draw shadow volumes): the light SURFACE_LIGHT's
// unshadowed contribution, negated, for an additive pass that runs only where the stencil says
// the visible point is inside one of that light's shadow volumes.
override SURFACE_LIGHT: u32 = 0u;

// A rasterised surface point as the shading functions take it.
struct Seen {
    x: vec3<f32>,
    // the normal facing the viewer (zero: the back of a one-sided surface)
    n: vec3<f32>,
    // unit direction toward the eye
    v: vec3<f32>,
    o: ObjectData,
    // distance from the eye (m)
    d: f32,
};

fn seen(i: VsOut, front: bool) -> Seen {
    let o = objects[i.object];
    let to_eye = camera.position.xyz - i.world;
    let d = camera_surface_distance(camera, i.clip.xy, i.world);
    return Seen(i.world, facing_normal(i.normal, front, o), normalize(to_eye), o, d);
}

@fragment
fn fs_remove_light(i: VsOut, @builtin(front_facing) front: bool) -> @location(0) vec4<f32> {
    let s = seen(i, front);
    let l = shade_light(SURFACE_LIGHT, s.x, s.n, s.v, s.o) * eye_transmittance(s.x, s.d);
    return vec4<f32>(-l, 0.0);
}

@fragment
fn fs(i: VsOut, @builtin(front_facing) front: bool) -> FsOut {
    // On the pixel's own ray, whatever the adapter's sub-pixel precision.
    let d = camera_surface_distance(camera, i.clip.xy, i.world);
    let l = shade(i.world, i.normal, front, objects[i.object]) * eye_transmittance(i.world, d);
    return FsOut(vec4<f32>(l, 1.0), vec4<f32>(d, 0.0, 0.0, 0.0));
}
