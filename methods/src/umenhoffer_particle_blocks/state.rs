//! The prepared method (both ids): the block set built once, and each frame's lists, light
//! maps, uniform and passes (surfaces, impostors, light slices and surface shadows, gathering,
//! resolve), timed per phase.

use anyhow::{Result, bail};
use glam::Vec3;
use harness::gpu::{PhaseTimer, phases};
use harness::method::PrepareContext;
use harness::{FrameReport, Gpu, KnobRead, Prepared, Targets};
use scenes::Particles;
use scenes::particles::Particle;
use scenes::{FrameState, LightState};

use super::accuracy::{self, Accuracy};
use super::blocks::{self, Instancing};
use super::passes::{self, Modes, Passes, PbUniform, Sizes};
use super::primitives::{BlockSet, Prim, Tile, TileView, tile_frames};
use super::{camera_bins, dominant, held, light_maps};
use crate::common::renderer::SceneRenderer;
use crate::common::shadow_maps::ShadowSettings;

/// The largest atlas side (texels); tiles shrink to fit when there are many blocks.
const ATLAS_MAX: u32 = 2048;
/// Steps of the background medium's march in the resolve pass (only if it scatters).
const BACKGROUND_STEPS: f32 = 32.0;

/// The prepared method (either id).
pub struct State {
    renderer: SceneRenderer,
    passes: Passes,
    set: BlockSet,
    clip_fix: bool,
    background_dimming: bool,
    /// Blocks whose centre is within this many radii of a local light are gathered as their
    /// particles (knob `near_light`; 0 for the splat, which has no blocks).
    near_light: f32,
    /// Each block's own particles (None: the splat, or clusters that did not match).
    members: held::Members,
    /// The knobs `slices`, `chord_steps` and `eye_slices`, `auto` resolved (accuracy.rs).
    accuracy: Accuracy,
    /// Camera impostor bins per side (knob `camera_bins`; 1: one camera tile, the paper, and
    /// always for clusters and the splat): the prototype's camera tiles are 1 .. 1 + g².
    camera_grid: usize,
    blocked: bool,
    sky: Vec3,
    background_scatters: bool,
    /// GPU time per phase (counters `gpu_ms_<phase>`), where timestamps inside encoders exist.
    timer: Option<PhaseTimer>,
    /// The most dominant spheres (knob `dominant`; 0: none, the paper) and the cloud's extent
    /// that makes a sphere huge (dominant.rs).
    dominant: usize,
    extent: f32,
}

