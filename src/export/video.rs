//! Clips as video a browser plays, encoded by the system's `ffmpeg` (found on `PATH` when the
//! clip starts; a clear error names the Debian/Ubuntu package `ffmpeg` when it is missing).
//! The frames are piped to it raw (RGBA8, `-f rawvideo`), one after the other.
//!
//! Pixel-exact panes:
//! - `.webm`: VP9 profile 1, 4:4:4 (every pixel keeps its own chroma; Chromium and Firefox play
//!   it), at the clip's own size (padded to even sides with the sheet's background colour).
//! - `.mp4`: H.264 High profile, 4:2:0 (browsers play no 4:4:4 H.264). Every pixel of the
//!   clip becomes a 2x2 block (nearest neighbour), aligned on the 2x2 chroma grid, so no
//!   chroma sample is shared by two pixels of the clip and none can smear into its neighbour;
//!   the frame is twice the clip's size, so sides above 4096 (8192 doubled, H.264's largest
//!   level) are refused.
//!
//! Both use BT.709 limited range and a high, constant quality (H.264 CRF 18, VP9 CRF 20:
//! clip edges stay sharp, and a 48-frame full-frame grid stays near 20 MB); the exact
//! ffmpeg arguments are [`ffmpeg_arguments`]. The video is written to the output's temporary
//! file ([`crate::files::PendingFile`]) and moved into place when ffmpeg succeeds.

use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::{Child, ChildStdin, Command, Stdio};

use crate::files::{self, Overwrite, PendingFile};

/// Largest side of an MP4 clip before doubling (H.264 level 6.2 allows 8192 pixels).
pub const MAX_MP4_SIDE: u32 = 4096;
/// Largest side of a WebM clip (VP9 allows 65536; browsers decode up to 16384).
pub const MAX_WEBM_SIDE: u32 = 16384;

/// Errors of writing a video.
#[derive(Debug, thiserror::Error)]
pub enum VideoError {
    /// ffmpeg is not installed.
    #[error(
        "{format} clips are encoded by the system's ffmpeg, and there is no `ffmpeg` on PATH: \
         install it (Debian/Ubuntu: `apt-get install ffmpeg`), or write an animated PNG \
         (.png) or GIF (.gif)"
    )]
    NoFfmpeg {
        /// MP4 or WebM.
        format: &'static str,
    },
    /// The clip is too large for the codec.
    #[error(
        "a {format} clip is at most {limit} pixels a side; this one is {width}x{height} (use \
         --region, fewer techniques, or .webm)"
    )]
    TooLarge {
        /// MP4 or WebM.
        format: &'static str,
        /// The limit.
        limit: u32,
        /// Width.
        width: u32,
        /// Height.
        height: u32,
    },
    /// The output could not be written.
    #[error(transparent)]
    File(#[from] files::FileError),
    /// ffmpeg failed.
    #[error("ffmpeg failed writing {}: {message}", path.display())]
    Ffmpeg {
        /// The output.
        path: PathBuf,
        /// Its error output, or what went wrong with it.
        message: String,
    },
}

/// Which video an output path asks for.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum VideoFormat {
    /// H.264 in MP4, 4:2:0 with every pixel doubled.
    Mp4,
    /// VP9 profile 1 (4:4:4) in WebM.
    Webm,
}

impl VideoFormat {
    /// Its name in messages.
    pub fn name(self) -> &'static str {
        match self {
            Self::Mp4 => "MP4",
            Self::Webm => "WebM",
        }
    }

    /// How many times each pixel is repeated in each direction.
    pub fn scale(self) -> u32 {
        match self {
            Self::Mp4 => 2,
            Self::Webm => 1,
        }
    }

    fn max_side(self) -> u32 {
        match self {
            Self::Mp4 => MAX_MP4_SIDE,
            Self::Webm => MAX_WEBM_SIDE,
        }
    }
}

/// The `ffmpeg` on `PATH`, or the error naming the package.
pub fn find_ffmpeg(format: VideoFormat) -> Result<PathBuf, VideoError> {
    std::env::var_os("PATH")
        .iter()
        .flat_map(std::env::split_paths)
        .map(|dir| dir.join("ffmpeg"))
        .find(|path| path.is_file())
        .ok_or(VideoError::NoFfmpeg {
            format: format.name(),
        })
}

/// ffmpeg's arguments for `size` frames (even sides) at `fps` into `out`.
pub fn ffmpeg_arguments(
    format: VideoFormat,
    size: (u32, u32),
    fps: u16,
    out: &Path,
) -> Vec<String> {
    let mut args: Vec<String> = [
        "-hide_banner",
        "-loglevel",
        "error",
        "-f",
        "rawvideo",
        "-pix_fmt",
        "rgba",
        "-video_size",
        &format!("{}x{}", size.0, size.1),
        "-framerate",
        &fps.max(1).to_string(),
        "-i",
        "pipe:0",
        "-an",
        "-vf",
    ]
    .map(str::to_owned)
    .into();
    let scale = format.scale();
    let (pixel_format, codec): (&str, &[&str]) = match format {
        VideoFormat::Mp4 => (
            "yuv420p",
            &[
                "-c:v",
                "libx264",
                "-preset",
                "veryfast",
                "-crf",
                "18",
                "-movflags",
                "+faststart",
                "-f",
                "mp4",
            ],
        ),
        VideoFormat::Webm => (
            "yuv444p",
            &[
                "-c:v",
                "libvpx-vp9",
                "-profile:v",
                "1",
                "-crf",
                "20",
                "-b:v",
                "0",
                "-deadline",
                "good",
                "-cpu-used",
                "5",
                "-row-mt",
                "1",
                "-f",
                "webm",
            ],
        ),
    };
    args.push(format!(
        "scale=iw*{scale}:ih*{scale}:flags=neighbor+accurate_rnd+full_chroma_int:out_color_matrix=bt709:out_range=tv,format={pixel_format}"
    ));
    args.extend(codec.iter().map(|&a| a.to_owned()));
    args.extend(
        [
            "-colorspace",
            "bt709",
            "-color_primaries",
            "bt709",
            "-color_trc",
            "iec61966-2-1",
            "-color_range",
            "tv",
            "-y",
        ]
        .map(str::to_owned),
    );
    args.push(out.to_string_lossy().into_owned());
    args
}

