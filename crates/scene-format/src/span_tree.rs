//! A parsed document reduced to what locating needs: the byte span of
//! every key and value, and their nesting. TOML's comes from the toml
//! crate's spanned parse; JSON's from `json_spans`.

pub use crate::span_node::{Node, NodeKind};
use crate::{json_spans, Format};

/// The span-keeping tree of `text`, or `None` if the text does not parse.
pub fn tree(text: &str, format: Format) -> Option<Node> {
    match format {
        Format::Toml => toml_tree(text),
        Format::Json => json_spans::parse(text).ok(),
    }
}

fn toml_tree(text: &str) -> Option<Node> {
    let table = toml::de::DeTable::parse(text).ok()?;
    let span = table.span();
    Some(Node {
        span,
        kind: toml_table(table.get_ref()),
    })
}

fn toml_table(table: &toml::de::DeTable<'_>) -> NodeKind {
    NodeKind::Table(
        table
            .iter()
            .map(|(k, v)| (k.get_ref().to_string(), k.span(), toml_node(v)))
            .collect(),
    )
}

fn toml_node(value: &toml::Spanned<toml::de::DeValue<'_>>) -> Node {
    use toml::de::DeValue;
    let kind = match value.get_ref() {
        DeValue::Table(t) => toml_table(t),
        DeValue::Array(a) => NodeKind::Array(a.iter().map(toml_node).collect()),
        _ => NodeKind::Scalar,
    };
    Node {
        span: value.span(),
        kind,
    }
}
