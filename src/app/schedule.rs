//! What the viewer's engine renders in a frame, decided from plain data (no GPU, no egui) so
//! that the rules are tested on their own:
//! - a technique renders when it is on and its view changed (camera pose, size, scene, or the
//!   animation frame of an animated scene), when its settings changed, when it has no output
//!   yet, on a camera cut, and, for temporal techniques, whenever the clock advanced;
//! - the progressive reference renders only while the view stays the same (it would start
//!   over every frame otherwise), starting over when the view it accumulated for is gone, and
//!   stops once complete.

use crate::scene::camera::OrbitPose;

/// What determines the image of a non-temporal technique.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ViewKey {
    /// Camera pose.
    pub pose: OrbitPose,
    /// Output size in pixels.
    pub size: (u32, u32),
    /// Counts scene replacements.
    pub scene: u64,
    /// The frame number for animated scenes, 0 for static ones.
    pub animation: u64,
}

/// The view and frame an output was rendered at.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Stamp {
    /// The view.
    pub key: ViewKey,
    /// The clock's frame.
    pub frame: u64,
}

/// One technique as the scheduler sees it.
#[derive(Clone, Copy, Debug, Default)]
pub struct TechniqueState {
    /// Switched on and available.
    pub enabled: bool,
    /// Keeps state across frames.
    pub temporal: bool,
    /// Its settings changed since it last rendered.
    pub dirty: bool,
    /// When it last rendered.
    pub rendered: Option<Stamp>,
}

/// The reference as the scheduler sees it.
#[derive(Clone, Copy, Debug, Default)]
pub struct ReferenceState {
    /// Something shows or measures it.
    pub wanted: bool,
    /// The view its accumulated samples belong to.
    pub accumulated_for: Option<ViewKey>,
    /// Every sample of its pattern is in.
    pub complete: bool,
}

/// What one frame renders.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Schedule {
    /// Indices (into the technique list) of the techniques that render.
    pub run: Vec<usize>,
    /// `Some(restart)` when the reference adds samples, starting over when `restart`.
    pub reference: Option<bool>,
    /// The view did not change since the previous frame.
    pub still: bool,
}

impl Schedule {
    /// Nothing to render.
    pub fn is_empty(&self) -> bool {
        self.run.is_empty() && self.reference.is_none()
    }
}

/// Decides a frame at `key` and clock `frame`; `previous` is the key of the previous frame
/// and `cut` a camera cut (every technique re-renders, histories reset).
pub fn schedule(
    techniques: &[TechniqueState],
    reference: ReferenceState,
    previous: Option<ViewKey>,
    key: ViewKey,
    frame: u64,
    cut: bool,
) -> Schedule {
    let run = techniques
        .iter()
        .enumerate()
        .filter(|(_, t)| {
            let stale = match t.rendered {
                None => true,
                Some(done) => done.key != key || (t.temporal && done.frame != frame),
            };
            t.enabled && (cut || t.dirty || stale)
        })
        .map(|(i, _)| i)
        .collect();
    let still = !cut && previous == Some(key);
    let restart = reference.accumulated_for != Some(key);
    let reference =
        (reference.wanted && still && (restart || !reference.complete)).then_some(restart);
    Schedule {
        run,
        reference,
        still,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn key(yaw: f32) -> ViewKey {
        ViewKey {
            pose: OrbitPose {
                yaw_degrees: yaw,
                ..OrbitPose::default()
            },
            size: (64, 32),
            scene: 0,
            animation: 0,
        }
    }

    fn rendered(key: ViewKey, frame: u64) -> Option<Stamp> {
        Some(Stamp { key, frame })
    }

    #[test]
    fn first_frame_renders_every_enabled_technique() {
        let techniques = [
            TechniqueState {
                enabled: true,
                ..Default::default()
            },
            TechniqueState::default(),
            TechniqueState {
                enabled: true,
                temporal: true,
                ..Default::default()
            },
        ];
        let s = schedule(
            &techniques,
            ReferenceState::default(),
            None,
            key(0.0),
            0,
            false,
        );
        assert_eq!(s.run, vec![0, 2]);
        assert!(!s.still);
        assert_eq!(s.reference, None);
    }

    #[test]
    fn still_views_rerender_only_temporal_dirty_or_cut() {
        let k = key(0.0);
        let techniques = [
            TechniqueState {
                enabled: true,
                rendered: rendered(k, 1),
                ..Default::default()
            },
            TechniqueState {
                enabled: true,
                temporal: true,
                rendered: rendered(k, 1),
                ..Default::default()
            },
            TechniqueState {
                enabled: true,
                dirty: true,
                rendered: rendered(k, 1),
                ..Default::default()
            },
        ];
        let none = ReferenceState::default();
        assert!(schedule(&techniques[..1], none, Some(k), k, 2, false).is_empty());
        assert_eq!(
            schedule(&techniques, none, Some(k), k, 1, false).run,
            vec![2]
        );
        assert_eq!(
            schedule(&techniques, none, Some(k), k, 2, false).run,
            vec![1, 2]
        );
        assert_eq!(
            schedule(&techniques, none, Some(k), k, 1, true).run,
            vec![0, 1, 2]
        );
        let moved = schedule(&techniques, none, Some(k), key(1.0), 1, false);
        assert_eq!(moved.run, vec![0, 1, 2]);
    }

    #[test]
    fn reference_waits_for_a_still_view_and_stops_when_complete() {
        let k = key(0.0);
        let wanted = ReferenceState {
            wanted: true,
            ..Default::default()
        };
        // Moving: the reference waits.
        assert_eq!(
            schedule(&[], wanted, Some(key(1.0)), k, 0, false).reference,
            None
        );
        // Still: it starts over for the new view...
        assert_eq!(
            schedule(&[], wanted, Some(k), k, 0, false).reference,
            Some(true)
        );
        // ...then adds samples to it...
        let accumulating = ReferenceState {
            accumulated_for: Some(k),
            ..wanted
        };
        assert_eq!(
            schedule(&[], accumulating, Some(k), k, 0, false).reference,
            Some(false)
        );
        // ...until complete, and never when nothing wants it or the camera cuts.
        let complete = ReferenceState {
            complete: true,
            ..accumulating
        };
        assert!(schedule(&[], complete, Some(k), k, 0, false).is_empty());
        let unwanted = ReferenceState {
            wanted: false,
            ..accumulating
        };
        assert!(schedule(&[], unwanted, Some(k), k, 0, false).is_empty());
        assert_eq!(
            schedule(&[], accumulating, Some(k), k, 0, true).reference,
            None
        );
    }
}
