//! Where a clip's frames go, by the output's extension ([`ClipFormat`]): a streamed animated
//! PNG or GIF ([`super::animation`]), or a browser-playable MP4/WebM ([`super::video`]).
//!
//! A video's frames are full images, and a clip's first frame is final only once the last has
//! rendered (its captions hold the figures over the whole clip). So a video is first streamed
//! into a lossless animated PNG in an anonymous scratch file, compressed on every core like any
//! APNG, and [`ClipWriter::finish`] then decodes it frame by frame (memory holds one frame)
//! and pipes the frames to ffmpeg. An unknown extension is refused before any work, naming the
//! formats aa-lab writes.

use std::io::BufReader;
use std::path::{Path, PathBuf};

use super::animation::{AnimationError, AnimationFormat, AnimationOptions, AnimationStream};
use super::video::{VideoError, VideoFormat, VideoStream};
use crate::files::Overwrite;

/// The formats and their extensions, as error messages list them.
pub const FORMATS: &str =
    "animated PNG (.png, .apng), GIF (.gif), MP4 (.mp4, H.264) or WebM (.webm, VP9)";

/// Errors of writing a clip.
#[derive(Debug, thiserror::Error)]
pub enum ClipWriteError {
    /// The output's extension names no format aa-lab writes.
    #[error("{}: aa-lab writes clips as {FORMATS}, chosen by the name's extension", path.display())]
    UnknownExtension {
        /// The output path.
        path: PathBuf,
    },
    /// Writing the animation failed.
    #[error(transparent)]
    Animation(#[from] AnimationError),
    /// Writing the video failed.
    #[error(transparent)]
    Video(#[from] VideoError),
    /// The intermediate animation of a video could not be read back.
    #[error("cannot read back the frames of {}: {reason}", path.display())]
    Intermediate {
        /// The output path.
        path: PathBuf,
        /// What went wrong.
        reason: String,
    },
}

/// What a clip is written as.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(untagged)]
pub enum ClipFormat {
    /// Animated PNG or GIF.
    Animation(AnimationFormat),
    /// MP4 or WebM.
    Video(VideoFormat),
}

impl ClipFormat {
    /// The format of an output path by its extension (any case): `.png`/`.apng`, `.gif`,
    /// `.mp4`, `.webm`; anything else is refused, naming the formats. A video format also
    /// needs ffmpeg, which is looked for now.
    pub fn of_path(path: &Path) -> Result<Self, ClipWriteError> {
        let extension = path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase);
        let format = match extension.as_deref() {
            Some("png" | "apng") => Self::Animation(AnimationFormat::Apng),
            Some("gif") => Self::Animation(AnimationFormat::Gif),
            Some("mp4") => Self::Video(VideoFormat::Mp4),
            Some("webm") => Self::Video(VideoFormat::Webm),
            _ => {
                return Err(ClipWriteError::UnknownExtension {
                    path: path.to_owned(),
                });
            }
        };
        if let Self::Video(video) = format {
            super::video::find_ffmpeg(video)?;
        }
        Ok(format)
    }
}

/// A clip being written.
pub enum ClipWriter {
    /// Straight into the animation.
    Animation(AnimationStream),
    /// Into a lossless intermediate, piped to ffmpeg at the end.
    Video {
        /// The intermediate.
        intermediate: AnimationStream,
        /// The output.
        path: PathBuf,
        /// Its policy.
        policy: Overwrite,
        /// The video format.
        format: VideoFormat,
        /// Frames per second.
        fps: u16,
    },
}

impl ClipWriter {
    /// Starts writing `path` in `format` for frames of `size` pixels (`options.format` is
    /// ignored: `format` decides).
    pub fn create(
        path: &Path,
        policy: &Overwrite,
        size: (u32, u32),
        format: ClipFormat,
        options: AnimationOptions,
    ) -> Result<Self, ClipWriteError> {
        Ok(match format {
            ClipFormat::Animation(animation) => Self::Animation(AnimationStream::create(
                path,
                policy,
                size,
                AnimationOptions {
                    format: animation,
                    ..options
                },
            )?),
            ClipFormat::Video(video) => {
                policy.check(path).map_err(AnimationError::from)?;
                super::video::check_size(video, size)?;
                Self::Video {
                    intermediate: AnimationStream::intermediate(path, size, options.threads)?,
                    path: path.to_owned(),
                    policy: policy.clone(),
                    format: video,
                    fps: options.fps,
                }
            }
        })
    }

    /// Hands `frame` to `writer`, first starting it (sized by this first frame) when there is
    /// none yet.
    pub fn push_or_start(
        writer: &mut Option<Self>,
        path: &Path,
        policy: &Overwrite,
        format: ClipFormat,
        options: AnimationOptions,
        frame: image::RgbaImage,
    ) -> Result<(), ClipWriteError> {
        let writer = match writer {
            Some(writer) => writer,
            None => writer.insert(Self::create(
                path,
                policy,
                frame.dimensions(),
                format,
                options,
            )?),
        };
        writer.push(frame)
    }

    /// Hands over the next frame (see [`AnimationStream::push`]).
    pub fn push(&mut self, frame: image::RgbaImage) -> Result<(), ClipWriteError> {
        Ok(self.stream().push(frame)?)
    }

    fn stream(&mut self) -> &mut AnimationStream {
        match self {
            Self::Animation(stream)
            | Self::Video {
                intermediate: stream,
                ..
            } => stream,
        }
    }

    /// Frames compressed so far.
    pub fn written(&mut self) -> usize {
        self.stream().written()
    }

    /// Finishes the clip (see [`AnimationStream::finish`] for `first`; `record` goes
    /// into an APNG's text chunk) and moves it into place; returns whether an existing file was
    /// replaced. `background` pads a video's odd sides.
    pub fn finish(
        self,
        first: &image::RgbaImage,
        record: Option<&str>,
        background: [u8; 4],
    ) -> Result<bool, ClipWriteError> {
        let (intermediate, path, policy, format, fps) = match self {
            Self::Animation(stream) => return Ok(stream.finish(first, record)?),
            Self::Video {
                intermediate,
                path,
                policy,
                format,
                fps,
            } => (intermediate, path, policy, format, fps),
        };
        let unreadable = |reason: String| ClipWriteError::Intermediate {
            path: path.clone(),
            reason,
        };
        let file = intermediate.finish_intermediate(first)?;
        let decoder = image::codecs::png::PngDecoder::new(BufReader::new(file))
            .and_then(|decoder| decoder.apng())
            .map_err(|e| unreadable(e.to_string()))?;
        let mut video: Option<VideoStream> = None;
        for frame in image::AnimationDecoder::into_frames(decoder) {
            let frame = frame.map_err(|e| unreadable(e.to_string()))?.into_buffer();
            let video = match &mut video {
                Some(video) => video,
                None => video.insert(VideoStream::create(
                    &path,
                    &policy,
                    frame.dimensions(),
                    format,
                    fps,
                    background,
                )?),
            };
            video.push(&frame)?;
        }
        let video = video.ok_or_else(|| unreadable("it has no frame".to_owned()))?;
        Ok(video.finish()?)
    }
}
