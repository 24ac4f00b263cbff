//! Words on pictures: a 5×9 bitmap font (printable ASCII and a few signs: × ° ² · …),
//! drawn at an integer scale into linear RGB images, each label on a dark box so it reads
//! over any picture. No font files and no rasterizer: every glyph is a constant below, one
//! row of five bits per line (bit 4 is the leftmost column), rows 0-6 from the cap line to
//! the baseline and rows 7-8 for descenders.
//!
//! At scale 2 with even coordinates and padding, a picture shrunk by 2 (a 2 × 2 box filter,
//! as the demo's `contact-small.png`) shows the same text at scale 1, still sharp.

use super::Rgb;

/// Columns of a glyph.
pub const GLYPH_WIDTH: usize = 5;
/// Rows of a glyph: 7 above the baseline, 2 below.
pub const GLYPH_HEIGHT: usize = 9;
/// Columns from one character to the next: the glyph and one blank column.
pub const ADVANCE: usize = GLYPH_WIDTH + 1;

/// The glyphs, ASCII 32-126 in order, then the extra signs.
#[rustfmt::skip]
const GLYPHS: [(char, [u8; GLYPH_HEIGHT]); 100] = [
    (' ', [0b00000, 0b00000, 0b00000, 0b00000, 0b00000, 0b00000, 0b00000, 0b00000, 0b00000]),
    ('!', [0b00100, 0b00100, 0b00100, 0b00100, 0b00100, 0b00000, 0b00100, 0b00000, 0b00000]),
    ('"', [0b01010, 0b01010, 0b01010, 0b00000, 0b00000, 0b00000, 0b00000, 0b00000, 0b00000]),
    ('#', [0b01010, 0b01010, 0b11111, 0b01010, 0b11111, 0b01010, 0b01010, 0b00000, 0b00000]),
    ('$', [0b00100, 0b01111, 0b10100, 0b01110, 0b00101, 0b11110, 0b00100, 0b00000, 0b00000]),
    ('%', [0b11000, 0b11001, 0b00010, 0b00100, 0b01000, 0b10011, 0b00011, 0b00000, 0b00000]),
    ('&', [0b01100, 0b10010, 0b10100, 0b01000, 0b10101, 0b10010, 0b01101, 0b00000, 0b00000]),
    ('\'', [0b00100, 0b00100, 0b01000, 0b00000, 0b00000, 0b00000, 0b00000, 0b00000, 0b00000]),
    ('(', [0b00010, 0b00100, 0b01000, 0b01000, 0b01000, 0b00100, 0b00010, 0b00000, 0b00000]),
    (')', [0b01000, 0b00100, 0b00010, 0b00010, 0b00010, 0b00100, 0b01000, 0b00000, 0b00000]),
    ('*', [0b00000, 0b00100, 0b10101, 0b01110, 0b10101, 0b00100, 0b00000, 0b00000, 0b00000]),
    ('+', [0b00000, 0b00100, 0b00100, 0b11111, 0b00100, 0b00100, 0b00000, 0b00000, 0b00000]),
    (',', [0b00000, 0b00000, 0b00000, 0b00000, 0b00000, 0b01100, 0b01100, 0b00100, 0b01000]),
    ('-', [0b00000, 0b00000, 0b00000, 0b11111, 0b00000, 0b00000, 0b00000, 0b00000, 0b00000]),
    ('.', [0b00000, 0b00000, 0b00000, 0b00000, 0b00000, 0b01100, 0b01100, 0b00000, 0b00000]),
    ('/', [0b00000, 0b00001, 0b00010, 0b00100, 0b01000, 0b10000, 0b00000, 0b00000, 0b00000]),
    ('0', [0b01110, 0b10001, 0b10011, 0b10101, 0b11001, 0b10001, 0b01110, 0b00000, 0b00000]),
    ('1', [0b00100, 0b01100, 0b00100, 0b00100, 0b00100, 0b00100, 0b01110, 0b00000, 0b00000]),
    ('2', [0b01110, 0b10001, 0b00001, 0b00010, 0b00100, 0b01000, 0b11111, 0b00000, 0b00000]),
    ('3', [0b11111, 0b00010, 0b00100, 0b00010, 0b00001, 0b10001, 0b01110, 0b00000, 0b00000]),
    ('4', [0b00010, 0b00110, 0b01010, 0b10010, 0b11111, 0b00010, 0b00010, 0b00000, 0b00000]),
    ('5', [0b11111, 0b10000, 0b11110, 0b00001, 0b00001, 0b10001, 0b01110, 0b00000, 0b00000]),
    ('6', [0b00110, 0b01000, 0b10000, 0b11110, 0b10001, 0b10001, 0b01110, 0b00000, 0b00000]),
    ('7', [0b11111, 0b00001, 0b00010, 0b00100, 0b01000, 0b01000, 0b01000, 0b00000, 0b00000]),
    ('8', [0b01110, 0b10001, 0b10001, 0b01110, 0b10001, 0b10001, 0b01110, 0b00000, 0b00000]),
    ('9', [0b01110, 0b10001, 0b10001, 0b01111, 0b00001, 0b00010, 0b01100, 0b00000, 0b00000]),
    (':', [0b00000, 0b01100, 0b01100, 0b00000, 0b01100, 0b01100, 0b00000, 0b00000, 0b00000]),
    (';', [0b00000, 0b01100, 0b01100, 0b00000, 0b01100, 0b01100, 0b00100, 0b01000, 0b00000]),
    ('<', [0b00010, 0b00100, 0b01000, 0b10000, 0b01000, 0b00100, 0b00010, 0b00000, 0b00000]),
    ('=', [0b00000, 0b00000, 0b11111, 0b00000, 0b11111, 0b00000, 0b00000, 0b00000, 0b00000]),
    ('>', [0b01000, 0b00100, 0b00010, 0b00001, 0b00010, 0b00100, 0b01000, 0b00000, 0b00000]),
    ('?', [0b01110, 0b10001, 0b00001, 0b00010, 0b00100, 0b00000, 0b00100, 0b00000, 0b00000]),
    ('@', [0b01110, 0b10001, 0b00001, 0b01101, 0b10101, 0b10101, 0b01110, 0b00000, 0b00000]),
    ('A', [0b01110, 0b10001, 0b10001, 0b11111, 0b10001, 0b10001, 0b10001, 0b00000, 0b00000]),
    ('B', [0b11110, 0b10001, 0b10001, 0b11110, 0b10001, 0b10001, 0b11110, 0b00000, 0b00000]),
    ('C', [0b01110, 0b10001, 0b10000, 0b10000, 0b10000, 0b10001, 0b01110, 0b00000, 0b00000]),
    ('D', [0b11100, 0b10010, 0b10001, 0b10001, 0b10001, 0b10010, 0b11100, 0b00000, 0b00000]),
    ('E', [0b11111, 0b10000, 0b10000, 0b11110, 0b10000, 0b10000, 0b11111, 0b00000, 0b00000]),
    ('F', [0b11111, 0b10000, 0b10000, 0b11110, 0b10000, 0b10000, 0b10000, 0b00000, 0b00000]),
    ('G', [0b01110, 0b10001, 0b10000, 0b10111, 0b10001, 0b10001, 0b01111, 0b00000, 0b00000]),
    ('H', [0b10001, 0b10001, 0b10001, 0b11111, 0b10001, 0b10001, 0b10001, 0b00000, 0b00000]),
    ('I', [0b01110, 0b00100, 0b00100, 0b00100, 0b00100, 0b00100, 0b01110, 0b00000, 0b00000]),
    ('J', [0b00111, 0b00010, 0b00010, 0b00010, 0b00010, 0b10010, 0b01100, 0b00000, 0b00000]),
    ('K', [0b10001, 0b10010, 0b10100, 0b11000, 0b10100, 0b10010, 0b10001, 0b00000, 0b00000]),
    ('L', [0b10000, 0b10000, 0b10000, 0b10000, 0b10000, 0b10000, 0b11111, 0b00000, 0b00000]),
    ('M', [0b10001, 0b11011, 0b10101, 0b10101, 0b10001, 0b10001, 0b10001, 0b00000, 0b00000]),
    ('N', [0b10001, 0b10001, 0b11001, 0b10101, 0b10011, 0b10001, 0b10001, 0b00000, 0b00000]),
    ('O', [0b01110, 0b10001, 0b10001, 0b10001, 0b10001, 0b10001, 0b01110, 0b00000, 0b00000]),
    ('P', [0b11110, 0b10001, 0b10001, 0b11110, 0b10000, 0b10000, 0b10000, 0b00000, 0b00000]),
    ('Q', [0b01110, 0b10001, 0b10001, 0b10001, 0b10101, 0b10010, 0b01101, 0b00000, 0b00000]),
    ('R', [0b11110, 0b10001, 0b10001, 0b11110, 0b10100, 0b10010, 0b10001, 0b00000, 0b00000]),
    ('S', [0b01111, 0b10000, 0b10000, 0b01110, 0b00001, 0b00001, 0b11110, 0b00000, 0b00000]),
    ('T', [0b11111, 0b00100, 0b00100, 0b00100, 0b00100, 0b00100, 0b00100, 0b00000, 0b00000]),
    ('U', [0b10001, 0b10001, 0b10001, 0b10001, 0b10001, 0b10001, 0b01110, 0b00000, 0b00000]),
    ('V', [0b10001, 0b10001, 0b10001, 0b10001, 0b10001, 0b01010, 0b00100, 0b00000, 0b00000]),
    ('W', [0b10001, 0b10001, 0b10001, 0b10101, 0b10101, 0b10101, 0b01010, 0b00000, 0b00000]),
    ('X', [0b10001, 0b10001, 0b01010, 0b00100, 0b01010, 0b10001, 0b10001, 0b00000, 0b00000]),
    ('Y', [0b10001, 0b10001, 0b01010, 0b00100, 0b00100, 0b00100, 0b00100, 0b00000, 0b00000]),
    ('Z', [0b11111, 0b00001, 0b00010, 0b00100, 0b01000, 0b10000, 0b11111, 0b00000, 0b00000]),
    ('[', [0b01110, 0b01000, 0b01000, 0b01000, 0b01000, 0b01000, 0b01110, 0b00000, 0b00000]),
    ('\\', [0b00000, 0b10000, 0b01000, 0b00100, 0b00010, 0b00001, 0b00000, 0b00000, 0b00000]),
    (']', [0b01110, 0b00010, 0b00010, 0b00010, 0b00010, 0b00010, 0b01110, 0b00000, 0b00000]),
    ('^', [0b00100, 0b01010, 0b10001, 0b00000, 0b00000, 0b00000, 0b00000, 0b00000, 0b00000]),
    ('_', [0b00000, 0b00000, 0b00000, 0b00000, 0b00000, 0b00000, 0b00000, 0b11111, 0b00000]),
    ('`', [0b01000, 0b00100, 0b00010, 0b00000, 0b00000, 0b00000, 0b00000, 0b00000, 0b00000]),
    ('a', [0b00000, 0b00000, 0b01110, 0b00001, 0b01111, 0b10001, 0b01111, 0b00000, 0b00000]),
    ('b', [0b10000, 0b10000, 0b11110, 0b10001, 0b10001, 0b10001, 0b11110, 0b00000, 0b00000]),
    ('c', [0b00000, 0b00000, 0b01110, 0b10000, 0b10000, 0b10001, 0b01110, 0b00000, 0b00000]),
    ('d', [0b00001, 0b00001, 0b01111, 0b10001, 0b10001, 0b10001, 0b01111, 0b00000, 0b00000]),
    ('e', [0b00000, 0b00000, 0b01110, 0b10001, 0b11111, 0b10000, 0b01110, 0b00000, 0b00000]),
    ('f', [0b00110, 0b01001, 0b01000, 0b11100, 0b01000, 0b01000, 0b01000, 0b00000, 0b00000]),
    ('g', [0b00000, 0b00000, 0b01111, 0b10001, 0b10001, 0b10001, 0b01111, 0b00001, 0b01110]),
    ('h', [0b10000, 0b10000, 0b10110, 0b11001, 0b10001, 0b10001, 0b10001, 0b00000, 0b00000]),
    ('i', [0b00100, 0b00000, 0b01100, 0b00100, 0b00100, 0b00100, 0b01110, 0b00000, 0b00000]),
    ('j', [0b00010, 0b00000, 0b00110, 0b00010, 0b00010, 0b00010, 0b00010, 0b10010, 0b01100]),
    ('k', [0b10000, 0b10000, 0b10010, 0b10100, 0b11000, 0b10100, 0b10010, 0b00000, 0b00000]),
    ('l', [0b01100, 0b00100, 0b00100, 0b00100, 0b00100, 0b00100, 0b01110, 0b00000, 0b00000]),
    ('m', [0b00000, 0b00000, 0b11010, 0b10101, 0b10101, 0b10101, 0b10001, 0b00000, 0b00000]),
    ('n', [0b00000, 0b00000, 0b10110, 0b11001, 0b10001, 0b10001, 0b10001, 0b00000, 0b00000]),
    ('o', [0b00000, 0b00000, 0b01110, 0b10001, 0b10001, 0b10001, 0b01110, 0b00000, 0b00000]),
    ('p', [0b00000, 0b00000, 0b11110, 0b10001, 0b10001, 0b10001, 0b11110, 0b10000, 0b10000]),
    ('q', [0b00000, 0b00000, 0b01111, 0b10001, 0b10001, 0b10001, 0b01111, 0b00001, 0b00001]),
    ('r', [0b00000, 0b00000, 0b10110, 0b11001, 0b10000, 0b10000, 0b10000, 0b00000, 0b00000]),
    ('s', [0b00000, 0b00000, 0b01111, 0b10000, 0b01110, 0b00001, 0b11110, 0b00000, 0b00000]),
    ('t', [0b01000, 0b01000, 0b11100, 0b01000, 0b01000, 0b01001, 0b00110, 0b00000, 0b00000]),
    ('u', [0b00000, 0b00000, 0b10001, 0b10001, 0b10001, 0b10011, 0b01101, 0b00000, 0b00000]),
    ('v', [0b00000, 0b00000, 0b10001, 0b10001, 0b10001, 0b01010, 0b00100, 0b00000, 0b00000]),
    ('w', [0b00000, 0b00000, 0b10001, 0b10001, 0b10101, 0b10101, 0b01010, 0b00000, 0b00000]),
    ('x', [0b00000, 0b00000, 0b10001, 0b01010, 0b00100, 0b01010, 0b10001, 0b00000, 0b00000]),
    ('y', [0b00000, 0b00000, 0b10001, 0b10001, 0b10001, 0b10001, 0b01111, 0b00001, 0b01110]),
    ('z', [0b00000, 0b00000, 0b11111, 0b00010, 0b00100, 0b01000, 0b11111, 0b00000, 0b00000]),
    ('{', [0b00010, 0b00100, 0b00100, 0b01000, 0b00100, 0b00100, 0b00010, 0b00000, 0b00000]),
    ('|', [0b00100, 0b00100, 0b00100, 0b00100, 0b00100, 0b00100, 0b00100, 0b00100, 0b00000]),
    ('}', [0b01000, 0b00100, 0b00100, 0b00010, 0b00100, 0b00100, 0b01000, 0b00000, 0b00000]),
    ('~', [0b00000, 0b00000, 0b01000, 0b10101, 0b00010, 0b00000, 0b00000, 0b00000, 0b00000]),
    ('×', [0b00000, 0b00000, 0b01010, 0b00100, 0b01010, 0b00000, 0b00000, 0b00000, 0b00000]),
    ('°', [0b01100, 0b10010, 0b10010, 0b01100, 0b00000, 0b00000, 0b00000, 0b00000, 0b00000]),
    ('²', [0b01100, 0b10010, 0b00100, 0b01000, 0b11110, 0b00000, 0b00000, 0b00000, 0b00000]),
    ('·', [0b00000, 0b00000, 0b00000, 0b01100, 0b01100, 0b00000, 0b00000, 0b00000, 0b00000]),
    ('…', [0b00000, 0b00000, 0b00000, 0b00000, 0b00000, 0b00000, 0b10101, 0b00000, 0b00000]),
];

