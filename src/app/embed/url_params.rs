//! The page's URL parameters, read from `location.search` and checked here, natively tested:
//! `index.html?src=URL&methods=sssm,dtfcn&t=12.5&autoplay=1&embed=1`.
//!
//! * `src` — the file to load instead of the bundled sample: a path on the page's site
//!   (`www/02_01.bvh`) or an `http(s)` URL. Another origin must be allowed by the page's
//!   Content-Security-Policy (`connect-src`, checked before fetching) and must answer with CORS
//!   headers; the messages say which of these went wrong ([`super::fetch_rules`]).
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
    /// Whether the URL says what to show — `src`, `t`, `autoplay` or `embed` is given, valid or not — so that the page
    /// does not open the workspace kept in this browser ([`crate::app::session`]).
    pub says_what_to_show: bool,
}

/// The parameters that say what the page shows (any of them, valid or not, keeps the workspace kept in this browser
/// closed).
pub const SAY_WHAT_TO_SHOW: [&str; 4] = ["src", "t", "autoplay", "embed"];

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
    out.params.says_what_to_show = seen.iter().any(|k| SAY_WHAT_TO_SHOW.contains(&k.as_str()));
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

/// A load's failure of the file from `src=` (the parser's message), naming the URL.
pub fn load_failed(url: &str, message: &str) -> String {
    format!("src={url}: {message}")
}

#[cfg(test)]
mod tests;
