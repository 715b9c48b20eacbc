//! The magnifier: the lens region of every compared technique (and optionally the reference)
//! side by side, nearest-neighbour zoomed by an integer factor from 2x to 32x, with an optional
//! pixel grid, a crosshair linked across panes and the pixel values under the cursor. In
//! difference mode each pane shows its error against the reference as a heatmap.
//!
//! Panes draw the published textures (nearest sampler, integer zoom, pixel-aligned), so they
//! show the very pixels of the frame; pixel values and heatmaps come from the same published
//! images on the CPU. Heatmaps (difference.rs) are recomputed in the background when the lens,
//! the images or the metric change, from the lens region plus a margin so that windowed
//! metrics see the pixels' neighbourhood.
//!
//! What this module owns:
//! - [`MagnifierState`]: the heatmaps and their worker, the panes' captions and the composed
//!   magnifier sheet (exports and the clipboard). Where the lens is, the panes' sources and
//!   labels are the context's (`context/shown.rs`), since the viewport, exports and blind
//!   answers read them too.
//! - [`MagnifierPanel`], the panel: it sizes the lens to its panes and owns the pane pixel under
//!   the pointer; the viewport's hovered pixel is passed in for the crosshair.

use egui::{Color32, Rect, Sense, Stroke, TextureHandle, pos2, vec2};

use super::blit;
use super::context::{Command, Context, Level};
use super::difference::{
    self, DiffMetric, HeatInput, HeatJob, HeatKey, HeatResult, heat_color, lens_heatmap,
};
use super::engine::ReferenceState;
use super::lens::{Source, crop};
use super::settings::MagnifierSettings;
use super::shortcuts::{Action, shortcut_hint};
use super::style::{self, ShowKeyed};
use super::worker::Worker;
use crate::export::sheet::{self, Cell, Row};
use crate::gpu::readback::Region;

/// The zoom factors offered.
pub const ZOOM_STEPS: [u32; 9] = [2, 3, 4, 6, 8, 12, 16, 24, 32];
/// Gap between panes, in points.
const PANE_GAP: f32 = 8.0;

/// The newest heatmap of a pane.
struct PaneHeat {
    source: Source,
    key: HeatKey,
    /// The texture, the lens it covers and its mean, or why there is none.
    result: Result<(TextureHandle, Region, f64), String>,
}

/// The heatmaps, kept between frames by the workspace: export sheets and the test API read
/// them, and scene and image set changes forget them with the quality figures
/// (`Command::ForgetMeasurements`).
#[derive(Default)]
pub struct MagnifierState {
    worker: Option<Worker<HeatJob, HeatResult>>,
    worker_error: Option<String>,
    /// The heatmaps last asked for.
    requested: Option<HeatKey>,
    heatmaps: Vec<PaneHeat>,
}

impl MagnifierState {
    /// Forgets the heatmaps (new scene).
    pub fn clear(&mut self) {
        self.heatmaps.clear();
        self.requested = None;
    }

    /// Whether heatmaps are being computed.
    pub fn computing(&self) -> bool {
        self.worker.as_ref().is_some_and(Worker::busy)
    }

    /// Steps the zoom through [`ZOOM_STEPS`].
    pub fn zoom_by(&self, settings: &mut MagnifierSettings, steps: i32) {
        let index = ZOOM_STEPS
            .iter()
            .position(|z| *z >= settings.zoom)
            .unwrap_or(ZOOM_STEPS.len() - 1) as i32;
        let next = (index + steps).clamp(0, ZOOM_STEPS.len() as i32 - 1) as usize;
        settings.zoom = ZOOM_STEPS[next];
    }
}

