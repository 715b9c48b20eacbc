//! Long runs stay flat: every technique renders a hundred frames in a row without the process
//! growing. Found on lavapipe, which specialises and recompiles at every draw the shaders whose
//! `if` conditions read uniforms only, and never frees the old variants: TAA grew by 1.1 MB
//! per frame, and every scene render of the atrium by about 4 MB (material switches). A test binary of its own, so that no other test's allocations
//! show in this process's resident size.

mod common;

use aa_lab::aa::{self, FrameInfo};
use aa_lab::graph::{FrameGraph, FrameScope};
use aa_lab::scene::camera::FrameCamera;
use aa_lab::scene::procedural::SceneOptions;
use aa_lab::scene::source;

/// Frames rendered before the first measurement (pipelines, pools and caches fill up).
const WARM_UP_FRAMES: u64 = 12;
/// Frames between the two measurements.
const MEASURED_FRAMES: u64 = 100;
/// Growth allowed per frame: allocator noise is a few kB; the TAA leak was about 1100 kB.
const ALLOWED_KB_PER_FRAME: f64 = 60.0;

/// Resident set size of this process in kB.
fn resident_kb() -> u64 {
    let status = std::fs::read_to_string("/proc/self/status").expect("/proc/self/status");
    status
        .lines()
        .find_map(|line| line.strip_prefix("VmRSS:"))
        .and_then(|rest| rest.split_whitespace().next()?.parse().ok())
        .expect("VmRSS in /proc/self/status")
}

#[test]
#[cfg(target_os = "linux")]
fn every_technique_renders_hundreds_of_frames_without_growing() {
    let gpu = common::gpu();
    // The atrium: many materials (masked, unlit, lit) drawn in turn, spinning objects.
    let scene = source::load("atrium", &SceneOptions::default()).expect("atrium");
    let size = (48, 32);
    let mut report = Vec::new();
    let available: Vec<_> = aa::registry()
        .into_iter()
        .filter(|info| (info.availability)(&gpu.caps).is_ok())
        .map(|info| (info.id, info.create))
        .collect();
    for ((id, create), debug_views) in available
        .iter()
        .flat_map(|technique| [(technique, false), (technique, true)])
    {
        let mut graph = FrameGraph::new(gpu.clone(), &scene);
        let index = graph.add(create(&gpu));
        graph.slots_mut()[index]
            .technique
            .set_debug_views(debug_views);
        let mut render = |frames: std::ops::Range<u64>| {
            for frame in frames {
                let info = FrameInfo {
                    camera: FrameCamera::from_rig(&scene.camera, frame, size),
                    reset_history: frame == 0,
                };
                graph.render(&info, FrameScope::All).expect("frame renders");
                // Nothing may pile up in flight: each frame finishes before the next.
                graph.finish();
            }
        };
        render(0..WARM_UP_FRAMES);
        let before = resident_kb();
        render(WARM_UP_FRAMES..WARM_UP_FRAMES + MEASURED_FRAMES);
        let after = resident_kb();
        let per_frame = after.saturating_sub(before) as f64 / MEASURED_FRAMES as f64;
        let name = format!(
            "{}{}",
            id,
            if debug_views { " with debug views" } else { "" }
        );
        report.push(format!(
            "{name}: {before} -> {after} kB ({per_frame:.1} kB/frame)"
        ));
        assert!(
            per_frame <= ALLOWED_KB_PER_FRAME,
            "{name} grows by {per_frame:.0} kB per frame (allowed {ALLOWED_KB_PER_FRAME}):\n{}",
            report.join("\n")
        );
    }
    println!("{}", report.join("\n"));
}
