//! User techniques in WGSL (`--technique user:PATH`, `aa::user`): a pass-through file
//! reproduces No AA bit for bit, errors name the file, line and column with a non-zero exit,
//! `override` constants are parameters (`--set user.NAME=VALUE`), and records keep the file's
//! path and content hash so that `render --from` refuses a changed file; on the HDR `neon`
//! scene the tonemap order (`user.tonemap_order`) runs a file on display values (after, the
//! default, unchanged) or on compressed radiance expanded back and tonemapped (before).

mod common;

use std::path::{Path, PathBuf};

use aa_lab::aa::user::program;
use common::{aa_lab, fails_with, stderr};

fn example(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("assets/user_techniques")
        .join(name)
}

/// Renders `scene` at a small size through `techniques` into `dir` with extra arguments.
fn render(dir: &Path, scene: &str, techniques: &str, extra: &[&str]) {
    let mut args = vec![
        "render",
        "--scene",
        scene,
        "--size",
        "96x54",
        "--frame",
        "2",
        "--technique",
        techniques,
        "--out",
        dir.to_str().expect("utf-8"),
        "--force",
    ];
    args.extend_from_slice(extra);
    let out = aa_lab(&args);
    assert!(out.status.success(), "{args:?}: {}", stderr(&out));
}

/// The image a technique wrote into `dir` (`<scene>-<id part>.png`).
fn image_of(dir: &Path, scene: &str, id_part: &str) -> image::RgbaImage {
    let prefix = format!("{scene}-{id_part}");
    let path = std::fs::read_dir(dir)
        .expect("output dir")
        .filter_map(Result::ok)
        .map(|e| e.path())
        .find(|p| {
            p.file_name()
                .and_then(|n| n.to_str())
                .is_some_and(|n| n.starts_with(&prefix) && n.ends_with(".png"))
        })
        .unwrap_or_else(|| panic!("no {prefix}*.png in {}", dir.display()));
    image::open(&path).expect("png").to_rgba8()
}

fn user_arg(path: &Path) -> String {
    format!("user:{}", path.display())
}

#[test]
fn every_example_file_compiles() {
    for entry in std::fs::read_dir(example("")).expect("assets/user_techniques") {
        let path = entry.expect("entry").path();
        if let Err(e) = program::load(&path) {
            panic!("{e}");
        }
    }
}

#[test]
fn a_pass_through_reproduces_no_aa_bit_for_bit() {
    let dir = tempfile::tempdir().expect("temp dir");
    // The same pass-through reading depth and motion (weighted by zero): it reads the render
    // with motion vectors at a zero jitter offset, which must be the same image.
    let with_motion = dir.path().join("motion_passthrough.wgsl");
    std::fs::write(
        &with_motion,
        "fn aa_main(pixel: vec2<u32>, uv: vec2<f32>) -> vec4<f32> {\n\
         \x20   let p = vec2<i32>(pixel);\n\
         \x20   let unused = 0.0 * (aa_depth(p) + aa_motion(p).x + f32(aa_frame()));\n\
         \x20   return aa_load(p) + vec4<f32>(unused);\n}\n",
    )
    .expect("write");
    for scene in ["hairball", "atrium"] {
        let list = format!(
            "none,{},{}",
            user_arg(&example("passthrough.wgsl")),
            user_arg(&with_motion)
        );
        render(dir.path(), scene, &list, &[]);
        let none = image_of(dir.path(), scene, "none");
        let plain = image_of(dir.path(), scene, "user-passthrough-");
        let motion = image_of(dir.path(), scene, "user-motion_passthrough-");
        assert!(
            none == plain,
            "{scene}: the pass-through differs from No AA"
        );
        assert!(
            none == motion,
            "{scene}: the pass-through on the motion render differs from No AA"
        );
    }
}

#[test]
fn a_broken_file_is_reported_with_its_line_and_column() {
    let dir = tempfile::tempdir().expect("temp dir");
    let out = dir.path().join("out");
    // Writes `name` with `bytes` (when given) and checks that rendering it fails with `needles`.
    let fails = |name: &str, bytes: Option<&[u8]>, needles: &[&str]| {
        let file = dir.path().join(name);
        if let Some(bytes) = bytes {
            std::fs::write(&file, bytes).expect("write");
        }
        let technique = user_arg(&file);
        let args = [
            "render",
            "--scene",
            "chart",
            "--size",
            "32x18",
            "--technique",
            &technique,
            "--out",
            out.to_str().expect("utf-8"),
        ];
        fails_with(&args, needles)
    };
    let text = fails(
        "broken.wgsl",
        Some(b"// a typo on line 4\n\nfn aa_main(pixel: vec2<u32>, uv: vec2<f32>) -> vec4<f32> {\n    return aa_lod(vec2<i32>(pixel));\n}\n"),
        &["broken.wgsl:4:12: ", "aa_lod"],
    );
    assert!(text.contains("return aa_lod"), "{text}");
    fails(
        "wrong.wgsl",
        Some(b"fn aa_main(pixel: vec2<i32>) -> vec4<f32> {\n    return aa_load(pixel);\n}\n"),
        &["wrong.wgsl:1:1: ", program::CONTRACT],
    );
    fails(
        "binary.wgsl",
        Some(b"fn aa_main\xff\xfe"),
        &["binary.wgsl:1:11: ", "not UTF-8"],
    );
    fails("missing.wgsl", None, &["missing.wgsl", "cannot read"]);
}

