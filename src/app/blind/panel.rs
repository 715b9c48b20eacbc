//! The blind comparison's panel and keys (which pane looks better: a digit, or the
//! buttons), and what they do to the workspace: starting a session from the compared
//! techniques, answering a trial with what was on screen, moving to the next trial.

use super::*;

impl BlindState {
    /// The keys of a session: digits answer (0: no preference), Enter goes on after a reveal.
    /// They are consumed, so the number keys do not switch techniques meanwhile.
    fn keys(&self, ctx: &egui::Context) -> Option<BlindAction> {
        if !self.active() || ctx.egui_wants_keyboard_input() {
            return None;
        }
        ctx.input_mut(|input| {
            let mut action = None;
            for (digit, key) in DIGIT_KEYS.iter().enumerate() {
                if input.consume_key(Modifiers::NONE, *key) {
                    action = Some(BlindAction::Answer(match digit {
                        0 => Choice::NoPreference,
                        n => Choice::Pane(n - 1),
                    }));
                }
            }
            if input.consume_key(Modifiers::NONE, Key::Enter) {
                action = Some(BlindAction::Next);
            }
            action
        })
    }

    /// The session's panel: the question, the answers, the reveal, the summary and the file.
    pub fn ui(&mut self, ui: &mut egui::Ui) -> Option<BlindAction> {
        self.poll();
        let reveal = &mut self.reveal;
        let session = self.session.as_ref()?;
        let mut action = None;
        let panes = session.order.len();
        style::section(ui, "Blind comparison");
        let trial = session.trials.len() + usize::from(!session.revealed);
        ui.label(RichText::new(format!("Trial {trial}")).strong());
        ui.label("Which pane looks better?");
        ui.add_enabled_ui(!session.revealed, |ui| {
            ui.horizontal_wrapped(|ui| {
                for pane in 0..panes {
                    let text = RichText::new(format!(" {} ", PANE_NUMBERS[pane]))
                        .strong()
                        .color(egui::Color32::BLACK);
                    if ui
                        .add(Button::new(text).fill(SLOT_COLORS[pane]))
                        .on_hover_text(format!("Pane {} looks better (key {})", pane + 1, pane + 1))
                        .clicked()
                    {
                        action = Some(BlindAction::Answer(Choice::Pane(pane)));
                    }
                }
                if ui
                    .button("No preference")
                    .on_hover_text("None looks better than the others (key 0)")
                    .clicked()
                {
                    action = Some(BlindAction::Answer(Choice::NoPreference));
                }
            });
        });
        ui.weak(format!(
            "Keys 1–{panes} (0: no preference), or click a pane in the view or the magnifier. \
             Judge a still frame, or record a clip and judge it playing."
        ));
        ui.checkbox(reveal, "Reveal the techniques after each answer");
        if session.revealed
            && let Some(last) = session.trials.last()
        {
            ui.add_space(4.0);
            ui.label(match last.pane {
                Some(pane) => format!("Trial {}: you chose pane {pane}", last.trial),
                None => format!("Trial {}: no preference", last.trial),
            });
            for (pane, id) in last.panes.iter().enumerate() {
                let text = format!("{}  {}", PANE_NUMBERS[pane], session.name(id));
                let chosen = last.pane == Some(pane + 1);
                ui.label(if chosen {
                    RichText::new(text).strong()
                } else {
                    RichText::new(text)
                });
            }
            if ui.button("Next trial (Enter)").clicked() {
                action = Some(BlindAction::Next);
            }
        } else if let Some(last) = session.trials.last() {
            ui.weak(format!(
                "Answer to trial {} recorded; the panes are reshuffled.",
                last.trial
            ));
        }
        ui.separator();
        let summary = session.summary();
        ui.label(format!(
            "{} answers, {} without preference",
            summary.trials, summary.ties
        ));
        egui::CollapsingHeader::new("Wins per technique")
            .default_open(false)
            .show(ui, |ui| {
                ui.weak("(shows which technique each answer chose)");
                egui::Grid::new("blind wins").striped(true).show(ui, |ui| {
                    for heading in ["technique", "wins", "still", "in motion"] {
                        ui.weak(heading);
                    }
                    ui.end_row();
                    for wins in &summary.wins {
                        ui.label(&wins.name);
                        for n in [wins.wins, wins.still, wins.in_motion] {
                            ui.monospace(n.to_string());
                        }
                        ui.end_row();
                    }
                });
            });
        ui.separator();
        ui.label(
            RichText::new(format!("seed {}", session.seed))
                .small()
                .monospace(),
        )
        .on_hover_text("Every trial's order follows from the seed; the file records both");
        match &session.saved {
            Ok(answers) => ui.label(
                RichText::new(format!(
                    "{} ({answers} answers saved)",
                    session.path.display()
                ))
                .small(),
            ),
            Err(err) => ui.label(RichText::new(err).small().color(style::ERROR)),
        };
        if ui
            .button("End session")
            .on_hover_text("Show the names again; the answers file stays")
            .clicked()
        {
            action = Some(BlindAction::End);
        }
        action
    }
}

