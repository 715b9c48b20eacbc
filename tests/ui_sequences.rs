//! UI tests of image sequences in the viewer: the real [`AaLabApp`] driven headless through
//! egui_kittest (see `tests/ui.rs`), with small generated sequences (64x48 PNG frames of a
//! square moving across a gradient) written into a temporary folder. They open sequences
//! through the path-taking function File > Open sequences calls and by dropping folders, step
//! and play them with the clip bar's buttons, and check that every pane shows the same instant
//! with the very pixels of its frame files, that offsets line captures up, and that sequences
//! that cannot play together are refused with a message naming the one at fault.

#[path = "common/viewer.rs"]
mod viewer;

use std::path::{Path, PathBuf};
use std::sync::Arc;

use aa_lab::app::AaLabApp;
use aa_lab::graph::hdr::TonemapChoice;
use aa_lab::scene::renderer::{Tonemap, Tonemapper};
use egui_kittest::kittest::Queryable;
use viewer::{drop_on_window, viewer, wait};

/// Frame size of the generated sequences.
const SIZE: (u32, u32) = (64, 48);

/// The frame a capture shows at moment `moment`: a square of `tint` that moves six pixels a
/// moment across a gradient.
fn frame(moment: u32, tint: [u8; 3], size: (u32, u32)) -> image::RgbaImage {
    let left = 2 + 6 * moment;
    image::RgbaImage::from_fn(size.0, size.1, |x, y| {
        if (left..left + 10).contains(&x) && (12..24).contains(&y) {
            image::Rgba([tint[0], tint[1], tint[2], 255])
        } else {
            image::Rgba([(x * 3) as u8, (y * 4) as u8, 90, 255])
        }
    })
}

/// Writes a sequence into folder `name` of `dir`: files `frame_0000.png`, ... showing the
/// moments `first_moment..first_moment + frames` (a capture that began `first_moment` frames
/// late has a negative one).
fn write_sequence(
    dir: &Path,
    name: &str,
    frames: u32,
    first_moment: i32,
    tint: [u8; 3],
) -> PathBuf {
    let folder = dir.join(name);
    std::fs::create_dir_all(&folder).expect("a sequence folder");
    for index in 0..frames {
        let moment = (first_moment + index as i32).max(0) as u32;
        frame(moment, tint, SIZE)
            .save(folder.join(format!("frame_{index:04}.png")))
            .expect("a frame");
    }
    folder
}

const TAA_TINT: [u8; 3] = [250, 200, 40];
const REFERENCE_TINT: [u8; 3] = [240, 210, 30];

fn last_notice(app: &AaLabApp) -> String {
    app.notices()
        .last()
        .map(|n| n.text.clone())
        .unwrap_or_default()
}

/// Waits until the sequence set shows instant `instant`.
fn wait_for_instant(harness: &mut egui_kittest::Harness<'_, AaLabApp>, instant: usize) {
    wait(harness, &format!("instant {instant}"), |app| {
        app.sequence_position().map(|(shown, _)| shown) == Some(instant)
    });
}

/// The pixels of `id` on screen.
fn shown(app: &AaLabApp, id: &str) -> Arc<image::RgbaImage> {
    app.output_pixels(id).expect("a frame on screen")
}

/// The temporal figures the viewer shows after playing `played` in a row are the metrics
/// library's over those frames, for test sequences of `tints` against the reference.
fn check_temporal_figures(app: &AaLabApp, played: std::ops::Range<u32>, tints: &[[u8; 3]]) {
    let mut library = aa_lab::metrics::stability::ClipMetrics::new(tints.len());
    for moment in played.clone() {
        let tests: Vec<_> = tints
            .iter()
            .map(|tint| frame(moment, *tint, SIZE))
            .collect();
        let tests: Vec<&image::RgbaImage> = tests.iter().collect();
        library
            .push(&frame(moment, REFERENCE_TINT, SIZE), &tests)
            .expect("comparable");
    }
    let (frames, scores) = app.sequence_temporal().expect("temporal figures");
    assert_eq!(frames, played.len());
    assert_eq!(scores, library.scores());
    for score in &scores {
        let instability = score.temporal_instability.expect("the reference moved");
        assert!(instability.is_finite() && instability > 0.0, "{scores:?}");
    }
}

