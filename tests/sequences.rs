//! Image sequences (`aa_lab::sequence`) and `aa-lab compare` on two of them, on tiny
//! sequences each test writes into a temporary folder: 8 frames of 32x24 in which a white bar
//! moves two pixels right per frame over a vertical gradient.

mod common;

use std::path::{Path, PathBuf};

use aa_lab::scene::renderer::{Tonemap, Tonemapper};
use aa_lab::sequence::{Sequence, SequenceError};
use common::fails_with;

const FRAMES: u32 = 8;
const WIDTH: u32 = 32;
const HEIGHT: u32 = 24;

/// Frame `t` of the moving bar (hard edges), `width` pixels wide.
fn bar_frame(t: u32, width: u32) -> image::RgbaImage {
    common::bar_frame(t, (width, HEIGHT), 0)
}

/// Writes frames `numbers` of the bar as `folder/name_NNNN.png`, frame `t` showing the bar at
/// step `t - lag` (clamped at 0); returns the folder.
fn write_sequence(root: &Path, folder: &str, numbers: std::ops::Range<u32>, lag: u32) -> PathBuf {
    let dir = root.join(folder);
    std::fs::create_dir_all(&dir).expect("folder");
    for t in numbers {
        bar_frame(t.saturating_sub(lag), WIDTH)
            .save(dir.join(format!("frame_{t:04}.png")))
            .expect("frame written");
    }
    dir
}

/// Opens `path`, expecting an error with every needle in its message.
fn open_fails(path: &Path, needles: &[&str]) {
    let err = match Sequence::open(path) {
        Ok(s) => panic!("{} opened as {} frames", path.display(), s.len()),
        Err(err) => err.to_string(),
    };
    for needle in needles {
        assert!(err.contains(needle), "`{needle}` missing from: {err}");
    }
}

#[test]
fn opening_reads_no_frame_and_frames_are_decoded_once_under_the_cache_cap() {
    let dir = tempfile::tempdir().expect("temp dir");
    let folder = write_sequence(dir.path(), "a", 0..FRAMES, 0);
    // Files that are not frames sit beside them and are left out.
    std::fs::write(folder.join("capture.log"), "engine log").expect("log");
    let sequence = Sequence::open(&folder).expect("opens");
    assert_eq!(sequence.len(), FRAMES as usize);
    assert_eq!(sequence.size(), (WIDTH, HEIGHT));
    assert_eq!(sequence.decoded_frames(), 0, "opening decodes nothing");
    let third = sequence.frame(3).expect("frame 3");
    assert_eq!(*third, bar_frame(3, WIDTH));
    sequence.frame(3).expect("frame 3 again");
    assert_eq!(
        sequence.decoded_frames(),
        1,
        "the second read is a cache hit"
    );
    assert!(matches!(
        sequence.frame(FRAMES as usize),
        Err(SequenceError::OutOfRange { .. })
    ));
    // A cache of one frame evicts frame 0 when frame 1 is read.
    let one_frame = (WIDTH * HEIGHT * 4) as usize;
    let small = Sequence::open(&folder)
        .expect("opens")
        .with_cache_bytes(one_frame);
    for index in [0, 1, 0] {
        small.frame(index).expect("frame");
    }
    assert_eq!(small.decoded_frames(), 3);
}

#[test]
fn frames_play_in_numeric_order_from_a_glob() {
    let dir = tempfile::tempdir().expect("temp dir");
    // Unpadded numbers 8..=11: name order would put 10 and 11 before 8.
    for t in 8..12 {
        bar_frame(t - 8, WIDTH)
            .save(dir.path().join(format!("taa_{t}.png")))
            .expect("frame");
    }
    bar_frame(0, WIDTH)
        .save(dir.path().join("other_0001.png"))
        .expect("frame");
    let sequence = Sequence::open(&dir.path().join("taa_*.png")).expect("opens");
    assert_eq!(sequence.len(), 4);
    assert_eq!(sequence.number(0), Some(8));
    assert_eq!(sequence.number(3), Some(11));
    assert_eq!(*sequence.frame(2).expect("frame"), bar_frame(2, WIDTH));
    open_fails(
        &dir.path().join("sub*/taa_*.png"),
        &["wildcards may only be in the file name"],
    );
}

