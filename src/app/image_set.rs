//! Images as panes: File > Open images (or PNG/JPEG files dropped on the window) shows up to
//! four images of one size, such as captures from another renderer or aa-lab's own exports,
//! in place of the technique outputs, one of them being the reference. Layouts, the
//! magnifier, the difference heatmaps and the quality figures work on them as on technique
//! outputs; the engine renders nothing meanwhile. Closing the set, or opening a scene, goes
//! back to the scene.
//!
//! What this module owns:
//! - [`ImageSet`]: the open images as [`Published`] images under the fixed ids
//!   [`IMAGE_IDS`] (`image-1` to `image-4`, in file order, which the compared slots A to D
//!   follow), which one is the reference, and the "view" their figures are stamped with (it
//!   changes whenever what is compared changes: another reference, another order).
//! - [`decode`] and the loader thread: files are decoded, checked (at most four, all PNG or
//!   JPEG, one size, within the texture limit) and uploaded to eframe's device off the UI
//!   thread; a set that fails any check is refused whole with a message, and whatever was
//!   shown stays.
//! - The lookups the viewport, the magnifier, the quality figures and the export use to find
//!   an image by id ([`Workspace::image_for`], [`Workspace::reference_for`], ...): the open set
//!   when there is one, the engine otherwise.
//!
//! **The reference** is by default the first file whose name contains the word `reference`
//! or `ref` (`bistro-ref.png`, `reference_64spp.jpg`, aa-lab bench's `*-reference.png`), or
//! else the first file; the images panel and the toolbar change it.

use std::path::{Path, PathBuf};
use std::sync::{Arc, mpsc};

use super::blit::Uploader;
use super::engine::{ImageStamp, Published, ReferenceState};
use super::render_thread::RenderedImage;
use super::workspace::{Level, Workspace};
use crate::aa::ssaa::Progress;

/// The ids of the images of a set, in file order.
pub const IMAGE_IDS: [&str; 4] = ["image-1", "image-2", "image-3", "image-4"];
/// Most images a set holds (one per compared slot).
pub const MAX_IMAGES: usize = IMAGE_IDS.len();
/// File extensions taken for images when files are dropped (lower case).
pub const IMAGE_EXTENSIONS: &[&str] = &["png", "jpg", "jpeg"];
/// Most pixels of one image (8192 x 8192; four of them take 1 GiB).
const MAX_PIXELS: u64 = 1 << 26;
/// The reference of a set "accumulates" nothing: it is complete with its one sample.
const COMPLETE: Progress = Progress {
    samples: 1,
    total: 1,
};

/// Whether a path names an image by its extension.
pub fn is_image_file(path: &Path) -> bool {
    path.extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| IMAGE_EXTENSIONS.iter().any(|x| e.eq_ignore_ascii_case(x)))
}

/// The file name of a path, for labels.
fn file_name(path: &Path) -> String {
    path.file_name().map_or_else(
        || path.display().to_string(),
        |n| n.to_string_lossy().into_owned(),
    )
}

/// The default reference of files named `names`: the first whose stem has the word
/// `reference` or `ref`, else the first.
pub fn default_reference(names: &[&str]) -> usize {
    names
        .iter()
        .position(|name| {
            let stem = Path::new(name)
                .file_stem()
                .map_or_else(String::new, |s| s.to_string_lossy().to_lowercase());
            stem.split(|c: char| !c.is_alphanumeric())
                .any(|word| word == "reference" || word == "ref")
        })
        .unwrap_or(0)
}

/// One decoded file.
pub struct DecodedImage {
    /// Where it came from.
    pub path: PathBuf,
    /// The pixels, sRGB-encoded RGBA8, opaque.
    pub pixels: image::RgbaImage,
}

/// A decoded set, ready to be shown.
pub struct Decoded {
    /// The images, in the order given.
    pub images: Vec<DecodedImage>,
    /// Things worth telling (transparency dropped).
    pub notes: Vec<String>,
}

/// The format of an image file from its first bytes (not its name).
fn sniff(path: &Path) -> Result<Option<image::ImageFormat>, String> {
    use std::io::Read;
    let mut head = Vec::with_capacity(64);
    std::fs::File::open(path)
        .and_then(|file| file.take(64).read_to_end(&mut head))
        .map_err(|e| format!("cannot read {}: {e}", path.display()))?;
    Ok(image::guess_format(&head).ok())
}

