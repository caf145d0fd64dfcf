//! The loader's memory budget, measured: a counting allocator records the peak bytes allocated
//! while a take is loaded, so "processed within the budget or refused before passing it" is
//! checked against what was really allocated, not against the loader's own estimate.
#![cfg(not(target_arch = "wasm32"))]

use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;

use mocapseg::load::{load_bytes_with_budget, MemoryBudget};

/// The system allocator, counting the bytes currently allocated and their peak.
struct Counting;

static CURRENT: AtomicUsize = AtomicUsize::new(0);
static PEAK: AtomicUsize = AtomicUsize::new(0);
/// The tests measure one at a time (the counters are global).
static MEASURING: Mutex<()> = Mutex::new(());

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        let p = unsafe { System.alloc(layout) };
        if !p.is_null() {
            let now = CURRENT.fetch_add(layout.size(), Ordering::Relaxed) + layout.size();
            PEAK.fetch_max(now, Ordering::Relaxed);
        }
        p
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) };
        CURRENT.fetch_sub(layout.size(), Ordering::Relaxed);
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        let p = unsafe { System.realloc(ptr, layout, new_size) };
        if !p.is_null() {
            if new_size >= layout.size() {
                let now = CURRENT.fetch_add(new_size - layout.size(), Ordering::Relaxed) + new_size - layout.size();
                PEAK.fetch_max(now, Ordering::Relaxed);
            } else {
                CURRENT.fetch_sub(layout.size() - new_size, Ordering::Relaxed);
            }
        }
        p
    }
}

#[global_allocator]
static ALLOCATOR: Counting = Counting;

/// Runs `f` and returns its result and the peak bytes allocated above what was allocated before.
fn peak_during<T>(f: impl FnOnce() -> T) -> (T, usize) {
    let base = CURRENT.load(Ordering::Relaxed);
    PEAK.store(base, Ordering::Relaxed);
    let out = f();
    (out, PEAK.load(Ordering::Relaxed) - base)
}

/// Prints what `what` allocated at its peak beside what it declared, and fails if the peak passed it.
fn assert_within(what: &str, peak: usize, declared: usize) {
    let mib = |b: usize| b as f64 / 1048576.0;
    println!("{what}: peak {:6.1} MiB, declared {:6.1} MiB", mib(peak), mib(declared));
    assert!(peak <= declared, "{what}: took {peak} bytes, more than the {declared} declared");
}

/// The hierarchy of the CMU fixture 12_01 (31 joints, 62 channels) with `frames` rows of zeros
/// and small angles.
fn cmu_take(frames: usize) -> String {
    let text = include_str!("fixtures/12_01.bvh");
    let head = &text[..text.find("MOTION").unwrap()];
    let channels: usize =
        head.lines().filter_map(|l| l.trim().strip_prefix("CHANNELS ")).map(|c| c[..1].parse::<usize>().unwrap()).sum();
    let row = format!("{}\n", vec!["1.5"; channels].join(" "));
    let mut out = String::with_capacity(head.len() + 64 + row.len() * frames);
    out += head;
    out += &format!("MOTION\nFrames: {frames}\nFrame Time: 0.008333\n");
    for _ in 0..frames {
        out += &row;
    }
    out
}

#[test]
fn a_million_frames_load_within_the_budget() {
    let _one = MEASURING.lock().unwrap();
    // one joint with three rotations and an End Site: a million frames, 10 MB of text
    let mut text = String::from("HIERARCHY\nROOT Hips\n{\nOFFSET 0 0 0\nCHANNELS 3 Zrotation Xrotation Yrotation\n");
    text += "End Site\n{\nOFFSET 0 10 0\n}\n}\nMOTION\nFrames: 1000000\nFrame Time: 0.008333\n";
    for i in 0..1_000_000u32 {
        text += &format!("{} 0 0\n", i % 90);
    }
    let budget = MemoryBudget::default();
    let (loaded, peak) = peak_during(|| load_bytes_with_budget("million.bvh", text.as_bytes(), &budget, &mut |_| {}));
    let loaded = loaded.expect("a million frames of a small skeleton fit the budget");
    assert_eq!(loaded.motion.frames(), 1_000_000);
    // what the budget counts for it (values and the per-frame estimate) bounds what was allocated
    let counted = 1_000_000 * (3 * 8 + MemoryBudget::estimate(1, 2));
    assert!(peak <= counted, "peak {peak} bytes > the {counted} the budget counts");
    assert!(peak + text.len() <= budget.max_bytes, "peak {peak} bytes + text {} > budget", text.len());
}

