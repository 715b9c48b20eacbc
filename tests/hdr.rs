//! GPU tests of the HDR path (`graph::hdr`) on the `neon` scene: the reference averages
//! radiance (a thin emitter widens, unlike the display-referred average of tonemapped
//! samples); which tonemap order scores better depends on which of the two references a
//! technique is held to, and the tests pin both (FXAA, TAA, and MSAA's luminance-weighted
//! resolve against its box resolve; FXAA before the tonemapper tests the edges of the
//! perceptual copy, and so ties with the after order against the display-referred reference); the morphological techniques (SMAA in every mode, CMAA 2,
//! MLAA) run on radiance before the tonemapper and then side with the camera reference; LDR
//! scenes ignore every HDR setting; and the command line records the tonemap and reproduces
//! it.

mod common;

use aa_lab::graph::hdr::TonemapChoice;
use aa_lab::graph::{FrameGraph, Technique};
use aa_lab::metrics::compare;
use aa_lab::scene::Scene;
use aa_lab::scene::renderer::{Tonemap, Tonemapper};
use aa_lab::scene::source::load;
use image::{RgbImage, RgbaImage};

/// Small, and an odd size, so tubes fall anywhere in the pixel grid.
const SIZE: (u32, u32) = (401, 227);
/// The frame the figures are taken at (TAA has accumulated a full jitter cycle by then).
const FRAME: u64 = 9;

fn neon() -> Scene {
    load("neon", &Default::default()).unwrap_or_else(|e| panic!("{e}"))
}

/// Renders `techniques` (made on `gpu`) on `scene` through `tonemap` over frames 0..=FRAME.
fn render(
    gpu: &aa_lab::gpu::Gpu,
    scene: &Scene,
    tonemap: Option<Tonemap>,
    techniques: Vec<Box<dyn Technique>>,
) -> Vec<RgbaImage> {
    let mut graph: FrameGraph = common::graph(gpu, scene, techniques);
    graph.set_tonemap(tonemap);
    common::render_frames(&mut graph, scene, SIZE, 0..=FRAME)
}

fn agx() -> Option<Tonemap> {
    Some(Tonemap {
        operator: Tonemapper::Agx,
        exposure: 0.0,
    })
}

/// The 64-sample reference: `before` averages radiance (a camera), `after` tonemaps every
/// sample (display-referred).
fn reference(gpu: &aa_lab::gpu::Gpu, order: &str) -> Box<dyn Technique> {
    common::technique(gpu, "ssaa", &[("factor", "8"), ("tonemap_order", order)])
}

fn flip(reference: &RgbaImage, test: &RgbaImage) -> f64 {
    compare(reference, test).expect("same size").flip
}

/// Mean of every channel of every pixel (display values).
fn mean_level(image: &RgbaImage) -> f64 {
    image
        .pixels()
        .map(|p| f64::from(p[0]) + f64::from(p[1]) + f64::from(p[2]))
        .sum::<f64>()
        / (3.0 * f64::from(image.width() * image.height()))
}

#[test]
fn the_reference_averages_radiance_so_thin_emitters_widen() {
    let gpu = common::gpu();
    let scene = neon();
    assert!(scene.is_hdr());
    let images = render(
        &gpu,
        &scene,
        agx(),
        vec![reference(&gpu, "before"), reference(&gpu, "after")],
    );
    let bright = |image: &RgbaImage| {
        (image.pixels())
            .filter(|p| p[0].max(p[1]).max(p[2]) > 160)
            .count()
    };
    let (camera, display) = (bright(&images[0]), bright(&images[1]));
    println!("bright pixels: radiance averaged {camera}, tonemapped samples averaged {display}");
    // A pixel a quarter covered by a tube of radiance 8 averages to 2, which the tonemapper
    // shows nearly as bright as the tube itself, where a quarter of the tube's displayed value
    // is a dim grey: around every emitter the camera reference has more bright pixels.
    assert!(
        camera as f64 > display as f64 * 1.3,
        "{camera} vs {display}"
    );
}

