//! The particle-media stress cases (issue 32): one particle filling the view, a million
//! particles, particles sharing one centre, zero-density particles, the camera inside a dense
//! particle, a point light inside a particle, and radii from 1e-4 to 1e3 m in one cloud. Each
//! builder returns scene JSON (parsed and validated by `Case::scene` like every case); they
//! start from a small sunlit puff over a floor with a sky behind (cloud-8000's look).

use serde_json::{Value, json};

fn sun() -> Value {
    json!({"kind": "directional", "direction": [-0.4, -1.0, -0.5], "irradiance": [3.0, 2.9, 2.7]})
}

fn floor() -> Value {
    json!({"name": "floor", "shape": {"kind": "plane", "size": [30.0, 30.0]},
           "material": {"albedo": [0.5, 0.5, 0.45]}})
}

fn particle(at: [f64; 3], radius: f64, density: f64) -> Value {
    json!({"center": at, "radius": radius, "density": density, "albedo": [0.9, 0.9, 0.9]})
}

/// A seeded cloud generator: `count` spheres of radius in `radii` and extinction `density`
/// (1/m) in an ellipsoid of semi-axes `extent` around `at`.
fn cloud(count: usize, at: [f64; 3], extent: [f64; 3], radii: [f64; 2], density: f64) -> Value {
    json!({"shape": "cloud", "count": count, "seed": 32, "center": at, "radii": extent,
           "particle_radius": radii, "density": density, "albedo": [0.95, 0.95, 0.95]})
}

/// A particle scene: the camera at `eye` looking at `at`, the explicit `particles` and
/// `generators`, the sun unless `lights` is given, the floor, a sky.
fn scene(eye: [f64; 3], at: [f64; 3], particles: Vec<Value>, generators: Vec<Value>) -> Value {
    json!({
        "camera": {"position": eye, "look_at": at, "fov_y_deg": 45, "near": 0.1, "far": 60},
        "medium": {"kind": "particles", "particles": particles, "generators": generators,
                   "phase": {"kind": "henyey-greenstein", "g": 0.3},
                   "sky": [0.25, 0.4, 0.7]},
        "lights": [sun()],
        "objects": [floor()],
    })
}

/// One sphere of radius 3 m, 4.5 m from the eye: its silhouette (41.8° angular radius) covers
/// the whole 45° view, corners included.
pub fn fills_view() -> Result<Value, String> {
    let at = [0.0, 3.5, 0.0];
    Ok(scene(
        [0.0, 3.5, 4.5],
        at,
        vec![particle(at, 3.0, 0.5)],
        vec![],
    ))
}

/// `n` small spheres (1 000 000 in the manual run, the most the scene format
/// allows; fewer in CI) in a 8 × 4 × 6 m ellipsoid: about one sphere's volume per sphere.
pub fn million(n: usize) -> Result<Value, String> {
    // Radii scaled so that the cloud's mean optical depth stays near 1.5 whatever the count.
    let r = 0.02 * (1e6 / n.max(1) as f64).cbrt();
    let c = cloud(n, [0.0, 2.2, 0.0], [4.0, 2.0, 3.0], [0.5 * r, 1.5 * r], 0.8);
    Ok(scene([0.0, 2.4, 11.0], [0.0, 2.0, 0.0], vec![], vec![c]))
}

/// 64 spheres of one radius at one centre: overlaps add (τ 64 × 0.03 /m), and every depth sort
/// ties.
pub fn same_centre() -> Result<Value, String> {
    let at = [0.0, 2.0, 0.0];
    let parts = vec![particle(at, 1.2, 0.03); 64];
    Ok(scene([0.0, 2.4, 8.0], at, parts, vec![]))
}

/// A cloud of zero-density spheres: no in-scatter, no shadow, nothing dimmed (0/0 where a
/// method divides by τ).
pub fn zero_density() -> Result<Value, String> {
    let c = cloud(2000, [0.0, 2.2, 0.0], [3.0, 1.4, 2.0], [0.08, 0.3], 0.0);
    Ok(scene([0.0, 2.4, 10.0], [0.0, 2.0, 0.0], vec![], vec![c]))
}

/// The eye at the centre of a sphere of radius 1 m and τ 3 /m (e^(−3) to its edge), in front of
/// a sunlit cloud.
pub fn camera_in_dense() -> Result<Value, String> {
    let eye = [0.0, 2.4, 8.0];
    let c = cloud(2000, [0.0, 2.2, 0.0], [3.0, 1.4, 2.0], [0.08, 0.3], 0.4);
    Ok(scene(
        eye,
        [0.0, 2.0, 0.0],
        vec![particle(eye, 1.0, 3.0)],
        vec![c],
    ))
}

/// A point light at the centre of a sphere (radius 0.5 m, τ 2 /m) inside a tall cloud of 400,
/// no sun; the light just above the view (the exact in-scatter of a ray through a point light
/// diverges, view-through-light's business), the cloud and the floor below it lit through its
/// particle: the light's rays all start inside τ.
pub fn light_in_particle() -> Result<Value, String> {
    let light = [0.0, 4.6, -1.0];
    let c = cloud(400, [0.0, 3.0, -1.0], [2.5, 1.8, 1.8], [0.1, 0.3], 0.5);
    let parts = vec![particle(light, 0.5, 2.0)];
    let mut v = scene([0.0, 1.0, 8.0], [0.0, 0.5, 0.0], parts, vec![c]);
    v["lights"] = json!([{"kind": "point", "position": light, "intensity": [40.0, 38.0, 34.0]}]);
    Ok(v)
}

/// Radii 1e-4, 1e-3, …, 1e3 m in one cloud (densities such that each is visible or, below a
/// pixel, harmless), plus a generated puff of radii 1e-4 to 0.3 m: the 1e3 m sphere holds the
/// whole scene, the eye included (a thin haze).
pub fn radii_span() -> Result<Value, String> {
    let parts = vec![
        particle([0.0, 0.0, 0.0], 1e3, 2e-3),
        particle([0.0, 8.0, -60.0], 1e2, 1e-3),
        particle([-4.0, 3.0, -12.0], 10.0, 0.02),
        particle([-2.0, 2.5, 0.0], 1.0, 0.4),
        particle([1.5, 2.0, 3.0], 0.1, 3.0),
        particle([0.5, 1.5, 5.0], 1e-2, 20.0),
        particle([0.2, 1.8, 6.0], 1e-3, 100.0),
        particle([-0.2, 1.9, 6.5], 1e-4, 100.0),
    ];
    let c = cloud(1000, [1.0, 2.2, 0.0], [2.0, 1.0, 1.5], [1e-4, 0.3], 0.5);
    Ok(scene([0.0, 2.4, 10.0], [0.0, 2.0, 0.0], parts, vec![c]))
}
