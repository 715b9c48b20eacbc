//! Clips in the viewer: what to record (the motion, its length, the reference), the recorded
//! frames of every compared technique (their memory counted and capped), and playback: a loop
//! or ping-pong at real time (30 or 60 frames per second) or in slow motion, single steps and a
//! scrub bar. Every layout and the magnifier read the same frame ([`ClipPlayer::frame`]), so
//! all panes show the same instant.
//!
//! Playback never skips a frame: the position follows the clock, but one UI frame advances it
//! by at most one clip frame, so a paint that comes late (a UI frame longer than the clip's
//! period) shows the next frame rather than the one after it. The time it fell behind is kept,
//! up to [`MAX_LAG_FRAMES`], and the following paints catch up with the clock: when UI frames
//! jitter around the clip's period (as they do on a software rasteriser), a short paint makes
//! up for a long one and the clip keeps its rate. Skipped frames
//! would change what is being judged (a flicker between two frames can vanish when every other
//! frame is dropped); when the window paints more slowly than the clip's rate all along, the
//! clip plays every frame more slowly, and the clip bar says at what rate it is shown
//! ([`ClipPlayer::shown_fps`]).
//!
//! Recording runs on the render thread ([`super::render_thread::ClipJob`]): temporal
//! techniques render the warm-up frames first, so the clip shows them with a real history, and
//! the thread scores the clip ([`crate::metrics::stability`]) as the frames come in. Playback
//! draws textures uploaded once while recording, so it costs one blit per pane per UI frame and
//! no engine work: recorded clips play at display rate on a machine whose engine makes a few
//! frames per second.
//!
//! The clip itself is the engine's; the clip settings are part of the workspace's settings.
//! The workspace's clip commands (record, show, tick the player) are here, and the clip bar
//! ([`panel`], drawing [`clip_bar`]) is a stateless function of the [`Workspace`].

use std::collections::VecDeque;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use egui::RichText;

use super::engine::Published;
use super::style;
use super::workspace::{Level, Workspace};
use crate::metrics::stability::TemporalScores;
use crate::scene::CameraRig;
use crate::scene::camera::{FrameCamera, OrbitPose};
use crate::scene::motion::{DEFAULT_SPEED_PX, Motion};

/// Frames of a clip unless the user picks another length.
pub const DEFAULT_FRAMES: u32 = 48;
/// Longest clip.
pub const MAX_FRAMES: u32 = 600;
/// Playback rates from which the UI repaints continuously (below, once per clip frame).
const REPAINT_EVERY_FRAME_FPS: f64 = 30.0;
/// How far (in clip frames) playback may fall behind the clock and still catch up; beyond
/// that a stalled window drops the time (a long stall does not fast-forward afterwards).
const MAX_LAG_FRAMES: f64 = 2.0;
/// The window over which the shown rate is measured.
const SHOWN_RATE_WINDOW: Duration = Duration::from_secs(1);
/// Memory a clip may hold unless the user allows more, MiB (pixels on the CPU and the same on
/// the display device).
pub const DEFAULT_BUDGET_MIB: u32 = 2048;

/// How the camera moves through a clip.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum ClipPath {
    /// One of the deterministic motions, starting from the current view.
    Motion(Motion),
    /// Through the scene's camera bookmarks in order, at an even pace.
    Bookmarks,
}

impl ClipPath {
    /// Every choice, in menu order.
    pub const ALL: [ClipPath; 5] = [
        ClipPath::Motion(Motion::Pan),
        ClipPath::Motion(Motion::Orbit),
        ClipPath::Motion(Motion::Dolly),
        ClipPath::Motion(Motion::Still),
        ClipPath::Bookmarks,
    ];

    /// Menu label.
    pub fn label(self) -> &'static str {
        match self {
            ClipPath::Motion(motion) => motion.name(),
            ClipPath::Bookmarks => "bookmarks",
        }
    }
}

/// What "Record clip" records (persisted with the settings).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(default)]
pub struct ClipSettings {
    /// Frames of the clip.
    pub frames: u32,
    /// Frames rendered before the clip for temporal history.
    pub warmup: u32,
    /// The camera path.
    pub path: ClipPath,
    /// Speed of pan and dolly, pixels per frame.
    pub speed_px: f32,
    /// Render the complete reference with every frame (the temporal figures need it).
    pub reference: bool,
    /// Its samples per pixel (a square: 16 or 64).
    pub reference_samples: u32,
    /// Memory cap, MiB.
    pub budget_mib: u32,
}

