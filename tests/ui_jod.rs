//! UI tests of ColorVideoVDP on image sequences in the viewer: the real [`AaLabApp`] driven
//! headless through egui_kittest (see `tests/ui_sequences.rs`), with two small generated
//! sequences and their reference (64x48 PNG frames of a square moving across a gradient; the
//! test sequences add flickering noise on their left part, one a little, one a lot). The
//! metrics panel's button scores them, the figures are the metrics library's, the worse one
//! scores lower, the "JOD distortion" heatmap computes maps that are hot where the sequences
//! differ, and the viewing distance setting reaches the scorer.

#[path = "common/viewer.rs"]
mod viewer;

use std::path::{Path, PathBuf};

use aa_lab::app::{AaLabApp, DiffMetric};
use aa_lab::metrics::jod::{DEFAULT_DISPLAY, JodDisplay, JodScorer};
use egui_kittest::kittest::Queryable;
use viewer::{viewer, wait};

/// Frame size of the generated sequences.
const SIZE: (u32, u32) = (64, 48);
/// Frames of each sequence.
const FRAMES: u32 = 8;
/// The test sequences differ from the reference left of this column.
const NOISY_COLUMNS: u32 = 24;

/// The reference's frame at `moment`: a square moving six pixels a frame across a gradient.
fn reference_frame(moment: u32) -> image::RgbaImage {
    let left = 2 + 6 * moment;
    image::RgbaImage::from_fn(SIZE.0, SIZE.1, |x, y| {
        if (left..left + 10).contains(&x) && (12..24).contains(&y) {
            image::Rgba([240, 210, 30, 255])
        } else {
            image::Rgba([(x * 3) as u8, (y * 4) as u8, 90, 255])
        }
    })
}

/// The reference's frame with noise of `amplitude` levels left of [`NOISY_COLUMNS`], other
/// in every frame.
fn noisy_frame(moment: u32, amplitude: i32) -> image::RgbaImage {
    let mut frame = reference_frame(moment);
    for (x, y, pixel) in frame.enumerate_pixels_mut() {
        if x >= NOISY_COLUMNS {
            continue;
        }
        let hash = x.wrapping_mul(73_856_093)
            ^ y.wrapping_mul(19_349_663)
            ^ moment.wrapping_mul(83_492_791);
        let delta = (hash % 1000) as i32 % (2 * amplitude + 1) - amplitude;
        for channel in &mut pixel.0[..3] {
            *channel = (i32::from(*channel) + delta).clamp(0, 255) as u8;
        }
    }
    frame
}

/// Writes `frames` as the sequence folder `name` of `dir`.
fn write_sequence(dir: &Path, name: &str, frames: &[image::RgbaImage]) -> PathBuf {
    let folder = dir.join(name);
    std::fs::create_dir_all(&folder).expect("a sequence folder");
    for (index, frame) in frames.iter().enumerate() {
        frame
            .save(folder.join(format!("frame_{index:04}.png")))
            .expect("a frame");
    }
    folder
}

/// The metrics library's JOD of `test` against `reference` at 30 fps on `display`.
fn library_jod(
    display: &JodDisplay,
    test: &[image::RgbaImage],
    reference: &[image::RgbaImage],
) -> f64 {
    JodScorer::for_display(display, false)
        .expect("a display")
        .score(test, reference, 30.0)
        .expect("scored")
}

/// Waits until both test sequences (panes 0 and 1) have a JOD and returns them.
fn wait_for_figures(harness: &mut egui_kittest::Harness<'_, AaLabApp>, what: &str) -> [f64; 2] {
    wait(harness, what, |app| {
        (0..2).all(|slot| app.jod(slot).is_some())
    });
    let app = harness.state();
    [0, 1].map(|slot| app.jod(slot).expect("scored").expect("a JOD"))
}

