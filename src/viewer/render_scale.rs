//! The 3D view's render scale, picked from measured frame times so that a large window on
//! software GL stays interactive (at least 30 frames a second where the machine allows it).
//!
//! On a software rasterizer the 3D pass costs in proportion to its pixels, so at scale $s$ a
//! frame takes about
//!
//! $$ F(s) = O + V \, (s / s_0)^2 $$
//!
//! where $V$ is the 3D view's part measured at the current scale $s_0$ and $O = F(s_0) - V$
//! everything else (egui, the refit, presenting). Solving $F(s) = T$ for a target frame time
//! $T$ gives the next scale. Medians over a window of frames keep one slow frame (a prepare
//! finishing, a texture upload) from moving it, and a band around the target keeps it from
//! hunting: the scale goes down when frames are slower than [`TARGET_MS`] and up only when
//! they are faster than [`RAISE_BELOW`] of it. Where no scale can meet the target (the rest
//! of the frame alone takes it), the view is not blurred for nothing: it is given about a
//! quarter of the rest's time.
//!
//! A scale the user sets (`--render-scale`, the panel's slider) turns the automatic choice off.

use super::display::MIN_SCALE;
use crate::study::median;

/// The frame time aimed for: 30 frames a second with 10% to spare.
pub const TARGET_MS: f64 = 0.9 * 1000.0 / 30.0;
/// Raise the scale only when frames take less than this fraction of [`TARGET_MS`].
pub const RAISE_BELOW: f64 = 0.6;
/// Frames per decision.
const WINDOW: usize = 8;
/// Frames ignored after a change (a new target is allocated) and at the start (shaders are
/// compiled, tables uploaded).
const SETTLE: usize = 3;
/// When the target cannot be met, the 3D view keeps this share of the rest of the frame.
const MIN_VIEW_SHARE: f64 = 0.25;
/// Scales are multiples of this: a change is always visible, and noise below it is ignored.
const STEP: f32 = 1.0 / 16.0;

/// The render scale and, when automatic, what it is chosen from.
#[derive(Clone, Debug, PartialEq)]
pub struct RenderScale {
    scale: f32,
    auto: bool,
    /// (whole frame, 3D view) milliseconds of the frames since the last decision.
    frames: Vec<(f64, f64)>,
    /// Frames still to ignore.
    settle: usize,
    /// Median frame time of the last full window, milliseconds.
    last_median_ms: Option<f64>,
}

impl RenderScale {
    /// Chosen from frame times, starting at full resolution.
    pub fn automatic() -> RenderScale {
        RenderScale { scale: 1.0, auto: true, frames: Vec::new(), settle: SETTLE, last_median_ms: None }
    }

    /// Fixed at `scale` (clamped to [`MIN_SCALE`]..=1).
    pub fn fixed(scale: f32) -> RenderScale {
        RenderScale { scale: clamp(scale), auto: false, ..RenderScale::automatic() }
    }

    /// The scale to render at now.
    pub fn scale(&self) -> f32 {
        self.scale
    }

    pub fn is_auto(&self) -> bool {
        self.auto
    }

    /// Median whole-frame time of the last window of frames, when one has been measured.
    pub fn median_frame_ms(&self) -> Option<f64> {
        self.last_median_ms
    }

    /// The user set a scale: it stays until automatic is chosen again.
    pub fn set_fixed(&mut self, scale: f32) {
        *self = RenderScale { last_median_ms: self.last_median_ms, ..RenderScale::fixed(scale) };
    }

    /// Back to choosing by itself, from the current scale.
    pub fn set_auto(&mut self) {
        if !self.auto {
            *self = RenderScale { scale: self.scale, last_median_ms: self.last_median_ms, ..RenderScale::automatic() };
        }
    }

    /// Records one frame: `frame_ms` the whole frame, `view_ms` the 3D view's part of it.
    /// Returns `true` when the scale changed.
    pub fn record(&mut self, frame_ms: f64, view_ms: f64) -> bool {
        if !(frame_ms.is_finite() && view_ms.is_finite() && frame_ms > 0.0) {
            return false;
        }
        if self.settle > 0 {
            self.settle -= 1;
            return false;
        }
        self.frames.push((frame_ms, view_ms.clamp(0.0, frame_ms)));
        if self.frames.len() < WINDOW {
            return false;
        }
        let frame = median(&self.frames.iter().map(|f| f.0).collect::<Vec<_>>());
        let view = median(&self.frames.iter().map(|f| f.1).collect::<Vec<_>>());
        self.frames.clear();
        self.last_median_ms = Some(frame);
        if !self.auto {
            return false;
        }
        let next = next_scale(self.scale, frame, view);
        if next == self.scale {
            return false;
        }
        self.scale = next;
        self.settle = SETTLE;
        true
    }
}

