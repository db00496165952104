//! Robustness from the outside: the CLI under SIGKILL and `--resume`, unwritable output,
//! unknown names; the reference cache with a corrupt entry; methods that raise a wgpu
//! validation error or lose the device are recorded as failed and the run goes on.

use harness::testing::{gpu_or_skip as have_gpu, temp_dir as tmp};
use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use harness::Gpu;
use harness::method::{
    ConformanceCase, FrameReport, Knob, Method, MethodInfo, PrepareContext, Prepared, ShaderCheck,
    Support, Targets,
};
use harness::reference::{self, Settings, cache};
use harness::results::{Results, Status};
use harness::stress::{self, StressConfig};
use scenes::{FrameState, SceneFeatures};

mod common;
use common::{BIN, cli};

/// Kills `scatterbench run` with SIGKILL once results.json holds a finished record: the file
/// left behind is a valid results file with every record finished so far; `--resume` completes
/// the run, keeping those records as they were and recording the one in flight as interrupted;
/// `--resume --retry-failed` runs that one again.
#[test]
fn sigkill_mid_run_leaves_valid_results_and_resume_completes_them() {
    if have_gpu().is_none() {
        return;
    }
    let out = tmp("kill");
    let cache = tmp("kill-cache");
    let args = |resume: bool| {
        let mut a = vec![
            "run",
            "--scenes",
            "clear-fog,sphere-point,fence-spot",
            "--methods",
            "no-scatter,raymarch-brute",
            "--res",
            "32",
            "--frames",
            "2",
            "--warmup",
            "0",
            "--out",
            out.to_str().unwrap(),
            "--cache",
            cache.to_str().unwrap(),
        ]
        .into_iter()
        .map(String::from)
        .collect::<Vec<_>>();
        if resume {
            a.push("--resume".into());
        }
        a
    };
    let mut child = Command::new(BIN)
        .args(args(false))
        .env("NODEVICE_SELECT", "1")
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let path = out.join("results.json");
    let start = Instant::now();
    let killed_at = loop {
        if let Ok(r) = Results::load(&path)
            && !r.records.is_empty()
        {
            child.kill().unwrap(); // SIGKILL on Unix
            break r.records.len();
        }
        if let Some(st) = child.try_wait().unwrap() {
            panic!("the run ended ({st}) before it could be killed");
        }
        assert!(
            start.elapsed() < Duration::from_secs(300),
            "no record after 300 s"
        );
        std::thread::sleep(Duration::from_millis(20));
    };
    child.wait().unwrap();
    let after_kill = Results::load(&path).expect("results.json is valid after SIGKILL");
    assert!(after_kill.records.len() >= killed_at);
    assert!(
        after_kill.records.len() < 6,
        "the kill came too late to test resume"
    );
    let (code, err) = cli(&args(true).iter().map(String::as_str).collect::<Vec<_>>());
    assert_eq!(code, 0, "{err}");
    let done = Results::load(&path).unwrap();
    assert_eq!(done.records.len(), 6, "3 scenes × 2 methods");
    assert_eq!(
        &done.records[..after_kill.records.len()],
        &after_kill.records[..],
        "finished records kept"
    );
    let mut keys: Vec<String> = done.records.iter().map(|r| r.key()).collect();
    keys.sort();
    keys.dedup();
    assert_eq!(keys.len(), 6, "no record twice");
    // The record in flight when the run was killed is recorded as interrupted, never re-run
    // (a crash must not repeat forever: ARCHITECTURE §9.2); every other record is ok.
    let interrupted = |r: &harness::results::Record| {
        r.status == Status::Failed
            && r.reason
                .as_deref()
                .is_some_and(|m| m.starts_with("interrupted"))
    };
    assert!(
        done.records
            .iter()
            .all(|r| r.status == Status::Ok || interrupted(r)),
        "{:?}",
        done.records
    );
    assert!(done.records.iter().filter(|r| interrupted(r)).count() <= 1);
    // --retry-failed runs it again, in place.
    let mut retry = args(true);
    retry.push("--retry-failed".into());
    let (code, err) = cli(&retry.iter().map(String::as_str).collect::<Vec<_>>());
    assert_eq!(code, 0, "{err}");
    let retried = Results::load(&path).unwrap();
    assert_eq!(retried.records.len(), 6);
    assert!(
        retried.records.iter().all(|r| r.status == Status::Ok),
        "{:?}",
        retried.records
    );
}