#[test]
fn openexr_frames_are_linear_clamped_and_srgb_encoded() {
    let dir = tempfile::tempdir().expect("temp dir");
    // Linear 0.5 encodes to sRGB 188; 4.0 (HDR) clamps to white; negative to black.
    let values = [0.5f32, 4.0, -1.0, 0.0];
    for number in 1..=3 {
        let image = image::Rgba32FImage::from_fn(WIDTH, HEIGHT, |x, _| {
            let v = values[(x % 4) as usize];
            image::Rgba([v, v, 0.5, 1.0])
        });
        image::DynamicImage::ImageRgba32F(image)
            .save(dir.path().join(format!("hdr.{number:03}.exr")))
            .expect("EXR written");
    }
    let sequence = Sequence::open(dir.path()).expect("opens");
    assert_eq!(sequence.len(), 3);
    let frame = sequence.frame(1).expect("decodes");
    let red = |x| frame.get_pixel(x, 0).0;
    assert_eq!(red(0), [188, 188, 188, 255]);
    assert_eq!(red(1), [255, 255, 188, 255]);
    assert_eq!(red(2), [0, 0, 188, 255]);
    // A PNG frame beside the EXR ones is another format: not one sequence.
    bar_frame(0, WIDTH)
        .save(dir.path().join("hdr.004.png"))
        .expect("frame");
    open_fails(dir.path(), &["do not belong to one sequence"]);
}

#[test]
fn openexr_frames_go_through_a_tonemapper_when_one_is_given() {
    let dir = tempfile::tempdir().expect("temp dir");
    let values = [0.5f32, 4.0, 1.0, 0.0];
    for number in 1..=2 {
        let image = image::Rgba32FImage::from_fn(WIDTH, HEIGHT, |x, _| {
            let v = values[(x % 4) as usize];
            image::Rgba([v, v, v, 1.0])
        });
        image::DynamicImage::ImageRgba32F(image)
            .save(dir.path().join(format!("hdr.{number:03}.exr")))
            .expect("EXR written");
    }
    let clamped = Sequence::open(dir.path()).expect("opens");
    assert_eq!(clamped.frame(0).expect("decodes").get_pixel(1, 0).0[0], 255);
    let reinhard = Tonemap {
        operator: Tonemapper::Reinhard,
        exposure: 0.0,
    };
    let sequence = clamped.with_tonemap(Some(reinhard));
    let frame = sequence.frame(0).expect("decodes");
    let shown = |x| frame.get_pixel(x, 0).0[0];
    // Reinhard: 0.5 -> 1/3, 4 -> 0.8, 1 -> 0.5 (linear), then sRGB-encoded.
    let encoded = |linear: f32| aa_lab::srgb::encode_byte(linear);
    assert_eq!(
        [shown(0), shown(1), shown(2), shown(3)],
        [encoded(1.0 / 3.0), encoded(0.8), encoded(0.5), 0]
    );
    // One stop more exposure doubles the radiance before the curve.
    let brighter = Sequence::open(dir.path())
        .expect("opens")
        .with_tonemap(Some(Tonemap {
            exposure: 1.0,
            ..reinhard
        }));
    assert_eq!(
        brighter.frame(0).expect("decodes").get_pixel(0, 0).0[0],
        encoded(0.5)
    );
    // Display-referred frames are not tonemapped.
    let png = write_sequence(dir.path(), "png", 0..2, 0);
    let plain = Sequence::open(&png).expect("opens");
    let mapped = Sequence::open(&png)
        .expect("opens")
        .with_tonemap(Some(reinhard));
    assert_eq!(
        *plain.frame(1).expect("decodes"),
        *mapped.frame(1).expect("decodes")
    );
}