impl Default for ClipSettings {
    fn default() -> Self {
        Self {
            frames: DEFAULT_FRAMES,
            warmup: 8,
            path: ClipPath::Motion(Motion::Pan),
            speed_px: DEFAULT_SPEED_PX,
            reference: true,
            reference_samples: 16,
            budget_mib: DEFAULT_BUDGET_MIB,
        }
    }
}

impl ClipSettings {
    /// Bytes a clip of these settings holds for `images` images per frame of `size`: the
    /// pixels on the CPU and their copies on the display device.
    pub fn bytes(&self, images: usize, size: (u32, u32)) -> u64 {
        2 * u64::from(self.frames) * images as u64 * u64::from(size.0) * u64::from(size.1) * 4
    }

    /// The cameras of the warm-up and the clip, starting at `start` (the current view) with
    /// the scene's orbit speed from `rig`; `bookmarks` are the poses of the bookmark path.
    /// `None` when the path needs bookmarks there are too few of.
    pub fn cameras(
        &self,
        rig: &CameraRig,
        start: OrbitPose,
        bookmarks: &[OrbitPose],
        size: (u32, u32),
    ) -> Option<Vec<FrameCamera>> {
        let total = u64::from(self.warmup + self.frames);
        let from_start = rig.starting_at(start);
        let clip_start = u64::from(self.warmup);
        let pose = |frame: u64| -> Option<OrbitPose> {
            match self.path {
                ClipPath::Motion(motion) => {
                    // The warm-up leads into the clip's first frame: the motion runs from
                    // the start of the warm-up.
                    Some(motion.pose(&from_start, size, self.speed_px, frame))
                }
                ClipPath::Bookmarks => {
                    let t =
                        frame.saturating_sub(clip_start) as f32 / (self.frames.max(2) - 1) as f32;
                    crate::scene::motion::along_path(bookmarks, t)
                }
            }
        };
        (0..total)
            .map(|frame| {
                Some(FrameCamera {
                    pose: pose(frame)?,
                    prev_pose: pose(frame.saturating_sub(1))?,
                    frame,
                    size,
                    render_size: None,
                })
            })
            .collect()
    }
}

/// One recorded instant: every technique's output (in the clip's technique order) and the
/// reference.
pub struct ClipFrame {
    /// The view its images are stamped with (each frame is a view of its own).
    pub view: u64,
    /// Per technique of [`Clip::techniques`].
    pub outputs: Vec<Option<Published>>,
    /// The complete reference, when recorded.
    pub reference: Option<Published>,
}

/// What a clip is of: everything needed to record it again, written into its exported record.
#[derive(Clone, Debug, serde::Serialize)]
pub struct ClipRecipe {
    /// The scene (built-in name or model path).
    pub scene: String,
    /// The camera path.
    pub path: ClipPath,
    /// Speed of pan and dolly, pixels per frame.
    pub speed_px: f32,
    /// Frames rendered before the clip.
    pub warmup: u32,
    /// Frames of the clip.
    pub frames: u32,
    /// Render size.
    pub size: (u32, u32),
    /// The camera the motion starts from.
    pub start: OrbitPose,
    /// The bookmarks of the bookmark path (empty for motions).
    pub bookmarks: Vec<OrbitPose>,
    /// Every technique with its settings, in pane order.
    pub techniques: Vec<crate::spec::TechniqueSpec>,
    /// Samples per pixel of the reference recorded with every frame (`None`: none).
    pub reference_samples: Option<u32>,
    /// Adapter and build.
    pub adapter: String,
    /// aa-lab's build.
    pub build: String,
}

impl ClipRecipe {
    /// One line for the clip bar and titles: scene, path, frames, size.
    pub fn describe(&self, scene_name: &str) -> String {
        let path = match self.path {
            ClipPath::Motion(motion) if motion.uses_speed() => {
                format!("{} {} px/frame", motion.name(), self.speed_px)
            }
            path => path.label().to_owned(),
        };
        format!(
            "{scene_name} · {path} · {} frames · {}x{}",
            self.frames, self.size.0, self.size.1
        )
    }
}

/// Where a clip stands.
pub enum ClipStatus {
    /// Frames are coming in; setting the flag stops the recording after the current frame.
    Recording(Arc<AtomicBool>),
    /// Every frame is here.
    Complete,
    /// Stopped early by the user; the frames recorded so far play.
    Cancelled,
    /// The render thread failed.
    Failed(String),
}

