//! The page's URL parameters, read from `location.search` and checked here, natively tested:
//! `index.html?src=URL&methods=sssm,dtfcn&t=12.5&autoplay=1&embed=1`.
//!
//! * `src` — the file to load instead of the bundled sample: a path on the page's site
//!   (`www/02_01.bvh`) or an `http(s)` URL. Another origin must be allowed by the page's
//!   Content-Security-Policy (`connect-src`, checked by [`connect_src_allows`] before fetching)
//!   and must answer with CORS headers; the messages ([`fetch_failed`], [`csp_refused`],
//!   [`http_failed`]) say which of these went wrong.
//! * `asf` — with an AMC motion in `src`, its ASF skeleton (a path or URL, as `src`): the CMU
//!   originals open from a URL as they do when both files are dropped
//!   (`?src=data/02_01.amc&asf=data/02.asf`). An AMC without `asf`, or an `asf` without an AMC,
//!   is refused with a message saying what to add ([`Parsed::messages`]).
//! * `methods` — the registry names of the methods that run after the load (comma separated);
//!   absent: every method whose `auto_run` is set; empty: none.
//! * `t` — where playback starts, in seconds (`12.5`, `12.5s` or `0:12.5`); a time past the end
//!   starts at the last frame and says so ([`start_frame`]).
//! * `autoplay` — `1` plays at once (`1`/`true`/`yes`/`on` or no value; `0`/`false`/`no`/`off`).
//! * `embed` — the compact player for documentation pages (same values as `autoplay`).
//! * `workers` — how many web workers the page starts (1 to 4; default one per core, at least two):
//!   the methods' rows run side by side on as many; `workers=1` runs everything in one worker, as
//!   a page embedded several times over may want.
//!
//! A value that cannot be used is never fatal: the parameter falls back to its default and
//! [`Parsed::messages`] says why, naming the parameter and what it accepts.

/// The parameters the page knows, in the order the messages list them.
pub const KNOWN: [&str; 7] = ["src", "asf", "methods", "t", "autoplay", "embed", "workers"];

/// What the URL asks of the page.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct UrlParams {
    /// The file to load (as written, trimmed); `None`: the bundled sample.
    pub src: Option<String>,
    /// The ASF skeleton of the AMC motion `src` (as written, trimmed); only with an `.amc` `src`.
    pub asf: Option<String>,
    /// Registry names of the methods to run after a load, each once, in the URL's order;
    /// `None`: the methods whose `auto_run` is set.
    pub methods: Option<Vec<String>>,
    /// Where playback starts, in seconds (finite, ≥ 0).
    pub t: Option<f64>,
    pub autoplay: bool,
    pub embed: bool,
    /// How many workers the page starts (1 to [`crate::worker::pool::MAX_WORKERS`]); `None`: one
    /// per core, at least two.
    pub workers: Option<usize>,
}

/// The parameters and a message for every value that could not be used.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Parsed {
    pub params: UrlParams,
    pub messages: Vec<String>,
}

/// Reads `query` (`location.search`, with or without its `?`). `known_methods` are the
/// registry's names.
pub fn parse(query: &str, known_methods: &[&str]) -> Parsed {
    let mut out = Parsed::default();
    let mut seen: Vec<String> = Vec::new();
    for (key, value) in pairs(query) {
        let name = key.trim().to_ascii_lowercase();
        if seen.contains(&name) && KNOWN.contains(&name.as_str()) {
            out.messages.push(format!("{name} is given more than once; the last one ({name}={value}) is used"));
        }
        seen.push(name.clone());
        match name.as_str() {
            "src" | "asf" => {
                let checked = check_url(&name, &value);
                let slot = if name == "src" { &mut out.params.src } else { &mut out.params.asf };
                match checked {
                    Ok(url) => *slot = Some(url),
                    Err(message) => {
                        *slot = None;
                        out.messages.push(message);
                    }
                }
            }
            "methods" => {
                let (methods, messages) = parse_methods(&value, known_methods);
                out.params.methods = Some(methods);
                out.messages.extend(messages);
            }
            "t" => match parse_time(&value) {
                Ok(t) => out.params.t = Some(t),
                Err(message) => {
                    out.params.t = None;
                    out.messages.push(message);
                }
            },
            "workers" => {
                let max = crate::worker::pool::MAX_WORKERS;
                match value.trim().parse::<usize>() {
                    Ok(n) if (1..=max).contains(&n) => out.params.workers = Some(n),
                    _ => {
                        out.params.workers = None;
                        out.messages.push(format!(
                            "workers={value}: expected a whole number from 1 to {max}; one worker per core is used"
                        ));
                    }
                }
            }
            "autoplay" | "embed" => {
                let flag = match parse_flag(&name, &value) {
                    Ok(flag) => flag,
                    Err(message) => {
                        out.messages.push(message);
                        false
                    }
                };
                if name == "embed" {
                    out.params.embed = flag;
                } else {
                    out.params.autoplay = flag;
                }
            }
            _ => out.messages.push(format!("unknown parameter `{key}` ignored; the page reads {}", KNOWN.join(", "))),
        }
    }
    pair_amc_with_asf(&mut out);
    out
}

