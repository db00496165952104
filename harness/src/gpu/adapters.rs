//! Which adapter a run renders on (ARCHITECTURE §7): every adapter wgpu can see, described with
//! the features the suite uses, and the rule that picks one.
//!
//! The choice is a [`DeviceChoice`]: an adapter name (a case-insensitive substring, from
//! `--adapter` or `WGPU_ADAPTER_NAME`) and whether the Khronos validation layer is on
//! (`--validate` or `WGPU_VALIDATION=1`). Worker processes receive it through their environment
//! ([`DeviceChoice::worker_env`]), so a record renders on the same adapter in or out of a worker.
//!
//! Without a name the best adapter wins: hardware before software (discrete, integrated,
//! virtual, CPU), then Vulkan/Metal/DX12 before GL (the GL backend lacks float32 blending and
//! stencil read-back), then SwiftShader last among equals, so that lavapipe stays the default
//! software adapter where both are present.

use std::ffi::OsString;

use serde::{Deserialize, Serialize};

/// Debian's chromium ships SwiftShader's Vulkan driver here; [`add_known_drivers`] adds it to
/// the loader's search.
pub const SWIFTSHADER_ICD: &str = "/usr/lib/chromium/vk_swiftshader_icd.json";
/// Set to 1 to leave the Vulkan loader's driver search alone (no SwiftShader added).
pub const NO_EXTRA_DRIVERS_ENV: &str = "SCATTERBENCH_NO_EXTRA_DRIVERS";
const ADAPTER_ENV: &str = "WGPU_ADAPTER_NAME";
const VALIDATION_ENV: &str = "WGPU_VALIDATION";

/// The fix to print when no adapter is found.
pub const NO_ADAPTER_HELP: &str = "no GPU adapter found. On a machine without a GPU install Mesa's software Vulkan driver \
(lavapipe): `apt-get install -y mesa-vulkan-drivers` (Debian/Ubuntu). WGPU_BACKEND=vulkan|gl and --adapter <substring> \
(or WGPU_ADAPTER_NAME) select an adapter; `scatterbench adapters` lists them.";

/// The fix to print when validation was asked for and the layer is absent.
pub const VALIDATION_HELP: &str = "validation was asked for (--validate or WGPU_VALIDATION=1) but the Khronos validation \
layer (VK_LAYER_KHRONOS_validation) is not installed: `apt-get install -y vulkan-validationlayers` (Debian/Ubuntu).";

/// The adapter and validation a process renders with.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct DeviceChoice {
    /// A case-insensitive substring of the adapter's name; None: the best adapter.
    pub adapter: Option<String>,
    /// Run with the Khronos validation layer and record its messages.
    pub validate: bool,
}

impl DeviceChoice {
    /// `WGPU_ADAPTER_NAME` and `WGPU_VALIDATION` (anything but "0" turns validation on).
    pub fn from_env() -> DeviceChoice {
        DeviceChoice {
            adapter: std::env::var(ADAPTER_ENV).ok().filter(|s| !s.is_empty()),
            validate: std::env::var(VALIDATION_ENV).is_ok_and(|v| v != "0"),
        }
    }

    /// The environment that makes a worker process choose the same (read by
    /// [`DeviceChoice::from_env`] there).
    pub fn worker_env(&self) -> Vec<(OsString, OsString)> {
        let mut env = Vec::new();
        if let Some(name) = &self.adapter {
            env.push((ADAPTER_ENV.into(), name.into()));
        }
        env.push((
            VALIDATION_ENV.into(),
            if self.validate { "1" } else { "0" }.into(),
        ));
        env
    }
}

/// The optional features the suite uses, as an adapter offers them.
#[derive(Clone, Debug, Default, Serialize, Deserialize, PartialEq)]
pub struct SuiteFeatures {
    /// Timestamp queries, also inside encoders: `gpu_ms` and phase timers (§4.1).
    pub timestamps: bool,
    /// Pipeline-statistics queries: the work counters (§4.1).
    pub pipeline_statistics: bool,
    /// Unclipped depth: shadow planes in front of the near plane are still counted (§6).
    pub depth_clip_control: bool,
    /// Additive blending into float32 targets (most methods' accumulation).
    pub float32_blending: bool,
}

