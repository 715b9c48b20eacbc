//! The techniques panel (left side): every registry technique with its switch, comparison
//! mark, presets, parameters, debug views and trade-off tooltip, unavailable ones greyed out
//! with the reason, the user techniques with their files' errors, the combinations added, and
//! the Render scale form (scale_form.rs). A stateless function of the context; while an image
//! set is open the images panel (image_panel.rs) takes its place.

use egui::{Button, Color32, RichText};

use super::context::{Context, Level};
use super::image_panel;
use super::scale_form;
use super::settings::MAX_COMPARE;
use super::style::{self, SLOT_COLORS, SLOT_LETTERS, ShowKeyed};
use crate::aa::{Param, ParamKind, ParamValue};

/// Every registry technique with its switch, comparison mark and settings.
pub(super) fn ui(ui: &mut egui::Ui, cx: &mut Context) {
    profiling::function_scope!();
    if cx.images.is_open() {
        image_panel::ui(ui, cx);
        return;
    }
    style::left_panel("techniques").show_keyed(ui, "techniques", |ui| {
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
                let ids: Vec<&'static str> = cx
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
                    technique_row(ui, cx, id, &mut number);
                }
                if cx.engine.is_none() {
                    ui.weak("The techniques appear once the scene is loaded.");
                    return;
                }
                ui.add_space(4.0);
                scale_form::ui(ui, cx);
                ui.add_space(4.0);
                let add_from_file = egui::Id::unique("techniques panel: add from file");
                if style::keyed(ui, add_from_file, |ui| {
                    ui.small_button("Add technique from file…")
                })
                .on_hover_text(USER_TECHNIQUE_HINT)
                .clicked()
                {
                    let ctx = ui.ctx().clone();
                    cx.add_technique_dialog(&ctx);
                }
            });
        });
}

fn technique_row(ui: &mut egui::Ui, cx: &mut Context, id: &'static str, number: &mut usize) {
    let Some(engine) = &cx.engine else { return };
    let Some(entry) = engine.entry(id) else {
        return;
    };
    let (name, summary, available, reason, enabled, problem, compiling) = (
        entry.name,
        entry.summary,
        entry.available(),
        entry.availability.clone().err(),
        entry.enabled,
        entry.problem.clone(),
        entry.compiling_for(),
    );
    let switchable = entry.switchable();
    let key = if available {
        *number += 1;
        (*number <= 9).then(|| number.to_string())
    } else {
        None
    };
    let compared = cx.compared();
    let slot = compared.iter().position(|c| *c == id);
    let mut toggled = None;
    let mut compare_clicked = false;
    let mut remove_clicked = false;
    let user = super::engine::is_added(id);
    let frame = egui::Frame::new()
        .inner_margin(egui::Margin::symmetric(4, 3))
        .corner_radius(4)
        .fill(if enabled {
            Color32::from_gray(38)
        } else {
            Color32::TRANSPARENT
        });
    // Keyed by the technique: rows come and go above it (user techniques, combinations).
    style::keyed(ui, egui::Id::unique(("technique row", id)), |ui| {
        frame.show(ui, |ui| {
            ui.horizontal(|ui| {
                let mut on = enabled;
                let tip = match &key {
                    Some(k) => format!("{summary}\n\nKey {k} switches it on or off."),
                    None => summary.to_owned(),
                };
                let response = ui
                    .add_enabled(
                        switchable,
                        egui::Checkbox::new(&mut on, RichText::new(name).strong()),
                    )
                    .on_hover_text(tip);
                let response = match &reason {
                    Some(reason) => response.on_disabled_hover_text(format!("Unavailable: {reason}")),
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
                                "Remove this technique (a user technique's file stays on disk; \
                                 add it again to bring it back)",
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
                                Some(s) => {
                                    format!("Compared as {}; click to stop comparing", SLOT_LETTERS[s])
                                }
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
            if let Some(elapsed) = compiling {
                compiling_note(ui, elapsed);
            }
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
                        &format!(
                            "The last change does not build; the previous build still runs: {problem}"
                        ),
                    );
                }
                if enabled {
                    technique_settings(ui, cx, id);
                }
            }
        })
    });
    if let Some(on) = toggled {
        cx.set_technique_enabled(id, on);
    }
    if compare_clicked {
        cx.toggle_compare(id);
    }
    if remove_clicked {
        cx.remove_user_technique(id);
    }
}

/// "compiling... Ns" under a user technique whose build is running (the other techniques go on
/// rendering meanwhile); the row is redrawn every second while it lasts.
fn compiling_note(ui: &mut egui::Ui, elapsed: std::time::Duration) {
    ui.label(
        RichText::new(format!("compiling... {}s", elapsed.as_secs()))
            .small()
            .italics(),
    )
    .on_hover_text(
        "The GPU driver is compiling this technique's shader; the other techniques keep \
         rendering, and this one appears (or its previous build is replaced) when it is done.",
    );
    ui.ctx()
        .request_repaint_after(std::time::Duration::from_secs(1));
}

/// Presets, parameters, debug views and code path of an enabled technique.
fn technique_settings(ui: &mut egui::Ui, cx: &mut Context, id: &'static str) {
    let Some(engine) = &cx.engine else { return };
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
    if let Some(engine) = &mut cx.engine {
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
                    cx.settings.debug_views.insert(id.to_owned(), v);
                }
                None => {
                    cx.settings.debug_views.remove(id);
                }
            }
        }
    }
    cx.remember_params(id);
    for err in failed {
        cx.notify(Level::Error, err);
    }
}

/// What "Add technique from file" does, for its tooltips.
pub(super) const USER_TECHNIQUE_HINT: &str = "Run your own post-process pass, written in WGSL, beside the \
     built-in techniques, with the same metrics and exports (docs/user-techniques.md in \
     aa-lab's repository); it is rebuilt whenever the file changes";

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
