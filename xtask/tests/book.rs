//! `cargo xtask book`: the book's pages are sound (links, images, anchors,
//! the summary, the commands of its `sh` blocks), its generated pages are
//! current and say what the definitions say, and the README fits on a
//! screen. None of it needs mdbook. (Its scenes are checked with the
//! `tracer` binary itself: crates/tracer-cli/tests/book.rs.)

use clap::CommandFactory;
use std::path::{Path, PathBuf};
use xtask::book;

fn root() -> PathBuf {
    xtask::workspace_root()
}

#[test]
fn the_books_pages_are_sound_and_the_generated_ones_current() {
    let problems = book::check(&root()).unwrap();
    assert!(
        problems.is_empty(),
        "{}\n(run cargo xtask book --check)",
        problems.join("\n")
    );
}

fn write(dir: &Path, file: &str, text: &str) {
    let path = dir.join(file);
    std::fs::create_dir_all(path.parent().unwrap()).unwrap();
    std::fs::write(path, text).unwrap();
}

/// The checks themselves, on a small book with one mistake of each kind.
#[test]
fn a_broken_link_a_lost_page_and_a_misspelt_command_are_each_reported() {
    let dir = tempfile::tempdir().unwrap();
    let root = dir.path();
    write(
        root,
        "docs/src/SUMMARY.md",
        "# Summary\n\n- [A](a.md)\n- [Gone](gone.md)\n",
    );
    write(
        root,
        "docs/src/a.md",
        "# A\n\n## Its part\n\n[ok](a.md#its-part) [self](#its-part) [bad](#nope)\n\
         [missing](b.md) ![no picture](pic.png) [outside](../../README.md)\n\n\
         ```sh\ntracer render scenes/a.toml --samples 4\ntracer rendr scenes/a.toml\n\
         cargo xtask golden --blesss\nls -l\n```\n",
    );
    write(root, "docs/src/lost.md", "# Lost\n");
    write(
        root,
        "README.md",
        "# R\n\n[book](docs/src/a.md) [folder](docs/) [no](nothing.md)\n",
    );
    let mut problems = book::links::check(root).unwrap();
    problems.extend(book::commands::check(root).unwrap());
    let expected = [
        "docs/src/a.md:5: `#nope`: no heading of docs/src/a.md has the anchor `nope`",
        "docs/src/a.md:6: `b.md` does not exist",
        "docs/src/a.md:6: `pic.png` does not exist",
        "docs/src/a.md:6: `../../README.md` is a page outside the book",
        "docs/src/lost.md: not in SUMMARY.md",
        "README.md:3: `nothing.md` does not exist",
        "docs/src/SUMMARY.md:4: `gone.md` does not exist",
        "docs/src/a.md:10: `tracer rendr scenes/a.toml`",
        "docs/src/a.md:11: `cargo xtask golden --blesss`",
    ];
    for want in expected {
        assert!(
            problems.iter().any(|p| p.contains(want)),
            "{want} not in\n{}",
            problems.join("\n")
        );
    }
    assert_eq!(problems.len(), expected.len(), "{}", problems.join("\n"));
}

/// Every key of every definition in the schema has its place on the
/// page, and a key one integrator alone reads says so.
#[test]
fn the_reference_names_every_key_of_the_schema() {
    let page = std::fs::read_to_string(root().join(book::KEYS_PAGE)).unwrap();
    let schema: serde_json::Value =
        serde_json::from_str(&scene_format::schema::json_schema()).unwrap();
    let mut keys = 0;
    for (def, body) in schema["$defs"].as_object().unwrap() {
        let Some(props) = body["properties"].as_object() else {
            continue;
        };
        for (key, value) in props {
            keys += 1;
            let named = page.contains(&format!("`{key}`"))
                || page.contains(&format!(".{key}`"))
                || page.contains(&format!("]{key}`"));
            assert!(named, "{def}.{key} is not on the page");
            if let Some(by) = value["x-integrator"].as_str() {
                let words = if by == "path" {
                    "path mode only"
                } else {
                    "Whitted mode only"
                };
                let section = page
                    .split(&format!(".{key}`\n\n"))
                    .nth(1)
                    .unwrap_or_else(|| panic!("{key}: no section"));
                let facts = section.lines().next().unwrap();
                assert!(
                    facts.contains(&format!("Read by: {words}")),
                    "{key}: {facts}"
                );
            }
        }
    }
    assert!(keys > 80, "{keys} keys");
    // The page's lines come from the definitions: a description, a default.
    assert!(page.contains("Horizontal field of view in degrees, at least 1 and below 180."));
    assert!(page.contains("| [`camera.fov`](#camerafov) | a number | `50` | both |"));
    assert!(page.contains("Example, from `scenes/"));
}

