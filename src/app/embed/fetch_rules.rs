//! What the page allows and says when it fetches a file from a URL (`src=`, `asf=`), natively tested: whether
//! the page's Content-Security-Policy lets it fetch from another origin ([`connect_src_allows`]), the most it
//! reads of one file ([`MAX_FILE_BYTES`], [`SizeCap`]), and the messages naming the URL and what went wrong
//! ([`csp_refused`], [`http_failed`], [`fetch_failed`], [`too_large`]).

/// Whether a page whose Content-Security-Policy is `csp` (a `<meta>`'s content; empty: none)
/// may fetch from `origin` (`https://host[:port]`), the page being on `page_origin`: the sources
/// of `connect-src`, else of `default-src`, else anything. Understands `'self'`, `'none'`, `*`,
/// schemes (`https:`) and hosts (`https://a.org`, `a.org:8080`, `*.a.org`, paths ignored).
pub fn connect_src_allows(csp: &str, page_origin: &str, origin: &str) -> bool {
    let directives: Vec<(String, Vec<&str>)> = csp
        .split(';')
        .filter_map(|d| {
            let mut words = d.split_whitespace();
            let name = words.next()?.to_ascii_lowercase();
            Some((name, words.collect()))
        })
        .collect();
    let sources = directives
        .iter()
        .find(|(n, _)| n == "connect-src")
        .or_else(|| directives.iter().find(|(n, _)| n == "default-src"));
    let Some((_, sources)) = sources else { return true };
    let (scheme, host, port) = split_origin(origin);
    let (page_scheme, _, _) = split_origin(page_origin);
    sources.iter().any(|source| {
        let s = source.to_ascii_lowercase();
        match s.as_str() {
            "'self'" => origin.eq_ignore_ascii_case(page_origin),
            "'none'" => false,
            "*" => scheme == "http" || scheme == "https",
            _ if s.starts_with('\'') => false, // nonces, hashes, keywords that do not name hosts
            _ if s.ends_with(':') && !s.contains('/') => {
                let wanted = &s[..s.len() - 1];
                // http: also allows https (the secure upgrade)
                scheme == wanted || (wanted == "http" && scheme == "https")
            }
            _ => {
                let (s_scheme, rest) = match s.split_once("://") {
                    Some((sc, rest)) => (Some(sc), rest),
                    None => (None, s.as_str()),
                };
                let scheme_ok = match s_scheme {
                    Some(sc) => sc == scheme || (sc == "http" && scheme == "https"),
                    None => scheme == page_scheme || (page_scheme == "http" && scheme == "https"),
                };
                let hostport = rest.split('/').next().unwrap_or("");
                let (s_host, s_port) = match hostport.rsplit_once(':') {
                    Some((h, p)) => (h, Some(p)),
                    None => (hostport, None),
                };
                let host_ok = match s_host.strip_prefix("*.") {
                    Some(suffix) => host.len() > suffix.len() + 1 && host.ends_with(&format!(".{suffix}")),
                    None => s_host == host,
                };
                let port_ok = match s_port {
                    Some("*") => true,
                    Some(p) => p == port,
                    None => port == default_port(&scheme),
                };
                scheme_ok && host_ok && port_ok
            }
        }
    })
}

/// (scheme, host, port) of `scheme://host[:port]`, the port made explicit.
fn split_origin(origin: &str) -> (String, String, String) {
    let lower = origin.to_ascii_lowercase();
    let (scheme, rest) = lower.split_once("://").unwrap_or(("", lower.as_str()));
    let hostport = rest.split('/').next().unwrap_or("");
    let (host, port) = match hostport.rsplit_once(':') {
        // `[::1]:8080` has a port, `[::1]` has none
        Some((h, p)) if !p.contains(']') => (h.to_string(), p.to_string()),
        _ => (hostport.to_string(), default_port(scheme)),
    };
    (scheme.to_string(), host, port)
}

fn default_port(scheme: &str) -> String {
    match scheme {
        "https" => "443".into(),
        _ => "80".into(),
    }
}

