//! The worker side: a process of the same binary (or of a test binary) that runs records for
//! its parent, one at a time, over a registry it is given ([`serve`]).
//!
//! Set-up, in order:
//! - The protocol leaves through a duplicate of the inherited stdout; fd 1 is then pointed at
//!   stderr, so a stray `println!` of a method or a driver cannot corrupt the protocol.
//! - `prctl(PR_SET_PDEATHSIG, SIGKILL)`: the kernel kills the worker when its parent dies.
//!   End of input on stdin also makes the worker exit, but only between records — a worker
//!   stuck in a driver call never reads stdin again, so the signal is what guarantees that no
//!   worker outlives its parent (Linux only; elsewhere the stdin rule alone applies). A parent
//!   that died before the `prctl` is caught by comparing `getppid()` with the pid the parent
//!   passed in [`PARENT_ENV`].

use std::cell::RefCell;
use std::fs::File;
use std::io::BufReader;
use std::rc::Rc;

use scenes::Scene;

use super::protocol::{FromWorker, ToWorker, read_line, read_scene, write_line};
use crate::gpu::Gpu;
use crate::image::metrics::ToneMap;
use crate::method::Method;
use crate::record::phase::{self, Phase};
use crate::record::run_one;
use crate::reference::ReferenceImages;
use crate::results::Record;

/// Environment variable naming the parent's pid; its presence is what makes a process a worker.
pub const PARENT_ENV: &str = "SCATTERBENCH_WORKER_PARENT";

/// Exit code of a worker that gave up (no device, a protocol error).
pub const EXIT_FATAL: i32 = 3;

/// Whether this process was started as a worker (the parent sets [`PARENT_ENV`]).
pub fn is_worker() -> bool {
    std::env::var_os(PARENT_ENV).is_some()
}

/// Serves the parent until its input ends, then exits the process. `registry` is where job
/// method ids are looked up: the real registry for `scatterbench`, a test registry for a
/// test binary acting as its own worker.
pub fn serve(registry: &[&dyn Method]) -> ! {
    let mut proto = match protocol_output() {
        Ok(f) => f,
        Err(e) => {
            eprintln!("worker: {e}");
            std::process::exit(EXIT_FATAL)
        }
    };
    die_with_parent();
    let code = match serve_on(registry, &mut proto) {
        Ok(()) => 0,
        Err(e) => {
            let _ = write_line(&mut proto, &FromWorker::Fatal(e.clone()));
            eprintln!("worker: {e}");
            EXIT_FATAL
        }
    };
    std::process::exit(code)
}

fn serve_on(registry: &[&dyn Method], proto: &mut File) -> Result<(), String> {
    let gpu = Gpu::new()?;
    let send = |proto: &mut File, msg: &FromWorker| {
        write_line(proto, msg).map_err(|e| format!("cannot write to the parent: {e}"))
    };
    send(
        proto,
        &FromWorker::Ready {
            pid: std::process::id(),
        },
    )?;
    let mut input = BufReader::new(std::io::stdin().lock());
    let mut scene: Option<(Scene, ReferenceImages, ToneMap)> = None;
    let proto = Rc::new(RefCell::new(proto.try_clone().map_err(|e| e.to_string())?));
    while let Some(msg) = read_line::<ToWorker>(&mut input)? {
        match msg {
            ToWorker::Scene(header) => {
                let (s, r) = read_scene(&mut input, header)?;
                let tone = ToneMap::auto(&r.total);
                scene = Some((s, r, tone));
            }
            ToWorker::Job {
                method,
                params,
                settings,
            } => {
                let (s, r, tone) = scene.as_ref().ok_or("a job before any scene")?;
                let find = |id: &str, what: &str| {
                    registry
                        .iter()
                        .copied()
                        .find(|m| m.id() == id)
                        .ok_or_else(|| format!("unknown {what} '{id}' in this worker's registry"))
                };
                let entry = find(&method, "method")?;
                let floor = match settings.paired_floor.as_deref() {
                    None => None,
                    Some(id) => Some(find(id, "paired floor")?),
                };
                let out = Rc::clone(&proto);
                let record: Record = phase::with_hook(
                    move |p: Phase| {
                        // A parent that cannot hear the phase will see the record or the exit.
                        let _ = write_line(&mut *out.borrow_mut(), &FromWorker::Phase(p));
                    },
                    || run_one(&gpu, s, entry, &params, &settings, (r, tone), floor),
                );
                send(
                    &mut proto.borrow_mut(),
                    &FromWorker::Record(Box::new(record)),
                )?;
            }
        }
    }
    Ok(())
}

/// A duplicate of fd 1 for the protocol; fd 1 itself then points at stderr.
#[cfg(unix)]
fn protocol_output() -> Result<File, String> {
    use std::os::fd::FromRawFd;
    // SAFETY: dup/dup2 on the process's own standard descriptors; the duplicate is owned by
    // the returned File alone.
    unsafe {
        let fd = libc::dup(1);
        if fd < 0 || libc::dup2(2, 1) < 0 {
            return Err(format!(
                "cannot set up the protocol pipe: {}",
                std::io::Error::last_os_error()
            ));
        }
        Ok(File::from_raw_fd(fd))
    }
}

#[cfg(target_os = "linux")]
fn die_with_parent() {
    // SAFETY: prctl(PR_SET_PDEATHSIG) and getppid take no pointers.
    unsafe {
        libc::prctl(libc::PR_SET_PDEATHSIG, libc::SIGKILL as libc::c_ulong);
        let expected = std::env::var(PARENT_ENV)
            .ok()
            .and_then(|s| s.parse::<i32>().ok());
        if expected.is_some_and(|p| p != libc::getppid()) {
            std::process::exit(EXIT_FATAL);
        }
    }
}

#[cfg(not(target_os = "linux"))]
fn die_with_parent() {}
