//! Looping animations of equally sized RGBA8 frames, streamed: [`AnimationStream`] takes the
//! frames as they are rendered, works out each frame's change from the one before (the
//! bounding box of the pixels that differ; unchanged pixels transparent) and has it compressed
//! on a pool of worker threads while the next frames render, then writes the compressed frames
//! in order to an anonymous scratch file. Memory holds a few frames whatever the clip's length
//! (the frame before the newest, and those being compressed), and the compression runs on
//! every core.
//!
//! Two containers: animated PNG (lossless, [`super::apng`]) and GIF (256 colours per frame,
//! [`super::gif`]); both loop forever. The first frame is compressed last, from the version
//! the caller hands to [`AnimationStream::finish`]: a clip's captions hold figures over the
//! whole clip, known only after its last frame, and they lie in pixels no later frame changes,
//! so later frames, stored as changes, show them from the first. The stream does not keep the
//! first frame it was given: held to the end, it would be one more whole frame in memory for
//! the clip's length, and the caller has what it needs to make the final one.
//!
//! The output is written atomically under the caller's overwrite policy
//! ([`crate::files::PendingFile`]): an error, a cancel or an interruption leaves no file
//! behind. The encoding is deterministic: the same frames and settings give the same bytes,
//! whatever the number of threads.

use std::collections::BTreeMap;
use std::fs::File;
use std::io::{self, BufWriter, Seek, Write};
use std::path::{Path, PathBuf};
use std::sync::{Arc, mpsc};

use super::apng::{self, ApngFrame, ApngSequence, Compression};
use super::frame_change::Change;
use super::gif::{self as gif_format, GifFrame};
use crate::files::{self, Overwrite, PendingFile};

/// Errors of writing an animation.
#[derive(Debug, thiserror::Error)]
pub enum AnimationError {
    /// The file could not be written, or the overwrite policy refused it.
    #[error(transparent)]
    File(#[from] files::FileError),
    /// There is nothing to animate, or the frames differ in size.
    #[error("an animation needs at least one frame, all of one size")]
    Frames,
    /// A GIF side is limited to 65535 pixels.
    #[error("a GIF is at most 65535 pixels a side; this animation is {width}x{height}")]
    TooLargeForGif {
        /// Width.
        width: u32,
        /// Height.
        height: u32,
    },
}

/// The container of an animation.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum AnimationFormat {
    /// Animated PNG.
    Apng,
    /// GIF89a.
    Gif,
}

/// How an animation is written.
#[derive(Clone, Copy, Debug)]
pub struct AnimationOptions {
    /// Container.
    pub format: AnimationFormat,
    /// Playback rate, frames per second.
    pub fps: u16,
    /// Compression level of APNG frames.
    pub compression: Compression,
    /// Worker threads compressing frames (at least 1).
    pub threads: usize,
}

impl AnimationOptions {
    /// `format` at `fps` frames per second, fast compression on every core.
    pub fn new(format: AnimationFormat, fps: u16) -> Self {
        Self {
            format,
            fps,
            compression: Compression::Fast,
            threads: default_threads(),
        }
    }
}

/// The number of cores, the default number of encoding threads.
pub fn default_threads() -> usize {
    std::thread::available_parallelism().map_or(1, usize::from)
}

/// A compressed frame after the first, in either container.
enum EncodedFrame {
    Apng(ApngFrame),
    Gif(Box<GifFrame>),
}

type Outcome = (usize, io::Result<EncodedFrame>);

/// An animation being written (see the module docs).
pub struct AnimationStream {
    path: PathBuf,
    /// The output; `None` while writing an intermediate animation ([`AnimationStream::intermediate`]).
    output: Option<PendingFile>,
    scratch: BufWriter<File>,
    options: AnimationOptions,
    size: (u32, u32),
    pool: rayon::ThreadPool,
    sender: mpsc::Sender<Outcome>,
    results: mpsc::Receiver<Outcome>,
    previous: Option<Arc<image::RgbaImage>>,
    /// Compressed frames waiting for their predecessors.
    ready: BTreeMap<usize, EncodedFrame>,
    pushed: usize,
    written: usize,
    sequence: ApngSequence,
}

impl AnimationStream {
    /// Starts writing `path` (checked against `policy` now) for frames of `size` pixels.
    pub fn create(
        path: &Path,
        policy: &Overwrite,
        size: (u32, u32),
        options: AnimationOptions,
    ) -> Result<Self, AnimationError> {
        Self::start(path, Some(policy), size, options)
    }