#[test]
fn gaps_duplicates_strays_and_empty_folders_are_errors_naming_the_files() {
    let dir = tempfile::tempdir().expect("temp dir");
    let gap = write_sequence(dir.path(), "gap", 0..FRAMES, 0);
    std::fs::remove_file(gap.join("frame_0003.png")).expect("removed");
    std::fs::remove_file(gap.join("frame_0004.png")).expect("removed");
    open_fails(
        &gap,
        &[
            "frames 3 to 4 are missing",
            "frame_0002.png",
            "frame_0005.png",
        ],
    );
    std::fs::remove_file(gap.join("frame_0006.png")).expect("removed");
    bar_frame(0, WIDTH)
        .save(gap.join("frame_0003.png"))
        .expect("frame");
    open_fails(
        &gap,
        &["frame 4 is missing", "frame_0003.png is followed by"],
    );
    let twice = write_sequence(dir.path(), "twice", 0..FRAMES, 0);
    std::fs::copy(twice.join("frame_0003.png"), twice.join("frame_3.png")).expect("copy");
    open_fails(&twice, &["are both frame 3", "frame_3.png"]);
    let stray = write_sequence(dir.path(), "stray", 0..FRAMES, 0);
    std::fs::copy(stray.join("frame_0003.png"), stray.join("thumbnail.png")).expect("copy");
    open_fails(&stray, &["thumbnail.png has no frame number"]);
    std::fs::rename(stray.join("thumbnail.png"), stray.join("take2_0009.png")).expect("rename");
    open_fails(&stray, &["take2_0009.png", "do not belong to one sequence"]);
    let empty = dir.path().join("empty");
    std::fs::create_dir(&empty).expect("folder");
    open_fails(&empty, &["holds no frames"]);
}

#[test]
fn a_frame_of_another_size_or_that_does_not_decode_is_an_error_when_read() {
    let dir = tempfile::tempdir().expect("temp dir");
    let folder = write_sequence(dir.path(), "a", 0..FRAMES, 0);
    bar_frame(5, WIDTH + 2)
        .save(folder.join("frame_0005.png"))
        .expect("frame");
    std::fs::write(folder.join("frame_0006.png"), b"not a png").expect("garbage");
    let sequence = Sequence::open(&folder).expect("opening reads only the first frame");
    let err = sequence.frame(5).expect_err("another size").to_string();
    assert!(
        err.contains("frame_0005.png is 34x24") && err.contains("frame_0000.png is 32x24"),
        "{err}"
    );
    let err = sequence.frame(6).expect_err("garbage").to_string();
    assert!(
        err.contains("cannot decode") && err.contains("frame_0006.png"),
        "{err}"
    );
}

fn json(args: &[&str]) -> serde_json::Value {
    let out = common::aa_lab(args);
    assert!(out.status.success(), "{}", common::stderr(&out));
    serde_json::from_slice(&out.stdout).expect("JSON output")
}

fn number(value: &serde_json::Value, key: &str) -> f64 {
    value[key]
        .as_f64()
        .unwrap_or_else(|| panic!("{key} in {value}"))
}

