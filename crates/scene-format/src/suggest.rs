//! "Did you mean": the known name nearest a misspelt one.

/// Names longer than this get no "did you mean": comparing two names
/// costs the product of their lengths, and no one misspells a name this
/// long letter by letter.
const MAX_NAME_LEN: usize = 64;
/// At most this many names are listed as expected.
const MAX_LISTED: usize = 10;

/// The known name closest to a misspelt one, if it is close enough to be
/// a likely typo (a third of the letters or fewer wrong, at least one).
pub fn suggestion<'a>(found: &str, known: &[&'a str]) -> Option<&'a str> {
    let len = found.chars().count();
    if len > MAX_NAME_LEN {
        return None;
    }
    let found_lower = found.to_lowercase();
    let allowed = (len / 3).max(1);
    known
        .iter()
        // The length difference alone rules most names out, cheaply.
        .filter(|k| k.len() <= 4 * MAX_NAME_LEN && k.chars().count().abs_diff(len) <= allowed)
        .map(|k| (strsim::damerau_levenshtein(&found_lower, k), *k))
        .filter(|(d, _)| *d <= allowed)
        .min_by_key(|(d, _)| *d)
        .map(|(_, k)| k)
}

/// Keys other renderers (and textbooks) use, each with the keys of this
/// format that say the same: no misspelling is near them.
const SYNONYMS: &[(&[&str], &[&str])] = &[
    (
        &[
            "color",
            "colour",
            "albedo",
            "basecolor",
            "base_colour",
            "kd",
        ],
        &["diffuse", "base_color"],
    ),
    (
        &[
            "emissive",
            "emit",
            "emittance",
            "radiance",
            "intensity",
            "power",
            "ke",
        ],
        &["emission", "color"],
    ),
    (&["metalness", "metal"], &["metallic"]),
    (&["eta", "refraction", "refractive_index", "ni"], &["ior"]),
    (
        &["transparency", "transparent", "refract"],
        &["transmittance", "transmission"],
    ),
    (&["spp", "samples_per_pixel", "paths"], &["samples"]),
    (
        &["depth", "maxdepth", "max_bounces", "bounces"],
        &["max_depth"],
    ),
];

/// "did you mean `a` or `b`?" for a key another renderer would use, when
/// this table has keys for it.
pub(crate) fn synonym_hint(found: &str, known: &[&str]) -> Option<String> {
    let found = found.to_lowercase();
    let (_, targets) = SYNONYMS
        .iter()
        .find(|(aliases, _)| aliases.contains(&found.as_str()))?;
    let present: Vec<String> = targets
        .iter()
        .filter(|t| known.contains(t) && **t != found)
        .map(|t| format!("`{t}`"))
        .collect();
    (!present.is_empty()).then(|| format!("did you mean {}?", present.join(" or ")))
}

/// "did you mean `x`?" for a near miss, else the list of known names.
pub(crate) fn hint(name: &str, known: &[&str]) -> String {
    match suggestion(name, known) {
        Some(s) => format!("did you mean `{s}`?"),
        None => format!("expected one of {}", list(known)),
    }
}

/// Names in backticks: "`a`, `b`", all of them.
pub(crate) fn list_all(names: &[&str]) -> String {
    let listed: Vec<String> = names.iter().map(|n| format!("`{n}`")).collect();
    listed.join(", ")
}

/// Names in backticks: "`a`, `b`"; the first ten of a long list, then
/// how many more.
pub(crate) fn list(names: &[&str]) -> String {
    let mut out = names
        .iter()
        .take(MAX_LISTED)
        .map(|n| format!("`{n}`"))
        .collect::<Vec<_>>()
        .join(", ");
    if names.len() > MAX_LISTED {
        out += &format!(" and {} more", names.len() - MAX_LISTED);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn other_renderers_keys_are_pointed_to_this_formats_when_the_table_has_them() {
        let material = ["diffuse", "emission", "base_color", "metallic", "ior"];
        let hint = |found| synonym_hint(found, &material);
        assert_eq!(
            hint("albedo").unwrap(),
            "did you mean `diffuse` or `base_color`?"
        );
        assert_eq!(hint("Metalness").unwrap(), "did you mean `metallic`?");
        assert_eq!(hint("intensity").unwrap(), "did you mean `emission`?");
        let light = ["position", "color", "radius"];
        assert_eq!(
            synonym_hint("intensity", &light).unwrap(),
            "did you mean `color`?"
        );
        assert_eq!(synonym_hint("spp", &light), None);
        assert_eq!(hint("glow"), None);
    }

    #[test]
    fn suggestions_catch_typos_and_not_strangers() {
        let camera = ["eye", "look_at", "up", "fov", "width", "height"];
        assert_eq!(suggestion("fvo", &camera), Some("fov"));
        assert_eq!(suggestion("lookat", &camera), Some("look_at"));
        assert_eq!(suggestion("heigth", &camera), Some("height"));
        assert_eq!(suggestion("Width", &camera), Some("width"));
        assert_eq!(suggestion("zoom", &camera), None);
        assert_eq!(suggestion("position", &camera), None);
        let long = "x".repeat(20_000);
        assert_eq!(suggestion(&long, &[long.as_str()]), None);
    }

    #[test]
    fn long_lists_name_ten() {
        let names: Vec<String> = (0..5000).map(|i| format!("m{i}")).collect();
        let names: Vec<&str> = names.iter().map(String::as_str).collect();
        let l = list(&names);
        assert!(l.ends_with("`m9` and 4990 more"), "{l}");
    }
}
