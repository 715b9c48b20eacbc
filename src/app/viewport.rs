//! The central viewport: the compared techniques' images at exactly 1:1 physical pixels in
//! the four layouts (single, wipe, A/B flip, 2x2 grid), the magnifier lens drawn over them,
//! and the mouse: orbit, pan and zoom the camera, drag the lens or the wipe divider.
//!
//! Images are drawn with nearest sampling at integer physical-pixel positions and their own
//! size, never scaled: in "fit" mode the render size is the tile's physical
//! size, so each image fills its tile exactly; with a fixed resolution the image is centred
//! and cropped. The render size decided here is used by the next frame's render; while it
//! differs from the displayed image (a resize in progress) frames keep coming.
//!
//! [`ViewportPanel`] owns what only the viewport uses between frames (the drag in progress,
//! the pixel under the pointer, where image A was drawn); the render size it decides is the
//! context's (`Context::render_size`), and so is the lens it draws and moves.

use egui::{Color32, CursorIcon, Pos2, Rect, Sense, Stroke, Vec2, pos2, vec2};

use super::blit;
use super::context::Context;
use super::engine::Published;
use super::settings::{Layout, Resolution};
use super::style::{self, REFERENCE_COLOR, SLOT_COLORS, ShowKeyed, VIEWPORT_BG};

/// Gap between grid tiles, in points.
const GRID_GAP: f32 = 2.0;
/// How close (points) the pointer must be to grab the wipe divider.
const DIVIDER_GRAB: f32 = 6.0;

/// What a drag started on.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Drag {
    /// Orbit or pan the camera.
    Camera,
    /// Move the lens; the offset from the lens centre to the pointer in frame pixels.
    Lens(Vec2),
    /// Move the wipe divider.
    Wipe,
}

/// The viewport panel and what it keeps between frames. The size the techniques render at,
/// which its layout decides, is the context's (`Context::render_size`).
#[derive(Debug, Default)]
pub(super) struct ViewportPanel {
    /// The render size changed in the last layout (the next frame renders at the new size).
    resized: bool,
    /// The frame pixel under the pointer.
    hover_pixel: Option<(u32, u32)>,
    /// Where the first tile's image was drawn (screen points), clipped to its tile.
    image_rect: Option<Rect>,
    drag: Option<Drag>,
}

/// Which image a tile shows.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Shown {
    /// A compared technique: its slot (0 = A) and id.
    Technique(usize, &'static str),
    /// The reference.
    Reference,
}

/// A tile of the viewport and where frame pixel (0, 0) lands in it.
#[derive(Clone, Copy, Debug)]
struct Tile {
    rect: Rect,
    origin: Pos2,
}

impl Tile {
    /// Where an image of `size` points is drawn: centred, clipped by the tile.
    fn image_rect(self, size: Vec2) -> Rect {
        Rect::from_min_size(self.origin, size).intersect(self.rect)
    }

    fn to_screen(self, ppp: f32, frame: Vec2) -> Pos2 {
        self.origin + frame / ppp
    }

    fn to_frame(self, ppp: f32, screen: Pos2) -> Vec2 {
        (screen - self.origin) * ppp
    }
}

/// Snaps a point to the physical pixel grid.
fn snap(p: Pos2, ppp: f32) -> Pos2 {
    pos2((p.x * ppp).round() / ppp, (p.y * ppp).round() / ppp)
}

/// Physical pixel size of a rectangle (whole pixels inside it).
fn physical_size(rect: Rect, ppp: f32) -> (u32, u32) {
    (
        (rect.width() * ppp).floor().max(0.0) as u32,
        (rect.height() * ppp).floor().max(0.0) as u32,
    )
}

