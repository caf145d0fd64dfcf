//! The import rules of docs/architecture.md, read from the source tree: a rule broken anywhere in `src/` fails here,
//! naming the file and what it reaches.
//!
//! - **No method imports another**: a file under `src/methods/<m>/` reaches no `methods::<n>` for another method `n`,
//!   nor the registry (a method that knows the registry knows every method).
//! - **Everything else reaches methods only through the method interface**: outside `src/methods/`, the only paths into
//!   `methods::` are the registry's (`registry`, `find`, `shipped_cards`); what methods share lives outside every method
//!   folder (`crate::labeller`, `crate::similarity`, `crate::labels`, ...).
//! - **No import circle among the page's files** (`src/app/`).
//! - **No process-wide state in the core**: no `static` holding a lock or a lazily read value (a model cache) outside
//!   the page and the command line; the shipped models are their runner's, in its `ModelStore`.
//! - **Small units**: no function outside tests over [`MAX_FN_LINES`] lines, no file under `src/app/` over
//!   [`MAX_PAGE_FILE_LINES`].
//!
//! Each rule keeps a list of the places that broke it when the rule was written (issue 47), so that the test passes
//! while they are mended one by one: a new break fails, and so does a listed place that no longer breaks the rule (take
//! it off the list — the list only shrinks). Empty lists are the goal.
//!
//! Paths are read as the compiler resolves them: `crate::`, `super::`, `self::`, a child module declared in the file
//! (`mod loader;` then `loader::Loader`), and in the command line's files `mocapseg::` for the library. Comments and
//! string literals are blanked first, so a path written in a doc comment or a message is not an import.
#![cfg(not(target_arch = "wasm32"))]

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// The longest function allowed outside tests, in lines from `fn` to its closing brace.
const MAX_FN_LINES: usize = 120;
/// The longest file allowed under `src/app/`.
const MAX_PAGE_FILE_LINES: usize = 600;

/// Methods that reached another method when the rule was written: `file -> methods::<other>`.
const KNOWN_CROSS_METHOD: &[&str] = &[];

/// Files outside `src/methods/` that reached a method's internals when the rule was written: `file -> methods::<m>`.
const KNOWN_INTERNALS: &[&str] = &[];

/// Page files in an import circle when the rule was written (34, every page file but four, when the page's state
/// and helpers sat in `src/app/mod.rs`); none since the features' jobs left the loader (each feature's own, its
/// replies routed by run id, `loader::Jobs`) and the loader's files became layers.
const KNOWN_CIRCLE: &[&str] = &[];

/// Functions over [`MAX_FN_LINES`] when the rule was written: `file fn name`.
const KNOWN_LONG_FNS: &[&str] = &[];

/// Page files over [`MAX_PAGE_FILE_LINES`] when the rule was written (none left: each was cut by concept).
const KNOWN_LONG_PAGE_FILES: &[&str] = &[];

/// What the registry offers to the rest of the program (src/methods/mod.rs).
const REGISTRY: [&str; 3] = ["registry", "find", "shipped_cards"];

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    let mut entries: Vec<PathBuf> = std::fs::read_dir(dir).unwrap().map(|e| e.unwrap().path()).collect();
    entries.sort();
    for p in entries {
        if p.is_dir() {
            rust_files(&p, out);
        } else if p.extension().is_some_and(|e| e == "rs") {
            out.push(p);
        }
    }
}

/// A source file: where it is, the module it is (`["methods", "knn", "search"]`; the command line's files start
/// with `"<bin>"`), and its text with comments and literals blanked (newlines kept).
struct Source {
    rel: String,
    module: Vec<String>,
    clean: String,
    lines: usize,
}

