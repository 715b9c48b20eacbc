//! Loads scenes on a worker thread (procedural generation and OBJ parsing can take seconds), so
//! the window keeps responding; the UI polls for the result once per frame and wakes up when
//! the worker finishes. A newer request supersedes an older one still running.

use std::sync::mpsc;
use std::thread;

use crate::scene::Scene;
use crate::scene::procedural::SceneOptions;
use crate::scene::source::{self, SceneError};

/// Why a scene did not load.
#[derive(Debug, thiserror::Error)]
pub enum LoadError {
    /// The scene source rejected it (unknown name, unreadable or malformed file).
    #[error(transparent)]
    Scene(#[from] SceneError),
    /// The worker thread could not start or died without an answer.
    #[error("loading {0} failed: {1}")]
    Worker(String, String),
}

/// A finished load.
pub struct Loaded {
    /// What was asked for (built-in name or path).
    pub spec: String,
    /// The scene, or why it could not be loaded.
    pub result: Result<Scene, LoadError>,
}

/// See the module docs.
#[derive(Default)]
pub struct SceneLoader {
    pending: Option<(String, mpsc::Receiver<Loaded>)>,
}

impl SceneLoader {
    /// Starts loading `spec` (a built-in scene name or an OBJ path); `wake` is called from the
    /// worker when it is done.
    pub fn load(&mut self, spec: &str, wake: impl FnOnce() + Send + 'static) {
        let (sender, receiver) = mpsc::channel();
        let owned = spec.to_owned();
        let failed = sender.clone();
        let worker = thread::Builder::new()
            .name("aa-lab scene loader".to_owned())
            .spawn(move || {
                super::worker::lower_priority();
                let result = source::load(&owned, &SceneOptions::default()).map_err(Into::into);
                let _ = sender.send(Loaded {
                    spec: owned,
                    result,
                });
                wake();
            });
        if let Err(err) = worker {
            let _ = failed.send(Loaded {
                spec: spec.to_owned(),
                result: Err(LoadError::Worker(spec.to_owned(), err.to_string())),
            });
        }
        self.pending = Some((spec.to_owned(), receiver));
    }

    /// What is being loaded, if anything.
    pub fn loading(&self) -> Option<&str> {
        self.pending.as_ref().map(|(spec, _)| spec.as_str())
    }

    /// The finished load, if the worker is done.
    pub fn poll(&mut self) -> Option<Loaded> {
        let (_, receiver) = self.pending.as_ref()?;
        match receiver.try_recv() {
            Ok(loaded) => {
                self.pending = None;
                Some(loaded)
            }
            Err(mpsc::TryRecvError::Empty) => None,
            Err(mpsc::TryRecvError::Disconnected) => {
                let (spec, _) = self.pending.take()?;
                Some(Loaded {
                    result: Err(LoadError::Worker(
                        spec.clone(),
                        "the loader thread stopped without an answer".to_owned(),
                    )),
                    spec,
                })
            }
        }
    }
}
