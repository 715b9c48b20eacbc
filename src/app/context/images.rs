//! The context's image-set commands (File > Open images, files dropped on the window): opening
//! a set on the loader thread and showing it in place of the techniques once it has loaded,
//! closing it, choosing its reference and swapping the first two images.

use std::path::PathBuf;

use std::sync::mpsc;

use super::{Command, Context, Level};
use crate::app::engine::{ImageStamp, Published};
use crate::app::image_set::{
    ImageSet, MAX_IMAGES, SetImage, decode, default_reference, file_name, is_image_file,
};
use crate::app::render_thread::RenderedImage;

impl Context {
    /// Opens up to four images of one size as panes (File > Open images, dropped images, and
    /// tests): they are decoded on a worker thread and replace what is shown when they all
    /// load; otherwise a notice says why, and what was shown stays.
    pub(in crate::app) fn open_images(&mut self, ctx: &egui::Context, paths: Vec<PathBuf>) {
        if paths.len() > MAX_IMAGES {
            self.notify(
                Level::Error,
                format!(
                    "{} images chosen; aa-lab compares at most {MAX_IMAGES}: nothing was opened",
                    paths.len()
                ),
            );
            return;
        }
        if paths.is_empty() {
            return;
        }
        let (sender, receiver) = mpsc::channel();
        let max_side = self.gpu.caps.max_texture_dimension_2d;
        let wake = ctx.clone();
        let files = paths.clone();
        let uploader = self.images.uploader.clone();
        let spawned = std::thread::Builder::new()
            .name("aa-lab image decoder".to_owned())
            .spawn(move || {
                let uploaded = decode(&files, max_side).map(|decoded| {
                    let images = decoded
                        .images
                        .into_iter()
                        .map(|image| {
                            let texture = uploader.upload(&image.pixels);
                            let rendered = RenderedImage {
                                pixels: image.pixels,
                                texture,
                            };
                            (image.path, rendered)
                        })
                        .collect();
                    uploader.flush();
                    (images, decoded.notes)
                });
                let _ = sender.send(uploaded);
                crate::app::request_one_frame(&wake);
            });
        match spawned {
            // A newer request supersedes one still decoding.
            Ok(_) => self.images.pending = Some((paths, receiver)),
            Err(err) => self.notify(
                Level::Error,
                format!("cannot decode images: no thread ({err})"),
            ),
        }
    }

    /// Closes the image set: the scene shows again.
    pub(in crate::app) fn close_images(&mut self) {
        if self.images.open.take().is_some() {
            self.request(Command::ForgetMeasurements);
            self.camera.cut();
        }
    }

    /// Makes image `index` of the open set the reference.
    pub(in crate::app) fn set_image_reference(&mut self, index: usize) {
        let view = self.images.next_serial();
        if let Some(set) = &mut self.images.open
            && index < set.images.len()
            && index != set.reference
        {
            set.reference = index;
            set.restamp(view);
        }
    }

    /// Swaps the first two images (A and B).
    pub(in crate::app) fn swap_images(&mut self) {
        let view = self.images.next_serial();
        if let Some(set) = &mut self.images.open
            && set.images.len() >= 2
        {
            set.images.swap(0, 1);
            set.reference = match set.reference {
                0 => 1,
                1 => 0,
                other => other,
            };
            set.restamp(view);
        }
    }

    /// Shows a finished load (called once per UI frame).
    pub(in crate::app) fn finish_image_load(&mut self) {
        let Some(answer) = self.images.poll() else {
            return;
        };
        let (loaded, notes) = match answer {
            Ok(uploaded) => uploaded,
            Err(err) => {
                let kept = if self.images.is_open() {
                    "the open images stay"
                } else {
                    "the scene stays"
                };
                self.notify(Level::Error, format!("{err}; {kept}"));
                return;
            }
        };
        let view = self.images.next_serial();
        let mut images = Vec::new();
        for (path, image) in loaded {
            let stamp = ImageStamp {
                view,
                revision: 0,
                serial: self.images.next_serial(),
            };
            images.push(SetImage {
                name: file_name(&path),
                published: Published::new(image, stamp),
                path,
            });
        }
        let names: Vec<&str> = images.iter().map(|i| i.name.as_str()).collect();
        let reference = default_reference(&names);
        let (w, h) = images[0].published.size();
        let text = format!(
            "Opened {} image(s) of {w}×{h}: {}; reference: {}",
            names.len(),
            names.join(", "),
            names[reference]
        );
        self.images.open = Some(ImageSet {
            images,
            reference,
            view,
        });
        self.images.stay();
        self.request(Command::ForgetMeasurements);
        for note in notes {
            self.notify(Level::Warning, note);
        }
        self.notify(Level::Info, text);
    }

    /// Opens dropped files: images as an image set, a model as the scene.
    pub(in crate::app) fn open_dropped(&mut self, ctx: &egui::Context, paths: Vec<PathBuf>) {
        let scenes: Vec<&PathBuf> = paths
            .iter()
            .filter(|p| crate::scene::source::is_scene_file(p))
            .collect();
        let any_image = paths.iter().any(|p| is_image_file(p));
        match (any_image, scenes.last()) {
            (true, Some(_)) => self.notify(
                Level::Error,
                "Dropped images and a model together: drop up to four images, or one model",
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
