//! The live metrics panel (right side): frame rate and a plot of frame times, GPU
//! milliseconds per shared scene render, per technique and per pass, memory per technique
//! and in total, and quality against the reference with how many reference samples it rests
//! on. Every figure has a tooltip saying exactly what it measures; figures that no longer
//! describe the displayed frame say so instead of showing a number.
//!
//! A stateless function of the [`Workspace`] ([`ui`]); while an image set is open its quality
//! section comes from image_panel.rs.

use std::time::Duration;

use egui::RichText;
use egui_plot::{Legend, Line, Plot};

use super::bench::{BenchFeature, BenchRequest};
use super::engine::ReferenceState;
use super::image_panel;
use super::jod_panel;
use super::quality;
use super::reference::REFERENCE_ID;
use super::style::{self, ACCENT, SLOT_COLORS, SLOT_LETTERS, ShowKeyed, number, number_weak};
use super::workspace::Workspace;

/// The panel. See the module docs.
pub(super) fn ui(ui: &mut egui::Ui, ws: &mut Workspace, bench: &mut BenchFeature) {
    profiling::function_scope!();
    egui::Panel::right("metrics")
        .resizable(true)
        .default_size(340.0)
        .size_range(260.0..=560.0)
        .show_keyed(ui, "metrics", |ui| {
            egui::ScrollArea::vertical().show(ui, |ui| {
                ui.add_space(4.0);
                ui.heading("Metrics");
                // Each section in a scope of its own: the figures in one come and go with the
                // frames, and the controls of the next keep their ids (`style::keyed`).
                let section = |name: &str| egui::Id::unique(("metrics section", name));
                if ws.cx.images.is_open() {
                    // Nothing renders: only the images' figures apply.
                    style::keyed(ui, section("images"), |ui| {
                        image_panel::quality_section(ui, ws);
                    });
                    return;
                }
                style::keyed(ui, section("performance"), |ui| performance_section(ui, ws));
                ui.separator();
                style::keyed(ui, section("gpu"), |ui| gpu_section(ui, ws));
                ui.separator();
                style::keyed(ui, section("memory"), |ui| memory_section(ui, ws));
                ui.separator();
                style::keyed(ui, section("quality"), |ui| quality_section(ui, ws));
                if ws.cx.engine.as_ref().is_some_and(|e| e.clip().is_some()) {
                    ui.separator();
                    style::keyed(ui, section("clip"), |ui| clip_section(ui, ws));
                }
                ui.separator();
                let asked = style::keyed(ui, section("bench"), |ui| {
                    bench.ui(ui, || bench_request(ws))
                });
                if let Some((level, text)) = asked {
                    ws.cx.notify(level, text);
                }
            });
        });
}

/// What a bench of the compared techniques measures: the loaded scene from the current view,
/// at the render size.
fn bench_request(ws: &Workspace) -> Result<BenchRequest, String> {
    let (Some(engine), Some(scene)) = (&ws.cx.engine, &ws.cx.scene) else {
        return Err("Load a scene to bench.".to_owned());
    };
    let ids = ws.cx.compared();
    if ids.is_empty() {
        return Err("Switch on a technique to bench it.".to_owned());
    }
    if ws.cx.render_size.0 == 0 || ws.cx.render_size.1 == 0 {
        return Err("The viewport has no size to bench at.".to_owned());
    }
    Ok(BenchRequest {
        scene: scene.spec.clone(),
        rig: *ws.cx.camera.rig(),
        size: ws.cx.render_size,
        techniques: ids.iter().map(|id| engine.technique_spec(id)).collect(),
        export_dir: ws.cx.settings.export_dir.clone(),
        overlay: ws.cx.settings.ui_overlay,
        specular_aa: engine.specular_aa(),
        tonemap: engine.tonemap().0,
        exposure: engine.tonemap().1,
    })
}

