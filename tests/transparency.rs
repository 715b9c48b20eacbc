//! Alpha blending and the reactive mask: a blended pane composites over what is behind it by
//! its alpha; two overlapping panes give the same picture whichever order the scene lists
//! them in (the renderer sorts them back to front); a scene without blended surfaces renders
//! the same with the reactive mask asked for; on `glass`, the mask lowers TAA's and TAAU's
//! error against the 64-sample reference where the particles move; the render record keeps
//! the setting and `render --from` reproduces it.

mod common;

use aa_lab::aa::Technique;
use aa_lab::gpu::Gpu;
use aa_lab::graph::{FrameGraph, FrameScope};
use aa_lab::metrics::Plane;
use aa_lab::metrics::stability::MovingEdgeError;
use aa_lab::scene::procedural::{SceneOptions, builtin};
use aa_lab::scene::{AlphaMode, CameraRig, Material, Mesh, Motion, Scene, Vertex};
use glam::Vec3;
use image::{Rgba, RgbaImage};

const SIZE: (u32, u32) = (64, 64);

/// An unlit, double-sided square facing +Z, `half` across from its centre.
fn square(centre: Vec3, half: f32, material: usize) -> Mesh {
    let corner = |x: f32, y: f32| Vertex::new(centre + Vec3::new(x, y, 0.0), Vec3::Z, [0.0; 2]);
    Mesh {
        name: format!("square at {centre}"),
        vertices: vec![
            corner(-half, -half),
            corner(half, -half),
            corner(half, half),
            corner(-half, half),
        ],
        indices: vec![0, 1, 2, 0, 2, 3],
        material,
        spin: None,
    }
}

fn unlit(colour: Vec3, alpha: f32) -> Material {
    Material {
        base_color: colour,
        opacity: alpha,
        unlit: true,
        alpha_mode: if alpha < 1.0 {
            AlphaMode::Blend
        } else {
            AlphaMode::Opaque
        },
        ..Material::default()
    }
}

/// A scene of `meshes` over a large opaque background square, looked at head-on from +Z.
fn flat_scene(materials: Vec<Material>, meshes: Vec<Mesh>) -> Scene {
    let mut scene = Scene::empty("flat");
    scene.materials = materials;
    scene.meshes = meshes;
    scene.camera = CameraRig {
        target: Vec3::ZERO,
        distance: 4.0,
        yaw_degrees: 0.0,
        pitch_degrees: 0.0,
        fov_y_degrees: 30.0,
        near: 0.1,
        far: 20.0,
        orbit_degrees_per_frame: 0.0,
    };
    scene
}

/// No AA's image of `scene`.
fn no_aa(gpu: &Gpu, scene: &Scene) -> RgbaImage {
    let techniques = vec![common::technique(gpu, "none", &[])];
    common::render_techniques(gpu, scene, techniques, SIZE, 0).remove(0)
}

/// The sRGB pixel of linear `colour`.
fn encoded(colour: Vec3) -> [u8; 3] {
    colour.to_array().map(aa_lab::srgb::encode_byte)
}

fn assert_near(pixel: &Rgba<u8>, expected: [u8; 3], what: &str) {
    let off = (0..3).map(|c| pixel.0[c].abs_diff(expected[c])).max();
    assert!(
        off <= Some(2),
        "{what}: {:?}, expected {expected:?}",
        pixel.0
    );
}

const BACKGROUND: Vec3 = Vec3::new(0.2, 0.4, 0.6);
const RED: Vec3 = Vec3::new(0.9, 0.2, 0.1);
const BLUE: Vec3 = Vec3::new(0.1, 0.3, 0.95);

#[test]
fn a_pane_blends_over_what_is_behind_it_by_its_alpha() {
    let gpu = common::gpu();
    let alpha = 0.4;
    let scene = flat_scene(
        vec![unlit(BACKGROUND, 1.0), unlit(RED, alpha)],
        vec![
            square(Vec3::new(0.0, 0.0, -1.0), 5.0, 0),
            square(Vec3::ZERO, 0.3, 1),
        ],
    );
    let image = no_aa(&gpu, &scene);
    let blended = RED * alpha + BACKGROUND * (1.0 - alpha);
    assert_near(image.get_pixel(32, 32), encoded(blended), "under the pane");
    assert_near(
        image.get_pixel(3, 3),
        encoded(BACKGROUND),
        "beside the pane",
    );
}

