//! Building a user technique off the caller's thread. A user's WGSL file can take a driver a
//! very long time to compile (a large function-local array has kept lavapipe busy for minutes),
//! and pipeline creation cannot be interrupted, so every user technique is read, checked and
//! built on a thread of its own ([`PendingBuild`]): the viewer's render thread keeps rendering
//! the other techniques and polls the build, and the command line waits for it with progress
//! and a time limit ([`BuildWait`], `--build-timeout`), whose expiry is an error of the
//! technique. A build that is given up keeps its thread until the driver returns; its result is
//! then dropped.

use std::path::Path;
use std::sync::mpsc::{self, RecvTimeoutError, TryRecvError};
use std::sync::{Mutex, PoisonError};
use std::time::{Duration, Instant};

use super::LoadError;
use crate::aa::Technique;
use crate::gpu::Gpu;

/// What a finished build gives.
pub type BuildResult = Result<Box<dyn Technique>, LoadError>;

/// How long [`super::create`] waits for a build before it gives up, by default.
pub const DEFAULT_BUILD_TIMEOUT: Duration = Duration::from_secs(600);

/// How often a waiting caller hears about a build that is still running.
pub const PROGRESS_INTERVAL: Duration = Duration::from_secs(1);

/// How [`super::create`] waits for a build: at most `timeout`, calling `progress` with the
/// file and the time so far every [`PROGRESS_INTERVAL`] while it runs (the command line prints
/// it).
#[derive(Clone, Copy, Debug)]
pub struct BuildWait {
    /// Longest wait; a build still running then is an error.
    pub timeout: Duration,
    /// Called while the build runs.
    pub progress: Option<fn(&Path, Duration)>,
}

impl Default for BuildWait {
    fn default() -> Self {
        Self {
            timeout: DEFAULT_BUILD_TIMEOUT,
            progress: None,
        }
    }
}

/// The process's way of waiting (a command-line setting, so process-wide).
static WAIT: Mutex<Option<BuildWait>> = Mutex::new(None);

/// Sets how [`super::create`] waits for builds from now on.
pub fn set_build_wait(wait: BuildWait) {
    *WAIT.lock().unwrap_or_else(PoisonError::into_inner) = Some(wait);
}

/// How [`super::create`] waits for builds now.
pub fn build_wait() -> BuildWait {
    WAIT.lock()
        .unwrap_or_else(PoisonError::into_inner)
        .unwrap_or_default()
}

/// A user technique being read, checked and built on a thread of its own.
pub struct PendingBuild {
    id: &'static str,
    started: Instant,
    result: mpsc::Receiver<BuildResult>,
}

impl PendingBuild {
    /// Starts building the user technique `id` (`user:PATH`) on `gpu`.
    pub fn start(gpu: &Gpu, id: &'static str) -> Self {
        let (send, result) = mpsc::channel();
        let gpu = gpu.clone();
        // Should the thread not start, the sender is dropped and the build reports that.
        let _ = std::thread::Builder::new()
            .name("aa-lab user build".to_owned())
            .spawn(move || {
                let _ = send.send(super::build_here(&gpu, id));
            });
        Self {
            id,
            started: Instant::now(),
            result,
        }
    }

    /// The technique's id.
    pub fn id(&self) -> &'static str {
        self.id
    }

    /// How long it has been building.
    pub fn elapsed(&self) -> Duration {
        self.started.elapsed()
    }

    /// The result when the build has finished, `None` while it runs.
    pub fn finished(&self) -> Option<BuildResult> {
        match self.result.try_recv() {
            Ok(result) => Some(result),
            Err(TryRecvError::Empty) => None,
            Err(TryRecvError::Disconnected) => Some(Err(self.lost())),
        }
    }

    /// Waits for the result as `wait` says (see [`BuildWait`]).
    pub fn wait(self, wait: BuildWait) -> BuildResult {
        let path = super::path_of(self.id).unwrap_or(Path::new(self.id));
        loop {
            let left = wait.timeout.saturating_sub(self.elapsed());
            if left.is_zero() {
                return Err(LoadError {
                    path: path.to_owned(),
                    location: None,
                    message: format!(
                        "its GPU pipeline was still compiling after {} s (--build-timeout); the \
                         driver may never finish a shader this large (a big function-local \
                         array, a long loop it unrolls): simplify the shader or allow more time",
                        wait.timeout.as_secs_f64()
                    ),
                    excerpt: None,
                });
            }
            match self.result.recv_timeout(left.min(PROGRESS_INTERVAL)) {
                Ok(result) => return result,
                Err(RecvTimeoutError::Disconnected) => return Err(self.lost()),
                Err(RecvTimeoutError::Timeout) => {
                    if let Some(progress) = wait.progress {
                        progress(path, self.elapsed());
                    }
                }
            }
        }
    }

    /// The error of a build thread that ended without a result (it could not start, or the
    /// driver panicked in it).
    fn lost(&self) -> LoadError {
        LoadError {
            path: super::path_of(self.id)
                .unwrap_or(Path::new(self.id))
                .to_owned(),
            location: None,
            message: "its build ended without a result (the build thread could not start or \
                      failed; see the log)"
                .to_owned(),
            excerpt: None,
        }
    }
}