/// The bitmap of `c`: row `r`, column `i` (0 at the left) is inked where
/// `glyph(c)[r] >> (GLYPH_WIDTH - 1 - i) & 1 == 1`. The minus sign is drawn as a hyphen;
/// a character the font lacks is drawn as `?`.
pub fn glyph(c: char) -> [u8; GLYPH_HEIGHT] {
    let c = if c == '\u{2212}' { '-' } else { c };
    let ascii = (' '..='~').contains(&c).then(|| GLYPHS[c as usize - ' ' as usize].1);
    ascii
        .or_else(|| GLYPHS[95..].iter().find(|(g, _)| *g == c).map(|(_, bits)| *bits))
        .unwrap_or(GLYPHS['?' as usize - ' ' as usize].1)
}

/// Whether the font has a glyph of its own for `c`.
pub fn has_glyph(c: char) -> bool {
    c == '\u{2212}' || GLYPHS.iter().any(|(g, _)| *g == c)
}

/// `text` cut to at most `n` characters, the last one an ellipsis when it was cut.
pub fn clip(text: &str, n: usize) -> String {
    if text.chars().count() <= n {
        return text.to_string();
    }
    let mut t: String = text.chars().take(n.saturating_sub(1)).collect();
    if n > 0 {
        t.push('…');
    }
    t
}

