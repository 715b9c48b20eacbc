//! Everything the viewer remembers between runs: layout, enabled and compared techniques with
//! their parameters, magnifier and reference options, panels shown, recent files, camera
//! bookmarks and the export folder.
//!
//! The settings are one serde struct stored as JSON under one key of eframe's storage. Every
//! field has a default (`#[serde(default)]`), so files from older or newer versions load with
//! what they share; a value that cannot be read at all falls back to the defaults and the user
//! is told why ([`Settings::from_stored`], which names the settings file; the app also logs
//! it). Values are brought into range on load, and against the adapter's limits once the
//! device is known ([`Settings::fit_to_adapter`]): a saved 99999x99999 resolution would
//! otherwise never render.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use crate::aa::{self, ParamMap};
use crate::scene::camera::OrbitPose;

use super::difference::DiffMetric;

/// Application id: window class and the folder eframe persists settings in.
pub const APP_ID: &str = "aa-lab";

/// Key of the settings in eframe's storage.
pub const STORAGE_KEY: &str = "aa-lab viewer settings";

/// Most techniques compared side by side (the magnifier panes and the grid tiles).
pub const MAX_COMPARE: usize = 4;

/// Most entries in File > Recent.
pub const MAX_RECENT: usize = 8;

/// How the viewport shows the compared techniques.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum Layout {
    /// The first compared technique fills the viewport.
    #[default]
    Single,
    /// A draggable divider: technique A left of it, B right of it, on the same frame.
    Wipe,
    /// Technique A; holding B shows technique B, holding R the reference.
    Flip,
    /// Four techniques in a 2x2 grid, each rendered at the tile size.
    Grid,
}

impl Layout {
    /// Every layout, in menu order.
    pub const ALL: [Self; 4] = [Self::Single, Self::Wipe, Self::Flip, Self::Grid];

    /// Menu label.
    pub fn label(self) -> &'static str {
        match self {
            Self::Single => "Single",
            Self::Wipe => "Wipe",
            Self::Flip => "A/B flip",
            Self::Grid => "2x2 grid",
        }
    }

    /// Tooltip.
    pub fn help(self) -> &'static str {
        match self {
            Self::Single => "Technique A fills the viewport at 1:1 pixels.",
            Self::Wipe => {
                "Technique A left of a draggable divider, B right of it, both from the same frame."
            }
            Self::Flip => {
                "Technique A; hold B to show technique B, hold R to show the reference, on the same frame."
            }
            Self::Grid => {
                "Techniques A to D in a 2x2 grid; every tile is rendered at the tile's own size, 1:1."
            }
        }
    }
}

/// What the magnifier shows.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(default)]
pub struct MagnifierSettings {
    /// Centre of the lens in frame pixels (clamped to the frame); `None` is the frame centre.
    pub center: Option<[f32; 2]>,
    /// Nearest-neighbour zoom factor, 2..=32.
    pub zoom: u32,
    /// Draw a line between magnified pixels.
    pub pixel_grid: bool,
    /// Add a pane with the reference.
    pub show_reference: bool,
    /// Show each pane's error against the reference instead of its pixels.
    pub difference: bool,
    /// The error metric of the difference mode.
    pub metric: DiffMetric,
}

impl Default for MagnifierSettings {
    fn default() -> Self {
        Self {
            center: None,
            zoom: 8,
            pixel_grid: true,
            show_reference: true,
            difference: false,
            metric: DiffMetric::AbsoluteError,
        }
    }
}

/// The render resolution.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum Resolution {
    /// The viewport's physical pixel size.
    #[default]
    FitViewport,
    /// A fixed size, shown 1:1 and centred (cropped when the viewport is smaller).
    Fixed(u32, u32),
}

impl Resolution {
    /// The fixed sizes offered in the menu.
    pub const PRESETS: [(u32, u32); 4] = [(640, 360), (1280, 720), (1920, 1080), (2560, 1440)];
}

/// A saved camera position for one scene.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Bookmark {
    /// The scene (built-in name or model path) it belongs to.
    pub scene: String,
    /// Name shown in the menu.
    pub name: String,
    /// The camera.
    pub pose: OrbitPose,
}

