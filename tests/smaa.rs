//! GPU tests of SMAA 1x, T2x and S2x on generated scenes whose content is known: SMAA changes
//! edge pixels only, moves the image towards the 64-sample supersampled reference, honours
//! its settings, and the temporal mode is deterministic and resets its history.

mod common;

use aa_lab::aa::{self, Technique};
use aa_lab::gpu::{Gpu, read_texture_rgba8};
use aa_lab::graph::{FrameGraph, FrameScope};
use aa_lab::scene::Scene;
use image::RgbaImage;

const SIZE: (u32, u32) = (320, 180);

/// Every slot's output after rendering frames `frames` at [`SIZE`].
fn render_frames(
    graph: &mut FrameGraph,
    scene: &Scene,
    frames: std::ops::RangeInclusive<u64>,
) -> Vec<RgbaImage> {
    common::render_frames(graph, scene, SIZE, frames)
}

fn render(gpu: &Gpu, scene: &Scene, techniques: Vec<Box<dyn Technique>>) -> Vec<RgbaImage> {
    common::render_techniques(gpu, scene, techniques, SIZE, 0)
}

/// Mean absolute difference of the RGB bytes in the band of 12 pixels either side of the flat
/// chart's slanted edge, rows 40..140 (away from the quad's corners). The chart's other
/// edges are pixel-aligned: the reference has them exact, and there SMAA can only lose (it
/// softens the corners of rectangles a little, as it is designed to).
fn edge_band_error(a: &RgbaImage, b: &RgbaImage, slant_degrees: f32) -> f64 {
    let t = slant_degrees.to_radians().tan();
    let (mut sum, mut count) = (0u64, 0u64);
    for y in 40..140u32 {
        // The edge's x at this row: world x = -0.2 + t * world y, 100 pixels per unit.
        let world_y = (90.0 - y as f32 - 0.5) / 100.0;
        let edge_x = 160.0 + 100.0 * (-0.2 + t * world_y);
        for x in 0..SIZE.0 {
            if (x as f32 + 0.5 - edge_x).abs() < 12.0 {
                let (p, q) = (a.get_pixel(x, y), b.get_pixel(x, y));
                sum += (0..3).map(|c| u64::from(p[c].abs_diff(q[c]))).sum::<u64>();
                count += 3;
            }
        }
    }
    sum as f64 / count as f64
}

/// Whether every pixel of the 5x5 block around (x, y) equals it in the No AA image: such a
/// pixel lies in a flat region, farther than SMAA's reach (two pixels) from any edge.
fn flat(image: &RgbaImage, x: u32, y: u32) -> bool {
    let centre = image.get_pixel(x, y);
    (-2i32..=2).all(|dy| {
        (-2i32..=2).all(|dx| {
            let (nx, ny) = (x as i32 + dx, y as i32 + dy);
            nx < 0
                || ny < 0
                || nx >= image.width() as i32
                || ny >= image.height() as i32
                || image.get_pixel(nx as u32, ny as u32) == centre
        })
    })
}

/// (changed edge pixels, worst change of a flat pixel) of `result` against No AA `base`.
fn changes(base: &RgbaImage, result: &RgbaImage) -> (usize, u8) {
    let mut changed = 0;
    let mut worst_flat = 0;
    for (x, y, p) in base.enumerate_pixels() {
        let d = common::largest_channel_difference(p, result.get_pixel(x, y));
        if flat(base, x, y) {
            worst_flat = worst_flat.max(d);
        } else if d > 1 {
            changed += 1;
        }
    }
    (changed, worst_flat)
}

#[test]
fn smaa_changes_edges_only_in_every_edge_mode() {
    let gpu = common::gpu();
    let scene = common::flat_chart(5.0);
    let images = render(
        &gpu,
        &scene,
        vec![
            common::technique(&gpu, "none", &[]),
            common::technique(&gpu, "smaa", &[]),
            common::technique(&gpu, "smaa", &[("edge_detection", "color")]),
            common::technique(&gpu, "smaa", &[("edge_detection", "depth")]),
            common::technique(&gpu, "smaa", &[("predication", "on")]),
        ],
    );
    for (i, image) in images.iter().enumerate().skip(1) {
        let (changed, worst_flat) = changes(&images[0], image);
        assert!(
            worst_flat <= 1,
            "variant {i}: a flat pixel changed by {worst_flat}"
        );
        assert!(
            changed > 50,
            "variant {i}: only {changed} edge pixels changed"
        );
    }
}

