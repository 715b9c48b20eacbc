//! Shared helpers of the tests: the device (failing loudly when no adapter exists), a
//! technique with settings, the one harness that renders techniques on a scene and reads their
//! outputs back, image differences, fixture images, running the binary, and small generated
//! scenes whose expected pixels are known exactly.

#![allow(dead_code)]

pub mod temporal;

use std::ops::RangeInclusive;

use aa_lab::aa::{self, FrameInfo, Technique};
use aa_lab::gpu::{Gpu, read_texture_rgba8};
use aa_lab::graph::{FrameGraph, FrameScope};
use aa_lab::metrics::Plane;
use aa_lab::metrics::stability::{ChangeAccumulator, temporal_instability};
use aa_lab::scene::camera::FrameCamera;
use aa_lab::scene::{AlphaMode, CameraRig, Material, Mesh, Motion, Scene, TextureImage, Vertex};
use glam::{Vec2, Vec3};
use image::RgbaImage;

/// The test device. GPU tests must never pass silently without one.
pub fn gpu() -> Gpu {
    match Gpu::headless() {
        Ok(gpu) => gpu,
        Err(err) => panic!(
            "GPU tests need a Vulkan (or Metal/DX12) adapter and none was found: {err}. \
             On Debian/Ubuntu install Mesa's software driver: apt-get install mesa-vulkan-drivers libvulkan1"
        ),
    }
}

fn quad(corners: [Vec2; 4], z: f32, material: usize, name: &str) -> Mesh {
    let vertices = corners
        .iter()
        .zip([[0.0, 1.0], [1.0, 1.0], [1.0, 0.0], [0.0, 0.0]])
        .map(|(c, uv)| Vertex::new(c.extend(z), Vec3::Z, uv))
        .collect();
    Mesh {
        name: name.to_owned(),
        vertices,
        indices: vec![0, 1, 2, 0, 2, 3],
        material,
        spin: None,
    }
}

/// A flat, unlit chart seen head-on: white background, a black quad whose left edge is slanted
/// by `slant_degrees` from vertical, and an alpha-masked card (left half opaque by texture
/// alpha, a soft alpha ramp across the middle). World units map to the view so that the chart
/// spans x in -1.6..1.6 and y in -0.9..0.9.
pub fn flat_chart(slant_degrees: f32) -> Scene {
    let black = Material {
        name: "black".into(),
        base_color: Vec3::ZERO,
        unlit: true,
        ..Material::default()
    };
    // Alpha ramp texture: alpha falls from 1 to 0 across the texture's width.
    let ramp = image::RgbaImage::from_fn(64, 8, |x, _| {
        image::Rgba([0, 0, 0, (255 - x * 4).min(255) as u8])
    });
    let masked = Material {
        name: "masked".into(),
        base_color: Vec3::ZERO,
        base_color_texture: Some(0),
        unlit: true,
        alpha_mode: AlphaMode::Mask { cutoff: 0.5 },
        ..Material::default()
    };
    let t = slant_degrees.to_radians().tan();
    let slanted = quad(
        [
            Vec2::new(-0.2 - 0.6 * t, -0.6),
            Vec2::new(1.4, -0.6),
            Vec2::new(1.4, 0.6),
            Vec2::new(-0.2 + 0.6 * t, 0.6),
        ],
        0.0,
        0,
        "slanted edge",
    );
    let card = quad(
        [
            Vec2::new(-1.5, -0.3),
            Vec2::new(-0.5, -0.3),
            Vec2::new(-0.5, 0.3),
            Vec2::new(-1.5, 0.3),
        ],
        0.0,
        1,
        "card",
    );
    let fov: f32 = 40.0;
    Scene {
        name: "flat-chart".into(),
        meshes: vec![slanted, card],
        materials: vec![black, masked],
        textures: vec![TextureImage {
            label: "alpha ramp".into(),
            image: ramp,
        }],
        camera: CameraRig {
            target: Vec3::ZERO,
            distance: 0.9 / (fov.to_radians() * 0.5).tan(),
            yaw_degrees: 0.0,
            pitch_degrees: 0.0,
            fov_y_degrees: fov,
            near: 0.1,
            far: 100.0,
            orbit_degrees_per_frame: 0.0,
        },
        interior: false,
        light: Default::default(),
        clear_color: Vec3::ONE,
        views: Vec::new(),
        notes: Vec::new(),
        warnings: Vec::new(),
    }
}

