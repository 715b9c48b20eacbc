//! Camera paths and the ghost-trail measure the temporal techniques' tests share (TAA in
//! `fxaa_taa.rs`, the temporal upscaler in `taau.rs`).

#![allow(dead_code)]

use aa_lab::gpu::Gpu;
use aa_lab::graph::FrameScope;
use aa_lab::scene::camera::{FrameCamera, OrbitPose};
use aa_lab::scene::{Scene, Spin};
use glam::Vec3;
use image::RgbaImage;

/// Whether the (2r+1)^2 neighbourhood of (x, y) in `image` has one colour (never at the
/// border).
pub fn flat_within(image: &RgbaImage, x: u32, y: u32, r: u32) -> bool {
    if x < r || y < r || x + r >= image.width() || y + r >= image.height() {
        return false;
    }
    let centre = image.get_pixel(x, y);
    (y - r..=y + r).all(|j| (x - r..=x + r).all(|i| image.get_pixel(i, j) == centre))
}

/// The camera of each frame number.
pub type CameraPath<'a> = dyn Fn(u64) -> FrameCamera + 'a;

/// A camera panning sideways at `speed` world units per frame (pure translation).
pub fn panning(scene: &Scene, frame: u64, speed: f32, size: (u32, u32)) -> FrameCamera {
    let pose = |f: u64| {
        let mut pose = OrbitPose::at_frame(&scene.camera, 0);
        pose.target.x += speed * f as f32;
        pose
    };
    FrameCamera {
        pose: pose(frame),
        prev_pose: pose(frame.saturating_sub(1)),
        frame,
        size,
        render_size: None,
    }
}

/// The flat chart with the black quad spinning about its own centre (object motion).
pub fn spinning_chart() -> Scene {
    let mut scene = super::flat_chart(5.0);
    scene.meshes[0].spin = Some(Spin {
        pivot: Vec3::new(0.6, 0.0, 0.0),
        axis: Vec3::Z,
        radians_per_frame: 0.03,
    });
    scene
}

/// How the temporal technique `id` (with `settings`) matches the current No AA frame after 12 frames of motion, over
/// the pixels whose content changed during the last four frames: the largest difference among
/// those at least two pixels from any edge now (where the jittered 3x3 neighbourhood is flat,
/// so any old content left is a ghost), and the mean difference over all of them (edges
/// included, where TAA legitimately differs from No AA by its antialiasing).
pub fn trail(
    gpu: &Gpu,
    id: &str,
    scene: &Scene,
    camera: &CameraPath<'_>,
    settings: &[(&str, &str)],
) -> (u8, f64) {
    const FRAMES: u64 = 12;
    const LOOK_BACK: u64 = 4;
    let mut g = super::graph(
        gpu,
        scene,
        vec![
            super::technique(gpu, "none", &[]),
            super::technique(gpu, id, settings),
        ],
    );
    let mut recent = Vec::new();
    for f in 0..=FRAMES {
        super::render(&mut g, camera(f), f == 0, FrameScope::All);
        if f + LOOK_BACK >= FRAMES {
            recent.push(super::outputs(&mut g));
        }
    }
    let current = recent.last().expect("frames ran");
    let (no_aa, temporal) = (&current[0], &current[1]);
    let (mut interior, mut changed, mut total) = (0, 0, 0u64);
    let mut worst = 0;
    for (x, y, p) in no_aa.enumerate_pixels() {
        let moved = recent[..recent.len() - 1]
            .iter()
            .any(|earlier| earlier[0].get_pixel(x, y) != p);
        if !moved {
            continue;
        }
        let d = super::largest_channel_difference(p, temporal.get_pixel(x, y));
        changed += 1;
        total += u64::from(d);
        if flat_within(no_aa, x, y, 2) {
            interior += 1;
            worst = worst.max(d);
        }
    }
    assert!(
        interior > 200,
        "only {interior} interior pixels changed: the test moves too little"
    );
    (worst, total as f64 / changed as f64)
}