fn module_of(rel: &str) -> Vec<String> {
    let rel = rel.strip_prefix("src/").unwrap().strip_suffix(".rs").unwrap();
    if let Some(bin) = rel.strip_prefix("bin/") {
        let mut m = vec!["<bin>".to_string()];
        // src/bin/mocapseg.rs is the binary's root; src/bin/mocapseg/x.rs its module x (#[path])
        m.extend(bin.split('/').skip(1).map(str::to_string));
        return m;
    }
    let mut parts: Vec<String> = rel.split('/').map(str::to_string).collect();
    if parts.last().is_some_and(|l| l == "mod" || l == "lib") {
        parts.pop();
    }
    parts
}

/// `text` with comments, string literals and char literals replaced by spaces (newlines kept).
fn blank(text: &str) -> String {
    let b: Vec<char> = text.chars().collect();
    let mut out = String::with_capacity(text.len());
    let mut i = 0;
    let keep = |c: char| if c == '\n' { '\n' } else { ' ' };
    while i < b.len() {
        let c = b[i];
        let next = b.get(i + 1).copied();
        if c == '/' && next == Some('/') {
            while i < b.len() && b[i] != '\n' {
                out.push(' ');
                i += 1;
            }
        } else if c == '/' && next == Some('*') {
            let mut depth = 0;
            while i < b.len() {
                if b[i] == '/' && b.get(i + 1) == Some(&'*') {
                    depth += 1;
                    out.push_str("  ");
                    i += 2;
                } else if b[i] == '*' && b.get(i + 1) == Some(&'/') {
                    depth -= 1;
                    out.push_str("  ");
                    i += 2;
                    if depth == 0 {
                        break;
                    }
                } else {
                    out.push(keep(b[i]));
                    i += 1;
                }
            }
        } else if c == 'r' && (next == Some('"') || next == Some('#')) && !ident_char(prev(&b, i)) {
            // raw string r"..." or r#"..."#
            let mut j = i + 1;
            let mut hashes = 0;
            while b.get(j) == Some(&'#') {
                hashes += 1;
                j += 1;
            }
            if b.get(j) != Some(&'"') {
                out.push(c);
                i += 1;
                continue;
            }
            out.push('"');
            for _ in i + 1..=j {
                out.push(' ');
            }
            i = j + 1;
            loop {
                if i >= b.len() {
                    break;
                }
                if b[i] == '"' && (0..hashes).all(|h| b.get(i + 1 + h) == Some(&'#')) {
                    out.push('"');
                    for _ in 0..hashes {
                        out.push(' ');
                    }
                    i += 1 + hashes;
                    break;
                }
                out.push(keep(b[i]));
                i += 1;
            }
        } else if c == '"' {
            out.push('"');
            i += 1;
            while i < b.len() && b[i] != '"' {
                if b[i] == '\\' {
                    out.push(' ');
                    i += 1;
                }
                if i < b.len() {
                    out.push(keep(b[i]));
                    i += 1;
                }
            }
            out.push('"');
            i += 1;
        } else if c == '\'' {
            // a char literal ('x', '\n', '\u{..}') or a lifetime ('a)
            let close = if next == Some('\\') {
                (i + 2..(i + 12).min(b.len())).find(|&j| b[j] == '\'')
            } else if b.get(i + 2) == Some(&'\'') {
                Some(i + 2)
            } else {
                None
            };
            match close {
                Some(end) => {
                    out.push('\'');
                    for _ in i + 1..end {
                        out.push(' ');
                    }
                    out.push('\'');
                    i = end + 1;
                }
                None => {
                    out.push(c);
                    i += 1;
                }
            }
        } else {
            out.push(c);
            i += 1;
        }
    }
    out
}

fn prev(b: &[char], i: usize) -> char {
    if i == 0 {
        ' '
    } else {
        b[i - 1]
    }
}

fn ident_char(c: char) -> bool {
    c.is_alphanumeric() || c == '_'
}

