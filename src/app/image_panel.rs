//! The panels of an open image set (image_set.rs): the left panel that replaces the
//! techniques while images are shown (the files or sequences in file order, each sequence's
//! frame offset, the reference, the way back to the scene), the reference choice in the
//! toolbar, and the quality table of the metrics panel (every image against the chosen
//! reference): stateless functions of the context ([`ui`], [`strip`]) and of the workspace
//! ([`quality_section`], which reads the figures). Every row is marked with its pane's letter,
//! or R for a reference that is no pane (a set of five: `Context::image_mark`).

use egui::RichText;

use super::context::Context;
use super::image_set::IMAGE_IDS;
use super::jod_panel;
use super::quality;
use super::style::{self, ShowKeyed, number, number_weak};
use super::workspace::Workspace;

/// What the reference of an image set is, for tooltips.
const REFERENCE_HELP: &str = "The image every other one is measured against (SSIM, PSNR, MAE, FLIP, the magnifier's heatmaps; hold R in the A/B flip layout to see it). By default the first file whose name has the word \"reference\" or \"ref\", else the first file.";

/// The reference combo box; `salt` tells its instances apart.
fn reference_choice(ui: &mut egui::Ui, cx: &mut Context, salt: &str) {
    let Some((names, reference)) = cx.image_names() else {
        return;
    };
    let mut chosen = reference;
    egui::ComboBox::from_id_salt(("image reference", salt))
        .selected_text(&names[reference])
        .show_ui(ui, |ui| {
            for (i, name) in names.iter().enumerate() {
                ui.selectable_value(&mut chosen, i, name);
            }
        })
        .response
        .on_hover_text(REFERENCE_HELP);
    if chosen != reference {
        cx.images.set_reference(chosen);
    }
}

/// The reference choice in the toolbar, after the compared images.
pub(super) fn strip(ui: &mut egui::Ui, cx: &mut Context) {
    ui.separator();
    ui.label(style::badge("R", style::REFERENCE_COLOR))
        .on_hover_text(REFERENCE_HELP);
    reference_choice(ui, cx, "toolbar");
}

/// The left panel while images are shown.
pub(super) fn ui(ui: &mut egui::Ui, cx: &mut Context) {
    let ctx = ui.ctx().clone();
    style::left_panel("images").show_keyed(ui, "images", |ui| {
        ui.add_space(4.0);
        ui.heading("Images");
        ui.separator();
        let Some(set) = cx.images.open() else {
            return;
        };
        let (w, h) = set.size();
        match set.sequences() {
            Some(sequences) => ui.label(format!(
                "{} sequence(s) of {} frames, {w} × {h} pixels",
                set.images().len(),
                sequences.len()
            )),
            None => ui.label(format!("{} image(s), {w} × {h} pixels", set.images().len())),
        };
        ui.add_space(4.0);
        let rows: Vec<(String, String)> = set
            .images()
            .iter()
            .enumerate()
            .map(|(slot, i)| {
                let shown = set.sequences().and_then(|s| s.shown_path(slot));
                let path = shown.unwrap_or(&i.path).display().to_string();
                (i.name.clone(), path)
            })
            .collect();
        for (slot, (name, path)) in rows.iter().enumerate() {
            let label = cx
                .image_label(IMAGE_IDS[slot])
                .unwrap_or_else(|| name.clone());
            style::marked_name(ui, cx.image_mark(slot), label).on_hover_text(path);
            offset_field(ui, cx, slot);
        }
        ui.add_space(6.0);
        ui.horizontal(|ui| {
            ui.label("Reference").on_hover_text(REFERENCE_HELP);
            reference_choice(ui, cx, "panel");
        });
        ui.add_space(6.0);
        ui.label(
            RichText::new(
                "The panes, layouts, magnifier, heatmaps and quality figures show these \
                     images as they show technique outputs; the scene is not rendered \
                     meanwhile.",
            )
            .small()
            .weak(),
        );
        ui.add_space(6.0);
        // Keyed: the figures above change as they are measured.
        style::keyed(ui, egui::Id::unique("image panel: open and close"), |ui| {
            ui.horizontal(|ui| {
                if cx.images.has_sequences() {
                    if ui.button("Open other sequences…").clicked() {
                        cx.open_sequences_dialog(&ctx);
                    }
                } else if ui.button("Open other images…").clicked() {
                    cx.open_images_dialog(&ctx);
                }
                let back = match &cx.scene {
                    Some(scene) => format!("Back to {}", scene.name),
                    None => "Close images".to_owned(),
                };
                if ui
                    .button(back)
                    .on_hover_text("Close the images and show the scene again")
                    .clicked()
                {
                    cx.close_images();
                }
            })
        });
    });
}

/// The frame offset of sequence `slot` of an open sequence set (nothing for still images).
fn offset_field(ui: &mut egui::Ui, cx: &mut Context, slot: usize) {
    let Some(sequences) = cx.images.sequences_mut() else {
        return;
    };
    let mut offset = sequences.offset(slot);
    let max = sequences.max_offset(slot);
    ui.horizontal(|ui| {
        ui.add_space(24.0);
        ui.label("offset");
        let field = ui
            .add(egui::DragValue::new(&mut offset).range(0..=max).suffix(" frames"))
            .on_hover_text("Frames of this sequence skipped at its start, so that captures which begin on different frames line up: at every instant it shows its frame (instant + offset)");
        if field.changed() {
            sequences.set_offset(slot, offset);
        }
    });
}

