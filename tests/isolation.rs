//! Process isolation (issue 23), end to end: test-only methods compiled into this binary —
//! one aborts in `render`, one never returns from `render`, one exits in `prepare`, two wait
//! on a gate file — run next to real methods with this binary as its own worker (it serves
//! [`REGISTRY`] when started as a worker). Also: workers killed or stopped from outside, the
//! parent killed and the run resumed, and every command writing into a closed pipe.
//!
//! A custom harness (`harness = false`): a worker speaks its protocol on the stdout it
//! inherits, so no test framework may print there first. Run one test by naming it:
//! `cargo test --release --test isolation -- resume`.

use std::io::Read;
use std::os::fd::{FromRawFd, OwnedFd};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::Duration;

use harness::Gpu;
use harness::isolate::marker::{self, InFlight};
use harness::isolate::{Isolation, Phase, Reuse, WorkerCommand, worker};
use harness::method::{
    ConformanceCase, FrameReport, Knob, Method, MethodInfo, Params, PrepareContext, Prepared,
    ShaderCheck, Support, Targets, resolve_params,
};
use harness::results::{Record, Results, Status};
use harness::runner::{WorkItem, run_items};
use scenes::{FrameState, SceneFeatures};

/// Where the gate methods look for their gate file (set in the worker's environment).
const GATE_ENV: &str = "ISOLATION_TEST_GATE";
/// Set (to an output directory) when this binary is started as a parent that will be killed.
const PARENT_ENV: &str = "ISOLATION_TEST_PARENT";

#[derive(Clone, Copy)]
enum Misbehave {
    AbortInRender,
    HangInRender,
    ExitInPrepare,
    GateInPrepare,
    GateInRender,
}

/// A test-only method: `misbehave` says how. The gate methods wait on the gate file.
struct TestMethod {
    id: &'static str,
    misbehave: Misbehave,
}

fn wait_for_gate() {
    let gate = PathBuf::from(std::env::var_os(GATE_ENV).expect("gate path in the environment"));
    while !gate.exists() {
        std::thread::sleep(Duration::from_millis(20));
    }
}

/// What a test method's `prepare` returns: renders nothing (or misbehaves).
struct TestState(Misbehave);

impl Method for TestMethod {
    fn info(&self) -> MethodInfo {
        MethodInfo {
            id: self.id,
            paper: "test only",
            summary: "misbehaves on purpose",
            baseline: false,
            medium: harness::Medium::Both,
            readme: "",
            source: "",
        }
    }
    fn knobs(&self) -> Vec<Knob> {
        Vec::new()
    }
    fn support(&self, _: &SceneFeatures, _: wgpu::Features) -> Support {
        Support::Full
    }
    fn prepare(&self, _: &PrepareContext) -> anyhow::Result<Box<dyn Prepared>> {
        match self.misbehave {
            Misbehave::ExitInPrepare => {
                eprintln!("test-exit-in-prepare: exiting with code 7 on purpose");
                std::process::exit(7)
            }
            Misbehave::GateInPrepare => wait_for_gate(),
            _ => {}
        }
        Ok(Box::new(TestState(self.misbehave)))
    }
    fn shaders(&self) -> Vec<ShaderCheck> {
        Vec::new()
    }
    fn conformance(&self) -> Vec<ConformanceCase> {
        Vec::new()
    }
}

impl Prepared for TestState {
    fn render(
        &mut self,
        _: &Gpu,
        _: &FrameState,
        _: &Targets,
        _: &mut wgpu::CommandEncoder,
    ) -> anyhow::Result<FrameReport> {
        match self.0 {
            Misbehave::AbortInRender => {
                eprintln!("test-abort-in-render: aborting on purpose");
                std::process::abort()
            }
            Misbehave::HangInRender => loop {
                std::thread::park();
            },
            Misbehave::GateInRender => wait_for_gate(),
            _ => {}
        }
        Ok(FrameReport::default())
    }
}

static TEST_METHODS: &[&dyn Method] = &[
    &TestMethod {
        id: "test-abort-in-render",
        misbehave: Misbehave::AbortInRender,
    },
    &TestMethod {
        id: "test-hang-in-render",
        misbehave: Misbehave::HangInRender,
    },
    &TestMethod {
        id: "test-exit-in-prepare",
        misbehave: Misbehave::ExitInPrepare,
    },
    &TestMethod {
        id: "test-gate-in-prepare",
        misbehave: Misbehave::GateInPrepare,
    },
    &TestMethod {
        id: "test-gate-in-render",
        misbehave: Misbehave::GateInRender,
    },
];

