//! Which `Host` a request may name: the address the server listens on, so
//! that a page of another site that rebinds its own name to this machine
//! (DNS rebinding) is not answered: its requests name that site.

use std::net::{IpAddr, SocketAddr};

/// Whether a request naming `host` (a Host header: `name`, `name:port`,
/// `[v6]:port`) is one to the server listening on `listening`: its port,
/// and `localhost` or an IP address of it. A server listening on a
/// loopback address answers `127.0.0.1`, `localhost` and `[::1]`; one on
/// an address of all interfaces (`0.0.0.0`, to be seen by other machines)
/// any IP address of the machine, which a browser names only when it
/// connected to it; no other name, whatever it resolves to.
pub fn host_allowed(host: &str, listening: SocketAddr) -> bool {
    let Some((name, port)) = split(host) else {
        return false;
    };
    if port != listening.port() {
        return false;
    }
    let ip = listening.ip();
    let local = ip.is_loopback() || ip.is_unspecified();
    if name.eq_ignore_ascii_case("localhost") {
        return local;
    }
    match name.parse::<IpAddr>() {
        Ok(named) => named == ip || named.is_loopback() && local || ip.is_unspecified(),
        Err(_) => false,
    }
}

/// The name and port of a Host header (port 80 when it has none); None
/// when it cannot be one.
fn split(host: &str) -> Option<(&str, u16)> {
    let (name, port) = match host.strip_prefix('[') {
        // [v6] or [v6]:port
        Some(rest) => {
            let (name, after) = rest.split_once(']')?;
            let port = match after {
                "" => None,
                _ => Some(after.strip_prefix(':')?),
            };
            (name, port)
        }
        None => match host.split_once(':') {
            Some((name, port)) => (name, Some(port)),
            None => (host, None),
        },
    };
    let port = match port {
        Some(p) => p.parse().ok()?,
        None => 80,
    };
    Some((name, port))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_the_names_of_the_address_listened_on_are_answered() {
        let loopback: SocketAddr = "127.0.0.1:7878".parse().unwrap();
        for host in [
            "127.0.0.1:7878",
            "localhost:7878",
            "LOCALHOST:7878",
            "[::1]:7878",
        ] {
            assert!(host_allowed(host, loopback), "{host}");
        }
        for host in [
            "attacker.example:7878",
            "attacker.example",
            "127.0.0.1:7879",
            "127.0.0.1",
            "localhost",
            "localhost.attacker.example:7878",
            "192.168.1.5:7878",
            "[::1]",
            "[::1:7878",
            "127.0.0.1:7878:1",
            "",
        ] {
            assert!(!host_allowed(host, loopback), "{host}");
        }
        // Port 80 may go unnamed.
        let eighty: SocketAddr = "127.0.0.1:80".parse().unwrap();
        assert!(host_allowed("localhost", eighty));
        // Seen by other machines: by the machine's IP address, not a name.
        let all: SocketAddr = "0.0.0.0:8000".parse().unwrap();
        for host in ["192.168.1.5:8000", "localhost:8000", "[fe80::1]:8000"] {
            assert!(host_allowed(host, all), "{host}");
        }
        assert!(!host_allowed("attacker.example:8000", all));
        let one: SocketAddr = "192.168.1.5:8000".parse().unwrap();
        assert!(host_allowed("192.168.1.5:8000", one));
        assert!(!host_allowed("localhost:8000", one));
    }
}