/// The message when the page's Content-Security-Policy does not allow fetching `url` (given as
/// parameter `param`, `src` or `asf`; on
/// `origin`) from a page on `page_origin`.
pub fn csp_refused(param: &str, url: &str, origin: &str, page_origin: &str) -> String {
    format!(
        "{param}={url}: not loaded: {origin} is another origin, and this page's Content-Security-Policy lets it fetch \
         files from {page_origin} only (connect-src). Copy the file next to the page, or, on a site you host, add \
         {origin} to connect-src in index.html (docs/page.md, \"Embedding\")"
    )
}

/// The message when the server answered `url` with an HTTP error.
pub fn http_failed(param: &str, url: &str, status: u16, status_text: &str) -> String {
    let what = match status {
        404 | 410 => "there is no such file",
        401 | 403 => "the server refuses to give it",
        s if s >= 500 => "the server failed",
        _ => "the server refused the request",
    };
    let text = if status_text.is_empty() { String::new() } else { format!(" {status_text}") };
    format!("{param}={url}: not loaded: HTTP {status}{text} ({what})")
}

/// The message when fetching `url` failed without an answer (`error`: the browser's words):
/// for another origin, most often a server that sends no CORS header for this page.
pub fn fetch_failed(param: &str, url: &str, cross_origin: Option<(&str, &str)>, error: &str) -> String {
    match cross_origin {
        Some((origin, page_origin)) => format!(
            "{param}={url}: not loaded ({error}): {origin} did not let this page read the file — it must answer with \
             Access-Control-Allow-Origin: {page_origin} (or *) — or it could not be reached"
        ),
        None => format!("{param}={url}: not loaded ({error}): the server could not be reached"),
    }
}

/// The largest file the page reads, dropped, picked or from `src=` (bytes); the worker's memory
/// budget then checks what the take needs.
pub const MAX_FILE_BYTES: u64 = 512 * 1024 * 1024;

/// A download that may not pass `cap` bytes: the answer's `Content-Length` is checked before its
/// body is read ([`SizeCap::declared`]), and the body as it arrives ([`SizeCap::add`]) — a server
/// may send no length, or a wrong one.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SizeCap {
    cap: u64,
    read: u64,
}

impl SizeCap {
    pub fn new(cap: u64) -> SizeCap {
        SizeCap { cap, read: 0 }
    }

    /// The size a `Content-Length` header announces, refused (`Err(size)`) past the cap; a
    /// missing or unreadable header is left to [`SizeCap::add`].
    pub fn declared(&self, content_length: Option<&str>) -> Result<(), u64> {
        match content_length.and_then(|l| l.trim().parse::<u64>().ok()) {
            Some(size) if size > self.cap => Err(size),
            _ => Ok(()),
        }
    }

    /// `n` more bytes arrived: `Err(read so far)` once they pass the cap (stop reading then).
    pub fn add(&mut self, n: u64) -> Result<(), u64> {
        self.read = self.read.saturating_add(n);
        if self.read > self.cap {
            Err(self.read)
        } else {
            Ok(())
        }
    }

    /// The bytes read so far.
    pub fn read(&self) -> u64 {
        self.read
    }
}

