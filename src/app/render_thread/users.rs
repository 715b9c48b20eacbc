//! Techniques the user adds on the render thread. User techniques: adding a WGSL file, building
//! its pipelines on a thread of their own (`aa::user::build`) so a slow driver compile stalls
//! nothing, installing a finished build, and rebuilding when the file changes (the last good
//! build runs on while a change does not compile). Combinations (`aa::combo`: a technique at a
//! render scale, upscaled, sharpened): created at once and installed the same way, at the
//! next index.

use super::*;

impl RenderState {
    /// The registry index of the added technique `id`: the one it had, or the next one.
    fn added_index(&mut self, id: &'static str) -> usize {
        match self.user_ids.iter().find(|(_, known)| *known == id) {
            Some(&(index, _)) => index,
            None => {
                let index = self.slots.len();
                self.slots.push(None);
                self.user_ids.push((index, id));
                index
            }
        }
    }

    /// Adds the combination `id` (a technique at a render scale, with an upscaler or
    /// sharpening) at the next registry index, with its error when it cannot run here; one
    /// already added keeps its index and settings.
    pub(super) fn add_combination(&mut self, id: &'static str, send: &dyn Fn(Event)) {
        let index = self.added_index(id);
        if let Some(slot) = self.slots[index] {
            let technique = self.graph.slots()[slot].technique.as_ref();
            return send(Event::UserTechnique {
                index,
                id,
                name: aa::registry::display_name(id),
                result: Ok(TechniqueSettings::of(technique)),
            });
        }
        let created = aa::create(&self.gpu, id).map_err(|e| e.to_string());
        send(self.install_added(index, id, aa::registry::display_name(id), created));
    }

    /// Adds the user technique of `path` at the next registry index (with its error, when it
    /// does not build), or rebuilds it when it was added before.
    pub(super) fn add_user(&mut self, path: &std::path::Path, send: &dyn Fn(Event)) {
        let id = match aa::user::interned_id(path) {
            Ok(id) => id,
            Err(err) => return send(Event::UserRefused(err.to_string())),
        };
        let index = self.added_index(id);
        // (Again after a removal.)
        self.watcher
            .watch(index, aa::user::path_of(id).unwrap_or(path));
        send(self.build_user(index, id));
    }

    /// Starts building the user technique at `index` from its file (see the module docs).
    fn build_user(&mut self, index: usize, id: &'static str) -> Event {
        self.builds.retain(|(building, _)| *building != index);
        self.builds
            .push((index, PendingBuild::start(&self.gpu, id)));
        Event::UserBuilding {
            index,
            id,
            name: aa::user::display_name(id),
        }
    }

    /// Installs the user techniques whose builds finished, keeping the settings of the builds
    /// they replace where they still apply.
    pub(super) fn finish_user_builds(&mut self, send: &dyn Fn(Event)) {
        let mut finished = Vec::new();
        self.builds.retain(|(index, build)| match build.finished() {
            Some(result) => {
                finished.push((*index, build.id(), result));
                false
            }
            None => true,
        });
        for (index, id, result) in finished {
            let result = result.map_err(|e| e.to_string());
            send(self.install_added(index, id, aa::user::display_name(id), result));
        }
    }

    /// Puts a user technique's finished build, or a created combination, at `index` in the
    /// graph (replacing the build before, whose settings carry over where they still apply).
    fn install_added(
        &mut self,
        index: usize,
        id: &'static str,
        name: String,
        result: Result<Box<dyn aa::Technique>, String>,
    ) -> Event {
        let result = result.map(|mut technique| {
            if let Some(slot) = self.slots[index] {
                let previous = aa::param_map(self.graph.slots()[slot].technique.as_ref());
                for (key, value) in previous {
                    // A setting the new file no longer has (or ranges differently) is dropped.
                    let _ = aa::set_param(technique.as_mut(), &key, value);
                }
            }
            let settings = TechniqueSettings::of(technique.as_ref());
            match self.slots[index] {
                Some(slot) => self.graph.slots_mut()[slot].technique = technique,
                None => {
                    let slot = self.graph.add(technique);
                    self.graph.slots_mut()[slot].enabled = false;
                    self.slots[index] = Some(slot);
                }
            }
            settings
        });
        Event::UserTechnique {
            index,
            id,
            name,
            result,
        }
    }

    /// Rebuilds the user techniques whose files changed (looked at about once a second).
    pub(super) fn reload_user_techniques(&mut self, send: &dyn Fn(Event)) {
        for index in self.watcher.changed(std::time::Instant::now()) {
            if let Some(&(_, id)) = self.user_ids.iter().find(|(i, _)| *i == index) {
                send(self.build_user(index, id));
            }
        }
    }
}
