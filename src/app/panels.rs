//! The bars around the viewport, stateless functions of the [`Workspace`]: the menu bar
//! ([`menu_bar`]), the toolbar ([`toolbar`]: layout, compared techniques, time and camera
//! controls, resolution, export) and the status bar ([`status_bar`]: adapter, software
//! rendering, resolution, scene, frame, FPS, notices). What they show is the workspace's; the
//! help overlay and the side panels' visibility, which the menus and the toolbar switch, are
//! the app's and passed in.

use egui::{Button, Color32, RichText};

use super::context::{Command, Level};
use super::image_panel;
use super::settings::{Layout, Resolution};
use super::shortcuts::{self, Action, shortcut_hint};
use super::style::{self, SLOT_COLORS, ShowKeyed};
use super::techniques_panel::USER_TECHNIQUE_HINT;
use super::workspace::Workspace;
use crate::scene::procedural::BUILTIN_SCENES;

/// A menu button with its shortcut on the right.
fn menu_item(ui: &mut egui::Ui, text: &str, action: Option<Action>) -> bool {
    let shortcut = action
        .and_then(|a| shortcuts::label(ui.ctx(), a))
        .unwrap_or_default();
    ui.add(Button::new(text).shortcut_text(shortcut)).clicked()
}

/// File, View, Camera and Help menus; Help opens the help overlay (`help_open`), View hides
/// the side panels (`panels_hidden`).
pub(super) fn menu_bar(
    ui: &mut egui::Ui,
    ws: &mut Workspace,
    help_open: &mut bool,
    panels_hidden: &mut bool,
) {
    let ctx = ui.ctx().clone();
    egui::Panel::top("menu bar").show_keyed(ui, "menu bar", |ui| {
        egui::MenuBar::new().ui(ui, |ui| {
            ui.menu_button("File", |ui| file_menu(ui, ws, &ctx));
            ui.menu_button("View", |ui| view_menu(ui, ws, panels_hidden));
            ui.menu_button("Camera", |ui| camera_menu(ui, ws));
            ui.menu_button("Help", |ui| {
                if menu_item(ui, "Keyboard shortcuts", Some(Action::Help)) {
                    *help_open = true;
                }
                ui.separator();
                ui.label(crate::spec::build_id());
                ui.weak(format!(
                    "{} ({})",
                    ws.cx.gpu.caps.adapter_name, ws.cx.gpu.caps.backend
                ));
            });
        });
    });
}

fn file_menu(ui: &mut egui::Ui, ws: &mut Workspace, ctx: &egui::Context) {
    if menu_item(ui, "Open OBJ…", Some(Action::Open)) {
        ws.cx.open_file_dialog(ctx);
    }
    if ui
        .button("Open images…")
        .on_hover_text("Compare up to four PNG or JPEG images of one size (captures from another renderer, aa-lab's own exports) instead of the scene, one of them as the reference, or four and a fifth as the reference; dropping image files on the window does the same")
        .clicked()
    {
        ws.cx.open_images_dialog(ctx);
    }
    if ui
        .button("Open sequences…")
        .on_hover_text("Play up to four image sequences of one size in lockstep (folders of numbered PNG, JPEG or OpenEXR frames captured from an engine) instead of the scene, one of them as the reference, or four and a fifth as the reference (the one named \"ref\" or \"reference\", else the first; the toolbar's R changes it); dropping folders on the window does the same")
        .clicked()
    {
        ws.cx.open_sequences_dialog(ctx);
    }
    if ui
        .button("Add technique from file…")
        .on_hover_text(USER_TECHNIQUE_HINT)
        .clicked()
    {
        ws.cx.add_technique_dialog(ctx);
    }
    if ws.cx.images.is_open()
        && ui
            .button("Close images")
            .on_hover_text("Back to the scene")
            .clicked()
    {
        ws.cx.close_images();
    }
    ui.menu_button("Open recent", |ui| {
        if ws.cx.settings.recent.is_empty() {
            ui.weak("No recent files");
        }
        for path in ws.cx.settings.recent.clone() {
            if ui.button(&path).clicked() {
                ws.cx.open_scene(ctx, &path);
            }
        }
    });
    ui.menu_button("Built-in scenes", |ui| {
        for name in BUILTIN_SCENES {
            let current = ws.cx.scene.as_ref().is_some_and(|s| s.spec == *name);
            if ui.add(Button::selectable(current, *name)).clicked() {
                ws.cx.open_scene(ctx, name);
            }
        }
    });
    if let Some(engine) = ws.cx.engine.as_mut() {
        let mut specular_aa = engine.specular_aa();
        if ui
            .checkbox(&mut specular_aa, "Specular antialiasing")
            .on_hover_text(
                "Widen every technique's highlights by the normal's change across the pixel \
                 (--specular-aa); the reference stays unfiltered",
            )
            .changed()
        {
            engine.set_specular_aa(specular_aa);
        }
    }
    ui.separator();
    if menu_item(ui, "Export", Some(Action::Export)) {
        ws.cx.request(Command::ExportFrame);
    }
    if menu_item(ui, "Copy magnifier sheet", Some(Action::CopySheet)) {
        ws.cx.request(Command::CopySheet);
    }
    if ui
        .button(format!(
            "Export folder: {}…",
            ws.cx.settings.export_dir.display()
        ))
        .on_hover_text("Choose where exports go (created when needed)")
        .clicked()
    {
        ws.cx.pick_export_dir(ctx);
    }
    ui.separator();
    if ui.button("Quit").clicked() {
        ctx.send_viewport_cmd(egui::ViewportCommand::Close);
    }
}

