//! The parent side: a worker process with a watchdog. [`Pool::run`] sends one job, follows
//! the worker's phase announcements and returns its record — or, when the worker exceeds the
//! record timeout, dies or breaks the protocol, a failed record saying what happened, in
//! which phase, with the last lines of the worker's stderr. The dead worker is replaced at
//! the next job; the run goes on.

use std::collections::VecDeque;
use std::io::{BufReader, BufWriter, Write};
use std::process::{Child, ChildStdin, Command, ExitStatus, Stdio};
use std::sync::mpsc::{Receiver, RecvTimeoutError};
use std::sync::{Arc, Mutex};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use scenes::Scene;

use super::config::{Reuse, WorkerCommand};
use super::protocol::{FromWorker, ToWorker, read_line, write_line, write_scene};
use super::worker::PARENT_ENV;
use crate::record::{Phase, RecordSettings};
use crate::reference::ReferenceImages;
use crate::results::Record;

/// Lines of a crashed worker's stderr kept for its record.
const STDERR_TAIL: usize = 8;

/// A running worker.
struct Worker {
    child: Child,
    stdin: BufWriter<ChildStdin>,
    rx: Receiver<FromWorker>,
    stderr_tail: Arc<Mutex<VecDeque<String>>>,
    stderr_thread: Option<JoinHandle<()>>,
    /// The (scene index, method) of its last job, for [`Reuse::SceneMethod`].
    last: Option<(usize, String)>,
    /// Scene index whose scene and reference it holds.
    scene: Option<usize>,
}

/// One record's job, as the pool needs it.
pub struct Job<'a> {
    pub scene_index: usize,
    pub scene: &'a Scene,
    pub reference: &'a ReferenceImages,
    pub method: &'a str,
    pub params: &'a crate::method::Params,
    pub settings: &'a RecordSettings,
}

/// How a job ended when no record came back.
pub struct Failure {
    pub reason: String,
}

/// At most one live worker, replaced when it dies (and, by policy, between records).
pub struct Pool {
    command: WorkerCommand,
    reuse: Reuse,
    timeout: Duration,
    worker: Option<Worker>,
    /// Workers started so far (for the overhead statistics).
    pub spawned: u32,
}

impl Pool {
    pub fn new(command: WorkerCommand, reuse: Reuse, timeout: Duration) -> Pool {
        Pool {
            command,
            reuse,
            timeout,
            worker: None,
            spawned: 0,
        }
    }

    /// Runs one job in a worker. `on_phase` hears every phase and the worker's pid.
    pub fn run(
        &mut self,
        job: &Job,
        on_phase: &mut dyn FnMut(Phase, u32),
    ) -> Result<Record, Failure> {
        let key = (job.scene_index, job.method.to_string());
        let keep = match (&self.worker, self.reuse) {
            (Some(_), Reuse::None) => false,
            (Some(w), Reuse::SceneMethod) => w.last.as_ref() == Some(&key),
            (Some(_), Reuse::Run) => true,
            (None, _) => false,
        };
        if !keep {
            self.retire();
        }
        let start = Instant::now();
        if self.worker.is_none() {
            on_phase(Phase::Start, 0);
            let w = self.spawn(start)?;
            self.worker = Some(w);
        }
        let w = self.worker.as_mut().expect("spawned above");
        let pid = w.child.id();
        on_phase(Phase::Start, pid);
        let mut sent = Ok(());
        if w.scene != Some(job.scene_index) {
            sent = write_scene(&mut w.stdin, job.scene, job.reference);
            w.scene = Some(job.scene_index);
        }
        let msg = ToWorker::Job {
            method: job.method.to_string(),
            params: job.params.clone(),
            settings: job.settings.clone(),
        };
        sent = sent
            .and_then(|()| write_line(&mut w.stdin, &msg))
            .and_then(|()| w.stdin.flush());
        w.last = Some(key);
        let mut phase = Phase::Start;
        if sent.is_ok() {
            loop {
                let left = self.timeout.saturating_sub(start.elapsed());
                match w.rx.recv_timeout(left) {
                    Ok(FromWorker::Phase(p)) => {
                        phase = p;
                        on_phase(p, pid);
                    }
                    Ok(FromWorker::Record(r)) => {
                        if r.status == crate::results::Status::Failed {
                            // A clean device for the next record.
                            self.retire();
                        }
                        return Ok(*r);
                    }
                    Ok(FromWorker::Ready { .. }) => {}
                    Ok(FromWorker::Fatal(m)) => {
                        let w = self.worker.take().expect("live");
                        let (status, tail) = w.end(true);
                        return Err(Failure {
                            reason: format!(
                                "worker failed in {phase}: {m} ({}){tail}",
                                describe(status)
                            ),
                        });
                    }
                    Err(RecvTimeoutError::Timeout) => {
                        let w = self.worker.take().expect("live");
                        let _ = w.end(true);
                        return Err(Failure {
                            reason: format!(
                                "timed out in {phase} after {:.0} s (--record-timeout); the worker was killed",
                                self.timeout.as_secs_f64()
                            ),
                        });
                    }
                    Err(RecvTimeoutError::Disconnected) => break,
                }
            }
        }
        // The worker closed its end (or our write failed): it died.
        let w = self.worker.take().expect("live");
        let (status, tail) = w.end(false);
        Err(Failure {
            reason: format!("crashed in {phase}: the worker {}{tail}", describe(status)),
        })
    }