/// Plays the open set of `frames` instants from instant `first` until it has shown `frames`
/// of them (wrapping round to the first after the last): every pane `(id, tint)` shows its
/// frame of the same instant, none is skipped, and `at_last` checks the viewer on the last
/// instant; then pauses.
fn play_in_lockstep(
    harness: &mut egui_kittest::Harness<'_, AaLabApp>,
    panes: &[(&str, [u8; 3])],
    first: usize,
    frames: usize,
    at_last: impl Fn(&AaLabApp),
) {
    harness.get_by_label("Play clip").click();
    let mut seen = vec![first];
    while seen.len() < frames {
        harness.step();
        std::thread::sleep(std::time::Duration::from_millis(5));
        let app = harness.state();
        let Some((instant, _)) = app.sequence_position() else {
            continue;
        };
        assert_eq!(
            app.sequence_frame_numbers(),
            vec![Some(instant as u64); panes.len()],
            "the panes play in lockstep"
        );
        for (id, tint) in panes {
            assert_eq!(*shown(app, id), frame(instant as u32, *tint, SIZE), "{id}");
        }
        if seen.last() != Some(&instant) {
            assert_eq!(
                instant,
                (seen.last().expect("a frame") + 1) % frames,
                "no frame is skipped"
            );
            seen.push(instant);
            if instant == frames - 1 {
                at_last(app);
            }
        }
    }
    harness.get_by_label("Pause clip").click();
    harness.step();
}

/// Two sequences opened as File > Open sequences opens them show their first frames in two
/// panes (the one named ref is the reference); +1 shows the next frame in both, labelled with
/// its frame number; the quality figures measure the frame on screen against the reference's
/// same frame; playing moves both panes together through every frame, and the temporal
/// figures of the frames played in a row are the metrics library's; folders dropped on the
/// window open as sequences too.
#[test]
fn two_sequences_play_in_lockstep() {
    const FRAMES: u32 = 6;
    let dir = tempfile::tempdir().expect("temp dir");
    let taa = write_sequence(dir.path(), "taa", FRAMES, 0, TAA_TINT);
    let reference = write_sequence(dir.path(), "ref", FRAMES, 0, REFERENCE_TINT);
    let mut harness = viewer("chart");
    let ctx = harness.ctx.clone();
    harness
        .state_mut()
        .open_sequences(&ctx, vec![taa.clone(), reference.clone()]);
    wait(&mut harness, "the sequences", AaLabApp::image_set_open);
    let app = harness.state();
    assert_eq!(app.compared(), ["image-1", "image-2"]);
    let (names, reference_index) = app.image_names().expect("a set");
    assert_eq!(names, ["taa", "ref"]);
    assert_eq!(
        reference_index, 1,
        "the sequence named ref is the reference"
    );
    assert_eq!(app.sequence_position(), Some((0, FRAMES as usize)));
    assert_eq!(app.render_size(), SIZE, "shown at the frames' size");
    assert_eq!(*shown(app, "image-1"), frame(0, TAA_TINT, SIZE));
    assert_eq!(*shown(app, "image-2"), frame(0, REFERENCE_TINT, SIZE));

    // One step: both panes show the next frame, and say which.
    harness.get_by_label("+1").click();
    harness.step();
    wait_for_instant(&mut harness, 1);
    let app = harness.state();
    assert_eq!(app.sequence_frame_numbers(), [Some(1), Some(1)]);
    assert_eq!(*shown(app, "image-1"), frame(1, TAA_TINT, SIZE));
    assert_eq!(*shown(app, "image-2"), frame(1, REFERENCE_TINT, SIZE));
    assert!(
        harness.query_all_by_label("taa · frame 1").next().is_some(),
        "the pane names the frame it shows"
    );

    // The figures of the frame on screen, against the reference's same frame.
    wait(&mut harness, "the figures of frame 1", |app| {
        app.quality_figures("image-1")
            .is_some_and(|f| f.flip.is_some())
    });
    let figures = harness.state().quality_figures("image-1").expect("figures");
    let library =
        aa_lab::metrics::compare(&frame(1, REFERENCE_TINT, SIZE), &frame(1, TAA_TINT, SIZE))
            .expect("comparable");
    assert!(
        (figures.pixels.ssim - library.ssim).abs() < 1e-3,
        "{figures:?} vs {library:?}"
    );
    assert!((figures.pixels.psnr - library.psnr).abs() < 0.01);
    assert!((figures.flip.expect("FLIP").0 - library.flip).abs() < 1e-9);

    // Playing: every frame of both, together, in order.
    play_in_lockstep(
        &mut harness,
        &[("image-1", TAA_TINT), ("image-2", REFERENCE_TINT)],
        1,
        FRAMES as usize,
        |app| check_temporal_figures(app, 1..FRAMES, &[TAA_TINT]),
    );

    // Folders dropped on the window open as sequences.
    harness.state_mut().close_images();
    wait(&mut harness, "the scene", AaLabApp::frame_ready);
    drop_on_window(&mut harness, [reference, taa]);
    wait(&mut harness, "the dropped sequences", |app| {
        app.sequence_position().is_some()
    });
    let (names, reference_index) = harness.state().image_names().expect("a set");
    assert_eq!(
        (names, reference_index),
        (vec!["ref".to_owned(), "taa".to_owned()], 0)
    );
}