fn sources() -> Vec<Source> {
    let mut files = Vec::new();
    rust_files(&root().join("src"), &mut files);
    files
        .into_iter()
        .map(|p| {
            let text = std::fs::read_to_string(&p).unwrap();
            let rel = p.strip_prefix(root()).unwrap().to_string_lossy().replace('\\', "/");
            Source { module: module_of(&rel), clean: blank(&text), lines: text.lines().count(), rel }
        })
        .collect()
}

/// The identifier starting at `i` (empty when none).
fn ident_at(b: &[char], i: usize) -> String {
    b[i..].iter().take_while(|c| ident_char(**c)).collect()
}

fn skip_ws(b: &[char], mut i: usize) -> usize {
    while i < b.len() && b[i].is_whitespace() {
        i += 1;
    }
    i
}

/// The index of the bracket closing the one at `open`.
fn matching(b: &[char], open: usize) -> usize {
    let (o, c) = (
        b[open],
        match b[open] {
            '{' => '}',
            '(' => ')',
            '[' => ']',
            _ => unreachable!(),
        },
    );
    let mut depth = 0;
    for (j, ch) in b.iter().enumerate().skip(open) {
        if *ch == o {
            depth += 1;
        } else if *ch == c {
            depth -= 1;
            if depth == 0 {
                return j;
            }
        }
    }
    b.len() - 1
}

/// The paths written at `i` (after a path's first segment and its `::`): `a::b`, `a::{b, c::d}` → each in full.
fn path_tails(b: &[char], i: usize) -> Vec<Vec<String>> {
    let i = skip_ws(b, i);
    if i >= b.len() {
        return vec![vec![]];
    }
    if b[i] == '{' {
        let close = matching(b, i);
        let inner: String = b[i + 1..close].iter().collect();
        let inner: Vec<char> = inner.chars().collect();
        // split at top-level commas
        let mut out = Vec::new();
        let (mut depth, mut start) = (0, 0);
        for j in 0..=inner.len() {
            let c = inner.get(j).copied().unwrap_or(',');
            match c {
                '{' => depth += 1,
                '}' => depth -= 1,
                ',' if depth == 0 => {
                    let part: Vec<char> = inner[start..j].to_vec();
                    out.extend(path_tails(&part, 0).into_iter().filter(|p| !p.is_empty()));
                    start = j + 1;
                }
                _ => {}
            }
        }
        return out;
    }
    let name = ident_at(b, i);
    if name.is_empty() {
        return vec![vec![]];
    }
    let after = skip_ws(b, i + name.len());
    if b.get(after) == Some(&':') && b.get(after + 1) == Some(&':') {
        path_tails(b, after + 2)
            .into_iter()
            .map(|mut t| {
                t.insert(0, name.clone());
                t
            })
            .collect()
    } else {
        vec![vec![name]]
    }
}

/// What a source file is made of: the paths it reaches (resolved from the library's root; `"<bin>"` first for the
/// command line's own modules), its functions outside tests (name, lines) and the child modules it declares.
struct Read {
    paths: Vec<Vec<String>>,
    functions: Vec<(String, usize)>,
}

