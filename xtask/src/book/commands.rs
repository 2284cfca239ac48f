//! The commands the book shows: every line of a `sh` block that runs
//! `tracer` (or `cargo run ... --bin tracer --`, or `cargo xtask`) parses
//! with the clap definition the binary itself parses, so a renamed command
//! or option fails a test; and the page of every command's `--help`.

use super::markdown;
use super::{pages, shown};
use anyhow::{Context, Result};
use clap::{CommandFactory, Parser};
use std::fmt::Write;
use std::path::Path;

/// The problems of the `sh` blocks of the book and the README.
pub fn check(root: &Path) -> Result<Vec<String>> {
    let mut problems = Vec::new();
    for page in pages(root)? {
        let text = std::fs::read_to_string(&page)
            .with_context(|| format!("cannot read {}", page.display()))?;
        for fence in markdown::fences(&text) {
            if !matches!(fence.lang.as_str(), "sh" | "bash" | "shell") {
                continue;
            }
            for (offset, line) in command_lines(&fence.body) {
                if let Err(problem) = check_line(&line) {
                    let at = fence.line + 1 + offset;
                    problems.push(format!("{}:{at}: `{line}`: {problem}", shown(root, &page)));
                }
            }
        }
    }
    Ok(problems)
}

/// A block's commands with their line offsets: `$ ` prompts and comments
/// taken off, lines continued by `\` joined.
pub fn command_lines(body: &str) -> Vec<(usize, String)> {
    let mut out: Vec<(usize, String)> = Vec::new();
    let mut continued = false;
    for (i, raw) in body.lines().enumerate() {
        let line = raw.trim();
        let line = line.strip_prefix("$ ").unwrap_or(line);
        let (text, more) = match line.strip_suffix('\\') {
            Some(head) => (head.trim_end(), true),
            None => (line, false),
        };
        if continued {
            if let Some((_, last)) = out.last_mut() {
                last.push(' ');
                last.push_str(text);
            }
        } else if !text.is_empty() && !text.starts_with('#') {
            out.push((i, text.to_string()));
        }
        continued = more;
    }
    out
}

/// Whether one command line is one `tracer` or `cargo xtask` accepts;
/// other programs' lines pass unread.
pub fn check_line(line: &str) -> Result<(), String> {
    let words = words(line);
    let mut words: Vec<&str> = words.iter().map(String::as_str).collect();
    // `VAR=value command ...`
    while words.first().is_some_and(|w| is_assignment(w)) {
        words.remove(0);
    }
    match words.as_slice() {
        ["tracer", ..] => parse_tracer(&words),
        ["cargo", "xtask", rest @ ..] => {
            let mut argv = vec!["cargo xtask"];
            argv.extend(rest);
            parsed(crate::cli::Cli::try_parse_from(argv).map(drop))
        }
        ["cargo", "run", rest @ ..] if rest.windows(2).any(|w| w == ["--bin", "tracer"]) => {
            let Some(dashes) = rest.iter().position(|w| *w == "--") else {
                return Err("`cargo run --bin tracer` without `--` before its arguments".into());
            };
            let mut argv = vec!["tracer"];
            argv.extend(&rest[dashes + 1..]);
            parse_tracer(&argv)
        }
        _ => Ok(()),
    }
}

fn parse_tracer(argv: &[&str]) -> Result<(), String> {
    parsed(tracer_cli::Cli::try_parse_from(argv).map(drop))
}

fn parsed(result: Result<(), clap::Error>) -> Result<(), String> {
    use clap::error::ErrorKind;
    match result {
        Ok(()) => Ok(()),
        Err(e) if matches!(e.kind(), ErrorKind::DisplayHelp | ErrorKind::DisplayVersion) => Ok(()),
        Err(e) => Err(e
            .render()
            .to_string()
            .lines()
            .next()
            .unwrap_or_default()
            .to_string()),
    }
}

