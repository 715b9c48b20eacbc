//! Shortcut keys answered before egui's pass: [`take_press`] removes a key's presses from a
//! list of events as egui's `consume_key` would, and [`KeyIntake`] applies the viewer's key
//! handling to a frame's raw input, removing the presses it answered together with their
//! releases and typed text; [`HeldKeys`] tells the window's event filter
//! (`app::event_filter`) which releases it may drop before eframe sees them. This file imports
//! nothing of the viewer; the shortcut table and the blind comparison's keys use it.

use std::sync::{Arc, Mutex, MutexGuard, PoisonError};

use egui::{Key, Modifiers};

/// Removes every press of `key` (repeats included) whose modifiers match `modifiers` as egui's
/// `InputState::consume_key` matches them; true if there was one.
pub(super) fn take_press(events: &mut Vec<egui::Event>, modifiers: Modifiers, key: Key) -> bool {
    let before = events.len();
    events.retain(|event| {
        !matches!(
            event,
            egui::Event::Key { key: k, modifiers: m, pressed: true, .. }
                if *k == key && m.matches_logically(modifiers)
        )
    });
    events.len() != before
}

/// The keys whose presses a shortcut took before egui's pass ([`KeyIntake::take`]): their
/// releases and typed text go too, so the frame that answers a key has no input events left.
///
/// Why: egui asks for two more frames after any frame with input events (to let things settle),
/// so a key press and its release cost up to six painted frames. On a software rasteriser each
/// paint of the whole window takes tens of milliseconds of both cores; a shortcut answered in
/// the raw input costs one paint (the window's event filter drops a release that comes in a
/// batch of its own, which would otherwise cost a second).
#[derive(Default)]
pub(super) struct KeyIntake {
    held: HeldKeys,
}

/// The keys pressed for a shortcut and not yet released, shared by the [`KeyIntake`] that took
/// their presses and the window's event filter, which drops their releases.
#[derive(Clone, Debug, Default)]
pub struct HeldKeys(Arc<Mutex<Vec<Key>>>);

impl HeldKeys {
    fn lock(&self) -> MutexGuard<'_, Vec<Key>> {
        self.0.lock().unwrap_or_else(PoisonError::into_inner)
    }

    /// Forgets `key` if it is held: its release is answered. True if it was.
    pub(super) fn release(&self, key: Key) -> bool {
        let mut held = self.lock();
        let found = held.iter().position(|k| *k == key);
        if let Some(i) = found {
            held.swap_remove(i);
        }
        found.is_some()
    }
}

impl KeyIntake {
    /// An intake whose held keys are `held` (shared with the window's event filter).
    pub(super) fn new(held: HeldKeys) -> Self {
        Self { held }
    }

    /// Runs `take` (which removes the presses it answers) on a frame's raw events, then removes
    /// the releases of the keys taken, now or in an earlier frame, and the text typed with them.
    pub(super) fn take<T>(
        &mut self,
        events: &mut Vec<egui::Event>,
        take: impl FnOnce(&mut Vec<egui::Event>) -> T,
    ) -> T {
        let before = pressed_keys(events);
        let answer = take(events);
        let left = pressed_keys(events);
        let mut unmatched = left.clone();
        let mut taken = Vec::new();
        for key in before {
            match unmatched.iter().position(|k| *k == key) {
                Some(i) => {
                    unmatched.swap_remove(i);
                }
                None => taken.push(key),
            }
        }
        let typed_with_a_shortcut = !taken.is_empty();
        // A press that egui sees owns its release again (the key was released unseen, say
        // while the window had no focus); a repeat does not add the key twice.
        let mut held = self.held.lock();
        held.retain(|k| !left.contains(k));
        for key in taken {
            if !held.contains(&key) {
                held.push(key);
            }
        }
        drop(held);
        events.retain(|event| match event {
            egui::Event::Key {
                key,
                pressed: false,
                ..
            } => !self.held.release(*key),
            egui::Event::Text(_) => !typed_with_a_shortcut,
            _ => true,
        });
        answer
    }
}

