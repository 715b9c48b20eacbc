//! GPU tests of the engine foundation: every built-in scene and every well-formed OBJ fixture
//! renders non-blank at several sizes, the same frame renders byte-identically twice, and
//! impossible sizes are refused with the limit named.

mod common;

use std::path::Path;

use aa_lab::aa::{self, FrameInfo};
use aa_lab::gpu::Gpu;
use aa_lab::graph::{FrameScope, GraphError};
use aa_lab::scene::procedural::{BUILTIN_SCENES, SceneOptions};
use aa_lab::scene::{Scene, source};

fn render_none(
    gpu: &Gpu,
    scene: &Scene,
    size: (u32, u32),
    frame: u64,
) -> Result<image::RgbaImage, GraphError> {
    let mut graph = common::graph(gpu, scene, vec![common::technique(gpu, aa::none::ID, &[])]);
    let info = FrameInfo {
        camera: common::camera(scene, frame, size),
        reset_history: true,
    };
    graph.render(&info, FrameScope::All)?;
    Ok(common::outputs(&mut graph).remove(0))
}

/// Share of pixels that differ from the top-left pixel (the background in every scene here).
fn coverage(image: &image::RgbaImage) -> f64 {
    let background = image.get_pixel(0, 0);
    image.pixels().filter(|p| *p != background).count() as f64
        / f64::from(image.width() * image.height())
}

#[test]
fn every_builtin_scene_renders_non_blank_at_several_sizes() {
    let gpu = common::gpu();
    for name in BUILTIN_SCENES {
        let scene = source::load(name, &SceneOptions::default()).expect("built-in scene loads");
        for size in [(64, 36), (333, 211), (640, 360)] {
            let image = render_none(&gpu, &scene, size, 0).expect("renders");
            assert_eq!(image.dimensions(), size);
            let covered = coverage(&image);
            assert!(
                covered > 0.05,
                "{name} at {size:?} is nearly blank ({covered:.3} covered)"
            );
        }
    }
}

#[test]
fn the_same_frame_renders_byte_identically_twice() {
    let gpu = common::gpu();
    for name in BUILTIN_SCENES {
        let scene = source::load(name, &SceneOptions::default()).expect("built-in scene loads");
        let first = render_none(&gpu, &scene, (320, 180), 17).expect("renders");
        let again = source::load(name, &SceneOptions::default()).expect("built-in scene loads");
        let second = render_none(&gpu, &again, (320, 180), 17).expect("renders");
        assert!(first == second, "{name}: frame 17 differs between two runs");
        if scene.camera.orbit_degrees_per_frame != 0.0 {
            let other = render_none(&gpu, &scene, (320, 180), 18).expect("renders");
            assert!(
                first != other,
                "{name}: frame 18 equals frame 17 although the camera orbits"
            );
        }
    }
}

#[test]
fn well_formed_obj_fixtures_render() {
    let gpu = common::gpu();
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/obj");
    for name in [
        "cube.obj",
        "textured_quad.obj",
        "ngons.obj",
        "two_materials.obj",
        "alpha_card.obj",
        "subdir_texture.obj",
    ] {
        let scene = source::load(
            dir.join(name).to_str().expect("utf-8 path"),
            &SceneOptions::default(),
        )
        .unwrap_or_else(|e| panic!("{name}: {e}"));
        let image = render_none(&gpu, &scene, (160, 90), 0).expect("renders");
        assert!(coverage(&image) > 0.02, "{name} rendered blank");
    }
}

#[test]
fn zero_and_oversized_images_are_refused_with_the_limit_named() {
    let gpu = common::gpu();
    let scene = common::flat_chart(5.0);
    let zero = render_none(&gpu, &scene, (0, 100), 0).expect_err("zero width refused");
    assert!(zero.to_string().contains("at least 1"), "{zero}");
    let limit = gpu.caps.max_texture_dimension_2d;
    let huge = render_none(&gpu, &scene, (limit + 1, 10), 0).expect_err("oversized refused");
    assert!(huge.to_string().contains(&limit.to_string()), "{huge}");
}

/// Renders `ids` together in one graph over frames 0..=`last` of the orbiting camera and
/// returns each technique's final output, keyed by id.
fn render_together(
    gpu: &Gpu,
    scene: &Scene,
    ids: &[&str],
    last: u64,
) -> Vec<(String, image::RgbaImage)> {
    let techniques = ids
        .iter()
        .map(|id| {
            let settings: &[(&str, &str)] = if *id == aa::ssaa::ID {
                &[("mode", "jittered")]
            } else {
                &[]
            };
            common::technique(gpu, id, settings)
        })
        .collect();
    let images = common::render_techniques(gpu, scene, techniques, (160, 90), last);
    ids.iter().map(|id| (*id).to_owned()).zip(images).collect()
}