/// The largest channel value of a radiance (OpenEXR) output, which must be finite throughout.
fn largest_finite_radiance(path: &Path) -> f32 {
    let image = image::open(path).expect("exr").to_rgba32f();
    image.pixels().flat_map(|p| p.0).fold(0.0, |largest, x| {
        assert!(x.is_finite(), "{}: a non-finite value", path.display());
        largest.max(x)
    })
}

#[test]
fn the_tonemap_order_runs_a_file_on_radiance_before_the_tonemapper() {
    let dir = tempfile::tempdir().expect("temp dir");
    let (blur, through) = (
        user_arg(&example("edge_blur.wgsl")),
        user_arg(&example("passthrough.wgsl")),
    );
    let neon = |folder: &str, techniques: &str, order: &str| {
        let out = dir.path().join(folder);
        let set = format!("user.tonemap_order={order}");
        let extra: &[&str] = &["--set", &set, "--exr"];
        render(&out, "neon", techniques, extra);
        out
    };
    let list = |user: &str| format!("none,{user}");
    // After (the default): the file reads the displayed image, so a pass-through is No AA
    // bit for bit on an HDR scene too, and nothing is written as radiance.
    let after = neon("after", &list(&blur), "after");
    let none = image_of(&after, "neon", "none");
    let blurred_after = image_of(&after, "neon", "user-edge_blur-");
    let through_after = neon("through-after", &list(&through), "after");
    assert!(image_of(&through_after, "neon", "user-passthrough-") == none);
    assert!(!std::fs::read_dir(&after).expect("dir").any(|e| {
        e.expect("entry")
            .path()
            .extension()
            .is_some_and(|x| x == "exr")
    }));
    // Before: compressed, then expanded back to radiance (far above white, finite) and
    // tonemapped by the graph: a pass-through then shows No AA's frame within half-float
    // rounding, where radiance shown without the tonemap would be a different image.
    let through_before = neon("through-before", &list(&through), "before");
    let exr = |folder: &Path, stem: &str| {
        std::fs::read_dir(folder)
            .expect("dir")
            .map(|e| e.expect("entry").path())
            .find(|p| {
                p.extension().is_some_and(|x| x == "exr")
                    && p.file_name()
                        .is_some_and(|n| n.to_string_lossy().contains(stem))
            })
            .unwrap_or_else(|| panic!("no {stem} radiance in {}", folder.display()))
    };
    let brightest = largest_finite_radiance(&exr(&through_before, "passthrough"));
    assert!(brightest > 4.0, "the radiance peaks at {brightest}");
    let shown = image_of(&through_before, "neon", "user-passthrough-");
    let difference = aa_lab::metrics::compare(&none, &shown).expect("same size");
    assert!(difference.flip < 0.002, "{difference:?}");
    // With two stops of exposure the file reads the exposed radiance, and the expansion takes
    // the exposure off again before the tonemapper applies it (not twice).
    let exposed = dir.path().join("exposed");
    let extra = ["--set", "user.tonemap_order=before", "--exposure", "2"];
    render(&exposed, "neon", &list(&through), &extra);
    let exposed_none = image_of(&exposed, "neon", "none");
    let exposed_shown = image_of(&exposed, "neon", "user-passthrough-");
    let difference = aa_lab::metrics::compare(&exposed_none, &exposed_shown).expect("size");
    assert!(difference.flip < 0.01, "at +2 EV: {difference:?}");
    // The blur runs in either order, and the orders differ (edges judged and blended on the
    // compressed radiance), but it is the same frame.
    let before = neon("before", &list(&blur), "before");
    largest_finite_radiance(&exr(&before, "edge_blur"));
    let blurred_before = image_of(&before, "neon", "user-edge_blur-");
    assert!(blurred_before != blurred_after, "the order changed nothing");
    assert!(
        blurred_before != none,
        "the blur did nothing before the tonemapper"
    );
    let between = aa_lab::metrics::compare(&blurred_after, &blurred_before).expect("size");
    assert!(between.flip < 0.05, "{between:?}");
    // The record keeps the order, and `render --from` reproduces it.
    let recorded_dir = dir.path().join("recorded");
    render(
        &recorded_dir,
        "neon",
        &blur,
        &["--set", "user.tonemap_order=before"],
    );
    let recorded = std::fs::read_dir(&recorded_dir)
        .expect("dir")
        .map(|e| e.expect("entry").path())
        .next()
        .expect("the blur's image");
    let record = aa_lab::export::png::read_record(&recorded)
        .expect("readable")
        .expect("has a record");
    let spec: aa_lab::spec::RenderSpec = serde_json::from_str(&record).expect("json");
    let entry = spec.techniques.iter().find(|t| t.id.starts_with("user:"));
    assert_eq!(
        entry.and_then(|t| t.settings.get("tonemap_order")),
        Some(&aa_lab::aa::ParamValue::Choice("before".to_owned()))
    );
    common::assert_from_reproduces(&recorded);
}

