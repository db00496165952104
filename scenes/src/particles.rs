//! Particle media in integrator form: the spheres of a `particles` medium, explicit ones
//! followed by each generator's, in file order. Generators are seeded and reproducible: their
//! own SplitMix64 stream, f64 arithmetic rounded once to f32, so the same file gives
//! bit-identical particles on every platform. A `blocks` generator expands to every instance's
//! copy of its block (instance after instance) and records where they went ([`BlockInstancing`]),
//! so a method can use the declared structure while everyone renders the same spheres.

use glam::{DVec3, Vec3};

use crate::desc::{BlockDesc, GeneratorDesc, InstanceDesc, ParticleDesc, PlacementDesc};

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

/// Where a `blocks` generator's particles are: its block and its instances.
#[derive(Clone, Debug, PartialEq)]
pub struct BlockInstancing {
    /// The block's particles in block-local metres (about the block's origin).
    pub block: Vec<Particle>,
    /// Every instance, in expansion order.
    pub instances: Vec<BlockInstance>,
}

/// One instance of a block, and the range of the medium's particles it expanded to.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BlockInstance {
    /// Where the block's origin went, m.
    pub center: Vec3,
    /// Uniform scale of positions and radii.
    pub scale: f32,
    /// Multiplier of τ.
    pub density_scale: f32,
    /// Index of this instance's first particle in the medium's particle list; its particles are
    /// `first .. first + block.len()`, in the block's order.
    pub first: usize,
}

impl BlockInstance {
    /// Block-local particle `p` placed by this instance (f64, rounded once).
    pub fn place(&self, p: &Particle) -> Particle {
        let s = self.scale as f64;
        Particle {
            center: (self.center.as_dvec3() + p.center.as_dvec3() * s).as_vec3(),
            radius: (p.radius as f64 * s) as f32,
            density: (p.density as f64 * self.density_scale as f64) as f32,
            albedo: p.albedo,
        }
    }
}

/// How many particles a generator makes (without making them). Saturates (validation refuses
/// anything near the limit).
pub fn generated_count(g: &GeneratorDesc) -> u64 {
    match g {
        GeneratorDesc::Cloud { count, .. } | GeneratorDesc::SmokeColumn { count, .. } => {
            *count as u64
        }
        GeneratorDesc::Blocks {
            block,
            instances,
            placement,
        } => block_count(block).saturating_mul(instance_count(instances, placement)),
    }
}

/// Particles in one copy of a block.
pub fn block_count(b: &BlockDesc) -> u64 {
    b.generators
        .iter()
        .map(generated_count)
        .fold(b.particles.len() as u64, u64::saturating_add)
}

/// Instances a `blocks` generator declares (explicit + placed).
pub fn instance_count(instances: &[InstanceDesc], placement: &Option<PlacementDesc>) -> u64 {
    instances.len() as u64 + placement.as_ref().map_or(0, |p| p.count as u64)
}

/// Every particle: the explicit ones, then each generator's.
pub fn expand(explicit: &[ParticleDesc], generators: &[GeneratorDesc]) -> Vec<Particle> {
    expand_with_blocks(explicit, generators).0
}

/// [`expand`], plus one [`BlockInstancing`] per `blocks` generator, in file order.
pub fn expand_with_blocks(
    explicit: &[ParticleDesc],
    generators: &[GeneratorDesc],
) -> (Vec<Particle>, Vec<BlockInstancing>) {
    let total = generators
        .iter()
        .map(generated_count)
        .fold(explicit.len() as u64, u64::saturating_add);
    let mut out = Vec::with_capacity(total.min(1 << 24) as usize);
    out.extend(explicit.iter().map(|p| Particle {
        center: p.center,
        radius: p.radius,
        density: p.density,
        albedo: p.albedo,
    }));
    let mut blocks = Vec::new();
    for g in generators {
        if let Some(b) = generate(g, &mut out) {
            blocks.push(b);
        }
    }
    (out, blocks)
}

