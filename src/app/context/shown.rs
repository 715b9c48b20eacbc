//! What the panes show, as every feature looks it up: a compared id's image (the open image
//! set's when there is one, the engine's otherwise), the reference and where it stands, the
//! view the figures are stamped with, the labels and letters of the panes (which a blind
//! comparison hides), the magnifier's lens and its panes' sources, and the render record of
//! the displayed frame.

use std::path::PathBuf;
use std::sync::Arc;

use egui::Color32;

use super::{Context, DialogPurpose, Level};
use crate::aa::ssaa::Progress;
use crate::app::engine::{ImageStamp, Published, ReferenceState};
use crate::app::image_set::{COMPLETE, IMAGE_IDS, ImageSet};
use crate::app::lens::{Source, lens_region};
use crate::app::style::{self, REFERENCE_COLOR, SLOT_COLORS};
use crate::gpu::readback::Region;
use crate::spec::RenderSpec;

impl Context {
    /// The image shown for `id`: an image of the open set, else a technique's image (its
    /// debug view when one is selected).
    pub(in crate::app) fn image_for(&self, id: &str) -> Option<&Published> {
        match self.images.open() {
            Some(set) => set.get(id).map(|i| &i.published),
            None => self.engine.as_ref()?.image(id),
        }
    }

    /// The image measured and exported for `id`: an image of the open set, else a
    /// technique's output.
    pub(in crate::app) fn output_for(&self, id: &str) -> Option<&Published> {
        match self.images.open() {
            Some(set) => set.get(id).map(|i| &i.published),
            None => self.engine.as_ref()?.output(id),
        }
    }

    /// The reference and how far it has accumulated: the chosen image of the open set
    /// (complete), else the engine's reference of the displayed view.
    pub(in crate::app) fn reference_for(&self) -> Option<(&Published, Progress)> {
        match self.images.open() {
            Some(set) => Some((&set.reference().published, COMPLETE)),
            None => self.engine.as_ref()?.reference(),
        }
    }

    /// Where the reference stands.
    pub(in crate::app) fn reference_state_for(&self) -> Option<ReferenceState> {
        match self.images.open() {
            Some(_) => Some(ReferenceState::Ready(COMPLETE)),
            None => self.engine.as_ref().map(|e| e.reference_state()),
        }
    }

    /// The reference's title on chips and panes.
    pub(in crate::app) fn reference_title(&self) -> String {
        match (self.images.open(), self.reference_state_for()) {
            (Some(set), _) => format!("Reference · {}", set.reference().name),
            (None, Some(ReferenceState::Ready(p))) => {
                format!("Reference {}/{} spp", p.samples, p.total)
            }
            _ => "Reference".to_owned(),
        }
    }

    /// The label of an image of the open set: its file name (a sequence's with the number of
    /// the frame shown), marked when it is the reference.
    pub(in crate::app) fn image_label(&self, id: &str) -> Option<String> {
        let set = self.images.open()?;
        let index = ImageSet::index(id)?;
        let image = set.images().get(index)?;
        let mut label = image.name.clone();
        if let Some(number) = set
            .sequences()
            .and_then(|s| s.shown_numbers().get(index).copied().flatten())
        {
            label = format!("{label} · frame {number}");
        }
        if self.is_reference_image(id) {
            label.push_str(" · reference");
        }
        Some(label)
    }

    /// The letter and colour of image `index` of the open set in its tables: its pane's
    /// (A to D), or the reference's R when it is no pane (a set of five).
    pub(in crate::app) fn image_mark(&self, index: usize) -> (&'static str, Color32) {
        style::slot_mark(self.images.open().and_then(|set| set.pane_of(index)))
    }

    /// Whether `id` is the reference image of the open set.
    pub(in crate::app) fn is_reference_image(&self, id: &str) -> bool {
        self.images
            .open()
            .is_some_and(|set| ImageSet::index(id) == Some(set.reference_index()))
    }

    /// The view being shown: the open set's, else the engine's.
    pub(in crate::app) fn current_view(&self) -> Option<u64> {
        match self.images.open() {
            Some(set) => Some(set.view()),
            None => self.engine.as_ref().map(|e| e.current_view()),
        }
    }

    /// The view and settings revision a measurement of `id` must have been made at to
    /// describe what is shown now (`None` when `id` shows nothing).
    pub(in crate::app) fn measure_key(&self, id: &str) -> Option<(u64, u64)> {
        match self.images.open() {
            Some(set) => set.get(id).map(|_| (set.view(), 0)),
            None => {
                let engine = self.engine.as_ref()?;
                let entry = engine.entry(id).filter(|e| e.enabled)?;
                Some((engine.current_view(), entry.revision()))
            }
        }
    }