#[test]
fn a_take_past_the_budget_is_refused_before_allocating_past_it() {
    let _one = MEASURING.lock().unwrap();
    // 20 000 frames of the CMU skeleton (13 MB of text) against a 32 MiB budget: about 8000
    // frames fit; the parser must stop at the first row past them, having allocated less than
    // the budget (the text is the caller's and counts against the budget too).
    let text = cmu_take(20_000);
    let budget = MemoryBudget { max_bytes: 32 << 20 };
    let (result, peak) = peak_during(|| load_bytes_with_budget("long.bvh", text.as_bytes(), &budget, &mut |_| {}));
    let message = result.expect_err("over the budget").to_string();
    assert!(message.starts_with("long.bvh: line "), "{message}");
    assert!(message.contains("the take is too large for the memory budget of 32 MiB"), "{message}");
    let fits: usize = message.split("at most ").nth(1).and_then(|s| s.split(' ').next()).unwrap().parse().unwrap();
    assert!((1000..20_000).contains(&fits), "{message}");
    // the row named is the first past the budget: the header's lines, then `fits` rows
    let line: usize = message["long.bvh: line ".len()..].split(',').next().unwrap().parse().unwrap();
    let first_row = text.lines().position(|l| l.starts_with("Frame Time")).unwrap() + 2;
    assert_eq!(line, first_row + fits, "{message}");
    assert!(peak + text.len() <= budget.max_bytes, "peak {peak} bytes + text {} > budget", text.len());
    // and the same take within a budget it fits loads, within that budget
    let roomy = MemoryBudget { max_bytes: 128 << 20 };
    let (loaded, peak) = peak_during(|| load_bytes_with_budget("long.bvh", text.as_bytes(), &roomy, &mut |_| {}));
    assert_eq!(loaded.expect("fits").motion.frames(), 20_000);
    assert!(peak + text.len() <= roomy.max_bytes, "peak {peak} bytes + text {} > budget", text.len());
}

/// CMU 13_31 (mocap6, 120 Hz) concatenated to `frames` frames at `fps` (30: resampled first).
fn working_take(frames: usize, fps: f64) -> mocapseg::motion::Motion {
    let loaded = mocapseg::load::load_bytes("13_31.bvh", include_bytes!("fixtures/13_31.bvh"), &mut |_| {}).unwrap();
    let base = if fps == 120.0 { loaded.motion } else { loaded.motion.resample(fps).unwrap() };
    mocapseg::motion::Motion::concatenate(std::slice::from_ref(&base), frames).unwrap()
}

/// Every method's own arrays, measured: the peak allocated during a run stays within the
/// [`mocapseg::method::Work`] it declares (which the run is checked against before it starts),
/// on takes of two lengths (so a per-frame figure too low for longer takes fails) at its working
/// rate and at 4× it (the resampled copy counts too). The repeated take is SSSM's worst case: every
/// frame has neighbours in every repetition.
#[test]
fn every_method_stays_within_the_work_it_declares() {
    use mocapseg::method::{NoProgress, RunOptions};
    let _one = MEASURING.lock().unwrap();
    for m in mocapseg::methods::registry() {
        let name = m.info().name;
        let mut variants = vec![serde_json::json!({})];
        if name == "lma" {
            variants.push(serde_json::json!({"exhaustive": true}));
        }
        // LMA (its exhaustive search above all) is the slow one in the tests' build: shorter takes
        let lengths: &[usize] = if name == "lma" { &[600, 1800] } else { &[1500, 6000] };
        for params in &variants {
            let checked = m.check_json(params).unwrap();
            let work = m.work(&checked).unwrap();
            // the SSSM declares its arrays, not its neighbour entries: it counts those as it finds
            // them against what the budget leaves (`sssm_entries_stay_within_the_run_budget`); here
            // it runs with room for them beside what it declares
            let entries_room = if name == "sssm" { 256 << 20 } else { 0 };
            for (k, &frames) in lengths.iter().enumerate() {
                // the resampled copy counted once, on the shorter take
                let rates: &[f64] = if k == 0 { &[30.0, 120.0] } else { &[30.0] };
                for &fps in rates {
                    let take = working_take(if fps == 120.0 { 4 * frames } else { frames }, fps);
                    let working = work.frames(&take);
                    assert!(working.abs_diff(frames) <= 1, "{name}: {working} working frames of {frames}");
                    let declared = work.bytes(working, take.joints()) + entries_room;
                    let limits = mocapseg::method::WorkLimits { max_bytes: declared, ..Default::default() };
                    let (out, peak) = peak_during(|| {
                        m.run_checked(&take, &checked, &RunOptions { pictures: true, limits }, &mut NoProgress)
                    });
                    out.unwrap_or_else(|e| panic!("{name} {params} on {frames} frames at {fps} Hz: {e}"));
                    println!(
                        "{name:8} {params} {frames:5} frames from {fps:3} Hz: peak {:6.1} MiB ({:5.0} B/frame), \
                         declared {:6.1} MiB",
                        peak as f64 / 1048576.0,
                        peak as f64 / frames as f64,
                        declared as f64 / 1048576.0
                    );
                    assert!(
                        peak <= declared,
                        "{name} {params}: {frames} frames from {fps} Hz took {peak} bytes at the peak, more than the \
                         {declared} its Work declares"
                    );
                }
            }
        }
    }
}

