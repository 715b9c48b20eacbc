//! What "flat" means for a long run (`tests/long_runs.rs`, `tests/soak.rs`): the live GPU
//! objects wgpu counts (the dev-dependency feature `counters`) are the same at the end of the
//! measured windows as at their start, and the process's resident size grows by no more than a
//! few kB per frame in the smaller of two windows measured after a warm-up (a leak grows the
//! process in both windows; a cache that fills late, in one only).

#![allow(dead_code)]

/// The live GPU objects and memory wgpu counts on `device`. wgpu 30's Vulkan backend counts a
/// texture only when it is released (its `create_texture` does not add one), so its texture
/// count only falls, with every texture released, and cannot show a texture kept alive: the
/// texture memory and the texture views stand for the textures.
pub fn gpu_objects(device: &wgpu::Device) -> Vec<(&'static str, isize)> {
    let hal = device.get_internal_counters().hal;
    vec![
        ("buffers", hal.buffers.read()),
        ("texture views", hal.texture_views.read()),
        ("samplers", hal.samplers.read()),
        ("bind groups", hal.bind_groups.read()),
        ("bind group layouts", hal.bind_group_layouts.read()),
        ("pipeline layouts", hal.pipeline_layouts.read()),
        ("render pipelines", hal.render_pipelines.read()),
        ("compute pipelines", hal.compute_pipelines.read()),
        ("shader modules", hal.shader_modules.read()),
        ("query sets", hal.query_sets.read()),
        ("buffer memory", hal.buffer_memory.read()),
        ("texture memory", hal.texture_memory.read()),
    ]
}

/// Resident set size of this process in kB.
pub fn resident_kb() -> u64 {
    let status = std::fs::read_to_string("/proc/self/status").expect("/proc/self/status");
    status
        .lines()
        .find_map(|line| line.strip_prefix("VmRSS:"))
        .and_then(|rest| rest.split_whitespace().next()?.parse().ok())
        .expect("VmRSS in /proc/self/status")
}

/// The growth per frame of the window that grew less: resident sizes at the start, between
/// the windows and at the end (kB), and the frames of each window.
pub fn growth_per_frame([start, middle, end]: [u64; 3], [first, second]: [u64; 2]) -> f64 {
    let per_frame =
        |from: u64, to: u64, frames: u64| to.saturating_sub(from) as f64 / frames.max(1) as f64;
    per_frame(start, middle, first).min(per_frame(middle, end, second))
}

/// The GPU figures of [`gpu_objects`] that grew in both of two windows, with their values at
/// the start, between the windows and at the end. A leak grows a figure in both windows; a
/// high-water mark that is reached late, in one only (egui's vertex and index buffers are
/// replaced by buffers twice the size when a frame needs more: the count stays, the memory
/// grows once).
pub fn grown_in_both_windows(
    [start, middle, end]: [&[(&'static str, isize)]; 3],
) -> Vec<(&'static str, [isize; 3])> {
    start
        .iter()
        .zip(middle)
        .zip(end)
        .filter(|(((_, a), (_, b)), (_, c))| b > a && c > b)
        .map(|(((name, a), (_, b)), (_, c))| (*name, [*a, *b, *c]))
        .collect()
}
