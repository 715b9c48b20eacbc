//! The viewer's look: a dark theme tuned for judging images (neutral greys that do not tint
//! what is next to them, one accent colour), the colours that identify compared techniques A
//! to D and the reference everywhere they appear (tile labels, magnifier panes, plot lines),
//! and small shared widgets and number formats.

use egui::{Color32, CornerRadius, FontId, RichText, Stroke};

/// Accent colour (selection, active buttons).
pub const ACCENT: Color32 = Color32::from_rgb(0x4a, 0x9e, 0xff);
/// Colours of compared techniques A, B, C, D.
pub const SLOT_COLORS: [Color32; 4] = [
    Color32::from_rgb(0xff, 0xa6, 0x2b),
    Color32::from_rgb(0x3d, 0xd6, 0xd0),
    Color32::from_rgb(0x9b, 0xe5, 0x64),
    Color32::from_rgb(0xe0, 0x7b, 0xf0),
];
/// Colour of the reference.
pub const REFERENCE_COLOR: Color32 = Color32::from_rgb(0xe8, 0xe8, 0xe8);
/// Letter of the reference.
pub const REFERENCE_LETTER: &str = "R";
/// Letters of compared techniques.
pub const SLOT_LETTERS: [&str; 4] = ["A", "B", "C", "D"];
/// Background of the panels: the colour the window is cleared to (filled once, by
/// [`super::blit::fill`], where the renderer does not clear to it), so egui's panels themselves
/// are transparent.
pub const PANEL_FILL: Color32 = Color32::from_gray(30);
/// Background behind images (neutral, darker than the panels).
pub const VIEWPORT_BG: Color32 = Color32::from_gray(18);
/// Text that warns (stale figures, unavailable techniques).
pub const WARN: Color32 = Color32::from_rgb(0xf0, 0xb4, 0x3c);
/// Text of errors.
pub const ERROR: Color32 = Color32::from_rgb(0xff, 0x6b, 0x5e);

/// Applies the theme to every style of the context.
pub fn apply(ctx: &egui::Context) {
    ctx.set_theme(egui::Theme::Dark);
    ctx.all_styles_mut(|style| {
        let v = &mut style.visuals;
        v.panel_fill = Color32::TRANSPARENT;
        v.window_fill = Color32::from_gray(34);
        v.extreme_bg_color = Color32::from_gray(20);
        v.faint_bg_color = Color32::from_gray(36);
        v.selection.bg_fill = ACCENT.gamma_multiply(0.55);
        v.selection.stroke = Stroke::new(1.0, ACCENT);
        v.hyperlink_color = ACCENT;
        v.warn_fg_color = WARN;
        v.error_fg_color = ERROR;
        v.window_corner_radius = CornerRadius::same(6);
        v.menu_corner_radius = CornerRadius::same(4);
        v.widgets.noninteractive.bg_stroke = Stroke::new(1.0, Color32::from_gray(46));
        v.widgets.inactive.corner_radius = CornerRadius::same(3);
        v.widgets.hovered.corner_radius = CornerRadius::same(3);
        v.widgets.active.corner_radius = CornerRadius::same(3);
        v.slider_trailing_fill = true;
        v.striped = true;
        let s = &mut style.spacing;
        s.item_spacing = egui::vec2(6.0, 5.0);
        s.button_padding = egui::vec2(7.0, 3.0);
        s.slider_width = 120.0;
        s.combo_width = 120.0;
        style.interaction.tooltip_delay = 0.35;
    });
}

/// A small caps-like section title.
pub fn section(ui: &mut egui::Ui, title: &str) {
    ui.add_space(4.0);
    ui.label(
        RichText::new(title.to_uppercase())
            .size(11.0)
            .strong()
            .color(ui.visuals().weak_text_color()),
    );
}

/// A table of figures: a striped grid whose first row holds the column titles, weak, each with
/// its hover text when it has one; `rows` adds the rest.
pub fn figures_table<R>(
    ui: &mut egui::Ui,
    id: &str,
    columns: &[(&str, Option<&str>)],
    rows: impl FnOnce(&mut egui::Ui) -> R,
) -> R {
    egui::Grid::new(id)
        .num_columns(columns.len())
        .striped(true)
        .spacing([10.0, 3.0])
        .show(ui, |ui| {
            for &(title, tip) in columns {
                let title = ui.weak(title);
                if let Some(tip) = tip {
                    title.on_hover_text(tip);
                }
            }
            ui.end_row();
            rows(ui)
        })
        .inner
}

/// The left side panel: the techniques, or the images in their place, at the same size.
pub fn left_panel(id: &'static str) -> egui::Panel {
    egui::Panel::left(id)
        .resizable(true)
        .default_size(300.0)
        .size_range(240.0..=480.0)
}

