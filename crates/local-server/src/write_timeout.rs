//! A connection whose writes fail after waiting too long on a client that
//! does not read, so that a vanished client's connection ends.

use std::future::Future;
use std::pin::Pin;
use std::task::{Context as TaskContext, Poll};
use std::time::Duration;

/// A connection whose writes fail after waiting its limit on a client
/// that does not read: its task ends and its slot is freed.
pub struct WriteTimeout<S> {
    stream: S,
    limit: Duration,
    /// Set when a write first waits; cleared when one goes through.
    deadline: Option<Pin<Box<tokio::time::Sleep>>>,
}

impl<S> WriteTimeout<S> {
    pub fn new(stream: S, limit: Duration) -> WriteTimeout<S> {
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
    use tokio::io::AsyncWriteExt;

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
            let mut conn = WriteTimeout::new(near, Duration::from_millis(200));
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
