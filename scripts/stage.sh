#!/usr/bin/env bash
# scripts/stage.sh NAME COMMAND… — runs one stage of `make test`, prints how long it took and
# appends "NAME SECONDS" to $STAGE_TIMES (if set), so the whole run ends with a table of times.
set -uo pipefail
name=$1
shift
start=$(date +%s)
printf '\n==> %s: %s\n' "$name" "$*"
"$@"
rc=$?
took=$(($(date +%s) - start))
if [ "$rc" -eq 0 ]; then
    printf '==> %s: done in %d min %02d s\n' "$name" $((took / 60)) $((took % 60))
else
    printf '==> %s: FAILED (exit %d) after %d min %02d s\n' "$name" "$rc" $((took / 60)) $((took % 60)) >&2
fi
[ -n "${STAGE_TIMES:-}" ] && printf '%-8s %4d s%s\n' "$name" "$took" "$([ "$rc" -eq 0 ] || echo '  FAILED')" >>"$STAGE_TIMES"
exit "$rc"
