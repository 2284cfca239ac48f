//! The node of a span-keeping tree: what the TOML and JSON readers build
//! and what locating walks.

use std::ops::Range;

/// A parsed document reduced to what locating needs: spans and nesting.
#[derive(Debug)]
pub struct Node {
    pub span: Range<usize>,
    pub kind: NodeKind,
}

#[derive(Debug)]
pub enum NodeKind {
    /// Entries in file order: key, key span, value.
    Table(Vec<(String, Range<usize>, Node)>),
    Array(Vec<Node>),
    Scalar,
}
