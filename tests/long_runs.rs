//! Long runs stay flat: every technique renders a hundred frames in a row without the process
//! growing and with the same live GPU objects (buffers, textures, views, bind groups,
//! pipelines, GPU memory) at the end as at the start. Found on lavapipe, which specialises and recompiles at every draw the shaders whose
//! `if` conditions read uniforms only, and never frees the old variants: TAA grew by 1.1 MB
//! per frame, and every scene render of the atrium by about 4 MB (material switches). A test binary of its own, so that no other test's allocations
//! show in this process's resident size.

mod common;
#[path = "common/flat.rs"]
mod flat;

use aa_lab::aa::{self, FrameInfo};
use aa_lab::graph::{FrameGraph, FrameScope};
use aa_lab::scene::camera::FrameCamera;
use aa_lab::scene::procedural::SceneOptions;
use aa_lab::scene::source;

/// Frames rendered before the first measurement (pipelines, pools and caches fill up).
const WARM_UP_FRAMES: u64 = 12;
/// Frames of each of the two measured windows. A leak grows the process in both; a cache that
/// fills late (allocator arenas, the driver's first use of some state) only in one, so the
/// smaller growth of the two is what is judged.
const WINDOW_FRAMES: u64 = 50;
/// Growth allowed per frame: noise is a few kB; the leaks this guards against were 977-8059 kB.
const ALLOWED_KB_PER_FRAME: f64 = 100.0;

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
        let start = flat::resident_kb();
        let objects_before = flat::gpu_objects(&gpu.device);
        let middle_frame = WARM_UP_FRAMES + WINDOW_FRAMES;
        render(WARM_UP_FRAMES..middle_frame);
        let middle = flat::resident_kb();
        render(middle_frame..middle_frame + WINDOW_FRAMES);
        let end = flat::resident_kb();
        let objects_after = flat::gpu_objects(&gpu.device);
        let per_frame = flat::growth_per_frame([start, middle, end], [WINDOW_FRAMES; 2]);
        let name = format!(
            "{}{}",
            id,
            if debug_views { " with debug views" } else { "" }
        );
        report.push(format!(
            "{name}: {start} -> {middle} -> {end} kB ({per_frame:.1} kB/frame)"
        ));
        assert!(
            objects_before.iter().any(|(_, n)| *n > 0),
            "wgpu counts no GPU objects: the `counters` feature is off"
        );
        assert_eq!(
            objects_after,
            objects_before,
            "{name}: live GPU objects changed over {} frames",
            2 * WINDOW_FRAMES
        );
        assert!(
            per_frame <= ALLOWED_KB_PER_FRAME,
            "{name} grows by {per_frame:.0} kB per frame (allowed {ALLOWED_KB_PER_FRAME}):\n{}",
            report.join("\n")
        );
    }
    println!("{}", report.join("\n"));
}
