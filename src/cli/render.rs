//! `aa-lab render`: renders a scene through one or more techniques from one frame graph and
//! writes one PNG per technique (and per debug view), each carrying its reproducibility record.

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use anyhow::{Context, bail};
use indicatif::{ProgressBar, ProgressStyle};

pub use super::parse::{parse_exposure, parse_overlay, parse_size, parse_tonemap};
use crate::aa::ssaa::Mode;
use crate::aa::{self, Named, ParamValue, params::parse_value};
use crate::export::{
    self,
    png::{MAX_RECORD_BYTES, read_record},
};
use crate::files::{self, Overwrite};
use crate::gpu::Gpu;
use crate::graph::hdr::TonemapChoice;
use crate::graph::overlay::OverlayOrder;
use crate::scene::procedural::SceneOptions;
use crate::scene::source::{self, DEFAULT_SCENE};
use crate::spec::{self, RenderSpec, RunOptions, TechniqueSpec};

use super::camera::CameraArgs;

/// Which techniques to run and how they are set up; shared by `render` and `sheet`.
#[derive(Debug, clap::Args)]
pub struct TechniqueArgs {
    /// Comma-separated technique ids, or `all` (see `aa-lab techniques`).
    #[arg(long, short, default_value = aa::none::ID)]
    pub technique: String,
    /// SSAA ordered grid: k x k samples per pixel (8 gives the 64-sample reference).
    #[arg(long, value_name = "K")]
    pub ssaa_factor: Option<u32>,
    /// SSAA jittered pattern: grid, rgss, random, poisson, halton.
    #[arg(long, value_name = "PATTERN")]
    pub ssaa_pattern: Option<String>,
    /// SSAA jittered sample count (1..=256).
    #[arg(long, value_name = "N")]
    pub ssaa_samples: Option<u32>,
    /// SSAA jittered reconstruction filter: box, tent, gaussian, blackman-harris.
    #[arg(long, value_name = "FILTER")]
    pub ssaa_filter: Option<String>,
    /// MSAA resolve: box, tent, gaussian, blackman-harris, quincunx.
    #[arg(long, value_name = "RESOLVE")]
    pub msaa_resolve: Option<String>,
    /// Apply a preset: TECHNIQUE=PRESET (repeatable), e.g. smaa=ultra.
    #[arg(long, value_name = "TECHNIQUE=PRESET")]
    pub preset: Vec<String>,
    /// Set any parameter: TECHNIQUE.KEY=VALUE (repeatable), e.g. msaa4.alpha_to_coverage=on.
    #[arg(long = "set", value_name = "TECHNIQUE.KEY=VALUE")]
    pub set: Vec<String>,
    /// Longest wait for a user technique's GPU pipeline to compile, in seconds; a build still
    /// running then is an error (progress is printed every second meanwhile).
    #[arg(
        long,
        value_name = "SECONDS",
        default_value_t = aa::user::build::DEFAULT_BUILD_TIMEOUT.as_secs_f64(),
        value_parser = parse_build_timeout
    )]
    pub build_timeout: f64,
}

/// Parses `--build-timeout`: a positive number of seconds.
fn parse_build_timeout(text: &str) -> Result<f64, String> {
    match text.parse::<f64>() {
        Ok(seconds) if seconds > 0.0 && Duration::try_from_secs_f64(seconds).is_ok() => Ok(seconds),
        _ => Err(format!(
            "expected a positive number of seconds, got `{text}`"
        )),
    }
}

impl TechniqueArgs {
    /// How user technique builds are waited for under these arguments: `--build-timeout`,
    /// with a progress line on standard error every second.
    pub fn build_wait(&self) -> aa::user::BuildWait {
        aa::user::BuildWait {
            timeout: Duration::from_secs_f64(self.build_timeout),
            progress: Some(print_build_progress),
        }
    }
}

/// The command line's progress line for a user technique that is still compiling.
pub(super) fn print_build_progress(path: &Path, elapsed: Duration) {
    eprintln!(
        "compiling the GPU pipeline of {}... {} s",
        path.display(),
        elapsed.as_secs()
    );
}