impl MagnifierState {
    /// Takes finished heatmaps and asks for new ones when the lens, the images or the metric
    /// changed.
    pub(super) fn update(&mut self, cx: &mut Context, ctx: &egui::Context) {
        profiling::function_scope!();
        let results = self.worker.as_mut().map(Worker::poll).unwrap_or_default();
        for result in results {
            let result_for_pane = result.heatmap.map(|heat| {
                let handle = ctx.load_texture(
                    format!("magnifier heatmap {:?}", result.source),
                    heat.colors,
                    egui::TextureOptions::NEAREST,
                );
                (handle, heat.lens, heat.mean)
            });
            self.heatmaps.retain(|h| h.source != result.source);
            self.heatmaps.push(PaneHeat {
                source: result.source,
                key: result.key,
                result: result_for_pane,
            });
        }
        if !cx.settings.show_magnifier || !cx.settings.magnifier.difference {
            return;
        }
        let Some(job) = self.heat_job(cx) else { return };
        if self.requested.as_ref() == Some(&job.key) {
            return;
        }
        let key = job.key.clone();
        if self.worker.is_none() && self.worker_error.is_none() {
            match difference::spawn_heat_worker(ctx) {
                Ok(worker) => self.worker = Some(worker),
                Err(err) => {
                    let text = format!("no thread for the magnifier's heatmaps: {err}");
                    self.worker_error = Some(text.clone());
                    cx.notify(Level::Error, text);
                }
            }
        }
        if let Some(worker) = &mut self.worker
            && worker.submit(job)
        {
            self.requested = Some(key);
        }
    }

    /// The heatmaps the panes should show now: the lens, the newest images, the metric.
    fn heat_job(&self, cx: &Context) -> Option<HeatJob> {
        let lens = cx.lens()?;
        let reference = cx.source_image(Source::Reference)?;
        // The images' own size: a clip keeps the size it was recorded at.
        let size = reference.size();
        let reference_pixels = reference.pixels.clone()?;
        let mut images = vec![reference.stamp.serial];
        let mut tests = Vec::new();
        let metric = cx.settings.magnifier.metric;
        for source in cx.magnifier_sources() {
            let Source::Technique(_, id) = source else {
                continue;
            };
            let Some(image) = cx.source_image(source).filter(|i| i.size() == size) else {
                continue;
            };
            // The maps over the clip or sequences hold whichever of their frames shows.
            let input = match metric {
                DiffMetric::Instability => match cx.instability_map(id) {
                    Some(map) => HeatInput::Map(map),
                    None => HeatInput::Missing(
                        "temporal instability needs a clip recorded with the reference on screen"
                            .to_owned(),
                    ),
                },
                DiffMetric::JodDistortion => match cx.jod_maps.panes.get(id) {
                    Some(Ok(map)) => HeatInput::Map(std::sync::Arc::clone(map)),
                    Some(Err(why)) => HeatInput::Missing(why.clone()),
                    None => HeatInput::Missing(
                        "the JOD distortion needs a clip recorded with the reference, or \
                         sequences with a reference"
                            .to_owned(),
                    ),
                },
                _ => {
                    let Some(pixels) = &image.pixels else {
                        continue;
                    };
                    HeatInput::Image(std::sync::Arc::clone(pixels))
                }
            };
            images.push(image.stamp.serial);
            tests.push((source, input));
        }
        (!tests.is_empty()).then(|| HeatJob {
            key: HeatKey {
                lens,
                images,
                sources: tests.iter().map(|(s, _)| *s).collect(),
                view: reference.stamp.view,
                metric,
                maps: match metric {
                    DiffMetric::JodDistortion => cx.jod_maps.generation,
                    _ => 0,
                },
            },
            reference: reference_pixels,
            tests,
        })
    }

    /// In difference mode, once every technique pane shows the heatmap of the current lens,
    /// images and metric: the lens means of the panes' maps, in pane order (SSIM itself for
    /// the SSIM map).
    pub(super) fn difference_means(&self, cx: &Context) -> Option<Vec<f64>> {
        let job = self.heat_job(cx)?;
        job.key
            .sources
            .iter()
            .map(|source| {
                let heat = self.heatmaps.iter().find(|h| h.source == *source)?;
                match &heat.result {
                    Ok((_, _, mean)) if heat.key == job.key => Some(*mean),
                    _ => None,
                }
            })
            .collect()
    }