#[test]
fn sequences_score_against_their_reference_with_maps_and_a_viewing_distance() {
    let dir = tempfile::tempdir().expect("temp dir");
    let reference: Vec<_> = (0..FRAMES).map(reference_frame).collect();
    let slight: Vec<_> = (0..FRAMES).map(|m| noisy_frame(m, 6)).collect();
    let strong: Vec<_> = (0..FRAMES).map(|m| noisy_frame(m, 60)).collect();
    let paths = vec![
        write_sequence(dir.path(), "slight", &slight),
        write_sequence(dir.path(), "strong", &strong),
        write_sequence(dir.path(), "ref", &reference),
    ];
    let mut harness = viewer("chart");
    let ctx = harness.ctx.clone();
    harness.state_mut().open_sequences(&ctx, paths);
    wait(&mut harness, "the sequences", |app| {
        app.sequence_position().is_some()
    });
    assert_eq!(harness.state().image_names().expect("a set").1, 2);
    assert!(
        harness.state().jod(0).is_none(),
        "sequences are scored when asked"
    );

    // The button scores both against the reference, as the metrics library does.
    // By the button's id, not its position: figures arriving on the worker can move it
    // between the frame that placed it and the click.
    harness
        .get_by_label("Score with ColorVideoVDP")
        .click_accesskit();
    harness.step();
    let [slight_jod, strong_jod] = wait_for_figures(&mut harness, "the JOD of both");
    let standard = JodDisplay::named(DEFAULT_DISPLAY);
    assert!((slight_jod - library_jod(&standard, &slight, &reference)).abs() < 1e-3);
    assert!((strong_jod - library_jod(&standard, &strong, &reference)).abs() < 1e-3);
    assert!(
        strong_jod < slight_jod - 0.5,
        "the worse sequence scores lower: {strong_jod} vs {slight_jod}"
    );
    assert!(
        harness.state().jod_map("image-1").is_none(),
        "no map unless asked"
    );

    // The JOD distortion heatmap: the same worker scores again with the maps.
    let settings = harness.state_mut().settings_mut();
    settings.show_magnifier = true;
    settings.magnifier.difference = true;
    settings.magnifier.metric = DiffMetric::JodDistortion;
    harness.step();
    wait(&mut harness, "the distortion maps", |app| {
        ["image-1", "image-2"]
            .iter()
            .all(|id| matches!(app.jod_map(id), Some(Ok(_))))
    });
    let map = harness
        .state()
        .jod_map("image-2")
        .expect("a map")
        .expect("computed");
    assert_eq!((map.width, map.height), SIZE);
    let mean = |columns: std::ops::Range<u32>| {
        let values: Vec<f32> = (0..SIZE.1)
            .flat_map(|y| columns.clone().map(move |x| (x, y)))
            .map(|(x, y)| map.at(x, y))
            .collect();
        values.iter().sum::<f32>() / values.len() as f32
    };
    let (noisy, clean) = (mean(0..NOISY_COLUMNS - 4), mean(40..SIZE.0));
    assert!(
        noisy > 2.0 * clean && noisy > 0.05,
        "hot where the sequences differ: {noisy} left, {clean} right"
    );
    let reference_map = harness
        .state()
        .jod_map("image-3")
        .expect("the reference pane")
        .expect("a map");
    assert!(
        reference_map.data.iter().all(|v| *v == 0.0),
        "the reference has no distortion"
    );
    wait(&mut harness, "the magnifier's heatmaps", |app| {
        app.difference_means().is_some()
    });
    let means = harness.state().difference_means().expect("heatmaps");
    assert!(means.iter().all(|m| (0.0..=1.0).contains(m)), "{means:?}");

    // A viewing distance: the figures are scored again at its pixels per degree.
    harness.state_mut().settings_mut().jod_pixels_per_degree = Some(20.0);
    harness.step();
    wait(&mut harness, "the figures at 20 pixels per degree", |app| {
        app.jod(1)
            .and_then(Result::ok)
            .is_some_and(|jod| (jod - strong_jod).abs() > 1e-3)
    });
    let [_, near] = wait_for_figures(&mut harness, "both at 20 pixels per degree");
    let close_up = JodDisplay {
        name: DEFAULT_DISPLAY.to_owned(),
        pixels_per_degree: Some(20.0),
    };
    assert!((near - library_jod(&close_up, &strong, &reference)).abs() < 1e-3);
    let stored = serde_json::to_value(harness.state().settings()).expect("settings");
    assert_eq!(stored["jod_pixels_per_degree"], 20.0, "persisted");
}