fn read(src: &Source) -> Read {
    let b: Vec<char> = src.clean.chars().collect();
    let in_bin = src.module.first().is_some_and(|m| m == "<bin>");
    // child modules declared as `mod x;` (files) or `mod x {` (inline), with the block of each inline one
    let mut children: BTreeSet<String> = BTreeSet::new();
    let mut inline: Vec<(usize, usize, String)> = Vec::new();
    let mut tests: Vec<(usize, usize)> = Vec::new();
    let mut functions = Vec::new();
    let mut pending_test: Option<usize> = None;
    let line_of = |pos: usize| b[..pos].iter().filter(|c| **c == '\n').count();
    let mut i = 0;
    while i < b.len() {
        if b[i] == '#' && b.get(i + 1) == Some(&'[') {
            let close = matching(&b, i + 1);
            let attr: String = b[i + 2..close].iter().filter(|c| !c.is_whitespace()).collect();
            let test = attr == "test"
                || attr.ends_with("_test")
                || (attr.starts_with("cfg(") && attr.contains("test") && !attr.contains("not(test"));
            if test {
                pending_test = Some(i);
            }
            i = close + 1;
            continue;
        }
        if pending_test.is_some() && b[i] == ';' {
            pending_test = None;
        }
        if pending_test.is_some() && b[i] == '{' {
            tests.push((i, matching(&b, i)));
            pending_test = None;
        }
        if ident_char(b[i]) && !ident_char(prev(&b, i)) {
            let word = ident_at(&b, i);
            let after = skip_ws(&b, i + word.len());
            if word == "mod" {
                let name = ident_at(&b, after);
                let end = skip_ws(&b, after + name.len());
                children.insert(name.clone());
                if b.get(end) == Some(&'{') {
                    inline.push((end, matching(&b, end), name));
                }
            } else if word == "fn" && b.get(after).is_some_and(|c| ident_char(*c)) {
                let name = ident_at(&b, after);
                // the body: the first `{` before any `;` (a declaration without body ends at `;`)
                let mut j = after + name.len();
                let mut depth = 0i32;
                while j < b.len() {
                    match b[j] {
                        '(' | '[' => depth += 1,
                        ')' | ']' => depth -= 1,
                        '{' if depth == 0 => break,
                        ';' if depth == 0 => break,
                        _ => {}
                    }
                    j += 1;
                }
                if b.get(j) == Some(&'{') {
                    let end = matching(&b, j);
                    let in_test = tests.iter().any(|(s, e)| *s <= i && i <= *e) || pending_test.is_some();
                    if !in_test {
                        functions.push((name.clone(), line_of(end) - line_of(i) + 1));
                    }
                }
            }
            i += word.len();
            continue;
        }
        i += 1;
    }
    // the module at a position: the file's module and the inline modules around it
    let module_at = |pos: usize| {
        let mut m = src.module.clone();
        for (s, e, name) in &inline {
            if *s <= pos && pos <= *e {
                m.push(name.clone());
            }
        }
        m
    };
    let mut paths = Vec::new();
    let mut i = 0;
    while i < b.len() {
        if !(ident_char(b[i]) && !ident_char(prev(&b, i)) && !(i >= 2 && b[i - 1] == ':' && b[i - 2] == ':')) {
            i += 1;
            continue;
        }
        let word = ident_at(&b, i);
        let after = skip_ws(&b, i + word.len());
        let is_path = b.get(after) == Some(&':') && b.get(after + 1) == Some(&':');
        if !is_path {
            i += word.len();
            continue;
        }
        let base: Option<Vec<String>> = match word.as_str() {
            "crate" if in_bin => Some(vec!["<bin>".to_string()]),
            "crate" => Some(vec![]),
            "mocapseg" if in_bin => Some(vec![]),
            "self" => Some(module_at(i)),
            "super" => {
                let mut m = module_at(i);
                m.pop();
                Some(m)
            }
            w if children.contains(w) => Some(module_at(i)),
            _ => None,
        };
        if let Some(mut base) = base {
            let include_word = !matches!(word.as_str(), "crate" | "mocapseg" | "self" | "super");
            if include_word {
                base.push(word.clone());
            }
            for tail in path_tails(&b, after + 2) {
                let mut full = base.clone();
                for seg in tail {
                    match seg.as_str() {
                        "super" => {
                            full.pop();
                        }
                        "self" => {}
                        _ => full.push(seg),
                    }
                }
                paths.push(full);
            }
        }
        i += word.len();
    }
    Read { paths, functions }
}

