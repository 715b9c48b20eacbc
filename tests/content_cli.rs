//! The content features of the `aa-lab` binary: image mode (`render --image`) reproduces the
//! scene path's FXAA and SMAA exactly and refuses what cannot run on an image, camera flags
//! change and record the view, and output names of same-named models cannot collide.

mod common;

use std::path::{Path, PathBuf};

fn run_ok(args: &[&str]) -> String {
    let out = common::aa_lab(args);
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(out.status.success(), "{args:?} failed: {stderr}");
    String::from_utf8_lossy(&out.stdout).into_owned() + &stderr
}

fn pixels(path: &Path) -> image::RgbaImage {
    image::open(path)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
        .to_rgba8()
}

/// The single file in `dir` whose name ends with `suffix`.
fn file_ending(dir: &Path, suffix: &str) -> PathBuf {
    let found: Vec<PathBuf> = std::fs::read_dir(dir)
        .expect("read dir")
        .map(|e| e.expect("entry").path())
        .filter(|p| p.to_string_lossy().ends_with(suffix))
        .collect();
    assert_eq!(found.len(), 1, "{suffix} in {}: {found:?}", dir.display());
    found[0].clone()
}

fn text(path: &Path) -> &str {
    path.to_str().expect("utf-8 path")
}

#[test]
fn image_mode_reproduces_the_scene_path_exactly() {
    let dir = tempfile::tempdir().expect("temp dir");
    let scene_out = dir.path().join("scene");
    run_ok(&[
        "render",
        "--scene",
        "atrium",
        "--size",
        "240x136",
        "--frame",
        "5",
        "--technique",
        "none,fxaa,smaa",
        "--out",
        text(&scene_out),
    ]);
    let none = scene_out.join("atrium-none.png");
    let image_out = dir.path().join("image");
    run_ok(&[
        "render",
        "--image",
        text(&none),
        "--technique",
        "fxaa,smaa",
        "--out",
        text(&image_out),
    ]);
    for id in ["fxaa", "smaa"] {
        let from_scene = pixels(&scene_out.join(format!("atrium-{id}.png")));
        let from_image = pixels(&file_ending(&image_out, &format!("-{id}.png")));
        assert!(
            from_scene == from_image,
            "{id}: image mode differs from the scene path ({} of {} pixels)",
            from_scene
                .pixels()
                .zip(from_image.pixels())
                .filter(|(a, b)| a != b)
                .count(),
            from_scene.pixels().len()
        );
        // And the technique did something: the output is not the input.
        assert!(from_scene != pixels(&none), "{id} changed nothing");
    }
    // The record names the input image; `--from` reproduces the image-mode run.
    let fxaa = file_ending(&image_out, "-fxaa.png");
    let again = dir.path().join("again");
    run_ok(&["render", "--from", text(&fxaa), "--out", text(&again)]);
    assert!(pixels(&file_ending(&again, "-fxaa.png")) == pixels(&fxaa));
}

#[test]
fn image_mode_refuses_techniques_that_need_the_scene_and_bad_images() {
    let dir = tempfile::tempdir().expect("temp dir");
    let input = dir.path().join("capture.png");
    image::RgbaImage::from_fn(64, 32, |x, y| {
        image::Rgba([(x * 4) as u8, (y * 8) as u8, 90, 255])
    })
    .save(&input)
    .expect("write input");
    for (technique, reason) in [
        ("taa", "jittered renders of several frames"),
        ("ssaa", "renders the scene itself"),
    ] {
        let out = common::aa_lab(&[
            "render",
            "--image",
            text(&input),
            "--technique",
            technique,
            "--out",
            text(dir.path()),
        ]);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "{technique} ran on an image");
        assert!(
            stderr.contains("cannot run on an image") && stderr.contains(reason),
            "{technique}: {stderr}"
        );
        assert!(!stderr.contains("panicked"), "{stderr}");
    }
    // SMAA with depth edges reads depth, which an image has not.
    let out = common::aa_lab(&[
        "render",
        "--image",
        text(&input),
        "--technique",
        "smaa",
        "--set",
        "smaa.edge_detection=depth",
        "--out",
        text(dir.path()),
    ]);
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("depth"));
    // Not an image.
    let bogus = dir.path().join("bogus.png");
    std::fs::write(&bogus, b"not a png").expect("write");
    let out = common::aa_lab(&["render", "--image", text(&bogus), "--technique", "fxaa"]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        !out.status.success() && stderr.contains("bogus.png"),
        "{stderr}"
    );
    // A JPEG works like a PNG.
    let jpeg = dir.path().join("capture.jpg");
    image::DynamicImage::ImageRgba8(pixels(&input))
        .to_rgb8()
        .save(&jpeg)
        .expect("write jpeg");
    run_ok(&[
        "render",
        "--image",
        text(&jpeg),
        "--technique",
        "fxaa",
        "--out",
        text(&dir.path().join("jpeg")),
    ]);
}