/// Outlines `rect` in black, then in white one pixel further out, so that it shows on any
/// image (the lens in the viewport, the pixel under the pointer in the magnifier).
pub fn outline(painter: &egui::Painter, rect: egui::Rect) {
    for (rect, color) in [(rect, Color32::BLACK), (rect.expand(1.0), Color32::WHITE)] {
        painter.rect_stroke(
            rect,
            0.0,
            Stroke::new(1.0, color),
            egui::StrokeKind::Outside,
        );
    }
}

/// The letter and colour of compared slot `slot` (A to D), or the reference's (R, neutral)
/// for what is no compared slot: `None`, such as the reference of an image set of five.
pub fn slot_mark(slot: Option<usize>) -> (&'static str, Color32) {
    slot.and_then(|s| Some((*SLOT_LETTERS.get(s)?, *SLOT_COLORS.get(s)?)))
        .unwrap_or((REFERENCE_LETTER, REFERENCE_COLOR))
}

/// A coloured letter badge (A, B, C, D, R) as text.
pub fn badge(letter: &str, color: Color32) -> RichText {
    RichText::new(format!(" {letter} "))
        .font(FontId::monospace(11.0))
        .strong()
        .color(Color32::BLACK)
        .background_color(color)
}

/// A table row's first cell: a pane's badge (`mark`: letter and colour, [`badge`]) and the
/// name beside it; the name's response, for a tooltip.
pub fn marked_name(
    ui: &mut egui::Ui,
    (letter, color): (&str, Color32),
    name: impl Into<egui::WidgetText>,
) -> egui::Response {
    ui.horizontal(|ui| {
        ui.label(badge(letter, color));
        ui.label(name)
    })
    .inner
}

/// Paints a label chip (coloured letter, then text) with its top-left corner at `at`, over a
/// dark translucent backing so it reads on any image; returns its rectangle.
pub fn chip(
    painter: &egui::Painter,
    at: egui::Pos2,
    letter: &str,
    color: Color32,
    text: &str,
) -> egui::Rect {
    let font = FontId::proportional(12.5);
    let letter_galley =
        painter.layout_no_wrap(letter.to_owned(), FontId::monospace(12.0), Color32::BLACK);
    let text_galley = painter.layout_no_wrap(text.to_owned(), font, Color32::from_gray(235));
    let pad = egui::vec2(6.0, 3.0);
    let letter_w = letter_galley.size().x + 8.0;
    let height = text_galley.size().y.max(letter_galley.size().y) + 2.0 * pad.y;
    let rect = egui::Rect::from_min_size(
        at,
        egui::vec2(letter_w + text_galley.size().x + 2.0 * pad.x, height),
    );
    painter.rect_filled(rect, CornerRadius::same(3), Color32::from_black_alpha(170));
    let letter_rect = egui::Rect::from_min_size(at, egui::vec2(letter_w, height));
    painter.rect_filled(letter_rect, CornerRadius::same(3), color);
    painter.galley(
        letter_rect.center() - letter_galley.size() * 0.5,
        letter_galley,
        Color32::BLACK,
    );
    painter.galley(
        egui::pos2(
            letter_rect.max.x + pad.x,
            rect.center().y - text_galley.size().y * 0.5,
        ),
        text_galley,
        Color32::from_gray(235),
    );
    rect
}

/// Adds widgets in a scope whose ids come from `key` alone, not from the widgets before it.
///
/// egui numbers a widget after the ones added before it in the same `Ui` (`push_id` too: its
/// scope is numbered the same way). Where a widget before a button comes and goes between frames
/// (a warning, figures that arrive), the button's id changes, and a click sent to it by id in one
/// frame (as assistive technology and the UI tests do) misses it in the next. `key` must be
/// unique among the widgets shown in a frame.
pub fn keyed<R>(ui: &mut egui::Ui, key: egui::Id, add: impl FnOnce(&mut egui::Ui) -> R) -> R {
    ui.scope_builder(egui::UiBuilder::new().scope_id(key), add)
        .inner
}

/// Panels whose contents keep their ids whatever panels come before them.
///
/// egui numbers a panel's contents after the panels shown before it in the frame, as it numbers
/// widgets (see [`keyed`]). A panel that comes or goes (the clip bar when a recording ends, the
/// magnifier, a sequence set's bar) would renumber every control in the panels after it.
pub trait ShowKeyed {
    /// Shows the panel with its contents in a scope keyed by `key`, which must be unique among
    /// the panels of a frame.
    fn show_keyed<R>(
        self,
        ui: &mut egui::Ui,
        key: &'static str,
        add: impl FnOnce(&mut egui::Ui) -> R,
    ) -> egui::InnerResponse<R>;
}

