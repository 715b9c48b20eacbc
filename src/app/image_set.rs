//! Images as panes: File > Open images (or PNG/JPEG files dropped on the window) shows up to
//! five images of one size, such as captures from another renderer or aa-lab's own exports,
//! in place of the technique outputs, one of them being the reference. Layouts, the
//! magnifier, the difference heatmaps and the quality figures work on them as on technique
//! outputs; the engine renders nothing meanwhile. Closing the set, or opening a scene, goes
//! back to the scene.
//!
//! **Panes and the reference.** A set of up to four images shows every image as a pane, the
//! reference among them (so two captures and their reference show three panes). A fifth
//! image makes room for four compared images and a separate reference: the reference then
//! leaves the panes (the compared slots A to D are the four others, in file order) and shows
//! where a technique view's reference shows, as R: the magnifier's reference pane, the flip
//! layout's R key, the heatmaps' and figures' ground truth. The compared slots are never more
//! than the four the layouts, letters and colours have ([`MAX_COMPARE`]), and every table
//! that lists the set's images marks each with its pane's letter or the reference's R
//! ([`ImageSet::pane_of`]).
//!
//! What this module owns:
//! - [`ImageSet`]: the open images as [`Published`] images under the fixed ids
//!   [`IMAGE_IDS`] (`image-1` to `image-5`, in file order), which one is the reference, which
//!   are panes, and the "view" their figures are stamped with (it
//!   changes whenever what is compared changes: another reference, another order).
//! - [`decode`] and the loader thread: files are decoded, checked (at most five, all PNG or
//!   JPEG, one size, within the texture limit) and uploaded to eframe's device off the UI
//!   thread; a set that fails any check is refused whole with a message, and whatever was
//!   shown stays.
//!
//! - The [`SequenceSet`] of a set opened from image sequences (File > Open sequences,
//!   folders dropped on the window; `sequence_set.rs`): the set's images are then the frames
//!   of the playhead, replaced and stamped with a new view whenever the playhead moves
//!   ([`ImageSetState::tick_sequences`]), so everything that works on images works on every
//!   frame.
//!
//! Opening, closing and choosing the reference are the context's commands
//! (`context/images.rs`); the lookups every feature uses to find an image by id, the open set's
//! when there is one and the engine's otherwise, are the context's too (`context/shown.rs`).
//!
//! **The reference** is by default the first file whose name contains the word `reference`
//! or `ref` (`bistro-ref.png`, `reference_64spp.jpg`, aa-lab bench's `*-reference.png`), or
//! else the first file; the images panel and the toolbar change it.

use std::path::{Path, PathBuf};
use std::sync::mpsc;

use super::blit::Uploader;
use super::engine::{ImageStamp, Published};
use super::render_thread::RenderedImage;
use super::sequence_set::{self, FrameNews, SequenceSet};
use super::settings::MAX_COMPARE;
use crate::aa::ssaa::Progress;

/// The ids of the images of a set, in file order.
pub const IMAGE_IDS: [&str; 5] = ["image-1", "image-2", "image-3", "image-4", "image-5"];
/// Most images a set holds: one per compared slot and a separate reference.
pub const MAX_IMAGES: usize = IMAGE_IDS.len();
// Four compared slots (A to D) and the reference apart: every id has a place.
const _: () = assert!(MAX_IMAGES == MAX_COMPARE + 1);
/// File extensions taken for images when files are dropped (lower case).
pub const IMAGE_EXTENSIONS: &[&str] = &["png", "jpg", "jpeg"];
/// Most pixels of one image (8192 x 8192; five of them take 1.25 GiB).
const MAX_PIXELS: u64 = 1 << 26;
/// The reference of a set "accumulates" nothing: it is complete with its one sample.
pub(in crate::app) const COMPLETE: Progress = Progress {
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

/// What a set is opened from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SetKind {
    /// Still image files.
    Images,
    /// Image sequences (folders or globs of numbered frames).
    Sequences,
}

impl SetKind {
    /// `images` or `sequences`, for messages.
    pub fn noun(self) -> &'static str {
        match self {
            SetKind::Images => "images",
            SetKind::Sequences => "sequences",
        }
    }
}

/// Why `count` files of `kind` are too many for a set.
pub fn too_many(count: usize, kind: SetKind) -> String {
    let noun = kind.noun();
    format!(
        "{count} {noun} were given; aa-lab compares at most {MAX_COMPARE} {noun} and a \
         reference ({MAX_IMAGES} in all) at a time"
    )
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
        return Err(too_many(paths.len(), SetKind::Images));
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
    /// The sequences whose frames the images are (`None`: still images).
    sequences: Option<SequenceSet>,
}

