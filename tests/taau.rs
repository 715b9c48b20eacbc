//! GPU tests of the temporal upscaler (`taau`, software Vulkan in CI): on a still camera it
//! converges to the 64-sample reference at native and below it (and at 1/1.5 scores above the
//! native post-process techniques on hairball and atrium), leaves no ghost trail behind camera
//! or object motion, keeps its lead or its calm against TAA under the orbit and the pan, and its
//! scene input carries the jitter phases and the mip bias of its render scale.

mod common;

use aa_lab::aa::FrameInfo;
use aa_lab::aa::common::temporal::jitter_offset;
use aa_lab::scene::CameraRig;
use aa_lab::scene::camera::FrameCamera;

const SIZE: (u32, u32) = (320, 180);

#[test]
fn taau_converges_to_the_reference_on_a_still_camera() {
    let gpu = common::gpu();
    let scene = common::flat_chart(5.0);
    let ids = [
        "none",
        "taa",
        "taau",
        "taau@quality",
        "taau@performance",
        "none@quality:bilinear",
        "none@performance:bilinear",
    ];
    let mut techniques = vec![common::reference(&gpu)];
    techniques.extend(ids.iter().map(|id| common::technique(&gpu, id, &[])));
    // 64 frames: two cycles of the 32 phases at 1/2.
    let images = common::render_techniques(&gpu, &scene, techniques, SIZE, 63);
    let reference = &images[0];
    let errors: Vec<f64> = images[1..]
        .iter()
        .map(|image| common::mean_error(image, reference))
        .collect();
    for (id, error) in ids.iter().zip(&errors) {
        println!("{id}: mean error {error:.3}");
    }
    let [
        none,
        taa,
        native,
        quality,
        performance,
        spatial_quality,
        spatial_performance,
    ] = errors[..]
    else {
        unreachable!("seven techniques")
    };
    // Measured: 0.071 against TAA's 0.067 (its history keeps 6 samples to TAA's 10).
    assert!(
        native <= taa * 1.1,
        "taau {native:.3} vs taa {taa:.3} at native"
    );
    assert!(native < 0.5 * none, "taau {native:.3} vs No AA {none:.3}");
    // Below native the chart's edges are rebuilt from the jittered low-resolution samples:
    // far closer to the reference than a spatial upscale of the same render size.
    for (id, error, spatial) in [
        ("taau@quality", quality, spatial_quality),
        ("taau@performance", performance, spatial_performance),
    ] {
        assert!(
            error < 0.5 * spatial,
            "{id} {error:.3} vs {spatial:.3} upscaled without temporal reconstruction"
        );
    }
}

#[test]
fn taau_leaves_no_ghost_trail_behind_camera_or_object_motion() {
    let gpu = common::gpu();
    let chart = common::flat_chart(5.0);
    let spinning = common::temporal::spinning_chart();
    let pan = |f| common::temporal::panning(&chart, f, 0.03, SIZE);
    let spin = |f| common::camera(&spinning, f, SIZE);
    let cases: [(
        &str,
        &aa_lab::scene::Scene,
        &common::temporal::CameraPath<'_>,
    ); 2] = [
        ("camera pan", &chart, &pan),
        ("spinning object", &spinning, &spin),
    ];
    for (name, scene, camera) in cases {
        for id in ["taau", "taau@quality"] {
            // Nothing that removes a ghost: no rectification, no disocclusion test, no falloff
            // of the history with the speed or the parallax.
            let unrectified = [
                ("rectify", "none"),
                ("depth_tolerance", "1"),
                ("speed_falloff", "0"),
                ("parallax_falloff", "0"),
            ];
            let (ghost, ghost_mean) =
                common::temporal::trail(&gpu, id, scene, camera, &unrectified);
            println!("{name}, {id}, none: worst {ghost}, mean {ghost_mean:.2}");
            assert!(ghost > 64, "{name}, {id}: no ghost unrectified ({ghost})");
            for rectify in ["variance", "clip", "clamp"] {
                let (worst, mean) =
                    common::temporal::trail(&gpu, id, scene, camera, &[("rectify", rectify)]);
                println!("{name}, {id}, {rectify}: worst {worst}, mean {mean:.2}");
                assert!(
                    worst <= 2,
                    "{name}, {id}, {rectify}: a trail pixel is off by {worst}/255"
                );
                // The mean takes in the edges, where the upscaler's kernel (and below native
                // its lower render resolution) legitimately differs from No AA under motion,
                // so it falls less than the worst pixel: measured 0.58 (taau) and 0.66
                // (taau@quality) of the unrectified mean on the spinning object.
                assert!(
                    mean < 0.75 * ghost_mean,
                    "{name}, {id}, {rectify}: mean {mean:.2} vs {ghost_mean:.2} unrectified"
                );
            }
        }
    }
}

