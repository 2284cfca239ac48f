//! The glasses a path is inside: entered by refraction through a front
//! face, left through a back face, innermost last. Each stretch of the
//! path inside glass loses to the innermost's absorption (Beer-Lambert).
//! Glass on an open shape is entered and never left, as its warning says.

use crate::material::Glass;

/// Glasses inside glasses followed; a deeper one is not counted as
/// entered, and leaving it changes nothing.
const MAX_NESTED: usize = 8;

/// A fixed stack: no allocation per path.
#[derive(Debug, Clone, Copy, Default)]
pub(super) struct Inside<'a> {
    glasses: [Option<&'a Glass>; MAX_NESTED],
    len: usize,
}

impl<'a> Inside<'a> {
    /// The glass the path is in, innermost.
    #[inline(always)]
    pub(super) fn innermost(&self) -> Option<&'a Glass> {
        self.len.checked_sub(1).and_then(|top| self.glasses[top])
    }

    /// The path refracted into `glass` through its front.
    pub(super) fn enter(&mut self, glass: &'a Glass) {
        if self.len < MAX_NESTED {
            self.glasses[self.len] = Some(glass);
            self.len += 1;
        }
    }

    /// The path refracted out of `glass` through its back: the innermost
    /// entry of that glass goes (overlapping volumes, as a liquid in a
    /// glass, are left in any order); one never entered changes nothing.
    pub(super) fn leave(&mut self, glass: &Glass) {
        let found = (0..self.len)
            .rev()
            .find(|&k| self.glasses[k].is_some_and(|g| std::ptr::eq(g, glass)));
        if let Some(k) = found {
            self.glasses.copy_within(k + 1..self.len, k);
            self.len -= 1;
            self.glasses[self.len] = None;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn glass() -> Glass {
        Glass {
            surface: crate::material::Phong::default_grey(),
            transmittance: 1.0,
            ior: 1.5,
            fresnel: true,
            absorption: glam::Vec3::ZERO,
        }
    }

    #[test]
    fn leaving_takes_out_the_glass_left_not_the_innermost() {
        let (cup, water, other) = (glass(), glass(), glass());
        let mut inside = Inside::default();
        assert!(inside.innermost().is_none());
        inside.enter(&cup);
        inside.enter(&water);
        assert!(std::ptr::eq(inside.innermost().unwrap(), &water));
        // Out through the cup's wall first: still in the water.
        inside.leave(&cup);
        assert!(std::ptr::eq(inside.innermost().unwrap(), &water));
        inside.leave(&other);
        assert!(std::ptr::eq(inside.innermost().unwrap(), &water));
        inside.leave(&water);
        assert!(inside.innermost().is_none());
    }

    #[test]
    fn past_its_depth_entering_and_leaving_change_nothing() {
        let glasses: Vec<Glass> = (0..MAX_NESTED + 1).map(|_| glass()).collect();
        let mut inside = Inside::default();
        for g in &glasses {
            inside.enter(g);
        }
        let deepest = &glasses[MAX_NESTED - 1];
        assert!(std::ptr::eq(inside.innermost().unwrap(), deepest));
        inside.leave(&glasses[MAX_NESTED]);
        assert!(std::ptr::eq(inside.innermost().unwrap(), deepest));
    }
}