/// Whether `url` names an AMC motion (by its file name's extension).
fn is_amc(url: &str) -> bool {
    file_name(url).to_ascii_lowercase().ends_with(".amc")
}

/// An AMC motion is read with its ASF skeleton: both or neither. What is missing is said, and
/// the half given is dropped (the bundled sample is shown instead of a lone AMC).
fn pair_amc_with_asf(out: &mut Parsed) {
    let params = &mut out.params;
    match (&params.src, &params.asf) {
        (Some(src), None) if is_amc(src) => {
            out.messages.push(format!(
                "src={src} is an AMC motion, which needs its skeleton: add asf= with the URL of its .asf file                  (e.g. ?src=02_01.amc&asf=02.asf). The bundled sample is shown"
            ));
            params.src = None;
        }
        (None, Some(asf)) => {
            out.messages.push(format!(
                "asf={asf} is ignored: it is the skeleton of an AMC motion, and no src= names one                  (e.g. ?src=02_01.amc&asf=02.asf)"
            ));
            params.asf = None;
        }
        (Some(src), Some(asf)) if !is_amc(src) => {
            out.messages.push(format!(
                "asf={asf} is ignored: a skeleton is read only with an AMC motion, and src={src} is not an .amc file"
            ));
            params.asf = None;
        }
        _ => {}
    }
}

/// The `key=value` pairs of a query, decoded as `URLSearchParams` does (`+` is a space, `%XX`
/// a byte, malformed escapes kept as written, bytes that are not UTF-8 replaced); empty pairs
/// (`a=1&&b=2`) are skipped.
pub fn pairs(query: &str) -> Vec<(String, String)> {
    let query = query.strip_prefix('?').unwrap_or(query);
    query
        .split('&')
        .filter(|p| !p.is_empty())
        .map(|p| {
            let (k, v) = p.split_once('=').unwrap_or((p, ""));
            (decode(k), decode(v))
        })
        .collect()
}

/// Percent-decoding of one query component.
pub fn decode(s: &str) -> String {
    let bytes = s.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        match bytes[i] {
            b'+' => out.push(b' '),
            b'%' if i + 2 < bytes.len() && hex(bytes[i + 1]).is_some() && hex(bytes[i + 2]).is_some() => {
                out.push(hex(bytes[i + 1]).unwrap_or(0) * 16 + hex(bytes[i + 2]).unwrap_or(0));
                i += 2;
            }
            b => out.push(b),
        }
        i += 1;
    }
    String::from_utf8_lossy(&out).into_owned()
}

fn hex(b: u8) -> Option<u8> {
    (b as char).to_digit(16).map(|d| d as u8)
}

/// Percent-encoding of one query component (what [`decode`] reads back).
pub fn encode(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for b in s.bytes() {
        match b {
            b'A'..=b'Z' | b'a'..=b'z' | b'0'..=b'9' | b'-' | b'_' | b'.' | b'~' | b'/' | b':' | b',' => {
                out.push(b as char)
            }
            _ => out.push_str(&format!("%{b:02X}")),
        }
    }
    out
}