#[test]
fn each_tonemap_order_wins_against_its_own_reference() {
    let gpu = common::gpu();
    let scene = neon();
    let technique = |id: &str, settings: &[(&str, &str)]| common::technique(&gpu, id, settings);
    let images = render(
        &gpu,
        &scene,
        agx(),
        vec![
            reference(&gpu, "before"),
            reference(&gpu, "after"),
            technique("fxaa", &[("tonemap_order", "before")]),
            technique("fxaa", &[("tonemap_order", "after")]),
            technique("taa", &[("tonemap_order", "before")]),
            technique("taa", &[("tonemap_order", "after")]),
        ],
    );
    let (camera, display) = (&images[0], &images[1]);
    for (name, before, after) in [
        ("fxaa", &images[2], &images[3]),
        ("taa", &images[4], &images[5]),
    ] {
        let against_camera = (flip(camera, before), flip(camera, after));
        let against_display = (flip(display, before), flip(display, after));
        println!(
            "{name} FLIP (before, after) against the camera reference {against_camera:.4?}, \
             against the display-referred one {against_display:.4?}"
        );
        // Run on radiance, the technique spreads a bright tube's radiance over its
        // neighbours, as the camera's average does; run on displayed values, it blends
        // displayed values, as the display-referred average does. (The first margin is the
        // smaller: on the wide background the two orders now agree, and the gap is the tubes'.)
        assert!(
            against_camera.0 < against_camera.1 * 0.9,
            "{name}: {against_camera:?}"
        );
        if name == "fxaa" {
            // FXAA before the tonemapper finds its edges on the perceptual copy, the same ones
            // as after it (`fxaa_before_the_tonemapper_finds_the_edges_of_the_displayed_image`),
            // so against the display-referred reference the orders come close (on raw
            // radiance's edges the before order scored 45% worse there). They tied while both
            // read the sub-pixel amount from the darker side in encoded luma; after the
            // tonemapper it is a linear fraction now, which that reference favours (measured
            // .0301 before, .0262 after); before it, a fraction of radiance would light the
            // pixels beside a tube past white (.0445), so it keeps the darker-side reading.
            let ratio = against_display.0 / against_display.1;
            assert!((1.0..1.2).contains(&ratio), "{name}: {against_display:?}");
        } else {
            assert!(
                against_display.1 < against_display.0 * 0.8,
                "{name}: {against_display:?}"
            );
        }
    }
}

/// The debug view `view` (a file name) of a `render --debug-views` of `neon` with `args`
/// added, into the folder `name` of `dir`.
fn neon_debug_view(dir: &std::path::Path, name: &str, args: &[&str], view: &str) -> RgbImage {
    let out = dir.join(name);
    let size = format!("{}x{}", SIZE.0, SIZE.1);
    let frame = FRAME.to_string();
    let mut command = vec![
        "render", "--scene", "neon", "--size", &size, "--frame", &frame,
    ];
    command.extend_from_slice(args);
    let out_arg = out.to_str().expect("utf-8 path");
    command.extend_from_slice(&["--debug-views", "--out", out_arg]);
    let output = common::aa_lab(&command);
    assert!(output.status.success(), "{}", common::stderr(&output));
    image::open(out.join(view))
        .unwrap_or_else(|e| panic!("{view}: {e}"))
        .to_rgb8()
}

/// The pixels FXAA's edge-mask debug view marks as edges (coloured, where the rest is grey)
/// with FXAA in `order`.
fn fxaa_edge_pixels(dir: &std::path::Path, order: &str) -> Vec<bool> {
    let set = format!("fxaa.tonemap_order={order}");
    let mask = neon_debug_view(
        dir,
        order,
        &["-t", "fxaa", "--set", &set],
        "neon-fxaa-edges.png",
    );
    mask.pixels().map(|p| p[0].abs_diff(p[2]) > 20).collect()
}

/// Before the tonemapper FXAA's luma tests read the perceptual copy (compressed, encoded), so
/// its thresholds find the edges of the displayed image; on raw radiance they found 5% other
/// pixels.
#[test]
fn fxaa_before_the_tonemapper_finds_the_edges_of_the_displayed_image() {
    let dir = tempfile::tempdir().expect("temp dir");
    let (before, after) = (
        fxaa_edge_pixels(dir.path(), "before"),
        fxaa_edge_pixels(dir.path(), "after"),
    );
    let edges = after.iter().filter(|&&e| e).count();
    let disagree = before.iter().zip(&after).filter(|(b, a)| b != a).count();
    println!("FXAA edge pixels after the tonemapper {edges}, differing before it {disagree}");
    assert!(edges > 1000, "only {edges} edge pixels");
    assert!(
        disagree * 100 < edges,
        "{disagree} of {edges} edge pixels differ"
    );
}