/// Tile rectangles of a layout inside the viewport rectangle.
fn tile_rects(layout: Layout, rect: Rect, ppp: f32) -> Vec<Rect> {
    match layout {
        Layout::Grid => {
            let half = vec2(
                ((rect.width() - GRID_GAP) * 0.5 * ppp).floor() / ppp,
                ((rect.height() - GRID_GAP) * 0.5 * ppp).floor() / ppp,
            );
            let min = snap(rect.min, ppp);
            [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0), (1.0, 1.0)]
                .iter()
                .map(|(x, y)| {
                    Rect::from_min_size(
                        snap(
                            min + vec2(x * (half.x + GRID_GAP), y * (half.y + GRID_GAP)),
                            ppp,
                        ),
                        half,
                    )
                })
                .collect()
        }
        _ => vec![Rect::from_min_size(snap(rect.min, ppp), rect.size())],
    }
}

/// Paints the viewport's background over `area` except where `covered` (the images, which
/// are opaque) lies: on a software rasteriser every painted pixel costs, and the images cover
/// most of the viewport. Plain meshes, so no anti-aliasing fringe reaches into an image.
fn paint_background(painter: &egui::Painter, area: Rect, covered: &[Rect]) {
    for rect in uncovered(area, covered) {
        blit::fill(painter, rect, VIEWPORT_BG);
    }
}

/// `area` minus the union of `covered`, as disjoint rectangles (horizontal bands split at
/// every rectangle's top and bottom).
fn uncovered(area: Rect, covered: &[Rect]) -> Vec<Rect> {
    let covered: Vec<Rect> = covered
        .iter()
        .map(|r| r.intersect(area))
        .filter(|r| r.is_positive())
        .collect();
    let mut edges: Vec<f32> = covered
        .iter()
        .flat_map(|r| [r.top(), r.bottom()])
        .chain([area.top(), area.bottom()])
        .collect();
    edges.sort_by(f32::total_cmp);
    edges.dedup();
    let mut out = Vec::new();
    for band in edges.windows(2) {
        let (top, bottom) = (band[0], band[1]);
        let mut spans: Vec<(f32, f32)> = covered
            .iter()
            .filter(|r| r.top() <= top && r.bottom() >= bottom)
            .map(|r| (r.left(), r.right()))
            .collect();
        spans.sort_by(|a, b| a.0.total_cmp(&b.0));
        let mut x = area.left();
        for (left, right) in spans {
            if left > x {
                out.push(Rect::from_min_max(pos2(x, top), pos2(left, bottom)));
            }
            x = x.max(right);
        }
        if x < area.right() {
            out.push(Rect::from_min_max(pos2(x, top), pos2(area.right(), bottom)));
        }
    }
    out
}

/// The size in points an image of `size` pixels is drawn at: 1:1 physical pixels, except an
/// image of another size than the one being rendered (the previous frame after a layout change
/// or a resize, until the new one arrives), which is scaled to fit its tile so that the change
/// shows at once.
fn shown_size(size: (u32, u32), rendering: (u32, u32), tile: &Rect, ppp: f32) -> Vec2 {
    let native = vec2(size.0 as f32, size.1 as f32) / ppp;
    if size == rendering || native.x <= 0.0 || native.y <= 0.0 {
        return native;
    }
    native * (tile.width() / native.x).min(tile.height() / native.y)
}

impl ViewportPanel {
    /// Whether the render size changed in the last layout.
    pub(super) fn resized(&self) -> bool {
        self.resized
    }

    /// The frame pixel under the pointer in the last frame.
    pub(super) fn hover_pixel(&self) -> Option<(u32, u32)> {
        self.hover_pixel
    }

    /// Where technique A's image was drawn in the last frame (points).
    pub(super) fn image_rect(&self) -> Option<Rect> {
        self.image_rect
    }

