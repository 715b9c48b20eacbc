//! A clip as one self-contained HTML page that opens offline in any browser: every frame's
//! panes embedded as a lossless PNG sprite (the panes side by side, unzoomed, base64 in a data
//! URI), played in lockstep with play/pause/step, a draggable wipe between any two panes, a
//! synchronised nearest-neighbour zoom (integer factors, whole source pixels; drag a pane to
//! move every view), the figures as a table and the full record (the recipe that reproduces
//! the clip). The player is `html_page.js`, embedded as it is.
//!
//! The page is written as the frames render ([`HtmlPage::push`]: one `<script>` per frame, so
//! memory holds one frame), and the record, known at the end, comes last. Under `#selftest`
//! the page steps, zooms, moves the wipe and plays by itself, writes what its wipe view shows
//! into `#selftest` and the console, and closes; tests/html.rs checks it in headless Chromium
//! against the embedded frames. Written atomically ([`crate::files::PendingFile`]).

use std::io::{self, Write};
use std::path::Path;

use base64::Engine;

use crate::files::{FileError, Overwrite, PendingFile};

/// Widest view of the page, CSS pixels (a wider clip is shown zoomed out of a window).
const MAX_VIEW: u32 = 960;

/// The player.
const PLAYER: &str = include_str!("html_page.js");

/// Errors of writing a page.
#[derive(Debug, thiserror::Error)]
pub enum HtmlError {
    /// The file could not be written.
    #[error(transparent)]
    File(#[from] FileError),
    /// A frame's panes differ from the page's.
    #[error("every frame of a page needs its {panes} panes of {width}x{height} pixels")]
    Panes {
        /// Panes.
        panes: usize,
        /// Width of a pane.
        width: u32,
        /// Height.
        height: u32,
    },
}

/// What the page shows besides the frames.
#[derive(serde::Serialize)]
struct Meta<'a> {
    labels: &'a [String],
    width: u32,
    height: u32,
    fps: u16,
    zoom: u32,
    max_view: u32,
}

/// JSON safe inside `<script>` (no `</script>` can end it early).
fn script_json(value: &impl serde::Serialize) -> io::Result<String> {
    Ok(serde_json::to_string(value)?.replace("</", "<\\/"))
}

fn escape_html(text: &str) -> String {
    text.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
}

/// A page being written.
pub struct HtmlPage {
    output: PendingFile,
    panes: usize,
    size: (u32, u32),
}

impl HtmlPage {
    /// Starts the page at `path` (checked against `policy`) for `labels.len()` panes of `size`
    /// pixels each, played at `fps`, shown `zoom` times enlarged.
    pub fn create(
        path: &Path,
        policy: &Overwrite,
        title: &str,
        labels: &[String],
        size: (u32, u32),
        fps: u16,
        zoom: u32,
    ) -> Result<Self, HtmlError> {
        let mut output = PendingFile::create(path, policy)?;
        let meta = Meta {
            labels,
            width: size.0,
            height: size.1,
            fps: fps.max(1),
            zoom: zoom.max(1),
            max_view: MAX_VIEW,
        };
        let head = (|| -> io::Result<()> {
            let out = output.writer();
            write!(out, "{}", HEAD.replace("{title}", &escape_html(title)))?;
            writeln!(
                out,
                "<script>const META = {}; const F = [];</script>",
                script_json(&meta)?
            )
        })();
        head.map_err(|e| output.write_error(e))?;
        Ok(Self {
            output,
            panes: labels.len(),
            size,
        })
    }