fn performance_section(ui: &mut egui::Ui, ws: &mut Workspace) {
    style::section(ui, "Frame rate");
    ui.horizontal(|ui| match ws.cx.clock.fps(Duration::from_secs(2)) {
        Some((fps, ms)) => {
            ui.label(RichText::new(format!("{fps:.1}")).size(26.0).strong().color(ACCENT))
                .on_hover_text("Frames per second: rendered frames in the last 2 s divided by their total time (UI frames that only redrew the interface are not counted).");
            ui.vertical(|ui| {
                ui.label("FPS");
                ui.label(RichText::new(style::ms(ms)).monospace().small())
                    .on_hover_text("Median wall-clock time between consecutive rendered frames over the last 2 s (CPU, GPU and presentation together).");
            });
        }
        None => {
            ui.weak("techniques idle: their view has not changed")
                .on_hover_text("Techniques render only when the view, their settings or time change (the reference keeps accumulating meanwhile). Turn on Orbit, or drag the view, to measure frame rates continuously.");
        }
    });
    let frame_points = ws.cx.clock.points();
    let gpu_points = ws
        .cx
        .engine
        .as_ref()
        .map(|e| e.gpu_stats.total_points())
        .unwrap_or_default();
    Plot::new("frame times")
        .height(110.0)
        .legend(Legend::default().position(egui_plot::Corner::LeftTop))
        .allow_drag(false)
        .allow_zoom(false)
        .allow_scroll(false)
        .show_x(false)
        .include_y(0.0)
        .y_axis_label("ms")
        .x_axis_formatter(|mark, _| format!("{:.0} s", mark.value))
        .show(ui, |plot| {
            plot.line(Line::new("frame (wall clock)", frame_points).color(ACCENT));
            plot.line(Line::new("GPU (all passes)", gpu_points).color(SLOT_COLORS[0]));
        })
        .response
        .on_hover_text("Wall-clock time between rendered frames, and the GPU time of all timed passes of each frame whose timestamps came back, over the last 20 s.");
}

fn gpu_section(ui: &mut egui::Ui, ws: &mut Workspace) {
    ui.horizontal(|ui| {
        style::section(ui, "GPU time per frame");
        ui.with_layout(egui::Layout::right_to_left(egui::Align::Center), |ui| {
            ui.checkbox(&mut ws.cx.settings.show_passes, "passes")
                .on_hover_text("List every pass of every technique");
        });
    });
    let show_passes = ws.cx.settings.show_passes;
    let Some(engine) = &ws.cx.engine else { return };
    if !engine.caps().timestamps {
        ui.weak(format!(
            "{} has no timestamp queries: no GPU times.",
            engine.caps().adapter_name
        ));
        return;
    }
    let stats = &engine.gpu_stats;
    let memory = engine.memory();
    let users_of = |input: &str| -> Vec<String> {
        memory
            .map(|m| {
                m.techniques
                    .iter()
                    .filter(|t| t.input.as_deref() == Some(input) && t.technique != REFERENCE_ID)
                    .map(|t| t.technique.clone())
                    .collect()
            })
            .unwrap_or_default()
    };
    let renders = stats.scene_renders();
    let enabled: Vec<(&'static str, &'static str)> = engine
        .entries()
        .iter()
        .filter(|e| e.enabled)
        .map(|e| (e.id, e.name))
        .collect();
    style::figures_table(
        ui,
        "gpu table",
        &[
            ("pass", None),
            ("own", None),
            (
                "to run alone",
                Some(
                    "Own passes plus the scene render it reads, i.e. what the technique would cost without sharing.",
                ),
            ),
        ],
        |ui| {
            for (label, ms) in &renders {
                let users = users_of(label);
                ui.label(label.clone()).on_hover_text(format!(
                    "One scene render per frame, shared by: {}",
                    if users.is_empty() {
                        "—".to_owned()
                    } else {
                        users.join(", ")
                    }
                ));
                number(
                    ui,
                    style::ms(*ms),
                    "Median GPU time of this scene render over the last 30 frames that ran it (timestamp queries around the render pass).",
                );
                ui.label(
                    RichText::new(format!("shared by {}", users.len()))
                        .small()
                        .weak(),
                );
                ui.end_row();
            }
            for (id, name) in &enabled {
                let own = stats.technique_ms(id);
                let input_ms = memory
                    .and_then(|m| m.techniques.iter().find(|t| t.technique == *id))
                    .and_then(|t| t.input.as_deref())
                    .and_then(|input| stats.pass_ms(input));
                ui.strong(*name);
                number(
                    ui,
                    own.map_or_else(|| "—".to_owned(), style::ms),
                    "Sum of the median GPU times of this technique's own passes (after the shared scene render).",
                );
                number(
                    ui,
                    own.map(|o| o + input_ms.unwrap_or(0.0))
                        .map_or_else(|| "—".to_owned(), style::ms),
                    "Own passes plus the scene render this technique reads.",
                );
                ui.end_row();
                for (pass, ms) in stats
                    .technique_passes(id)
                    .into_iter()
                    .filter(|_| show_passes)
                {
                    ui.label(RichText::new(format!("   {pass}")).small());
                    number(
                        ui,
                        style::ms(ms),
                        "Median GPU time of this pass over the last 30 frames that ran it.",
                    );
                    ui.label("");
                    ui.end_row();
                }
            }
            if let Some(ms) = stats.technique_ms(REFERENCE_ID) {
                ui.label("reference (viewer)")
                    .on_hover_text("The progressive reference's samples of a frame; it runs only while the camera is still.");
                number(
                    ui,
                    style::ms(ms),
                    "GPU time the reference added to its frames (median).",
                );
                ui.label("");
                ui.end_row();
            }
        },
    );
    let techniques = enabled.len();
    let renders = engine.scene_renders();
    if techniques > 0 && renders > 0 {
        ui.label(
            RichText::new(format!(
                "{renders} scene render(s) for {techniques} technique(s) per frame"
            ))
            .small(),
        )
        .on_hover_text("Techniques that read the same scene image (No AA, FXAA and SMAA 1x read the 1x render) share one render: the frame graph draws each distinct scene input once.");
    }
}

