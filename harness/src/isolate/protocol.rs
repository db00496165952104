//! The parent ↔ worker protocol: one JSON object per line, a [`ToWorker::Scene`] line followed
//! by its raw little-endian payload (meshes, then the reference images), so a 1M-triangle
//! mesh or a 1024² reference crosses the pipe as bytes rather than as decimal text.
//!
//! Parent → worker (the worker's stdin): `Scene` (the scene and its reference, once per scene
//! a worker sees), then `Job`s. Closing stdin asks the worker to exit.
//! Worker → parent (a pipe that was the worker's stdout; stray prints go to stderr): `Ready`
//! once the device exists, `Phase` before each phase of a job, then `Record`; or `Fatal` if
//! the worker cannot go on.

use std::io::{BufRead, Read, Write};
use std::path::PathBuf;
use std::sync::Arc;

use glam::Vec3;
use scenes::Scene;
use scenes::desc::SceneDesc;
use scenes::mesh::TriMesh;
use serde::{Deserialize, Serialize};

use crate::image::Image;
use crate::method::Params;
use crate::record::{Phase, RecordSettings};
use crate::reference::{ReferenceImages, ReferenceStats};
use crate::results::Record;

#[derive(Debug, Serialize, Deserialize)]
pub enum ToWorker {
    /// The scene of the following jobs; the payload (`meshes` then three `reference` images)
    /// follows the line.
    Scene(SceneHeader),
    /// One record: the method, its full parameter set and how to measure it — the run's
    /// settings, the same the in-process runner uses.
    Job {
        method: String,
        params: Params,
        settings: RecordSettings,
    },
}

#[derive(Debug, Serialize, Deserialize)]
pub struct SceneHeader {
    pub name: String,
    pub desc: SceneDesc,
    pub source: Option<PathBuf>,
    /// The scene's unmodelled imported content (`Scene::ignored`).
    #[serde(default)]
    pub ignored: Vec<String>,
    /// Per mesh: (positions, normals, triangles).
    pub meshes: Vec<(usize, usize, usize)>,
    /// Width and height of the reference images (inscatter, surface, total, and the
    /// per-pixel distance to the first surface, which scoring needs to tell whether a light is
    /// in view: the light core, ARCHITECTURE §4.4).
    pub reference: (u32, u32),
}

#[derive(Debug, Serialize, Deserialize)]
pub enum FromWorker {
    Ready { pid: u32 },
    Phase(Phase),
    Record(Box<Record>),
    Fatal(String),
}

/// Writes one line of JSON.
pub fn write_line<T: Serialize>(w: &mut impl Write, msg: &T) -> std::io::Result<()> {
    let mut line = serde_json::to_vec(msg).map_err(std::io::Error::other)?;
    line.push(b'\n');
    w.write_all(&line)
}

/// Reads one line of JSON; `Ok(None)` at end of input.
pub fn read_line<T: for<'de> Deserialize<'de>>(r: &mut impl BufRead) -> Result<Option<T>, String> {
    let mut line = String::new();
    match r.read_line(&mut line) {
        Ok(0) => Ok(None),
        Ok(_) => serde_json::from_str(&line)
            .map(Some)
            .map_err(|e| format!("bad protocol line ({e}): {}", line.trim_end())),
        Err(e) => Err(format!("cannot read the protocol pipe: {e}")),
    }
}

/// Sends a scene and its reference: the header line, then the payload.
pub fn write_scene(
    w: &mut impl Write,
    scene: &Scene,
    reference: &ReferenceImages,
) -> std::io::Result<()> {
    let pixels = reference.total.width as usize * reference.total.height as usize;
    if reference.distance.len() != pixels {
        return Err(std::io::Error::new(
            std::io::ErrorKind::InvalidInput,
            format!(
                "reference of scene '{}': {} distances for {pixels} pixels",
                scene.name,
                reference.distance.len()
            ),
        ));
    }
    let header = ToWorker::Scene(SceneHeader {
        name: scene.name.clone(),
        desc: scene.desc.clone(),
        source: scene.source.clone(),
        ignored: scene.ignored.clone(),
        meshes: scene
            .meshes
            .iter()
            .map(|m| (m.positions.len(), m.normals.len(), m.indices.len()))
            .collect(),
        reference: (reference.total.width, reference.total.height),
    });
    write_line(w, &header)?;
    for m in &scene.meshes {
        w.write_all(bytemuck::cast_slice(&m.positions))?;
        w.write_all(bytemuck::cast_slice(&m.normals))?;
        w.write_all(bytemuck::cast_slice(&m.indices))?;
    }
    for img in [&reference.inscatter, &reference.surface, &reference.total] {
        w.write_all(bytemuck::cast_slice(&img.pixels))?;
    }
    w.write_all(bytemuck::cast_slice(&reference.distance))?;
    w.flush()
}

/// Reads the payload announced by `header`: the scene and the reference (without its
/// statistics, which scoring does not use).
pub fn read_scene(
    r: &mut impl Read,
    header: SceneHeader,
) -> Result<(Scene, ReferenceImages), String> {
    fn vec<T: bytemuck::Pod + bytemuck::Zeroable>(
        r: &mut impl Read,
        n: usize,
    ) -> Result<Vec<T>, String> {
        let mut v = vec![T::zeroed(); n];
        r.read_exact(bytemuck::cast_slice_mut(&mut v))
            .map_err(|e| format!("scene payload cut short: {e}"))?;
        Ok(v)
    }
    let mut meshes = Vec::with_capacity(header.meshes.len());
    for &(np, nn, ni) in &header.meshes {
        meshes.push(Arc::new(TriMesh {
            positions: vec::<Vec3>(r, np)?,
            normals: vec::<Vec3>(r, nn)?,
            indices: vec::<[u32; 3]>(r, ni)?,
        }));
    }
    let (width, height) = header.reference;
    let mut image = || -> Result<Image, String> {
        Ok(Image {
            width,
            height,
            pixels: vec::<[f32; 3]>(r, width as usize * height as usize)?,
        })
    };
    let (inscatter, surface, total) = (image()?, image()?, image()?);
    let distance = vec::<f32>(r, width as usize * height as usize)?;
    let scene = Scene {
        name: header.name,
        desc: header.desc,
        meshes,
        source: header.source,
        ignored: header.ignored,
    };
    let reference = ReferenceImages {
        inscatter,
        surface,
        total,
        distance,
        stats: ReferenceStats::default(),
    };
    Ok((scene, reference))
}
