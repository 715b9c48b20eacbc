//! Running a hostile case where it cannot hurt the machine: in a child process (this test
//! binary again, filtered to one test) under an address-space limit and a time limit, so a
//! loader that reads `/dev/zero` until memory runs out dies alone (an allocation failure
//! aborts the child) and one that waits on a FIFO for ever is killed, and the test reports
//! either as a failure instead of taking the machine or the run with it.
//!
//! A test that uses it starts with [`case`]: in the child that returns the case to run (and
//! has already lowered the limit), in the parent `None`. The parent calls [`run`] per case.

use std::io::Read;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// Environment variable naming the case a child runs.
const CASE_VARIABLE: &str = "AA_LAB_CONFINED_CASE";
/// Environment variable holding the child's address-space limit in bytes.
const LIMIT_VARIABLE: &str = "AA_LAB_CONFINED_LIMIT";
/// Prefix of the line a child prints with its case's outcome.
const OUTCOME_PREFIX: &str = "confined outcome: ";

/// Address space a child may use: the test binary and its threads take a few hundred MiB, the
/// rest is far more than any bounded load of a small file needs and far less than the
/// machine has.
pub const ADDRESS_SPACE_LIMIT: u64 = 2 << 30;

/// In the child (the variables are set), applies the address-space limit and returns the
/// case to run; in the parent `None`.
pub fn case() -> Option<String> {
    let case = std::env::var(CASE_VARIABLE).ok()?;
    let limit: u64 = std::env::var(LIMIT_VARIABLE)
        .ok()
        .and_then(|v| v.parse().ok())
        .expect("a confined child has its limit");
    nix::sys::resource::setrlimit(nix::sys::resource::Resource::RLIMIT_AS, limit, limit)
        .expect("setrlimit(RLIMIT_AS)");
    Some(case)
}

/// Reports a case's outcome from the child (the parent reads it back).
pub fn report(outcome: &str) {
    println!("{OUTCOME_PREFIX}{}", outcome.replace('\n', " | "));
}

/// How a confined case ended.
#[derive(Debug)]
pub enum Ended {
    /// The child ran the case to its end and reported this outcome.
    Reported(String),
    /// The child failed (a panic, an allocation failure under the limit, a signal): its exit
    /// status and output.
    Failed(String),
    /// The child was still running after the time limit and was killed: its output.
    TimedOut(String),
}

/// Runs `case` of the test `test` (its full name, as `--exact` wants it) in a child under
/// `limit` bytes of address space, killed after `timeout`.
pub fn run(test: &str, case: &str, limit: u64, timeout: Duration) -> Ended {
    let exe = std::env::current_exe().expect("the test binary's path");
    let mut child = Command::new(exe)
        .args([test, "--exact", "--nocapture", "--test-threads=1"])
        .env(CASE_VARIABLE, case)
        .env(LIMIT_VARIABLE, limit.to_string())
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("the test binary starts again");
    let mut stdout = child.stdout.take().expect("piped stdout");
    let mut stderr = child.stderr.take().expect("piped stderr");
    // Drained on threads so that a chatty child never blocks on a full pipe.
    let out = std::thread::spawn(move || {
        let mut text = String::new();
        let _ = stdout.read_to_string(&mut text);
        text
    });
    let err = std::thread::spawn(move || {
        let mut text = String::new();
        let _ = stderr.read_to_string(&mut text);
        text
    });
    let deadline = Instant::now() + timeout;
    let status = loop {
        if let Some(status) = child.try_wait().expect("waiting for the child") {
            break Some(status);
        }
        if Instant::now() > deadline {
            let _ = child.kill();
            let _ = child.wait();
            break None;
        }
        std::thread::sleep(Duration::from_millis(20));
    };
    let out = out.join().unwrap_or_default();
    let err = err.join().unwrap_or_default();
    let Some(status) = status else {
        return Ended::TimedOut(format!("{out}\n{err}"));
    };
    // The harness's `test NAME ... ` precedes the child's first line.
    let reported = out
        .lines()
        .find_map(|line| line.split_once(OUTCOME_PREFIX).map(|(_, outcome)| outcome));
    match reported {
        Some(outcome) if status.success() => Ended::Reported(outcome.to_owned()),
        _ => Ended::Failed(format!("{status}\n{out}\n{err}")),
    }
}
