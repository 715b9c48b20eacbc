//! GPU tests of the metrics (software Vulkan in CI): the compute-shader SSIM/MAE/PSNR against
//! the CPU reference, fragment-invocation counts from pipeline-statistics queries, the copy
//! floor pass, and the chart's analytic ground truth against a 64-sample render.

mod common;

use aa_lab::aa::floor::{COPY_FLOOR_ID, CopyFloor};
use aa_lab::aa::{self, ParamValue};
use aa_lab::graph::FrameGraph;
use aa_lab::metrics::coverage::chart_truth;
use aa_lab::metrics::gpu::{GpuMetrics, upload_image};
use aa_lab::metrics::{self, ssim};
use aa_lab::scene::procedural::{SceneOptions, chart, chart_layout};

/// Renders `ids` (with settings) of a scene at frame 0 and reads every output back.
fn render(
    gpu: &aa_lab::gpu::Gpu,
    scene: &aa_lab::scene::Scene,
    size: (u32, u32),
    techniques: &[(&str, &[(&str, ParamValue)])],
    statistics: bool,
) -> (FrameGraph, Vec<image::RgbaImage>) {
    let techniques = techniques
        .iter()
        .map(|(id, settings)| {
            let mut technique = aa::create(gpu, id).expect("technique");
            for (key, value) in *settings {
                aa::set_param(technique.as_mut(), key, value.clone()).expect("setting");
            }
            technique
        })
        .collect();
    let mut graph = common::graph(gpu, scene, techniques);
    assert_eq!(graph.set_pipeline_statistics(statistics), statistics);
    let images = common::render_frames(&mut graph, scene, size, 0..=0);
    (graph, images)
}

#[test]
fn gpu_metrics_agree_with_the_cpu_reference() {
    let gpu = common::gpu();
    let mut metrics = GpuMetrics::new(&gpu);
    // Fixture crops (96x72 and 61x37: sizes that are not multiples of the workgroup) and a
    // rendered pair straight from technique outputs.
    let scene = common::flat_chart(7.0);
    let (graph, rendered) = render(
        &gpu,
        &scene,
        (320, 180),
        &[("none", &[]), ("ssaa", &[])],
        false,
    );
    let mut pairs = vec![
        (
            common::metrics_fixture("hairball_ssaa"),
            common::metrics_fixture("hairball_none"),
        ),
        (
            common::metrics_fixture("atrium_ssaa"),
            common::metrics_fixture("atrium_msaa4"),
        ),
        (
            common::metrics_fixture("noise_clean"),
            common::metrics_fixture("noise_noisy"),
        ),
    ];
    pairs.push((rendered[1].clone(), rendered[0].clone()));
    for (i, (reference, test)) in pairs.iter().enumerate() {
        let cpu = ssim::ssim(reference, test).unwrap();
        let errors = metrics::pixel::error_maps(reference, test)
            .unwrap()
            .pool(None);
        let a = upload_image(&gpu, reference, "reference").unwrap();
        let b = upload_image(&gpu, test, "test").unwrap();
        let got = metrics.compare(&gpu, &a, &b).unwrap();
        assert!(
            (got.ssim - cpu.mean).abs() < 1e-3,
            "pair {i}: GPU SSIM {} vs CPU {}",
            got.ssim,
            cpu.mean
        );
        assert!(
            (got.mae - errors.mae).abs() < 1e-3,
            "pair {i}: GPU MAE {} vs CPU {}",
            got.mae,
            errors.mae
        );
        assert!((got.psnr() - errors.psnr()).abs() < 1e-3, "pair {i}: PSNR");
        let map = metrics.read_ssim_map(&gpu).unwrap();
        let worst = map
            .data
            .iter()
            .zip(&cpu.map.data)
            .map(|(g, c)| (g - c).abs())
            .fold(0.0f32, f32::max);
        assert!(worst < 1e-3, "pair {i}: SSIM maps differ by up to {worst}");
    }
    // Technique outputs (sRGB textures read through their Rgba8Unorm view) directly.
    let slots = graph.slots();
    let direct = metrics
        .compare(&gpu, slots[1].output().unwrap(), slots[0].output().unwrap())
        .unwrap();
    let cpu = ssim::ssim(&rendered[1], &rendered[0]).unwrap();
    assert!((direct.ssim - cpu.mean).abs() < 1e-3);
    // Identical inputs.
    let same = metrics
        .compare(&gpu, slots[0].output().unwrap(), slots[0].output().unwrap())
        .unwrap();
    assert!((same.ssim - 1.0).abs() < 1e-5 && same.mae == 0.0 && same.psnr().is_infinite());
    // Size mismatch is an error, not a panic.
    let small = upload_image(&gpu, &common::metrics_fixture("noise_clean"), "small").unwrap();
    assert!(
        metrics
            .compare(&gpu, &small, slots[0].output().unwrap())
            .is_err()
    );
}

