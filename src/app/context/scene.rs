//! The context's scene commands: loading a scene on the worker thread and installing it (the
//! engine is created with the first one, with the saved technique settings and user
//! techniques), user techniques added from WGSL files, and the loaded scene's camera
//! bookmarks (saved in the settings, exported to and imported from JSON files).

use std::path::PathBuf;
use std::sync::Arc;

use super::{Command, Context, DialogPurpose, Level, SceneInfo};
use crate::app::engine::Engine;
use crate::app::settings::Bookmark;
use crate::scene::Scene;

/// Largest bookmarks file read (thousands of bookmarks; anything larger is not ours).
const BOOKMARKS_LIMIT: u64 = 4 << 20;

impl Context {
    /// Starts loading a scene (built-in name or OBJ/glTF/GLB path) on the worker thread.
    pub(in crate::app) fn load_scene(&mut self, ctx: &egui::Context, spec: &str) {
        let ctx = ctx.clone();
        self.loader
            .load(spec, move || crate::app::repaint::request_one_frame(&ctx));
    }

    /// Loads a scene the user asked for: an open image set gives way to it once it has
    /// loaded.
    pub(in crate::app) fn open_scene(&mut self, ctx: &egui::Context, spec: &str) {
        self.images.leave_for_scene();
        self.load_scene(ctx, spec);
    }

    /// Adds the user technique in the WGSL file at `path` (see `aa::user`; File > Add
    /// technique from file): the render thread builds it, and it appears in the techniques
    /// panel, switched on, or with its file's error. The file is remembered in the settings and
    /// added again at the next start.
    pub(in crate::app) fn add_user_technique(&mut self, path: PathBuf) {
        let Some(engine) = &mut self.engine else {
            return self.notify(
                Level::Warning,
                "techniques can be added once the scene has loaded".to_owned(),
            );
        };
        let path = std::fs::canonicalize(&path).unwrap_or(path);
        let remembered = path.display().to_string();
        engine.add_user_technique(path);
        if !self.settings.user_techniques.contains(&remembered) {
            self.settings.user_techniques.push(remembered);
        }
    }

