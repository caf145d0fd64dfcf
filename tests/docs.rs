//! The documentation's links: every markdown link and image in `README.md`, `docs/**/*.md` and the other markdown
//! files of the repository that link anywhere must lead somewhere — a relative target must exist, and a `#anchor`
//! must be a heading of its target (GitHub's slugs). External `http(s)://` and `mailto:` links are not fetched (no
//! network in CI). And the README stays short enough for a newcomer to read in two minutes.
#![cfg(not(target_arch = "wasm32"))]

use std::collections::HashMap;
use std::path::{Component, Path, PathBuf};

/// The README's length limit (issue 22: "a README a newcomer reads in two minutes").
const README_MAX_LINES: usize = 250;

/// The markdown files whose links are checked besides `docs/**/*.md`.
const OTHER_FILES: [&str; 5] =
    ["README.md", "models/README.md", "www/SOURCES.md", "tests/fixtures/SOURCES.md", "bench/peers/README.md"];

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// GitHub's anchor for a heading: lowercase; letters, digits, `_`, `-` and spaces kept, every other character
/// dropped; each space becomes `-`. Inline code's backticks and emphasis markers are punctuation, so they go too.
fn slug(heading: &str) -> String {
    heading
        .trim()
        .to_lowercase()
        .chars()
        .filter(|c| c.is_alphanumeric() || matches!(c, '-' | '_' | ' '))
        .map(|c| if c == ' ' { '-' } else { c })
        .collect()
}

/// The text of an ATX heading line (`## Title ##` → `Title`), links reduced to their text.
fn heading_text(line: &str) -> Option<String> {
    let t = line.trim_start_matches(' ');
    if line.len() - t.len() > 3 {
        return None;
    }
    let hashes = t.chars().take_while(|&c| c == '#').count();
    let rest = &t[hashes..];
    if !(1..=6).contains(&hashes) || !(rest.is_empty() || rest.starts_with(' ') || rest.starts_with('\t')) {
        return None;
    }
    let text = rest.trim().trim_end_matches('#').trim_end();
    // `[text](target)` → `text` (GitHub slugs the rendered text)
    let mut out = String::new();
    let mut links = links_in_line(text).into_iter().peekable();
    let mut i = 0;
    while i < text.len() {
        match links.peek() {
            Some(l) if l.start == i => {
                out += &text[l.start + 1 + usize::from(l.image)..l.text_end];
                i = l.end;
                links.next();
            }
            _ => {
                let c = text[i..].chars().next().unwrap_or(' ');
                out.push(c);
                i += c.len_utf8();
            }
        }
    }
    Some(out)
}

/// Every anchor of a markdown text, numbered as GitHub numbers repeated headings (`x`, `x-1`, `x-2`, …).
fn anchors(text: &str) -> Vec<String> {
    let mut seen: HashMap<String, usize> = HashMap::new();
    let mut out = Vec::new();
    for (line, _) in outside_code_blocks(text) {
        if let Some(h) = heading_text(line) {
            let s = slug(&h);
            let n = seen.entry(s.clone()).or_insert(0);
            out.push(if *n == 0 { s.clone() } else { format!("{s}-{n}") });
            *n += 1;
        }
    }
    out
}

/// The lines of a markdown text outside fenced code blocks, with their 1-based numbers.
fn outside_code_blocks(text: &str) -> Vec<(&str, usize)> {
    let mut fence: Option<&str> = None;
    let mut out = Vec::new();
    for (i, line) in text.lines().enumerate() {
        let t = line.trim_start();
        let marker = if t.starts_with("```") {
            Some("```")
        } else if t.starts_with("~~~") {
            Some("~~~")
        } else {
            None
        };
        match (fence, marker) {
            (None, Some(m)) => fence = Some(m),
            (Some(f), Some(m)) if f == m => fence = None,
            (None, None) => out.push((line, i + 1)),
            _ => {}
        }
    }
    out
}

/// One inline link or image of a line: `[text](target)` or `![alt](target)`, by byte offsets.
#[derive(Debug, PartialEq)]
struct Link {
    start: usize,
    text_end: usize,
    end: usize,
    image: bool,
    target: String,
}