#[test]
fn overlapping_panes_give_the_same_picture_in_either_order() {
    let gpu = common::gpu();
    let materials = vec![unlit(BACKGROUND, 1.0), unlit(RED, 0.5), unlit(BLUE, 0.5)];
    let background = square(Vec3::new(0.0, 0.0, -1.0), 5.0, 0);
    // The red pane is behind (z = 0), the blue one in front (z = 0.5); they overlap in the
    // middle of the image.
    let red = square(Vec3::new(-0.15, 0.0, 0.0), 0.3, 1);
    let blue = square(Vec3::new(0.15, 0.0, 0.5), 0.3, 2);
    let listed = |order: [&Mesh; 2]| {
        let meshes = [&background, order[0], order[1]].map(Mesh::clone).to_vec();
        no_aa(&gpu, &flat_scene(materials.clone(), meshes))
    };
    let (back_first, front_first) = (listed([&red, &blue]), listed([&blue, &red]));
    assert!(
        back_first == front_first,
        "the submission order changed the picture"
    );
    // Blue over red over the background, whichever came first.
    let expected = BLUE * 0.5 + (RED * 0.5 + BACKGROUND * 0.5) * 0.5;
    assert_near(
        front_first.get_pixel(32, 32),
        encoded(expected),
        "the overlap",
    );
}

/// TAA and TAAU, each without and with the reactive mask, in that order.
fn temporal_with_and_without_mask(gpu: &Gpu) -> Vec<Box<dyn Technique>> {
    let mask = [("reactive_mask", "1")];
    ["taa", "taa", "taau", "taau"]
        .iter()
        .zip([&[][..], &mask, &[], &mask])
        .map(|(id, settings)| common::technique(gpu, id, settings))
        .collect()
}

/// Every technique's image of every frame `0..=last` of `scene` seen by a still camera at
/// `size` (only the particles move).
fn still_frames(
    mut graph: FrameGraph,
    scene: &Scene,
    size: (u32, u32),
    last: u64,
) -> Vec<Vec<RgbaImage>> {
    (0..=last)
        .map(|frame| {
            let camera = Motion::Still.camera(&scene.camera, size, 0.25, frame);
            common::render(&mut graph, camera, frame == 0, FrameScope::All);
            common::outputs(&mut graph)
        })
        .collect()
}

#[test]
fn the_reactive_mask_changes_nothing_without_blended_surfaces() {
    let gpu = common::gpu();
    let scene = builtin("sparkle", &SceneOptions::default()).expect("built-in");
    let graph = common::graph(&gpu, &scene, temporal_with_and_without_mask(&gpu));
    let frames = still_frames(graph, &scene, (96, 64), 4);
    for images in &frames {
        assert!(images[0] == images[1], "TAA changed with the mask");
        assert!(images[2] == images[3], "TAAU changed with the mask");
    }
}

#[test]
fn the_reactive_mask_lowers_temporal_error_behind_the_moving_particles() {
    const WARMUP: usize = 6;
    const LAST: u64 = 14;
    let size = (240, 136);
    let gpu = common::gpu();
    let scene = builtin("glass", &SceneOptions::default()).expect("built-in");
    let mut techniques = temporal_with_and_without_mask(&gpu);
    techniques.push(common::reference(&gpu));
    let frames = still_frames(common::graph(&gpu, &scene, techniques), &scene, size, LAST);
    let luma: Vec<Vec<Plane>> = frames
        .iter()
        .map(|images| images.iter().map(Plane::luma).collect())
        .collect();
    let ghosting = |technique: usize| {
        let mut error = MovingEdgeError::new();
        for step in WARMUP..luma.len() {
            let (now, before) = (&luma[step], &luma[step - 1]);
            error
                .push(&now[technique], &now[4], &before[4])
                .expect("same size");
        }
        error.ghosting().expect("the particles moved")
    };
    let [taa, taa_mask, taau, taau_mask] = [0, 1, 2, 3].map(ghosting);
    eprintln!(
        "ghosting behind the particles: TAA {taa:.2} -> {taa_mask:.2} with the mask, \
         TAAU {taau:.2} -> {taau_mask:.2}"
    );
    assert!(
        taa_mask < 0.9 * taa,
        "TAA: {taa_mask:.2} with, {taa:.2} without"
    );
    assert!(
        taau_mask < 0.9 * taau,
        "TAAU: {taau_mask:.2} with, {taau:.2} without"
    );
}

#[test]
fn render_records_the_mask_setting_on_glass_and_from_reproduces_it() {
    let dir = tempfile::tempdir().expect("temp dir");
    let recorded = dir.path().join("glass-taa.png");
    let out = common::aa_lab(&[
        "render",
        "--scene",
        "glass",
        "--size",
        "160x90",
        "--frame",
        "3",
        "--technique",
        "taa",
        "--set",
        "taa.reactive_mask=0.5",
        "--out",
        recorded.to_str().expect("utf-8"),
    ]);
    assert!(out.status.success(), "{}", common::stderr(&out));
    let record = aa_lab::export::png::read_record(&recorded)
        .expect("readable")
        .expect("has a record");
    assert!(
        record.contains("\"scene\": \"glass\"") && record.contains("\"reactive_mask\": 0.5"),
        "{record}"
    );
    common::assert_from_reproduces(&recorded);
}
