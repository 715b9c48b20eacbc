//! Clip playback ([`ClipPlayer`]): a loop or ping-pong at real time (30 or 60 frames per
//! second) or in slow motion ([`PlayRate`]), single steps and scrubbing (which stop playback).
//!
//! Playback never skips a frame: the position follows the clock, but one UI frame advances it
//! by at most one clip frame, so a paint that comes late (a UI frame longer than the clip's
//! period) shows the next frame rather than the one after it. The time it fell behind is kept,
//! up to [`MAX_LAG_FRAMES`], and the following paints catch up with the clock: when UI frames
//! jitter around the clip's period (as they do on a software rasteriser), a short paint makes
//! up for a long one and the clip keeps its rate. Skipped frames would change what is being
//! judged (a flicker between two frames can vanish when every other frame is dropped); when the
//! window paints more slowly than the clip's rate all along, the clip plays every frame more
//! slowly, and the clip bar says at what rate it is shown ([`ClipPlayer::shown_fps`]).

use std::collections::VecDeque;
use std::time::{Duration, Instant};

/// How far (in clip frames) playback may fall behind the clock and still catch up; beyond
/// that a stalled window drops the time (a long stall does not fast-forward afterwards).
const MAX_LAG_FRAMES: f64 = 2.0;
/// The window over which the shown rate is measured.
const SHOWN_RATE_WINDOW: Duration = Duration::from_secs(1);

/// Playback rates.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PlayRate {
    /// 30 frames per second.
    Fps30,
    /// 60 frames per second.
    Fps60,
    /// A quarter of 30 frames per second.
    Slow,
}

impl PlayRate {
    /// Every rate, in menu order.
    pub const ALL: [PlayRate; 3] = [PlayRate::Fps30, PlayRate::Fps60, PlayRate::Slow];

    /// Clip frames per second.
    pub fn fps(self) -> f64 {
        match self {
            PlayRate::Fps30 => 30.0,
            PlayRate::Fps60 => 60.0,
            PlayRate::Slow => 7.5,
        }
    }

    /// Menu label.
    pub fn label(self) -> &'static str {
        match self {
            PlayRate::Fps30 => "30 fps",
            PlayRate::Fps60 => "60 fps",
            PlayRate::Slow => "slow (7.5 fps)",
        }
    }
}

/// Which frame a clip shows, as time goes by.
#[derive(Clone, Debug)]
pub struct ClipPlayer {
    /// Position in frames (fractional between frames).
    position: f64,
    /// Time runs.
    pub playing: bool,
    /// Speed.
    pub rate: PlayRate,
    /// Back and forth instead of wrapping around.
    pub ping_pong: bool,
    /// Clip frames the clock is ahead of `position` (at most [`MAX_LAG_FRAMES`]).
    lag: f64,
    last_tick: Option<Instant>,
    /// When the shown frame changed while playing, over the last [`SHOWN_RATE_WINDOW`].
    changes: VecDeque<Instant>,
}

impl Default for ClipPlayer {
    fn default() -> Self {
        Self {
            position: 0.0,
            playing: true,
            rate: PlayRate::Fps30,
            ping_pong: false,
            lag: 0.0,
            last_tick: None,
            changes: VecDeque::new(),
        }
    }
}

impl ClipPlayer {
    /// Advances the position by the time since the last tick (`now`), over `frames` frames,
    /// by at most one frame (see the module docs: no frame is skipped).
    pub fn tick(&mut self, now: Instant, frames: usize) {
        let elapsed = self.last_tick.map_or(0.0, |last| {
            now.saturating_duration_since(last).as_secs_f64()
        });
        self.last_tick = Some(now);
        if self.playing && frames > 1 {
            let period = if self.ping_pong {
                2 * (frames - 1)
            } else {
                frames
            } as f64;
            let step = self.position.floor();
            let clock = (self.position + self.lag + elapsed * self.rate.fps())
                .min(step + 2.0 + MAX_LAG_FRAMES - 1e-9);
            // Late: the next frame now, due again at once; the rest is lag to catch up on.
            let shown = clock.min(step + 2.0 - 1e-9);
            if shown.floor() > step {
                self.changes.push_back(now);
            }
            self.lag = clock - shown;
            self.position = shown.rem_euclid(period);
        }
        while self
            .changes
            .front()
            .is_some_and(|at| now.saturating_duration_since(*at) > SHOWN_RATE_WINDOW)
        {
            self.changes.pop_front();
        }
    }