/// The keys of the presses in `events`, in order.
fn pressed_keys(events: &[egui::Event]) -> Vec<Key> {
    events
        .iter()
        .filter_map(|event| match event {
            egui::Event::Key {
                key, pressed: true, ..
            } => Some(*key),
            _ => None,
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn key(key: Key, pressed: bool) -> egui::Event {
        egui::Event::Key {
            key,
            physical_key: None,
            pressed,
            repeat: false,
            modifiers: Modifiers::NONE,
        }
    }

    /// Takes the presses of F1 only, as a shortcut table would.
    fn take_f1(events: &mut Vec<egui::Event>) -> bool {
        take_press(events, Modifiers::NONE, Key::F1)
    }

    #[test]
    fn a_taken_press_takes_its_release_and_text_along() {
        let mut intake = KeyIntake::default();
        let mut events = vec![
            key(Key::F1, true),
            egui::Event::Text("x".to_owned()),
            key(Key::F1, false),
            key(Key::B, true),
        ];
        assert!(intake.take(&mut events, take_f1));
        assert_eq!(events, vec![key(Key::B, true)]);
    }

    #[test]
    fn a_release_in_a_later_batch_goes_too_and_only_once() {
        let mut intake = KeyIntake::default();
        let mut press = vec![key(Key::F1, true), key(Key::F1, true)];
        assert!(intake.take(&mut press, take_f1));
        assert!(press.is_empty());
        let mut release = vec![key(Key::F1, false), egui::Event::Text("y".to_owned())];
        assert!(!intake.take(&mut release, take_f1));
        // No press was taken in this batch, so typed text stays.
        assert_eq!(release, vec![egui::Event::Text("y".to_owned())]);
        let mut again = vec![key(Key::F1, false)];
        intake.take(&mut again, take_f1);
        assert_eq!(
            again,
            vec![key(Key::F1, false)],
            "the release was already taken"
        );
    }

    #[test]
    fn a_release_the_window_filter_answered_is_no_longer_held() {
        let held = HeldKeys::default();
        let mut intake = KeyIntake::new(held.clone());
        let mut press = vec![key(Key::F1, true)];
        assert!(intake.take(&mut press, take_f1));
        assert!(!held.release(Key::B), "B was not taken");
        assert!(held.release(Key::F1), "the filter drops F1's release");
        assert!(!held.release(Key::F1), "and only once");
        // A release egui sees later (the key pressed while egui had the keyboard) stays.
        let mut release = vec![key(Key::F1, false)];
        intake.take(&mut release, take_f1);
        assert_eq!(release, vec![key(Key::F1, false)]);
    }

    #[test]
    fn keys_left_to_egui_keep_their_releases() {
        let mut intake = KeyIntake::default();
        let mut events = vec![key(Key::F1, true)];
        intake.take(&mut events, take_f1);
        // The next press of F1 is left to egui (say a text field has focus): its release is
        // egui's again.
        let mut seen = vec![key(Key::F1, true), key(Key::F1, false)];
        intake.take(&mut seen, |_| false);
        assert_eq!(seen, vec![key(Key::F1, true), key(Key::F1, false)]);
        let mut other = vec![key(Key::Space, true), key(Key::Space, false)];
        intake.take(&mut other, take_f1);
        assert_eq!(other.len(), 2);
    }

    #[test]
    fn presses_match_modifiers_as_egui_does() {
        let ctrl_d = egui::Event::Key {
            key: Key::D,
            physical_key: None,
            pressed: true,
            repeat: false,
            modifiers: Modifiers::COMMAND,
        };
        let mut events = vec![ctrl_d.clone()];
        assert!(!take_press(&mut events, Modifiers::NONE, Key::D));
        assert!(take_press(&mut events, Modifiers::COMMAND, Key::D));
        assert!(events.is_empty());
    }
}
