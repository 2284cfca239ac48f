//! A client of one raw request, shared by the tests of the servers built
//! on this crate (its own, `tracer watch --serve`'s and `cargo xtask web
//! --serve`'s): it sends the bytes as they are, as a careless or hostile
//! client would, and reads the answer's status line. It panics when it
//! cannot connect: a test's failure.

use std::io::{Read, Write};
use std::net::{SocketAddr, TcpStream};
use std::time::Duration;

/// The status line of the answer to `request`, sent raw ("" when the
/// server closed without one).
pub fn status_of(addr: SocketAddr, request: &[u8]) -> String {
    let mut stream = TcpStream::connect(addr).expect("connect to the server");
    stream
        .set_read_timeout(Some(Duration::from_secs(10)))
        .expect("a read timeout");
    // The server may close as soon as it has refused the head.
    let _ = stream.write_all(request);
    let mut answer = Vec::new();
    let _ = stream.read_to_end(&mut answer);
    let answer = String::from_utf8_lossy(&answer);
    answer.lines().next().unwrap_or("").to_string()
}

/// A GET of `path` naming the server `host`, as a browser sends it.
pub fn get(host: &str, path: &str) -> Vec<u8> {
    format!("GET {path} HTTP/1.1\r\nHost: {host}\r\nConnection: close\r\n\r\n").into_bytes()
}