/// The scheme of a URL written with one (`https` of `https://…`, `data` of `data:…`); `None`
/// for a path (`www/a.bvh`, `/a.bvh`, `//host/a.bvh`, `a:b/c.bvh` is a scheme, as a browser reads it).
fn scheme(url: &str) -> Option<&str> {
    let (head, _) = url.split_once(':')?;
    let mut chars = head.chars();
    let first = chars.next()?;
    (first.is_ascii_alphabetic() && chars.all(|c| c.is_ascii_alphanumeric() || "+-.".contains(c))).then_some(head)
}

/// The file parameter `name` (`src`, `asf`): a path on this site or an http(s) URL.
fn check_url(name: &str, value: &str) -> Result<String, String> {
    let url = value.trim();
    if url.is_empty() {
        return Err(format!(
            "{name} is empty: give the file to load, e.g. {name}=www/sample.{}; the bundled sample is shown",
            if name == "asf" { "asf" } else { "bvh" }
        ));
    }
    match scheme(url).map(str::to_ascii_lowercase).as_deref() {
        None | Some("http") | Some("https") => Ok(url.to_string()),
        Some(other) => Err(format!(
            "{name}={url}: a `{other}:` URL cannot be loaded; give a path on this site (www/take.bvh) or an http(s) URL. \
             The bundled sample is shown"
        )),
    }
}

/// The methods of `methods=`: the known ones in the URL's order (each once), and a message
/// naming the unknown ones and listing the known.
fn parse_methods(value: &str, known: &[&str]) -> (Vec<String>, Vec<String>) {
    let mut methods: Vec<String> = Vec::new();
    let mut unknown: Vec<String> = Vec::new();
    for name in value.split(',').map(|n| n.trim()).filter(|n| !n.is_empty()) {
        let lower = name.to_ascii_lowercase();
        if known.contains(&lower.as_str()) {
            if !methods.contains(&lower) {
                methods.push(lower);
            }
        } else if !unknown.iter().any(|u| u == name) {
            unknown.push(name.to_string());
        }
    }
    let mut messages = Vec::new();
    if !unknown.is_empty() {
        let names = unknown.iter().map(|u| format!("`{u}`")).collect::<Vec<_>>().join(", ");
        let what = if unknown.len() == 1 { "unknown method" } else { "unknown methods" };
        let runs =
            if methods.is_empty() { "no method runs".to_string() } else { format!("runs {}", methods.join(", ")) };
        messages.push(format!("methods={value}: {what} {names} ({runs}); the known methods are {}", known.join(", ")));
    }
    (methods, messages)
}

/// A time in seconds: `12.5`, `12.5s`, `1:02.5` (minutes and seconds) or `1:00:05` (hours too).
pub fn parse_time(value: &str) -> Result<f64, String> {
    let v = value.trim();
    let refuse = || {
        format!("t={value}: expected a time in seconds from the start, e.g. t=12.5 (or t=1:02.5); playback starts at 0")
    };
    let v = v.strip_suffix('s').unwrap_or(v);
    if v.is_empty() {
        return Err(refuse());
    }
    let parts: Vec<&str> = v.split(':').collect();
    if parts.len() > 3 {
        return Err(refuse());
    }
    let mut seconds = 0.0;
    for (i, part) in parts.iter().enumerate() {
        let last = i + 1 == parts.len();
        // only the last part may have a fraction; every part is digits (no sign, no exponent)
        let ok = !part.is_empty()
            && part.chars().all(|c| c.is_ascii_digit() || (last && c == '.'))
            && part.chars().filter(|c| *c == '.').count() <= 1
            && part.chars().any(|c| c.is_ascii_digit());
        if !ok {
            return Err(if part.starts_with('-') {
                format!("t={value}: a time cannot be negative; playback starts at 0")
            } else {
                refuse()
            });
        }
        let x: f64 = part.parse().map_err(|_| refuse())?;
        if i > 0 && x >= 60.0 {
            return Err(format!("t={value}: {x} is not below 60 in m:ss; write t=1:05 or t=65"));
        }
        seconds = seconds * 60.0 + x;
    }
    if seconds.is_finite() {
        Ok(seconds)
    } else {
        Err(refuse())
    }
}

fn parse_flag(name: &str, value: &str) -> Result<bool, String> {
    match value.trim().to_ascii_lowercase().as_str() {
        "" | "1" | "true" | "yes" | "on" => Ok(true),
        "0" | "false" | "no" | "off" => Ok(false),
        _ => Err(format!("{name}={value}: expected {name}=1 or {name}=0; taken as 0")),
    }
}

