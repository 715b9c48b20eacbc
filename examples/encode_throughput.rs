//! Measures the clip encoder's throughput with a given number of threads, on real clip frames:
//! it decodes the first frames of an animated PNG (e.g. one `aa-lab clip` wrote), then encodes
//! them again through [`aa_lab::export::animation::AnimationStream`] once per thread count and
//! prints frames per second (decoding is not timed):
//!
//! ```sh
//! cargo run --release --example encode_throughput -- clip.png 12 1,2,16 [fast|best]
//! ```

use std::time::Instant;

use aa_lab::export::animation::{AnimationFormat, AnimationOptions, AnimationStream};
use aa_lab::export::apng::Compression;
use aa_lab::files::Overwrite;
use anyhow::Context;
use clap::ValueEnum;

fn main() -> anyhow::Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let [input, count, threads, rest @ ..] = args.as_slice() else {
        anyhow::bail!("usage: encode_throughput CLIP.png FRAMES THREADS[,THREADS...] [fast|best]");
    };
    let count: usize = count.parse().context("FRAMES")?;
    let compression = match rest.first() {
        Some(name) => Compression::from_str(name, true).map_err(anyhow::Error::msg)?,
        None => Compression::Fast,
    };
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
    let dir = std::env::temp_dir().join(format!("aa-lab-throughput-{}", std::process::id()));
    std::fs::create_dir_all(&dir)?;
    for threads in threads.split(',') {
        let threads: usize = threads.parse().context("THREADS")?;
        let out = dir.join(format!("t{threads}.png"));
        let options = AnimationOptions {
            compression,
            threads,
            ..AnimationOptions::new(AnimationFormat::Apng, 30)
        };
        let start = Instant::now();
        let mut stream = AnimationStream::create(&out, &Overwrite::new(true), size, options)?;
        for frame in &frames {
            stream.push(frame.clone())?;
        }
        stream.finish(None, None)?;
        let seconds = start.elapsed().as_secs_f64();
        let bytes = std::fs::metadata(&out)?.len();
        println!(
            "{threads} threads, {compression:?}: {} frames of {}x{} in {seconds:.2} s = {:.2} frames/s, {:.1} MB",
            frames.len(),
            size.0,
            size.1,
            frames.len() as f64 / seconds,
            bytes as f64 / 1e6
        );
    }
    std::fs::remove_dir_all(&dir)?;
    Ok(())
}
