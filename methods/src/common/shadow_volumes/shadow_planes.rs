//! Shadow planes on the CPU, shared by both Biri methods (and any other method that draws
//! silhouette shadow planes): the casters' edge meshes, their silhouettes per light (recomputed
//! only when a light or a caster moved), the quads extruded from them in eye-distance order, and
//! the number of shadow volumes that contain the eye (the seed of a z-pass stencil count).
//!
//! Each caster is split into its closed pieces first (`EdgeMesh::components`, `Split`): a union
//! of touching closed solids casts one silhouette volume per solid instead of three planes per
//! triangle.

use std::time::Instant;

use glam::{Mat4, Vec3};
use harness::FrameReport;
use scenes::{FrameState, LightState, Scene};

use super::silhouette::{EdgeMesh, LightPos, extrude};

/// Drawing order of one light's planes, by the eye distance of each silhouette edge's midpoint.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Order {
    /// Farthest first (Biri et al. 2006, step 4).
    BackToFront,
    /// Nearest first (Biri, Michelin & Arquès, §4.3).
    FrontToBack,
}

/// How casters become shadow volumes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Split {
    /// Each closed piece of a caster (`EdgeMesh::components`) casts its silhouette volume; only
    /// open or non-manifold pieces fall back to per-triangle volumes.
    #[default]
    Components,
    /// A caster that is not a closed 2-manifold as a whole falls back to per-triangle volumes
    /// entirely (the former behaviour; kept to compare against).
    WholeMesh,
}

/// One light's shadow planes.
#[derive(Clone, Debug, Default)]
pub struct LightPlanes {
    /// Quads as two triangles [p, q, q', p, q', p'], outward-wound, in the requested order.
    pub quads: Vec<[Vec3; 6]>,
    /// Shadow volumes of this light that contain the eye.
    pub eye_count: u32,
}

/// The scene's volumetric-shadow casters, with silhouettes cached per light.
pub struct ShadowCasters {
    /// (object index, one piece of its edge mesh in local space): several per object when it
    /// splits into closed pieces (`Split::Components`).
    casters: Vec<(usize, EdgeMesh)>,
    /// Per piece: whether it is a closed 2-manifold (silhouette planes), else per-triangle
    /// planes.
    closed: Vec<bool>,
    /// Names of the objects with an open or non-manifold piece, for the recorded warning.
    open_names: Vec<String>,
    /// Light positions/directions and caster transforms the silhouettes were built for.
    built_for: Option<(Vec<LightPos>, Vec<Mat4>)>,
    silhouettes: Vec<Vec<[Vec3; 2]>>,
}

/// Where a light is, for silhouettes: point and spot lights by position, directional ones by
/// propagation direction.
pub fn light_pos(light: &LightState) -> LightPos {
    match light {
        LightState::Directional { direction, .. } => LightPos::Direction(*direction),
        _ => LightPos::Point(light.position().unwrap_or(Vec3::ZERO)),
    }
}

impl ShadowCasters {
    /// Every object with `casts_volumetric_shadow`, split into closed pieces.
    pub fn new(scene: &Scene) -> ShadowCasters {
        ShadowCasters::with_split(scene, Split::Components)
    }

    /// Every object with `casts_volumetric_shadow`, split as `split` says.
    pub fn with_split(scene: &Scene, split: Split) -> ShadowCasters {
        let casters: Vec<(usize, EdgeMesh)> = scene
            .desc
            .objects
            .iter()
            .enumerate()
            .filter(|(_, o)| o.casts_volumetric_shadow)
            .flat_map(|(k, _)| {
                let mesh = EdgeMesh::new(&scene.meshes[k]);
                let pieces = match split {
                    Split::Components => mesh.components(),
                    Split::WholeMesh => vec![mesh],
                };
                pieces.into_iter().map(move |m| (k, m))
            })
            .collect();
        let closed: Vec<bool> = casters
            .iter()
            .map(|(_, m)| m.is_closed_manifold())
            .collect();
        let mut open_names: Vec<String> = Vec::new();
        for ((k, _), _) in casters.iter().zip(&closed).filter(|(_, c)| !**c) {
            let name = &scene.desc.objects[*k].name;
            if !open_names.contains(name) {
                open_names.push(name.clone());
            }
        }
        ShadowCasters {
            closed,
            open_names,
            casters,
            built_for: None,
            silhouettes: Vec::new(),
        }
    }

