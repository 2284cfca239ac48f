//! A mesh face of more than three corners cut into triangles. A convex
//! face keeps the fan around its first corner that the readers always made
//! (so every mesh drawn before draws the same triangles); a concave one (an
//! L, a star) is cut by ear clipping in the plane it lies in, so it does
//! not cover its own notch. A face that cannot be cut (degenerate,
//! self-intersecting, or too large to check) keeps the fan, with a warning.

/// Corners a concave face may have to be cut by ear clipping (cubic in the
/// corners at worst); a larger one is fanned, with a warning.
pub const MAX_CLIPPED_CORNERS: usize = 1024;
/// Steps (corner against corner) of ear clipping one mesh file may take in
/// all, at worst about a second: a file of many hostile concave faces is not
/// cut for minutes; the faces past it are fanned, with a warning.
pub const CLIP_WORK: u64 = 400_000_000;

/// Why a face was fanned though it may not be convex.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Trouble {
    /// Its corners span no area (all on a line, or repeated).
    Degenerate,
    /// Its edges cross each other.
    SelfIntersecting,
    /// More than `MAX_CLIPPED_CORNERS` corners, or past the file's `CLIP_WORK`.
    TooManyCorners,
}

impl Trouble {
    /// What the warning says of such a face.
    pub fn says(self) -> &'static str {
        match self {
            Trouble::Degenerate => "degenerate (its corners span no area)",
            Trouble::SelfIntersecting => "self-intersecting",
            Trouble::TooManyCorners => {
                "concave with too many corners to cut (or past the file's many such faces)"
            }
        }
    }
}

/// The triangles of the face with corners `points`, as indices into them,
/// `points.len() - 2` of them, and why the fan was kept if it may be wrong.
/// `work_left` (start it at `CLIP_WORK` for each file) is what ear clipping
/// may still spend.
pub fn triangulate(points: &[[f32; 3]], work_left: &mut u64) -> (Vec<[usize; 3]>, Option<Trouble>) {
    let n = points.len();
    let fan = || (1..n.saturating_sub(1)).map(|k| [0, k, k + 1]).collect();
    if n <= 3 {
        return (fan(), None);
    }
    let p = |i: usize| points[i].map(f64::from);
    // Newell's normal: right for any planar polygon, and the best plane for
    // a slightly bent one.
    let mut normal = [0.0f64; 3];
    for i in 0..n {
        let (a, b) = (p(i), p((i + 1) % n));
        normal[0] += (a[1] - b[1]) * (a[2] + b[2]);
        normal[1] += (a[2] - b[2]) * (a[0] + b[0]);
        normal[2] += (a[0] - b[0]) * (a[1] + b[1]);
    }
    let axis = (0..3)
        .max_by(|&i, &j| normal[i].abs().total_cmp(&normal[j].abs()))
        .unwrap_or(2);
    if !(normal[axis].abs() > 0.0 && normal[axis].is_finite()) {
        // No net area: all on a line, or lobes that cancel (a bow tie),
        // which only a polygon crossing itself has.
        let o = p(0);
        let spans = (1..n).any(|i| {
            let (a, b) = (p(i), p((i + 1) % n));
            let (e, f) = (
                [a[0] - o[0], a[1] - o[1], a[2] - o[2]],
                [b[0] - o[0], b[1] - o[1], b[2] - o[2]],
            );
            let c = [
                e[1] * f[2] - e[2] * f[1],
                e[2] * f[0] - e[0] * f[2],
                e[0] * f[1] - e[1] * f[0],
            ];
            c.iter().any(|&x| x != 0.0)
        });
        let trouble = if spans && normal[axis].is_finite() {
            Trouble::SelfIntersecting
        } else {
            Trouble::Degenerate
        };
        return (fan(), Some(trouble));
    }
    // Projected onto the plane of the two other axes, turning
    // counter-clockwise (the pair swapped when the normal points down).
    let (mut u, mut v) = [(1, 2), (2, 0), (0, 1)][axis];
    if normal[axis] < 0.0 {
        std::mem::swap(&mut u, &mut v);
    }
    let flat: Vec<[f64; 2]> = (0..n).map(|i| [p(i)[u], p(i)[v]]).collect();
    if is_convex(&flat) {
        return (fan(), None);
    }
    // Its worst case charged before it is tried.
    let work = (n as u64).pow(3);
    if n > MAX_CLIPPED_CORNERS || work > *work_left {
        return (fan(), Some(Trouble::TooManyCorners));
    }
    *work_left -= work;
    if self_intersects(&flat) {
        return (fan(), Some(Trouble::SelfIntersecting));
    }
    match clip_ears(&flat) {
        Some(triangles) => (triangles, None),
        None => (fan(), Some(Trouble::SelfIntersecting)),
    }
}

