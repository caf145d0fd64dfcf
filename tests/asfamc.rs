//! ASF + AMC (the CMU originals) through the same `Motion` as BVH: the CMU subject 02 skeleton
//! and its walk 02_01 give the same joint positions as their BVH conversion (within the BVH's
//! print precision), and bad files are refused naming file, line and column.
#![cfg(not(target_arch = "wasm32"))]

use std::path::Path;

use mocapseg::load::{load_asf_amc, load_path, MemoryBudget};

fn fixture(name: &str) -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures").join(name)
}

/// The largest difference of any coordinate of any joint in any frame.
fn largest_difference(a: &mocapseg::motion::Motion, b: &mocapseg::motion::Motion) -> f32 {
    a.positions.iter().zip(&b.positions).map(|(p, q)| (*p - *q).abs().max_element()).fold(0.0, f32::max)
}

#[test]
fn asf_amc_gives_the_positions_of_its_bvh_conversion() {
    let amc = load_path(&fixture("02_01.amc")).expect("the AMC loads with the ASF beside it");
    let bvh = load_path(&fixture("02_01.bvh")).expect("the conversion loads");
    let (a, b) = (&amc.motion, &bvh.motion);
    assert_eq!((a.frames(), a.joints()), (b.frames(), b.joints()));
    assert_eq!((a.frames(), a.joints()), (343, 38));
    assert!((a.fps - 120.0).abs() < 1e-9 && (b.fps - 120.0).abs() < 1e-2);
    assert_eq!(a.units, b.units);
    assert_eq!(a.up_axis, b.up_axis);
    // the same nodes in the same order: bones renamed by the converter, End Sites alike
    let ends = |m: &mocapseg::motion::Motion| m.skeleton.is_end_site.clone();
    assert_eq!(ends(a), ends(b));
    assert_eq!(&a.skeleton.names[..3], ["root", "lhipjoint", "lfemur"]);
    let worst = largest_difference(a, b);
    eprintln!("ASF/AMC vs BVH conversion: largest position difference {worst} units");
    // the BVH prints 4 decimals (degrees and ASF units; a body is ~ 30 units tall): 8e-5 measured
    assert!(worst < 5e-4, "largest difference {worst} units");
    assert!(a.warnings.iter().any(|w| w.contains("120 fps (the CMU rate) assumed")), "{:?}", a.warnings);
}

#[test]
fn bad_asf_and_amc_are_refused_naming_file_line_and_column() {
    // the fixtures have CRLF line ends (as CMU wrote them); LF here so the edits below match
    let asf = std::fs::read_to_string(fixture("02.asf")).unwrap().replace("\r\n", "\n");
    let amc = std::fs::read_to_string(fixture("02_01.amc")).unwrap().replace("\r\n", "\n");
    let load = |asf: &str, amc: &str| {
        load_asf_amc(("02.asf", asf.as_bytes()), ("02_01.amc", amc.as_bytes()), &MemoryBudget::default())
            .map(|_| ())
            .unwrap_err()
            .to_string()
    };
    let line_of = |text: &str, needle: &str| text.lines().position(|l| l.contains(needle)).unwrap() + 1;
    let cases = [
        // (asf, amc, expected start, expected words)
        (
            asf.replace("direction 0.34202 -0.939693 0  ", "direction 0.34202 x 0"),
            amc.clone(),
            format!("02.asf: line {}, column 24:", line_of(&asf, "direction 0.34202 -0.939693 0  ")),
            "expected a number after `direction`, found `x`",
        ),
        (
            asf.replace("    dof rx ry rz\n    limits (-160.0 20.0)", "    dof rx ry qz\n    limits (-160.0 20.0)"),
            amc.clone(),
            String::from("02.asf: line "),
            "expected rx, ry or rz after `dof`, found `qz`",
        ),
        (
            asf.replace("    lfemur ltibia\n", "    lfemur ltibia lfoot\n"),
            amc.clone(),
            String::from("02.asf: line "),
            "bone `lfoot` has two parents",
        ),
        (
            asf.replace("name lfemur", "name l{femur"),
            amc.clone(),
            String::from("02.asf: line "),
            "a bone's name cannot contain `{` or `}`",
        ),
        (
            asf.replace(":hierarchy", ":hierarchy_x"),
            amc.clone(),
            String::from("02.asf: line "),
            "no `:hierarchy` section",
        ),
        (
            asf.clone(),
            amc.replacen("lfemur ", "lfemurX ", 1),
            format!("02_01.amc: line {}, column 1:", line_of(&amc, "lfemur ")),
            "no bone `lfemurX` in the skeleton",
        ),
        (
            asf.clone(),
            amc.replacen("rwrist -16.7798", "rwrist -16.7798 3", 1),
            format!("02_01.amc: line {}, column 17:", line_of(&amc, "rwrist -16.7798")),
            "`rwrist` has 1 values in the skeleton (its `dof`), found 2",
        ),
        (
            asf.clone(),
            amc.replacen("rwrist -16.7798", "rwrist nan", 1),
            format!("02_01.amc: line {}, column 8:", line_of(&amc, "rwrist -16.7798")),
            "expected a finite number for `rwrist`, found `nan`",
        ),
        (
            asf.clone(),
            amc.replacen("rwrist -16.7798\n", "", 1),
            format!("02_01.amc: line {}, column 1:", line_of(&amc, ":DEGREES") + 1),
            "frame 1 has no line for bone `rwrist`",
        ),
        (
            asf.clone(),
            amc.split("\n1\n").next().unwrap().to_string(),
            String::from("02_01.amc: line "),
            "the file has no frames",
        ),
    ];
    for (i, (edited_asf, edited_amc, start, words)) in cases.into_iter().enumerate() {
        assert!(edited_asf != asf || edited_amc != amc, "case {i} edits nothing");
        let (asf, amc) = (edited_asf, edited_amc);
        let message = load(&asf, &amc);
        assert!(
            message.starts_with(&start) && message.contains(words),
            "expected `{start}` … `{words}`, got: {message}"
        );
    }
}

