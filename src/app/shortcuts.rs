//! Keyboard shortcuts: one table ([`SHORTCUTS`]) drives both the key handling and the help
//! overlay, so the overlay can never list a key that does nothing. Keys that act while held
//! (flip to B or to the reference) and the lens nudges are listed in the same overlay.

use std::sync::Arc;

use egui::{Key, KeyboardShortcut, Modifiers};

use super::blind::DIGIT_KEYS;
use super::key_events::take_press;
use super::settings::Layout;
use super::{blit, style};

/// Something a shortcut does.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Action {
    /// Switch the n-th technique of the panel (0-based) on or off.
    ToggleTechnique(usize),
    /// Pause or resume time.
    PlayPause,
    /// Advance one frame (while paused).
    Step,
    /// Auto-rotation on or off.
    AutoRotate,
    /// Back to the scene's camera.
    ResetView,
    /// Switch between the orbit and the fly camera.
    FlyMode,
    /// Save the camera as a bookmark.
    AddBookmark,
    /// Go to bookmark n (0-based).
    GoToBookmark(usize),
    /// Switch layout.
    Layout(Layout),
    /// Magnifier zoom in.
    ZoomIn,
    /// Magnifier zoom out.
    ZoomOut,
    /// Pixel grid in the magnifier.
    PixelGrid,
    /// Difference mode in the magnifier.
    Difference,
    /// Export everything.
    Export,
    /// Copy the magnifier sheet to the clipboard.
    CopySheet,
    /// Open a model file (OBJ, glTF, GLB).
    Open,
    /// Hide or show the side panels.
    TogglePanels,
    /// Show or hide this help.
    Help,
}

/// A key, its modifiers, what it does and how the help names it.
pub struct Shortcut {
    /// The key combination.
    pub shortcut: KeyboardShortcut,
    /// The action.
    pub action: Action,
    /// Help text.
    pub help: &'static str,
}

const fn plain(key: Key, action: Action, help: &'static str) -> Shortcut {
    Shortcut {
        shortcut: KeyboardShortcut::new(Modifiers::NONE, key),
        action,
        help,
    }
}

const fn command(key: Key, action: Action, help: &'static str) -> Shortcut {
    Shortcut {
        shortcut: KeyboardShortcut::new(Modifiers::COMMAND, key),
        action,
        help,
    }
}

const BOOKMARK_KEYS: [Key; 4] = [Key::F5, Key::F6, Key::F7, Key::F8];

/// Every single-press shortcut except the number and bookmark keys, which
/// [`pressed_actions`] handles from [`DIGIT_KEYS`] and [`BOOKMARK_KEYS`].
pub const SHORTCUTS: &[Shortcut] = &[
    plain(Key::Space, Action::PlayPause, "Pause / resume time"),
    plain(Key::Period, Action::Step, "Step one frame"),
    plain(
        Key::A,
        Action::AutoRotate,
        "Auto-rotate (the thesis' camera path) on / off",
    ),
    plain(Key::Home, Action::ResetView, "Reset the view"),
    plain(
        Key::C,
        Action::FlyMode,
        "Fly camera (interiors) / orbit camera",
    ),
    command(Key::D, Action::AddBookmark, "Bookmark the camera"),
    plain(Key::S, Action::Layout(Layout::Single), "Single view"),
    plain(Key::W, Action::Layout(Layout::Wipe), "Wipe between A and B"),
    plain(Key::F, Action::Layout(Layout::Flip), "A/B flip"),
    plain(Key::G, Action::Layout(Layout::Grid), "2x2 grid"),
    plain(Key::CloseBracket, Action::ZoomIn, "Magnifier zoom in"),
    plain(Key::OpenBracket, Action::ZoomOut, "Magnifier zoom out"),
    plain(Key::P, Action::PixelGrid, "Magnifier pixel grid"),
    plain(
        Key::D,
        Action::Difference,
        "Magnifier difference mode (error against the reference)",
    ),
    plain(
        Key::F12,
        Action::Export,
        "Export frames, magnifier sheet and sidecar",
    ),
    Shortcut {
        shortcut: KeyboardShortcut::new(Modifiers::COMMAND.plus(Modifiers::SHIFT), Key::C),
        action: Action::CopySheet,
        help: "Copy the magnifier sheet to the clipboard",
    },
    command(Key::O, Action::Open, "Open a model (OBJ, glTF, GLB)"),
    plain(
        Key::Tab,
        Action::TogglePanels,
        "Hide / show the side panels",
    ),
    plain(Key::F1, Action::Help, "This help"),
    plain(Key::Questionmark, Action::Help, "This help"),
];

