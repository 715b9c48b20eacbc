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
//! - [`MagnifierState`], the workspace's: the lens size and the heatmaps, with the workspace's
//!   magnifier queries (the panes' sources, labels and figures, the lens, the heatmap jobs),
//!   which the viewport, exports, blind answers and the test API use as well.
//! - [`MagnifierPanel`], the panel: it sizes the lens to its panes and owns the pane pixel under
//!   the pointer; the viewport's hovered pixel is passed in for the crosshair.

use egui::{Color32, Rect, Sense, Stroke, TextureHandle, pos2, vec2};

use super::blit;
use super::difference::{self, HeatInput, HeatJob, HeatKey, HeatResult, heat_color};
use super::engine::{Published, ReferenceState};
use super::settings::{DiffMetric, MagnifierSettings};
use super::shortcuts::{Action, shortcut_hint};
use super::style::{self, REFERENCE_COLOR, SLOT_COLORS};
use super::worker::Worker;
use super::workspace::{Level, Workspace};
use crate::gpu::readback::Region;

/// The zoom factors offered.
pub const ZOOM_STEPS: [u32; 9] = [2, 3, 4, 6, 8, 12, 16, 24, 32];
/// Pixels read around the lens, so that windowed metrics see context: more than SSIM's window
/// radius (5) and FLIP's widest filter radius (10 at 67 pixels per degree).
pub const MARGIN: u32 = 12;
/// Gap between panes, in points.
const PANE_GAP: f32 = 8.0;

/// The lens rectangle in frame pixels: `side` pixels square around the saved centre (the
/// frame centre by default), moved inside the frame.
pub fn lens_region(settings: &MagnifierSettings, side: u32, size: (u32, u32)) -> Option<Region> {
    if side == 0 || size.0 == 0 || size.1 == 0 {
        return None;
    }
    let [cx, cy] = settings
        .center
        .unwrap_or([size.0 as f32 * 0.5, size.1 as f32 * 0.5]);
    let place = |c: f32, extent: u32| {
        let side = side.min(extent);
        let start = (c - side as f32 * 0.5).round().max(0.0) as u32;
        (start.min(extent - side), side)
    };
    let (x, width) = place(if cx.is_finite() { cx } else { 0.0 }, size.0);
    let (y, height) = place(if cy.is_finite() { cy } else { 0.0 }, size.1);
    Some(Region {
        x,
        y,
        width,
        height,
    })
}

/// Where a pane's pixels come from.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Source {
    /// A compared technique (slot 0 = A) by id.
    Technique(usize, &'static str),
    /// The reference.
    Reference,
}

/// The newest heatmap of a pane.
struct PaneHeat {
    source: Source,
    key: HeatKey,
    /// The texture, the lens it covers and its mean, or why there is none.
    result: Result<(TextureHandle, Region, f64), String>,
}

/// The lens size and the heatmaps, kept between frames in the workspace: the viewport draws
/// and moves the lens, exports and blind answers record it; export sheets and the test API
/// read the heatmaps, which scene and image set changes forget with the quality figures.
#[derive(Default)]
pub struct MagnifierState {
    /// Frame pixels a pane covers (decided by the pane size and the zoom).
    pub lens_side: u32,
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

/// Pixels of `region` of an image.
pub fn crop(image: &image::RgbaImage, region: Region) -> image::RgbaImage {
    image::imageops::crop_imm(image, region.x, region.y, region.width, region.height).to_image()
}

impl Workspace {
    /// The panes' sources: the compared techniques, then the reference when shown.
    pub(super) fn magnifier_sources(&self) -> Vec<Source> {
        let mut sources: Vec<Source> = self
            .compared()
            .into_iter()
            .enumerate()
            .map(|(slot, id)| Source::Technique(slot, id))
            .collect();
        if self.settings.magnifier.show_reference || self.settings.magnifier.difference {
            sources.push(Source::Reference);
        }
        sources
    }

    /// The published image of a pane (a technique's, or an image of the open set).
    pub(super) fn source_image(&self, source: Source) -> Option<&Published> {
        match source {
            Source::Technique(_, id) => self.image_for(id),
            Source::Reference => self.reference_for().map(|(image, _)| image),
        }
    }