/// The SSSM's neighbour entries are counted as its searches find them, against what the run's
/// budget leaves after the arrays it declares ([`mocapseg::methods::sssm::BYTES_PER_ENTRY`] each):
/// on the takes with the most neighbours — a repeated take (every frame near its repetitions) and a
/// still one (every frame near every other) — and budgets from a few MiB to hundreds, the peak
/// allocated stays within the budget whether the run finishes or is refused, the small budgets
/// refuse (naming the budget and max_neighbours) and the large ones finish.
#[test]
fn sssm_entries_stay_within_the_run_budget() {
    use mocapseg::method::{NoProgress, RunOptions, WorkLimits};
    let _one = MEASURING.lock().unwrap();
    let m = mocapseg::methods::registry().into_iter().find(|m| m.info().name == "sssm").unwrap();
    let checked = m.check_json(&serde_json::json!({})).unwrap();
    let work = m.work(&checked).unwrap();
    let repeated = working_take(6000, 30.0);
    let still = {
        let one = mocapseg::motion::Motion::concatenate(&[repeated.clone()], 1).unwrap();
        mocapseg::motion::Motion::concatenate(&[one], 6000).unwrap()
    };
    for (what, take) in [("repeated", &repeated), ("still", &still)] {
        let declared = work.bytes(work.frames(take), take.joints());
        let (mut refused, mut finished) = (0, 0);
        for room_mib in [4usize, 16, 64, 256, 512, 1024] {
            let limits = WorkLimits { max_bytes: declared + (room_mib << 20), ..Default::default() };
            let (out, peak) =
                peak_during(|| m.run_checked(take, &checked, &RunOptions { pictures: true, limits }, &mut NoProgress));
            println!(
                "sssm {what}: room {room_mib:3} MiB → {}, peak {:.1} MiB of {:.1}",
                if out.is_ok() { "finished" } else { "refused" },
                peak as f64 / 1048576.0,
                limits.max_bytes as f64 / 1048576.0
            );
            assert!(peak <= limits.max_bytes, "{what}, room {room_mib} MiB: peak {peak} > {}", limits.max_bytes);
            match out {
                Ok(_) => finished += 1,
                Err(e) => {
                    let e = e.to_string();
                    assert!(e.contains("needs more memory than the budget") && e.contains("max_neighbours"), "{e}");
                    refused += 1;
                }
            }
        }
        assert!(refused > 0 && finished > 0, "{what}: {refused} refused, {finished} finished");
    }
}

/// A CMU take's first `frames` rows with its Frame Time replaced.
fn with_frame_time(frames: usize, frame_time: &str) -> String {
    let text = include_str!("fixtures/35_01.bvh");
    let (head, motion) = text.split_at(text.find("MOTION").unwrap());
    let rows: Vec<&str> = motion.lines().skip(3).take(frames).collect();
    format!("{head}MOTION\nFrames: {}\nFrame Time: {frame_time}\n{}\n", rows.len(), rows.join("\n"))
}

/// The file (200 frames with `Frame Time: 100`, 5.5 hours long: 597,000 frames at 30 Hz,
/// which ran past 300 s and 2.5 GB in LMA) and its siblings: every method refuses the ones below
/// 1 Hz at once, naming the Frame Time, before allocating their working take; at 1 Hz (a
/// minute of motion) every method finishes within what it declares.
#[test]
fn slow_frame_times_are_refused_or_run_within_the_budget() {
    use mocapseg::method::{NoProgress, RunOptions};
    let _one = MEASURING.lock().unwrap();
    for (frame_time, refused) in [("100", true), ("10", true), ("1.5", true), ("1", false), ("0.5", false)] {
        let text = with_frame_time(if refused { 200 } else { 61 }, frame_time);
        let file = format!("ft{frame_time}.bvh");
        let motion = mocapseg::load::load_bytes(&file, text.as_bytes(), &mut |_| {}).unwrap().motion;
        for m in mocapseg::methods::registry() {
            let name = m.info().name;
            let checked = m.check_json(&serde_json::json!({})).unwrap();
            let work = m.work(&checked).unwrap();
            // the SSSM's entries beside what it declares, as in `every_method_stays_within_the_work_it_declares`
            let entries_room = if name == "sssm" { 256 << 20 } else { 0 };
            let declared = work.bytes(work.frames(&motion), motion.joints()) + entries_room;
            let limits = mocapseg::method::WorkLimits { max_bytes: declared, ..Default::default() };
            let (out, peak) = peak_during(|| {
                m.run_checked(&motion, &checked, &RunOptions { pictures: true, limits }, &mut NoProgress)
            });
            if refused {
                let message = out.err().unwrap_or_else(|| panic!("{name} ran on {file}")).to_string();
                assert!(
                    message.starts_with(&format!("Frame Time {frame_time} s is ")) && message.contains("1 Hz or more"),
                    "{name}: {message}"
                );
                assert!(peak < 1 << 20, "{name} allocated {peak} bytes before refusing {file}");
            } else {
                let out = out.unwrap_or_else(|e| panic!("{name} on {file}: {e}"));
                assert_eq!(out.segmentation.frames, 61, "{name}");
                assert!(peak <= declared, "{name}: {peak} bytes on {file}, more than {declared}");
            }
        }
    }
}

