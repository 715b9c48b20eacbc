//! Measures the clip encoder's throughput on real clip frames: it decodes the first frames of
//! an animated PNG (e.g. one `aa-lab clip` wrote), then writes them again through
//! [`aa_lab::export::clip_writer::ClipWriter`] once per thread count, in the format of the
//! output name's extension (APNG, GIF, MP4, WebM), and prints the time, frames per second and
//! size (decoding is not timed):
//!
//! ```sh
//! cargo run --release --example encode_throughput -- clip.png 12 1,2,16 out.png [fast|best]
//! ```

use std::path::Path;
use std::time::Instant;

use aa_lab::export::animation::{AnimationFormat, AnimationOptions};
use aa_lab::export::apng::Compression;
use aa_lab::export::clip_writer::{ClipFormat, ClipWriter};
use aa_lab::export::sheet::BACKGROUND_RGBA;
use aa_lab::files::Overwrite;
use anyhow::Context;
use clap::ValueEnum;

fn main() -> anyhow::Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let [input, count, threads, out, rest @ ..] = args.as_slice() else {
        anyhow::bail!(
            "usage: encode_throughput CLIP.png FRAMES THREADS[,THREADS...] OUT.(png|gif|mp4|webm) [fast|best]"
        );
    };
    let count: usize = count.parse().context("FRAMES")?;
    let compression = match rest.first() {
        Some(name) => Compression::from_str(name, true).map_err(anyhow::Error::msg)?,
        None => Compression::Fast,
    };
    let out = Path::new(out);
    let format = ClipFormat::of_path(out)?;
    let file = std::io::BufReader::new(std::fs::File::open(input).context("the clip")?);
    let decoder = image::codecs::png::PngDecoder::new(file)?;
    let frames: Vec<image::RgbaImage> = image::AnimationDecoder::into_frames(decoder.apng()?)
        .take(count)
        .map(|frame| frame.map(image::Frame::into_buffer))
        .collect::<Result<_, _>>()?;
    let size = frames
        .first()
        .context("the clip has no frame")?
        .dimensions();
    for threads in threads.split(',') {
        let threads: usize = threads.parse().context("THREADS")?;
        let options = AnimationOptions {
            compression,
            threads,
            ..AnimationOptions::new(AnimationFormat::Apng, 30)
        };
        let start = Instant::now();
        let policy = Overwrite::new(true);
        let mut writer = ClipWriter::create(out, &policy, size, format, options)?;
        for frame in &frames {
            writer.push(frame.clone())?;
        }
        writer.finish(&frames[0], None, BACKGROUND_RGBA)?;
        let seconds = start.elapsed().as_secs_f64();
        let bytes = std::fs::metadata(out)?.len();
        println!(
            "{} with {threads} threads ({compression:?}): {} frames of {}x{} in {seconds:.2} s = {:.2} frames/s, {:.1} MB",
            out.display(),
            frames.len(),
            size.0,
            size.1,
            frames.len() as f64 / seconds,
            bytes as f64 / 1e6
        );
    }
    Ok(())
}