#[test]
fn taau_keeps_its_detail_on_atrium_under_the_orbit() {
    // Under the orbit the history is read between texels every frame and each read blurs it a
    // little; a moving pixel whose read landed near a texel once kept a long history that the
    // following reads blurred again, generation after generation. The history now keeps only
    // its motion samples wherever the pixel moves half an output pixel per frame or more,
    // which lifted taau from below TAA to above it at native and taau@quality by about .009
    // SSIM. Measured on frame 16 before and after (docs/upscaling.md): taau .9391 -> .9482 and
    // .9453 -> .9534 (TAA .9410 and .9464), taau@quality .8798 -> .8883 and .8868 -> .8955 at
    // 640x360 and 853x481.
    // At native scale the kernel's estimate (which blurs a texture) now stands in for the
    // pixel's own sample in full only where the 3x3 spans more than one surface (on one
    // surface half of it), which lifted taau from .9508 to .9533 at 640x360 (TAA .9475) and
    // to .9589 at 853x481 (TAA .9543); with moving edges filtered in full in both, .9529
    // against .9473 at 640x360. It must lead TAA by .004.
    let gpu = common::gpu();
    let scene = aa_lab::scene::source::load("atrium", &Default::default())
        .unwrap_or_else(|e| panic!("{e}"));
    for (size, quality_floor) in [((640, 360), 0.885), ((853, 481), 0.892)] {
        let techniques = ["taa", "taau", "taau@quality"].map(|id| common::technique(&gpu, id, &[]));
        // Frames 0 to 16; the reference renders the last one only.
        let (reference, images) = common::with_reference(&gpu, &scene, techniques.into(), 17, size);
        let [taa, native, quality] = [0, 1, 2].map(|i| common::ssim_mean(&reference, &images[i]));
        println!(
            "atrium {size:?} frame 16: taa {taa:.4}, taau {native:.4}, taau@quality {quality:.4}"
        );
        assert!(
            native >= taa + 0.004,
            "{size:?}: taau {native:.4} vs taa {taa:.4}"
        );
        assert!(
            quality >= quality_floor,
            "{size:?}: taau@quality {quality:.4} vs {quality_floor}"
        );
    }
}

#[test]
fn taau_at_quality_meets_the_native_techniques_where_its_history_lasts() {
    // Issue 30 asks taau@quality above native No AA, FXAA and SMAA 1x in SSIM and FLIP and
    // within .01 SSIM of native TAA. Under the scenes' orbit it misses (the history is read
    // between texels every frame and keeps about two samples' worth); on a still camera, where
    // the history lasts, it meets every one at 640x360, 1280x720 and 1920x1080
    // (docs/upscaling.md, "Where the history lasts"). Held here at 640x360 and the odd
    // 427x241 after 17 frames: a change that breaks the
    // reconstruction below native fails here even where the orbit hides it.
    let gpu = common::gpu();
    for name in ["hairball", "atrium"] {
        let scene = aa_lab::scene::source::load(name, &Default::default())
            .unwrap_or_else(|e| panic!("{e}"));
        // `aa-lab render --camera-motion still`: the orbit stopped at the scene's first view.
        let still = CameraRig {
            orbit_degrees_per_frame: 0.0,
            ..scene.camera
        };
        for size in [(640, 360), (427, 241)] {
            let ids = ["none", "fxaa", "smaa", "taa", "taau@quality"];
            let techniques = ids.map(|id| common::technique(&gpu, id, &[]));
            let (reference, images) =
                common::with_reference_on(&gpu, &scene, techniques.into(), 17, &|frame| {
                    FrameCamera::from_rig(&still, frame, size)
                });
            let scores: Vec<(f64, f64)> = images
                .iter()
                .map(|image| {
                    (
                        common::ssim_mean(&reference, image),
                        common::flip_mean(&reference, image),
                    )
                })
                .collect();
            for (id, (ssim, flip)) in ids.iter().zip(&scores) {
                println!("{name} {size:?} still: {id} {ssim:.4} / {flip:.4}");
            }
            let (quality_ssim, quality_flip) = scores[4];
            for (id, (ssim, flip)) in ids[..3].iter().zip(&scores[..3]) {
                assert!(
                    quality_ssim > *ssim && quality_flip < *flip,
                    "{name} {size:?}: taau@quality {quality_ssim:.4} / {quality_flip:.4} vs {id} {ssim:.4} / {flip:.4}"
                );
            }
            let taa_ssim = scores[3].0;
            assert!(
                quality_ssim >= taa_ssim - 0.01,
                "{name} {size:?}: taau@quality {quality_ssim:.4} vs taa {taa_ssim:.4}"
            );
        }
    }
}