impl SuiteFeatures {
    pub fn of(f: wgpu::Features) -> SuiteFeatures {
        SuiteFeatures {
            timestamps: f.contains(
                wgpu::Features::TIMESTAMP_QUERY | wgpu::Features::TIMESTAMP_QUERY_INSIDE_ENCODERS,
            ),
            pipeline_statistics: f.contains(wgpu::Features::PIPELINE_STATISTICS_QUERY),
            depth_clip_control: f.contains(wgpu::Features::DEPTH_CLIP_CONTROL),
            float32_blending: f.contains(wgpu::Features::FLOAT32_BLENDABLE),
        }
    }
}

/// What adapter a result was measured on (ARCHITECTURE §4.3: every record's run carries the
/// machine).
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq, Default)]
pub struct AdapterSummary {
    pub adapter: String,
    pub backend: String,
    pub driver: String,
    pub driver_info: String,
    pub device_type: String,
    /// True for software rasterisers (lavapipe, llvmpipe, SwiftShader, WARP): their timings
    /// compare only as ratios within one run.
    pub software: bool,
}

impl AdapterSummary {
    pub fn of(i: &wgpu::AdapterInfo) -> AdapterSummary {
        AdapterSummary {
            adapter: i.name.clone(),
            backend: backend_name(i),
            driver: i.driver.clone(),
            driver_info: i.driver_info.clone(),
            device_type: format!("{:?}", i.device_type),
            software: is_software(i),
        }
    }
}

/// "vulkan", "gl", … as results and listings write it.
fn backend_name(i: &wgpu::AdapterInfo) -> String {
    format!("{:?}", i.backend).to_lowercase()
}

/// One adapter as `scatterbench adapters` lists it.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct AdapterReport {
    pub name: String,
    pub backend: String,
    pub driver: String,
    pub driver_info: String,
    pub device_type: String,
    /// A software rasteriser (lavapipe/llvmpipe, SwiftShader, WARP): its timings compare only
    /// as ratios within one run.
    pub software: bool,
    pub features: SuiteFeatures,
    /// Whether it is the one a run picks without `--adapter`.
    pub default: bool,
}

/// Whether an adapter is a software rasteriser.
pub fn is_software(info: &wgpu::AdapterInfo) -> bool {
    info.device_type == wgpu::DeviceType::Cpu
        || ["llvmpipe", "lavapipe", "swiftshader", "warp"]
            .iter()
            .any(|s| info.name.to_lowercase().contains(s))
}

/// The instance every adapter comes from: the backends of `WGPU_BACKEND` (default all), with
/// validation as chosen. Validation needs wgpu's DEBUG flag too: without it wgpu-hal creates
/// no debug messenger and the layer's messages never reach [`super::validation`].
pub fn instance(validate: bool) -> wgpu::Instance {
    let mut desc = wgpu::InstanceDescriptor::new_without_display_handle_from_env();
    let flags = wgpu::InstanceFlags::VALIDATION | wgpu::InstanceFlags::DEBUG;
    desc.flags.set(flags, validate);
    if validate {
        super::validation::while_creating_instance(|| wgpu::Instance::new(desc))
    } else {
        wgpu::Instance::new(desc)
    }
}

/// Every adapter of the instance, best first (see the module doc for the order).
pub fn ranked(instance: &wgpu::Instance) -> Vec<wgpu::Adapter> {
    let mut adapters = pollster::block_on(instance.enumerate_adapters(wgpu::Backends::all()));
    adapters.sort_by_key(|a| std::cmp::Reverse(rank(&a.get_info())));
    adapters
}

