//! The live page of `tracer watch --serve`: the page, the latest image and
//! a stream of events (server-sent events), nothing else. No path reaches
//! the file system; a request's head is bounded in size and time, the
//! connections in number; a slow or vanished client is dropped rather than
//! waited for, so rendering never stalls on it.

use crate::console::note;
use anyhow::{Context, Result};
use bytes::Bytes;
use http_body_util::{combinators::BoxBody, BodyExt, Full};
use hyper::body::{Body, Frame, Incoming};
use hyper::{Method, Request, Response, StatusCode};
use hyper_util::rt::{TokioIo, TokioTimer};
use std::convert::Infallible;
use std::future::Future;
use std::net::SocketAddr;
use std::pin::Pin;
use std::sync::{Arc, Mutex};
use std::task::{Context as TaskContext, Poll};
use std::time::Duration;
use tokio::sync::{mpsc, Semaphore};

/// The page: one file, no external resources.
const PAGE: &str = include_str!("page.html");
/// Connections served at once; one more is closed as soon as it is
/// accepted (rather than left waiting in the backlog, where a crowd of
/// idle clients would keep a page waiting for ever).
const MAX_CONNECTIONS: usize = 512;
/// Event streams open at once (a page holds one): more are answered 503,
/// so never-reading streams cannot take every connection.
const MAX_EVENT_STREAMS: usize = 64;
/// Bytes of a request's head (request line and headers).
const MAX_HEAD_BYTES: usize = 8 * 1024;
/// Time a client has to send its request's head, counted from when the
/// connection waits for one: an idle or byte-a-second client is closed.
const HEAD_TIMEOUT: Duration = Duration::from_secs(3);
/// Time a write may wait on a client that does not read before the
/// connection is dropped.
const WRITE_TIMEOUT: Duration = Duration::from_secs(5);
/// Events queued for one client before it counts as too slow and is dropped.
const CLIENT_QUEUE: usize = 16;
/// How often an idle event stream gets a comment, which finds vanished clients.
const KEEP_ALIVE: Duration = Duration::from_secs(15);

/// What the live page asks of a clicked pixel: its tree as text, or why
/// not (shown as it is).
pub type Explainer = Arc<dyn Fn(u32, u32) -> Result<String, String> + Send + Sync>;

/// What the page shows: the latest image and the events that describe it.
#[derive(Default)]
struct State {
    /// The current scene's explainer (none until a scene has loaded).
    explain: Option<Explainer>,
    png: Option<Bytes>,
    /// The last render's event and the last error's (None once fixed):
    /// sent to a page as soon as it connects.
    render_event: Option<Bytes>,
    error_event: Option<Bytes>,
    clients: Vec<mpsc::Sender<Bytes>>,
}

impl State {
    /// Queues `event` for every client; a full queue (a slow client) or a
    /// closed one (a vanished client) drops that client.
    fn broadcast(&mut self, event: &Bytes) {
        self.clients.retain(|c| c.try_send(event.clone()).is_ok());
    }
}

/// A running server; the watch loop publishes to it.
pub struct Server {
    state: Arc<Mutex<State>>,
    pub addr: SocketAddr,
}

impl Server {
    /// Binds `addr` and serves on a thread of its own.
    pub fn start(addr: SocketAddr) -> Result<Server> {
        let runtime = tokio::runtime::Builder::new_current_thread()
            .enable_all()
            .build()
            .context("cannot start the page's server")?;
        let listener = runtime
            .block_on(tokio::net::TcpListener::bind(addr))
            .with_context(|| format!("cannot serve the page on {addr}"))?;
        let addr = listener.local_addr()?;
        let state = Arc::new(Mutex::new(State::default()));
        let served = state.clone();
        std::thread::spawn(move || runtime.block_on(serve(listener, served)));
        Ok(Server { state, addr })
    }

    /// A new image (PNG bytes) and its numbers, for the page.
    pub fn image(&self, png: Vec<u8>, info: serde_json::Value) {
        let mut state = self.state.lock().expect("the page's state");
        state.png = Some(Bytes::from(png));
        let render = event("render", &info);
        state.broadcast(&render);
        state.render_event = Some(render);
        if state.error_event.take().is_some() {
            state.broadcast(&event("fixed", &serde_json::json!({})));
        }
    }

    /// What a click on the image explains: the scene now shown.
    pub fn explain_with(&self, explainer: Explainer) {
        self.state.lock().expect("the page's state").explain = Some(explainer);
    }

