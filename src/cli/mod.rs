//! The command line: `aa-lab` opens the viewer (without a display it renders every technique
//! headless instead); `render`, `sheet`, `clip`, `compare`, `bench`, `info` and
//! `techniques` run headless on the same engine. Parsing is clap's; each subcommand lives in
//! its own file and returns `anyhow::Result` (errors are printed once, by `main`, through
//! [`error_message`]).
//!
//! Overwrite policy, the same for every subcommand: an existing file is never replaced unless
//! `--force` is given, an input of the command is never replaced even then, and every output
//! is written to a temporary file and renamed into place (see [`crate::files`]). The main job
//! without a display renders into `out/` with `--force`: that folder is its own scratch space.

mod bench;
mod camera;
mod clip;
mod clip_frames;
mod clip_record;
mod clip_sequences;
mod compare;
mod compare_hdr;
mod compare_sequences;
mod heatmap_files;
mod info;
mod parse;
mod render;
mod sheet;

use clap::{Parser, Subcommand};

use crate::sequence::is_sequence_path;

pub use bench::{BenchArgs, Sweep};
pub use camera::parse_vec3;
pub use clip::ClipArgs;
pub use compare::CompareArgs;
pub use render::{RenderArgs, TechniqueArgs, technique_specs};

/// The overwrite policy as `--help` states it (see the module docs).
const FILES_HELP: &str = "Files: aa-lab never replaces an existing file unless the command is given \
--force, and never writes over one of the command's inputs, even with --force. Outputs are \
written to a temporary file in the same folder and renamed into place. The viewer's export \
takes the next free numbered name instead.";

/// Compare real-time antialiasing techniques on the same frame.
#[derive(Debug, Parser)]
#[command(
    name = "aa-lab",
    version,
    about,
    long_about = None,
    after_help = FILES_HELP,
    args_conflicts_with_subcommands = true
)]
pub struct Cli {
    /// What to do; without a subcommand the viewer opens.
    #[command(subcommand)]
    pub command: Option<Command>,
    /// Viewer: open this built-in scene (hairball, atrium, chart, sparkle, glass) or .obj file instead of the
    /// last one.
    #[arg(long)]
    pub scene: Option<String>,
    /// Viewer: start from the default settings instead of the saved ones.
    #[arg(long)]
    pub default_settings: bool,
    /// Viewer: compare these images (up to five PNG/JPEG files of one size, e.g. captures
    /// from another renderer) instead of the scene; the first whose name has the word
    /// `reference` or `ref`, else the first, is the reference (with five, it is no pane).
    #[arg(long, num_args = 1.., value_name = "IMAGE")]
    pub images: Vec<std::path::PathBuf>,
    /// Viewer: play these image sequences in lockstep (up to five folders or globs of
    /// numbered PNG/JPEG/OpenEXR frames of one size) instead of the scene; the first whose
    /// name has the word `reference` or `ref`, else the first, is the reference (with five,
    /// four panes and the reference apart).
    #[arg(long, num_args = 1.., value_name = "SEQUENCE", conflicts_with = "images")]
    pub sequences: Vec<std::path::PathBuf>,
}

/// The subcommands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Render a scene through one or more techniques to PNG files.
    Render(Box<RenderArgs>),
    /// Lay zoomed crops of several techniques side by side in one labelled PNG.
    Sheet(Box<sheet::SheetArgs>),
    /// Render a camera motion through several techniques and the reference into a looping
    /// animation (APNG, or GIF for a .gif path) of zoomed panes side by side, with each
    /// technique's temporal instability and ghosting in <out>.json.
    Clip(Box<ClipArgs>),
    /// Score an image against a reference: SSIM, PSNR, MAE and FLIP, optionally a heatmap; two
    /// sequences (folders or globs of numbered frames) frame by frame and over time.
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

/// Makes SIGINT, SIGTERM and SIGHUP remove the temporary files of the outputs being written
/// before the process ends (with 128 + the signal's number, as the shell reports a signal),
/// so an interrupted export leaves nothing behind and touches no existing output (see
/// [`crate::files::remove_temporaries_and_exit`]). A thread of its own waits for the signals.
pub fn remove_temporaries_on_interrupt() -> std::io::Result<()> {
    use signal_hook::consts::{SIGHUP, SIGINT, SIGTERM};
    let mut signals = signal_hook::iterator::Signals::new([SIGINT, SIGTERM, SIGHUP])?;
    std::thread::Builder::new()
        .name("aa-lab signals".to_owned())
        .spawn(move || {
            if let Some(signal) = signals.forever().next() {
                crate::files::remove_temporaries_and_exit(128 + signal);
            }
        })?;
    Ok(())
}

/// Parses the process's command line, noting what the derived parser cannot say: whether
/// `clip` was given `--technique` (a clip of captured sequences renders techniques only when
/// asked to). Exits with clap's message on a bad command line.
pub fn parse() -> Cli {
    use clap::{CommandFactory, FromArgMatches, parser::ValueSource};
    let matches = Cli::command().get_matches();
    let mut cli = Cli::from_arg_matches(&matches).unwrap_or_else(|err| err.exit());
    if let (Some(Command::Clip(args)), Some(("clip", clip))) =
        (&mut cli.command, matches.subcommand())
    {
        args.techniques_given = clip.value_source("technique") == Some(ValueSource::CommandLine);
    }
    cli
}