/// Technique `id` from the registry with `settings` (key, value as typed on the command line).
pub fn technique(gpu: &Gpu, id: &str, settings: &[(&str, &str)]) -> Box<dyn Technique> {
    let mut t = aa::create(gpu, id).unwrap_or_else(|e| panic!("{e}"));
    for (key, value) in settings {
        aa::set_param(t.as_mut(), key, aa::params::parse_value(value))
            .unwrap_or_else(|e| panic!("{e}"));
    }
    t
}

/// Frame `frame` of the scene's own camera path at `size`.
pub fn camera(scene: &Scene, frame: u64, size: (u32, u32)) -> FrameCamera {
    FrameCamera::from_rig(&scene.camera, frame, size)
}

/// A frame graph over `scene` running `techniques`, in that order.
pub fn graph(gpu: &Gpu, scene: &Scene, techniques: Vec<Box<dyn Technique>>) -> FrameGraph {
    let mut graph = FrameGraph::new(gpu.clone(), scene);
    for technique in techniques {
        graph.add(technique);
    }
    graph
}

/// Renders one frame of `graph` (`scope`: every technique, or only the temporal ones as a
/// warm-up), panicking with the graph's error.
pub fn render(graph: &mut FrameGraph, camera: FrameCamera, reset_history: bool, scope: FrameScope) {
    graph
        .render(
            &FrameInfo {
                camera,
                reset_history,
            },
            scope,
        )
        .unwrap_or_else(|e| panic!("{e}"));
}

/// Finishes the graph's frame and reads every technique's output back, in the order the
/// techniques were added.
pub fn outputs(graph: &mut FrameGraph) -> Vec<RgbaImage> {
    graph.finish();
    graph
        .slots()
        .iter()
        .map(|s| read_texture_rgba8(graph.gpu(), s.output().expect("output")).expect("readback"))
        .collect()
}

/// Renders frames `frames` of the scene's camera at `size` with every technique of `graph`
/// (the first frame resets the histories) and reads every output of the last frame back.
pub fn render_frames(
    graph: &mut FrameGraph,
    scene: &Scene,
    size: (u32, u32),
    frames: RangeInclusive<u64>,
) -> Vec<RgbaImage> {
    let first = *frames.start();
    for frame in frames {
        render(
            graph,
            camera(scene, frame, size),
            frame == first,
            FrameScope::All,
        );
    }
    outputs(graph)
}

/// The harness in one call: renders `techniques` together on `scene` at `size` over frames
/// `0..=last` and returns each technique's output of the last frame.
pub fn render_techniques(
    gpu: &Gpu,
    scene: &Scene,
    techniques: Vec<Box<dyn Technique>>,
    size: (u32, u32),
    last: u64,
) -> Vec<RgbaImage> {
    render_frames(&mut graph(gpu, scene, techniques), scene, size, 0..=last)
}

/// Runs `cameras` in order (the first frame resets the history; earlier frames run only the
/// temporal techniques, as `spec::run` does) and returns every technique's output after the
/// last one.
pub fn run_cameras(graph: &mut FrameGraph, cameras: &[FrameCamera]) -> Vec<RgbaImage> {
    for (i, camera) in cameras.iter().enumerate() {
        let scope = if i + 1 == cameras.len() {
            FrameScope::All
        } else {
            FrameScope::TemporalOnly
        };
        render(graph, *camera, i == 0, scope);
    }
    outputs(graph)
}

/// The 64-sample ordered-grid SSAA reference and the given techniques after `frames` frames of
/// the scene's own camera path at `size` (the last frame is the one compared).
pub fn with_reference(
    gpu: &Gpu,
    scene: &Scene,
    techniques: Vec<Box<dyn Technique>>,
    frames: u64,
    size: (u32, u32),
) -> (RgbaImage, Vec<RgbaImage>) {
    with_reference_on(gpu, scene, techniques, frames, &|f| camera(scene, f, size))
}

