//! The little HTTP/1.1 the design page needs, on `std::net` alone: one
//! request per connection, every read bounded in bytes and in time, and
//! every request checked for where it comes from before it reaches the
//! session.
//!
//! Why not a general HTTP library: the page needs `GET` and small JSON
//! `POST`s from one browser on this machine, and what must hold is what a
//! general server leaves to its user: no allocation or read driven by what a
//! header claims (a `Content-Length` past the limit is refused before any
//! byte of the body is read), a deadline on every connection, a bounded
//! number of connections that cannot starve each other, and a stop that is
//! honoured within a fraction of a second. The request head is parsed by
//! [`parse_head`], a pure function the property tests feed arbitrary bytes.
//!
//! What a request must show to be answered ([`check_origin`]):
//! - a `Host` that names this server: `localhost` or an IP literal the
//!   server listens on, with its port if a port is given (a page that
//!   rebinds its own domain name to 127.0.0.1 sends its own name, and is
//!   refused);
//! - for anything but `GET` and `HEAD`: an `Origin` equal to the page's own
//!   (`http://` and the `Host`; browsers send it with every cross-origin and
//!   same-origin `POST`, other programs add it themselves) and the content
//!   type `application/json`, which no cross-site form or `no-cors` fetch
//!   can send.

use std::io::{Read, Write};
use std::net::{IpAddr, SocketAddr, TcpListener, TcpStream};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::time::{Duration, Instant};

use super::server::Reply;

/// Largest request head (request line and headers), in bytes.
pub const MAX_HEAD: usize = 16 << 10;
/// Largest request body, in bytes.
pub const MAX_BODY: usize = 1 << 20;
/// Most headers in one request.
const MAX_HEADERS: usize = 64;
/// Time a client has to send its whole request, and to take the answer.
pub const REQUEST_DEADLINE: Duration = Duration::from_secs(10);
/// Connections served at once; one more is answered 503 at once.
pub const MAX_CONNECTIONS: usize = 32;
/// How often a waiting read or accept looks at the stop flag.
const POLL: Duration = Duration::from_millis(100);

/// A request head as sent: method, target, version and headers.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Head {
    /// `GET`, `POST`, …
    pub method: String,
    /// The request target (`/api/state?sort=score`).
    pub target: String,
    /// Header names in lower case, values trimmed, in order.
    pub headers: Vec<(String, String)>,
}

impl Head {
    /// The first value of header `name` (lower case), if present
    /// ([`parse_head`] refuses repeats of the headers the checks read).
    #[must_use]
    pub fn header(&self, name: &str) -> Option<&str> {
        self.headers
            .iter()
            .find(|(n, _)| n == name)
            .map(|(_, v)| v.as_str())
    }

    /// The body's length: 0 without `Content-Length`.
    fn content_length(&self) -> Result<usize, Refusal> {
        match self.header("content-length") {
            None => Ok(0),
            Some(v) => {
                let n: u64 = v.parse().map_err(|_| {
                    Refusal::new(400, format!("Content-Length `{v}` is not a number"))
                })?;
                if n > MAX_BODY as u64 {
                    return Err(Refusal::new(
                        413,
                        format!("a request body may hold {MAX_BODY} bytes, this one declares {n}"),
                    ));
                }
                Ok(n as usize)
            }
        }
    }
}

/// A request refused before it reaches the session: status and reason.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Refusal {
    /// HTTP status.
    pub status: u16,
    /// Why, for the client.
    pub reason: String,
}

impl Refusal {
    fn new(status: u16, reason: impl Into<String>) -> Self {
        Self {
            status,
            reason: reason.into(),
        }
    }
}