/// `shipped` (a shipped model file) made into another model of the same kind, called `name`: `edit` changes its
/// header and labeller. The payload and its hash are written anew, so the file is as valid as one a user trained.
fn edited_model(
    shipped: &str,
    name: &str,
    edit: impl FnOnce(&mut mocapseg::labeller::model::Model),
) -> mocapseg::method::supervised::Loaded {
    use mocapseg::labeller::model::Model;
    let bytes = mocapseg::method::ModelStore::default().shipped_bytes(shipped).unwrap();
    let mut model = Model::from_bytes(&bytes, shipped, &mocapseg::methods::LABELLERS).unwrap();
    model.header.name = name.to_string();
    edit(&mut model);
    let bytes = model.to_bytes().unwrap();
    let method = mocapseg::methods::find(&model.header.kind).unwrap();
    method.supervised().unwrap().read_model(&format!("{name}.model"), &bytes).unwrap()
}

/// The labellers' work is computed from their model, not assumed from the shipped ones: models a user could make —
/// a k-NN of 250 classes (seven taught, the rest never voted for) decoded with the longest minimum run a run accepts,
/// a wide DT-FCN of four layers whose dilations give it a 2.4 k-frame receptive field, an ensemble of three such
/// networks — each run on two lengths within what its Work declares, the declared bytes growing with the classes,
/// the network and the members, and each refused before it starts under a budget below its declaration.
#[test]
fn labellers_stay_within_the_work_their_model_declares() {
    use mocapseg::labeller::model::Json;
    use mocapseg::method::{NoProgress, RunOptions, WorkLimits};
    use mocapseg::methods::dtfcn::model::Networks;
    use mocapseg::methods::dtfcn::network::DtFcnConfig;
    let _one = MEASURING.lock().unwrap();
    let classes: Vec<String> = (0..250).map(|i| format!("class{i}")).collect();
    let colours: Vec<String> = (0..250).map(|i| format!("#{:06x}", i * 0x10101)).collect();
    let wide = |members: usize| {
        move |model: &mut mocapseg::labeller::model::Model| {
            let shipped: DtFcnConfig = model.header.network.as_ref().unwrap().read().unwrap();
            let config = DtFcnConfig { width: 7, filters: vec![64, 128, 128, 256], ..shipped };
            let device = mocapseg::methods::dtfcn::device();
            let nets = (0..members as u64).map(|s| config.init_seeded(&device, s)).collect();
            model.header.network = Some(Json::of(&config).unwrap());
            model.labeller = Box::new(Networks { config, nets });
        }
    };
    let cases: Vec<(&str, &str, _, serde_json::Value)> = vec![
        (
            "knn",
            "knn-exercises.model",
            edited_model("knn-exercises.model", "many", |m| {
                m.header.classes = classes.clone();
                m.header.colours = colours.clone();
            }),
            serde_json::json!({"model": "many", "decoding": "custom", "min_duration_s": 30.0, "fit_check": false}),
        ),
        // the open-set unknown in force (issue 50): each frame's window searched again among its class's
        (
            "knn",
            "knn-exercises.model",
            edited_model("knn-exercises.model", "open", |m| {
                m.header.classes = classes.clone();
                m.header.colours = colours.clone();
                m.header.open_set = Some(mocapseg::labeller::openset::OpenSetUnknown {
                    ratio: 1.5,
                    folds: 1,
                    accuracy: 0.8,
                    never: 0.7,
                });
            }),
            serde_json::json!({"model": "open", "fit_check": false}),
        ),
        (
            "dtfcn",
            "dtfcn-exercises.model",
            edited_model("dtfcn-exercises.model", "wide", wide(1)),
            serde_json::json!({"model": "wide", "decoding": "raw"}),
        ),
        (
            "dtfcn",
            "dtfcn-exercises.model",
            edited_model("dtfcn-exercises.model", "wide3", wide(3)),
            serde_json::json!({"model": "wide3", "decoding": "raw"}),
        ),
    ];
    for (method, shipped, loaded, params) in cases {
        let m = mocapseg::methods::find(method).unwrap();
        let mut store = mocapseg::method::ModelStore::new();
        store.install(loaded);
        let checked = m.check_json_in(&params, &store).unwrap_or_else(|e| panic!("{method} {params}: {e}"));
        let work = m.work(&checked).unwrap();
        let shipped_work = m.work(&m.check_json(&serde_json::json!({"decoding": "raw"})).unwrap()).unwrap();
        assert!(
            work.bytes(6000, 31) > shipped_work.bytes(6000, 31),
            "{method} {params}: declares no more than the shipped {shipped} ({} bytes)",
            work.bytes(6000, 31)
        );
        for frames in [1500, 6000] {
            let take = working_take(frames, 30.0);
            let declared = work.bytes(work.frames(&take), take.joints());
            let limits = WorkLimits { max_bytes: declared, ..Default::default() };
            let (out, peak) =
                peak_during(|| m.run_checked(&take, &checked, &RunOptions { pictures: true, limits }, &mut NoProgress));
            out.unwrap_or_else(|e| panic!("{method} {params} on {frames} frames: {e}"));
            assert_within(&format!("{method:6} {params} {frames:5} frames"), peak, declared);
            // below its declaration the run is refused before it starts, naming the budget
            let tight = WorkLimits { max_bytes: declared - 1, ..Default::default() };
            let (out, peak) = peak_during(|| {
                m.run_checked(&take, &checked, &RunOptions { pictures: true, limits: tight }, &mut NoProgress)
            });
            let message = out.err().unwrap_or_else(|| panic!("{method} {params} ran past its budget")).to_string();
            assert!(message.contains("more than the budget"), "{method}: {message}");
            assert!(peak < 1 << 20, "{method} allocated {peak} bytes before refusing");
        }
    }
}