    /// Clip frames shown per second over the last second of playback (`None` before a second
    /// has been played).
    pub fn shown_fps(&self) -> Option<f64> {
        let (first, last) = (self.changes.front()?, self.changes.back()?);
        let span = last.saturating_duration_since(*first);
        (self.playing && span >= SHOWN_RATE_WINDOW.mul_f64(0.9))
            .then(|| (self.changes.len() - 1) as f64 / span.as_secs_f64())
    }

    /// Seconds until the frame shown changes, while playing.
    pub fn until_next_frame(&self) -> f64 {
        (self.position.floor() + 1.0 - self.position) / self.rate.fps()
    }

    /// Stops the clock between ticks (so a pause does not jump on resume).
    pub fn pause_clock(&mut self) {
        self.last_tick = None;
        self.lag = 0.0;
        self.changes.clear();
    }

    /// The frame index shown, of `frames` frames.
    pub fn frame(&self, frames: usize) -> usize {
        if frames == 0 {
            return 0;
        }
        let step = self.position.floor() as usize;
        if self.ping_pong && frames > 1 {
            let period = 2 * (frames - 1);
            let step = step % period;
            if step < frames { step } else { period - step }
        } else {
            step % frames
        }
    }

    /// Shows the last of `frames` frames without changing whether it plays (a clip being
    /// recorded); the clock starts afresh at the next tick.
    pub fn show_newest(&mut self, frames: usize) {
        self.position = frames.saturating_sub(1) as f64;
        self.lag = 0.0;
        self.last_tick = None;
    }

    /// Shows frame `index` (stops playback).
    pub fn seek(&mut self, index: usize) {
        self.playing = false;
        self.position = index as f64;
        self.lag = 0.0;
    }

