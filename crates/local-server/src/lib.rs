//! The HTTP/1.1 server of the pages the tracer serves to a browser on this
//! machine: `tracer watch --serve`'s live page and `cargo xtask web
//! --serve`'s playground. What both need of a server is here, once:
//!
//! - only `GET` and `HEAD`, without a body;
//! - only requests whose `Host` names the address listened on (`host.rs`):
//!   a page of another site cannot rebind its name to 127.0.0.1 and read
//!   what is served (DNS rebinding); 421 otherwise;
//! - a request's head bounded in size and in time: a client that sends an
//!   endless line, or a byte a second, is closed;
//! - connections bounded in number, each a task (not a thread): one more
//!   is closed as soon as it is accepted, and the accept loop never ends;
//! - a write that waits on a client that does not read fails after a
//!   timeout (`write_timeout.rs`), so the connection is dropped.
//!
//! What is served is the caller's: a handler from a request to its reply.
//! `test_client` is the raw client their tests share.

mod host;
pub mod test_client;
mod write_timeout;

use anyhow::{Context, Result};
use bytes::Bytes;
use http_body_util::{combinators::BoxBody, BodyExt, Full};
use hyper::body::{Body, Incoming};
use hyper::{Method, Request, Response, StatusCode};
use hyper_util::rt::{TokioIo, TokioTimer};
use std::convert::Infallible;
use std::future::Future;
use std::net::SocketAddr;
use std::sync::Arc;
use std::time::Duration;
use tokio::sync::Semaphore;
use write_timeout::WriteTimeout;

pub use host::host_allowed;

/// A reply of any body: bytes, or a stream (server-sent events).
pub type Reply = Response<BoxBody<Bytes, Infallible>>;

/// The server's bounds.
#[derive(Debug, Clone, Copy)]
pub struct Limits {
    /// Connections served at once; one more is closed as soon as it is
    /// accepted (rather than left waiting in the backlog, where a crowd of
    /// idle clients would keep a page waiting for ever).
    pub connections: usize,
    /// Bytes of a request's head (request line and headers); hyper's
    /// least is 8 KiB.
    pub head_bytes: usize,
    /// Time a client has to send its request's head, counted from when
    /// the connection waits for one: an idle or byte-a-second client is
    /// closed.
    pub head_time: Duration,
    /// Time a write may wait on a client that does not read before the
    /// connection is dropped.
    pub write_time: Duration,
}

impl Default for Limits {
    fn default() -> Limits {
        Limits {
            connections: 512,
            head_bytes: 8 * 1024,
            head_time: Duration::from_secs(3),
            write_time: Duration::from_secs(5),
        }
    }
}

/// Threads of the pool a handler's blocking work runs on
/// (`tokio::task::spawn_blocking`): more wait for one.
const BLOCKING_THREADS: usize = 4;
/// After a failed accept (too many open files), a pause before the next:
/// the loop goes on, without spinning.
const ACCEPT_PAUSE: Duration = Duration::from_millis(50);

/// A running server.
pub struct Server {
    /// The address bound (its port chosen when 0 was asked for).
    pub addr: SocketAddr,
    /// Its runtime, for the caller's own tasks (a keep-alive timer).
    pub runtime: tokio::runtime::Handle,
}

/// Binds `addr` and serves `handler`'s replies on a thread of its own,
/// within `limits`.
pub fn start<H, F>(addr: SocketAddr, limits: Limits, handler: H) -> Result<Server>
where
    H: Fn(Request<Incoming>) -> F + Send + Sync + 'static,
    F: Future<Output = Reply> + Send + 'static,
{
    let runtime = tokio::runtime::Builder::new_current_thread()
        .enable_all()
        .max_blocking_threads(BLOCKING_THREADS)
        .build()
        .context("cannot start the server")?;
    let listener = runtime
        .block_on(tokio::net::TcpListener::bind(addr))
        .with_context(|| format!("cannot serve on {addr}"))?;
    let addr = listener.local_addr()?;
    let handle = runtime.handle().clone();
    let handler = Arc::new(handler);
    std::thread::Builder::new()
        .name(format!("server on {addr}"))
        .spawn(move || runtime.block_on(serve(listener, addr, limits, handler)))
        .context("cannot start the server's thread")?;
    Ok(Server {
        addr,
        runtime: handle,
    })
}

async fn serve<H, F>(
    listener: tokio::net::TcpListener,
    addr: SocketAddr,
    limits: Limits,
    handler: Arc<H>,
) where
    H: Fn(Request<Incoming>) -> F + Send + Sync + 'static,
    F: Future<Output = Reply> + Send + 'static,
{
    let slots = Arc::new(Semaphore::new(limits.connections));
    loop {
        let stream = match listener.accept().await {
            Ok((stream, _)) => stream,
            Err(_) => {
                tokio::time::sleep(ACCEPT_PAUSE).await;
                continue;
            }
        };
        let Ok(slot) = slots.clone().try_acquire_owned() else {
            // Full: closed at once (dropped), the client told by the close.
            continue;
        };
        let handler = handler.clone();
        tokio::spawn(async move {
            let service = hyper::service::service_fn(move |request| {
                let handler = handler.clone();
                async move { Ok::<_, Infallible>(checked(request, addr, &*handler).await) }
            });
            let _ = hyper::server::conn::http1::Builder::new()
                .timer(TokioTimer::new())
                .header_read_timeout(limits.head_time)
                .max_buf_size(limits.head_bytes.max(8 * 1024))
                .serve_connection(
                    TokioIo::new(WriteTimeout::new(stream, limits.write_time)),
                    service,
                )
                .await;
            drop(slot);
        });
    }
}

/// The handler's reply to `request`, once it is one the server answers:
/// its Host the address listened on, GET or HEAD, no body.
async fn checked<H, F>(request: Request<Incoming>, addr: SocketAddr, handler: &H) -> Reply
where
    H: Fn(Request<Incoming>) -> F,
    F: Future<Output = Reply>,
{
    let host = request
        .headers()
        .get(hyper::header::HOST)
        .and_then(|h| h.to_str().ok());
    // An absolute target (`GET http://name/`) names the host too.
    let named = request.uri().authority().map(|a| a.as_str());
    let allowed = |h: Option<&str>| h.is_some_and(|h| host_allowed(h, addr));
    if !allowed(host) || named.is_some_and(|n| !allowed(Some(n))) {
        return plain(
            StatusCode::MISDIRECTED_REQUEST,
            "this server answers only requests to the address it listens on (localhost, or its IP address)",
        );
    }
    if request.method() != Method::GET && request.method() != Method::HEAD {
        return plain(StatusCode::METHOD_NOT_ALLOWED, "only GET");
    }
    if request.body().size_hint().lower() > 0 {
        return plain(StatusCode::PAYLOAD_TOO_LARGE, "no request body");
    }
    handler(request).await
}

/// A reply of `body`, of `content_type`, not to be cached.
pub fn bytes(content_type: &str, body: Bytes) -> Reply {
    Response::builder()
        .header("content-type", content_type)
        .header("cache-control", "no-store")
        .body(Full::new(body).boxed())
        .expect("a valid response")
}

/// A reply of `status` and a line of text.
pub fn plain(status: StatusCode, text: &'static str) -> Reply {
    let mut reply = bytes(
        "text/plain; charset=utf-8",
        Bytes::from_static(text.as_bytes()),
    );
    *reply.status_mut() = status;
    reply
}

#[cfg(test)]
mod tests;
