//! Support for the test suites of every crate (GPU tests, CLI tests, benches): one definition of
//! "get an adapter or skip", of a scratch directory and of a small run configuration, and the
//! test kit the method tests share (prepare, render, compare with the reference).

use std::path::PathBuf;

use crate::gpu::Gpu;
use crate::image::Image;
use crate::image::metrics::{ToneMap, compare};
use crate::method::{
    Aov, FrameReport, Method, ParamValue, Params, PrepareContext, Prepared, resolve_params,
};
use crate::record::{AovTargets, RecordSettings, render_frame};
use crate::reference::{ReferenceImages, Settings};
use crate::runner::RunConfig;

/// The GPU, or None with a message when there is no adapter — except when `CI` is set, where a
/// missing adapter panics: a CI machine that cannot run the GPU tests must not pass silently.
pub fn gpu_or_skip() -> Option<Gpu> {
    match Gpu::new() {
        Ok(g) => Some(g),
        Err(e) if std::env::var_os("CI").is_some() => {
            panic!("CI is set and there is no GPU adapter: {e}")
        }
        Err(e) => {
            eprintln!("skipping GPU test: {e}");
            None
        }
    }
}

/// A fresh, empty directory under the system temp dir, unique to this process and `name`.
pub fn temp_dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("scatterbench-test-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    d
}

/// A square `res`² run of `frames` timed frames, no warm-up, no cache, no overrides.
pub fn run_config(out: PathBuf, res: u32, frames: u32) -> RunConfig {
    RunConfig::new(RecordSettings::new(out, (res, res), (frames, 0)), "test")
}

/// Knob overrides from (name, value) pairs.
pub fn knobs(list: &[(&str, ParamValue)]) -> Params {
    list.iter()
        .map(|(k, v)| (k.to_string(), v.clone()))
        .collect()
}

/// A library scene by name (panics with the library's message: test setup).
pub fn library(name: &str) -> scenes::Scene {
    scenes::library::resolve(name).unwrap_or_else(|e| panic!("{e}"))
}

/// A scene from JSON text (a test's own scene file, `include_str!`-ed), named `name` (panics
/// with the loader's message: test setup).
pub fn scene_text(text: &str, name: &str) -> scenes::Scene {
    let file = format!("{name}.json");
    scenes::load::parse_scene(text, &file, name, std::path::Path::new("."))
        .unwrap_or_else(|e| panic!("{e}"))
}

/// `method` prepared on `scene` at `res`² with `list` over its defaults (a refused knob is an
/// error, as in a run).
pub fn prepare(
    gpu: &Gpu,
    method: &dyn Method,
    scene: &scenes::Scene,
    res: u32,
    list: &[(&str, ParamValue)],
    no_skip: bool,
) -> anyhow::Result<Box<dyn Prepared>> {
    let params = resolve_params(method, &knobs(list))?;
    method.prepare(&PrepareContext {
        gpu,
        scene,
        params: &params,
        width: res,
        height: res,
        no_skip,
    })
}

/// A rendered frame: the three AOVs read back and the method's report.
pub struct Rendered {
    pub inscatter: Image,
    pub surface: Image,
    pub total: Image,
    pub report: FrameReport,
}

impl Rendered {
    pub fn aov(&self, aov: Aov) -> &Image {
        match aov {
            Aov::Inscatter => &self.inscatter,
            Aov::Surface => &self.surface,
            Aov::Total => &self.total,
        }
    }
}

/// Renders frame `index` of `scene` with a prepared method `frames` times (counters read back a
/// frame late need two) into fresh `res`² targets and reads the AOVs back.
pub fn render_prepared(
    gpu: &Gpu,
    prepared: &mut dyn Prepared,
    scene: &scenes::Scene,
    res: u32,
    index: u32,
    frames: u32,
) -> anyhow::Result<Rendered> {
    let aovs = AovTargets::new(gpu, res, res);
    let mut report = FrameReport::default();
    for _ in 0..frames.max(1) {
        report = render_frame(gpu, prepared, scene, index, &aovs, None)
            .map_err(anyhow::Error::msg)?
            .report;
    }
    let [inscatter, surface, total] = aovs.read(gpu).map_err(anyhow::Error::msg)?;
    Ok(Rendered {
        inscatter,
        surface,
        total,
        report,
    })
}

/// `method` with `list` over its defaults, prepared and rendered once at frame 0, `res`².
pub fn render_method(
    gpu: &Gpu,
    method: &dyn Method,
    scene: &scenes::Scene,
    res: u32,
    list: &[(&str, ParamValue)],
) -> anyhow::Result<Rendered> {
    let mut p = prepare(gpu, method, scene, res, list, false)?;
    render_prepared(gpu, p.as_mut(), scene, res, 0, 1)
}

/// Relative RMSE of `test` against `reference` (RMSE / mean of the reference, all channels).
pub fn rel_rmse(test: &Image, reference: &Image) -> f64 {
    compare(test, reference, &ToneMap { exposure: 0.0 })
        .expect("images of one size")
        .rel_rmse
}

/// The largest per-pixel, per-channel difference between `a` and `b` relative to `b`'s largest
/// value.
pub fn max_rel_diff(a: &Image, b: &Image) -> f64 {
    let scale = b
        .pixels
        .iter()
        .flat_map(|p| p.iter())
        .fold(0.0f32, |m, v| m.max(v.abs())) as f64;
    let diff = a
        .pixels
        .iter()
        .zip(&b.pixels)
        .flat_map(|(p, q)| (0..3).map(move |c| (p[c] - q[c]).abs()))
        .fold(0.0f32, f32::max);
    diff as f64 / scale.max(1e-30)
}

/// The reference images of frame 0 at `res`², cached across test runs in the system temp dir.
pub fn reference(scene: &scenes::Scene, res: u32) -> ReferenceImages {
    let dir = std::env::temp_dir().join("scatterbench-test-reference-cache");
    std::fs::create_dir_all(&dir).expect("temp dir");
    crate::reference::cache::render_cached(
        Some(&dir),
        scene,
        0,
        res,
        res,
        Settings::default(),
        &|_| {},
    )
    .unwrap_or_else(|e| panic!("reference of {}: {e}", scene.name))
    .0
}

/// Deterministic pseudo-random source for test noise (64-bit LCG, Knuth's MMIX constants), so
/// tests never flake.
pub struct Lcg(pub u64);

impl Lcg {
    /// Uniform in (0, 1).
    pub fn uniform(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((self.0 >> 11) as f64 + 0.5) / (1u64 << 53) as f64
    }

    /// Approximately standard normal: Irwin–Hall sum of 12 uniforms − 6.
    pub fn gaussian(&mut self) -> f64 {
        (0..12).map(|_| self.uniform()).sum::<f64>() - 6.0
    }
}
