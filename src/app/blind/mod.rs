//! Blind comparison for artists (issue 12): the compared techniques (two to four) are shown
//! under pane numbers instead of their names, in an order shuffled for every trial, and the
//! artist says which pane looks better, or that none does. Every answer goes at once to a JSON
//! file with what was on screen (the scene, the live frame or the clip and its frame, the
//! layout, the magnifier's region, the render size and every technique's settings) and a
//! summary of wins per technique.
//!
//! - The shuffle is deterministic: trial `k`'s order comes from the session's seed alone
//!   ([`pane_order`]); the file records the seed and the order of every trial.
//! - While a session runs, every place that names a technique shows the pane number instead
//!   (the chips of every layout, the magnifier's panes and pixel readout, the toolbar:
//!   [`BlindState::letter`], [`BlindState::label`]); the techniques and metrics panels (names,
//!   costs, figures) give way to the session's panel ([`BlindState::ui`]) and the magnifier
//!   hides its figures.
//! - Answers: the number keys (0: no preference), a click on a pane in the viewport or the
//!   magnifier, or the panel's buttons. A still frame and a clip, playing or paused, work the
//!   same way: every pane shows the same instant. Optionally the mapping is revealed after
//!   each answer; the next trial, reshuffled, starts at once or on Enter after a reveal.
//! - The file: `<export folder>/<scene>-blind.json` (`-2`, `-3`, ... when the name is taken:
//!   no existing file is ever replaced), created when the session starts and rewritten
//!   atomically after every answer by a writer thread of the session, so the UI thread never
//!   waits on the disk.
//!
//! The session ([`BlindState`]) is the context's, since the labels of every panel follow it;
//! the context's session commands (start, answer, keys) are in `context/blind.rs`, and the
//! session's panel ([`panel`]) draws the state and returns what was asked for.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::sync::mpsc;
use std::time::{Instant, SystemTime, UNIX_EPOCH};

use egui::{Button, Key, Modifiers, RichText};

use super::engine::ClipRecipe;
use super::settings::Layout;
use super::style::{self, SLOT_COLORS, SLOT_LETTERS};
use crate::aa::ParamMap;
use crate::files::{self, Overwrite};
use crate::scene::camera::OrbitPose;

mod answers;
mod panel;

use answers::{AnswersFile, JodAgreement, Summary, Wins, Writer};
pub(super) use panel::panel;

/// The panes' names while a session runs (the slot letters otherwise).
const PANE_NUMBERS: [&str; 4] = ["1", "2", "3", "4"];
/// Schema of the answers file.
const SCHEMA: &str = "aa-lab-blind/1";
/// The digit keys, 0 to 9: a blind comparison answers with them (0: no preference, n: pane n);
/// outside one, 1 to 9 switch techniques (`shortcuts.rs`, `DIGIT_KEYS[1..]`).
pub const DIGIT_KEYS: [Key; 10] = [
    Key::Num0,
    Key::Num1,
    Key::Num2,
    Key::Num3,
    Key::Num4,
    Key::Num5,
    Key::Num6,
    Key::Num7,
    Key::Num8,
    Key::Num9,
];

/// Which technique each pane shows in trial `trial` (0-based) of a session seeded with
/// `seed`: pane `i` shows technique `order[i]` of the session's list. A Fisher-Yates shuffle
/// driven by SplitMix64 (Steele, Lea and Flood, 2014) seeded with `seed + trial`, spelled out
/// here so that a seed in an answers file gives the same orders with any later build (a
/// generator crate may change its sequence between versions).
pub fn pane_order(seed: u64, trial: usize, count: usize) -> Vec<usize> {
    let mut state = seed.wrapping_add(trial as u64);
    let mut next = move || {
        state = state.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = state;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    };
    let mut order: Vec<usize> = (0..count).collect();
    for i in (1..count).rev() {
        // Multiply-shift maps the 64 random bits onto 0..=i (bias below 2^-58).
        let j = ((u128::from(next()) * (i as u128 + 1)) >> 64) as usize;
        order.swap(i, j);
    }
    order
}

/// An answer.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Choice {
    /// Pane `n` (0-based) looks better.
    Pane(usize),
    /// No pane looks better than the others.
    NoPreference,
}

