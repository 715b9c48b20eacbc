//! The panels around the viewport: the menu bar, the toolbar (layout, compared techniques,
//! time and camera controls, resolution, export), the status bar (adapter, software rendering,
//! resolution, scene, frame, FPS, notices) and the techniques panel (every registry technique
//! with its switch, comparison mark, presets, parameters, debug views and trade-off tooltip;
//! unavailable ones greyed out with the reason).

use egui::{Button, Color32, RichText};

use super::settings::{Bookmark, Layout, MAX_COMPARE, Resolution};
use super::shortcuts::{self, Action, shortcut_hint};
use super::style::{self, SLOT_COLORS, SLOT_LETTERS};
use super::workspace::{DialogPurpose, Level, Workspace};
use crate::aa::{Param, ParamKind, ParamValue};
use crate::scene::procedural::BUILTIN_SCENES;

/// Largest bookmarks file read (thousands of bookmarks; anything larger is not ours).
const BOOKMARKS_LIMIT: u64 = 4 << 20;

/// A menu button with its shortcut on the right.
fn menu_item(ui: &mut egui::Ui, text: &str, action: Option<Action>) -> bool {
    let shortcut = action
        .and_then(|a| shortcuts::label(ui.ctx(), a))
        .unwrap_or_default();
    ui.add(Button::new(text).shortcut_text(shortcut)).clicked()
}

impl Workspace {
    /// File, View, Camera and Help menus.
    pub(super) fn menu_bar(&mut self, ui: &mut egui::Ui) {
        let ctx = ui.ctx().clone();
        egui::Panel::top("menu bar").show(ui, |ui| {
            egui::MenuBar::new().ui(ui, |ui| {
                ui.menu_button("File", |ui| self.file_menu(ui, &ctx));
                ui.menu_button("View", |ui| self.view_menu(ui));
                ui.menu_button("Camera", |ui| self.camera_menu(ui));
                ui.menu_button("Help", |ui| {
                    if menu_item(ui, "Keyboard shortcuts", Some(Action::Help)) {
                        self.help_open = true;
                    }
                    ui.separator();
                    ui.label(crate::spec::build_id());
                    ui.weak(format!(
                        "{} ({})",
                        self.gpu.caps.adapter_name, self.gpu.caps.backend
                    ));
                });
            });
        });
    }

    fn file_menu(&mut self, ui: &mut egui::Ui, ctx: &egui::Context) {
        if menu_item(ui, "Open OBJ…", Some(Action::Open)) {
            self.open_file_dialog(ctx);
        }
        if ui
            .button("Open images…")
            .on_hover_text("Compare up to four PNG or JPEG images of one size (captures from another renderer, aa-lab's own exports) instead of the scene, one of them as the reference; dropping image files on the window does the same")
            .clicked()
        {
            self.open_images_dialog(ctx);
        }
        if ui
            .button("Add technique from file…")
            .on_hover_text(USER_TECHNIQUE_HINT)
            .clicked()
        {
            self.add_technique_dialog(ctx);
        }
        if self.images.is_open()
            && ui
                .button("Close images")
                .on_hover_text("Back to the scene")
                .clicked()
        {
            self.close_images();
        }
        ui.menu_button("Open recent", |ui| {
            if self.settings.recent.is_empty() {
                ui.weak("No recent files");
            }
            for path in self.settings.recent.clone() {
                if ui.button(&path).clicked() {
                    self.open_scene(ctx, &path);
                }
            }
        });
        ui.menu_button("Built-in scenes", |ui| {
            for name in BUILTIN_SCENES {
                let current = self.scene.as_ref().is_some_and(|s| s.spec == *name);
                if ui.add(Button::selectable(current, *name)).clicked() {
                    self.open_scene(ctx, name);
                }
            }
        });
        ui.separator();
        if menu_item(ui, "Export", Some(Action::Export)) {
            self.start_export(ctx);
        }
        if menu_item(ui, "Copy magnifier sheet", Some(Action::CopySheet)) {
            self.copy_sheet(ctx);
        }
        if ui
            .button(format!(
                "Export folder: {}…",
                self.settings.export_dir.display()
            ))
            .on_hover_text("Choose where exports go (created when needed)")
            .clicked()
        {
            self.pick_export_dir(ctx);
        }
        ui.separator();
        if ui.button("Quit").clicked() {
            ctx.send_viewport_cmd(egui::ViewportCommand::Close);
        }
    }