#[test]
fn an_amc_without_its_asf_or_an_asf_alone_is_explained() {
    let folder = std::env::temp_dir().join(format!("mocapseg-asfamc-{}", std::process::id()));
    std::fs::create_dir_all(&folder).unwrap();
    std::fs::copy(fixture("02_01.amc"), folder.join("02_01.amc")).unwrap();
    let e = load_path(&folder.join("02_01.amc")).unwrap_err().to_string();
    assert!(e.contains("02_01.amc") && e.contains("expected 02.asf beside it"), "{e}");
    let e = load_path(&fixture("02.asf")).unwrap_err().to_string();
    assert!(e.contains("a skeleton with no motion") && e.contains("AMC"), "{e}");
    std::fs::remove_dir_all(&folder).ok();
}

#[test]
fn a_long_amc_is_refused_within_the_budget() {
    let asf = std::fs::read(fixture("02.asf")).unwrap();
    let amc = std::fs::read(fixture("02_01.amc")).unwrap();
    let budget = MemoryBudget { max_bytes: amc.len() + 100 * 5000 };
    let e = load_asf_amc(("02.asf", &asf), ("02_01.amc", &amc), &budget).map(|_| ()).unwrap_err().to_string();
    assert!(e.starts_with("02_01.amc: line ") && e.contains("too large for the memory budget"), "{e}");
}

/// The ASF/AMC takes of the shared data (`cmu/locomotion/`) that have a BVH conversion beside them,
/// copied into `tests/fixtures/` (see its SOURCES.md) so that this runs wherever the tests run.
const TAKES: [(&str, &str, usize); 3] = [("02_01", "02.asf", 343), ("02_02", "02.asf", 298), ("35_01", "35.asf", 358)];

#[test]
fn every_asf_amc_take_matches_its_bvh_conversion() {
    for (take, asf, frames) in TAKES {
        assert!(fixture(asf).is_file(), "{asf}");
        let amc = fixture(&format!("{take}.amc"));
        let a = load_path(&amc).unwrap_or_else(|e| panic!("{e}")).motion;
        let b = load_path(&amc.with_extension("bvh")).unwrap_or_else(|e| panic!("{e}")).motion;
        assert_eq!((a.frames(), a.joints()), (b.frames(), b.joints()), "{take}");
        assert_eq!(a.frames(), frames, "{take}");
        let worst = largest_difference(&a, &b);
        eprintln!("{take}: ASF/AMC vs BVH conversion: largest position difference {worst} units");
        assert!(worst < 5e-4, "{take}: largest difference {worst} units");
    }
    // the shared data's other AMC files are gzipped (`*.amc.gz`, 0.7 to 1.2 MB packed), too large to copy: not compared
    let shared = Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/data/cmu");
    let gzipped: Vec<String> = std::fs::read_dir(&shared)
        .into_iter()
        .flatten()
        .filter_map(|e| e.ok())
        .flat_map(|folder| std::fs::read_dir(folder.path()).into_iter().flatten().filter_map(|e| e.ok()))
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".amc.gz"))
        .collect();
    if !gzipped.is_empty() {
        eprintln!("SKIPPED (gzipped, not read by the loader): {} in {}", gzipped.join(", "), shared.display());
    }
}