/// The 64-sample ordered-grid SSAA reference and the given techniques after `frames` frames of
/// a camera path (the last frame is the one compared).
pub fn with_reference_on(
    gpu: &Gpu,
    scene: &Scene,
    techniques: Vec<Box<dyn Technique>>,
    frames: u64,
    camera: &temporal::CameraPath<'_>,
) -> (RgbaImage, Vec<RgbaImage>) {
    let mut all = vec![reference(gpu)];
    all.extend(techniques);
    let mut graph = graph(gpu, scene, all);
    let cameras: Vec<FrameCamera> = (0..frames).map(camera).collect();
    let mut images = run_cameras(&mut graph, &cameras);
    let reference = images.remove(0);
    (reference, images)
}

/// The bench's 64-sample reference (ordered-grid SSAA), as `compare` and `clip` score against.
pub fn reference(gpu: &Gpu) -> Box<dyn Technique> {
    let spec = aa_lab::bench::reference_spec(gpu).expect("reference");
    spec.create(gpu).expect("reference technique")
}

/// A graph of the techniques `ids` and, last, the bench's 64-sample reference marked as the
/// reference (which a clip's temporal figures are measured against).
pub fn graph_with_reference(gpu: &Gpu, scene: &Scene, ids: &[&str]) -> FrameGraph {
    let mut techniques: Vec<_> = ids.iter().map(|id| technique(gpu, id, &[])).collect();
    techniques.push(reference(gpu));
    let mut graph = graph(gpu, scene, techniques);
    if let Some(slot) = graph.slots_mut().last_mut() {
        slot.reference = true;
    }
    graph
}

/// Temporal instability of each technique of a [`graph_with_reference`] (the reference left
/// out) on the clip's pan of a quarter pixel per frame at `size`: `warmup` frames, then
/// `frames` measured, as `aa-lab clip --motion pan` measures it.
pub fn pan_instability(
    graph: &mut FrameGraph,
    scene: &Scene,
    size: (u32, u32),
    warmup: u64,
    frames: u64,
) -> Vec<f64> {
    let mut changes = vec![ChangeAccumulator::new(); graph.slots().len()];
    for frame in 0..warmup + frames {
        let camera = Motion::Pan.camera(&scene.camera, size, 0.25, frame);
        render(graph, camera, frame == 0, FrameScope::All);
        if frame >= warmup {
            for (change, image) in changes.iter_mut().zip(outputs(graph)) {
                change.push(Plane::luma(&image)).expect("same size");
            }
        }
    }
    let (reference, techniques) = changes.split_last().expect("the reference");
    techniques
        .iter()
        .map(|change| temporal_instability(change, reference).expect("the reference moved"))
        .collect()
}

/// Mean SSIM (scikit-image settings) of `image` against `reference`, as `aa-lab compare` gives.
pub fn ssim_mean(reference: &RgbaImage, image: &RgbaImage) -> f64 {
    aa_lab::metrics::ssim::ssim(reference, image)
        .expect("same size")
        .mean
}

/// Mean FLIP of `image` against `reference`, as `aa-lab compare` gives.
pub fn flip_mean(reference: &RgbaImage, image: &RgbaImage) -> f64 {
    aa_lab::metrics::flip::flip_map(reference, image)
        .expect("same size")
        .mean(None)
        .expect("pixels")
}

/// Mean absolute difference over RGB of two images of the same size, in 8-bit steps.
pub fn mean_error(a: &image::RgbaImage, b: &image::RgbaImage) -> f64 {
    window_error(a, b, (0, 0, a.width(), a.height()))
}

/// Mean absolute difference over RGB, in 8-bit steps, inside `(x, y, width, height)`.
pub fn window_error(
    a: &image::RgbaImage,
    b: &image::RgbaImage,
    (x0, y0, w, h): (u32, u32, u32, u32),
) -> f64 {
    assert_eq!(a.dimensions(), b.dimensions());
    let mut total = 0u64;
    for y in y0..y0 + h {
        for x in x0..x0 + w {
            let (p, q) = (a.get_pixel(x, y), b.get_pixel(x, y));
            total += (0..3).map(|c| u64::from(p[c].abs_diff(q[c]))).sum::<u64>();
        }
    }
    total as f64 / f64::from(3 * w * h)
}