impl State {
    /// `blocked_mode`: (blocks, instancing, impostor resolution, use the scene's declared
    /// block instances), or None for particle-splat.
    pub fn new(
        ctx: &PrepareContext,
        blocked_mode: Option<(usize, Instancing, u32, bool)>,
    ) -> Result<State> {
        let medium = ctx.scene.medium();
        let Some(particles) = medium.particles() else {
            bail!("scene '{}' has no particle medium", ctx.scene.name);
        };
        let p = ctx.params;
        let lights = ctx.scene.desc.lights.len();
        let most_layers = ctx.gpu.device.limits().max_texture_array_layers;
        // The accuracy knobs, `auto` resolved for this scene (accuracy.rs).
        let accuracy = accuracy::resolve(
            p,
            accuracy::viewer_among_particles(ctx.scene, &particles.particles),
            |s| passes::slice_layers_for(lights, s) <= most_layers,
        )?;
        let slices = accuracy.slices;
        let dominant: usize = p.knob::<u32>("dominant")? as usize;
        let (mut set, tile_res_knob) = block_set(particles, blocked_mode, dominant > 0);
        // Prototype mode: g² camera tiles of the prototype (camera_bins.rs), tiles 1 .. 1 + g²;
        // no more bins than instances (g² ≤ blocks: one block has one direction).
        let camera_grid = match blocked_mode {
            Some((_, Instancing::Prototype, ..)) if set.tiles.len() == 2 => {
                let most = (set.prims.len() as f64).sqrt().floor().max(1.0) as usize;
                (p.knob::<u32>("camera_bins")? as usize).min(most)
            }
            _ => 1,
        };
        let cam = set.tiles[..].get(1).copied();
        set.tiles
            .extend(cam.into_iter().cycle().take(camera_grid * camera_grid - 1));
        // Each block's own particles, for blocks that hold a viewer (held.rs).
        let members = held::Members::of(&particles.particles, &set);
        held::Members::index(&mut set.prims);
        let (tiles, cols, tile_res) = atlas(&set, lights, tile_res_knob);
        // The particle methods sample no spot pattern: a small texture.
        let renderer = SceneRenderer::new(ctx, ShadowSettings::from_params(p)?, 64)?;
        let sizes = Sizes {
            prims: set.prims.len() + held::capacity(&set.prims, &members),
            imp: set.imp.len(),
            tiles: tiles as usize,
            atlas: cols * tile_res,
            cols,
            tile_res,
            light_res: p.knob("light_res")?,
            slices,
            lights,
            camera_tiles: (camera_grid * camera_grid) as u32,
        };
        let (layers, most) = (passes::slice_layers(&sizes), most_layers);
        if layers > most {
            bail!(
                "scene '{}': knob `slices` = {slices} with {lights} lights needs {layers} slice-texture layers (6 light maps per light, {} passes of eight slices each); this adapter allows {most}: use fewer slices (4 … 32)",
                ctx.scene.name,
                passes::slice_passes(slices)
            );
        }
        let modes = Modes {
            blocks: blocked_mode.is_some(),
            forward_scattering: p.knob("forward_scattering")?,
            chord_steps: accuracy.chord_steps,
            eye_slices: accuracy.eye_slices,
            dominant: dominant > 0 && dominant::possible(ctx.scene, &particles.particles),
            moments: match blocked_mode {
                Some(_) => p.knob::<String>("interval")? == "moments",
                None => false,
            },
        };
        let modes_dominant = modes.dominant;
        let passes = Passes::new(ctx.gpu, &renderer, sizes, modes);
        if !set.imp.is_empty() {
            ctx.gpu
                .queue
                .write_buffer(&passes.res.imp, 0, bytemuck::cast_slice(&set.imp));
        }
        Ok(State {
            renderer,
            passes,
            blocked: blocked_mode.is_some(),
            set,
            clip_fix: p.knob("clip_fix")?,
            background_dimming: p.knob("background_dimming")?,
            members,
            near_light: match blocked_mode {
                Some(_) => p.knob::<f64>("near_light")? as f32,
                None => 0.0,
            },
            accuracy,
            camera_grid,
            sky: particles.sky,
            background_scatters: particles.background.sigma_s.max_element() > 0.0,
            timer: PhaseTimer::new(ctx.gpu, 6),
            // None picked where the shaders were built without them (`possible` is false).
            dominant: if modes_dominant { dominant } else { 0 },
            extent: dominant::extent(&particles.particles),
        })
    }

    /// The gathering's list (back to front from the eye) and each light's list, every block
    /// holding that viewer replaced by its particles (held.rs), and in both kinds of list
    /// every block within `near_light` radii of a local light and the block holding the eye.
    fn lists(&self, frame: &FrameState) -> (Vec<Prim>, Vec<Vec<Prim>>) {
        let members = &self.members;
        let eye = frame.camera.position;
        let mut sorted = self.set.prims.clone();
        sorted.sort_by(|a, b| distance2(b, eye).total_cmp(&distance2(a, eye)));
        let local = local_lights(frame);
        let near = self.near_light;
        let mut gather = held::expand(&sorted, members, eye, true, |p| {
            members.holds(p, eye) || local.iter().any(|&lp| members.near(p, lp, near))
        });
        // Back to front over the whole list, blocks and their stand-in particles alike: clusters
        // interpenetrate, and one block's particles kept in its place were composited over
        // particles of other blocks far in front of them (a light inside the cloud: 1.7× the
        // reference's mean in-scatter).
        gather.sort_by(|a, b| distance2(b, eye).total_cmp(&distance2(a, eye)));
        // The block holding the eye is drawn as its particles in every light's pass too: what
        // the eye sees around it is lit through its real particles, not the block's uniform
        // interval (a dense particle holding the eye, lit through the prototype's average, was
        // 18× too bright).
        let lights = frame
            .lights
            .iter()
            .map(|l| {
                let lp = l
                    .position()
                    .filter(|_| !matches!(l, LightState::Directional { .. }));
                held::expand(&self.set.prims, members, lp.unwrap_or(eye), false, |p| {
                    members.holds(p, eye)
                        || lp.is_some_and(|lp| members.near(p, lp, near.max(held::COVERS)))
                })
            })
            .collect();
        (gather, lights)
    }