/// What the session's panel or keys ask for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BlindAction {
    /// Record an answer for the trial on screen.
    Answer(Choice),
    /// After a reveal: the next trial.
    Next,
    /// End the session (the file stays).
    End,
}

/// A technique of the session.
#[derive(Clone, Debug, serde::Serialize)]
struct Contestant {
    id: &'static str,
    name: String,
}

/// What the panes showed when an answer was given.
#[derive(Clone, Debug, serde::Serialize)]
#[serde(tag = "source", rename_all = "kebab-case")]
pub(super) enum OnScreen {
    /// The live view: the camera's frame and pose, every technique's settings.
    Live {
        frame: u64,
        camera: OrbitPose,
        camera_moving: bool,
        settings: BTreeMap<&'static str, ParamMap>,
    },
    /// A recorded clip (whose recipe holds the settings it was recorded with).
    Clip {
        /// The frame on screen (0-based).
        frame: usize,
        frames: usize,
        playing: bool,
        fps: f64,
        ping_pong: bool,
        recipe: ClipRecipe,
    },
    /// Images opened as panes.
    Images { paths: Vec<PathBuf> },
}

/// The magnifier's region.
#[derive(Clone, Copy, Debug, serde::Serialize)]
pub(super) struct Lens {
    pub(in crate::app) x: u32,
    pub(in crate::app) y: u32,
    pub(in crate::app) width: u32,
    pub(in crate::app) height: u32,
    pub(in crate::app) zoom: u32,
}

/// The circumstances of an answer, from the app.
#[derive(Clone, Debug, serde::Serialize)]
pub(super) struct TrialContext {
    pub(in crate::app) scene: String,
    /// A playing clip (or a camera moving by itself) rather than a still image.
    pub(in crate::app) in_motion: bool,
    #[serde(flatten)]
    pub(in crate::app) shown: OnScreen,
    pub(in crate::app) layout: Layout,
    /// The magnifier's lens when it is open (`None`: the whole frame).
    pub(in crate::app) region: Option<Lens>,
    pub(in crate::app) render_size: (u32, u32),
    /// ColorVideoVDP's JOD of each technique over the clip on screen, when it has been scored
    /// (the metrics panel's clip table).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(in crate::app) jod: Option<BTreeMap<&'static str, f64>>,
}

/// One answer.
#[derive(Clone, Debug, serde::Serialize)]
struct Trial {
    /// 1-based.
    trial: usize,
    /// The technique of pane 1, 2, ...
    panes: Vec<&'static str>,
    /// The pane chosen (1-based; `None`: no preference).
    pane: Option<usize>,
    /// Its technique.
    answer: Option<&'static str>,
    /// Seconds from the trial's start to the answer.
    seconds: f64,
    /// Whether the mapping was being revealed after each answer.
    reveal: bool,
    #[serde(flatten)]
    context: TrialContext,
}

/// A running session.
struct Session {
    techniques: Vec<Contestant>,
    seed: u64,
    started_unix_seconds: u64,
    build: String,
    adapter: String,
    /// Pane `i` shows `techniques[order[i]]`.
    order: Vec<usize>,
    trials: Vec<Trial>,
    /// The last answer's mapping is on screen; the next trial waits.
    revealed: bool,
    trial_started: Instant,
    path: PathBuf,
    writer: Writer,
    /// Answers in the file, or why the last write failed.
    saved: Result<usize, String>,
}

