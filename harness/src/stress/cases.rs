//! The stress cases: extreme but valid scenes, each built in code as scene JSON and parsed by
//! `scenes::parse_scene` — so every case also passes the loader's validation, exactly like a
//! user's file would. Names are stable (results.json records use them as the scene name, and
//! methods key their declared error bounds on them).

use std::path::Path;

use scenes::{Scene, parse_scene};
use serde_json::{Value, json};

use super::meshes;
use super::particle_cases as particles;

/// What a case builder may depend on.
pub struct BuildContext<'a> {
    /// The image size the case is rendered at (the view-through-light case aims the light at a
    /// pixel centre of this image).
    pub width: u32,
    pub height: u32,
    /// Where the case's OBJ files are written.
    pub mesh_dir: &'a Path,
    /// Triangle count of `many-triangles` (1M in the manual run; smaller in CI).
    pub triangles: usize,
    /// Particle count of `particle-million` (1M in the manual run; smaller in CI).
    pub particles: usize,
}

/// One stress case.
pub struct Case {
    pub name: &'static str,
    /// What it stresses and which formula it targets.
    pub about: &'static str,
    build: fn(&BuildContext) -> Result<Value, String>,
}

impl Case {
    /// The case's scene (its name is the case name).
    pub fn scene(&self, ctx: &BuildContext) -> Result<Scene, String> {
        let v = (self.build)(ctx)?;
        parse_scene(
            &v.to_string(),
            &format!("stress case {}", self.name),
            self.name,
            ctx.mesh_dir,
        )
        .map_err(|e| e.to_string())
    }
}

/// Every case, in a stable order.
pub const CASES: &[Case] = &[
    Case {
        name: "light-near-surface",
        about: "point light 1e-4 m above the floor, inside the view: the 1/r² peak on the surface and in the medium",
        build: light_near_surface,
    },
    Case {
        name: "camera-at-light",
        about: "the eye sits exactly on the point light: r = 0 at the start of every view ray",
        build: camera_at_light,
    },
    Case {
        name: "camera-in-shadow",
        about: "the eye is inside the shadow volume of a slab: every ray starts in shadow",
        build: camera_in_shadow,
    },
    Case {
        name: "view-through-light",
        about: "one pixel's ray passes through the light (h → 0, γ → 0: Biri's 1/h, Sun's 1/sin γ)",
        build: view_through_light,
    },
    Case {
        name: "light-behind-camera",
        about: "the light on the view axis just behind the eye (γ → π)",
        build: light_behind_camera,
    },
    Case {
        name: "grazing-shadow-planes",
        about: "a blade edge-on to the light at eye height: view rays graze its degenerate shadow planes",
        build: grazing_shadow_planes,
    },
    Case {
        name: "near-plane-cuts-shadow-plane",
        about: "the eye 1 cm from a post's shadow plane, near plane 10 cm: the plane crosses half the view rays between the eye and the near plane (z-pass counting)",
        build: near_plane_cuts_shadow_plane,
    },
    Case {
        name: "sigma-t-1e-6",
        about: "σ_t = 1e-6 /m: nearly clear air (1 − e^(−σ_t d) cancellation)",
        build: thin_medium,
    },
    Case {
        name: "sigma-t-10",
        about: "σ_t = 10 /m: transmittance underflows a few metres from the eye",
        build: dense_medium,
    },
    Case {
        name: "deep-scene-1e4m",
        about: "everything 1e4 m from the origin, far plane 2e4 m, 5 cm detail: f32 cancellation",
        build: deep_scene,
    },
    Case {
        name: "intensity-1e18",
        about: "I = 1e18 W/sr: radiance near the f32 range's top after 1/r²",
        build: huge_intensity,
    },
    Case {
        name: "intensity-1e-18",
        about: "I = 1e-18 W/sr: radiance near f32 denormals",
        build: tiny_intensity,
    },
    Case {
        name: "open-mesh",
        about: "an OBJ box with two faces missing (open, light inside it can leak)",
        build: open_mesh,
    },
    Case {
        name: "non-manifold-mesh",
        about: "an OBJ with three faces on one edge and a doubled face of opposite winding",
        build: non_manifold_mesh,
    },
    Case {
        name: "degenerate-mesh",
        about: "an OBJ with zero-area (collinear) triangles and needle slivers",
        build: degenerate_mesh,
    },
    Case {
        name: "many-triangles",
        about: "a finely tessellated sphere (1M triangles in the full run) over a floor",
        build: many_triangles,
    },
    Case {
        name: "particle-fills-view",
        about: "one sphere particle covers every pixel: every ray's chord, the whole screen one impostor",
        build: |_| particles::fills_view(),
    },
    Case {
        name: "particle-million",
        about: "a million small particles (the format's most; fewer in CI): memory, bins and sorting at scale",
        build: |ctx| particles::million(ctx.particles),
    },
    Case {
        name: "particles-same-centre",
        about: "64 equal spheres at one centre: overlapping τ adds, every depth sort ties",
        build: |_| particles::same_centre(),
    },
    Case {
        name: "particles-zero-density",
        about: "a cloud of τ = 0 spheres: nothing scatters or dims (0/0 where a method divides by τ)",
        build: |_| particles::zero_density(),
    },
    Case {
        name: "camera-in-dense-particle",
        about: "the eye inside a sphere of τ 3 /m: every ray starts inside a particle",
        build: |_| particles::camera_in_dense(),
    },
    Case {
        name: "light-in-particle",
        about: "a point light inside a sphere of a cloud: the 1/r² peak inside τ, every light ray starts in it",
        build: |_| particles::light_in_particle(),
    },
    Case {
        name: "particle-radii-1e-4-to-1e3",
        about: "radii 1e-4 to 1e3 m in one cloud: sub-pixel spheres beside one that holds the whole scene and the eye",
        build: |_| particles::radii_span(),
    },
];

