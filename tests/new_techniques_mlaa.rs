//! GPU tests of MLAA and SMAA 4x (software Vulkan in CI). On the built-in chart, scored against
//! its exact analytic coverage (`metrics::coverage`), both remove most of No AA's error on the
//! slanted-edge bars; MLAA changes edge pixels only and honours its settings; both are
//! deterministic, have debug views of the output's size, and SMAA 4x says which path it runs,
//! renders the scene as often as that path needs and drops its history on a reset.

mod common;

use aa_lab::aa::{FrameInfo, Technique};
use aa_lab::gpu::{Gpu, read_texture_rgba8};
use aa_lab::graph::{FrameGraph, FrameScope};
use aa_lab::metrics::coverage::chart_truth;
use aa_lab::scene::Scene;
use aa_lab::scene::camera::FrameCamera;
use aa_lab::scene::procedural::{ChartFeature, SceneOptions, chart_layout};
use image::RgbaImage;

const SIZE: (u32, u32) = (320, 180);

fn graph(gpu: &Gpu, scene: &Scene, techniques: Vec<Box<dyn Technique>>) -> FrameGraph {
    let mut graph = FrameGraph::new(gpu.clone(), scene);
    for t in techniques {
        graph.add(t);
    }
    graph
}

/// Renders frames `frames` of the scene's own (still) camera at `size`, the first with a
/// history reset, and returns every slot's output after the last.
fn render_frames(
    graph: &mut FrameGraph,
    scene: &Scene,
    frames: std::ops::RangeInclusive<u64>,
    size: (u32, u32),
) -> Vec<RgbaImage> {
    let first = *frames.start();
    for frame in frames {
        let info = FrameInfo {
            camera: FrameCamera::from_rig(&scene.camera, frame, size),
            reset_history: frame == first,
        };
        graph
            .render(&info, FrameScope::All)
            .unwrap_or_else(|e| panic!("{e}"));
    }
    graph.finish();
    graph
        .slots()
        .iter()
        .map(|s| read_texture_rgba8(graph.gpu(), s.output().expect("output")).expect("readback"))
        .collect()
}

/// The pixel rectangles (x0, y0, x1, y1; max exclusive) of the chart's slanted-edge bars at
/// `size`, grown by two pixels, with their labels.
fn slanted_edge_windows(size: (u32, u32)) -> Vec<(String, (u32, u32, u32, u32))> {
    let layout = chart_layout();
    let scale = size.1 as f32 / (layout.max.y - layout.min.y);
    let centre = (layout.min + layout.max) * 0.5;
    let to_pixels = |p: glam::Vec2| {
        glam::Vec2::new(
            size.0 as f32 * 0.5 + (p.x - centre.x) * scale,
            size.1 as f32 * 0.5 - (p.y - centre.y) * scale,
        )
    };
    layout
        .regions
        .iter()
        .filter(|r| r.feature == ChartFeature::SlantedEdge)
        .map(|r| {
            let (a, b) = (to_pixels(r.min), to_pixels(r.max));
            let lo = (a.min(b) - 2.0).floor().max(glam::Vec2::ZERO);
            let hi = (a.max(b) + 2.0).ceil();
            let window = (
                lo.x as u32,
                lo.y as u32,
                (hi.x as u32).min(size.0),
                (hi.y as u32).min(size.1),
            );
            (r.label.clone(), window)
        })
        .collect()
}

/// Mean absolute error in 8-bit steps over the windows.
fn windows_error(image: &RgbaImage, truth: &RgbaImage, windows: &[(u32, u32, u32, u32)]) -> f64 {
    let (mut sum, mut count) = (0u64, 0u64);
    for &(x0, y0, x1, y1) in windows {
        for y in y0..y1 {
            for x in x0..x1 {
                let (p, q) = (image.get_pixel(x, y), truth.get_pixel(x, y));
                sum += (0..3).map(|c| u64::from(p[c].abs_diff(q[c]))).sum::<u64>();
                count += 3;
            }
        }
    }
    sum as f64 / count as f64
}