/// What this binary serves as a worker: the real methods and the test-only ones.
fn registry() -> Vec<&'static dyn Method> {
    methods::REGISTRY
        .iter()
        .chain(TEST_METHODS)
        .copied()
        .collect()
}

fn entry(id: &str) -> &'static dyn Method {
    registry()
        .into_iter()
        .find(|m| m.id() == id)
        .unwrap_or_else(|| panic!("no method {id}"))
}

fn scratch(name: &str) -> PathBuf {
    harness::testing::temp_dir(&format!("isolation-{name}"))
}

/// Workers are this binary, with the gate path in their environment.
fn isolation(gate: &Path, timeout_s: f64) -> Isolation {
    Isolation {
        worker: Some(WorkerCommand {
            program: std::env::current_exe().unwrap(),
            args: Vec::new(),
            env: vec![(GATE_ENV.into(), gate.into())],
        }),
        reuse: Reuse::Run,
        record_timeout: Some(Duration::from_secs_f64(timeout_s)),
        retry_failed: false,
    }
}

/// Runs `ids` (default parameters) on sphere-point at 32², 2 timed frames.
fn run(out: &Path, ids: &[&str], iso: Isolation, resume: bool) -> Results {
    let gpu = Gpu::new().expect("a GPU adapter (lavapipe)");
    let scene = scenes::library::resolve("sphere-point").unwrap();
    let mut cfg = harness::testing::run_config(out.to_path_buf(), 32, 2);
    cfg.isolation = iso;
    cfg.resume = resume;
    let work: Vec<WorkItem> = ids
        .iter()
        .map(|id| {
            let e = entry(id);
            WorkItem {
                scene: 0,
                entry: e,
                params: resolve_params(e, &Params::new()).unwrap(),
            }
        })
        .collect();
    run_items(&gpu, &[scene], &work, &cfg, None, &mut |_| {}).unwrap()
}

fn record<'a>(r: &'a Results, method: &str) -> &'a Record {
    let found: Vec<&Record> = r.records.iter().filter(|x| x.method == method).collect();
    assert_eq!(found.len(), 1, "{method} appears {} times", found.len());
    found[0]
}

fn assert_ok(r: &Results, method: &str) {
    let rec = record(r, method);
    assert_eq!(rec.status, Status::Ok, "{method}: {:?}", rec.reason);
    assert!(
        rec.timing.is_some() && !rec.errors.is_empty(),
        "{method}: not measured"
    );
}

fn assert_failed(r: &Results, method: &str, needles: &[&str]) {
    let rec = record(r, method);
    assert_eq!(rec.status, Status::Failed, "{method} should have failed");
    let why = rec.reason.as_deref().unwrap_or("");
    for n in needles {
        assert!(why.contains(n), "{method}: reason lacks '{n}': {why}");
    }
}

/// Waits until the in-flight marker names `method` in `phase` with a worker pid.
fn wait_for_marker(
    out: &Path,
    method: &str,
    phase: Phase,
    alive: &mut dyn FnMut() -> bool,
) -> InFlight {
    loop {
        if let Ok(Some(m)) = marker::read(out)
            && m.method == method
            && m.phase == phase
            && m.pid.is_some()
        {
            return m;
        }
        assert!(alive(), "the run ended before {method} reached {phase}");
        std::thread::sleep(Duration::from_millis(20));
    }
}

fn signal(pid: u32, sig: i32) {
    // SAFETY: kill(2) takes no pointers.
    assert_eq!(
        unsafe { libc::kill(pid as i32, sig) },
        0,
        "kill({pid}, {sig})"
    );
}

/// Whether a process is gone (no such pid, or a zombie waiting for a reaper).
fn gone(pid: u32) -> bool {
    match std::fs::read_to_string(format!("/proc/{pid}/stat")) {
        Err(_) => true,
        Ok(s) => s
            .rsplit(')')
            .next()
            .is_some_and(|rest| rest.trim_start().starts_with('Z')),
    }
}

