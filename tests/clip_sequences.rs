//! `aa-lab clip` with captured image sequences as panes (`--sequence`, `--reference-sequence`,
//! `--offset`), on small sequences each test writes into a temporary folder (PNG and OpenEXR):
//! the figures of every pane match `aa-lab compare` on the same pair of sequences, the record
//! states the sequences, and sizes or lengths that do not fit are clear errors. A clip of
//! sequences alone renders nothing, so only the test that mixes in a rendered technique needs
//! an adapter.

mod common;

use std::path::{Path, PathBuf};

use common::{fails_with, stderr};

const WIDTH: u32 = 32;
const HEIGHT: u32 = 24;
/// Frames of the reference sequence, and so of the clips.
const FRAMES: u32 = 8;

/// Frame `t` of the moving bar at the sequences' size.
fn bar_frame(t: u32, blur: u32) -> image::RgbaImage {
    common::bar_frame(t, (WIDTH, HEIGHT), blur)
}

/// Writes `frames` PNG frames numbered from `first` into `root/folder`, frame `i` showing the
/// bar at step `step(i)`.
fn png_sequence(
    root: &Path,
    folder: &str,
    first: u32,
    frames: u32,
    step: impl Fn(u32) -> u32,
    blur: u32,
) -> PathBuf {
    let dir = root.join(folder);
    std::fs::create_dir_all(&dir).expect("folder");
    for i in 0..frames {
        bar_frame(step(i), blur)
            .save(dir.join(format!("frame_{:04}.png", first + i)))
            .expect("frame written");
    }
    dir
}

/// Writes `frames` OpenEXR frames (linear light) of the bar, lagging one frame behind.
fn exr_sequence(root: &Path, folder: &str, frames: u32) -> PathBuf {
    let dir = root.join(folder);
    std::fs::create_dir_all(&dir).expect("folder");
    let linear = |v: u8| (f32::from(v) / 255.0).powf(2.2);
    for i in 0..frames {
        let srgb = bar_frame(i.saturating_sub(1), 0);
        let image = image::Rgba32FImage::from_fn(WIDTH, HEIGHT, |x, y| {
            let p = srgb.get_pixel(x, y).0;
            image::Rgba([linear(p[0]), linear(p[1]), linear(p[2]), 1.0])
        });
        image::DynamicImage::ImageRgba32F(image)
            .save(dir.join(format!("lag.{i:03}.exr")))
            .expect("EXR written");
    }
    dir
}

fn text(path: &Path) -> &str {
    path.to_str().expect("utf-8 path")
}

fn number(value: &serde_json::Value, key: &str) -> f64 {
    value[key]
        .as_f64()
        .unwrap_or_else(|| panic!("{key} in {value}"))
}

/// `aa-lab compare REFERENCE TEST --json --jod`'s summary.
fn compare_summary(reference: &str, test: &str) -> serde_json::Value {
    let out = common::aa_lab(&["compare", reference, test, "--json", "--jod"]);
    assert!(out.status.success(), "{}", stderr(&out));
    let output: serde_json::Value = serde_json::from_slice(&out.stdout).expect("JSON");
    assert_eq!(output["frames"], FRAMES);
    output["summary"].clone()
}

/// Checks that a clip pane's figures are the ones `compare` gave for the same frames.
fn assert_same_figures(pane: &serde_json::Value, summary: &serde_json::Value) {
    let quality = &pane["quality"];
    for key in ["ssim", "psnr", "mae", "flip", "worst_flip"] {
        let (clip, compare) = (number(quality, key), number(summary, key));
        assert!(
            (clip - compare).abs() <= 1e-9 * compare.abs().max(1.0),
            "{key}: clip {clip}, compare {compare}"
        );
    }
    assert_eq!(quality["worst_frame"], summary["worst_frame"]);
    assert_eq!(quality["per_frame"].as_array().map(Vec::len), Some(8));
    for key in ["mean_change", "temporal_instability", "ghosting"] {
        let (clip, compare) = (number(pane, key), number(summary, key));
        assert!((clip - compare).abs() <= 1e-9, "{key}: {clip} vs {compare}");
    }
    let (clip, compare) = (number(pane, "jod"), number(&summary["jod"], "jod"));
    assert!((clip - compare).abs() <= 1e-6, "JOD: {clip} vs {compare}");
}

