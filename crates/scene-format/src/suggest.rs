//! "Did you mean": the known name nearest a misspelt one.

/// The known name closest to a misspelt one, if it is close enough to be
/// a likely typo (a third of the letters or fewer wrong, at least one).
pub fn suggestion<'a>(found: &str, known: &[&'a str]) -> Option<&'a str> {
    let found_lower = found.to_lowercase();
    let allowed = (found.chars().count() / 3).max(1);
    known
        .iter()
        .map(|k| (strsim::damerau_levenshtein(&found_lower, k), *k))
        .filter(|(d, _)| *d <= allowed)
        .min_by_key(|(d, _)| *d)
        .map(|(_, k)| k)
}

/// "did you mean `x`?" for a near miss, else the list of known names.
pub(crate) fn hint(name: &str, known: &[&str]) -> String {
    match suggestion(name, known) {
        Some(s) => format!("did you mean `{s}`?"),
        None => format!("expected one of {}", list(known)),
    }
}

/// Names in backticks: "`a`, `b`".
pub(crate) fn list(names: &[&str]) -> String {
    names
        .iter()
        .map(|n| format!("`{n}`"))
        .collect::<Vec<_>>()
        .join(", ")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn suggestions_catch_typos_and_not_strangers() {
        let camera = ["eye", "look_at", "up", "fov", "width", "height"];
        assert_eq!(suggestion("fvo", &camera), Some("fov"));
        assert_eq!(suggestion("lookat", &camera), Some("look_at"));
        assert_eq!(suggestion("heigth", &camera), Some("height"));
        assert_eq!(suggestion("Width", &camera), Some("width"));
        assert_eq!(suggestion("zoom", &camera), None);
        assert_eq!(suggestion("position", &camera), None);
    }
}