    /// Starts a worker and waits (within the record timeout) for its device.
    fn spawn(&mut self, start: Instant) -> Result<Worker, Failure> {
        let c = &self.command;
        let mut child = Command::new(&c.program)
            .args(&c.args)
            .envs(c.env.iter().map(|(k, v)| (k, v)))
            .env(PARENT_ENV, std::process::id().to_string())
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .map_err(|e| Failure {
                reason: format!("cannot start a worker ({}): {e}", c.program.display()),
            })?;
        self.spawned += 1;
        let (tx, rx) = std::sync::mpsc::channel();
        let stdout = child.stdout.take().expect("piped");
        std::thread::spawn(move || {
            let mut r = BufReader::new(stdout);
            loop {
                match read_line::<FromWorker>(&mut r) {
                    Ok(Some(m)) => {
                        if tx.send(m).is_err() {
                            break;
                        }
                    }
                    Ok(None) => break,
                    Err(e) => {
                        let _ = tx.send(FromWorker::Fatal(e));
                        break;
                    }
                }
            }
        });
        let stderr_tail = Arc::new(Mutex::new(VecDeque::new()));
        let tail = Arc::clone(&stderr_tail);
        let stderr = child.stderr.take().expect("piped");
        let stderr_thread = std::thread::spawn(move || {
            use std::io::BufRead;
            for line in BufReader::new(stderr).lines() {
                let Ok(line) = line else { break };
                // Passed on so warnings stay visible; a closed stderr is not an error here.
                let _ = writeln!(std::io::stderr(), "{line}");
                let mut t = tail.lock().expect("tail");
                if t.len() == STDERR_TAIL {
                    t.pop_front();
                }
                t.push_back(line);
            }
        });
        let w = Worker {
            stdin: BufWriter::new(child.stdin.take().expect("piped")),
            child,
            rx,
            stderr_tail,
            stderr_thread: Some(stderr_thread),
            last: None,
            scene: None,
        };
        let left = self.timeout.saturating_sub(start.elapsed());
        let why = match w.rx.recv_timeout(left) {
            Ok(FromWorker::Ready { .. }) => return Ok(w),
            Ok(FromWorker::Fatal(m)) => m,
            Ok(_) => "it spoke before it was ready".to_string(),
            Err(RecvTimeoutError::Timeout) => {
                let _ = w.end(true);
                return Err(Failure {
                    reason: format!(
                        "timed out in start after {:.0} s (--record-timeout); the worker was killed",
                        self.timeout.as_secs_f64()
                    ),
                });
            }
            Err(RecvTimeoutError::Disconnected) => "it exited".to_string(),
        };
        let (status, tail) = w.end(true);
        Err(Failure {
            reason: format!(
                "the worker could not start: {why} ({}){tail}",
                describe(status)
            ),
        })
    }

    /// Lets the current worker finish: closing its stdin makes it exit.
    fn retire(&mut self) {
        if let Some(w) = self.worker.take() {
            let _ = w.end(false);
        }
    }
}

impl Drop for Pool {
    fn drop(&mut self) {
        self.retire();
    }
}

impl Worker {
    /// Ends the worker (killing it first when `kill`), reaps it and returns its exit status
    /// and the tail of its stderr, formatted for a reason.
    fn end(mut self, kill: bool) -> (Option<ExitStatus>, String) {
        if kill {
            let _ = self.child.kill();
        }
        drop(self.stdin);
        let status = self.child.wait().ok();
        if let Some(t) = self.stderr_thread.take() {
            let _ = t.join();
        }
        let tail: Vec<String> = self
            .stderr_tail
            .lock()
            .expect("tail")
            .iter()
            .cloned()
            .collect();
        let tail = if tail.is_empty() {
            String::new()
        } else {
            format!("; last stderr lines: {}", tail.join(" | "))
        };
        (status, tail)
    }
}

/// "was killed by signal 6 (SIGABRT)", "exited with code 3".
fn describe(status: Option<ExitStatus>) -> String {
    let Some(s) = status else {
        return "ended (exit status unavailable)".into();
    };
    #[cfg(unix)]
    {
        use std::os::unix::process::ExitStatusExt;
        if let Some(sig) = s.signal() {
            return format!("was killed by signal {sig} ({})", signal_name(sig));
        }
    }
    match s.code() {
        Some(c) => format!("exited with code {c}"),
        None => format!("ended: {s}"),
    }
}

fn signal_name(sig: i32) -> &'static str {
    match sig {
        4 => "SIGILL",
        6 => "SIGABRT",
        7 => "SIGBUS",
        8 => "SIGFPE",
        9 => "SIGKILL",
        11 => "SIGSEGV",
        13 => "SIGPIPE",
        15 => "SIGTERM",
        _ => "signal",
    }
}