/// The pixels of SMAA's edge debug view (before the tonemapper, at `exposure` stops) that hold
/// an edge.
fn smaa_edge_pixels(dir: &std::path::Path, exposure: &str) -> Vec<bool> {
    let args = [
        "-t",
        "smaa",
        "--set",
        "smaa.tonemap_order=before",
        "--exposure",
        exposure,
    ];
    let edges = neon_debug_view(dir, exposure, &args, "neon-smaa-edges.png");
    edges.pixels().map(|p| p[0] > 0 || p[1] > 0).collect()
}

/// The perceptual copy applies the frame's exposure before compressing, as the tonemapper
/// does, so two stops more bring dim edges up to SMAA's threshold as on the displayed image
/// (ignoring the exposure, the copy gave the same edges at every exposure).
#[test]
fn the_exposure_changes_the_edges_found_before_the_tonemapper() {
    let dir = tempfile::tempdir().expect("temp dir");
    let (plain, brighter) = (
        smaa_edge_pixels(dir.path(), "0"),
        smaa_edge_pixels(dir.path(), "2"),
    );
    let count = |edges: &[bool]| edges.iter().filter(|&&e| e).count();
    let changed = plain.iter().zip(&brighter).filter(|(a, b)| a != b).count();
    println!(
        "SMAA edge pixels at 0 EV {}, at +2 EV {}, changed {changed}",
        count(&plain),
        count(&brighter)
    );
    assert!(count(&brighter) > count(&plain), "no more edges at +2 EV");
    assert!(changed > 20, "only {changed} edge pixels changed");
}

/// The morphological techniques, each in both orders, after the tonemapper's references.
const MORPHOLOGICAL: [&str; 6] = ["smaa", "cmaa2", "mlaa", "smaa-t2x", "smaa-s2x", "smaa-4x"];

#[test]
fn the_morphological_techniques_run_on_radiance_before_the_tonemapper() {
    let gpu = common::gpu();
    let scene = neon();
    let mut techniques = vec![
        reference(&gpu, "before"),
        common::technique(&gpu, "none", &[]),
    ];
    for id in MORPHOLOGICAL {
        for order in ["before", "after"] {
            techniques.push(common::technique(&gpu, id, &[("tonemap_order", order)]));
        }
    }
    let images = render(&gpu, &scene, agx(), techniques);
    let (camera, no_aa) = (&images[0], &images[1]);
    let no_aa_flip = flip(camera, no_aa);
    for (i, id) in MORPHOLOGICAL.into_iter().enumerate() {
        let (before, after) = (&images[2 + 2 * i], &images[3 + 2 * i]);
        let against_camera = (flip(camera, before), flip(camera, after));
        let between = flip(after, before);
        println!(
            "{id} FLIP (before, after) against the camera reference {against_camera:.4?} (No AA \
             {no_aa_flip:.4}), between the orders {between:.4}"
        );
        // The order ran: edges found on the perceptual copy, blends of radiance.
        assert_ne!(before, after, "{id}: the order changed nothing");
        // A sensible image: the same frame as after the tonemapper but for the edges (not
        // radiance shown raw, not a black or white frame, not edges torn apart), and closer to
        // the camera reference than no antialiasing.
        assert!(between < 0.05, "{id}: {between} from the after-order image");
        assert!(against_camera.0 < no_aa_flip, "{id}: {against_camera:?}");
        // Blending radiance spreads a bright tube over its neighbours as the camera's average
        // does: closer to the camera reference than blending displayed values.
        assert!(
            against_camera.0 < against_camera.1 * 0.9,
            "{id}: {against_camera:?}"
        );
    }
}

#[test]
fn the_luminance_weighted_msaa_resolve_keeps_bright_edges_antialiased() {
    let gpu = common::gpu();
    let scene = neon();
    let msaa = |settings: &[(&str, &str)]| common::technique(&gpu, "msaa4", settings);
    let images = render(
        &gpu,
        &scene,
        agx(),
        vec![
            reference(&gpu, "after"),
            msaa(&[]),
            msaa(&[("luma_weighted", "on")]),
            msaa(&[("tonemap_order", "after")]),
        ],
    );
    let display = &images[0];
    let [box_resolve, weighted, tonemapped] = [1, 2, 3].map(|i| flip(display, &images[i]));
    println!(
        "MSAA 4x FLIP against the display-referred reference: box resolve of radiance \
         {box_resolve:.4}, luminance-weighted {weighted:.4}, box resolve of tonemapped samples \
         {tonemapped:.4}"
    );
    // The box resolve of radiance shows a quarter-covered bright edge pixel nearly white (the
    // stair steps stay); weighting each sample by 1 / (1 + luma) brings it towards the
    // quarter grey the display-referred average has; resolving tonemapped samples is that
    // average at four samples.
    assert!(weighted < box_resolve * 0.85, "{weighted} vs {box_resolve}");
    assert!(tonemapped < weighted, "{tonemapped} vs {weighted}");
}

