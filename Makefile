# mocapseg — build, serve, test and benchmark (plain make; no trunk).
#
#   make demo    set up, build the page and serve it on http://localhost:8080
#   make test    set up, then every test: native (cargo test), the page bundle, the wasm
#                tests in headless Chromium (one binary sharing the bundle's build), and the
#                Playwright end-to-end test; prints each stage's time
#   make bench   one table: parse, FK, every method at 1×/2×/4×/16× a take (16×: 10 minutes) with where
#                each run's time goes, and the batch rate, native and in headless Chromium; the page's
#                load (bytes before the first result, time to it) and the user's view (every row of a
#                40 s and a 10-minute take, the sample, the library); with ../shared/data also the peer
#                libraries (bench/peers)
#   make setup   install the toolchain (scripts/setup.sh; idempotent, seconds when done)
#   make release the page as `make web` builds it, with whole-program optimisation (profile `web-release`)
#   make web     build the page into dist/ (the wasm in the `web` profile — the release profile —,
#                wasm-bindgen + wasm-opt + assets, the shipped models in dist/models/, fetched by the
#                page when a method first needs one; wasm-bindgen and wasm-opt only run again when the
#                wasm changed)
#   make accuracy  the scoreboard: every method on every labelled take of ../shared/data, in-sample and
#                nested leave-one-take-out side by side, beside chance and oracle-K; writes docs/accuracy.md,
#                docs/accuracy.json, each method's rows into its docs/methods/<method>.md and the held-out summary
#                into README.md (examples/accuracy.rs; not part of make test); then the library of takes (shared
#                clusters, label transfer) into docs/library.md and docs/library.json (examples/library.rs).
#                The scoreboard's markdown alone, again from the saved JSON:
#                cargo run --example accuracy -- --from-json docs/accuracy.json
#   make fuzz    the cargo-fuzz targets (fuzz/) one after another, FUZZ_S seconds each (default 60;
#                FUZZ_TARGETS="a b" picks some), then a table of executions; not part of make test
#
# scripts/setup.sh writes .toolchain.env, which says how to drive cargo (Route S: rustup;
# Route D: Debian rustc-web with -Zbuild-std). The top-level targets run setup first and then
# re-invoke make so that the freshly written file is read.

SHELL := /bin/bash
.SHELLFLAGS := -eu -o pipefail -c
.DEFAULT_GOAL := help
MAKEFLAGS += --no-print-directory

HOME ?= $(shell getent passwd $$(id -u) | cut -d: -f6)
export PATH := $(HOME)/.cargo/bin:$(PATH)
export PLAYWRIGHT_SKIP_BROWSER_DOWNLOAD := 1

-include .toolchain.env
CARGO ?= cargo
WASM_CARGO_FLAGS ?=

WASM_TARGET := wasm32-unknown-unknown
# The cargo profile of the page's wasm (Cargo.toml [profile.web]: the release profile, built on every core);
# `make release` builds [profile.web-release] (fat LTO, one codegen unit) instead.
WASM_PROFILE ?= web
CRATE       := mocapseg
DIST        := dist
WASM_OPT    := tests/e2e/node_modules/.bin/wasm-opt
DEMO_PORT   ?= 8080
# Seconds a headless wasm-bindgen-test run may take (the runner's default is 20).
WASM_TEST_TIMEOUT ?= 300
BENCH_WASM_TIMEOUT ?= 900

# Where `make test` writes each stage's time.
STAGE_TIMES := $(CURDIR)/test-output/stage-times.txt
export STAGE_TIMES

# SSSM benchmark sequence (written by `cargo run --example bench_sssm -- --write-bvh`).
BENCH_SEQ ?= $(CURDIR)/target/bench/sssm-sequence-30hz.bvh

# Batch benchmark: every BVH of the shared data (CMU takes and other exporters' files).
BENCH_DATA ?= $(abspath $(CURDIR)/../shared/data)

# make bench's results: JSON lines per side (examples/bench_table.rs prints the one table).
BENCH_DIR := $(CURDIR)/target/bench