/// The JSON file camera bookmarks are exported to and imported from.
#[derive(Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct BookmarkFile {
    /// Format marker and version (1).
    pub aa_lab_bookmarks: u32,
    /// The bookmarks (each camera is an orbit pose; fly-mode views are poses too).
    pub bookmarks: Vec<Bookmark>,
}

/// The bookmarks as the JSON of a [`BookmarkFile`].
pub fn bookmarks_to_json(bookmarks: &[Bookmark]) -> String {
    let file = BookmarkFile {
        aa_lab_bookmarks: 1,
        bookmarks: bookmarks.to_vec(),
    };
    serde_json::to_string_pretty(&file).unwrap_or_else(|_| "{}".to_owned())
}

/// Bookmarks from the JSON of a [`BookmarkFile`], moved to `scene` (a file exported for a
/// model elsewhere names that model's path); every pose must be finite.
pub fn bookmarks_from_json(text: &str, scene: &str) -> Result<Vec<Bookmark>, String> {
    let file: BookmarkFile =
        serde_json::from_str(text).map_err(|e| format!("not an aa-lab bookmarks file: {e}"))?;
    file.bookmarks
        .into_iter()
        .map(|b| {
            let p = &b.pose;
            let finite = p.target.is_finite()
                && [
                    p.distance,
                    p.yaw_degrees,
                    p.pitch_degrees,
                    p.fov_y_degrees,
                    p.near,
                ]
                .iter()
                .all(|v| v.is_finite())
                && p.distance > 0.0
                && p.near > 0.0
                && p.fov_y_degrees > 0.0
                && p.fov_y_degrees < 180.0;
            if finite {
                Ok(Bookmark {
                    scene: scene.to_owned(),
                    ..b
                })
            } else {
                Err(format!("bookmark \"{}\" has an unusable camera", b.name))
            }
        })
        .collect()
}

/// Writes `text` to `path` through a temporary file in the same folder and a rename, so a
/// failed write never leaves half a file.
pub fn write_atomically(path: &std::path::Path, text: &str) -> std::io::Result<()> {
    let mut temp = path.as_os_str().to_owned();
    temp.push(".tmp");
    let temp = std::path::PathBuf::from(temp);
    std::fs::write(&temp, text)?;
    std::fs::rename(&temp, path).inspect_err(|_| {
        let _ = std::fs::remove_file(&temp);
    })
}

/// Everything persisted. See the module docs.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(default)]
pub struct Settings {
    /// Viewport layout.
    pub layout: Layout,
    /// Ids of the techniques switched on.
    pub enabled: Vec<String>,
    /// Ids of the techniques compared (A, B, C, D), at most [`MAX_COMPARE`].
    pub compare: Vec<String>,
    /// Parameters per technique id (only what differs from the defaults needs to be here).
    pub technique_settings: BTreeMap<String, ParamMap>,
    /// Debug view shown instead of the output, per technique id.
    pub debug_views: BTreeMap<String, String>,
    /// Position of the wipe divider as a fraction of the viewport width.
    pub wipe: f32,
    /// Magnifier options.
    pub magnifier: MagnifierSettings,
    /// Render resolution.
    pub resolution: Resolution,
    /// The camera follows the scene's orbit path.
    pub auto_rotate: bool,
    /// Scene opened at start (built-in name or OBJ path).
    pub scene: String,
    /// Recently opened OBJ files, newest first.
    pub recent: Vec<String>,
    /// The WGSL files of the user techniques added, in the order added (absolute paths): the
    /// viewer adds them again at the next start.
    pub user_techniques: Vec<String>,
    /// The combinations added (`aa::combo` ids such as `smaa@performance:easu+rcas=0.2`), in
    /// the order added: the viewer adds them again at the next start.
    pub combinations: Vec<String>,
    /// The display model clips are scored for with ColorVideoVDP (`metrics::jod`).
    pub jod_display: String,
    /// The viewing distance ColorVideoVDP scores for, as pixels per degree replacing the
    /// display model's (`None`: the model's own).
    pub jod_pixels_per_degree: Option<f64>,
    /// Camera bookmarks.
    pub bookmarks: Vec<Bookmark>,
    /// Folder exports go to.
    pub export_dir: PathBuf,
    /// Samples per pixel of the reference (k x k ordered grid: 16, 64 or 256).
    pub reference_samples: u32,
    /// The UI overlay over the frames, before or after the antialiasing (`None`: off).
    pub ui_overlay: Option<crate::graph::overlay::OverlayOrder>,
    /// How the scene's radiance is displayed (`auto`: HDR scenes through the default
    /// tonemapper) and the exposure of HDR renders in stops.
    pub tonemap: crate::graph::hdr::TonemapChoice,
    /// Exposure of HDR renders in stops (EV).
    pub exposure: f32,
    /// Compute SSIM, PSNR and FLIP against the reference.
    pub quality: bool,
    /// Panels shown.
    pub show_techniques: bool,
    /// Metrics panel shown.
    pub show_metrics: bool,
    /// Magnifier shown.
    pub show_magnifier: bool,
    /// The GPU table lists every pass, not only per technique.
    pub show_passes: bool,
    /// What "Record clip" records.
    pub clip: super::engine::ClipSettings,
}

