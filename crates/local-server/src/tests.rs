use super::test_client::status_of;
use super::*;
use std::io::Read;
use std::net::TcpStream;

/// A server of one page, "ok", within `limits`.
fn ok_server(limits: Limits) -> SocketAddr {
    let server = start("127.0.0.1:0".parse().unwrap(), limits, |_| async {
        bytes("text/plain", Bytes::from_static(b"ok"))
    })
    .unwrap();
    server.addr
}

/// A GET of the page naming the server `host`, its `{port}` the server's.
fn get(addr: SocketAddr, host: &str) -> Vec<u8> {
    test_client::get(&host.replace("{port}", &addr.port().to_string()), "/")
}

#[test]
fn a_host_other_than_the_address_listened_on_is_refused() {
    let addr = ok_server(Limits::default());
    for host in ["127.0.0.1:{port}", "localhost:{port}"] {
        assert_eq!(
            status_of(addr, &get(addr, host)),
            "HTTP/1.1 200 OK",
            "{host}"
        );
    }
    for host in ["attacker.example:{port}", "attacker.example", "localhost:1"] {
        assert_eq!(
            status_of(addr, &get(addr, host)),
            "HTTP/1.1 421 Misdirected Request",
            "{host}"
        );
    }
    let port = addr.port();
    let absolute =
        format!("GET http://attacker.example:{port}/ HTTP/1.1\r\nHost: 127.0.0.1:{port}\r\nConnection: close\r\n\r\n");
    assert_eq!(
        status_of(addr, absolute.as_bytes()),
        "HTTP/1.1 421 Misdirected Request"
    );
    let without = b"GET / HTTP/1.0\r\n\r\n";
    assert_eq!(status_of(addr, without), "HTTP/1.0 421 Misdirected Request");
}

#[test]
fn a_request_line_without_an_end_is_refused_and_the_server_serves_on() {
    let addr = ok_server(Limits::default());
    // A megabyte of request line and no line break: refused once past the
    // head's 8 KiB, not read into memory for ever.
    let endless = vec![b'A'; 1 << 20];
    let status = status_of(addr, &endless);
    assert_eq!(status, "HTTP/1.1 431 Request Header Fields Too Large");
    assert_eq!(
        status_of(addr, &get(addr, "127.0.0.1:{port}")),
        "HTTP/1.1 200 OK"
    );
}

#[test]
fn connections_past_the_limit_are_closed_and_the_page_served_once_they_go() {
    let limits = Limits {
        connections: 4,
        head_time: Duration::from_millis(300),
        ..Limits::default()
    };
    let addr = ok_server(limits);
    let idle: Vec<TcpStream> = (0..4).map(|_| TcpStream::connect(addr).unwrap()).collect();
    // Accepted and closed at once: the end of the stream, or a reset.
    let mut fifth = TcpStream::connect(addr).unwrap();
    fifth
        .set_read_timeout(Some(Duration::from_secs(2)))
        .unwrap();
    let mut byte = [0u8; 1];
    match fifth.read(&mut byte) {
        Ok(0) => {}
        Err(e) if e.kind() == std::io::ErrorKind::ConnectionReset => {}
        other => panic!("the connection past the limit was kept: {other:?}"),
    }
    // The idle ones are closed after the head's time; the page is served.
    std::thread::sleep(Duration::from_millis(800));
    assert_eq!(
        status_of(addr, &get(addr, "localhost:{port}")),
        "HTTP/1.1 200 OK"
    );
    drop(idle);
}