    /// The heatmap of a pane when it shows the displayed view with the selected metric.
    fn pane_heat(&self, cx: &Context, source: Source) -> Option<&PaneHeat> {
        let view = cx.current_view()?;
        self.heatmaps.iter().find(|h| {
            h.source == source && h.key.view == view && h.key.metric == cx.settings.magnifier.metric
        })
    }

    /// The figures under a pane: quality against the reference (or the region's mean error in
    /// difference mode).
    pub(super) fn pane_figures(
        &self,
        cx: &Context,
        source: Source,
        figures: &dyn Fn(&str) -> Option<String>,
    ) -> String {
        match source {
            Source::Reference if cx.images.is_open() => "reference image".to_owned(),
            Source::Reference => match cx.reference_state_for() {
                Some(ReferenceState::Ready(p)) if p.complete() => "converged".to_owned(),
                Some(ReferenceState::Ready(p)) => format!("accumulating {}/{}", p.samples, p.total),
                _ => "waiting for a still camera".to_owned(),
            },
            // Figures would tell the techniques apart.
            Source::Technique(..) if cx.blind.active() => String::new(),
            Source::Technique(_, id) => {
                let mut parts = Vec::new();
                let lens = cx.lens();
                if cx.settings.magnifier.difference
                    && let Some(PaneHeat {
                        result: Ok((_, at, mean)),
                        ..
                    }) = self.pane_heat(cx, source)
                    && Some(*at) == lens
                {
                    parts.push(cx.settings.magnifier.metric.mean_text(*mean));
                }
                if let Some(figures) = figures(id) {
                    parts.push(figures);
                }
                if cx.is_reference_image(id) {
                    parts.push("reference image".to_owned());
                }
                parts.join(" · ")
            }
        }
    }

    /// The magnifier sheet of the current lens, composed: every pane as the magnifier shows it
    /// (pixels, or heatmaps in difference mode), labelled, with its figures underneath.
    pub(super) fn sheet(
        &self,
        cx: &Context,
        figures: &dyn Fn(&str) -> Option<String>,
    ) -> Option<image::RgbaImage> {
        let lens = cx.lens()?;
        let zoom = cx.settings.magnifier.zoom;
        let metric = cx.settings.magnifier.metric;
        let reference = cx.source_image(Source::Reference);
        let mut columns = Vec::new();
        let mut cells = Vec::new();
        for source in cx.magnifier_sources() {
            let Some(image) = cx.source_image(source).and_then(|i| i.pixels.as_ref()) else {
                continue;
            };
            let reference = reference.and_then(|r| r.pixels.as_ref());
            let pixels = match reference {
                Some(reference)
                    if cx.settings.magnifier.difference && source != Source::Reference =>
                {
                    lens_heatmap(metric, reference, image, lens).ok()?.to_rgba()
                }
                _ => crop(image, lens),
            };
            let whole = sheet::Rect {
                x: 0,
                y: 0,
                width: lens.width,
                height: lens.height,
            };
            let (letter, _, title) = cx.source_label(source);
            columns.push(format!("{letter} · {title}"));
            let caption = self.pane_figures(cx, source, figures);
            cells.push(Cell {
                image: sheet::crop_zoom(&pixels, whole, zoom).ok()?,
                caption: (!caption.is_empty()).then_some(caption),
            });
        }
        if cells.is_empty() {
            return None;
        }
        let scene = cx.scene.as_ref().map_or("", |s| s.name.as_str());
        let frame = cx
            .engine
            .as_ref()
            .and_then(|e| e.displayed())
            .map_or(0, |c| c.frame);
        let (w, h) = cx.render_size;
        let mode = if cx.settings.magnifier.difference {
            format!(", {} against the reference", metric.label().to_lowercase())
        } else {
            String::new()
        };
        let what = match cx.image_names() {
            Some((names, _)) => names.join(", "),
            None => format!("{scene}, frame {frame}"),
        };
        Some(sheet::compose(&sheet::Sheet {
            title: format!("{what}, {w}×{h}{mode}"),
            columns,
            rows: vec![Row {
                label: format!("lens {zoom}×"),
                detail: Some(format!(
                    "{}×{} at ({}, {})",
                    lens.width, lens.height, lens.x, lens.y
                )),
                cells,
            }],
            footer: Some(format!(
                "{} on {}",
                crate::spec::build_id(),
                cx.gpu.caps.adapter_name
            )),
        }))
    }

