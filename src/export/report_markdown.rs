//! `report.md`: the bench report as Markdown tables for people, from the same
//! [`BenchReport`] that `report.json` serialises: the run's heading and what the numbers mean,
//! costs (alone, relative to No AA, as multiples of the copy floor, shared scene renders),
//! quality, flicker and ghosting, the Pareto fronts of quality against cost (in a scale sweep,
//! which technique at which render scale for a budget), shading work, memory, the scaling
//! sweeps and every pass.

use std::fmt::Write as _;

use super::report::{
    BenchReport, RunReport, TechniqueReport, fmt_ms, is_scale_sweep, scale_label, scaling_curves,
    scaling_sweep, scene_label, scenes, technique_columns, tradeoff_chart_name, unscaled_name,
};
use crate::aa::combo::Combo;
use crate::metrics::Metric;

fn mib(bytes: u64) -> String {
    format!("{:.1}", bytes as f64 / (1024.0 * 1024.0))
}

fn opt(value: Option<f64>, decimals: usize) -> String {
    match value {
        Some(v) if v.is_finite() => format!("{v:.decimals$}"),
        Some(v) if v.is_infinite() => "inf".to_owned(),
        _ => "-".to_owned(),
    }
}

/// A table with one row per run and one column per technique.
fn run_by_technique_table(
    out: &mut String,
    report: &BenchReport,
    cell: impl Fn(&RunReport, &TechniqueReport) -> String,
) {
    let columns = technique_columns(report);
    out.push_str("| scene | size |");
    for (_, name) in &columns {
        let _ = write!(out, " {name} |");
    }
    out.push_str("\n|---|---|");
    out.push_str(&"---:|".repeat(columns.len()));
    out.push('\n');
    for run in &report.runs {
        let _ = write!(
            out,
            "| {} | {}x{} |",
            scene_label(run),
            run.width,
            run.height
        );
        for (id, _) in &columns {
            let text = run
                .technique(id)
                .map_or_else(|| "-".to_owned(), |t| cell(run, t));
            let _ = write!(out, " {text} |");
        }
        out.push('\n');
    }
    out.push('\n');
}

/// The "which technique for my budget" section: per run, the SSIM Pareto front (cheapest
/// first) and the chart; in a scale sweep, [`scale_front_markdown`] instead.
fn tradeoff_markdown(out: &mut String, report: &BenchReport) {
    if is_scale_sweep(report) {
        scale_front_markdown(out, report);
        return;
    }
    out.push_str(
        "## Quality against cost: which technique for a budget

Each technique is a point (GPU ms \
         per frame running alone, SSIM against the reference); the Pareto front joins the techniques \
         that nothing cheaper matches in SSIM. Read off the front at your budget: the last front \
         technique at or below it is the best there is for it.\n\n",
    );
    for run in &report.runs {
        let Some(fronts) = &run.quality_fronts else {
            continue;
        };
        let front: Vec<String> = fronts
            .ssim
            .iter()
            .filter_map(|id| run.technique(id))
            .map(|t| {
                format!(
                    "{} ({} ms, SSIM {})",
                    t.name,
                    fmt_ms(t.total_ms.median),
                    opt(t.quality.map(|q| q.ssim), 4)
                )
            })
            .collect();
        if front.is_empty() {
            continue;
        }
        let _ = writeln!(
            out,
            "**{} {}x{}**: front, cheapest first: {}.\n\n![quality against cost, {} {}x{}]({})\n",
            scene_label(run),
            run.width,
            run.height,
            front.join(" -> "),
            run.scene,
            run.width,
            run.height,
            tradeoff_chart_name(run, Metric::Ssim)
        );
    }
}

