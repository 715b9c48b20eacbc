//! `aa-lab sheet`: renders techniques and lays zoomed crops of chosen regions side by side in
//! one labelled PNG. The `thesis` preset reproduces the thesis' five zoom categories (shape
//! preservation, diagonals, textures, multiple edges, fine geometry) across the built-in scenes.

use std::path::{Path, PathBuf};

use anyhow::{Context, bail};

use super::render::{
    SceneArgs, SceneSource, TechniqueArgs, load_scene, spec_for_scene, technique_specs,
};
use crate::export::sheet::{self, Cell, Rect, Row, Sheet};
use crate::export::write_png;
use crate::files::{self, Overwrite};
use crate::gpu::Gpu;
use crate::spec::{self, RunOptions};

/// Arguments of `aa-lab sheet`.
#[derive(Debug, clap::Args)]
pub struct SheetArgs {
    /// Scene, size and frame (ignored for rows of a preset, which name their own scenes).
    #[command(flatten)]
    pub scene: SceneArgs,
    /// Techniques and their settings (`--technique all` for every technique this adapter runs).
    #[command(flatten)]
    pub techniques: TechniqueArgs,
    /// A curated set of rows: `thesis` (the five zoom categories across the built-in scenes).
    #[arg(long)]
    pub rows: Option<String>,
    /// A region of --scene to show: LABEL=X,Y,W,H in pixels of the rendered image (repeatable).
    #[arg(long, value_name = "LABEL=X,Y,W,H")]
    pub region: Vec<String>,
    /// Zoom factor of the crops (nearest neighbour); the sheet may be at most 16384 pixels a
    /// side.
    #[arg(long, default_value_t = 5, value_parser = clap::value_parser!(u32).range(1..))]
    pub zoom: u32,
    /// Output PNG.
    #[arg(long, short, default_value = "sheet.png")]
    pub out: PathBuf,
    /// Replace an existing output file (without it, aa-lab never replaces a file).
    #[arg(long)]
    pub force: bool,
}

/// A row of a curated sheet: a scene and a region given in pixels of a 1280x720 render
/// (scaled to the requested size).
struct CuratedRow {
    label: &'static str,
    scene: &'static str,
    region: Rect,
}

const fn r(x: u32, y: u32, width: u32, height: u32) -> Rect {
    Rect {
        x,
        y,
        width,
        height,
    }
}

/// The thesis' five zoom categories, each where a built-in scene shows it best.
const THESIS_ROWS: &[CuratedRow] = &[
    CuratedRow {
        label: "shape preservation",
        scene: "chart",
        region: r(144, 413, 64, 48),
    },
    CuratedRow {
        label: "diagonals",
        scene: "chart",
        region: r(530, 230, 64, 48),
    },
    CuratedRow {
        label: "textures",
        scene: "atrium",
        region: r(800, 420, 64, 48),
    },
    CuratedRow {
        label: "multiple edges",
        scene: "atrium",
        region: r(130, 70, 64, 48),
    },
    CuratedRow {
        label: "fine geometry",
        scene: "hairball",
        region: r(880, 330, 64, 48),
    },
];

fn parse_region(text: &str) -> anyhow::Result<(String, Rect)> {
    let (label, numbers) = text
        .split_once('=')
        .with_context(|| format!("--region {text}: expected LABEL=X,Y,W,H"))?;
    Ok((label.to_owned(), parse_rect(numbers, text)?))
}

/// Parses `X,Y,W,H` (width and height at least 1); `option` is the whole `--region` value,
/// quoted in errors.
pub(super) fn parse_rect(numbers: &str, option: &str) -> anyhow::Result<Rect> {
    let values: Vec<u32> = numbers
        .split(',')
        .map(|n| n.trim().parse::<u32>())
        .collect::<Result<_, _>>()
        .with_context(|| format!("--region {option}: X,Y,W,H must be whole numbers"))?;
    let [x, y, width, height] = values[..] else {
        bail!("--region {option}: expected four numbers X,Y,W,H");
    };
    if width == 0 || height == 0 {
        bail!("--region {option}: width and height must be at least 1");
    }
    Ok(Rect {
        x,
        y,
        width,
        height,
    })
}

/// A user's region checked against the render size: refused when it lies entirely outside,
/// cropped (with a warning) when it sticks out.
fn inside_render(text: &str, rect: Rect, size: (u32, u32)) -> anyhow::Result<Rect> {
    if rect.x >= size.0 || rect.y >= size.1 {
        bail!(
            "--region {text}: the region lies outside the {}x{} render (--size); X must be below {} and Y below {}",
            size.0,
            size.1,
            size.0,
            size.1
        );
    }
    let inside = rect.clamped(size);
    if inside != rect {
        eprintln!(
            "warning: --region {text} sticks out of the {}x{} render; showing {},{},{},{}",
            size.0, size.1, inside.x, inside.y, inside.width, inside.height
        );
    }
    Ok(inside)
}

