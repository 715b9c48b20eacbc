//! Background workers for measurements that take longer than a UI frame (quality figures,
//! the magnifier's error maps): one thread per worker running one job at a time. The UI hands
//! a job over only while the worker is idle and always builds it from the newest images, so
//! results never queue up behind outdated work ("latest wins"). A job streams its results
//! back as they are ready and the worker wakes the UI for each; when the job ends the worker
//! reports how long it took, which the caller uses to pace the next one.
//!
//! Every background thread of the viewer (these workers, the render thread, the scene loader)
//! runs at the lowest CPU priority ([`lower_priority`]): the window's paint comes first.

use std::sync::mpsc;
use std::time::{Duration, Instant};

/// How long dropping a background thread's handle (a [`Worker`], the render thread) waits for
/// the thread to end. The handles are dropped when the app closes, and they must wait for
/// threads that hold a device: a driver crashed the process (a segfault or `free(): invalid
/// pointer`) when it exited while such a thread was still releasing its device objects (NVIDIA's
/// Vulkan driver at the end of a viewer benchmark; lavapipe at the end of the soak test, where
/// the quality worker releases its own device). A thread stuck in a job is left behind after
/// this long rather than hanging the exit.
pub const EXIT_WAIT: Duration = Duration::from_secs(10);

enum Message<R> {
    Result(R),
    Done(Duration),
}

/// Hands a job's results back to the UI.
pub struct Reporter<R> {
    sender: mpsc::Sender<Message<R>>,
    ctx: egui::Context,
}

impl<R> Reporter<R> {
    /// Sends one result and wakes the UI.
    pub fn send(&self, result: R) {
        let _ = self.sender.send(Message::Result(result));
        super::repaint::request_one_frame(&self.ctx);
    }
}

/// Gives the calling background thread the lowest CPU priority: the idle scheduling class
/// (SCHED_IDLE) on Linux, the lowest priority elsewhere. On a machine with few cores the
/// engine's frames, the quality figures and the window's paint compete for every core; at
/// equal priority the UI thread's paint waited behind them, and at nice 19 it still waited
/// for a time slice. The render thread and the quality worker call it before they open their
/// devices ([`super::render_thread::open_device`], each on an instance of its own), so the
/// threads a driver starts for that device inherit it: on lavapipe that is the rasteriser
/// threads of the device's own llvmpipe screen. The cost: while other programs keep every core
/// busy, idle-class threads get almost no CPU and the engine's frame rate drops near zero
/// (nice 19 behaved nearly the same). On a GPU the threads mostly wait and this changes nothing
/// measurable. Where the system refuses, the thread keeps its priority.
pub fn lower_priority() {
    #[cfg(target_os = "linux")]
    let lowered = {
        use thread_priority::unix::{
            NormalThreadSchedulePolicy, ThreadSchedulePolicy, set_thread_priority_and_policy,
            thread_native_id,
        };
        set_thread_priority_and_policy(
            thread_native_id(),
            thread_priority::ThreadPriority::Min,
            ThreadSchedulePolicy::Normal(NormalThreadSchedulePolicy::Idle),
        )
    };
    #[cfg(not(target_os = "linux"))]
    let lowered =
        thread_priority::set_current_thread_priority(thread_priority::ThreadPriority::Min);
    if let Err(err) = lowered {
        log::info!("a background thread keeps its priority: {err:?}");
    }
}

/// A background thread running jobs of type `J` that produce results of type `R`. Dropping
/// it ends the thread after its job and waits for that, at most [`EXIT_WAIT`].
pub struct Worker<J, R> {
    jobs: mpsc::Sender<J>,
    results: mpsc::Receiver<Message<R>>,
    /// Disconnects when the thread has dropped `run` (and whatever device it holds) and ended.
    ended: mpsc::Receiver<()>,
    busy: bool,
    last_duration: Duration,
    finished_at: Option<Instant>,
}

impl<J: Send + 'static, R: Send + 'static> Worker<J, R> {
    /// Starts the thread; `run` handles one job, reporting results through the reporter.
    pub fn spawn(
        name: &str,
        ctx: &egui::Context,
        run: impl FnMut(J, &Reporter<R>) + Send + 'static,
    ) -> std::io::Result<Self> {
        let (jobs, job_receiver) = mpsc::channel::<J>();
        let (sender, results) = mpsc::channel();
        let (ending, ended) = mpsc::channel::<()>();
        let reporter = Reporter {
            sender,
            ctx: ctx.clone(),
        };
        std::thread::Builder::new()
            .name(name.to_owned())
            .spawn(move || {
                // Locals drop in reverse order: `run` before `_ending`, which disconnects.
                let _ending = ending;
                let mut run = run;
                lower_priority();
                while let Ok(job) = job_receiver.recv() {
                    let start = Instant::now();
                    run(job, &reporter);
                    let _ = reporter.sender.send(Message::Done(start.elapsed()));
                    super::repaint::request_one_frame(&reporter.ctx);
                }
            })?;
        Ok(Self {
            jobs,
            results,
            ended,
            busy: false,
            last_duration: Duration::ZERO,
            finished_at: None,
        })
    }

