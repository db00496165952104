//! Particle media in integrator form: the spheres of a `particles` medium, explicit ones
//! followed by each generator's, in file order. Generators are seeded and reproducible: their
//! own SplitMix64 stream, f64 arithmetic rounded once to f32, so the same file gives
//! bit-identical particles on every platform.

use glam::{DVec3, Vec3};

use crate::desc::{GeneratorDesc, ParticleDesc};

/// One sphere of constant extinction.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Particle {
    /// m.
    pub center: Vec3,
    /// m.
    pub radius: f32,
    /// Extinction τ inside the sphere, 1/m (grey).
    pub density: f32,
    /// Single-scattering albedo: σ_s = albedo · τ, RGB.
    pub albedo: Vec3,
}

/// How many particles a generator makes (without making them).
pub fn generated_count(g: &GeneratorDesc) -> u64 {
    match g {
        GeneratorDesc::Cloud { count, .. } | GeneratorDesc::SmokeColumn { count, .. } => {
            *count as u64
        }
    }
}

/// Every particle: the explicit ones, then each generator's.
pub fn expand(explicit: &[ParticleDesc], generators: &[GeneratorDesc]) -> Vec<Particle> {
    let total = explicit.len() as u64 + generators.iter().map(generated_count).sum::<u64>();
    let mut out = Vec::with_capacity(total.min(1 << 24) as usize);
    out.extend(explicit.iter().map(|p| Particle {
        center: p.center,
        radius: p.radius,
        density: p.density,
        albedo: p.albedo,
    }));
    for g in generators {
        generate(g, &mut out);
    }
    out
}

/// SplitMix64 (Steele et al. 2014): tiny, fast, and fully specified, so seeds are portable.
struct SplitMix64(u64);

impl SplitMix64 {
    fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    /// Uniform in [0, 1).
    fn unit(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }
    /// Uniform in the unit ball (rejection from the cube; accepts ~52%).
    fn in_ball(&mut self) -> DVec3 {
        loop {
            let v = DVec3::new(self.unit(), self.unit(), self.unit()) * 2.0 - DVec3::ONE;
            if v.length_squared() <= 1.0 {
                return v;
            }
        }
    }
    /// Uniform in the unit disc (x, z).
    fn in_disc(&mut self) -> (f64, f64) {
        loop {
            let (x, z) = (self.unit() * 2.0 - 1.0, self.unit() * 2.0 - 1.0);
            if x * x + z * z <= 1.0 {
                return (x, z);
            }
        }
    }
}

fn lerp(a: f32, b: f32, t: f64) -> f64 {
    a as f64 + (b as f64 - a as f64) * t
}

fn generate(g: &GeneratorDesc, out: &mut Vec<Particle>) {
    match g {
        GeneratorDesc::Cloud {
            count,
            seed,
            center,
            radii,
            particle_radius,
            density,
            albedo,
        } => {
            let mut rng = SplitMix64(*seed);
            for _ in 0..*count {
                let p = center.as_dvec3() + rng.in_ball() * radii.as_dvec3();
                let r = lerp(particle_radius[0], particle_radius[1], rng.unit());
                out.push(Particle {
                    center: p.as_vec3(),
                    radius: r as f32,
                    density: *density,
                    albedo: *albedo,
                });
            }
        }
        GeneratorDesc::SmokeColumn {
            count,
            seed,
            base,
            height,
            radius_bottom,
            radius_top,
            particle_radius,
            density,
            albedo,
        } => {
            let mut rng = SplitMix64(*seed);
            let h = *height as f64;
            for _ in 0..*count {
                let u = rng.unit();
                let spread = lerp(*radius_bottom, *radius_top, u);
                let (dx, dz) = rng.in_disc();
                // A gentle sway of the column's axis: two sines of the height, amplitude growing
                // with it, so the plume bends like smoke in a light draught.
                let sway = spread * 0.5;
                let ax = sway * (u * 5.0).sin();
                let az = sway * (u * 3.0 + 1.0).sin() * 0.5;
                let p = base.as_dvec3() + DVec3::new(ax + dx * spread, u * h, az + dz * spread);
                out.push(Particle {
                    center: p.as_vec3(),
                    radius: lerp(particle_radius[0], particle_radius[1], u) as f32,
                    density: *density,
                    albedo: *albedo,
                });
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cloud(seed: u64) -> GeneratorDesc {
        GeneratorDesc::Cloud {
            count: 500,
            seed,
            center: Vec3::new(1.0, 2.0, 3.0),
            radii: Vec3::new(2.0, 1.0, 0.5),
            particle_radius: [0.1, 0.2],
            density: 3.0,
            albedo: Vec3::ONE,
        }
    }

    #[test]
    fn generators_are_reproducible_and_seed_dependent() {
        let a = expand(&[], &[cloud(7)]);
        assert_eq!(a, expand(&[], &[cloud(7)]));
        assert_ne!(a, expand(&[], &[cloud(8)]));
        assert_eq!(a.len(), 500);
    }

    #[test]
    fn cloud_particles_lie_in_the_ellipsoid_with_radii_in_range() {
        let ps = expand(&[], &[cloud(1)]);
        let mut mean = DVec3::ZERO;
        for p in &ps {
            let q = (p.center - Vec3::new(1.0, 2.0, 3.0)) / Vec3::new(2.0, 1.0, 0.5);
            assert!(q.length() <= 1.0 + 1e-5, "{q}");
            assert!((0.1..=0.2).contains(&p.radius), "{}", p.radius);
            mean += p.center.as_dvec3();
        }
        // Uniform in the ellipsoid: the mean is near the centre (σ of each coordinate of the
        // mean ≤ 2/√5/√500 ≈ 0.04).
        let mean = mean / ps.len() as f64;
        assert!((mean - DVec3::new(1.0, 2.0, 3.0)).length() < 0.2, "{mean}");
    }

    #[test]
    fn smoke_rises_from_its_base_and_widens() {
        let g = GeneratorDesc::SmokeColumn {
            count: 2000,
            seed: 3,
            base: Vec3::ZERO,
            height: 4.0,
            radius_bottom: 0.1,
            radius_top: 1.0,
            particle_radius: [0.05, 0.3],
            density: 1.0,
            albedo: Vec3::ONE,
        };
        let ps = expand(&[], &[g]);
        assert!(ps.iter().all(|p| (0.0..=4.0).contains(&p.center.y)));
        let spread = |lo: f32, hi: f32| {
            let sel: Vec<&Particle> = ps
                .iter()
                .filter(|p| p.center.y >= lo && p.center.y < hi)
                .collect();
            let mx = sel.iter().map(|p| p.center.x).sum::<f32>() / sel.len() as f32;
            sel.iter().map(|p| (p.center.x - mx).abs()).sum::<f32>() / sel.len() as f32
        };
        assert!(spread(3.0, 4.0) > 3.0 * spread(0.0, 1.0));
    }
}