    /// Adds the combination `text` (`ID[@SCALE][:UPSCALER][+SHARPEN[=STRENGTH]]`, see
    /// `aa::combo`): the render thread creates it and it appears in the techniques panel,
    /// switched on and compared, or with the reason it cannot run. It is remembered in the
    /// settings and added again at the next start. A plain id (scale 1, no sharpening) is the
    /// registry technique itself, which is switched on instead. Returns the canonical id.
    pub(in crate::app) fn add_combination(&mut self, text: &str) -> Option<&'static str> {
        let combo = match crate::aa::combo::Combo::parse(text.trim()) {
            Ok(combo) => combo,
            Err(err) => {
                self.notify(Level::Error, err.to_string());
                return None;
            }
        };
        let Some(engine) = &mut self.engine else {
            self.notify(
                Level::Warning,
                "techniques can be added once the scene has loaded",
            );
            return None;
        };
        let Some(base) = engine.entry(&combo.base) else {
            self.notify(
                Level::Error,
                format!("{text}: no technique `{}` in this viewer", combo.base),
            );
            return None;
        };
        let combo = match combo.resolve(base.reconstructs_at_output()) {
            Ok(combo) => combo,
            Err(err) => {
                self.notify(Level::Error, err.to_string());
                return None;
            }
        };
        let id = crate::aa::user::intern(&combo.id());
        if !combo.is_plain() {
            engine.add_combination(id);
            if !self.settings.combinations.iter().any(|c| c == id) {
                self.settings.combinations.push(id.to_owned());
            }
        }
        if !self.settings.compare.iter().any(|c| c == id) {
            self.toggle_compare(id);
        }
        Some(id)
    }

    /// Removes the user technique or combination `id`: off, out of the comparison and the
    /// techniques panel, forgotten by the settings (a user technique's file is left alone;
    /// adding it again brings it back).
    pub(in crate::app) fn remove_user_technique(&mut self, id: &str) {
        let Some(engine) = &mut self.engine else {
            return;
        };
        engine.remove_user_technique(id);
        if let Some(path) = crate::aa::user::path_of(id) {
            let path = path.display().to_string();
            self.settings.user_techniques.retain(|p| *p != path);
        }
        self.settings.combinations.retain(|c| c != id);
        self.settings.enabled.retain(|e| e != id);
        self.settings.compare.retain(|c| c != id);
        self.settings.technique_settings.remove(id);
        self.settings.debug_views.remove(id);
    }

    /// Adds the user techniques and combinations the settings remember (at start, once the
    /// engine exists); a file that is gone is forgotten, with a notice, and so is a
    /// combination this build no longer reads.
    pub(super) fn restore_user_techniques(&mut self) {
        let Some(engine) = &mut self.engine else {
            return;
        };
        let (readable, unreadable): (Vec<String>, Vec<String>) =
            std::mem::take(&mut self.settings.combinations)
                .into_iter()
                .partition(|id| {
                    crate::aa::combo::Combo::parse(id)
                        .is_ok_and(|c| !c.is_plain() && engine.entry(&c.base).is_some())
                });
        for id in &readable {
            engine.add_combination(crate::aa::user::intern(id));
        }
        self.settings.combinations = readable;
        let (present, gone): (Vec<String>, Vec<String>) =
            std::mem::take(&mut self.settings.user_techniques)
                .into_iter()
                .partition(|path| std::path::Path::new(path).is_file());
        for path in &present {
            engine.add_user_technique(PathBuf::from(path));
        }
        self.settings.user_techniques = present;
        for id in unreadable {
            self.notify(
                Level::Warning,
                format!("saved combination {id} is not a technique here; removed"),
            );
        }
        for path in gone {
            self.notify(
                Level::Warning,
                format!("user technique {path} no longer exists; removed from the techniques"),
            );
        }
    }

    pub(super) fn finish_load(&mut self, ctx: &egui::Context) {
        let Some(loaded) = self.loader.poll() else {
            return;
        };
        match loaded.result {
            Ok(scene) => self.install_scene(ctx, &loaded.spec, scene),
            Err(err) => {
                self.images.stay();
                let kept = match &self.scene {
                    Some(s) => format!("; {} stays loaded", s.name),
                    None => String::new(),
                };
                self.notify(Level::Error, format!("{err}{kept}"));
                if self.scene.is_none() && loaded.spec != crate::scene::source::DEFAULT_SCENE {
                    // Nothing to show yet: fall back to the default scene.
                    self.load_scene(ctx, crate::scene::source::DEFAULT_SCENE);
                }
            }
        }
    }

    fn install_scene(&mut self, ctx: &egui::Context, spec: &str, scene: Scene) {
        for note in &scene.notes {
            self.notify(Level::Info, format!("{}: {note}", scene.name));
        }
        for warning in &scene.warnings {
            self.notify(Level::Warning, format!("{}: {warning}", scene.name));
        }
        let is_file = std::path::Path::new(spec).is_file();
        let spec = if is_file {
            std::fs::canonicalize(spec)
                .map_or_else(|_| spec.to_owned(), |p| p.display().to_string())
        } else {
            spec.to_owned()
        };
        let camera = scene.camera;
        let interior = scene.interior;
        let info = SceneInfo {
            spec: spec.clone(),
            name: scene.name.clone(),
            triangles: scene.triangle_count(),
            views: scene.views.clone(),
        };
        let scene = Arc::new(scene);
        match &mut self.engine {
            Some(engine) => engine.set_scene(scene),
            None => {
                let mut engine = match Engine::new(
                    self.display.clone(),
                    self.gpu.caps.clone(),
                    ctx,
                    scene,
                    self.settings.reference_samples,
                    self.engine_frame_delay,
                ) {
                    Ok(engine) => engine,
                    Err(err) => {
                        self.notify(Level::Error, err.to_string());
                        return;
                    }
                };
                let mut problems = Vec::new();
                for (id, map) in &self.settings.technique_settings {
                    if let Err(err) = engine.apply_param_map(id, map) {
                        problems.push(format!("saved settings of {id} not applied: {err}"));
                    }
                }
                for id in &self.settings.enabled {
                    engine.set_enabled(id, true);
                }
                for (id, view) in &self.settings.debug_views {
                    engine.set_debug_view(id, Some(view.clone()));
                }
                self.engine = Some(engine);
                for p in problems {
                    self.notify(Level::Warning, p);
                }
                self.restore_user_techniques();
            }
        }
        if is_file {
            self.settings.remember_recent(&spec);
        }
        self.settings.scene = spec;
        if self.images.take_leave() {
            self.close_images();
        }
        self.camera.set_rig(camera);
        self.camera.set_mode(if interior {
            crate::app::camera::CameraMode::Fly
        } else {
            crate::app::camera::CameraMode::Orbit
        });
        self.scene = Some(info);
        self.request(Command::ForgetMeasurements);
        ctx.request_repaint();
    }

    /// The bookmarks of the loaded scene.
    pub(in crate::app) fn scene_bookmarks(&self) -> Vec<&Bookmark> {
        let scene = self.scene.as_ref().map(|s| s.spec.as_str()).unwrap_or("");
        self.settings
            .bookmarks
            .iter()
            .filter(|b| b.scene == scene)
            .collect()
    }

    pub(in crate::app) fn add_bookmark(&mut self) {
        let Some(scene) = &self.scene else { return };
        let n = self.scene_bookmarks().len() + 1;
        let bookmark = Bookmark {
            scene: scene.spec.clone(),
            name: format!("View {n}"),
            pose: self.camera.pose(),
        };
        self.notify(
            Level::Info,
            format!("Saved camera bookmark \"{}\"", bookmark.name),
        );
        self.settings.bookmarks.push(bookmark);
    }

    /// Asks where to write the loaded scene's bookmarks (JSON).
    pub(in crate::app) fn export_bookmarks(&mut self, ctx: &egui::Context) {
        let marks: Vec<_> = self.scene_bookmarks().into_iter().cloned().collect();
        let name = self.scene.as_ref().map_or("scene", |s| s.name.as_str());
        let file_name = format!("{name}-bookmarks.json");
        self.ask_for_path(ctx, DialogPurpose::ExportBookmarks(marks), move || {
            rfd::FileDialog::new()
                .set_title("Export camera bookmarks")
                .set_file_name(file_name)
                .add_filter("JSON", &["json"])
                .save_file()
        });
    }

    /// Writes bookmarks to `path` (atomically).
    pub(super) fn write_bookmarks(&mut self, path: &std::path::Path, marks: &[Bookmark]) {
        let json = crate::app::settings::bookmarks_to_json(marks);
        match crate::app::settings::write_atomically(path, &json) {
            Ok(()) => self.notify(
                Level::Info,
                format!("Wrote {} bookmark(s) to {}", marks.len(), path.display()),
            ),
            Err(e) => self.notify(
                Level::Error,
                format!("cannot write {}: {e}", path.display()),
            ),
        }
    }

    /// Asks for a JSON file of bookmarks to add to the loaded scene.
    pub(in crate::app) fn import_bookmarks(&mut self, ctx: &egui::Context) {
        let Some(scene) = self.scene.as_ref().map(|s| s.spec.clone()) else {
            return;
        };
        self.ask_for_path(ctx, DialogPurpose::ImportBookmarks(scene), || {
            rfd::FileDialog::new()
                .set_title("Import camera bookmarks")
                .add_filter("JSON", &["json"])
                .pick_file()
        });
    }

    /// Adds the bookmarks of the file at `path` to `scene`.
    pub(super) fn read_bookmarks(&mut self, path: &std::path::Path, scene: &str) {
        let loaded = crate::files::read_bounded(path, BOOKMARKS_LIMIT, "bookmarks file")
            .map_err(|e| e.to_string())
            .and_then(|bytes| String::from_utf8(bytes).map_err(|e| e.to_string()))
            .and_then(|text| crate::app::settings::bookmarks_from_json(&text, scene));
        match loaded {
            Ok(marks) => {
                self.notify(
                    Level::Info,
                    format!(
                        "Imported {} bookmark(s) from {}",
                        marks.len(),
                        path.display()
                    ),
                );
                self.settings.bookmarks.extend(marks);
            }
            Err(e) => self.notify(Level::Error, format!("{}: {e}", path.display())),
        }
    }
}
