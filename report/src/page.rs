//! The whole page's model, as the template sees it.

use serde::Serialize;

use crate::matrix::Matrix;
use crate::metric::MetricView;
use crate::verdict::VerdictTable;
use crate::view::{Counts, SceneView};

#[derive(Serialize)]
pub struct Page {
    pub title: String,
    pub run: harness::results::RunInfo,
    /// The adapter's calibration as one line (`calibration::text`), where the run has one.
    pub calibration: Option<String>,
    pub counts: Counts,
    /// The metrics the reader can switch between; the first is the verdict metric.
    pub metrics: Vec<MetricView>,
    /// Per metric: the verdict table (same order as `metrics`).
    pub verdicts: Vec<VerdictTable>,
    pub matrix: Matrix,
    /// Every method of the run with its paper, summary, medium and baseline flag.
    pub methods: Vec<crate::methods::MethodRow>,
    pub scenes: Vec<SceneView>,
    /// The tune's verdicts, for a `scatterbench tune` run only.
    pub tune: Option<crate::tune::TuneView>,
    /// The stability table, for a stress run only.
    pub stability: Option<crate::stability::Stability>,
    /// The scaling sweeps, for a `scatterbench scaling` run only.
    pub scaling: Option<crate::scaling::ScalingView>,
    /// Error vs each swept numeric knob (empty without a sweep).
    pub knobs: Vec<crate::knobs::KnobPlot>,
    pub budgets: Vec<String>,
    pub generator: String,
    /// The viewer's script (inlined; no network).
    pub script: &'static str,
}