impl Session {
    fn panes(&self) -> Vec<&'static str> {
        self.order.iter().map(|&i| self.techniques[i].id).collect()
    }

    fn name<'a>(&'a self, id: &'a str) -> &'a str {
        self.techniques
            .iter()
            .find(|t| t.id == id)
            .map_or(id, |t| t.name.as_str())
    }

    fn summary(&self) -> Summary {
        let wins = self
            .techniques
            .iter()
            .map(|t| {
                let won: Vec<&Trial> = self
                    .trials
                    .iter()
                    .filter(|trial| trial.answer == Some(t.id))
                    .collect();
                let in_motion = won.iter().filter(|trial| trial.context.in_motion).count();
                Wins {
                    id: t.id,
                    name: t.name.clone(),
                    wins: won.len(),
                    still: won.len() - in_motion,
                    in_motion,
                }
            })
            .collect();
        Summary {
            trials: self.trials.len(),
            ties: self.trials.iter().filter(|t| t.pane.is_none()).count(),
            wins,
            jod_agreement: JodAgreement::of(&self.trials),
        }
    }

    /// Hands the whole file to the writer.
    fn save(&mut self) {
        let file = AnswersFile {
            schema: SCHEMA,
            seed: self.seed,
            started_unix_seconds: self.started_unix_seconds,
            build: &self.build,
            adapter: &self.adapter,
            techniques: &self.techniques,
            summary: self.summary(),
            trials: &self.trials,
        };
        let sent = serde_json::to_string_pretty(&file)
            .map_err(|err| err.to_string())
            .and_then(|text| {
                self.writer
                    .contents
                    .send((self.trials.len(), text + "\n"))
                    .map_err(|_| "the writer thread stopped".to_owned())
            });
        if let Err(err) = sent {
            self.saved = Err(format!("cannot write {}: {err}", self.path.display()));
        }
    }

    /// The next trial, reshuffled.
    fn next(&mut self) {
        self.revealed = false;
        self.order = pane_order(self.seed, self.trials.len(), self.techniques.len());
        self.trial_started = Instant::now();
    }

    /// One line: answers, ties and wins per technique.
    fn summary_line(&self) -> String {
        let summary = self.summary();
        let wins: Vec<String> = summary
            .wins
            .iter()
            .map(|w| format!("{} {}", w.name, w.wins))
            .collect();
        let agreement = summary.jod_agreement.map_or_else(String::new, |a| {
            format!(
                "; agreed with ColorVideoVDP on {} of {} scored answers",
                a.agreed, a.answers
            )
        });
        format!(
            "{} answers, {} without preference; wins: {}{agreement}",
            summary.trials,
            summary.ties,
            wins.join(", ")
        )
    }
}

/// The blind comparison mode: its session (if one runs) and its options.
#[derive(Default)]
pub struct BlindState {
    session: Option<Session>,
    /// Show after each answer which technique was in which pane.
    pub reveal: bool,
}

impl BlindState {
    /// Whether a session runs.
    pub fn active(&self) -> bool {
        self.session.is_some()
    }