/// Which scene, at what size, seen from where; shared by `render`, `sheet` and `clip`.
#[derive(Clone, Debug, clap::Args)]
pub struct SceneSource {
    /// Built-in scene (hairball, atrium, chart, sparkle, glass, neon) or path to an .obj, .gltf or .glb file.
    #[arg(long, default_value = DEFAULT_SCENE)]
    pub scene: String,
    /// Built-in scene density (hairball: 1 is about 300k triangles, 7 over 2M).
    #[arg(long, default_value_t = 1.0)]
    pub density: f32,
    /// Built-in scene random seed.
    #[arg(long, default_value_t = SceneOptions::default().seed)]
    pub seed: u64,
    /// Specular antialiasing in every technique's scene render (each highlight's lobe widened
    /// by the normal's variation inside the pixel). A clip's reference stays unfiltered; render
    /// a reference for `compare` without this flag.
    #[arg(long)]
    pub specular_aa: bool,
    /// How radiance is displayed: auto (HDR scenes such as neon through agx, the others on
    /// the LDR path), none (the LDR path: values clamped to white), or an HDR render through
    /// reinhard, aces, agx or neutral. Techniques then run before or after the tonemapper by
    /// their tonemap_order setting.
    #[arg(long, value_name = "NAME", default_value = "auto", value_parser = parse_tonemap)]
    pub tonemap: TonemapChoice,
    /// Exposure of an HDR render in stops (EV): radiance is scaled by 2^EV before the
    /// tonemapper.
    #[arg(long, value_name = "EV", default_value_t = 0.0, allow_hyphen_values = true, value_parser = parse_exposure)]
    pub exposure: f32,
    /// Image size, WIDTHxHEIGHT in pixels (each at least 1, at most the adapter's largest
    /// texture side, e.g. 16384).
    #[arg(long, default_value = "1280x720", value_parser = parse_size, allow_hyphen_values = true)]
    pub size: (u32, u32),
    /// Treat scene warnings (a missing texture replaced by a checker) as errors.
    #[arg(long)]
    pub strict: bool,
    /// Draw a game-like UI overlay (text, a crosshair, a framed bar) over the frames:
    /// `before` the antialiasing, as engines that blur their UI do, or `after` it.
    #[arg(long, value_name = "ORDER", value_parser = parse_overlay)]
    pub ui_overlay: Option<OverlayOrder>,
    /// The camera, when not the scene's default view.
    #[command(flatten)]
    pub camera: CameraArgs,
}

/// Which scene and frame to render; shared by `render` and `sheet`.
#[derive(Clone, Debug, clap::Args)]
pub struct SceneArgs {
    /// Scene, size and camera.
    #[command(flatten)]
    pub source: SceneSource,
    /// Frame of the deterministic camera path (temporal techniques run frames 0..=N; at most
    /// 1000000).
    #[arg(long, default_value_t = 0, value_parser = clap::value_parser!(u64).range(0..=spec::MAX_FRAME))]
    pub frame: u64,
}

/// Arguments of `aa-lab render`.
#[derive(Debug, clap::Args)]
pub struct RenderArgs {
    /// Scene, size and frame.
    #[command(flatten)]
    pub scene: SceneArgs,
    /// Techniques and their settings.
    #[command(flatten)]
    pub techniques: TechniqueArgs,
    /// Output: a .png file for a single image, otherwise a directory that receives
    /// <scene>-<technique>.png per technique (<stem>-<hash of the path>-<technique>.png for
    /// a model file).
    #[arg(long, short, default_value = "out")]
    pub out: PathBuf,
    /// Print GPU milliseconds per pass (median of 5 extra renders of the frame).
    #[arg(long)]
    pub timings: bool,
    /// Print the memory report (every target each technique owns or reads).
    #[arg(long)]
    pub memory: bool,
    /// Also write each technique's debug views (<scene>-<technique>-<view>.png).
    #[arg(long)]
    pub debug_views: bool,
    /// Also write the linear radiance of every technique that ran before the tonemapper of an
    /// HDR frame (the reference, MSAA, and whatever has tonemap_order=before) as OpenEXR beside
    /// its PNG, for `compare` to score with HDR-FLIP.
    #[arg(long)]
    pub exr: bool,
    /// Reproduce a render from a sidecar JSON or from a PNG aa-lab wrote (scene, size, frame,
    /// camera and every technique setting come from the record).
    #[arg(long, value_name = "FILE", conflicts_with_all = ["scene", "technique", "size", "frame", "density", "seed", "ui_overlay", "specular_aa", "tonemap", "exposure"])]
    pub from: Option<PathBuf>,
    /// Replace existing output files (without it, aa-lab never replaces a file; an input is
    /// never replaced).
    #[arg(long)]
    pub force: bool,
    /// Run the techniques that work on a finished image (No AA, FXAA, SMAA 1x) on this PNG or
    /// JPEG instead of a scene, e.g. a capture from another engine; others are refused with
    /// the reason.
    #[arg(long, value_name = "FILE", conflicts_with_all = ["scene", "from", "size", "frame", "density", "seed", "specular_aa", "tonemap", "exposure", "camera_eye", "fov"])]
    pub image: Option<PathBuf>,
}