#[test]
fn fragment_invocations_show_where_shading_happens() {
    let gpu = common::gpu();
    if !gpu.caps.pipeline_statistics || !gpu.caps.supports_sample_count(4) {
        panic!("this test needs pipeline-statistics queries and 4x MSAA (lavapipe has both)");
    }
    let scene = common::flat_chart(7.0);
    let size = (320, 180);
    let per_sample = [("sample_shading", ParamValue::Bool(true))];
    let (graph, _) = render(
        &gpu,
        &scene,
        size,
        &[("none", &[]), ("msaa4", &[]), ("ssaa", &[])],
        true,
    );
    let stats = graph
        .pipeline_statistics()
        .expect("statistics of the frame")
        .clone();
    let scene_1x = stats.pass_invocations("scene 1x").unwrap() as f64;
    let msaa = stats.pass_invocations("scene msaa4").unwrap() as f64;
    let ssaa = stats.technique_invocations("ssaa") as f64;
    // MSAA shades about once per covered pixel (plus the pixels edges cover partly); SSAA 2x2
    // once per sample (plus its downsample pass, one per pixel).
    assert!(scene_1x > 10_000.0, "{scene_1x}");
    assert!(msaa / scene_1x < 1.25, "msaa4 {msaa} vs 1x {scene_1x}");
    assert!(ssaa / scene_1x > 3.5, "ssaa {ssaa} vs 1x {scene_1x}");
    let (graph, _) = render(&gpu, &scene, size, &[("msaa4", &per_sample)], true);
    let stats = graph.pipeline_statistics().expect("statistics").clone();
    let sample_rate = stats.pass_invocations("scene msaa4 per-sample").unwrap() as f64;
    // The counter is the driver's: lavapipe runs all samples of a pixel in one invocation and
    // counts it once, so sample-rate shading does not show up there (a GPU that invokes per
    // sample counts about 4x). What holds everywhere: it never counts less.
    assert!(
        sample_rate >= 0.95 * scene_1x,
        "sample-rate shading {sample_rate} vs 1x {scene_1x}"
    );
    // Off means off.
    let (graph, _) = render(&gpu, &scene, size, &[("none", &[])], false);
    assert!(graph.pipeline_statistics().is_none());
}

#[test]
fn copy_floor_copies_the_shared_input_exactly() {
    let gpu = common::gpu();
    let scene = common::flat_chart(3.0);
    let techniques = vec![
        common::technique(&gpu, aa::none::ID, &[]),
        Box::new(CopyFloor::new(&gpu)) as Box<dyn aa::Technique>,
    ];
    let mut graph = common::graph(&gpu, &scene, techniques);
    let images = common::render_frames(&mut graph, &scene, (200, 120), 0..=1);
    assert_eq!(
        graph.scene_renders_last_frame(),
        1,
        "the floor shares No AA's input"
    );
    assert!(images[0] == images[1], "the copy pass changed pixels");
    let timings = graph.timings().unwrap();
    assert_eq!(timings.technique_passes(COPY_FLOOR_ID).count(), 1);
}

#[test]
fn chart_ground_truth_matches_a_64_sample_render() {
    let gpu = common::gpu();
    let scene = chart(&SceneOptions::default());
    let size = (320, 180);
    let reference = [
        ("mode", ParamValue::Choice("ordered".into())),
        ("factor", ParamValue::Int(8)),
    ];
    let (_, images) = render(
        &gpu,
        &scene,
        size,
        &[("ssaa", &reference), ("none", &[])],
        false,
    );
    let truth = chart_truth(&chart_layout(), size);
    let (_, maps) = metrics::compare_with_maps(&truth.image, &images[0]).unwrap();
    let supersampled = maps.pool(Some(&truth.mask));
    let (_, maps) = metrics::compare_with_maps(&truth.image, &images[1]).unwrap();
    let aliased = maps.pool(Some(&truth.mask));
    // 64 samples approximate exact coverage to within 1/64 per pixel, so the render matches
    // the truth closely and far better than one sample does; a misplaced truth (half a pixel
    // off, flipped) would not.
    assert!(supersampled.ssim > 0.97, "{supersampled:?}");
    assert!(supersampled.mae < 3.0, "{supersampled:?}");
    assert!(
        aliased.mae > 2.0 * supersampled.mae,
        "{aliased:?} vs {supersampled:?}"
    );
}