/// A case by name.
pub fn find(name: &str) -> Option<&'static Case> {
    CASES.iter().find(|c| c.name == name)
}

pub fn names() -> Vec<&'static str> {
    CASES.iter().map(|c| c.name).collect()
}

fn medium(sigma_a: f64, sigma_s: f64) -> Value {
    json!({"kind": "homogeneous", "sigma_a": [sigma_a, sigma_a, sigma_a], "sigma_s": [sigma_s, sigma_s, sigma_s]})
}

fn floor(size: f64) -> Value {
    json!({"name": "floor", "shape": {"kind": "plane", "size": [size, size]},
           "material": {"albedo": [0.7, 0.7, 0.7]}})
}

fn sphere(at: [f64; 3], radius: f64) -> Value {
    json!({"name": "sphere", "shape": {"kind": "sphere", "radius": radius},
           "transform": {"translation": at}, "material": {"albedo": [0.8, 0.3, 0.2]}})
}

fn point(at: [f64; 3], intensity: f64) -> Value {
    json!({"kind": "point", "position": at, "intensity": [intensity, intensity, intensity]})
}

/// The sphere-over-floor scene most cases start from (sphere-point, with the light `intensity`).
fn base(intensity: f64) -> Value {
    json!({
        "camera": {"position": [0.0, 2.6, 8.0], "look_at": [0.0, 1.2, 0.0], "fov_y_deg": 45, "near": 0.1, "far": 40},
        "medium": medium(0.01, 0.08),
        "lights": [point([0.6, 4.6, -0.4], intensity)],
        "objects": [floor(14.0), sphere([0.0, 2.0, 0.0], 0.9)],
    })
}

fn light_near_surface(_: &BuildContext) -> Result<Value, String> {
    let mut v = base(20.0);
    v["lights"] = json!([point([0.0, 1e-4, 1.0], 20.0)]);
    v["camera"] =
        json!({"position": [0.0, 1.5, 5.0], "look_at": [0.0, 0.3, 0.5], "near": 0.1, "far": 40});
    Ok(v)
}