/// Keys that act while held or that the table above does not list, for the help overlay.
pub const OTHER_KEYS: &[(&str, &str)] = &[
    ("1 … 9", "Switch the n-th technique of the panel on / off"),
    ("F5 … F8", "Go to camera bookmark 1 … 4"),
    ("hold B", "A/B flip: show technique B"),
    ("hold R", "A/B flip: show the reference"),
    ("arrows", "Move the magnifier lens one pixel (Shift: ten)"),
    (
        "drag",
        "Orbit; fly camera: look around (on the lens: move the lens)",
    ),
    (
        "W A S D / Q E",
        "Fly camera: move / down, up (Shift: fast); these keys' shortcuts pause while flying",
    ),
    ("right / middle drag", "Pan"),
    ("wheel", "Zoom the camera"),
    ("Ctrl + click", "Put the lens here"),
    ("Esc", "Close this help"),
];

/// Keys that move the fly camera; their shortcuts do not fire while it is on.
pub const FLY_KEYS: [Key; 6] = [Key::W, Key::A, Key::S, Key::D, Key::Q, Key::E];

/// The fly movement the held keys ask for (nothing while a text field has focus).
pub fn fly_input(ctx: &egui::Context) -> super::camera::FlyInput {
    if ctx.egui_wants_keyboard_input() {
        return super::camera::FlyInput::default();
    }
    ctx.input(|i| {
        let axis = |neg: Key, pos: Key| {
            f32::from(u8::from(i.key_down(pos))) - f32::from(u8::from(i.key_down(neg)))
        };
        super::camera::FlyInput {
            right: axis(Key::A, Key::D),
            up: axis(Key::Q, Key::E),
            forward: axis(Key::S, Key::W),
            fast: i.modifiers.shift,
        }
    })
}

/// Takes the presses of the single-press shortcuts out of `events` (so egui widgets do not see
/// them) and returns their actions, in the table's order. With `flying`, the plain shortcuts on
/// [`FLY_KEYS`] are left to the fly camera. The caller checks first that no text field has
/// keyboard focus.
pub fn take_actions(events: &mut Vec<egui::Event>, flying: bool) -> Vec<Action> {
    let mut actions = Vec::new();
    // Longer modifier combinations first, so Ctrl+Shift+C is not taken for Ctrl+C.
    let mut table: Vec<&Shortcut> = SHORTCUTS.iter().collect();
    table.sort_by_key(|s| std::cmp::Reverse(modifier_count(s.shortcut.modifiers)));
    for entry in table {
        let fly_key = FLY_KEYS.contains(&entry.shortcut.logical_key)
            && entry.shortcut.modifiers == Modifiers::NONE;
        if flying && fly_key {
            continue;
        }
        if take_press(events, entry.shortcut.modifiers, entry.shortcut.logical_key) {
            actions.push(entry.action);
        }
    }
    for (n, key) in DIGIT_KEYS[1..].iter().enumerate() {
        if take_press(events, Modifiers::NONE, *key) {
            actions.push(Action::ToggleTechnique(n));
        }
    }
    for (n, key) in BOOKMARK_KEYS.iter().enumerate() {
        if take_press(events, Modifiers::NONE, *key) {
            actions.push(Action::GoToBookmark(n));
        }
    }
    actions
}

fn modifier_count(m: Modifiers) -> u8 {
    u8::from(m.alt)
        + u8::from(m.ctrl)
        + u8::from(m.shift)
        + u8::from(m.mac_cmd)
        + u8::from(m.command)
}

/// A key combination as people write it: egui's wording of the modifiers, and the key's own
/// character where it has a plain one (`]` rather than egui's `CloseBracket`, `?` rather than
/// `Questionmark`).
fn shortcut_text(ctx: &egui::Context, shortcut: &KeyboardShortcut) -> String {
    let text = ctx.format_shortcut(shortcut);
    let key = shortcut.logical_key;
    let symbol = key.symbol_or_name();
    match text.strip_suffix(key.name()) {
        Some(modifiers) if symbol.len() == 1 && symbol.is_ascii() => format!("{modifiers}{symbol}"),
        _ => text,
    }
}

/// How a shortcut is written in menus and the help.
pub fn label(ctx: &egui::Context, action: Action) -> Option<String> {
    SHORTCUTS
        .iter()
        .find(|s| s.action == action)
        .map(|s| shortcut_text(ctx, &s.shortcut))
}