    /// The techniques in pane order while a session runs.
    pub fn panes(&self) -> Option<Vec<&'static str>> {
        self.session.as_ref().map(Session::panes)
    }

    /// The name of pane `slot`: its number during a session, else its letter.
    pub fn letter(&self, slot: usize) -> &'static str {
        if self.active() {
            PANE_NUMBERS[slot]
        } else {
            SLOT_LETTERS[slot]
        }
    }

    /// What a technique's label says during a session: nothing, or its name while the last
    /// answer's mapping is revealed (`None`: no session, the usual label).
    pub fn label(&self, id: &str) -> Option<String> {
        let session = self.session.as_ref()?;
        Some(if session.revealed {
            session.name(id).to_owned()
        } else {
            String::new()
        })
    }

    /// Shows the next trial, reshuffled, once the last answer's mapping has been revealed.
    pub fn next_trial(&mut self) {
        if let Some(session) = self.session.as_mut().filter(|s| s.revealed) {
            session.next();
        }
    }

    /// Ends the session; the line that says how it went and where its answers are.
    pub fn end(&mut self) -> Option<String> {
        let session = self.session.take()?;
        Some(format!(
            "Blind comparison ended: {} (in {})",
            session.summary_line(),
            session.path.display()
        ))
    }

    /// The answers file of the running session.
    pub fn file(&self) -> Option<&Path> {
        self.session.as_ref().map(|s| s.path.as_path())
    }

    /// Starts a session over `techniques` (id, name) in panes, writing to `path`.
    pub(in crate::app) fn start(
        &mut self,
        techniques: Vec<(&'static str, String)>,
        seed: u64,
        path: PathBuf,
        adapter: String,
        ctx: &egui::Context,
    ) -> std::io::Result<()> {
        let writer = Writer::spawn(path.clone(), ctx)?;
        let count = techniques.len();
        let mut session = Session {
            techniques: techniques
                .into_iter()
                .map(|(id, name)| Contestant { id, name })
                .collect(),
            seed,
            started_unix_seconds: SystemTime::now()
                .duration_since(UNIX_EPOCH)
                .map_or(0, |d| d.as_secs()),
            build: crate::spec::build_id(),
            adapter,
            order: pane_order(seed, 0, count),
            trials: Vec::new(),
            revealed: false,
            trial_started: Instant::now(),
            path,
            writer,
            saved: Ok(0),
        };
        // The file exists from the start, which also keeps its name from the next session.
        session.save();
        self.session = Some(session);
        Ok(())
    }

    /// Records an answer for the trial on screen; returns whether it was taken (not while a
    /// reveal waits, nor for a pane that does not exist).
    pub(in crate::app) fn answer(&mut self, choice: Choice, context: TrialContext) -> bool {
        let reveal = self.reveal;
        let Some(session) = &mut self.session else {
            return false;
        };
        let pane = match choice {
            Choice::Pane(pane) if pane < session.order.len() => Some(pane),
            Choice::Pane(_) => return false,
            Choice::NoPreference => None,
        };
        if session.revealed {
            return false;
        }
        let panes = session.panes();
        session.trials.push(Trial {
            trial: session.trials.len() + 1,
            pane: pane.map(|p| p + 1),
            answer: pane.map(|p| panes[p]),
            panes,
            seconds: session.trial_started.elapsed().as_secs_f64(),
            reveal,
            context,
        });
        session.save();
        if reveal {
            session.revealed = true;
        } else {
            session.next();
        }
        true
    }

    /// Picks up the writer's reports.
    fn poll(&mut self) {
        if let Some(session) = &mut self.session {
            while let Ok((answers, result)) = session.writer.results.try_recv() {
                session.saved = result.map(|()| answers);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pane_orders_are_permutations_that_follow_from_the_seed() {
        for count in 2..=4 {
            for trial in 0..20 {
                let order = pane_order(7, trial, count);
                let mut sorted = order.clone();
                sorted.sort_unstable();
                assert_eq!(sorted, (0..count).collect::<Vec<_>>());
                assert_eq!(order, pane_order(7, trial, count), "deterministic");
            }
        }
        // Over many trials every technique lands in every pane.
        let mut seen = [[false; 4]; 4];
        for trial in 0..200 {
            for (pane, technique) in pane_order(12345, trial, 4).into_iter().enumerate() {
                seen[pane][technique] = true;
            }
        }
        assert!(seen.iter().flatten().all(|s| *s), "{seen:?}");
        let orders = |seed| (0..10).map(|t| pane_order(seed, t, 4)).collect::<Vec<_>>();
        assert_ne!(orders(1), orders(2), "another seed, other orders");
        // Pinned: the files' seeds must give the same orders in every later build.
        assert_eq!(
            orders(2026)[..3],
            [vec![0, 2, 1, 3], vec![3, 0, 2, 1], vec![0, 2, 3, 1]]
        );
    }

    fn context(in_motion: bool) -> TrialContext {
        TrialContext {
            scene: "chart".to_owned(),
            in_motion,
            shown: OnScreen::Images { paths: Vec::new() },
            layout: Layout::Grid,
            region: None,
            render_size: (64, 32),
            jod: None,
        }
    }

    #[test]
    fn answers_count_wins_per_technique_and_ties_and_the_file_says_so() {
        let dir = tempfile::tempdir().unwrap();
        // Another file of the same name is never replaced.
        let path = dir.path().join("chart-blind.json");
        let ctx = egui::Context::default();
        let mut state = BlindState::default();
        let techniques = vec![("none", "No AA".to_owned()), ("fxaa", "FXAA".to_owned())];
        state
            .start(techniques, 99, path.clone(), "test".to_owned(), &ctx)
            .unwrap();
        assert_eq!(state.letter(1), "2");
        assert_eq!(state.label("fxaa").as_deref(), Some(""));
        let first = state.panes().unwrap();
        assert!(state.answer(Choice::Pane(0), context(false)));
        assert!(!state.answer(Choice::Pane(2), context(false)), "no pane 3");
        let second = state.panes().unwrap();
        assert_eq!(
            second,
            pane_order(99, 1, 2)
                .iter()
                .map(|&i| ["none", "fxaa"][i])
                .collect::<Vec<_>>()
        );
        assert!(state.answer(Choice::Pane(1), context(true)));
        assert!(state.answer(Choice::NoPreference, context(true)));
        // With the reveal, the next trial waits and the names show.
        state.reveal = true;
        let fourth = state.panes().unwrap();
        assert!(state.answer(Choice::Pane(0), context(false)));
        assert_eq!(state.label("fxaa").as_deref(), Some("FXAA"));
        assert!(
            !state.answer(Choice::Pane(1), context(false)),
            "waits for Next"
        );
        let session = state.session.as_mut().unwrap();
        session.next();
        let summary = session.summary();
        assert_eq!((summary.trials, summary.ties), (4, 1));
        // Winners: trial 1 pane 1 (still), trial 2 pane 2 (in motion), trial 4 pane 1 (still).
        let winners = [(first[0], false), (second[1], true), (fourth[0], false)];
        for wins in &summary.wins {
            let count = |moving: bool| {
                winners
                    .iter()
                    .filter(|(id, m)| *id == wins.id && *m == moving)
                    .count()
            };
            assert_eq!(
                (wins.still, wins.in_motion),
                (count(false), count(true)),
                "{wins:?}"
            );
            assert_eq!(wins.wins, wins.still + wins.in_motion);
        }
        // The writer catches up with the last answer.
        let start = Instant::now();
        while state.session.as_ref().unwrap().saved != Ok(4) {
            assert!(
                start.elapsed().as_secs() < 10,
                "the answers file was not written"
            );
            std::thread::sleep(std::time::Duration::from_millis(5));
            state.poll();
        }
        let file: serde_json::Value =
            serde_json::from_slice(&std::fs::read(&path).unwrap()).unwrap();
        assert_eq!(file["schema"], SCHEMA);
        assert_eq!(file["seed"], 99);
        assert_eq!(file["summary"]["trials"], 4);
        assert_eq!(file["summary"]["ties"], 1);
        assert_eq!(file["trials"][0]["answer"], first[0]);
        assert_eq!(file["trials"][0]["pane"], 1);
        assert!(file["trials"][2]["answer"].is_null());
        assert_eq!(file["trials"][1]["in_motion"], true);
        assert_eq!(file["trials"][1]["scene"], "chart");
    }

    #[test]
    fn the_summary_counts_how_often_answers_agree_with_the_jod_ranking() {
        let dir = tempfile::tempdir().unwrap();
        let ctx = egui::Context::default();
        let mut state = BlindState::default();
        let techniques = vec![("none", "No AA".to_owned()), ("taa", "TAA".to_owned())];
        state
            .start(
                techniques,
                7,
                dir.path().join("a.json"),
                "t".to_owned(),
                &ctx,
            )
            .unwrap();
        let scored = |in_motion| TrialContext {
            jod: Some(BTreeMap::from([("none", 7.2), ("taa", 8.8)])),
            ..context(in_motion)
        };
        // TAA chosen (agrees), No AA chosen (disagrees), no preference and an unscored
        // answer (neither counts).
        for (choice, trial) in [("taa", scored(true)), ("none", scored(true))] {
            let pane = state.panes().unwrap().iter().position(|p| *p == choice);
            assert!(state.answer(Choice::Pane(pane.unwrap()), trial));
        }
        assert!(state.answer(Choice::NoPreference, scored(true)));
        assert!(state.answer(Choice::Pane(0), context(false)));
        let session = state.session.as_ref().unwrap();
        assert_eq!(
            session.summary().jod_agreement,
            Some(JodAgreement {
                answers: 2,
                agreed: 1
            })
        );
        assert!(
            session
                .summary_line()
                .contains("agreed with ColorVideoVDP on 1 of 2"),
            "{}",
            session.summary_line()
        );
    }

    #[test]
    fn a_session_never_replaces_a_file_it_did_not_create() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("taken.json");
        std::fs::write(&path, "precious").unwrap();
        let ctx = egui::Context::default();
        let mut state = BlindState::default();
        let techniques = vec![("none", "No AA".to_owned()), ("fxaa", "FXAA".to_owned())];
        state
            .start(techniques, 1, path.clone(), "test".to_owned(), &ctx)
            .unwrap();
        state.answer(Choice::Pane(0), context(false));
        let start = Instant::now();
        while state.session.as_ref().unwrap().saved.is_ok() {
            assert!(start.elapsed().as_secs() < 10, "no error reported");
            std::thread::sleep(std::time::Duration::from_millis(5));
            state.poll();
        }
        let err = state.session.as_ref().unwrap().saved.clone().unwrap_err();
        assert!(err.contains("taken.json"), "{err}");
        assert_eq!(std::fs::read_to_string(&path).unwrap(), "precious");
    }
}
