//! GPU tests of the sampling-based techniques (MSAA, SSAA) and of the frame graph's sharing and
//! memory accounting, on the generated flat chart whose content is known exactly.

mod common;

use std::collections::BTreeSet;

use aa_lab::aa::{self, FrameInfo, ParamValue, SceneInput, Technique};
use aa_lab::gpu::Gpu;
use aa_lab::graph::{FrameGraph, FrameScope};
use aa_lab::scene::Scene;

const SIZE: (u32, u32) = (320, 180);

fn frame(scene: &Scene, size: (u32, u32)) -> FrameInfo {
    FrameInfo {
        camera: common::camera(scene, 0, size),
        reset_history: true,
    }
}

/// Renders one frame of `techniques` and returns each output's red channel, row-major.
fn render(gpu: &Gpu, scene: &Scene, techniques: Vec<Box<dyn Technique>>) -> Vec<Vec<u8>> {
    render_frames(gpu, scene, techniques, 0)
}

/// Renders frames 0..=`last` of `techniques` (temporal ones converge on the still chart) and
/// returns each output's red channel of the last frame, row-major.
fn render_frames(
    gpu: &Gpu,
    scene: &Scene,
    techniques: Vec<Box<dyn Technique>>,
    last: u64,
) -> Vec<Vec<u8>> {
    common::render_techniques(gpu, scene, techniques, SIZE, last)
        .iter()
        .map(|image| image.pixels().map(|p| p[0]).collect())
        .collect()
}

/// Distinct grey levels among the pixels of rows `rows` whose value is strictly between black
/// and white, in the columns `columns`.
fn levels(image: &[u8], rows: std::ops::Range<u32>, columns: std::ops::Range<u32>) -> BTreeSet<u8> {
    rows.flat_map(|y| columns.clone().map(move |x| (x, y)))
        .map(|(x, y)| image[(y * SIZE.0 + x) as usize])
        .filter(|v| *v > 0 && *v < 255)
        .collect()
}

/// The intermediate levels along the edge that hold at least 10% of the edge's intermediate
/// pixels: the gradation a viewer actually sees.
fn common_levels(image: &[u8]) -> BTreeSet<u8> {
    let values: Vec<u8> = EDGE_ROWS
        .flat_map(|y| EDGE_COLUMNS.map(move |x| image[(y * SIZE.0 + x) as usize]))
        .filter(|v| *v > 0 && *v < 255)
        .collect();
    let distinct: BTreeSet<u8> = values.iter().copied().collect();
    distinct
        .into_iter()
        .filter(|l| values.iter().filter(|v| *v == l).count() * 10 >= values.len())
        .collect()
}

// The flat chart's slanted edge runs through the middle rows, from about x = 150 to 170 at
// 320x180; the alpha card occupies x 20..110, y 60..120.
const EDGE_ROWS: std::ops::Range<u32> = 40..140;
const EDGE_COLUMNS: std::ops::Range<u32> = 130..190;

#[test]
fn msaa4_box_resolve_gives_exactly_the_coverage_levels() {
    let gpu = common::gpu();
    let scene = common::flat_chart(5.0);
    let images = render(
        &gpu,
        &scene,
        vec![
            common::technique(&gpu, "msaa4", &[]),
            common::technique(&gpu, "ssaa", &[("factor", "4")]),
        ],
    );
    let allowed: Vec<u8> = [0.25f32, 0.5, 0.75]
        .iter()
        .map(|c| aa_lab::srgb::encode_byte(1.0 - c))
        .collect();
    let msaa = levels(&images[0], EDGE_ROWS, EDGE_COLUMNS);
    assert!(!msaa.is_empty(), "no edge pixels found");
    for v in &msaa {
        assert!(
            allowed.iter().any(|a| a.abs_diff(*v) <= 1),
            "MSAA 4x level {v} is not a coverage level {allowed:?}"
        );
    }
    let ssaa = levels(&images[1], EDGE_ROWS, EDGE_COLUMNS);
    assert!(
        ssaa.len() > msaa.len(),
        "SSAA 16x levels {ssaa:?} should outnumber MSAA 4x levels {msaa:?}"
    );
    assert!(
        ssaa.len() >= 8,
        "SSAA 16x gives only {} levels: {ssaa:?}",
        ssaa.len()
    );
}