/// The scale after a window whose median frame took `frame` ms, `view` of them the 3D view,
/// at scale `scale` (the model of the module docs).
fn next_scale(scale: f32, frame: f64, view: f64) -> f32 {
    let slow = frame > TARGET_MS;
    let fast = frame < RAISE_BELOW * TARGET_MS && scale < 1.0;
    if !(slow || fast) {
        return scale;
    }
    let other = frame - view;
    let unreachable = slow && TARGET_MS <= (1.0 + MIN_VIEW_SHARE) * other;
    // Aim at the middle of the band when raising, so the next window does not fall back out.
    let target = if slow { TARGET_MS } else { 0.5 * (1.0 + RAISE_BELOW) * TARGET_MS };
    let wanted = if view <= 0.0 {
        // Nothing measured for the view: step, do not jump.
        if slow { scale - STEP } else { scale + STEP }
    } else if unreachable {
        // No scale reaches the target (egui or a loaded machine takes the frame): shrinking
        // the view further would cost its sharpness for little time, so it keeps to a
        // [`MIN_VIEW_SHARE`] of the rest.
        scale * (MIN_VIEW_SHARE * other / view).sqrt() as f32
    } else {
        scale * ((target - other) / view).sqrt() as f32
    };
    // Down in whole steps below the wanted scale, up in whole steps below it too (never
    // overshooting the target), and at least one step either way.
    let mut next = clamp((wanted / STEP).floor() * STEP);
    if unreachable {
        return next;
    }
    if slow && next >= scale {
        next = clamp(scale - STEP);
    }
    if fast && next <= scale {
        next = clamp(scale + STEP);
    }
    next
}

fn clamp(scale: f32) -> f32 {
    if scale.is_finite() {
        scale.clamp(MIN_SCALE, 1.0)
    } else {
        1.0
    }
}


#[cfg(test)]
mod tests {
    use super::*;

    /// A simulated machine: `other` ms of fixed work and `full_view` ms for the 3D view at
    /// scale 1, scaling with its pixels.
    fn run(scale: &mut RenderScale, other: f64, full_view: f64, frames: usize) -> Vec<f32> {
        let mut seen = Vec::new();
        for _ in 0..frames {
            let s = scale.scale() as f64;
            let view = full_view * s * s;
            scale.record(other + view, view);
            seen.push(scale.scale());
        }
        seen
    }

    #[test]
    fn a_slow_view_is_scaled_down_until_frames_meet_the_target_and_stays() {
        // The loaded machine: 45-62 ms a frame at full scale, about 40 of it the view.
        let mut s = RenderScale::automatic();
        let seen = run(&mut s, 14.0, 40.0, 200);
        let last = *seen.last().unwrap();
        let frame = 14.0 + 40.0 * (last as f64).powi(2);
        assert!(frame <= TARGET_MS, "settled at scale {last}: {frame:.1} ms a frame");
        // The largest step-multiple that meets the target: sqrt((30 - 14) / 40) = 0.632 -> 0.625.
        assert_eq!(last, 0.625, "{seen:?}");
        // It settled within a few windows and never moved after.
        let first = seen.iter().position(|&x| x == last).unwrap();
        assert!(first < 4 * (WINDOW + SETTLE), "settled after {first} frames");
        assert!(seen[first..].iter().all(|&x| x == last), "hunting: {seen:?}");
    }

    #[test]
    fn a_fast_machine_keeps_full_scale_and_a_recovering_one_goes_back_up() {
        let mut s = RenderScale::automatic();
        assert!(run(&mut s, 5.0, 10.0, 100).iter().all(|&x| x == 1.0));
        // Load comes and goes.
        let mut s = RenderScale::automatic();
        run(&mut s, 14.0, 60.0, 100);
        let low = s.scale();
        assert!(low < 0.6, "{low}");
        run(&mut s, 4.0, 12.0, 200);
        assert_eq!(s.scale(), 1.0, "the load went away");
    }

    #[test]
    fn when_nothing_is_fast_enough_the_view_keeps_a_quarter_of_the_rest() {
        // 45 ms of egui alone: no scale meets 30 ms. The view gets about 11 ms: 30 s^2 = 11.25
        // at s = 0.61, in steps of 1/16 below it: 0.5625.
        let mut s = RenderScale::automatic();
        run(&mut s, 45.0, 30.0, 200);
        assert_eq!(s.scale(), 0.5625);
        // A view that is the whole cost still goes down to the smallest scale.
        let mut s = RenderScale::automatic();
        run(&mut s, 2.0, 900.0, 200);
        assert_eq!(s.scale(), MIN_SCALE);
    }

    #[test]
    fn a_fixed_scale_is_never_changed_and_the_first_frames_are_ignored() {
        let mut s = RenderScale::fixed(0.5);
        run(&mut s, 30.0, 100.0, 100);
        assert_eq!(s.scale(), 0.5);
        assert!(s.median_frame_ms().unwrap() > 50.0, "still measured");
        // Automatic, with slow frames: nothing changes before a whole window after the start.
        let mut s = RenderScale::automatic();
        let seen = run(&mut s, 30.0, 100.0, SETTLE + WINDOW - 1);
        assert!(seen.iter().all(|&x| x == 1.0), "{seen:?}");
        s.set_fixed(0.8);
        assert_eq!((s.scale(), s.is_auto()), (0.8, false));
        assert_eq!(RenderScale::fixed(f32::NAN).scale(), 1.0);
        assert_eq!(RenderScale::fixed(0.01).scale(), MIN_SCALE);
    }

    #[test]
    fn median_of_even_and_odd_counts() {
        assert_eq!(median(&[3.0, 1.0, 2.0]), 2.0);
        assert_eq!(median(&[4.0, 1.0, 2.0, 3.0]), 2.5);
    }
}