/// The message when the file of `param` (`src`, `asf`) at `url` is larger than `cap` bytes:
/// `size` is what its `Content-Length` says (`declared`) or what arrived before the page stopped.
pub fn too_large(param: &str, url: &str, size: u64, declared: bool, cap: u64) -> String {
    let mib = |b: u64| format!("{:.0} MiB", (b as f64 / 1024.0 / 1024.0).ceil());
    if declared {
        format!(
            "{param}={url}: not loaded: the file is {}, more than the page reads ({}); cut the take",
            mib(size),
            mib(cap)
        )
    } else {
        format!("{param}={url}: not loaded: the download passed {}, the most the page reads; cut the take", mib(cap))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::app::embed::url_params::load_failed;

    #[test]
    fn a_download_is_capped_by_its_length_and_by_what_arrives() {
        let cap = SizeCap::new(1000);
        assert_eq!(cap.declared(Some("1000")), Ok(()));
        assert_eq!(cap.declared(Some(" 1001 ")), Err(1001));
        assert_eq!(cap.declared(Some("629145600")), Err(629_145_600));
        assert_eq!(cap.declared(None), Ok(()), "no length: the body is counted instead");
        assert_eq!(cap.declared(Some("lots")), Ok(()));
        let mut body = SizeCap::new(1000);
        assert_eq!(body.add(600), Ok(()));
        assert_eq!(body.add(400), Ok(()));
        assert_eq!(body.add(1), Err(1001), "one byte past the cap stops the download");
        assert_eq!(body.read(), 1001);
        let mut huge = SizeCap::new(MAX_FILE_BYTES);
        assert_eq!(huge.add(u64::MAX).unwrap_err(), u64::MAX, "no overflow");
        assert_eq!(
            too_large("src", "huge.bvh", 600 * 1024 * 1024, true, MAX_FILE_BYTES),
            "src=huge.bvh: not loaded: the file is 600 MiB, more than the page reads (512 MiB); cut the take"
        );
        assert_eq!(
            too_large("asf", "a.asf", MAX_FILE_BYTES + 1, false, MAX_FILE_BYTES),
            "asf=a.asf: not loaded: the download passed 512 MiB, the most the page reads; cut the take"
        );
    }

    const PAGE: &str = "http://127.0.0.1:8080";

    #[test]
    fn the_page_csp_allows_its_own_origin_only() {
        let csp = "default-src 'self'; script-src 'self' 'wasm-unsafe-eval'; connect-src 'self'; img-src 'self'";
        assert!(connect_src_allows(csp, PAGE, PAGE));
        assert!(!connect_src_allows(csp, PAGE, "http://localhost:8080"));
        assert!(!connect_src_allows(csp, PAGE, "https://a.org"));
        // no policy: anything; default-src when connect-src is absent
        assert!(connect_src_allows("", PAGE, "https://a.org"));
        assert!(!connect_src_allows("default-src 'self'", PAGE, "https://a.org"));
        assert!(!connect_src_allows("connect-src 'none'", PAGE, PAGE));
    }

    #[test]
    fn csp_host_and_scheme_sources() {
        let csp = "connect-src 'self' https://data.example.org *.cdn.org:8443";
        assert!(connect_src_allows(csp, PAGE, "https://data.example.org"));
        assert!(!connect_src_allows(csp, PAGE, "https://data.example.org:444"));
        assert!(connect_src_allows(csp, PAGE, "http://x.cdn.org:8443"));
        assert!(!connect_src_allows(csp, PAGE, "http://cdn.org:8443"), "*.host needs a subdomain");
        assert!(!connect_src_allows(csp, PAGE, "http://anything.net"));
        assert!(connect_src_allows("connect-src http:", PAGE, "http://anything.net"), "http: names a scheme");
        assert!(connect_src_allows("connect-src http:", PAGE, "https://anything.net"), "and its secure upgrade");
        assert!(connect_src_allows("connect-src *", PAGE, "https://a.org"));
        assert!(connect_src_allows("connect-src a.org", "https://me.org", "https://a.org"));
        assert!(!connect_src_allows("connect-src a.org", "https://me.org", "http://a.org"));
        assert!(connect_src_allows("connect-src https://a.org/data/", PAGE, "https://a.org"));
        assert!(connect_src_allows("connect-src https://a.org:*", PAGE, "https://a.org:9000"));
    }

    #[test]
    fn messages_name_the_url_and_what_happened() {
        let m = http_failed("src", "www/none.bvh", 404, "File not found");
        assert_eq!(m, "src=www/none.bvh: not loaded: HTTP 404 File not found (there is no such file)");
        assert!(http_failed("src", "x", 500, "").contains("HTTP 500 (the server failed)"));
        assert!(http_failed("asf", "02.asf", 404, "").starts_with("asf=02.asf: not loaded: HTTP 404"));
        let m = csp_refused("src", "http://localhost:8080/a.bvh", "http://localhost:8080", PAGE);
        assert!(m.starts_with("src=http://localhost:8080/a.bvh: not loaded:") && m.contains("connect-src"), "{m}");
        let m = fetch_failed("src", "https://a.org/a.bvh", Some(("https://a.org", PAGE)), "Failed to fetch");
        assert!(m.contains("Access-Control-Allow-Origin: http://127.0.0.1:8080"), "{m}");
        let m = fetch_failed("src", "a.bvh", None, "Failed to fetch");
        assert_eq!(m, "src=a.bvh: not loaded (Failed to fetch): the server could not be reached");
        assert_eq!(
            load_failed("a.bvh", "a.bvh: line 1: expected HIERARCHY"),
            "src=a.bvh: a.bvh: line 1: expected HIERARCHY"
        );
    }
}
