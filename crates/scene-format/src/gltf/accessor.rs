//! Reading accessors: typed elements out of buffer views, every range
//! checked against the view and the buffer before anything is allocated;
//! `byteStride`, normalised integers and sparse accessors.

use super::doc::{Accessor, Document};
use super::Failure;
use crate::key_path::KeyPath;

/// Most elements one accessor may have: three vertices for each triangle
/// a scene may make.
pub const MAX_ELEMENTS: u64 = 3 * crate::budget::MAX_TRIANGLES as u64;

const BYTE: u32 = 5120;
const UNSIGNED_BYTE: u32 = 5121;
const SHORT: u32 = 5122;
const UNSIGNED_SHORT: u32 = 5123;
const UNSIGNED_INT: u32 = 5125;
const FLOAT: u32 = 5126;

/// What an accessor's elements must be to be read as something.
pub(crate) struct Expect {
    /// The `type`s allowed, by their component count: "VEC3" is 3.
    pub kinds: &'static [&'static str],
    /// The component types allowed, and whether an integer one must be
    /// `normalized`.
    pub components: &'static [u32],
    pub normalized_integers: bool,
}

pub(crate) const VEC3_FLOAT: Expect = Expect {
    kinds: &["VEC3"],
    components: &[FLOAT],
    normalized_integers: false,
};
pub(crate) const VEC4_FLOAT: Expect = Expect {
    kinds: &["VEC4"],
    components: &[FLOAT],
    normalized_integers: false,
};
pub(crate) const TEXCOORD: Expect = Expect {
    kinds: &["VEC2"],
    components: &[FLOAT, UNSIGNED_BYTE, UNSIGNED_SHORT],
    normalized_integers: true,
};
pub(crate) const INDICES: Expect = Expect {
    kinds: &["SCALAR"],
    components: &[UNSIGNED_BYTE, UNSIGNED_SHORT, UNSIGNED_INT],
    normalized_integers: false,
};

/// Reads accessors of one document from its loaded buffers.
pub(crate) struct Reader<'a> {
    pub doc: &'a Document,
    pub buffers: &'a [Vec<u8>],
}

fn components_of(kind: &str) -> Option<usize> {
    Some(match kind {
        "SCALAR" => 1,
        "VEC2" => 2,
        "VEC3" => 3,
        "VEC4" => 4,
        "MAT2" => 4,
        "MAT3" => 9,
        "MAT4" => 16,
        _ => return None,
    })
}

fn component_size(component: u32) -> Option<u64> {
    Some(match component {
        BYTE | UNSIGNED_BYTE => 1,
        SHORT | UNSIGNED_SHORT => 2,
        UNSIGNED_INT | FLOAT => 4,
        _ => return None,
    })
}

fn component_name(component: u32) -> &'static str {
    match component {
        BYTE => "BYTE",
        UNSIGNED_BYTE => "UNSIGNED_BYTE",
        SHORT => "SHORT",
        UNSIGNED_SHORT => "UNSIGNED_SHORT",
        UNSIGNED_INT => "UNSIGNED_INT",
        FLOAT => "FLOAT",
        _ => "an unknown type",
    }
}

/// Where one run of elements lies in a buffer: its bytes from `start`,
/// `stride` apart.
#[derive(Clone, Copy)]
struct Run<'a> {
    bytes: &'a [u8],
    start: usize,
    stride: usize,
    component: u32,
    normalized: bool,
}

impl Run<'_> {
    /// Component `c` of element `i` as a float (normalised integers mapped
    /// to [0, 1] or [-1, 1] as the spec says).
    fn value(&self, i: usize, c: usize) -> f32 {
        let size = component_size(self.component).unwrap_or(4) as usize;
        let at = self.start + i * self.stride + c * size;
        let b = &self.bytes[at..at + size];
        let n = self.normalized;
        match self.component {
            FLOAT => f32::from_le_bytes([b[0], b[1], b[2], b[3]]),
            UNSIGNED_BYTE if n => f32::from(b[0]) / 255.0,
            UNSIGNED_BYTE => f32::from(b[0]),
            BYTE if n => (f32::from(b[0] as i8) / 127.0).max(-1.0),
            BYTE => f32::from(b[0] as i8),
            UNSIGNED_SHORT if n => f32::from(u16::from_le_bytes([b[0], b[1]])) / 65535.0,
            UNSIGNED_SHORT => f32::from(u16::from_le_bytes([b[0], b[1]])),
            SHORT if n => (f32::from(i16::from_le_bytes([b[0], b[1]])) / 32767.0).max(-1.0),
            SHORT => f32::from(i16::from_le_bytes([b[0], b[1]])),
            _ => u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f32,
        }
    }

    /// Element `i`'s single component as an unsigned integer.
    fn index(&self, i: usize) -> u32 {
        let size = component_size(self.component).unwrap_or(4) as usize;
        let at = self.start + i * self.stride;
        let b = &self.bytes[at..at + size];
        match self.component {
            UNSIGNED_BYTE => u32::from(b[0]),
            UNSIGNED_SHORT => u32::from(u16::from_le_bytes([b[0], b[1]])),
            _ => u32::from_le_bytes([b[0], b[1], b[2], b[3]]),
        }
    }
}