    /// The central panel. See the module docs.
    pub(super) fn ui(&mut self, ui: &mut egui::Ui, cx: &mut Context) {
        profiling::function_scope!();
        // No panel fill: the background is painted around the images only (see
        // `paint_background`).
        egui::CentralPanel::default()
            .frame(egui::Frame::NONE)
            .show_keyed(ui, "viewport", |ui| {
                let rect = ui.max_rect();
                let ppp = ui.ctx().pixels_per_point();
                let tiles_rects = tile_rects(cx.settings.layout, rect, ppp);
                let clip_size = cx
                    .engine
                    .as_ref()
                    .filter(|e| e.clip_shown())
                    .and_then(|e| e.clip())
                    .map(|c| c.recipe.size);
                // Open images are shown at their own size, and a clip on screen keeps the
                // size it was recorded at (the lens is in their pixels); the live view
                // renders at the size the viewport asks for.
                let fixed = cx.images.open().map(|set| set.size()).or(clip_size);
                let wanted = match (fixed, cx.settings.resolution) {
                    (Some(size), _) => size,
                    (None, Resolution::FitViewport) => physical_size(tiles_rects[0], ppp),
                    (None, Resolution::Fixed(w, h)) => (w, h),
                };
                self.resized = wanted != cx.render_size;
                cx.render_size = wanted;
                let response = ui.interact(
                    rect,
                    ui.scope_id().with("viewport"),
                    Sense::click_and_drag(),
                );
                if cx.engine.is_none() && !cx.images.is_open() {
                    paint_background(ui.painter(), rect, &[]);
                    empty_state(ui, cx, rect, true);
                    return;
                }
                let compared = cx.compared();
                if compared.is_empty() {
                    paint_background(ui.painter(), rect, &[]);
                    empty_state(ui, cx, rect, false);
                    return;
                }
                let shown = shown_by_layout(cx, &compared, ui.ctx());
                // Where each tile's image goes.
                let placed: Vec<(Option<Shown>, Option<&Published>, Tile, Vec2)> = tiles_rects
                    .iter()
                    .enumerate()
                    .map(|(i, tile_rect)| {
                        let what = match cx.settings.layout {
                            Layout::Grid => compared.get(i).map(|id| Shown::Technique(i, id)),
                            _ => shown.first().copied(),
                        };
                        let image = what.and_then(|w| shown_image(cx, w));
                        let size = image.map_or(cx.render_size, Published::size);
                        let size_points = shown_size(size, cx.render_size, tile_rect, ppp);
                        // Centred; an image larger than its tile (fixed resolution) is cropped
                        // evenly.
                        let origin =
                            snap(tile_rect.min + (tile_rect.size() - size_points) * 0.5, ppp);
                        let tile = Tile {
                            rect: *tile_rect,
                            origin,
                        };
                        (what, image, tile, size_points)
                    })
                    .collect();
                let covered: Vec<Rect> = placed
                    .iter()
                    .filter(|(_, image, _, _)| image.is_some())
                    .map(|(_, _, tile, size)| tile.image_rect(*size))
                    .collect();
                paint_background(ui.painter(), rect, &covered);
                let mut tiles = Vec::new();
                let mut first_image = None;
                for (i, (what, image, tile, size_points)) in placed.into_iter().enumerate() {
                    let tile_rect = tile.rect;
                    let painter = ui.painter().with_clip_rect(tile_rect);
                    if cx.settings.layout == Layout::Wipe && shown.len() == 2 {
                        paint_wipe(&painter, cx, &tile, size_points, &shown, ppp);
                    } else if let (Some(what), Some(image)) = (what, image) {
                        blit::paint(
                            &painter,
                            image.texture(),
                            Rect::from_min_size(tile.origin, size_points),
                            Rect::from_min_max(pos2(0.0, 0.0), pos2(1.0, 1.0)),
                        );
                        tile_label(&painter, cx, tile_rect.min + vec2(8.0, 8.0), what);
                    } else {
                        painter.text(
                            tile_rect.center(),
                            egui::Align2::CENTER_CENTER,
                            "rendering…",
                            egui::FontId::proportional(14.0),
                            ui.visuals().weak_text_color(),
                        );
                    }
                    if cx.settings.show_magnifier {
                        paint_lens(&painter, cx, &tile, ppp);
                    }
                    if i == 0 && image.is_some() {
                        first_image = Some(tile.image_rect(size_points));
                    }
                    tiles.push(tile);
                }
                self.image_rect = first_image;
                self.input(ui, cx, &response, &tiles, ppp);
                hovered_files_overlay(ui, rect);
            });
    }

