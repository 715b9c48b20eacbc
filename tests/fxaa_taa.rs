//! GPU tests of FXAA and TAA (software Vulkan in CI) on generated scenes whose content is known:
//! both change edge pixels and leave flat regions alone, both move the image towards the
//! 64-sample supersampled reference, TAA converges on a still camera, forgets its history on a
//! camera cut, a resize or a settings change, and leaves no ghost trail behind moving content.

mod common;

use aa_lab::aa::{self, FrameInfo};
use aa_lab::gpu::{Gpu, read_texture_rgba8};
use aa_lab::graph::{FrameGraph, FrameScope};
use aa_lab::metrics::edges;
use aa_lab::scene::camera::FrameCamera;
use aa_lab::scene::procedural::SceneOptions;
use aa_lab::scene::source::load;
use aa_lab::scene::{Material, Mesh, Scene, Vertex};
use glam::Vec3;
use image::RgbaImage;

const SIZE: (u32, u32) = (320, 180);

/// The sizes the fidelity tests (FXAA's and TAA's error against the reference) run at: the
/// usual one and an odd one of about the same aspect, whose pixels fall elsewhere on every
/// edge, so that tuning to one size fails here.
const FIDELITY_SIZES: [(u32, u32); 2] = [SIZE, (411, 233)];

/// Frame `frame` of the scene's own camera path (still for the flat chart).
fn still(scene: &Scene, frame: u64, size: (u32, u32)) -> FrameCamera {
    common::camera(scene, frame, size)
}

/// Renders one frame of every technique.
fn render(graph: &mut FrameGraph, camera: FrameCamera, reset_history: bool) {
    common::render(graph, camera, reset_history, FrameScope::All);
}

/// The window `(x, y, width, height)` around the flat chart's slanted edge at `size`: at
/// 320x180 (100 pixels per world unit) `(112, 40, 78, 100)`, away from the chart's other edges,
/// which are axis-aligned (at 320x180 they fall exactly on pixel borders, where No AA is
/// already exact and any filter can only add error).
fn slanted_edge((width, height): (u32, u32)) -> (u32, u32, u32, u32) {
    // The chart spans y -0.9..0.9 over the height.
    let per_unit = height as f32 / 1.8;
    let (centre_x, centre_y) = (width as f32 / 2.0, height as f32 / 2.0);
    let pixels = |v: f32| v.round() as u32;
    (
        pixels(centre_x - 0.48 * per_unit),
        pixels(centre_y - 0.5 * per_unit),
        pixels(0.78 * per_unit),
        pixels(per_unit),
    )
}

/// Counts, against the No AA image: flat pixels that moved by more than 1/255 (must be none)
/// and edge pixels that changed at all.
fn flat_and_edge_changes(no_aa: &RgbaImage, image: &RgbaImage) -> (Vec<(u32, u32, u8)>, usize) {
    let mut flat_changes = Vec::new();
    let mut edge_changes = 0;
    for (x, y, p) in no_aa.enumerate_pixels() {
        let d = common::largest_channel_difference(p, image.get_pixel(x, y));
        if common::temporal::flat_within(no_aa, x, y, 1) {
            if d > 1 {
                flat_changes.push((x, y, d));
            }
        } else if d > 0 {
            edge_changes += 1;
        }
    }
    (flat_changes, edge_changes)
}

/// The 64-sample reference, No AA and FXAA (its defaults) of the scene's first frame.
fn no_aa_and_fxaa(gpu: &Gpu, scene: &Scene, size: (u32, u32)) -> (RgbaImage, Vec<RgbaImage>) {
    let techniques = vec![
        common::technique(gpu, "none", &[]),
        common::technique(gpu, "fxaa", &[]),
    ];
    common::with_reference(gpu, scene, techniques, 1, size)
}

