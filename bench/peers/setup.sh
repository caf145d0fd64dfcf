#!/usr/bin/env bash
# The Python environment of the peer benchmark (bench/peers/run.py): bench/peers/.venv with the
# pinned requirements.txt from PyPI, wheels only. Idempotent: seconds when the environment is
# there and matches requirements.txt (its checksum is kept in .venv/requirements.sha256).
# Installs Debian's python3 / python3-venv with apt when they are missing (as scripts/setup.sh does).
set -euo pipefail

HERE=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
VENV="$HERE/.venv"
REQ="$HERE/requirements.txt"

log() { printf 'peers setup: %s\n' "$*"; }
die() { printf 'peers setup: ERROR: %s\n' "$*" >&2; exit 1; }
have() { command -v "$1" >/dev/null 2>&1; }
as_root() {
    if [ "$(id -u)" -eq 0 ]; then "$@"
    elif have sudo; then sudo -E "$@"
    else die "need root for '$*' (run as root or install sudo)"; fi
}
APT_UPDATED=0
apt_install() {
    have apt-get || die "no apt-get: install $* by hand"
    if [ "$APT_UPDATED" -eq 0 ]; then
        log "apt-get update"
        as_root apt-get update -qq
        APT_UPDATED=1
    fi
    log "apt-get install $*"
    as_root env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq "$@"
}

have python3 || apt_install python3
# Debian's python3 has no venv/ensurepip without python3-venv
if ! python3 -c 'import venv, ensurepip' >/dev/null 2>&1; then
    apt_install python3-venv
fi

sum=$(sha256sum "$REQ" | cut -d' ' -f1)
if [ -x "$VENV/bin/python" ] && [ -f "$VENV/requirements.sha256" ] && [ "$(cat "$VENV/requirements.sha256")" = "$sum" ]; then
    log "$VENV is up to date with requirements.txt"
    exit 0
fi

if [ ! -x "$VENV/bin/python" ]; then
    log "python3 -m venv $VENV ($(python3 --version))"
    python3 -m venv "$VENV"
fi
log "pip install --only-binary :all: -r requirements.txt"
"$VENV/bin/python" -m pip install -q --disable-pip-version-check --only-binary :all: -r "$REQ"
echo "$sum" >"$VENV/requirements.sha256"
log "installed: $("$VENV/bin/python" -m pip freeze | grep -iE '^(claspy|stumpy|ruptures|numpy)==' | tr '\n' ' ')"
