//! The progress bar of the commands that work face by face (`mesh`, its
//! regularization, `field`).

use std::sync::Arc;

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

/// A "`label [bar] done/total faces`" progress bar on stderr, or nothing when quiet.
pub struct FaceProgress {
    bar: Option<ProgressBar>,
}

impl FaceProgress {
    /// A bar over `faces` faces, labelled `label`; none when `quiet`.
    pub fn new(quiet: bool, faces: usize, label: &str) -> Self {
        let bar = (!quiet).then(|| {
            let b = ProgressBar::new(faces as u64);
            b.set_style(
                ProgressStyle::with_template(&format!(
                    "{label} {{bar:30}} {{pos}}/{{len}} faces {{elapsed}}"
                ))
                .unwrap_or_else(|_| ProgressStyle::default_bar()),
            );
            b
        });
        FaceProgress { bar }
    }

    /// The callback the library calls as faces finish.
    pub fn callback(&self) -> Option<quadrille::ProgressFn> {
        self.bar.clone().map(|b| -> quadrille::ProgressFn {
            Arc::new(move |done, total| {
                b.set_length(total as u64);
                b.set_position(done as u64)
            })
        })
    }

    /// The same bar, not drawn until its callback is first called (a
    /// second phase's bar, made before the work starts).
    pub fn hidden_until_first(self) -> Self {
        if let Some(b) = &self.bar {
            b.set_draw_target(ProgressDrawTarget::hidden());
        }
        self
    }

    /// [`FaceProgress::callback`] for a second phase after `first`: its first
    /// call clears `first`'s bar and shows this one.
    pub fn callback_after(&self, first: &FaceProgress) -> Option<quadrille::ProgressFn> {
        let bar = self.bar.clone()?;
        let first = first.bar.clone();
        let shown = std::sync::Once::new();
        Some(Arc::new(move |done, total| {
            shown.call_once(|| {
                if let Some(f) = &first {
                    f.finish_and_clear();
                }
                bar.set_draw_target(ProgressDrawTarget::stderr());
            });
            bar.set_length(total as u64);
            bar.set_position(done as u64)
        }))
    }

    /// Removes the bar from the terminal.
    pub fn finish(&self) {
        if let Some(b) = &self.bar {
            b.finish_and_clear();
        }
    }
}