    /// The lens region now.
    pub(super) fn lens(&self) -> Option<Region> {
        lens_region(
            &self.settings.magnifier,
            self.magnifier.lens_side,
            self.render_size,
        )
    }

    /// Takes finished heatmaps and asks for new ones when the lens, the images or the metric
    /// changed.
    pub(super) fn update_magnifier(&mut self, ctx: &egui::Context) {
        profiling::function_scope!();
        let results = self
            .magnifier
            .worker
            .as_mut()
            .map(Worker::poll)
            .unwrap_or_default();
        for result in results {
            let result_for_pane = result.heatmap.map(|heat| {
                let handle = ctx.load_texture(
                    format!("magnifier heatmap {:?}", result.source),
                    heat.colors,
                    egui::TextureOptions::NEAREST,
                );
                (handle, heat.lens, heat.mean)
            });
            self.magnifier
                .heatmaps
                .retain(|h| h.source != result.source);
            self.magnifier.heatmaps.push(PaneHeat {
                source: result.source,
                key: result.key,
                result: result_for_pane,
            });
        }
        if !self.settings.show_magnifier || !self.settings.magnifier.difference {
            return;
        }
        let Some(job) = self.heat_job() else { return };
        if self.magnifier.requested.as_ref() == Some(&job.key) {
            return;
        }
        let key = job.key.clone();
        if self.magnifier.worker.is_none() && self.magnifier.worker_error.is_none() {
            match difference::spawn_heat_worker(ctx) {
                Ok(worker) => self.magnifier.worker = Some(worker),
                Err(err) => {
                    let text = format!("no thread for the magnifier's heatmaps: {err}");
                    self.magnifier.worker_error = Some(text.clone());
                    self.notify(Level::Error, text);
                }
            }
        }
        if let Some(worker) = &mut self.magnifier.worker
            && worker.submit(job)
        {
            self.magnifier.requested = Some(key);
        }
    }

    /// The heatmaps the panes should show now: the lens, the newest images, the metric.
    fn heat_job(&self) -> Option<HeatJob> {
        let lens = self.lens()?;
        let reference = self.source_image(Source::Reference)?;
        // The images' own size: a clip keeps the size it was recorded at.
        let size = reference.size();
        let reference_pixels = reference.pixels.clone()?;
        let mut images = vec![reference.stamp.serial];
        let mut tests = Vec::new();
        let metric = self.settings.magnifier.metric;
        for source in self.magnifier_sources() {
            let Source::Technique(_, id) = source else {
                continue;
            };
            let Some(image) = self.source_image(source).filter(|i| i.size() == size) else {
                continue;
            };
            let input = if metric == DiffMetric::Instability {
                // The clip's map of the technique, whichever of its frames shows.
                match self.instability_map(id) {
                    Some(map) => HeatInput::Map(map),
                    None => HeatInput::Missing(
                        "temporal instability needs a clip recorded with the reference on screen"
                            .to_owned(),
                    ),
                }
            } else {
                let Some(pixels) = &image.pixels else {
                    continue;
                };
                HeatInput::Image(std::sync::Arc::clone(pixels))
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
                metric: self.settings.magnifier.metric,
            },
            reference: reference_pixels,
            tests,
        })
    }

    /// In difference mode, once every technique pane shows the heatmap of the current lens,
    /// images and metric: the lens means of the panes' maps, in pane order (SSIM itself for
    /// the SSIM map).
    pub(super) fn difference_means(&self) -> Option<Vec<f64>> {
        let job = self.heat_job()?;
        job.key
            .sources
            .iter()
            .map(|source| {
                let heat = self
                    .magnifier
                    .heatmaps
                    .iter()
                    .find(|h| h.source == *source)?;
                match &heat.result {
                    Ok((_, _, mean)) if heat.key == job.key => Some(*mean),
                    _ => None,
                }
            })
            .collect()
    }