fn wait_until_gone(pid: u32) {
    for _ in 0..1000 {
        if gone(pid) {
            return;
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    panic!("process {pid} outlived its parent");
}

// ---------------------------------------------------------------------------------------------

/// Three test-only methods crash, hang and exit; the two real methods around them are ok.
fn misbehaving_methods_fail_with_reason_and_phase() {
    let out = scratch("misbehave");
    let r = run(
        &out,
        &[
            "no-scatter",
            "test-abort-in-render",
            "test-hang-in-render",
            "test-exit-in-prepare",
            "raymarch-brute",
        ],
        isolation(&out.join("no-gate"), 30.0),
        false,
    );
    assert_eq!(r.records.len(), 5);
    assert_ok(&r, "no-scatter");
    assert_ok(&r, "raymarch-brute");
    assert_failed(
        &r,
        "test-abort-in-render",
        &[
            "crashed in render",
            "signal 6 (SIGABRT)",
            "aborting on purpose",
        ],
    );
    assert_failed(&r, "test-hang-in-render", &["timed out in render"]);
    assert_failed(
        &r,
        "test-exit-in-prepare",
        &[
            "crashed in prepare",
            "exited with code 7",
            "exiting with code 7 on purpose",
        ],
    );
    // What the parent wrote is what it returned, and no record is left in flight.
    assert_eq!(
        Results::load(&out.join("results.json")).unwrap().records,
        r.records
    );
    assert!(marker::read(&out).unwrap().is_none());
}

/// SIGKILL from outside on the worker running one record fails that record alone.
fn sigkill_of_a_worker_fails_only_its_record() {
    let out = scratch("sigkill");
    let o = out.clone();
    let runner = std::thread::spawn(move || {
        run(
            &o,
            &["no-scatter", "test-hang-in-render", "raymarch-brute"],
            isolation(&o.join("gate"), 600.0),
            false,
        )
    });
    let m = wait_for_marker(&out, "test-hang-in-render", Phase::Render, &mut || {
        !runner.is_finished()
    });
    signal(m.pid.unwrap(), libc::SIGKILL);
    let r = runner.join().unwrap();
    assert_ok(&r, "no-scatter");
    assert_ok(&r, "raymarch-brute");
    assert_failed(
        &r,
        "test-hang-in-render",
        &["crashed in render", "signal 9 (SIGKILL)"],
    );
}

/// A stopped worker (SIGSTOP) trips the watchdog: the gate opens right after the stop, so
/// without the stop the record would finish ok.
fn sigstop_on_a_worker_trips_the_watchdog() {
    let out = scratch("sigstop");
    std::fs::create_dir_all(&out).unwrap();
    let gate = out.join("gate");
    let (o, g) = (out.clone(), gate.clone());
    let runner = std::thread::spawn(move || {
        run(
            &o,
            &["test-gate-in-prepare", "no-scatter"],
            isolation(&g, 20.0),
            false,
        )
    });
    let m = wait_for_marker(&out, "test-gate-in-prepare", Phase::Prepare, &mut || {
        !runner.is_finished()
    });
    let pid = m.pid.unwrap();
    signal(pid, libc::SIGSTOP);
    std::fs::write(&gate, "open").unwrap();
    let r = runner.join().unwrap();
    assert_failed(&r, "test-gate-in-prepare", &["timed out in prepare"]);
    assert_ok(&r, "no-scatter");
    assert!(gone(pid), "the stopped worker {pid} is still alive");
}

/// The parent is killed while a record is in flight; its worker dies with it; `--resume`
/// records the in-flight record as interrupted without running it; `--retry-failed` runs it.
fn killed_parent_resume_and_retry_failed() {
    let out = scratch("parent");
    std::fs::create_dir_all(&out).unwrap();
    let gate = out.join("gate");
    let mut parent = Command::new(std::env::current_exe().unwrap())
        .env(PARENT_ENV, &out)
        .stdout(Stdio::null())
        .spawn()
        .unwrap();
    let m = wait_for_marker(&out, "test-gate-in-render", Phase::Render, &mut || {
        parent.try_wait().unwrap().is_none()
    });
    signal(parent.id(), libc::SIGKILL);
    parent.wait().unwrap();
    wait_until_gone(m.pid.unwrap());
    let before = Results::load(&out.join("results.json")).unwrap();
    assert_eq!(before.records.len(), 1, "only no-scatter was finished");

    // Resume: were the gated record run again, it would block until the 60 s watchdog and
    // say "timed out", not "interrupted".
    let ids = ["no-scatter", "test-gate-in-render", "raymarch-brute"];
    let r = run(&out, &ids, isolation(&gate, 60.0), true);
    assert_eq!(r.records.len(), 3);
    assert_eq!(
        r.records[0], before.records[0],
        "the finished record is kept as it was"
    );
    assert_failed(&r, "test-gate-in-render", &["interrupted", "in render"]);
    assert_ok(&r, "raymarch-brute");
    assert!(marker::read(&out).unwrap().is_none());

    std::fs::write(&gate, "open").unwrap();
    let mut iso = isolation(&gate, 60.0);
    iso.retry_failed = true;
    let again = run(&out, &ids, iso, true);
    assert_eq!(again.records.len(), 3, "every record exactly once");
    assert_eq!(
        again.records[1].method, "test-gate-in-render",
        "replaced in place"
    );
    assert_ok(&again, "test-gate-in-render");
    assert_eq!(again.records[0], r.records[0]);
    assert_eq!(
        again.records[2], r.records[2],
        "ok records are not run again"
    );
}

/// The parent of `killed_parent_resume_and_retry_failed`: runs until it is killed.
/// Issue 29: the light core is scored in the worker as in process. clear-fog has a point light
/// in view; the worker used to get the reference without its distances, decide that no light
/// was in view and record a null light core. Both runs use one reference (rendered here).
fn light_core_through_a_worker_equals_in_process() {
    let gpu = Gpu::new().expect("a GPU adapter (lavapipe)");
    let scene = scenes::library::resolve("clear-fog").unwrap();
    let ids = ["raymarch-brute", "no-scatter"];
    let work: Vec<WorkItem> = ids
        .iter()
        .map(|id| WorkItem {
            scene: 0,
            entry: entry(id),
            params: resolve_params(entry(id), &Params::new()).unwrap(),
        })
        .collect();
    let cache = scratch("light-core-cache");
    let score = |name: &str, iso: Isolation| {
        let mut cfg = harness::testing::run_config(scratch(name), 64, 1);
        cfg.isolation = iso;
        cfg.record.cache_dir = Some(cache.clone());
        run_items(
            &gpu,
            std::slice::from_ref(&scene),
            &work,
            &cfg,
            None,
            &mut |_| {},
        )
        .unwrap()
    };
    let in_process = score("light-core-off", Isolation::default());
    let isolated = score(
        "light-core-on",
        isolation(&scratch("light-core-gate"), 300.0),
    );
    for id in ids {
        let (a, b) = (record(&in_process, id), record(&isolated, id));
        assert_eq!(a.status, Status::Ok, "{id}: {:?}", a.reason);
        assert_eq!(b.status, Status::Ok, "{id}: {:?}", b.reason);
        let pixels = |r: &Record| r.counters.get("light_core_pixels").copied().unwrap_or(0.0);
        assert!(pixels(a) > 0.0, "{id}: clear-fog's light is in view");
        assert_eq!(pixels(a), pixels(b), "{id}: light_core_pixels");
        for aov in ["inscatter", "total"] {
            let core = |r: &Record| r.errors.get(aov).and_then(|m| m.light_core);
            assert!(core(a).is_some(), "{id}.{aov}: in-process light core");
            assert_eq!(
                core(a),
                core(b),
                "{id}.{aov}: light core in process vs worker"
            );
        }
    }
}

fn serve_as_parent(out: &Path) -> ! {
    let gate = out.join("gate");
    run(
        out,
        &["no-scatter", "test-gate-in-render", "raymarch-brute"],
        isolation(&gate, 600.0),
        false,
    );
    std::process::exit(0)
}

/// A pipe whose reader is already closed.
fn closed_pipe() -> Stdio {
    let mut fds = [0; 2];
    // SAFETY: pipe(2) fills the two descriptors, which are then owned here.
    unsafe {
        assert_eq!(libc::pipe(fds.as_mut_ptr()), 0);
        libc::close(fds[0]);
        Stdio::from(OwnedFd::from_raw_fd(fds[1]))
    }
}

/// Every command writing into a pipe whose reader has gone exits without a panic (exit code
/// 101) or a signal; the files it writes are still written.
fn every_command_exits_cleanly_on_a_closed_pipe() {
    let bin = env!("CARGO_BIN_EXE_scatterbench");
    let out = scratch("pipes");
    let d = |s: &str| out.join(s).display().to_string();
    let library = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/scenes/library/sphere-point.json"
    );
    let small = ["--res", "16", "--cache", &d("cache")];
    let commands: Vec<(Vec<String>, Option<String>)> = vec![
        (vec!["--help".into()], None),
        (vec!["--version".into()], None),
        (vec!["list".into()], None),
        (vec!["list".into(), "--json".into()], None),
        (vec!["validate".into(), library.into()], None),
        (
            [
                "reference",
                "--scene",
                "sphere-point",
                "--res",
                "8",
                "--out",
                &d("ref"),
            ]
            .map(String::from)
            .to_vec(),
            Some(d("ref")),
        ),
        (
            [
                &[
                    "run",
                    "--scenes",
                    "sphere-point",
                    "--methods",
                    "no-scatter",
                    "--frames",
                    "1",
                    "--warmup",
                    "0",
                    "--out",
                    &d("run"),
                ][..],
                &small[..],
            ]
            .concat()
            .iter()
            .map(|s| s.to_string())
            .collect(),
            Some(d("run/results.json")),
        ),
        (
            vec!["report".into(), d("run")],
            Some(d("run/report/index.html")),
        ),
        (
            vec!["merge".into(), d("run"), "--out".into(), d("merged")],
            Some(d("merged/results.json")),
        ),
        (
            [
                &[
                    "stress",
                    "--methods",
                    "no-scatter",
                    "--cases",
                    "camera-at-light",
                    "--out",
                    &d("stress"),
                ][..],
                &small[..],
            ]
            .concat()
            .iter()
            .map(|s| s.to_string())
            .collect(),
            Some(d("stress/results.json")),
        ),
        (
            [
                "scaling",
                "--methods",
                "no-scatter",
                "--triangles",
                "1k",
                "--triangles-res",
                "16",
                "--res",
                "16",
                "--lights",
                "none",
                "--frames",
                "1",
                "--warmup",
                "0",
                "--cache",
                &d("cache"),
                "--out",
                &d("scaling"),
            ]
            .map(String::from)
            .to_vec(),
            Some(d("scaling/results.json")),
        ),
    ];
    for (args, file) in commands {
        let child = Command::new(bin)
            .args(&args)
            .env("NODEVICE_SELECT", "1")
            .stdin(Stdio::null())
            .stdout(closed_pipe())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        let o = child.wait_with_output().unwrap();
        let mut err = String::from_utf8_lossy(&o.stderr).into_owned();
        err.truncate(4000);
        assert!(
            !err.contains("panicked") && !err.contains("Broken pipe"),
            "{args:?}: {err}"
        );
        assert!(
            o.status.code().is_some(),
            "{args:?} ended by a signal: {:?}",
            o.status
        );
        assert_ne!(o.status.code(), Some(101), "{args:?}: {err}");
        if let Some(f) = file {
            assert!(Path::new(&f).exists(), "{args:?} did not write {f}: {err}");
        }
    }
    // The worker subcommand with its input closed at once exits 0 (nothing to do).
    let mut w = Command::new(bin)
        .arg("__worker")
        .env(worker::PARENT_ENV, std::process::id().to_string())
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .spawn()
        .unwrap();
    let mut proto = String::new();
    w.stdout.take().unwrap().read_to_string(&mut proto).unwrap();
    assert!(proto.starts_with("{\"Ready\""), "worker said: {proto}");
    assert_eq!(w.wait().unwrap().code(), Some(0));
}

const TESTS: &[(&str, fn())] = &[
    (
        "misbehaving_methods_fail_with_reason_and_phase",
        misbehaving_methods_fail_with_reason_and_phase,
    ),
    (
        "sigkill_of_a_worker_fails_only_its_record",
        sigkill_of_a_worker_fails_only_its_record,
    ),
    (
        "sigstop_on_a_worker_trips_the_watchdog",
        sigstop_on_a_worker_trips_the_watchdog,
    ),
    (
        "killed_parent_resume_and_retry_failed",
        killed_parent_resume_and_retry_failed,
    ),
    (
        "light_core_through_a_worker_equals_in_process",
        light_core_through_a_worker_equals_in_process,
    ),
    (
        "every_command_exits_cleanly_on_a_closed_pipe",
        every_command_exits_cleanly_on_a_closed_pipe,
    ),
];

fn main() {
    if worker::is_worker() {
        worker::serve(&registry());
    }
    if let Some(out) = std::env::var_os(PARENT_ENV) {
        serve_as_parent(Path::new(&out));
    }
    let filters: Vec<String> = std::env::args()
        .skip(1)
        .filter(|a| !a.starts_with('-'))
        .collect();
    let chosen: Vec<_> = TESTS
        .iter()
        .filter(|(n, _)| filters.is_empty() || filters.iter().any(|f| n.contains(f.as_str())))
        .collect();
    if harness::testing::gpu_or_skip().is_none() {
        return;
    }
    let mut failed = Vec::new();
    for (name, test) in &chosen {
        eprintln!("test {name} ...");
        match std::panic::catch_unwind(test) {
            Ok(()) => eprintln!("test {name} ... ok"),
            Err(_) => {
                eprintln!("test {name} ... FAILED");
                failed.push(*name);
            }
        }
    }
    eprintln!(
        "{} passed, {} failed {failed:?}",
        chosen.len() - failed.len(),
        failed.len()
    );
    if !failed.is_empty() {
        std::process::exit(1);
    }
}