    /// The dominant spheres of the gathering's list (indices, dominant.rs), the light lists
    /// without them, and the primitives the light maps' extents are taken over (the set's,
    /// without them).
    fn split_dominant(
        &self,
        frame: &FrameState,
        gather: &[Prim],
        light_lists: Vec<Vec<Prim>>,
    ) -> (Vec<usize>, Vec<Vec<Prim>>, Vec<Prim>) {
        let eye = frame.camera.position;
        let picked = dominant::pick(
            gather,
            eye,
            &local_lights(frame),
            self.extent,
            self.dominant,
        );
        if picked.is_empty() {
            return (picked, light_lists, self.set.prims.clone());
        }
        let spheres: Vec<Prim> = picked.iter().map(|&i| gather[i]).collect();
        let lists = light_lists
            .iter()
            .map(|l| dominant::without(l, &spheres))
            .collect();
        (picked, lists, dominant::without(&self.set.prims, &spheres))
    }

    /// The eye's slice view over the gathering's list: along the camera's axis, its square
    /// field covering the screen's diagonal (the map's axes are not the screen's).
    fn eye_view(&self, frame: &FrameState, gather: &[Prim]) -> passes::ViewUniform {
        let cam = &frame.camera;
        let aspect = self.renderer.width as f32 / self.renderer.height.max(1) as f32;
        let tan_y = (cam.fov_y_deg.to_radians() * 0.5).tan();
        let tan = tan_y * (1.0 + aspect * aspect).sqrt() * 1.02;
        let axis = cam.forward().as_vec3();
        light_maps::eye_view(cam.position, axis, tan, gather, self.accuracy.slices)
    }

    /// With camera bins: each gathered block's camera tile (its bin's) and the set's tiles with
    /// the camera tiles anchored at their bins (camera_bins.rs); otherwise the set's tiles.
    fn bin_camera_tiles(&self, eye: Vec3, gather: &mut [Prim]) -> Vec<(TileView, f32)> {
        let mut tiles = self.set.tiles.clone();
        if self.camera_grid < 2 {
            return tiles;
        }
        let blocks: Vec<usize> = (0..gather.len())
            .filter(|&i| gather[i].extra[1] >= 0.0)
            .collect();
        let centres: Vec<Vec3> = blocks
            .iter()
            .map(|&i| Vec3::from_slice(&gather[i].center[..3]))
            .collect();
        let (bin, anchors) = camera_bins::bins(&centres, eye, self.camera_grid);
        for (&i, &b) in blocks.iter().zip(&bin) {
            gather[i].extra[2] = (1 + b) as f32;
        }
        for (b, a) in anchors.into_iter().enumerate() {
            tiles[1 + b].0 = TileView::Camera(a);
        }
        tiles
    }

    /// This frame's impostor tile frames: light k's tiles are `set` (the set's tiles, camera
    /// tiles binned) framed for light k, k·T further on.
    fn tile_frames(&self, frame: &FrameState, set: &[(TileView, f32)]) -> Vec<Tile> {
        let eye = frame.camera.position;
        if frame.lights.is_empty() {
            return tile_frames(set, eye, None, None);
        }
        let mut tiles = Vec::new();
        for light in &frame.lights {
            let (ldir, lpos) = match light {
                LightState::Directional { direction, .. } => (Some(direction.normalize()), None),
                l => (None, l.position()),
            };
            tiles.extend(tile_frames(set, eye, ldir, lpos));
        }
        tiles
    }

    /// This frame's uniform: the light maps written by `light_maps`, the atlas layout, the
    /// flags (clip fix, background steps while any light is lit, dimming), counts and sky.
    fn frame_uniform(&self, mut u: PbUniform, lit: bool) -> PbUniform {
        let sz = &self.passes.sizes;
        u.atlas = [
            sz.cols as f32,
            sz.tile_res as f32,
            self.set.imp.len() as f32,
            sz.atlas as f32,
        ];
        u.flags = [
            self.clip_fix as u32 as f32,
            if self.background_scatters && lit {
                BACKGROUND_STEPS
            } else {
                0.0
            },
            self.background_dimming as u32 as f32,
            0.0,
        ];
        u.counts = [
            sz.prims as f32,
            self.set.tiles.len() as f32,
            sz.light_res as f32,
            sz.camera_tiles as f32,
        ];
        u.sky = [self.sky.x, self.sky.y, self.sky.z, 0.0];
        u
    }