    /// The heatmap of a pane when it shows the displayed view with the selected metric.
    fn pane_heat(&self, source: Source) -> Option<&PaneHeat> {
        let view = self.current_view()?;
        self.magnifier.heatmaps.iter().find(|h| {
            h.source == source
                && h.key.view == view
                && h.key.metric == self.settings.magnifier.metric
        })
    }

    /// Letter, colour and name of a pane.
    pub(super) fn source_label(&self, source: Source) -> (&'static str, Color32, String) {
        match source {
            Source::Technique(slot, id) => (
                self.blind.letter(slot),
                SLOT_COLORS[slot],
                self.shown_label(id),
            ),
            Source::Reference => ("R", REFERENCE_COLOR, self.reference_title()),
        }
    }

    /// The figures under a pane: quality against the reference (or the region's mean error in
    /// difference mode).
    pub(super) fn pane_figures(&self, source: Source) -> String {
        match source {
            Source::Reference if self.images.is_open() => "reference image".to_owned(),
            Source::Reference => match self.reference_state_for() {
                Some(ReferenceState::Ready(p)) if p.complete() => "converged".to_owned(),
                Some(ReferenceState::Ready(p)) => format!("accumulating {}/{}", p.samples, p.total),
                _ => "waiting for a still camera".to_owned(),
            },
            // Figures would tell the techniques apart.
            Source::Technique(..) if self.blind.active() => String::new(),
            Source::Technique(_, id) => {
                let mut parts = Vec::new();
                let lens = self.lens();
                if self.settings.magnifier.difference
                    && let Some(PaneHeat {
                        result: Ok((_, at, mean)),
                        ..
                    }) = self.pane_heat(source)
                    && Some(*at) == lens
                {
                    parts.push(self.settings.magnifier.metric.mean_text(*mean));
                }
                if let Some(figures) = self.figures_text(id) {
                    parts.push(figures);
                }
                if self.is_reference_image(id) {
                    parts.push("reference image".to_owned());
                }
                parts.join(" · ")
            }
        }
    }
}

/// The magnifier panel; the lens size it decides and the heatmaps are the workspace's
/// ([`MagnifierState`]).
#[derive(Default)]
pub(super) struct MagnifierPanel {
    /// The frame pixel under the pointer in a pane.
    hover: Option<(u32, u32)>,
}

impl MagnifierPanel {
    /// The frame pixel under the pointer in a pane, in the last frame.
    pub(super) fn hover(&self) -> Option<(u32, u32)> {
        self.hover
    }

    /// The magnifier panel (bottom of the window).
    pub(super) fn ui(
        &mut self,
        ui: &mut egui::Ui,
        ws: &mut Workspace,
        viewport_hover: Option<(u32, u32)>,
    ) {
        profiling::function_scope!();
        egui::Panel::bottom("magnifier")
            .resizable(true)
            .default_size(330.0)
            .size_range(180.0..=700.0)
            .frame(
                egui::Frame::side_top_panel(ui.style())
                    .inner_margin(egui::Margin::symmetric(10, 6)),
            )
            .show(ui, |ui| {
                // Keep the panel at its set height (panels otherwise shrink to their content).
                ui.set_min_height(ui.available_height());
                header(ui, ws);
                ui.add_space(4.0);
                self.panes(ui, ws, viewport_hover);
            });
    }

    fn panes(&mut self, ui: &mut egui::Ui, ws: &mut Workspace, viewport_hover: Option<(u32, u32)>) {
        let ppp = ui.ctx().pixels_per_point();
        let sources = ws.magnifier_sources();
        let zoom = ws.settings.magnifier.zoom.max(1);
        let caption_height = 42.0;
        let n = sources.len().max(1) as f32;
        let avail = ui.available_size();
        let side_points = ((avail.x - PANE_GAP * (n - 1.0)) / n)
            .min(avail.y - caption_height)
            .max(16.0);
        let side_px = (side_points * ppp).floor() as u32;
        ws.magnifier.lens_side = (side_px / zoom).max(1);
        let Some(lens) = ws.lens() else {
            ui.weak("The lens appears once the first frame is rendered.");
            return;
        };
        let size = ws.render_size;
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
                    paint_pane(ui, ws, *source, rect, lens, size);
                    pane_caption(ui, ws, *source, pane_points.x);
                });
            }
        });
        self.hover = hover;
        if let Some(slot) = clicked {
            ws.blind_click(slot);
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
            pixel_readout(ui, ws, (x, y), &sources);
        } else {
            ui.weak("Point at a pane (or at the lens in the view) to read pixel values.");
        }
    }
}

