//! Writing results: clips (streamed animated PNG/GIF, MP4/WebM through ffmpeg), PNG images with their reproducibility record embedded, labelled comparison
//! sheets of zoomed crops, text rendering for them, error heatmaps with legends, bench reports
//! (JSON and Markdown) and charts.

pub mod animation;
pub mod apng;
pub mod charts;
pub mod clip;
pub mod clip_writer;
pub mod frame_change;
pub mod gif;
pub mod heatmap;
pub mod html;
pub mod png;
pub mod radiance;
pub mod report;
pub mod report_markdown;
pub mod sheet;
pub mod tradeoff;
pub mod video;

pub use self::png::{ExportError, write_png};

/// The stem of output file names for a scene: its name for a built-in scene, and for a file
/// the file stem plus a short hash of its full path (`sponza-3fa9c1`), so models of the same
/// name from different folders never overwrite each other's images. The PNG record keeps the
/// full path.
pub fn output_stem(scene_name: &str, scene_spec: &str) -> String {
    if crate::scene::procedural::BUILTIN_SCENES.contains(&scene_spec) {
        return scene_name.to_owned();
    }
    let full = std::fs::canonicalize(scene_spec)
        .map_or_else(|_| scene_spec.to_owned(), |p| p.display().to_string());
    // FNV-1a: stable across runs, platforms and Rust versions, unlike std's hasher.
    let hash = full.bytes().fold(0x811c_9dc5_u32, |h, b| {
        (h ^ u32::from(b)).wrapping_mul(0x0100_0193)
    });
    format!("{scene_name}-{:06x}", hash & 0xff_ffff)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn output_stems_differ_by_folder() {
        assert_eq!(output_stem("atrium", "atrium"), "atrium");
        let a = output_stem("sponza", "/a/sponza.obj");
        let b = output_stem("sponza", "/b/sponza.obj");
        assert_ne!(a, b);
        assert!(
            a.starts_with("sponza-") && a.len() == "sponza-".len() + 6,
            "{a}"
        );
        assert_eq!(a, output_stem("sponza", "/a/sponza.obj"));
    }
}