/// Decodes and checks a set of image files (see the module docs); `max_side` is the largest
/// texture side the window's device takes. The error says what is wrong with which file.
pub fn decode(paths: &[PathBuf], max_side: u32) -> Result<Decoded, String> {
    if paths.is_empty() {
        return Err("no image files were given".to_owned());
    }
    if paths.len() > MAX_IMAGES {
        return Err(format!(
            "{} images were given; aa-lab compares at most {MAX_IMAGES} at a time",
            paths.len()
        ));
    }
    let mut images = Vec::new();
    let mut notes = Vec::new();
    for path in paths {
        let format = sniff(path)?;
        if !matches!(
            format,
            Some(image::ImageFormat::Png | image::ImageFormat::Jpeg)
        ) {
            return Err(format!(
                "{} is not a PNG or JPEG image{}",
                path.display(),
                match format {
                    Some(other) => format!(" (it is {other:?})"),
                    None => String::new(),
                }
            ));
        }
        let mut pixels =
            crate::export::png::read_image_limited(path, MAX_PIXELS, "the viewer's image set")
                .map_err(|e| e.to_string())?;
        let (width, height) = pixels.dimensions();
        if width.max(height) > max_side {
            return Err(format!(
                "{} is {width}x{height}; this adapter shows images up to {max_side} pixels a side",
                path.display()
            ));
        }
        if pixels.pixels().any(|p| p.0[3] < 255) {
            // Technique outputs are opaque, and so is what the figures compare.
            for p in pixels.pixels_mut() {
                p.0[3] = 255;
            }
            notes.push(format!(
                "{} has transparent pixels; its colours are shown and compared as if opaque",
                file_name(path)
            ));
        }
        images.push(DecodedImage {
            path: path.clone(),
            pixels,
        });
    }
    let first = images[0].pixels.dimensions();
    if images.iter().any(|i| i.pixels.dimensions() != first) {
        let sizes: Vec<String> = images
            .iter()
            .map(|i| {
                let (w, h) = i.pixels.dimensions();
                format!("{} {w}x{h}", file_name(&i.path))
            })
            .collect();
        return Err(format!(
            "the images differ in size ({}); open images of one size",
            sizes.join(", ")
        ));
    }
    Ok(Decoded { images, notes })
}

/// One image of an open set.
pub struct SetImage {
    /// Its file.
    pub path: PathBuf,
    /// Its file name (the pane's label).
    pub name: String,
    /// The image as the panes draw it.
    pub published: Published,
}

/// The open images (see the module docs).
pub struct ImageSet {
    images: Vec<SetImage>,
    reference: usize,
    view: u64,
}

impl ImageSet {
    /// The ids of its images, in order.
    pub fn ids(&self) -> Vec<&'static str> {
        IMAGE_IDS[..self.images.len()].to_vec()
    }

    fn index(id: &str) -> Option<usize> {
        IMAGE_IDS.iter().position(|i| *i == id)
    }

    /// The image with an id.
    pub fn get(&self, id: &str) -> Option<&SetImage> {
        self.images.get(Self::index(id)?)
    }

    /// The images, in order.
    pub fn images(&self) -> &[SetImage] {
        &self.images
    }

    /// The reference.
    pub fn reference(&self) -> &SetImage {
        &self.images[self.reference]
    }

    /// The images' size.
    pub fn size(&self) -> (u32, u32) {
        self.images[0].published.size()
    }

    /// Stamps every image with a new view: the figures of the old one no longer apply.
    fn restamp(&mut self, view: u64) {
        self.view = view;
        for image in &mut self.images {
            image.published.stamp.view = view;
        }
    }
}

/// A loaded set: each file with its pixels on eframe's device, and the notes.
type Uploaded = (Vec<(PathBuf, RenderedImage)>, Vec<String>);

/// A load in progress: the files asked for and the answer to come.
type Pending = (Vec<PathBuf>, mpsc::Receiver<Result<Uploaded, String>>);

/// The image set of the viewer: the open one, the one loading, and the bookkeeping.
pub struct ImageSetState {
    /// Puts decoded images on eframe's device (from the decoder thread).
    uploader: Uploader,
    open: Option<ImageSet>,
    pending: Option<Pending>,
    /// Counts views and publications of image sets.
    serial: u64,
    /// A scene the user asked for replaces the set once it has loaded.
    leave_for_scene: bool,
}

impl ImageSetState {
    /// No set, images to be uploaded by `uploader`.
    pub fn new(uploader: Uploader) -> Self {
        Self {
            uploader,
            open: None,
            pending: None,
            serial: 0,
            leave_for_scene: false,
        }
    }

    /// The open set.
    pub fn open(&self) -> Option<&ImageSet> {
        self.open.as_ref()
    }

    /// Whether a set is open.
    pub fn is_open(&self) -> bool {
        self.open.is_some()
    }