/// Parses a request head (everything before the blank line, without it).
/// Refuses what this server does not take: another version than HTTP/1.x,
/// folded or malformed header lines, repeated `Host` or `Content-Length`,
/// any `Transfer-Encoding` (a body must state its length), a head with too
/// many headers.
pub fn parse_head(bytes: &[u8]) -> Result<Head, Refusal> {
    let bad = |why: &str| Refusal::new(400, format!("malformed request: {why}"));
    let text = std::str::from_utf8(bytes).map_err(|_| bad("the head is not UTF-8"))?;
    let mut lines = text.split("\r\n");
    let request_line = lines.next().unwrap_or_default();
    let mut parts = request_line.split(' ');
    let (Some(method), Some(target), Some(version), None) =
        (parts.next(), parts.next(), parts.next(), parts.next())
    else {
        return Err(bad("the request line is not `METHOD TARGET HTTP/1.1`"));
    };
    if method.is_empty() || !method.bytes().all(|b| b.is_ascii_uppercase()) {
        return Err(bad("the method is not a word in capitals"));
    }
    if !target.starts_with('/') || target.bytes().any(|b| b.is_ascii_control()) {
        return Err(bad("the target is not a path"));
    }
    if version != "HTTP/1.1" && version != "HTTP/1.0" {
        return Err(Refusal::new(505, format!("{version} is not HTTP/1.1")));
    }
    let mut headers = Vec::new();
    for line in lines {
        if headers.len() == MAX_HEADERS {
            return Err(Refusal::new(
                431,
                format!("more than {MAX_HEADERS} headers"),
            ));
        }
        if line.starts_with([' ', '\t']) {
            return Err(bad("folded header lines are not accepted"));
        }
        let (name, value) = line
            .split_once(':')
            .ok_or_else(|| bad("a header line without `:`"))?;
        if name.is_empty()
            || !name
                .bytes()
                .all(|b| b.is_ascii_alphanumeric() || b"!#$%&'*+-.^_`|~".contains(&b))
        {
            return Err(bad("a header's name is not a token"));
        }
        let value = value.trim_matches([' ', '\t']);
        if value.bytes().any(|b| b.is_ascii_control() && b != b'\t') {
            return Err(bad("a header's value holds a control character"));
        }
        headers.push((name.to_ascii_lowercase(), value.to_string()));
    }
    for once in ["host", "content-length", "origin", "content-type"] {
        if headers.iter().filter(|(n, _)| n == once).count() > 1 {
            return Err(bad(&format!("`{once}` given more than once")));
        }
    }
    if headers.iter().any(|(n, _)| n == "transfer-encoding") {
        return Err(Refusal::new(
            411,
            "Transfer-Encoding is not accepted: send the body with a Content-Length",
        ));
    }
    Ok(Head {
        method: method.to_string(),
        target: target.to_string(),
        headers,
    })
}

/// Whether `host` (a `Host` header's value) names a server bound to `bound`:
/// `localhost` (when bound to a loopback or every address) or an IP literal
/// the server listens on, and `bound`'s port if a port is given.
fn names_this_server(host: &str, bound: SocketAddr) -> bool {
    let (name, port) = match host.rsplit_once(':') {
        // An IPv6 literal's colons are inside brackets.
        Some((name, port)) if !port.contains(']') => (name, Some(port)),
        _ => (host, None),
    };
    if port.is_some_and(|p| p.parse::<u16>() != Ok(bound.port())) {
        return false;
    }
    let ip = bound.ip();
    if name.eq_ignore_ascii_case("localhost") {
        return ip.is_loopback() || ip.is_unspecified();
    }
    let literal = name
        .strip_prefix('[')
        .and_then(|n| n.strip_suffix(']'))
        .unwrap_or(name);
    match literal.parse::<IpAddr>() {
        Ok(named) => named == ip || ip.is_unspecified(),
        Err(_) => false,
    }
}