/// A tooltip with the action's shortcut appended.
pub(super) fn shortcut_hint(ctx: &egui::Context, action: Action, text: &str) -> String {
    match label(ctx, action) {
        Some(key) => format!("{text} ({key})"),
        None => text.to_owned(),
    }
}

/// The help overlay listing every key, while `open` is set; a click anywhere, F1 or Esc
/// closes it.
///
/// It is painted, not built of widgets, into an area that is shown in every frame (empty while
/// the help is closed): egui asks for two more frames when an area becomes visible and when a
/// widget it has not seen before appears (a modal, a grid, a Close button), and on a software
/// rasteriser each of those paints took as long as the one that shows the help. Its large areas
/// are [`blit::fill`]s, which skip egui's per-pixel texture sampling (figures: `docs/viewer.md`).
/// It shows in full on the first frame after the key.
pub fn help_overlay(ctx: &egui::Context, open: &mut bool) {
    let window = ctx.content_rect();
    egui::Area::new(egui::Id::unique("aa-lab help"))
        .order(egui::Order::Foreground)
        .fixed_pos(window.min)
        .interactable(*open)
        .show(ctx, |ui| {
            if !*open {
                return;
            }
            // Covers the window, so that no click reaches the widgets under the help.
            let cover = ui.allocate_rect(window, egui::Sense::click());
            cover.widget_info(|| egui::WidgetInfo::labeled(egui::Role::Dialog, true, HELP_TITLE));
            if cover.clicked() {
                *open = false;
            }
            let painter = ui.painter();
            blit::fill(painter, window, HELP_BACKDROP);
            HelpText::lay_out(ui).paint(ui, painter, window.center());
        });
}

/// How much the help overlay darkens the window under it.
const HELP_BACKDROP: egui::Color32 = egui::Color32::from_black_alpha(100);

/// The margin around the help overlay's text (points).
const HELP_MARGIN: f32 = 14.0;

/// The help overlay's heading.
const HELP_TITLE: &str = "Keyboard and mouse";

/// The help overlay's text, laid out: a heading, a two-column table of keys and what they do,
/// and a footer.
struct HelpText {
    heading: Arc<egui::Galley>,
    rows: Vec<(Arc<egui::Galley>, Arc<egui::Galley>)>,
    footer: Arc<egui::Galley>,
    closing: Arc<egui::Galley>,
    /// Width of the key column (points).
    keys_width: f32,
}

impl HelpText {
    /// Space between the two columns, between rows and between the blocks (points).
    const COLUMN_GAP: f32 = 24.0;
    const ROW_GAP: f32 = 4.0;
    const BLOCK_GAP: f32 = 8.0;
    /// Width of the text (points).
    const WIDTH: f32 = 560.0;

    fn lay_out(ui: &egui::Ui) -> Self {
        let visuals = ui.visuals();
        let text = |text: &str, style: egui::TextStyle, color: egui::Color32| {
            ui.painter()
                .layout_no_wrap(text.to_owned(), style.resolve(ui.style()), color)
        };
        let ctx = ui.ctx();
        let mut keys: Vec<(String, &str)> = Vec::new();
        let mut seen = Vec::new();
        for s in SHORTCUTS {
            if seen.contains(&s.action) {
                continue;
            }
            seen.push(s.action);
            let combos: Vec<String> = SHORTCUTS
                .iter()
                .filter(|o| o.action == s.action)
                .map(|o| shortcut_text(ctx, &o.shortcut))
                .collect();
            keys.push((combos.join("  or  "), s.help));
        }
        keys.extend(OTHER_KEYS.iter().map(|(k, help)| ((*k).to_owned(), *help)));
        let strong = visuals.strong_text_color();
        let normal = visuals.text_color();
        let rows: Vec<_> = keys
            .iter()
            .map(|(k, help)| {
                (
                    text(k, egui::TextStyle::Monospace, strong),
                    text(help, egui::TextStyle::Body, normal),
                )
            })
            .collect();
        let keys_width = rows.iter().map(|(k, _)| k.size().x).fold(0.0, f32::max);
        let weak = visuals.weak_text_color();
        Self {
            heading: text(HELP_TITLE, egui::TextStyle::Heading, strong),
            rows,
            footer: text(
                "Every number in the metrics panel explains itself in a tooltip.",
                egui::TextStyle::Body,
                weak,
            ),
            closing: text(
                "F1, Esc or a click closes this",
                egui::TextStyle::Body,
                weak,
            ),
            keys_width,
        }
    }

