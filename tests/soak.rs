//! Issue 29, item 5: a soak of the features a viewer session uses. The real [`AaLabApp`],
//! driven headless as in `tests/ui.rs` on the small `chart` scene in a small window, goes
//! through the same cycle again and again: every layout (wipe, 2x2 grid, A/B flip, single), an
//! orbit of the camera there and back and a step of the clock, a blind comparison with two
//! answers, a user WGSL technique added from a file and removed again, a short clip recorded,
//! played and left for the live view, and a paint of the window. After a warm-up, two windows
//! of cycles are measured as `tests/long_runs.rs` measures (`common/flat.rs`): no count of
//! live GPU objects or GPU memory of the engine's device or of the window's grows in both
//! windows (the window's paint keeps high-water marks that may be reached late: egui's vertex
//! buffer grew once, in one window, in one of four runs), and the resident size grows by no
//! more than a few kB per engine frame in the window that grew less. A test binary of its own, so that no other test's allocations show in this
//! process's resident size.
//!
//! The live view is only rendered when something changes: the chart's camera rig does not
//! orbit by itself (`orbit_degrees_per_frame` is 0), and none of the default techniques is
//! temporal, so auto-rotation or a step of the clock alone renders nothing there; the cycle
//! moves the camera by dragging.

#[path = "common/flat.rs"]
mod flat;
#[path = "common/viewer.rs"]
mod viewer;

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use aa_lab::app::{AaLabApp, DisplayPath, Layout};
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use viewer::{
    add_user_technique_instead_of_fxaa, blind_answers, drag, pan_clip_with_reference, settled,
    viewer_in, wait,
};

/// A small window: the view between the panels is a few hundred pixels wide.
const SOAK_WINDOW: egui::Vec2 = egui::vec2(960.0, 640.0);
/// Cycles before the first measurement (pipelines, pools, caches and the clip fill up).
const WARM_UP_CYCLES: usize = 3;
/// Cycles of each of the two measured windows.
const WINDOW_CYCLES: usize = 6;
/// Frames of the clip recorded in each cycle (after one of warm-up).
const CLIP_FRAMES: usize = 3;
/// Growth allowed per engine frame; see `docs/viewer.md` for the measured noise.
const ALLOWED_KB_PER_FRAME: f64 = 64.0;

/// A user technique: a pass-through of the scene render.
const USER_TECHNIQUE: &str = "fn aa_main(pixel: vec2<u32>, uv: vec2<f32>) -> vec4<f32> {\n\
                              \x20   return aa_load(vec2<i32>(pixel));\n}\n";