    /// What the quality figures measure against the reference now: every image of the set
    /// but the reference, or every enabled technique's output of the current view.
    pub(in crate::app) fn measured_images(
        &self,
        view: u64,
    ) -> Vec<(&'static str, ImageStamp, Arc<image::RgbaImage>)> {
        if let Some(set) = self.images.open() {
            return IMAGE_IDS
                .iter()
                .zip(set.images())
                .enumerate()
                .filter(|(i, _)| *i != set.reference_index())
                .filter_map(|(_, (id, image))| {
                    let pixels = image.published.pixels.as_ref()?;
                    Some((*id, image.published.stamp, Arc::clone(pixels)))
                })
                .collect();
        }
        let Some(engine) = &self.engine else {
            return Vec::new();
        };
        engine
            .entries()
            .iter()
            .filter_map(|entry| {
                let output = engine.output(entry.id)?;
                let pixels = output.pixels.as_ref()?;
                (output.stamp.view == view && output.stamp.revision == entry.revision())
                    .then(|| (entry.id, output.stamp, Arc::clone(pixels)))
            })
            .collect()
    }

    /// The file names of the open set, in pane order, and the index of the reference.
    pub(in crate::app) fn image_names(&self) -> Option<(Vec<String>, usize)> {
        let set = self.images.open()?;
        let names = set.images().iter().map(|i| i.name.clone()).collect();
        Some((names, set.reference_index()))
    }

    /// The panes' sources: the compared techniques, then the reference when shown.
    pub(in crate::app) fn magnifier_sources(&self) -> Vec<Source> {
        let mut sources: Vec<Source> = self
            .compared()
            .into_iter()
            .enumerate()
            .map(|(slot, id)| Source::Technique(slot, id))
            .collect();
        if self.settings.magnifier.show_reference || self.settings.magnifier.difference {
            sources.push(Source::Reference);
        }
        sources
    }

    /// The published image of a pane (a technique's, or an image of the open set).
    pub(in crate::app) fn source_image(&self, source: Source) -> Option<&Published> {
        match source {
            Source::Technique(_, id) => self.image_for(id),
            Source::Reference => self.reference_for().map(|(image, _)| image),
        }
    }

    /// The lens region now.
    pub(in crate::app) fn lens(&self) -> Option<Region> {
        lens_region(
            self.settings.magnifier.center,
            self.lens_side,
            self.render_size,
        )
    }

    /// Letter, colour and name of a pane.
    pub(in crate::app) fn source_label(&self, source: Source) -> (&'static str, Color32, String) {
        match source {
            Source::Technique(slot, id) => (
                self.blind.letter(slot),
                SLOT_COLORS[slot],
                self.shown_label(id),
            ),
            Source::Reference => ("R", REFERENCE_COLOR, self.reference_title()),
        }
    }

    /// The render record of the displayed frame: `aa-lab render --from` reproduces it.
    pub(in crate::app) fn current_spec(&self) -> Option<RenderSpec> {
        let engine = self.engine.as_ref()?;
        let camera = engine.displayed()?;
        let scene = self.scene.as_ref()?;
        let techniques = engine
            .entries()
            .iter()
            .filter(|e| e.enabled && engine.output(e.id).is_some())
            .map(|e| engine.technique_spec(e.id))
            .collect();
        Some(RenderSpec {
            scene: scene.spec.clone(),
            density: 1.0,
            seed: crate::scene::procedural::SceneOptions::default().seed,
            specular_aa: engine.specular_aa(),
            tonemap: engine.tonemap().0,
            exposure: engine.tonemap().1,
            width: camera.size.0,
            height: camera.size.1,
            frame: camera.frame,
            camera: Some(camera.pose),
            rig: None,
            image: None,
            techniques,
            overlay: self.settings.ui_overlay,
            adapter: Some(format!(
                "{} ({})",
                engine.caps().adapter_name,
                engine.caps().backend
            )),
            build: Some(crate::spec::build_id()),
        })
    }

    /// Asks for the export folder.
    pub(in crate::app) fn pick_export_dir(&mut self, ctx: &egui::Context) {
        let start = self.settings.export_dir.clone();
        self.ask_for_path(ctx, DialogPurpose::ExportFolder, move || {
            rfd::FileDialog::new()
                .set_title("Export folder")
                .set_directory(&start)
                .pick_folder()
        });
    }

    /// Sends exports to `dir` (a folder picked in the dialog).
    pub(in crate::app) fn use_export_dir(&mut self, dir: PathBuf) {
        self.notify(Level::Info, format!("Exports go to {}", dir.display()));
        self.settings.export_dir = dir;
    }
}
