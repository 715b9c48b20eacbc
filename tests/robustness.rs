//! Issue 10 (reliability), items 2 to 7, through the binary: GPU limits, the OpenGL backend,
//! inputs that would take unbounded memory, outputs that must never be lost or clobbered,
//! arithmetic that must not wrap into wrong results, and messages that say what is expected.
//! Every case ends in a clear message or a correct result, never a panic.

mod common;

use std::path::{Path, PathBuf};
use std::process::Output;

use common::{fails_with as refused, stderr, stdout};

fn utf8(path: &Path) -> &str {
    path.to_str().expect("utf-8 path")
}

/// `sheet` of the 64x36 chart with one region, written to `out`, plus `extra` arguments.
fn sheet_args<'a>(region: &'a str, out: &'a Path, extra: &[&'a str]) -> Vec<&'a str> {
    let mut args = vec![
        "sheet", "--scene", "chart", "--size", "64x36", "--region", region, "--out",
    ];
    args.push(utf8(out));
    args.extend_from_slice(extra);
    args
}

fn succeeds(args: &[&str]) -> Output {
    let out = common::aa_lab(args);
    assert!(out.status.success(), "{args:?} failed: {}", stderr(&out));
    out
}

/// A textured quad whose `map_Kd` is `texture` (written next to it).
fn textured_quad(dir: &Path, texture: &image::RgbaImage) -> PathBuf {
    texture.save(dir.join("wide.png")).expect("texture");
    std::fs::write(
        dir.join("quad.mtl"),
        "newmtl wide\nKd 1 1 1\nmap_Kd wide.png\n",
    )
    .expect("mtl");
    let obj = dir.join("quad.obj");
    std::fs::write(
        &obj,
        "mtllib quad.mtl\nv -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\n\
         vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nusemtl wide\nf 1/1 2/2 3/3 4/4\n",
    )
    .expect("obj");
    obj
}

/// Item 2: a `map_Kd` wider than any adapter's largest texture is downscaled with a warning.
#[test]
fn a_texture_wider_than_the_adapter_is_downscaled_with_a_warning() {
    let dir = tempfile::tempdir().expect("temp dir");
    let limit = common::gpu().caps.max_texture_dimension_2d;
    let obj = textured_quad(dir.path(), &image::RgbaImage::new(limit + 1, 2));
    let png = dir.path().join("quad.png");
    let out = succeeds(&[
        "render",
        "--scene",
        utf8(&obj),
        "--technique",
        "none",
        "--size",
        "32x18",
        "--out",
        utf8(&png),
    ]);
    let text = stderr(&out);
    assert!(
        text.contains("downscaled") && text.contains(&format!("{}x2", limit + 1)),
        "{text}"
    );
    assert!(png.is_file());
}

/// Item 2: `compare --gpu` of images wider than the adapter allows says so instead of
/// panicking in the upload.
#[test]
fn compare_on_the_gpu_refuses_images_beyond_the_adapter() {
    let dir = tempfile::tempdir().expect("temp dir");
    let limit = common::gpu().caps.max_texture_dimension_2d;
    let image = image::RgbaImage::from_fn(limit + 1, 12, |x, y| {
        image::Rgba([(x % 251) as u8, (y * 20) as u8, 9, 255])
    });
    let (a, b) = (dir.path().join("a.png"), dir.path().join("b.png"));
    image.save(&a).expect("a");
    image.save(&b).expect("b");
    succeeds(&["compare", utf8(&a), utf8(&b)]);
    refused(
        &["compare", utf8(&a), utf8(&b), "--gpu"],
        &["largest texture side", &limit.to_string()],
    );
}