impl ImageSet {
    /// The ids of the images shown as panes (compared as A, B, C, D), in order.
    pub fn ids(&self) -> Vec<&'static str> {
        self.panes()
            .into_iter()
            .map(|index| IMAGE_IDS[index])
            .collect()
    }

    /// The indices of the images shown as panes, in file order: every image of a set of up
    /// to [`MAX_COMPARE`], else every image but the reference.
    pub fn panes(&self) -> Vec<usize> {
        let all = self.images.len() <= MAX_COMPARE;
        (0..self.images.len())
            .filter(|index| all || *index != self.reference)
            .collect()
    }

    /// The compared slot (0 for A, ...) of image `index`: `None` for the reference when it
    /// is not a pane (and for an index past the set).
    pub fn pane_of(&self, index: usize) -> Option<usize> {
        self.panes().iter().position(|pane| *pane == index)
    }

    pub(in crate::app) fn index(id: &str) -> Option<usize> {
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

    /// The index of the reference image (in file order).
    pub fn reference_index(&self) -> usize {
        self.reference
    }

    /// The view the set's images are stamped with (it changes with the reference or the
    /// order).
    pub fn view(&self) -> u64 {
        self.view
    }

    /// The reference.
    pub fn reference(&self) -> &SetImage {
        &self.images[self.reference]
    }

    /// The images' size.
    pub fn size(&self) -> (u32, u32) {
        self.images[0].published.size()
    }

    /// The sequences whose frames are shown, when the set was opened from sequences.
    pub fn sequences(&self) -> Option<&SequenceSet> {
        self.sequences.as_ref()
    }

    /// Stamps every image with a new view: the figures of the old one no longer apply.
    fn restamp(&mut self, view: u64) {
        self.view = view;
        for image in &mut self.images {
            image.published.stamp.view = view;
        }
    }
}