/// A capture that began two frames early lines up with the reference once its offset is 2
/// (then every pixel matches and the figures are perfect); sequences of different sizes are
/// refused with a message naming the one that differs, and a frame of another size inside a
/// sequence stops playback with a message naming its file, while what was shown stays.
/// Writes two OpenEXR frames (linear light): `highlight` on the left half, 0.25 on the right.
fn write_exr_sequence(root: &Path, name: &str, highlight: f32) -> PathBuf {
    let dir = root.join(name);
    std::fs::create_dir_all(&dir).expect("folder");
    for number in 0..2 {
        let image = image::Rgba32FImage::from_fn(SIZE.0, SIZE.1, |x, _| {
            let v = if x < SIZE.0 / 2 { highlight } else { 0.25 };
            image::Rgba([v, v, v, 1.0])
        });
        image::DynamicImage::ImageRgba32F(image)
            .save(dir.join(format!("{name}.{number:03}.exr")))
            .expect("EXR written");
    }
    dir
}

#[test]
fn openexr_sequences_are_shown_through_the_tonemapper_of_the_view_menu() {
    let dir = tempfile::tempdir().expect("temp dir");
    let bright = write_exr_sequence(dir.path(), "bright", 4.0);
    let reference = write_exr_sequence(dir.path(), "ref", 8.0);
    let mut harness = viewer("chart");
    let ctx = harness.ctx.clone();
    harness
        .state_mut()
        .open_sequences(&ctx, vec![bright, reference]);
    wait(&mut harness, "the sequences", AaLabApp::image_set_open);
    let highlight = |app: &AaLabApp| shown(app, "image-1").get_pixel(0, 0).0[0];
    // auto: captures are clamped to the display's white.
    harness.step();
    assert_eq!(highlight(harness.state()), 255);
    harness.state_mut().settings_mut().tonemap = TonemapChoice::Aces;
    let aces = Tonemap {
        operator: Tonemapper::Aces,
        exposure: 0.0,
    };
    let expected = aa_lab::srgb::encode_byte(aces.apply(glam::Vec3::splat(4.0)).x);
    assert!(expected < 255);
    wait(&mut harness, "the frames through ACES", |app| {
        highlight(app) == expected
    });
    let right = shown(harness.state(), "image-1").get_pixel(SIZE.0 - 1, 0).0[0];
    assert_eq!(
        right,
        aa_lab::srgb::encode_byte(aces.apply(glam::Vec3::splat(0.25)).x)
    );
    // Back to auto: clamped again.
    harness.state_mut().settings_mut().tonemap = TonemapChoice::Auto;
    wait(&mut harness, "the clamped frames", |app| {
        highlight(app) == 255
    });
}