/// The inline links and images of one line, code spans left out; an image inside a link's text (a badge) counts as
/// well as the link. The target drops a `"title"` and `<…>` brackets; parentheses inside it must balance.
fn links_in_line(line: &str) -> Vec<Link> {
    let b = line.as_bytes();
    let mut out = Vec::new();
    let mut i = 0;
    while i < b.len() {
        match b[i] {
            b'`' => {
                // a code span: skip to the closing run of as many backticks
                let run = b[i..].iter().take_while(|&&c| c == b'`').count();
                let close = "`".repeat(run);
                i = line[i + run..].find(&close).map_or(b.len(), |p| i + run + p + run);
            }
            b'\\' => i += 2,
            b'[' => {
                let image = i > 0 && b[i - 1] == b'!' && (i < 2 || b[i - 2] != b'\\');
                let start = if image { i - 1 } else { i };
                // the matching `]` (nested brackets allowed, code spans skipped)
                let (mut depth, mut j) = (0usize, i);
                let mut text_end = None;
                while j < b.len() {
                    match b[j] {
                        b'`' => {
                            let run = b[j..].iter().take_while(|&&c| c == b'`').count();
                            let close = "`".repeat(run);
                            j = line[j + run..].find(&close).map_or(b.len(), |p| j + run + p + run);
                            continue;
                        }
                        b'\\' => j += 1,
                        b'[' => depth += 1,
                        b']' => {
                            depth -= 1;
                            if depth == 0 {
                                text_end = Some(j);
                                break;
                            }
                        }
                        _ => {}
                    }
                    j += 1;
                }
                let Some(te) = text_end else {
                    i += 1;
                    continue;
                };
                if b.get(te + 1) != Some(&b'(') {
                    i += 1; // not a link: look inside the brackets too
                    continue;
                }
                let (mut depth, mut k) = (1usize, te + 2);
                while k < b.len() && depth > 0 {
                    match b[k] {
                        b'(' => depth += 1,
                        b')' => depth -= 1,
                        b'\\' => k += 1,
                        _ => {}
                    }
                    k += 1;
                }
                if depth != 0 {
                    i += 1;
                    continue;
                }
                let inner = line[te + 2..k - 1].trim();
                let target = if let Some(rest) = inner.strip_prefix('<') {
                    rest.split('>').next().unwrap_or_default()
                } else {
                    inner.split_whitespace().next().unwrap_or_default()
                };
                out.push(Link { start, text_end: te, end: k, image, target: target.to_string() });
                // links inside the text (an image in a link) are found by going on just past the `[`
                i += 1;
            }
            _ => i += 1,
        }
    }
    out.sort_by_key(|l| l.start);
    out
}

/// `[label]: target` reference definitions of a line.
fn reference_definition(line: &str) -> Option<String> {
    let t = line.trim_start();
    if line.len() - t.len() > 3 || !t.starts_with('[') || t.starts_with("[^") {
        return None;
    }
    let close = t.find("]:")?;
    let target = t[close + 2..].split_whitespace().next()?;
    Some(target.trim_start_matches('<').trim_end_matches('>').to_string())
}

/// Every link and image target of a markdown text with its line number.
fn targets(text: &str) -> Vec<(usize, String)> {
    let mut out = Vec::new();
    for (line, n) in outside_code_blocks(text) {
        out.extend(links_in_line(line).into_iter().map(|l| (n, l.target)));
        out.extend(reference_definition(line).map(|t| (n, t)));
    }
    out
}

fn is_external(target: &str) -> bool {
    let lower = target.to_ascii_lowercase();
    ["http://", "https://", "mailto:", "ftp://"].iter().any(|p| lower.starts_with(p))
}

/// `%20`-style escapes decoded (ASCII only, as the repository's file names are).
fn percent_decode(s: &str) -> String {
    let b = s.as_bytes();
    let mut out = Vec::with_capacity(b.len());
    let mut i = 0;
    while i < b.len() {
        if b[i] == b'%' && i + 2 < b.len() {
            if let Some(v) = std::str::from_utf8(&b[i + 1..i + 3]).ok().and_then(|h| u8::from_str_radix(h, 16).ok()) {
                out.push(v);
                i += 3;
                continue;
            }
        }
        out.push(b[i]);
        i += 1;
    }
    String::from_utf8_lossy(&out).into_owned()
}