#[test]
fn camera_flags_set_and_record_the_view() {
    let dir = tempfile::tempdir().expect("temp dir");
    let default = dir.path().join("default.png");
    let moved = dir.path().join("moved.png");
    let common_args = [
        "render",
        "--scene",
        "atrium",
        "--size",
        "160x90",
        "--technique",
        "none",
    ];
    run_ok(&[&common_args[..], &["--out", text(&default)]].concat());
    run_ok(
        &[
            &common_args[..],
            &[
                "--camera-eye",
                "0,1.6,0",
                "--camera-look-at",
                "5,2,-3",
                "--fov",
                "75",
                "--camera-motion",
                "still",
                "--frame",
                "3",
                "--out",
                text(&moved),
            ],
        ]
        .concat(),
    );
    assert!(
        pixels(&default) != pixels(&moved),
        "the camera flags changed nothing"
    );
    let record = aa_lab::export::png::read_record(&moved)
        .expect("readable")
        .expect("a record");
    let spec: aa_lab::spec::RenderSpec = serde_json::from_str(&record).expect("spec");
    let rig = spec.rig.expect("the record keeps the camera");
    assert_eq!(rig.fov_y_degrees, 75.0);
    assert_eq!(rig.orbit_degrees_per_frame, 0.0);
    assert_eq!(rig.target, glam::Vec3::new(5.0, 2.0, -3.0));
    // The record reproduces the view.
    let again = dir.path().join("again.png");
    run_ok(&["render", "--from", text(&moved), "--out", text(&again)]);
    assert!(pixels(&again) == pixels(&moved));
    // A still camera is the same at every frame (the atrium's objects still move).
    let pose = |frame| aa_lab::scene::camera::OrbitPose::at_frame(&rig, frame);
    assert_eq!(pose(0), pose(3));
    // Bad values are errors, not panics.
    let out = common::aa_lab(
        &[
            &common_args[..],
            &["--camera-eye", "1,2", "--camera-look-at", "0,0,0"],
        ]
        .concat(),
    );
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("X,Y,Z"));
}

#[test]
fn same_named_models_from_different_folders_do_not_collide() {
    let dir = tempfile::tempdir().expect("temp dir");
    let out = dir.path().join("out");
    for folder in ["a", "b"] {
        let model = dir.path().join(folder);
        std::fs::create_dir_all(&model).expect("dir");
        // An untextured triangle without a material: the mid-grey default.
        std::fs::write(
            model.join("model.obj"),
            "v -1 -1 0\nv 1 -1 0\nv 0 1 0\nf 1 2 3\n",
        )
        .expect("write obj");
        run_ok(&[
            "render",
            "--scene",
            text(&model.join("model.obj")),
            "--size",
            "64x64",
            "--technique",
            "none",
            "--out",
            text(&out),
        ]);
    }
    let names: Vec<String> = std::fs::read_dir(&out)
        .expect("read out")
        .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
        .collect();
    assert_eq!(names.len(), 2, "{names:?}");
    assert!(
        names
            .iter()
            .all(|n| n.starts_with("model-") && n.ends_with("-none.png"))
    );
    // The untextured triangle is mid grey, not near-white.
    let image = pixels(&out.join(&names[0]));
    let centre = image.get_pixel(32, 34);
    assert!(centre[0] < 180 && centre[0] > 20, "{centre:?}");
}
