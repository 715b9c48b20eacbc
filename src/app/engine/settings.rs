//! The techniques' settings as the UI mirrors them (and the two options every scene render
//! follows: specular antialiasing and the UI overlay): switching techniques on and off,
//! parameters validated against the mirrored descriptions and applied at once (the render
//! thread answers with the authoritative values), presets, debug views, records of a
//! technique's settings, and user techniques added, removed and announced.

use super::*;

impl Engine {
    /// Whether the techniques' scene renders have geometric specular antialiasing.
    pub fn specular_aa(&self) -> bool {
        self.specular_aa
    }

    /// Turns geometric specular antialiasing on or off in every technique's scene render but
    /// the reference's; everything renders again, as after a scene change.
    pub fn set_specular_aa(&mut self, on: bool) {
        if on != self.specular_aa {
            self.specular_aa = on;
            self.send(Command::SpecularAa(on));
            self.scene_generation += 1;
        }
    }

    /// Draws the UI overlay over every frame (before or after the antialiasing) or not: every
    /// output and the reference start over, as after a scene change.
    pub fn set_overlay(&mut self, order: Option<OverlayOrder>) {
        if order != self.overlay {
            self.overlay = order;
            self.send(Command::Overlay(order));
            self.scene_generation += 1;
            self.memory = None;
            self.discard_clip();
        }
    }

    /// The tonemap choice and exposure every render follows.
    pub fn tonemap(&self) -> (TonemapChoice, f32) {
        self.tonemap
    }

    /// Shows the scene through `choice` at `exposure` stops (see `graph::hdr`): every output and
    /// the reference start over, as after a scene change.
    pub fn set_tonemap(&mut self, choice: TonemapChoice, exposure: f32) {
        if (choice, exposure) != self.tonemap {
            self.tonemap = (choice, exposure);
            self.send(Command::Tonemap(choice, exposure));
            self.scene_generation += 1;
            self.memory = None;
            self.discard_clip();
        }
    }

    /// Switches a technique on or off (unavailable ones stay off).
    pub fn set_enabled(&mut self, id: &str, on: bool) {
        if let Some(entry) = self.entries.iter_mut().find(|e| e.id == id)
            && entry.switchable()
        {
            entry.enabled = on;
        }
    }

    /// A technique's parameters with their current values (none until the render thread has
    /// created it).
    pub fn params(&self, id: &str) -> Vec<Param> {
        self.entry(id)
            .and_then(|e| e.settings.as_ref())
            .map(|s| s.params.clone())
            .unwrap_or_default()
    }