#[test]
fn mlaa_and_smaa_4x_remove_most_of_no_aas_error_on_the_charts_slanted_edges() {
    let gpu = common::gpu();
    let scene = aa_lab::scene::source::load("chart", &SceneOptions::default())
        .unwrap_or_else(|e| panic!("{e}"));
    let size = (640, 360);
    let ids = ["none", "mlaa", "smaa-4x", "smaa"];
    let techniques = ids.iter().map(|id| common::technique(&gpu, id, &[]));
    let mut graph = graph(&gpu, &scene, techniques.collect());
    // Two frames: SMAA 4x has seen all four of its sample positions.
    let images = render_frames(&mut graph, &scene, 0..=1, size);
    let truth = chart_truth(&chart_layout(), size);
    let bars = slanted_edge_windows(size);
    assert_eq!(bars.len(), 5, "{bars:?}");
    let all: Vec<_> = bars.iter().map(|(_, w)| *w).collect();
    for (label, window) in &bars {
        let errors: Vec<String> = ids
            .iter()
            .zip(&images)
            .map(|(id, image)| {
                format!("{id} {:.3}", windows_error(image, &truth.image, &[*window]))
            })
            .collect();
        println!("{label}: {}", errors.join(", "));
    }
    let [none, mlaa, smaa_4x, smaa] =
        [0, 1, 2, 3].map(|i| windows_error(&images[i], &truth.image, &all));
    println!(
        "slanted edges vs the analytic truth: No AA {none:.3}, MLAA {mlaa:.3}, SMAA 4x {smaa_4x:.3}, \
         SMAA 1x {smaa:.3}"
    );
    assert!(mlaa < 0.5 * none, "MLAA {mlaa:.3} vs No AA {none:.3}");
    assert!(
        smaa_4x < 0.5 * none,
        "SMAA 4x {smaa_4x:.3} vs No AA {none:.3}"
    );
}

/// Whether the (2r+1)^2 neighbourhood of (x, y) has one colour (never at the border).
fn flat_within(image: &RgbaImage, x: u32, y: u32, r: u32) -> bool {
    if x < r || y < r || x + r >= image.width() || y + r >= image.height() {
        return false;
    }
    let centre = image.get_pixel(x, y);
    (y - r..=y + r).all(|j| (x - r..=x + r).all(|i| image.get_pixel(i, j) == centre))
}

#[test]
fn mlaa_changes_edges_only_and_honours_its_settings() {
    let gpu = common::gpu();
    let scene = common::flat_chart(5.0);
    let preset = |name: &str| {
        let mut t = common::technique(&gpu, "mlaa", &[]);
        t.apply_preset(name).unwrap_or_else(|e| panic!("{e}"));
        t
    };
    let mut graph = graph(
        &gpu,
        &scene,
        vec![
            common::reference(&gpu),
            common::technique(&gpu, "none", &[]),
            common::technique(&gpu, "mlaa", &[]),
            common::technique(&gpu, "mlaa", &[("edge_detection", "color")]),
            preset("low"),
            preset("high"),
            common::technique(&gpu, "mlaa", &[("max_search_steps", "1")]),
        ],
    );
    let images = render_frames(&mut graph, &scene, 0..=0, SIZE);
    let (reference, none) = (&images[0], &images[1]);
    // The slanted edge of the flat chart (its other edges are pixel-aligned).
    let window = (112, 40, 78, 100);
    let error = |i: usize| common::window_error(&images[i], reference, window);
    for (i, image) in images.iter().enumerate().skip(2) {
        let mut changed = 0;
        for (x, y, p) in none.enumerate_pixels() {
            let d = common::largest_channel_difference(p, image.get_pixel(x, y));
            if flat_within(none, x, y, 2) {
                assert!(d <= 1, "variant {i}: flat pixel {x},{y} changed by {d}");
            } else if d > 1 {
                changed += 1;
            }
        }
        assert!(
            changed > 50,
            "variant {i}: only {changed} edge pixels changed"
        );
    }
    let [no_aa, default, color, low, high, short] = [1, 2, 3, 4, 5, 6].map(error);
    println!(
        "flat chart, 5 degrees: No AA {no_aa:.3}, MLAA {default:.3}, color {color:.3}, low {low:.3}, \
         high {high:.3}, one search step {short:.3}"
    );
    for (name, e) in [
        ("default", default),
        ("color", color),
        ("low", low),
        ("high", high),
    ] {
        assert!(e < 0.5 * no_aa, "{name}: {e:.3} vs No AA {no_aa:.3}");
    }
    // The edge's runs are about 11 pixels long: one fetch each way (two pixels) misses most
    // ends, and an end not found is treated as flat.
    assert!(
        short > default,
        "one search step {short:.3} vs default {default:.3}"
    );
}