#[test]
fn a_clip_of_two_captures_and_their_reference_reports_what_compare_does() {
    let dir = tempfile::tempdir().expect("temp dir");
    let root = dir.path();
    // The reference starts at frame number 10; the blurred capture has two lead-in frames
    // (numbers 0 and 1) that --offset skips; the lagging EXR capture has a frame too many.
    let reference = png_sequence(root, "ssaa", 10, FRAMES, |i| i, 0);
    let blurred = png_sequence(root, "taa", 0, FRAMES + 2, |i| i.saturating_sub(2), 1);
    let lagging = exr_sequence(root, "lag", FRAMES + 1);
    let out = root.join("clip.png");
    let run = common::aa_lab(&[
        "clip",
        "--sequence",
        &format!("blurred={}", text(&blurred)),
        "--sequence",
        &format!("lagging={}/lag.*.exr", text(&lagging)),
        "--reference-sequence",
        text(&reference),
        "--offset",
        "blurred=2",
        "--jod",
        "--out",
        text(&out),
    ]);
    assert!(run.status.success(), "{}", stderr(&run));
    let warning = stderr(&run);
    assert!(
        warning.contains("the clip has 8 frames")
            && warning.contains("the later frames of lagging"),
        "no warning of the frames left out: {warning}"
    );
    let table = common::stdout(&run);
    assert!(
        table.contains("SSIM") && table.contains("JOD (standard_fhd)"),
        "{table}"
    );

    let record: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(root.join("clip.json")).expect("the record beside"),
    )
    .expect("JSON");
    assert_eq!(record["frames"], FRAMES);
    assert!(
        record["spec"].is_null() && record["motion"].is_null(),
        "nothing was rendered: {record}"
    );
    let sequences = record["sequences"].as_array().expect("sequences");
    assert_eq!(sequences.len(), 2);
    assert_eq!(sequences[0]["label"], "blurred");
    assert_eq!(sequences[0]["offset"], 2);
    assert_eq!(sequences[0]["sequence_frames"], FRAMES + 2);
    assert_eq!(sequences[0]["first_number"], 2);
    assert_eq!(sequences[0]["last_number"], 9);
    assert!(
        Path::new(sequences[0]["path"].as_str().expect("a path")).is_absolute(),
        "paths are recorded absolute"
    );
    assert_eq!(sequences[1]["last_number"], 7);
    assert!(
        sequences[1]["last_file"]
            .as_str()
            .is_some_and(|f| f.ends_with("lag.007.exr"))
    );
    assert_eq!(record["reference"]["first_number"], 10);
    assert_eq!(record["reference"]["last_number"], 17);
    assert_eq!(record["jod"]["display"], "standard_fhd");

    let panes = record["techniques"].as_array().expect("panes");
    assert_eq!(panes.len(), 2);
    let blurred_frames = format!("{}/frame_000[2-9].png", text(&blurred));
    let lagging_frames = format!("{}/lag.00[0-7].exr", text(&lagging));
    assert_same_figures(
        &panes[0],
        &compare_summary(text(&reference), &blurred_frames),
    );
    assert_same_figures(
        &panes[1],
        &compare_summary(text(&reference), &lagging_frames),
    );
    // The lagging capture ghosts more than the blurred one.
    assert!(number(&panes[1], "ghosting") > number(&panes[0], "ghosting"));

    // The animation has one frame per clip frame.
    let bytes = std::fs::read(&out).expect("the animation");
    let chunks = aa_lab::export::png::png_chunks(&bytes).expect("a PNG");
    assert_eq!(
        chunks.iter().filter(|(kind, _)| kind == b"fcTL").count(),
        FRAMES as usize
    );
}