fn view_menu(ui: &mut egui::Ui, ws: &mut Workspace, panels_hidden: &mut bool) {
    for layout in Layout::ALL {
        let action = Action::Layout(layout);
        let shortcut = shortcuts::label(ui.ctx(), action).unwrap_or_default();
        if ui
            .add(
                Button::selectable(ws.cx.settings.layout == layout, layout.label())
                    .shortcut_text(shortcut),
            )
            .on_hover_text(layout.help())
            .clicked()
        {
            ws.cx.settings.layout = layout;
        }
    }
    ui.separator();
    ui.checkbox(&mut ws.cx.settings.show_techniques, "Techniques panel");
    ui.checkbox(&mut ws.cx.settings.show_metrics, "Metrics panel");
    ui.checkbox(&mut ws.cx.settings.show_magnifier, "Magnifier");
    if menu_item(ui, "Hide side panels", Some(Action::TogglePanels)) {
        *panels_hidden = !*panels_hidden;
    }
    ui.separator();
    ui.menu_button("Resolution", |ui| resolution_choices(ui, ws));
    ui.menu_button("UI overlay", |ui| overlay_choices(ui, ws));
    ui.menu_button("Tonemap", |ui| tonemap_choices(ui, ws));
    ui.separator();
    if ui
        .add_enabled(!ws.cx.blind.active(), Button::new("Blind comparison"))
        .on_hover_text("Number and shuffle the compared techniques' panes, ask which looks better and record every answer (a JSON file in the export folder)")
        .clicked()
    {
        ws.cx.start_blind(ui.ctx());
    }
}

fn resolution_choices(ui: &mut egui::Ui, ws: &mut Workspace) {
    ui.radio_value(
        &mut ws.cx.settings.resolution,
        Resolution::FitViewport,
        "Fit the viewport",
    )
    .on_hover_text("Render at the viewport's physical pixel size (grid: the tile's size)");
    for (w, h) in Resolution::PRESETS {
        ui.radio_value(
            &mut ws.cx.settings.resolution,
            Resolution::Fixed(w, h),
            format!("{w} × {h}"),
        )
        .on_hover_text(
            "Render at this size and show it 1:1, centred (cropped if the viewport is smaller)",
        );
    }
}

fn overlay_choices(ui: &mut egui::Ui, ws: &mut Workspace) {
    use crate::graph::overlay::OverlayOrder;
    let overlay = &mut ws.cx.settings.ui_overlay;
    ui.radio_value(overlay, None, "Off");
    ui.radio_value(overlay, Some(OverlayOrder::Before), "Before the antialiasing")
        .on_hover_text("Draw a game-like HUD into the scene renders the techniques read, as engines that blur their UI do (the reference gets it after its resolve)");
    ui.radio_value(overlay, Some(OverlayOrder::After), "After the antialiasing")
        .on_hover_text("Draw the HUD over each technique's output, where it stays exact");
}