#[test]
fn both_are_deterministic_and_have_debug_views_of_the_output_size() {
    let gpu = common::gpu();
    let scene = common::flat_chart(5.0);
    let run = || {
        let mut techniques = vec![
            common::technique(&gpu, "mlaa", &[]),
            common::technique(&gpu, "smaa-4x", &[]),
        ];
        for t in &mut techniques {
            t.set_debug_views(true);
        }
        let mut graph = graph(&gpu, &scene, techniques);
        let images = render_frames(&mut graph, &scene, 0..=2, SIZE);
        let mut views = Vec::new();
        for slot in graph.slots() {
            for view in slot.technique.debug_views() {
                let image = read_texture_rgba8(&gpu, view.texture).expect("readback");
                views.push((format!("{} {}", slot.technique.id(), view.name), image));
            }
        }
        (images, views)
    };
    let (a, views) = run();
    let (b, _) = run();
    assert_eq!(a[0], b[0], "MLAA differs between runs");
    assert_eq!(a[1], b[1], "SMAA 4x frame 2 differs between runs");
    let names: Vec<&str> = views.iter().map(|(n, _)| n.as_str()).collect();
    assert_eq!(
        names,
        [
            "mlaa edges",
            "mlaa weights",
            "smaa-4x edges",
            "smaa-4x weights"
        ]
    );
    for (name, image) in &views {
        assert_eq!(image.dimensions(), SIZE, "{name}");
        let lit = image
            .pixels()
            .filter(|p| p[0].max(p[1]).max(p[2]) > 100)
            .count();
        assert!(lit > 50, "{name} is nearly black ({lit} lit pixels)");
    }
    // The stencil keeps MLAA's weight pass off pixels without edges.
    let (edges, weights) = (&views[0].1, &views[1].1);
    for (x, y, e) in edges.enumerate_pixels() {
        if e[0] == 0 && e[1] == 0 {
            let w = weights.get_pixel(x, y);
            assert_eq!((w[0], w[1]), (0, 0), "weights at non-edge pixel {x},{y}");
        }
    }
}

#[test]
fn smaa_4x_reports_its_path_renders_per_frame_as_it_needs_and_resets() {
    let gpu = common::gpu();
    let scene = common::flat_chart(5.0);
    let t = common::technique(&gpu, "smaa-4x", &[]);
    let note = t.path_note().expect("path note");
    assert!(t.temporal());
    let mut graph = graph(&gpu, &scene, vec![t]);
    let three = render_frames(&mut graph, &scene, 0..=2, SIZE);
    if gpu.caps.supports_sample_count(2) {
        assert!(note.contains("jittered 2x MSAA render"), "{note}");
        assert_eq!(graph.scene_renders_last_frame(), 1);
    } else {
        assert!(note.contains("two jittered 1x renders"), "{note}");
        assert_eq!(graph.scene_renders_last_frame(), 2);
    }
    assert!(note.contains("4 sample positions"), "{note}");

    // A reset drops the history: frame 2 after a reset equals frame 2 rendered fresh, and
    // differs from frame 2 resolved with frame 1.
    let info = FrameInfo {
        camera: FrameCamera::from_rig(&scene.camera, 2, SIZE),
        reset_history: true,
    };
    graph
        .render(&info, FrameScope::All)
        .unwrap_or_else(|e| panic!("{e}"));
    graph.finish();
    let after_reset =
        read_texture_rgba8(&gpu, graph.slots()[0].output().expect("output")).expect("readback");
    let fresh = {
        let mut graph = graph_of(&gpu, &scene, "smaa-4x");
        render_frames(&mut graph, &scene, 2..=2, SIZE)
    };
    assert_eq!(after_reset, fresh[0]);
    assert_ne!(
        after_reset, three[0],
        "the reset frame should lack the history"
    );
}

fn graph_of(gpu: &Gpu, scene: &Scene, id: &str) -> FrameGraph {
    graph(gpu, scene, vec![common::technique(gpu, id, &[])])
}