    fn view_menu(&mut self, ui: &mut egui::Ui) {
        for layout in Layout::ALL {
            let action = Action::Layout(layout);
            let shortcut = shortcuts::label(ui.ctx(), action).unwrap_or_default();
            if ui
                .add(
                    Button::selectable(self.settings.layout == layout, layout.label())
                        .shortcut_text(shortcut),
                )
                .on_hover_text(layout.help())
                .clicked()
            {
                self.settings.layout = layout;
            }
        }
        ui.separator();
        ui.checkbox(&mut self.settings.show_techniques, "Techniques panel");
        ui.checkbox(&mut self.settings.show_metrics, "Metrics panel");
        ui.checkbox(&mut self.settings.show_magnifier, "Magnifier");
        if menu_item(ui, "Hide side panels", Some(Action::TogglePanels)) {
            self.panels_hidden = !self.panels_hidden;
        }
        ui.separator();
        ui.menu_button("Resolution", |ui| self.resolution_choices(ui));
        ui.separator();
        if ui
            .add_enabled(!self.blind.active(), Button::new("Blind comparison"))
            .on_hover_text("Number and shuffle the compared techniques' panes, ask which looks better and record every answer (a JSON file in the export folder)")
            .clicked()
        {
            self.start_blind(ui.ctx());
        }
    }

    fn resolution_choices(&mut self, ui: &mut egui::Ui) {
        ui.radio_value(
            &mut self.settings.resolution,
            Resolution::FitViewport,
            "Fit the viewport",
        )
        .on_hover_text("Render at the viewport's physical pixel size (grid: the tile's size)");
        for (w, h) in Resolution::PRESETS {
            ui.radio_value(
                &mut self.settings.resolution,
                Resolution::Fixed(w, h),
                format!("{w} × {h}"),
            )
            .on_hover_text(
                "Render at this size and show it 1:1, centred (cropped if the viewport is smaller)",
            );
        }
    }

    fn camera_menu(&mut self, ui: &mut egui::Ui) {
        let play = if self.camera.playing { "Pause" } else { "Play" };
        if menu_item(ui, play, Some(Action::PlayPause)) {
            self.toggle_play();
        }
        if menu_item(ui, "Step one frame", Some(Action::Step)) {
            self.camera.playing = false;
            self.camera.step();
        }
        let mut auto = self.camera.auto_rotate;
        if ui
            .checkbox(&mut auto, "Auto-rotate")
            .on_hover_text("Orbit at the scene's speed per frame (the thesis' camera path)")
            .changed()
        {
            self.camera.auto_rotate = auto;
            self.settings.auto_rotate = auto;
        }
        if menu_item(ui, "Reset view", Some(Action::ResetView)) {
            self.camera.reset();
        }
        let mut flying = self.camera.mode == super::camera::CameraMode::Fly;
        if ui
            .checkbox(&mut flying, "Fly camera")
            .on_hover_text("First person for interiors: drag to look, W A S D / Q E to move, Shift for fast (C)")
            .changed()
        {
            self.camera.toggle_mode();
        }
        let views = self
            .scene
            .as_ref()
            .map(|s| s.views.clone())
            .unwrap_or_default();
        if !views.is_empty() {
            ui.separator();
            ui.label("Cameras in the file");
            for view in &views {
                if ui.button(&view.name).clicked() {
                    self.camera
                        .jump_to(crate::scene::camera::OrbitPose::at_frame(&view.camera, 0));
                }
            }
        }
        ui.separator();
        if menu_item(ui, "Bookmark this view", Some(Action::AddBookmark)) {
            self.add_bookmark();
        }
        let scene = self
            .scene
            .as_ref()
            .map(|s| s.spec.clone())
            .unwrap_or_default();
        let mut remove = None;
        let mut go = None;
        for (n, (i, bookmark)) in self
            .settings
            .bookmarks
            .iter()
            .enumerate()
            .filter(|(_, b)| b.scene == scene)
            .enumerate()
        {
            ui.horizontal(|ui| {
                let key = if n < 4 {
                    format!("F{}", n + 5)
                } else {
                    String::new()
                };
                if ui
                    .add(Button::new(&bookmark.name).shortcut_text(key))
                    .clicked()
                {
                    go = Some(bookmark.pose);
                }
                if ui
                    .small_button("×")
                    .on_hover_text("Delete this bookmark")
                    .clicked()
                {
                    remove = Some(i);
                }
            });
        }
        if let Some(pose) = go {
            self.camera.jump_to(pose);
        }
        if let Some(i) = remove {
            self.settings.bookmarks.remove(i);
        }
        ui.separator();
        if ui.button("Export bookmarks…").clicked() {
            self.export_bookmarks(ui.ctx());
        }
        if ui.button("Import bookmarks…").clicked() {
            self.import_bookmarks(ui.ctx());
        }
    }