fn scaled(rect: Rect, size: (u32, u32)) -> Rect {
    let sx = f64::from(size.0) / 1280.0;
    let sy = f64::from(size.1) / 720.0;
    let scale = |v: u32, s: f64| ((f64::from(v) * s).round() as u32).max(1);
    Rect {
        x: scale(rect.x, sx),
        y: scale(rect.y, sy),
        width: scale(rect.width, sx),
        height: scale(rect.height, sy),
    }
}

/// Runs `aa-lab sheet`.
pub fn run(args: &SheetArgs) -> anyhow::Result<()> {
    let gpu = Gpu::headless()?;
    let size = args.scene.source.size;
    let rows: Vec<(String, String, Rect)> = match args.rows.as_deref() {
        Some("thesis") => THESIS_ROWS
            .iter()
            .map(|c| {
                (
                    c.label.to_owned(),
                    c.scene.to_owned(),
                    scaled(c.region, size),
                )
            })
            .collect(),
        Some(other) => bail!("unknown --rows `{other}`; curated row sets: thesis"),
        None if args.region.is_empty() => {
            bail!("give --rows thesis or at least one --region LABEL=X,Y,W,H")
        }
        None => args
            .region
            .iter()
            .map(|text| {
                let (label, rect) = parse_region(text)?;
                let rect = inside_render(text, rect, size)?;
                Ok((label, args.scene.source.scene.clone(), rect))
            })
            .collect::<anyhow::Result<_>>()?,
    };
    let regions: Vec<Rect> = rows.iter().map(|(_, _, rect)| *rect).collect();
    let mut scenes: Vec<String> = rows.iter().map(|(_, scene, _)| scene.clone()).collect();
    let mut seen = std::collections::HashSet::new();
    scenes.retain(|scene| seen.insert(scene.clone()));

    let techniques = technique_specs(&gpu, &args.techniques)?;
    sheet::check_layout(techniques.len(), &regions, args.zoom)?;
    let mut policy = Overwrite::new(args.force);
    for scene in &scenes {
        if Path::new(scene).is_file() {
            policy = policy.with_input(Path::new(scene));
        }
    }
    policy.check(&args.out)?;
    let mut columns = Vec::new();
    let mut sheet_rows: Vec<Option<Row>> = rows.iter().map(|_| None).collect();
    let mut record = None;
    for scene_name in &scenes {
        let source = SceneSource {
            scene: scene_name.clone(),
            ..args.scene.source.clone()
        };
        let mut spec = spec_for_scene(&source, args.scene.frame, techniques.clone());
        spec.adapter = Some(format!("{} ({})", gpu.caps.adapter_name, gpu.caps.backend));
        let mut scene = load_scene(&spec, args.scene.source.strict)?;
        args.scene.source.camera.apply(&mut spec, &mut scene)?;
        eprintln!(
            "rendering {} ({} techniques)...",
            scene.name,
            spec.techniques.len()
        );
        let output = spec::run(&gpu, &scene, &spec, &RunOptions::default())?;
        columns = output
            .images
            .iter()
            .filter(|i| i.view.is_none())
            .map(|i| i.label.clone())
            .collect();
        for (i, (label, row_scene, rect)) in rows.iter().enumerate() {
            if row_scene != scene_name {
                continue;
            }
            let cells = output
                .images
                .iter()
                .filter(|image| image.view.is_none())
                .map(|image| {
                    Ok(Cell {
                        image: sheet::crop_zoom(&image.image, *rect, args.zoom)?,
                        caption: None,
                    })
                })
                .collect::<Result<_, sheet::TooLarge>>()?;
            let detail = format!(
                "{} {}x{} at {},{}",
                scene.name, rect.width, rect.height, rect.x, rect.y
            );
            sheet_rows[i] = Some(Row {
                label: label.clone(),
                detail: Some(detail),
                cells,
            });
        }
        record.get_or_insert(spec);
    }
    let Some(record) = record else {
        bail!("nothing to render")
    };
    let sheet = Sheet {
        title: format!(
            "aa-lab comparison: {}x{}, frame {}, {}x zoom",
            size.0, size.1, args.scene.frame, args.zoom
        ),
        columns,
        rows: sheet_rows.into_iter().flatten().collect(),
        footer: Some(format!(
            "{} on {}",
            spec::build_id(),
            record.adapter.clone().unwrap_or_default()
        )),
    };
    let image = sheet::compose(&sheet);
    if let Some(parent) = args.out.parent().filter(|p| !p.as_os_str().is_empty()) {
        std::fs::create_dir_all(parent)
            .with_context(|| format!("cannot create directory {}", parent.display()))?;
    }
    let replaced = write_png(
        &args.out,
        &image,
        Some(&serde_json::to_string_pretty(&record)?),
        &policy,
    )?;
    println!("{}", files::wrote_line(&args.out, replaced));
    Ok(())
}