/// Refuses a request that does not come from this server's own page (see
/// the module's documentation): 403 with the reason, or 415 for a `POST`
/// that is not JSON.
pub fn check_origin(head: &Head, bound: SocketAddr) -> Result<(), Refusal> {
    let host = head
        .header("host")
        .ok_or_else(|| Refusal::new(400, "a request needs a Host header"))?;
    if !names_this_server(host, bound) {
        return Err(Refusal::new(
            403,
            format!(
                "Host `{host}` is not this server's address ({bound}, or localhost): open the page at http://{bound}/"
            ),
        ));
    }
    if matches!(head.method.as_str(), "GET" | "HEAD") {
        return Ok(());
    }
    let own = format!("http://{host}");
    match head.header("origin") {
        Some(origin) if origin.eq_ignore_ascii_case(&own) => {}
        Some(origin) => {
            return Err(Refusal::new(
                403,
                format!(
                    "a page from `{origin}` may not change this session: only the page at {own}/ may"
                ),
            ));
        }
        None => {
            return Err(Refusal::new(
                403,
                format!(
                    "a {} needs the header `Origin: {own}` (browsers send it; other programs must add it)",
                    head.method
                ),
            ));
        }
    }
    let json = head.header("content-type").is_some_and(|t| {
        t.split(';')
            .next()
            .is_some_and(|m| m.trim().eq_ignore_ascii_case("application/json"))
    });
    if !json {
        return Err(Refusal::new(
            415,
            format!("a {} needs the content type application/json", head.method),
        ));
    }
    Ok(())
}

/// What answers a request that passed the checks: its method (`HEAD` is
/// asked as `GET`), target and body.
pub type Handler<'a> = dyn Fn(&str, &str, &[u8]) -> Reply + Sync + 'a;

fn reason_phrase(status: u16) -> &'static str {
    match status {
        100 => "Continue",
        200 => "OK",
        400 => "Bad Request",
        403 => "Forbidden",
        404 => "Not Found",
        405 => "Method Not Allowed",
        408 => "Request Timeout",
        409 => "Conflict",
        411 => "Length Required",
        413 => "Content Too Large",
        415 => "Unsupported Media Type",
        422 => "Unprocessable Content",
        431 => "Request Header Fields Too Large",
        500 => "Internal Server Error",
        503 => "Service Unavailable",
        505 => "HTTP Version Not Supported",
        _ => "",
    }
}

/// Writes `answer` with the headers every answer carries: no caching, no
/// sniffing, no framing or embedding by other sites, and the connection
/// closed after it.
fn write_answer(stream: &mut TcpStream, answer: &Reply, head_only: bool) -> std::io::Result<()> {
    let head = format!(
        "HTTP/1.1 {} {}\r\nContent-Type: {}\r\nContent-Length: {}\r\nCache-Control: no-store\r\nX-Content-Type-Options: nosniff\r\nX-Frame-Options: DENY\r\nCross-Origin-Resource-Policy: same-origin\r\nConnection: close\r\n\r\n",
        answer.status,
        reason_phrase(answer.status),
        answer.content_type,
        answer.body.len()
    );
    stream.write_all(head.as_bytes())?;
    if !head_only {
        stream.write_all(&answer.body)?;
    }
    stream.flush()
}

/// Why a connection ended without a request to answer.
enum Ended {
    /// The client closed, went silent past the deadline, or the server is stopping.
    Quietly,
    /// Answer this and close.
    Refused(Refusal),
}

/// Reads into `buf` until `wanted(buf)` or the deadline, in slices of
/// [`POLL`] so that `stop` is seen; at most `limit` bytes in all.
fn read_until(
    stream: &mut TcpStream,
    buf: &mut Vec<u8>,
    limit: usize,
    deadline: Instant,
    stop: &AtomicBool,
    wanted: impl Fn(&[u8]) -> bool,
) -> Result<(), Ended> {
    let mut chunk = [0u8; 8192];
    while !wanted(buf) {
        if stop.load(Ordering::SeqCst) {
            return Err(Ended::Quietly);
        }
        let now = Instant::now();
        if now >= deadline {
            return Err(Ended::Refused(Refusal::new(
                408,
                format!(
                    "the request was not complete within {} s",
                    REQUEST_DEADLINE.as_secs()
                ),
            )));
        }
        stream
            .set_read_timeout(Some(POLL.min(deadline - now)))
            .map_err(|_| Ended::Quietly)?;
        let room = (limit - buf.len()).min(chunk.len());
        if room == 0 {
            return Ok(());
        }
        match stream.read(&mut chunk[..room]) {
            Ok(0) => return Err(Ended::Quietly),
            Ok(n) => buf.extend_from_slice(&chunk[..n]),
            Err(e)
                if matches!(
                    e.kind(),
                    std::io::ErrorKind::WouldBlock
                        | std::io::ErrorKind::TimedOut
                        | std::io::ErrorKind::Interrupted
                ) => {}
            Err(_) => return Err(Ended::Quietly),
        }
    }
    Ok(())
}