/// A loaded set: each file (or sequence) with its pixels on eframe's device, the notes, and
/// the sequences when it is a sequence set.
struct Uploaded {
    images: Vec<(PathBuf, RenderedImage)>,
    notes: Vec<String>,
    sequences: Option<SequenceSet>,
}

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

    /// Starts loading `paths` as a set of `kind` (at most [`MAX_IMAGES`], sides at most
    /// `max_side`) on a thread of its own: still images are decoded, sequences opened and
    /// their first frames read; the thread uploads them with the set's uploader and wakes
    /// `wake` when done. A newer request supersedes one still loading.
    pub fn start_load(
        &mut self,
        kind: SetKind,
        paths: Vec<PathBuf>,
        max_side: u32,
        wake: egui::Context,
    ) -> std::io::Result<()> {
        let (sender, receiver) = mpsc::channel();
        let files = paths.clone();
        let uploader = self.uploader.clone();
        std::thread::Builder::new()
            .name(format!("aa-lab {} loader", kind.noun()))
            .spawn(move || {
                let loaded = match kind {
                    SetKind::Images => load_images(&files, max_side, &uploader),
                    SetKind::Sequences => load_sequences(&files, max_side, uploader, &wake),
                };
                let _ = sender.send(loaded);
                crate::app::repaint::request_one_frame(&wake);
            })?;
        self.pending = Some((paths, receiver));
        Ok(())
    }

    /// Opens a finished load as the set (the reference chosen by [`default_reference`]): a
    /// line saying what opened and the decoder's notes, or why the load failed (the set that
    /// was open stays). `None` while nothing has finished.
    pub fn finish_load(&mut self) -> Option<Result<(String, Vec<String>), String>> {
        let Uploaded {
            images: loaded,
            notes,
            sequences,
        } = match self.poll()? {
            Ok(uploaded) => uploaded,
            Err(err) => return Some(Err(err)),
        };
        let view = self.next_serial();
        let mut images = Vec::new();
        for (path, image) in loaded {
            let stamp = ImageStamp {
                view,
                revision: 0,
                serial: self.next_serial(),
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
        let what = match &sequences {
            Some(set) => format!("{} sequence(s) of {} frames", names.len(), set.len()),
            None => format!("{} image(s)", names.len()),
        };
        let text = format!(
            "Opened {what} of {w}×{h}: {}; reference: {}",
            names.join(", "),
            names[reference]
        );
        self.open = Some(ImageSet {
            images,
            reference,
            view,
            sequences,
        });
        self.stay();
        Some(Ok((text, notes)))
    }

    /// Closes the open set; whether there was one.
    pub fn close(&mut self) -> bool {
        self.open.take().is_some()
    }

    /// Makes image `index` of the open set the reference.
    pub fn set_reference(&mut self, index: usize) {
        let view = self.next_serial();
        if let Some(set) = &mut self.open
            && index < set.images.len()
            && index != set.reference
        {
            set.reference = index;
            set.restamp(view);
        }
    }

    /// Swaps the images of panes A and B, the reference with them when it is one.
    pub fn swap_first_two(&mut self) {
        let view = self.next_serial();
        let Some(set) = &mut self.open else {
            return;
        };
        let &[a, b, ..] = set.panes().as_slice() else {
            return;
        };
        set.images.swap(a, b);
        if let Some(sequences) = &mut set.sequences {
            sequences.swap(a, b);
        }
        set.reference = match set.reference {
            r if r == a => b,
            r if r == b => a,
            other => other,
        };
        set.restamp(view);
    }

    /// The sequences of the open set, to play and align.
    pub fn sequences_mut(&mut self) -> Option<&mut SequenceSet> {
        self.open.as_mut()?.sequences.as_mut()
    }

    /// Whether the open set is a sequence set.
    pub fn has_sequences(&self) -> bool {
        self.open.as_ref().and_then(ImageSet::sequences).is_some()
    }

    /// Whether the open set is a sequence set that plays.
    pub fn sequences_playing(&self) -> bool {
        self.open
            .as_ref()
            .and_then(ImageSet::sequences)
            .is_some_and(SequenceSet::playing)
    }

    /// Advances the open sequence set (see [`SequenceSet::tick`]): the frames read for the
    /// playhead become the set's images, under a new view. The error of a frame that could
    /// not be read (playback stopped, the frames shown stay).
    pub fn tick_sequences(&mut self, ctx: &egui::Context) -> Option<String> {
        let set = self.open.as_mut()?;
        let reference = set.reference;
        let news = set.sequences.as_mut()?.tick(ctx, reference)?;
        let frames = match news {
            FrameNews::Frames(frames) => frames,
            FrameNews::Failed(err) => return Some(err),
        };
        let view = self.next_serial();
        let serials: Vec<u64> = frames.iter().map(|_| self.next_serial()).collect();
        let set = self.open.as_mut()?;
        set.view = view;
        for ((image, frame), serial) in set.images.iter_mut().zip(frames).zip(serials) {
            let stamp = ImageStamp {
                view,
                revision: 0,
                serial,
            };
            image.published = Published::new(frame, stamp);
        }
        None
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

/// Decodes the images at `paths` and uploads them (see [`ImageSetState::start_load`]).
fn load_images(paths: &[PathBuf], max_side: u32, uploader: &Uploader) -> Result<Uploaded, String> {
    let decoded = decode(paths, max_side)?;
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
    Ok(Uploaded {
        images,
        notes: decoded.notes,
        sequences: None,
    })
}

/// Opens the sequences at `paths` and reads their first frames (see
/// [`ImageSetState::start_load`]).
fn load_sequences(
    paths: &[PathBuf],
    max_side: u32,
    uploader: Uploader,
    wake: &egui::Context,
) -> Result<Uploaded, String> {
    if paths.len() > MAX_IMAGES {
        return Err(too_many(paths.len(), SetKind::Sequences));
    }
    let sequences = sequence_set::open_all(paths)?;
    let (width, height) = sequences[0].size();
    if width.max(height) > max_side {
        return Err(format!(
            "{} has frames of {width}x{height}; this adapter shows images up to {max_side} pixels a side",
            sequences[0].source().display()
        ));
    }
    let frames = sequence_set::first_frames(&sequences, &uploader)?;
    let set = SequenceSet::new(sequences, uploader, wake)
        .map_err(|e| format!("cannot read sequences: no thread ({e})"))?;
    Ok(Uploaded {
        images: paths.iter().cloned().zip(frames).collect(),
        notes: Vec::new(),
        sequences: Some(set),
    })
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

        let five = decode(&vec![a.clone(); 5], 4096).unwrap();
        assert_eq!(five.images.len(), 5, "four to compare and a reference");
        let six = vec![a.clone(); 6];
        let err = decode(&six, 4096).err().unwrap();
        assert!(
            err.contains("6 images") && err.contains("at most 4 images and a reference"),
            "{err}"
        );
        let err = decode(&[a], 4).err().unwrap();
        assert!(err.contains("up to 4 pixels"), "{err}");
        assert!(is_image_file(Path::new("x/Y.JPG")) && !is_image_file(Path::new("y.obj")));
    }
}