fn is_assignment(word: &str) -> bool {
    word.split_once('=').is_some_and(|(name, _)| {
        !name.is_empty()
            && name
                .chars()
                .all(|c| c.is_ascii_uppercase() || c == '_' || c.is_ascii_digit())
    })
}

/// The words of a shell line up to its first pipe, redirection, `;`, `&&`
/// or comment, quotes taken off.
pub fn words(line: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut word = String::new();
    let mut in_word = false;
    let mut quote: Option<char> = None;
    for c in line.chars() {
        match quote {
            Some(q) if c == q => quote = None,
            Some(_) => word.push(c),
            None => match c {
                '\'' | '"' => {
                    quote = Some(c);
                    in_word = true;
                }
                '|' | '>' | '<' | ';' | '&' => break,
                '#' if !in_word => break,
                c if c.is_whitespace() => {
                    if in_word {
                        out.push(std::mem::take(&mut word));
                        in_word = false;
                    }
                }
                c => {
                    word.push(c);
                    in_word = true;
                }
            },
        }
    }
    if in_word {
        out.push(word);
    }
    // `2>` leaves its `2`.
    if out.last().is_some_and(|w| w == "2") && line.contains("2>") {
        out.pop();
    }
    out
}

/// The page of every command: its `--help`, as `tracer help CMD` prints it.
pub fn reference_page() -> String {
    let mut out = String::from(
        "# Commands\n\n\
         <!-- Generated by `cargo xtask book` from the command line's definition \
         (crates/tracer-cli/src/args.rs): edit the definition, not this page. -->\n\n\
         Every command of `tracer` and its options, as `tracer COMMAND --help` prints \
         them. The same text makes the man pages (`cargo xtask man`).\n",
    );
    let mut cmd = tracer_cli::Cli::command().disable_help_subcommand(true);
    cmd.build();
    section(&mut out, &cmd, "tracer");
    out
}

fn section(out: &mut String, cmd: &clap::Command, name: &str) {
    let mut cmd = cmd.clone().bin_name(name);
    let help = cmd.render_long_help().to_string();
    let _ = write!(out, "\n## `{name}`\n\n```text\n{}\n```\n", help.trim_end());
    for sub in cmd.get_subcommands().filter(|s| !s.is_hide_set()) {
        section(out, sub, &format!("{name} {}", sub.get_name()));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_line_is_its_words_up_to_a_pipe_or_comment() {
        assert_eq!(
            words("tracer render 'a b.toml' -o x.png  # note"),
            ["tracer", "render", "a b.toml", "-o", "x.png"]
        );
        assert_eq!(words("tracer schema > schema.json"), ["tracer", "schema"]);
        assert_eq!(
            words("tracer check a.toml 2> errors.txt"),
            ["tracer", "check", "a.toml"]
        );
    }

    #[test]
    fn real_commands_pass_and_misspelt_ones_fail() {
        assert!(check_line("tracer render scenes/a.toml --samples 16").is_ok());
        assert!(check_line("cargo run --release --bin tracer -- render scenes/a.toml").is_ok());
        assert!(check_line("cargo xtask golden --bless texture").is_ok());
        assert!(check_line("tracer --help").is_ok());
        assert!(check_line("ls -l").is_ok());
        assert!(check_line("tracer rendr scenes/a.toml").is_err());
        assert!(check_line("tracer render scenes/a.toml --sample 16").is_err());
        assert!(check_line("tracer explain scenes/a.toml X Y").is_err());
        assert!(check_line("cargo xtask gold").is_err());
        assert!(check_line("NO_COLOR=1 tracer check --fast a.toml").is_err());
    }

    #[test]
    fn prompts_comments_and_continuations() {
        let body = "# a comment\n$ tracer render a.toml \\\n    --samples 4\ntracer check a.toml\n";
        assert_eq!(
            command_lines(body),
            [
                (1, "tracer render a.toml --samples 4".to_string()),
                (3, "tracer check a.toml".to_string())
            ]
        );
    }
}
