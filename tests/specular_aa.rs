//! The `sparkle` scene and the scene renderer's geometric specular antialiasing
//! (`--specular-aa`): the scene renders the same twice and has sub-pixel glints that No AA
//! shows and the 64-sample reference averages away; the option changes nothing on a scene
//! without specular highlights, is followed by every technique but the reference, and lowers
//! the sparkle scene's temporal instability on a pan for No AA and for TAA.

mod common;

use aa_lab::gpu::Gpu;
use aa_lab::graph::FrameGraph;
use aa_lab::scene::Scene;
use aa_lab::scene::procedural::{SceneOptions, builtin};
use image::RgbaImage;

const SIZE: (u32, u32) = (320, 180);

fn scene(name: &str) -> Scene {
    builtin(name, &SceneOptions::default()).expect("built-in scene")
}

/// A graph of `ids` (No AA, TAA...) and, last, the bench's 64-sample reference, with
/// specular antialiasing as `specular_aa` says.
fn graph_with_reference(gpu: &Gpu, scene: &Scene, ids: &[&str], specular_aa: bool) -> FrameGraph {
    let mut graph = common::graph_with_reference(gpu, scene, ids);
    graph.set_specular_aa(specular_aa);
    graph
}

/// Pixels brighter than half of full scale whose eight neighbours are all at most half as
/// bright (largest channel): glints a pixel or less across.
fn isolated_glints(image: &RgbaImage) -> usize {
    let level = |x: u32, y: u32| {
        image.get_pixel(x, y).0[..3]
            .iter()
            .copied()
            .max()
            .unwrap_or(0)
    };
    let (w, h) = image.dimensions();
    let mut count = 0;
    for y in 1..h - 1 {
        for x in 1..w - 1 {
            let centre = level(x, y);
            let isolated = (y - 1..=y + 1)
                .flat_map(|j| (x - 1..=x + 1).map(move |i| (i, j)))
                .filter(|&(i, j)| (i, j) != (x, y))
                .all(|(i, j)| 2 * u16::from(level(i, j)) <= u16::from(centre));
            count += usize::from(centre >= 128 && isolated);
        }
    }
    count
}

#[test]
fn sparkle_has_sub_pixel_glints_that_the_reference_averages_away() {
    let gpu = common::gpu();
    let scene = scene("sparkle");
    let render = || {
        let mut graph = graph_with_reference(&gpu, &scene, &["none"], false);
        common::render_frames(&mut graph, &scene, SIZE, 16..=16)
    };
    let (first, second) = (render(), render());
    assert!(first == second, "two renders of sparkle differ");
    let (none, reference) = (&first[0], &first[1]);
    let (glints, reference_glints) = (isolated_glints(none), isolated_glints(reference));
    assert!(glints >= 40, "No AA shows {glints} isolated glints");
    assert!(
        reference_glints * 10 <= glints,
        "the reference keeps {reference_glints} of No AA's {glints} isolated glints"
    );
}

#[test]
fn specular_aa_spares_unshaded_scenes_and_the_reference() {
    let gpu = common::gpu();
    // The chart is unlit: no specular lobe to widen, so the option must not change a byte.
    let chart = scene("chart");
    let chart_render = |on: bool| {
        let mut graph = common::graph(&gpu, &chart, vec![common::technique(&gpu, "none", &[])]);
        graph.set_specular_aa(on);
        common::render_frames(&mut graph, &chart, SIZE, 0..=0)
    };
    assert!(
        chart_render(false) == chart_render(true),
        "the option changed the chart"
    );
    // On sparkle it changes No AA but not the reference in the same graph.
    let sparkle = scene("sparkle");
    let render = |on: bool| {
        let mut graph = graph_with_reference(&gpu, &sparkle, &["none"], on);
        common::render_frames(&mut graph, &sparkle, SIZE, 16..=16)
    };
    let (off, on) = (render(false), render(true));
    assert!(
        off[0] != on[0],
        "the option did not change No AA on sparkle"
    );
    assert!(off[1] == on[1], "the option changed the reference");
    assert!(
        isolated_glints(&on[0]) * 2 <= isolated_glints(&off[0]),
        "the option left {} of No AA's {} isolated glints",
        isolated_glints(&on[0]),
        isolated_glints(&off[0])
    );
}

/// Temporal instability of No AA and TAA (in that order) on a pan over sparkle, against the
/// reference of the same graph, the first 4 frames left out.
fn pan_instability(gpu: &Gpu, scene: &Scene, specular_aa: bool) -> [f64; 2] {
    let mut graph = graph_with_reference(gpu, scene, &["none", "taa"], specular_aa);
    let figures = common::pan_instability(&mut graph, scene, SIZE, 4, 12);
    [figures[0], figures[1]]
}

#[test]
fn specular_aa_lowers_sparkle_instability_for_no_aa_and_taa() {
    let gpu = common::gpu();
    let scene = scene("sparkle");
    let off = pan_instability(&gpu, &scene, false);
    let on = pan_instability(&gpu, &scene, true);
    eprintln!("instability of No AA and TAA: {off:.3?} without, {on:.3?} with specular AA");
    for (name, (off, on)) in ["No AA", "TAA"].iter().zip(off.into_iter().zip(on)) {
        assert!(on < 0.8 * off, "{name}: {on:.3} with, {off:.3} without");
    }
}

/// Runs the binary with `args`, failing with its error output.
fn run_ok(args: &[&str]) {
    let out = common::aa_lab(args);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{args:?} failed: {stderr}");
}

fn pixels(path: &std::path::Path) -> RgbaImage {
    image::open(path)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
        .to_rgba8()
}

#[test]
fn the_render_record_keeps_the_option_and_from_reproduces_it() {
    let dir = tempfile::tempdir().expect("temp dir");
    let path = |name: &str| dir.path().join(name).to_str().expect("utf-8").to_owned();
    let scene = [
        "--scene", "sparkle", "-t", "none", "--size", "160x90", "--frame", "2",
    ];
    run_ok(&[&["render"][..], &scene, &["--out", &path("off.png")]].concat());
    run_ok(
        &[
            &["render"][..],
            &scene,
            &["--specular-aa", "--out", &path("on.png")],
        ]
        .concat(),
    );
    let (off, on) = (
        pixels(&dir.path().join("off.png")),
        pixels(&dir.path().join("on.png")),
    );
    assert!(off != on, "--specular-aa changed nothing");
    assert!(
        common::assert_from_reproduces(&dir.path().join("on.png")) == on,
        "--from lost the option"
    );
}
