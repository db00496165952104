//! The bins are conservative: every ray a pass casts through a column (anywhere in its pixels for
//! the camera grid, its centre ray for a light grid) that crosses a particle finds that particle
//! in the column's list — checked by brute force over random clouds.

use super::*;

/// Deterministic uniform numbers in [0, 1).
struct Lcg(u64);

impl Lcg {
    fn next(&mut self) -> f32 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (self.0 >> 40) as f32 / (1u64 << 24) as f32
    }
}

fn cloud(rng: &mut Lcg, n: usize, centre: Vec3, spread: f32) -> Vec<GpuParticle> {
    (0..n)
        .map(|_| {
            let o = Vec3::new(rng.next(), rng.next(), rng.next()) * 2.0 - 1.0;
            GpuParticle {
                center: (centre + o * spread).to_array(),
                radius: 0.05 + 0.3 * rng.next(),
                sigma_s: [1.0; 3],
                tau: 1.0,
            }
        })
        .collect()
}

fn hits(p: &GpuParticle, o: Vec3, d: Vec3, tmax: f32) -> bool {
    let q = Vec3::from_array(p.center) - o;
    let tc = q.dot(d);
    let h2 = p.radius * p.radius - (q - d * tc).length_squared();
    h2 > 0.0 && tc + h2.sqrt() > 0.0 && tc - h2.sqrt() < tmax
}

fn listed(b: &Bins, col: usize, i: usize) -> bool {
    b.indices[b.offsets[col] as usize..b.offsets[col + 1] as usize].contains(&(i as u32))
}

#[test]
fn camera_bins_list_every_particle_a_column_ray_crosses() {
    let cam = CameraPose {
        position: Vec3::new(0.0, 1.0, 4.0),
        look_at: Vec3::new(0.0, 1.0, 0.0),
        up: Vec3::Y,
        fov_y_deg: 50.0,
        near: 0.1,
        far: 30.0,
    };
    let mut rng = Lcg(7);
    // A cloud around and in front of the eye (some spheres contain it or cross its plane).
    let parts = cloud(&mut rng, 400, Vec3::new(0.0, 1.0, 1.0), 3.5);
    let (w, h, ps) = (60u32, 44u32, 8u32);
    let grid = (w.div_ceil(ps), h.div_ceil(ps));
    let bins = camera_bins(&parts, &cam, (w, h), ps as f32, grid);
    check_camera_bins(&parts, &cam, (w, h), ps as f32, grid, &bins);
    // A fixed number of columns: fractional pixels per column.
    let grid = (7, 6);
    let ps = w as f32 / 7.0;
    let bins = camera_bins(&parts, &cam, (w, h), ps, grid);
    check_camera_bins(&parts, &cam, (w, h), ps, grid, &bins);
}

fn check_camera_bins(
    parts: &[GpuParticle],
    cam: &CameraPose,
    (w, h): (u32, u32),
    ps: f32,
    grid: (u32, u32),
    bins: &Bins,
) {
    let world_from_clip = cam.clip_from_world(w as f32 / h as f32).inverse();
    let mut checked = 0;
    for cy in 0..grid.1 {
        for cx in 0..grid.0 {
            for s in 0..25 {
                // Pixel position within the column, edges included, clamped to the image.
                let fx = ((cx as f32 + (s % 5) as f32 / 4.0) * ps).min(w as f32);
                let fy = ((cy as f32 + (s / 5) as f32 / 4.0) * ps).min(h as f32);
                let ndc = Vec3::new(2.0 * fx / w as f32 - 1.0, 1.0 - 2.0 * fy / h as f32, 1.0);
                let d = (world_from_clip.project_point3(ndc) - cam.position).normalize();
                for (i, p) in parts.iter().enumerate() {
                    if hits(p, cam.position, d, 100.0) {
                        checked += 1;
                        let col = (cy * grid.0 + cx) as usize;
                        assert!(
                            listed(bins, col, i),
                            "column ({cx}, {cy}) misses particle {i}"
                        );
                    }
                }
            }
        }
    }
    assert!(
        checked > 1000,
        "too few crossings to mean anything: {checked}"
    );
}

/// Every column centre ray of `light`'s grid around a 300-particle cloud at `centre` finds each
/// particle it crosses in its list; the grid has kind `kind`.
fn light_grid_case(light: LightState, centre: Vec3, kind: u32) {
    let mut rng = Lcg(11);
    let parts = cloud(&mut rng, 300, centre, 2.0);
    let n = 24;
    let (g, bins) = light_grid(&light, &parts, n);
    assert_eq!(g.kind, kind);
    let mut checked = 0;
    for f in 0..g.faces() {
        let (right, up, axis) = if g.kind == 3 {
            let axis = CUBE_FACE_AXES[f as usize];
            let (right, up) = basis(axis);
            (right, up, axis)
        } else {
            (
                Vec3::from_slice(&g.right),
                Vec3::from_slice(&g.up),
                Vec3::from_slice(&g.axis),
            )
        };
        checked += face_case(&g, (right, up, axis), &parts, &bins, f * n * n);
    }
    assert!(checked > 300, "too few crossings: {checked}");
}

/// Crossings checked over one face of grid `g` (its columns from `first`).
fn face_case(
    g: &LightGrid,
    (right, up, axis): (Vec3, Vec3, Vec3),
    parts: &[GpuParticle],
    bins: &Bins,
    first: u32,
) -> usize {
    let (n, o) = (g.n, Vec3::from_slice(&g.origin));
    let mut checked = 0;
    for j in 0..n {
        for i in 0..n {
            // The column's centre ray, as particles.wgsl casts it.
            let u = (i as f32 + 0.5) / n as f32 * 2.0 - 1.0;
            let v = (j as f32 + 0.5) / n as f32 * 2.0 - 1.0;
            // (The sun's depths may be negative: its rays start far behind their plane.)
            let (ro, rd) = if g.kind == 1 {
                (o + (right * u + up * v) * g.right[3] - axis * 1e3, axis)
            } else {
                (o, (axis + (right * u + up * v) * g.right[3]).normalize())
            };
            for (k, p) in parts.iter().enumerate() {
                if hits(p, ro, rd, 2e3) {
                    checked += 1;
                    let col = (first + j * n + i) as usize;
                    assert!(
                        listed(bins, col, k),
                        "column ({i}, {j}) misses particle {k}"
                    );
                }
            }
        }
    }
    checked
}

#[test]
fn sun_grid_bins_list_every_particle_a_column_ray_crosses() {
    let sun = LightState::Directional {
        direction: Vec3::new(-0.4, -1.0, -0.5).normalize(),
        irradiance: Vec3::ONE,
    };
    light_grid_case(sun, Vec3::new(0.0, 2.0, 0.0), 1);
}

#[test]
fn local_light_grid_bins_list_every_particle_a_column_ray_crosses() {
    let point = LightState::Point {
        position: Vec3::new(6.0, 3.0, 1.0),
        intensity: Vec3::ONE,
    };
    light_grid_case(point, Vec3::new(0.0, 2.0, 0.0), 2);
}

/// A point light at the centre of the cloud (inside particles, the cloud all around it) gets a
/// cube grid, and its bins are conservative on all six faces.
#[test]
fn a_local_light_inside_the_cloud_gets_a_cube() {
    let point = LightState::Point {
        position: Vec3::new(0.1, 2.05, -0.07),
        intensity: Vec3::ONE,
    };
    light_grid_case(point, Vec3::new(0.0, 2.0, 0.0), 3);
}