/// The largest difference of the colour channels of two pixels.
pub fn largest_channel_difference(a: &image::Rgba<u8>, b: &image::Rgba<u8>) -> u8 {
    (0..3).map(|c| a[c].abs_diff(b[c])).max().unwrap_or(0)
}

/// `tests/fixtures/metrics/<name>.png`.
pub fn metrics_fixture(name: &str) -> image::RgbaImage {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/fixtures/metrics")
        .join(format!("{name}.png"));
    image::open(&path)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
        .to_rgba8()
}

/// A command's standard error as text.
pub fn stderr(out: &std::process::Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

/// A command's standard output as text.
pub fn stdout(out: &std::process::Output) -> String {
    String::from_utf8_lossy(&out.stdout).into_owned()
}

/// Runs the binary with `args` and checks that it failed cleanly (no panic) with every needle
/// in its message; returns the message.
pub fn fails_with(args: &[&str], needles: &[&str]) -> String {
    let out = aa_lab(args);
    let text = stderr(&out);
    assert!(!out.status.success(), "{args:?} succeeded: {text}");
    assert!(!text.contains("panicked"), "{args:?} panicked: {text}");
    for needle in needles {
        assert!(
            text.contains(needle),
            "{args:?}: `{needle}` missing from: {text}"
        );
    }
    text
}

/// Frame `t` of a moving bar, for image sequences: a 3-pixel vertical bar moving two pixels
/// right per frame over a vertical gradient, at `size`. `blur` spreads its edges over that
/// many pixels, as antialiasing would; without it every step changes the same pixels by the
/// same amounts.
pub fn bar_frame(t: u32, (width, height): (u32, u32), blur: u32) -> RgbaImage {
    RgbaImage::from_fn(width, height, |x, y| {
        let left = 4 + 2 * t;
        let distance = if x < left {
            left - x
        } else if x >= left + 3 {
            x + 1 - (left + 3)
        } else {
            0
        };
        let ground = (y * 8) as u8;
        let v = match distance {
            0 => 255,
            d if d <= blur => (255 + u32::from(ground) * d / (blur + 1)).min(255) as u8,
            _ => ground,
        };
        image::Rgba([v, v / 2, 255 - v, 255])
    })
}

/// Runs the `aa-lab` binary with `args`.
pub fn aa_lab(args: &[&str]) -> std::process::Output {
    std::process::Command::new(env!("CARGO_BIN_EXE_aa-lab"))
        .args(args)
        .output()
        .expect("the aa-lab binary runs")
}

/// Runs `render --from RECORDED` into the folder of `recorded` and checks that the record
/// reproduces the image exactly; returns the image.
pub fn assert_from_reproduces(recorded: &std::path::Path) -> image::RgbaImage {
    let again = recorded.with_file_name("reproduced.png");
    let out = aa_lab(&[
        "render",
        "--from",
        recorded.to_str().expect("a UTF-8 path"),
        "--out",
        again.to_str().expect("a UTF-8 path"),
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    let [a, b] = [recorded, &again].map(|p| {
        image::open(p)
            .unwrap_or_else(|e| panic!("{}: {e}", p.display()))
            .to_rgba8()
    });
    assert!(
        a == b,
        "render --from {} did not reproduce it",
        recorded.display()
    );
    a
}

/// Runs `aa-lab clip` on a tiny chart (64x48, 4 frames after 2 of warm-up, No AA, FXAA, TAA
/// and MSAA 4x besides the reference) into `out`, with `extra` arguments.
pub fn clip(out: &std::path::Path, extra: &[&str]) -> std::process::Output {
    let mut args = vec![
        "clip",
        "--scene",
        "chart",
        "--size",
        "64x48",
        "--frames",
        "4",
        "--warmup",
        "2",
        "--technique",
        "none,fxaa,taa,msaa4",
        "--out",
        out.to_str().expect("utf-8"),
    ];
    args.extend_from_slice(extra);
    aa_lab(&args)
}