# Benchmark input: the long CMU take 86_01 from shared data if present, else the bundled
# sample (CMU 13_30), else the largest fixture.
BENCH_BVH ?= $(firstword $(wildcard $(abspath $(CURDIR)/../shared/data/cmu/86/86_01.bvh) \
                /work/shared/data/cmu/86/86_01.bvh $(CURDIR)/www/sample.bvh) \
                $(abspath $(shell ls -S tests/fixtures/*.bvh 2>/dev/null | head -n 1)))

.PHONY: help setup demo release test bench web serve check-toolchain accuracy \
        test-native fmt-check fuzz-check test-wasm test-e2e bench-native bench-wasm bench-page bench-rows bench-peers bench-table fuzz

help:
	@sed -n '3,/^#$$/{/^#$$/!p}' Makefile | sed 's/^# \{0,1\}//'

setup:
	scripts/setup.sh

demo: setup
	$(MAKE) web
	$(MAKE) serve

# The page built with whole-program optimisation (Cargo.toml [profile.web-release]) into dist/, for publishing.
release: setup
	$(MAKE) web WASM_PROFILE=web-release

# Stages in the order that builds least: the wasm tests reuse the library `web` built (profile `web`).
test:
	@mkdir -p test-output && : >$(STAGE_TIMES)
	@scripts/stage.sh setup scripts/setup.sh
	@scripts/stage.sh native $(MAKE) test-native
	@scripts/stage.sh web $(MAKE) web
	@scripts/stage.sh wasm $(MAKE) test-wasm
	@scripts/stage.sh e2e $(MAKE) test-e2e
	@echo; echo "make test: all stages passed (native, web bundle, wasm in headless Chromium, e2e). Times:"
	@cat $(STAGE_TIMES)

# The detailed outputs first, then the peers (when the shared data is there), and last the one
# table (bench_table, from the JSON lines the native and the wasm benchmarks wrote).
bench: setup
	$(MAKE) bench-native
	$(MAKE) bench-wasm
	$(MAKE) bench-page
	$(MAKE) bench-rows
	@if [ -d "$(BENCH_DATA)/labels" ]; then $(MAKE) bench-peers; \
	else echo "note: $(BENCH_DATA) is absent: the peer libraries (bench/peers) are not run"; fi
	$(MAKE) bench-table

# The cargo-fuzz targets (fuzz/, docs/development.md "Fuzzing"): FUZZ_S seconds each, one fuzzer process at a
# time, built into fuzz/target. `make test` builds them (fuzz-check: `cargo check` of the fuzz crate, libFuzzer
# included) and runs their code on its seeds (tests/fuzz_targets.rs), but does not fuzz.
FUZZ_S ?= 60
FUZZ_TARGETS ?=
fuzz:
	FUZZ_S="$(FUZZ_S)" FUZZ_TARGETS="$(FUZZ_TARGETS)" scripts/fuzz.sh

# The scoreboard (docs/scoreboard.md). Says what is missing and fails when the shared data is absent.
ACCURACY_DATA ?= $(abspath $(CURDIR)/../shared/data)
accuracy: setup
	$(MAKE) check-toolchain
	@test -d "$(ACCURACY_DATA)/labels" || { echo "make accuracy: $(ACCURACY_DATA) is absent (the shared data: cmu/ and labels/ with 86_01 and the mocap6 takes); set ACCURACY_DATA=DIR" >&2; exit 1; }
	$(CARGO) run --release --example accuracy -- --data "$(ACCURACY_DATA)" --out docs --readme README.md \
	    --methods docs/methods
	$(CARGO) run --release --example library -- --data "$(ACCURACY_DATA)" --out docs

check-toolchain:
	@test -f .toolchain.env || { echo "No .toolchain.env: run 'make setup' first." >&2; exit 1; }

# --- build ------------------------------------------------------------------------------

# The page: the wasm of the lib with the `web` feature (cargo profile `web`: the release profile; `make release`:
# fat LTO, one codegen unit) → wasm-bindgen → wasm-opt -O1 → dist/ (-O1: smaller gzipped than -O2, the first result
# 0.3 s sooner, 24 s instead of 73: docs/benchmarks.md "The page's load").
# dist/.wasm-sum records the checksum of the wasm it was made from: an unchanged build skips
# wasm-bindgen and wasm-opt (the slow part) and only refreshes the static files.
# dist/sw.js (the service worker, from www/sw.js) lists every file with its sha256: its version.
# scripts/wasm-symbols.py fails the build when a symbol of the library outgrows what rustc's LTO can read back
# (the wasm tests link that library; see the script).
web: check-toolchain
	$(CARGO) build $(WASM_CARGO_FLAGS) --lib --profile $(WASM_PROFILE) --target $(WASM_TARGET) --features web
	@tdir=$$($(CARGO) metadata --format-version 1 --no-deps | python3 -c 'import json,sys; print(json.load(sys.stdin)["target_directory"])'); \
	wasm="$$tdir/$(WASM_TARGET)/$(WASM_PROFILE)/$(CRATE).wasm"; \
	python3 scripts/wasm-symbols.py "$$tdir/$(WASM_TARGET)/$(WASM_PROFILE)/deps/lib$(CRATE).rlib" || exit 1; \
	sum=$$(sha256sum "$$wasm" | cut -d' ' -f1); \
	if [ -f $(DIST)/.wasm-sum ] && [ "$$(cat $(DIST)/.wasm-sum)" = "$$sum" ] && [ -f $(DIST)/pkg/$(CRATE)_bg.wasm ]; then \
		echo "$(DIST)/pkg is up to date with $$wasm"; \
	else \
		rm -rf $(DIST) && mkdir -p $(DIST); \
		echo "wasm-bindgen --target web --no-typescript --out-dir $(DIST)/pkg $$wasm"; \
		wasm-bindgen --target web --no-typescript --out-dir $(DIST)/pkg "$$wasm"; \
		if [ -x $(WASM_OPT) ]; then \
			echo "$(WASM_OPT) -O1 $(DIST)/pkg/$(CRATE)_bg.wasm"; \
			$(WASM_OPT) -O1 $(DIST)/pkg/$(CRATE)_bg.wasm -o $(DIST)/pkg/$(CRATE)_bg.wasm; \
		else \
			echo "note: $(WASM_OPT) (npm binaryen@132) not installed: wasm left unoptimised (run 'make setup')"; \
		fi; \
		echo "$$sum" >$(DIST)/.wasm-sum; \
	fi; \
	cp index.html $(DIST)/; \
	rm -rf $(DIST)/www && cp -r www $(DIST)/www; \
	rm -rf $(DIST)/models && mkdir -p $(DIST)/models && cp models/*.model models/*.json $(DIST)/models/; \
	python3 scripts/service-worker.py $(DIST); \
	echo "built $(DIST)/: $$(du -h $(DIST)/pkg/$(CRATE)_bg.wasm | cut -f1) wasm"

serve:
	@test -f $(DIST)/index.html || { echo "No $(DIST)/index.html: run 'make web' first." >&2; exit 1; }
	@echo "Serving $(DIST)/ on http://localhost:$(DEMO_PORT)/ (Ctrl-C to stop)"
	cd $(DIST) && python3 -m http.server $(DEMO_PORT) --bind 127.0.0.1

# --- tests ------------------------------------------------------------------------------

# Every native test: unit tests, integration tests (incl. the CLI), doc tests. The fuzz targets' code
# (fuzz/src/targets) is compiled and run on its seeds by tests/fuzz_targets.rs; `make fuzz` fuzzes.
test-native: check-toolchain fmt-check fuzz-check
	$(CARGO) test

# The fuzz crate (its own workspace: fuzz/Cargo.toml) built as `make fuzz` builds it, its nine libFuzzer entries
# included, so that a target that no longer builds fails `make test` (into the target folder's fuzz-check/: the main
# crate's build is not disturbed).
fuzz-check: check-toolchain
	CARGO_TARGET_DIR="$${CARGO_TARGET_DIR:-$(CURDIR)/target}/fuzz-check" $(CARGO) check --quiet \
	    --manifest-path fuzz/Cargo.toml --bins

# The tree as rustfmt writes it (rustfmt.toml); `cargo fmt` fixes it. With the toolchain's rustfmt, else Debian's
# (rustfmt-web, which `make setup` installs where rustup has none); without either it fails rather than check nothing.
fmt-check:
	@if $(CARGO) fmt --version >/dev/null 2>&1; then fmt="$(CARGO) fmt"; \
	elif [ -x /usr/bin/cargo-fmt ] && [ -x /usr/bin/rustfmt ]; then fmt="env RUSTFMT=/usr/bin/rustfmt /usr/bin/cargo-fmt"; \
	else echo "fmt-check: no rustfmt (neither '$(CARGO) fmt' nor Debian's /usr/bin/cargo-fmt): run 'make setup'" >&2; exit 1; fi; \
	$$fmt --check || { echo "fmt-check: the diff above is what '$$fmt' would change; run it" >&2; exit 1; }

# One wasm test binary (tests/wasm.rs: the core, the SSSM suite, the worker's glue) in headless
# Chromium, in the `web` profile with the `web` feature: it links the library `make web`
# built instead of building every dependency a second time.
test-wasm: check-toolchain
	WASM_BINDGEN_TEST_TIMEOUT=$(WASM_TEST_TIMEOUT) \
	$(CARGO) test $(WASM_CARGO_FLAGS) --profile $(WASM_PROFILE) --target $(WASM_TARGET) --features web --test wasm

# Playwright against dist/ served on a free loopback port (needs `make web` first).
test-e2e:
	scripts/e2e.sh $(DIST)

# --- benchmarks -------------------------------------------------------------------------

# SSSM: the CMU sequence at 3000/6000/12000 frames (and its 30 Hz BVH for the wasm bench), the
# same without the search horizon (the paper's all-pairs SSSM), the sequence at 1300/2600/5200
# frames (all distinct material), then the worst case of one take repeated (every frame also
# neighbours its copies).
bench-native: check-toolchain
	@echo "bench input: $(BENCH_BVH)"
	$(CARGO) run --release --bin $(CRATE) -- bench "$(BENCH_BVH)"
	@mkdir -p $(dir $(BENCH_SEQ))
	$(CARGO) run --release --example bench_sssm -- --write-bvh "$(BENCH_SEQ)"
	$(CARGO) run --release --example bench_sssm -- --reps 3 --param horizon_s=0
	$(CARGO) run --release --example bench_sssm -- --frames 1300
	$(CARGO) run --release --example bench_sssm -- --reps 3 "$(BENCH_BVH)"
	$(CARGO) run --release --example bench_lma -- "$(BENCH_SEQ)" --reps 3
	$(CARGO) run --release --example bench_dtfcn -- "$(BENCH_SEQ)" --reps 5
	@echo "the table's native column: parse, FK, every method at 1×/2×/4× a take, batch over $(BENCH_DATA)"
	$(CARGO) build --release --bin $(CRATE)
	@tdir=$$($(CARGO) metadata --format-version 1 --no-deps | python3 -c 'import json,sys; print(json.load(sys.stdin)["target_directory"])'); \
	$(CARGO) run --release --example bench_methods -- --parse "$(BENCH_BVH)" --sequence "$(BENCH_SEQ)" \
		--batch "$(BENCH_DATA)" --cli "$$tdir/release/$(CRATE)" --out "$(BENCH_DIR)/results-native.jsonl"

$(BENCH_SEQ):
	@mkdir -p $(dir $(BENCH_SEQ))
	$(CARGO) run --release --example bench_sssm -- --reps 1 --write-bvh "$(BENCH_SEQ)"

# --nocapture makes the runner print the test's console output (the numbers); the table's
# wasm column is what the methods_table test prints after BENCHJSON.
bench-wasm: check-toolchain $(BENCH_SEQ)
	@echo "bench input: $(BENCH_BVH), SSSM sequence $(BENCH_SEQ)"
	@mkdir -p $(BENCH_DIR)
	MOCAPSEG_BENCH_BVH="$(BENCH_BVH)" MOCAPSEG_BENCH_SSSM_BVH="$(BENCH_SEQ)" WASM_BINDGEN_TEST_TIMEOUT=$(BENCH_WASM_TIMEOUT) \
	$(CARGO) test $(WASM_CARGO_FLAGS) --profile $(WASM_PROFILE) --target $(WASM_TARGET) --features web --test wasm_bench -- --nocapture \
		2>&1 | tee $(BENCH_DIR)/wasm-bench.log
	@grep -o 'BENCHJSON {.*}' $(BENCH_DIR)/wasm-bench.log | sed 's/^BENCHJSON //' >$(BENCH_DIR)/results-wasm.jsonl
	@echo "the table's wasm column: $$(wc -l <$(BENCH_DIR)/results-wasm.jsonl) results in $(BENCH_DIR)/results-wasm.jsonl"

# The peer libraries (ClaSP, FLUSS, ruptures) beside mocapseg's methods on the labelled takes of the
# shared data: accuracy and time (bench/peers/README.md). Sets up its own Python environment.
bench-peers: check-toolchain
	$(CARGO) build --release --bin $(CRATE)
	bench/peers/setup.sh
	@tdir=$$($(CARGO) metadata --format-version 1 --no-deps | python3 -c 'import json,sys; print(json.load(sys.stdin)["target_directory"])'); \
	bench/peers/.venv/bin/python bench/peers/run.py --data "$(BENCH_DATA)" --cli "$$tdir/release/$(CRATE)" \
		--out "$(BENCH_DIR)/peers"

# The one table, last: native beside wasm with the wasm/native time ratio.
# The page as a visitor gets it (tests/e2e/page-load.bench.mjs): bytes fetched before the first
# segmentation and in all, time to the first result, first and repeat visits, in headless Chromium.
bench-page: check-toolchain
	$(MAKE) web
	@mkdir -p $(BENCH_DIR)
	E2E_FILES="page-load.bench.mjs" scripts/e2e.sh 2>&1 | tee $(BENCH_DIR)/page-load.log

# The user's view (tests/e2e/rows.bench.mjs): a 40 s CMU take from drop (and from a first visit) to every row
# filled, the sample's first paint and every row, a 10-minute take (every row, the workers' memory), the library
# of the five shared labelled takes — in headless Chromium on the built page. Needs the shared data for all
# but the sample's row (it says so when absent).
bench-rows: check-toolchain
	$(MAKE) web
	@mkdir -p $(BENCH_DIR)
	BENCH_DATA="$(BENCH_DATA)" E2E_FILES="rows.bench.mjs" scripts/e2e.sh 2>&1 | tee $(BENCH_DIR)/rows.log

bench-table: check-toolchain
	@$(CARGO) run -q --release --example bench_table -- "$(BENCH_DIR)/results-native.jsonl" "$(BENCH_DIR)/results-wasm.jsonl"