/// The scale sweep's "which technique at which scale for my budget": per run, every technique
/// at a render scale on the SSIM or the FLIP front, cheapest first, and both charts.
fn scale_front_markdown(out: &mut String, report: &BenchReport) {
    out.push_str(
        "## Which technique at which scale for my budget\n\nEvery technique ran at every render \
         scale, upscaled to the same output size and scored against the native 64-sample reference. \
         The table lists the techniques at a scale that nothing cheaper matches in SSIM or in FLIP \
         (the Pareto fronts), cheapest first: at a budget, the last row at or below it on the \
         metric you trust is the best there is for it. In the charts, each technique's scales share \
         a colour; circles are rendered at the output resolution, triangles below it and \
         upscaled; filled points are on the front.\n\n",
    );
    for run in &report.runs {
        let Some(fronts) = &run.quality_fronts else {
            continue;
        };
        let mut rows: Vec<&TechniqueReport> = run
            .techniques
            .iter()
            .filter(|t| fronts.ssim.contains(&t.id) || fronts.flip.contains(&t.id))
            .collect();
        rows.sort_by(|a, b| a.total_ms.median.total_cmp(&b.total_ms.median));
        let _ = writeln!(
            out,
            "### {} {}x{}\n\n| GPU ms (alone) | technique | render scale | render size | SSIM | FLIP | front |\n|---:|---|---|---|---:|---:|---|",
            scene_label(run),
            run.width,
            run.height
        );
        for t in rows {
            let combo = Combo::parse(&t.id).ok();
            let (name, scale, size) = combo.as_ref().map_or_else(
                || (t.name.clone(), "-".to_owned(), "-".to_owned()),
                |c| {
                    let (w, h) = c.render_size((run.width, run.height));
                    (unscaled_name(c), scale_label(c), format!("{w}x{h}"))
                },
            );
            let on: Vec<&str> = [("SSIM", &fronts.ssim), ("FLIP", &fronts.flip)]
                .into_iter()
                .filter(|(_, front)| front.contains(&t.id))
                .map(|(metric, _)| metric)
                .collect();
            let _ = writeln!(
                out,
                "| {} | {name} | {scale} | {size} | {} | {} | {} |",
                fmt_ms(t.total_ms.median),
                opt(t.quality.map(|q| q.ssim), 4),
                opt(t.quality.map(|q| q.flip), 4),
                on.join(", ")
            );
        }
        let _ = writeln!(
            out,
            "\n| SSIM against cost | FLIP against cost |\n|---|---|\n| ![SSIM against cost, {key}]({}) | ![FLIP against cost, {key}]({}) |\n",
            tradeoff_chart_name(run, Metric::Ssim),
            tradeoff_chart_name(run, Metric::Flip),
            key = run.key()
        );
    }
}

/// Renders the report as Markdown.
pub fn markdown(report: &BenchReport) -> String {
    let mut out = String::new();
    intro_markdown(&mut out, report);
    cost_markdown(&mut out, report);
    if report.settings.quality {
        quality_markdown(&mut out, report);
    }
    work_markdown(&mut out, report);
    out
}

/// The report's heading: the command, build and adapter, and what the numbers mean.
fn intro_markdown(out: &mut String, report: &BenchReport) {
    let s = &report.settings;
    let _ = writeln!(out, "# aa-lab bench report\n");
    let _ = writeln!(
        out,
        "- command: `{}`\n- build: {}\n- adapter: {} ({}, {}; driver {})\n- wall time: {:.0} s ({:.1} min)\n- frames: {} timed after {} warm-up, per run\n",
        report.command,
        report.build,
        report.adapter.adapter_name,
        report.adapter.backend,
        report.adapter.device_type,
        report.adapter.driver,
        report.wall_seconds,
        report.wall_seconds / 60.0,
        s.frames,
        s.warmup
    );
    out.push_str(
        "## What the numbers mean\n\n\
         - **GPU ms** come from timestamp queries around every pass, summarised over the timed frames \
         (median; p95 in report.json). All techniques run together in one frame graph, so a scene render that \
         several techniques read is rendered once per frame.\n\
         - A technique's **total** is its own passes plus the scene render it reads: what it would cost alone. \
         The **shared-input** tables give each scene render once, which is what the frame actually spends.\n\
         - **x No AA** divides a technique's total by No AA's total. **x floor** divides a post-process \
         technique's own passes by a full-screen copy pass (read every pixel, write every pixel), the least \
         any post-process pass can cost here.\n",
    );
    let _ = writeln!(
        out,
        "- The timed frames follow a slow camera track ({} px per frame at the orbit target), so every \
         frame shows nearly the same view; temporal techniques accumulate history over it.",
        s.track_step_px
    );
    if s.specular_aa {
        out.push_str(
            "- Every technique's scene render had **geometric specular antialiasing** \
             (`--specular-aa`); the reference's did not.\n",
        );
    }
    if !s.tonemap.is_auto() || s.exposure != 0.0 {
        let _ = writeln!(
            out,
            "- Tonemap **{}** at exposure {:+.1} EV (`--tonemap`, `--exposure`); each technique \
             ran before or after it by its `tonemap_order`.",
            crate::graph::params::Named::name(s.tonemap),
            s.exposure
        );
    }
    if s.quality {
        let _ = writeln!(
            out,
            "- **SSIM, PSNR, MAE, FLIP** score frame {} of each scene's own camera path (temporal techniques run \
             frames 0..={} of it) against a 64-sample ordered-grid SSAA render of the same frame. SSIM is on BT.601 \
             luma with an 11x11 Gaussian window; PSNR and MAE on sRGB-encoded R'G'B' (MAE in 0..255); FLIP is the \
             mean of NVIDIA's LDR-FLIP map.\n\
             - **Flicker** is a technique's mean frame-to-frame luma change over the last {} timed frames divided \
             by the reference's over the same frames (1 = as stable as the reference).",
            s.quality_frame, s.quality_frame, s.flicker_frames
        );
    }
    out.push_str(
        "- **Fragment invocations** come from pipeline-statistics queries (one extra, untimed frame).\n\n",
    );
}