/// `dir/../x/./y` → `x/y`, without touching the file system.
fn normalise(p: &Path) -> PathBuf {
    let mut out = PathBuf::new();
    for c in p.components() {
        match c {
            Component::ParentDir => {
                out.pop();
            }
            Component::CurDir => {}
            c => out.push(c),
        }
    }
    out
}

/// What is wrong with `target` as written in `file` (relative to the repository root), if anything.
fn check_target(root: &Path, file: &Path, target: &str) -> Option<String> {
    if target.is_empty() {
        return Some("empty link target".into());
    }
    if is_external(target) {
        return None;
    }
    if target.contains("://") || target.starts_with("//") {
        return Some("a link to another scheme or host (only http(s) links are left unchecked)".into());
    }
    let (path, anchor) = match target.split_once('#') {
        Some((p, a)) => (p, Some(a)),
        None => (target, None),
    };
    let path = percent_decode(path.split('?').next().unwrap_or_default());
    let resolved = if path.is_empty() {
        file.to_path_buf()
    } else if let Some(abs) = path.strip_prefix('/') {
        normalise(Path::new(abs))
    } else {
        normalise(&file.parent().unwrap_or(Path::new("")).join(&path))
    };
    if resolved.components().next().is_none() && !path.is_empty() {
        // the repository root itself
        return None;
    }
    let full = root.join(&resolved);
    if !full.exists() {
        return Some(format!("{} does not exist", resolved.display()));
    }
    let anchor = anchor.filter(|a| !a.is_empty())?;
    if full.is_dir() {
        return Some(format!("an anchor on a folder ({})", resolved.display()));
    }
    if resolved.extension().and_then(|e| e.to_str()) != Some("md") {
        return None; // anchors of other files (e.g. source lines) are not headings
    }
    let text = std::fs::read_to_string(&full).ok()?;
    let anchor = percent_decode(anchor);
    if anchors(&text).contains(&anchor) {
        None
    } else {
        Some(format!("no heading of {} has the anchor #{anchor}", resolved.display()))
    }
}

/// The markdown files checked, relative to the root.
fn files(root: &Path) -> Vec<PathBuf> {
    fn walk(root: &Path, dir: &Path, out: &mut Vec<PathBuf>) {
        let Ok(entries) = std::fs::read_dir(root.join(dir)) else { return };
        let mut entries: Vec<_> = entries.flatten().map(|e| e.file_name()).collect();
        entries.sort();
        for name in entries {
            let rel = dir.join(&name);
            if root.join(&rel).is_dir() {
                walk(root, &rel, out);
            } else if rel.extension().and_then(|e| e.to_str()) == Some("md") {
                out.push(rel);
            }
        }
    }
    let mut out: Vec<PathBuf> = OTHER_FILES.iter().map(PathBuf::from).filter(|p| root.join(p).is_file()).collect();
    walk(root, Path::new("docs"), &mut out);
    out
}

#[test]
fn every_link_of_the_documentation_resolves() {
    let root = root();
    let files = files(&root);
    assert!(files.iter().any(|f| f == Path::new("README.md")), "README.md not found");
    assert!(files.iter().any(|f| f.starts_with("docs/methods")), "no docs/methods/*.md found: {files:?}");
    let mut problems = Vec::new();
    let mut checked = 0;
    for file in &files {
        let text = std::fs::read_to_string(root.join(file)).unwrap_or_else(|e| panic!("{}: {e}", file.display()));
        for (line, target) in targets(&text) {
            checked += 1;
            if let Some(why) = check_target(&root, file, &target) {
                problems.push(format!("{}:{line}: ({target}) — {why}", file.display()));
            }
        }
    }
    assert!(checked > 50, "only {checked} links found in {files:?}: is the extractor broken?");
    assert!(problems.is_empty(), "{} broken link(s):\n{}", problems.len(), problems.join("\n"));
}

#[test]
fn the_readme_is_short() {
    let text = std::fs::read_to_string(root().join("README.md")).expect("README.md");
    let lines = text.lines().count();
    assert!(
        lines <= README_MAX_LINES,
        "README.md has {lines} lines; at most {README_MAX_LINES} (move detail to docs/)"
    );
}