/// The spec of image mode: the techniques run on the image at `path`, at its size.
pub fn spec_for_image(
    path: &Path,
    techniques: Vec<TechniqueSpec>,
    overlay: Option<OverlayOrder>,
) -> anyhow::Result<(RenderSpec, image::RgbaImage)> {
    let full = std::fs::canonicalize(path)
        .with_context(|| format!("cannot read image {}", path.display()))?;
    let image = load_input_image(&full)?;
    let name = full
        .file_stem()
        .map_or_else(|| "image".to_owned(), |s| s.to_string_lossy().into_owned());
    let spec = RenderSpec {
        scene: name,
        density: 1.0,
        seed: SceneOptions::default().seed,
        specular_aa: false,
        tonemap: TonemapChoice::Auto,
        exposure: 0.0,
        width: image.width(),
        height: image.height(),
        frame: 0,
        camera: None,
        rig: None,
        image: Some(full.display().to_string()),
        techniques,
        overlay,
        adapter: None,
        build: Some(spec::build_id()),
    };
    Ok((spec, image))
}

/// Decodes a PNG or JPEG input image to sRGB-encoded RGBA8, within the limits of every image
/// aa-lab reads (a regular file of bounded size, pixel count checked from the header).
pub fn load_input_image(path: &Path) -> anyhow::Result<image::RgbaImage> {
    Ok(crate::export::png::read_image(path)?)
}

/// The technique ids of a `--technique` list; `all` expands to every technique this adapter
/// can run, and the unavailable ones are reported on stderr.
pub(super) fn technique_ids(gpu: &Gpu, list: &str) -> anyhow::Result<Vec<String>> {
    let items = technique_list(list);
    let mut ids = Vec::new();
    for item in &items {
        if item == "all" {
            for info in aa::registry() {
                match (info.availability)(&gpu.caps) {
                    Ok(()) => ids.push(info.id.to_owned()),
                    Err(reason) => eprintln!("skipping {}: {reason}", info.id),
                }
            }
        } else {
            ids.push(item.clone());
        }
    }
    // Each technique once, in first-mention order (`none,fxaa,none` renders none once).
    let mut seen = std::collections::HashSet::new();
    ids.retain(|id| seen.insert(id.clone()));
    if ids.is_empty() && items.iter().any(|item| item == "all") {
        bail!(
            "no technique can run on {} ({}); the reasons are above",
            gpu.caps.adapter_name,
            gpu.caps.backend
        );
    }
    if ids.is_empty() {
        bail!("no technique given; use --technique with ids from `aa-lab techniques`, or `all`");
    }
    Ok(ids)
}

/// The items of a comma-separated `--technique` list. A user technique's path may hold commas:
/// when `user:PATH` names no file, the shortest run of the following items that, joined back
/// with their commas, names one is taken as its path (`user:a,b.wgsl,fxaa` is `user:a,b.wgsl`
/// and `fxaa` when `a,b.wgsl` exists).
fn technique_list(list: &str) -> Vec<String> {
    let parts: Vec<&str> = list.split(',').collect();
    let mut items = Vec::new();
    let mut next = 0;
    while next < parts.len() {
        let item = parts[next].trim();
        next += 1;
        if item.is_empty() {
            continue;
        }
        let mut taken = item.to_owned();
        if let Some(path) = item.strip_prefix(aa::user::PREFIX)
            && !std::path::Path::new(path).is_file()
        {
            let mut joined = path.to_owned();
            for (offset, part) in parts[next..].iter().enumerate() {
                joined.push(',');
                joined.push_str(part);
                if std::path::Path::new(joined.trim_end()).is_file() {
                    taken = format!("{}{}", aa::user::PREFIX, joined.trim_end());
                    next += offset + 1;
                    break;
                }
            }
        }
        items.push(taken);
    }
    items
}