impl Default for Settings {
    fn default() -> Self {
        let first_four = [aa::none::ID, aa::fxaa::ID, aa::smaa::ID_1X, aa::msaa::ID_4X];
        Self {
            layout: Layout::Single,
            enabled: first_four.iter().map(|s| (*s).to_owned()).collect(),
            compare: first_four.iter().map(|s| (*s).to_owned()).collect(),
            technique_settings: BTreeMap::new(),
            debug_views: BTreeMap::new(),
            wipe: 0.5,
            magnifier: MagnifierSettings::default(),
            resolution: Resolution::FitViewport,
            auto_rotate: false,
            scene: crate::scene::source::DEFAULT_SCENE.to_owned(),
            recent: Vec::new(),
            user_techniques: Vec::new(),
            combinations: Vec::new(),
            jod_display: crate::metrics::jod::DEFAULT_DISPLAY.to_owned(),
            jod_pixels_per_degree: None,
            bookmarks: Vec::new(),
            export_dir: PathBuf::from("screenshots"),
            reference_samples: 64,
            ui_overlay: None,
            tonemap: crate::graph::hdr::TonemapChoice::Auto,
            exposure: 0.0,
            quality: true,
            show_techniques: true,
            show_metrics: true,
            show_magnifier: true,
            show_passes: false,
            clip: super::engine::ClipSettings::default(),
        }
    }
}

impl Settings {
    /// Settings from the stored text: the defaults when nothing was stored, and the defaults
    /// plus a notice saying why when the text cannot be read.
    /// `file` is where they were stored, for the notice.
    pub fn from_stored(text: Option<&str>, file: Option<&Path>) -> (Self, Option<String>) {
        let Some(text) = text else {
            return (Self::default(), None);
        };
        match serde_json::from_str::<Self>(text) {
            Ok(settings) => (settings.sanitized(), None),
            Err(err) => (
                Self::default(),
                Some(format!(
                    "The saved viewer settings{} could not be read ({err}); the defaults are in \
                     use and will replace them on exit.",
                    file.map(|f| format!(" in {}", f.display()))
                        .unwrap_or_default()
                )),
            ),
        }
    }

    /// Brings what depends on the adapter into its limits: a fixed resolution larger than its
    /// largest texture side falls back to the viewport size. Returns a notice saying so.
    pub fn fit_to_adapter(&mut self, max_texture_side: u32) -> Option<String> {
        match self.resolution {
            Resolution::Fixed(w, h) if w > max_texture_side || h > max_texture_side => {
                self.resolution = Resolution::FitViewport;
                Some(format!(
                    "The saved resolution {w}x{h} is larger than this adapter's largest texture \
                     side ({max_texture_side}); the viewport size is used instead."
                ))
            }
            _ => None,
        }
    }

    /// The JSON text stored.
    pub fn to_stored(&self) -> String {
        serde_json::to_string(self).unwrap_or_default()
    }

    /// Brings values from a hand-edited or foreign file into range.
    fn sanitized(mut self) -> Self {
        self.wipe = if self.wipe.is_finite() {
            self.wipe.clamp(0.0, 1.0)
        } else {
            0.5
        };
        self.magnifier.zoom = self.magnifier.zoom.clamp(2, 32);
        self.compare.dedup();
        self.compare.truncate(MAX_COMPARE);
        self.recent.truncate(MAX_RECENT);
        if ![16, 64, 256].contains(&self.reference_samples) {
            self.reference_samples = 64;
        }
        if let Resolution::Fixed(w, h) = self.resolution
            && (w == 0 || h == 0)
        {
            self.resolution = Resolution::FitViewport;
        }
        self
    }