    /// A scene error, as `tracer check` prints it (without colours).
    pub fn error(&self, text: &str) {
        let mut state = self.state.lock().expect("the page's state");
        let error = event("error", &serde_json::json!({ "text": text }));
        state.broadcast(&error);
        state.error_event = Some(error);
    }
}

/// A server-sent event: its name and one line of JSON.
fn event(name: &str, data: &serde_json::Value) -> Bytes {
    Bytes::from(format!("event: {name}\ndata: {data}\n\n"))
}

async fn serve(listener: tokio::net::TcpListener, state: Arc<Mutex<State>>) {
    let slots = Arc::new(Semaphore::new(MAX_CONNECTIONS));
    tokio::spawn(keep_alive(state.clone()));
    loop {
        let Ok((stream, _)) = listener.accept().await else {
            continue;
        };
        let Ok(slot) = slots.clone().try_acquire_owned() else {
            // Full: closed at once (dropped), the client told by the close.
            continue;
        };
        let state = state.clone();
        tokio::spawn(async move {
            let service = hyper::service::service_fn(move |r| respond(r, state.clone()));
            let _ = hyper::server::conn::http1::Builder::new()
                .timer(TokioTimer::new())
                .header_read_timeout(HEAD_TIMEOUT)
                .max_buf_size(MAX_HEAD_BYTES)
                .serve_connection(TokioIo::new(WriteTimeout::new(stream)), service)
                .await;
            drop(slot);
        });
    }
}

async fn keep_alive(state: Arc<Mutex<State>>) {
    let mut ticks = tokio::time::interval(KEEP_ALIVE);
    loop {
        ticks.tick().await;
        let ping = Bytes::from_static(b": keep-alive\n\n");
        state.lock().expect("the page's state").broadcast(&ping);
    }
}

type Reply = Response<BoxBody<Bytes, Infallible>>;

async fn respond(
    request: Request<Incoming>,
    state: Arc<Mutex<State>>,
) -> Result<Reply, Infallible> {
    if request.method() != Method::GET && request.method() != Method::HEAD {
        return Ok(plain(StatusCode::METHOD_NOT_ALLOWED, "only GET"));
    }
    if request.body().size_hint().lower() > 0 {
        return Ok(plain(StatusCode::PAYLOAD_TOO_LARGE, "no request body"));
    }
    Ok(match request.uri().path() {
        "/" => bytes(
            "text/html; charset=utf-8",
            Bytes::from_static(PAGE.as_bytes()),
        ),
        "/image.png" => match state.lock().expect("the page's state").png.clone() {
            Some(png) => bytes("image/png", png),
            None => plain(StatusCode::NOT_FOUND, "no image yet"),
        },
        "/events" => events(&state),
        "/explain" => explain(request.uri().query(), &state).await,
        _ => plain(StatusCode::NOT_FOUND, "not found"),
    })
}

/// `/explain?x=X&y=Y`: the tree of pixel (X, Y) of the scene shown, worked
/// out on a thread of the blocking pool (a large scene takes a moment to
/// prepare), as text.
async fn explain(query: Option<&str>, state: &Mutex<State>) -> Reply {
    let Some((x, y)) = query.and_then(pixel_of) else {
        return plain(
            StatusCode::BAD_REQUEST,
            "expected /explain?x=X&y=Y, whole numbers",
        );
    };
    let Some(explainer) = state.lock().expect("the page's state").explain.clone() else {
        return plain(StatusCode::NOT_FOUND, "no scene yet");
    };
    match tokio::task::spawn_blocking(move || explainer(x, y)).await {
        Ok(Ok(text)) => bytes("text/plain; charset=utf-8", Bytes::from(text)),
        Ok(Err(why)) => {
            let mut reply = bytes("text/plain; charset=utf-8", Bytes::from(why));
            *reply.status_mut() = StatusCode::UNPROCESSABLE_ENTITY;
            reply
        }
        Err(_) => plain(StatusCode::INTERNAL_SERVER_ERROR, "the explanation failed"),
    }
}

/// X and Y of a query `x=X&y=Y` (in either order).
fn pixel_of(query: &str) -> Option<(u32, u32)> {
    let (mut x, mut y) = (None, None);
    for pair in query.split('&') {
        match pair.split_once('=')? {
            ("x", value) => x = Some(value.parse().ok()?),
            ("y", value) => y = Some(value.parse().ok()?),
            _ => return None,
        }
    }
    Some((x?, y?))
}