/// The Effort layer (LMA's annotation of any segmentation: the page's Effort bars, `mocapseg effort`) passes the same
/// gate as a run: on a long take with one segment over all of it, what it declares ([`Method::annotation_work`],
/// which grows with the longest segment) bounds what it allocates, and under a budget below that it is refused before
/// it starts; the issue's `Frame Time: 100` take is refused at once, naming its Frame Time.
#[test]
fn effort_annotations_stay_within_the_work_they_declare() {
    use mocapseg::method::{NoProgress, WorkLimits};
    use mocapseg::segment::{Level, Segment};
    let _one = MEASURING.lock().unwrap();
    let lma = mocapseg::methods::find("lma").unwrap();
    let checked = lma.check_json(&serde_json::json!({})).unwrap();
    let segment = |start: usize, end: usize| Segment {
        start,
        end,
        label: String::new(),
        level: Level::Action,
        cluster: None,
        score: None,
        mirror_of: None,
        effort: None,
    };
    let take = working_take(1800, 30.0);
    let last = take.frames() - 1;
    let mut declared_short = 0;
    for (what, segments) in [
        ("short segments", vec![segment(0, 59), segment(60, 119)]),
        ("one segment over the take", vec![segment(0, last)]),
    ] {
        // what it declares, as the gate computes it; it runs within that and is refused below it
        let work = lma.annotation_work(&checked, &take, &segments).unwrap();
        let fits = work.bytes(work.frames(&take), take.joints());
        let (out, peak) = peak_during(|| {
            lma.annotate_checked(
                &take,
                &checked,
                &segments,
                &WorkLimits { max_bytes: fits, ..Default::default() },
                &mut NoProgress,
            )
        });
        let annotations = out.unwrap();
        assert_eq!(annotations.segments.len(), segments.len());
        println!(
            "effort, {what}: peak {:.1} MiB, declared {:.1} MiB",
            peak as f64 / 1048576.0,
            fits as f64 / 1048576.0
        );
        assert!(peak <= fits, "{what}: {peak} bytes, more than the {fits} it passed with");
        // below what it declares it is refused before allocating
        let (out, peak) = peak_during(|| {
            lma.annotate_checked(
                &take,
                &checked,
                &segments,
                &WorkLimits { max_bytes: fits - 1, ..Default::default() },
                &mut NoProgress,
            )
        });
        let message = out.err().unwrap().to_string();
        assert!(
            message.contains("more than the budget") && message.contains("or annotate shorter segments"),
            "{what}: {message}"
        );
        assert!(peak < 1 << 20, "{what}: {peak} bytes allocated before refusing");
        if declared_short == 0 {
            declared_short = fits;
        } else {
            assert!(
                fits > declared_short,
                "one long segment declares more than short ones ({fits} against {declared_short})"
            );
        }
    }
    let text = with_frame_time(200, "100");
    let motion = mocapseg::load::load_bytes("ft100.bvh", text.as_bytes(), &mut |_| {}).unwrap().motion;
    let (out, peak) = peak_during(|| {
        lma.annotate_checked(&motion, &checked, &[segment(0, 199)], &WorkLimits::default(), &mut NoProgress)
    });
    let message = out.err().unwrap().to_string();
    assert!(message.starts_with("Frame Time 100 s is ") && message.contains("1 Hz or more"), "{message}");
    assert!(peak < 1 << 20, "{peak} bytes allocated before refusing the Frame Time");
}