/// The turn at `b` from `a`: positive to the left.
fn cross(a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> f64 {
    (b[0] - a[0]) * (c[1] - b[1]) - (b[1] - a[1]) * (c[0] - b[0])
}

/// Every corner turns left or goes straight (within rounding), and the
/// turns add up to one turn (not a star's two).
fn is_convex(flat: &[[f64; 2]]) -> bool {
    let n = flat.len();
    let mut turning = 0.0;
    for i in 0..n {
        let (a, b, c) = (flat[(i + n - 1) % n], flat[i], flat[(i + 1) % n]);
        let (e, f) = ([b[0] - a[0], b[1] - a[1]], [c[0] - b[0], c[1] - b[1]]);
        let turn = e[0] * f[1] - e[1] * f[0];
        let scale = e[0].hypot(e[1]) * f[0].hypot(f[1]);
        if turn < -1e-6 * scale {
            return false;
        }
        turning += turn.atan2(e[0] * f[0] + e[1] * f[1]);
    }
    turning < 3.0 * std::f64::consts::PI
}

/// Whether two edges that do not share a corner cross or touch.
fn self_intersects(flat: &[[f64; 2]]) -> bool {
    let n = flat.len();
    let side = |a, b, c| cross(a, b, c).signum();
    for i in 0..n {
        let (a, b) = (flat[i], flat[(i + 1) % n]);
        for j in i + 2..n {
            if (j + 1) % n == i {
                continue;
            }
            let (c, d) = (flat[j], flat[(j + 1) % n]);
            if side(a, b, c) * side(a, b, d) < 0.0 && side(c, d, a) * side(c, d, b) < 0.0 {
                return true;
            }
        }
    }
    false
}

/// Ear clipping of a simple counter-clockwise polygon: a corner that turns
/// left and whose triangle holds no other corner is cut off, until three
/// are left. None when no ear is found (the polygon was not simple).
fn clip_ears(flat: &[[f64; 2]]) -> Option<Vec<[usize; 3]>> {
    let mut left: Vec<usize> = (0..flat.len()).collect();
    let mut out = Vec::with_capacity(flat.len() - 2);
    while left.len() > 3 {
        let m = left.len();
        let ear = (0..m).find(|&i| {
            let (a, b, c) = (left[(i + m - 1) % m], left[i], left[(i + 1) % m]);
            let (pa, pb, pc) = (flat[a], flat[b], flat[c]);
            cross(pa, pb, pc) > 0.0
                && !left.iter().any(|&k| {
                    let q = flat[k];
                    k != a
                        && k != b
                        && k != c
                        && q != pa
                        && q != pb
                        && q != pc
                        && cross(pa, pb, q) >= 0.0
                        && cross(pb, pc, q) >= 0.0
                        && cross(pc, pa, q) >= 0.0
                })
        })?;
        out.push([left[(ear + m - 1) % m], left[ear], left[(ear + 1) % m]]);
        left.remove(ear);
    }
    out.push([left[0], left[1], left[2]]);
    Some(out)
}

/// The summed area of triangles lying in the plane z = 0: what the
/// readers' tests check a cut polygon by.
#[cfg(test)]
pub(crate) fn flat_area(triangles: &[[[f32; 3]; 3]]) -> f32 {
    triangles
        .iter()
        .map(|[a, b, c]| {
            let (e, f) = ([b[0] - a[0], b[1] - a[1]], [c[0] - a[0], c[1] - a[1]]);
            (e[0] * f[1] - e[1] * f[0]).abs() / 2.0
        })
        .sum()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Twice the area of triangle (a, b, c) in the plane z = 0.
    fn area2(t: [usize; 3], points: &[[f32; 3]]) -> f64 {
        let p = |i: usize| [f64::from(points[i][0]), f64::from(points[i][1])];
        cross(p(t[0]), p(t[1]), p(t[2])).abs()
    }

    /// Whether the point lies inside one of the triangles.
    fn covered(triangles: &[[usize; 3]], points: &[[f32; 3]], q: [f64; 2]) -> bool {
        let p = |i: usize| [f64::from(points[i][0]), f64::from(points[i][1])];
        triangles.iter().any(|t| {
            let s = [
                cross(p(t[0]), p(t[1]), q),
                cross(p(t[1]), p(t[2]), q),
                cross(p(t[2]), p(t[0]), q),
            ];
            s.iter().all(|&x| x > 0.0) || s.iter().all(|&x| x < 0.0)
        })
    }

    fn flat(xy: &[[f32; 2]]) -> Vec<[f32; 3]> {
        xy.iter().map(|&[x, y]| [x, y, 0.0]).collect()
    }

    /// An L of area 3: the unit squares (0,0), (1,0), (0,1); its notch is
    /// the square (1,1).
    fn l_shape() -> Vec<[f32; 3]> {
        flat(&[
            [0.0, 2.0],
            [0.0, 0.0],
            [2.0, 0.0],
            [2.0, 1.0],
            [1.0, 1.0],
            [1.0, 2.0],
        ])
    }

    #[test]
    fn an_l_covers_its_area_and_not_its_notch() {
        // The fan from corner 0 would cover the notch's lower part.
        let l = l_shape();
        let (triangles, trouble) = triangulate(&l, &mut CLIP_WORK.clone());
        assert_eq!(trouble, None);
        assert_eq!(triangles.len(), 4);
        let area: f64 = triangles.iter().map(|&t| area2(t, &l)).sum::<f64>() / 2.0;
        assert_eq!(area, 3.0);
        assert!(!covered(&triangles, &l, [1.6, 1.1]));
        assert!(!covered(&triangles, &l, [1.5, 1.5]));
        assert!(covered(&triangles, &l, [0.5, 1.5]));
        assert!(covered(&triangles, &l, [1.5, 0.5]));
        // What the fan did: the notch covered, more than the L's area.
        let fan: Vec<[usize; 3]> = (1..5).map(|k| [0, k, k + 1]).collect();
        assert!(covered(&fan, &l, [1.6, 1.1]));
        let fan_area: f64 = fan.iter().map(|&t| area2(t, &l)).sum::<f64>() / 2.0;
        assert_eq!(fan_area, 4.0);
    }

    #[test]
    fn a_star_covers_its_area_and_not_between_its_points() {
        // A five-pointed star, its outer corners at radius 2, inner at 1,
        // starting at an inner corner (reflex: a fan from it is wrong).
        let star: Vec<[f32; 3]> = (0..10)
            .map(|k| {
                let r = if k % 2 == 0 { 1.0 } else { 2.0 };
                let a = std::f32::consts::PI * k as f32 / 5.0;
                [r * a.cos(), r * a.sin(), 0.0]
            })
            .collect();
        let (triangles, trouble) = triangulate(&star, &mut CLIP_WORK.clone());
        assert_eq!(trouble, None);
        assert_eq!(triangles.len(), 8);
        // Shoelace area of the star.
        let area: f64 = (0..10)
            .map(|i| {
                let (a, b) = (star[i], star[(i + 1) % 10]);
                f64::from(a[0]) * f64::from(b[1]) - f64::from(b[0]) * f64::from(a[1])
            })
            .sum::<f64>()
            / 2.0;
        let covered_area: f64 = triangles.iter().map(|&t| area2(t, &star)).sum::<f64>() / 2.0;
        assert!((covered_area - area).abs() < 1e-5, "{covered_area} {area}");
        // Between two points, at radius 1.5 (outside the star), not covered;
        // a point's tip is.
        let between = [1.5 * 0.0f64.cos(), 0.0];
        assert!(!covered(&triangles, &star, between));
        let tip = std::f64::consts::PI / 5.0;
        assert!(covered(
            &triangles,
            &star,
            [1.8 * tip.cos(), 1.8 * tip.sin()]
        ));
    }

    #[test]
    fn a_convex_polygon_keeps_the_fan() {
        let quad = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.2],
            [1.0, 1.0, 0.0],
            [0.0, 1.0, 0.1],
        ];
        assert_eq!(
            triangulate(&quad, &mut CLIP_WORK.clone()),
            (vec![[0, 1, 2], [0, 2, 3]], None)
        );
        // Facing the other way, and with a corner on a straight edge.
        let mut reversed = quad;
        reversed.reverse();
        assert_eq!(
            triangulate(&reversed, &mut CLIP_WORK.clone()).0,
            vec![[0, 1, 2], [0, 2, 3]]
        );
        let hexagon = flat(&[[0.0, 0.0], [1.0, 0.0], [2.0, 0.0], [2.0, 1.0], [0.0, 1.0]]);
        assert_eq!(triangulate(&hexagon, &mut CLIP_WORK.clone()).1, None);
        assert_eq!(
            triangulate(&hexagon, &mut CLIP_WORK.clone()).0[0],
            [0, 1, 2]
        );
    }

    #[test]
    fn concave_faces_past_the_work_are_fanned_and_said() {
        let l = l_shape();
        let mut work = 216 + 215;
        assert_eq!(triangulate(&l, &mut work).1, None);
        assert_eq!(work, 215);
        let (triangles, trouble) = triangulate(&l, &mut work);
        assert_eq!(trouble, Some(Trouble::TooManyCorners));
        assert_eq!(triangles[0], [0, 1, 2]);
        // Convex faces cost nothing.
        let square = flat(&[[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]]);
        assert_eq!(triangulate(&square, &mut 0).1, None);
    }

    #[test]
    fn a_self_intersecting_or_degenerate_polygon_is_fanned_and_said() {
        let bow_tie = flat(&[[0.0, 0.0], [1.0, 1.0], [1.0, 0.0], [0.0, 1.0], [-0.5, 0.5]]);
        let (triangles, trouble) = triangulate(&bow_tie, &mut CLIP_WORK.clone());
        assert_eq!(trouble, Some(Trouble::SelfIntersecting));
        assert_eq!(triangles, vec![[0, 1, 2], [0, 2, 3], [0, 3, 4]]);
        let line = flat(&[[0.0, 0.0], [1.0, 0.0], [2.0, 0.0], [3.0, 0.0]]);
        assert_eq!(
            triangulate(&line, &mut CLIP_WORK.clone()).1,
            Some(Trouble::Degenerate)
        );
        // A pentagram: every corner turns left, twice around.
        let pentagram: Vec<[f32; 3]> = (0..5)
            .map(|k| {
                let a = 4.0 * std::f32::consts::PI * k as f32 / 5.0;
                [a.cos(), a.sin(), 0.0]
            })
            .collect();
        assert_eq!(
            triangulate(&pentagram, &mut CLIP_WORK.clone()).1,
            Some(Trouble::SelfIntersecting)
        );
    }
}
