//! `cargo xtask web --serve`: a tiny static file server for trying the page
//! (workers and wasm are not allowed from `file://`): files of the one
//! folder only, on the address given (127.0.0.1 by default). The server
//! itself is `local_server`'s, as `tracer watch --serve`'s is: GET only,
//! requests to its own address only, heads bounded in size and time,
//! connections in number. Unlike that one's, what it serves is files, read
//! from the folder, for a few local tabs and the tests.

use anyhow::{Context, Result};
use bytes::Bytes;
use hyper::StatusCode;
use local_server::{plain, Limits};
use std::net::{SocketAddr, ToSocketAddrs};
use std::path::{Component, Path, PathBuf};
use std::sync::Arc;

/// Serves `dir` on `addr` in a background thread; the address bound.
pub fn start(dir: &Path, addr: &str) -> Result<SocketAddr> {
    let bind = addr
        .to_socket_addrs()
        .with_context(|| format!("cannot listen on {addr}"))?
        .next()
        .with_context(|| format!("cannot listen on {addr}: no address"))?;
    let dir = Arc::new(dir.to_path_buf());
    let server = local_server::start(bind, Limits::default(), move |request| {
        let file = file_of(&dir, request.uri().path());
        async move {
            // Read on the blocking pool: the server's one thread goes on.
            let read = tokio::task::spawn_blocking(move || {
                let file = file?;
                std::fs::read(&file).ok().map(|body| (file, body))
            });
            match read.await.ok().flatten() {
                Some((path, body)) => local_server::bytes(content_type(&path), Bytes::from(body)),
                None => plain(StatusCode::NOT_FOUND, "not found"),
            }
        }
    })?;
    Ok(server.addr)
}

/// The file a request's target names inside `dir`; none for a path that
/// would leave it. `/` is `index.html`; a query or fragment is ignored.
fn file_of(dir: &Path, target: &str) -> Option<PathBuf> {
    let path = target.split(['?', '#']).next()?;
    let path = percent_decode(path.strip_prefix('/')?)?;
    let path = if path.is_empty() || path.ends_with('/') {
        format!("{path}index.html")
    } else {
        path
    };
    let relative = Path::new(&path);
    if !relative
        .components()
        .all(|c| matches!(c, Component::Normal(_)))
    {
        return None;
    }
    Some(dir.join(relative)).filter(|p| p.is_file())
}

fn percent_decode(s: &str) -> Option<String> {
    let bytes = s.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        if bytes[i] == b'%' {
            let hex = std::str::from_utf8(bytes.get(i + 1..i + 3)?).ok()?;
            out.push(u8::from_str_radix(hex, 16).ok()?);
            i += 3;
        } else {
            out.push(bytes[i]);
            i += 1;
        }
    }
    String::from_utf8(out).ok()
}

fn content_type(path: &Path) -> &'static str {
    match path.extension().and_then(|e| e.to_str()).unwrap_or("") {
        "html" => "text/html; charset=utf-8",
        "js" => "text/javascript; charset=utf-8",
        "css" => "text/css; charset=utf-8",
        // compileStreaming needs this type.
        "wasm" => "application/wasm",
        "json" => "application/json",
        "png" => "image/png",
        "toml" | "obj" | "mtl" | "ply" => "text/plain; charset=utf-8",
        _ => "application/octet-stream",
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use local_server::test_client::{self, status_of};

    #[test]
    fn only_files_inside_the_folder_are_served() {
        let dir = tempfile::tempdir().unwrap();
        std::fs::write(dir.path().join("index.html"), "x").unwrap();
        std::fs::create_dir(dir.path().join("a b")).unwrap();
        std::fs::write(dir.path().join("a b/c.toml"), "x").unwrap();
        let d = dir.path();
        assert_eq!(file_of(d, "/"), Some(d.join("index.html")));
        assert_eq!(file_of(d, "/?workers=1#x"), Some(d.join("index.html")));
        assert_eq!(file_of(d, "/a%20b/c.toml"), Some(d.join("a b/c.toml")));
        assert_eq!(file_of(d, "/../etc/passwd"), None);
        assert_eq!(file_of(d, "/a%20b/../index.html"), None);
        assert_eq!(file_of(d, "//etc/passwd"), None);
        assert_eq!(file_of(d, "/missing.js"), None);
    }

    #[test]
    fn an_endless_request_line_and_another_site_s_host_are_refused() {
        let dir = tempfile::tempdir().unwrap();
        std::fs::write(dir.path().join("index.html"), "x").unwrap();
        let addr = start(dir.path(), "127.0.0.1:0").unwrap();
        let port = addr.port();
        let get = |host: &str| test_client::get(host, "/");
        assert_eq!(
            status_of(addr, &get(&format!("127.0.0.1:{port}"))),
            "HTTP/1.1 200 OK"
        );
        // Another site's page, its name rebound to 127.0.0.1.
        assert_eq!(
            status_of(addr, &get(&format!("attacker.example:{port}"))),
            "HTTP/1.1 421 Misdirected Request"
        );
        // A request line that never ends (the server once read it into
        // memory until an allocation failed): refused, and served on.
        let status = status_of(addr, &vec![b'A'; 4 << 20]);
        assert_eq!(status, "HTTP/1.1 431 Request Header Fields Too Large");
        assert_eq!(
            status_of(addr, &get(&format!("localhost:{port}"))),
            "HTTP/1.1 200 OK"
        );
    }
}