/// The state of the process between cycles.
struct Measure {
    resident_kb: u64,
    engine_frames: u64,
    window_objects: Vec<(&'static str, isize)>,
    engine_objects: Vec<(&'static str, isize)>,
}

impl Measure {
    fn take(harness: &Harness<'_, AaLabApp>) -> Self {
        let (window, engine) = harness.state().gpu_devices();
        let engine = engine.expect("the render thread has opened its device");
        Self {
            resident_kb: flat::resident_kb(),
            engine_frames: harness.state().engine_frames(),
            window_objects: flat::gpu_objects(&window),
            engine_objects: flat::gpu_objects(&engine),
        }
    }
}

#[test]
#[cfg(target_os = "linux")]
fn a_session_of_layouts_blind_trials_user_techniques_and_clips_stays_flat() {
    let started = Instant::now();
    let dir = tempfile::tempdir().expect("temp dir");
    let technique_file = dir.path().join("soak.wgsl");
    std::fs::write(&technique_file, USER_TECHNIQUE).expect("write the technique");
    let mut harness = viewer_in(SOAK_WINDOW, "chart", Duration::ZERO, DisplayPath::Auto);
    harness.state_mut().set_export_dir(dir.path().to_path_buf());
    pan_clip_with_reference(&mut harness, CLIP_FRAMES as u32, 1);
    let mut cycles = 0;
    let mut run = |harness: &mut Harness<'_, AaLabApp>, count: usize| {
        for _ in 0..count {
            cycle(harness, &technique_file, cycles);
            cycles += 1;
        }
        Measure::take(harness)
    };
    let warm = run(&mut harness, WARM_UP_CYCLES);
    let middle = run(&mut harness, WINDOW_CYCLES);
    let end = run(&mut harness, WINDOW_CYCLES);
    let frames = [
        middle.engine_frames - warm.engine_frames,
        end.engine_frames - middle.engine_frames,
    ];
    let per_frame = flat::growth_per_frame(
        [warm.resident_kb, middle.resident_kb, end.resident_kb],
        frames,
    );
    let report = format!(
        "{cycles} cycles, {} engine frames in {:.0?}; measured windows of {frames:?} engine \
         frames: {} -> {} -> {} kB ({per_frame:.1} kB/frame)",
        end.engine_frames,
        started.elapsed(),
        warm.resident_kb,
        middle.resident_kb,
        end.resident_kb,
    );
    println!("{report}");
    assert!(
        warm.engine_objects.iter().any(|(_, n)| *n > 0),
        "wgpu counts no GPU objects: the `counters` feature is off"
    );
    for (device, objects) in [
        (
            "engine",
            [&warm, &middle, &end].map(|m| m.engine_objects.as_slice()),
        ),
        (
            "window",
            [&warm, &middle, &end].map(|m| m.window_objects.as_slice()),
        ),
    ] {
        let grown = flat::grown_in_both_windows(objects);
        assert!(
            grown.is_empty(),
            "live GPU objects of the {device}'s device grew in both windows of \
             {WINDOW_CYCLES} cycles: {grown:?} ({report})"
        );
    }
    assert!(
        per_frame <= ALLOWED_KB_PER_FRAME,
        "the session grows by {per_frame:.0} kB per engine frame (allowed \
         {ALLOWED_KB_PER_FRAME}): {report}"
    );
}

/// One cycle of the session (`index` counts them); it ends where it started: single layout,
/// the default techniques compared, the live view settled.
fn cycle(harness: &mut Harness<'_, AaLabApp>, technique_file: &Path, index: usize) {
    for (key, layout) in [
        (egui::Key::W, Layout::Wipe),
        (egui::Key::G, Layout::Grid),
        (egui::Key::F, Layout::Flip),
        (egui::Key::S, Layout::Single),
    ] {
        harness.key_press(key);
        harness.step();
        assert_eq!(harness.state().settings().layout, layout);
        wait(harness, "a frame of the layout", AaLabApp::frame_ready);
    }
    orbit_there_and_back(harness);
    blind_trials(harness, index);
    user_technique_added_and_removed(harness, technique_file);
    clip_recorded_and_played(harness);
    wait(harness, "the settled live view", settled);
    harness.render().expect("the window paints");
}

/// Orbits the camera by dragging in the view (away from the lens, which a drag would move)
/// and back, then steps the clock.
fn orbit_there_and_back(harness: &mut Harness<'_, AaLabApp>) {
    let image = harness.state().image_rect().expect("an image is drawn");
    let start = image.min + egui::vec2(30.0, 40.0);
    let aside = start + egui::vec2(24.0, 8.0);
    for (from, to) in [(start, aside), (aside, start)] {
        let before = harness.state().engine_frames();
        drag(harness, from, to);
        wait(harness, "a frame of the moved camera", |app| {
            app.frame_ready() && app.engine_frames() > before
        });
    }
    harness.key_press(egui::Key::Period);
    harness.step();
    wait(harness, "a frame after the step", AaLabApp::frame_ready);
}

/// Starts a blind comparison from the View menu, answers two trials (pane 1, no preference)
/// and ends it.
fn blind_trials(harness: &mut Harness<'_, AaLabApp>, index: usize) {
    harness.get_by_label("View").click();
    // The menu opens in the next frame.
    harness.step();
    harness.step();
    harness.get_by_label("Blind comparison").click();
    harness.step();
    let file: PathBuf = harness
        .state()
        .blind_file()
        .unwrap_or_else(|| panic!("cycle {index}: no blind session"))
        .to_path_buf();
    wait(harness, "the blind panes", AaLabApp::frame_ready);
    for key in [egui::Key::Num1, egui::Key::Num0] {
        harness.key_press(key);
        harness.step();
    }
    let answers = blind_answers(harness, 2);
    assert_eq!(answers["summary"]["ties"], 1, "{}", file.display());
    harness.get_by_label("End session").click();
    // The panels come back in the frame after the click.
    harness.step();
    harness.step();
    assert!(harness.state().blind_file().is_none());
}

/// Adds the user technique in `file` in place of FXAA, waits for its frame, removes it and
/// switches FXAA back on.
fn user_technique_added_and_removed(harness: &mut Harness<'_, AaLabApp>, file: &Path) {
    let id = add_user_technique_instead_of_fxaa(harness, file);
    wait(harness, "the user technique's frame", |app| {
        app.frame_ready()
            && app.compared().contains(&id.as_str())
            && app.output_pixels(&id).is_some()
    });
    harness.state_mut().remove_user_technique(&id);
    harness.step();
    harness
        .get_by_role_and_label(egui::accesskit::Role::CheckBox, "FXAA")
        .click();
    harness.step();
    assert_eq!(
        harness.state().compared(),
        ["none", "fxaa", "smaa", "msaa4"],
        "the user technique is gone and FXAA back"
    );
    wait(harness, "FXAA's frame", AaLabApp::frame_ready);
}

/// Records a clip, lets it play for a few of its frames and goes back to the live view.
fn clip_recorded_and_played(harness: &mut Harness<'_, AaLabApp>) {
    harness.get_by_label("Record").click();
    harness.step();
    wait(harness, "the clip", |app| {
        app.clip_progress() == Some((CLIP_FRAMES, false))
    });
    for _ in 0..CLIP_FRAMES {
        let shown = harness.state().shown_clip_frame();
        wait(harness, "the next frame of the playing clip", |app| {
            std::thread::sleep(Duration::from_millis(10));
            app.shown_clip_frame() != shown
        });
    }
    // By id: the playing clip's rate warning can come before the button and move it.
    harness.get_by_label("Live").click_accesskit();
    harness.step();
    assert_eq!(harness.state().shown_clip_frame(), None);
    wait(
        harness,
        "a live frame after the clip",
        AaLabApp::frame_ready,
    );
}