/// CMU 13_31 (mocap6) as a BVH file of `frames` rows, its frames repeated, at `frame_time` seconds a frame.
fn repeated_13_31(frames: usize, frame_time: &str) -> Vec<u8> {
    let text = include_str!("fixtures/13_31.bvh");
    let at = text.find("MOTION").unwrap();
    let rows: Vec<&str> = text[at..].lines().skip(3).filter(|l| !l.trim().is_empty()).collect();
    let mut out = String::from(&text[..at]);
    out += &format!("MOTION\nFrames: {frames}\nFrame Time: {frame_time}\n");
    for i in 0..frames {
        out += rows[i % rows.len()];
        out.push('\n');
    }
    out.into_bytes()
}

/// Every training (the k-NN's fit, DT-FCN's epochs, LMA's family) holds every take's file, motion and its own arrays
/// at once: what it allocates stays within what its method declares for training
/// ([`mocapseg::method::Supervised::training_work`], summed by [`mocapseg::method::work::TrainingHold`] as the takes are
/// read), on takes of two lengths and two file rates, DT-FCN with a small, the default and a wide network; and under
/// a budget below that the training is refused after reading the take, before it builds its arrays, naming the budget.
#[test]
fn trainings_stay_within_the_work_they_declare() {
    use mocapseg::method::supervised::TrainingAsk;
    use mocapseg::method::work::TrainingHold;
    use mocapseg::method::{NoProgress, WorkLimits};
    let _one = MEASURING.lock().unwrap();
    let lma = serde_json::json!({"restarts": 1, "max_epochs": 2, "shift_epochs": 1, "shift_restarts": 1, "saliency_rounds": 1});
    let cases = [
        ("knn", serde_json::json!({})),
        // the windows and inputs the scoreboard's nested folds choose among (its training table's rows)
        ("knn", serde_json::json!({"half_window_s": 0.5, "k": 9})),
        ("knn", serde_json::json!({"half_window_s": 2})),
        ("knn", serde_json::json!({"input": "network"})),
        ("dtfcn", serde_json::json!({"epochs": 1, "filters": [16, 16, 16, 16]})),
        ("dtfcn", serde_json::json!({"epochs": 1})),
        ("dtfcn", serde_json::json!({"epochs": 1, "filters": [64, 64, 128, 256, 512], "batch": 8, "crop_frames": 256})),
        ("lma", lma),
    ];
    for (method, options) in cases {
        let m = mocapseg::methods::find(method).unwrap();
        let s = m.supervised().unwrap();
        let work = s.training_work(&options).unwrap();
        for (frames, frame_time) in [(6_000usize, "0.033333"), (24_000, "0.033333"), (24_000, "0.008333")] {
            let half = frames / 2;
            let bytes = repeated_13_31(frames, frame_time);
            let ask = |limits| TrainingAsk {
                name: "measured".into(),
                // LMA learns from its stand-in labels (descriptor terciles) without a label file
                labels_name: if method == "lma" { String::new() } else { "l.csv".into() },
                labels: if method == "lma" {
                    String::new()
                } else {
                    format!(
                        "file,start_frame,end_frame,label\nlong.bvh,0,{},still\nlong.bvh,{half},{},moving\n",
                        half - 1,
                        frames - 1
                    )
                },
                takes: vec![("long.bvh".into(), bytes.clone())],
                options: options.clone(),
                to_file: true,
                limits,
                ..TrainingAsk::default()
            };
            let take = mocapseg::load::load_bytes("long.bvh", &bytes, &mut |_| {}).unwrap().motion;
            let mut hold = TrainingHold::new(method, work, WorkLimits { max_bytes: usize::MAX, ..Default::default() });
            hold.add(&take, bytes.len()).unwrap();
            let declared = hold.bytes();
            let train = |ask: TrainingAsk| -> Result<(), String> {
                let mut t = s.start_training(ask, &mut NoProgress).map_err(|e| e.to_string())?;
                while !t.done() {
                    t.step(&mut NoProgress).map_err(|e| e.to_string())?;
                }
                t.finish().map(|_| ()).map_err(|e| e.to_string())
            };
            // the ask (its copy of the file) made before measuring: the file is the caller's
            let within = ask(WorkLimits { max_bytes: declared, ..Default::default() });
            let (out, peak) = peak_during(|| train(within));
            out.unwrap_or_else(|e| panic!("{method} {options} on {frames} frames: {e}"));
            assert_within(
                &format!("training {method:5} {options} on {frames:5} frames at {frame_time} s"),
                peak,
                declared,
            );
            // below its declaration it is refused once the take is read, before its arrays, naming the budget
            let tight = ask(WorkLimits { max_bytes: declared - 1, ..Default::default() });
            let (out, peak) = peak_during(|| train(tight));
            let message = out.err().unwrap_or_else(|| panic!("{method} trained past its budget"));
            assert!(
                message.contains("more than the budget of") && message.contains("train on at most"),
                "{method}: {message}"
            );
            let (_, read) =
                peak_during(|| mocapseg::load::load_bytes("long.bvh", &bytes, &mut |_| {}).map(|l| l.motion));
            assert!(
                peak <= read + (1 << 20),
                "{method} allocated {peak} bytes before refusing, more than reading the take ({read}) and 1 MiB"
            );
        }
    }
}

