//! What a blind session records: each technique's wins and ties ([`Summary`]) and the
//! answers file, rewritten after every answer by a writer thread of its own (atomically, and
//! never over a file the session did not create).

use super::*;

/// Wins of one technique.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub(super) struct Wins {
    pub(super) id: &'static str,
    pub(super) name: String,
    pub(super) wins: usize,
    pub(super) still: usize,
    pub(super) in_motion: usize,
}

/// The file's summary.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub(super) struct Summary {
    pub(super) trials: usize,
    /// Answers of no preference.
    pub(super) ties: usize,
    /// Per technique, in the session's order.
    pub(super) wins: Vec<Wins>,
    /// How often a choice agreed with ColorVideoVDP's ranking, over the answers given while
    /// a scored clip was on screen (`None`: no such answer).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(super) jod_agreement: Option<JodAgreement>,
}

/// Answers that chose a pane while every pane's JOD was known, and those of them whose choice
/// had the highest JOD of the panes.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub(super) struct JodAgreement {
    pub(super) answers: usize,
    pub(super) agreed: usize,
}

impl JodAgreement {
    /// Over `trials`; `None` when none was scored.
    pub(super) fn of(trials: &[Trial]) -> Option<Self> {
        let judged: Vec<bool> = trials
            .iter()
            .filter_map(|trial| {
                let answer = trial.answer?;
                let jod = trial.context.jod.as_ref()?;
                let scores: Option<Vec<f64>> =
                    trial.panes.iter().map(|p| jod.get(p).copied()).collect();
                let best = scores?.into_iter().fold(f64::MIN, f64::max);
                Some(jod.get(answer).is_some_and(|&j| j >= best))
            })
            .collect();
        (!judged.is_empty()).then(|| Self {
            answers: judged.len(),
            agreed: judged.iter().filter(|&&a| a).count(),
        })
    }
}

/// The answers file.
#[derive(serde::Serialize)]
pub(super) struct AnswersFile<'a> {
    pub(super) schema: &'static str,
    pub(super) seed: u64,
    pub(super) started_unix_seconds: u64,
    pub(super) build: &'a str,
    pub(super) adapter: &'a str,
    pub(super) techniques: &'a [Contestant],
    pub(super) summary: Summary,
    pub(super) trials: &'a [Trial],
}

/// Writes the answers file on a thread of its own, newest contents first.
pub(super) struct Writer {
    pub(super) contents: mpsc::Sender<(usize, String)>,
    pub(super) results: mpsc::Receiver<(usize, Result<(), String>)>,
}

impl Writer {
    /// Starts the thread that writes `path`: the first write creates it (and fails when the
    /// name is taken), later ones replace it.
    pub(super) fn spawn(path: PathBuf, ctx: &egui::Context) -> std::io::Result<Self> {
        let (contents, jobs) = mpsc::channel::<(usize, String)>();
        let (done, results) = mpsc::channel();
        let ctx = ctx.clone();
        std::thread::Builder::new()
            .name("aa-lab blind answers".to_owned())
            .spawn(move || {
                let mut created = false;
                while let Ok(mut job) = jobs.recv() {
                    // Every text holds every answer: only the newest waiting one matters.
                    while let Ok(newer) = jobs.try_recv() {
                        job = newer;
                    }
                    let (answers, text) = job;
                    let result = write_answers(&path, created, &text);
                    created |= result.is_ok();
                    let _ = done.send((answers, result));
                    crate::app::repaint::request_one_frame(&ctx);
                }
            })?;
        Ok(Self { contents, results })
    }
}

/// Writes the answers file atomically; `ours` allows replacing it (it is this session's).
pub(super) fn write_answers(path: &Path, ours: bool, text: &str) -> Result<(), String> {
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir)
            .map_err(|err| format!("cannot create {}: {err}", dir.display()))?;
    }
    files::write_bytes(path, &Overwrite::new(ours), text.as_bytes())
        .map(|_| ())
        .map_err(|err| err.to_string())
}
