//! The window's events before eframe sees them: the viewer runs the winit event loop itself
//! (eframe's `create_native`) and drops the release of a key whose press a shortcut answered
//! ([`HeldKeys`]); every other event goes to eframe unchanged.
//!
//! Why: egui-winit asks for a repaint at every keyboard event, before the app's raw-input hook
//! can take the event out of egui's input. The hook answers a shortcut at its press and would
//! remove the release from a later frame anyway, so when the release arrives in a batch of its
//! own, the repaint it asked for is a whole paint of the window that shows nothing new. On a
//! software rasteriser that paint takes tens of milliseconds of both cores, taken from the
//! engine and from whatever else runs (figures: `docs/viewer.md`).
//!
//! Which release: the key is named as egui names it (the logical key, by its name), so a key
//! this filter cannot name is passed on, and the hook removes it as before. A synthetic release
//! (winit's, when the window loses focus) is passed on too.

use eframe::UserEvent;
use winit::application::ApplicationHandler;
use winit::event::{DeviceEvent, DeviceId, ElementState, StartCause, WindowEvent};
use winit::event_loop::ActiveEventLoop;
use winit::keyboard::Key as WinitKey;
use winit::window::WindowId;

use super::key_events::HeldKeys;

/// eframe's application handler behind the filter.
pub(super) struct ShortcutReleaseFilter<'a> {
    eframe: eframe::EframeWinitApplication<'a>,
    held: HeldKeys,
}

impl<'a> ShortcutReleaseFilter<'a> {
    pub(super) fn new(eframe: eframe::EframeWinitApplication<'a>, held: HeldKeys) -> Self {
        Self { eframe, held }
    }

    /// Whether `event` releases a held shortcut key (which is then no longer held).
    fn takes(&self, event: &WindowEvent) -> bool {
        released_key(event).is_some_and(|key| self.held.release(key))
    }
}

/// The key a real (not synthetic) key release event releases, as egui names it.
fn released_key(event: &WindowEvent) -> Option<egui::Key> {
    let WindowEvent::KeyboardInput {
        event,
        is_synthetic: false,
        ..
    } = event
    else {
        return None;
    };
    if event.state != ElementState::Released {
        return None;
    }
    egui_key(&event.logical_key)
}

/// egui's key for a winit logical key, found by name (egui-winit's own table is private).
fn egui_key(key: &WinitKey) -> Option<egui::Key> {
    match key {
        WinitKey::Named(named) => egui::Key::from_name(&format!("{named:?}")),
        WinitKey::Character(text) => egui::Key::from_name(text),
        _ => None,
    }
}

impl ApplicationHandler<UserEvent> for ShortcutReleaseFilter<'_> {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        self.eframe.resumed(event_loop);
    }

    fn window_event(
        &mut self,
        event_loop: &ActiveEventLoop,
        window_id: WindowId,
        event: WindowEvent,
    ) {
        if !self.takes(&event) {
            self.eframe.window_event(event_loop, window_id, event);
        }
    }

    fn new_events(&mut self, event_loop: &ActiveEventLoop, cause: StartCause) {
        self.eframe.new_events(event_loop, cause);
    }

    fn user_event(&mut self, event_loop: &ActiveEventLoop, event: UserEvent) {
        self.eframe.user_event(event_loop, event);
    }

    fn device_event(
        &mut self,
        event_loop: &ActiveEventLoop,
        device_id: DeviceId,
        event: DeviceEvent,
    ) {
        self.eframe.device_event(event_loop, device_id, event);
    }

    fn about_to_wait(&mut self, event_loop: &ActiveEventLoop) {
        self.eframe.about_to_wait(event_loop);
    }

    fn suspended(&mut self, event_loop: &ActiveEventLoop) {
        self.eframe.suspended(event_loop);
    }

    fn exiting(&mut self, event_loop: &ActiveEventLoop) {
        self.eframe.exiting(event_loop);
    }

    fn memory_warning(&mut self, event_loop: &ActiveEventLoop) {
        self.eframe.memory_warning(event_loop);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use winit::keyboard::NamedKey;

    #[test]
    fn the_shortcut_keys_are_named_as_egui_names_them() {
        let named = [
            (NamedKey::F1, egui::Key::F1),
            (NamedKey::F12, egui::Key::F12),
            (NamedKey::Escape, egui::Key::Escape),
            (NamedKey::Space, egui::Key::Space),
            (NamedKey::Home, egui::Key::Home),
            (NamedKey::Tab, egui::Key::Tab),
            (NamedKey::ArrowLeft, egui::Key::ArrowLeft),
            (NamedKey::ArrowDown, egui::Key::ArrowDown),
        ];
        for (winit, egui) in named {
            assert_eq!(egui_key(&WinitKey::Named(winit)), Some(egui), "{winit:?}");
        }
        for (text, egui) in [
            ("a", egui::Key::A),
            ("[", egui::Key::OpenBracket),
            ("]", egui::Key::CloseBracket),
            (".", egui::Key::Period),
            ("?", egui::Key::Questionmark),
            ("1", egui::Key::Num1),
        ] {
            assert_eq!(
                egui_key(&WinitKey::Character(text.into())),
                Some(egui),
                "{text}"
            );
        }
    }
}
