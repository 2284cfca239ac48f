//! The text of a Wavefront OBJ file, read in one pass over its bytes: the
//! vertex lists, and every face fanned into triangles of corners. Written
//! by hand (tobj took 0.7 s on a 1.1M-triangle file, most of it in a
//! `String` per line and a hash map per corner); MTL files are still read
//! by tobj (`mtl.rs`). What a line means follows tobj 4, which this replaces,
//! except that a face without normals or uv has none (tobj lent it its
//! neighbour's), `l` lines are left out (tobj made one of 3 or more
//! vertices a face) and a face of fewer than 3 vertices is an error (tobj
//! left it out).

use crate::budget::Budget;
use std::collections::HashMap;
use std::path::Path;

/// A face corner's indices into the vertex lists, counted from 0
/// (negative ones already resolved); `NONE` where the corner names none.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Corner {
    pub v: u32,
    pub vt: u32,
    pub vn: u32,
}

pub(crate) const NONE: u32 = u32::MAX;

/// What an OBJ file holds.
#[derive(Debug, Default)]
pub(crate) struct ObjText {
    pub positions: Vec<[f32; 3]>,
    pub texcoords: Vec<[f32; 2]>,
    pub normals: Vec<[f32; 3]>,
    /// The faces' triangles (a face of n corners gives n - 2, a fan around
    /// its first corner), in the file's order.
    pub triangles: Vec<[Corner; 3]>,
    /// Each triangle's material (its face's `usemtl`) among the materials
    /// the `mtllib` lines before it gave, when any did; else empty.
    pub triangle_materials: Vec<Option<u32>>,
    /// Faces fanned though they may not be convex (see `polygon`), and the
    /// line and trouble of the first.
    pub polygon_troubles: usize,
    pub first_polygon_trouble: Option<(usize, crate::polygon::Trouble)>,
}

/// Why a file is not a valid OBJ, and the line (counted from 1) it is on.
#[derive(Debug)]
pub(crate) struct ObjError {
    pub what: &'static str,
    pub line: usize,
}

/// Loads one `mtllib` file: its materials' names, in its order.
pub(crate) trait MaterialLibraries {
    fn load(&mut self, name: &Path) -> Vec<String>;
}

/// For tests: an OBJ whose `mtllib` files give nothing.
#[cfg(test)]
pub(crate) struct NoLibraries;

#[cfg(test)]
impl MaterialLibraries for NoLibraries {
    fn load(&mut self, _: &Path) -> Vec<String> {
        Vec::new()
    }
}

/// Parses `bytes`, an OBJ file's text.
pub(crate) fn parse(
    bytes: &[u8],
    libraries: &mut dyn MaterialLibraries,
    budget: &mut Budget,
) -> Result<ObjText, ObjError> {
    let mut parser = Parser {
        budget,
        text: ObjText::default(),
        materials: HashMap::new(),
        material_count: 0,
        material: None,
        face: Vec::new(),
        line: 0,
        clip_work: crate::polygon::CLIP_WORK,
    };
    // A guess from typical files (shared vertices, about 38 bytes a
    // triangle), so the lists seldom grow and copy.
    let triangles = (bytes.len() / 38).min(crate::budget::MAX_TRIANGLES);
    parser.text.positions.reserve(triangles / 2);
    parser.text.triangles.reserve(triangles);
    let mut start = 0;
    for (i, end) in memchr::memchr_iter(b'\n', bytes)
        .chain([bytes.len()])
        .enumerate()
    {
        parser.line = i + 1;
        parser
            .line(&bytes[start..end], libraries)
            .map_err(|what| ObjError { what, line: i + 1 })?;
        start = end + 1;
    }
    Ok(parser.text)
}

struct Parser<'b> {
    /// The scene's triangles left: a face's are taken before they are made.
    budget: &'b mut Budget,
    text: ObjText,
    /// Every material name the libraries gave so far, to its index (a
    /// later library's material of the same name wins, as in tobj).
    materials: HashMap<String, u32>,
    /// How many materials the libraries gave, names repeated or not.
    material_count: u32,
    material: Option<u32>,
    /// Corners of the face being read, reused from face to face.
    face: Vec<Corner>,
    /// The line being read, counted from 1.
    line: usize,
    /// What ear clipping may still spend on this file.
    clip_work: u64,
}

