#!/usr/bin/env bash
# scripts/setup.sh — install everything mocapseg needs to build, serve and test, idempotently.
#
# Works on a fresh Debian 12 machine whose only network is crates.io, npm, PyPI and Debian apt,
# as root or as a user with sudo. When everything is already there it finishes in seconds.
#
# What it installs (each step is skipped when already satisfied):
#   1. A Rust toolchain that can target wasm32-unknown-unknown, by one of two routes:
#        Route S  rustup's toolchain + `rustup target add wasm32-unknown-unknown`.
#        Route D  (when rustup is missing or cannot fetch the target) Debian's rustc-web 1.9x +
#                 std sources + lld, used with RUSTC_BOOTSTRAP=1 and -Zbuild-std for wasm32.
#      The chosen route is written to .toolchain.env (make syntax, git-ignored), which the
#      Makefile includes so that every target builds the same way.
#   2. wasm-bindgen-cli at exactly the version of the `wasm-bindgen` crate in Cargo.lock
#      (wasm-bindgen, wasm-bindgen-test-runner).
#   3. Debian chromium + chromium-driver (for wasm-bindgen-test and Playwright; never a
#      downloaded browser).
#   4. The npm packages of tests/e2e (playwright-core, binaryen@132 whose wasm-opt is the one
#      `make web` uses — Debian's binaryen 108 miscompiles wasm-bindgen output) via `npm ci`.
#   5. python3 (the static file server of `make demo` and the e2e test).
#
# Environment: SETUP_FORCE_ROUTE=S|D forces a toolchain route (for testing the fallback).
set -euo pipefail

ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$ROOT"

# CI may run with a minimal environment: make sure HOME (where cargo installs) is set.
export HOME="${HOME:-$(getent passwd "$(id -u)" | cut -d: -f6)}"

export PATH="$HOME/.cargo/bin:$PATH"
export PLAYWRIGHT_SKIP_BROWSER_DOWNLOAD=1
export DEBIAN_FRONTEND=noninteractive

WASM_TARGET=wasm32-unknown-unknown
ENV_FILE="$ROOT/.toolchain.env"
E2E_DIR="$ROOT/tests/e2e"
START=$SECONDS

log() { printf 'setup: %s\n' "$*"; }
die() { printf 'setup: ERROR: %s\n' "$*" >&2; exit 1; }
have() { command -v "$1" >/dev/null 2>&1; }

# Run a command as root: directly when we are root, through sudo otherwise.
as_root() {
    if [ "$(id -u)" -eq 0 ]; then
        "$@"
    elif have sudo; then
        sudo -E "$@"
    else
        die "need root for '$*' (run as root or install sudo)"
    fi
}

APT_UPDATED=0
apt_install() {
    if [ "$APT_UPDATED" -eq 0 ]; then
        log "apt-get update"
        as_root apt-get update -qq
        APT_UPDATED=1
    fi
    log "apt-get install $*"
    as_root apt-get install -y -qq "$@"
}

# True if every named Debian package is installed.
dpkg_installed() {
    local p
    for p in "$@"; do
        dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || return 1
    done
}

# ---------------------------------------------------------------------------------------------
# 0. Basics: a C linker for native Rust builds, a C++ compiler for libFuzzer, python3 for the static server.
# ---------------------------------------------------------------------------------------------
ensure_basics() {
    if ! have cc; then
        apt_install gcc libc6-dev
    fi
    # a C++ compiler: the fuzz crate's libFuzzer, which make test builds (make fuzz-check)
    if ! have c++; then
        apt_install g++
    fi
    if have python3 && python3 -c 'import http.server' 2>/dev/null; then
        log "python3 ok ($(python3 --version 2>&1))"
    else
        apt_install python3
    fi
}