/// The `--ssaa-*` and `--msaa-resolve` flags as parameter settings per technique id.
fn shorthand_settings(
    args: &TechniqueArgs,
    ids: &[String],
) -> anyhow::Result<Vec<(String, String, ParamValue)>> {
    let mut out = Vec::new();
    let jittered =
        args.ssaa_pattern.is_some() || args.ssaa_samples.is_some() || args.ssaa_filter.is_some();
    if args.ssaa_factor.is_some() && jittered {
        bail!(
            "--ssaa-factor selects the ordered grid; --ssaa-pattern/--ssaa-samples/--ssaa-filter select jittered sampling: give one or the other"
        );
    }
    let mut ssaa =
        |key: &str, value: ParamValue| out.push((aa::ssaa::ID.to_owned(), key.to_owned(), value));
    if let Some(k) = args.ssaa_factor {
        ssaa("mode", ParamValue::Choice(Mode::Ordered.name().into()));
        ssaa("factor", ParamValue::Int(i64::from(k)));
    }
    if jittered {
        ssaa("mode", ParamValue::Choice(Mode::Jittered.name().into()));
    }
    if let Some(p) = &args.ssaa_pattern {
        ssaa("pattern", ParamValue::Choice(p.clone()));
    }
    if let Some(n) = args.ssaa_samples {
        ssaa("samples", ParamValue::Int(i64::from(n)));
    }
    if let Some(f) = &args.ssaa_filter {
        ssaa("filter", ParamValue::Choice(f.clone()));
    }
    if !out.is_empty() && !ids.iter().any(|id| id == aa::ssaa::ID) {
        bail!(
            "--ssaa-* options apply to the ssaa technique, which is not among --technique {}",
            ids.join(",")
        );
    }
    if let Some(resolve) = &args.msaa_resolve {
        let msaa: Vec<&String> = ids
            .iter()
            .filter(|id| aa::msaa::INFOS.iter().any(|info| info.id == id.as_str()))
            .collect();
        if msaa.is_empty() {
            bail!(
                "--msaa-resolve applies to MSAA techniques, and none is among --technique {}",
                ids.join(",")
            );
        }
        for id in msaa {
            out.push((
                id.clone(),
                "resolve".to_owned(),
                ParamValue::Choice(resolve.clone()),
            ));
        }
    }
    out.extend(set_flags(&args.set, ids)?);
    Ok(out)
}

/// The `--set TECHNIQUE.KEY=VALUE` flags as parameter settings, each naming one of `ids`.
pub(super) fn set_flags(
    sets: &[String],
    ids: &[String],
) -> anyhow::Result<Vec<(String, String, ParamValue)>> {
    let mut out = Vec::new();
    for item in sets {
        // A combination's id may hold `=` (`smaa+rcas=0.2`): the `=` that ends `TECHNIQUE.KEY`
        // is the first one after a technique of `ids` and a dot.
        let split = item.match_indices('=').map(|(at, _)| at).find(|&at| {
            item[..at]
                .rsplit_once('.')
                .is_some_and(|(id, _)| ids.iter().any(|i| i == id))
        });
        let (target, value) = split
            .map(|at| (&item[..at], &item[at + 1..]))
            .or_else(|| item.split_once('='))
            .with_context(|| format!("--set {item}: expected TECHNIQUE.KEY=VALUE"))?;
        // Keys have no dots, ids may (`user:edge.wgsl`): the key is after the last one.
        let (id, key) = target
            .rsplit_once('.')
            .with_context(|| format!("--set {item}: expected TECHNIQUE.KEY=VALUE"))?;
        let id =
            aa::user::resolve_alias(id, ids).map_err(|e| anyhow::anyhow!("--set {item}: {e}"))?;
        if !ids.iter().any(|i| i == id) {
            bail!(
                "--set {item}: {id} is not among --technique {}",
                ids.join(",")
            );
        }
        out.push((id.to_owned(), key.to_owned(), parse_value(value)));
    }
    Ok(out)
}

/// Builds the spec of a command line: techniques created once to resolve presets and validate
/// every setting, then stored as full settings maps.
pub fn technique_specs(gpu: &Gpu, args: &TechniqueArgs) -> anyhow::Result<Vec<TechniqueSpec>> {
    let ids = technique_ids(gpu, &args.technique)?;
    let settings = shorthand_settings(args, &ids)?;
    configured_specs(gpu, &ids, &args.preset, &settings)
}