/// Item 3: on the OpenGL backend nothing panics; what cannot run is listed with the reason, and
/// what can (No AA, SSAA) renders the same image as on the default backend.
#[test]
fn the_opengl_backend_lists_what_it_cannot_run_and_never_panics() {
    let run = |args: &[&str]| {
        std::process::Command::new(env!("CARGO_BIN_EXE_aa-lab"))
            .args(args)
            .env("WGPU_BACKEND", "gl")
            .output()
            .expect("the aa-lab binary runs")
    };
    let info = run(&["info"]);
    assert!(
        info.status.success(),
        "no OpenGL adapter: install Mesa's EGL/GL drivers (Debian/Ubuntu: apt-get install \
         libegl-mesa0 libgl1-mesa-dri): {}",
        stderr(&info)
    );
    assert!(stdout(&info).contains("Gl"), "{}", stdout(&info));
    let techniques = run(&["techniques"]);
    assert!(techniques.status.success(), "{}", stderr(&techniques));
    let listed = stdout(&techniques);
    assert!(
        listed.contains("smaa-s2x") && listed.contains("mesa-vulkan-drivers"),
        "{listed}"
    );
    assert!(
        listed
            .lines()
            .any(|l| l.contains("none") && l.contains("available") && !l.contains("unavailable"))
            && listed
                .lines()
                .any(|l| l.contains("ssaa") && !l.contains("unavailable")),
        "No AA and SSAA need no format reinterpretation and must run on GL:\n{listed}"
    );
    let dir = tempfile::tempdir().expect("temp dir");
    // What runs on GL renders the same image as on the default backend.
    let render_into = |runner: &dyn Fn(&[&str]) -> Output, out_dir: &Path| {
        let out = runner(&[
            "render",
            "--scene",
            "chart",
            "--technique",
            "none,ssaa",
            "--size",
            "64x36",
            "--out",
            utf8(out_dir),
        ]);
        assert!(out.status.success(), "No AA and SSAA: {}", stderr(&out));
    };
    let gl_dir = dir.path().join("gl");
    render_into(&run, &gl_dir);
    let default_dir = dir.path().join("default");
    render_into(&common::aa_lab, &default_dir);
    for name in ["chart-none.png", "chart-ssaa.png"] {
        let read = |d: &Path| image::open(d.join(name)).expect("written").to_rgba8();
        let error = common::mean_error(&read(&gl_dir), &read(&default_dir));
        assert!(
            error < 0.5,
            "{name}: GL differs from the default backend by {error}"
        );
    }
    for args in [
        vec!["render", "--technique", "all", "--size", "32x18", "--out"],
        vec!["render", "--technique", "fxaa", "--size", "32x18", "--out"],
    ] {
        let mut args = args;
        args.push(utf8(dir.path()));
        args.push("--force");
        let out = run(&args);
        let text = stderr(&out);
        assert!(!text.contains("panicked"), "{args:?} panicked: {text}");
        assert!(
            out.status.success() || text.contains("mesa-vulkan-drivers"),
            "{args:?} failed without naming the driver that runs it: {text}"
        );
    }
    let image = dir.path().join("noise.png");
    common::metrics_fixture("noise_clean")
        .save(&image)
        .expect("fixture");
    let compare = run(&["compare", utf8(&image), utf8(&image), "--gpu"]);
    let text = stderr(&compare);
    assert!(!text.contains("panicked"), "compare --gpu panicked: {text}");
}

/// Item 4: devices, FIFOs and directories are refused up front wherever a file is read.
#[test]
fn non_regular_files_are_refused_up_front() {
    let dir = tempfile::tempdir().expect("temp dir");
    let out = dir.path().join("x.png");
    refused(
        &["render", "--scene", "/dev/zero", "--out", utf8(&out)],
        &["/dev/zero", "not a regular file"],
    );
    refused(
        &["render", "--from", "/dev/zero", "--out", utf8(&out)],
        &["/dev/zero", "not a regular file"],
    );
    let obj = dir.path().join("zero.obj");
    std::fs::write(
        &obj,
        "mtllib /dev/zero\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
    )
    .expect("obj");
    refused(
        &["render", "--scene", utf8(&obj), "--out", utf8(&out)],
        &["/dev/zero", "not a regular file"],
    );
}