/// Checks that frames of `size` pixels fit `format`.
pub fn check_size(format: VideoFormat, size: (u32, u32)) -> Result<(), VideoError> {
    if size.0 > format.max_side() || size.1 > format.max_side() {
        return Err(VideoError::TooLarge {
            format: format.name(),
            limit: format.max_side(),
            width: size.0,
            height: size.1,
        });
    }
    Ok(())
}

/// A video being encoded by ffmpeg.
pub struct VideoStream {
    path: PathBuf,
    /// `None` once moved into place.
    output: Option<PendingFile>,
    child: Child,
    stdin: Option<ChildStdin>,
    size: (u32, u32),
    padded: (u32, u32),
    background: [u8; 4],
}

impl VideoStream {
    /// Starts ffmpeg writing `path` (checked against `policy`) for frames of `size` pixels,
    /// padded to even sides with `background`.
    pub fn create(
        path: &Path,
        policy: &Overwrite,
        size: (u32, u32),
        format: VideoFormat,
        fps: u16,
        background: [u8; 4],
    ) -> Result<Self, VideoError> {
        let ffmpeg = find_ffmpeg(format)?;
        check_size(format, size)?;
        let padded = (size.0 + size.0 % 2, size.1 + size.1 % 2);
        let output = PendingFile::create(path, policy)?;
        let mut child = Command::new(ffmpeg)
            .args(ffmpeg_arguments(
                format,
                padded,
                fps,
                output.temporary_path(),
            ))
            .stdin(Stdio::piped())
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .map_err(|e| VideoError::Ffmpeg {
                path: path.to_owned(),
                message: format!("cannot start it: {e}"),
            })?;
        let stdin = child.stdin.take();
        Ok(Self {
            path: path.to_owned(),
            output: Some(output),
            child,
            stdin,
            size,
            padded,
            background,
        })
    }

    /// Pipes the next frame to ffmpeg.
    pub fn push(&mut self, frame: &image::RgbaImage) -> Result<(), VideoError> {
        if frame.dimensions() != self.size {
            return Err(self.failed("the frames differ in size".to_owned()));
        }
        let row = self.size.0 as usize * 4;
        let mut bytes = Vec::with_capacity(self.padded.0 as usize * self.padded.1 as usize * 4);
        for line in frame.as_raw().chunks_exact(row) {
            bytes.extend_from_slice(line);
            if self.padded.0 > self.size.0 {
                bytes.extend_from_slice(&self.background);
            }
        }
        while bytes.len() < bytes.capacity() {
            bytes.extend_from_slice(&self.background);
        }
        let written = self.stdin.as_mut().map(|stdin| stdin.write_all(&bytes));
        match written {
            Some(Ok(())) => Ok(()),
            // ffmpeg stopped: its error output says why.
            _ => Err(self.ffmpeg_error()),
        }
    }

    fn failed(&self, message: String) -> VideoError {
        VideoError::Ffmpeg {
            path: self.path.clone(),
            message,
        }
    }

    /// Waits for ffmpeg and returns its error output as the error.
    fn ffmpeg_error(&mut self) -> VideoError {
        self.stdin = None;
        let mut message = String::new();
        if let Some(mut stderr) = self.child.stderr.take() {
            use std::io::Read;
            let _ = (&mut stderr).take(64 << 10).read_to_string(&mut message);
        }
        let status = self.child.wait();
        let message = match (message.trim(), status) {
            ("", Ok(status)) => format!("it ended with {status}"),
            ("", Err(e)) => e.to_string(),
            (text, _) => text.to_owned(),
        };
        self.failed(message)
    }

    /// Closes the pipe, waits for ffmpeg and moves the video into place; returns whether an
    /// existing file was replaced.
    pub fn finish(mut self) -> Result<bool, VideoError> {
        self.stdin = None;
        let status = self.child.wait().map_err(|e| self.failed(e.to_string()))?;
        if !status.success() {
            return Err(self.ffmpeg_error());
        }
        // Nothing was written through the handle; commit syncs the file ffmpeg wrote.
        let output = self
            .output
            .take()
            .ok_or_else(|| self.failed("finished twice".to_owned()))?;
        Ok(output.commit()?)
    }
}

impl Drop for VideoStream {
    /// An abandoned video stops ffmpeg; the temporary file goes with the [`PendingFile`].
    fn drop(&mut self) {
        self.stdin = None;
        if matches!(self.child.try_wait(), Ok(None)) {
            let _ = self.child.kill();
        }
        let _ = self.child.wait();
    }
}
