//! What the viewer tells the user: the state it is in, the last thing that happened, the
//! last error, and the stroke → frame timings.

use crate::live::Refit;

/// The status line's parts.
#[derive(Default)]
pub(super) struct Status {
    /// The last thing that happened ("saved material to …") and the paintings' stamp then
    /// ([`super::easel::Easel::stamp`]): shown only while the paintings are unchanged, so it
    /// never describes a state that is gone.
    note: Option<(String, u64)>,
    /// The last error, until the next success.
    pub error: Option<String>,
}

impl Status {
    pub fn note(&mut self, text: impl Into<String>, stamp: u64) {
        self.note = Some((text.into(), stamp));
    }

    /// The note, while the paintings' stamp is still `stamp`.
    pub fn note_for(&self, stamp: u64) -> Option<&str> {
        self.note.as_ref().filter(|n| n.1 == stamp).map(|n| n.0.as_str())
    }

    pub fn fail(&mut self, text: impl Into<String>) {
        self.error = Some(text.into());
    }
}

/// Rolling stroke → frame timings, milliseconds.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize)]
pub struct Timings {
    pub stroke_ms: f64,
    pub values_ms: f64,
    pub solve_ms: f64,
    pub upload_ms: f64,
    /// The whole window frame: the 3D view and the egui panel, to `glFinish`.
    pub frame_ms: f64,
    /// The 3D view's part of the frame.
    pub view_ms: f64,
    pub total_ms: f64,
    /// Samples of the last refit.
    pub samples: usize,
    /// Refits measured.
    pub count: usize,
}

/// Collects one stroke's way to the screen over the frame that shows it.
#[derive(Default)]
pub(super) struct TimingMeter {
    pub timings: Timings,
    /// Canvas work of the strokes since the last frame.
    pub stroke_ms: f64,
    /// A live refit waiting for the frame that shows it.
    pub pending: Option<Refit>,
    /// The last refit (live or full), for the panel.
    pub last: Option<Refit>,
}

impl TimingMeter {
    /// Completes the stroke → frame timing when this frame showed a refit.
    pub fn frame_done(&mut self, frame_ms: f64, view_ms: f64) {
        if let Some(r) = self.pending.take() {
            let t = &mut self.timings;
            t.stroke_ms = self.stroke_ms;
            t.values_ms = r.values_ms;
            t.solve_ms = r.solve_ms;
            t.frame_ms = frame_ms;
            t.view_ms = view_ms;
            t.total_ms = t.stroke_ms + t.values_ms + t.solve_ms + t.upload_ms + t.frame_ms;
            t.samples = r.samples;
            t.count += 1;
        }
        self.stroke_ms = 0.0;
    }
}