    /// (object index, piece) of every caster piece.
    pub fn casters(&self) -> &[(usize, EdgeMesh)] {
        &self.casters
    }

    /// Silhouettes (cached), extrusion `reach` metres past each edge, ordering, eye counts.
    /// Counters: `silhouettes_recomputed`, `silhouette_ms`, `sort_ms`, `silhouette_edges`,
    /// `nonmanifold_casters` (objects with an open or non-manifold piece, whose every triangle
    /// casts its own planes instead; each is also recorded as a skipped "silhouette of <name>"),
    /// `closed_pieces` (caster pieces casting silhouette volumes).
    pub fn planes(
        &mut self,
        frame: &FrameState,
        order: Order,
        reach: impl Fn(&LightState) -> f32,
        report: &mut FrameReport,
    ) -> Vec<LightPlanes> {
        let eye = frame.camera.position;
        let lights: Vec<LightPos> = frame.lights.iter().map(light_pos).collect();
        let transforms: Vec<Mat4> = self
            .casters
            .iter()
            .map(|(k, _)| frame.world_from_local[*k])
            .collect();
        let t0 = Instant::now();
        let key = (lights.clone(), transforms);
        let moved = self.built_for.as_ref() != Some(&key);
        if moved {
            self.silhouettes = lights
                .iter()
                .map(|l| {
                    self.casters
                        .iter()
                        .zip(&self.closed)
                        .flat_map(|((k, m), closed)| {
                            let w = &frame.world_from_local[*k];
                            if *closed {
                                m.silhouette(w, *l)
                            } else {
                                m.triangle_edges(w, *l)
                            }
                        })
                        .collect()
                })
                .collect();
            self.built_for = Some(key);
        }
        report.count("silhouettes_recomputed", moved as u32 as f64);
        report.count("nonmanifold_casters", self.open_names.len() as f64);
        let closed = self.closed.iter().filter(|c| **c).count();
        report.count("closed_pieces", closed as f64);
        for name in &self.open_names {
            report.skip(
                &format!("silhouette of {name}"),
                "open or non-manifold piece: per-triangle shadow planes for it instead",
            );
        }
        report.count("silhouette_ms", t0.elapsed().as_secs_f64() * 1e3);
        let t1 = Instant::now();
        let out: Vec<LightPlanes> = lights
            .iter()
            .zip(&frame.lights)
            .enumerate()
            .map(|(k, (l, state))| {
                let reach = reach(state);
                let mut keyed: Vec<(f32, [Vec3; 6])> = self.silhouettes[k]
                    .iter()
                    .map(|e| (((e[0] + e[1]) * 0.5 - eye).length(), extrude(*e, *l, reach)))
                    .collect();
                match order {
                    Order::BackToFront => keyed.sort_by(|a, b| b.0.total_cmp(&a.0)),
                    Order::FrontToBack => keyed.sort_by(|a, b| a.0.total_cmp(&b.0)),
                }
                LightPlanes {
                    quads: keyed.into_iter().map(|(_, q)| q).collect(),
                    eye_count: self.eye_count(frame, *l, eye),
                }
            })
            .collect();
        report.count("sort_ms", t1.elapsed().as_secs_f64() * 1e3);
        let edges: usize = self.silhouettes.iter().map(Vec::len).sum();
        report.count("silhouette_edges", edges as f64);
        out
    }

