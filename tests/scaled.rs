//! Render scale, upscaling and sharpening (`aa::scaled`, `aa::combo`): each upscaler and
//! sharpening filter on analytic images (run through the real passes on the GPU), the sharing
//! of scene inputs between techniques at the same scale, temporal and supersampling techniques
//! at a scale, and a combination's record reproducing its image through `render --from`.

mod common;

use aa_lab::aa::combo::{Sharpen, Sharpening, Upscaler};
use aa_lab::aa::scaled::passes::Resampler;
use aa_lab::aa::{FrameInfo, Named};
use aa_lab::gpu::{Gpu, read_texture_rgba8, write_rgba8};
use aa_lab::graph::{FrameGraph, output_texture};
use image::{Rgba, RgbaImage};

/// Runs `record` on a fresh graph (any scene: the passes read only their images).
fn with_passes(gpu: &Gpu, record: impl FnOnce(&mut aa_lab::graph::PassContext<'_>)) {
    let scene = common::flat_chart(0.0);
    let mut graph = FrameGraph::new(gpu.clone(), &scene);
    let frame = FrameInfo {
        camera: common::camera(&scene, 0, (16, 16)),
        reset_history: true,
    };
    graph
        .run_passes(&frame, "test", record)
        .unwrap_or_else(|e| panic!("{e}"));
}

fn uploaded(gpu: &Gpu, image: &RgbaImage) -> wgpu::Texture {
    let texture = output_texture(gpu, "source", image.dimensions());
    write_rgba8(gpu, &texture, image);
    texture
}

/// `source` upscaled to `size` by `upscaler`.
fn upscale(gpu: &Gpu, upscaler: Upscaler, source: &RgbaImage, size: (u32, u32)) -> RgbaImage {
    let source = uploaded(gpu, source);
    let target = output_texture(gpu, "target", size);
    let mut resampler = Resampler::new(gpu);
    with_passes(gpu, |ctx| {
        resampler.upscale(ctx, upscaler, &source, &target)
    });
    read_texture_rgba8(gpu, &target).expect("readback")
}

/// `source` sharpened by `sharpening`.
fn sharpen(gpu: &Gpu, sharpening: Sharpening, source: &RgbaImage) -> RgbaImage {
    let texture = uploaded(gpu, source);
    let target = output_texture(gpu, "target", source.dimensions());
    let mut resampler = Resampler::new(gpu);
    with_passes(gpu, |ctx| {
        resampler.sharpen(ctx, sharpening, &texture, &target);
    });
    read_texture_rgba8(gpu, &target).expect("readback")
}

const SOURCE: (u32, u32) = (24, 16);
/// Upscale ratios 1.5 and 2.
const OUTPUTS: [(u32, u32); 2] = [(36, 24), (48, 32)];

/// A deterministic pseudo-random image (hash of the position).
fn noise(size: (u32, u32), seed: u32) -> RgbaImage {
    RgbaImage::from_fn(size.0, size.1, |x, y| {
        let mut h = x.wrapping_mul(0x9e37_79b9) ^ y.wrapping_mul(0x85eb_ca6b) ^ seed;
        h ^= h >> 15;
        h = h.wrapping_mul(0x2c1b_3c6d);
        h ^= h >> 12;
        Rgba([h as u8, (h >> 8) as u8, (h >> 16) as u8, 255])
    })
}

/// Hard-edged shapes: a disc and a bar on a mid-grey ground (where ringing filters overshoot).
fn shapes(size: (u32, u32)) -> RgbaImage {
    RgbaImage::from_fn(size.0, size.1, |x, y| {
        let (dx, dy) = (x as f32 - 8.0, y as f32 - 8.0);
        if dx * dx + dy * dy < 20.0 {
            Rgba([250, 250, 250, 255])
        } else if (15..18).contains(&x) {
            Rgba([10, 10, 10, 255])
        } else {
            Rgba([128, 128, 128, 255])
        }
    })
}

/// The source position of an output pixel's centre (source pixel units, centres at +0.5).
fn source_position(x: u32, size: u32, source: u32) -> f32 {
    (x as f32 + 0.5) * source as f32 / size as f32
}

/// The 2x2 source pixels around an output pixel's source position, clamped to the image.
fn neighbourhood(image: &RgbaImage, x: u32, y: u32, size: (u32, u32)) -> Vec<Rgba<u8>> {
    let (w, h) = image.dimensions();
    let base = |p: f32, n: u32| ((p - 0.5).floor().max(0.0) as u32).min(n - 1);
    let bx = base(source_position(x, size.0, w), w);
    let by = base(source_position(y, size.1, h), h);
    let mut pixels = Vec::new();
    for (px, py) in [(bx, by), (bx + 1, by), (bx, by + 1), (bx + 1, by + 1)] {
        pixels.push(*image.get_pixel(px.min(w - 1), py.min(h - 1)));
    }
    pixels
}

/// Whether an output pixel lies outside the range of its 2x2 source neighbourhood, by more
/// than `slack` levels in some channel.
fn outside(out: &RgbaImage, source: &RgbaImage, x: u32, y: u32, slack: u8) -> bool {
    let around = neighbourhood(source, x, y, out.dimensions());
    let value = out.get_pixel(x, y);
    (0..3).any(|c| {
        let low = around.iter().map(|p| p[c]).min().unwrap_or(0);
        let high = around.iter().map(|p| p[c]).max().unwrap_or(255);
        value[c] < low.saturating_sub(slack) || value[c] > high.saturating_add(slack)
    })
}

#[test]
fn every_upscaler_keeps_a_constant_image_constant() {
    let gpu = common::gpu();
    let constant = RgbaImage::from_pixel(SOURCE.0, SOURCE.1, Rgba([90, 141, 203, 255]));
    for upscaler in Upscaler::ALL {
        for size in OUTPUTS {
            let out = upscale(&gpu, *upscaler, &constant, size);
            let off = out
                .pixels()
                .filter(|p| **p != Rgba([90, 141, 203, 255]))
                .count();
            assert_eq!(
                off,
                0,
                "{}: {off} pixels changed at {size:?}",
                upscaler.name()
            );
        }
    }
}

#[test]
fn every_upscaler_keeps_a_linear_ramp_linear_away_from_the_borders() {
    let gpu = common::gpu();
    // Red rises 5 levels per source pixel to the right, green 6 per pixel downwards.
    let ramp = RgbaImage::from_fn(SOURCE.0, SOURCE.1, |x, y| {
        Rgba([20 + 5 * x as u8, 30 + 6 * y as u8, 128, 255])
    });
    for upscaler in Upscaler::ALL {
        let tolerance = match upscaler {
            Upscaler::Bilinear | Upscaler::Bicubic => 1.0,
            Upscaler::Lanczos | Upscaler::Easu => 2.0,
        };
        for size in OUTPUTS {
            let out = upscale(&gpu, *upscaler, &ramp, size);
            let mut worst = 0.0f32;
            for (x, y, p) in out.enumerate_pixels() {
                let sx = source_position(x, size.0, SOURCE.0);
                let sy = source_position(y, size.1, SOURCE.1);
                let inside = |p: f32, n: u32| p > 2.5 && p < n as f32 - 2.5;
                if !inside(sx, SOURCE.0) || !inside(sy, SOURCE.1) {
                    continue;
                }
                let red = 20.0 + 5.0 * (sx - 0.5);
                let green = 30.0 + 6.0 * (sy - 0.5);
                worst = worst
                    .max((p[0] as f32 - red).abs())
                    .max((p[1] as f32 - green).abs())
                    .max((p[2] as f32 - 128.0).abs());
            }
            assert!(
                worst <= tolerance,
                "{} at {size:?}: {worst} levels off the ramp (tolerance {tolerance})",
                upscaler.name()
            );
        }
    }
}

#[test]
fn bilinear_and_easu_stay_in_the_neighbourhood_range_where_lanczos_and_bicubic_overshoot() {
    let gpu = common::gpu();
    let images = [shapes(SOURCE), noise(SOURCE, 7)];
    for upscaler in Upscaler::ALL {
        let mut overshoots = 0;
        for image in &images {
            for size in OUTPUTS {
                let out = upscale(&gpu, *upscaler, image, size);
                // Bilinear's hardware weights round; one level of slack covers it.
                let slack = u8::from(*upscaler == Upscaler::Bilinear);
                overshoots += out
                    .enumerate_pixels()
                    .filter(|(x, y, _)| outside(&out, image, *x, *y, slack))
                    .count();
            }
        }
        match upscaler {
            Upscaler::Bilinear | Upscaler::Easu => assert_eq!(
                overshoots,
                0,
                "{} left the 2x2 range at {overshoots} pixels",
                upscaler.name()
            ),
            // What they trade for sharpness: a filter with negative lobes rings at hard
            // edges (this also shows the check above can fail).
            Upscaler::Bicubic | Upscaler::Lanczos => assert!(
                overshoots > 0,
                "{} never overshot a hard edge",
                upscaler.name()
            ),
        }
    }
}

#[test]
fn easu_is_sharper_than_bilinear_across_an_edge() {
    let gpu = common::gpu();
    // A diagonal edge: easu keeps it steeper (larger largest step between neighbours).
    let edge = RgbaImage::from_fn(SOURCE.0, SOURCE.1, |x, y| {
        let v = if x as i32 - y as i32 > 3 { 230 } else { 30 };
        Rgba([v, v, v, 255])
    });
    let steepness = |image: &RgbaImage| {
        let mut total = 0u64;
        for (x, y, p) in image.enumerate_pixels() {
            if x + 1 < image.width() {
                total += u64::from(p[0].abs_diff(image.get_pixel(x + 1, y)[0])).pow(2);
            }
        }
        total
    };
    let bilinear = upscale(&gpu, Upscaler::Bilinear, &edge, (48, 32));
    let easu = upscale(&gpu, Upscaler::Easu, &edge, (48, 32));
    assert!(
        steepness(&easu) > steepness(&bilinear),
        "easu {} vs bilinear {}",
        steepness(&easu),
        steepness(&bilinear)
    );
}

#[test]
fn sharpening_keeps_constants_does_nothing_at_strength_zero_and_sharpens_at_one() {
    let gpu = common::gpu();
    let constant = RgbaImage::from_pixel(20, 12, Rgba([77, 160, 211, 255]));
    let soft = upscale(&gpu, Upscaler::Bilinear, &shapes(SOURCE), (48, 32));
    let contrast = |image: &RgbaImage| -> u64 {
        image
            .enumerate_pixels()
            .filter(|(x, _, _)| x + 1 < image.width())
            .map(|(x, y, p)| u64::from(p[1].abs_diff(image.get_pixel(x + 1, y)[1])).pow(2))
            .sum()
    };
    for filter in Sharpen::ALL {
        let at = |strength| Sharpening {
            filter: *filter,
            strength,
        };
        for strength in [0.0, 0.5, 1.0] {
            assert_eq!(
                sharpen(&gpu, at(strength), &constant),
                constant,
                "{} {strength} changed a constant",
                filter.name()
            );
        }
        let noise = noise((20, 12), 3);
        assert_eq!(
            sharpen(&gpu, at(0.0), &noise),
            noise,
            "{} at strength 0 changed the image",
            filter.name()
        );
        let half = contrast(&sharpen(&gpu, at(0.5), &soft));
        let full = contrast(&sharpen(&gpu, at(1.0), &soft));
        assert!(
            contrast(&soft) < half && half < full,
            "{}: contrast {} -> {half} (0.5) -> {full} (1)",
            filter.name(),
            contrast(&soft)
        );
    }
}

#[test]
fn rcas_never_leaves_the_range_of_a_pixel_and_its_four_neighbours_and_cas_may() {
    let gpu = common::gpu();
    let image = noise((32, 24), 11);
    let range_breaks = |out: &RgbaImage| {
        out.enumerate_pixels()
            .filter(|(x, y, p)| {
                let (x, y) = (*x as i64, *y as i64);
                let at = |dx: i64, dy: i64| {
                    let px = (x + dx).clamp(0, 31) as u32;
                    let py = (y + dy).clamp(0, 23) as u32;
                    *image.get_pixel(px, py)
                };
                let around = [at(0, 0), at(-1, 0), at(1, 0), at(0, -1), at(0, 1)];
                (0..3).any(|c| {
                    let low = around.iter().map(|q| q[c]).min().unwrap_or(0);
                    let high = around.iter().map(|q| q[c]).max().unwrap_or(255);
                    p[c] < low || p[c] > high
                })
            })
            .count()
    };
    let strongest = |filter| Sharpening {
        filter,
        strength: 1.0,
    };
    let rcas = sharpen(&gpu, strongest(Sharpen::Rcas), &image);
    assert_ne!(rcas, image, "rcas at strength 1 changed nothing");
    assert_eq!(range_breaks(&rcas), 0, "rcas left the neighbours' range");
    let cas = sharpen(&gpu, strongest(Sharpen::Cas), &image);
    assert!(
        range_breaks(&cas) > 0,
        "cas never left the range: the check cannot fail"
    );
}

#[test]
fn techniques_at_one_scale_share_one_scene_render() {
    let gpu = common::gpu();
    let scene = common::flat_chart(5.0);
    let ids = [
        "none@performance:bilinear",
        "fxaa@0.5:easu",
        "smaa@performance:lanczos+rcas=0.3",
    ];
    let techniques = ids
        .iter()
        .map(|id| common::technique(&gpu, id, &[]))
        .collect();
    let mut graph = common::graph(&gpu, &scene, techniques);
    let outputs = common::render_frames(&mut graph, &scene, (64, 36), 0..=0);
    assert!(outputs.iter().all(|o| o.dimensions() == (64, 36)));
    assert_eq!(graph.scene_renders_last_frame(), 1);
    let report = graph.memory_report();
    for technique in &report.techniques {
        assert_eq!(technique.input_shared_with.len(), 3, "{technique:?}");
        let input_bytes: u64 = technique.input_items.iter().map(|i| i.bytes).sum();
        assert!(input_bytes > 0, "{technique:?}");
    }
    // A native technique beside them needs its own render; the upscale and sharpen passes
    // are the techniques' own, timed and in the memory report.
    let techniques = ["none", "none@performance:bilinear", "smaa+cas"]
        .iter()
        .map(|id| common::technique(&gpu, id, &[]))
        .collect();
    let mut graph = common::graph(&gpu, &scene, techniques);
    common::render_frames(&mut graph, &scene, (64, 36), 0..=0);
    assert_eq!(graph.scene_renders_last_frame(), 2);
    let report = graph.memory_report();
    let scaled = &report.techniques[1];
    assert_eq!(
        scaled.input.as_deref(),
        Some("scene 1x 32x18"),
        "{scaled:?}"
    );
    assert_eq!(report.techniques[0].input.as_deref(), Some("scene 1x"));
    assert!(
        scaled
            .private_items
            .iter()
            .any(|i| i.label.ends_with("render")),
        "{scaled:?}"
    );
    if let Some(timings) = graph.timings() {
        let labels: Vec<&str> = timings.passes.iter().map(|p| p.label.as_str()).collect();
        for pass in ["none@performance:bilinear/upscale", "smaa+cas=0.5/sharpen"] {
            assert!(labels.contains(&pass), "{pass} not in {labels:?}");
        }
    }
}

#[test]
fn temporal_and_supersampled_techniques_work_at_a_render_scale() {
    // At half scale the chart's detail is lost to the scale itself, so each technique is
    // scored against the 64-sample render at the same scale, upscaled the same way: what
    // antialiasing can reach there.
    let gpu = common::gpu();
    let scene = common::flat_chart(5.0);
    let at_half = "@performance:bilinear";
    let ssaa = |factor| {
        let id = format!("ssaa{at_half}");
        common::technique(&gpu, &id, &[("mode", "ordered"), ("factor", factor)])
    };
    let ids = ["none", "taa", "msaa4"];
    let mut techniques = vec![ssaa("8"), ssaa("2")];
    techniques.extend(
        ids.iter()
            .map(|id| common::technique(&gpu, &format!("{id}{at_half}"), &[])),
    );
    let outputs = common::render_techniques(&gpu, &scene, techniques, (128, 72), 16);
    let error = |n: usize| common::mean_error(&outputs[0], &outputs[n]);
    let none = error(2);
    for (n, id) in [(1, "ssaa 2x2"), (3, "taa"), (4, "msaa4")] {
        assert!(
            error(n) < 0.75 * none,
            "{id} at half scale: {} vs No AA's {none} (levels from SSAA 8x8 at half scale)",
            error(n)
        );
    }
}

#[test]
fn a_combination_round_trips_through_its_record_and_reproduces_its_image() {
    let dir = tempfile::tempdir().expect("temp dir");
    let out = dir.path().join("out");
    let ok = common::aa_lab(&[
        "render",
        "--scene",
        "chart",
        "--size",
        "64x36",
        "--frame",
        "2",
        "--technique",
        "smaa@performance:easu+rcas=0.2,taa@0.6:lanczos,fxaa+cas,taau@0.5+rcas=0.2",
        "--out",
        out.to_str().expect("utf-8"),
    ]);
    assert!(ok.status.success(), "{}", common::stderr(&ok));
    let mut files: Vec<_> = std::fs::read_dir(&out)
        .expect("out dir")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|e| e == "png"))
        .collect();
    files.sort();
    assert_eq!(files.len(), 4, "{files:?}");
    // Each image's record lists all four techniques: one `render --from` renders them again.
    let again = dir.path().join("again");
    let ok = common::aa_lab(&[
        "render",
        "--from",
        files[0].to_str().expect("utf-8"),
        "--out",
        again.to_str().expect("utf-8"),
    ]);
    assert!(ok.status.success(), "{}", common::stderr(&ok));
    for file in &files {
        let record = aa_lab::export::png::read_record(file)
            .expect("readable")
            .expect("has a record");
        let spec = aa_lab::spec::parse_record(&record).expect("valid record");
        let ids: Vec<&str> = spec.techniques.iter().map(|t| t.id.as_str()).collect();
        assert_eq!(
            ids,
            [
                "smaa@performance:easu+rcas=0.2",
                "taa@0.6:lanczos",
                "fxaa+cas=0.5",
                "taau@performance+rcas=0.2"
            ]
        );
        let name = file.file_name().expect("a file name");
        let first = image::open(file).expect("png").to_rgba8();
        let second = image::open(again.join(name)).expect("png").to_rgba8();
        assert!(first == second, "{name:?}: render --from differs");
    }
}

#[test]
fn bad_combinations_are_refused_with_what_is_accepted() {
    for (id, needles) in [
        ("smaa@0", &["render scale `0`", "0.25 to 1"][..]),
        ("smaa@1.5", &["`1.5`", "out of range"]),
        ("smaa@quality:nearest", &["upscaler `nearest`", "easu"]),
        ("smaa+cas=abc", &["strength `abc`", "0 to 1"]),
        (
            "taau@quality:easu",
            &["reconstructs at the output size itself", "drop `:easu`"],
        ),
    ] {
        common::fails_with(
            &[
                "render",
                "--scene",
                "chart",
                "--size",
                "32x18",
                "--technique",
                id,
                "--out",
                "x.png",
            ],
            needles,
        );
    }
}