impl Workspace {
    /// Starts a blind session over the compared techniques (two to four), writing its answers
    /// into the export folder.
    pub(in crate::app) fn start_blind(&mut self, ctx: &egui::Context) {
        let ids = self.compared();
        if ids.len() < 2 {
            self.notify(
                Level::Warning,
                "A blind comparison needs at least two compared techniques: switch on another.",
            );
            return;
        }
        let techniques = ids.iter().map(|id| (*id, self.shown_label(id))).collect();
        let seed = SystemTime::now()
            .duration_since(UNIX_EPOCH)
            .map_or(0, |d| d.as_nanos() as u64);
        let scene = if self.images.is_open() {
            "images"
        } else {
            self.scene.as_ref().map_or("scene", |s| s.name.as_str())
        };
        let dir = self.settings.export_dir.clone();
        let stem = crate::files::free_stem(&dir, &format!("{scene}-blind"), &[".json".to_owned()]);
        let path = dir.join(format!("{stem}.json"));
        let adapter = format!("{} ({})", self.gpu.caps.adapter_name, self.gpu.caps.backend);
        match self.blind.start(techniques, seed, path, adapter, ctx) {
            Ok(()) => self.notify(
                Level::Info,
                "Blind comparison: the panes are numbered and shuffled; answer with 1–4 or 0.",
            ),
            Err(err) => self.notify(
                Level::Error,
                format!("cannot start the blind comparison: {err}"),
            ),
        }
    }

    /// The session's keys (before the shortcuts, which they take precedence over).
    pub(in crate::app) fn blind_keys(&mut self, ctx: &egui::Context) {
        if let Some(action) = self.blind.keys(ctx) {
            self.blind_act(action);
        }
    }

    /// A click on the pane of `slot` (viewport or magnifier) answers during a session.
    pub(in crate::app) fn blind_click(&mut self, slot: usize) {
        if self.blind.active() {
            self.blind_act(BlindAction::Answer(Choice::Pane(slot)));
        }
    }

    fn blind_act(&mut self, action: BlindAction) {
        match action {
            BlindAction::Answer(choice) => {
                let context = self.trial_context();
                self.blind.answer(choice, context);
            }
            BlindAction::Next => {
                if let Some(session) = self.blind.session.as_mut().filter(|s| s.revealed) {
                    session.next();
                }
            }
            BlindAction::End => {
                if let Some(session) = self.blind.session.take() {
                    let line = format!(
                        "Blind comparison ended: {} (in {})",
                        session.summary_line(),
                        session.path.display()
                    );
                    self.notify(Level::Info, line);
                }
            }
        }
    }

    /// What is on screen now, for an answer's record.
    fn trial_context(&self) -> TrialContext {
        let engine = self.engine.as_ref();
        let clip = engine
            .filter(|e| e.clip_shown())
            .and_then(|e| e.clip())
            .filter(|_| !self.images.is_open());
        let (shown, in_motion) = if let Some(set) = self.images.open() {
            let paths = set.images().iter().map(|i| i.path.clone()).collect();
            (OnScreen::Images { paths }, false)
        } else if let Some(clip) = clip {
            let frames = clip.frames.len();
            let playing = clip.player.playing && frames > 1;
            let shown = OnScreen::Clip {
                frame: clip.player.frame(frames),
                frames,
                playing,
                fps: clip.player.rate.fps(),
                ping_pong: clip.player.ping_pong,
                recipe: clip.recipe.clone(),
            };
            (shown, playing)
        } else {
            let moving = self.camera.moving_by_itself();
            let settings = self
                .compared()
                .into_iter()
                .filter_map(|id| Some((id, engine?.param_map(id))))
                .collect();
            let shown = OnScreen::Live {
                frame: self.camera.frame(),
                camera: self.camera.pose(),
                camera_moving: moving,
                settings,
            };
            (shown, moving)
        };
        let region = self
            .settings
            .show_magnifier
            .then(|| self.lens())
            .flatten()
            .map(|lens| Lens {
                x: lens.x,
                y: lens.y,
                width: lens.width,
                height: lens.height,
                zoom: self.settings.magnifier.zoom,
            });
        TrialContext {
            scene: self
                .scene
                .as_ref()
                .filter(|_| !self.images.is_open())
                .map_or_else(|| "images".to_owned(), |s| s.spec.clone()),
            in_motion,
            shown,
            layout: self.settings.layout,
            region,
            render_size: self.render_size,
        }
    }
}

/// The session's panel, in place of the techniques and metrics panels.
pub(in crate::app) fn panel(ui: &mut egui::Ui, ws: &mut Workspace) {
    let action = egui::Panel::right("blind comparison")
        .resizable(true)
        .default_size(280.0)
        .size_range(220.0..=480.0)
        .show(ui, |ui| {
            egui::ScrollArea::vertical()
                .show(ui, |ui| ws.blind.ui(ui))
                .inner
        })
        .inner;
    if let Some(action) = action {
        ws.blind_act(action);
    }
}