/// The clip's temporal figures (see `metrics::stability`).
fn clip_section(ui: &mut egui::Ui, ws: &mut Workspace) {
    style::section(ui, "Clip: temporal stability");
    let Some(clip) = ws.cx.engine.as_ref().and_then(|e| e.clip()) else {
        return;
    };
    let Some(scores) = &clip.scores else {
        ui.weak(if clip.recording_now() {
            "after the recording"
        } else {
            "recorded without the reference: no figures"
        });
        return;
    };
    style::figures_table(
        ui,
        "clip table",
        &[
            ("technique", None),
            ("instability", None),
            ("ghosting", None),
            ("JOD", Some(jod_panel::JOD_HELP)),
        ],
        |ui| {
            for (slot, (id, scores)) in clip.techniques.iter().zip(scores).enumerate() {
                ui.label(ws.cx.shown_label(id));
                let figure = |v: Option<f64>, digits: usize| {
                    v.map_or_else(|| "n/a".to_owned(), |v| format!("{v:.digits$}"))
                };
                number(
                    ui,
                    figure(scores.temporal_instability, 2),
                    "Mean frame-to-frame luma change over the reference's (1 = as steady as the reference, higher flickers more).",
                );
                number(
                    ui,
                    figure(scores.ghosting, 1),
                    "Mean luma error against the reference where the reference moved (levels of 0..255): trails and aliasing on moving edges.",
                );
                jod_panel::figure_cell(ui, ws, slot);
                ui.end_row();
            }
        },
    );
    if let Some(change) = clip.reference_change {
        ui.weak(format!(
            "reference: {change:.2} luma levels change per pixel and frame"
        ));
    }
    jod_panel::controls(ui, ws, "clip");
}

fn memory_section(ui: &mut egui::Ui, ws: &mut Workspace) {
    style::section(ui, "GPU memory");
    let Some(memory) = ws.cx.engine.as_ref().and_then(|e| e.memory()) else {
        ui.weak("after the first frame");
        return;
    };
    let reference_bytes: u64 = memory
        .techniques
        .iter()
        .filter(|t| t.technique == REFERENCE_ID)
        .map(|t| t.own_bytes())
        .sum();
    style::figures_table(
        ui,
        "memory table",
        &[("technique", None), ("own", None), ("to run alone", None)],
        |ui| {
            for t in memory
                .techniques
                .iter()
                .filter(|t| t.technique != REFERENCE_ID)
            {
                let name = ws
                    .cx
                    .engine
                    .as_ref()
                    .and_then(|e| e.entry(&t.technique))
                    .map_or(t.technique.as_str(), |e| e.name);
                let items: Vec<String> = t
                    .input_items
                    .iter()
                    .chain(&t.private_items)
                    .chain(t.output.iter())
                    .map(|i| {
                        format!(
                            "{}: {} {}x{} {} spp, {}",
                            i.label,
                            i.format,
                            i.width,
                            i.height,
                            i.samples,
                            style::mib(i.bytes)
                        )
                    })
                    .collect();
                ui.label(name).on_hover_text(items.join("\n"));
                number(
                    ui,
                    style::mib(t.own_bytes()),
                    "Textures and buffers this technique owns, its output included.",
                );
                number(
                    ui,
                    style::mib(t.standalone_bytes()),
                    "Own memory plus the scene render targets it reads (shared ones would be needed anyway).",
                );
                ui.end_row();
            }
            ui.label("scene");
            number(
                ui,
                style::mib(memory.scene_bytes),
                "The uploaded scene: vertex and index buffers, textures with their mip chains.",
            );
            ui.label("");
            ui.end_row();
            ui.strong("total");
            number(
                ui,
                style::mib(
                    memory
                        .total_bytes
                        .saturating_sub(reference_bytes + memory.idle_bytes()),
                ),
                "Everything the enabled techniques use, shared scene inputs counted once, scene included (the viewer's reference and switched-off techniques not included).",
            );
            ui.label("");
            ui.end_row();
            if !memory.idle.is_empty() {
                let ids: Vec<&str> = memory.idle.iter().map(|t| t.technique.as_str()).collect();
                ui.weak("switched off");
                number(
                    ui,
                    style::mib(memory.idle_bytes()),
                    &format!(
                        "Still allocated by techniques switched off (their private targets and last output, kept so that switching one back on is instant; they read no scene input): {}.",
                        ids.join(", ")
                    ),
                );
                ui.label("");
                ui.end_row();
            }
            if reference_bytes > 0 {
                ui.weak("reference (viewer)");
                number(
                    ui,
                    style::mib(reference_bytes),
                    "The progressive reference's accumulator and render targets.",
                );
                ui.label("");
                ui.end_row();
            }
        },
    );
}

