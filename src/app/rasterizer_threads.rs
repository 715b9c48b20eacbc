//! Where the window's software-rasteriser threads run: on a software adapter (lavapipe on
//! Linux), the rasteriser threads of eframe's device get one CPU each.
//!
//! Why: the engine and the quality worker run on devices of their own whose rasteriser threads
//! are in the idle scheduling class ([`super::worker::lower_priority`]), and they keep every core
//! busy. Linux then stops looking for a free core when it wakes a thread (its scan for an idle
//! CPU is skipped when the cache domain is fully used), so the window's rasteriser threads wake
//! on the core they last ran on, which is often the same one: both then take turns on one core
//! while the other core runs the idle-class engine, and the load balancer does not move one of
//! them within a paint. `perf sched` in the viewer benchmark showed the slow paints were
//! exactly those; with one CPU each they are gone (figures: `docs/viewer.md`).
//!
//! The threads are found by name (llvmpipe names its rasteriser threads `llvmpipe-N`), among
//! the threads that are not idle-class (the background devices' threads are), and thread `N`
//! gets the `N`-th CPU the process may use. Called once the window's device exists and before
//! the app opens its own devices. Elsewhere (a hardware adapter, another system) it does
//! nothing; a refusal leaves the threads where they were, with a log line.

/// Gives each of the window device's software-rasteriser threads a CPU of its own when
/// `adapter` is a software rasteriser (see the module docs).
pub fn spread_window_rasterizer_threads(adapter: &wgpu::AdapterInfo) {
    if adapter.device_type != wgpu::DeviceType::Cpu {
        return;
    }
    #[cfg(target_os = "linux")]
    linux::spread();
}

#[cfg(target_os = "linux")]
mod linux {
    use nix::libc::SCHED_IDLE;
    use nix::sched::{CpuSet, sched_getaffinity, sched_setaffinity};
    use nix::unistd::Pid;

    /// The rasteriser index of a thread named `name` (`llvmpipe-3` → 3).
    fn rasterizer_index(name: &str) -> Option<usize> {
        name.trim().strip_prefix("llvmpipe-")?.parse().ok()
    }

    /// The scheduling policy in a thread's `/proc/…/stat` line (its 41st field).
    fn policy_from_stat(stat: &str) -> Option<i32> {
        // The name (field 2) is in parentheses and may hold spaces: count after its end.
        let after_name = &stat[stat.rfind(')')? + 1..];
        after_name.split_whitespace().nth(41 - 3)?.parse().ok()
    }

    /// The CPU for rasteriser thread `index`, among the CPUs the process may use.
    fn cpu_for(index: usize, allowed: &[usize]) -> Option<usize> {
        (!allowed.is_empty()).then(|| allowed[index % allowed.len()])
    }

    /// A thread of this process that is a window rasteriser: its id and rasteriser index.
    fn window_rasterizers() -> Vec<(i32, usize)> {
        let Ok(tasks) = std::fs::read_dir("/proc/self/task") else {
            return Vec::new();
        };
        tasks
            .flatten()
            .filter_map(|task| {
                let tid: i32 = task.file_name().to_str()?.parse().ok()?;
                let name = std::fs::read_to_string(task.path().join("comm")).ok()?;
                let index = rasterizer_index(&name)?;
                let stat = std::fs::read_to_string(task.path().join("stat")).ok()?;
                (policy_from_stat(&stat)? != SCHED_IDLE).then_some((tid, index))
            })
            .collect()
    }

    /// The CPUs the process may run on.
    fn allowed_cpus() -> Vec<usize> {
        sched_getaffinity(Pid::from_raw(0))
            .map(|set| {
                (0..CpuSet::count())
                    .filter(|&cpu| set.is_set(cpu).unwrap_or(false))
                    .collect()
            })
            .unwrap_or_default()
    }

    pub(super) fn spread() {
        let allowed = allowed_cpus();
        for (tid, index) in window_rasterizers() {
            let Some(cpu) = cpu_for(index, &allowed) else {
                return;
            };
            let mut set = CpuSet::new();
            let pinned = set
                .set(cpu)
                .and_then(|()| sched_setaffinity(Pid::from_raw(tid), &set));
            match pinned {
                Ok(()) => log::debug!("window rasteriser thread {index} runs on CPU {cpu}"),
                Err(err) => {
                    log::info!("window rasteriser thread {index} keeps its CPUs: {err}");
                }
            }
        }
    }

    #[cfg(test)]
    mod tests {
        use super::*;

        #[test]
        fn reads_the_rasteriser_index_from_the_thread_name() {
            assert_eq!(rasterizer_index("llvmpipe-0\n"), Some(0));
            assert_eq!(rasterizer_index("llvmpipe-15"), Some(15));
            assert_eq!(rasterizer_index("llvmpipe-"), None);
            assert_eq!(rasterizer_index("aa-lab render"), None);
        }

        #[test]
        fn reads_the_policy_past_a_name_with_spaces_and_parentheses() {
            // The format of an idle-class thread's line, with a name that holds ") (".
            let stat = "4242 (aa-lab ) (x) S 1 4242 4242 0 -1 4194368 2069 0 0 0 12 3 0 0 39 19 \
                        3 0 21817 1999624192 146116 18446744073709551615 1 1 0 0 0 0 0 4096 \
                        17642 0 0 0 -1 1 0 5 0 0 0 0 0 0 0 0 0 0 0";
            assert_eq!(policy_from_stat(stat), Some(SCHED_IDLE));
            let normal = stat.replace(" 0 5 0 0 0 0", " 0 0 0 0 0 0");
            assert_eq!(policy_from_stat(&normal), Some(0));
            assert_eq!(policy_from_stat("4242 (cut"), None);
        }

        #[test]
        fn thread_n_gets_the_nth_allowed_cpu() {
            let allowed = [2, 3, 6];
            assert_eq!(cpu_for(0, &allowed), Some(2));
            assert_eq!(cpu_for(2, &allowed), Some(6));
            // More threads than CPUs: they share them in turn.
            assert_eq!(cpu_for(4, &allowed), Some(3));
            assert_eq!(cpu_for(0, &[]), None);
        }
    }
}