    /// Mouse and arrow keys over the viewport.
    fn input(
        &mut self,
        ui: &egui::Ui,
        cx: &mut Context,
        response: &egui::Response,
        tiles: &[Tile],
        ppp: f32,
    ) {
        let ctx = ui.ctx().clone();
        let pointer = response.hover_pos().or(response.interact_pointer_pos());
        let tile = pointer.and_then(|p| tiles.iter().find(|t| t.rect.contains(p)).copied());
        let size = cx.render_size;
        let frame_at = |t: &Tile, p: Pos2| t.to_frame(ppp, p);
        self.hover_pixel = match (tile, response.hover_pos()) {
            (Some(t), Some(p)) => {
                let f = frame_at(&t, p);
                (f.x >= 0.0 && f.y >= 0.0 && (f.x as u32) < size.0 && (f.y as u32) < size.1)
                    .then_some((f.x as u32, f.y as u32))
            }
            _ => None,
        };
        let lens = cx.lens();
        let over_lens = |f: Vec2| {
            lens.is_some_and(|r| {
                f.x >= r.x as f32
                    && f.y >= r.y as f32
                    && f.x < (r.x + r.width) as f32
                    && f.y < (r.y + r.height) as f32
            })
        };
        let divider_x = tiles.first().map(|t| {
            let visible = Rect::from_min_size(t.origin, vec2(size.0 as f32, size.1 as f32) / ppp)
                .intersect(t.rect);
            visible.left() + visible.width() * cx.settings.wipe
        });
        let near_divider = |p: Pos2| {
            cx.settings.layout == Layout::Wipe
                && divider_x.is_some_and(|x| (p.x - x).abs() <= DIVIDER_GRAB)
        };

        // Cursor shape while hovering.
        if let (Some(t), Some(p)) = (tile, response.hover_pos())
            && self.drag.is_none()
        {
            if near_divider(p) {
                ctx.set_cursor_icon(CursorIcon::ResizeHorizontal);
            } else if cx.settings.show_magnifier && over_lens(frame_at(&t, p)) {
                ctx.set_cursor_icon(CursorIcon::Grab);
            }
        }

        // Ctrl+click puts the lens under the pointer.
        if response.clicked()
            && ctx.input(|i| i.modifiers.command)
            && let (Some(t), Some(p)) = (tile, pointer)
        {
            let f = frame_at(&t, p);
            cx.settings.magnifier.center = Some([f.x, f.y]);
        }

        // Where the button went down: a drag starts only after a few pixels of movement.
        let origin = ctx.input(|i| i.pointer.press_origin()).or(pointer);
        let origin_tile = origin.and_then(|p| tiles.iter().find(|t| t.rect.contains(p)).copied());
        if response.drag_started()
            && let (Some(t), Some(p)) = (origin_tile, origin)
        {
            let f = frame_at(&t, p);
            self.drag = Some(if near_divider(p) {
                Drag::Wipe
            } else if cx.settings.show_magnifier
                && response.dragged_by(egui::PointerButton::Primary)
                && over_lens(f)
            {
                let center = lens.map_or(f, |r| {
                    vec2(
                        r.x as f32 + r.width as f32 * 0.5,
                        r.y as f32 + r.height as f32 * 0.5,
                    )
                });
                Drag::Lens(f - center)
            } else {
                Drag::Camera
            });
        }
        if response.dragged() {
            let delta = response.drag_delta();
            match (self.drag, tile, pointer) {
                (Some(Drag::Wipe), Some(t), Some(p)) => {
                    let visible =
                        Rect::from_min_size(t.origin, vec2(size.0 as f32, size.1 as f32) / ppp)
                            .intersect(t.rect);
                    if visible.width() > 0.0 {
                        cx.settings.wipe =
                            ((p.x - visible.left()) / visible.width()).clamp(0.0, 1.0);
                    }
                    ctx.set_cursor_icon(CursorIcon::ResizeHorizontal);
                }
                (Some(Drag::Lens(offset)), Some(t), Some(p)) => {
                    let f = frame_at(&t, p) - offset;
                    cx.settings.magnifier.center = Some([f.x, f.y]);
                    ctx.set_cursor_icon(CursorIcon::Grabbing);
                }
                // Images have no camera.
                (Some(Drag::Camera), _, _) if cx.images.is_open() => {}
                (Some(Drag::Camera), _, _) => {
                    if response.dragged_by(egui::PointerButton::Primary)
                        && !ctx.input(|i| i.modifiers.shift)
                    {
                        cx.camera.orbit(glam::Vec2::new(delta.x, delta.y));
                    } else {
                        let height = tiles.first().map_or(1.0, |t| t.rect.height());
                        cx.camera.pan(glam::Vec2::new(delta.x, delta.y), height);
                    }
                }
                _ => {}
            }
        }
        if response.drag_stopped() {
            self.drag = None;
        }
        if response.hovered() && !cx.images.is_open() {
            let scroll = ctx.input(|i| i.smooth_scroll_delta.y);
            if scroll != 0.0 {
                cx.camera.zoom(scroll);
            }
        }
        // During a blind comparison a plain click answers with the pane under the pointer.
        if response.clicked()
            && !ctx.input(|i| i.modifiers.command)
            && let Some(p) = pointer
        {
            let slot = match cx.settings.layout {
                Layout::Grid => tiles.iter().position(|t| t.rect.contains(p)),
                Layout::Wipe => Some(usize::from(divider_x.is_some_and(|x| p.x >= x))),
                Layout::Flip => Some(usize::from(ctx.input(|i| i.key_down(egui::Key::B)))),
                Layout::Single => Some(0),
            };
            if let Some(slot) = slot {
                cx.blind_click(slot);
            }
        }
        nudge_lens(cx, &ctx);
    }
}