/// Writes two frames of a grey ramp in linear light whose right half is `highlight` (above
/// the display's white).
fn highlight_sequence(root: &Path, folder: &str, highlight: f32) -> PathBuf {
    let dir = root.join(folder);
    std::fs::create_dir_all(&dir).expect("folder");
    for i in 0..2 {
        let image = image::Rgba32FImage::from_fn(WIDTH, HEIGHT, |x, _| {
            let v = if x >= WIDTH / 2 {
                highlight
            } else {
                x as f32 / WIDTH as f32
            };
            image::Rgba([v, v, v, 1.0])
        });
        image::DynamicImage::ImageRgba32F(image)
            .save(dir.join(format!("hdr.{i:03}.exr")))
            .expect("EXR written");
    }
    dir
}

#[test]
fn compare_sees_highlights_of_openexr_captures_through_a_named_tonemapper() {
    let dir = tempfile::tempdir().expect("temp dir");
    let dim = highlight_sequence(dir.path(), "dim", 2.0);
    let bright = highlight_sequence(dir.path(), "bright", 8.0);
    let mae = |extra: &[&str]| {
        let mut args = vec!["compare", text(&dim), text(&bright), "--json"];
        args.extend_from_slice(extra);
        let out = common::aa_lab(&args);
        assert!(out.status.success(), "{}", stderr(&out));
        let json: serde_json::Value = serde_json::from_str(&common::stdout(&out)).expect("JSON");
        number(&json["summary"], "mae")
    };
    // Clamped, both highlights are white: the captures look the same.
    let clamped = mae(&[]);
    let tonemapped = mae(&["--tonemap", "aces"]);
    assert!(
        clamped == 0.0 && tonemapped > 0.001,
        "mean absolute error clamped {clamped}, through ACES {tonemapped}"
    );
    // Two OpenEXR images are scored by HDR-FLIP, which has its own exposures.
    let single = dir.path().join("one.exr");
    std::fs::copy(dim.join("hdr.000.exr"), &single).expect("copied");
    fails_with(
        &["compare", text(&single), text(&single), "--tonemap", "aces"],
        &["--tonemap applies to sequences of OpenEXR frames"],
    );
}

#[test]
fn sizes_and_lengths_that_do_not_fit_are_clear_errors() {
    let dir = tempfile::tempdir().expect("temp dir");
    let root = dir.path();
    let reference = png_sequence(root, "ssaa", 0, FRAMES, |i| i, 0);
    let short = png_sequence(root, "short", 0, FRAMES - 1, |i| i, 1);
    let wide = root.join("wide");
    std::fs::create_dir(&wide).expect("folder");
    for t in 0..FRAMES {
        image::RgbaImage::new(WIDTH + 8, HEIGHT)
            .save(wide.join(format!("w{t}.png")))
            .expect("frame");
    }
    let out = root.join("clip.png");
    let clip = |extra: &[&str]| {
        let mut args = vec![
            "clip",
            "--reference-sequence",
            text(&reference),
            "--out",
            text(&out),
        ];
        args.extend_from_slice(extra);
        args.into_iter().map(str::to_owned).collect::<Vec<_>>()
    };
    let run = |extra: &[&str], needles: &[&str]| {
        let args = clip(extra);
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        fails_with(&args, needles);
    };
    let wide_flag = format!("wide={}", text(&wide));
    run(
        &["--sequence", &wide_flag],
        &["the sequence wide", "is 40x24", "32x24"],
    );
    let short_flag = format!("short={}", text(&short));
    run(
        &["--sequence", &short_flag, "--frames", "8"],
        &["--frames 8", "short", "has only 7"],
    );
    run(
        &["--sequence", &short_flag, "--offset", "short=7"],
        &["--offset short=7", "has only 7 frames"],
    );
    run(
        &["--sequence", &short_flag, "--offset", "taa=1"],
        &["no sequence is labelled taa"],
    );
    run(
        &["--sequence", &short_flag, "--sequence", &short_flag],
        &["two sequences are labelled short"],
    );
    run(&["--sequence", "short"], &["expected LABEL=VALUE"]);
    assert!(!out.exists(), "nothing written on an error");

    // Without --frames the clip is as long as the shortest sequence, and says so.
    let ok = clip(&["--sequence", &short_flag]);
    let ok: Vec<&str> = ok.iter().map(String::as_str).collect();
    let done = common::aa_lab(&ok);
    assert!(done.status.success(), "{}", stderr(&done));
    assert!(
        stderr(&done).contains("the clip has 7 frames (the shortest sequence is short"),
        "{}",
        stderr(&done)
    );
    // An output inside a sequence's folder never replaces one of its frames.
    let frame = reference.join("frame_0003.png");
    let mut inside = clip(&["--sequence", &short_flag, "--force"]);
    let position = inside.iter().position(|a| a == "--out").expect("--out") + 1;
    inside[position] = text(&frame).to_owned();
    let inside: Vec<&str> = inside.iter().map(String::as_str).collect();
    fails_with(&inside, &["it is an input of this command"]);
}