/// The methods: the folders under `src/methods/`.
fn methods() -> BTreeSet<String> {
    std::fs::read_dir(root().join("src/methods"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.is_dir())
        .map(|p| p.file_name().unwrap().to_string_lossy().to_string())
        .collect()
}

/// Compares what the rule found with its list of known places: a new place fails, and so does a listed one that
/// is gone (the list only shrinks).
fn check(rule: &str, found: BTreeSet<String>, known: &[&str]) {
    let known: BTreeSet<String> = known.iter().map(|s| s.to_string()).collect();
    let new: Vec<&String> = found.difference(&known).collect();
    let gone: Vec<&String> = known.difference(&found).collect();
    let mut msg = String::new();
    if !new.is_empty() {
        msg += &format!(
            "{rule}: broken (docs/architecture.md says why):\n  {}\n",
            new.iter().map(|s| s.as_str()).collect::<Vec<_>>().join("\n  ")
        );
    }
    if !gone.is_empty() {
        msg += &format!(
            "{rule}: these listed places keep the rule now — take them off its list in tests/architecture.rs:\n  {}\n",
            gone.iter().map(|s| s.as_str()).collect::<Vec<_>>().join("\n  ")
        );
    }
    assert!(msg.is_empty(), "{msg}");
}

#[test]
fn no_method_imports_another() {
    let methods = methods();
    let mut found = BTreeSet::new();
    for src in sources() {
        let Some(own) =
            (src.module.first().is_some_and(|m| m == "methods") && src.module.len() > 1).then(|| src.module[1].clone())
        else {
            continue;
        };
        for p in read(&src).paths {
            if p.first().is_some_and(|m| m == "methods") && p.len() > 1 && p[1] != own {
                if methods.contains(&p[1]) || REGISTRY.contains(&p[1].as_str()) {
                    found.insert(format!("{} -> methods::{}", src.rel, p[1]));
                }
            }
        }
    }
    check("no method imports another", found, KNOWN_CROSS_METHOD);
}

#[test]
fn the_rest_reaches_methods_only_through_the_registry() {
    let methods = methods();
    let mut found = BTreeSet::new();
    for src in sources() {
        if src.module.first().is_some_and(|m| m == "methods") {
            continue;
        }
        for p in read(&src).paths {
            if p.first().is_some_and(|m| m == "methods") && p.len() > 1 && methods.contains(&p[1]) {
                found.insert(format!("{} -> methods::{}", src.rel, p[1]));
            }
        }
    }
    check("only the registry outside src/methods/", found, KNOWN_INTERNALS);
}

#[test]
fn no_import_circle_among_the_page_files() {
    let page: Vec<Source> = sources().into_iter().filter(|s| s.rel.starts_with("src/app/")).collect();
    let modules: BTreeMap<Vec<String>, usize> = page.iter().enumerate().map(|(i, s)| (s.module.clone(), i)).collect();
    // edges: a file to the file whose module is the longest prefix of a path it reaches
    let mut edges: Vec<BTreeSet<usize>> = vec![BTreeSet::new(); page.len()];
    for (i, src) in page.iter().enumerate() {
        for p in read(src).paths {
            if let Some(j) = (1..=p.len()).rev().find_map(|n| modules.get(&p[..n])) {
                if *j != i {
                    edges[i].insert(*j);
                }
            }
        }
    }
    // the files that reach themselves through another file: strongly connected components of more than one file
    let reach = |from: usize| {
        let mut seen = BTreeSet::new();
        let mut stack = vec![from];
        while let Some(n) = stack.pop() {
            for &m in &edges[n] {
                if seen.insert(m) {
                    stack.push(m);
                }
            }
        }
        seen
    };
    let reaches: Vec<BTreeSet<usize>> = (0..page.len()).map(reach).collect();
    let found: BTreeSet<String> =
        (0..page.len()).filter(|&i| reaches[i].contains(&i)).map(|i| page[i].rel.clone()).collect();
    check("no import circle among the page's files", found, KNOWN_CIRCLE);
}

/// The `static` items of `clean` source whose type holds a lock or a lazily set value (a clock's start is no state
/// worth the name: `OnceLock<Instant>` passes).
fn shared_statics(clean: &str) -> Vec<String> {
    let mut found = Vec::new();
    for piece in clean.split("static ").skip(1) {
        let Some((head, _)) = piece.split_once('=') else { continue };
        let Some((name, ty)) = head.split_once(':') else { continue };
        let name = name.trim();
        if !name.chars().all(|c| c.is_ascii_uppercase() || c.is_ascii_digit() || c == '_') || name.is_empty() {
            continue;
        }
        let locked = ["Mutex", "RwLock", "LazyLock"].iter().any(|t| ty.contains(t));
        if locked || (ty.contains("OnceLock") && !ty.contains("Instant")) {
            found.push(name.to_string());
        }
    }
    found
}

#[test]
fn no_process_wide_state_in_the_core() {
    let mut found = BTreeSet::new();
    for src in sources() {
        if src.rel.starts_with("src/app/") || src.rel.starts_with("src/bin/") || src.rel == "src/worker/glue.rs" {
            continue;
        }
        for name in shared_statics(&src.clean) {
            found.insert(format!("{} static {name}", src.rel));
        }
    }
    check("no process-wide state in the core", found, &[]);
    let cache = "static LOADED: Mutex<Vec<(String, Arc<Model>)>> = Mutex::new(Vec::new());\n\
                 static START: OnceLock<Instant> = OnceLock::new();\nstatic MODEL: OnceLock<Arc<EffortModel>> = x;";
    assert_eq!(shared_statics(cache), vec!["LOADED", "MODEL"], "the rule sees a model cache, not a clock");
}

#[test]
fn functions_stay_short() {
    let mut found = BTreeSet::new();
    for src in sources() {
        for (name, lines) in read(&src).functions {
            if lines > MAX_FN_LINES {
                found.insert(format!("{} fn {name}", src.rel));
            }
        }
    }
    check(&format!("no function outside tests over {MAX_FN_LINES} lines"), found, KNOWN_LONG_FNS);
}

#[test]
fn page_files_stay_small() {
    let found: BTreeSet<String> = sources()
        .into_iter()
        .filter(|s| s.rel.starts_with("src/app/") && s.lines > MAX_PAGE_FILE_LINES)
        .map(|s| s.rel)
        .collect();
    check(&format!("no file under src/app/ over {MAX_PAGE_FILE_LINES} lines"), found, KNOWN_LONG_PAGE_FILES);
}

/// The reader itself: a path in a comment or a string is no import; groups, `super` and child modules resolve.
#[test]
fn the_reader_resolves_paths_as_the_compiler_does() {
    let src = Source {
        rel: "src/methods/knn/mod.rs".into(),
        module: module_of("src/methods/knn/mod.rs"),
        clean: blank(
            "//! see crate::methods::dtfcn\nmod search;\nuse crate::methods::{dtfcn::{input, fit}, lma};\n\
             fn f() { let s = \"crate::methods::sssm\"; let c = '{'; super::pca::x(); search::y(); }\n\
             #[cfg(test)]\nmod tests { use super::super::kcs::Z; fn long() {} }\n",
        ),
        lines: 6,
    };
    let r = read(&src);
    let joined: BTreeSet<String> = r.paths.iter().map(|p| p.join("::")).collect();
    let want: BTreeSet<String> = [
        "methods::dtfcn::input",
        "methods::dtfcn::fit",
        "methods::lma",
        "methods::pca::x",
        "methods::knn::search::y",
        "methods::kcs::Z",
    ]
    .iter()
    .map(|s| s.to_string())
    .collect();
    assert_eq!(joined, want);
    assert_eq!(r.functions, vec![("f".to_string(), 1)], "the test module's function is not counted");
    assert_eq!(module_of("src/bin/mocapseg/library_cli.rs"), vec!["<bin>", "library_cli"]);
    assert_eq!(module_of("src/app/loader/mod.rs"), vec!["app", "loader"]);
}