    /// Starts an animated PNG that is no output of its own but the lossless intermediate of
    /// one (a video): [`AnimationStream::finish_intermediate`] returns it as an anonymous
    /// scratch file in the folder of `beside`.
    pub fn intermediate(
        beside: &Path,
        size: (u32, u32),
        threads: usize,
    ) -> Result<Self, AnimationError> {
        let options = AnimationOptions {
            threads,
            ..AnimationOptions::new(AnimationFormat::Apng, 30)
        };
        Self::start(beside, None, size, options)
    }

    fn start(
        path: &Path,
        policy: Option<&Overwrite>,
        size: (u32, u32),
        options: AnimationOptions,
    ) -> Result<Self, AnimationError> {
        if size.0 == 0 || size.1 == 0 {
            return Err(AnimationError::Frames);
        }
        let limit = u32::from(u16::MAX);
        if options.format == AnimationFormat::Gif && (size.0 > limit || size.1 > limit) {
            return Err(AnimationError::TooLargeForGif {
                width: size.0,
                height: size.1,
            });
        }
        let output = policy
            .map(|policy| PendingFile::create(path, policy))
            .transpose()?;
        let scratch = BufWriter::new(files::anonymous_scratch(path)?);
        let path = path.to_owned();
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(options.threads.max(1))
            .thread_name(|i| format!("aa-lab encoder {i}"))
            .build()
            .map_err(|e| write_error(&path, io::Error::other(e.to_string())))?;
        let (sender, results) = mpsc::channel();
        Ok(Self {
            path,
            output,
            scratch,
            options,
            size,
            pool,
            sender,
            results,
            previous: None,
            ready: BTreeMap::new(),
            pushed: 0,
            written: 0,
            sequence: ApngSequence::default(),
        })
    }

    /// Frames handed over so far.
    pub fn pushed(&self) -> usize {
        self.pushed
    }

    /// Frames compressed and written so far.
    pub fn written(&self) -> usize {
        self.written
    }

    /// Hands over the next frame; blocks while more frames than the workers can take are
    /// being compressed.
    pub fn push(&mut self, frame: image::RgbaImage) -> Result<(), AnimationError> {
        if frame.dimensions() != self.size {
            return Err(AnimationError::Frames);
        }
        let frame = Arc::new(frame);
        let index = self.pushed;
        match self.previous.replace(Arc::clone(&frame)) {
            None => self.written = 1,
            Some(previous) => {
                let sender = self.sender.clone();
                let options = self.options;
                self.pool.spawn(move || {
                    let change = Change::between(&previous, &frame);
                    drop((previous, frame));
                    let encoded = match options.format {
                        AnimationFormat::Apng => apng::encode_change(&change, options.compression)
                            .map(EncodedFrame::Apng),
                        AnimationFormat::Gif => gif_format::encode_change(change, options.fps)
                            .map(|f| EncodedFrame::Gif(Box::new(f))),
                    };
                    let _ = sender.send((index, encoded));
                });
            }
        }
        self.pushed += 1;
        let in_flight_limit = self.pool.current_num_threads();
        while self.pushed - self.written > in_flight_limit {
            self.collect(true)?;
        }
        self.collect(false)
    }

    /// Takes finished frames (waiting for one when `wait`) and writes those whose turn it is.
    fn collect(&mut self, wait: bool) -> Result<(), AnimationError> {
        let mut next = if wait {
            let stopped = || io::Error::other("an encoding thread stopped");
            Some(
                self.results
                    .recv()
                    .map_err(|_| write_error(&self.path, stopped()))?,
            )
        } else {
            self.results.try_recv().ok()
        };
        while let Some((index, encoded)) = next {
            let encoded = encoded.map_err(|e| write_error(&self.path, e))?;
            self.ready.insert(index, encoded);
            next = self.results.try_recv().ok();
        }
        while let Some(frame) = self.ready.remove(&self.written) {
            let written = match &frame {
                EncodedFrame::Apng(frame) => {
                    self.sequence
                        .write_frame(&mut self.scratch, frame, self.options.fps)
                }
                EncodedFrame::Gif(frame) => {
                    gif_format::write_frame(&mut self.scratch, frame, self.size)
                }
            };
            written.map_err(|e| write_error(&self.path, e))?;
            self.written += 1;
        }
        Ok(())
    }