#[test]
fn the_readme_keeps_the_two_commands() {
    // .ci/run runs "the README's test command": it must stay `make test` in the "Two commands" section
    let text = std::fs::read_to_string(root().join("README.md")).expect("README.md");
    let section = text.split("## Two commands").nth(1).expect("a \"## Two commands\" section");
    let section = section.split("\n## ").next().unwrap_or_default();
    assert!(section.lines().any(|l| l.starts_with("make demo ")), "{section}");
    assert!(section.lines().any(|l| l.starts_with("make test ")), "{section}");
}

#[test]
fn every_method_page_has_its_generated_accuracy_block() {
    let root = root();
    for page in ["sssm", "pca", "velocity", "kcs", "lma", "dtfcn", "consensus"] {
        let path = root.join(format!("docs/methods/{page}.md"));
        let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        let (a, b) = (text.find("<!-- accuracy:begin -->"), text.find("<!-- accuracy:end -->"));
        let (Some(a), Some(b)) = (a, b) else { panic!("{}: no accuracy block", path.display()) };
        let block = &text[a..b];
        assert!(block.contains(&format!("| {page} |")), "{}: no row of {page} in its block", path.display());
        assert!(block.contains("| chance |"), "{}: no chance row in its block", path.display());
    }
}

/// The scoreboard's markdown is what `docs/accuracy.json` says (issue 50): accuracy.md, the README's summary and each
/// method page's block regenerated from the saved JSON (`examples/accuracy.rs --from-json`, no evaluation) are the
/// files in the repository, byte for byte — a hand-edited figure, or a JSON regenerated without its tables, fails.
#[test]
fn the_scoreboard_tables_are_regenerated_from_accuracy_json() {
    let root = root();
    // the repository's layout (the README links into docs/ relative to itself)
    let out = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("scoreboard");
    let _ = std::fs::remove_dir_all(&out);
    std::fs::create_dir_all(out.join("docs/methods")).unwrap();
    std::fs::copy(root.join("README.md"), out.join("README.md")).unwrap();
    let pages: Vec<PathBuf> = std::fs::read_dir(root.join("docs/methods"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "md"))
        .collect();
    for p in &pages {
        std::fs::copy(p, out.join("docs/methods").join(p.file_name().unwrap())).unwrap();
    }
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    let run = std::process::Command::new(cargo)
        .current_dir(&root)
        .args(["run", "--quiet", "--example", "accuracy", "--", "--from-json", "docs/accuracy.json", "--cards", ""])
        .arg("--out")
        .arg(out.join("docs"))
        .arg("--readme")
        .arg(out.join("README.md"))
        .arg("--methods")
        .arg(out.join("docs/methods"))
        .output()
        .unwrap();
    assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
    let mut compared = vec![(root.join("docs/accuracy.md"), out.join("docs/accuracy.md"))];
    compared.push((root.join("README.md"), out.join("README.md")));
    compared.extend(pages.iter().map(|p| (p.clone(), out.join("docs/methods").join(p.file_name().unwrap()))));
    for (kept, made) in compared {
        let (a, b) = (std::fs::read_to_string(&kept).unwrap(), std::fs::read_to_string(&made).unwrap());
        if a != b {
            let line =
                a.lines().zip(b.lines()).position(|(x, y)| x != y).unwrap_or(a.lines().count().min(b.lines().count()));
            panic!(
                "{} is not what docs/accuracy.json makes (line {}): `{}` against `{}` — run `cargo run --example \
                 accuracy -- --from-json docs/accuracy.json` (or `make accuracy`)",
                kept.display(),
                line + 1,
                a.lines().nth(line).unwrap_or(""),
                b.lines().nth(line).unwrap_or("")
            );
        }
    }
}

