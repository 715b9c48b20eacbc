//! The clips the viewer records: what to record ([`ClipSettings`]: the motion, its length, the
//! reference, the memory cap, and the cameras they give), the recording's record
//! ([`ClipRecipe`]) and the recorded frames of every compared technique with their memory
//! counted ([`Clip`]). Every layout and the magnifier read the same frame ([`Clip::shown`],
//! through the clip's [`ClipPlayer`]), so all panes show the same instant.
//!
//! Recording runs on the render thread ([`super::super::render_thread::ClipJob`]): temporal
//! techniques render the warm-up frames first, so the clip shows them with a real history, and
//! the thread scores the clip ([`crate::metrics::stability`]) as the frames come in. Playback
//! draws textures uploaded once while recording, so it costs one blit per pane per UI frame and
//! no engine work: recorded clips play at display rate on a machine whose engine makes a few
//! frames per second.
//!
//! The clip is the engine's (`clip.rs` beside this file starts and fills it); the clip settings
//! are part of the viewer's settings; the clip bar (`app/clip_bar.rs`) records, plays and
//! exports it.

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;

use super::Published;
use super::player::ClipPlayer;
use crate::metrics::stability::TemporalScores;
use crate::scene::CameraRig;
use crate::scene::camera::{FrameCamera, OrbitPose};
use crate::scene::motion::{DEFAULT_SPEED_PX, Motion};

/// Frames of a clip unless the user picks another length.
pub const DEFAULT_FRAMES: u32 = 48;
/// Longest clip.
pub const MAX_FRAMES: u32 = 600;
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

    /// When the recording started: it tells one clip from another.
    pub fn started(&self) -> Instant {
        self.started
    }

    /// Seconds since the recording started.
    pub fn seconds(&self) -> f64 {
        self.started.elapsed().as_secs_f64()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

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
