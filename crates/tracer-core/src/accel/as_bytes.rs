//! The tree's plain-data vectors (nodes, triangle blocks) serialized as
//! their bytes: read back with one copy instead of float by float (a kept
//! bunny decoded in about 1 ms instead of 4.5). The bytes are this
//! machine's layout, which is all a kept scene needs: it is read only by
//! the same build of the tracer.

use bytemuck::Pod;
use serde::de::{Error, SeqAccess, Visitor};
use serde::{Deserializer, Serializer};
use std::fmt;
use std::marker::PhantomData;

pub(super) fn serialize<T: Pod, S: Serializer>(
    items: &[T],
    serializer: S,
) -> Result<S::Ok, S::Error> {
    serializer.serialize_bytes(bytemuck::cast_slice(items))
}

pub(super) fn deserialize<'de, T: Pod, D: Deserializer<'de>>(
    deserializer: D,
) -> Result<Vec<T>, D::Error> {
    deserializer.deserialize_bytes(Items(PhantomData))
}

/// Reads the bytes of a `Vec<T>`.
struct Items<T>(PhantomData<T>);

impl<'de, T: Pod> Visitor<'de> for Items<T> {
    type Value = Vec<T>;

    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        write!(f, "bytes of items of {} bytes", size_of::<T>())
    }

    fn visit_bytes<E: Error>(self, bytes: &[u8]) -> Result<Vec<T>, E> {
        if !bytes.len().is_multiple_of(size_of::<T>()) {
            return Err(E::invalid_length(bytes.len(), &self));
        }
        // A copy into memory aligned for T (the bytes may be at any address).
        Ok(bytemuck::pod_collect_to_vec(bytes))
    }

    /// The bytes as a sequence of numbers: a format without a byte string
    /// (JSON) writes them so.
    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Vec<T>, A::Error> {
        let mut bytes = Vec::new();
        while let Some(byte) = seq.next_element::<u8>()? {
            bytes.push(byte);
        }
        self.visit_bytes(&bytes)
    }
}