#[test]
fn an_unwritable_output_directory_is_a_clear_error() {
    if have_gpu().is_none() {
        return;
    }
    // A directory under a regular file cannot be created, even by root.
    let dir = tmp("unwritable");
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("a-file");
    std::fs::write(&file, "x").unwrap();
    let out = file.join("out");
    for cmd in ["run", "stress"] {
        let mut args = vec![
            cmd,
            "--methods",
            "no-scatter",
            "--res",
            "16",
            "--out",
            out.to_str().unwrap(),
        ];
        if cmd == "run" {
            args.extend(["--scenes", "clear-fog", "--frames", "1", "--warmup", "0"]);
        } else {
            args.extend(["--cases", "sigma-t-1e-6"]);
        }
        let (code, err) = cli(&args);
        assert_eq!(code, 1, "{cmd}: {err}");
        assert!(
            err.contains("cannot create the output directory"),
            "{cmd}: {err}"
        );
        assert!(!err.contains("panicked"), "{cmd}: {err}");
    }
}

/// Unknown names are bad input: exit 2 (ARCHITECTURE §8.3), like every refused argument.
#[test]
fn unknown_names_are_refused_with_the_valid_ones() {
    let (code, err) = cli(&[
        "run",
        "--scenes",
        "no-such-scene",
        "--methods",
        "no-scatter",
    ]);
    assert_eq!(code, 2, "{err}");
    for name in scenes::library::names() {
        assert!(err.contains(name), "{err}");
    }
    for (cmd, extra) in [
        ("run", ["--scenes", "clear-fog"]),
        ("stress", ["--cases", "all"]),
    ] {
        let (code, err) = cli(&[cmd, "--methods", "no-such-method", extra[0], extra[1]]);
        assert_eq!(code, 2, "{cmd}: {err}");
        for e in methods::REGISTRY {
            assert!(err.contains(e.id()), "{cmd}: {err}");
        }
    }
    let (code, err) = cli(&["stress", "--cases", "no-such-case"]);
    assert_eq!(code, 2, "{err}");
    for c in stress::names() {
        assert!(err.contains(c), "{err}");
    }
    let (code, err) = cli(&["reference", "--scene", "no-such-scene"]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("sphere-point"), "{err}");
}

fn truncate(p: &Path) {
    let bytes = std::fs::read(p).unwrap();
    std::fs::write(p, &bytes[..bytes.len() / 2]).unwrap();
}

/// A cached reference whose images file was truncated is not trusted: it is recomputed, the
/// images equal a fresh render, and the entry is whole again afterwards.
#[test]
fn a_corrupt_cache_entry_is_recomputed_not_trusted() {
    let scene = scenes::library::resolve("sphere-point").unwrap();
    let dir = tmp("cache");
    let (w, h, s) = (24, 16, Settings::default());
    let (first, cached) = cache::render_cached(Some(&dir), &scene, 0, w, h, s, &|_| {}).unwrap();
    assert!(!cached);
    let (_, cached) = cache::render_cached(Some(&dir), &scene, 0, w, h, s, &|_| {}).unwrap();
    assert!(cached, "a whole entry is used");
    let key = cache::key(&scene, 0, w, h, &s);
    let file = "images.sbref";
    truncate(&dir.join(&key).join(file));
    assert!(
        cache::load(&dir, &key).is_none(),
        "{file} truncated but the entry loads"
    );
    let (again, cached) = cache::render_cached(Some(&dir), &scene, 0, w, h, s, &|_| {}).unwrap();
    assert!(!cached, "{file} truncated but the entry was trusted");
    let fresh = reference::render(&scene, 0, w, h, s, &|_| {}).unwrap();
    for (a, b) in [
        (&again.inscatter, &fresh.inscatter),
        (&again.total, &fresh.total),
        (&again.surface, &fresh.surface),
    ] {
        assert_eq!(a.pixels, b.pixels);
    }
    assert_eq!(again.total.pixels, first.total.pixels);
    assert!(
        cache::load(&dir, &key).is_some(),
        "the entry is rewritten whole"
    );
    // Garbage in stats.json: not trusted either.
    std::fs::write(dir.join(&key).join("stats.json"), "{not json").unwrap();
    assert!(cache::load(&dir, &key).is_none());
}

/// Test-only methods: one whose render encodes a render pass with mismatched attachment sizes
/// (a wgpu validation error), one that destroys the device.
struct Faulty {
    lose_device: bool,
}

impl Method for Faulty {
    fn info(&self) -> MethodInfo {
        MethodInfo {
            id: if self.lose_device {
                "test-device-lost"
            } else {
                "test-validation"
            },
            paper: "test",
            summary: "fails on purpose",
            baseline: false,
            medium: harness::Medium::Both,
            readme: "",
            source: "",
        }
    }
    fn knobs(&self) -> Vec<Knob> {
        vec![]
    }
    fn support(&self, _: &SceneFeatures, _: wgpu::Features) -> Support {
        Support::Full
    }
    fn prepare(&self, _: &PrepareContext) -> anyhow::Result<Box<dyn Prepared>> {
        Ok(Box::new(Faulty {
            lose_device: self.lose_device,
        }))
    }
    fn shaders(&self) -> Vec<ShaderCheck> {
        vec![]
    }
    fn conformance(&self) -> Vec<ConformanceCase> {
        vec![]
    }
}