    /// Waits for every frame, writes the file (an APNG with `record` in its text chunk) and
    /// moves it into place; returns whether an existing file was replaced. `first` is the first
    /// frame as stored: the one pushed first, or a final version of it that differs only in
    /// pixels no later frame changes (a clip's captions), as later frames are stored as changes.
    pub fn finish(
        mut self,
        first: &image::RgbaImage,
        record: Option<&str>,
    ) -> Result<bool, AnimationError> {
        let mut output = self.output.take().ok_or(AnimationError::Frames)?;
        self.assemble(output.writer(), first, record)?;
        Ok(output.commit()?)
    }

    /// [`AnimationStream::finish`] of an [`AnimationStream::intermediate`]: the animated PNG,
    /// in an anonymous scratch file, rewound.
    pub fn finish_intermediate(mut self, first: &image::RgbaImage) -> Result<File, AnimationError> {
        let mut out = BufWriter::new(files::anonymous_scratch(&self.path)?);
        self.assemble(&mut out, first, None)?;
        let mut file = out
            .into_inner()
            .map_err(|e| write_error(&self.path, e.into_error()))?;
        file.rewind().map_err(|e| write_error(&self.path, e))?;
        Ok(file)
    }

    /// Waits for every frame and writes the whole file to `out`.
    fn assemble(
        &mut self,
        out: &mut BufWriter<File>,
        first: &image::RgbaImage,
        record: Option<&str>,
    ) -> Result<(), AnimationError> {
        while self.written < self.pushed {
            self.collect(true)?;
        }
        if self.pushed == 0 || first.dimensions() != self.size {
            return Err(AnimationError::Frames);
        }
        let frames = u32::try_from(self.pushed).map_err(|_| AnimationError::Frames)?;
        let options = self.options;
        let assembled = (|| {
            self.scratch.flush()?;
            let scratch = self.scratch.get_mut();
            scratch.rewind()?;
            match options.format {
                AnimationFormat::Apng => apng::assemble(
                    out,
                    first,
                    frames,
                    options.fps,
                    options.compression,
                    record,
                    scratch,
                ),
                AnimationFormat::Gif => gif_format::assemble(out, first, options.fps, scratch),
            }
        })();
        assembled.map_err(|e| write_error(&self.path, e))?;
        Ok(())
    }
}

fn write_error(path: &Path, source: io::Error) -> AnimationError {
    files::FileError::Write {
        path: path.to_owned(),
        source,
    }
    .into()
}

