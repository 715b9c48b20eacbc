//! The context's image-set commands (File > Open images, File > Open sequences, files and
//! folders dropped on the window): opening a set of images or sequences on the loader thread
//! and showing it in place of the techniques once it has loaded, playing a sequence set,
//! closing it. A set holds up to five: four compared and a reference (`image_set.rs`).

use std::path::PathBuf;

use super::{Command, Context, DialogPurpose, Level};
use crate::app::image_set::{MAX_IMAGES, SetKind, is_image_file, too_many};
use crate::sequence::is_sequence_path;

impl Context {
    /// Opens up to five images of one size as panes and reference (File > Open images,
    /// dropped images, and tests): they are decoded on a worker thread and replace what is shown when they all
    /// load; otherwise a notice says why, and what was shown stays.
    pub(in crate::app) fn open_images(&mut self, ctx: &egui::Context, paths: Vec<PathBuf>) {
        self.open_set(ctx, SetKind::Images, paths);
    }

    /// Opens up to five image sequences of one frame size as panes and reference (File > Open
    /// sequences, dropped folders, and tests): their first frames are read on a worker thread and
    /// replace what is shown when they have; otherwise a notice says why (naming the sequence
    /// at fault), and what was shown stays.
    pub(in crate::app) fn open_sequences(&mut self, ctx: &egui::Context, paths: Vec<PathBuf>) {
        self.open_set(ctx, SetKind::Sequences, paths);
    }

    /// Opens `paths` as a set of `kind`, at most [`MAX_IMAGES`] of them.
    fn open_set(&mut self, ctx: &egui::Context, kind: SetKind, paths: Vec<PathBuf>) {
        let noun = kind.noun();
        if paths.len() > MAX_IMAGES {
            let why = too_many(paths.len(), kind);
            self.notify(Level::Error, format!("{why}: nothing was opened"));
            return;
        }
        if paths.is_empty() {
            return;
        }
        let max_side = self.gpu.caps.max_texture_dimension_2d;
        if let Err(err) = self.images.start_load(kind, paths, max_side, ctx.clone()) {
            self.notify(
                Level::Error,
                format!("cannot open {noun}: no thread ({err})"),
            );
        }
    }

    /// Asks the OS for up to five folders of numbered frames to open as sequences.
    pub(in crate::app) fn open_sequences_dialog(&mut self, ctx: &egui::Context) {
        self.ask_for_paths(ctx, DialogPurpose::OpenSequences, || {
            rfd::FileDialog::new()
                .set_title(
                    "Open up to five folders of numbered frames (PNG, JPEG, OpenEXR): up to four \
                     to compare and their reference",
                )
                .pick_folders()
        });
    }

    /// Advances a shown sequence set's playback (called once per UI frame).
    pub(in crate::app) fn tick_sequences(&mut self, ctx: &egui::Context) {
        if let Some(err) = self.images.tick_sequences(ctx) {
            self.notify(
                Level::Error,
                format!("{err}; playback stopped, the frames shown stay"),
            );
        }
    }

    /// Closes the image set: the scene shows again.
    pub(in crate::app) fn close_images(&mut self) {
        if self.images.close() {
            self.request(Command::ForgetMeasurements);
            self.camera.cut();
        }
    }

    /// Shows a finished load (called once per UI frame).
    pub(in crate::app) fn finish_image_load(&mut self) {
        match self.images.finish_load() {
            None => {}
            Some(Err(err)) => {
                let kept = if self.images.is_open() {
                    "the open images stay"
                } else {
                    "the scene stays"
                };
                self.notify(Level::Error, format!("{err}; {kept}"));
            }
            Some(Ok((text, notes))) => {
                self.request(Command::ForgetMeasurements);
                for note in notes {
                    self.notify(Level::Warning, note);
                }
                self.notify(Level::Info, text);
            }
        }
    }

    /// Opens dropped files: folders as sequences, images as an image set, a model as the
    /// scene.
    pub(in crate::app) fn open_dropped(&mut self, ctx: &egui::Context, paths: Vec<PathBuf>) {
        let folders = paths.iter().filter(|p| is_sequence_path(p)).count();
        if folders == paths.len() {
            self.open_sequences(ctx, paths);
            return;
        }
        if folders > 0 {
            self.notify(
                Level::Error,
                "Dropped folders and files together: drop up to five folders of frames (sequences), up to five images, or one model",
            );
            return;
        }
        let scenes: Vec<&PathBuf> = paths
            .iter()
            .filter(|p| crate::scene::source::is_scene_file(p))
            .collect();
        let any_image = paths.iter().any(|p| is_image_file(p));
        match (any_image, scenes.last()) {
            (true, Some(_)) => self.notify(
                Level::Error,
                "Dropped images and a model together: drop up to five images, or one model",
            ),
            (true, None) => self.open_images(ctx, paths),
            (false, _) => {
                if let Some(path) = paths.last() {
                    self.open_scene(ctx, &path.display().to_string());
                }
            }
        }
    }
}