#[test]
fn slugs_are_githubs() {
    assert_eq!(slug("Two commands"), "two-commands");
    assert_eq!(slug("Scores (`mocapseg eval`)"), "scores-mocapseg-eval");
    assert_eq!(slug("Fuzzing (`make fuzz`)"), "fuzzing-make-fuzz");
    assert_eq!(slug("Training labels (`src/labels/`)"), "training-labels-srclabels");
    assert_eq!(
        slug("A gesture-level benchmark: spliced takes (`mocapseg splice`)"),
        "a-gesture-level-benchmark-spliced-takes-mocapseg-splice"
    );
    // `&` between spaces leaves two hyphens; letters beyond ASCII stay
    assert_eq!(
        slug("KCS: kinematic centroid segmentation (Jenkins & Matarić 2003)"),
        "kcs-kinematic-centroid-segmentation-jenkins--matarić-2003"
    );
    assert_eq!(slug("snake_case and CAPS — 1×2"), "snake_case-and-caps--12");
    assert_eq!(slug("  Trailing  "), "trailing");
}

#[test]
fn headings_give_numbered_anchors() {
    let text = "# Title\n\n## Same\n\n```sh\n# not a heading\n```\n\n## Same\n\n#### [Linked](x.md) `code` ##\n\
                #hashtag is no heading\n    # indented code is no heading\n## Same\n";
    assert_eq!(anchors(text), ["title", "same", "same-1", "linked-code", "same-2"]);
    assert_eq!(heading_text("### Limits"), Some("Limits".into()));
    assert_eq!(heading_text("#nospace"), None);
    assert_eq!(heading_text("####### seven"), None);
}

#[test]
fn links_and_images_are_extracted() {
    let t = |line: &str| links_in_line(line).into_iter().map(|l| (l.image, l.target)).collect::<Vec<_>>();
    assert_eq!(
        t("see [the page](docs/page.md) and [x](#anchor)."),
        [(false, "docs/page.md".to_string()), (false, "#anchor".to_string())]
    );
    assert_eq!(t("![shot](docs/screenshots/01.jpg) caption"), [(true, "docs/screenshots/01.jpg".to_string())]);
    // a title and angle brackets are not part of the target; balanced parentheses are
    assert_eq!(
        t(r#"[a](b.md "Title") [c](<d e.md>) [f](g_(h).md)"#),
        [(false, "b.md".to_string()), (false, "d e.md".to_string()), (false, "g_(h).md".to_string())]
    );
    // code spans, escaped brackets and brackets without a target are no links
    assert_eq!(t("`[no](link.md)` \\[no](x) [just brackets] [a [nested] text](n.md)"), [(false, "n.md".to_string())]);
    assert_eq!(t("``a ` [no](x.md)`` [yes](y.md)"), [(false, "y.md".to_string())]);
    // an image inside a link: both
    assert_eq!(t("[![badge](b.svg)](target.md)"), [(false, "target.md".to_string()), (true, "b.svg".to_string())]);
    // fenced blocks and reference definitions
    let text = "a [x](one.md)\n```\n[y](in-code.md)\n```\n[ref]: ref.md \"t\"\n[^note]: no link\n";
    assert_eq!(targets(text), [(1, "one.md".to_string()), (5, "ref.md".to_string())]);
}

#[test]
fn targets_are_checked_against_files_and_headings() {
    let root = root();
    let readme = Path::new("README.md");
    let page = Path::new("docs/methods/sssm.md");
    assert_eq!(check_target(&root, readme, "https://example.org/missing"), None);
    assert_eq!(check_target(&root, readme, "docs/page.md"), None);
    assert_eq!(check_target(&root, readme, "docs/page.md#embedding"), None);
    assert_eq!(check_target(&root, page, "../benchmarks.md#sssm-in-detail"), None);
    assert_eq!(check_target(&root, page, "#neighbour-search"), None);
    assert_eq!(check_target(&root, page, "../screenshots/"), None);
    assert!(check_target(&root, readme, "docs/nope.md").is_some_and(|w| w.contains("docs/nope.md does not exist")));
    assert!(check_target(&root, readme, "docs/page.md#no-such-heading").is_some_and(|w| w.contains("#no-such-heading")));
    assert!(check_target(&root, page, "#embedding").is_some_and(|w| w.contains("docs/methods/sssm.md")));
    assert!(check_target(&root, page, "page.md").is_some_and(|w| w.contains("docs/methods/page.md")));
    assert!(check_target(&root, readme, "file:///etc/passwd").is_some());
    assert_eq!(percent_decode("a%20b.md"), "a b.md");
    assert_eq!(normalise(Path::new("docs/methods/../../README.md")), PathBuf::from("README.md"));
}