fn camera_at_light(_: &BuildContext) -> Result<Value, String> {
    let mut v = base(60.0);
    v["lights"] = json!([point([0.0, 2.6, 8.0], 60.0)]);
    Ok(v)
}

fn camera_in_shadow(_: &BuildContext) -> Result<Value, String> {
    let mut v = base(60.0);
    v["lights"] = json!([point([0.0, 5.0, 0.0], 60.0)]);
    v["objects"] = json!([
        floor(14.0),
        {"name": "slab", "shape": {"kind": "box", "size": [3.0, 0.2, 3.0]},
         "transform": {"translation": [0.0, 3.5, 0.0]}},
        sphere([2.5, 0.6, -2.0], 0.6),
    ]);
    v["camera"] =
        json!({"position": [0.0, 1.5, 0.2], "look_at": [2.0, 1.0, -3.0], "near": 0.05, "far": 40});
    Ok(v)
}

fn view_through_light(ctx: &BuildContext) -> Result<Value, String> {
    let mut v = base(60.0);
    // Aim the light at the centre of the pixel nearest the image centre: build the scene once to
    // get the exact f64 ray of that pixel, then put the light 4 m along it.
    let probe =
        parse_scene(&v.to_string(), "probe", "probe", ctx.mesh_dir).map_err(|e| e.to_string())?;
    let rays = probe.frame(0).camera.rays(ctx.width, ctx.height);
    let dir = rays.direction(ctx.width / 2, ctx.height / 2);
    let at = rays.origin + dir * 4.0;
    v["lights"] = json!([point([at.x, at.y, at.z], 60.0)]);
    Ok(v)
}

fn light_behind_camera(_: &BuildContext) -> Result<Value, String> {
    let mut v = base(60.0);
    // 1 cm behind the eye, on the line through the eye and the look-at point.
    let (eye, at) = ([0.0, 2.6, 8.0], [0.0, 1.2, 0.0]);
    let d: Vec<f64> = (0..3).map(|i| eye[i] - at[i]).collect();
    let n = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
    let l: Vec<f64> = (0..3).map(|i| eye[i] + 0.01 * d[i] / n).collect();
    v["lights"] = json!([point([l[0], l[1], l[2]], 60.0)]);
    Ok(v)
}

fn near_plane_cuts_shadow_plane(_: &BuildContext) -> Result<Value, String> {
    let mut v = base(60.0);
    v["lights"] = json!([point([0.0, 2.0, 0.0], 60.0)]);
    // A post whose front vertical edge at (0.1, y, -1.9) is on the light's silhouette: its
    // shadow plane holds the light and that edge. The eye sits 5 m along the plane from the
    // light, 1 cm outside it (on the lit side), looking back past the post: the plane is seen
    // edge-on through the middle of the view.
    let (ex, ez) = (0.1f64, -1.9f64);
    let len = (ex * ex + ez * ez).sqrt();
    let (dx, dz) = (ex / len, ez / len);
    let (nx, nz) = (-dz, dx);
    let eye = [5.0 * dx + 0.01 * nx, 1.0, 5.0 * dz + 0.01 * nz];
    let at = [-0.6, 0.8, -1.0];
    v["objects"] = json!([
        floor(14.0),
        {"name": "post", "shape": {"kind": "box", "size": [0.2, 2.4, 0.2]},
         "transform": {"translation": [0.0, 1.2, -2.0]}},
    ]);
    v["camera"] = json!({"position": eye, "look_at": at, "fov_y_deg": 60, "near": 0.1, "far": 40});
    Ok(v)
}