impl Prepared for Faulty {
    fn render(
        &mut self,
        gpu: &Gpu,
        _: &FrameState,
        t: &Targets,
        enc: &mut wgpu::CommandEncoder,
    ) -> anyhow::Result<FrameReport> {
        if self.lose_device {
            gpu.device.destroy();
            return Ok(FrameReport::default());
        }
        let small = gpu.device.create_texture(&wgpu::TextureDescriptor {
            label: Some("mismatched"),
            size: wgpu::Extent3d {
                width: 1,
                height: 1,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: harness::method::AOV_FORMAT,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT,
            view_formats: &[],
        });
        let small = small.create_view(&Default::default());
        let att = |v| {
            Some(wgpu::RenderPassColorAttachment {
                view: v,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(wgpu::Color::BLACK),
                    store: wgpu::StoreOp::Store,
                },
            })
        };
        let _ = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("mismatched attachments"),
            color_attachments: &[att(t.inscatter), att(&small)],
            ..Default::default()
        });
        Ok(FrameReport::default())
    }
}

static VALIDATION: Faulty = Faulty { lose_device: false };
static DEVICE_LOST: Faulty = Faulty { lose_device: true };

/// A wgpu validation error and a lost device are each recorded as failed with the message, and
/// the run goes on: the next method's record (on a fresh device after the loss) is ok.
#[test]
fn validation_errors_and_device_loss_are_recorded_as_failed() {
    let Some(mut gpu) = have_gpu() else { return };
    let out = tmp("faulty");
    let cfg = StressConfig {
        record: stress::one_frame(&out, (16, 16)),
        cases: vec![stress::find("sigma-t-1e-6").unwrap()],
        triangles: 1000,
        particles: 1000,
        resume: false,
        run_id: "test".into(),
        isolation: Default::default(),
    };
    let no_scatter = methods::find("no-scatter").unwrap();
    let r = stress::run(
        &mut gpu,
        &[&VALIDATION, no_scatter, &DEVICE_LOST, no_scatter],
        &cfg,
        &mut |_| {},
    )
    .unwrap();
    // no-scatter twice is one record (the second is the resumed first): 3 records.
    let by = |id: &str| r.records.iter().find(|x| x.method == id).unwrap();
    let v = by("test-validation");
    assert_eq!(v.status, Status::Failed);
    assert!(
        v.reason.as_deref().unwrap().contains("Validation"),
        "{:?}",
        v.reason
    );
    let l = by("test-device-lost");
    assert_eq!(l.status, Status::Failed);
    assert!(
        l.reason.as_deref().unwrap().to_lowercase().contains("lost"),
        "{:?}",
        l.reason
    );
    assert_eq!(by("no-scatter").status, Status::Ok);
    // The run goes on after the loss, on a working device.
    let again = stress::run(
        &mut gpu,
        &[no_scatter],
        &StressConfig {
            record: stress::one_frame(tmp("faulty2"), (16, 16)),
            ..cfg
        },
        &mut |_| {},
    )
    .unwrap();
    assert_eq!(
        again.records[0].status,
        Status::Ok,
        "{:?}",
        again.records[0].reason
    );
    assert_eq!(Results::load(&out.join("results.json")).unwrap(), r);
}

/// With `--paired-floor`, the floor timed after a record does not take the record's own wgpu
/// errors with it: the faulty method's record still fails with the validation message, and
/// the floor's own record is ok.
#[test]
fn a_paired_floor_leaves_the_methods_validation_error_in_its_record() {
    let Some(gpu) = have_gpu() else { return };
    let mut record = harness::record::RecordSettings::new(tmp("faulty-paired"), (16, 16), (1, 0));
    record.paired_floor = Some("no-scatter".into());
    let cfg = harness::runner::RunConfig::new(record, "test");
    let scene = scenes::library::resolve("clear-fog").expect("library scene");
    let no_scatter = methods::find("no-scatter").unwrap();
    let r = harness::runner::run(
        &gpu,
        &[scene],
        &[&VALIDATION, no_scatter],
        &cfg,
        &mut |_| {},
    )
    .unwrap();
    let by = |id: &str| r.records.iter().find(|x| x.method == id).unwrap();
    let v = by("test-validation");
    assert_eq!(v.status, Status::Failed, "{:?}", v.timing);
    assert!(
        v.reason.as_deref().unwrap().contains("Validation"),
        "{:?}",
        v.reason
    );
    assert_eq!(by("no-scatter").status, Status::Ok);
}
