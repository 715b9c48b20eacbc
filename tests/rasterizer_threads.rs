//! On a software adapter the window's rasteriser threads get one CPU each
//! (`app::spread_window_rasterizer_threads`), and the idle-class threads of the app's own
//! devices keep every CPU. A test binary of its own: no other test opens devices (and starts
//! rasteriser threads) while this one looks at the process's threads. Linux only, as the
//! pinning is.
#![cfg(target_os = "linux")]

mod common;

/// A thread of this process: its name, whether it is in the idle scheduling class and the CPUs
/// it may run on (from `/proc/self/task/*/status` and `sched`).
struct ThreadInfo {
    name: String,
    idle_class: bool,
    cpus: Vec<usize>,
}

/// CPUs in a `Cpus_allowed_list` value such as `0-3,6`.
fn cpu_list(list: &str) -> Vec<usize> {
    list.trim()
        .split(',')
        .flat_map(|part| {
            let (first, last) = part.split_once('-').unwrap_or((part, part));
            let first: usize = first.parse().expect("a CPU number");
            let last: usize = last.parse().expect("a CPU number");
            first..=last
        })
        .collect()
}

fn allowed_cpus(status: &str) -> Vec<usize> {
    let list = status
        .lines()
        .find_map(|line| line.strip_prefix("Cpus_allowed_list:"))
        .expect("Cpus_allowed_list in status");
    cpu_list(list)
}

fn threads() -> Vec<ThreadInfo> {
    std::fs::read_dir("/proc/self/task")
        .expect("/proc/self/task")
        .flatten()
        .filter_map(|task| {
            let name = std::fs::read_to_string(task.path().join("comm")).ok()?;
            let status = std::fs::read_to_string(task.path().join("status")).ok()?;
            let sched = std::fs::read_to_string(task.path().join("sched")).ok()?;
            let policy = sched
                .lines()
                .find_map(|line| line.strip_prefix("policy"))?
                .trim_start_matches([' ', ':'])
                .trim()
                .to_owned();
            Some(ThreadInfo {
                name: name.trim().to_owned(),
                idle_class: policy == nix::libc::SCHED_IDLE.to_string(),
                cpus: allowed_cpus(&status),
            })
        })
        .collect()
}

/// The threads llvmpipe has named `llvmpipe-N`. A rasteriser thread names itself when it
/// first runs, and an idle-class one may not run for a while on a machine whose cores are
/// busy: on a `software` adapter, wait (up to [`NAMING_WAIT`]) until idle-class ones show.
fn named_rasterizers(software: bool) -> Vec<ThreadInfo> {
    let start = std::time::Instant::now();
    loop {
        let rasterizers: Vec<_> = threads()
            .into_iter()
            .filter(|t| t.name.starts_with("llvmpipe-"))
            .collect();
        if !software || rasterizers.iter().any(|t| t.idle_class) || start.elapsed() > NAMING_WAIT {
            return rasterizers;
        }
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
}

/// How long a busy machine may take to run a new idle-class thread for the first time.
const NAMING_WAIT: std::time::Duration = std::time::Duration::from_secs(30);

#[test]
fn the_window_rasterizer_threads_get_a_cpu_each_and_background_ones_keep_all() {
    let process_cpus = allowed_cpus(&std::fs::read_to_string("/proc/self/status").unwrap());
    // The window's device, opened on this (normal priority) thread.
    let window = common::gpu();
    // A background device: its thread lowers its priority first, as the render thread does.
    let background = std::thread::spawn(|| {
        aa_lab::app::lower_priority();
        common::gpu()
    })
    .join()
    .expect("the background device opens");
    aa_lab::app::spread_window_rasterizer_threads(&window.adapter.get_info());

    let software = window.adapter.get_info().device_type == wgpu::DeviceType::Cpu;
    let rasterizers = named_rasterizers(software);
    if !software {
        // A hardware adapter: nothing is pinned.
        assert!(rasterizers.iter().all(|t| t.cpus == process_cpus));
        return;
    }
    assert!(
        !rasterizers.is_empty(),
        "a software adapter without llvmpipe threads: {}",
        window.adapter.get_info().name
    );
    let (idle, window_threads): (Vec<_>, Vec<_>) =
        rasterizers.into_iter().partition(|t| t.idle_class);
    assert!(!window_threads.is_empty(), "no window rasteriser threads");
    assert!(!idle.is_empty(), "no idle-class rasteriser threads");
    for thread in &window_threads {
        let index: usize = thread.name["llvmpipe-".len()..].parse().unwrap();
        assert_eq!(
            thread.cpus,
            [process_cpus[index % process_cpus.len()]],
            "{} runs on its own CPU",
            thread.name
        );
    }
    for thread in &idle {
        assert_eq!(thread.cpus, process_cpus, "{} keeps every CPU", thread.name);
    }
    drop(background);
}
