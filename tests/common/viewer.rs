//! The viewer under test: the real [`AaLabApp`] launched headless through egui_kittest on the
//! wgpu renderer (software Vulkan when there is no GPU), and the steps tests take with it (wait
//! for a state, click, drag, add a user technique, read a blind session's answers). Every wait
//! also checks that the controls on screen keep their ids from one frame to the next
//! ([`wait`]). Shared by the UI tests (`tests/ui*.rs`) and the soak (`tests/soak.rs`), each
//! including it with `#[path]`.

#![allow(dead_code)]

use std::collections::{HashMap, HashSet};
use std::time::{Duration, Instant};

use aa_lab::app::{AaLabApp, ClipPath, DisplayPath, LaunchOptions};
use aa_lab::scene::motion::Motion;
use egui::{Event, Modifiers, PointerButton, Pos2};
use egui_kittest::Harness;
use egui_kittest::kittest::{NodeT, Queryable};

/// Window size: side panels and magnifier leave a viewport of a few hundred pixels.
pub const WINDOW: egui::Vec2 = egui::vec2(1180.0, 760.0);
/// The longest any wait may take (software rendering of a few small frames).
pub const TIMEOUT: Duration = Duration::from_secs(180);

/// The viewer on `scene` with default settings, paused (frames stay put), after its first
/// complete frame.
pub fn viewer(scene: &str) -> Harness<'static, AaLabApp> {
    viewer_with(scene, Duration::ZERO, DisplayPath::Auto)
}

/// [`viewer`] with an engine whose every frame takes at least `frame_delay` and images that
/// reach the screen by `display`; when the delay is not
/// zero, the quality figures and the lens are off (the reference would keep a slow engine busy
/// for many frames).
pub fn viewer_with(
    scene: &str,
    frame_delay: Duration,
    display: DisplayPath,
) -> Harness<'static, AaLabApp> {
    viewer_in(WINDOW, scene, frame_delay, display)
}

/// [`viewer_with`] in a window of `window` points.
pub fn viewer_in(
    window: egui::Vec2,
    scene: &str,
    frame_delay: Duration,
    display: DisplayPath,
) -> Harness<'static, AaLabApp> {
    let mut harness = launch_in(window, scene, frame_delay, display);
    harness.state_mut().camera_mut().playing = false;
    if !frame_delay.is_zero() {
        let settings = harness.state_mut().settings_mut();
        settings.quality = false;
        settings.show_magnifier = false;
    }
    wait(&mut harness, "the first frame", AaLabApp::frame_ready);
    harness
}

/// The viewer on `scene` with fresh settings in a window of `window` points, before its first
/// UI frame (the scene loads in the background).
pub fn launch_in(
    window: egui::Vec2,
    scene: &str,
    frame_delay: Duration,
    display: DisplayPath,
) -> Harness<'static, AaLabApp> {
    launch_stepped(
        window,
        scene,
        frame_delay,
        display,
        Harness::<AaLabApp>::builder(),
    )
}

/// [`launch_in`] with the harness's own settings from `builder` (its time step, say).
pub fn launch_stepped(
    window: egui::Vec2,
    scene: &str,
    frame_delay: Duration,
    display: DisplayPath,
    builder: egui_kittest::HarnessBuilder<AaLabApp>,
) -> Harness<'static, AaLabApp> {
    let scene = scene.to_owned();
    builder
        .with_size(window)
        .wgpu_setup(aa_lab::app::wgpu_setup())
        .build_eframe(move |cc| {
            AaLabApp::new(
                cc,
                LaunchOptions {
                    scene: Some(scene),
                    fresh_settings: true,
                    engine_frame_delay: frame_delay,
                    display,
                    ..Default::default()
                },
            )
            .expect("the viewer starts")
        })
}

/// Sets the clip bar to record `frames` frames after `warmup` of a pan, two pixels a frame,
/// with the 16-sample reference (the temporal figures need it).
pub fn pan_clip_with_reference(harness: &mut Harness<'_, AaLabApp>, frames: u32, warmup: u32) {
    let clip = &mut harness.state_mut().settings_mut().clip;
    clip.frames = frames;
    clip.warmup = warmup;
    clip.path = ClipPath::Motion(Motion::Pan);
    clip.speed_px = 2.0;
    clip.reference = true;
    clip.reference_samples = 16;
}

/// A control as one frame shows it: its accesskit id, place and parent's id.
struct ShownControl {
    id: String,
    rect: egui::Rect,
    parent: String,
}

/// The controls of the frame (buttons, checkboxes, combo boxes, sliders, drag values) by
/// label, for the labels one control has. The frame-time plot's legend entries are left out:
/// egui_plot numbers them after the plot's axis labels, which follow the data.
fn controls(harness: &Harness<'_, AaLabApp>) -> HashMap<String, ShownControl> {
    let mut controls = HashMap::new();
    let mut repeated = HashSet::new();
    let control = |node: &egui_kittest::kittest::AccessKitNode<'_>| {
        use egui::accesskit::Role;
        let legend = ["frame (wall clock)", "GPU (all passes)"];
        match node.role() {
            Role::Button | Role::ComboBox | Role::Slider | Role::SpinButton => true,
            Role::CheckBox => node.label().is_none_or(|l| !legend.contains(&l.as_str())),
            _ => false,
        }
    };
    for node in harness.query_all_by(control) {
        let shown = ShownControl {
            id: format!("{:?}", node.accesskit_node().id()),
            rect: node.rect(),
            parent: format!("{:?}", node.parent().map(|p| p.accesskit_node().id())),
        };
        let Some(label) = node.accesskit_node().label() else {
            continue;
        };
        if controls.insert(label.clone(), shown).is_some() {
            repeated.insert(label);
        }
    }
    controls.retain(|label, _| !repeated.contains(label));
    controls
}

