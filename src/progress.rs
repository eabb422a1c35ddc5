//! Progress of a long computation, for a display: one type for the validated flow, the
//! figures, the stability table and the orders. It is told what is being done and how far
//! along; it sees nothing else and cannot change a result. A leaf: it imports nothing.

use std::sync::Arc;

/// Told `(what, done, total)` as work proceeds: `done` of `total` units (steps, cases, or,
/// for a flow, the time reached of the time asked for). `Progress::default()` is silent.
///
/// ```
/// use dalembert::{flow, FlowOptions, Model, Progress};
/// use std::sync::{Arc, Mutex};
/// let model = Model::new(&dalembert::AnyScene::new("knife", &[]).unwrap()).unwrap();
/// let seen = Arc::new(Mutex::new(0.0));
/// let s = seen.clone();
/// let opts = FlowOptions::default()
///     .with_progress(Progress::new(move |_what, done, total| *s.lock().unwrap() = done / total));
/// flow(&model, &[0.0, 0.0, 0.0], &[0.8, 0.8], 1.0, &opts).unwrap();
/// assert_eq!(*seen.lock().unwrap(), 1.0);
/// ```
#[derive(Clone, Default)]
pub struct Progress(Option<Arc<Told>>);

/// What a [`Progress`] calls.
type Told = dyn Fn(&str, f64, f64) + Send + Sync;

impl Progress {
    /// A progress told to `f(what, done, total)`.
    pub fn new(f: impl Fn(&str, f64, f64) + Send + Sync + 'static) -> Self {
        Progress(Some(Arc::new(f)))
    }

    /// Tell `done` of `total` units of `what` (nothing when silent).
    pub fn tell(&self, what: &str, done: f64, total: f64) {
        if let Some(f) = &self.0 {
            f(what, done, total)
        }
    }

    /// Counts as [`Progress::tell`] does (`done` of `total` items).
    pub fn count(&self, what: &str, done: usize, total: usize) {
        self.tell(what, done as f64, total as f64)
    }

    /// Whether this progress is told anything (the default is not).
    pub fn is_silent(&self) -> bool {
        self.0.is_none()
    }
}

impl std::fmt::Debug for Progress {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(if self.is_silent() {
            "Progress(silent)"
        } else {
            "Progress"
        })
    }
}