    /// A technique's presets.
    pub fn presets(&self, id: &str) -> &'static [&'static str] {
        self.entry(id)
            .and_then(|e| e.settings.as_ref())
            .map_or(&[], |s| s.presets)
    }

    /// Which code path a technique runs on this adapter, when it has a choice.
    pub fn path_note(&self, id: &str) -> Option<String> {
        self.entry(id)
            .and_then(|e| e.settings.as_ref())
            .and_then(|s| s.path_note.clone())
    }

    /// The content hash of a user technique's file, as the render thread built it.
    pub fn source_hash(&self, id: &str) -> Option<String> {
        self.entry(id)
            .and_then(|e| e.settings.as_ref())
            .and_then(|s| s.source_hash.clone())
    }

    /// The settings of a technique as a map (sidecar form).
    pub fn param_map(&self, id: &str) -> aa::ParamMap {
        self.params(id)
            .into_iter()
            .map(|p| (p.key.to_owned(), p.value))
            .collect()
    }

    /// A technique with its current settings, as records keep it.
    pub fn technique_spec(&self, id: &str) -> crate::spec::TechniqueSpec {
        crate::spec::TechniqueSpec {
            id: id.to_owned(),
            settings: self.param_map(id),
            source_hash: self.source_hash(id),
        }
    }

    /// Sends a settings change and marks the technique for re-rendering.
    fn configure(&mut self, index: usize, change: SettingsChange) {
        self.send(Command::Configure(index, change));
        let entry = &mut self.entries[index];
        entry.dirty = true;
        entry.revision += 1;
    }

    /// Validates a value against the mirrored description and stores it in the mirror.
    fn validate_into_mirror(
        &mut self,
        index: usize,
        key: &str,
        value: ParamValue,
    ) -> Result<ParamValue, ParamError> {
        let entry = &mut self.entries[index];
        let Some(settings) = &mut entry.settings else {
            // Not created yet: the render thread validates and reports.
            return Ok(value);
        };
        let (position, value) = validate_setting(&settings.params, entry.id, key, value)?;
        settings.params[position].value = value.clone();
        Ok(value)
    }

    /// Sets one parameter (validated).
    pub fn set_param(&mut self, id: &str, key: &str, value: ParamValue) -> Result<(), ParamError> {
        let Some(index) = self.index(id) else {
            return Ok(());
        };
        let value = self.validate_into_mirror(index, key, value)?;
        self.configure(index, SettingsChange::Param(key.to_owned(), value));
        Ok(())
    }

    /// Restores a whole settings map (from the saved settings).
    pub fn apply_param_map(&mut self, id: &str, map: &aa::ParamMap) -> Result<(), ParamError> {
        let Some(index) = self.index(id) else {
            return Ok(());
        };
        let mut valid = aa::ParamMap::new();
        for (key, value) in map {
            valid.insert(
                key.clone(),
                self.validate_into_mirror(index, key, value.clone())?,
            );
        }
        self.configure(index, SettingsChange::Map(valid));
        Ok(())
    }

    /// Applies a preset.
    pub fn apply_preset(&mut self, id: &str, preset: &str) -> Result<(), ParamError> {
        let Some(index) = self.index(id) else {
            return Ok(());
        };
        let known = self.presets(id);
        if self.entries[index].settings.is_some() && !known.contains(&preset) {
            return Err(ParamError::UnknownPreset {
                technique: id.to_owned(),
                name: preset.to_owned(),
                known: known.join(", "),
            });
        }
        self.configure(index, SettingsChange::Preset(preset.to_owned()));
        Ok(())
    }

    /// Shows a debug view (by name; empty for the first one) instead of a technique's output,
    /// or the output (`None`). The technique computes its debug views only while one is shown.
    pub fn set_debug_view(&mut self, id: &str, view: Option<String>) {
        let Some(index) = self.index(id) else {
            return;
        };
        let entry = &mut self.entries[index];
        let was_on = entry.debug_view.is_some();
        let on = view.is_some();
        entry.debug_view = view;
        if !on {
            entry.debug_images.clear();
        }
        if on != was_on {
            self.configure(index, SettingsChange::DebugViews(on));
        }
    }

    /// Adds the user technique in `path` (see `aa::user`), or rebuilds it if it is there:
    /// the render thread reads and builds it, and it appears in [`Engine::entries`], switched
    /// on, when it answers (with its error when the file does not build).
    pub fn add_user_technique(&mut self, path: std::path::PathBuf) {
        self.send(Command::AddUser(path));
    }

    /// Adds the combination `id` (a canonical `aa::combo` id with a scale, upscaler or
    /// sharpening): the render thread creates it and it appears in [`Engine::entries`],
    /// switched on, when it answers (with its error when it cannot run here).
    pub fn add_combination(&mut self, id: &'static str) {
        self.send(Command::AddCombination(id));
    }

    /// Removes the user technique or combination `id` from the comparison: it is switched off
    /// and no longer listed (a user technique's file no longer watched); adding it again
    /// brings it back.
    pub fn remove_user_technique(&mut self, id: &str) {
        let Some(index) = self.index(id).filter(|_| is_added(id)) else {
            return;
        };
        let entry = &mut self.entries[index];
        entry.removed = true;
        entry.enabled = false;
        self.send(Command::RemoveUser(index));
    }

    /// The entry of the user technique or combination at `index`: a new one at the next index (switched off
    /// until its first build works).
    pub(super) fn user_entry(
        &mut self,
        index: usize,
        id: &'static str,
        name: &str,
    ) -> Option<&mut TechniqueEntry> {
        if index == self.entries.len() {
            let summary = match aa::user::path_of(id) {
                Some(path) => format!(
                    "Your technique from {}: a post-process pass over the scene render, \
                     reloaded when the file changes.",
                    path.display()
                ),
                None => format!(
                    "{id}: the technique at a render scale, upscaled to the output size (and \
                     sharpened), measured against the native reference like any other."
                ),
            };
            self.entries.push(TechniqueEntry::new(
                id,
                aa::user::intern(name),
                aa::user::intern(&summary),
                Ok(()),
            ));
        }
        self.entries.get_mut(index)
    }

    /// A user technique's (re)build from the render thread: new settings and a re-render, or
    /// the error of its file.
    pub(super) fn user_technique(
        &mut self,
        index: usize,
        id: &'static str,
        name: &str,
        result: Result<TechniqueSettings, String>,
        publication: &mut Publication,
    ) {
        let Some(entry) = self.user_entry(index, id, name) else {
            return;
        };
        entry.building = None;
        // A build (after the file was added again) lists it again.
        let returning = std::mem::take(&mut entry.removed);
        match result {
            Ok(settings) => {
                // The first build that works switches it on, and so does the first after the
                // file was added again.
                if entry.settings.is_none() || returning {
                    entry.enabled = true;
                    publication.added_users.push(id);
                }
                entry.availability = Ok(());
                entry.settings = Some(settings);
                entry.problem = None;
                entry.dirty = true;
                entry.revision += 1;
            }
            Err(error) => {
                publication.problems.push(error.clone());
                if entry.settings.is_some() {
                    entry.problem = Some(error);
                } else {
                    entry.availability = Err(error);
                    entry.enabled = false;
                }
            }
        }
    }

    pub(super) fn ready_techniques(&mut self, techniques: Vec<Result<TechniqueSettings, String>>) {
        for (entry, created) in self.entries.iter_mut().zip(techniques) {
            match created {
                Ok(settings) => {
                    // Changes sent before the thread was ready were applied in order after
                    // the creation; the mirror takes the thread's view of them with the next
                    // settings event, and the creation defaults until then.
                    entry.settings.get_or_insert(settings);
                }
                Err(reason) if entry.available() => {
                    entry.availability = Err(reason);
                    entry.enabled = false;
                }
                Err(_) => {}
            }
        }
    }
}

/// Whether `id` is one the user added (a user technique or a combination) rather than a
/// registry technique: it can be removed.
pub fn is_added(id: &str) -> bool {
    aa::user::is_user_id(id) || aa::combo::Combo::parse(id).is_ok_and(|c| !c.is_plain())
}