    /// Copies the magnifier sheet to the clipboard.
    pub(super) fn copy_sheet(
        &self,
        cx: &mut Context,
        ctx: &egui::Context,
        figures: &dyn Fn(&str) -> Option<String>,
    ) {
        match self.sheet(cx, figures) {
            Some(image) => {
                let size = [image.width() as usize, image.height() as usize];
                ctx.copy_image(egui::ColorImage::from_rgba_unmultiplied(
                    size,
                    image.as_raw(),
                ));
                cx.notify(
                    Level::Info,
                    format!(
                        "Copied the magnifier sheet ({}×{}) to the clipboard",
                        size[0], size[1]
                    ),
                );
            }
            None => cx.notify(
                Level::Warning,
                "The magnifier has no pixels yet: show the magnifier and wait for the first frame.",
            ),
        }
    }
}

/// The magnifier panel; the lens size it decides is the context's, the heatmaps the
/// [`MagnifierState`]'s.
#[derive(Default)]
pub(super) struct MagnifierPanel {
    /// The frame pixel under the pointer in a pane.
    hover: Option<(u32, u32)>,
}

/// What the panel reads besides the context.
#[derive(Clone, Copy)]
pub(super) struct PanelInputs<'a> {
    /// The heatmaps and captions.
    pub state: &'a MagnifierState,
    /// The figures line of a compared technique (the quality feature's).
    pub figures: &'a dyn Fn(&str) -> Option<String>,
    /// The frame pixel under the pointer in the viewport, for the crosshair.
    pub viewport_hover: Option<(u32, u32)>,
}

impl MagnifierPanel {
    /// The frame pixel under the pointer in a pane, in the last frame.
    pub(super) fn hover(&self) -> Option<(u32, u32)> {
        self.hover
    }

    /// The magnifier panel (bottom of the window).
    pub(super) fn ui(&mut self, ui: &mut egui::Ui, cx: &mut Context, inputs: PanelInputs<'_>) {
        profiling::function_scope!();
        egui::Panel::bottom("magnifier")
            .resizable(true)
            .default_size(330.0)
            .size_range(180.0..=700.0)
            .frame(
                egui::Frame::side_top_panel(ui.style())
                    .inner_margin(egui::Margin::symmetric(10, 6)),
            )
            .show_keyed(ui, "magnifier", |ui| {
                // Keep the panel at its set height (panels otherwise shrink to their content).
                ui.set_min_height(ui.available_height());
                header(ui, cx);
                ui.add_space(4.0);
                self.panes(ui, cx, &inputs);
            });
    }