# ---------------------------------------------------------------------------------------------
# 1. Rust toolchain → Route S or Route D, recorded in .toolchain.env
# ---------------------------------------------------------------------------------------------
try_route_s() {
    have rustup || { log "no rustup: Route S not available"; return 1; }
    if ! cargo --version >/dev/null 2>&1; then
        log "rustup has no usable default toolchain; trying 'rustup toolchain install stable'"
        timeout 900 rustup toolchain install stable --profile minimal --target "$WASM_TARGET" \
            && rustup default stable || return 1
    fi
    # rustfmt for make test's format check, which fails without one: rustup's, else Debian's (rustfmt-web)
    cargo fmt --version >/dev/null 2>&1 || timeout 300 rustup component add rustfmt >/dev/null 2>&1 \
        || { log "rustup could not add rustfmt: Debian's rustfmt-web instead"; debian_rustfmt; }
    if rustup target list --installed 2>/dev/null | grep -qx "$WASM_TARGET"; then
        log "rustup: $WASM_TARGET already installed ($(rustc --version))"
        return 0
    fi
    log "rustup target add $WASM_TARGET"
    if timeout 600 rustup target add "$WASM_TARGET"; then
        return 0
    fi
    log "rustup could not add $WASM_TARGET"
    return 1
}

# Debian's rustfmt and cargo-fmt (/usr/bin), which `make fmt-check` uses where rustup has none.
debian_rustfmt() {
    [ -x /usr/bin/cargo-fmt ] && [ -x /usr/bin/rustfmt ] && return 0
    apt_install rustfmt-web || log "rustfmt-web did not install: make test's format check will fail until a rustfmt is there"
}

route_d_ready() {
    [ -x /usr/bin/cargo ] && [ -x /usr/bin/rustc ] && [ -x /usr/bin/rustdoc ] \
        && [ -d /usr/lib/rustlib/src/rust/library ] && dpkg_installed lld-22
}

setup_route_d() {
    if route_d_ready; then
        log "Debian rustc-web already installed ($(/usr/bin/rustc --version))"
    else
        apt_install rustc-web cargo-web rust-web-src lld-22
        route_d_ready || die "Debian rustc-web/cargo-web/rust-web-src/lld-22 did not install completely"
    fi
    debian_rustfmt
}

write_env_file() {
    local route=$1 tmp
    tmp=$(mktemp)
    {
        echo "# Generated by scripts/setup.sh — the Rust toolchain route every make target uses."
        echo "# Re-run 'make setup' to regenerate. Not committed (.gitignore)."
        echo "TOOLCHAIN_ROUTE := $route"
        if [ "$route" = S ]; then
            echo "CARGO := cargo"
            echo "WASM_CARGO_FLAGS :="
        else
            echo "CARGO := /usr/bin/cargo"
            echo "WASM_CARGO_FLAGS := -Zbuild-std=std,panic_abort -Zbuild-std-features="
            echo "export RUSTC_BOOTSTRAP := 1"
            echo "export RUSTC := /usr/bin/rustc"
            echo "export RUSTDOC := /usr/bin/rustdoc"
        fi
    } >"$tmp"
    if ! cmp -s "$tmp" "$ENV_FILE" 2>/dev/null; then
        mv "$tmp" "$ENV_FILE"
        log "wrote $(basename "$ENV_FILE") (Route $route)"
    else
        rm -f "$tmp"
    fi
}

ensure_rust() {
    local route=${SETUP_FORCE_ROUTE:-}
    if [ -z "$route" ]; then
        if try_route_s; then route=S; else route=D; fi
    elif [ "$route" = S ]; then
        try_route_s || die "SETUP_FORCE_ROUTE=S but rustup cannot provide $WASM_TARGET"
    fi
    case "$route" in
        S) CARGO_BIN=cargo; unset RUSTC RUSTDOC RUSTC_BOOTSTRAP || true ;;
        D) setup_route_d; CARGO_BIN=/usr/bin/cargo; export RUSTC=/usr/bin/rustc RUSTDOC=/usr/bin/rustdoc ;;
        *) die "SETUP_FORCE_ROUTE must be S or D, not '$route'" ;;
    esac
    ROUTE=$route
    write_env_file "$route"
}

