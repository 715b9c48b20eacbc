//! The clip bar above the status bar (record, play, scrub, export) and what its buttons ask
//! of the context (`context/clip.rs` records the compared techniques along the chosen camera
//! path within the memory cap, shows the clip or the live view, ticks playback) or, for an
//! export, of the workspace (a `Command`). While a sequence set is open (`sequence_set.rs`)
//! the bar is its transport: the same playback controls on the sequences' player.

use egui::RichText;

use super::context::{Command, Context};
use super::engine::{Clip, ClipPath, ClipPlayer, ClipSettings, ClipStatus, MAX_FRAMES, PlayRate};
use super::sequence_set::{CACHE_FRAMES, SequenceSet};
use super::style::{self, ShowKeyed, whole_mib};

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
            if recipe_controls(ui, settings) {
                action = Some(ClipAction::Record);
            }
        });
        if let Some(bytes) = estimate {
            ui.label(
                RichText::new(format!("≈ {}", whole_mib(bytes)))
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
            if bar_button(ui, "clip bar", "Cancel").clicked() {
                action = Some(ClipAction::Cancel);
            }
        }
        if count == 0 {
            return;
        }
        if !shown {
            if bar_button(ui, "clip bar", "Show clip").clicked() {
                action = Some(ClipAction::ShowClip);
            }
        } else {
            playback_controls(ui, "clip bar", &mut clip.player, count);
            if bar_button(ui, "clip bar", "Live").on_hover_text("Back to the live view (the clip stays)").clicked() {
                action = Some(ClipAction::ShowLive);
            }
        }
        if !recording {
            if bar_button(ui, "clip bar", "Export…").on_hover_text("Write the clip as a looping animated PNG and a self-contained HTML comparison page, with its record").clicked() {
                action = Some(ClipAction::Export);
            }
            if bar_button(ui, "clip bar", "Discard").clicked() {
                action = Some(ClipAction::Discard);
            }
        }
        let status = match &clip.status {
            ClipStatus::Recording(_) => format!("{:.0} s", clip.seconds()),
            ClipStatus::Complete => String::new(),
            ClipStatus::Cancelled => "cancelled".to_owned(),
            ClipStatus::Failed(reason) => format!("failed: {reason}"),
        };
        let text = format!("{} · {}{}", clip.description, whole_mib(clip.bytes), if status.is_empty() { String::new() } else { format!(" · {status}") });
        ui.label(RichText::new(text).small().color(if matches!(clip.status, ClipStatus::Failed(_)) { style::ERROR } else { ui.visuals().weak_text_color() }));
    });
    action
}

/// The Record button and what a recording takes: the camera path, frames, speed and the
/// reference; returns whether Record was pressed.
fn recipe_controls(ui: &mut egui::Ui, settings: &mut ClipSettings) -> bool {
    let record = ui
        .button("Record")
        .on_hover_text("Render the camera path through the compared techniques and keep the frames for playback")
        .clicked();
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
    record
}

/// A button of a bar, keyed by the bar and its text ([`style::keyed`]): the widgets before it
/// come and go (the recipe's options, the progress, the playback rate warning).
fn bar_button(ui: &mut egui::Ui, bar: &str, text: &str) -> egui::Response {
    style::keyed(ui, egui::Id::unique((bar, text)), |ui| ui.button(text))
}

/// Play and pause, single steps, the scrubber, the rate and ping-pong of a shown clip of
/// `count` frames, in the bar named `bar`.
fn playback_controls(ui: &mut egui::Ui, bar: &str, player: &mut ClipPlayer, count: usize) {
    // Keyed by the bar: what comes before the controls changes (a recording's progress),
    // their own widgets do not, but for the rate warning at the end.
    style::keyed(ui, egui::Id::unique(("playback controls", bar)), |ui| {
        let play = if player.playing {
            "Pause clip"
        } else {
            "Play clip"
        };
        if ui
            .button(play)
            .on_hover_text("Play or pause (Space)")
            .clicked()
        {
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
        // Keyed: the ids before it shifted while a recording's first frames arrived (the UI
        // tests' id check found it).
        style::keyed(ui, egui::Id::unique(("ping-pong", bar)), |ui| {
            ui.checkbox(&mut player.ping_pong, "ping-pong")
        });
        if let Some(shown) = player
            .shown_fps()
            .filter(|fps| *fps < 0.95 * player.rate.fps())
        {
            ui.label(RichText::new(format!("shown at {shown:.0} fps")).small().color(style::WARN))
                .on_hover_text("The window paints fewer frames per second than the clip's rate: every frame is shown, more slowly");
        }
    });
}

/// The bar's frame: a bottom panel above the status bar.
fn bar(ui: &egui::Ui) -> egui::Panel {
    egui::Panel::bottom("clip bar")
        .frame(egui::Frame::side_top_panel(ui.style()).inner_margin(egui::Margin::symmetric(8, 4)))
}

/// The transport of an open sequence set: its playback controls and what it holds.
fn sequence_bar(ui: &mut egui::Ui, sequences: &mut SequenceSet) {
    bar(ui).show_keyed(ui, "sequence bar", |ui| {
        ui.horizontal_wrapped(|ui| {
            ui.label(RichText::new("Sequences").strong());
            let count = sequences.len();
            if !sequences.is_empty() {
                playback_controls(ui, "sequence bar", &mut sequences.player, count);
            }
            let Some(first) = sequences.sequences().first() else {
                return;
            };
            let (w, h) = first.size();
            let cache = (CACHE_FRAMES * sequences.sequences().len()) as u64 * u64::from(w) * u64::from(h) * 4;
            ui.label(
                RichText::new(format!("{count} frames · {w}x{h} · frames read as they play, at most {} decoded", whole_mib(cache)))
                    .small()
                    .color(ui.visuals().weak_text_color()),
            )
            .on_hover_text("Each sequence keeps its last few decoded frames; the others stay on disk until the playhead reaches them");
        });
    });
}

/// The clip bar (a bottom panel above the status bar) and what its buttons ask for; the
/// sequences' transport while a sequence set is open.
pub(in crate::app) fn panel(ui: &mut egui::Ui, cx: &mut Context) {
    if let Some(sequences) = cx.images.sequences_mut() {
        sequence_bar(ui, sequences);
        return;
    }
    let images = cx.compared().len() + usize::from(cx.settings.clip.reference);
    let estimate = cx.settings.clip.bytes(images, cx.render_size);
    let Some(engine) = &mut cx.engine else {
        return;
    };
    let shown = engine.clip_shown();
    let settings = &mut cx.settings.clip;
    let action = bar(ui)
        .show_keyed(ui, "clip bar", |ui| {
            clip_bar(ui, settings, engine.clip_mut(), shown, Some(estimate))
        })
        .inner;
    match action {
        Some(ClipAction::Record) => cx.record_clip(),
        Some(ClipAction::Cancel) => {
            if let Some(clip) = engine.clip() {
                clip.cancel();
            }
        }
        Some(ClipAction::ShowLive) => cx.show_clip(false),
        Some(ClipAction::ShowClip) => cx.show_clip(true),
        Some(ClipAction::Discard) => {
            if let Some(engine) = &mut cx.engine {
                engine.discard_clip();
            }
        }
        Some(ClipAction::Export) => cx.request(Command::ExportClip),
        None => {}
    }
}