fn quality_section(ui: &mut egui::Ui, ws: &mut Workspace) {
    style::section(ui, "Quality against the reference");
    ui.checkbox(&mut ws.cx.settings.quality, "Measure")
        .on_hover_text("Accumulate the supersampled reference while the camera is still and score every technique against it.");
    ui.horizontal(|ui| {
        ui.label("Reference");
        let mut samples = ws.cx.settings.reference_samples;
        egui::ComboBox::from_id_salt("reference samples")
            .width(150.0)
            .selected_text(format!("{samples} spp ({0}×{0} grid)", super::reference::grid_factor(samples)))
            .show_ui(ui, |ui| {
                for n in [16, 64, 256] {
                    ui.selectable_value(&mut samples, n, format!("{n} spp ({0}×{0} grid)", super::reference::grid_factor(n)));
                }
            })
            .response
            .on_hover_text("Samples per pixel of the reference: an ordered k×k grid with a box filter, the same samples as `aa-lab render --ssaa-factor k` (the thesis used 16).");
        if samples != ws.cx.settings.reference_samples {
            ws.cx.settings.reference_samples = samples;
            if let Some(engine) = &mut ws.cx.engine {
                engine.set_reference_samples(samples);
            }
        }
    });
    let state = ws
        .cx
        .engine
        .as_ref()
        .map_or(ReferenceState::Off, |e| e.reference_state());
    let status = match state {
        ReferenceState::Off => RichText::new("off").weak(),
        ReferenceState::Waiting => RichText::new(
            if ws.cx.engine.as_ref().is_some_and(|e| e.animated()) && ws.cx.camera.playing {
                "stale: the scene animates; pause (Space) to measure"
            } else {
                "stale: waiting for the camera to stop"
            },
        )
        .color(style::WARN),
        ReferenceState::Ready(p) if p.complete() => {
            RichText::new(format!("converged: {} samples per pixel", p.total))
        }
        ReferenceState::Ready(p) => RichText::new(format!(
            "accumulating: {} of {} samples per pixel",
            p.samples, p.total
        )),
    };
    ui.label(status).on_hover_text(
        "The reference is re-accumulated from scratch whenever the view changes, a few samples per frame; figures below rest on the samples it had when they were measured.",
    );
    if let ReferenceState::Ready(p) = state {
        ui.add(
            egui::ProgressBar::new(p.samples as f32 / p.total.max(1) as f32).desired_height(6.0),
        );
    }
    quality_table(ui, ws, state);
}

