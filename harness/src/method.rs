//! The Method contract (DESIGN §2): what every technique implements, and what the harness gives
//! it. A method declares its knobs and what it supports; the harness owns timing, read-back and
//! metrics — a method never times itself.

use std::collections::BTreeMap;

use scenes::{FrameState, Scene, SceneFeatures};
use serde::{Deserialize, Serialize};

use crate::gpu::Gpu;

/// Who a method is.
#[derive(Clone, Debug, Serialize)]
pub struct MethodInfo {
    /// Stable id used on the command line and in results (`raymarch-brute`).
    pub id: &'static str,
    /// The paper (authors, title, venue, year), or "baseline".
    pub paper: &'static str,
    pub summary: &'static str,
}

/// A knob value. Untagged in JSON: 64, 0.5, true, "float".
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq, PartialOrd)]
#[serde(untagged)]
pub enum ParamValue {
    Bool(bool),
    Int(i64),
    Float(f64),
    Text(String),
}

impl ParamValue {
    pub fn as_i64(&self) -> Option<i64> {
        match self {
            ParamValue::Int(i) => Some(*i),
            ParamValue::Float(f) if f.fract() == 0.0 => Some(*f as i64),
            _ => None,
        }
    }
    pub fn as_f64(&self) -> Option<f64> {
        match self {
            ParamValue::Int(i) => Some(*i as f64),
            ParamValue::Float(f) => Some(*f),
            _ => None,
        }
    }
    pub fn as_bool(&self) -> Option<bool> {
        match self {
            ParamValue::Bool(b) => Some(*b),
            _ => None,
        }
    }
    pub fn as_str(&self) -> Option<&str> {
        match self {
            ParamValue::Text(s) => Some(s),
            _ => None,
        }
    }
    /// Parses a command-line value like the one declared (`64`, `0.5`, `true`, `float`).
    pub fn parse_like(text: &str, like: &ParamValue) -> Result<ParamValue, String> {
        match like {
            ParamValue::Bool(_) => text
                .parse()
                .map(ParamValue::Bool)
                .map_err(|_| format!("'{text}' is not true/false")),
            ParamValue::Int(_) => text
                .parse()
                .map(ParamValue::Int)
                .map_err(|_| format!("'{text}' is not an integer")),
            ParamValue::Float(_) => text
                .parse()
                .map(ParamValue::Float)
                .map_err(|_| format!("'{text}' is not a number")),
            ParamValue::Text(_) => Ok(ParamValue::Text(text.to_string())),
        }
    }
}

impl std::fmt::Display for ParamValue {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            ParamValue::Bool(b) => write!(f, "{b}"),
            ParamValue::Int(i) => write!(f, "{i}"),
            ParamValue::Float(x) => write!(f, "{x}"),
            ParamValue::Text(s) => write!(f, "{s}"),
        }
    }
}

/// One knob: its default, the values `--sweep` runs, and what it means (with units).
#[derive(Clone, Debug, Serialize)]
pub struct ParamSpec {
    pub name: &'static str,
    pub default: ParamValue,
    pub sweep: Vec<ParamValue>,
    /// Allowed text values (for Text knobs); empty = free.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub choices: Vec<&'static str>,
    pub meaning: &'static str,
}

/// Knob name → value; a full set (defaults filled in) is what a record carries.
pub type Params = BTreeMap<String, ParamValue>;

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

/// A pass the method did not run this frame, and why (DESIGN §2, "skip what a scene doesn't need").
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
/// linear radiance to all three (DESIGN §1: inscatter, surface, total).
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

pub trait Method {
    fn info(&self) -> MethodInfo;
    fn params(&self) -> Vec<ParamSpec>;
    /// Decided from the scene's features and the device's features alone.
    fn support(&self, scene: &SceneFeatures, device: wgpu::Features) -> Support;
    /// Builds tables, buffers and pipelines. Allocate GPU memory through `Gpu::buffer` /
    /// `Gpu::texture` so the harness can count it.
    fn prepare(&mut self, ctx: &PrepareContext) -> anyhow::Result<()>;
    /// Encodes one frame into `encoder` (the harness submits and times it). CPU-side work done
    /// here (silhouettes, sorting) is measured as the frame's CPU time.
    fn render(
        &mut self,
        gpu: &Gpu,
        frame: &FrameState,
        targets: &Targets,
        encoder: &mut wgpu::CommandEncoder,
    ) -> anyhow::Result<FrameReport>;

    /// The error this method promises on a `scatterbench stress` case (case names in
    /// `harness::stress::CASES`): a bound on the relative RMSE (RMSE / mean of the reference) of
    /// the `total` AOV at the method's default parameters. `None` (the default): only the
    /// no-panic, no-wgpu-error and no-non-finite-pixel criteria apply to that case.
    fn stress_bound(&self, case: &str) -> Option<f64> {
        let _ = case;
        None
    }

    /// The method's per-phase GPU timer, if it keeps one (`gpu::PhaseTimer`): after each frame
    /// the runner stores its phases as counters `gpu_ms_<phase>`. Default: none.
    fn phase_timer(&self) -> Option<&crate::gpu::PhaseTimer> {
        None
    }
}

/// A registry entry: the id and a constructor.
pub struct Entry {
    pub id: &'static str,
    pub make: fn() -> Box<dyn Method>,
}

/// Fills in defaults, checks names and types of overrides against the declared knobs.
pub fn resolve_params(specs: &[ParamSpec], overrides: &Params) -> Result<Params, String> {
    let mut p: Params = specs
        .iter()
        .map(|s| (s.name.to_string(), s.default.clone()))
        .collect();
    for (k, v) in overrides {
        let Some(spec) = specs.iter().find(|s| s.name == k) else {
            let names: Vec<&str> = specs.iter().map(|s| s.name).collect();
            return Err(format!(
                "unknown knob '{k}'; knobs are: {}",
                if names.is_empty() {
                    "(none)".to_string()
                } else {
                    names.join(", ")
                }
            ));
        };
        let ok = matches!(
            (&spec.default, v),
            (ParamValue::Bool(_), ParamValue::Bool(_))
                | (ParamValue::Int(_), ParamValue::Int(_))
                | (
                    ParamValue::Float(_),
                    ParamValue::Float(_) | ParamValue::Int(_)
                )
                | (ParamValue::Text(_), ParamValue::Text(_))
        );
        if !ok {
            return Err(format!(
                "knob '{k}': {v} does not have the type of its default {}",
                spec.default
            ));
        }
        if let ParamValue::Text(t) = v
            && !spec.choices.is_empty()
            && !spec.choices.contains(&t.as_str())
        {
            return Err(format!(
                "knob '{k}': '{t}' is not one of {}",
                spec.choices.join(", ")
            ));
        }
        p.insert(k.clone(), v.clone());
    }
    Ok(p)
}