/// How a label looks: the font's scale, the ink, the box behind the text and its padding.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Label {
    /// Pixels per font pixel.
    pub scale: usize,
    /// Colour of the text (linear).
    pub ink: [f32; 3],
    /// Colour of the box (linear).
    pub backing: [f32; 3],
    /// Pixels between the box's edge and the text.
    pub pad: usize,
}

/// Light grey text: 0.75 linear is sRGB code 225.
pub const INK: [f32; 3] = [0.75, 0.75, 0.75];
/// Dimmer text for what follows a name: 0.3 linear is sRGB code 149.
pub const INK_DIM: [f32; 3] = [0.3, 0.3, 0.3];
/// The box: near black, 0.002 linear is sRGB code 7.
pub const BACKING: [f32; 3] = [0.002, 0.002, 0.002];

impl Label {
    /// Light text on a near-black box, padded by two font pixels.
    pub const fn new(scale: usize) -> Label {
        Label { scale, ink: INK, backing: BACKING, pad: 2 * scale }
    }

    /// The same label in another ink.
    pub const fn ink(self, ink: [f32; 3]) -> Label {
        Label { ink, ..self }
    }

    /// Width of `text` alone, pixels (no trailing blank column).
    pub fn text_width(&self, text: &str) -> usize {
        (text.chars().count() * ADVANCE).saturating_sub(1) * self.scale
    }

