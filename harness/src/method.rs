//! The Method contract (ARCHITECTURE §2.3): what every technique implements, and what the
//! harness gives it. A method declares its knobs and what it supports; the harness owns timing,
//! read-back and metrics — a method never times itself. The knob functions that take a method
//! (`resolve_params`, `parse_knob`, `param_sets`) are here, over `crate::knobs`.

use std::collections::BTreeMap;

use scenes::{FrameState, Scene, SceneFeatures};
use serde::{Deserialize, Serialize};

use crate::gpu::{Gpu, PhaseTimer};
use crate::knobs;
pub use crate::knobs::{
    Knob, KnobError, KnobProblem, KnobRead, KnobType, ParamValue, Params, Range, Requirement,
};

/// Who a method is.
#[derive(Clone, Debug, Serialize)]
pub struct MethodInfo {
    /// Stable id used on the command line and in results (`raymarch-brute`).
    pub id: &'static str,
    /// The paper (authors, title, venue, year); for a baseline, what it stands for.
    pub paper: &'static str,
    pub summary: &'static str,
    /// A reference point rather than a published technique (brute force, no scattering, the
    /// un-accelerated form of a paper's method): the report ranks baselines below the line.
    pub baseline: bool,
    /// The participating media it renders; the conformance checks hold it to `support`.
    pub medium: Medium,
    /// The method's README.md (`include_str!("README.md")`): the conformance test checks it
    /// exists and follows docs/ADDING_A_METHOD.md.
    #[serde(skip)]
    pub readme: &'static str,
    /// The source of the method's `mod.rs` (`include_str!("mod.rs")`), whose `//!` module doc
    /// the conformance test checks.
    #[serde(skip)]
    pub source: &'static str,
}

/// A method's [`MethodInfo`], with its `README.md` and `mod.rs` read from the folder of the
/// file that invokes it (which must be the method's `mod.rs`):
/// `method_info!(id, medium, paper, summary)`, or `method_info!(baseline id, …)` for a baseline.
#[macro_export]
macro_rules! method_info {
    (baseline $id:expr, $medium:expr, $paper:expr, $summary:expr $(,)?) => {
        $crate::method_info!(@info true, $id, $medium, $paper, $summary)
    };
    (@info $baseline:expr, $id:expr, $medium:expr, $paper:expr, $summary:expr) => {
        $crate::MethodInfo {
            id: $id,
            paper: $paper,
            summary: $summary,
            baseline: $baseline,
            medium: $medium,
            readme: include_str!("README.md"),
            source: include_str!("mod.rs"),
        }
    };
    ($id:expr, $medium:expr, $paper:expr, $summary:expr $(,)?) => {
        $crate::method_info!(@info false, $id, $medium, $paper, $summary)
    };
}

/// The participating media a method renders (`scenes::SceneFeatures::medium` names a scene's).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Medium {
    Homogeneous,
    Particles,
    /// Homogeneous and particle media.
    Both,
}

impl Medium {
    /// "homogeneous", "particles" or "both" (as in results.json).
    pub fn name(self) -> &'static str {
        match self {
            Medium::Homogeneous => "homogeneous",
            Medium::Particles => "particles",
            Medium::Both => "both",
        }
    }

    /// Whether it includes a scene's medium (`SceneFeatures::medium`).
    pub fn covers(self, scene_medium: &str) -> bool {
        self == Medium::Both || self.name() == scene_medium
    }
}

/// The method of `registry` with this id.
pub fn find<'a>(registry: &[&'a dyn Method], id: &str) -> Option<&'a dyn Method> {
    registry.iter().copied().find(|m| m.id() == id)
}

/// Whether a method can render a scene.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(tag = "support", content = "detail", rename_all = "lowercase")]
pub enum Support {
    Full,
    /// Renders, but ignores these features (listed in the record).
    Partial(Vec<String>),
    /// Cannot render it; the reason is recorded and the pair skipped.
    No(String),
}

/// A pass the method did not run this frame, and why (ARCHITECTURE §2.4, "skip what a scene
/// doesn't need").
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct SkippedPass {
    pub pass: String,
    pub why: String,
}