#[test]
fn taau_at_native_pans_over_atrium_as_calmly_as_taa() {
    // On one surface taau's estimate in motion is half the kernel's and half the pixel's own
    // sample. The own sample alone made atrium's textures sharper under the orbit but flicker
    // more than TAA's on the clip's slow pan (`aa-lab clip --motion pan`, 640x360, 8 + 24
    // frames: instability .972 against TAA's .949); as kept .928, with the kernel alone .894
    // (docs/upscaling.md).
    let gpu = common::gpu();
    let scene = aa_lab::scene::source::load("atrium", &Default::default())
        .unwrap_or_else(|e| panic!("{e}"));
    let mut graph = common::graph_with_reference(&gpu, &scene, &["taa", "taau"]);
    let figures = common::pan_instability(&mut graph, &scene, (640, 360), 8, 24);
    let (taa, taau) = (figures[0], figures[1]);
    println!("atrium pan 640x360: instability taa {taa:.3}, taau {taau:.3}");
    assert!(taau <= taa, "taau {taau:.3} vs taa {taa:.3}");
}

#[test]
fn taau_at_native_leads_taa_on_hairball_at_full_hd() {
    // At native scale the parallax scales the history's share against one new sample, as in
    // TAA, rather than its sample count, which let a long history keep most of its share where
    // the strands part. That put taau ahead of TAA on hairball at 1920x1080 (docs/upscaling.md,
    // frame 16): SSIM / FLIP .9330 / .0401 against .9312 / .0403, from .9302 / .0407. Then both
    // took their filtered estimate in full where a moving pixel spans surfaces (an edge),
    // whatever the fraction of their history read: .9341 / .0399 against .9320 / .0401, and
    // TAA must keep its gain (it was .9312 without).
    const TAA_FLOOR: f64 = 0.9316;
    let gpu = common::gpu();
    let scene = aa_lab::scene::source::load("hairball", &Default::default())
        .unwrap_or_else(|e| panic!("{e}"));
    let techniques = ["taa", "taau"].map(|id| common::technique(&gpu, id, &[]));
    let (reference, images) =
        common::with_reference(&gpu, &scene, techniques.into(), 17, (1920, 1080));
    let [taa, native] = [0, 1].map(|i| common::ssim_mean(&reference, &images[i]));
    let [taa_flip, native_flip] = [0, 1].map(|i| common::flip_mean(&reference, &images[i]));
    println!(
        "hairball 1920x1080 frame 16: taa {taa:.4} / {taa_flip:.4}, taau {native:.4} / {native_flip:.4}"
    );
    assert!(
        native >= taa + 0.001,
        "SSIM: taau {native:.4} vs taa {taa:.4}"
    );
    assert!(taa >= TAA_FLOOR, "SSIM: taa {taa:.4} vs {TAA_FLOOR}");
    assert!(
        native_flip <= taa_flip,
        "FLIP: taau {native_flip:.4} vs taa {taa_flip:.4}"
    );
}

#[test]
fn the_scene_input_has_the_phases_and_mip_bias_of_the_render_scale() {
    let gpu = common::gpu();
    let output = (1280, 720);
    let camera = FrameCamera::from_rig(&CameraRig::default(), 3, output);
    let frame = FrameInfo {
        camera,
        reset_history: false,
    };
    // (id, render size, jitter phases, total mip bias: log2(render / output) plus the
    // technique's own: -1 for both, as FSR 2 recommends at native scale).
    for (id, render, phases, bias) in [
        ("taau", (1280, 720), 8, -1.0),
        ("taau@performance", (640, 360), 32, -2.0),
        (
            "taau@quality+rcas",
            (853, 480),
            18,
            -1.0 + (2.0f32 / 3.0).log2(),
        ),
        ("taa@performance", (640, 360), 8, -2.0),
    ] {
        let technique = common::technique(&gpu, id, &[]);
        assert_eq!(technique.render_size(&frame), render, "{id}");
        let input = technique.scene_input(&frame).expect("a scene input");
        let jitter = jitter_offset(3, phases);
        assert!((input.offset() - jitter).length() < 1e-4, "{id}: jitter");
        let total = camera
            .at_render_size(render)
            .params(input.offset(), input.mip_bias())
            .mip_bias;
        assert!(
            (total - bias).abs() < 0.01,
            "{id}: mip bias {total} vs {bias}"
        );
    }
}