#[test]
fn fxaa_and_taa_change_edges_and_leave_flat_regions() {
    let gpu = common::gpu();
    let scene = common::flat_chart(5.0);
    let mut graph = common::graph(
        &gpu,
        &scene,
        vec![
            common::technique(&gpu, "none", &[]),
            common::technique(&gpu, "fxaa", &[]),
            common::technique(&gpu, "taa", &[]),
            // The lowest thresholds: a flat black cross then passes the contrast test's
            // comparison (0 < 0 is false), and only its own test keeps it out.
            common::technique(
                &gpu,
                "fxaa",
                &[("edge_threshold", "0.03"), ("edge_threshold_min", "0")],
            ),
        ],
    );
    let cameras: Vec<FrameCamera> = (0..16).map(|f| still(&scene, f, SIZE)).collect();
    let images = common::run_cameras(&mut graph, &cameras);
    for (name, image) in [
        ("fxaa", &images[1]),
        ("taa", &images[2]),
        ("fxaa at the lowest thresholds", &images[3]),
    ] {
        let (flat_changes, edge_changes) = flat_and_edge_changes(&images[0], image);
        assert!(
            flat_changes.is_empty(),
            "{name} changed {} flat pixels, e.g. {:?}",
            flat_changes.len(),
            &flat_changes[..flat_changes.len().min(8)]
        );
        // The slanted edge alone crosses about 120 rows.
        assert!(
            edge_changes > 100,
            "{name} changed only {edge_changes} edge pixels"
        );
    }
}

#[test]
fn every_fxaa_quality_preset_and_luma_antialiases_the_edge() {
    let gpu = common::gpu();
    let scene = common::flat_chart(5.0);
    let presets = <aa::fxaa::Quality as aa::Named>::NAMES;
    let mut techniques = vec![
        common::technique(&gpu, "none", &[]),
        common::technique(&gpu, "fxaa", &[("luma", "green")]),
    ];
    techniques.extend(
        presets
            .iter()
            .map(|q| common::technique(&gpu, "fxaa", &[("quality", q)])),
    );
    let (reference, images) = common::with_reference(&gpu, &scene, techniques, 1, SIZE);
    let none = common::window_error(&images[0], &reference, slanted_edge(SIZE));
    for (name, image) in std::iter::once("green luma")
        .chain(presets.iter().copied())
        .zip(&images[1..])
    {
        let error = common::window_error(image, &reference, slanted_edge(SIZE));
        assert!(
            error < none,
            "FXAA {name}: error {error:.3} is not below No AA's {none:.3}"
        );
    }
}

#[test]
fn fxaa_lowers_the_error_against_the_reference() {
    let gpu = common::gpu();
    // The sub-pixel amount moves the read by a linear fraction (as Lottes' and Bevy's FXAA do),
    // which lifts the black pixels beside a near-straight edge by a few percent of the light;
    // beside a clean edge (neighbours along it alike) the amount is halved: FXAA removes 53-56%
    // of No AA's error in the window at 3 degrees and 59-63% at 20 at the two sizes (40-44% and
    // 54-59% with the full amount, the defaults of 2026-11-27, which fail here). While the
    // amount was read from the darker side of the edge in encoded luma (until 2026-11-27) it
    // removed 80% and 68% at 320x180, but it gained less than Bevy's FXAA on the built-in
    // chart and hairball (`docs/techniques/fxaa.md`).
    for ((slant, bound), size) in [(3.0, 0.5), (20.0, 0.45)]
        .into_iter()
        .flat_map(|case| FIDELITY_SIZES.map(|size| (case, size)))
    {
        let scene = common::flat_chart(slant);
        let window = slanted_edge(size);
        let (reference, images) = no_aa_and_fxaa(&gpu, &scene, size);
        let none = common::window_error(&images[0], &reference, window);
        let fxaa = common::window_error(&images[1], &reference, window);
        // Blending in linear light keeps the light of the edge window; blending the encoded
        // values darkens every blended pixel (a half-covered black/white pixel came out at
        // 100/255 instead of the reference's 179 and the error fell by only a third).
        let [light_none, light_fxaa, light_reference] =
            [&images[0], &images[1], &reference].map(|i| window_light(i, window));
        println!(
            "slant {slant}, {size:?}: No AA {none:.3}, FXAA {fxaa:.3}; light No AA {light_none:.4}, \
             FXAA {light_fxaa:.4}, reference {light_reference:.4}"
        );
        assert!(
            fxaa < bound * none,
            "slant {slant}, {size:?}: FXAA error {fxaa:.3} vs No AA {none:.3}"
        );
        assert!(
            (light_fxaa - light_reference).abs() < 0.01 * light_reference,
            "slant {slant}, {size:?}: FXAA changed the edge window's light to {light_fxaa:.4} (reference \
             {light_reference:.4})"
        );
    }
}