fn bytes(content_type: &str, body: Bytes) -> Reply {
    Response::builder()
        .header("content-type", content_type)
        .header("cache-control", "no-store")
        .body(Full::new(body).boxed())
        .expect("a valid response")
}

fn plain(status: StatusCode, text: &'static str) -> Reply {
    let mut reply = bytes(
        "text/plain; charset=utf-8",
        Bytes::from_static(text.as_bytes()),
    );
    *reply.status_mut() = status;
    reply
}

/// A new event stream: what the page shows now, then every change.
fn events(state: &Mutex<State>) -> Reply {
    let (send, receive) = mpsc::channel(CLIENT_QUEUE);
    let mut state = state.lock().expect("the page's state");
    state.clients.retain(|c| !c.is_closed());
    if state.clients.len() >= MAX_EVENT_STREAMS {
        return plain(StatusCode::SERVICE_UNAVAILABLE, "too many live pages open");
    }
    for current in [&state.render_event, &state.error_event]
        .into_iter()
        .flatten()
    {
        let _ = send.try_send(current.clone());
    }
    state.clients.push(send);
    note!("a live page connected ({} open)", state.clients.len());
    Response::builder()
        .header("content-type", "text/event-stream")
        .header("cache-control", "no-store")
        .body(EventStream(receive).boxed())
        .expect("a valid response")
}

/// The body of an event stream: the events queued for this client.
struct EventStream(mpsc::Receiver<Bytes>);

impl Body for EventStream {
    type Data = Bytes;
    type Error = Infallible;

    fn poll_frame(
        mut self: Pin<&mut Self>,
        cx: &mut TaskContext<'_>,
    ) -> Poll<Option<Result<Frame<Bytes>, Infallible>>> {
        self.0.poll_recv(cx).map(|e| e.map(|b| Ok(Frame::data(b))))
    }
}

/// A connection whose writes fail after waiting `WRITE_TIMEOUT` on a
/// client that does not read: its task ends and its slot is freed.
struct WriteTimeout<S = tokio::net::TcpStream> {
    stream: S,
    limit: Duration,
    /// Set when a write first waits; cleared when one goes through.
    deadline: Option<Pin<Box<tokio::time::Sleep>>>,
}

impl<S> WriteTimeout<S> {
    fn new(stream: S) -> WriteTimeout<S> {
        WriteTimeout::with_limit(stream, WRITE_TIMEOUT)
    }

    fn with_limit(stream: S, limit: Duration) -> WriteTimeout<S> {
        WriteTimeout {
            stream,
            limit,
            deadline: None,
        }
    }

    /// `result` of a write, or an error once the writes waited too long.
    fn timed<T>(
        &mut self,
        cx: &mut TaskContext<'_>,
        result: Poll<std::io::Result<T>>,
    ) -> Poll<std::io::Result<T>> {
        if result.is_ready() {
            self.deadline = None;
            return result;
        }
        let limit = self.limit;
        let deadline = self
            .deadline
            .get_or_insert_with(|| Box::pin(tokio::time::sleep(limit)));
        match deadline.as_mut().poll(cx) {
            Poll::Ready(()) => Poll::Ready(Err(std::io::ErrorKind::TimedOut.into())),
            Poll::Pending => Poll::Pending,
        }
    }
}

impl<S: tokio::io::AsyncRead + Unpin> tokio::io::AsyncRead for WriteTimeout<S> {
    fn poll_read(
        mut self: Pin<&mut Self>,
        cx: &mut TaskContext<'_>,
        buf: &mut tokio::io::ReadBuf<'_>,
    ) -> Poll<std::io::Result<()>> {
        Pin::new(&mut self.stream).poll_read(cx, buf)
    }
}

impl<S: tokio::io::AsyncWrite + Unpin> tokio::io::AsyncWrite for WriteTimeout<S> {
    fn poll_write(
        mut self: Pin<&mut Self>,
        cx: &mut TaskContext<'_>,
        buf: &[u8],
    ) -> Poll<std::io::Result<usize>> {
        let result = Pin::new(&mut self.stream).poll_write(cx, buf);
        self.timed(cx, result)
    }

    fn poll_flush(mut self: Pin<&mut Self>, cx: &mut TaskContext<'_>) -> Poll<std::io::Result<()>> {
        let result = Pin::new(&mut self.stream).poll_flush(cx);
        self.timed(cx, result)
    }