    fn row_height(&self, row: &(Arc<egui::Galley>, Arc<egui::Galley>)) -> f32 {
        row.0.size().y.max(row.1.size().y)
    }

    /// The panel's size (points), margins included.
    fn size(&self) -> egui::Vec2 {
        let table: f32 = self
            .rows
            .iter()
            .map(|row| self.row_height(row) + Self::ROW_GAP)
            .sum();
        let height = self.heading.size().y
            + Self::BLOCK_GAP
            + table
            + Self::BLOCK_GAP
            + self.footer.size().y;
        let width = Self::WIDTH.max(
            self.keys_width
                + Self::COLUMN_GAP
                + self.rows.iter().map(|r| r.1.size().x).fold(0.0, f32::max),
        );
        egui::vec2(width, height) + egui::Vec2::splat(2.0 * HELP_MARGIN)
    }

    /// Paints the panel centred on `center`.
    fn paint(&self, ui: &egui::Ui, painter: &egui::Painter, center: egui::Pos2) {
        let panel = egui::emath::GuiRounding::round_to_pixels(
            egui::Rect::from_center_size(center, self.size()),
            ui.pixels_per_point(),
        );
        blit::fill(painter, panel, style::PANEL_FILL);
        let border = egui::Stroke::new(1.0, ui.visuals().window_stroke.color);
        painter.rect_stroke(panel, 0.0, border, egui::StrokeKind::Inside);
        let inner = panel.shrink(HELP_MARGIN);
        let mut y = inner.top();
        painter.galley(
            egui::pos2(inner.left(), y),
            self.heading.clone(),
            egui::Color32::PLACEHOLDER,
        );
        y += self.heading.size().y + Self::BLOCK_GAP;
        let stripe = ui.visuals().faint_bg_color;
        for (i, row) in self.rows.iter().enumerate() {
            let height = self.row_height(row);
            if i % 2 == 1 {
                let band = egui::Rect::from_x_y_ranges(
                    inner.x_range(),
                    y - Self::ROW_GAP / 2.0..=y + height + Self::ROW_GAP / 2.0,
                );
                painter.rect_filled(band, 0.0, stripe);
            }
            painter.galley(
                egui::pos2(inner.left(), y),
                row.0.clone(),
                egui::Color32::PLACEHOLDER,
            );
            let help_x = inner.left() + self.keys_width + Self::COLUMN_GAP;
            painter.galley(
                egui::pos2(help_x, y),
                row.1.clone(),
                egui::Color32::PLACEHOLDER,
            );
            y += height + Self::ROW_GAP;
        }
        y += Self::BLOCK_GAP;
        painter.galley(
            egui::pos2(inner.left(), y),
            self.footer.clone(),
            egui::Color32::PLACEHOLDER,
        );
        let closing_x = inner.right() - self.closing.size().x;
        painter.galley(
            egui::pos2(closing_x, y),
            self.closing.clone(),
            egui::Color32::PLACEHOLDER,
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn keys_are_written_as_their_characters() {
        let ctx = egui::Context::default();
        let text = |modifiers, key| shortcut_text(&ctx, &KeyboardShortcut::new(modifiers, key));
        assert_eq!(text(Modifiers::NONE, Key::CloseBracket), "]");
        assert_eq!(text(Modifiers::NONE, Key::Questionmark), "?");
        assert_eq!(text(Modifiers::NONE, Key::F1), "F1");
        let ctrl_d = KeyboardShortcut::new(Modifiers::COMMAND, Key::D);
        assert_eq!(
            text(Modifiers::COMMAND, Key::D),
            ctx.format_shortcut(&ctrl_d)
        );
        let ctrl_bracket = text(Modifiers::COMMAND, Key::OpenBracket);
        assert!(
            ctrl_bracket.ends_with('[') && ctrl_bracket.len() > 1,
            "{ctrl_bracket}"
        );
    }

    #[test]
    fn no_two_shortcuts_share_a_key_combination() {
        for (i, a) in SHORTCUTS.iter().enumerate() {
            for b in &SHORTCUTS[i + 1..] {
                assert!(
                    a.shortcut != b.shortcut,
                    "{:?} and {:?} share a key",
                    a.action,
                    b.action
                );
            }
            assert!(!DIGIT_KEYS[1..].contains(&a.shortcut.logical_key));
            assert!(!BOOKMARK_KEYS.contains(&a.shortcut.logical_key));
        }
    }
}
