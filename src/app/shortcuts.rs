//! Keyboard shortcuts: one table ([`SHORTCUTS`]) drives both the key handling and the help
//! overlay, so the overlay can never list a key that does nothing. Keys that act while held
//! (flip to B or to the reference) and the lens nudges are listed in the same overlay.

use egui::{Key, KeyboardShortcut, Modifiers};

use super::blind::DIGIT_KEYS;
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

/// The actions whose keys were pressed this frame (consumed, so egui widgets do not see them).
/// Nothing is consumed while a text field has keyboard focus; with `flying`, the plain
/// shortcuts on [`FLY_KEYS`] are left to the fly camera.
pub fn pressed_actions(ctx: &egui::Context, flying: bool) -> Vec<Action> {
    if ctx.egui_wants_keyboard_input() {
        return Vec::new();
    }
    ctx.input_mut(|input| {
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
            if input.consume_shortcut(&entry.shortcut) {
                actions.push(entry.action);
            }
        }
        for (n, key) in DIGIT_KEYS[1..].iter().enumerate() {
            if input.consume_key(Modifiers::NONE, *key) {
                actions.push(Action::ToggleTechnique(n));
            }
        }
        for (n, key) in BOOKMARK_KEYS.iter().enumerate() {
            if input.consume_key(Modifiers::NONE, *key) {
                actions.push(Action::GoToBookmark(n));
            }
        }
        actions
    })
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

/// The help overlay (a modal listing every key), while `open` is set.
///
/// It shows in full on the first frame after the key, and its large areas are painted by
/// [`blit::fill`]: egui's modal fades in over several frames and paints its backdrop and
/// frame through egui's textured shader, which on a software rasteriser made each frame of
/// the overlay several times as slow as the window without it (figures: `docs/viewer.md`).
pub fn help_overlay(ctx: &egui::Context, open: &mut bool) {
    if !*open {
        return;
    }
    let id = egui::Id::unique("aa-lab help");
    // Between the panels (background) and the modal (foreground).
    let backdrop = ctx.layer_painter(egui::LayerId::new(egui::Order::Middle, id.with("backdrop")));
    blit::fill(&backdrop, ctx.content_rect(), HELP_BACKDROP);
    let modal = egui::Modal::new(id)
        .area(egui::Modal::default_area(id).fade_in(false))
        .backdrop_color(egui::Color32::TRANSPARENT)
        .frame(egui::Frame::NONE)
        .show(ctx, |ui| {
            let background = ui.painter().add(egui::Shape::Noop);
            let panel = egui::Frame::NONE
                .inner_margin(HELP_MARGIN)
                .show(ui, help_contents);
            let rect = panel.response.rect;
            ui.painter()
                .set(background, blit::fill_shape(ctx, rect, style::PANEL_FILL));
            let border = egui::Stroke::new(1.0, ui.visuals().window_stroke.color);
            ui.painter()
                .rect_stroke(rect, 0.0, border, egui::StrokeKind::Inside);
            panel.inner
        });
    if modal.inner || modal.should_close() {
        *open = false;
    }
}

/// How much the help overlay darkens the window under it.
const HELP_BACKDROP: egui::Color32 = egui::Color32::from_black_alpha(100);

/// The margin around the help overlay's text (points).
const HELP_MARGIN: f32 = 14.0;

/// The help overlay's text; true when its Close button was clicked.
fn help_contents(ui: &mut egui::Ui) -> bool {
    let ctx = ui.ctx().clone();
    ui.set_width(560.0);
    ui.heading("Keyboard and mouse");
    ui.add_space(6.0);
    egui::Grid::new("shortcut table")
        .num_columns(2)
        .spacing([24.0, 4.0])
        .striped(true)
        .show(ui, |ui| {
            let mut seen = Vec::new();
            for s in SHORTCUTS {
                if seen.contains(&s.action) {
                    continue;
                }
                seen.push(s.action);
                let keys: Vec<String> = SHORTCUTS
                    .iter()
                    .filter(|o| o.action == s.action)
                    .map(|o| shortcut_text(&ctx, &o.shortcut))
                    .collect();
                ui.monospace(keys.join("  or  "));
                ui.label(s.help);
                ui.end_row();
            }
            for (keys, help) in OTHER_KEYS {
                ui.monospace(*keys);
                ui.label(*help);
                ui.end_row();
            }
        });
    ui.add_space(8.0);
    ui.horizontal(|ui| {
        ui.weak("Every number in the metrics panel explains itself in a tooltip.");
        ui.with_layout(egui::Layout::right_to_left(egui::Align::Center), |ui| {
            ui.button("Close").clicked()
        })
        .inner
    })
    .inner
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