    fn panes(&mut self, ui: &mut egui::Ui, cx: &mut Context, inputs: &PanelInputs<'_>) {
        let PanelInputs {
            state,
            figures,
            viewport_hover,
        } = *inputs;
        let ppp = ui.ctx().pixels_per_point();
        let sources = cx.magnifier_sources();
        let zoom = cx.settings.magnifier.zoom.max(1);
        let caption_height = 42.0;
        let n = sources.len().max(1) as f32;
        let avail = ui.available_size();
        let side_points = ((avail.x - PANE_GAP * (n - 1.0)) / n)
            .min(avail.y - caption_height)
            .max(16.0);
        let side_px = (side_points * ppp).floor() as u32;
        cx.lens_side = (side_px / zoom).max(1);
        let Some(lens) = cx.lens() else {
            ui.weak("The lens appears once the first frame is rendered.");
            return;
        };
        let size = cx.render_size;
        let pane_points = vec2(
            (lens.width * zoom) as f32 / ppp,
            (lens.height * zoom) as f32 / ppp,
        );
        let mut hover = None;
        let mut clicked = None;
        let mut pane_rects = Vec::new();
        ui.horizontal_top(|ui| {
            ui.spacing_mut().item_spacing.x = PANE_GAP;
            for source in &sources {
                ui.vertical(|ui| {
                    let (rect, response) = ui.allocate_exact_size(pane_points, Sense::click());
                    if let (true, Source::Technique(slot, _)) = (response.clicked(), *source) {
                        clicked = Some(slot);
                    }
                    let rect = Rect::from_min_size(
                        pos2(
                            (rect.min.x * ppp).round() / ppp,
                            (rect.min.y * ppp).round() / ppp,
                        ),
                        pane_points,
                    );
                    pane_rects.push((*source, rect));
                    if let Some(p) = response.hover_pos() {
                        let local = (p - rect.min) * ppp / zoom as f32;
                        if local.x >= 0.0 && local.y >= 0.0 {
                            hover = Some((
                                lens.x + (local.x as u32).min(lens.width - 1),
                                lens.y + (local.y as u32).min(lens.height - 1),
                            ));
                        }
                    }
                    paint_pane(ui, cx, state, *source, rect, lens, size);
                    pane_caption(ui, state.pane_figures(cx, *source, figures), pane_points.x);
                });
            }
        });
        self.hover = hover;
        if let Some(slot) = clicked {
            cx.blind_click(slot);
        }
        let marked = hover.or(viewport_hover.filter(|(x, y)| {
            *x >= lens.x && *y >= lens.y && *x < lens.x + lens.width && *y < lens.y + lens.height
        }));
        if let Some((x, y)) = marked {
            for (_, rect) in &pane_rects {
                let cell = Rect::from_min_size(
                    rect.min
                        + vec2(
                            ((x - lens.x) * zoom) as f32 / ppp,
                            ((y - lens.y) * zoom) as f32 / ppp,
                        ),
                    vec2(zoom as f32 / ppp, zoom as f32 / ppp),
                );
                let painter = ui.painter().with_clip_rect(*rect);
                style::outline(&painter, cell);
            }
            pixel_readout(ui, cx, (x, y), &sources);
        } else {
            ui.weak("Point at a pane (or at the lens in the view) to read pixel values.");
        }
    }
}

fn header(ui: &mut egui::Ui, cx: &mut Context) {
    let ctx = ui.ctx().clone();
    ui.horizontal(|ui| {
            ui.strong("Magnifier");
            ui.separator();
            let m = &mut cx.settings.magnifier;
            ui.label("Zoom").on_hover_text("Nearest-neighbour zoom: each frame pixel becomes a zoom x zoom block.");
            egui::ComboBox::from_id_salt("magnifier zoom")
                .width(64.0)
                .selected_text(format!("{}×", m.zoom))
                .show_ui(ui, |ui| {
                    for z in ZOOM_STEPS {
                        ui.selectable_value(&mut m.zoom, z, format!("{z}×"));
                    }
                })
                .response
                .on_hover_text(shortcut_hint(&ctx, Action::ZoomIn, "Zoom in"));
            ui.checkbox(&mut m.pixel_grid, "Pixel grid")
                .on_hover_text(shortcut_hint(&ctx, Action::PixelGrid, "Lines between magnified pixels"));
            ui.checkbox(&mut m.show_reference, "Reference")
                .on_hover_text("Add a pane with the supersampled reference of the same frame");
            ui.checkbox(&mut m.difference, "Difference")
                .on_hover_text(shortcut_hint(&ctx, Action::Difference, "Show each pane's error against the reference as a heatmap"));
            ui.add_enabled_ui(m.difference, |ui| {
                egui::ComboBox::from_id_salt("difference metric")
                    .width(120.0)
                    .selected_text(m.metric.label())
                    .show_ui(ui, |ui| {
                        for metric in DiffMetric::MENU {
                            ui.selectable_value(&mut m.metric, metric, metric.label())
                                .on_hover_text(metric.help());
                        }
                    })
                    .response
                    .on_hover_text(m.metric.help());
                if m.difference {
                    heat_legend(ui, m.metric);
                }
            });
            if let Some(lens) = cx.lens() {
                ui.separator();
                ui.weak(format!(
                    "lens {}×{} at ({}, {})",
                    lens.width, lens.height, lens.x, lens.y
                ))
                .on_hover_text("Drag the white rectangle in the view, Ctrl+click to place it, or nudge it with the arrow keys.");
            }
            ui.with_layout(egui::Layout::right_to_left(egui::Align::Center), |ui| {
                // Keyed: the lens readout and the legend before it come and go.
                let copy = egui::Id::unique("magnifier: copy sheet");
                if style::keyed(ui, copy, |ui| ui.button("Copy sheet"))
                    .on_hover_text(shortcut_hint(&ctx, Action::CopySheet, "Copy the magnifier sheet (all panes with labels and metrics) to the clipboard"))
                    .clicked()
                {
                    cx.request(Command::CopySheet);
                }
            });
        });
}