/// What the single, wipe and flip layouts show (first entry) and the wipe's right side.
fn shown_by_layout(cx: &Context, compared: &[&'static str], ctx: &egui::Context) -> Vec<Shown> {
    let a = Shown::Technique(0, compared[0]);
    let b = compared.get(1).map(|id| Shown::Technique(1, id));
    match cx.settings.layout {
        Layout::Single | Layout::Grid => vec![a],
        Layout::Wipe => std::iter::once(a).chain(b).collect(),
        Layout::Flip => {
            let (hold_b, hold_r) =
                ctx.input(|i| (i.key_down(egui::Key::B), i.key_down(egui::Key::R)));
            let typing = ctx.egui_wants_keyboard_input();
            if hold_r && !typing && cx.reference_for().is_some() {
                vec![Shown::Reference]
            } else if hold_b && !typing {
                vec![b.unwrap_or(a)]
            } else {
                vec![a]
            }
        }
    }
}

fn shown_image(cx: &Context, shown: Shown) -> Option<&Published> {
    match shown {
        Shown::Technique(_, id) => cx.image_for(id),
        Shown::Reference => cx.reference_for().map(|(image, _)| image),
    }
}

fn tile_label(painter: &egui::Painter, cx: &Context, at: Pos2, shown: Shown) -> Rect {
    match shown {
        Shown::Technique(slot, id) => style::chip(
            painter,
            at,
            cx.blind.letter(slot),
            SLOT_COLORS[slot],
            &cx.shown_label(id),
        ),
        Shown::Reference => style::chip(painter, at, "R", REFERENCE_COLOR, &cx.reference_title()),
    }
}

fn paint_wipe(
    painter: &egui::Painter,
    cx: &Context,
    tile: &Tile,
    size_points: Vec2,
    shown: &[Shown],
    ppp: f32,
) {
    let image_rect = Rect::from_min_size(tile.origin, size_points);
    let visible = image_rect.intersect(tile.rect);
    let x = snap(
        pos2(visible.left() + visible.width() * cx.settings.wipe, 0.0),
        ppp,
    )
    .x;
    let uv = Rect::from_min_max(pos2(0.0, 0.0), pos2(1.0, 1.0));
    for (side, what) in shown.iter().enumerate() {
        let Some(image) = shown_image(cx, *what) else {
            continue;
        };
        let clip = if side == 0 {
            Rect::from_min_max(tile.rect.min, pos2(x, tile.rect.max.y))
        } else {
            Rect::from_min_max(pos2(x, tile.rect.min.y), tile.rect.max)
        };
        blit::paint(
            &painter.with_clip_rect(clip.intersect(tile.rect)),
            image.texture(),
            image_rect,
            uv,
        );
    }
    let top = pos2(x, visible.top());
    let bottom = pos2(x, visible.bottom());
    painter.line_segment(
        [top, bottom],
        Stroke::new(1.0, Color32::from_white_alpha(200)),
    );
    let handle = pos2(x, visible.center().y);
    painter.circle_filled(handle, 11.0, Color32::from_black_alpha(190));
    painter.circle_stroke(
        handle,
        11.0,
        Stroke::new(1.0, Color32::from_white_alpha(200)),
    );
    for dir in [-1.0f32, 1.0] {
        let tip = handle + vec2(dir * 7.0, 0.0);
        let base = handle + vec2(dir * 2.0, 0.0);
        painter.add(egui::Shape::convex_polygon(
            vec![tip, base + vec2(0.0, -4.0), base + vec2(0.0, 4.0)],
            Color32::WHITE,
            Stroke::NONE,
        ));
    }
    tile_label(painter, cx, tile.rect.min + vec2(8.0, 8.0), shown[0]);
    let label_width = 8.0
        + painter
            .layout_no_wrap(
                cx.shown_label(match shown[1] {
                    Shown::Technique(_, id) => id,
                    Shown::Reference => "reference",
                }),
                egui::FontId::proportional(12.5),
                Color32::WHITE,
            )
            .size()
            .x
        + 40.0;
    tile_label(
        painter,
        cx,
        pos2(tile.rect.max.x - label_width, tile.rect.min.y + 8.0),
        shown[1],
    );
}

/// The lens outline over a tile.
fn paint_lens(painter: &egui::Painter, cx: &Context, tile: &Tile, ppp: f32) {
    let Some(region) = cx.lens() else {
        return;
    };
    let min = tile.to_screen(ppp, vec2(region.x as f32, region.y as f32));
    let max = tile.to_screen(
        ppp,
        vec2(
            (region.x + region.width) as f32,
            (region.y + region.height) as f32,
        ),
    );
    let rect = Rect::from_min_max(min, max);
    style::outline(painter, rect);
    painter.text(
        pos2(rect.min.x, rect.min.y - 4.0),
        egui::Align2::LEFT_BOTTOM,
        format!("×{}", cx.settings.magnifier.zoom),
        egui::FontId::monospace(10.0),
        Color32::WHITE,
    );
}

fn empty_state(ui: &egui::Ui, cx: &Context, rect: Rect, loading: bool) {
    let text = if loading {
        match cx.loader.loading() {
            Some(spec) => format!("Loading {spec}…"),
            None => "No scene loaded: open one from the File menu".to_owned(),
        }
    } else {
        "No technique is on: switch one on in the left panel (keys 1 … 9)".to_owned()
    };
    ui.painter().text(
        rect.center(),
        egui::Align2::CENTER_CENTER,
        text,
        egui::FontId::proportional(16.0),
        ui.visuals().weak_text_color(),
    );
}

fn hovered_files_overlay(ui: &egui::Ui, rect: Rect) {
    let hovering = ui.ctx().input(|i| !i.raw.hovered_files.is_empty());
    if hovering {
        let painter = ui.painter();
        painter.rect_filled(rect, 0.0, Color32::from_black_alpha(160));
        painter.text(
            rect.center(),
            egui::Align2::CENTER_CENTER,
            "Drop an OBJ, glTF or GLB file, or up to five PNG/JPEG images",
            egui::FontId::proportional(22.0),
            Color32::WHITE,
        );
    }
}

/// Arrow keys move the lens by one frame pixel (ten with Shift).
fn nudge_lens(cx: &mut Context, ctx: &egui::Context) {
    if ctx.egui_wants_keyboard_input() || !cx.settings.show_magnifier {
        return;
    }
    let (dx, dy, shift) = ctx.input(|i| {
        let d = |neg: egui::Key, pos: egui::Key| {
            f32::from(u8::from(i.key_pressed(pos))) - f32::from(u8::from(i.key_pressed(neg)))
        };
        (
            d(egui::Key::ArrowLeft, egui::Key::ArrowRight),
            d(egui::Key::ArrowUp, egui::Key::ArrowDown),
            i.modifiers.shift,
        )
    });
    if dx == 0.0 && dy == 0.0 {
        return;
    }
    let step = if shift { 10.0 } else { 1.0 };
    if let Some(region) = cx.lens() {
        let x = region.x as f32 + region.width as f32 * 0.5 + dx * step;
        let y = region.y as f32 + region.height as f32 * 0.5 + dy * step;
        cx.settings.magnifier.center = Some([x, y]);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_background_covers_exactly_what_the_images_leave() {
        let area = Rect::from_min_max(pos2(0.0, 0.0), pos2(100.0, 60.0));
        let images = [
            Rect::from_min_max(pos2(10.0, 10.0), pos2(40.0, 50.0)),
            Rect::from_min_max(pos2(50.0, 0.0), pos2(100.0, 30.0)),
            // Partly outside the area.
            Rect::from_min_max(pos2(90.0, 40.0), pos2(130.0, 90.0)),
        ];
        let background = uncovered(area, &images);
        let area_of = |r: &Rect| r.width() * r.height();
        let covered: f32 = images.iter().map(|r| area_of(&r.intersect(area))).sum();
        let filled: f32 = background.iter().map(area_of).sum();
        assert_eq!(filled + covered, area_of(&area));
        for b in &background {
            assert!(area.contains_rect(*b));
            for i in &images {
                assert!(!b.intersect(*i).is_positive(), "{b:?} overlaps {i:?}");
            }
        }
        assert_eq!(uncovered(area, &[]), vec![area]);
        assert!(uncovered(area, &[area]).is_empty());
    }

    #[test]
    fn grid_tiles_are_pixel_aligned_and_disjoint() {
        let rect = Rect::from_min_size(pos2(10.3, 20.7), vec2(801.0, 451.0));
        for ppp in [1.0, 1.25, 2.0] {
            let tiles = tile_rects(Layout::Grid, rect, ppp);
            assert_eq!(tiles.len(), 4);
            for t in &tiles {
                let px = t.min * ppp;
                assert!((px.x - px.x.round()).abs() < 1e-3 && (px.y - px.y.round()).abs() < 1e-3);
                assert!(t.width() * ppp - (t.width() * ppp).round() < 1e-3);
            }
            assert!(tiles[0].right() < tiles[1].left());
            assert!(tiles[0].bottom() < tiles[2].top());
            assert_eq!(physical_size(tiles[0], ppp), physical_size(tiles[3], ppp));
        }
        assert_eq!(tile_rects(Layout::Single, rect, 1.0).len(), 1);
    }

    #[test]
    fn tile_mapping_round_trips() {
        let tile = Tile {
            rect: Rect::from_min_size(pos2(0.0, 0.0), vec2(100.0, 100.0)),
            origin: pos2(10.0, 5.0),
        };
        let p = tile.to_screen(2.0, vec2(30.0, 40.0));
        assert_eq!(p, pos2(25.0, 25.0));
        assert_eq!(tile.to_frame(2.0, p), vec2(30.0, 40.0));
    }
}