#[test]
fn compare_scores_sequences_frame_by_frame_and_over_time() {
    let dir = tempfile::tempdir().expect("temp dir");
    let reference = write_sequence(dir.path(), "reference", 0..FRAMES, 0);
    let same = write_sequence(dir.path(), "same", 0..FRAMES, 0);
    let lagging = write_sequence(dir.path(), "lagging", 0..FRAMES, 1);
    let path = |p: &Path| p.to_str().expect("utf-8").to_owned();
    let identical = json(&["compare", &path(&reference), &path(&same), "--json"]);
    assert_eq!(identical["frames"], 8);
    assert_eq!(identical["per_frame"].as_array().map(Vec::len), Some(8));
    let summary = &identical["summary"];
    assert_eq!(number(summary, "ssim"), 1.0);
    assert_eq!(number(summary, "flip"), 0.0);
    assert!(summary["psnr"].is_null(), "identical: infinite PSNR");
    assert!((number(summary, "temporal_instability") - 1.0).abs() < 1e-9);
    assert_eq!(number(summary, "ghosting"), 0.0);

    let glob = format!("{}/frame_*.png", path(&lagging));
    let lag = json(&["compare", &path(&reference), &glob, "--json"]);
    let summary = &lag["summary"];
    assert!(number(summary, "ssim") < 0.99, "{summary}");
    assert!(number(summary, "ghosting") > 50.0, "{summary}");
    // The lagging sequence repeats its first frame: one step of change fewer than 7.
    let instability = number(summary, "temporal_instability");
    assert!((instability - 6.0 / 7.0).abs() < 1e-6, "{instability}");
    // Frame 0 is identical in both, the others are not.
    assert_eq!(number(&lag["per_frame"][0], "ssim"), 1.0);
    assert!(number(&lag["per_frame"][1], "ssim") < 1.0);

    let out = common::aa_lab(&["compare", &path(&reference), &path(&lagging)]);
    let text = common::stdout(&out);
    assert!(out.status.success(), "{}", common::stderr(&out));
    assert!(
        text.contains("8 frames of 32x24") && text.contains("temporal instability 0.857"),
        "{text}"
    );

    // ColorVideoVDP over the whole sequences: no visible difference for the same frames, a
    // visible one for the lagging sequence; JOD is for sequences only.
    let jod = |test: &Path| {
        let out = json(&["compare", &path(&reference), &path(test), "--json", "--jod"]);
        assert_eq!(out["summary"]["jod"]["display"], "standard_fhd");
        assert_eq!(out["summary"]["jod"]["fps"], 30.0);
        number(&out["summary"]["jod"], "jod")
    };
    assert!((jod(&same) - 10.0).abs() < 1e-3);
    assert!(jod(&lagging) < 9.5);
    // The model's per-pixel distortion map, as a heatmap with the JOD in its record.
    let heatmap = reference
        .parent()
        .expect("the temp dir")
        .join("jod-map.png");
    json(&[
        "compare",
        &path(&reference),
        &path(&lagging),
        "--json",
        "--jod",
        "--jod-heatmap",
        &path(&heatmap),
    ]);
    let record = aa_lab::export::png::read_record(&heatmap)
        .expect("a PNG")
        .expect("its record");
    let record: serde_json::Value = serde_json::from_str(&record).expect("JSON");
    assert!(
        (number(&record["compare"], "jod") - jod(&lagging)).abs() < 1e-3,
        "{record}"
    );
    let one = reference.join("frame_0000.png");
    let out = common::aa_lab(&[
        "compare",
        one.to_str().unwrap(),
        one.to_str().unwrap(),
        "--jod",
    ]);
    assert!(!out.status.success());
    assert!(common::stderr(&out).contains("--jod scores two sequences"));
}

#[test]
fn compare_refuses_sequences_that_differ_and_never_overwrites() {
    let dir = tempfile::tempdir().expect("temp dir");
    let reference = write_sequence(dir.path(), "reference", 0..FRAMES, 0);
    let short = write_sequence(dir.path(), "short", 0..FRAMES - 1, 0);
    let path = |p: &Path| p.to_str().expect("utf-8").to_owned();
    fails_with(
        &["compare", &path(&reference), &path(&short)],
        &[
            "frame counts differ",
            "has 8 frames of 32x24",
            "has 7 frames",
        ],
    );
    let wide = dir.path().join("wide");
    std::fs::create_dir(&wide).expect("folder");
    for t in 0..FRAMES {
        bar_frame(t, WIDTH + 8)
            .save(wide.join(format!("w{t}.png")))
            .expect("frame");
    }
    fails_with(
        &["compare", &path(&reference), &path(&wide)],
        &["frame sizes differ", "40x24"],
    );
    let image = reference.join("frame_0000.png");
    fails_with(
        &["compare", &path(&image), &path(&reference)],
        &[
            "the test is a sequence",
            "compare two images or two sequences",
        ],
    );
    let heatmap = dir.path().join("flip.png");
    std::fs::write(&heatmap, "keep me").expect("existing file");
    let args = [
        "compare",
        &path(&reference),
        &path(&reference),
        "--heatmap",
        &path(&heatmap),
    ];
    fails_with(&args, &["exists", "--force"]);
    assert_eq!(std::fs::read(&heatmap).expect("kept"), b"keep me");
    let frame = reference.join("frame_0002.png");
    fails_with(
        &[
            "compare",
            &path(&reference),
            &path(&reference),
            "--heatmap",
            &path(&frame),
            "--force",
        ],
        &["it is an input of this command"],
    );
    let mut forced = args.to_vec();
    forced.push("--force");
    let out = common::aa_lab(&forced);
    assert!(out.status.success(), "{}", common::stderr(&out));
    let map = image::open(&heatmap).expect("a heatmap PNG");
    assert!(map.width() >= WIDTH);
}