#[test]
fn ldr_scenes_ignore_the_tonemap_order_and_auto_leaves_them_on_the_ldr_path() {
    let gpu = common::gpu();
    let scene = load(
        "hairball",
        &aa_lab::scene::procedural::SceneOptions {
            density: 0.05,
            ..Default::default()
        },
    )
    .unwrap_or_else(|e| panic!("{e}"));
    assert!(!scene.is_hdr());
    assert_eq!(TonemapChoice::Auto.resolve(scene.is_hdr(), 1.0), None);
    assert!(TonemapChoice::Auto.resolve(true, 0.0).is_some());
    let set = |order: &str| {
        (["fxaa", "msaa4", "taa"].into_iter().chain(MORPHOLOGICAL))
            .map(|id| common::technique(&gpu, id, &[("tonemap_order", order)]))
            .collect()
    };
    let before = render(&gpu, &scene, None, set("before"));
    let after = render(&gpu, &scene, None, set("after"));
    assert_eq!(before, after, "the order must not matter on the LDR path");
}

#[test]
fn the_ldr_path_clamps_what_the_hdr_path_tonemaps() {
    let scene = neon();
    let gpu = common::gpu();
    let ldr = render(
        &gpu,
        &scene,
        None,
        vec![common::technique(&gpu, "none", &[])],
    );
    let hdr = render(
        &gpu,
        &scene,
        agx(),
        vec![common::technique(&gpu, "none", &[])],
    );
    // Clamped, every tube pixel brighter than white in some channel shows 255 there; through
    // AgX only the bulbs do (AgX reaches white 16.5 stops above black, the tubes stay below).
    let clipped = |image: &RgbaImage| {
        image
            .pixels()
            .filter(|p| p[0].max(p[1]).max(p[2]) == 255)
            .count()
    };
    let (clamped, tonemapped) = (clipped(&ldr[0]), clipped(&hdr[0]));
    println!("pixels at 255: LDR {clamped}, AgX {tonemapped}");
    assert!(
        clamped > 200 && tonemapped < clamped / 2,
        "{clamped} vs {tonemapped}"
    );
    // Exposure scales radiance before the tonemapper: three stops down darkens the frame.
    let darker = Some(Tonemap {
        exposure: -3.0,
        ..agx().expect("a tonemap")
    });
    let dim = render(
        &gpu,
        &scene,
        darker,
        vec![common::technique(&gpu, "none", &[])],
    );
    assert!(mean_level(&dim[0]) < mean_level(&hdr[0]) * 0.8);
}

#[test]
fn the_command_line_records_the_tonemap_and_reproduces_it() {
    let dir = tempfile::tempdir().expect("temp dir");
    // FXAA, and SMAA T2x for the morphological techniques (its temporal resolve included).
    for id in ["fxaa", "smaa-t2x"] {
        let out = dir.path().join(id).join("neon.png");
        let order = format!("{id}.tonemap_order=before");
        std::fs::create_dir_all(dir.path().join(id)).expect("a folder");
        let output = common::aa_lab(&[
            "render",
            "--scene",
            "neon",
            "--size",
            "96x54",
            "--frame",
            "2",
            "--technique",
            id,
            "--set",
            &order,
            "--tonemap",
            "aces",
            "--exposure",
            "-1.5",
            "--out",
            out.to_str().expect("utf-8 path"),
        ]);
        assert!(output.status.success(), "{}", common::stderr(&output));
        let text = aa_lab::export::png::read_record(&out)
            .unwrap_or_else(|e| panic!("{e}"))
            .expect("an aa-lab record");
        let record = aa_lab::spec::parse_record(&text).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(
            (record.tonemap, record.exposure),
            (TonemapChoice::Aces, -1.5)
        );
        let settings = &record.techniques[0].settings;
        assert_eq!(
            (settings.get("tonemap_order"))
                .map(ToString::to_string)
                .as_deref(),
            Some("before"),
            "{id}: {settings:?}"
        );
        common::assert_from_reproduces(&out);
    }
    common::fails_with(
        &["render", "--scene", "neon", "--tonemap", "filmic"],
        &["filmic", "reinhard, aces, agx, neutral"],
    );
    common::fails_with(
        &["render", "--scene", "neon", "--exposure", "40"],
        &["40", "between -20 and 20"],
    );
}