#[test]
fn fxaa_and_taa_approach_the_reference_on_the_builtin_chart_and_hairball() {
    let gpu = common::gpu();
    // 480x270 and an odd size of about the same aspect.
    for (name, size) in ["chart", "hairball"]
        .into_iter()
        .flat_map(|name| [(480, 270), (397, 223)].map(|size| (name, size)))
    {
        let scene = load(name, &SceneOptions::default()).unwrap_or_else(|e| panic!("{e}"));
        let (reference, images) = common::with_reference(
            &gpu,
            &scene,
            vec![
                common::technique(&gpu, "none", &[]),
                common::technique(&gpu, "fxaa", &[]),
                common::technique(&gpu, "taa", &[]),
            ],
            33,
            size,
        );
        let [none, fxaa, taa] = [0, 1, 2].map(|i| common::mean_error(&images[i], &reference));
        println!("{name} {size:?}: No AA {none:.3}, FXAA {fxaa:.3}, TAA (32 frames) {taa:.3}");
        assert!(
            fxaa < none,
            "{name} {size:?}: FXAA {fxaa:.3} vs No AA {none:.3}"
        );
        assert!(
            taa < 0.5 * none,
            "{name} {size:?}: TAA {taa:.3} vs No AA {none:.3}"
        );
    }
}

/// FXAA's edge gain (the share of No AA's error on the reference's strong gradients that it
/// removes, `metrics::edges`) and FLIP on the built-in chart and hairball, each at two sizes
/// (one odd). Bevy's FXAA, run as a user technique on the same frames, gains .455, .492, .317
/// and .296 (FLIP .0307, .0520, .0730, .0771; `docs/techniques/fxaa.md`); the gains sit at or
/// above those, where the defaults before the sub-pixel factors (2026-11-27: .450, .491, .310,
/// .294) fail, and FLIP may not rise above what those defaults scored (.0290, .0508, .0681,
/// .0720).
#[test]
fn fxaa_edge_gain_and_flip_on_the_chart_and_hairball() {
    let gpu = common::gpu();
    for (name, size, least_gain, most_flip) in [
        ("chart", (1280, 720), 0.455, 0.0292),
        ("chart", (853, 481), 0.5, 0.0508),
        ("hairball", (640, 360), 0.315, 0.0681),
        ("hairball", (427, 241), 0.3, 0.0720),
    ] {
        let scene = load(name, &SceneOptions::default()).unwrap_or_else(|e| panic!("{e}"));
        let (reference, images) = no_aa_and_fxaa(&gpu, &scene, size);
        let gain = edges::edge_gain(&reference, &images[0], &images[1])
            .expect("same sizes")
            .expect("No AA has edge error");
        let flip = common::flip_mean(&reference, &images[1]);
        println!("{name} {size:?}: FXAA edge gain {gain:.3}, FLIP {flip:.4}");
        assert!(
            gain >= least_gain,
            "{name} {size:?}: FXAA edge gain {gain:.3} below {least_gain}"
        );
        assert!(
            flip <= most_flip,
            "{name} {size:?}: FXAA FLIP {flip:.4} above {most_flip}"
        );
    }
}

#[test]
fn taa_converges_on_a_still_camera() {
    let gpu = common::gpu();
    let scene = common::flat_chart(5.0);
    for size in FIDELITY_SIZES {
        taa_converges_at(&gpu, &scene, size);
    }
}

fn taa_converges_at(gpu: &Gpu, scene: &Scene, size: (u32, u32)) {
    let (reference, images) = common::with_reference(
        gpu,
        scene,
        vec![
            common::technique(gpu, "none", &[]),
            common::technique(gpu, "taa", &[]),
            common::technique(
                gpu,
                "taa",
                &[("samples", "16"), ("history_filter", "bilinear")],
            ),
        ],
        33,
        size,
    );
    let none = common::mean_error(&images[0], &reference);
    for (name, image) in [("default", &images[1]), ("16 bilinear", &images[2])] {
        let taa = common::mean_error(image, &reference);
        println!("{size:?}: No AA {none:.3}, TAA {name} {taa:.3}");
        assert!(
            taa < 0.5 * none,
            "{size:?}: TAA {name} after 32 frames: error {taa:.3} vs No AA {none:.3}"
        );
    }
}

