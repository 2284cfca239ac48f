//! `cargo xtask man`: one page per `tracer` command, each with its options.

use std::path::Path;

/// Every command of `tracer`, as the README's table lists them (help excluded).
const PAGES: [&str; 15] = [
    "tracer-new",
    "tracer-convert",
    "tracer",
    "tracer-render",
    "tracer-calib-chart",
    "tracer-gamma",
    "tracer-gamma-fit",
    "tracer-check",
    "tracer-watch",
    "tracer-pack",
    "tracer-merge",
    "tracer-schema",
    "tracer-completions",
    "tracer-compare",
    "tracer-explain",
];

fn page(dir: &Path, name: &str) -> String {
    std::fs::read_to_string(dir.join(format!("{name}.1")))
        .unwrap_or_else(|e| panic!("{name}.1: {e}"))
}

/// roff writes a `-` as `\-`.
fn roff(text: &str) -> String {
    text.replace('-', "\\-")
}

#[test]
fn every_command_has_a_page_with_its_name() {
    let dir = tempfile::tempdir().unwrap();
    let pages = xtask::man::write_pages(dir.path()).unwrap();
    let mut names: Vec<String> = pages
        .iter()
        .map(|p| p.file_stem().unwrap().to_str().unwrap().to_string())
        .collect();
    names.sort();
    let mut expected: Vec<String> = PAGES.iter().map(|s| s.to_string()).collect();
    expected.sort();
    assert_eq!(names, expected);
    for name in PAGES {
        let text = page(dir.path(), name);
        assert!(text.contains(&format!(".TH {name} 1")), "{name}: title");
        assert!(
            text.contains(&format!("{} \\- ", roff(name))),
            "{name}: NAME"
        );
    }
}

#[test]
fn a_page_lists_its_commands_options() {
    let dir = tempfile::tempdir().unwrap();
    xtask::man::write_pages(dir.path()).unwrap();
    // A few options of each, read off `tracer <command> --help`.
    let options = [
        (
            "tracer-render",
            &["--output", "--bit-depth", "--samples", "--aov", "--quiet"][..],
        ),
        ("tracer-watch", &["--serve", "--threads"]),
        ("tracer-calib-chart", &["--gamma", "--width"]),
        ("tracer-gamma-fit", &["--plot"]),
        ("tracer-pack", &["--output"]),
        ("tracer", &["--version"]),
    ];
    for (name, opts) in options {
        let text = page(dir.path(), name);
        for opt in opts {
            assert!(text.contains(&roff(opt)), "{name}.1 lacks {opt}");
        }
    }
    // Every subcommand's page names each of its long options.
    let cmd = tracer_cli::command();
    for sub in cmd.get_subcommands() {
        let text = page(dir.path(), &format!("tracer-{}", sub.get_name()));
        for arg in sub.get_arguments().filter_map(|a| a.get_long()) {
            assert!(
                text.contains(&roff(&format!("--{arg}"))),
                "{}: --{arg}",
                sub.get_name()
            );
        }
    }
}

#[test]
fn the_render_page_says_how_it_is_called() {
    let dir = tempfile::tempdir().unwrap();
    xtask::man::write_pages(dir.path()).unwrap();
    let text = page(dir.path(), "tracer-render");
    assert!(text.contains("\\fBtracer render\\fR"), "synopsis");
    let footer = format!("\"tracer {}\"", env!("CARGO_PKG_VERSION"));
    assert!(text.contains(&footer), "footer names the program");
}

/// The main page says where the book is, as `tracer --help` does.
#[test]
fn the_main_page_points_to_the_book() {
    let dir = tempfile::tempdir().unwrap();
    xtask::man::write_pages(dir.path()).unwrap();
    let text = page(dir.path(), "tracer");
    assert!(text.contains(&roff("docs/src/SUMMARY.md")), "{text}");
}