/// GPU time per technique, relative to No AA and to the copy floor, and of the shared scene renders.
fn cost_markdown(out: &mut String, report: &BenchReport) {
    out.push_str("## GPU time per frame, technique alone (ms, median)\n\nThe shape of the thesis' figures 4.3 and 4.4 (there: FPS on a Galaxy S8).\n\n");
    run_by_technique_table(out, report, |_, t| fmt_ms(t.total_ms.median));
    out.push_str("## Cost relative to No AA (total / No AA total)\n\n");
    run_by_technique_table(out, report, |_, t| opt(t.relative_to_none, 2));
    out.push_str("## Post-process passes as multiples of the full-screen copy floor\n\n");
    let _ = writeln!(
        out,
        "| scene | size | copy floor ms | techniques (own passes ms, x floor) |\n|---|---|---:|---|"
    );
    for run in &report.runs {
        let cells: Vec<String> = run
            .techniques
            .iter()
            .filter(|t| t.post_process)
            .map(|t| {
                format!(
                    "{} {} ms ({}x)",
                    t.name,
                    fmt_ms(t.own_ms.median),
                    opt(t.floor_multiple, 1)
                )
            })
            .collect();
        let _ = writeln!(
            out,
            "| {} | {}x{} | {} | {} |",
            scene_label(run),
            run.width,
            run.height,
            fmt_ms(run.floor_ms.median),
            cells.join("; ")
        );
    }
    out.push('\n');
    out.push_str("## Shared scene renders (ms per frame, each rendered once)\n\n| scene | size | input | read by | median ms | p95 ms | fragment invocations |\n|---|---|---|---|---:|---:|---:|\n");
    for run in &report.runs {
        for input in &run.inputs {
            let _ = writeln!(
                out,
                "| {} | {}x{} | {} | {} | {} | {} | {} |",
                scene_label(run),
                run.width,
                run.height,
                input.label,
                input.users.join(", "),
                fmt_ms(input.ms.median),
                fmt_ms(input.ms.p95),
                input
                    .fragment_invocations
                    .map_or_else(|| "-".to_owned(), |n| n.to_string())
            );
        }
        let _ = writeln!(
            out,
            "| {} | {}x{} | **whole frame** | all | {} | {} | |",
            scene_label(run),
            run.width,
            run.height,
            fmt_ms(run.frame_ms.median),
            fmt_ms(run.frame_ms.p95)
        );
    }
    out.push('\n');
}