    /// Shadow volumes around the eye: light-facing caster triangles that the segment from the
    /// eye to the light (for a directional light, a long segment against its direction) crosses.
    pub fn eye_count(&self, frame: &FrameState, light: LightPos, eye: Vec3) -> u32 {
        let source = match light {
            LightPos::Point(l) => l,
            LightPos::Direction(d) => eye - d * (2.0 * frame.camera.far + 1e4),
        };
        let mut n = 0;
        for ((k, m), closed) in self.casters.iter().zip(&self.closed) {
            let w = frame.world_from_local[*k];
            for t in &m.triangles {
                let [a, b, c] = t.map(|i| w.transform_point3(m.positions[i as usize]));
                let normal = (b - a).cross(c - a);
                // Per-triangle (two-sided) volumes of open casters: every crossed triangle.
                if *closed && normal.dot(source - a) <= 0.0 {
                    continue;
                }
                if segment_hits(source, eye, a, b, c) {
                    n += 1;
                }
            }
        }
        n
    }
}

/// Does the segment p → q cross triangle (a, b, c)? (Möller–Trumbore, open interval.)
fn segment_hits(p: Vec3, q: Vec3, a: Vec3, b: Vec3, c: Vec3) -> bool {
    let d = q - p;
    let (e1, e2) = (b - a, c - a);
    let h = d.cross(e2);
    let det = e1.dot(h);
    if det.abs() < 1e-12 {
        return false;
    }
    let s = p - a;
    let u = s.dot(h) / det;
    if !(0.0..=1.0).contains(&u) {
        return false;
    }
    let qv = s.cross(e1);
    let v = d.dot(qv) / det;
    if v < 0.0 || u + v > 1.0 {
        return false;
    }
    let t = e2.dot(qv) / det;
    t > 0.0 && t < 1.0
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn eye_count_counts_the_volumes_between_eye_and_light() {
        // Two spheres stacked under a point light: an eye under both is in two volumes, an eye
        // beside them in none.
        let text = r#"{
          "camera": { "position": [0, 0.2, 0], "look_at": [0, 0.2, -1], "fov_y_deg": 45, "near": 0.1, "far": 40 },
          "medium": { "kind": "homogeneous", "sigma_a": [0.01,0.01,0.01], "sigma_s": [0.05,0.05,0.05] },
          "lights": [ { "kind": "point", "position": [0, 8, 0], "intensity": [10,10,10] } ],
          "objects": [
            { "name": "a", "shape": { "kind": "sphere", "radius": 0.5 }, "transform": { "translation": [0, 2, 0] } },
            { "name": "b", "shape": { "kind": "sphere", "radius": 0.5 }, "transform": { "translation": [0, 4, 0] } }
          ] }"#;
        let scene = scenes::load::parse_scene(text, "test.json", "test", std::path::Path::new("."))
            .expect("scene");
        let casters = ShadowCasters::new(&scene);
        let frame = scene.frame(0);
        let light = light_pos(&frame.lights[0]);
        // Off the poles' axis: a segment through a shared vertex counts every triangle there
        // (a known degenerate case of the triangle count, as with any z-pass seed).
        assert_eq!(
            casters.eye_count(&frame, light, Vec3::new(0.07, 0.2, 0.03)),
            2
        );
        assert_eq!(
            casters.eye_count(&frame, light, Vec3::new(3.0, 0.2, 0.0)),
            0
        );
        assert_eq!(
            casters.eye_count(&frame, light, Vec3::new(0.07, 3.0, 0.03)),
            1
        );
    }

    #[test]
    fn planes_come_in_the_requested_order() {
        let scene = scenes::library::resolve("sphere-point").expect("library scene");
        let mut casters = ShadowCasters::new(&scene);
        let frame = scene.frame(0);
        let eye = frame.camera.position;
        let mut report = FrameReport::default();
        let dist = |q: &[Vec3; 6]| ((q[0] + q[1]) * 0.5 - eye).length();
        for order in [Order::BackToFront, Order::FrontToBack] {
            let planes = casters.planes(&frame, order, |_| 50.0, &mut report);
            let d: Vec<f32> = planes[0].quads.iter().map(dist).collect();
            assert!(d.len() > 8, "a sphere has a silhouette loop");
            let sorted = d.windows(2).all(|w| match order {
                Order::BackToFront => w[0] >= w[1],
                Order::FrontToBack => w[0] <= w[1],
            });
            assert!(sorted, "{order:?}: {d:?}");
        }
        // The second call found nothing moved.
        assert_eq!(report.counters["silhouettes_recomputed"], 1.0);
    }
}