/// Item 4: a sheet that would need terabytes, and images too large to compare, are refused
/// with the limit before any allocation.
#[test]
fn huge_sheets_and_comparisons_are_refused_with_the_limit() {
    let dir = tempfile::tempdir().expect("temp dir");
    let sheet = dir.path().join("sheet.png");
    for zoom in ["1000", "100000", "2147483648"] {
        refused(
            &sheet_args("a=0,0,32,18", &sheet, &["--zoom", zoom]),
            &["16384"],
        );
    }
    assert!(!sheet.exists());
    // A PNG header claiming 11000x11000 (494 KB would hold the real thing) is enough: the
    // limit is checked before decoding.
    let big = dir.path().join("big.png");
    {
        let file = std::fs::File::create(&big).expect("big");
        let mut encoder = png::Encoder::new(file, 11000, 11000);
        encoder.set_color(png::ColorType::Rgba);
        let mut writer = encoder.write_header().expect("header");
        // One token IDAT chunk: decoders read the header up to it.
        writer
            .write_chunk(png::chunk::IDAT, &[0x78, 0x9c])
            .expect("idat");
        drop(writer);
    }
    refused(
        &["compare", utf8(&big), utf8(&big)],
        &["11000x11000", "compare handles at most"],
    );
}

/// Item 5: nothing is replaced without --force, inputs never, and --force replaces and says so.
#[test]
fn outputs_are_never_clobbered_without_force_and_inputs_never() {
    let dir = tempfile::tempdir().expect("temp dir");
    let png = dir.path().join("chart.png");
    let render = |extra: &[&str]| {
        let mut args = vec![
            "render",
            "--scene",
            "chart",
            "--size",
            "32x18",
            "--out",
            utf8(&png),
        ];
        args.extend_from_slice(extra);
        common::aa_lab(&args)
    };
    let first = render(&[]);
    assert!(first.status.success(), "{}", stderr(&first));
    assert!(stdout(&first).contains("wrote"), "{}", stdout(&first));
    let before = std::fs::read(&png).expect("png");
    let again = render(&[]);
    assert!(!again.status.success());
    assert!(stderr(&again).contains("--force"), "{}", stderr(&again));
    assert_eq!(std::fs::read(&png).expect("png"), before);
    let forced = render(&["--force"]);
    assert!(forced.status.success(), "{}", stderr(&forced));
    assert!(stdout(&forced).contains("replaced"), "{}", stdout(&forced));
    // The reference of a comparison is never its heatmap, --force or not.
    for force in [false, true] {
        let mut args = vec!["compare", utf8(&png), utf8(&png), "--heatmap", utf8(&png)];
        if force {
            args.push("--force");
        }
        refused(&args, &["input"]);
        assert_eq!(std::fs::read(&png).expect("png"), before);
    }
    // Nor the record a render reproduces.
    refused(
        &[
            "render",
            "--from",
            utf8(&png),
            "--out",
            utf8(&png),
            "--force",
        ],
        &["input"],
    );
    // bench refuses to replace an earlier report before measuring anything.
    let report = dir.path().join("report");
    std::fs::create_dir_all(&report).expect("dir");
    std::fs::write(report.join("report.md"), "earlier").expect("report");
    refused(
        &["bench", "--out", utf8(&report), "--frames", "1"],
        &["report.md", "--force"],
    );
    assert_eq!(
        std::fs::read_to_string(report.join("report.md")).expect("report"),
        "earlier"
    );
    let leftovers: Vec<_> = std::fs::read_dir(dir.path())
        .expect("dir")
        .filter_map(Result::ok)
        .filter(|e| e.file_name().to_string_lossy().contains("aa-lab-tmp"))
        .collect();
    assert!(leftovers.is_empty(), "{leftovers:?}");
}

