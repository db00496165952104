// What the particle resolves share (particle-march, no-scatter's particle floor): the pixel's
// ray and what lies behind it. Needs PRELUDE, FULLSCREEN, resolve_io.wgsl and
// particle_trace.wgsl.

// A pixel's camera ray: its direction, its length d (to the visible surface or the far
// plane) and whether it hit a surface.
struct PixelRay {
    dir: vec3<f32>,
    d: f32,
    hit: bool,
};

fn pixel_ray(px: vec2<i32>, frag: vec2<f32>) -> PixelRay {
    let dir = camera_ray_dir(camera, frag);
    let hit = textureLoad(ray_distance, px, 0).r;
    return PixelRay(dir, camera_ray_length(camera, dir, hit), hit >= 0.0);
}

// The radiance behind the medium's particles: the surface (its lights' cloud shadows removed,
// common::particles::surfaces) or the sky through the background medium.
fn surface_or_sky(px: vec2<i32>, ray: PixelRay) -> vec3<f32> {
    var behind = grid.sky.rgb * transmittance(medium, ray.d);
    if (ray.hit) {
        behind = textureLoad(surface, px, 0).rgb;
    }
    return behind;
}