    /// Height of the box, pixels.
    pub const fn height(&self) -> usize {
        GLYPH_HEIGHT * self.scale + 2 * self.pad
    }

    /// Width and height of the box of `text`, pixels.
    pub fn size(&self, text: &str) -> (usize, usize) {
        (self.text_width(text) + 2 * self.pad, self.height())
    }

    /// Where the first glyph's top-left pixel goes in a box at `(x, y)`.
    pub const fn text_origin(&self, x: usize, y: usize) -> (usize, usize) {
        (x + self.pad, y + self.pad)
    }

    /// Draws `text` in its box with the box's top-left at `(x, y)`, clipped to the image;
    /// returns the box's width and height.
    pub fn draw(&self, image: &mut Rgb, x: usize, y: usize, text: &str) -> (usize, usize) {
        let (w, h) = self.size(text);
        fill(image, x, y, w, h, self.backing);
        let (x0, y0) = self.text_origin(x, y);
        let s = self.scale;
        for (n, c) in text.chars().enumerate() {
            for (r, row) in glyph(c).iter().enumerate() {
                for col in 0..GLYPH_WIDTH {
                    if row >> (GLYPH_WIDTH - 1 - col) & 1 == 1 {
                        fill(image, x0 + (n * ADVANCE + col) * s, y0 + r * s, s, s, self.ink);
                    }
                }
            }
        }
        (w, h)
    }
}