impl Parser<'_> {
    fn line(
        &mut self,
        line: &[u8],
        libraries: &mut dyn MaterialLibraries,
    ) -> Result<(), &'static str> {
        let mut words = words(line);
        match words.next() {
            Some(b"v") => self.vertex(words),
            Some(b"vt") => {
                let [u, v] = floats(&mut words).ok_or("texcoord parse error")?;
                self.text.texcoords.push([u, v]);
                Ok(())
            }
            Some(b"vn") => {
                let n = floats(&mut words).ok_or("normal parse error")?;
                self.text.normals.push(n);
                Ok(())
            }
            Some(b"f") => self.face(words),
            Some(b"mtllib") => {
                self.library(rest_after_keyword(line)?, libraries);
                Ok(())
            }
            Some(b"usemtl") => {
                let name = String::from_utf8_lossy(rest_after_keyword(line)?);
                self.material = self.materials.get(name.as_ref()).copied();
                Ok(())
            }
            // Comments, groups, objects, smoothing groups, lines, points...
            _ => Ok(()),
        }
    }

    /// `v x y z`, `v x y z w` (divided by w) or `v x y z r g b` (the colour
    /// is not used).
    fn vertex<'a>(
        &mut self,
        mut words: impl Iterator<Item = &'a [u8]>,
    ) -> Result<(), &'static str> {
        let mut p: [f32; 3] = floats(&mut words).ok_or("position parse error")?;
        match (words.next(), words.next(), words.next(), words.next()) {
            (None, ..) => {}
            (Some(w), None, ..) => {
                let w = float(w).ok_or("position parse error")?;
                if w == 0.0 {
                    return Err("vertex weight of zero");
                }
                p = p.map(|x| x / w);
            }
            (Some(_), Some(_), Some(_), None) => {}
            _ => return Err("color parse error"),
        }
        self.text.positions.push(p);
        Ok(())
    }

    fn face<'a>(&mut self, words: impl Iterator<Item = &'a [u8]>) -> Result<(), &'static str> {
        self.face.clear();
        let counts = [
            self.text.positions.len(),
            self.text.texcoords.len(),
            self.text.normals.len(),
        ];
        for word in words {
            let corner = corner(word, counts).ok_or("face parse error")?;
            self.face.push(corner);
        }
        if self.face.len() < 3 {
            return Err("face parse error");
        }
        self.budget.take(self.face.len() - 2)?;
        let cut = if self.face.len() == 3 {
            vec![[0, 1, 2]]
        } else {
            // `corner` checked each index against the positions read.
            let points: Vec<[f32; 3]> = (self.face.iter())
                .map(|c| self.text.positions[c.v as usize])
                .collect();
            let (cut, trouble) = crate::polygon::triangulate(&points, &mut self.clip_work);
            if let Some(trouble) = trouble {
                self.text.polygon_troubles += 1;
                (self.text.first_polygon_trouble).get_or_insert((self.line, trouble));
            }
            cut
        };
        for [a, b, c] in cut {
            let triangle = [self.face[a], self.face[b], self.face[c]];
            self.text.triangles.push(triangle);
            if !self.materials.is_empty() {
                self.text.triangle_materials.push(self.material);
            }
        }
        Ok(())
    }

    fn library(&mut self, name: &[u8], libraries: &mut dyn MaterialLibraries) {
        let name = String::from_utf8_lossy(name);
        let had_materials = !self.materials.is_empty();
        for material in libraries.load(Path::new(name.as_ref())) {
            self.materials.insert(material, self.material_count);
            self.material_count += 1;
        }
        // The faces before the first material had none to name.
        if !had_materials && !self.materials.is_empty() {
            self.text.triangle_materials = vec![None; self.text.triangles.len()];
        }
    }
}

/// The words of a line, split at ASCII white space.
fn words(line: &[u8]) -> impl Iterator<Item = &[u8]> {
    line.split(u8::is_ascii_whitespace)
        .filter(|w| !w.is_empty())
}

/// The rest of the line after its keyword, trimmed: a file or material
/// name, which may hold spaces.
fn rest_after_keyword(line: &[u8]) -> Result<&[u8], &'static str> {
    let line = line.trim_ascii_start();
    let start = line
        .iter()
        .position(u8::is_ascii_whitespace)
        .unwrap_or(line.len());
    let rest = line[start..].trim_ascii();
    if rest.is_empty() {
        return Err("material parse error");
    }
    Ok(rest)
}