/// A clip: what it shows, its frames and its figures.
pub struct Clip {
    /// Technique ids, in pane order.
    pub techniques: Vec<&'static str>,
    /// Frames recorded so far.
    pub frames: Vec<ClipFrame>,
    /// The frames asked for.
    pub expected: usize,
    /// Where it stands.
    pub status: ClipStatus,
    /// What was recorded.
    pub recipe: ClipRecipe,
    /// One line saying what it shows.
    pub description: String,
    /// Temporal figures per technique (with the reference), once complete.
    pub scores: Option<Vec<TemporalScores>>,
    /// The reference's mean luma change per frame.
    pub reference_change: Option<f64>,
    /// Per technique, the instability map (see [`super::render_thread::ClipSummary`]).
    pub instability_maps: Option<Vec<Arc<crate::metrics::Plane>>>,
    /// Playback.
    pub player: ClipPlayer,
    /// Bytes held (CPU pixels and display textures).
    pub bytes: u64,
    started: Instant,
}

impl Clip {
    /// A clip about to be recorded.
    pub fn recording(
        techniques: Vec<&'static str>,
        recipe: ClipRecipe,
        description: String,
        cancel: Arc<AtomicBool>,
    ) -> Self {
        let expected = recipe.frames as usize;
        Self {
            techniques,
            frames: Vec::with_capacity(expected),
            expected,
            status: ClipStatus::Recording(cancel),
            recipe,
            description,
            scores: None,
            reference_change: None,
            instability_maps: None,
            player: ClipPlayer::default(),
            bytes: 0,
            started: Instant::now(),
        }
    }

    /// Whether frames are still coming.
    pub fn recording_now(&self) -> bool {
        matches!(self.status, ClipStatus::Recording(_))
    }

    /// Stops the recording after the frame being rendered.
    pub fn cancel(&self) {
        if let ClipStatus::Recording(flag) = &self.status {
            flag.store(true, Ordering::Relaxed);
        }
    }

    /// Adds a recorded frame.
    pub fn push(&mut self, frame: ClipFrame) {
        let images = frame.outputs.iter().flatten().chain(&frame.reference);
        self.bytes += images
            .map(|image| {
                let (w, h) = image.size();
                2 * u64::from(w) * u64::from(h) * 4
            })
            .sum::<u64>();
        self.frames.push(frame);
    }

    /// The frame shown now.
    pub fn shown(&self) -> Option<&ClipFrame> {
        self.frames.get(self.player.frame(self.frames.len()))
    }

    /// A technique's image in the shown frame.
    pub fn image(&self, id: &str) -> Option<&Published> {
        let slot = self.techniques.iter().position(|t| *t == id)?;
        self.shown()?.outputs.get(slot)?.as_ref()
    }

    /// Seconds since the recording started.
    pub fn seconds(&self) -> f64 {
        self.started.elapsed().as_secs_f64()
    }
}

/// Playback rates.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PlayRate {
    /// 30 frames per second.
    Fps30,
    /// 60 frames per second.
    Fps60,
    /// A quarter of 30 frames per second.
    Slow,
}

impl PlayRate {
    /// Every rate, in menu order.
    pub const ALL: [PlayRate; 3] = [PlayRate::Fps30, PlayRate::Fps60, PlayRate::Slow];

    /// Clip frames per second.
    pub fn fps(self) -> f64 {
        match self {
            PlayRate::Fps30 => 30.0,
            PlayRate::Fps60 => 60.0,
            PlayRate::Slow => 7.5,
        }
    }

    /// Menu label.
    pub fn label(self) -> &'static str {
        match self {
            PlayRate::Fps30 => "30 fps",
            PlayRate::Fps60 => "60 fps",
            PlayRate::Slow => "slow (7.5 fps)",
        }
    }
}

/// Which frame a clip shows, as time goes by.
#[derive(Clone, Debug)]
pub struct ClipPlayer {
    /// Position in frames (fractional between frames).
    position: f64,
    /// Time runs.
    pub playing: bool,
    /// Speed.
    pub rate: PlayRate,
    /// Back and forth instead of wrapping around.
    pub ping_pong: bool,
    /// Clip frames the clock is ahead of `position` (at most [`MAX_LAG_FRAMES`]).
    lag: f64,
    last_tick: Option<Instant>,
    /// When the shown frame changed while playing, over the last [`SHOWN_RATE_WINDOW`].
    changes: VecDeque<Instant>,
}

impl Default for ClipPlayer {
    fn default() -> Self {
        Self {
            position: 0.0,
            playing: true,
            rate: PlayRate::Fps30,
            ping_pong: false,
            lag: 0.0,
            last_tick: None,
            changes: VecDeque::new(),
        }
    }
}