impl<'a> Reader<'a> {
    /// Accessor `index`, named at `at` (the key that refers to it).
    fn accessor(&self, index: usize, at: &KeyPath) -> Result<&'a Accessor, Failure> {
        self.doc.accessors.get(index).ok_or_else(|| {
            Failure::at(
                at.clone(),
                format!(
                    "expected an index of `accessors` (0 to {}), found {index}",
                    self.doc.accessors.len() as i64 - 1
                ),
            )
        })
    }

    /// The elements of accessor `index` as `N` floats each.
    pub fn floats<const N: usize>(
        &self,
        index: usize,
        at: &KeyPath,
        expect: &Expect,
    ) -> Result<Vec<[f32; N]>, Failure> {
        let a = self.accessor(index, at)?;
        let name = format!("accessors[{index}]");
        let fail = |m: String| Failure::at(at.clone(), format!("{name}: {m}"));
        self.check_kind(a, expect).map_err(&fail)?;
        let count = a.count as usize;
        let mut out = vec![[0.0f32; N]; count];
        if let Some(run) = self
            .run(a, a.buffer_view, a.byte_offset, N)
            .map_err(&fail)?
        {
            for (i, element) in out.iter_mut().enumerate() {
                for (c, v) in element.iter_mut().enumerate() {
                    *v = run.value(i, c);
                }
            }
        }
        if let Some((indices, values)) = self.sparse(a, N).map_err(&fail)? {
            for (k, &i) in indices.iter().enumerate() {
                for (c, v) in out[i as usize].iter_mut().enumerate() {
                    *v = values.value(k, c);
                }
            }
        }
        Ok(out)
    }

    /// The elements of index accessor `index`.
    pub fn indices(&self, index: usize, at: &KeyPath) -> Result<Vec<u32>, Failure> {
        let a = self.accessor(index, at)?;
        let name = format!("accessors[{index}]");
        let fail = |m: String| Failure::at(at.clone(), format!("{name}: {m}"));
        self.check_kind(a, &INDICES).map_err(&fail)?;
        let mut out = vec![0u32; a.count as usize];
        if let Some(run) = self
            .run(a, a.buffer_view, a.byte_offset, 1)
            .map_err(&fail)?
        {
            for (i, v) in out.iter_mut().enumerate() {
                *v = run.index(i);
            }
        }
        if let Some((indices, values)) = self.sparse(a, 1).map_err(&fail)? {
            for (k, &i) in indices.iter().enumerate() {
                out[i as usize] = values.index(k);
            }
        }
        Ok(out)
    }

    fn check_kind(&self, a: &Accessor, expect: &Expect) -> Result<(), String> {
        if components_of(&a.kind).is_none() {
            return Err(format!(
                "expected `type` SCALAR, VEC2, VEC3, VEC4, MAT2, MAT3 or MAT4, found {:?}",
                a.kind
            ));
        }
        if component_size(a.component_type).is_none() {
            return Err(format!(
                "expected a `componentType` of 5120 to 5126 (not 5124), found {}",
                a.component_type
            ));
        }
        let allowed = |list: &[u32]| {
            list.iter()
                .map(|&c| component_name(c))
                .collect::<Vec<_>>()
                .join(", ")
        };
        if !expect.kinds.contains(&a.kind.as_str())
            || !expect.components.contains(&a.component_type)
        {
            return Err(format!(
                "expected a {} accessor of {}, found {} of {}",
                expect.kinds.join(" or "),
                allowed(expect.components),
                a.kind,
                component_name(a.component_type)
            ));
        }
        let integer = a.component_type != FLOAT;
        if integer && expect.normalized_integers && !a.normalized {
            return Err(format!(
                "expected `normalized: true` on an accessor of {} here",
                component_name(a.component_type)
            ));
        }
        if a.count == 0 {
            return Err("expected a `count` of at least 1, found 0".to_string());
        }
        if a.count > MAX_ELEMENTS {
            return Err(format!(
                "`count` is {}; expected at most {MAX_ELEMENTS} elements",
                a.count
            ));
        }
        Ok(())
    }

    /// Where the `count` elements of `a` (of `n` components) lie, read from
    /// buffer view `view` at `offset`: None without a view (zeros). The
    /// whole range is checked to lie within the view and the view within
    /// its buffer.
    fn run(
        &self,
        a: &Accessor,
        view: Option<usize>,
        offset: u64,
        n: usize,
    ) -> Result<Option<Run<'a>>, String> {
        let Some(v) = view else {
            return Ok(None);
        };
        let size = component_size(a.component_type).expect("checked") * n as u64;
        self.run_of(
            v,
            offset,
            a.count,
            size,
            a.component_type,
            a.normalized,
            true,
        )
        .map(Some)
    }

    #[allow(clippy::too_many_arguments)]
    fn run_of(
        &self,
        v: usize,
        offset: u64,
        count: u64,
        element: u64,
        component: u32,
        normalized: bool,
        strided: bool,
    ) -> Result<Run<'a>, String> {
        let view = self.doc.buffer_views.get(v).ok_or_else(|| {
            format!(
                "its `bufferView` {v} is not an index of `bufferViews` (0 to {})",
                self.doc.buffer_views.len() as i64 - 1
            )
        })?;
        let bytes = self.buffers.get(view.buffer).ok_or_else(|| {
            format!(
                "bufferViews[{v}]: its `buffer` {} is not an index of `buffers` (0 to {})",
                view.buffer,
                self.buffers.len() as i64 - 1
            )
        })?;
        let declared = self.doc.buffers[view.buffer].byte_length;
        let view_end = view.byte_offset.checked_add(view.byte_length);
        if view_end.is_none_or(|end| end > declared) {
            return Err(format!(
                "bufferViews[{v}] runs from byte {} for {} bytes, past the end of buffers[{}] ({declared} bytes)",
                view.byte_offset, view.byte_length, view.buffer
            ));
        }
        let stride = match view.byte_stride.filter(|_| strided) {
            Some(s) if s < element || s > 252 || s % 4 != 0 => {
                return Err(format!(
                    "bufferViews[{v}] has a `byteStride` of {s}; expected a multiple of 4 from {} to 252 for elements of {element} bytes",
                    element.div_ceil(4) * 4
                ))
            }
            Some(s) => s,
            None => element,
        };
        // Every product and sum checked: a count of 2^60 must not wrap.
        let last = (count - 1)
            .checked_mul(stride)
            .and_then(|x| x.checked_add(offset))
            .and_then(|x| x.checked_add(element));
        if last.is_none_or(|end| end > view.byte_length) {
            return Err(format!(
                "{count} elements of {element} bytes, {stride} apart from byte {offset}, reach past the end of bufferViews[{v}] ({} bytes); expected them within the view",
                view.byte_length
            ));
        }
        let start = view.byte_offset + offset;
        // `bytes` holds at least the declared length (checked on loading).
        debug_assert!(start as usize + (last.unwrap_or(0) - offset) as usize <= bytes.len());
        Ok(Run {
            bytes,
            start: start as usize,
            stride: stride as usize,
            component,
            normalized,
        })
    }

    /// A sparse accessor's indices (checked to be increasing and below its
    /// count) and values.
    fn sparse(&self, a: &Accessor, n: usize) -> Result<Option<(Vec<u32>, Run<'a>)>, String> {
        let Some(s) = &a.sparse else {
            return Ok(None);
        };
        if s.count == 0 || s.count > a.count {
            return Err(format!(
                "its `sparse.count` is {}; expected 1 to the accessor's count, {}",
                s.count, a.count
            ));
        }
        let index_size = match s.indices.component_type {
            UNSIGNED_BYTE => 1,
            UNSIGNED_SHORT => 2,
            UNSIGNED_INT => 4,
            other => {
                return Err(format!(
                    "expected `sparse.indices.componentType` 5121, 5123 or 5125, found {other}"
                ))
            }
        };
        let indices = self
            .run_of(
                s.indices.buffer_view,
                s.indices.byte_offset,
                s.count,
                index_size,
                s.indices.component_type,
                false,
                false,
            )
            .map_err(|m| format!("sparse.indices: {m}"))?;
        let element = component_size(a.component_type).expect("checked") * n as u64;
        let values = self
            .run_of(
                s.values.buffer_view,
                s.values.byte_offset,
                s.count,
                element,
                a.component_type,
                a.normalized,
                false,
            )
            .map_err(|m| format!("sparse.values: {m}"))?;
        let mut list = Vec::with_capacity(s.count as usize);
        for k in 0..s.count as usize {
            let i = indices.index(k);
            if u64::from(i) >= a.count || list.last().is_some_and(|&p| i <= p) {
                return Err(format!(
                    "sparse index {k} is {i}; expected strictly increasing indices below the accessor's count, {}",
                    a.count
                ));
            }
            list.push(i);
        }
        Ok(Some((list, values)))
    }
}