fn find_blank_line(buf: &[u8]) -> Option<usize> {
    buf.windows(4).position(|w| w == b"\r\n\r\n")
}

/// Reads one request: its head, checked, then exactly its body.
fn read_request(
    stream: &mut TcpStream,
    bound: SocketAddr,
    stop: &AtomicBool,
) -> Result<(Head, Vec<u8>), Ended> {
    let deadline = Instant::now() + REQUEST_DEADLINE;
    let mut buf = Vec::new();
    read_until(stream, &mut buf, MAX_HEAD + 4, deadline, stop, |b| {
        find_blank_line(b).is_some()
    })?;
    let Some(end) = find_blank_line(&buf) else {
        return Err(Ended::Refused(Refusal::new(
            431,
            format!("the request head is longer than {MAX_HEAD} bytes"),
        )));
    };
    let head = parse_head(&buf[..end]).map_err(Ended::Refused)?;
    check_origin(&head, bound).map_err(Ended::Refused)?;
    let length = head.content_length().map_err(Ended::Refused)?;
    let mut body = buf.split_off(end + 4);
    if body.len() > length {
        return Err(Ended::Refused(Refusal::new(
            400,
            "more bytes than the Content-Length, or a second request on the connection",
        )));
    }
    if body.len() < length
        && head
            .header("expect")
            .is_some_and(|e| e.eq_ignore_ascii_case("100-continue"))
    {
        stream
            .write_all(b"HTTP/1.1 100 Continue\r\n\r\n")
            .map_err(|_| Ended::Quietly)?;
    }
    body.reserve_exact(length - body.len());
    read_until(stream, &mut body, length, deadline, stop, |b| {
        b.len() == length
    })?;
    Ok((head, body))
}

/// Serves one connection: reads a request, answers it with `respond`
/// (method, target, body), closes.
fn serve_connection(
    mut stream: TcpStream,
    bound: SocketAddr,
    stop: &AtomicBool,
    respond: &Handler<'_>,
) {
    stream.set_write_timeout(Some(REQUEST_DEADLINE)).ok();
    stream.set_nodelay(true).ok();
    match read_request(&mut stream, bound, stop) {
        Ok((head, body)) => {
            let head_only = head.method == "HEAD";
            let method = if head_only {
                "GET"
            } else {
                head.method.as_str()
            };
            let reply = respond(method, &head.target, &body);
            write_answer(&mut stream, &reply, head_only).ok();
        }
        Err(Ended::Refused(r)) => {
            write_answer(&mut stream, &Reply::error(r.status, r.reason), false).ok();
        }
        Err(Ended::Quietly) => {}
    }
    stream.shutdown(std::net::Shutdown::Both).ok();
}