fn paint_pane(
    ui: &egui::Ui,
    cx: &Context,
    state: &MagnifierState,
    source: Source,
    rect: Rect,
    lens: Region,
    size: (u32, u32),
) {
    let painter = ui.painter().with_clip_rect(rect);
    let ppp = ui.ctx().pixels_per_point();
    let zoom = cx.settings.magnifier.zoom.max(1);
    let difference = cx.settings.magnifier.difference && source != Source::Reference;
    let image = cx
        .source_image(source)
        .filter(|i| !difference && i.size() == size);
    // The pane's background, except under an image, which covers the pane and is drawn
    // without blending (on a software rasteriser every painted pixel costs, in every paint).
    if image.is_none() {
        blit::fill(&painter, rect, Color32::from_gray(12));
    }
    if difference {
        let heat = state.pane_heat(cx, source).map(|h| &h.result);
        match heat {
            Some(Ok((handle, at, _))) => {
                // Drawn where it was computed: while the lens moves, the newest map stays
                // on its own pixels until the map of the new position arrives.
                let scale = zoom as f32 / ppp;
                let min = rect.min
                    + vec2(
                        (at.x as f32 - lens.x as f32) * scale,
                        (at.y as f32 - lens.y as f32) * scale,
                    );
                let placed = Rect::from_min_size(
                    min,
                    vec2(at.width as f32 * scale, at.height as f32 * scale),
                );
                painter.image(
                    handle.id(),
                    placed,
                    Rect::from_min_max(pos2(0.0, 0.0), pos2(1.0, 1.0)),
                    Color32::WHITE,
                );
            }
            Some(Err(err)) => {
                painter.text(
                    rect.center(),
                    egui::Align2::CENTER_CENTER,
                    format!("no heatmap: {err}"),
                    egui::FontId::proportional(12.0),
                    style::ERROR,
                );
            }
            None => {
                let text = match cx.reference_state_for() {
                    Some(ReferenceState::Ready(_)) => "computing…",
                    _ => "waiting for the reference\n(it accumulates while the camera is still)",
                };
                painter.text(
                    rect.center(),
                    egui::Align2::CENTER_CENTER,
                    text,
                    egui::FontId::proportional(12.0),
                    ui.visuals().weak_text_color(),
                );
            }
        }
    } else if let Some(image) = image {
        let uv = Rect::from_min_max(
            pos2(lens.x as f32 / size.0 as f32, lens.y as f32 / size.1 as f32),
            pos2(
                (lens.x + lens.width) as f32 / size.0 as f32,
                (lens.y + lens.height) as f32 / size.1 as f32,
            ),
        );
        let grid = cx.settings.magnifier.pixel_grid && zoom >= 4;
        // egui's former grid: black lines at 90/255.
        let darken = if grid { 90.0 / 255.0 } else { 0.0 };
        blit::paint_with_grid(&painter, image.texture(), rect, uv, darken);
    } else {
        let text = match source {
            Source::Reference => "reference: waiting for a still camera",
            Source::Technique(..) => "rendering…",
        };
        // Wrapped to the pane, so that narrow panes show the whole message.
        let color = ui.visuals().weak_text_color();
        let galley = painter.layout(
            text.to_owned(),
            egui::FontId::proportional(12.0),
            color,
            (rect.width() - 8.0).max(1.0),
        );
        painter.galley(rect.center() - galley.size() / 2.0, galley, color);
    }
    // Over heatmaps (egui images) the grid is drawn as lines; image panes draw it in their
    // blit.
    if difference && cx.settings.magnifier.pixel_grid && zoom >= 4 {
        let stroke = Stroke::new(1.0, Color32::from_black_alpha(90));
        let step = zoom as f32 / ppp;
        for i in 1..lens.width {
            let x = rect.min.x + i as f32 * step;
            painter.line_segment([pos2(x, rect.min.y), pos2(x, rect.max.y)], stroke);
        }
        for j in 1..lens.height {
            let y = rect.min.y + j as f32 * step;
            painter.line_segment([pos2(rect.min.x, y), pos2(rect.max.x, y)], stroke);
        }
    }
    let (letter, color, name) = cx.source_label(source);
    style::chip(&painter, rect.min + vec2(6.0, 6.0), letter, color, &name);
}

