//! The ColorVideoVDP parts of the metrics panel (the figures are the JOD feature's, jod.rs):
//! a pane's JOD as a table cell (the clip's table, the sequences' table), the sequences'
//! section with its button, and the controls under both: progress and cancel, the display
//! model, and the viewing distance as pixels per degree (persisted with the settings).
//! Functions of the [`Workspace`], owning nothing.

use egui::RichText;

use super::jod::JodScores;
use super::style::{self, number};
use super::workspace::Workspace;
use crate::metrics::jod::{self, JodScorer};

/// What the JOD column means.
pub(super) const JOD_HELP: &str = "ColorVideoVDP: how visible the difference from the \
    reference is to a person watching it on the chosen display, in JOD (10: none; one JOD \
    apart, 75 % of observers prefer the higher). Computed on a thread of its own.";

/// The JOD of pane `slot` as a table cell: the figure, why there is none, or that it is
/// being (or not yet) scored.
pub(super) fn figure_cell(ui: &mut egui::Ui, ws: &Workspace, slot: usize) {
    match ws.jod.figure(&ws.cx, slot) {
        Some(Ok(value)) => number(ui, format!("{value:.2}"), JOD_HELP),
        Some(Err(err)) => {
            ui.weak("n/a").on_hover_text(err);
        }
        None if ws.jod.started(&ws.cx) => {
            ui.weak("…").on_hover_text("being scored");
        }
        None => {
            ui.weak("–").on_hover_text("not scored yet");
        }
    }
}

/// The open sequences' JOD against the reference sequence, with the button that scores them.
pub(super) fn sequences_section(ui: &mut egui::Ui, ws: &mut Workspace) {
    let Some((names, reference)) = ws.cx.image_names() else {
        return;
    };
    style::section(ui, "Sequences: ColorVideoVDP");
    if !JodScores::scorable(&ws.cx) {
        ui.weak("needs two sequences or more");
        return;
    }
    style::figures_table(
        ui,
        "sequence jod table",
        &[("sequence", None), ("JOD", Some(JOD_HELP))],
        |ui| {
            for (slot, name) in names.iter().enumerate() {
                style::marked_name(ui, ws.cx.image_mark(slot), name);
                if slot == reference {
                    ui.weak("reference");
                } else {
                    figure_cell(ui, ws, slot);
                }
                ui.end_row();
            }
        },
    );
    controls(ui, ws, "sequences");
}

/// Progress with its cancel button (or the button that scores), the display model and the
/// viewing distance; `scope` names the table they are under (`clip`, `sequences`).
pub(super) fn controls(ui: &mut egui::Ui, ws: &mut Workspace, scope: &str) {
    // Keyed: the figures above the buttons arrive while they are shown.
    let buttons = egui::Id::unique(("colorvideovdp buttons", scope));
    style::keyed(ui, buttons, |ui| scoring_buttons(ui, ws));
    let settings = &mut ws.cx.settings;
    ui.horizontal(|ui| {
        ui.label("JOD display");
        egui::ComboBox::from_id_salt("jod display")
            .selected_text(settings.jod_display.as_str())
            .show_ui(ui, |ui| {
                for name in JodScorer::displays() {
                    ui.selectable_value(&mut settings.jod_display, name.to_owned(), name);
                }
            })
            .response
            .on_hover_text("The display model ColorVideoVDP predicts for: its size, resolution, viewing distance, peak luminance and room light.");
    });
    ui.horizontal(|ui| {
        let own = JodScorer::model_pixels_per_degree(&settings.jod_display);
        let mut set = settings.jod_pixels_per_degree.is_some();
        let help = format!(
            "Replace the display model's viewing distance, given as pixels per degree of visual angle (twice as far is about twice as many). The model's own: {}.",
            own.map_or_else(|| "unknown".to_owned(), |p| format!("{p:.1}"))
        );
        if ui
            .checkbox(&mut set, "Viewing distance")
            .on_hover_text(&help)
            .changed()
        {
            settings.jod_pixels_per_degree = set.then(|| own.unwrap_or(60.0));
        }
        if let Some(ppd) = &mut settings.jod_pixels_per_degree {
            ui.add(
                egui::DragValue::new(ppd)
                    .range(1.0..=jod::MAX_PIXELS_PER_DEGREE)
                    .speed(0.5)
                    .max_decimals(1)
                    .suffix(" px/°"),
            )
            .on_hover_text(help);
        } else {
            ui.weak(RichText::new("the model's").small());
        }
    });
}

/// Scoring's progress with its cancel button, or the button that starts it.
fn scoring_buttons(ui: &mut egui::Ui, ws: &mut Workspace) {
    let Some((done, total)) = ws.jod.progress() else {
        if ui
            .button("Score with ColorVideoVDP")
            .on_hover_text("Score every pane against the reference over all its frames, at the playback rate (seconds per pane; the frames are read on a thread of their own).")
            .clicked()
        {
            ws.jod.start(&ws.cx);
        }
        return;
    };
    ui.horizontal(|ui| {
        ui.add(
            egui::ProgressBar::new(done as f32 / total.max(1) as f32)
                .desired_width(180.0)
                .text(format!("ColorVideoVDP: {done}/{total} scored")),
        );
        if ui
            .button("Cancel scoring")
            .on_hover_text("Stop after the one being scored")
            .clicked()
        {
            ws.jod.cancel();
        }
    });
}