/// `ShowKeyed` for panel types whose `show` takes a `Ui` and the contents.
macro_rules! show_keyed_for {
    ($($panel:ty),*) => {$(
        impl ShowKeyed for $panel {
            fn show_keyed<R>(
                self,
                ui: &mut egui::Ui,
                key: &'static str,
                add: impl FnOnce(&mut egui::Ui) -> R,
            ) -> egui::InnerResponse<R> {
                self.show(ui, |ui| keyed(ui, egui::Id::unique(key), add))
            }
        }
    )*};
}

show_keyed_for!(egui::Panel, egui::CentralPanel);

/// Milliseconds with a precision that suits the size.
pub fn ms(value: f64) -> String {
    if value >= 100.0 {
        format!("{value:.0} ms")
    } else if value >= 10.0 {
        format!("{value:.1} ms")
    } else {
        format!("{value:.2} ms")
    }
}

/// Bytes as MiB.
pub fn mib(bytes: u64) -> String {
    format!("{:.1} MiB", bytes as f64 / (1024.0 * 1024.0))
}

/// Bytes as whole MiB, for estimates and budgets.
pub fn whole_mib(bytes: u64) -> String {
    format!("{:.0} MiB", bytes as f64 / (1024.0 * 1024.0))
}

/// A right-aligned monospace number cell with a tooltip.
pub(super) fn number(ui: &mut egui::Ui, text: String, tip: &str) {
    ui.with_layout(egui::Layout::right_to_left(egui::Align::Center), |ui| {
        ui.label(RichText::new(text).monospace()).on_hover_text(tip);
    });
}

/// A right-aligned greyed cell standing for a missing number, with why as its tooltip.
pub(super) fn number_weak(ui: &mut egui::Ui, text: &str, tip: &str) {
    ui.with_layout(egui::Layout::right_to_left(egui::Align::Center), |ui| {
        ui.label(RichText::new(text).monospace().weak())
            .on_hover_text(tip);
    });
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn number_formats() {
        assert_eq!(ms(0.1234), "0.12 ms");
        assert_eq!(ms(12.34), "12.3 ms");
        assert_eq!(ms(1234.0), "1234 ms");
        assert_eq!(mib(3 * 1024 * 1024 / 2), "1.5 MiB");
        assert_eq!(whole_mib(3 * 1024 * 1024 / 2), "2 MiB");
    }

    #[test]
    fn slots_have_their_letters_and_anything_else_is_the_reference() {
        assert_eq!(slot_mark(Some(0)), ("A", SLOT_COLORS[0]));
        assert_eq!(slot_mark(Some(3)), ("D", SLOT_COLORS[3]));
        for other in [None, Some(4), Some(usize::MAX)] {
            assert_eq!(slot_mark(other), (REFERENCE_LETTER, REFERENCE_COLOR));
        }
    }

    #[test]
    fn a_keyed_button_keeps_its_id_whatever_comes_before_it() {
        let ctx = egui::Context::default();
        // The ids of a plain button and a keyed one after `preceding` labels.
        let ids = |preceding: usize| {
            let mut ids = None;
            let _ = ctx.run_ui(egui::RawInput::default(), |ui| {
                for n in 0..preceding {
                    ui.label(format!("warning {n}"));
                }
                let plain = ui.button("Discard").id;
                let keyed = keyed(ui, egui::Id::unique("keyed test"), |ui| {
                    ui.button("Export").id
                });
                ids = Some((plain, keyed));
            });
            ids.expect("the buttons were added")
        };
        let (before, after) = (ids(0), ids(2));
        assert_ne!(
            before.0, after.0,
            "the plain button is numbered after the labels"
        );
        assert_eq!(before.1, after.1);
    }

    #[test]
    fn a_keyed_panel_keeps_its_contents_ids_whatever_panels_come_before_it() {
        let ctx = egui::Context::default();
        // The ids of a button in a plain panel and in a keyed one, with or without a bar
        // shown before them.
        let ids = |with_bar: bool| {
            let mut ids = None;
            let _ = ctx.run_ui(egui::RawInput::default(), |ui| {
                if with_bar {
                    egui::Panel::bottom("bar").show(ui, |ui| ui.label("clip"));
                }
                let plain = egui::Panel::left("plain")
                    .show(ui, |ui| ui.button("Run").id)
                    .inner;
                let keyed = egui::Panel::right("keyed")
                    .show_keyed(ui, "keyed panel test", |ui| ui.button("Copy").id)
                    .inner;
                ids = Some((plain, keyed));
            });
            ids.expect("the panels were shown")
        };
        let (before, after) = (ids(false), ids(true));
        assert_ne!(
            before.0, after.0,
            "the plain panel is numbered after the bar"
        );
        assert_eq!(before.1, after.1);
    }
}