/// Serves on `listener` until `stop` returns true (looked at every
/// [`POLL`]): each connection on a thread of its own, at most
/// [`MAX_CONNECTIONS`] at once (one more is answered 503 at once). Returns
/// once every connection has ended, within a [`POLL`] of the stop for those
/// still reading and after the answer for those being answered.
pub fn serve(
    listener: &TcpListener,
    stop: &(dyn Fn() -> bool + Sync),
    respond: &Handler<'_>,
) -> std::io::Result<()> {
    let bound = listener.local_addr()?;
    listener.set_nonblocking(true)?;
    let stopping = AtomicBool::new(false);
    let active = AtomicUsize::new(0);
    std::thread::scope(|scope| {
        while !stop() {
            match listener.accept() {
                Ok((mut stream, _)) => {
                    stream.set_nonblocking(false).ok();
                    if active.load(Ordering::SeqCst) >= MAX_CONNECTIONS {
                        stream.set_write_timeout(Some(POLL)).ok();
                        let busy = Reply::error(503, "the server is busy: try again");
                        write_answer(&mut stream, &busy, false).ok();
                        continue;
                    }
                    active.fetch_add(1, Ordering::SeqCst);
                    let (stopping, active) = (&stopping, &active);
                    scope.spawn(move || {
                        serve_connection(stream, bound, stopping, respond);
                        active.fetch_sub(1, Ordering::SeqCst);
                    });
                }
                Err(e) if e.kind() == std::io::ErrorKind::WouldBlock => {
                    std::thread::sleep(Duration::from_millis(20));
                }
                Err(e) if e.kind() == std::io::ErrorKind::Interrupted => {}
                // A connection reset before it was accepted, or too many open
                // files for a moment: the next accept may succeed.
                Err(_) => std::thread::sleep(POLL),
            }
        }
        stopping.store(true, Ordering::SeqCst);
    });
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn head(method: &str, headers: &[(&str, &str)]) -> Head {
        Head {
            method: method.into(),
            target: "/api/score".into(),
            headers: headers
                .iter()
                .map(|(n, v)| ((*n).to_string(), (*v).to_string()))
                .collect(),
        }
    }

    #[test]
    fn hosts_that_name_this_server() {
        let loopback: SocketAddr = "127.0.0.1:8765".parse().unwrap();
        let any: SocketAddr = "0.0.0.0:8765".parse().unwrap();
        let v6: SocketAddr = "[::1]:8765".parse().unwrap();
        for host in ["127.0.0.1:8765", "localhost:8765", "LOCALHOST", "127.0.0.1"] {
            assert!(names_this_server(host, loopback), "{host}");
        }
        for host in [
            "evil.example:8765",
            "127.0.0.1:80",
            "127.0.0.2:8765",
            "localhost.evil.example:8765",
            "127.0.0.1:8765:8765",
            "",
        ] {
            assert!(!names_this_server(host, loopback), "{host}");
        }
        assert!(names_this_server("192.168.1.7:8765", any));
        assert!(!names_this_server("printer.local:8765", any));
        assert!(names_this_server("[::1]:8765", v6));
        assert!(names_this_server("localhost:8765", v6));
        assert!(!names_this_server("[::2]:8765", v6));
    }

    #[test]
    fn origins_and_content_types() {
        let bound: SocketAddr = "127.0.0.1:8765".parse().unwrap();
        let ok = [
            ("host", "127.0.0.1:8765"),
            ("origin", "http://127.0.0.1:8765"),
            ("content-type", "application/json; charset=utf-8"),
        ];
        assert_eq!(check_origin(&head("POST", &ok), bound), Ok(()));
        let status = |h: &[(&str, &str)]| check_origin(&head("POST", h), bound).unwrap_err().status;
        assert_eq!(status(&ok[1..]), 400, "no Host");
        assert_eq!(status(&[ok[0], ok[2]]), 403, "no Origin");
        assert_eq!(
            status(&[ok[0], ("origin", "http://evil.example"), ok[2]]),
            403
        );
        assert_eq!(status(&[ok[0], ("origin", "null"), ok[2]]), 403);
        assert_eq!(status(&[ok[0], ok[1], ("content-type", "text/plain")]), 415);
        assert_eq!(status(&[ok[0], ok[1]]), 415);
        assert_eq!(
            status(&[
                ("host", "evil.example:8765"),
                ("origin", "http://evil.example:8765"),
                ok[2]
            ]),
            403,
            "DNS rebinding"
        );
        // Reads need only the Host.
        assert_eq!(check_origin(&head("GET", &ok[..1]), bound), Ok(()));
        assert_eq!(
            check_origin(&head("GET", &[("host", "evil.example:8765")]), bound)
                .unwrap_err()
                .status,
            403
        );
    }

    #[test]
    fn heads_refused_and_taken() {
        let h = parse_head(b"POST /api/score HTTP/1.1\r\nHost: localhost\r\nContent-Length: 12")
            .unwrap();
        assert_eq!(
            (h.method.as_str(), h.target.as_str()),
            ("POST", "/api/score")
        );
        assert_eq!(h.content_length(), Ok(12));
        let status = |b: &[u8]| parse_head(b).unwrap_err().status;
        assert_eq!(status(b"GET / HTTP/2.0"), 505);
        assert_eq!(status(b"GET /  HTTP/1.1"), 400);
        assert_eq!(status(b"get / HTTP/1.1"), 400);
        assert_eq!(status(b"GET http://x/ HTTP/1.1"), 400);
        assert_eq!(status(b"GET / HTTP/1.1\r\nHost: a\r\nHost: b"), 400);
        assert_eq!(status(b"GET / HTTP/1.1\r\nHost: a\r\n folded"), 400);
        assert_eq!(status(b"GET / HTTP/1.1\r\nTransfer-Encoding: chunked"), 411);
        assert_eq!(status(b"GET / HTTP/1.1\r\nNo colon"), 400);
        assert_eq!(status(b"GET / HTTP/1.1\r\nX: \x01"), 400);
        let big = parse_head(b"POST / HTTP/1.1\r\nContent-Length: 99999999999").unwrap();
        assert_eq!(big.content_length().unwrap_err().status, 413);
        let huge = parse_head(b"POST / HTTP/1.1\r\nContent-Length: 18446744073709551616").unwrap();
        assert_eq!(huge.content_length().unwrap_err().status, 400);
        let many: String = (0..=MAX_HEADERS).map(|i| format!("\r\nX-{i}: y")).collect();
        assert_eq!(status(format!("GET / HTTP/1.1{many}").as_bytes()), 431);
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(2000))]

        /// Any bytes: a head or a refusal with a client-error status, never a
        /// panic; a head's length is within the limit or refused.
        #[test]
        fn any_bytes_parse_or_are_refused(bytes in proptest::collection::vec(any::<u8>(), 0..600)) {
            match parse_head(&bytes) {
                Ok(h) => {
                    prop_assert!(h.target.starts_with('/'));
                    if let Ok(n) = h.content_length() {
                        prop_assert!(n <= MAX_BODY);
                    }
                    let _ = check_origin(&h, "127.0.0.1:1".parse().unwrap());
                }
                Err(r) => prop_assert!((400..=505).contains(&r.status)),
            }
        }

        /// Well-formed heads with arbitrary header values: parsed back as
        /// written, and the checks decide without panicking.
        #[test]
        fn written_heads_parse_back(
            values in proptest::collection::vec("[ -~]{0,40}", 0..8),
            length in any::<u64>(),
        ) {
            let mut text = format!("POST /api/x HTTP/1.1\r\nContent-Length: {length}");
            for (i, v) in values.iter().enumerate() {
                text += &format!("\r\nX-{i}: {v}");
            }
            let h = parse_head(text.as_bytes()).unwrap();
            prop_assert_eq!(h.headers.len(), values.len() + 1);
            for (i, v) in values.iter().enumerate() {
                prop_assert_eq!(h.header(&format!("x-{i}")), Some(v.trim_matches([' ', '\t'])));
            }
            match h.content_length() {
                Ok(n) => prop_assert_eq!(n as u64, length),
                Err(r) => prop_assert!(length > MAX_BODY as u64 && r.status == 413),
            }
        }
    }
}