/// The techniques `ids` with the `--preset TECHNIQUE=PRESET` flags `presets` applied, then
/// `settings`; every preset must name one of `ids`.
pub(super) fn configured_specs(
    gpu: &Gpu,
    ids: &[String],
    presets: &[String],
    settings: &[(String, String, ParamValue)],
) -> anyhow::Result<Vec<TechniqueSpec>> {
    let mut techniques = Vec::new();
    for id in ids {
        let mut technique = aa::create(gpu, id)?;
        for preset in presets {
            // Preset names have no `=`; a combination's id may (`smaa+rcas=0.2`).
            let (target, name) = preset
                .rsplit_once('=')
                .with_context(|| format!("--preset {preset}: expected TECHNIQUE=PRESET"))?;
            if target == id {
                technique.apply_preset(name)?;
            }
        }
        for (target, key, value) in settings {
            if target == id {
                aa::set_param(technique.as_mut(), key, value.clone())?;
            }
        }
        techniques.push(TechniqueSpec::of(technique.as_ref()));
    }
    for preset in presets {
        if let Some((target, _)) = preset.rsplit_once('=')
            && !ids.iter().any(|i| i == target)
        {
            bail!(
                "--preset {preset}: {target} is not among --technique {}",
                ids.join(",")
            );
        }
    }
    Ok(techniques)
}

/// The spec of a scene given on the command line at `frame`, with already resolved
/// techniques.
pub fn spec_for_scene(
    scene: &SceneSource,
    frame: u64,
    techniques: Vec<TechniqueSpec>,
) -> RenderSpec {
    // Store OBJ paths absolute so a record reproduces from any directory.
    let name = match std::fs::canonicalize(&scene.scene) {
        Ok(p) if p.is_file() => p.display().to_string(),
        _ => scene.scene.clone(),
    };
    RenderSpec {
        scene: name,
        density: scene.density,
        seed: scene.seed,
        specular_aa: scene.specular_aa,
        tonemap: scene.tonemap,
        exposure: scene.exposure,
        width: scene.size.0,
        height: scene.size.1,
        frame,
        camera: None,
        rig: None,
        image: None,
        techniques,
        overlay: scene.ui_overlay,
        adapter: None,
        build: Some(spec::build_id()),
    }
}

/// Loads the scene of a spec, printing its warnings; `strict` turns warnings into an error.
/// A camera path the spec records replaces the scene's.
pub fn load_scene(spec: &RenderSpec, strict: bool) -> anyhow::Result<crate::scene::Scene> {
    let options = SceneOptions {
        density: spec.density,
        seed: spec.seed,
    };
    let mut scene = source::load(&spec.scene, &options)?;
    if let Some(rig) = spec.rig {
        scene.camera = rig;
    }
    for note in &scene.notes {
        eprintln!("note: {note}");
    }
    for warning in &scene.warnings {
        eprintln!("warning: {warning}");
    }
    if strict && !scene.warnings.is_empty() {
        bail!(
            "{} scene warning(s) and --strict was given",
            scene.warnings.len()
        );
    }
    Ok(scene)
}

/// Loads a spec from a sidecar JSON or the record inside an aa-lab PNG.
pub fn load_spec(path: &Path) -> anyhow::Result<RenderSpec> {
    let is_png = path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("png"));
    let text = if is_png {
        read_record(path)?.with_context(|| {
            format!(
                "{} has no aa-lab record (it was not written by aa-lab)",
                path.display()
            )
        })?
    } else {
        let bytes = files::read_bounded(path, MAX_RECORD_BYTES as u64, "a render record")?;
        String::from_utf8(bytes).with_context(|| format!("{} is not UTF-8 text", path.display()))?
    };
    spec::parse_record(&text)
        .with_context(|| format!("{} is not a valid aa-lab render record", path.display()))
}

/// The overwrite policy of `render` and `sheet`: `--force` or not, with the record the spec
/// came from and an OBJ scene as inputs that are never written.
pub fn output_policy(force: bool, from: Option<&Path>, spec: &RenderSpec) -> Overwrite {
    let mut policy = Overwrite::new(force);
    if let Some(from) = from {
        policy = policy.with_input(from);
    }
    let scene = Path::new(&spec.scene);
    if scene.is_file() {
        policy = policy.with_input(scene);
    }
    if let Some(image) = &spec.image {
        policy = policy.with_input(Path::new(image));
    }
    policy
}