fn tonemap_choices(ui: &mut egui::Ui, ws: &mut Workspace) {
    use crate::graph::hdr::TonemapChoice;
    use crate::graph::params::Named;
    let settings = &mut ws.cx.settings;
    for (choice, doc) in TonemapChoice::ALL.iter().zip(TonemapChoice::DOCS) {
        ui.radio_value(&mut settings.tonemap, *choice, choice.name())
            .on_hover_text(*doc);
    }
    ui.separator();
    ui.add(
        egui::Slider::new(&mut settings.exposure, -8.0..=8.0)
            .step_by(0.5)
            .text("Exposure (EV)"),
    )
    .on_hover_text(
        "Radiance is scaled by 2^EV before the tonemapper (HDR renders, and OpenEXR sequences \
         when a tonemapper is named: auto clamps captures). Each technique runs before or after \
         the tonemapper by its tonemap_order setting.",
    );
}

fn camera_menu(ui: &mut egui::Ui, ws: &mut Workspace) {
    let play = if ws.cx.camera.playing {
        "Pause"
    } else {
        "Play"
    };
    if menu_item(ui, play, Some(Action::PlayPause)) {
        ws.cx.toggle_play();
    }
    if menu_item(ui, "Step one frame", Some(Action::Step)) {
        ws.cx.camera.playing = false;
        ws.cx.camera.step();
    }
    let mut auto = ws.cx.camera.auto_rotate;
    if ui
        .checkbox(&mut auto, "Auto-rotate")
        .on_hover_text("Orbit at the scene's speed per frame (the thesis' camera path)")
        .changed()
    {
        ws.cx.camera.auto_rotate = auto;
        ws.cx.settings.auto_rotate = auto;
    }
    if menu_item(ui, "Reset view", Some(Action::ResetView)) {
        ws.cx.camera.reset();
    }
    let mut flying = ws.cx.camera.mode == super::camera::CameraMode::Fly;
    if ui
        .checkbox(&mut flying, "Fly camera")
        .on_hover_text(
            "First person for interiors: drag to look, W A S D / Q E to move, Shift for fast (C)",
        )
        .changed()
    {
        ws.cx.camera.toggle_mode();
    }
    let views = ws
        .cx
        .scene
        .as_ref()
        .map(|s| s.views.clone())
        .unwrap_or_default();
    if !views.is_empty() {
        ui.separator();
        ui.label("Cameras in the file");
        for view in &views {
            if ui.button(&view.name).clicked() {
                ws.cx
                    .camera
                    .jump_to(crate::scene::camera::OrbitPose::at_frame(&view.camera, 0));
            }
        }
    }
    ui.separator();
    if menu_item(ui, "Bookmark this view", Some(Action::AddBookmark)) {
        ws.cx.add_bookmark();
    }
    let scene = ws
        .cx
        .scene
        .as_ref()
        .map(|s| s.spec.clone())
        .unwrap_or_default();
    let mut remove = None;
    let mut go = None;
    for (n, (i, bookmark)) in ws
        .cx
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
        ws.cx.camera.jump_to(pose);
    }
    if let Some(i) = remove {
        ws.cx.settings.bookmarks.remove(i);
    }
    ui.separator();
    if ui.button("Export bookmarks…").clicked() {
        ws.cx.export_bookmarks(ui.ctx());
    }
    if ui.button("Import bookmarks…").clicked() {
        ws.cx.import_bookmarks(ui.ctx());
    }
}