    /// Uploads the uniform, the primitive lists (the gathering's at 0, light k's at (k + 1)·C)
    /// and the tile frames.
    fn upload(
        &self,
        gpu: &Gpu,
        u: &PbUniform,
        gather: &[Prim],
        lights: &[Vec<Prim>],
        tiles: &[Tile],
    ) {
        let res = &self.passes.res;
        gpu.queue
            .write_buffer(&res.uniform, 0, bytemuck::bytes_of(u));
        let stride = (self.passes.sizes.prims * size_of::<Prim>()) as u64;
        for (k, list) in std::iter::once(gather)
            .chain(lights.iter().map(Vec::as_slice))
            .enumerate()
        {
            if !list.is_empty() {
                let at = k as u64 * stride;
                gpu.queue
                    .write_buffer(&res.prims, at, bytemuck::cast_slice(list));
            }
        }
        if !tiles.is_empty() {
            gpu.queue
                .write_buffer(&res.tiles, 0, bytemuck::cast_slice(tiles));
        }
    }

    /// The frame's passes in order, each phase marked: shadow maps and surfaces (into the
    /// unshadowed surface target), impostors, light slices and surface shadows, gathering,
    /// resolve. `views[k]`: light k's maps; `lengths[k]`: its list's length.
    fn encode_passes(
        &mut self,
        gpu: &Gpu,
        enc: &mut wgpu::CommandEncoder,
        targets: &Targets,
        lists: (&[u32], &[usize], usize, bool),
        report: &mut FrameReport,
    ) {
        let (views, lengths, gathered, dominant) = lists;
        phases::mark(&mut self.timer, enc, "surfaces");
        self.renderer.encode_shadows(enc, report);
        let surface_targets = Targets {
            inscatter: targets.inscatter,
            surface: &self.passes.res.surface_view,
            total: targets.total,
            width: targets.width,
            height: targets.height,
        };
        self.renderer.encode_surface(enc, &surface_targets, report);
        if self.blocked {
            phases::mark(&mut self.timer, enc, "impostors");
            self.passes.encode_impostors(enc, &self.renderer);
            report.ran("impostors");
            let groups = 1 + self.passes.sizes.lights;
            report.count("impostor_splats", (groups * self.set.imp.len()) as f64);
        }
        phases::mark(&mut self.timer, enc, "light");
        let eye = if self.accuracy.eye_slices {
            gathered
        } else {
            0
        };
        self.passes
            .encode_light(enc, &self.renderer, views, lengths, eye, dominant);
        if views.iter().any(|&n| n > 0) || dominant {
            report.ran("light-slices");
            report.ran("surface-shadows");
        } else {
            report.skip("light-slices", "no light or no particles");
            report.skip("surface-shadows", "no light or no particles");
        }
        report.count("light_faces", views.iter().sum::<u32>() as f64);
        phases::mark(&mut self.timer, enc, "gather");
        self.passes.encode_gather(enc, &self.renderer, gathered);
        report.ran("gather");
        phases::mark(&mut self.timer, enc, "resolve");
        self.passes
            .encode_resolve(gpu, enc, &self.renderer, targets);
        report.ran("resolve");
        phases::finish(&mut self.timer, enc);
    }
}