fn rank(i: &wgpu::AdapterInfo) -> (u8, u8, u8) {
    let ty = match i.device_type {
        wgpu::DeviceType::DiscreteGpu => 4,
        wgpu::DeviceType::IntegratedGpu => 3,
        wgpu::DeviceType::VirtualGpu => 2,
        wgpu::DeviceType::Cpu => 1,
        wgpu::DeviceType::Other => 0,
    };
    let backend = match i.backend {
        wgpu::Backend::Vulkan | wgpu::Backend::Metal | wgpu::Backend::Dx12 => 1,
        _ => 0,
    };
    let not_swiftshader = u8::from(!i.name.to_lowercase().contains("swiftshader"));
    (ty, backend, not_swiftshader)
}

/// The adapter a choice names (the best one whose name contains it), or the best of all.
/// The error lists the adapters found.
pub fn choose(ranked: Vec<wgpu::Adapter>, name: Option<&str>) -> Result<wgpu::Adapter, String> {
    if ranked.is_empty() {
        return Err(NO_ADAPTER_HELP.to_string());
    }
    let Some(name) = name else {
        return Ok(ranked.into_iter().next().expect("non-empty"));
    };
    let wanted = name.to_lowercase();
    let names: Vec<String> = ranked.iter().map(|a| describe(&a.get_info())).collect();
    ranked
        .into_iter()
        .find(|a| a.get_info().name.to_lowercase().contains(&wanted))
        .ok_or_else(|| {
            format!(
                "adapter '{name}': no adapter's name contains it; found: {}",
                names.join("; ")
            )
        })
}

/// "name (backend, device type)".
pub fn describe(i: &wgpu::AdapterInfo) -> String {
    format!("{} ({}, {:?})", i.name, backend_name(i), i.device_type)
}

/// Every adapter wgpu can see, best first; `default` marks the one a run picks without a name.
pub fn list() -> Vec<AdapterReport> {
    ranked(&instance(false))
        .iter()
        .enumerate()
        .map(|(k, a)| report(a, k == 0))
        .collect()
}

fn report(a: &wgpu::Adapter, default: bool) -> AdapterReport {
    let s = AdapterSummary::of(&a.get_info());
    AdapterReport {
        name: s.adapter,
        backend: s.backend,
        driver: s.driver,
        driver_info: s.driver_info,
        device_type: s.device_type,
        software: s.software,
        features: SuiteFeatures::of(a.features()),
        default,
    }
}

/// Adds SwiftShader (Debian chromium's Vulkan driver, [`SWIFTSHADER_ICD`]) to the Vulkan
/// loader's search through `VK_ADD_DRIVER_FILES`, so `--adapter swiftshader` finds it with no
/// setup. Left alone when the file is absent, when `VK_DRIVER_FILES` or `VK_ICD_FILENAMES`
/// pins the drivers, or when `SCATTERBENCH_NO_EXTRA_DRIVERS=1`.
///
/// # Safety
/// Changes the process environment: call it before any other thread exists (first thing in
/// `main`); worker processes inherit it.
pub unsafe fn add_known_drivers() {
    let set = |k: &str| std::env::var_os(k).is_some_and(|v| !v.is_empty());
    if set("VK_DRIVER_FILES")
        || set("VK_ICD_FILENAMES")
        || std::env::var(NO_EXTRA_DRIVERS_ENV).is_ok_and(|v| v != "0")
        || !std::path::Path::new(SWIFTSHADER_ICD).is_file()
    {
        return;
    }
    let mut files = std::env::var_os("VK_ADD_DRIVER_FILES").unwrap_or_default();
    if files
        .to_string_lossy()
        .split(':')
        .any(|f| f == SWIFTSHADER_ICD)
    {
        return;
    }
    if !files.is_empty() {
        files.push(":");
    }
    files.push(SWIFTSHADER_ICD);
    // SAFETY: the caller guarantees no other thread reads or writes the environment now.
    unsafe { std::env::set_var("VK_ADD_DRIVER_FILES", files) };
}
