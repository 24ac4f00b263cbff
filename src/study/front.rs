//! Something in front of a lit sphere ([`crate::litsphere::occluder`]) judged against the
//! truth of a picture made with a known circle and a known box top (`examples/disk_pictures`,
//! `tools/mypaint/make_exemplars.sh`).

use glam::DVec2;

use crate::litsphere::{Disk, Picture};

/// Pixels of the true disk (within 0.98 of its radius, as a fit samples it) by what they
/// show and whether the picture's reading left them out as something in front.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct FrontPixels {
    /// Pixels of the thing in front: all, and those still samples.
    pub thing: usize,
    pub thing_kept: usize,
    /// Pixels of the sphere: all, and those left out.
    pub sphere: usize,
    pub sphere_lost: usize,
}

impl FrontPixels {
    /// The counts of `picture`, whose sphere is `truth` and whose thing in front covers the
    /// rows below `front` (none: nothing in front), both in the file's pixels.
    pub fn of(picture: &Picture, truth: &Disk, front: Option<f64>) -> FrontPixels {
        let mut f = FrontPixels::default();
        let s = picture.scale;
        for j in 0..(picture.painting.height as f64 * s) as usize {
            for i in 0..(picture.painting.width as f64 * s) as usize {
                if truth.normal(i, j, 0.98).is_none() {
                    continue;
                }
                let at = DVec2::new(i as f64 + 0.5, j as f64 + 0.5);
                let left_out = picture.hidden.is_some_and(|h| h.line.hides(at / s));
                if front.is_some_and(|y| at.y > y) {
                    f.thing += 1;
                    f.thing_kept += usize::from(!left_out);
                } else {
                    f.sphere += 1;
                    f.sphere_lost += usize::from(left_out);
                }
            }
        }
        f
    }
}

impl std::ops::AddAssign for FrontPixels {
    fn add_assign(&mut self, o: FrontPixels) {
        self.thing += o.thing;
        self.thing_kept += o.thing_kept;
        self.sphere += o.sphere;
        self.sphere_lost += o.sphere_lost;
    }
}