    /// Adds the next frame: its panes, in label order.
    pub fn push(&mut self, panes: &[&image::RgbaImage]) -> Result<(), HtmlError> {
        let (width, height) = self.size;
        if panes.len() != self.panes || panes.iter().any(|p| p.dimensions() != self.size) {
            return Err(HtmlError::Panes {
                panes: self.panes,
                width,
                height,
            });
        }
        let mut sprite = image::RgbaImage::new(width * self.panes as u32, height);
        for (i, pane) in panes.iter().enumerate() {
            image::imageops::replace(&mut sprite, *pane, i64::from(width) * i as i64, 0);
        }
        let written = (|| -> io::Result<()> {
            let mut png = Vec::new();
            let mut encoder = ::png::Encoder::new(&mut png, sprite.width(), sprite.height());
            encoder.set_color(::png::ColorType::Rgba);
            encoder.set_depth(::png::BitDepth::Eight);
            encoder.set_compression(::png::Compression::Fast);
            let mut writer = encoder.write_header().map_err(io::Error::other)?;
            writer
                .write_image_data(sprite.as_raw())
                .map_err(io::Error::other)?;
            writer.finish().map_err(io::Error::other)?;
            let data = base64::engine::general_purpose::STANDARD.encode(&png);
            writeln!(
                self.output.writer(),
                "<script>F.push(\"data:image/png;base64,{data}\");</script>"
            )
        })();
        written.map_err(|e| self.output.write_error(e))?;
        Ok(())
    }

    /// Ends the page with `record` (the clip's JSON record) and the player, and moves it into
    /// place; returns whether an existing file was replaced.
    pub fn finish(mut self, record: &serde_json::Value) -> Result<bool, HtmlError> {
        let written = (|| -> io::Result<()> {
            let out = self.output.writer();
            writeln!(
                out,
                "<script>const RECORD = {};</script>",
                script_json(record)?
            )?;
            writeln!(out, "<script>\n{PLAYER}</script>\n</body>\n</html>")
        })();
        written.map_err(|e| self.output.write_error(e))?;
        Ok(self.output.commit()?)
    }
}

/// The page up to the frames: layout, styles and controls.
const HEAD: &str = r#"<!doctype html>
<html lang="en">
<head>
<meta charset="utf-8">
<meta name="viewport" content="width=device-width, initial-scale=1">
<title>{title}</title>
<style>
body { background: #18191e; color: #e8e8ec; font: 14px system-ui, sans-serif; margin: 16px; }
h1 { font-size: 18px; font-weight: 600; }
button, select, input { font: inherit; }
#controls { display: flex; gap: 8px; align-items: center; flex-wrap: wrap; margin: 8px 0; }
#wipebox { position: relative; }
#wipebox canvas, #grid canvas { display: block; image-rendering: pixelated; border: 1px solid #464850; }
#wipeline { position: absolute; top: 0; bottom: 0; width: 2px; background: #ffd24a; pointer-events: none; }
#grid { display: flex; flex-wrap: wrap; gap: 12px; margin-top: 12px; }
#grid figure { margin: 0; }
figcaption { color: #a0a2aa; margin-top: 4px; }
table { border-collapse: collapse; margin-top: 16px; }
th, td { border-bottom: 1px solid #464850; padding: 4px 10px; text-align: right; }
th:first-child, td:first-child { text-align: left; }
pre { background: #23242b; padding: 8px; overflow: auto; max-height: 24em; }
</style>
</head>
<body>
<h1>{title}</h1>
<div id="controls">
<button id="play">Play</button><button id="prev" title="previous frame">&#9664;</button><button id="next" title="next frame">&#9654;</button>
<span>frame <span id="frame"></span></span>
<label>zoom <input id="zoom" type="range" min="1" max="32" step="1"></label><span id="zoomvalue"></span>
<label>wipe <select id="left"></select></label><label>| <select id="right"></select></label>
</div>
<div id="wipebox"><canvas id="wipe"></canvas><div id="wipeline"></div></div>
<div id="grid"></div>
<table id="metrics"></table>
<details><summary>Recipe: the clip's record (<code>aa-lab clip</code> reproduces it from these settings)</summary><pre id="recipe"></pre></details>
<pre id="selftest" hidden></pre>
"#;
