//! `no-scatter`: the classic OpenGL fog model — surfaces attenuated by e^(−σ_t d) (plus the
//! ambient term), no in-scattered light at all. Not a paper's method: the floor that shows what
//! ignoring single scattering costs, in error, against the methods that compute it.
//!
//! It shares the forward surface pass and shadow maps with the other rasterising methods, so
//! its `surface` AOV is directly comparable; its `inscatter` AOV is zero by construction.

use anyhow::Result;
use harness::method::PrepareContext;
use harness::{FrameReport, Gpu, Method, MethodInfo, ParamSpec, ParamValue, Support, Targets};
use scenes::{FrameState, SceneFeatures};

use crate::common::renderer::{SceneRenderer, unsupported};
use crate::common::resolve::ResolvePass;

pub const RESOLVE_WGSL: &str = include_str!("resolve.wgsl");

#[derive(Default)]
pub struct NoScatter {
    state: Option<(SceneRenderer, ResolvePass)>,
}

impl Method for NoScatter {
    fn info(&self) -> MethodInfo {
        MethodInfo {
            id: "no-scatter",
            paper: "baseline (fixed-function fog: attenuation only)",
            summary: "Attenuated surfaces, no in-scattering",
        }
    }

    fn params(&self) -> Vec<ParamSpec> {
        vec![ParamSpec {
            name: "shadow_map",
            default: ParamValue::Int(1024),
            sweep: vec![],
            choices: vec![],
            meaning: "shadow-map resolution per face for surface shadows, texels",
        }]
    }

    fn support(&self, scene: &SceneFeatures, _device: wgpu::Features) -> Support {
        match unsupported(scene) {
            Some(why) => Support::No(why),
            None => Support::Full,
        }
    }

    fn prepare(&mut self, ctx: &PrepareContext) -> Result<()> {
        let size = ctx
            .params
            .get("shadow_map")
            .and_then(ParamValue::as_i64)
            .unwrap_or(1024)
            .clamp(16, 8192) as u32;
        let renderer = SceneRenderer::new(ctx, size, 256)?;
        let resolve = ResolvePass::new(ctx.gpu, &renderer, "fog resolve", RESOLVE_WGSL, None);
        self.state = Some((renderer, resolve));
        Ok(())
    }

    fn render(
        &mut self,
        gpu: &Gpu,
        frame: &FrameState,
        targets: &Targets,
        enc: &mut wgpu::CommandEncoder,
    ) -> Result<FrameReport> {
        let (renderer, resolve) = self
            .state
            .as_mut()
            .ok_or_else(|| anyhow::anyhow!("render before prepare"))?;
        let mut report = FrameReport::default();
        renderer.update(gpu, frame);
        renderer.encode_shadows(enc, &mut report);
        renderer.encode_surface(enc, targets, &mut report);
        resolve.encode(gpu, enc, renderer, targets);
        report.ran("fog-resolve");
        Ok(report)
    }
}