/// Steps the UI until `done` holds, and checks that no control changes its id meanwhile (the
/// same label in the same place or under the same parent with another id): the frames a wait
/// steps through have no input, and a widget whose id moves with what arrives before it (figures,
/// frames, progress) loses the clicks aimed at it.
pub fn wait(harness: &mut Harness<'_, AaLabApp>, what: &str, done: impl Fn(&AaLabApp) -> bool) {
    let start = Instant::now();
    let mut before = controls(harness);
    while !done(harness.state()) {
        assert!(
            start.elapsed() < TIMEOUT,
            "timed out after {TIMEOUT:?} waiting for {what}; notices: {:?}",
            harness
                .state()
                .notices()
                .iter()
                .map(|n| &n.text)
                .collect::<Vec<_>>()
        );
        harness.step();
        let now = controls(harness);
        for (label, shown) in &now {
            let Some(old) = before.get(label) else {
                continue;
            };
            assert!(
                old.id == shown.id || (old.rect != shown.rect && old.parent != shown.parent),
                "the control {label:?} changed its id ({} -> {}) in a frame without input, \
                 while waiting for {what}: a click aimed at it in one frame (by id, as accesskit \
                 sends it, or pressed in one frame and released in the next) would miss it; key \
                 it (`style::keyed`) or put what comes and goes before it in a scope of its own",
                old.id,
                shown.id
            );
        }
        before = now;
        std::thread::sleep(Duration::from_millis(5));
    }
    harness.step();
}

/// Switches FXAA off, so that a new technique is among the four compared (and read back), and
/// adds the user technique in `file`; returns its id.
pub fn add_user_technique_instead_of_fxaa(
    harness: &mut Harness<'_, AaLabApp>,
    file: &std::path::Path,
) -> String {
    harness
        .get_by_role_and_label(egui::accesskit::Role::CheckBox, "FXAA")
        .click();
    harness.step();
    harness.state_mut().add_user_technique(file.to_path_buf());
    format!(
        "user:{}",
        std::fs::canonicalize(file).expect("canonical").display()
    )
}

/// Clicks at `pos` with `modifiers` held (as the window reports them: in the input state, not
/// only on the click) and runs a frame.
pub fn click_with(harness: &mut Harness<'_, AaLabApp>, pos: Pos2, modifiers: Modifiers) {
    harness.event(Event::ModifiersChanged(modifiers));
    harness.event(Event::PointerMoved(pos));
    for pressed in [true, false] {
        harness.event(Event::PointerButton {
            pos,
            button: PointerButton::Primary,
            pressed,
            modifiers,
        });
    }
    harness.step();
    harness.event(Event::ModifiersChanged(Modifiers::NONE));
}

pub fn drag(harness: &mut Harness<'_, AaLabApp>, from: Pos2, to: Pos2) {
    harness.event(Event::PointerMoved(from));
    harness.event(Event::PointerButton {
        pos: from,
        button: PointerButton::Primary,
        pressed: true,
        modifiers: Modifiers::NONE,
    });
    harness.step();
    for i in 1..=4 {
        harness.event(Event::PointerMoved(from + (to - from) * (i as f32 / 4.0)));
        harness.step();
    }
    harness.event(Event::PointerButton {
        pos: to,
        button: PointerButton::Primary,
        pressed: false,
        modifiers: Modifiers::NONE,
    });
    harness.step();
}

/// A file or folder dropped on the window.
#[derive(Debug)]
struct Dropped(std::path::PathBuf);

impl egui::DroppedFile for Dropped {
    fn path(&self) -> &std::path::Path {
        &self.0
    }

    fn bytes(&self) -> Result<Vec<u8>, String> {
        std::fs::read(&self.0).map_err(|e| e.to_string())
    }
}

/// Drops `paths` (files or folders) on the window together and runs a frame.
pub fn drop_on_window(
    harness: &mut Harness<'_, AaLabApp>,
    paths: impl IntoIterator<Item = std::path::PathBuf>,
) {
    for path in paths {
        harness
            .input_mut()
            .dropped_files
            .push(std::sync::Arc::new(Dropped(path)));
    }
    harness.step();
}

/// The answers file once it holds `trials` answers.
pub fn blind_answers(harness: &mut Harness<'_, AaLabApp>, trials: usize) -> serde_json::Value {
    let path = harness
        .state()
        .blind_file()
        .expect("a blind session")
        .to_path_buf();
    let start = Instant::now();
    loop {
        let file = std::fs::read(&path)
            .ok()
            .and_then(|bytes| serde_json::from_slice::<serde_json::Value>(&bytes).ok());
        if let Some(file) = file.filter(|f| f["trials"].as_array().map(Vec::len) == Some(trials)) {
            return file;
        }
        assert!(
            start.elapsed() < TIMEOUT,
            "{} never held {trials} answers",
            path.display()
        );
        harness.step();
        std::thread::sleep(Duration::from_millis(5));
    }
}

/// The reference has converged and every compared technique's figures (FLIP included) rest
/// on all of its samples.
pub fn settled(app: &AaLabApp) -> bool {
    let total = app.settings().reference_samples;
    app.frame_ready()
        && app.reference_samples_done() == total
        && app.compared().iter().all(|id| {
            app.quality_figures(id).is_some_and(|f| {
                f.reference_samples == total && f.flip.map(|(_, n)| n) == Some(total)
            })
        })
}