#[test]
fn rotated_grid_gives_more_levels_than_regular_grid_on_a_near_vertical_edge() {
    let gpu = common::gpu();
    let scene = common::flat_chart(3.0);
    let jittered = |pattern| {
        common::technique(
            &gpu,
            "ssaa",
            &[("mode", "jittered"), ("samples", "4"), ("pattern", pattern)],
        )
    };
    let images = render(&gpu, &scene, vec![jittered("grid"), jittered("rgss")]);
    let grid = common_levels(&images[0]);
    let rgss = common_levels(&images[1]);
    // A 2x2 grid has two sample columns, so a near-vertical edge gives one intermediate level
    // (the others appear only where the edge slips between the two sample rows); the rotated
    // grid has four distinct columns and gives three, evenly.
    assert_eq!(grid.len(), 1, "grid levels {grid:?}");
    assert!(rgss.len() >= 3, "rgss levels {rgss:?}");
}

#[test]
fn alpha_to_coverage_gives_partial_pixels_where_the_alpha_test_gives_none() {
    let gpu = common::gpu();
    let scene = common::flat_chart(5.0);
    let images = render(
        &gpu,
        &scene,
        vec![
            common::technique(&gpu, "msaa4", &[]),
            common::technique(&gpu, "msaa4", &[("alpha_to_coverage", "on")]),
        ],
    );
    // Interior rows of the card (away from its top and bottom geometric edges), across the
    // alpha ramp; the card's left geometric edge is at x = 20 and its right at x = 110.
    let card = |image: &[u8]| levels(image, 70..110, 25..105);
    let tested = card(&images[0]);
    let covered = card(&images[1]);
    assert!(
        tested.is_empty(),
        "alpha test produced partial pixels {tested:?}"
    );
    assert!(
        !covered.is_empty(),
        "alpha-to-coverage produced no partial pixels"
    );
}

#[test]
fn ssaa_reference_edge_has_intermediate_values() {
    let gpu = common::gpu();
    let scene = common::flat_chart(5.0);
    let images = render(
        &gpu,
        &scene,
        vec![
            common::technique(&gpu, "ssaa", &[("factor", "8")]),
            common::technique(&gpu, "none", &[]),
        ],
    );
    assert!(
        levels(&images[0], EDGE_ROWS, EDGE_COLUMNS).len() >= 16,
        "64-sample reference lacks gradation"
    );
    assert!(
        levels(&images[1], EDGE_ROWS, EDGE_COLUMNS).is_empty(),
        "No AA should be pure black and white"
    );
}

#[test]
fn every_technique_differs_from_no_aa_on_edges_and_matches_it_on_flat_areas() {
    let gpu = common::gpu();
    let scene = common::flat_chart(5.0);
    let ids: Vec<&str> = aa::registry()
        .into_iter()
        .filter(|i| (i.availability)(&gpu.caps).is_ok())
        .map(|i| i.id)
        .collect();
    // Sixteen frames, so that temporal techniques have accumulated their jitter sequence.
    let images = render_frames(
        &gpu,
        &scene,
        ids.iter()
            .map(|id| common::technique(&gpu, id, &[]))
            .collect(),
        16,
    );
    let none = &images[ids
        .iter()
        .position(|id| *id == "none")
        .expect("none is registered")];
    for (id, image) in ids.iter().zip(&images) {
        // Flat areas: the white background's corner and the black quad's interior.
        for (x, y) in [(5, 5), (300, 20), (260, 90), (230, 70)] {
            let i = (y * SIZE.0 + x) as usize;
            assert!(
                image[i].abs_diff(none[i]) <= 1,
                "{id} changed flat pixel ({x},{y})"
            );
        }
        if *id != "none" {
            let changed = EDGE_ROWS
                .flat_map(|y| EDGE_COLUMNS.map(move |x| (y * SIZE.0 + x) as usize))
                .filter(|&i| image[i] != none[i])
                .count();
            assert!(changed >= 50, "{id} changed only {changed} edge pixels");
        }
    }
}

