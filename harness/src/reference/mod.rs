//! The ground truth (ARCHITECTURE §3): a CPU, f64, parallel renderer of the three AOVs that shares
//! none of the approximations it judges — no Γ tables, no F(u,v), no polynomials, no shadow
//! maps. Visibility is exact ray casting against the same triangles the GPU rasterises (our
//! own BVH, see [`bvh`]); the in-scatter integral is computed as described in [`integrate`].
//! Each pixel is sampled at its centre, like the rasteriser. The reference reports its own
//! convergence: the same pixels at 4× tighter tolerances differ by a relative RMSE it prints.
//! Particle media ([`particles`]): exact chord optical depth through the spheres (a BVH over
//! them), the camera ray cut into constant-density pieces, single scattering with
//! self-shadowing, the sky behind.
//!
//! Exponential height fog ([`height_fog`]): every e^(−σ_t d) becomes e^(−σ_t L) with L a
//! segment's closed-form fog length, σ_s(x) scales the in-scatter integrand, and a directional
//! light's lit interval keeps its closed form in L.
//!
//! Biri 2006's indirect single scattering ([`indirect`]), where a scene enables it, is added to
//! the `surface` AOV (and `total`); point lights in a homogeneous medium only (a clear error
//! otherwise, never a wrong image).

pub mod bvh;
pub mod cache;
pub mod height_fog;
pub mod indirect;
pub mod integrate;
pub mod pack;
mod particle_ray;
pub mod particles;
pub mod quadrature;
pub mod shadow;
pub mod world;

use std::time::Instant;

use glam::DVec3;
use rayon::prelude::*;
use scenes::Scene;
use serde::{Deserialize, Serialize};

use crate::image::Image;
pub use integrate::Settings;
use integrate::{RayRadiance, Tracer};
use particles::ParticleField;
use world::World;

/// The reference's three AOVs and the per-pixel ray length (surface hit or far plane).
#[derive(Clone, Debug)]
pub struct ReferenceImages {
    pub inscatter: Image,
    pub surface: Image,
    pub total: Image,
    /// Distance along each pixel's ray to the visible surface (or the far plane), m; row-major, top row first.
    pub distance: Vec<f32>,
    pub stats: ReferenceStats,
}

#[derive(Clone, Debug, Default, Serialize, Deserialize, PartialEq)]
pub struct ReferenceStats {
    pub seconds: f64,
    pub settings: Option<Settings>,
    pub threads: usize,
    /// Where a cache entry was stored rounded (a bundle's, ARCHITECTURE §9.1): the mantissa
    /// bits its values kept; absent when lossless.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mantissa_bits: Option<u32>,
}

/// How far the reference is from its own 4×-tighter self.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct Convergence {
    /// Pixels compared (a regular grid subset of the image).
    pub pixels: usize,
    /// RMSE / mean of the tighter image, per AOV.
    pub rel_rmse_inscatter: f64,
    pub rel_rmse_total: f64,
    pub seconds: f64,
}

fn tracer_for<'a>(
    scene: &Scene,
    world: &'a World,
    particles: Option<&'a ParticleField>,
    lights: &'a [scenes::LightState],
    far: f64,
    settings: Settings,
) -> Tracer<'a> {
    let scale = world.scale();
    Tracer {
        world,
        medium: scene.medium().background(),
        lights,
        settings,
        eps: 1e-7 * scale,
        sun_distance: 10.0 * scale.max(far),
        particles,
        indirect: scene.desc.indirect_single_scattering,
    }
}

/// Rejects what the reference cannot compute yet, rather than rendering it wrong.
pub fn check_supported(scene: &Scene) -> Result<(), String> {
    indirect::check(scene)
}

/// Traces the given pixels of frame `frame` at `width`×`height`, in parallel.
pub fn trace_pixels(
    scene: &Scene,
    frame: u32,
    width: u32,
    height: u32,
    settings: Settings,
    pixels: &[(u32, u32)],
    progress: &(dyn Fn(u64) + Sync),
) -> Result<Vec<RayRadiance>, String> {
    check_supported(scene)?;
    let state = scene.frame(frame);
    let world = World::new(scene, &state);
    let field = scene.medium().particles().map(ParticleField::new);
    let rays = state.camera.rays(width, height);
    let tracer = tracer_for(
        scene,
        &world,
        field.as_ref(),
        &state.lights,
        rays.far,
        settings,
    );
    Ok(pixels
        .par_chunks(64)
        .flat_map_iter(|chunk| {
            let out: Vec<RayRadiance> = chunk
                .iter()
                .map(|&(i, j)| {
                    let d = rays.direction(i, j);
                    tracer.trace(rays.origin, d, rays.near_distance(d), rays.far_distance(d))
                })
                .collect();
            progress(chunk.len() as u64);
            out
        })
        .collect())
}

/// Renders the full image of one frame.
pub fn render(
    scene: &Scene,
    frame: u32,
    width: u32,
    height: u32,
    settings: Settings,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<ReferenceImages, String> {
    let start = Instant::now();
    let pixels: Vec<(u32, u32)> = (0..height)
        .flat_map(|j| (0..width).map(move |i| (i, j)))
        .collect();
    let rad = trace_pixels(scene, frame, width, height, settings, &pixels, progress)?;
    let to_image = |f: &dyn Fn(&RayRadiance) -> DVec3| {
        let mut img = Image::new(width, height);
        for (k, r) in rad.iter().enumerate() {
            img.pixels[k] = f(r).as_vec3().to_array();
        }
        img
    };
    Ok(ReferenceImages {
        inscatter: to_image(&|r| r.inscatter),
        surface: to_image(&|r| r.surface),
        total: to_image(&|r| r.total),
        distance: rad.iter().map(|r| r.distance as f32).collect(),
        stats: ReferenceStats {
            seconds: start.elapsed().as_secs_f64(),
            settings: Some(settings),
            threads: rayon::current_num_threads(),
            mantissa_bits: None,
        },
    })
}

/// Re-traces every `stride`-th pixel (in both directions) at `settings.tighter()` and compares
/// with `images`, which were rendered at `settings`.
pub fn convergence(
    scene: &Scene,
    frame: u32,
    images: &ReferenceImages,
    settings: Settings,
    stride: u32,
) -> Result<Convergence, String> {
    let start = Instant::now();
    let (w, h) = (images.total.width, images.total.height);
    let stride = stride.max(1);
    let pixels: Vec<(u32, u32)> = (0..h)
        .step_by(stride as usize)
        .flat_map(|j| (0..w).step_by(stride as usize).map(move |i| (i, j)))
        .collect();
    let tight = trace_pixels(scene, frame, w, h, settings.tighter(), &pixels, &|_| {})?;
    let rel = |img: &Image, pick: &dyn Fn(&RayRadiance) -> DVec3| {
        let (mut se, mut mean) = (0.0, 0.0);
        for (&(i, j), t) in pixels.iter().zip(&tight) {
            let a = DVec3::from_array(img.get(i, j).map(f64::from));
            let b = pick(t);
            se += (a - b).length_squared();
            mean += b.x + b.y + b.z;
        }
        let n = (3 * pixels.len()) as f64;
        let mean = mean / n;
        (se / n).sqrt() / mean.max(1e-300)
    };
    Ok(Convergence {
        pixels: pixels.len(),
        rel_rmse_inscatter: rel(&images.inscatter, &|r| r.inscatter),
        rel_rmse_total: rel(&images.total, &|r| r.total),
        seconds: start.elapsed().as_secs_f64(),
    })
}
