//! The paint tools: which tool, the brush, the guides under the painting.

use crate::live::Brush;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Tool {
    Brush,
    Eraser,
    Fill,
}

/// Smallest and largest brush radius, canvas pixels.
pub const RADIUS: std::ops::RangeInclusive<f32> = 1.0..=200.0;
/// `[` and `]` change the radius by this factor.
const RADIUS_STEP: f32 = 1.25;

pub(super) struct PaintTools {
    pub tool: Tool,
    /// Colour, size, hardness, opacity (its `erase` flag is set by the tool in use).
    pub brush: Brush,
    /// Draw the outline over the painting.
    pub show_outline: bool,
    /// Draw the reference image under the painting.
    pub show_reference: bool,
    /// Where "Save painting" writes.
    pub save_painting: String,
}

impl Default for PaintTools {
    fn default() -> Self {
        PaintTools {
            tool: Tool::Brush,
            brush: Brush::default(),
            show_outline: true,
            show_reference: true,
            save_painting: "painting.png".into(),
        }
    }
}

impl PaintTools {
    /// The brush a stroke starts with: erasing with the eraser.
    pub fn stroke_brush(&self) -> Brush {
        Brush { erase: self.tool == Tool::Eraser, ..self.brush }
    }

    pub fn smaller(&mut self) {
        self.brush.radius = (self.brush.radius / RADIUS_STEP).max(*RADIUS.start());
    }

    pub fn larger(&mut self) {
        self.brush.radius = (self.brush.radius * RADIUS_STEP).min(*RADIUS.end());
    }
}