fn grazing_shadow_planes(_: &BuildContext) -> Result<Value, String> {
    let mut v = base(60.0);
    v["lights"] = json!([point([0.0, 2.0, 0.0], 60.0)]);
    v["objects"] = json!([
        floor(14.0),
        // A blade in the plane y = 2, the light's height: edge-on to the light.
        {"name": "blade", "shape": {"kind": "plane", "size": [2.0, 2.0]},
         "transform": {"translation": [2.0, 2.0, 0.0]}, "material": {"two_sided": true}},
        // A box whose top face lies in the same plane.
        {"name": "box", "shape": {"kind": "box", "size": [1.0, 2.0, 1.0]},
         "transform": {"translation": [-2.0, 1.0, -1.0]}},
    ]);
    // The eye in that plane too: the middle row of rays runs along it.
    v["camera"] =
        json!({"position": [0.5, 2.0, 7.0], "look_at": [0.5, 2.0, 0.0], "near": 0.1, "far": 40});
    Ok(v)
}

fn thin_medium(_: &BuildContext) -> Result<Value, String> {
    let mut v = base(60.0);
    v["medium"] = medium(0.0, 1e-6);
    Ok(v)
}

fn dense_medium(_: &BuildContext) -> Result<Value, String> {
    let mut v = base(60.0);
    v["medium"] = medium(5.0, 5.0);
    // The light 1.5 m in front of the eye, so something is visible through the fog.
    v["lights"] = json!([point([0.3, 2.3, 6.5], 60.0)]);
    Ok(v)
}

fn deep_scene(_: &BuildContext) -> Result<Value, String> {
    let o = 1.0e4;
    let small = |x: f64, z: f64| {
        json!({"shape": {"kind": "sphere", "radius": 0.05, "segments": 12, "rings": 6},
               "transform": {"translation": [o + x, 3.2, o + z]}})
    };
    Ok(json!({
        "camera": {"position": [o, 2.6, o + 8.0], "look_at": [o, 1.2, o], "near": 0.1, "far": 2.0e4},
        "medium": medium(1e-5, 2e-4),
        "lights": [point([o + 0.6, 4.6, o - 0.4], 60.0)],
        "objects": [
            {"name": "floor", "shape": {"kind": "plane", "size": [2.0e4, 2.0e4]},
             "transform": {"translation": [o, 0.0, o]}},
            sphere([o, 2.0, o], 0.9),
            small(0.3, -0.2), small(-0.2, 0.1), small(0.1, 0.3),
        ],
    }))
}

fn huge_intensity(_: &BuildContext) -> Result<Value, String> {
    Ok(base(1e18))
}

fn tiny_intensity(_: &BuildContext) -> Result<Value, String> {
    Ok(base(1e-18))
}

fn obj_case(ctx: &BuildContext, file: &str, text: &str, two_sided: bool) -> Result<Value, String> {
    meshes::write(ctx.mesh_dir, file, text)?;
    let mut v = base(60.0);
    v["objects"] = json!([
        floor(14.0),
        {"name": file, "shape": {"kind": "obj", "path": file},
         "transform": {"translation": [0.0, 1.0, 0.0]},
         "material": {"two_sided": two_sided}},
    ]);
    Ok(v)
}

fn open_mesh(ctx: &BuildContext) -> Result<Value, String> {
    obj_case(ctx, "open-box.obj", meshes::OPEN_BOX, true)
}

fn non_manifold_mesh(ctx: &BuildContext) -> Result<Value, String> {
    obj_case(ctx, "non-manifold.obj", meshes::NON_MANIFOLD, true)
}

fn degenerate_mesh(ctx: &BuildContext) -> Result<Value, String> {
    obj_case(ctx, "degenerate.obj", meshes::DEGENERATE, true)
}

fn many_triangles(ctx: &BuildContext) -> Result<Value, String> {
    // A UV sphere has 2·segments·(rings − 1) triangles; with segments = 2·rings that is
    // 4·rings·(rings − 1) ≥ `triangles` for the smallest rings ≥ (1 + √(1 + triangles)) / 2.
    let rings = (((1.0 + (1.0 + ctx.triangles as f64).sqrt()) / 2.0).ceil() as u64).clamp(2, 2048);
    let mut v = base(60.0);
    v["objects"][1]["shape"] =
        json!({"kind": "sphere", "radius": 0.9, "segments": 2 * rings, "rings": rings});
    Ok(v)
}
