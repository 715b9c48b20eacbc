//! The blind comparison's panel and keys (which pane looks better: a digit, or the
//! buttons), returned as a [`BlindAction`] that the context carries out
//! (`context/blind.rs`: starting a session from the compared techniques, answering a trial
//! with what was on screen, moving to the next trial).

use super::*;
use crate::app::key_events::take_press;
use crate::app::style::ShowKeyed;

impl BlindState {
    /// The keys of a session, taken out of `events`: digits answer (0: no preference), Enter
    /// goes on after a reveal. They are taken before the shortcuts, so the number keys do not
    /// switch techniques meanwhile. The caller checks that no text field has keyboard focus.
    pub(in crate::app) fn take_keys(&self, events: &mut Vec<egui::Event>) -> Option<BlindAction> {
        if !self.active() {
            return None;
        }
        let mut action = None;
        for (digit, key) in DIGIT_KEYS.iter().enumerate() {
            if take_press(events, Modifiers::NONE, *key) {
                action = Some(BlindAction::Answer(match digit {
                    0 => Choice::NoPreference,
                    n => Choice::Pane(n - 1),
                }));
            }
        }
        if take_press(events, Modifiers::NONE, Key::Enter) {
            action = Some(BlindAction::Next);
        }
        action
    }

    /// The session's panel: the question, the answers, the reveal, the summary and the file.
    pub fn ui(&mut self, ui: &mut egui::Ui) -> Option<BlindAction> {
        self.poll();
        let reveal = &mut self.reveal;
        let session = self.session.as_ref()?;
        let mut action = None;
        let panes = session.order.len();
        style::section(ui, "Blind comparison");
        let trial = session.trials.len() + usize::from(!session.revealed);
        ui.label(RichText::new(format!("Trial {trial}")).strong());
        ui.label("Which pane looks better?");
        ui.add_enabled_ui(!session.revealed, |ui| {
            ui.horizontal_wrapped(|ui| {
                for pane in 0..panes {
                    let text = RichText::new(format!(" {} ", PANE_NUMBERS[pane]))
                        .strong()
                        .color(egui::Color32::BLACK);
                    if ui
                        .add(Button::new(text).fill(SLOT_COLORS[pane]))
                        .on_hover_text(format!("Pane {} looks better (key {})", pane + 1, pane + 1))
                        .clicked()
                    {
                        action = Some(BlindAction::Answer(Choice::Pane(pane)));
                    }
                }
                if ui
                    .button("No preference")
                    .on_hover_text("None looks better than the others (key 0)")
                    .clicked()
                {
                    action = Some(BlindAction::Answer(Choice::NoPreference));
                }
            });
        });
        ui.weak(format!(
            "Keys 1–{panes} (0: no preference), or click a pane in the view or the magnifier. \
             Judge a still frame, or record a clip and judge it playing."
        ));
        ui.checkbox(reveal, "Reveal the techniques after each answer");
        if session.revealed
            && let Some(last) = session.trials.last()
        {
            ui.add_space(4.0);
            ui.label(match last.pane {
                Some(pane) => format!("Trial {}: you chose pane {pane}", last.trial),
                None => format!("Trial {}: no preference", last.trial),
            });
            for (pane, id) in last.panes.iter().enumerate() {
                let text = format!("{}  {}", PANE_NUMBERS[pane], session.name(id));
                let chosen = last.pane == Some(pane + 1);
                ui.label(if chosen {
                    RichText::new(text).strong()
                } else {
                    RichText::new(text)
                });
            }
            if ui.button("Next trial (Enter)").clicked() {
                action = Some(BlindAction::Next);
            }
        } else if let Some(last) = session.trials.last() {
            ui.weak(format!(
                "Answer to trial {} recorded; the panes are reshuffled.",
                last.trial
            ));
        }
        ui.separator();
        let summary = session.summary();
        ui.label(format!(
            "{} answers, {} without preference",
            summary.trials, summary.ties
        ));
        egui::CollapsingHeader::new("Wins per technique")
            .default_open(false)
            .show(ui, |ui| {
                ui.weak("(shows which technique each answer chose)");
                egui::Grid::new("blind wins").striped(true).show(ui, |ui| {
                    for heading in ["technique", "wins", "still", "in motion"] {
                        ui.weak(heading);
                    }
                    ui.end_row();
                    for wins in &summary.wins {
                        ui.label(&wins.name);
                        for n in [wins.wins, wins.still, wins.in_motion] {
                            ui.monospace(n.to_string());
                        }
                        ui.end_row();
                    }
                });
            });
        ui.separator();
        ui.label(
            RichText::new(format!("seed {}", session.seed))
                .small()
                .monospace(),
        )
        .on_hover_text("Every trial's order follows from the seed; the file records both");
        match &session.saved {
            Ok(answers) => ui.label(
                RichText::new(format!(
                    "{} ({answers} answers saved)",
                    session.path.display()
                ))
                .small(),
            ),
            Err(err) => ui.label(RichText::new(err).small().color(style::ERROR)),
        };
        if ui
            .button("End session")
            .on_hover_text("Show the names again; the answers file stays")
            .clicked()
        {
            action = Some(BlindAction::End);
        }
        action
    }
}

/// The session's panel, in place of the techniques and metrics panels.
pub(in crate::app) fn panel(ui: &mut egui::Ui, blind: &mut BlindState) -> Option<BlindAction> {
    egui::Panel::right("blind comparison")
        .resizable(true)
        .default_size(280.0)
        .size_range(220.0..=480.0)
        .show_keyed(ui, "blind comparison", |ui| {
            egui::ScrollArea::vertical()
                .show(ui, |ui| blind.ui(ui))
                .inner
        })
        .inner
}