/// The instances of a `blocks` generator: the explicit ones, then the placed ones (centres
/// uniform in the ellipsoid, scales uniform in the range). `first` is left 0.
pub fn instances(
    explicit: &[InstanceDesc],
    placement: &Option<PlacementDesc>,
) -> Vec<BlockInstance> {
    let mut out: Vec<BlockInstance> = explicit
        .iter()
        .map(|i| BlockInstance {
            center: i.center,
            scale: i.scale,
            density_scale: i.density_scale,
            first: 0,
        })
        .collect();
    if let Some(p) = placement {
        let mut rng = SplitMix64(p.seed);
        for _ in 0..p.count {
            let c = p.center.as_dvec3() + rng.in_ball() * p.radii.as_dvec3();
            out.push(BlockInstance {
                center: c.as_vec3(),
                scale: lerp(p.scale[0], p.scale[1], rng.unit()) as f32,
                density_scale: 1.0,
                first: 0,
            });
        }
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

/// Appends `g`'s particles; a `blocks` generator also returns where its instances went.
fn generate(g: &GeneratorDesc, out: &mut Vec<Particle>) -> Option<BlockInstancing> {
    match g {
        GeneratorDesc::Blocks {
            block,
            instances: explicit,
            placement,
        } => {
            let block = expand(&block.particles, &block.generators);
            let mut inst = instances(explicit, placement);
            for i in inst.iter_mut() {
                i.first = out.len();
                out.extend(block.iter().map(|p| i.place(p)));
            }
            return Some(BlockInstancing {
                block,
                instances: inst,
            });
        }
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
    None
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

    fn blocks(
        block: BlockDesc,
        instances: Vec<InstanceDesc>,
        placement: Option<PlacementDesc>,
    ) -> GeneratorDesc {
        GeneratorDesc::Blocks {
            block,
            instances,
            placement,
        }
    }

    #[test]
    fn blocks_expand_to_every_instance_of_the_block_moved_scaled_and_recorded() {
        let block = BlockDesc {
            particles: vec![ParticleDesc {
                center: Vec3::new(0.5, 0.0, -0.25),
                radius: 0.2,
                density: 2.0,
                albedo: Vec3::new(0.9, 0.8, 0.7),
            }],
            generators: vec![cloud(5)],
        };
        let inst = vec![
            InstanceDesc {
                center: Vec3::new(10.0, 0.0, 0.0),
                scale: 1.0,
                density_scale: 1.0,
            },
            InstanceDesc {
                center: Vec3::new(-4.0, 2.0, 1.0),
                scale: 0.5,
                density_scale: 3.0,
            },
        ];
        let placement = |seed| PlacementDesc {
            count: 3,
            seed,
            center: Vec3::new(0.0, 5.0, 0.0),
            radii: Vec3::new(2.0, 1.0, 1.0),
            scale: [0.5, 2.0],
        };
        let explicit = [ParticleDesc {
            center: Vec3::ZERO,
            radius: 1.0,
            density: 1.0,
            albedo: Vec3::ONE,
        }];
        let g = blocks(block.clone(), inst, Some(placement(9)));
        assert_eq!(generated_count(&g), 501 * 5);
        let (ps, bl) = expand_with_blocks(&explicit, &[g]);
        assert_eq!(ps.len(), 1 + 501 * 5);
        assert_eq!(bl.len(), 1);
        let b = &bl[0];
        // The block is exactly the block's own expansion (explicit particle, then the cloud).
        let local = expand(&block.particles, &block.generators);
        assert_eq!(b.block, local);
        assert_eq!(b.instances.len(), 5);
        // Explicit instances come first, unchanged; each instance's range is contiguous and
        // follows the previous one, after the medium's explicit particle.
        assert_eq!(b.instances[1].center, Vec3::new(-4.0, 2.0, 1.0));
        assert_eq!(
            (b.instances[1].scale, b.instances[1].density_scale),
            (0.5, 3.0)
        );
        for (k, i) in b.instances.iter().enumerate() {
            assert_eq!(i.first, 1 + 501 * k);
            for (j, q) in local.iter().enumerate() {
                let p = ps[i.first + j];
                let want = i.center + q.center * i.scale;
                assert!(
                    (p.center - want).length() < 1e-5,
                    "{k} {j}: {} vs {want}",
                    p.center
                );
                assert!((p.radius - q.radius * i.scale).abs() < 1e-6);
                assert!((p.density - q.density * i.density_scale).abs() < 1e-5);
                assert_eq!(p.albedo, q.albedo);
            }
        }
        // Placed instances: centres in the ellipsoid, scales in range, τ unscaled.
        for i in &b.instances[2..] {
            let q = (i.center - Vec3::new(0.0, 5.0, 0.0)) / Vec3::new(2.0, 1.0, 1.0);
            assert!(q.length() <= 1.0 + 1e-5, "{q}");
            assert!((0.5..=2.0).contains(&i.scale) && i.density_scale == 1.0);
        }
        // Reproducible and seed-dependent like every generator: the placed instances alone.
        let placed = |seed| {
            let g = blocks(block.clone(), vec![], Some(placement(seed)));
            expand_with_blocks(&explicit, &[g]).1[0].instances[0].center
        };
        assert_eq!(placed(9), b.instances[2].center);
        assert_ne!(placed(10), b.instances[2].center);
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
