//! The command line: `aa-lab` opens the viewer (without a display it renders every technique
//! headless instead); `render`, `compare`, `bench`, `info` and
//! `techniques` run headless on the same engine. Parsing is clap's; each subcommand lives in
//! its own file and returns `anyhow::Result` (errors are printed once, by `main`).

mod bench;
mod compare;
mod info;
mod render;
mod sheet;

use clap::{Parser, Subcommand};

pub use bench::{BenchArgs, Sweep};
pub use compare::CompareArgs;
pub use render::{RenderArgs, parse_vec3};

/// Compare real-time antialiasing techniques on the same frame.
#[derive(Debug, Parser)]
#[command(name = "aa-lab", version, about, long_about = None, args_conflicts_with_subcommands = true)]
pub struct Cli {
    /// What to do; without a subcommand the viewer opens.
    #[command(subcommand)]
    pub command: Option<Command>,
    /// Viewer: open this built-in scene (hairball, atrium, chart) or .obj file instead of the
    /// last one.
    #[arg(long)]
    pub scene: Option<String>,
    /// Viewer: start from the default settings instead of the saved ones.
    #[arg(long)]
    pub default_settings: bool,
}

/// The subcommands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Render a scene through one or more techniques to PNG files.
    Render(Box<RenderArgs>),
    /// Lay zoomed crops of several techniques side by side in one labelled PNG.
    Sheet(Box<sheet::SheetArgs>),
    /// Score an image against a reference: SSIM, PSNR, MAE and FLIP, optionally a heatmap.
    Compare(CompareArgs),
    /// Measure every technique's GPU time, memory, shading work, image quality and flicker,
    /// and write report.json, report.md and charts.
    Bench(BenchArgs),
    /// Print what the GPU adapter can do (sample counts, timestamps, limits).
    Info {
        /// Print JSON instead of text.
        #[arg(long)]
        json: bool,
    },
    /// List every technique with its availability on this adapter.
    Techniques {
        /// Print JSON instead of text.
        #[arg(long)]
        json: bool,
        /// Also list every parameter with its range and help.
        #[arg(long, short)]
        verbose: bool,
    },
}

/// Runs a parsed command line.
pub fn run(cli: Cli) -> anyhow::Result<()> {
    match cli.command {
        Some(Command::Render(args)) => render::run(&args),
        Some(Command::Sheet(args)) => sheet::run(&args),
        Some(Command::Compare(args)) => compare::run(&args),
        Some(Command::Bench(args)) => bench::run(&args),
        Some(Command::Info { json }) => info::info(json),
        Some(Command::Techniques { json, verbose }) => info::techniques(json, verbose),
        None if !crate::app::display_available() => render_headless(cli.scene),
        None => Ok(crate::app::run(crate::app::LaunchOptions {
            scene: cli.scene,
            fresh_settings: cli.default_settings,
        })?),
    }
}

/// The main job where no window can open: every technique on the scene (the default one
/// unless `--scene` names another) rendered headless into `out/`, with GPU timings.
fn render_headless(scene: Option<String>) -> anyhow::Result<()> {
    eprintln!(
        "no display (neither DISPLAY nor WAYLAND_DISPLAY is set): rendering every technique \
         headless into out/ instead of opening the viewer (see `aa-lab render --help`)"
    );
    /// `aa-lab render`'s arguments parsed on their own.
    #[derive(Parser)]
    struct Headless {
        #[command(flatten)]
        render: RenderArgs,
    }
    let mut argv = vec!["aa-lab", "--technique", "all", "--out", "out", "--timings"];
    if let Some(scene) = scene.as_deref() {
        argv.extend(["--scene", scene]);
    }
    render::run(&Headless::try_parse_from(argv)?.render)
}
