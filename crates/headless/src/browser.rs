//! Headless Chromium showing a page, driven over its DevTools socket: a
//! test or the bench reads and scripts the live page.

use anyhow::{bail, Context, Result};
use std::io::{BufRead, BufReader};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

const START: Duration = Duration::from_secs(60);

pub struct Browser {
    child: Child,
    socket: tungstenite::WebSocket<std::net::TcpStream>,
    /// The DevTools session attached to the page.
    session: String,
    next_id: u64,
    _profile: tempfile::TempDir,
}

impl Browser {
    /// Chromium (`chromium`, see `crate::find_chromium`) showing `url`.
    pub fn open(chromium: &std::path::Path, url: &str) -> Result<Browser> {
        let profile = tempfile::tempdir()?;
        let mut child = Command::new(chromium)
            .args([
                "--headless",
                "--no-sandbox",
                "--disable-gpu",
                "--disable-dev-shm-usage",
                "--no-first-run",
                "--disable-background-networking",
                "--disable-component-update",
                "--remote-debugging-port=0",
                "--window-size=1280,800",
            ])
            .arg(format!("--user-data-dir={}", profile.path().display()))
            .arg(url)
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .with_context(|| format!("cannot start {}", chromium.display()))?;
        let socket_url = devtools_url(child.stderr.take().context("stderr")?)?;
        let port: u16 = socket_url
            .trim_start_matches("ws://127.0.0.1:")
            .split('/')
            .next()
            .and_then(|p| p.parse().ok())
            .context("no port in the DevTools address")?;
        let stream = std::net::TcpStream::connect(("127.0.0.1", port))?;
        stream.set_read_timeout(Some(Duration::from_secs(600)))?;
        let (socket, _) = tungstenite::client(socket_url.as_str(), stream)
            .map_err(|e| anyhow::anyhow!("DevTools: {e}"))?;
        let mut browser = Browser {
            child,
            socket,
            session: String::new(),
            next_id: 1,
            _profile: profile,
        };
        browser.session = browser.attach(url)?;
        Ok(browser)
    }

    /// Attaches to the page showing `url`, once it is there.
    fn attach(&mut self, url: &str) -> Result<String> {
        let end = Instant::now() + START;
        while Instant::now() < end {
            let targets = self.call("Target.getTargets", serde_json::json!({}))?;
            let page = targets["targetInfos"]
                .as_array()
                .into_iter()
                .flatten()
                .find(|t| t["type"] == "page" && t["url"].as_str() == Some(url));
            if let Some(id) = page.map(|p| p["targetId"].clone()) {
                let params = serde_json::json!({ "targetId": id, "flatten": true });
                let attached = self.call("Target.attachToTarget", params)?;
                return Ok(attached["sessionId"]
                    .as_str()
                    .context("no DevTools session")?
                    .to_string());
            }
            std::thread::sleep(Duration::from_millis(100));
        }
        bail!("Chromium opened no page at {url}")
    }

    /// Calls DevTools' `method` (in the page's session once attached).
    pub fn call(&mut self, method: &str, params: serde_json::Value) -> Result<serde_json::Value> {
        let id = self.next_id;
        self.next_id += 1;
        let mut call = serde_json::json!({ "id": id, "method": method, "params": params });
        if !self.session.is_empty() {
            call["sessionId"] = self.session.clone().into();
        }
        self.socket
            .send(call.to_string().into())
            .map_err(|e| anyhow::anyhow!("DevTools: {e}"))?;
        loop {
            let message = self
                .socket
                .read()
                .map_err(|e| anyhow::anyhow!("DevTools: {e}"))?;
            let Ok(text) = message.to_text() else {
                continue;
            };
            let answer: serde_json::Value = serde_json::from_str(text)?;
            if answer["id"] == id {
                if let Some(error) = answer.get("error") {
                    bail!("{method}: {error}");
                }
                return Ok(answer["result"].clone());
            }
        }
    }

    /// The value of the JavaScript `expression` in the page (promises awaited).
    pub fn eval(&mut self, expression: &str) -> Result<serde_json::Value> {
        let params = serde_json::json!({
            "expression": expression,
            "returnByValue": true,
            "awaitPromise": true,
        });
        let result = self.call("Runtime.evaluate", params)?;
        if let Some(e) = result.get("exceptionDetails") {
            bail!("{expression}: {e}");
        }
        Ok(result["result"]["value"].clone())
    }

    /// Waits up to `limit` for `expression` to be true in the page.
    pub fn wait_for(&mut self, expression: &str, limit: Duration) -> Result<()> {
        let end = Instant::now() + limit;
        while Instant::now() < end {
            // An exception (the page still loading) counts as not yet.
            if self.eval(expression).ok() == Some(serde_json::Value::Bool(true)) {
                return Ok(());
            }
            std::thread::sleep(Duration::from_millis(50));
        }
        let body = self.eval("document.body?.outerHTML")?;
        let body = body.as_str().unwrap_or_default();
        let shown: String = body.chars().take(4000).collect();
        bail!("{expression} not true within {limit:?}; the page's body:\n{shown}")
    }

    /// A screenshot of the page, PNG bytes.
    pub fn screenshot(&mut self) -> Result<Vec<u8>> {
        let shot = self.call(
            "Page.captureScreenshot",
            serde_json::json!({ "format": "png" }),
        )?;
        base64_decode(shot["data"].as_str().context("no screenshot")?)
    }
}

impl Drop for Browser {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// The browser's socket in "DevTools listening on ws://..." on Chromium's
/// stderr, which is drained afterwards.
fn devtools_url(stderr: std::process::ChildStderr) -> Result<String> {
    let mut lines = BufReader::new(stderr).lines();
    for line in lines.by_ref().map_while(Result::ok) {
        if let Some(at) = line.find("ws://") {
            let url = line[at..].trim().to_string();
            std::thread::spawn(move || lines.for_each(drop));
            return Ok(url);
        }
    }
    bail!("Chromium did not open its DevTools socket")
}

/// Standard, padded base64: what the DevTools protocol, `btoa` and
/// `toDataURL` write.
pub fn base64_decode(text: &str) -> Result<Vec<u8>> {
    use base64::Engine;
    Ok(base64::engine::general_purpose::STANDARD.decode(text)?)
}