/// A k-NN training on two takes also chooses its open-set unknown on folds that leave a class out (issue 50): each
/// fold fits a k-NN of its own while the model is held. What it allocates stays within the training work it declares
/// for both takes.
#[test]
fn a_knn_trainings_open_set_folds_stay_within_its_work() {
    use mocapseg::method::supervised::TrainingAsk;
    use mocapseg::method::work::TrainingHold;
    use mocapseg::method::{NoProgress, WorkLimits};
    let _one = MEASURING.lock().unwrap();
    let s = mocapseg::methods::find("knn").unwrap().supervised().unwrap();
    let options = serde_json::json!({});
    let work = s.training_work(&options).unwrap();
    let frames = 12_000usize;
    let bytes = repeated_13_31(frames, "0.033333");
    let (third, two_thirds) = (frames / 3, 2 * frames / 3);
    // a: still, moving; b: moving, still, turning — every class held by a take while the other has other labels
    let labels = format!(
        "file,start_frame,end_frame,label\na.bvh,0,{},still\na.bvh,{third},{},moving\nb.bvh,0,{},moving\n\
         b.bvh,{third},{},still\nb.bvh,{two_thirds},{},turning\n",
        third - 1,
        frames - 1,
        third - 1,
        two_thirds - 1,
        frames - 1
    );
    let take = mocapseg::load::load_bytes("a.bvh", &bytes, &mut |_| {}).unwrap().motion;
    let mut hold = TrainingHold::new("knn", work, WorkLimits { max_bytes: usize::MAX, ..Default::default() });
    hold.add(&take, bytes.len()).unwrap();
    hold.add(&take, bytes.len()).unwrap();
    let declared = hold.bytes();
    let ask = TrainingAsk {
        name: "measured".into(),
        labels_name: "l.csv".into(),
        labels,
        takes: vec![("a.bvh".into(), bytes.clone()), ("b.bvh".into(), bytes.clone())],
        options,
        to_file: true,
        limits: WorkLimits { max_bytes: declared, ..Default::default() },
        ..TrainingAsk::default()
    };
    let (out, peak) = peak_during(|| -> Result<String, String> {
        let mut t = s.start_training(ask, &mut NoProgress).map_err(|e| e.to_string())?;
        while !t.done() {
            t.step(&mut NoProgress).map_err(|e| e.to_string())?;
        }
        t.finish().map(|t| t.report.summary).map_err(|e| e.to_string())
    });
    let summary = out.unwrap();
    assert!(summary.contains("Open-set unknown chosen on 5 folds"), "{summary}");
    assert_within("training knn on two takes of 12000 frames, its open-set folds too", peak, declared);
}

#[path = "support/hostile.rs"]
mod hostile;