#[test]
fn offsets_align_captures_and_mismatched_sizes_are_refused() {
    let dir = tempfile::tempdir().expect("temp dir");
    let reference = write_sequence(dir.path(), "ref", 6, 0, REFERENCE_TINT);
    let early = write_sequence(dir.path(), "early", 8, -2, REFERENCE_TINT);
    let mut harness = viewer("chart");
    let ctx = harness.ctx.clone();
    harness
        .state_mut()
        .open_sequences(&ctx, vec![early.clone(), reference.clone()]);
    wait(&mut harness, "the sequences", |app| {
        app.sequence_position().is_some()
    });
    assert_eq!(harness.state().sequence_position(), Some((0, 6)));
    harness.get_by_label("+1").click();
    harness.step();
    wait_for_instant(&mut harness, 1);
    assert_ne!(
        shown(harness.state(), "image-1"),
        shown(harness.state(), "image-2"),
        "without an offset the early capture lags"
    );

    harness.state_mut().set_sequence_offset(0, 2);
    wait(&mut harness, "the frames of the offset", |app| {
        app.sequence_frame_numbers() == [Some(3), Some(1)] && app.sequence_position().is_some()
    });
    let app = harness.state();
    assert_eq!(app.sequence_position(), Some((1, 6)), "8 - 2 frames play");
    assert_eq!(shown(app, "image-1"), shown(app, "image-2"));
    wait(&mut harness, "the figures", |app| {
        app.quality_figures("image-1").is_some()
    });
    let figures = harness.state().quality_figures("image-1").expect("figures");
    assert_eq!(figures.pixels.ssim, 1.0);
    assert!(figures.pixels.psnr.is_infinite());

    // Sequences of another size: refused, naming it; the open ones stay.
    let small = dir.path().join("small");
    std::fs::create_dir_all(&small).expect("a folder");
    for index in 0..3 {
        frame(index, TAA_TINT, (32, 24))
            .save(small.join(format!("s{index}.png")))
            .expect("a frame");
    }
    harness
        .state_mut()
        .open_sequences(&ctx, vec![reference.clone(), small.clone()]);
    wait(&mut harness, "the refusal", |app| !app.images_loading());
    let notice = last_notice(harness.state());
    assert!(
        notice.contains("differ in size") && notice.contains("small") && notice.contains("32x24"),
        "{notice}"
    );
    assert_eq!(
        harness.state().image_names().expect("the set stays").0,
        ["early", "ref"]
    );

    // A frame of another size inside a sequence: playback stops on the frame before it.
    let broken = write_sequence(dir.path(), "broken", 4, 0, TAA_TINT);
    frame(2, TAA_TINT, (64, 40))
        .save(broken.join("frame_0002.png"))
        .expect("a frame");
    harness
        .state_mut()
        .open_sequences(&ctx, vec![broken, reference]);
    wait(&mut harness, "the broken sequence", |app| {
        app.image_names()
            .is_some_and(|(names, _)| names[0] == "broken")
            && app.sequence_position().is_some()
    });
    harness.get_by_label("Play clip").click();
    wait(&mut harness, "the error", |app| {
        last_notice(app).contains("frame_0002.png")
    });
    let app = harness.state();
    let notice = last_notice(app);
    assert!(
        notice.contains("64x40") && notice.contains("stopped"),
        "{notice}"
    );
    assert_eq!(app.sequence_position(), Some((1, 4)));
    assert_eq!(*shown(app, "image-1"), frame(1, TAA_TINT, SIZE));
    assert!(harness.query_by_label("Play clip").is_some(), "paused");
}