#[test]
fn smaa_moves_slanted_edges_towards_the_supersampled_reference() {
    let gpu = common::gpu();
    for slant in [5.0, 30.0, 40.0, -40.0] {
        let scene = common::flat_chart(slant);
        let images = render(
            &gpu,
            &scene,
            vec![
                common::reference(&gpu),
                common::technique(&gpu, "none", &[]),
                common::technique(&gpu, "smaa", &[]),
                common::technique(&gpu, "smaa-s2x", &[]),
                common::technique(&gpu, "smaa", &[("diagonal_detection", "off")]),
            ],
        );
        let error = |i: usize| edge_band_error(&images[i], &images[0], slant);
        let (none, smaa, s2x, orthogonal) = (error(1), error(2), error(3), error(4));
        assert!(
            smaa < 0.35 * none,
            "slant {slant}: SMAA {smaa:.3} vs No AA {none:.3}"
        );
        assert!(
            s2x < 0.35 * none,
            "slant {slant}: S2x {s2x:.3} vs No AA {none:.3}"
        );
        if slant.abs() == 40.0 {
            // Close to 45 degrees the staircase is mostly diagonal steps.
            assert!(
                smaa < 0.5 * orthogonal,
                "slant {slant}: diagonals {smaa:.3} vs orthogonal only {orthogonal:.3}"
            );
        }
    }
}

#[test]
fn debug_views_show_edges_and_weights_only_on_edges() {
    let gpu = common::gpu();
    let scene = common::flat_chart(5.0);
    let mut graph = common::graph(&gpu, &scene, vec![common::technique(&gpu, "none", &[])]);
    let mut smaa = common::technique(&gpu, "smaa", &[]);
    smaa.set_debug_views(true);
    graph.add(smaa);
    let images = render_frames(&mut graph, &scene, 0..=0);
    let views = graph.slots()[1].technique.debug_views();
    let names: Vec<&str> = views.iter().map(|v| v.name).collect();
    assert_eq!(names, ["edges", "weights"]);
    let edges = read_texture_rgba8(&gpu, views[0].texture).expect("edges");
    let weights = read_texture_rgba8(&gpu, views[1].texture).expect("weights");
    let mut edge_pixels = 0;
    for (x, y, e) in edges.enumerate_pixels() {
        let w = weights.get_pixel(x, y);
        if e[0] == 0 && e[1] == 0 {
            // The stencil keeps the weight pass off non-edge pixels.
            assert_eq!((w[0], w[1]), (0, 0), "weights at non-edge pixel {x},{y}");
        } else {
            edge_pixels += 1;
            assert!(
                !flat(&images[0], x, y),
                "edge found in a flat region at {x},{y}"
            );
        }
    }
    assert!(edge_pixels > 100, "only {edge_pixels} edge pixels");
}

#[test]
fn presets_and_settings_change_the_result() {
    let gpu = common::gpu();
    let scene = common::flat_chart(5.0);
    let preset = |name: &str| {
        let mut t = common::technique(&gpu, "smaa", &[]);
        t.apply_preset(name).unwrap_or_else(|e| panic!("{e}"));
        t
    };
    let images = render(
        &gpu,
        &scene,
        vec![
            common::reference(&gpu),
            common::technique(&gpu, "none", &[]),
            preset("low"),
            preset("ultra"),
            common::technique(&gpu, "smaa", &[("max_search_steps", "1")]),
        ],
    );
    let none = edge_band_error(&images[1], &images[0], 5.0);
    for (i, name) in [(2, "low"), (3, "ultra")] {
        let error = edge_band_error(&images[i], &images[0], 5.0);
        assert!(error < 0.5 * none, "{name}: {error:.3} vs No AA {none:.3}");
    }
    // The edge's runs are about 11 pixels long: a search of one step (two pixels) each way
    // misses most ends, four steps (low) reach them.
    let short = edge_band_error(&images[4], &images[0], 5.0);
    let low = edge_band_error(&images[2], &images[0], 5.0);
    assert!(short > low, "one search step {short:.3} vs low {low:.3}");
    assert_ne!(images[2], images[3], "low and ultra agree exactly");
}