/// The next `N` words as numbers (words after them are not read).
fn floats<'a, const N: usize>(words: &mut impl Iterator<Item = &'a [u8]>) -> Option<[f32; N]> {
    let mut values = [0.0; N];
    for value in &mut values {
        *value = float(words.next()?)?;
    }
    Some(values)
}

fn float(word: &[u8]) -> Option<f32> {
    short_decimal(word).or_else(|| std::str::from_utf8(word).ok()?.parse().ok())
}

/// A plain decimal (`-0.0378297`: no exponent, at most seven digits of
/// mantissa, at most ten after the point) by Clinger's fast path: its
/// digits as an integer below 2^24 and a power of ten up to 10^10 are both
/// exact in f32, so one division rounds once, correctly, to the value
/// `str::parse` gives. Other words are left to `str::parse` (None here).
/// Most OBJ numbers are such words, and this takes a fifth of the time.
fn short_decimal(word: &[u8]) -> Option<f32> {
    const POWERS: [f32; 11] = [1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10];
    let (negative, digits) = match word {
        [b'-', rest @ ..] => (true, rest),
        [b'+', rest @ ..] => (false, rest),
        _ => (false, word),
    };
    let (mut mantissa, mut count, mut after_point) = (0u32, 0usize, None::<usize>);
    for &b in digits {
        match b {
            b'0'..=b'9' => {
                mantissa = mantissa.checked_mul(10)?.checked_add(u32::from(b - b'0'))?;
                count += 1;
                if let Some(n) = &mut after_point {
                    *n += 1;
                }
            }
            b'.' if after_point.is_none() => after_point = Some(0),
            _ => return None,
        }
    }
    let decimals = after_point.unwrap_or(0);
    if count == 0 || mantissa > 1 << 24 || decimals >= POWERS.len() {
        return None;
    }
    let value = mantissa as f32 / POWERS[decimals];
    Some(if negative { -value } else { value })
}

/// A face corner `v`, `v/vt`, `v//vn` or `v/vt/vn`; `counts` are the
/// vertex lists' lengths so far, for negative indices.
fn corner(word: &[u8], counts: [usize; 3]) -> Option<Corner> {
    let mut parts = word.split(|&b| b == b'/');
    let v = index(parts.next()?, counts[0])?;
    let vt = optional_index(parts.next(), counts[1])?;
    let vn = optional_index(parts.next(), counts[2])?;
    if parts.next().is_some() || v == NONE {
        return None;
    }
    Some(Corner { v, vt, vn })
}

fn optional_index(part: Option<&[u8]>, count: usize) -> Option<u32> {
    match part {
        None | Some(b"") => Some(NONE),
        Some(part) => index(part, count),
    }
}

/// An OBJ index (from 1, or from -1 back from the last vertex so far) as an
/// index from 0. Indices past the end are checked when the faces are used
/// (tobj allowed a face to name vertices defined after it).
fn index(part: &[u8], count: usize) -> Option<u32> {
    let (negative, digits) = match part.split_first()? {
        (b'-', rest) => (true, rest),
        (b'+', rest) => (false, rest),
        _ => (false, part),
    };
    if digits.is_empty() || digits.len() > 10 {
        return None;
    }
    let mut n: u64 = 0;
    for &d in digits {
        if !d.is_ascii_digit() {
            return None;
        }
        n = n * 10 + u64::from(d - b'0');
    }
    let index = match (negative, n) {
        (_, 0) => return None,
        (false, n) => n - 1,
        (true, n) => (count as u64).checked_sub(n)?,
    };
    u32::try_from(index).ok().filter(|&i| i != NONE)
}