/// The metrics panel's quality section while images are shown.
pub(super) fn quality_section(ui: &mut egui::Ui, ws: &mut Workspace) {
    style::section(ui, "Quality against the reference");
    ui.checkbox(&mut ws.cx.settings.quality, "Measure")
        .on_hover_text("Score every image against the reference image.");
    ui.horizontal(|ui| {
        ui.label("Reference");
        reference_choice(ui, &mut ws.cx, "metrics");
    });
    let Some((names, reference)) = ws.cx.image_names() else {
        return;
    };
    let (missing, missing_tip) = if ws.cx.settings.quality {
        ("…", "Being measured in the background.")
    } else {
        ("off", "Measuring is off.")
    };
    let mut notes = Vec::new();
    style::figures_table(
        ui,
        "image quality table",
        &[
            ("image", None),
            ("SSIM", None),
            ("PSNR", None),
            ("MAE", None),
            ("FLIP", None),
        ],
        |ui| {
            for (slot, name) in names.iter().enumerate() {
                style::marked_name(ui, ws.cx.image_mark(slot), name);
                if slot == reference {
                    ui.weak("reference").on_hover_text(REFERENCE_HELP);
                    ui.end_row();
                    continue;
                }
                let id = IMAGE_IDS[slot];
                let key = ws.cx.measure_key(id);
                match ws.quality.current_pixels(id, key) {
                    Some(m) => match &m.value {
                        Ok(f) => {
                            let how =
                                format!("\n\nMeasured on the {} in {}.", m.on, style::ms(m.ms));
                            number(
                                ui,
                                format!("{:.4}", f.ssim),
                                &(image_help(
                                    "SSIM of BT.601 luma, Gaussian 11x11 window; 1 = identical.",
                                ) + &how),
                            );
                            number(
                                ui,
                                quality::psnr_text(f.psnr),
                                &(image_help("PSNR of R'G'B' in dB; ∞ = identical.") + &how),
                            );
                            number(
                                ui,
                                format!("{:.3}", f.mae),
                                &(image_help("Mean absolute error of R'G'B', 0..255.") + &how),
                            );
                        }
                        Err(err) => {
                            for _ in 0..3 {
                                number_weak(ui, "error", err);
                            }
                            notes.push(format!("{name}: {err}"));
                        }
                    },
                    None => {
                        for _ in 0..3 {
                            number_weak(ui, missing, missing_tip);
                        }
                    }
                }
                match ws.quality.current_flip(id, key).map(|m| &m.value) {
                    Some(Ok(v)) => number(
                        ui,
                        format!("{v:.4}"),
                        &image_help("Mean of NVIDIA's FLIP (LDR) error; 0 = indistinguishable."),
                    ),
                    Some(Err(err)) => number_weak(ui, "error", err),
                    None => number_weak(
                        ui,
                        missing,
                        "FLIP is computed on the CPU, after the others.",
                    ),
                }
                ui.end_row();
            }
        },
    );
    for note in notes {
        ui.label(RichText::new(note).small().color(style::ERROR));
    }
    played_section(ui, &ws.cx, &names, reference);
    if ws.cx.images.has_sequences() {
        ui.separator();
        jod_panel::sequences_section(ui, ws);
    }
}

/// The temporal figures of the sequences' frames played in a row (sequence sets only).
fn played_section(ui: &mut egui::Ui, cx: &Context, names: &[String], reference: usize) {
    let Some(run) = cx
        .images
        .open()
        .and_then(|set| set.sequences())
        .and_then(|s| s.played())
        .filter(|run| run.reference == reference && run.frames >= 2)
    else {
        return;
    };
    ui.add_space(6.0);
    ui.label(
        RichText::new(format!(
            "Over the last {} frames played in a row",
            run.frames
        ))
        .small()
        .weak(),
    )
    .on_hover_text("Measured as the frames are read while playing or stepping forward; a jump, the end of the sequences, another offset or reference starts again.");
    style::figures_table(
        ui,
        "sequence temporal table",
        &[
            ("sequence", None),
            ("instability", None),
            ("ghosting", None),
        ],
        |ui| {
            let others = (0..names.len()).filter(|pane| *pane != reference);
            for (pane, scores) in others.zip(&run.scores) {
                style::marked_name(ui, cx.image_mark(pane), &names[pane]);
                let figure = |value: Option<f64>| {
                    value.map_or_else(|| "–".to_owned(), |v| format!("{v:.3}"))
                };
                number(
                    ui,
                    figure(scores.temporal_instability),
                    "Mean luma change per frame over the reference's: 1 = it changes as much as the reference; above 1 it shimmers, below 1 it is steadier (usually blurrier).",
                );
                number(
                    ui,
                    figure(scores.ghosting),
                    "Mean absolute luma error against the reference on the pixels that moved, 0..255: lag and trails.",
                );
                ui.end_row();
            }
        },
    );
}

/// A figure's tooltip: what it measures, against the reference image.
fn image_help(what: &str) -> String {
    format!("{what} Measured against the reference image, as decoded from its file.")
}