/// Runs a parsed command line.
pub fn run(cli: Cli) -> anyhow::Result<()> {
    let techniques = match &cli.command {
        Some(Command::Render(args)) => Some(&args.techniques),
        Some(Command::Sheet(args)) => Some(&args.techniques),
        Some(Command::Clip(args)) => Some(&args.techniques),
        _ => None,
    };
    crate::aa::user::build::set_build_wait(techniques.map_or_else(
        || crate::aa::user::BuildWait {
            progress: Some(render::print_build_progress),
            ..Default::default()
        },
        TechniqueArgs::build_wait,
    ));
    match cli.command {
        Some(Command::Render(args)) => render::run(&args),
        Some(Command::Sheet(args)) => sheet::run(&args),
        Some(Command::Clip(args)) => clip::run(&args),
        Some(Command::Compare(args)) => run_compare(&args),
        Some(Command::Bench(args)) => bench::run(&args),
        Some(Command::Info { json }) => info::info(json),
        Some(Command::Techniques { json, verbose }) => info::techniques(json, verbose),
        None if !crate::app::display_available()
            && (!cli.images.is_empty() || !cli.sequences.is_empty()) =>
        {
            anyhow::bail!(
                "--images and --sequences open the viewer, and there is no display (neither \
                 DISPLAY nor WAYLAND_DISPLAY is set); `aa-lab compare` scores images and \
                 sequences headless"
            )
        }
        None if !crate::app::display_available() => render_headless(cli.scene),
        None => Ok(crate::app::run(crate::app::LaunchOptions {
            scene: cli.scene,
            fresh_settings: cli.default_settings,
            images: cli.images,
            sequences: cli.sequences,
            ..Default::default()
        })?),
    }
}

/// The main job where no window can open: every technique on the scene (the default one
/// unless `--scene` names another) rendered headless into `out/`, with GPU timings.
fn render_headless(scene: Option<String>) -> anyhow::Result<()> {
    eprintln!(
        "no display (neither DISPLAY nor WAYLAND_DISPLAY is set): rendering every technique \
         headless into out/ (replacing earlier renders there) instead of opening the viewer \
         (see `aa-lab render --help`)"
    );
    /// `aa-lab render`'s arguments parsed on their own.
    #[derive(Parser)]
    struct Headless {
        #[command(flatten)]
        render: RenderArgs,
    }
    let mut argv = vec![
        "aa-lab",
        "--technique",
        "all",
        "--out",
        "out",
        "--timings",
        "--force",
    ];
    if let Some(scene) = scene.as_deref() {
        argv.extend(["--scene", scene]);
    }
    render::run(&Headless::try_parse_from(argv)?.render)
}

/// The text `main` prints for an error: the error and its causes joined by `: `, leaving out a
/// cause whose text the message already contains (errors that quote their source would
/// otherwise print it twice: `Is a directory (os error 21): Is a directory (os error 21)`).
pub fn error_message(err: &anyhow::Error) -> String {
    let mut text = String::new();
    for cause in err.chain() {
        let cause = cause.to_string();
        if text.contains(&cause) {
            continue;
        }
        if !text.is_empty() {
            text.push_str(": ");
        }
        text.push_str(&cause);
    }
    text
}

/// `aa-lab compare`: two images ([`compare`]; two OpenEXR images: [`compare_hdr`]) or two
/// sequences ([`compare_sequences`]).
fn run_compare(args: &CompareArgs) -> anyhow::Result<()> {
    match (
        is_sequence_path(&args.reference),
        is_sequence_path(&args.test),
    ) {
        (true, true) if args.edge_gain.is_some() => anyhow::bail!(
            "--edge-gain scores one image against No AA's image of the same frame, not \
             sequences"
        ),
        (true, true) => compare_sequences::run(args),
        (false, false) if args.tonemap != crate::graph::hdr::TonemapChoice::Auto => anyhow::bail!(
            "--tonemap applies to sequences of OpenEXR frames; two OpenEXR images are scored \
             with HDR-FLIP over a range of exposures, other images as they are"
        ),
        (false, false) if args.jod => anyhow::bail!(
            "--jod scores two sequences (ColorVideoVDP is a video metric); record a clip with \
             `aa-lab clip --jod` or compare two folders of frames"
        ),
        (false, false)
            if crate::export::radiance::is_exr(&args.reference)
                && crate::export::radiance::is_exr(&args.test)
                && args.edge_gain.is_none() =>
        {
            compare_hdr::run(args)
        }
        (false, false) => compare::run(args),
        (reference, _) => anyhow::bail!(
            "cannot compare {} with {}: {} is a sequence (a folder or a pattern of frames) and \
             the other is not; compare two images or two sequences",
            args.reference.display(),
            args.test.display(),
            if reference {
                "the reference"
            } else {
                "the test"
            }
        ),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn causes_already_quoted_are_printed_once() {
        let io = std::io::Error::from_raw_os_error(21);
        let quoted = crate::files::FileError::Read {
            path: "/tmp/x.obj".into(),
            source: io,
        };
        let err = anyhow::Error::new(quoted).context("cannot load the scene");
        let text = error_message(&err);
        let os = std::io::Error::from_raw_os_error(21).to_string();
        assert_eq!(text.matches(&os).count(), 1, "{text}");
        assert!(
            text.starts_with("cannot load the scene: cannot read /tmp/x.obj"),
            "{text}"
        );
    }
}