fn output_paths(
    out: &Path,
    scene: &str,
    images: &[spec::TechniqueImage],
) -> anyhow::Result<Vec<PathBuf>> {
    let names_file = out
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("png"));
    if names_file {
        if images.len() != 1 {
            bail!(
                "--out {} names one file but this render produces {} images; give a directory instead",
                out.display(),
                images.len()
            );
        }
        if let Some(parent) = out.parent().filter(|p| !p.as_os_str().is_empty()) {
            std::fs::create_dir_all(parent)
                .with_context(|| format!("cannot create directory {}", parent.display()))?;
        }
        return Ok(vec![out.to_owned()]);
    }
    std::fs::create_dir_all(out)
        .with_context(|| format!("cannot create output directory {}", out.display()))?;
    Ok(images
        .iter()
        .map(|i| {
            let name = match i.view {
                None => format!("{scene}-{}.png", aa::user::file_name_part(&i.id)),
                Some(view) => format!("{scene}-{}-{view}.png", aa::user::file_name_part(&i.id)),
            };
            out.join(name)
        })
        .collect())
}

/// Where the radiance of each technique that has it goes: its PNG's path as `.exr`.
fn radiance_paths<'o>(
    output: &'o spec::RenderOutput,
    paths: &[PathBuf],
) -> Vec<(&'o image::Rgb32FImage, PathBuf)> {
    (output.radiance.iter())
        .filter_map(|(id, image)| {
            let index = (output.images.iter()).position(|i| i.id == *id && i.view.is_none())?;
            Some((image, paths[index].with_extension("exr")))
        })
        .collect()
}

fn progress_bar(total: u64) -> ProgressBar {
    let bar = ProgressBar::new(total);
    bar.set_style(
        ProgressStyle::with_template("{spinner} {msg} [{bar:30}] frame {pos}/{len} {elapsed}")
            .unwrap_or_else(|_| ProgressStyle::default_bar())
            .progress_chars("=> "),
    );
    bar.enable_steady_tick(std::time::Duration::from_millis(120));
    bar
}

/// The progress bar of `total` `unit`s (frames, steps) with the time elapsed and left, as
/// `clip` and `bench` show it.
pub(super) fn progress_bar_with_eta(total: u64, unit: &str) -> ProgressBar {
    let bar = ProgressBar::new(total);
    bar.set_style(
        ProgressStyle::with_template(&format!(
            "{{spinner}} [{{elapsed_precise}}] [{{bar:32}}] {{pos}}/{{len}} {unit}, eta {{eta}}  {{msg}}"
        ))
        .unwrap_or_else(|_| ProgressStyle::default_bar())
        .progress_chars("=> "),
    );
    bar.enable_steady_tick(std::time::Duration::from_millis(200));
    bar
}