#[test]
fn one_scene_render_per_distinct_input() {
    let gpu = common::gpu();
    let scene = common::flat_chart(5.0);
    let mut graph = FrameGraph::new(gpu.clone(), &scene);
    let info = frame(&scene, SIZE);
    let mut one_x = 0;
    for entry in aa::registry()
        .into_iter()
        .filter(|i| (i.availability)(&gpu.caps).is_ok())
    {
        let t = (entry.create)(&gpu);
        if t.scene_input(&info) == Some(SceneInput::Shared1x) {
            one_x += 1;
            graph.add(t);
        }
    }
    graph.add(common::technique(&gpu, "msaa4", &[]));
    graph.add(common::technique(&gpu, "msaa4", &[("resolve", "tent")]));
    graph.render(&info, FrameScope::All).expect("frame renders");
    graph.finish();
    assert!(one_x >= 1);
    // One 1x render for every 1x technique, one 4x render for both MSAA variants.
    assert_eq!(graph.scene_renders_last_frame(), 2);
    let timings = graph.timings().expect("lavapipe has timestamps");
    assert_eq!(
        timings
            .passes
            .iter()
            .filter(|p| p.label == "scene 1x")
            .count(),
        1
    );
    assert_eq!(
        timings
            .passes
            .iter()
            .filter(|p| p.label.starts_with("scene msaa4"))
            .count(),
        1
    );
}

#[test]
fn msaa4_memory_at_4k_matches_the_arithmetic() {
    let gpu = common::gpu();
    let scene = common::flat_chart(5.0);
    let mut graph = FrameGraph::new(gpu.clone(), &scene);
    graph.add(common::technique(&gpu, "msaa4", &[]));
    let info = frame(&scene, (3840, 2160));
    graph
        .render(&info, FrameScope::All)
        .expect("4K frame renders");
    graph.finish();
    let report = graph.memory_report();
    let msaa = &report.techniques[0];
    let pixels: u64 = 3840 * 2160;
    let bytes = |suffix: &str| {
        msaa.input_items
            .iter()
            .find(|i| i.label.ends_with(suffix))
            .map(|i| i.bytes)
    };
    // RGBA8 colour and 32-bit depth, 4 samples each: 4 x 3840 x 2160 x 4 bytes = 132.7 MB each
    // (the article's "33 MB -> 132 MB"), plus the 33.2 MB one-sample resolve target.
    assert_eq!(bytes("color"), Some(4 * pixels * 4));
    assert_eq!(bytes("depth"), Some(4 * pixels * 4));
    assert_eq!(bytes("resolve"), Some(pixels * 4));
    assert_eq!(msaa.input_bytes(), 9 * pixels * 4);
    assert_eq!(msaa.output.as_ref().map(|o| o.bytes), Some(pixels * 4));
}

#[test]
fn unsupported_sample_count_is_refused_with_the_supported_list() {
    let gpu = common::gpu();
    for id in ["msaa2", "msaa8", "msaa16"] {
        let samples: u32 = id[4..].parse().expect("count");
        match aa::create(&gpu, id) {
            Ok(_) => assert!(
                gpu.caps.supports_sample_count(samples),
                "{id} created although unsupported"
            ),
            Err(err) => {
                let text = err.to_string();
                assert!(text.contains("supported sample counts"), "{text}");
                assert!(!gpu.caps.supports_sample_count(samples));
            }
        }
    }
    // Parameters are validated against their ranges.
    let mut ssaa = aa::create(&gpu, "ssaa").expect("ssaa");
    assert!(aa::set_param(ssaa.as_mut(), "samples", ParamValue::Int(1000)).is_err());
    assert!(
        aa::set_param(
            ssaa.as_mut(),
            "pattern",
            ParamValue::Choice("spiral".into())
        )
        .is_err()
    );
}
