//! GPU tests of the engine on the generated flat chart (software Vulkan in CI).

mod common;

use aa_lab::aa::{self, FrameInfo};
use aa_lab::gpu::read_texture_rgba8;
use aa_lab::graph::{FrameGraph, FrameScope};
use aa_lab::scene::camera::FrameCamera;

#[test]
fn flat_chart_renders_through_every_available_technique() {
    let gpu = common::gpu();
    let scene = common::flat_chart(5.0);
    let mut graph = FrameGraph::new(gpu.clone(), &scene);
    for info in aa::registry() {
        if (info.availability)(&gpu.caps).is_ok() {
            graph.add((info.create)(&gpu));
        }
    }
    let frame = FrameInfo {
        camera: FrameCamera::from_rig(&scene.camera, 0, (320, 180)),
        reset_history: true,
    };
    graph
        .render(&frame, FrameScope::All)
        .expect("frame renders");
    graph.finish();
    for slot in graph.slots() {
        let image = read_texture_rgba8(&gpu, slot.output().expect("output")).expect("readback");
        image
            .save(format!("/tmp/flat-{}.png", slot.technique.id()))
            .ok();
        let dark = image.pixels().filter(|p| p[0] < 128).count();
        assert!(
            dark > 1000,
            "{} has {dark} dark pixels",
            slot.technique.id()
        );
    }
    println!("{:?}", graph.timings());
    println!("{}", graph.memory_report().table());
}