/// Reproducible numbers below `n` (xorshift from `state`), for the tests'
/// random words.
#[cfg(test)]
pub(crate) fn below(mut state: u64) -> impl FnMut(u64) -> u64 {
    move |n| {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        state % n
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn text(obj: &str) -> Result<ObjText, ObjError> {
        parse(obj.as_bytes(), &mut NoLibraries, &mut Budget::default())
    }

    /// The fast path must give `str::parse`'s bits, or leave the word to it.
    #[test]
    fn short_decimals_parse_as_the_standard_library_does() {
        let mut next = below(0x2545_f491_4f6c_dd1d);
        let mut fast = 0;
        for _ in 0..400_000 {
            let mut word = String::new();
            match next(3) {
                0 => word.push('-'),
                1 if next(4) == 0 => word.push('+'),
                _ => {}
            }
            let whole = next(12) as usize;
            let fraction = next(13) as usize;
            for _ in 0..whole {
                word.push(char::from(b'0' + next(10) as u8));
            }
            if fraction > 0 || next(2) == 0 {
                word.push('.');
            }
            for _ in 0..fraction {
                word.push(char::from(b'0' + next(10) as u8));
            }
            let parsed: Option<f32> = word.parse().ok();
            let ours = float(word.as_bytes());
            assert_eq!(ours.map(f32::to_bits), parsed.map(f32::to_bits), "{word:?}");
            fast += short_decimal(word.as_bytes()).is_some() as usize;
        }
        // Both paths were taken.
        assert!((50_000..350_000).contains(&fast), "{fast} fast");
        for word in [
            "1e3", "-2.5E-2", "inf", "nan", ".", "-", "1.2.3", "0x10", "",
        ] {
            let parsed: Option<f32> = word.parse().ok();
            assert_eq!(
                float(word.as_bytes()).map(f32::to_bits),
                parsed.map(f32::to_bits)
            );
        }
    }

    #[test]
    fn corners_resolve_every_index_form() {
        let counts = [5, 2, 3];
        let c = |v, vt, vn| Some(Corner { v, vt, vn });
        assert_eq!(corner(b"3", counts), c(2, NONE, NONE));
        assert_eq!(corner(b"3/2", counts), c(2, 1, NONE));
        assert_eq!(corner(b"3//1", counts), c(2, NONE, 0));
        assert_eq!(corner(b"-1/-2/-3", counts), c(4, 0, 0));
        for bad in [
            &b"0"[..],
            b"-6",
            b"x",
            b"1/2/3/4",
            b"/1",
            b"1/x",
            b"",
            b"99999999999",
        ] {
            assert_eq!(
                corner(bad, counts),
                None,
                "{}",
                String::from_utf8_lossy(bad)
            );
        }
    }

    #[test]
    fn polygons_fan_around_their_first_corner() {
        let t =
            text("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0 0\r\nf 1 2 3 4\r\nl 1 2 3\n").unwrap();
        let vs: Vec<[u32; 3]> = t.triangles.iter().map(|t| t.map(|c| c.v)).collect();
        assert_eq!(vs, [[0, 1, 2], [0, 2, 3]]);
        assert_eq!(t.positions[4], [2.0, 0.0, 0.0]);
        let line = text("v 0 0 0\nv 1 0 0\nf 1 2\n").unwrap_err().line;
        assert_eq!(line, 3);
    }

    #[test]
    fn weights_divide_and_colours_are_skipped() {
        let t = text("v 2 4 6 2\nv 1 2 3 0.5 0.5 0.5\n").unwrap();
        assert_eq!(t.positions, [[1.0, 2.0, 3.0], [1.0, 2.0, 3.0]]);
        assert_eq!(text("v 1 2 3 0\n").unwrap_err().line, 1);
        assert_eq!(text("v 1 2 3\nv 1 2 3 4 5\n").unwrap_err().line, 2);
        assert_eq!(text("v 1 2\n").unwrap_err().what, "position parse error");
    }

    #[test]
    fn materials_follow_usemtl_once_a_library_named_them() {
        struct Two;
        impl MaterialLibraries for Two {
            fn load(&mut self, name: &Path) -> Vec<String> {
                assert_eq!(name, Path::new("my lib.mtl"));
                vec!["red".into(), "blue".into()]
            }
        }
        let obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nmtllib my lib.mtl\nf 1 2 3\n\
                   usemtl blue\nf 1 2 3\nusemtl none\nf 1 2 3\nusemtl red \nf 1 2 3\n";
        let t = parse(obj.as_bytes(), &mut Two, &mut Budget::default()).unwrap();
        assert_eq!(t.triangle_materials, [None, None, Some(1), None, Some(0)]);
    }
}