fn pane_caption(ui: &mut egui::Ui, text: String, width: f32) {
    ui.set_max_width(width);
    ui.add(egui::Label::new(egui::RichText::new(text).small().monospace()).wrap());
}

fn pixel_readout(ui: &mut egui::Ui, cx: &Context, (x, y): (u32, u32), sources: &[Source]) {
    ui.horizontal_wrapped(|ui| {
        ui.monospace(format!("({x}, {y})"));
        for source in sources {
            let (letter, color, _) = cx.source_label(*source);
            ui.label(style::badge(letter, color));
            let pixel = cx
                .source_image(*source)
                .and_then(|i| i.pixels.as_ref()?.get_pixel_checked(x, y))
                .map(|p| p.0);
            match pixel {
                Some([r, g, b, _]) => {
                    let (swatch, _) = ui.allocate_exact_size(vec2(10.0, 10.0), Sense::hover());
                    ui.painter()
                        .rect_filled(swatch, 2.0, Color32::from_rgb(r, g, b));
                    ui.monospace(format!("{r:>3} {g:>3} {b:>3}  #{r:02x}{g:02x}{b:02x}"))
                        .on_hover_text(
                            "sRGB-encoded 8-bit values as stored in the technique's output",
                        );
                }
                None => {
                    ui.weak("—");
                }
            }
        }
    });
}

/// A small colour bar with the values at its ends.
fn heat_legend(ui: &mut egui::Ui, metric: DiffMetric) {
    let (low, high) = metric.scale_ends();
    ui.weak(low);
    let (rect, _) = ui.allocate_exact_size(vec2(72.0, 10.0), Sense::hover());
    let steps = 36;
    let step = rect.width() / steps as f32;
    for i in 0..steps {
        let x = rect.min.x + i as f32 * step;
        let cell = Rect::from_min_max(pos2(x, rect.min.y), pos2(x + step + 0.5, rect.max.y));
        let color = heat_color(i as f32 / (steps - 1) as f32);
        ui.painter().rect_filled(cell, 0.0, color);
    }
    ui.weak(high).on_hover_text(metric.help());
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn zoom_steps_clamp() {
        let state = MagnifierState::default();
        let mut m = MagnifierSettings {
            zoom: 8,
            ..Default::default()
        };
        state.zoom_by(&mut m, 1);
        assert_eq!(m.zoom, 12);
        state.zoom_by(&mut m, 10);
        assert_eq!(m.zoom, 32);
        state.zoom_by(&mut m, -20);
        assert_eq!(m.zoom, 2);
    }
}