    /// Asks where to write the loaded scene's bookmarks (JSON).
    fn export_bookmarks(&mut self, ctx: &egui::Context) {
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
        let json = super::settings::bookmarks_to_json(marks);
        match super::settings::write_atomically(path, &json) {
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
    fn import_bookmarks(&mut self, ctx: &egui::Context) {
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
            .and_then(|text| super::settings::bookmarks_from_json(&text, scene));
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

    /// Layout, compared techniques, time, camera and export controls.
    pub(super) fn toolbar(&mut self, ui: &mut egui::Ui) {
        let ctx = ui.ctx().clone();
        egui::Panel::top("toolbar")
            .frame(egui::Frame::side_top_panel(ui.style()).inner_margin(egui::Margin::symmetric(8, 5)))
            .show(ui, |ui| {
                ui.horizontal(|ui| {
                    for layout in Layout::ALL {
                        let tip = shortcut_hint(&ctx, Action::Layout(layout), layout.help());
                        ui.selectable_value(&mut self.settings.layout, layout, layout.label())
                            .on_hover_text(tip);
                    }
                    ui.separator();
                    self.compare_strip(ui);
                    ui.separator();
                    let (icon, tip) = if self.camera.playing {
                        ("Pause", "Pause time")
                    } else {
                        ("Play", "Resume time")
                    };
                    if ui
                        .button(icon)
                        .on_hover_text(shortcut_hint(&ctx, Action::PlayPause, tip))
                        .clicked()
                    {
                        self.toggle_play();
                    }
                    if ui
                        .button("Step")
                        .on_hover_text(shortcut_hint(&ctx, Action::Step, "Step one frame"))
                        .clicked()
                    {
                        self.camera.playing = false;
                        self.camera.step();
                    }
                    let mut auto = self.camera.auto_rotate;
                    if ui
                        .toggle_value(&mut auto, "Orbit")
                        .on_hover_text(shortcut_hint(&ctx, Action::AutoRotate, "Auto-rotate along the scene's camera path"))
                        .changed()
                    {
                        self.camera.auto_rotate = auto;
                        self.settings.auto_rotate = auto;
                    }
                    if ui
                        .button("Reset view")
                        .on_hover_text(shortcut_hint(&ctx, Action::ResetView, "Reset the view"))
                        .clicked()
                    {
                        self.camera.reset();
                    }
                    ui.separator();
                    let resolution = match self.settings.resolution {
                        Resolution::FitViewport => "Fit".to_owned(),
                        Resolution::Fixed(w, h) => format!("{w}×{h}"),
                    };
                    egui::ComboBox::from_id_salt("resolution")
                        .width(90.0)
                        .selected_text(resolution)
                        .show_ui(ui, |ui| self.resolution_choices(ui))
                        .response
                        .on_hover_text("Render resolution");
                    ui.with_layout(egui::Layout::right_to_left(egui::Align::Center), |ui| {
                        let label = if self.export.running() { "Exporting…" } else { "Export" };
                        if ui
                            .add_enabled(!self.export.running(), Button::new(label))
                            .on_hover_text(shortcut_hint(
                                &ctx,
                                Action::Export,
                                &format!(
                                    "Write every enabled technique's frame (PNG), the magnifier sheet and a sidecar JSON to {}",
                                    self.settings.export_dir.display()
                                ),
                            ))
                            .clicked()
                        {
                            self.start_export(&ctx);
                        }
                        if ui
                            .button("?")
                            .on_hover_text(shortcut_hint(&ctx, Action::Help, "Keyboard shortcuts"))
                            .clicked()
                        {
                            self.help_open = true;
                        }
                    });
                });
            });
    }

    /// The A/B/C/D chips of the compared techniques, with swap for the first two.
    fn compare_strip(&mut self, ui: &mut egui::Ui) {
        let compared = self.compared();
        if compared.is_empty() {
            ui.weak("nothing to compare");
            return;
        }
        for (slot, id) in compared.iter().enumerate() {
            let name = self.shown_label(id);
            let letter = self.blind.letter(slot);
            ui.label(style::badge(letter, SLOT_COLORS[slot]))
                .on_hover_text(format!("Compared technique {letter}: {name}"));
            ui.label(name);
        }
        if self.images.is_open() {
            self.image_strip(ui);
        }
        if compared.len() >= 2
            && ui
                .small_button("swap A/B")
                .on_hover_text("Swap A and B")
                .clicked()
        {
            if self.images.is_open() {
                self.swap_images();
                return;
            }
            let (a, b) = (compared[0].to_owned(), compared[1].to_owned());
            let mut order: Vec<String> = compared.iter().map(|s| (*s).to_owned()).collect();
            order[0] = b;
            order[1] = a;
            self.settings.compare = order;
        }
    }

    /// Adapter, software rendering, resolution, scene, frame, FPS and the latest notice.
    pub(super) fn status_bar(&mut self, ui: &mut egui::Ui, hover: Option<(u32, u32)>) {
        egui::Panel::bottom("status bar")
            .frame(egui::Frame::side_top_panel(ui.style()).inner_margin(egui::Margin::symmetric(8, 3)))
            .show(ui, |ui| {
                ui.horizontal(|ui| {
                    let caps = &self.gpu.caps;
                    ui.label(RichText::new(&caps.adapter_name).small())
                        .on_hover_text(caps.report());
                    ui.weak(RichText::new(&caps.backend).small());
                    if caps.software {
                        ui.label(
                            RichText::new(" SOFTWARE ")
                                .small()
                                .strong()
                                .color(Color32::BLACK)
                                .background_color(style::WARN),
                        )
                        .on_hover_text("This adapter rasterises on the CPU: frame times are far longer than on a GPU, and relative costs differ too.");
                    }
                    ui.separator();
                    let (w, h) = self.render_size;
                    ui.label(RichText::new(format!("{w} × {h}")).small().monospace())
                        .on_hover_text("Render resolution of every technique (1:1 on screen)");
                    if let Some(set) = self.images.open() {
                        ui.separator();
                        let (w, h) = set.size();
                        let paths: Vec<String> =
                            set.images().iter().map(|i| i.path.display().to_string()).collect();
                        ui.label(RichText::new(format!("{} image(s) · {w} × {h}", paths.len())).small())
                            .on_hover_text(paths.join("\n"));
                    } else if let Some(scene) = &self.scene {
                        ui.separator();
                        ui.label(RichText::new(format!("{} · {} triangles", scene.name, scene.triangles)).small())
                            .on_hover_text(&scene.spec);
                    }
                    if let Some(spec) = self.loader.loading() {
                        ui.separator();
                        // Static text, not a spinner: an animation repaints the window every
                        // frame, which on a software rasteriser takes CPU from the work.
                        ui.label(RichText::new(format!("loading {spec}…")).small());
                    }
                    ui.separator();
                    let frame = format!(
                        "frame {}{}",
                        self.camera.frame(),
                        if self.camera.playing { "" } else { " (paused)" }
                    );
                    ui.label(RichText::new(frame).small().monospace())
                        .on_hover_text("The animation clock and temporal jitter index; it advances once per rendered frame while playing.");
                    if let Some((x, y)) = hover {
                        ui.separator();
                        ui.label(RichText::new(format!("pixel ({x}, {y})")).small().monospace());
                    }
                    ui.with_layout(egui::Layout::right_to_left(egui::Align::Center), |ui| {
                        let window = std::time::Duration::from_secs(2);
                        if let Some((fps, ms)) = self.clock.fps(window) {
                            ui.label(RichText::new(format!("{fps:.1} FPS · {}", style::ms(ms))).small().monospace())
                                .on_hover_text("Rendered frames per second over the last 2 s (frames in which the techniques produced new images), and the median time between them.");
                        }
                        if self.rendering() {
                            // Static, like the loading note (an animation would repaint
                            // continuously).
                            ui.label(RichText::new("rendering…").small().weak())
                                .on_hover_text("A frame is being rendered; the interface keeps responding meanwhile.");
                        }
                        ui.separator();
                        if let Some(notice) = self.notices.last() {
                            let color = match notice.level {
                                Level::Info => ui.visuals().text_color(),
                                Level::Warning => style::WARN,
                                Level::Error => style::ERROR,
                            };
                            let all: Vec<String> = self.notices.iter().map(|n| n.text.clone()).collect();
                            ui.add(egui::Label::new(RichText::new(&notice.text).small().color(color)).truncate())
                                .on_hover_text(all.join("\n\n"));
                        }
                    });
                });
            });
    }

    /// Every registry technique with its switch, comparison mark and settings.
    pub(super) fn techniques_panel(&mut self, ui: &mut egui::Ui) {
        profiling::function_scope!();
        if self.images.is_open() {
            self.images_panel(ui);
            return;
        }
        egui::Panel::left("techniques")
            .resizable(true)
            .default_size(300.0)
            .size_range(240.0..=480.0)
            .show(ui, |ui| {
                ui.add_space(4.0);
                ui.horizontal(|ui| {
                    ui.heading("Techniques");
                    ui.with_layout(egui::Layout::right_to_left(egui::Align::Center), |ui| {
                        ui.weak(format!("compare up to {MAX_COMPARE}"))
                            .on_hover_text("Click a technique's A/B/C/D box to compare it; compared techniques fill the layouts and the magnifier.");
                    });
                });
                ui.separator();
                egui::ScrollArea::vertical().show(ui, |ui| {
                    let ids: Vec<&'static str> = self
                        .engine
                        .as_ref()
                        .map(|e| {
                            e.entries()
                                .iter()
                                .filter(|t| !t.removed)
                                .map(|t| t.id)
                                .collect()
                        })
                        .unwrap_or_default();
                    let mut number = 0;
                    for id in ids {
                        self.technique_row(ui, id, &mut number);
                    }
                    if self.engine.is_none() {
                        ui.weak("The techniques appear once the scene is loaded.");
                    } else if ui
                        .small_button("Add technique from file…")
                        .on_hover_text(USER_TECHNIQUE_HINT)
                        .clicked()
                    {
                        let ctx = ui.ctx().clone();
                        self.add_technique_dialog(&ctx);
                    }
                });
            });
    }

    fn technique_row(&mut self, ui: &mut egui::Ui, id: &'static str, number: &mut usize) {
        let Some(engine) = &self.engine else { return };
        let Some(entry) = engine.entry(id) else {
            return;
        };
        let (name, summary, available, reason, enabled, problem) = (
            entry.name,
            entry.summary,
            entry.available(),
            entry.availability.clone().err(),
            entry.enabled,
            entry.problem.clone(),
        );
        let key = if available {
            *number += 1;
            (*number <= 9).then(|| number.to_string())
        } else {
            None
        };
        let compared = self.compared();
        let slot = compared.iter().position(|c| *c == id);
        let mut toggled = None;
        let mut compare_clicked = false;
        let mut remove_clicked = false;
        let user = crate::aa::user::is_user_id(id);
        let frame = egui::Frame::new()
            .inner_margin(egui::Margin::symmetric(4, 3))
            .corner_radius(4)
            .fill(if enabled {
                Color32::from_gray(38)
            } else {
                Color32::TRANSPARENT
            });
        frame.show(ui, |ui| {
            ui.horizontal(|ui| {
                let mut on = enabled;
                let tip = match &key {
                    Some(k) => format!("{summary}\n\nKey {k} switches it on or off."),
                    None => summary.to_owned(),
                };
                let response = ui
                    .add_enabled(
                        available,
                        egui::Checkbox::new(&mut on, RichText::new(name).strong()),
                    )
                    .on_hover_text(tip);
                let response = match &reason {
                    Some(reason) => {
                        response.on_disabled_hover_text(format!("Unavailable: {reason}"))
                    }
                    None => response,
                };
                if response.changed() {
                    toggled = Some(on);
                }
                ui.with_layout(egui::Layout::right_to_left(egui::Align::Center), |ui| {
                    if user
                        && ui
                            .small_button("×")
                            .on_hover_text(
                                "Remove this technique (its file stays on disk; add it again \
                                 to bring it back)",
                            )
                            .clicked()
                    {
                        remove_clicked = true;
                    }
                    if available {
                        let (text, fill) = match slot {
                            Some(s) => (SLOT_LETTERS[s], SLOT_COLORS[s]),
                            None => ("+", Color32::from_gray(60)),
                        };
                        let button = Button::new(RichText::new(text).monospace().strong().color(
                            if slot.is_some() {
                                Color32::BLACK
                            } else {
                                Color32::from_gray(200)
                            },
                        ))
                        .fill(fill)
                        .min_size(egui::vec2(22.0, 18.0));
                        if ui
                            .add(button)
                            .on_hover_text(match slot {
                                Some(s) => format!(
                                    "Compared as {}; click to stop comparing",
                                    SLOT_LETTERS[s]
                                ),
                                None => "Compare this technique (switches it on)".to_owned(),
                            })
                            .clicked()
                        {
                            compare_clicked = true;
                        }
                    }
                    if let Some(k) = &key {
                        ui.weak(RichText::new(k).monospace().small());
                    }
                });
            });
            if let Some(reason) = &reason
                && user
            {
                file_error(ui, &format!("The file does not build: {reason}"));
            } else if let Some(reason) = &reason {
                ui.label(
                    RichText::new("not available on this adapter")
                        .small()
                        .weak(),
                )
                .on_hover_text(reason);
            } else {
                if let Some(problem) = &problem {
                    file_error(
                        ui,
                        &format!("The last change does not build; the previous build still runs: {problem}"),
                    );
                }
                if enabled {
                    self.technique_settings(ui, id);
                }
            }
        });
        if let Some(on) = toggled {
            self.set_technique_enabled(id, on);
        }
        if compare_clicked {
            self.toggle_compare(id);
        }
        if remove_clicked {
            self.remove_user_technique(id);
        }
    }

    /// Presets, parameters, debug views and code path of an enabled technique.
    fn technique_settings(&mut self, ui: &mut egui::Ui, id: &'static str) {
        let Some(engine) = &self.engine else { return };
        let presets = engine.presets(id);
        let params = engine.params(id);
        let note = engine.path_note(id);
        let entry = engine.entry(id);
        let debug_views: Vec<(&'static str, &'static str)> =
            entry.map(|e| e.debug_views().collect()).unwrap_or_default();
        let debug_selected = entry.and_then(|e| e.debug_view.clone());
        if presets.is_empty() && params.is_empty() {
            return;
        }
        let mut changes: Vec<(String, ParamValue)> = Vec::new();
        let mut preset_clicked = None;
        let mut debug_change = None;
        egui::CollapsingHeader::new(RichText::new("Settings").small())
            .id_salt(("settings", id))
            .show(ui, |ui| {
                if !presets.is_empty() {
                    ui.horizontal_wrapped(|ui| {
                        ui.label(RichText::new("Preset").small());
                        for preset in presets {
                            if ui.small_button(*preset).on_hover_text(format!("Apply the {preset} preset")).clicked() {
                                preset_clicked = Some(*preset);
                            }
                        }
                    });
                }
                egui::Grid::new(("params", id))
                    .num_columns(2)
                    .spacing([8.0, 4.0])
                    .show(ui, |ui| {
                        for param in &params {
                            ui.label(RichText::new(param.label).small()).on_hover_text(param.help);
                            if let Some(value) = param_widget(ui, id, param) {
                                changes.push((param.key.to_owned(), value));
                            }
                            ui.end_row();
                        }
                        ui.label(RichText::new("Show").small())
                            .on_hover_text("Show a debug view of this technique instead of its output (costs extra passes)");
                        let mut wants_debug = debug_selected.is_some();
                        ui.horizontal(|ui| {
                            if ui.checkbox(&mut wants_debug, RichText::new("debug view").small()).changed() {
                                debug_change = Some(if wants_debug {
                                    Some(debug_views.first().map_or_else(String::new, |(n, _)| (*n).to_owned()))
                                } else {
                                    None
                                });
                            }
                            if let Some(selected) = &debug_selected {
                                let mut choice = selected.clone();
                                egui::ComboBox::from_id_salt(("debug view", id))
                                    .width(100.0)
                                    .selected_text(if choice.is_empty() { "…" } else { choice.as_str() })
                                    .show_ui(ui, |ui| {
                                        for (name, description) in &debug_views {
                                            ui.selectable_value(&mut choice, (*name).to_owned(), *name)
                                                .on_hover_text(*description);
                                        }
                                    });
                                if &choice != selected {
                                    debug_change = Some(Some(choice));
                                }
                            }
                        });
                        ui.end_row();
                    });
                if let Some(note) = &note {
                    ui.add(egui::Label::new(RichText::new(note).small().weak()).wrap());
                }
            });
        let mut failed = Vec::new();
        if let Some(engine) = &mut self.engine {
            if let Some(preset) = preset_clicked
                && let Err(err) = engine.apply_preset(id, preset)
            {
                failed.push(err.to_string());
            }
            for (key, value) in changes {
                if let Err(err) = engine.set_param(id, &key, value) {
                    failed.push(err.to_string());
                }
            }
            if let Some(view) = debug_change {
                engine.set_debug_view(id, view.clone());
                match view {
                    Some(v) => {
                        self.settings.debug_views.insert(id.to_owned(), v);
                    }
                    None => {
                        self.settings.debug_views.remove(id);
                    }
                }
            }
        }
        self.remember_params(id);
        for err in failed {
            self.notify(Level::Error, err);
        }
    }
}

/// What "Add technique from file" does, for its tooltips.
const USER_TECHNIQUE_HINT: &str = "Run your own post-process pass, written in WGSL, beside the \
     built-in techniques, with the same metrics and exports (README: \"Your own technique in \
     WGSL\"); it is rebuilt whenever the file changes";

/// A user technique file's error (compiler message with file, line and column), in its row.
fn file_error(ui: &mut egui::Ui, text: &str) {
    ui.add(
        egui::Label::new(
            RichText::new(text)
                .small()
                .monospace()
                .color(Color32::from_rgb(255, 130, 110)),
        )
        .wrap(),
    );
}

/// The widget of one parameter of technique `id`; the new value when the user changed it
/// (sliders apply while dragging, so the image follows the slider).
fn param_widget(ui: &mut egui::Ui, id: &str, param: &Param) -> Option<ParamValue> {
    match (&param.kind, &param.value) {
        (ParamKind::Bool, ParamValue::Bool(v)) => {
            let mut v = *v;
            let r = ui.checkbox(&mut v, "");
            r.changed().then_some(ParamValue::Bool(v))
        }
        (ParamKind::Float { min, max }, value) => {
            let mut v = crate::aa::params::as_f32(value);
            let r = ui.add(egui::Slider::new(&mut v, *min..=*max).max_decimals(4));
            r.changed().then_some(ParamValue::Float(v))
        }
        (ParamKind::Int { min, max }, value) => {
            let mut v = crate::aa::params::as_i64(value);
            let r = ui.add(egui::Slider::new(&mut v, *min..=*max));
            r.changed().then_some(ParamValue::Int(v))
        }
        (ParamKind::Choice(options), value) => {
            let current = crate::aa::params::as_choice(value).to_owned();
            let mut choice = current.clone();
            egui::ComboBox::from_id_salt((id, param.key))
                .width(130.0)
                .selected_text(&choice)
                .show_ui(ui, |ui| {
                    for option in *options {
                        ui.selectable_value(&mut choice, (*option).to_owned(), *option);
                    }
                });
            (choice != current).then_some(ParamValue::Choice(choice))
        }
        (ParamKind::Bool, _) => None,
    }
}