/// Runs `aa-lab render`.
pub fn run(args: &RenderArgs) -> anyhow::Result<()> {
    let started = Instant::now();
    let gpu = Gpu::headless()?;
    let (mut spec, mut input) = match (&args.from, &args.image) {
        (Some(path), _) => (load_spec(path)?, None),
        (None, Some(path)) => {
            let (spec, image) = spec_for_image(
                path,
                technique_specs(&gpu, &args.techniques)?,
                args.scene.source.ui_overlay,
            )?;
            (spec, Some(image))
        }
        (None, None) => (
            spec_for_scene(
                &args.scene.source,
                args.scene.frame,
                technique_specs(&gpu, &args.techniques)?,
            ),
            None,
        ),
    };
    spec.adapter = Some(format!("{} ({})", gpu.caps.adapter_name, gpu.caps.backend));
    spec.build = Some(spec::build_id());
    let scene = match &spec.image {
        Some(path) => {
            let image = match input.take() {
                Some(image) => image,
                None => load_input_image(Path::new(path))?,
            };
            if image.dimensions() != (spec.width, spec.height) {
                bail!(
                    "{path} is {}x{} now; the record was made from a {}x{} image",
                    image.width(),
                    image.height(),
                    spec.width,
                    spec.height
                );
            }
            input = Some(image);
            crate::scene::Scene::empty(&spec.scene)
        }
        None => {
            let mut scene = load_scene(&spec, args.scene.source.strict)?;
            args.scene.source.camera.apply(&mut spec, &mut scene)?;
            scene
        }
    };
    let policy = output_policy(args.force, args.from.as_deref(), &spec);
    if args
        .out
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("png"))
    {
        // A single named output: refuse before rendering.
        policy.check(&args.out)?;
    }
    let loaded = started.elapsed();

    let bar = progress_bar(spec.frame + 1);
    bar.set_message(format!("{} {}x{}", scene.name, spec.width, spec.height));
    let progress = |done: u64, total: u64| {
        bar.set_length(total);
        bar.set_position(done);
    };
    let temporal_frames = spec.frame > 0;
    let run_options = RunOptions {
        debug_views: args.debug_views,
        timing_repeats: if args.timings { 5 } else { 0 },
        progress: temporal_frames.then_some(&progress as &dyn Fn(u64, u64)),
        image: input.as_ref(),
        radiance: args.exr,
    };
    let output = spec::run(&gpu, &scene, &spec, &run_options)?;
    bar.finish_and_clear();
    let rendered = started.elapsed();

    let record = serde_json::to_string_pretty(&spec)?;
    let paths = output_paths(
        &args.out,
        &crate::export::output_stem(&scene.name, spec.image.as_deref().unwrap_or(&spec.scene)),
        &output.images,
    )?;
    // Every output is checked before the first is written: all or nothing.
    policy.check_all(paths.iter().map(PathBuf::as_path))?;
    let radiance_paths = radiance_paths(&output, &paths);
    policy.check_all(radiance_paths.iter().map(|(_, p)| p.as_path()))?;
    for (image, path) in output.images.iter().zip(&paths) {
        let replaced = export::write_png(path, &image.image, Some(&record), &policy)?;
        println!("{}", files::wrote_line(path, replaced));
    }
    for (image, path) in radiance_paths {
        let replaced = export::radiance::write_exr(&path, image, &policy)?;
        println!("{}", files::wrote_line(&path, replaced));
    }
    if args.exr && output.radiance.is_empty() {
        eprintln!(
            "--exr: no technique ran before the tonemapper of an HDR frame; no radiance written"
        );
    }
    for (id, note) in &output.notes {
        println!("{id}: {note}");
    }
    eprintln!(
        "{}: {} triangles, {}x{}, frame {}, {} scene render(s) in the frame; scene ready in {:.2} s, rendered in {:.2} s, total {:.2} s",
        scene.name,
        scene.triangle_count(),
        spec.width,
        spec.height,
        spec.frame,
        output.scene_renders,
        loaded.as_secs_f64(),
        (rendered - loaded).as_secs_f64(),
        started.elapsed().as_secs_f64()
    );
    if args.timings {
        print_timings(&gpu, output.timings.as_ref());
    }
    if args.memory {
        print!("{}", output.memory.table());
    }
    Ok(())
}

fn print_timings(gpu: &Gpu, timings: Option<&crate::graph::FrameTimings>) {
    let Some(timings) = timings else {
        println!(
            "no GPU timings: {} has no timestamp queries",
            gpu.caps.adapter_name
        );
        return;
    };
    println!("GPU time per pass (ms, median of 5 frames):");
    for pass in &timings.passes {
        println!("  {:<36} {:>9.3}", pass.label, pass.ms);
    }
    println!("  {:<36} {:>9.3}", "total", timings.total_ms());
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes_parse_and_reject_garbage() {
        assert_eq!(parse_size("1280x720"), Ok((1280, 720)));
        assert!(parse_size("1280").is_err());
        assert!(parse_size("ax5").is_err());
        for bad in ["-5x5", "0x5", "5x0"] {
            let err = parse_size(bad).unwrap_err();
            assert!(err.contains("WIDTHxHEIGHT"), "{err}");
        }
    }

    #[test]
    fn user_technique_paths_may_hold_commas() {
        let dir = tempfile::tempdir().expect("temp dir");
        let odd = dir.path().join("a, b.wgsl");
        std::fs::write(&odd, "").expect("write");
        let odd = odd.display().to_string();
        assert_eq!(
            technique_list(&format!("none, user:{odd},fxaa")),
            ["none".to_owned(), format!("user:{odd}"), "fxaa".to_owned()]
        );
        // A path that names no file, with or without commas, stays one item per comma.
        assert_eq!(
            technique_list("user:missing.wgsl,fxaa,,"),
            ["user:missing.wgsl", "fxaa"]
        );
        assert_eq!(technique_list(" all "), ["all"]);
    }
}