/// Layout, compared techniques, time, camera and export controls; its "?" opens the help
/// overlay (`help_open`).
pub(super) fn toolbar(ui: &mut egui::Ui, ws: &mut Workspace, help_open: &mut bool) {
    let ctx = ui.ctx().clone();
    egui::Panel::top("toolbar")
        .frame(egui::Frame::side_top_panel(ui.style()).inner_margin(egui::Margin::symmetric(8, 5)))
        .show_keyed(ui, "toolbar", |ui| {
            ui.horizontal(|ui| {
                for layout in Layout::ALL {
                    let tip = shortcut_hint(&ctx, Action::Layout(layout), layout.help());
                    ui.selectable_value(&mut ws.cx.settings.layout, layout, layout.label())
                        .on_hover_text(tip);
                }
                ui.separator();
                // In a scope of its own: the strip's widgets come and go with the compared
                // techniques, and the buttons after it keep their ids.
                style::keyed(ui, egui::Id::unique("toolbar: compared techniques"), |ui| {
                    compare_strip(ui, ws);
                });
                ui.separator();
                let (icon, tip) = if ws.cx.camera.playing {
                    ("Pause", "Pause time")
                } else {
                    ("Play", "Resume time")
                };
                if ui
                    .button(icon)
                    .on_hover_text(shortcut_hint(&ctx, Action::PlayPause, tip))
                    .clicked()
                {
                    ws.cx.toggle_play();
                }
                if ui
                    .button("Step")
                    .on_hover_text(shortcut_hint(&ctx, Action::Step, "Step one frame"))
                    .clicked()
                {
                    ws.cx.camera.playing = false;
                    ws.cx.camera.step();
                }
                let mut auto = ws.cx.camera.auto_rotate;
                if ui
                    .toggle_value(&mut auto, "Orbit")
                    .on_hover_text(shortcut_hint(&ctx, Action::AutoRotate, "Auto-rotate along the scene's camera path"))
                    .changed()
                {
                    ws.cx.camera.auto_rotate = auto;
                    ws.cx.settings.auto_rotate = auto;
                }
                if ui
                    .button("Reset view")
                    .on_hover_text(shortcut_hint(&ctx, Action::ResetView, "Reset the view"))
                    .clicked()
                {
                    ws.cx.camera.reset();
                }
                ui.separator();
                let resolution = match ws.cx.settings.resolution {
                    Resolution::FitViewport => "Fit".to_owned(),
                    Resolution::Fixed(w, h) => format!("{w}×{h}"),
                };
                egui::ComboBox::from_id_salt("resolution")
                    .width(90.0)
                    .selected_text(resolution)
                    .show_ui(ui, |ui| resolution_choices(ui, ws))
                    .response
                    .on_hover_text("Render resolution");
                ui.with_layout(egui::Layout::right_to_left(egui::Align::Center), |ui| {
                    let status = ws.export.status();
                    // Keyed: Cancel comes and goes before the others.
                    let key = |name: &str| egui::Id::unique(("toolbar", name));
                    if status.is_some()
                        && style::keyed(ui, key("cancel export"), |ui| ui.button("Cancel"))
                            .on_hover_text("Stop the export; the file being written is removed")
                            .clicked()
                    {
                        ws.export.cancel();
                    }
                    let label = status.unwrap_or_else(|| "Export".to_owned());
                    if style::keyed(ui, key("export"), |ui| {
                        ui.add_enabled(!ws.export.running(), Button::new(label))
                    })
                        .on_hover_text(shortcut_hint(
                            &ctx,
                            Action::Export,
                            &format!(
                                "Write every enabled technique's frame (PNG), the magnifier sheet and a sidecar JSON to {}",
                                ws.cx.settings.export_dir.display()
                            ),
                        ))
                        .clicked()
                    {
                        ws.cx.request(Command::ExportFrame);
                    }
                    if style::keyed(ui, key("help"), |ui| ui.button("?"))
                        .on_hover_text(shortcut_hint(&ctx, Action::Help, "Keyboard shortcuts"))
                        .clicked()
                    {
                        *help_open = true;
                    }
                });
            });
        });
}

/// The A/B/C/D chips of the compared techniques, with swap for the first two.
fn compare_strip(ui: &mut egui::Ui, ws: &mut Workspace) {
    let compared = ws.cx.compared();
    if compared.is_empty() {
        ui.weak("nothing to compare");
        return;
    }
    for (slot, id) in compared.iter().enumerate() {
        let name = ws.cx.shown_label(id);
        let letter = ws.cx.blind.letter(slot);
        ui.label(style::badge(letter, SLOT_COLORS[slot]))
            .on_hover_text(format!("Compared technique {letter}: {name}"));
        ui.label(name);
    }
    if ws.cx.images.is_open() {
        image_panel::strip(ui, &mut ws.cx);
    }
    if compared.len() >= 2
        && style::keyed(ui, egui::Id::unique("toolbar: swap"), |ui| {
            ui.small_button("swap A/B")
        })
        .on_hover_text("Swap A and B")
        .clicked()
    {
        if ws.cx.images.is_open() {
            ws.cx.images.swap_first_two();
            return;
        }
        let (a, b) = (compared[0].to_owned(), compared[1].to_owned());
        let mut order: Vec<String> = compared.iter().map(|s| (*s).to_owned()).collect();
        order[0] = b;
        order[1] = a;
        ws.cx.settings.compare = order;
    }
}

