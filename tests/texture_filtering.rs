//! GPU tests of the scene shader's anisotropic texture filter (`sample_base_color` in
//! `shaders/scene.wgsl`) on a generated striped floor seen at a grazing angle, where plain
//! trilinear filtering blurs the stripes to grey and the 64-sample reference keeps them.

mod common;

use aa_lab::scene::{CameraRig, Material, Mesh, Scene, TextureImage, Vertex};
use glam::Vec3;
use image::RgbaImage;

const SIZE: (u32, u32) = (320, 180);

/// An unlit floor (y = 0) far larger than the view, textured with black and white stripes
/// across u (8 texels wide in a 64-texel texture) repeated every world unit, seen from `height`
/// above it looking `pitch_degrees` down at a point 12 units ahead, with the texture repeated
/// `repeats` times per world unit.
fn striped_floor(pitch_degrees: f32, repeats: f32) -> Scene {
    let stripes = RgbaImage::from_fn(64, 64, |x, _| {
        let v = if (x / 8) % 2 == 0 { 255 } else { 0 };
        image::Rgba([v, v, v, 255])
    });
    let floor = Material {
        name: "stripes".into(),
        base_color: Vec3::ONE,
        base_color_texture: Some(0),
        unlit: true,
        ..Material::default()
    };
    let (near, far, half_width) = (20.0_f32, -400.0_f32, 400.0_f32);
    let vertices = [
        (-half_width, near),
        (half_width, near),
        (half_width, far),
        (-half_width, far),
    ]
    .iter()
    .map(|&(x, z)| Vertex::new(Vec3::new(x, 0.0, z), Vec3::Y, [x * repeats, z * repeats]))
    .collect();
    let distance = 12.0 / pitch_degrees.to_radians().cos();
    Scene {
        name: "striped-floor".into(),
        meshes: vec![Mesh {
            name: "floor".into(),
            vertices,
            indices: vec![0, 1, 2, 0, 2, 3],
            material: 0,
            spin: None,
        }],
        materials: vec![floor],
        textures: vec![TextureImage {
            label: "stripes".into(),
            image: stripes,
        }],
        camera: CameraRig {
            target: Vec3::ZERO,
            distance,
            yaw_degrees: 0.0,
            pitch_degrees,
            fov_y_degrees: 40.0,
            near: 0.1,
            far: 1000.0,
            orbit_degrees_per_frame: 0.0,
        },
        interior: false,
        light: Default::default(),
        clear_color: Vec3::new(0.0, 0.0, 1.0),
        views: Vec::new(),
        notes: Vec::new(),
        warnings: Vec::new(),
    }
}

/// No AA's frame and the 64-sample SSAA reference of the same frame.
fn no_aa_and_reference(scene: &Scene) -> (RgbaImage, RgbaImage) {
    let gpu = common::gpu();
    let techniques = vec![
        common::technique(&gpu, "none", &[]),
        common::technique(&gpu, "ssaa", &[("factor", "8")]),
    ];
    let mut images = common::render_techniques(&gpu, scene, techniques, SIZE, 0).into_iter();
    let no_aa = images.next().expect("No AA output");
    let reference = images.next().expect("SSAA output");
    (no_aa, reference)
}

/// Standard deviation of the red channel inside `(x, y, width, height)`: the stripes' contrast.
fn contrast(image: &RgbaImage, (x0, y0, w, h): (u32, u32, u32, u32)) -> f64 {
    let values: Vec<f64> = (y0..y0 + h)
        .flat_map(|y| (x0..x0 + w).map(move |x| (x, y)))
        .map(|(x, y)| f64::from(image.get_pixel(x, y)[0]))
        .collect();
    let mean = values.iter().sum::<f64>() / values.len() as f64;
    (values.iter().map(|v| (v - mean) * (v - mean)).sum::<f64>() / values.len() as f64).sqrt()
}

/// Rows of the floor between the near stripes and the horizon, where the footprint is
/// several times longer (along the view) than wide: trilinear filtering there takes the level
/// of the long axis and greys the stripes out.
const GRAZING_BAND: (u32, u32, u32, u32) = (40, 96, 240, 14);

#[test]
fn grazing_stripes_at_1x_keep_the_contrast_and_the_values_of_the_reference() {
    let scene = striped_floor(4.0, 1.0);
    let (no_aa, reference) = no_aa_and_reference(&scene);
    let (sharp, wanted) = (
        contrast(&no_aa, GRAZING_BAND),
        contrast(&reference, GRAZING_BAND),
    );
    let error = common::window_error(&no_aa, &reference, GRAZING_BAND);
    eprintln!(
        "grazing band: contrast {sharp:.1} (reference {wanted:.1}), mean error {error:.2} steps"
    );
    assert!(
        wanted > 20.0,
        "the reference must resolve the stripes in the band (contrast {wanted:.1})"
    );
    assert!(
        sharp > 0.7 * wanted,
        "No AA's stripes are greyed out at a grazing angle: contrast {sharp:.1} against the \
         reference's {wanted:.1}"
    );
    assert!(
        error < 12.0,
        "No AA is {error:.2} steps from the reference in the grazing band"
    );
}

#[test]
fn an_edge_on_floor_with_extreme_footprints_renders_and_averages_to_grey() {
    // Nearly edge-on and repeated a thousand times per unit: footprints of many thousands of
    // texels along the view, which an unbounded filter would scan texel by texel.
    let scene = striped_floor(0.05, 1000.0);
    let gpu = common::gpu();
    let started = std::time::Instant::now();
    let image: RgbaImage = common::render_techniques(
        &gpu,
        &scene,
        vec![common::technique(&gpu, "none", &[])],
        SIZE,
        0,
    )
    .remove(0);
    let elapsed = started.elapsed();
    assert!(
        elapsed < std::time::Duration::from_secs(60),
        "an extreme footprint took {elapsed:?} for one frame"
    );
    // The floor (every pixel not the sky's blue): the stripes' mean, 50% grey in linear light
    // (sRGB 188), give or take the filter's precision.
    let floor: Vec<f64> = image
        .pixels()
        .filter(|p| p[0] == p[2])
        .map(|p| f64::from(p[0]))
        .collect();
    assert!(
        floor.len() > 2000,
        "the floor covers only {} pixels",
        floor.len()
    );
    let mean = floor.iter().sum::<f64>() / floor.len() as f64;
    assert!(
        (mean - 188.0).abs() < 12.0,
        "the floor's mean is {mean:.1}, not the stripes' average (sRGB 188)"
    );
}