impl ClipPlayer {
    /// Advances the position by the time since the last tick (`now`), over `frames` frames,
    /// by at most one frame (see the module docs: no frame is skipped).
    pub fn tick(&mut self, now: Instant, frames: usize) {
        let elapsed = self.last_tick.map_or(0.0, |last| {
            now.saturating_duration_since(last).as_secs_f64()
        });
        self.last_tick = Some(now);
        if self.playing && frames > 1 {
            let period = if self.ping_pong {
                2 * (frames - 1)
            } else {
                frames
            } as f64;
            let step = self.position.floor();
            let clock = (self.position + self.lag + elapsed * self.rate.fps())
                .min(step + 2.0 + MAX_LAG_FRAMES - 1e-9);
            // Late: the next frame now, due again at once; the rest is lag to catch up on.
            let shown = clock.min(step + 2.0 - 1e-9);
            if shown.floor() > step {
                self.changes.push_back(now);
            }
            self.lag = clock - shown;
            self.position = shown.rem_euclid(period);
        }
        while self
            .changes
            .front()
            .is_some_and(|at| now.saturating_duration_since(*at) > SHOWN_RATE_WINDOW)
        {
            self.changes.pop_front();
        }
    }

    /// Clip frames shown per second over the last second of playback (`None` before a second
    /// has been played).
    pub fn shown_fps(&self) -> Option<f64> {
        let (first, last) = (self.changes.front()?, self.changes.back()?);
        let span = last.saturating_duration_since(*first);
        (self.playing && span >= SHOWN_RATE_WINDOW.mul_f64(0.9))
            .then(|| (self.changes.len() - 1) as f64 / span.as_secs_f64())
    }

    /// Seconds until the frame shown changes, while playing.
    pub fn until_next_frame(&self) -> f64 {
        (self.position.floor() + 1.0 - self.position) / self.rate.fps()
    }

    /// Stops the clock between ticks (so a pause does not jump on resume).
    pub fn pause_clock(&mut self) {
        self.last_tick = None;
        self.lag = 0.0;
        self.changes.clear();
    }

    /// The frame index shown, of `frames` frames.
    pub fn frame(&self, frames: usize) -> usize {
        if frames == 0 {
            return 0;
        }
        let step = self.position.floor() as usize;
        if self.ping_pong && frames > 1 {
            let period = 2 * (frames - 1);
            let step = step % period;
            if step < frames { step } else { period - step }
        } else {
            step % frames
        }
    }

    /// Shows the last of `frames` frames without changing whether it plays (a clip being
    /// recorded); the clock starts afresh at the next tick.
    pub fn show_newest(&mut self, frames: usize) {
        self.position = frames.saturating_sub(1) as f64;
        self.lag = 0.0;
        self.last_tick = None;
    }

    /// Shows frame `index` (stops playback).
    pub fn seek(&mut self, index: usize) {
        self.playing = false;
        self.position = index as f64;
        self.lag = 0.0;
    }

    /// One frame forward (`1`) or back (`-1`), wrapping, stopping playback.
    pub fn step(&mut self, delta: i64, frames: usize) {
        if frames == 0 {
            return;
        }
        let current = self.frame(frames) as i64;
        self.seek((current + delta).rem_euclid(frames as i64) as usize);
    }
}

/// What the clip bar asks the app to do.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ClipAction {
    /// Record a clip with the current settings.
    Record,
    /// Stop the recording.
    Cancel,
    /// Show the live view again (the clip stays for later).
    ShowLive,
    /// Show the clip.
    ShowClip,
    /// Drop the clip.
    Discard,
    /// Export the clip as an animation.
    Export,
}