#[test]
fn a_captured_pane_beside_the_rendered_technique_it_captured_scores_the_same() {
    let _gpu = common::gpu();
    let dir = tempfile::tempdir().expect("temp dir");
    let root = dir.path();
    let frames = root.join("frames");
    let first = common::clip(
        &root.join("first.png"),
        &["--frames-dir", text(&frames), "--motion", "pan"],
    );
    assert!(first.status.success(), "{}", stderr(&first));
    // The same clip again, with TAA's frames of the first as a captured pane beside TAA: the
    // capture lines up with the render frame for frame, so every figure agrees.
    let second = common::clip(
        &root.join("second.png"),
        &[
            "--motion",
            "pan",
            "--sequence",
            &format!("captured-taa={}", text(&frames.join("taa"))),
        ],
    );
    assert!(second.status.success(), "{}", stderr(&second));
    let record: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(root.join("second.json")).expect("record"))
            .expect("JSON");
    assert_eq!(record["reference"]["id"], "ssaa", "the rendered reference");
    assert_eq!(record["motion"], "pan");
    let panes = record["techniques"].as_array().expect("panes");
    assert_eq!(panes.len(), 5);
    let (rendered, captured) = (&panes[2], &panes[4]);
    assert_eq!(rendered["id"], "taa");
    assert_eq!(captured["id"], "captured-taa");
    for key in ["mean_change", "temporal_instability", "ghosting"] {
        assert_eq!(rendered[key], captured[key], "{key}");
    }
    assert_eq!(rendered["quality"], captured["quality"]);
    assert!(number(&captured["quality"], "ssim") < 1.0);
    // A size other than the render's is refused before anything renders.
    let third = root.join("third.png");
    let captured = format!("captured-taa={}", text(&frames.join("taa")));
    let wrong = fails_with(
        &[
            "clip",
            "--scene",
            "chart",
            "--size",
            "48x48",
            "--technique",
            "none",
            "--sequence",
            &captured,
            "--out",
            text(&third),
        ],
        &["is 64x48 but the clip's render (--size) is 48x48"],
    );
    assert!(!third.exists(), "{wrong}");
}

