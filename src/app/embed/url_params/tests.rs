//! The tests of [`super`]: the query read parameter by parameter, the full page's link, file names
//! and percent-encoding.

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
            says_what_to_show: true,
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
    UrlParams { src: Some(src.into()), asf: Some(asf.into()), says_what_to_show: true, ..UrlParams::default() }
}

#[test]
fn src_is_decoded_and_may_be_an_http_url() {
    assert_eq!(p("src=https%3A%2F%2Fa.org%2Fmy%20take.bvh").params.src.as_deref(), Some("https://a.org/my take.bvh"));
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
        assert!(parsed.messages[0].contains(word) && parsed.messages[0].contains("http(s)"), "{:?}", parsed.messages);
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
fn the_full_page_link_stays_on_the_page_s_origin() {
    let o = "http://127.0.0.1:8080";
    assert_eq!(full_page_href(o, "/", "?embed=1&src=a.bvh"), "http://127.0.0.1:8080/?src=a.bvh");
    assert_eq!(full_page_href(o, "/app/index.html", "?embed=1"), "http://127.0.0.1:8080/app/index.html");
    assert_eq!(full_page_href(o, "", ""), "http://127.0.0.1:8080/");
    // a path that would make `//host` (protocol-relative) or `/\host` (read as `//host`)
    for path in ["//evil.example/x", "///evil.example", "/\\evil.example/x", "\\\\evil.example", "/\t/evil.example"] {
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

#[test]
fn a_url_says_what_to_show_with_src_t_autoplay_or_embed_even_when_their_values_are_refused() {
    let says = |q: &str| parse(q, &["sssm"]).params.says_what_to_show;
    assert!(!says(""), "no parameter: the workspace kept comes back");
    assert!(!says("?methods=sssm&workers=2"), "which methods run and on how many workers say nothing of the take");
    for q in
        ["?src=www/a.bvh", "?src=javascript:alert(1)", "?t=soon", "?t=3", "?autoplay=maybe", "?embed=1", "?EMBED=0"]
    {
        assert!(says(q), "{q}");
    }
}
