//! A local page loaded by headless Chromium, which prints its DOM once the
//! page's scripts ran; and what a report page's image check recorded in it.

use anyhow::{bail, Context, Result};
use std::io::Read;
use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// The DOM of `page` (a local HTML file) as Chromium has it once the page has
/// loaded and its scripts ran.
pub fn dump_dom(chromium: &Path, page: &Path, timeout: Duration) -> Result<String> {
    let page = std::fs::canonicalize(page)
        .with_context(|| format!("{}: cannot find the page", page.display()))?;
    let profile = tempfile::tempdir().context("cannot create a browser profile folder")?;
    let mut child = Command::new(chromium)
        .args([
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--disable-quic",
            "--no-first-run",
            "--disable-background-networking",
            "--disable-component-update",
            "--disable-sync",
            // Containers often have a tiny /dev/shm, which crashes Chromium.
            "--disable-dev-shm-usage",
            "--virtual-time-budget=10000",
            "--dump-dom",
        ])
        .arg(format!("--user-data-dir={}", profile.path().display()))
        .arg(file_url(&page))
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .with_context(|| format!("cannot start {}", chromium.display()))?;
    let mut stdout = child.stdout.take().context("no stdout")?;
    let mut stderr = child.stderr.take().context("no stderr")?;
    let out = std::thread::spawn(move || {
        let mut s = String::new();
        stdout.read_to_string(&mut s).map(|_| s)
    });
    let err = std::thread::spawn(move || {
        let mut s = String::new();
        let _ = stderr.read_to_string(&mut s);
        s
    });
    let status = wait_with_timeout(&mut child, timeout)?;
    let dom = out.join().expect("the reader thread does not panic")?;
    let log = err.join().unwrap_or_default();
    if !status.success() {
        bail!("{} failed ({status}):\n{log}", chromium.display());
    }
    Ok(dom)
}

fn wait_with_timeout(
    child: &mut std::process::Child,
    timeout: Duration,
) -> Result<std::process::ExitStatus> {
    let start = Instant::now();
    loop {
        if let Some(status) = child.try_wait()? {
            return Ok(status);
        }
        if start.elapsed() > timeout {
            let _ = child.kill();
            let _ = child.wait();
            bail!("the browser did not finish within {timeout:?}");
        }
        std::thread::sleep(Duration::from_millis(50));
    }
}

/// `file://` URL of an absolute path, with every byte outside the safe set escaped.
fn file_url(path: &Path) -> String {
    let escaped: String = path
        .to_string_lossy()
        .bytes()
        .map(|b| match b {
            b'A'..=b'Z' | b'a'..=b'z' | b'0'..=b'9' | b'-' | b'.' | b'_' | b'~' | b'/' => {
                (b as char).to_string()
            }
            _ => format!("%{b:02X}"),
        })
        .collect();
    format!("file://{escaped}")
}

/// What the report page's script recorded about its images.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ImageCheck {
    pub total: usize,
    pub loaded: usize,
    /// The `src` of every image that did not load.
    pub failed: Vec<String>,
}

/// Reads the record of the `<output id="image-check">` element in a dumped
/// DOM; an error when the script did not run.
pub fn image_check(dom: &str) -> Result<ImageCheck> {
    let start = dom
        .find("id=\"image-check\"")
        .context("the page has no image-check element")?;
    let tag_start = dom[..start].rfind('<').context("malformed DOM")?;
    let tag_end = start + dom[start..].find('>').context("malformed DOM")?;
    let tag = &dom[tag_start..tag_end];
    let number = |name: &str| -> Result<usize> {
        attribute(tag, name)
            .with_context(|| format!("the page's image check did not run (no {name})"))?
            .parse()
            .with_context(|| format!("{name} is not a number"))
    };
    Ok(ImageCheck {
        total: number("data-total")?,
        loaded: number("data-loaded")?,
        failed: attribute(tag, "data-failed")
            .unwrap_or("")
            .split_whitespace()
            .map(str::to_string)
            .collect(),
    })
}

fn attribute<'a>(tag: &'a str, name: &str) -> Option<&'a str> {
    let key = format!(" {name}=\"");
    let start = tag.find(&key)? + key.len();
    let len = tag[start..].find('"')?;
    Some(&tag[start..start + len])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_the_record_from_a_dumped_dom() {
        let dom = r#"<html><body><output id="image-check" data-total="3" data-loaded="2" data-failed="a%20b-diff.png">x</output></body></html>"#;
        assert_eq!(
            image_check(dom).unwrap(),
            ImageCheck {
                total: 3,
                loaded: 2,
                failed: vec!["a%20b-diff.png".to_string()]
            }
        );
    }

    #[test]
    fn a_page_whose_script_did_not_run_is_an_error() {
        let dom = r#"<output id="image-check">Image check did not run</output>"#;
        let err = image_check(dom).unwrap_err().to_string();
        assert!(err.contains("did not run"), "{err}");
        assert!(image_check("<html></html>").is_err());
    }

    #[test]
    fn file_urls_escape_odd_characters() {
        assert_eq!(
            file_url(Path::new("/tmp/a b#/index.html")),
            "file:///tmp/a%20b%23/index.html"
        );
    }
}