#[test]
fn override_constants_are_parameters() {
    let dir = tempfile::tempdir().expect("temp dir");
    let blur = user_arg(&example("edge_blur.wgsl"));
    let list = format!("none,{blur}");
    render(dir.path(), "hairball", &list, &["--set", "user.strength=0"]);
    let none = image_of(dir.path(), "hairball", "none");
    let off = image_of(dir.path(), "hairball", "user-edge_blur-");
    assert!(none == off, "strength 0 must leave the image unchanged");
    render(dir.path(), "hairball", &list, &["--set", "user.strength=1"]);
    let on = image_of(dir.path(), "hairball", "user-edge_blur-");
    let error = common::mean_error(&none, &on);
    assert!(error > 0.5, "strength 1 changed the image by only {error}");
    // The full id works as well as `user`; values are checked against the stated range.
    fails_with(
        &[
            "render",
            "--scene",
            "chart",
            "--size",
            "32x18",
            "--technique",
            &list,
            "--set",
            &format!("{blur}.strength=2"),
            "--out",
            dir.path().to_str().expect("utf-8"),
        ],
        &["strength", "outside 0..=1"],
    );
    fails_with(
        &[
            "render",
            "--scene",
            "chart",
            "--size",
            "32x18",
            "--technique",
            &list,
            "--set",
            "user.nope=1",
            "--out",
            dir.path().to_str().expect("utf-8"),
        ],
        &["no parameter `nope`", "strength, threshold, ramp"],
    );
}

#[test]
fn records_keep_the_path_and_hash_and_refuse_a_changed_file() {
    let dir = tempfile::tempdir().expect("temp dir");
    let file = dir.path().join("mine.wgsl");
    std::fs::copy(example("edge_blur.wgsl"), &file).expect("copy");
    let first = dir.path().join("first.png");
    let technique = user_arg(&file);
    let out = aa_lab(&[
        "render",
        "--scene",
        "chart",
        "--size",
        "64x36",
        "--technique",
        &technique,
        "--set",
        "user.strength=0.9",
        "--out",
        first.to_str().expect("utf-8"),
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    let record = aa_lab::export::png::read_record(&first)
        .expect("readable")
        .expect("has a record");
    let spec: aa_lab::spec::RenderSpec = serde_json::from_str(&record).expect("json");
    let canonical = std::fs::canonicalize(&file).expect("canonical");
    let entry = &spec.techniques[0];
    assert_eq!(entry.id, format!("user:{}", canonical.display()));
    let bytes = std::fs::read(&file).expect("read");
    assert_eq!(
        entry.source_hash.as_deref(),
        Some(program::content_hash(&bytes).as_str())
    );
    assert_eq!(
        entry.settings.get("strength"),
        Some(&aa_lab::aa::ParamValue::Float(0.9))
    );

    let again = dir.path().join("again.png");
    let out = aa_lab(&[
        "render",
        "--from",
        first.to_str().expect("utf-8"),
        "--out",
        again.to_str().expect("utf-8"),
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    let a = image::open(&first).expect("png").to_rgba8();
    let b = image::open(&again).expect("png").to_rgba8();
    assert!(
        a == b,
        "--from did not reproduce the user technique's image"
    );

    std::fs::write(&file, [bytes.as_slice(), b"\n// edited\n"].concat()).expect("edit");
    fails_with(
        &[
            "render",
            "--from",
            first.to_str().expect("utf-8"),
            "--out",
            dir.path().join("third.png").to_str().expect("utf-8"),
        ],
        &["mine.wgsl has changed since the record was made"],
    );
}

/// Issue 29, item 3: a file the driver takes minutes to compile (a large function-local array
/// keeps lavapipe busy for more than 100 s) no longer holds `render` without a word: progress
/// is printed every second and `--build-timeout` ends the wait with a clear error.
#[test]
fn a_build_past_the_timeout_is_a_clear_error_with_progress() {
    let dir = tempfile::tempdir().expect("temp dir");
    let file = dir.path().join("huge_array.wgsl");
    std::fs::write(
        &file,
        "fn aa_main(pixel: vec2<u32>, uv: vec2<f32>) -> vec4<f32> {\n\
         \x20   var big: array<f32, 65536>;\n\
         \x20   return aa_load(vec2<i32>(pixel)) + vec4<f32>(big[pixel.x % 65536u]);\n}\n",
    )
    .expect("write");
    let started = std::time::Instant::now();
    let text = fails_with(
        &[
            "render",
            "--scene",
            "chart",
            "--size",
            "64x36",
            "--technique",
            &format!("none,{}", user_arg(&file)),
            "--build-timeout",
            "2",
            "--out",
            dir.path().to_str().expect("utf-8"),
        ],
        &[
            "compiling the GPU pipeline of",
            "huge_array.wgsl",
            "still compiling after 2 s (--build-timeout)",
        ],
    );
    assert!(
        started.elapsed() < std::time::Duration::from_secs(60),
        "the timeout took {:?}: {text}",
        started.elapsed()
    );
}