/// The clip bar above the status bar: record, play, scrub, export.
pub fn clip_bar(
    ui: &mut egui::Ui,
    settings: &mut ClipSettings,
    clip: Option<&mut Clip>,
    shown: bool,
    estimate: Option<u64>,
) -> Option<ClipAction> {
    let mut action = None;
    ui.horizontal_wrapped(|ui| {
        ui.label(RichText::new("Clip").strong());
        let recording = clip.as_ref().is_some_and(|c| c.recording_now());
        ui.add_enabled_ui(!recording, |ui| {
            if ui
                .button("Record")
                .on_hover_text("Render the camera path through the compared techniques and keep the frames for playback")
                .clicked()
            {
                action = Some(ClipAction::Record);
            }
            egui::ComboBox::from_id_salt("clip path")
                .selected_text(settings.path.label())
                .width(90.0)
                .show_ui(ui, |ui| {
                    for path in ClipPath::ALL {
                        ui.selectable_value(&mut settings.path, path, path.label());
                    }
                })
                .response
                .on_hover_text("Camera path: pan turns in place (sub-pixel per frame), orbit circles the target, dolly moves in, still only jitters, bookmarks goes through the scene's camera bookmarks");
            ui.add(
                egui::DragValue::new(&mut settings.frames)
                    .range(2..=MAX_FRAMES)
                    .suffix(" frames"),
            );
            if matches!(settings.path, ClipPath::Motion(m) if m.uses_speed()) {
                ui.add(
                    egui::DragValue::new(&mut settings.speed_px)
                        .range(0.01..=64.0)
                        .speed(0.01)
                        .suffix(" px/frame"),
                );
            }
            ui.checkbox(&mut settings.reference, "reference")
                .on_hover_text("Render the complete reference with every frame: needed for temporal instability and ghosting (slower)");
            if settings.reference {
                egui::ComboBox::from_id_salt("clip reference samples")
                    .selected_text(format!("{} spp", settings.reference_samples))
                    .width(64.0)
                    .show_ui(ui, |ui| {
                        for samples in [16, 64] {
                            ui.selectable_value(
                                &mut settings.reference_samples,
                                samples,
                                format!("{samples} spp"),
                            );
                        }
                    })
                    .response
                    .on_hover_text("Samples per pixel of the clip's reference: 64 is the bench's, 16 records about four times faster");
            }
        });
        if let Some(bytes) = estimate {
            ui.label(
                RichText::new(format!("≈ {}", mib(bytes)))
                    .small()
                    .color(ui.visuals().weak_text_color()),
            )
            .on_hover_text(format!(
                "Memory the clip will hold (pixels and their display copies); the cap is {} MiB",
                settings.budget_mib
            ));
        }
        let Some(clip) = clip else {
            return;
        };
        ui.separator();
        let count = clip.frames.len();
        if recording {
            let progress = count as f32 / clip.expected.max(1) as f32;
            ui.add(
                egui::ProgressBar::new(progress)
                    .desired_width(160.0)
                    .text(format!("{count}/{} frames", clip.expected)),
            );
            if ui.button("Cancel").clicked() {
                action = Some(ClipAction::Cancel);
            }
        }
        if count == 0 {
            return;
        }
        if !shown {
            if ui.button("Show clip").clicked() {
                action = Some(ClipAction::ShowClip);
            }
        } else {
            let player = &mut clip.player;
            let play = if player.playing { "Pause clip" } else { "Play clip" };
            if ui.button(play).on_hover_text("Play or pause (Space)").clicked() {
                player.playing = !player.playing;
            }
            if ui.button("-1").on_hover_text("One frame back").clicked() {
                player.step(-1, count);
            }
            if ui.button("+1").on_hover_text("One frame forward").clicked() {
                player.step(1, count);
            }
            let mut index = player.frame(count);
            let scrub = ui.add(
                egui::Slider::new(&mut index, 0..=count - 1)
                    .show_value(false)
                    .trailing_fill(true),
            );
            if scrub.changed() {
                player.seek(index);
            }
            ui.label(RichText::new(format!("{:>3}/{count}", index + 1)).monospace());
            egui::ComboBox::from_id_salt("clip rate")
                .selected_text(player.rate.label())
                .width(70.0)
                .show_ui(ui, |ui| {
                    for rate in PlayRate::ALL {
                        ui.selectable_value(&mut player.rate, rate, rate.label());
                    }
                });
            ui.checkbox(&mut player.ping_pong, "ping-pong");
            if let Some(shown) = player.shown_fps().filter(|fps| *fps < 0.95 * player.rate.fps()) {
                ui.label(RichText::new(format!("shown at {shown:.0} fps")).small().color(style::WARN))
                    .on_hover_text("The window paints fewer frames per second than the clip's rate: every frame is shown, more slowly");
            }
            if ui.button("Live").on_hover_text("Back to the live view (the clip stays)").clicked() {
                action = Some(ClipAction::ShowLive);
            }
        }
        if !recording {
            if ui.button("Export…").on_hover_text("Write the clip as a looping animated PNG and a self-contained HTML comparison page, with its record").clicked() {
                action = Some(ClipAction::Export);
            }
            if ui.button("Discard").clicked() {
                action = Some(ClipAction::Discard);
            }
        }
        let status = match &clip.status {
            ClipStatus::Recording(_) => format!("{:.0} s", clip.seconds()),
            ClipStatus::Complete => String::new(),
            ClipStatus::Cancelled => "cancelled".to_owned(),
            ClipStatus::Failed(reason) => format!("failed: {reason}"),
        };
        let text = format!("{} · {}{}", clip.description, mib(clip.bytes), if status.is_empty() { String::new() } else { format!(" · {status}") });
        ui.label(RichText::new(text).small().color(if matches!(clip.status, ClipStatus::Failed(_)) { style::ERROR } else { ui.visuals().weak_text_color() }));
    });
    action
}