/// Issue 27: `clip --jod-heatmap DIR` writes every pane's ColorVideoVDP distortion map, with
/// its JOD (the record's) embedded; `--jod-ppd` replaces the display model's viewing distance,
/// is recorded, changes the figures and is what `compare --jod-ppd` gives for the same pair;
/// the flags need `--jod`, bad distances are refused, and no map is written over.
#[test]
fn clip_writes_jod_heatmaps_and_records_the_viewing_distance() {
    let dir = tempfile::tempdir().expect("temp dir");
    let root = dir.path();
    let reference = png_sequence(root, "ssaa", 0, FRAMES, |i| i, 0);
    let blurred = png_sequence(root, "taa", 0, FRAMES, |i| i, 1);
    let lagging = png_sequence(root, "lag", 0, FRAMES, |i| i.saturating_sub(1), 0);
    let maps = root.join("maps");
    let clip = |out: &str, extra: &[&str]| {
        let out = root.join(out);
        let (blurred, lagging) = (
            format!("blurred={}", text(&blurred)),
            format!("lagging={}", text(&lagging)),
        );
        let mut args = vec![
            "clip",
            "--sequence",
            &blurred,
            "--sequence",
            &lagging,
            "--reference-sequence",
            text(&reference),
            "--out",
            text(&out),
        ];
        args.extend_from_slice(extra);
        let run = common::aa_lab(&args);
        (run, out.with_extension("json"))
    };
    let (run, json) = clip(
        "near.png",
        &["--jod", "--jod-ppd", "20", "--jod-heatmap", text(&maps)],
    );
    assert!(run.status.success(), "{}", stderr(&run));
    let record: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(json).expect("record")).expect("JSON");
    assert_eq!(record["jod"]["pixels_per_degree"], 20.0);
    assert_eq!(record["jod"]["pixels_per_degree_given"], true);
    let panes = record["techniques"].as_array().expect("panes");
    for (pane, label) in panes.iter().zip(["blurred", "lagging"]) {
        let map = maps.join(format!("{label}-jod.png"));
        let embedded = aa_lab::export::png::read_record(&map)
            .expect("a PNG")
            .expect("its record");
        let embedded: serde_json::Value = serde_json::from_str(&embedded).expect("JSON");
        assert!(
            (number(&embedded["compare"], "jod") - number(pane, "jod")).abs() < 1e-9,
            "{embedded} vs {pane}"
        );
        assert_eq!(embedded["compare"]["setting"]["pixels_per_degree"], 20.0);
    }
    assert_eq!(std::fs::read_dir(&maps).expect("maps").count(), 2);
    // compare gives the same JOD at the same distance.
    let out = common::aa_lab(&[
        "compare",
        text(&reference),
        text(&lagging),
        "--json",
        "--jod",
        "--jod-ppd",
        "20",
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    let compared: serde_json::Value = serde_json::from_str(&common::stdout(&out)).expect("JSON");
    let jod = &compared["summary"]["jod"];
    assert_eq!(jod["pixels_per_degree"], 20.0);
    assert!((number(jod, "jod") - number(&panes[1], "jod")).abs() < 1e-6);

    // The model's own distance: recorded as such, and another figure.
    let (run, json) = clip("own.png", &["--jod"]);
    assert!(run.status.success(), "{}", stderr(&run));
    let own: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(json).expect("record")).expect("JSON");
    assert_eq!(own["jod"]["pixels_per_degree_given"], false);
    let model_ppd = number(&own["jod"], "pixels_per_degree");
    assert!(
        (30.0..45.0).contains(&model_ppd),
        "standard_fhd: {model_ppd}"
    );
    let own_lagging = number(&own["techniques"][1], "jod");
    assert!((own_lagging - number(&panes[1], "jod")).abs() > 1e-3);

    // The maps are never written over without --force; the flags need --jod; bad distances.
    let (run, _) = clip("again.png", &["--jod", "--jod-heatmap", text(&maps)]);
    assert!(!run.status.success());
    assert!(stderr(&run).contains("blurred-jod.png"), "{}", stderr(&run));
    assert!(
        !root.join("again.png").exists(),
        "refused before anything was written"
    );
    let (run, _) = clip("x.png", &["--jod-heatmap", text(&maps)]);
    assert!(!run.status.success() && stderr(&run).contains("--jod"));
    let (run, _) = clip("x.png", &["--jod", "--jod-ppd", "0"]);
    assert!(
        !run.status.success() && stderr(&run).contains("pixels per degree must be above 0"),
        "{}",
        stderr(&run)
    );
}