# ---------------------------------------------------------------------------------------------
# 2. wasm-bindgen-cli == the wasm-bindgen crate in Cargo.lock
# ---------------------------------------------------------------------------------------------
lock_version() {
    # The version line that follows `name = "<crate>"` in Cargo.lock.
    awk -v want="name = \"$1\"" '
        $0 == want { found = 1; next }
        found && /^version = / { gsub(/"/, "", $3); print $3; exit }
    ' "$ROOT/Cargo.lock"
}

ensure_wasm_bindgen() {
    [ -f "$ROOT/Cargo.lock" ] || die "Cargo.lock is missing"
    local want have_v=""
    want=$(lock_version wasm-bindgen)
    [ -n "$want" ] || die "no wasm-bindgen package in Cargo.lock"
    if have wasm-bindgen && have wasm-bindgen-test-runner; then
        have_v=$(wasm-bindgen --version 2>/dev/null | awk '{print $2}')
    fi
    if [ "$have_v" = "$want" ]; then
        log "wasm-bindgen-cli $want already installed"
        return
    fi
    log "cargo install wasm-bindgen-cli --version $want (found: ${have_v:-none}; takes a few minutes)"
    # Not --locked: its lock pins a webpki-roots the registry here lacks.
    "$CARGO_BIN" install wasm-bindgen-cli --version "$want"
    [ "$(wasm-bindgen --version | awk '{print $2}')" = "$want" ] \
        || die "wasm-bindgen on PATH is not $want after install: $(command -v wasm-bindgen)"
}

# ---------------------------------------------------------------------------------------------
# 3. Debian chromium + chromedriver
# ---------------------------------------------------------------------------------------------
ensure_chromium() {
    if [ -x /usr/bin/chromium ] && [ -x /usr/bin/chromedriver ]; then
        log "chromium + chromedriver already installed"
    else
        apt_install chromium chromium-driver
    fi
}

# ---------------------------------------------------------------------------------------------
# 4. npm packages of tests/e2e (playwright-core, binaryen@132)
# ---------------------------------------------------------------------------------------------
ensure_npm() {
    if ! have node || ! have npm; then
        apt_install nodejs npm
    fi
    ensure_node20
    local stamp="$E2E_DIR/node_modules/.setup-stamp" want
    want=$(cat "$E2E_DIR/package.json" "$E2E_DIR/package-lock.json" | sha256sum | cut -d' ' -f1)
    if [ -f "$stamp" ] && [ "$(cat "$stamp")" = "$want" ] \
        && [ -x "$E2E_DIR/node_modules/.bin/wasm-opt" ] && [ -d "$E2E_DIR/node_modules/playwright-core" ]; then
        log "npm packages of tests/e2e already installed"
        return
    fi
    log "npm ci in tests/e2e"
    (cd "$E2E_DIR" && npm ci --no-audit --no-fund --loglevel=error)
    "$E2E_DIR/node_modules/.bin/wasm-opt" --version | grep -q "version 132" \
        || die "tests/e2e/node_modules/.bin/wasm-opt is not binaryen 132"
    echo "$want" >"$stamp"
}

# playwright-core needs Node ≥ 20; Debian 12 ships 18. Then a Node 20 binary comes from the npm
# registry (package node-linux-<arch>) into .tools/node; scripts/e2e.sh puts it first on PATH.
ensure_node20() {
    local major
    major=$(node -p 'process.versions.node.split(".")[0]' 2>/dev/null || echo 0)
    if [ "$major" -ge 20 ]; then
        log "node $(node --version) is recent enough for playwright-core"
        return
    fi
    local arch
    case "$(uname -m)" in
        x86_64) arch=x64 ;;
        aarch64 | arm64) arch=arm64 ;;
        *) die "node $(node --version) is older than 20 and no Node 20 package exists for $(uname -m)" ;;
    esac
    local dir="$ROOT/.tools/node"
    if [ ! -x "$dir/node_modules/node-linux-$arch/bin/node" ]; then
        log "node $(node --version) is older than 20 (playwright-core needs ≥ 20): npm install node-linux-$arch@20 into .tools/node"
        mkdir -p "$dir"
        npm install --no-save --no-audit --no-fund --loglevel=error --prefix "$dir" "node-linux-$arch@20" \
            || die "could not install Node 20 from the npm registry"
    fi
    "$dir/node_modules/node-linux-$arch/bin/node" --version >/dev/null || die "the Node 20 from .tools/node does not run"
    log "using $("$dir/node_modules/node-linux-$arch/bin/node" --version) from .tools/node for the e2e test"
}

main() {
    ensure_basics
    ensure_rust
    ensure_wasm_bindgen
    ensure_chromium
    ensure_npm
    log "done in $((SECONDS - START)) s — Route $ROUTE ($("$CARGO_BIN" --version)), $(wasm-bindgen --version), $(/usr/bin/chromium --version 2>/dev/null | head -1)"
}

main "$@"
