//! The nine cargo-fuzz targets' code (`fuzz/src/targets/`), compiled into this crate's tests and run on
//! each target's seeds and on mutations of them, so a target that no longer compiles against the crate,
//! or whose checks fail on its own seeds, fails `cargo test` — without building libFuzzer or a second
//! copy of every dependency (the fuzz crate is its own workspace). `make fuzz` runs them for real.
//!
//! The mutations are a fixed pseudo-random sequence (the same on every run): byte flips, cuts, repeated
//! and inserted stretches, and for the structure-aware targets plain random bytes.
#![cfg(not(target_arch = "wasm32"))]

use std::path::Path;

#[path = "../fuzz/src/budget.rs"]
mod budget;
#[path = "../fuzz/src/seeds.rs"]
mod seeds;
#[path = "../fuzz/src/targets/mod.rs"]
mod targets;

// what the targets reach as `crate::…` (in the fuzz crate: its lib.rs)
use seeds::*;

/// The repository's root.
fn repo() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// xorshift64*: a fixed sequence, no dependency.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_F491_4F6C_DD1D)
    }

    fn below(&mut self, n: usize) -> usize {
        (self.next() % n.max(1) as u64) as usize
    }
}

/// `seed` changed by one to three edits of the kinds libFuzzer makes.
fn mutate(seed: &[u8], rng: &mut Rng) -> Vec<u8> {
    const TOKENS: [&[u8]; 8] = [b"nan", b"-1e309", b"}", b"{", b"\n", b"CHANNELS 7", b"Frames: 0", b"\xff\xfe"];
    let mut out = seed.to_vec();
    for _ in 0..1 + rng.below(3) {
        let at = rng.below(out.len() + 1);
        match rng.below(5) {
            0 if !out.is_empty() => {
                let i = at.min(out.len() - 1);
                out[i] ^= 1 << rng.below(8);
            }
            1 => out.truncate(at),
            2 => {
                let end = (at + 1 + rng.below(64)).min(out.len());
                let piece = out[at.min(end)..end].to_vec();
                out.splice(at..at, piece);
            }
            3 => {
                let token = TOKENS[rng.below(TOKENS.len())];
                out.splice(at..at, token.iter().copied());
            }
            _ => {
                let end = (at + rng.below(16)).min(out.len());
                out.drain(at..end);
            }
        }
    }
    out
}

/// The fuzz targets' allocator here too (issue 49: the targets ran without their budget under `cargo test`): one
/// allocation, or the live heap of this test binary's tests side by side, past 1 GiB aborts the binary — a runaway
/// allocation fails `cargo test` instead of swapping the machine. (`make fuzz` gives each target 256 MiB alone.)
#[global_allocator]
static ALLOCATOR: budget::Budgeted = budget::Budgeted;

/// Runs `run` on every seed and on `mutants` mutations of the seeds (or, without seeds, on `mutants`
/// random byte strings), under the budget.
fn exercise(seeds: Vec<(String, Vec<u8>)>, run: fn(&[u8]), mutants: usize, rng_seed: u64) {
    budget::set_limit(1 << 30);
    let mut rng = Rng(rng_seed);
    for (_, bytes) in &seeds {
        run(bytes);
    }
    for _ in 0..mutants {
        let input = match seeds.len() {
            0 => (0..rng.below(2048)).map(|_| rng.next() as u8).collect(),
            n => mutate(&seeds[rng.below(n)].1, &mut rng),
        };
        run(&input);
    }
}

#[test]
fn bvh_parse_holds_on_its_seeds_and_their_mutations() {
    let seeds = targets::bvh_parse::seeds();
    assert!(seeds.len() >= 10, "every fixture gives two seeds");
    exercise(seeds, targets::bvh_parse::run, 300, 1);
}

#[test]
fn bvh_grammar_holds_on_random_takes() {
    assert!(targets::bvh_grammar::seeds().is_empty(), "structure-aware: any bytes make a take");
    exercise(Vec::new(), targets::bvh_grammar::run, 300, 2);
}

#[test]
fn load_pipeline_holds_on_its_seeds_and_some_mutations() {
    let seeds = targets::load_pipeline::seeds();
    assert!(!seeds.is_empty());
    exercise(seeds, targets::load_pipeline::run, 40, 3);
}

#[test]
fn long_takes_hold_on_its_seeds_and_random_inputs() {
    exercise(targets::long_takes::seeds(), targets::long_takes::run, 30, 4);
}

#[test]
fn labels_import_holds_on_its_seeds_and_their_mutations() {
    let seeds = targets::labels_import::seeds();
    assert!(!seeds.is_empty());
    exercise(seeds, targets::labels_import::run, 200, 5);
}

#[test]
fn segmentation_json_holds_on_its_seeds_and_their_mutations() {
    let seeds = targets::segmentation_json::seeds();
    assert!(!seeds.is_empty());
    exercise(seeds, targets::segmentation_json::run, 200, 6);
}

#[test]
fn model_file_holds_on_its_seeds_and_their_mutations() {
    let seeds = targets::model_file::seeds();
    assert!(!seeds.is_empty());
    exercise(seeds, targets::model_file::run, 100, 7);
}

#[test]
fn project_file_holds_on_its_seeds_and_their_mutations() {
    let seeds = targets::project_file::seeds();
    assert_eq!(seeds.len(), 2);
    exercise(seeds, targets::project_file::run, 400, 9);
}

#[test]
fn asf_amc_holds_on_its_seeds_and_their_mutations() {
    let seeds = targets::asf_amc::seeds();
    assert!(!seeds.is_empty());
    exercise(seeds, targets::asf_amc::run, 100, 8);
}

/// The mutations are not the seeds: a harness that handed the targets their seeds again would test
/// nothing more.
#[test]
fn mutations_change_their_seed() {
    let mut rng = Rng(9);
    let seed = b"HIERARCHY\nROOT Hips\n{\n OFFSET 0 0 0\n}\n".to_vec();
    let changed = (0..100).filter(|_| mutate(&seed, &mut rng) != seed).count();
    assert!(changed >= 90, "{changed} of 100 mutants differ from their seed");
}