fn header(ui: &mut egui::Ui, ws: &mut Workspace) {
    let ctx = ui.ctx().clone();
    ui.horizontal(|ui| {
            ui.strong("Magnifier");
            ui.separator();
            let m = &mut ws.settings.magnifier;
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
            if let Some(lens) = ws.lens() {
                ui.separator();
                ui.weak(format!(
                    "lens {}×{} at ({}, {})",
                    lens.width, lens.height, lens.x, lens.y
                ))
                .on_hover_text("Drag the white rectangle in the view, Ctrl+click to place it, or nudge it with the arrow keys.");
            }
            ui.with_layout(egui::Layout::right_to_left(egui::Align::Center), |ui| {
                if ui
                    .button("Copy sheet")
                    .on_hover_text(shortcut_hint(&ctx, Action::CopySheet, "Copy the magnifier sheet (all panes with labels and metrics) to the clipboard"))
                    .clicked()
                {
                    ws.copy_sheet(&ctx);
                }
            });
        });
}

fn paint_pane(
    ui: &egui::Ui,
    ws: &Workspace,
    source: Source,
    rect: Rect,
    lens: Region,
    size: (u32, u32),
) {
    let painter = ui.painter().with_clip_rect(rect);
    blit::fill(&painter, rect, Color32::from_gray(12));
    let ppp = ui.ctx().pixels_per_point();
    let zoom = ws.settings.magnifier.zoom.max(1);
    let difference = ws.settings.magnifier.difference && source != Source::Reference;
    if difference {
        let heat = ws.pane_heat(source).map(|h| &h.result);
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
                let text = match ws.reference_state_for() {
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
    } else if let Some(image) = ws.source_image(source).filter(|i| i.size() == size) {
        let uv = Rect::from_min_max(
            pos2(lens.x as f32 / size.0 as f32, lens.y as f32 / size.1 as f32),
            pos2(
                (lens.x + lens.width) as f32 / size.0 as f32,
                (lens.y + lens.height) as f32 / size.1 as f32,
            ),
        );
        let grid = ws.settings.magnifier.pixel_grid && zoom >= 4;
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
    if difference && ws.settings.magnifier.pixel_grid && zoom >= 4 {
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
    let (letter, color, name) = ws.source_label(source);
    style::chip(&painter, rect.min + vec2(6.0, 6.0), letter, color, &name);
}

fn pane_caption(ui: &mut egui::Ui, ws: &Workspace, source: Source, width: f32) {
    ui.set_max_width(width);
    let text = ws.pane_figures(source);
    ui.add(egui::Label::new(egui::RichText::new(text).small().monospace()).wrap());
}

fn pixel_readout(ui: &mut egui::Ui, ws: &Workspace, (x, y): (u32, u32), sources: &[Source]) {
    ui.horizontal_wrapped(|ui| {
        ui.monospace(format!("({x}, {y})"));
        for source in sources {
            let (letter, color, _) = ws.source_label(*source);
            ui.label(style::badge(letter, color));
            let pixel = ws
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
    fn lens_stays_inside_the_frame() {
        let mut m = MagnifierSettings::default();
        let r = lens_region(&m, 32, (100, 50)).unwrap();
        assert_eq!((r.x, r.y, r.width, r.height), (34, 9, 32, 32));
        m.center = Some([-50.0, 1000.0]);
        let r = lens_region(&m, 32, (100, 50)).unwrap();
        assert_eq!((r.x, r.y), (0, 18));
        let r = lens_region(&m, 80, (100, 50)).unwrap();
        assert_eq!((r.width, r.height), (80, 50));
        assert!(lens_region(&m, 0, (100, 50)).is_none());
        m.center = Some([f32::NAN, 3.0]);
        assert!(lens_region(&m, 8, (100, 50)).is_some());
    }

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
