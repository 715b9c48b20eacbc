//! [`Workspace`]: the viewer's shared [`Context`] and the features that own their state beside
//! it (the magnifier's heatmaps, the quality figures, the exports, the JOD of clips and sequences), and the carrying out of
//! what features ask of one another ([`Command`]).
//!
//! Every UI frame the app calls [`Workspace::poll_background`] and [`Workspace::update`]
//! before the panels and [`Workspace::run_commands`] after them. The panels (`panels.rs`,
//! `*_panel.rs`, `viewport.rs`) are the shell: they lay the features out and may read any of
//! them, while a feature only sees the context. This file is the one place that knows every
//! feature, so a command that needs two of them (an export with the magnifier sheet and the
//! quality figures under its panes) is composed here.

use std::collections::BTreeMap;

use super::context::{Command, Context};
use super::export::ExportState;
use super::jod::JodScores;
use super::magnifier::MagnifierState;
use super::quality::{Figures, QualityTracker};

/// The context and the features (see the module docs).
pub(super) struct Workspace {
    /// What every feature shares: settings, engine, scene, camera, image set, notices.
    pub(super) cx: Context,
    /// The magnifier's heatmaps.
    pub(super) magnifier: MagnifierState,
    /// The quality figures and their workers.
    pub(super) quality: QualityTracker,
    /// The running export and the files of the last one.
    pub(super) export: ExportState,
    /// The ColorVideoVDP figures and maps of the shown clip or sequences.
    pub(super) jod: JodScores,
}

impl Workspace {
    /// The workspace around `cx`, its features not started yet.
    pub(super) fn new(cx: Context) -> Self {
        Self {
            cx,
            magnifier: MagnifierState::default(),
            quality: QualityTracker::default(),
            export: ExportState::default(),
            jod: JodScores::default(),
        }
    }

    /// Takes what finished in the background: scene and image loads, file dialogs, dropped
    /// files, exports.
    pub(super) fn poll_background(&mut self, ctx: &egui::Context) {
        self.cx.poll_background(ctx);
        for (level, text) in self.export.poll() {
            self.cx.notify(level, text);
        }
        self.run_commands(ctx);
    }

    /// Advances what changes with time before the panels draw: the clip's or the sequences'
    /// player, the JOD figures, the quality figures and the magnifier's heatmaps.
    pub(super) fn update(&mut self, ctx: &egui::Context) {
        if let Some(engine) = &mut self.cx.engine {
            engine.set_overlay(self.cx.settings.ui_overlay);
            engine.set_tonemap(self.cx.settings.tonemap, self.cx.settings.exposure);
        }
        // Captured OpenEXR frames through a named tonemapper (captures are not known to be HDR:
        // `auto` clamps them, as `clip --sequence` does).
        let settings = &self.cx.settings;
        let capture_tonemap = settings.tonemap.resolve(false, settings.exposure);
        if let Some(sequences) = self.cx.images.sequences_mut() {
            sequences.set_tonemap(capture_tonemap);
        }
        self.cx.tick_clip(ctx);
        self.cx.tick_sequences(ctx);
        self.jod.update(&mut self.cx, ctx);
        self.cx.clip_jod = self.jod.published(&self.cx);
        self.cx.jod_maps = self.jod.maps(&self.cx);
        self.quality.update(&mut self.cx, ctx);
        self.magnifier.update(&mut self.cx, ctx);
    }

    /// Carries out the commands the features asked for.
    pub(super) fn run_commands(&mut self, ctx: &egui::Context) {
        for command in self.cx.take_commands() {
            match command {
                Command::ForgetMeasurements => {
                    self.quality.clear();
                    self.magnifier.clear();
                }
                Command::ExportFrame => {
                    let sheet = self
                        .cx
                        .settings
                        .show_magnifier
                        .then(|| self.magnifier_sheet())
                        .flatten();
                    self.export.start_export(&mut self.cx, sheet);
                }
                Command::ExportClip => self.export.export_clip(&mut self.cx),
                Command::CopySheet => {
                    let figures = self.pane_figures();
                    self.magnifier
                        .copy_sheet(&mut self.cx, ctx, &|id| figures.get(id).cloned());
                }
            }
        }
    }

    /// The quality figures of a technique that describe what is on screen now.
    pub(super) fn quality_figures(&self, id: &str) -> Option<Figures> {
        self.quality.figures(&self.cx, id)
    }

    /// The figures line under every compared pane (the magnifier's captions), by id.
    pub(super) fn pane_figures(&self) -> BTreeMap<&'static str, String> {
        self.cx
            .compared()
            .into_iter()
            .filter_map(|id| Some((id, self.quality.figures_text(&self.cx, id)?)))
            .collect()
    }

    /// The magnifier sheet of the current lens, composed with the figures under its panes.
    pub(super) fn magnifier_sheet(&self) -> Option<image::RgbaImage> {
        let figures = self.pane_figures();
        self.magnifier
            .sheet(&self.cx, &|id| figures.get(id).cloned())
    }
}