/// A still camera looking at the flat chart from another place.
fn other_view(scene: &Scene, frame: u64, size: (u32, u32)) -> FrameCamera {
    let mut rig = scene.camera;
    rig.target = Vec3::new(0.5, 0.2, 0.0);
    rig.distance *= 0.7;
    FrameCamera::from_rig(&rig, frame, size)
}

#[test]
fn taa_forgets_its_history_on_a_cut_a_resize_and_a_settings_change() {
    let gpu = common::gpu();
    let scene = common::flat_chart(5.0);
    // A fresh TAA at one frame: what a reset must reproduce exactly.
    let fresh = |settings: &[(&str, &str)], camera: FrameCamera| {
        let mut g = common::graph(&gpu, &scene, vec![common::technique(&gpu, "taa", settings)]);
        render(&mut g, camera, true);
        common::outputs(&mut g).remove(0)
    };
    let mut g = common::graph(&gpu, &scene, vec![common::technique(&gpu, "taa", &[])]);
    let step = |g: &mut FrameGraph, camera: FrameCamera, reset: bool| {
        render(g, camera, reset);
        common::outputs(g).remove(0)
    };
    let mut settled = None;
    for f in 0..10 {
        settled = Some(step(&mut g, still(&scene, f, SIZE), f == 0));
    }
    let settled = settled.expect("frames ran");

    // A cut the caller does not flag: the frame's previous pose is not the history's pose.
    let cut = step(&mut g, other_view(&scene, 10, SIZE), false);
    let expected = fresh(&[], other_view(&scene, 10, SIZE));
    assert_eq!(
        common::mean_error(&cut, &expected),
        0.0,
        "history survived the cut"
    );
    assert!(
        common::mean_error(&cut, &settled) > 1.0,
        "the cut did not change the view"
    );

    // A continuing camera keeps its history...
    let kept = step(&mut g, other_view(&scene, 11, SIZE), false);
    let alone = fresh(&[], other_view(&scene, 11, SIZE));
    assert!(
        common::mean_error(&kept, &alone) > 0.01,
        "the history was not used"
    );
    // ...unless the caller flags a reset.
    let flagged = step(&mut g, other_view(&scene, 12, SIZE), true);
    let expected = fresh(&[], other_view(&scene, 12, SIZE));
    assert_eq!(
        common::mean_error(&flagged, &expected),
        0.0,
        "history survived the flagged reset"
    );

    // Resize.
    let small = (240, 135);
    let resized = step(&mut g, other_view(&scene, 13, small), false);
    let expected = fresh(&[], other_view(&scene, 13, small));
    assert_eq!(
        common::mean_error(&resized, &expected),
        0.0,
        "history survived the resize"
    );

    // Settings change.
    step(&mut g, other_view(&scene, 14, small), false);
    aa::set_param(
        g.slots_mut()[0].technique.as_mut(),
        "rectify",
        aa::params::parse_value("clip"),
    )
    .expect("clip is a rectification");
    let changed = step(&mut g, other_view(&scene, 15, small), false);
    let expected = fresh(&[("rectify", "clip")], other_view(&scene, 15, small));
    assert_eq!(
        common::mean_error(&changed, &expected),
        0.0,
        "history survived the settings change"
    );
}