    fn poll_shutdown(
        mut self: Pin<&mut Self>,
        cx: &mut TaskContext<'_>,
    ) -> Poll<std::io::Result<()>> {
        let result = Pin::new(&mut self.stream).poll_shutdown(cx);
        self.timed(cx, result)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::io::{Read, Write};
    use tokio::io::AsyncWriteExt;

    /// The status line of the answer to GET `path`, and the stream, left
    /// open (an event stream's answer never ends).
    fn get(addr: SocketAddr, path: &str) -> (String, std::net::TcpStream) {
        let mut stream = std::net::TcpStream::connect(addr).expect("connect");
        stream
            .set_read_timeout(Some(Duration::from_secs(10)))
            .unwrap();
        let request = format!("GET {path} HTTP/1.1\r\nHost: localhost\r\n\r\n");
        stream.write_all(request.as_bytes()).unwrap();
        let mut line = Vec::new();
        let mut byte = [0u8; 1];
        while !line.ends_with(b"\r\n") && stream.read(&mut byte).unwrap_or(0) == 1 {
            line.push(byte[0]);
        }
        (
            String::from_utf8_lossy(&line).trim_end().to_string(),
            stream,
        )
    }

    #[test]
    fn event_streams_past_the_limit_are_refused_and_the_page_still_served() {
        let server = Server::start("127.0.0.1:0".parse().unwrap()).unwrap();
        let streams: Vec<_> = (0..MAX_EVENT_STREAMS)
            .map(|_| {
                let (status, stream) = get(server.addr, "/events");
                assert_eq!(status, "HTTP/1.1 200 OK");
                stream
            })
            .collect();
        let (status, _) = get(server.addr, "/events");
        assert_eq!(status, "HTTP/1.1 503 Service Unavailable");
        assert_eq!(get(server.addr, "/").0, "HTTP/1.1 200 OK");
        drop(streams);
    }

    /// Writes of 64 bytes for `for_time` through a `WriteTimeout` of
    /// 200 ms to a peer of a 64-byte buffer that reads every `read_every`
    /// (never, if None): the first error, or Ok (an error of kind Other if
    /// a write never ended).
    fn write_to_a_peer(read_every: Option<Duration>, for_time: Duration) -> std::io::Result<()> {
        let runtime = tokio::runtime::Builder::new_current_thread()
            .enable_time()
            .build()
            .unwrap();
        runtime.block_on(async {
            let (near, mut far) = tokio::io::duplex(64);
            let mut conn = WriteTimeout::with_limit(near, Duration::from_millis(200));
            // Held open and never read, or read by a task of its own.
            let _unread = match read_every {
                None => Some(far),
                Some(every) => {
                    tokio::spawn(async move {
                        use tokio::io::AsyncReadExt;
                        let mut buf = [0u8; 64];
                        while far.read(&mut buf).await.unwrap_or(0) > 0 {
                            tokio::time::sleep(every).await;
                        }
                    });
                    None
                }
            };
            let writes = async {
                let start = tokio::time::Instant::now();
                while start.elapsed() < for_time {
                    conn.write_all(&[7u8; 64]).await?;
                }
                Ok(())
            };
            // A write that waits for ever fails the test rather than hangs it.
            let hung = std::io::Error::other("a write waited for ever");
            let bound = for_time + Duration::from_secs(2);
            tokio::time::timeout(bound, writes)
                .await
                .unwrap_or(Err(hung))
        })
    }

    #[test]
    fn a_client_that_does_not_read_is_dropped_after_the_write_timeout() {
        let start = std::time::Instant::now();
        let result = write_to_a_peer(None, Duration::from_secs(5));
        let err = result.expect_err("writes to a peer that never reads went on");
        assert_eq!(err.kind(), std::io::ErrorKind::TimedOut);
        let waited = start.elapsed();
        assert!(
            waited >= Duration::from_millis(200) && waited < Duration::from_secs(3),
            "{waited:?}"
        );
    }

    #[test]
    fn a_slow_reader_is_kept_while_each_write_goes_through_in_time() {
        // A read every 50 ms, each write waiting less than the 200 ms limit.
        let result = write_to_a_peer(Some(Duration::from_millis(50)), Duration::from_secs(1));
        assert!(result.is_ok(), "{result:?}");
    }
}