/// Fills the rectangle at `(x, y)` of `w` × `h` pixels with `colour`, clipped to the image.
pub fn fill(image: &mut Rgb, x: usize, y: usize, w: usize, h: usize, colour: [f32; 3]) {
    let (x1, y1) = ((x + w).min(image.width), (y + h).min(image.height));
    for j in y.min(y1)..y1 {
        image.pixels[j * image.width + x.min(x1)..j * image.width + x1].fill(colour);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_drawn_letter_is_its_hand_drawn_pattern_on_the_box() {
        // 'A' as drawn by hand here, not read from the table.
        let want = [".###.", "#...#", "#...#", "#####", "#...#", "#...#", "#...#", ".....", "....."];
        let label = Label::new(2);
        let mut img = Rgb::new(40, 40).unwrap();
        img.pixels.fill([0.5, 0.0, 0.0]);
        let (w, h) = label.draw(&mut img, 3, 5, "A");
        assert_eq!((w, h), (5 * 2 + 8, 9 * 2 + 8));
        for j in 0..40 {
            for i in 0..40 {
                let p = img.pixels[j * 40 + i];
                let in_box = (3..3 + w).contains(&i) && (5..5 + h).contains(&j);
                // The text starts at the box's corner plus the padding, 4 pixels.
                let ink = in_box && i >= 7 && j >= 9 && {
                    let (gi, gj) = ((i - 7) / 2, (j - 9) / 2);
                    gi < 5 && gj < 9 && want[gj].as_bytes()[gi] == b'#'
                };
                let expected = if ink {
                    INK
                } else if in_box {
                    BACKING
                } else {
                    [0.5, 0.0, 0.0]
                };
                assert_eq!(p, expected, "pixel ({i}, {j})");
            }
        }
    }

    #[test]
    fn every_glyph_is_distinct_and_within_its_cell() {
        for (k, (c, bits)) in GLYPHS.iter().enumerate() {
            if k < 95 {
                assert_eq!(*c as usize, 32 + k, "table out of ASCII order at {c:?}");
            }
            assert!(bits.iter().all(|&b| b < 1 << GLYPH_WIDTH), "{c:?} wider than {GLYPH_WIDTH}");
            assert_eq!(glyph(*c), *bits);
            assert!(*c == ' ' || bits.iter().any(|&b| b != 0), "{c:?} is blank");
            for (d, other) in &GLYPHS[k + 1..] {
                assert_ne!(bits, other, "{c:?} and {d:?} look the same");
            }
        }
        // Capitals and digits stand on the baseline: nothing below row 6.
        for c in ('A'..='Z').chain('0'..='9') {
            assert_eq!(glyph(c)[7..], [0, 0], "{c:?}");
            assert_ne!(glyph(c)[6], 0, "{c:?} does not reach the baseline");
        }
        assert_eq!(glyph('\u{2212}'), glyph('-'));
        assert_eq!(glyph('\u{263A}'), glyph('?'));
        assert!(has_glyph('×') && !has_glyph('\u{263A}'));
    }

    #[test]
    fn labels_measure_what_they_draw_and_clip_at_the_edge() {
        let label = Label::new(1);
        assert_eq!(label.text_width("ab"), 11);
        assert_eq!(label.size(""), (4, 13));
        let mut img = Rgb::new(10, 6).unwrap();
        // Off the right and bottom edges: clipped, no panic.
        label.draw(&mut img, 4, 2, "hello");
        assert_eq!(img.pixels[0], [0.0; 3]);
        assert_eq!(img.pixels[2 * 10 + 4], BACKING);
        assert_eq!(clip("abcdef", 4), "abc…");
        assert_eq!(clip("abc", 4), "abc");
    }
}