#[test]
fn taa_leaves_no_ghost_trail_behind_camera_or_object_motion() {
    let gpu = common::gpu();
    let chart = common::flat_chart(5.0);
    let spinning = common::temporal::spinning_chart();
    let pan = |f| common::temporal::panning(&chart, f, 0.03, SIZE);
    let spin = |f| still(&spinning, f, SIZE);
    let cases: [(&str, &Scene, &common::temporal::CameraPath<'_>); 2] = [
        ("camera pan", &chart, &pan),
        ("spinning object", &spinning, &spin),
    ];
    for (name, scene, camera) in cases {
        // Without rectification the history keeps the old content: the measure sees ghosts.
        let (ghost, ghost_mean) =
            common::temporal::trail(&gpu, "taa", scene, camera, &[("rectify", "none")]);
        println!("{name}, none: worst {ghost}, mean {ghost_mean:.2}");
        assert!(
            ghost > 64,
            "{name}: no ghost without rectification ({ghost})"
        );
        for rectify in ["clamp", "clip", "variance"] {
            let (worst, mean) =
                common::temporal::trail(&gpu, "taa", scene, camera, &[("rectify", rectify)]);
            println!("{name}, {rectify}: worst {worst}, mean {mean:.2}");
            assert!(
                worst <= 2,
                "{name}, {rectify}: a trail pixel is off by {worst}/255"
            );
            assert!(
                mean < 0.5 * ghost_mean,
                "{name}, {rectify}: mean difference {mean:.2} vs {ghost_mean:.2} unrectified"
            );
        }
    }
}

#[test]
fn debug_views_have_the_output_size_and_show_something() {
    let gpu = common::gpu();
    let scene = common::flat_chart(5.0);
    let mut techniques = vec![
        common::technique(&gpu, "fxaa", &[]),
        common::technique(&gpu, "taa", &[]),
    ];
    for t in &mut techniques {
        t.set_debug_views(true);
    }
    let mut g = common::graph(&gpu, &scene, techniques);
    for f in 0..3 {
        render(
            &mut g,
            common::temporal::panning(&scene, f, 0.02, SIZE),
            f == 0,
        );
    }
    g.finish();
    let mut names = Vec::new();
    for slot in g.slots() {
        for view in slot.technique.debug_views() {
            let image = read_texture_rgba8(&gpu, view.texture).expect("readback");
            assert_eq!(image.dimensions(), SIZE, "{}", view.name);
            let lit = image
                .pixels()
                .filter(|p| p[0].max(p[1]).max(p[2]) > 100)
                .count();
            assert!(
                lit > 50,
                "{} view is nearly black ({lit} lit pixels)",
                view.name
            );
            names.push(view.name);
        }
    }
    assert_eq!(names, ["edges", "velocity", "rejection", "jitter"]);
}

#[test]
fn settings_and_presets_are_data() {
    let gpu = common::gpu();
    for id in ["fxaa", "taa"] {
        let mut t = common::technique(&gpu, id, &[]);
        let params = t.params();
        assert!(!params.is_empty());
        // Every parameter accepts its own current value back.
        for p in &params {
            aa::set_param(t.as_mut(), p.key, p.value.clone()).unwrap_or_else(|e| panic!("{e}"));
        }
        assert_eq!(aa::param_map(t.as_ref()).len(), params.len());
        for preset in t.presets() {
            t.apply_preset(preset)
                .unwrap_or_else(|e| panic!("{id} {preset}: {e}"));
        }
        let err = t
            .apply_preset("nonsense")
            .expect_err("unknown preset")
            .to_string();
        assert!(err.contains("default"), "{err}");
        let err = aa::set_param(t.as_mut(), "bogus", aa::params::parse_value("1"))
            .expect_err("unknown key")
            .to_string();
        assert!(err.contains(id), "{err}");
        assert!(t.path_note().is_some());
    }
    let mut fxaa = common::technique(&gpu, "fxaa", &[("quality", "39"), ("subpix", "0.5")]);
    assert!(
        aa::set_param(fxaa.as_mut(), "quality", aa::params::parse_value("16")).is_err(),
        "16 is not an FXAA preset"
    );
    fxaa.apply_preset("extreme").expect("Bevy preset");
    let map = aa::param_map(fxaa.as_ref());
    assert_eq!(map["quality"], aa::ParamValue::Choice("39".into()));
    assert_eq!(map["edge_threshold"], aa::ParamValue::Float(0.031));
    let taa = common::technique(&gpu, "taa", &[("samples", "16"), ("mip_bias", "-1")]);
    let frame = FrameInfo {
        camera: still(&common::flat_chart(0.0), 3, SIZE),
        reset_history: false,
    };
    let input = taa.scene_input(&frame).expect("taa reads a scene render");
    assert!(input.motion());
    assert_eq!(input.mip_bias(), -1.0);
    assert!((input.offset() - aa::common::temporal::jitter_offset(3, 16)).length() < 1e-4);
    assert!(taa.temporal());
}

/// A white, unlit field of thin black bars, slightly slanted like balusters seen at an angle:
/// widths from a third of a pixel to a pixel and a half at 320x180 (the view spans 100 pixels
/// per world unit there), which a one-sample render hits only at some jitter positions.
fn thin_bars() -> Scene {
    let mut scene = common::flat_chart(0.0);
    const PIXEL: f32 = 0.01;
    let widths = [0.35, 0.5, 0.7, 1.0, 1.4];
    let lean = 4f32.to_radians().tan();
    let quad = |name: String, material: usize, corners: [Vec3; 4]| Mesh {
        name,
        vertices: corners
            .iter()
            .zip([[0.0, 1.0], [1.0, 1.0], [1.0, 0.0], [0.0, 0.0]])
            .map(|(c, uv)| Vertex::new(*c, Vec3::Z, uv))
            .collect(),
        indices: vec![0, 1, 2, 0, 2, 3],
        material,
        spin: None,
    };
    scene.meshes = (0..20)
        .map(|i| {
            let x = -0.95 + 0.083 * i as f32;
            let w = widths[i % widths.len()] * PIXEL;
            let (bottom, top) = (-0.55, 0.55);
            quad(
                format!("bar {i}"),
                0,
                [
                    Vec3::new(x + lean * bottom, bottom, 0.0),
                    Vec3::new(x + w + lean * bottom, bottom, 0.0),
                    Vec3::new(x + w + lean * top, top, 0.0),
                    Vec3::new(x + lean * top, top, 0.0),
                ],
            )
        })
        .collect();
    // A white wall a little behind the bars, as a railing has: the background moves with
    // the bars, only slightly slower (parallax).
    scene.materials.push(Material {
        name: "white".into(),
        base_color: Vec3::ONE,
        unlit: true,
        ..Material::default()
    });
    let z = -0.2;
    scene.meshes.push(quad(
        "wall".into(),
        scene.materials.len() - 1,
        [
            Vec3::new(-3.0, -2.0, z),
            Vec3::new(3.0, -2.0, z),
            Vec3::new(3.0, 2.0, z),
            Vec3::new(-3.0, 2.0, z),
        ],
    ));
    scene
}

/// The ink of an image: the sum over pixels of one minus the linear intensity (mean of RGB),
/// which box filtering preserves (the bars' total area).
fn ink(image: &RgbaImage) -> f64 {
    image.pixels().map(|p| 1.0 - light(p)).sum()
}

/// The linear intensity of a pixel (mean of its decoded RGB), 0..1.
fn light(p: &image::Rgba<u8>) -> f64 {
    (0..3)
        .map(|c| aa_lab::srgb::decode_byte_f64(p[c]))
        .sum::<f64>()
        / 3.0
}

/// The mean linear intensity inside `(x, y, width, height)`.
fn window_light(image: &RgbaImage, (x0, y0, w, h): (u32, u32, u32, u32)) -> f64 {
    let mut total = 0.0;
    for y in y0..y0 + h {
        for x in x0..x0 + w {
            total += light(image.get_pixel(x, y));
        }
    }
    total / f64::from(w * h)
}

#[test]
fn taa_keeps_thin_lines_on_a_moving_camera() {
    // Before the velocity-weighted rectification, TAA cut the bars that a frame's jitter
    // missed out of its history: on a still camera a quarter of their ink was gone (the 1/(1 +
    // luminance) weighting, then on by default, hid part of it), and in motion its error
    // against the reference was barely half No AA's.
    let gpu = common::gpu();
    let scene = thin_bars();
    // Still, slow (0.41 pixels per frame) and faster (1.37) pans.
    for speed in [0.0, 0.0041, 0.0137] {
        let (reference, images) = common::with_reference_on(
            &gpu,
            &scene,
            vec![
                common::technique(&gpu, "none", &[]),
                common::technique(&gpu, "taa", &[]),
            ],
            33,
            &|f| common::temporal::panning(&scene, f, speed, SIZE),
        );
        let [none, taa] = [0, 1].map(|i| common::mean_error(&images[i], &reference));
        let kept = ink(&images[1]) / ink(&reference);
        println!("pan {speed}: No AA {none:.3}, TAA {taa:.3}, TAA ink {kept:.3} of the reference");
        assert!(
            taa < 0.6 * none,
            "pan {speed}: TAA error {taa:.3} vs No AA {none:.3}"
        );
        assert!(
            (0.93..1.08).contains(&kept),
            "pan {speed}: TAA keeps {kept:.3} of the thin bars' ink"
        );
    }
}

#[test]
fn taa_keeps_up_with_msaa_4x_on_hairball_and_atrium_under_the_orbit() {
    // Hairball's strands are thinner than a pixel, so each jittered point sample is noise, and
    // under the orbit the resampled history never converges to the pixel's average: the
    // current frame's Gaussian estimate (`current_filter`) is what brings TAA level with MSAA
    // 4x there. At larger sizes MSAA 4x resolves more of the strands, and TAA's loss to the
    // orbit grows with the motion in pixels; the falloff of the history's share with the
    // parallax and the speed holds it (docs/techniques/taa.md, "At other sizes"). Issue 31's
    // target is TAA within .011 SSIM of MSAA 4x on hairball, and at or above it in SSIM and
    // FLIP on atrium: met at 640x360; the odd 853x481 pins today's gap on hairball (.015), so
    // that tuning TAA to one size fails here. Without the falloff atrium was .0019 behind in
    // SSIM at 640x360 and .0015 in FLIP at 853x481. The silhouette falloff (a 2 px parallax
    // length where the farthest surface is broad) is what puts atrium's FLIP ahead by a
    // margin: without it, TAA's FLIP there is higher.
    let gpu = common::gpu();
    for (name, size, margin) in [
        ("hairball", (640, 360), 0.011),
        ("hairball", (853, 481), 0.02),
        ("atrium", (640, 360), 0.0),
        ("atrium", (853, 481), 0.0),
    ] {
        let scene = load(name, &SceneOptions::default()).unwrap_or_else(|e| panic!("{e}"));
        let (reference, images) = common::with_reference(
            &gpu,
            &scene,
            vec![
                common::technique(&gpu, "msaa4", &[]),
                common::technique(&gpu, "taa", &[]),
                common::technique(&gpu, "taa", &[("current_filter", "sample")]),
                common::technique(&gpu, "taa", &[("silhouette_falloff", "0")]),
            ],
            17,
            size,
        );
        let [msaa, taa, point] = [0, 1, 2].map(|i| common::ssim_mean(&reference, &images[i]));
        let [msaa_flip, taa_flip, one_length_flip] =
            [0, 1, 3].map(|i| common::flip_mean(&reference, &images[i]));
        println!(
            "{name} {size:?} frame 16: MSAA 4x {msaa:.4} / {msaa_flip:.4}, TAA {taa:.4} / \
             {taa_flip:.4}, TAA point sample {point:.4}, TAA FLIP without the silhouette \
             falloff {one_length_flip:.4}"
        );
        assert!(
            taa >= msaa - margin,
            "{name} {size:?}: TAA SSIM {taa:.4} vs MSAA 4x {msaa:.4}"
        );
        if name == "atrium" {
            assert!(
                taa_flip <= msaa_flip,
                "atrium {size:?}: TAA FLIP {taa_flip:.4} vs MSAA 4x {msaa_flip:.4}"
            );
            // .0342 against .0349 at 640x360, .0316 against .0323 at 853x481.
            assert!(
                taa_flip < one_length_flip - 0.0004,
                "atrium {size:?}: TAA FLIP {taa_flip:.4} vs {one_length_flip:.4} without the \
                 silhouette falloff"
            );
        } else {
            assert!(
                taa > point + 0.004,
                "hairball {size:?}: the Gaussian current frame {taa:.4} vs the point sample \
                 {point:.4}"
            );
        }
    }
}