impl Prepared for State {
    fn render(
        &mut self,
        gpu: &Gpu,
        frame: &FrameState,
        targets: &Targets,
        enc: &mut wgpu::CommandEncoder,
    ) -> Result<FrameReport> {
        let mut report = self.renderer.start_frame(gpu, frame);
        let mut u: PbUniform = bytemuck::Zeroable::zeroed();
        let (mut gather, light_lists) = self.lists(frame);
        // Spheres standing in for blocks that hold the eye or a light, over every list (before
        // the dominant spheres leave the light lists).
        let listed = gather.len() + light_lists.iter().map(Vec::len).sum::<usize>();
        let plain = (1 + light_lists.len()) * self.set.prims.len();
        let (picked, light_lists, mapped) = self.split_dominant(frame, &gather, light_lists);
        let views: Vec<u32> = frame
            .lights
            .iter()
            .enumerate()
            .map(|(k, light)| {
                light_maps::light_views(
                    light,
                    &mapped,
                    self.set.centroid,
                    self.accuracy.slices,
                    k,
                    &mut u,
                )
            })
            .collect();
        let mut u = self.frame_uniform(u, views.iter().any(|&n| n > 0) || !picked.is_empty());
        u.flags[3] = picked.len() as f32;
        u.dominant = dominant::rows(&gather, &picked);
        report.count("dominant_spheres", picked.len() as f64);
        if self.accuracy.eye_slices {
            u.views[passes::FACES * views.len()] = self.eye_view(frame, &gather);
        }
        let binned = self.bin_camera_tiles(frame.camera.position, &mut gather);
        let tiles = self.tile_frames(frame, &binned);
        self.upload(gpu, &u, &gather, &light_lists, &tiles);
        let lengths: Vec<usize> = light_lists.iter().map(Vec::len).collect();
        let lists = (&views[..], &lengths[..], gather.len(), !picked.is_empty());
        // The accuracy knobs as used (`auto` resolved, accuracy.rs).
        report.count("eye_slices", self.accuracy.eye_slices as u32 as f64);
        report.count("slices", self.accuracy.slices as f64);
        report.count("chord_steps", self.accuracy.chord_steps as f64);
        self.encode_passes(gpu, enc, targets, lists, &mut report);
        report.count("blocks", self.set.prims.len() as f64);
        report.count("held_spheres", listed as f64 - plain as f64);
        report.count("particles_per_block", self.set.per_block);
        report.count("declared_blocks", self.set.declared as u32 as f64);
        Ok(report)
    }

    fn phase_timer(&self) -> Option<&PhaseTimer> {
        self.timer.as_ref()
    }
}

/// The squared distance from `eye` to primitive `p`'s centre.
fn distance2(p: &Prim, eye: Vec3) -> f32 {
    (Vec3::from_slice(&p.center[..3]) - eye).length_squared()
}

/// The positions of the frame's local (not directional) lights.
fn local_lights(frame: &FrameState) -> Vec<Vec3> {
    frame
        .lights
        .iter()
        .filter(|l| !matches!(l, LightState::Directional { .. }))
        .filter_map(LightState::position)
        .collect()
}

/// The block set of `particles` (declared blocks where the scene has them and `from_scene`,
/// else clusters; unblocked spheres for the splat) and the impostor resolution asked for.
/// With `loose_apart` (dominant spheres on), the loose particles are spheres of their own
/// (`blocks::with_loose`; the splat's are anyway).
fn block_set(
    particles: &Particles,
    blocked_mode: Option<(usize, Instancing, u32, bool)>,
    loose_apart: bool,
) -> (BlockSet, u32) {
    let ps = &particles.particles;
    match blocked_mode {
        None => (blocks::unblocked(ps), 1),
        Some((b, mode, res, from_scene)) => {
            let build = |ps: &[Particle]| {
                from_scene
                    .then(|| blocks::declared(ps, &particles.blocks, mode))
                    .flatten()
                    .unwrap_or_else(|| blocks::blocked(ps, b, mode))
            };
            let set = if loose_apart {
                blocks::with_loose(ps, dominant::extent(ps), build)
            } else {
                build(ps)
            };
            (set, res)
        }
    }
}

/// The atlas layout: tiles (every light has its own light tiles; the camera tiles repeat,
/// unused, per light), tile columns, and the tile resolution shrunk to fit [`ATLAS_MAX`].
fn atlas(set: &BlockSet, lights: usize, tile_res: u32) -> (u32, u32, u32) {
    let tiles = (set.tiles.len() * lights.max(1)) as u32;
    let cols = (tiles as f64).sqrt().ceil().max(1.0) as u32;
    let tile_res = if tiles == 0 {
        1
    } else {
        tile_res.min(ATLAS_MAX / cols).max(4)
    };
    (tiles, cols, tile_res)
}