/// What a frame did: passes run and skipped, and counters the paper talks about.
#[derive(Clone, Debug, Default, Serialize, Deserialize, PartialEq)]
pub struct FrameReport {
    pub run: Vec<String>,
    pub skipped: Vec<SkippedPass>,
    pub counters: BTreeMap<String, f64>,
}

impl FrameReport {
    pub fn ran(&mut self, pass: &str) {
        self.run.push(pass.to_string());
    }
    pub fn skip(&mut self, pass: &str, why: &str) {
        self.skipped.push(SkippedPass {
            pass: pass.to_string(),
            why: why.to_string(),
        });
    }
    pub fn count(&mut self, name: &str, v: f64) {
        *self.counters.entry(name.to_string()).or_default() += v;
    }
}

/// The three AOV targets (Rgba32Float, `width`×`height`, RENDER_ATTACHMENT | STORAGE_BINDING |
/// TEXTURE_BINDING | COPY_SRC), cleared to zero by the harness before each frame. A method writes
/// linear radiance to all three (ARCHITECTURE §1: inscatter, surface, total).
pub struct Targets<'a> {
    pub inscatter: &'a wgpu::TextureView,
    pub surface: &'a wgpu::TextureView,
    pub total: &'a wgpu::TextureView,
    pub width: u32,
    pub height: u32,
}

pub const AOV_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Float;

/// What `prepare` gets.
pub struct PrepareContext<'a> {
    pub gpu: &'a Gpu,
    pub scene: &'a Scene,
    pub params: &'a Params,
    pub width: u32,
    pub height: u32,
    /// `--no-skip`: run every pass even where the scene does not need it.
    pub no_skip: bool,
}

/// A method: a description (who, knobs, support, shaders, conformance cases) that holds no GPU
/// state. `prepare` builds the [`Prepared`] instance that renders. The registry
/// (`methods::REGISTRY`) is a static list of `&'static dyn Method`; the id lives in `info()`.
pub trait Method: Sync {
    fn info(&self) -> MethodInfo;

    /// The id (`info().id`), used on the command line and in results.
    fn id(&self) -> &'static str {
        self.info().id
    }

    /// Every knob, with type, default, range, sweep, unit and meaning.
    fn knobs(&self) -> Vec<Knob>;

    /// Decided from the scene's features and the device's features alone.
    fn support(&self, scene: &SceneFeatures, device: wgpu::Features) -> Support;

    /// Builds tables, buffers and pipelines for `ctx.params` (a full set from
    /// [`resolve_params`]; read it with [`KnobRead::knob`]). Allocate GPU memory through
    /// `Gpu::buffer` / `Gpu::texture` so the harness can count it.
    fn prepare(&self, ctx: &PrepareContext) -> anyhow::Result<Box<dyn Prepared>>;

    /// The error this method promises on a `scatterbench stress` case (case names in
    /// `harness::stress::CASES`): a bound on the relative RMSE (RMSE / mean of the reference) of
    /// the `total` AOV at the method's default parameters. `None` (the default): only the
    /// no-panic, no-wgpu-error and no-non-finite-pixel criteria apply to that case.
    fn stress_bound(&self, case: &str) -> Option<f64> {
        let _ = case;
        None
    }

    /// How many frames an accumulating method needs at `params` before its image is the one it
    /// converges to; 0 (the default) for a method whose every frame is complete.
    fn converge_frames(&self, params: &Params) -> u32 {
        let _ = params;
        0
    }

    /// Every composed WGSL module the method can build, once per combination of the
    /// pipeline-overridable constants its knobs can give it (the conformance test validates
    /// each with naga, specialised).
    fn shaders(&self) -> Vec<ShaderCheck>;

    /// The cases the conformance test renders (methods/tests/conformance.rs).
    fn conformance(&self) -> Vec<ConformanceCase>;
}

/// A prepared method: the GPU state built by [`Method::prepare`] for one scene, parameter set
/// and resolution.
pub trait Prepared {
    /// Encodes one frame into `encoder` (the harness submits and times it). CPU-side work done
    /// here (silhouettes, sorting) is measured as the frame's CPU time.
    fn render(
        &mut self,
        gpu: &Gpu,
        frame: &FrameState,
        targets: &Targets,
        encoder: &mut wgpu::CommandEncoder,
    ) -> anyhow::Result<FrameReport>;