    /// One frame forward (`1`) or back (`-1`), wrapping, stopping playback.
    pub fn step(&mut self, delta: i64, frames: usize) {
        if frames == 0 {
            return;
        }
        let current = self.frame(frames) as i64;
        self.seek((current + delta).rem_euclid(frames as i64) as usize);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The frames `player` shows at positions 0..9 of a 4-frame clip.
    fn shown_over_nine_steps(player: &mut ClipPlayer) -> Vec<usize> {
        (0..9)
            .map(|step| {
                player.position = f64::from(step);
                player.frame(4)
            })
            .collect()
    }

    #[test]
    fn loops_wrap_and_ping_pong_turns_at_the_ends() {
        let mut player = ClipPlayer::default();
        assert_eq!(
            shown_over_nine_steps(&mut player),
            [0, 1, 2, 3, 0, 1, 2, 3, 0]
        );
        player.ping_pong = true;
        assert_eq!(
            shown_over_nine_steps(&mut player),
            [0, 1, 2, 3, 2, 1, 0, 1, 2]
        );
    }

    /// Ticks `player` at `now + at_ms` for every entry of `at_ms`; the frames shown.
    fn ticks(player: &mut ClipPlayer, now: Instant, at_ms: &[u64]) -> Vec<usize> {
        at_ms
            .iter()
            .map(|ms| {
                player.tick(now + Duration::from_millis(*ms), 48);
                player.frame(48)
            })
            .collect()
    }

    #[test]
    fn playback_advances_with_time_at_the_chosen_rate() {
        let mut player = ClipPlayer::default();
        let start = Instant::now();
        // UI frames every 10 ms for half a second: 30 fps.
        let at: Vec<u64> = (0..=50).map(|i| i * 10).collect();
        assert_eq!(*ticks(&mut player, start, &at).last().unwrap(), 15);
        assert!(
            (player.until_next_frame() - 1.0 / 30.0).abs() < 1e-6,
            "at a frame boundary"
        );
        player.rate = PlayRate::Slow;
        let at: Vec<u64> = (51..=150).map(|i| i * 10).collect();
        assert_eq!(
            *ticks(&mut player, start, &at).last().unwrap(),
            22,
            "then 7.5 fps for a second"
        );
        player.playing = false;
        assert_eq!(ticks(&mut player, start, &[10_000]), [22], "paused");
    }

    #[test]
    fn late_paints_show_the_next_frame_and_catch_up_without_skipping() {
        let mut player = ClipPlayer::default();
        let start = Instant::now();
        // A 30 fps clip painted at 0, 40 and 60 ms, then after a stall of half a second (15
        // frames late): the next frame, then one frame per paint while it catches up on at
        // most two frames of lag, and from there on the clock's pace.
        let shown = ticks(
            &mut player,
            start,
            &[0, 40, 60, 560, 570, 580, 590, 600, 610, 620, 630],
        );
        assert_eq!(shown, [0, 1, 1, 2, 3, 4, 5, 6, 6, 6, 7]);
        // Every frame of a long run at 25 UI frames per second is shown once, in order.
        let mut player = ClipPlayer::default();
        let at: Vec<u64> = (0..=100).map(|i| i * 40).collect();
        let shown = ticks(&mut player, start, &at);
        assert!(
            shown.windows(2).all(|w| w[1] == (w[0] + 1) % 48),
            "{shown:?}"
        );
        let fps = player.shown_fps().expect("a second of playback");
        assert!((fps - 25.0).abs() < 0.01, "{fps}");
        // Paints jittering around the clip's period (28-38 ms, 30.3 fps on average) skip
        // nothing and keep the clip's rate.
        let mut player = ClipPlayer::default();
        let mut t = 0;
        let at: Vec<u64> = (0..300)
            .map(|i| {
                t += [28, 38, 29, 37, 33][i % 5];
                t
            })
            .collect();
        let shown = ticks(&mut player, start, &at);
        assert!(
            shown.windows(2).all(|w| (w[1] + 48 - w[0]) % 48 <= 1),
            "{shown:?}"
        );
        let fps = player.shown_fps().expect("a second of playback");
        assert!(fps > 29.9, "{fps}");
        // Quick paints with a long one (80 ms, 2.4 clip periods) every eighth: the long one
        // shows only the next frame, the quick ones after it catch up, and the clip keeps its
        // 30 frames per second over the run (without the lag it lost 1.4 frames in every
        // eight paints: 25 frames per second).
        let mut player = ClipPlayer::default();
        let periods = [25, 25, 25, 25, 25, 25, 25, 80];
        let mut t = 0;
        let at: Vec<u64> = (0..320)
            .map(|i| {
                t += periods[i % periods.len()];
                t
            })
            .collect();
        let shown = ticks(&mut player, start, &at);
        assert!(
            shown.windows(2).all(|w| (w[1] + 48 - w[0]) % 48 <= 1),
            "{shown:?}"
        );
        let changes = shown.windows(2).filter(|w| w[0] != w[1]).count();
        let seconds = (at[at.len() - 1] - at[0]) as f64 / 1000.0;
        let fps = changes as f64 / seconds;
        assert!(fps > 29.5, "{fps}");
    }

    #[test]
    fn steps_wrap_and_stop_playback() {
        let mut player = ClipPlayer::default();
        player.step(-1, 10);
        assert_eq!(player.frame(10), 9);
        assert!(!player.playing);
        player.step(1, 10);
        assert_eq!(player.frame(10), 0);
    }
}