/// Image quality against the reference and the analytic truth, flicker and ghosting.
fn quality_markdown(out: &mut String, report: &BenchReport) {
    out.push_str("## SSIM against the 64-sample SSAA reference\n\nThe shape of the thesis' figures 4.7 and 4.8 (there: against a 16-sample reference).\n\n");
    run_by_technique_table(out, report, |_, t| opt(t.quality.map(|q| q.ssim), 4));
    tradeoff_markdown(out, report);
    out.push_str("## FLIP (mean error, lower is better)\n\n");
    run_by_technique_table(out, report, |_, t| opt(t.quality.map(|q| q.flip), 4));
    out.push_str("## PSNR (dB) / MAE (0..255)\n\n");
    run_by_technique_table(out, report, |_, t| {
        format!(
            "{} / {}",
            opt(t.quality.map(|q| q.psnr), 2),
            opt(t.quality.map(|q| q.mae), 2)
        )
    });
    if report
        .runs
        .iter()
        .any(|r| r.techniques.iter().any(|t| t.truth.is_some()))
    {
        out.push_str("## Against the analytic ground truth (chart test elements): SSIM / FLIP\n\n");
        run_by_technique_table(out, report, |_, t| {
            format!(
                "{} / {}",
                opt(t.truth.map(|q| q.ssim), 4),
                opt(t.truth.map(|q| q.flip), 4)
            )
        });
    }
    out.push_str("## Temporal stability: flicker ratio (technique change / reference change)\n\n");
    run_by_technique_table(out, report, |_, t| opt(t.flicker_ratio, 2));
    out.push_str(
        "## Ghosting: luma error at moving edges (levels of 0..255, where the reference changed by more than 8 between frames)\n\n",
    );
    run_by_technique_table(out, report, |_, t| opt(t.ghosting, 1));
    if let Some(jod) = &report.settings.jod {
        out.push_str(&format!(
            "## ColorVideoVDP: JOD of the flicker frames (10 = no visible difference from the reference; {} at {} fps, model {})\n\n",
            jod.display, jod.fps, jod.model
        ));
        run_by_technique_table(out, report, |_, t| opt(t.jod, 2));
    }
}

/// Shading work, memory, the scaling sweeps and every pass in detail.
fn work_markdown(out: &mut String, report: &BenchReport) {
    out.push_str("## Shading work: fragment-shader invocations per output pixel (input + own passes)\n\nThe counterpart of the thesis' figure 4.5 (fragment instructions per frame).\n\n");
    run_by_technique_table(out, report, |_, t| {
        opt(t.fragment_invocations.map(|f| f.per_pixel), 2)
    });
    out.push_str("## Memory to run alone (MiB: input targets, private resources, output)\n\n");
    run_by_technique_table(out, report, |_, t| {
        t.memory
            .map_or_else(|| "-".to_owned(), |m| mib(m.standalone_bytes))
    });
    scaling_markdown(out, report);
    out.push_str("## Per-pass detail\n\n");
    for run in &report.runs {
        let _ = writeln!(
            out,
            "### {} {}x{} ({} triangles, {} scene renders per frame)\n\n| pass | count | median ms | p95 ms | fragment invocations |\n|---|---:|---:|---:|---:|",
            run.scene, run.width, run.height, run.triangles, run.scene_renders_per_frame
        );
        for t in &run.techniques {
            for p in &t.passes {
                let _ = writeln!(
                    out,
                    "| {} | {} | {} | {} | {} |",
                    p.label,
                    p.count,
                    fmt_ms(p.ms.median),
                    fmt_ms(p.ms.p95),
                    p.fragment_invocations
                        .map_or_else(|| "-".to_owned(), |n| n.to_string())
                );
            }
        }
        out.push('\n');
    }
}

fn scaling_markdown(out: &mut String, report: &BenchReport) {
    let Some(by) = scaling_sweep(report) else {
        return;
    };
    let unit = if by == "density" {
        "M triangles"
    } else {
        "megapixels"
    };
    for scene in scenes(report) {
        let curves = scaling_curves(report, &scene, by);
        let Some(xs) = curves
            .first()
            .map(|c| c.2.iter().map(|p| p.x).collect::<Vec<_>>())
        else {
            continue;
        };
        let _ = writeln!(
            out,
            "## Scaling with {by}: {scene} (median ms, technique alone; overhead over No AA in brackets)\n"
        );
        out.push_str("| technique |");
        for x in &xs {
            let _ = write!(out, " {x:.2} {unit} |");
        }
        out.push_str(" growth of overhead |\n|---|");
        out.push_str(&"---:|".repeat(xs.len() + 1));
        out.push('\n');
        for (_, name, points) in &curves {
            let _ = write!(out, "| {name} |");
            for p in points {
                let _ = write!(out, " {} ({}) |", fmt_ms(p.total_ms), fmt_ms(p.overhead_ms));
            }
            let growth = match (points.first(), points.last()) {
                (Some(a), Some(b)) if a.overhead_ms > 0.0 && points.len() > 1 => {
                    format!("x{:.2}", b.overhead_ms / a.overhead_ms)
                }
                _ => "-".to_owned(),
            };
            let _ = writeln!(out, " {growth} |");
        }
        if let (Some(first), Some(last)) = (xs.first(), xs.last()) {
            let _ = writeln!(
                out,
                "\n{unit} grew x{:.2} from the first to the last point.\n",
                last / first
            );
        }
    }
}