/// `bytes` in MiB, for labels.
fn mib(bytes: u64) -> String {
    format!("{:.0} MiB", bytes as f64 / (1024.0 * 1024.0))
}

impl Workspace {
    /// Shows the clip or the live view.
    pub(super) fn show_clip(&mut self, shown: bool) {
        if let Some(engine) = &mut self.engine {
            engine.show_clip(shown);
        }
    }

    /// Records a clip of the compared techniques along the chosen path from the current view.
    pub(super) fn record_clip(&mut self) {
        let ids = self.compared();
        let size = self.render_size;
        let settings = self.settings.clip;
        if ids.is_empty() {
            self.notify(
                Level::Warning,
                "Switch on a technique to record a clip of it.",
            );
            return;
        }
        if size.0 == 0 || size.1 == 0 {
            self.notify(Level::Warning, "The viewport has no size to record at.");
            return;
        }
        let bytes = settings.bytes(ids.len() + usize::from(settings.reference), size);
        let cap = u64::from(settings.budget_mib) << 20;
        if bytes > cap {
            self.notify(
                Level::Error,
                format!(
                    "A clip of {} frames of {} images at {}x{} would hold {}; the cap is {} MiB. Record fewer frames, at a smaller resolution or with fewer techniques.",
                    settings.frames,
                    ids.len() + usize::from(settings.reference),
                    size.0,
                    size.1,
                    mib(bytes),
                    settings.budget_mib
                ),
            );
            return;
        }
        let bookmarks: Vec<OrbitPose> = self.scene_bookmarks().iter().map(|b| b.pose).collect();
        let Some(cameras) =
            settings.cameras(self.camera.rig(), self.camera.pose(), &bookmarks, size)
        else {
            self.notify(
                Level::Warning,
                "The bookmark path needs at least two camera bookmarks of this scene (Camera > Add bookmark).",
            );
            return;
        };
        let Some(engine) = &self.engine else {
            return;
        };
        let recipe = ClipRecipe {
            scene: self
                .scene
                .as_ref()
                .map_or_else(String::new, |s| s.spec.clone()),
            path: settings.path,
            speed_px: settings.speed_px,
            warmup: settings.warmup,
            frames: settings.frames,
            size,
            start: self.camera.pose(),
            bookmarks: if settings.path == ClipPath::Bookmarks {
                bookmarks
            } else {
                Vec::new()
            },
            techniques: ids
                .iter()
                .map(|id| crate::spec::TechniqueSpec {
                    id: (*id).to_owned(),
                    settings: engine.param_map(id),
                    source_hash: engine.source_hash(id),
                })
                .collect(),
            reference_samples: settings.reference.then_some(settings.reference_samples),
            adapter: format!("{} ({})", engine.caps().adapter_name, engine.caps().backend),
            build: crate::spec::build_id(),
        };
        let description = recipe.describe(self.scene.as_ref().map_or("scene", |s| s.name.as_str()));
        let Some(engine) = &mut self.engine else {
            return;
        };
        if let Err(err) = engine.record_clip(cameras, &ids, recipe, description) {
            self.notify(Level::Error, err.to_string());
        }
    }

    /// The clip's progress: frames recorded, and whether it is still recording (`None`: no
    /// clip).
    pub(super) fn clip_progress(&self) -> Option<(usize, bool)> {
        let clip = self.engine.as_ref()?.clip()?;
        Some((clip.frames.len(), clip.recording_now()))
    }

    /// The clip's temporal figures per technique, once recorded with the reference.
    pub(super) fn clip_scores(&self) -> Option<Vec<TemporalScores>> {
        self.engine.as_ref()?.clip()?.scores.clone()
    }

    /// The instability map of technique `id` in the shown clip.
    pub(super) fn instability_map(&self, id: &str) -> Option<Arc<crate::metrics::Plane>> {
        let engine = self.engine.as_ref()?;
        let clip = engine.clip().filter(|_| engine.clip_shown())?;
        let slot = clip.techniques.iter().position(|t| *t == id)?;
        clip.instability_maps.as_ref()?.get(slot).cloned()
    }

    /// The index of the clip frame on screen (`None` when the live view is).
    pub(super) fn shown_clip_frame(&self) -> Option<usize> {
        let engine = self.engine.as_ref()?;
        let clip = engine.clip().filter(|_| engine.clip_shown())?;
        Some(clip.player.frame(clip.frames.len()))
    }