/// Per enabled technique: SSIM, PSNR, MAE and FLIP, each with a tooltip saying what it
/// measures against which reference, or why there is no number.
fn quality_table(ui: &mut egui::Ui, ws: &Workspace, state: ReferenceState) {
    let Some(engine) = &ws.cx.engine else { return };
    let compared = ws.cx.compared();
    // The compared techniques first, in the order of their letters (as the toolbar and the
    // magnifier show them), then the other running ones in list order.
    let mut enabled: Vec<&'static str> = engine
        .entries()
        .iter()
        .filter(|e| e.enabled)
        .map(|e| e.id)
        .collect();
    enabled.sort_by_key(|id| compared.iter().position(|c| c == id).unwrap_or(usize::MAX));
    if enabled.is_empty() {
        ui.weak("Switch a technique on to measure it.");
        return;
    }
    // Stale: the reference on hand is not of the view being rendered (the camera moved).
    let stale = engine
        .reference()
        .is_none_or(|(r, _)| r.stamp.view != engine.current_view());
    let (missing, missing_tip) = if !ws.cx.settings.quality || state == ReferenceState::Off {
        ("off", "Measuring is off.")
    } else if stale {
        (
            "stale",
            "Stale: the view changed since this was measured. New figures follow once the camera stops and the reference has samples of the new view.",
        )
    } else {
        (
            "…",
            "Being measured: the figures of the image on screen are computed in the background.",
        )
    };
    let mut notes = Vec::new();
    style::figures_table(
        ui,
        "quality table",
        &[
            ("technique", None),
            (
                "SSIM",
                Some("Structural similarity of luma; 1 = identical."),
            ),
            (
                "PSNR",
                Some("Peak signal-to-noise ratio of R'G'B' in dB; higher is closer."),
            ),
            (
                "MAE",
                Some("Mean absolute error of R'G'B', 0..255; 0 = identical."),
            ),
            (
                "FLIP",
                Some("NVIDIA's perceptual FLIP error, 0..1; 0 = indistinguishable."),
            ),
        ],
        |ui| {
            for id in &enabled {
                ui.horizontal(|ui| {
                    if let Some(slot) = compared.iter().position(|c| c == id) {
                        ui.label(style::badge(SLOT_LETTERS[slot], SLOT_COLORS[slot]));
                    }
                    ui.label(ws.cx.shown_label(id));
                });
                let pixels = ws.quality.current_pixels(id, ws.cx.measure_key(id));
                match pixels.map(|m| (&m.value, m)) {
                    Some((Ok(f), m)) => {
                        let n = m.reference.samples;
                        let how = format!("\n\nMeasured on the {} in {}.", m.on, style::ms(m.ms));
                        number(
                            ui,
                            format!("{:.4}", f.ssim),
                            &(quality::ssim_help(n) + &how),
                        );
                        number(
                            ui,
                            quality::psnr_text(f.psnr),
                            &(quality::psnr_help(n) + &how),
                        );
                        number(ui, format!("{:.3}", f.mae), &(quality::mae_help(n) + &how));
                    }
                    Some((Err(err), _)) => {
                        for _ in 0..3 {
                            number_weak(ui, "error", err);
                        }
                        notes.push(format!("{}: {err}", ws.cx.shown_label(id)));
                    }
                    None => {
                        for _ in 0..3 {
                            number_weak(ui, missing, missing_tip);
                        }
                    }
                }
                match ws.quality.current_flip(id, ws.cx.measure_key(id)) {
                    Some(m) => match &m.value {
                        Ok(v) => {
                            let tip = format!(
                                "{}\n\nMeasured in {}.",
                                quality::flip_help(m.reference.samples),
                                style::ms(m.ms)
                            );
                            number(ui, format!("{v:.4}"), &tip);
                        }
                        Err(err) => number_weak(ui, "error", err),
                    },
                    None if pixels.is_some() => number_weak(
                        ui,
                        "…",
                        "FLIP is computed on the CPU, after the others: once the camera has been still for a moment, and again when the reference has converged.",
                    ),
                    None => number_weak(ui, missing, missing_tip),
                }
                ui.end_row();
            }
        },
    );
    let samples: Vec<u32> = enabled
        .iter()
        .filter_map(|id| ws.quality.current_pixels(id, ws.cx.measure_key(id)))
        .map(|m| m.reference.samples)
        .collect();
    if let (Some(lo), Some(hi)) = (samples.iter().min(), samples.iter().max()) {
        let total = match state {
            ReferenceState::Ready(p) => p.total,
            _ => *hi,
        };
        let rest = if lo == hi {
            format!("Figures rest on {hi} of {total} reference samples per pixel.")
        } else {
            format!("Figures rest on {lo} to {hi} of {total} reference samples per pixel.")
        };
        ui.label(RichText::new(rest).small()).on_hover_text(
            "The reference the figures were measured against: they are refreshed as it gains samples, and exact once it has converged. FLIP may rest on fewer samples (see its tooltip).",
        );
    } else if stale && ws.cx.settings.quality {
        ui.label(
            RichText::new("Figures are stale while the view changes.")
                .small()
                .color(style::WARN),
        );
    }
    for note in notes {
        ui.label(RichText::new(note).small().color(style::ERROR));
    }
}