/// Writes `frames` (at least one, all of one size) through an [`AnimationStream`]; returns
/// whether an existing file was replaced.
pub fn write_animation(
    path: &Path,
    frames: impl IntoIterator<Item = image::RgbaImage>,
    options: AnimationOptions,
    record: Option<&str>,
    policy: &Overwrite,
) -> Result<bool, AnimationError> {
    let mut frames = frames.into_iter();
    let first = frames.next().ok_or(AnimationError::Frames)?;
    let mut stream = AnimationStream::create(path, policy, first.dimensions(), options)?;
    stream.push(first.clone())?;
    for frame in frames {
        stream.push(frame)?;
    }
    stream.finish(&first, record)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::export::png::png_chunks;

    /// Opaque frames where a few pixels change (and one frame repeats its predecessor).
    fn frames(n: u8) -> Vec<image::RgbaImage> {
        (0..n)
            .map(|i| {
                let v = if i == 2 { 1 } else { i };
                image::RgbaImage::from_fn(5, 3, |x, y| {
                    if x == u32::from(v) % 5 && y > 0 {
                        image::Rgba([v * 40, 0, 255 - v, 255])
                    } else {
                        image::Rgba([10, 20, 30, 255])
                    }
                })
            })
            .collect()
    }

    fn options(format: AnimationFormat, threads: usize) -> AnimationOptions {
        AnimationOptions {
            threads,
            ..AnimationOptions::new(format, 30)
        }
    }

    fn decoded_apng(bytes: &[u8]) -> Vec<image::RgbaImage> {
        let decoder = image::codecs::png::PngDecoder::new(std::io::Cursor::new(bytes)).unwrap();
        image::AnimationDecoder::into_frames(decoder.apng().unwrap())
            .collect_frames()
            .unwrap()
            .into_iter()
            .map(image::Frame::into_buffer)
            .collect()
    }

    #[test]
    fn apng_loops_forever_with_one_control_chunk_per_frame() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("a.png");
        let policy = Overwrite::new(false);
        write_animation(
            &path,
            frames(4),
            options(AnimationFormat::Apng, 2),
            Some("{}"),
            &policy,
        )
        .unwrap();
        let bytes = std::fs::read(&path).unwrap();
        let chunks = png_chunks(&bytes).unwrap();
        let actl = chunks.iter().find(|(k, _)| k == b"acTL").unwrap().1;
        assert_eq!(u32::from_be_bytes(actl[0..4].try_into().unwrap()), 4);
        assert_eq!(u32::from_be_bytes(actl[4..8].try_into().unwrap()), 0);
        assert_eq!(chunks.iter().filter(|(k, _)| k == b"fcTL").count(), 4);
        // The first frame is the default image (its fcTL comes before IDAT); every fcTL and
        // fdAT carries the next sequence number in file order; every frame lasts 1/30 s.
        let position = |kind: &[u8; 4]| chunks.iter().position(|(k, _)| k == kind).unwrap();
        assert!(position(b"acTL") < position(b"fcTL"));
        assert!(position(b"fcTL") < position(b"IDAT"));
        let be16 = |b: &[u8]| u16::from_be_bytes(b.try_into().unwrap());
        let mut sequence = 0;
        for (kind, data) in &chunks {
            if kind == b"fcTL" || kind == b"fdAT" {
                assert_eq!(u32::from_be_bytes(data[0..4].try_into().unwrap()), sequence);
                sequence += 1;
            }
            if kind == b"fcTL" {
                assert_eq!((be16(&data[20..22]), be16(&data[22..24])), (1, 30));
            }
        }
        assert!(sequence > 4, "frames after the first are fdAT chunks");
        assert_eq!(
            decoded_apng(&bytes),
            frames(4),
            "decodes back to the same frames"
        );
        // The same bytes whatever the number of threads, and no scratch file left.
        for threads in [1, 3] {
            let other = dir.path().join(format!("t{threads}.png"));
            write_animation(
                &other,
                frames(4),
                options(AnimationFormat::Apng, threads),
                Some("{}"),
                &policy,
            )
            .unwrap();
            assert!(std::fs::read(&other).unwrap() == bytes, "{threads} threads");
        }
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 3);
    }

    /// Frames whose bottom-right pixel (a "caption") never changes while the rest does.
    fn captioned(n: u8, caption: u8) -> Vec<image::RgbaImage> {
        frames(n)
            .into_iter()
            .map(|mut frame| {
                frame.put_pixel(4, 0, image::Rgba([caption, caption, 0, 255]));
                frame
            })
            .collect()
    }

    #[test]
    fn a_final_first_frame_shows_its_unchanging_pixels_in_every_frame() {
        let dir = tempfile::tempdir().unwrap();
        for format in [AnimationFormat::Apng, AnimationFormat::Gif] {
            let path = dir.path().join(format!("a.{format:?}"));
            let mut stream =
                AnimationStream::create(&path, &Overwrite::new(false), (5, 3), options(format, 2))
                    .unwrap();
            for frame in captioned(5, 0) {
                stream.push(frame).unwrap();
            }
            assert_eq!(stream.pushed(), 5);
            let final_frames = captioned(5, 200);
            stream.finish(&final_frames[0], None).unwrap();
            let bytes = std::fs::read(&path).unwrap();
            let decoded = match format {
                AnimationFormat::Apng => decoded_apng(&bytes),
                AnimationFormat::Gif => {
                    let decoder =
                        image::codecs::gif::GifDecoder::new(std::io::Cursor::new(&bytes)).unwrap();
                    image::AnimationDecoder::into_frames(decoder)
                        .collect_frames()
                        .unwrap()
                        .into_iter()
                        .map(image::Frame::into_buffer)
                        .collect()
                }
            };
            assert_eq!(decoded, final_frames, "{format:?}");
        }
    }

    #[test]
    fn an_abandoned_stream_leaves_nothing_behind() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("a.png");
        std::fs::write(&path, b"earlier clip").unwrap();
        let mut stream = AnimationStream::create(
            &path,
            &Overwrite::new(true),
            (5, 3),
            options(AnimationFormat::Apng, 2),
        )
        .unwrap();
        for frame in frames(3) {
            stream.push(frame).unwrap();
        }
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 2);
        drop(stream);
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1);
        assert_eq!(std::fs::read(&path).unwrap(), b"earlier clip");
    }

    #[test]
    fn gifs_loop_and_need_frames() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("a.gif");
        let gif = options(AnimationFormat::Gif, 2);
        write_animation(&path, frames(2), gif, None, &Overwrite::new(false)).unwrap();
        let bytes = std::fs::read(&path).unwrap();
        assert!(bytes.starts_with(b"GIF89a"));
        assert!(matches!(
            write_animation(&path, Vec::new(), gif, None, &Overwrite::new(true)),
            Err(AnimationError::Frames)
        ));
    }
}