/// Every command and option of `tracer` is on the commands page.
#[test]
fn the_commands_page_has_every_command_and_option() {
    let page = std::fs::read_to_string(root().join(book::COMMANDS_PAGE)).unwrap();
    fn walk(cmd: &clap::Command, name: &str, page: &str) {
        assert!(page.contains(&format!("## `{name}`\n")), "{name}");
        for arg in cmd.get_arguments().filter_map(|a| a.get_long()) {
            assert!(page.contains(&format!("--{arg}")), "{name} --{arg}");
        }
        for sub in cmd
            .get_subcommands()
            .filter(|s| !s.is_hide_set() && s.get_name() != "help")
        {
            walk(sub, &format!("{name} {}", sub.get_name()), page);
        }
    }
    walk(&tracer_cli::command(), "tracer", &page);
}

#[test]
fn the_readme_starts_with_the_two_commands_and_fits_on_a_screen() {
    let readme = std::fs::read_to_string(root().join("README.md")).unwrap();
    let start: Vec<&str> = readme.lines().take(6).collect();
    assert_eq!(
        start,
        [
            "# tracer: a data-driven ray tracer",
            "",
            "```sh",
            "cargo run --release --bin tracer -- render scenes/reflectance2.toml",
            "cargo test --workspace --release",
            "```",
        ]
    );
    let lines = readme.lines().count();
    assert!(lines <= 200, "README.md has {lines} lines");
    // Its tables name every command, one line each.
    for sub in tracer_cli::command().get_subcommands() {
        let row = format!("| `tracer {}", sub.get_name());
        assert!(readme.contains(&row), "{row}");
    }
    for sub in xtask::cli::Cli::command()
        .get_subcommands()
        .filter(|s| !s.is_hide_set())
    {
        let row = format!("| `cargo xtask {}", sub.get_name());
        assert!(readme.contains(&row), "{row}");
    }
}

/// The staged copy mdbook builds from holds every file the pages show, and
/// every link of a staged page stays inside it.
#[test]
fn the_staged_book_holds_every_file_its_pages_link() {
    let dir = tempfile::tempdir().unwrap();
    let stage = dir.path().join("stage");
    book::build::stage_book(&root(), &stage).unwrap();
    assert!(stage.join("book.toml").is_file());
    let src = stage.join("src");
    let mut pages = 0;
    for page in book::pages(&root()).unwrap() {
        let Ok(rel) = page.strip_prefix(root().join(book::SRC)) else {
            continue;
        };
        let staged = src.join(rel);
        let text = std::fs::read_to_string(&staged).unwrap();
        pages += 1;
        for link in book::markdown::links(&text) {
            let path = link.target.split('#').next().unwrap();
            if path.is_empty() || path.contains("://") {
                continue;
            }
            let target = book::links::normalize(&staged.parent().unwrap().join(path));
            assert!(
                target.starts_with(&src),
                "{}: {path} leaves the book",
                rel.display()
            );
            assert!(target.exists(), "{}: {path} is not staged", rel.display());
        }
    }
    assert!(pages > 30, "{pages} pages");
    assert!(src.join("repo/golden/reflectance2.png").is_file());
    assert!(src.join("repo/scenes/shadows.toml").is_file());
}

/// The playground's help link names the book's page of the playground, as
/// mdbook writes it (`guide/playground.md` as `guide/playground.html`).
#[test]
fn the_playgrounds_help_link_names_the_books_playground_page() {
    let page = std::fs::read_to_string(root().join("web/index.html")).unwrap();
    let href = page
        .split("id=\"help\" href=\"")
        .nth(1)
        .and_then(|rest| rest.split('"').next())
        .expect("a help link");
    let in_book = href
        .strip_prefix("book/")
        .expect("the book beside the page");
    let source = root().join(book::SRC).join(in_book.replace(".html", ".md"));
    assert!(source.is_file(), "{href}: no {}", source.display());
}