#[test]
fn t2x_is_deterministic_changes_edges_and_resets() {
    let gpu = common::gpu();
    let scene = common::flat_chart(5.0);
    let run = |frames: std::ops::RangeInclusive<u64>| {
        let techniques = vec![
            common::technique(&gpu, "none", &[]),
            common::technique(&gpu, "smaa-t2x", &[]),
            common::reference(&gpu),
        ];
        render_frames(&mut common::graph(&gpu, &scene, techniques), &scene, frames)
    };
    let a = run(0..=3);
    let b = run(0..=3);
    assert_eq!(a[1], b[1], "T2x frame 3 differs between runs");
    let (changed, worst_flat) = changes(&a[0], &a[1]);
    assert!(
        changed > 50 && worst_flat <= 1,
        "{changed} changed, flat pixels off by {worst_flat}"
    );
    let none = edge_band_error(&a[0], &a[2], 5.0);
    let t2x = edge_band_error(&a[1], &a[2], 5.0);
    assert!(t2x < 0.35 * none, "T2x {t2x:.3} vs No AA {none:.3}");
    // With a static camera the resolve averages the two jittered frames: the result differs
    // from either frame alone.
    let single = run(3..=3);
    assert_ne!(single[1], a[1], "frame 3 alone equals the resolved frame 3");
    let resolved = common::mean_error(&a[1], &a[2]);
    let first = common::mean_error(&single[1], &single[2]);
    assert!(
        resolved < first,
        "resolved {resolved:.3} vs first frame {first:.3}"
    );

    // A reset drops the history: frame 3 after a reset equals frame 3 rendered fresh.
    let mut graph = common::graph(&gpu, &scene, vec![common::technique(&gpu, "smaa-t2x", &[])]);
    render_frames(&mut graph, &scene, 0..=2);
    common::render(
        &mut graph,
        common::camera(&scene, 3, SIZE),
        true,
        FrameScope::All,
    );
    let after_reset = common::outputs(&mut graph);
    let fresh = {
        let mut graph = common::graph(&gpu, &scene, vec![common::technique(&gpu, "smaa-t2x", &[])]);
        render_frames(&mut graph, &scene, 3..=3)
    };
    assert_eq!(after_reset[0], fresh[0]);
    assert_ne!(
        after_reset[0], a[1],
        "the reset frame should lack the history"
    );

    // Changing a setting also drops it.
    let mut graph = common::graph(&gpu, &scene, vec![common::technique(&gpu, "smaa-t2x", &[])]);
    render_frames(&mut graph, &scene, 0..=2);
    aa::set_param(
        graph.slots_mut()[0].technique.as_mut(),
        "threshold",
        aa::ParamValue::Float(0.05),
    )
    .expect("threshold");
    common::render(
        &mut graph,
        common::camera(&scene, 3, SIZE),
        false,
        FrameScope::All,
    );
    let changed_settings = common::outputs(&mut graph);
    let fresh = {
        let t2x = common::technique(&gpu, "smaa-t2x", &[("threshold", "0.05")]);
        render_frames(&mut common::graph(&gpu, &scene, vec![t2x]), &scene, 3..=3)
    };
    assert_eq!(changed_settings[0], fresh[0]);
}

#[test]
fn s2x_reports_its_path_and_renders_once_per_sample_without_2x_msaa() {
    let gpu = common::gpu();
    let scene = common::flat_chart(5.0);
    let s2x = common::technique(&gpu, "smaa-s2x", &[]);
    let note = s2x.path_note().expect("path note");
    let mut graph = common::graph(&gpu, &scene, vec![s2x]);
    render_frames(&mut graph, &scene, 0..=0);
    if gpu.caps.supports_sample_count(2) {
        assert!(note.contains("2x MSAA render"), "{note}");
        assert_eq!(graph.scene_renders_last_frame(), 1);
    } else {
        assert!(note.contains("two jittered 1x renders"), "{note}");
        assert_eq!(graph.scene_renders_last_frame(), 2);
    }
}

#[test]
fn t2x_is_at_least_as_close_to_the_charts_exact_truth_as_smaa_1x() {
    // Before its mip bias T2x was below SMAA 1x on atrium (SSIM .8835 vs .8949 at frame 16):
    // its textures came out softer than the reference. On the built-in chart (still camera)
    // both are scored against the exact analytic coverage, over the chart's test elements, at
    // the usual size and at an odd one (tuning to one size fails here).
    let gpu = common::gpu();
    let scene =
        aa_lab::scene::source::load("chart", &Default::default()).unwrap_or_else(|e| panic!("{e}"));
    for size in [SIZE, (411, 233)] {
        let techniques = vec![
            common::technique(&gpu, "none", &[]),
            common::technique(&gpu, "smaa", &[]),
            common::technique(&gpu, "smaa-t2x", &[]),
        ];
        let mut graph = common::graph(&gpu, &scene, techniques);
        let images = common::render_frames(&mut graph, &scene, size, 0..=8);
        let truth = aa_lab::metrics::coverage::chart_truth(
            &aa_lab::scene::procedural::chart_layout(),
            size,
        );
        let score = |image: &RgbaImage| {
            let (_, maps) =
                aa_lab::metrics::compare_with_maps(&truth.image, image).expect("same size");
            maps.pool(Some(&truth.mask))
        };
        let [none, smaa, t2x] = [0, 1, 2].map(|i| score(&images[i]));
        println!(
            "chart vs truth at {size:?}, SSIM / FLIP: No AA {:.4} / {:.4}, SMAA 1x {:.4} / {:.4}, \
             T2x {:.4} / {:.4}",
            none.ssim, none.flip, smaa.ssim, smaa.flip, t2x.ssim, t2x.flip
        );
        assert!(
            t2x.ssim >= smaa.ssim,
            "{size:?}: T2x SSIM {:.4} below SMAA 1x's {:.4}",
            t2x.ssim,
            smaa.ssim
        );
        assert!(
            t2x.flip <= smaa.flip,
            "{size:?}: T2x FLIP {:.4} above SMAA 1x's {:.4}",
            t2x.flip,
            smaa.flip
        );
    }
}