/// Many scene renders in one frame (16 jittered SSAA samples, two temporal inputs, MSAA) must
/// not disturb one another: each technique's output is byte-identical to its output alone.
/// (Guards the per-render view uniforms: overlapping slots once corrupted the motion-vector
/// switch and texture mip bias of every scene render but the frame's last.)
#[test]
fn a_technique_renders_the_same_alone_and_among_others() {
    let gpu = common::gpu();
    let scene = source::load("atrium", &SceneOptions::default()).expect("built-in scene loads");
    let all = ["none", "ssaa", "msaa4", "smaa-t2x", "taa"];
    let together = render_together(&gpu, &scene, &all, 2);
    for (id, image) in together {
        let alone = render_together(&gpu, &scene, &[id.as_str()], 2);
        assert!(
            alone[0].1 == image,
            "{id} differs when other techniques share its frame"
        );
    }
}

/// Bytes of the textures wgpu's backend holds on the test device (dev-dependency feature
/// `counters`; each test opens a device of its own, so no other test shows here). The
/// texture count is not used: the Vulkan backend counts destructions but not every creation.
fn texture_bytes_held(gpu: &Gpu) -> isize {
    gpu.device.get_internal_counters().hal.texture_memory.read()
}

/// The memory report's scene inputs are exactly what the graph pools, and the total is the
/// scene, those inputs (each once) and every technique's own memory, idle ones included.
fn assert_report_is_what_is_held(graph: &aa_lab::graph::FrameGraph) {
    let report = graph.memory_report();
    let mut seen = Vec::new();
    let mut listed_inputs = 0;
    for t in &report.techniques {
        if let Some(input) = &t.input
            && !seen.contains(input)
        {
            seen.push(input.clone());
            listed_inputs += t.input_bytes();
        }
    }
    assert_eq!(
        listed_inputs,
        graph.pooled_input_bytes(),
        "{}",
        report.table()
    );
    let own: u64 = report
        .techniques
        .iter()
        .chain(&report.idle)
        .map(|t| t.own_bytes())
        .sum();
    assert_eq!(report.total_bytes, report.scene_bytes + listed_inputs + own);
}

/// A technique switched off gives its scene input back (MSAA 4x's multisampled targets are
/// released at the next frame, on the device as in the report), what it still owns is
/// reported apart as idle, and a technique that keeps an earlier image keeps its input.
#[test]
fn switching_a_technique_off_releases_its_scene_input_and_the_report_shows_what_is_held() {
    let gpu = common::gpu();
    let scene = source::load("hairball", &SceneOptions::default()).expect("built-in scene loads");
    let ids = [aa::none::ID, "msaa4", aa::taa::ID];
    let techniques = ids
        .iter()
        .map(|id| common::technique(&gpu, id, &[]))
        .collect();
    let mut graph = common::graph(&gpu, &scene, techniques);
    let frame = |n| FrameInfo {
        camera: common::camera(&scene, n, (96, 64)),
        reset_history: n == 0,
    };
    graph.render(&frame(0), FrameScope::All).expect("renders");
    graph.finish();
    assert_report_is_what_is_held(&graph);
    let before = graph.memory_report();
    let msaa = before.techniques.iter().find(|t| t.technique == "msaa4");
    let msaa = msaa.expect("MSAA 4x in the report");
    let msaa_input_bytes = msaa.input_bytes();
    assert!(msaa_input_bytes > 0 && msaa.input_shared_with == ["msaa4"]);
    let held_before = texture_bytes_held(&gpu);

    // Kept (not running, its image from the last frame on screen): nothing is released.
    graph.slots_mut()[1].enabled = false;
    graph.slots_mut()[1].kept = true;
    graph.render(&frame(1), FrameScope::All).expect("renders");
    graph.finish();
    assert_eq!(texture_bytes_held(&gpu), held_before);
    assert_report_is_what_is_held(&graph);
    let kept = graph.memory_report();
    assert_eq!(kept.total_bytes, before.total_bytes);
    assert!(kept.techniques.iter().any(|t| t.technique == "msaa4"));

    // Switched off: its input goes, its own targets are listed as idle.
    graph.slots_mut()[1].kept = false;
    graph.render(&frame(2), FrameScope::All).expect("renders");
    graph.finish();
    let released = held_before - texture_bytes_held(&gpu);
    assert!(
        released >= 0 && released as u64 >= msaa_input_bytes,
        "{released} bytes released on the device, {msaa_input_bytes} in the report"
    );
    assert_report_is_what_is_held(&graph);
    let after = graph.memory_report();
    assert_eq!(after.total_bytes, before.total_bytes - msaa_input_bytes);
    assert!(after.techniques.iter().all(|t| t.technique != "msaa4"));
    assert_eq!(after.idle.len(), 1);
    assert_eq!(after.idle[0].technique, "msaa4");

    // And back on: the same figures as before.
    graph.slots_mut()[1].enabled = true;
    graph.render(&frame(3), FrameScope::All).expect("renders");
    graph.finish();
    assert_eq!(graph.memory_report().total_bytes, before.total_bytes);
    assert_eq!(texture_bytes_held(&gpu), held_before);
}