    /// Whether a job is running.
    pub fn busy(&self) -> bool {
        self.busy
    }

    /// Idle, and at least `pause` (or the last job's duration, whichever is longer) has passed
    /// since the last job ended, so that measuring takes at most about half the time.
    pub fn rested(&self, pause: Duration) -> bool {
        !self.busy
            && self
                .finished_at
                .is_none_or(|at| at.elapsed() >= pause.max(self.last_duration))
    }

    /// Starts a job when idle; returns whether it was taken.
    pub fn submit(&mut self, job: J) -> bool {
        if self.busy {
            return false;
        }
        self.busy = self.jobs.send(job).is_ok();
        self.busy
    }

    /// The results that arrived since the last call, oldest first.
    pub fn poll(&mut self) -> Vec<R> {
        let mut out = Vec::new();
        loop {
            match self.results.try_recv() {
                Ok(Message::Result(result)) => out.push(result),
                Ok(Message::Done(duration)) => {
                    self.busy = false;
                    self.last_duration = duration;
                    self.finished_at = Some(Instant::now());
                }
                Err(mpsc::TryRecvError::Empty) => break,
                Err(mpsc::TryRecvError::Disconnected) => {
                    // The thread ended (a job panicked): accept no more jobs.
                    self.busy = true;
                    break;
                }
            }
        }
        out
    }
}

impl<J, R> Drop for Worker<J, R> {
    fn drop(&mut self) {
        // Replacing the sender drops the thread's only one: its loop ends after the job.
        self.jobs = mpsc::channel().0;
        if let Err(mpsc::RecvTimeoutError::Timeout) = self.ended.recv_timeout(EXIT_WAIT) {
            log::warn!(
                "a background worker did not end within {} s; leaving it behind",
                EXIT_WAIT.as_secs()
            );
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn wait_for<J: Send + 'static, R: Send + 'static>(worker: &mut Worker<J, R>) -> Vec<R> {
        let start = Instant::now();
        let mut out = Vec::new();
        while worker.busy() {
            assert!(start.elapsed() < Duration::from_secs(10), "worker stuck");
            out.extend(worker.poll());
            std::thread::sleep(Duration::from_millis(1));
        }
        out
    }

    #[test]
    fn runs_one_job_at_a_time_and_streams_results() {
        let ctx = egui::Context::default();
        let mut worker = Worker::spawn("test worker", &ctx, |n: u32, reporter| {
            for i in 0..n {
                reporter.send(i);
            }
        })
        .unwrap();
        assert!(worker.rested(Duration::from_secs(100)));
        assert!(worker.submit(3));
        assert!(!worker.submit(5), "busy workers take no second job");
        assert_eq!(wait_for(&mut worker), vec![0, 1, 2]);
        assert!(!worker.rested(Duration::from_secs(100)));
        std::thread::sleep(Duration::from_millis(20));
        assert!(worker.rested(Duration::ZERO));
        assert!(worker.submit(2));
        assert_eq!(wait_for(&mut worker), vec![0, 1]);
    }

    /// What a job's closure owns (a device, in the viewer) is released before the drop of the
    /// worker returns, even while a job is running: the process may exit right after it.
    #[test]
    fn dropping_a_worker_waits_for_its_thread_to_release_what_it_holds() {
        use std::sync::Arc;
        use std::sync::atomic::{AtomicBool, Ordering};

        struct Held(Arc<AtomicBool>);
        impl Drop for Held {
            fn drop(&mut self) {
                std::thread::sleep(Duration::from_millis(50));
                self.0.store(true, Ordering::SeqCst);
            }
        }
        let released = Arc::new(AtomicBool::new(false));
        let held = Held(Arc::clone(&released));
        let ctx = egui::Context::default();
        let mut worker = Worker::spawn("test worker", &ctx, move |(): (), reporter| {
            let _ = &held;
            std::thread::sleep(Duration::from_millis(100));
            reporter.send(());
        })
        .unwrap();
        assert!(worker.submit(()));
        drop(worker);
        assert!(
            released.load(Ordering::SeqCst),
            "the worker's state outlived its drop"
        );
    }
}