#[test]
fn render_writes_the_radiance_of_techniques_before_the_tonemapper_and_compare_scores_it_with_hdr_flip()
 {
    let dir = tempfile::tempdir().expect("temp dir");
    let out = dir.path().to_str().expect("utf-8 path");
    let output = common::aa_lab(&[
        "render",
        "--scene",
        "neon",
        "--size",
        "160x90",
        "--frame",
        "2",
        "--technique",
        "ssaa,msaa4,fxaa",
        "--set",
        "ssaa.factor=4",
        "--exr",
        "--out",
        out,
    ]);
    assert!(output.status.success(), "{}", common::stderr(&output));
    // SSAA and MSAA run on radiance by default, FXAA after the tonemapper: no radiance.
    let exr = |name: &str| dir.path().join(format!("neon-{name}.exr"));
    assert!(exr("ssaa").is_file() && exr("msaa4").is_file());
    assert!(!exr("fxaa").exists());
    let path = |p: std::path::PathBuf| p.to_str().expect("utf-8 path").to_owned();
    let scored = common::aa_lab(&["compare", "--json", &path(exr("ssaa")), &path(exr("msaa4"))]);
    assert!(scored.status.success(), "{}", common::stderr(&scored));
    let json: serde_json::Value =
        serde_json::from_str(&common::stdout(&scored)).expect("compare --json prints JSON");
    let hdr_flip = json["hdr_flip"].as_f64().expect("an HDR-FLIP figure");
    assert!(hdr_flip > 0.0 && hdr_flip < 0.5, "{json}");
    assert!(
        json["exposures"].as_u64().expect("exposures") >= 2,
        "{json}"
    );
    let same = common::aa_lab(&["compare", "--json", &path(exr("ssaa")), &path(exr("ssaa"))]);
    let same: serde_json::Value = serde_json::from_str(&common::stdout(&same)).expect("JSON");
    assert_eq!(same["hdr_flip"].as_f64(), Some(0.0));
    common::fails_with(
        &[
            "compare",
            &path(exr("ssaa")),
            &path(exr("msaa4")),
            "--heatmap",
            &path(dir.path().join("h.png")),
            "--metric",
            "ssim",
        ],
        &["HDR-FLIP only"],
    );
}

#[test]
fn the_memory_report_counts_the_radiance_outputs_only_while_they_exist() {
    let gpu = common::gpu();
    let scene = neon();
    let techniques = vec![common::technique(
        &gpu,
        "fxaa",
        &[("tonemap_order", "before")],
    )];
    let mut graph = common::graph(&gpu, &scene, techniques);
    let radiance_bytes = |graph: &FrameGraph| -> u64 {
        (graph.memory_report().techniques.iter())
            .flat_map(|t| &t.private_items)
            .filter(|item| item.label.contains("hdr output"))
            .map(|item| item.bytes)
            .sum()
    };
    graph.set_tonemap(agx());
    common::render_frames(&mut graph, &scene, SIZE, 0..=0);
    // Half floats, four channels.
    assert_eq!(radiance_bytes(&graph), u64::from(SIZE.0 * SIZE.1) * 8);
    graph.set_tonemap(None);
    common::render_frames(&mut graph, &scene, SIZE, 0..=0);
    assert_eq!(radiance_bytes(&graph), 0);
}

#[test]
fn the_background_is_tonemapped_alike_before_and_after_the_tonemapper() {
    // The clear colour of a tonemapped render is tonemapped on the CPU (`Tonemap::apply`);
    // that of a render of radiance goes through the graph's tonemap pass on the GPU. The
    // corner of neon is background: both must show it alike, for every operator and an
    // exposure that lifts it.
    let gpu = common::gpu();
    let scene = neon();
    for operator in [
        Tonemapper::Reinhard,
        Tonemapper::Aces,
        Tonemapper::Agx,
        Tonemapper::Neutral,
    ] {
        let tonemap = Some(Tonemap {
            operator,
            exposure: 4.0,
        });
        let techniques = vec![
            common::technique(&gpu, "none", &[]),
            common::technique(&gpu, "msaa4", &[]),
        ];
        let images = render(&gpu, &scene, tonemap, techniques);
        let (after, before) = (images[0].get_pixel(2, 2), images[1].get_pixel(2, 2));
        assert!(
            common::largest_channel_difference(after, before) <= 1,
            "{operator:?}: {after:?} after the tonemapper, {before:?} before"
        );
        assert!(
            after[2] > 20,
            "{operator:?}: the background {after:?} is not lifted"
        );
    }
}