    /// The method's per-phase GPU timer, if it keeps one (`gpu::PhaseTimer`): after each frame
    /// the runner stores its phases as counters `gpu_ms_<phase>`. Default: none.
    fn phase_timer(&self) -> Option<&PhaseTimer> {
        None
    }
}

/// One composed WGSL module with the pipeline-overridable constants one of its pipelines sets.
/// Constants the module declares but that are absent here keep their WGSL defaults; scene
/// constants (`LIGHT_COUNT`, `PHASE_KIND`, … of `lights.wgsl` / `medium.wgsl`) are added by the
/// conformance test for every library scene.
#[derive(Clone, Debug)]
pub struct ShaderCheck {
    /// `method-id/module` plus the constants, for messages.
    pub name: String,
    pub source: String,
    pub constants: Vec<(&'static str, f64)>,
}

impl ShaderCheck {
    /// `source` once per element of the cartesian product of `axes` (constant name, the values
    /// the method can give it); no axes: once, with the WGSL defaults.
    pub fn combinations(
        name: &str,
        source: &str,
        axes: &[(&'static str, &[f64])],
    ) -> Vec<ShaderCheck> {
        let mut sets: Vec<Vec<(&'static str, f64)>> = vec![Vec::new()];
        for (key, values) in axes {
            sets = sets
                .into_iter()
                .flat_map(|set| {
                    values.iter().map(move |v| {
                        let mut s = set.clone();
                        s.push((*key, *v));
                        s
                    })
                })
                .collect();
        }
        sets.into_iter()
            .map(|constants| ShaderCheck {
                name: name.to_string(),
                source: source.to_string(),
                constants,
            })
            .collect()
    }
}

/// Which AOV a conformance bound is on.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Aov {
    Inscatter,
    Surface,
    Total,
}

/// One case of the conformance test: a library scene, a square resolution, knobs over the
/// defaults, and a bound on the relative RMSE of one AOV against the reference renderer. The
/// test also renders the case with `no_skip` and requires the same image (ARCHITECTURE §2.4).
#[derive(Clone, Debug)]
pub struct ConformanceCase {
    pub scene: &'static str,
    pub res: u32,
    pub knobs: Vec<(&'static str, ParamValue)>,
    pub aov: Aov,
    /// Upper bound on rel RMSE (RMSE / mean of the reference), measured and given a margin.
    pub max_rel_rmse: f64,
}

impl ConformanceCase {
    /// The case at the method's defaults.
    pub fn new(scene: &'static str, res: u32, aov: Aov, max_rel_rmse: f64) -> ConformanceCase {
        ConformanceCase {
            scene,
            res,
            knobs: Vec::new(),
            aov,
            max_rel_rmse,
        }
    }
    /// With one knob set (over the defaults).
    pub fn knob(mut self, name: &'static str, v: impl Into<ParamValue>) -> ConformanceCase {
        self.knobs.push((name, v.into()));
        self
    }
}

/// The full parameter set of `method`: every knob at its default, `overrides` applied after
/// checking their names, types, ranges and requirements (`crate::knobs::resolve`).
pub fn resolve_params(method: &dyn Method, overrides: &Params) -> Result<Params, KnobError> {
    knobs::resolve(method.id(), &method.knobs(), overrides)
}

/// Parses `name=text` for `method` as given on the command line, checked against its range.
pub fn parse_knob(method: &dyn Method, name: &str, text: &str) -> Result<ParamValue, KnobError> {
    knobs::parse(method.id(), &method.knobs(), name, text)
}

/// The parameter sets to run: the defaults with the overrides, and with `sweep` one set per
/// declared sweep value of each knob (the others at their base values; a value's requirements
/// set with it, `crate::knobs::sweep`).
pub fn param_sets(
    method: &dyn Method,
    overrides: &Params,
    sweep: bool,
) -> Result<Vec<Params>, KnobError> {
    knobs::sweep(method.id(), &method.knobs(), overrides, sweep)
}