/// Item 6: counts that used to wrap are refused; a technique listed twice renders once; a
/// region outside the image is an error, not an empty cell.
#[test]
fn wrapping_counts_duplicates_and_empty_regions_are_caught() {
    let dir = tempfile::tempdir().expect("temp dir");
    let out = dir.path().join("bench");
    for args in [
        ["--warmup", "4294967295", "--frames", "1"],
        ["--warmup", "1", "--frames", "4294967295"],
    ] {
        let mut argv = vec!["bench", "--out", utf8(&out)];
        argv.extend_from_slice(&args);
        refused(&argv, &["100000"]);
    }
    let render = succeeds(&[
        "render",
        "--scene",
        "chart",
        "--size",
        "32x18",
        "--technique",
        "none,fxaa,none",
        "--out",
        utf8(dir.path()),
    ]);
    let wrote = stdout(&render);
    assert_eq!(wrote.matches("wrote").count(), 2, "{wrote}");
    assert_eq!(wrote.matches("chart-none.png").count(), 1, "{wrote}");
    let sheet = dir.path().join("sheet.png");
    refused(
        &sheet_args("far=500,500,10,10", &sheet, &[]),
        &["far=500,500,10,10", "outside", "64x36"],
    );
}

/// Item 7: `--size -5x5` says what --size expects, and an OS error is printed once.
#[test]
fn messages_say_what_is_expected_and_print_os_errors_once() {
    let dir = tempfile::tempdir().expect("temp dir");
    let text = refused(
        &["render", "--scene", "chart", "--size", "-5x5"],
        &["WIDTHxHEIGHT", "-5"],
    );
    assert!(!text.contains("unexpected argument"), "{text}");
    let file = dir.path().join("plain");
    std::fs::write(&file, "x").expect("file");
    let below_a_file = file.join("model.obj");
    let text = refused(
        &[
            "render",
            "--scene",
            utf8(&below_a_file),
            "--out",
            utf8(&dir.path().join("x.png")),
        ],
        &["model.obj", "os error"],
    );
    assert_eq!(text.matches("os error").count(), 1, "{text}");
}

/// Issue 29, item 2: a render record with a misspelt field, an unknown top-level field, a
/// value of the wrong type or a number no `f32` holds is refused with the field's path,
/// instead of rendering the default camera with exit 0.
#[test]
fn render_records_refuse_unknown_fields_and_wrong_types_by_path() {
    let dir = tempfile::tempdir().expect("temp dir");
    let out = dir.path().join("x.png");
    let record = |name: &str, camera: &str, extra: &str| {
        let path = dir.path().join(name);
        std::fs::write(
            &path,
            format!(
                r#"{{"scene": "chart", "width": 64, "height": 36, "frame": 0,
                    "camera": {camera}, {extra}
                    "techniques": [{{"id": "none"}}]}}"#
            ),
        )
        .expect("record");
        path
    };
    let misspelt = record(
        "misspelt.json",
        r#"{"yaw": 1e39, "pitch": "x"}"#,
        r#""colour": "red","#,
    );
    let text = refused(
        &["render", "--from", utf8(&misspelt), "--out", utf8(&out)],
        &["misspelt.json", "camera.yaw", "camera.pitch", "colour"],
    );
    assert!(text.contains("unknown field"), "{text}");
    let wrong_type = record("wrong-type.json", r#"{"pitch_degrees": "x"}"#, "");
    refused(
        &["render", "--from", utf8(&wrong_type), "--out", utf8(&out)],
        &["wrong-type.json", "camera.pitch_degrees", "invalid type"],
    );
    let too_large = record("too-large.json", r#"{"yaw_degrees": 1e39}"#, "");
    refused(
        &["render", "--from", utf8(&too_large), "--out", utf8(&out)],
        &["too-large.json", "camera.yaw_degrees", "finite"],
    );
    assert!(!out.exists(), "a refused record wrote {}", out.display());
    // Fields left out still take their defaults.
    let partial = record("partial.json", r#"{"yaw_degrees": 30}"#, "");
    succeeds(&["render", "--from", utf8(&partial), "--out", utf8(&out)]);
    assert!(out.exists());
}