/// Adapter, software rendering, resolution, scene, frame, FPS and the latest notice; `hover`
/// is the frame pixel under the pointer (in the viewport or the magnifier).
pub(super) fn status_bar(ui: &mut egui::Ui, ws: &Workspace, hover: Option<(u32, u32)>) {
    egui::Panel::bottom("status bar")
        .frame(egui::Frame::side_top_panel(ui.style()).inner_margin(egui::Margin::symmetric(8, 3)))
        .show_keyed(ui, "status bar", |ui| {
            ui.horizontal(|ui| {
                let caps = &ws.cx.gpu.caps;
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
                let (w, h) = ws.cx.render_size;
                ui.label(RichText::new(format!("{w} × {h}")).small().monospace())
                    .on_hover_text("Render resolution of every technique (1:1 on screen)");
                if let Some(set) = ws.cx.images.open() {
                    ui.separator();
                    let (w, h) = set.size();
                    let paths: Vec<String> =
                        set.images().iter().map(|i| i.path.display().to_string()).collect();
                    ui.label(RichText::new(format!("{} image(s) · {w} × {h}", paths.len())).small())
                        .on_hover_text(paths.join("\n"));
                } else if let Some(scene) = &ws.cx.scene {
                    ui.separator();
                    ui.label(RichText::new(format!("{} · {} triangles", scene.name, scene.triangles)).small())
                        .on_hover_text(&scene.spec);
                }
                if let Some(spec) = ws.cx.loader.loading() {
                    ui.separator();
                    // Static text, not a spinner: an animation repaints the window every
                    // frame, which on a software rasteriser takes CPU from the work.
                    ui.label(RichText::new(format!("loading {spec}…")).small());
                }
                ui.separator();
                let frame = format!(
                    "frame {}{}",
                    ws.cx.camera.frame(),
                    if ws.cx.camera.playing { "" } else { " (paused)" }
                );
                ui.label(RichText::new(frame).small().monospace())
                    .on_hover_text("The animation clock and temporal jitter index; it advances once per rendered frame while playing.");
                // What comes and goes every few frames (the pixel under the pointer, the FPS,
                // "rendering…") keeps its place, hidden, so that the widgets after it keep their
                // ids: a widget egui has not seen in the previous frame asks for two more frames
                // (see `key_events.rs` for what a frame costs on a software rasteriser).
                let pixel = egui::UiBuilder::new();
                let pixel = if hover.is_some() { pixel } else { pixel.invisible() };
                ui.scope_builder(pixel, |ui| {
                    let (x, y) = hover.unwrap_or_default();
                    ui.separator();
                    ui.label(RichText::new(format!("pixel ({x}, {y})")).small().monospace());
                });
                let right = egui::UiBuilder::new()
                    .scope_id(ui.scope_id().with("status bar, right"))
                    .layout(egui::Layout::right_to_left(egui::Align::Center));
                ui.scope_builder(right, |ui| {
                    let window = std::time::Duration::from_secs(2);
                    let fps = ws.cx.clock.fps(window);
                    let (rate, ms) = fps.unwrap_or_default();
                    ui.add_visible(fps.is_some(), egui::Label::new(RichText::new(format!("{rate:.1} FPS · {}", style::ms(ms))).small().monospace()))
                        .on_hover_text("Rendered frames per second over the last 2 s (frames in which the techniques produced new images), and the median time between them.");
                    // Static, like the loading note (an animation would repaint continuously).
                    ui.add_visible(ws.cx.rendering(), egui::Label::new(RichText::new("rendering…").small().weak()))
                        .on_hover_text("A frame is being rendered; the interface keeps responding meanwhile.");
                    ui.separator();
                    if let Some(notice) = ws.cx.notices.last() {
                        let color = match notice.level {
                            Level::Info => ui.visuals().text_color(),
                            Level::Warning => style::WARN,
                            Level::Error => style::ERROR,
                        };
                        let all: Vec<String> = ws.cx.notices.iter().map(|n| n.text.clone()).collect();
                        ui.add(egui::Label::new(RichText::new(&notice.text).small().color(color)).truncate())
                            .on_hover_text(all.join("\n\n"));
                    }
                });
            });
        });
}
