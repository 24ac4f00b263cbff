//! Paintings made on the coloring-book page (`brdfpaint sheet`): what the page itself put
//! there is not paint.
//!
//! The sheet writes `outline.png` (black lines on white, for printing or painting on in any
//! program) and `page.png` (the same lines on a transparent layer). An artist opens one,
//! paints, leaves gaps and the lines, and saves. The fit knows the lines, because it draws
//! them itself from the scene ([`crate::render::GBuffer::lines`]), so a painting whose line
//! pixels are still the page's black was made on the page. Then two kinds of pixels are not
//! paint: the line pixels still black, and the untouched white of the opaque page (pixels at
//! the file's largest code in every channel: their value is clipped in any case).

use crate::images::Painting;

/// Line pixels darker than this (linear; about 10/255 in sRGB) are the page's black.
const LINE_BLACK: f32 = 0.003;

/// What was left out of a painting made on the page.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct PageLeftovers {
    /// Line pixels still the page's black.
    pub lines: usize,
    /// Untouched white of the opaque page (clipped white) on the object.
    pub white: usize,
}

impl PageLeftovers {
    /// One line for the user.
    pub fn note(&self, painting: &str) -> crate::note::Note {
        crate::note::Note::Page { painting: painting.to_string(), lines: self.lines, white: self.white }
    }
}

/// When `painting` was made on the page whose lines are `lines` (per pixel, at the
/// painting's size) over the object pixels `hit`, makes the page's own pixels unpainted
/// (alpha 0) and says how many; `None` (and nothing changed) otherwise: fewer than 20 line
/// pixels are painted, or fewer than half of them are still black beside paint that is not.
pub fn remove_page(painting: &mut Painting, lines: &[bool], hit: &[bool]) -> Option<PageLeftovers> {
    let on_object = |k: usize| lines[k] && hit[k] && painting.alpha[k] > 0.0;
    let black = |p: &Painting, k: usize| p.pixels[k].iter().all(|&c| c < LINE_BLACK);
    let drawn: Vec<usize> = (0..painting.pixels.len()).filter(|&k| on_object(k)).collect();
    // A line pixel is the page's when it is black beside paint that is not: black lines in
    // a black shadow prove nothing.
    let beside_paint = |k: usize| {
        crate::images::neighbours4(k, painting.width, painting.pixels.len())
            .any(|n| !lines[n] && hit[n] && painting.alpha[n] > 0.0 && !black(painting, n))
    };
    let still_black = drawn.iter().filter(|&&k| black(painting, k) && beside_paint(k)).count();
    if drawn.len() < 20 || 2 * still_black < drawn.len() {
        return None;
    }
    let mut out = PageLeftovers::default();
    for k in 0..painting.pixels.len() {
        if painting.alpha[k] <= 0.0 || !hit[k] {
            continue;
        }
        if lines[k] && black(painting, k) {
            painting.alpha[k] = 0.0;
            out.lines += 1;
        } else if painting.saturated[k] {
            painting.alpha[k] = 0.0;
            out.white += 1;
        }
    }
    Some(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_page_is_recognized_only_when_its_lines_are_still_black() {
        let n = 100;
        let hit = vec![true; n];
        let lines: Vec<bool> = (0..n).map(|k| k % 4 == 0).collect();
        let mut p = Painting::opaque(10, 10, vec![[0.4, 0.2, 0.1]; n]).unwrap();
        // Paint everywhere, but leave the lines black and some untouched white.
        for (k, &line) in lines.iter().enumerate() {
            if line {
                p.pixels[k] = [0.0; 3];
            } else if k % 7 == 0 {
                p.pixels[k] = [1.0; 3];
                p.saturated[k] = true;
            }
        }
        let mut page = p.clone();
        let left = remove_page(&mut page, &lines, &hit).unwrap();
        assert_eq!(left.lines, 25);
        assert_eq!(left.white, (0..n).filter(|k| k % 4 != 0 && k % 7 == 0).count());
        assert!((0..n).all(|k| (page.alpha[k] == 0.0) == (lines[k] || (k % 7 == 0))));
        // A painting that is black where the lines are, and around them: a shadow, not the page.
        let mut shadow = p.clone();
        for px in shadow.pixels.iter_mut() {
            *px = [0.0; 3];
        }
        assert!(remove_page(&mut shadow, &lines, &hit).is_none());
        // Painted over the lines: half still black is the page; fewer is not, and nothing changes.
        let mut over = p.clone();
        for k in (0..n).filter(|k| k % 4 == 0 && k % 8 != 0) {
            over.pixels[k] = [0.4, 0.2, 0.1];
        }
        assert!(remove_page(&mut over.clone(), &lines, &hit).is_some(), "half the lines still black: the page");
        for k in (0..n).filter(|k| k % 8 == 0) {
            over.pixels[k] = [0.4, 0.2, 0.1];
        }
        let before = over.clone();
        assert!(remove_page(&mut over, &lines, &hit).is_none());
        assert_eq!(over.alpha, before.alpha);
    }
}