    /// Advances the shown clip's playback; asks for the next UI frame when it plays.
    pub(super) fn tick_clip(&mut self, ctx: &egui::Context) {
        let Some(engine) = &mut self.engine else {
            return;
        };
        if !engine.clip_shown() {
            return;
        }
        let Some(clip) = engine.clip_mut() else {
            return;
        };
        let frames = clip.frames.len();
        if clip.recording_now() {
            // While it records, the clip shows its newest frame; each recorded frame wakes the
            // UI. (Looping over the frames so far would repaint without pause and, on a
            // software rasteriser, take the CPU the recording needs, doubling its time; see
            // docs/viewer.md.) Playback starts when the recording ends.
            clip.player.show_newest(frames);
            return;
        }
        clip.player.tick(Instant::now(), frames);
        if clip.player.playing && frames > 1 {
            if clip.player.rate.fps() >= REPAINT_EVERY_FRAME_FPS {
                // Real time: paint as often as the display (or the rasteriser) allows, so a
                // frame that takes most of a clip period still lands on every clip frame.
                super::request_one_frame(ctx);
            } else {
                // Slow motion: the next UI frame when the next clip frame is due.
                let due = std::time::Duration::from_secs_f64(clip.player.until_next_frame());
                ctx.request_repaint_after(due);
            }
        }
    }
}

