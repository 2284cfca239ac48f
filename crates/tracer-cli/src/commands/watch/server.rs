//! The live page of `tracer watch --serve`: the page, the latest image and
//! a stream of events (server-sent events), nothing else. No path reaches
//! the file system; the server (`local_server`) answers only requests to
//! its own address, bounds a request's head in size and time and the
//! connections in number, and drops a slow or vanished client rather than
//! waiting for it, so rendering never stalls on it. A clicked pixel's
//! tree is worked out for a few requests at a time, each tree bounded.

use crate::console::note;
use anyhow::Result;
use bytes::Bytes;
use http_body_util::BodyExt;
use hyper::body::{Body, Frame, Incoming};
use hyper::{Request, Response, StatusCode};
use local_server::{bytes, plain, Limits, Reply};
use std::convert::Infallible;
use std::net::SocketAddr;
use std::pin::Pin;
use std::sync::{Arc, Mutex};
use std::task::{Context as TaskContext, Poll};
use std::time::Duration;
use tokio::sync::{mpsc, Semaphore};

/// The page: one file, no external resources.
const PAGE: &str = include_str!("page.html");
/// Event streams open at once (a page holds one): more are answered 503,
/// so never-reading streams cannot take every connection.
const MAX_EVENT_STREAMS: usize = 64;
/// Pixels explained at once: more are answered 503 (busy). Each tree is
/// bounded (`tracer_core::explain::Limits`), so their memory is too.
const MAX_EXPLAINS: usize = 2;
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
        let state = Arc::new(Mutex::new(State::default()));
        let explains = Arc::new(Semaphore::new(MAX_EXPLAINS));
        let served = state.clone();
        let server = local_server::start(addr, Limits::default(), move |request| {
            respond(request, served.clone(), explains.clone())
        })?;
        server.runtime.spawn(keep_alive(state.clone()));
        Ok(Server {
            state,
            addr: server.addr,
        })
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

async fn keep_alive(state: Arc<Mutex<State>>) {
    let mut ticks = tokio::time::interval(KEEP_ALIVE);
    loop {
        ticks.tick().await;
        let ping = Bytes::from_static(b": keep-alive\n\n");
        state.lock().expect("the page's state").broadcast(&ping);
    }
}

/// The reply to a request the server let through (GET or HEAD, to its
/// own address).
async fn respond(
    request: Request<Incoming>,
    state: Arc<Mutex<State>>,
    explains: Arc<Semaphore>,
) -> Reply {
    match request.uri().path() {
        "/" => bytes(
            "text/html; charset=utf-8",
            Bytes::from_static(PAGE.as_bytes()),
        ),
        "/image.png" => match state.lock().expect("the page's state").png.clone() {
            Some(png) => bytes("image/png", png),
            None => plain(StatusCode::NOT_FOUND, "no image yet"),
        },
        "/events" => events(&state),
        "/explain" => explain(request.uri().query(), &state, &explains).await,
        _ => plain(StatusCode::NOT_FOUND, "not found"),
    }
}

/// `/explain?x=X&y=Y`: the tree of pixel (X, Y) of the scene shown, worked
/// out on a thread of the blocking pool (a large scene takes a moment to
/// prepare), as text; at most `MAX_EXPLAINS` at once, more answered 503.
async fn explain(query: Option<&str>, state: &Mutex<State>, explains: &Arc<Semaphore>) -> Reply {
    let Some((x, y)) = query.and_then(pixel_of) else {
        return plain(
            StatusCode::BAD_REQUEST,
            "expected /explain?x=X&y=Y, whole numbers",
        );
    };
    let Some(explainer) = state.lock().expect("the page's state").explain.clone() else {
        return plain(StatusCode::NOT_FOUND, "no scene yet");
    };
    let Ok(slot) = explains.clone().try_acquire_owned() else {
        return plain(
            StatusCode::SERVICE_UNAVAILABLE,
            "busy explaining other pixels; click again in a moment",
        );
    };
    let work = move || {
        let text = explainer(x, y);
        drop(slot);
        text
    };
    match tokio::task::spawn_blocking(work).await {
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

#[cfg(test)]
mod tests {
    use super::*;
    use std::io::{Read, Write};

    /// The status line of the answer to GET `path`, and the stream, left
    /// open (an event stream's answer never ends).
    fn get(addr: SocketAddr, path: &str) -> (String, std::net::TcpStream) {
        let mut stream = std::net::TcpStream::connect(addr).expect("connect");
        stream
            .set_read_timeout(Some(Duration::from_secs(10)))
            .unwrap();
        let port = addr.port();
        let request = format!("GET {path} HTTP/1.1\r\nHost: localhost:{port}\r\n\r\n");
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

    #[test]
    fn pixels_are_explained_a_few_at_a_time_and_more_told_busy() {
        use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
        let server = Server::start("127.0.0.1:0".parse().unwrap()).unwrap();
        // An explainer that holds its thread until released.
        let started = Arc::new(AtomicUsize::new(0));
        let released = Arc::new(AtomicBool::new(false));
        let (s, r) = (started.clone(), released.clone());
        server.explain_with(Arc::new(move |_, _| {
            s.fetch_add(1, Ordering::SeqCst);
            while !r.load(Ordering::SeqCst) {
                std::thread::sleep(Duration::from_millis(5));
            }
            Ok("the tree".to_string())
        }));
        let addr = server.addr;
        let held: Vec<_> = (0..MAX_EXPLAINS)
            .map(|k| std::thread::spawn(move || get(addr, &format!("/explain?x={k}&y=0")).0))
            .collect();
        let waited = std::time::Instant::now();
        while started.load(Ordering::SeqCst) < MAX_EXPLAINS {
            assert!(waited.elapsed() < Duration::from_secs(10), "never started");
            std::thread::sleep(Duration::from_millis(5));
        }
        let (busy, _) = get(addr, "/explain?x=9&y=9");
        assert_eq!(busy, "HTTP/1.1 503 Service Unavailable");
        released.store(true, Ordering::SeqCst);
        for answer in held {
            assert_eq!(answer.join().unwrap(), "HTTP/1.1 200 OK");
        }
        assert_eq!(started.load(Ordering::SeqCst), MAX_EXPLAINS);
        // Free again.
        assert_eq!(get(addr, "/explain?x=9&y=9").0, "HTTP/1.1 200 OK");
    }
}