/// Four captures and a separate reference: the fifth folder is the reference (the one named
/// ref, here in the middle), not a pane; the four others are panes A to D, each measured
/// against the reference's frame of the same instant, with heatmaps, temporal figures and ColorVideoVDP's JOD; all five play in lockstep;
/// swapping A and B, choosing another reference and a blind session work on the four panes,
/// and six folders are refused with a message, leaving the set open.
#[test]
fn four_sequences_and_a_reference_play_as_four_panes() {
    const FRAMES: u32 = 5;
    let dir = tempfile::tempdir().expect("temp dir");
    let tints = [
        ("taa", TAA_TINT),
        ("fxaa", [200, 60, 60]),
        ("ref", REFERENCE_TINT),
        ("smaa", [60, 200, 90]),
        ("msaa", [90, 110, 230]),
    ];
    let paths: Vec<PathBuf> = tints
        .iter()
        .map(|(name, tint)| write_sequence(dir.path(), name, FRAMES, 0, *tint))
        .collect();
    let ids = ["image-1", "image-2", "image-3", "image-4", "image-5"];
    let panes = ["image-1", "image-2", "image-4", "image-5"];
    let mut harness = viewer("chart");
    let ctx = harness.ctx.clone();
    harness.state_mut().open_sequences(&ctx, paths.clone());
    wait(&mut harness, "the five sequences", |app| {
        app.sequence_position().is_some()
    });
    let app = harness.state();
    let (names, reference) = app.image_names().expect("a set");
    assert_eq!(names, ["taa", "fxaa", "ref", "smaa", "msaa"]);
    assert_eq!(reference, 2, "the sequence named ref is the reference");
    assert_eq!(app.compared(), panes, "four panes, the reference is none");
    assert!(
        harness
            .query_by_label("ref · frame 0 · reference")
            .is_some(),
        "the images panel lists the reference"
    );

    // Every pane's figures, against the reference's frame; the magnifier's heatmaps of the
    // four panes and of the reference (R, all black against itself).
    let settings = harness.state_mut().settings_mut();
    settings.layout = aa_lab::app::Layout::Grid;
    settings.show_magnifier = true;
    settings.magnifier.difference = true;
    // The lens on the square, where the captures differ from the reference.
    settings.magnifier.center = Some([7.0, 18.0]);
    harness.step();
    wait(&mut harness, "the figures of the four panes", |app| {
        panes
            .iter()
            .all(|id| app.quality_figures(id).is_some_and(|f| f.flip.is_some()))
    });
    for (index, (_, tint)) in tints.iter().enumerate().filter(|(i, _)| *i != 2) {
        let figures = harness
            .state()
            .quality_figures(ids[index])
            .expect("figures");
        let library =
            aa_lab::metrics::compare(&frame(0, REFERENCE_TINT, SIZE), &frame(0, *tint, SIZE))
                .expect("comparable");
        assert!(
            (figures.pixels.ssim - library.ssim).abs() < 1e-3,
            "{}: {figures:?} vs {library:?}",
            tints[index].0
        );
        assert!((figures.flip.expect("FLIP").0 - library.flip).abs() < 1e-9);
    }
    assert!(harness.state().quality_figures("image-3").is_none());
    wait(&mut harness, "the heatmaps", |app| {
        app.difference_means().is_some()
    });
    let means = harness.state().difference_means().expect("heatmaps");
    assert_eq!(means.len(), 4, "a heatmap per pane: {means:?}");
    assert!(
        means.iter().all(|m| *m > 0.0 && m.is_finite()),
        "each capture differs from the reference on the square: {means:?}"
    );
    harness.state_mut().settings_mut().magnifier.difference = false;

    // Playing: all five together, every frame in order; the temporal figures of the four.
    let all: Vec<(&str, [u8; 3])> = ids
        .iter()
        .copied()
        .zip(tints.map(|(_, tint)| tint))
        .collect();
    let tests = [0, 1, 3, 4].map(|index| tints[index].1);
    play_in_lockstep(&mut harness, &all, 0, FRAMES as usize, |app| {
        check_temporal_figures(app, 1..FRAMES, &tests);
    });

    // Swap A/B swaps the first two panes; another reference makes the ref folder a pane.
    harness.get_by_label("swap A/B").click();
    harness.step();
    let (names, reference) = harness.state().image_names().expect("a set");
    assert_eq!(
        (names, reference),
        (
            ["fxaa", "taa", "ref", "smaa", "msaa"]
                .map(str::to_owned)
                .to_vec(),
            2
        )
    );
    harness.state_mut().set_image_reference(0);
    harness.step();
    assert_eq!(
        harness.state().compared(),
        ["image-2", "image-3", "image-4", "image-5"]
    );
    harness.state_mut().set_image_reference(2);
    harness.step();
    assert_eq!(harness.state().compared(), panes);

    // Six folders: refused, the set stays.
    let mut six = paths.clone();
    six.push(write_sequence(dir.path(), "sixth", FRAMES, 0, TAA_TINT));
    harness.state_mut().open_sequences(&ctx, six);
    harness.step();
    let notice = last_notice(harness.state());
    assert!(
        notice.contains("6 sequences")
            && notice.contains("at most 4 sequences and a reference")
            && notice.contains("nothing was opened"),
        "{notice}"
    );
    assert!(!harness.state().images_loading());
    assert_eq!(
        harness
            .state()
            .image_names()
            .expect("the set stays")
            .0
            .len(),
        5
    );

    // ColorVideoVDP scores the four against the reference.
    // By the button's id, not its position: figures arriving on the worker can move it
    // between the frame that placed it and the click.
    harness
        .get_by_label("Score with ColorVideoVDP")
        .click_accesskit();
    harness.step();
    wait(&mut harness, "the JOD of the four", |app| {
        [0, 1, 3, 4].iter().all(|slot| app.jod(*slot).is_some())
    });
    let reference_frames: Vec<_> = (0..FRAMES)
        .map(|m| frame(m, REFERENCE_TINT, SIZE))
        .collect();
    let scorer = aa_lab::metrics::jod::JodScorer::for_display(
        &aa_lab::metrics::jod::JodDisplay::named(aa_lab::metrics::jod::DEFAULT_DISPLAY),
        false,
    )
    .expect("a display");
    // After the swap, image 1 is fxaa and image 2 taa.
    for (slot, tint) in [
        (0, tints[1].1),
        (1, TAA_TINT),
        (3, tints[3].1),
        (4, tints[4].1),
    ] {
        let test: Vec<_> = (0..FRAMES).map(|m| frame(m, tint, SIZE)).collect();
        let expected = scorer
            .score(&test, &reference_frames, 30.0)
            .expect("scored");
        let jod = harness.state().jod(slot).expect("scored").expect("a JOD");
        assert!(
            (jod - expected).abs() < 1e-3,
            "pane {slot}: {jod} vs {expected}"
        );
    }
    assert!(
        harness.state().jod(2).is_none(),
        "the reference is not scored"
    );

    // A blind session numbers and shuffles the four panes, never the reference.
    harness.state_mut().set_export_dir(dir.path().to_path_buf());
    harness.get_by_label("View").click();
    harness.step();
    harness.step();
    harness.get_by_label("Blind comparison").click();
    harness.step();
    let mut blind = harness.state().compared();
    blind.sort_unstable();
    assert_eq!(blind, panes);
    harness.key_press(egui::Key::Num1);
    harness.step();
    let answers = viewer::blind_answers(&mut harness, 1);
    assert_eq!(answers["techniques"].as_array().map(Vec::len), Some(4));
}