    /// Puts a path first in the recent list.
    pub fn remember_recent(&mut self, path: &str) {
        self.recent.retain(|p| p != path);
        self.recent.insert(0, path.to_owned());
        self.recent.truncate(MAX_RECENT);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_trip_and_partial_files() {
        let mut s = Settings {
            layout: Layout::Grid,
            wipe: 0.25,
            ..Settings::default()
        };
        s.remember_recent("/tmp/a.obj");
        let (back, notice) = Settings::from_stored(Some(&s.to_stored()), None);
        assert_eq!(back, s);
        assert!(notice.is_none());
        let (partial, notice) =
            Settings::from_stored(Some(r#"{"layout":"Wipe","wipe":7.0}"#), None);
        assert!(notice.is_none());
        assert_eq!(partial.layout, Layout::Wipe);
        assert_eq!(partial.wipe, 1.0);
        assert_eq!(partial.enabled, Settings::default().enabled);
    }

    #[test]
    fn corrupt_settings_fall_back_with_a_notice() {
        let file = Path::new("/home/u/.local/share/aa-lab/app.ron");
        let (s, notice) = Settings::from_stored(Some("{not json"), Some(file));
        assert_eq!(s, Settings::default());
        let notice = notice.expect("a notice");
        assert!(notice.contains("defaults"), "{notice}");
        // Bad JSON inside a readable file names the file (issue 10, item 7).
        assert!(notice.contains("app.ron"), "{notice}");
        assert_eq!(
            Settings::from_stored(None, None),
            (Settings::default(), None)
        );
    }

    #[test]
    fn a_resolution_beyond_the_adapter_falls_back_to_the_viewport() {
        let (mut s, notice) =
            Settings::from_stored(Some(r#"{"resolution":{"Fixed":[99999,99999]}}"#), None);
        assert!(notice.is_none());
        let notice = s.fit_to_adapter(16384).expect("a notice");
        assert_eq!(s.resolution, Resolution::FitViewport);
        assert!(
            notice.contains("99999x99999") && notice.contains("16384"),
            "{notice}"
        );
        s.resolution = Resolution::Fixed(1920, 1080);
        assert!(s.fit_to_adapter(16384).is_none());
        assert_eq!(s.resolution, Resolution::Fixed(1920, 1080));
    }

    #[test]
    fn recent_list_is_unique_newest_first_and_bounded() {
        let mut s = Settings::default();
        for i in 0..12 {
            s.remember_recent(&format!("{i}.obj"));
        }
        s.remember_recent("5.obj");
        assert_eq!(s.recent.len(), MAX_RECENT);
        assert_eq!(s.recent[0], "5.obj");
        assert_eq!(s.recent.iter().filter(|p| *p == "5.obj").count(), 1);
    }

    #[test]
    fn bookmarks_round_trip_through_json() {
        let pose = crate::scene::camera::OrbitPose::default();
        let marks = vec![Bookmark {
            scene: "/a/model.glb".to_owned(),
            name: "hall".to_owned(),
            pose,
        }];
        let json = bookmarks_to_json(&marks);
        let back = bookmarks_from_json(&json, "/b/model.glb").expect("parses");
        assert_eq!(back.len(), 1);
        assert_eq!(back[0].pose, pose);
        assert_eq!(back[0].name, "hall");
        assert_eq!(back[0].scene, "/b/model.glb");
        assert!(bookmarks_from_json("{}", "x").is_err());
        let bad = json.replace("\"distance\": 5.0", "\"distance\": -1.0");
        assert_ne!(bad, json);
        assert!(bookmarks_from_json(&bad, "x").is_err());
        // Left-out camera fields take their defaults.
        let sparse = r#"{"aa_lab_bookmarks": 1, "bookmarks": [{"scene": "s", "name": "n", "pose": {"distance": 2.0}}]}"#;
        let loaded = bookmarks_from_json(sparse, "s").expect("defaults fill in");
        assert_eq!(loaded[0].pose.distance, 2.0);
        assert_eq!(loaded[0].pose.fov_y_degrees, pose.fov_y_degrees);
    }
}