/// A k-NN file asking for the widest window (±300 frames, every frame: 30,651 values a window, 46× the shipped one's)
/// declares that in its run's time — the window projected onto 32 axes and its training windows scanned, every
/// working frame —, runs on a take within what it declares (bytes measured), and is refused before it starts past
/// either budget: below its declared multiply-adds on that take, and under the default budget on a take long enough
/// (1.9 h at 1 Hz), naming the multiply-adds and the duration that fits. The shipped model declares far less.
#[test]
fn a_wide_window_knn_declares_its_time_and_is_refused_past_it() {
    use mocapseg::method::{NoProgress, RunOptions, WorkLimits};
    let _one = MEASURING.lock().unwrap();
    let m = mocapseg::methods::find("knn").unwrap();
    let mut store = mocapseg::method::ModelStore::new();
    store.install(m.supervised().unwrap().read_model("wide.model", &hostile::wide_knn_file("wide", 2000)).unwrap());
    let params = serde_json::json!({"model": "wide", "fit_check": false});
    let checked = m.check_json_in(&params, &store).unwrap();
    let work = m.work(&checked).unwrap();
    let shipped = m.work(&m.check_json(&serde_json::json!({"fit_check": false})).unwrap()).unwrap();
    let window = (601 * 51 * 32) as f64;
    assert!(work.ops_per_frame >= window + (2000 * 32) as f64, "declares {} a frame", work.ops_per_frame);
    assert!(shipped.ops_per_frame < window / 4.0, "the shipped k-NN declares {} a frame", shipped.ops_per_frame);
    let take = working_take(600, 30.0);
    let frames = work.frames(&take);
    let (bytes, ops) = (work.bytes(frames, take.joints()), work.ops(frames));
    let fits = WorkLimits { max_bytes: bytes, max_ops: ops, ..Default::default() };
    let started = std::time::Instant::now();
    let (out, peak) =
        peak_during(|| m.run_checked(&take, &checked, &RunOptions { pictures: true, limits: fits }, &mut NoProgress));
    out.unwrap_or_else(|e| panic!("the wide k-NN on {frames} frames: {e}"));
    assert_within("knn, a ±300-frame window, 600 frames", peak, bytes);
    eprintln!(
        "wide k-NN, {frames} frames: {:.0} ms for {ops:.3e} declared multiply-adds",
        started.elapsed().as_secs_f64() * 1e3
    );
    let tight = WorkLimits { max_ops: ops - 1.0, ..fits };
    let (out, peak) =
        peak_during(|| m.run_checked(&take, &checked, &RunOptions { pictures: true, limits: tight }, &mut NoProgress));
    let message = out.err().expect("refused below its declared multiply-adds").to_string();
    assert!(message.contains("multiply-adds") && message.contains("more than the budget"), "{message}");
    assert!(peak < 1 << 20, "allocated {peak} bytes before refusing");
    // under the default budget: a 1 Hz take of 7000 frames (1.9 h, 210 k working frames) is refused, the shipped
    // model runs it (it is checked, not run, here)
    let long = working_take(7000, 1.0);
    let (out, peak) = peak_during(|| m.run_checked(&long, &checked, &RunOptions::default(), &mut NoProgress));
    let message = out.err().expect("the long take is past the default budget").to_string();
    assert!(message.contains("multiply-adds") && message.contains("cut the take to at most"), "{message}");
    assert!(peak < 1 << 20, "allocated {peak} bytes before refusing");
    assert!(shipped.ops(shipped.frames(&long)) <= WorkLimits::default().max_ops);
    // both shipped labellers fit a 2-hour take (the longest a run takes)
    let two_hours = working_take(7200, 1.0);
    for method in ["knn", "dtfcn"] {
        let m = mocapseg::methods::find(method).unwrap();
        let work = m.work(&m.check_json(&serde_json::json!({})).unwrap()).unwrap();
        let ops = work.ops(work.frames(&two_hours));
        assert!(ops <= WorkLimits::default().max_ops, "the shipped {method} declares {ops:.3e} for 2 hours");
    }
}

/// A run stops soon after it is cancelled, wherever it is: in the wide k-NN's projection, in the k-NN's search, in
/// the take fit's search, in the decoder (a 30 s minimum run of 7 classes), and between DT-FCN's blocks — at most one
/// report after the one that cancelled (before these asked, each ran to its end and only then said Cancelled).
#[test]
fn a_labelling_run_stops_where_it_is_cancelled() {
    use mocapseg::method::{MethodError, Progress, RunOptions};
    let _one = MEASURING.lock().unwrap();
    struct CancelAt {
        stage: &'static str,
        after: f64,
        cancelled: bool,
        reports_after: usize,
    }
    impl Progress for CancelAt {
        fn report(&mut self, stage: &str, fraction: f64) {
            if self.cancelled {
                self.reports_after += 1;
            } else if stage == self.stage && fraction > self.after {
                self.cancelled = true;
            }
        }
        fn cancelled(&self) -> bool {
            self.cancelled
        }
    }
    let mut store = mocapseg::method::ModelStore::new();
    let knn = mocapseg::methods::find("knn").unwrap();
    store.install(knn.supervised().unwrap().read_model("wide.model", &hostile::wide_knn_file("wide", 2000)).unwrap());
    let take = working_take(6000, 30.0);
    let cases = [
        ("knn", serde_json::json!({"model": "wide", "fit_check": false}), "neighbours", 0.12),
        ("knn", serde_json::json!({"fit_check": false}), "neighbours", 0.7),
        ("knn", serde_json::json!({}), "take fit", 0.01),
        (
            "knn",
            serde_json::json!({"decoding": "custom", "min_duration_s": 30.0, "fit_check": false}),
            "decoding",
            0.96,
        ),
        ("dtfcn", serde_json::json!({"decoding": "raw", "fit_check": false}), "network", 0.2),
    ];
    for (method, params, stage, after) in cases {
        let m = mocapseg::methods::find(method).unwrap();
        let checked = m.check_json_in(&params, &store).unwrap();
        let mut progress = CancelAt { stage, after, cancelled: false, reports_after: 0 };
        let out = m.run_checked(&take, &checked, &RunOptions::default(), &mut progress);
        assert!(progress.cancelled, "{method} {params}: never reached {stage} past {after}");
        assert!(matches!(out, Err(MethodError::Cancelled)), "{method} {params}: {:?}", out.map(|_| ()));
        assert!(progress.reports_after <= 1, "{method} {params}: {} reports after the cancel", progress.reports_after);
    }
}