    /// Whether images are being decoded.
    pub fn loading(&self) -> bool {
        self.pending.is_some()
    }

    fn next_serial(&mut self) -> u64 {
        self.serial += 1;
        self.serial
    }

    /// The next scene loaded replaces the set.
    pub fn leave_for_scene(&mut self) {
        self.leave_for_scene = true;
    }

    /// The scene asked for did not load: the set stays.
    pub fn stay(&mut self) {
        self.leave_for_scene = false;
    }

    /// Whether a scene that just loaded replaces the set (and forgets the request).
    pub fn take_leave(&mut self) -> bool {
        std::mem::take(&mut self.leave_for_scene)
    }

    /// The finished load, if the decoder is done.
    fn poll(&mut self) -> Option<Result<Uploaded, String>> {
        let (_, receiver) = self.pending.as_ref()?;
        let answer = match receiver.try_recv() {
            Ok(answer) => answer,
            Err(mpsc::TryRecvError::Empty) => return None,
            Err(mpsc::TryRecvError::Disconnected) => {
                Err("the image decoder stopped without an answer".to_owned())
            }
        };
        self.pending = None;
        Some(answer)
    }
}

impl Workspace {
    /// Opens up to four images of one size as panes (File > Open images, dropped images, and
    /// tests): they are decoded on a worker thread and replace what is shown when they all
    /// load; otherwise a notice says why, and what was shown stays.
    pub(super) fn open_images(&mut self, ctx: &egui::Context, paths: Vec<PathBuf>) {
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
                super::request_one_frame(&wake);
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
    pub(super) fn close_images(&mut self) {
        if self.images.open.take().is_some() {
            self.quality.clear();
            self.magnifier.clear();
            self.camera.cut();
        }
    }

    /// The file names of the open set, in pane order, and the index of the reference.
    pub(super) fn image_names(&self) -> Option<(Vec<String>, usize)> {
        let set = self.images.open()?;
        let names = set.images.iter().map(|i| i.name.clone()).collect();
        Some((names, set.reference))
    }

    /// Makes image `index` of the open set the reference.
    pub(super) fn set_image_reference(&mut self, index: usize) {
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
    pub(super) fn swap_images(&mut self) {
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
    pub(super) fn finish_image_load(&mut self) {
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
        self.quality.clear();
        self.magnifier.clear();
        for note in notes {
            self.notify(Level::Warning, note);
        }
        self.notify(Level::Info, text);
    }

    /// Opens dropped files: images as an image set, a model as the scene.
    pub(super) fn open_dropped(&mut self, ctx: &egui::Context, paths: Vec<PathBuf>) {
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

    /// The image shown for `id`: an image of the open set, else a technique's image (its
    /// debug view when one is selected).
    pub(super) fn image_for(&self, id: &str) -> Option<&Published> {
        match self.images.open() {
            Some(set) => set.get(id).map(|i| &i.published),
            None => self.engine.as_ref()?.image(id),
        }
    }

    /// The image measured and exported for `id`: an image of the open set, else a
    /// technique's output.
    pub(super) fn output_for(&self, id: &str) -> Option<&Published> {
        match self.images.open() {
            Some(set) => set.get(id).map(|i| &i.published),
            None => self.engine.as_ref()?.output(id),
        }
    }

    /// The reference and how far it has accumulated: the chosen image of the open set
    /// (complete), else the engine's reference of the displayed view.
    pub(super) fn reference_for(&self) -> Option<(&Published, Progress)> {
        match self.images.open() {
            Some(set) => Some((&set.reference().published, COMPLETE)),
            None => self.engine.as_ref()?.reference(),
        }
    }

    /// Where the reference stands.
    pub(super) fn reference_state_for(&self) -> Option<ReferenceState> {
        match self.images.open() {
            Some(_) => Some(ReferenceState::Ready(COMPLETE)),
            None => self.engine.as_ref().map(|e| e.reference_state()),
        }
    }

    /// The reference's title on chips and panes.
    pub(super) fn reference_title(&self) -> String {
        match (self.images.open(), self.reference_state_for()) {
            (Some(set), _) => format!("Reference · {}", set.reference().name),
            (None, Some(ReferenceState::Ready(p))) => {
                format!("Reference {}/{} spp", p.samples, p.total)
            }
            _ => "Reference".to_owned(),
        }
    }

    /// The label of an image of the open set: its file name, marked when it is the
    /// reference.
    pub(super) fn image_label(&self, id: &str) -> Option<String> {
        let set = self.images.open()?;
        let index = ImageSet::index(id)?;
        let image = set.images.get(index)?;
        Some(if self.is_reference_image(id) {
            format!("{} · reference", image.name)
        } else {
            image.name.clone()
        })
    }

    /// Whether `id` is the reference image of the open set.
    pub(super) fn is_reference_image(&self, id: &str) -> bool {
        self.images
            .open()
            .is_some_and(|set| ImageSet::index(id) == Some(set.reference))
    }

    /// The view being shown: the open set's, else the engine's.
    pub(super) fn current_view(&self) -> Option<u64> {
        match self.images.open() {
            Some(set) => Some(set.view),
            None => self.engine.as_ref().map(|e| e.current_view()),
        }
    }

    /// The view and settings revision a measurement of `id` must have been made at to
    /// describe what is shown now (`None` when `id` shows nothing).
    pub(super) fn measure_key(&self, id: &str) -> Option<(u64, u64)> {
        match self.images.open() {
            Some(set) => set.get(id).map(|_| (set.view, 0)),
            None => {
                let engine = self.engine.as_ref()?;
                let entry = engine.entry(id).filter(|e| e.enabled)?;
                Some((engine.current_view(), entry.revision()))
            }
        }
    }

    /// What the quality figures measure against the reference now: every image of the set
    /// but the reference, or every enabled technique's output of the current view.
    pub(super) fn measured_images(
        &self,
        view: u64,
    ) -> Vec<(&'static str, ImageStamp, Arc<image::RgbaImage>)> {
        if let Some(set) = self.images.open() {
            return IMAGE_IDS
                .iter()
                .zip(&set.images)
                .enumerate()
                .filter(|(i, _)| *i != set.reference)
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
}

#[cfg(test)]
mod tests {
    use super::*;

    fn write(dir: &Path, name: &str, image: &image::RgbaImage) -> PathBuf {
        let path = dir.join(name);
        image.save(&path).unwrap();
        path
    }

    fn gradient(w: u32, h: u32) -> image::RgbaImage {
        image::RgbaImage::from_fn(w, h, |x, y| image::Rgba([x as u8, y as u8, 77, 255]))
    }

    #[test]
    fn the_reference_is_the_file_named_so_or_the_first() {
        assert_eq!(default_reference(&["a.png", "b.png"]), 0);
        assert_eq!(default_reference(&["a.png", "bistro-ref.png"]), 1);
        assert_eq!(
            default_reference(&["fxaa.png", "Reference_64spp.jpg", "ref.png"]),
            1
        );
        assert_eq!(
            default_reference(&["chart-f0-none.png", "bench-reference.png"]),
            1
        );
        // Only whole words: "prefix" and "refraction" are no references.
        assert_eq!(default_reference(&["prefix.png", "refraction.png"]), 0);
    }

    #[test]
    fn sets_of_one_size_decode_and_everything_else_is_refused() {
        let dir = tempfile::tempdir().unwrap();
        let a = write(dir.path(), "a.png", &gradient(8, 6));
        let mut see_through = gradient(8, 6);
        see_through.put_pixel(1, 1, image::Rgba([1, 2, 3, 0]));
        let b = write(dir.path(), "b.png", &see_through);
        let decoded = decode(&[a.clone(), b.clone()], 4096).unwrap();
        assert_eq!(decoded.images.len(), 2);
        assert_eq!(decoded.images[0].pixels, gradient(8, 6));
        assert_eq!(decoded.images[1].pixels.get_pixel(1, 1).0, [1, 2, 3, 255]);
        assert_eq!(decoded.notes.len(), 1, "{:?}", decoded.notes);

        let other = write(dir.path(), "other.png", &gradient(9, 6));
        let err = decode(&[a.clone(), other], 4096).err().unwrap();
        assert!(
            err.contains("a.png 8x6") && err.contains("other.png 9x6"),
            "{err}"
        );

        let text = dir.path().join("notes.png");
        std::fs::write(&text, "not an image").unwrap();
        let err = decode(&[a.clone(), text], 4096).err().unwrap();
        assert!(
            err.contains("notes.png") && err.contains("not a PNG or JPEG"),
            "{err}"
        );

        let missing = dir.path().join("missing.png");
        let err = decode(&[missing], 4096).err().unwrap();
        assert!(err.contains("missing.png"), "{err}");

        let five = vec![a.clone(); 5];
        assert!(decode(&five, 4096).err().unwrap().contains("at most 4"));
        let err = decode(&[a], 4).err().unwrap();
        assert!(err.contains("up to 4 pixels"), "{err}");
        assert!(is_image_file(Path::new("x/Y.JPG")) && !is_image_file(Path::new("y.obj")));
    }
}