/// The 0-based frame time `t` (seconds) falls on in a take of `frames` frames at `fps`, and a
/// message when `t` is past the end (the last frame is used). `name` names the take.
pub fn start_frame(t: f64, fps: f64, frames: usize, name: &str) -> (usize, Option<String>) {
    if frames == 0 || fps <= 0.0 || !fps.is_finite() || !t.is_finite() || t <= 0.0 {
        return (0, None);
    }
    let frame = (t * fps).round();
    let last = frames - 1;
    if frame <= last as f64 {
        return (frame as usize, None);
    }
    let duration = frames as f64 / fps;
    let message = format!(
        "t={} is past the end of {name} ({frames} frames, {duration:.2} s): playback starts at its last frame ({:.3} s)",
        format_seconds(t),
        last as f64 / fps
    );
    (last, Some(message))
}

/// A time as the URL would write it (`12.5`, not `12.500000`).
fn format_seconds(t: f64) -> String {
    let s = format!("{t:.3}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    s.to_string()
}

/// The query of the full page for the same take: `query` without `embed` (kept as written
/// otherwise); empty when nothing is left.
pub fn full_page_query(query: &str) -> String {
    let query = query.strip_prefix('?').unwrap_or(query);
    let kept: Vec<&str> = query
        .split('&')
        .filter(|p| !p.is_empty())
        .filter(|p| decode(p.split_once('=').map_or(p, |(k, _)| k)).trim().to_ascii_lowercase() != "embed")
        .collect();
    if kept.is_empty() {
        String::new()
    } else {
        format!("?{}", kept.join("&"))
    }
}

/// The full page for the same take (embed mode's "Open in mocapseg" link): `path` and `query`
/// are `location.pathname` and `location.search`, `origin` is `location.origin`. The link always
/// stays on the page's own origin: it is absolute (`origin` + one `/`), and the path's leading
/// slashes — and backslashes, tabs and line breaks, which browsers read as slashes or drop — are
/// collapsed, so that a path like `//evil.example/x` (on a server that answers every path with
/// the page) cannot make it a link to another host. A page without an origin of its own
/// (`null`, as on `file:`) gets a path-absolute link, which the same collapsing keeps on it.
pub fn full_page_href(origin: &str, path: &str, query: &str) -> String {
    let rest = path.trim_start_matches(['/', '\\', '\t', '\n', '\r']);
    let base = if origin.starts_with("http://") || origin.starts_with("https://") { origin } else { "" };
    format!("{base}/{rest}{}", full_page_query(query))
}

/// The file name a URL ends with (`https://a.org/x/02_01.bvh?v=2` → `02_01.bvh`); the whole
/// URL when it ends with `/`.
pub fn file_name(url: &str) -> String {
    let path = url.split(['?', '#']).next().unwrap_or(url);
    match path.rsplit('/').next() {
        Some(name) if !name.is_empty() => decode(name),
        _ => url.to_string(),
    }
}

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

/// A load's failure of the file from `src=` (the parser's message), naming the URL.
pub fn load_failed(url: &str, message: &str) -> String {
    format!("src={url}: {message}")
}

#[cfg(test)]
mod tests {
    use super::*;

    const METHODS: [&str; 7] = ["sssm", "velocity", "kcs", "pca", "lma", "knn", "dtfcn"];

    fn p(q: &str) -> Parsed {
        parse(q, &METHODS)
    }

    #[test]
    fn defaults_when_there_is_no_query() {
        for q in ["", "?", "?&&"] {
            let parsed = p(q);
            assert_eq!(parsed.params, UrlParams::default(), "{q}");
            assert!(parsed.messages.is_empty(), "{q}: {:?}", parsed.messages);
        }
    }

    #[test]
    fn every_parameter_together() {
        let parsed = p("?src=www/02_01.bvh&methods=sssm,dtfcn&t=12.5&autoplay=1&embed=1&workers=2");
        assert_eq!(
            parsed.params,
            UrlParams {
                src: Some("www/02_01.bvh".into()),
                asf: None,
                methods: Some(vec!["sssm".into(), "dtfcn".into()]),
                t: Some(12.5),
                autoplay: true,
                embed: true,
                workers: Some(2),
            }
        );
        assert!(parsed.messages.is_empty(), "{:?}", parsed.messages);
    }

    #[test]
    fn an_amc_src_needs_its_asf_and_an_asf_needs_an_amc() {
        let both = p("?src=data/02_01.AMC&asf=https://a.org/02.asf");
        assert_eq!(both.params.src.as_deref(), Some("data/02_01.AMC"));
        assert_eq!(both.params.asf.as_deref(), Some("https://a.org/02.asf"));
        assert!(both.messages.is_empty(), "{:?}", both.messages);
        // in either order
        assert_eq!(p("asf=02.asf&src=02_01.amc").params, both_of("02_01.amc", "02.asf"));
        // an AMC alone: the sample, and what to add
        let alone = p("src=02_01.amc");
        assert_eq!(alone.params.src, None);
        assert!(alone.messages[0].contains("src=02_01.amc is an AMC motion") && alone.messages[0].contains("asf="));
        // a skeleton without an AMC: ignored, saying why
        let lone = p("asf=02.asf");
        assert_eq!((lone.params.src.clone(), lone.params.asf.clone()), (None, None));
        assert!(lone.messages[0].starts_with("asf=02.asf is ignored") && lone.messages[0].contains("no src="));
        let with_bvh = p("src=a.bvh&asf=02.asf");
        assert_eq!((with_bvh.params.src.as_deref(), with_bvh.params.asf.clone()), (Some("a.bvh"), None));
        assert!(with_bvh.messages[0].contains("src=a.bvh is not an .amc file"), "{:?}", with_bvh.messages);
        // an asf that cannot be fetched is refused as src is, by its own name; then the AMC is alone
        let bad = p("src=02_01.amc&asf=data:x");
        assert!(bad.messages[0].starts_with("asf=data:x: a `data:` URL cannot be loaded"), "{:?}", bad.messages);
        assert_eq!(bad.params.src, None);
        assert!(p("src=a.amc&asf=").messages[0].starts_with("asf is empty"));
    }

    fn both_of(src: &str, asf: &str) -> UrlParams {
        UrlParams { src: Some(src.into()), asf: Some(asf.into()), ..UrlParams::default() }
    }

    #[test]
    fn src_is_decoded_and_may_be_an_http_url() {
        assert_eq!(
            p("src=https%3A%2F%2Fa.org%2Fmy%20take.bvh").params.src.as_deref(),
            Some("https://a.org/my take.bvh")
        );
        assert_eq!(p("src=my+take.bvh").params.src.as_deref(), Some("my take.bvh"));
        assert_eq!(p("src=http://a.org/x.bvh?v=2").params.src.as_deref(), Some("http://a.org/x.bvh?v=2"));
        assert_eq!(p("src=//a.org/x.bvh").params.src.as_deref(), Some("//a.org/x.bvh"));
        assert_eq!(p("src=/data/x.bvh").params.src.as_deref(), Some("/data/x.bvh"));
        // a malformed escape stays as written, as URLSearchParams keeps it
        assert_eq!(p("src=50%.bvh").params.src.as_deref(), Some("50%.bvh"));
        assert_eq!(p("src=a%zz.bvh").params.src.as_deref(), Some("a%zz.bvh"));
    }

    #[test]
    fn src_refuses_other_schemes_and_empty() {
        for (q, word) in [
            ("src=javascript:alert(1)", "`javascript:`"),
            ("src=data:text/plain,HIERARCHY", "`data:`"),
            ("src=file:///etc/passwd", "`file:`"),
            ("src=blob:http://x/1", "`blob:`"),
        ] {
            let parsed = p(q);
            assert_eq!(parsed.params.src, None, "{q}");
            assert_eq!(parsed.messages.len(), 1, "{q}");
            assert!(
                parsed.messages[0].contains(word) && parsed.messages[0].contains("http(s)"),
                "{:?}",
                parsed.messages
            );
        }
        let parsed = p("src=&t=1");
        assert_eq!(parsed.params.src, None);
        assert_eq!(parsed.params.t, Some(1.0));
        assert!(parsed.messages[0].starts_with("src is empty"), "{:?}", parsed.messages);
    }

    #[test]
    fn methods_known_unknown_duplicates_and_empty() {
        let parsed = p("methods=SSSM, velocity,sssm,,lma");
        assert_eq!(parsed.params.methods, Some(vec!["sssm".into(), "velocity".into(), "lma".into()]));
        assert!(parsed.messages.is_empty());

        let parsed = p("methods=sssm,foo,bar,foo");
        assert_eq!(parsed.params.methods, Some(vec!["sssm".into()]));
        assert_eq!(
            parsed.messages,
            vec!["methods=sssm,foo,bar,foo: unknown methods `foo`, `bar` (runs sssm); the known methods are sssm, velocity, \
                  kcs, pca, lma, knn, dtfcn"
                .to_string()]
        );

        let parsed = p("methods=nope");
        assert_eq!(parsed.params.methods, Some(vec![]));
        assert!(parsed.messages[0].contains("unknown method `nope` (no method runs)"), "{:?}", parsed.messages);
        assert!(parsed.messages[0].contains("sssm, velocity, kcs, pca, lma, knn, dtfcn"));

        // present but empty: none runs, on purpose
        let parsed = p("methods=");
        assert_eq!(parsed.params.methods, Some(vec![]));
        assert!(parsed.messages.is_empty());
    }

    #[test]
    fn times_in_every_form() {
        for (v, want) in [
            ("12.5", 12.5),
            ("0", 0.0),
            ("12.5s", 12.5),
            ("1:02.5", 62.5),
            ("1:00:05", 3605.0),
            (" 3 ", 3.0),
            ("07", 7.0),
            (".5", 0.5),
        ] {
            assert_eq!(parse_time(v), Ok(want), "{v}");
            assert_eq!(p(&format!("t={v}")).params.t, Some(want), "{v}");
        }
    }

    #[test]
    fn bad_times_say_what_is_expected() {
        for v in ["", "abc", "1e3", "NaN", "inf", "1.2.3", "1:2:3:4", "1:", ":5", "12.5ms", "0x10", "1,5"] {
            let parsed = p(&format!("t={v}"));
            assert_eq!(parsed.params.t, None, "{v}");
            assert_eq!(parsed.messages.len(), 1, "{v}");
            assert!(parsed.messages[0].contains("expected a time in seconds"), "{v}: {:?}", parsed.messages);
        }
        let negative = p("t=-3").messages;
        assert!(negative[0].contains("cannot be negative"), "{negative:?}");
        let sixty = p("t=1:75").messages;
        assert!(sixty[0].contains("75 is not below 60"), "{sixty:?}");
        // a huge number of digits is not finite
        let huge = format!("t={}", "9".repeat(400));
        assert_eq!(p(&huge).params.t, None);
    }

    #[test]
    fn workers_is_a_count_from_one_to_the_pools_most() {
        assert_eq!(p("workers=1").params.workers, Some(1));
        assert_eq!(p("workers=4").params.workers, Some(4));
        assert_eq!(p("").params.workers, None);
        for bad in ["0", "5", "two", "-1", ""] {
            let parsed = p(&format!("workers={bad}"));
            assert_eq!(parsed.params.workers, None, "workers={bad}");
            assert_eq!(
                parsed.messages,
                [format!("workers={bad}: expected a whole number from 1 to 4; one worker per core is used")]
            );
        }
    }

    #[test]
    fn flags() {
        for (v, want) in [
            ("1", true),
            ("true", true),
            ("YES", true),
            ("on", true),
            ("", true),
            ("0", false),
            ("false", false),
            ("off", false),
            ("no", false),
        ] {
            assert_eq!(p(&format!("autoplay={v}")).params.autoplay, want, "autoplay={v}");
            assert_eq!(p(&format!("embed={v}")).params.embed, want, "embed={v}");
        }
        // a key without `=`
        assert!(p("autoplay").params.autoplay);
        let parsed = p("autoplay=2&embed=maybe");
        assert!(!parsed.params.autoplay && !parsed.params.embed);
        assert_eq!(
            parsed.messages,
            vec![
                "autoplay=2: expected autoplay=1 or autoplay=0; taken as 0".to_string(),
                "embed=maybe: expected embed=1 or embed=0; taken as 0".to_string()
            ]
        );
    }

    #[test]
    fn unknown_and_repeated_parameters_are_named() {
        let parsed = p("method=sssm&T=2&t=3");
        assert_eq!(parsed.params.t, Some(3.0), "names are case-insensitive, the last wins");
        assert_eq!(parsed.messages.len(), 2, "{:?}", parsed.messages);
        assert_eq!(
            parsed.messages[0],
            "unknown parameter `method` ignored; the page reads src, asf, methods, t, autoplay, embed, workers"
        );
        assert_eq!(parsed.messages[1], "t is given more than once; the last one (t=3) is used");
    }

    #[test]
    fn start_frame_rounds_and_clamps() {
        assert_eq!(start_frame(1.5, 120.0, 343, "02_01.bvh"), (180, None));
        assert_eq!(start_frame(0.0, 120.0, 343, "x"), (0, None));
        assert_eq!(start_frame(0.004, 120.0, 343, "x"), (0, None));
        assert_eq!(start_frame(0.005, 120.0, 343, "x"), (1, None));
        // the last frame exactly, and past it
        assert_eq!(start_frame(342.0 / 120.0, 120.0, 343, "x"), (342, None));
        let (frame, message) = start_frame(99.0, 120.0, 343, "02_01.bvh");
        assert_eq!(frame, 342);
        assert_eq!(
            message.as_deref(),
            Some("t=99 is past the end of 02_01.bvh (343 frames, 2.86 s): playback starts at its last frame (2.850 s)")
        );
        // no take, no frame rate
        assert_eq!(start_frame(5.0, 120.0, 0, "x"), (0, None));
        assert_eq!(start_frame(5.0, 0.0, 10, "x"), (0, None));
    }

    #[test]
    fn full_page_query_drops_embed_only() {
        assert_eq!(full_page_query("?embed=1&src=www/a.bvh&t=2"), "?src=www/a.bvh&t=2");
        assert_eq!(full_page_query("src=a%20b.bvh&EMBED=1&methods=sssm,lma"), "?src=a%20b.bvh&methods=sssm,lma");
        assert_eq!(full_page_query("?embed=1"), "");
        assert_eq!(full_page_query(""), "");
        assert_eq!(full_page_query("?embed"), "");
    }

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

    #[test]
    fn the_full_page_link_stays_on_the_page_s_origin() {
        let o = "http://127.0.0.1:8080";
        assert_eq!(full_page_href(o, "/", "?embed=1&src=a.bvh"), "http://127.0.0.1:8080/?src=a.bvh");
        assert_eq!(full_page_href(o, "/app/index.html", "?embed=1"), "http://127.0.0.1:8080/app/index.html");
        assert_eq!(full_page_href(o, "", ""), "http://127.0.0.1:8080/");
        // a path that would make `//host` (protocol-relative) or `/\host` (read as `//host`)
        for path in ["//evil.example/x", "///evil.example", "/\\evil.example/x", "\\\\evil.example", "/\t/evil.example"]
        {
            let href = full_page_href(o, path, "?embed=1&t=2");
            assert!(href.starts_with("http://127.0.0.1:8080/evil.example"), "{path:?} -> {href}");
            assert!(href.ends_with("?t=2"), "{href}");
        }
        // no origin of its own (file:): path-absolute, never protocol-relative
        assert_eq!(full_page_href("null", "//evil.example/x", ""), "/evil.example/x");
        assert_eq!(full_page_href("null", "/home/me/dist/index.html", "?embed=1"), "/home/me/dist/index.html");
        assert_eq!(full_page_href("", "", ""), "/");
    }

    #[test]
    fn file_names() {
        assert_eq!(file_name("www/02_01.bvh"), "02_01.bvh");
        assert_eq!(file_name("https://a.org/x/my%20take.bvh?v=2#f"), "my take.bvh");
        assert_eq!(file_name("take.bvh"), "take.bvh");
        assert_eq!(file_name("https://a.org/"), "https://a.org/");
    }

    #[test]
    fn encode_decodes_back() {
        for s in ["www/02_01.bvh", "https://a.org/x y.bvh?v=2&w=ü", "a+b%c"] {
            assert_eq!(decode(&encode(s)), s);
        }
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