/// The clip bar (a bottom panel above the status bar) and what its buttons ask for.
pub(super) fn panel(ui: &mut egui::Ui, ws: &mut Workspace) {
    let images = ws.compared().len() + usize::from(ws.settings.clip.reference);
    let estimate = ws.settings.clip.bytes(images, ws.render_size);
    let Some(engine) = &mut ws.engine else {
        return;
    };
    let shown = engine.clip_shown();
    let settings = &mut ws.settings.clip;
    let action = egui::Panel::bottom("clip bar")
        .frame(egui::Frame::side_top_panel(ui.style()).inner_margin(egui::Margin::symmetric(8, 4)))
        .show(ui, |ui| {
            clip_bar(ui, settings, engine.clip_mut(), shown, Some(estimate))
        })
        .inner;
    match action {
        Some(ClipAction::Record) => ws.record_clip(),
        Some(ClipAction::Cancel) => {
            if let Some(clip) = engine.clip() {
                clip.cancel();
            }
        }
        Some(ClipAction::ShowLive) => ws.show_clip(false),
        Some(ClipAction::ShowClip) => ws.show_clip(true),
        Some(ClipAction::Discard) => {
            if let Some(engine) = &mut ws.engine {
                engine.discard_clip();
            }
        }
        Some(ClipAction::Export) => ws.export_clip(),
        None => {}
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The frames `player` shows at positions 0..9 of a 4-frame clip.
    fn shown_over_nine_steps(player: &mut ClipPlayer) -> Vec<usize> {
        (0..9)
            .map(|step| {
                player.position = f64::from(step);
                player.frame(4)
            })
            .collect()
    }

    #[test]
    fn loops_wrap_and_ping_pong_turns_at_the_ends() {
        let mut player = ClipPlayer::default();
        assert_eq!(
            shown_over_nine_steps(&mut player),
            [0, 1, 2, 3, 0, 1, 2, 3, 0]
        );
        player.ping_pong = true;
        assert_eq!(
            shown_over_nine_steps(&mut player),
            [0, 1, 2, 3, 2, 1, 0, 1, 2]
        );
    }

    /// Ticks `player` at `now + at_ms` for every entry of `at_ms`; the frames shown.
    fn ticks(player: &mut ClipPlayer, now: Instant, at_ms: &[u64]) -> Vec<usize> {
        at_ms
            .iter()
            .map(|ms| {
                player.tick(now + Duration::from_millis(*ms), 48);
                player.frame(48)
            })
            .collect()
    }

    #[test]
    fn playback_advances_with_time_at_the_chosen_rate() {
        let mut player = ClipPlayer::default();
        let start = Instant::now();
        // UI frames every 10 ms for half a second: 30 fps.
        let at: Vec<u64> = (0..=50).map(|i| i * 10).collect();
        assert_eq!(*ticks(&mut player, start, &at).last().unwrap(), 15);
        assert!(
            (player.until_next_frame() - 1.0 / 30.0).abs() < 1e-6,
            "at a frame boundary"
        );
        player.rate = PlayRate::Slow;
        let at: Vec<u64> = (51..=150).map(|i| i * 10).collect();
        assert_eq!(
            *ticks(&mut player, start, &at).last().unwrap(),
            22,
            "then 7.5 fps for a second"
        );
        player.playing = false;
        assert_eq!(ticks(&mut player, start, &[10_000]), [22], "paused");
    }

    #[test]
    fn late_paints_show_the_next_frame_and_catch_up_without_skipping() {
        let mut player = ClipPlayer::default();
        let start = Instant::now();
        // A 30 fps clip painted at 0, 40 and 60 ms, then after a stall of half a second (15
        // frames late): the next frame, then one frame per paint while it catches up on at
        // most two frames of lag, and from there on the clock's pace.
        let shown = ticks(
            &mut player,
            start,
            &[0, 40, 60, 560, 570, 580, 590, 600, 610, 620, 630],
        );
        assert_eq!(shown, [0, 1, 1, 2, 3, 4, 5, 6, 6, 6, 7]);
        // Every frame of a long run at 25 UI frames per second is shown once, in order.
        let mut player = ClipPlayer::default();
        let at: Vec<u64> = (0..=100).map(|i| i * 40).collect();
        let shown = ticks(&mut player, start, &at);
        assert!(
            shown.windows(2).all(|w| w[1] == (w[0] + 1) % 48),
            "{shown:?}"
        );
        let fps = player.shown_fps().expect("a second of playback");
        assert!((fps - 25.0).abs() < 0.01, "{fps}");
        // Paints jittering around the clip's period (28-38 ms, 30.3 fps on average) skip
        // nothing and keep the clip's rate.
        let mut player = ClipPlayer::default();
        let mut t = 0;
        let at: Vec<u64> = (0..300)
            .map(|i| {
                t += [28, 38, 29, 37, 33][i % 5];
                t
            })
            .collect();
        let shown = ticks(&mut player, start, &at);
        assert!(
            shown.windows(2).all(|w| (w[1] + 48 - w[0]) % 48 <= 1),
            "{shown:?}"
        );
        let fps = player.shown_fps().expect("a second of playback");
        assert!(fps > 29.9, "{fps}");
        // Quick paints with a long one (80 ms, 2.4 clip periods) every eighth: the long one
        // shows only the next frame, the quick ones after it catch up, and the clip keeps its
        // 30 frames per second over the run (without the lag it lost 1.4 frames in every
        // eight paints: 25 frames per second).
        let mut player = ClipPlayer::default();
        let periods = [25, 25, 25, 25, 25, 25, 25, 80];
        let mut t = 0;
        let at: Vec<u64> = (0..320)
            .map(|i| {
                t += periods[i % periods.len()];
                t
            })
            .collect();
        let shown = ticks(&mut player, start, &at);
        assert!(
            shown.windows(2).all(|w| (w[1] + 48 - w[0]) % 48 <= 1),
            "{shown:?}"
        );
        let changes = shown.windows(2).filter(|w| w[0] != w[1]).count();
        let seconds = (at[at.len() - 1] - at[0]) as f64 / 1000.0;
        let fps = changes as f64 / seconds;
        assert!(fps > 29.5, "{fps}");
    }

    #[test]
    fn steps_wrap_and_stop_playback() {
        let mut player = ClipPlayer::default();
        player.step(-1, 10);
        assert_eq!(player.frame(10), 9);
        assert!(!player.playing);
        player.step(1, 10);
        assert_eq!(player.frame(10), 0);
    }

    #[test]
    fn the_memory_estimate_counts_pixels_twice() {
        let settings = ClipSettings {
            frames: 48,
            ..Default::default()
        };
        // 48 frames of 5 images of 1280x720 RGBA8, on the CPU and the display device.
        assert_eq!(settings.bytes(5, (1280, 720)), 2 * 48 * 5 * 1280 * 720 * 4);
    }

    #[test]
    fn motions_start_at_the_current_view_and_bookmark_paths_need_two_marks() {
        let rig = CameraRig::default();
        let start = OrbitPose {
            yaw_degrees: 40.0,
            ..OrbitPose::default()
        };
        let settings = ClipSettings {
            frames: 4,
            warmup: 2,
            path: ClipPath::Motion(Motion::Still),
            ..Default::default()
        };
        let cameras = settings
            .cameras(&rig, start, &[], (64, 32))
            .expect("a motion needs no bookmarks");
        assert_eq!(cameras.len(), 6);
        assert!(cameras.iter().all(|c| c.pose == start));
        assert_eq!(cameras[5].frame, 5);
        let path = ClipSettings {
            path: ClipPath::Bookmarks,
            ..settings
        };
        assert!(path.cameras(&rig, start, &[start], (64, 32)).is_none());
        let end = OrbitPose {
            yaw_degrees: 80.0,
            ..start
        };
        let cameras = path.cameras(&rig, start, &[start, end], (64, 32)).unwrap();
        assert_eq!(
            cameras[2].pose, start,
            "the clip starts at the first bookmark"
        );
        assert_eq!(cameras[5].pose, end, "and ends at the last");
    }
}
