#!/usr/bin/env python3
"""scripts/service-worker.py DIST — writes DIST/sw.js from the template DIST/www/sw.js (copied
there from www/sw.js by `make web`, and removed): ASSETS becomes every file of the build (paths
relative to DIST, hidden files left out) with its sha256, as a list of [path, sha256] pairs (the
template makes a Map of it, so that no path is looked up among an object's prototype keys),
VERSION the first 16 hex digits of the sha256 of that list and of the template. Any change to the
wasm, the page, a script, a style or a sample is a new sw.js, which browsers install as a new
version (www/sw.js says how)."""

import hashlib
import json
import os
import sys


def main(dist: str) -> None:
    template_path = os.path.join(dist, "www", "sw.js")
    with open(template_path, encoding="utf-8") as f:
        template = f.read()
    version_mark, assets_mark = '"__MOCAPSEG_VERSION__"', "/*__MOCAPSEG_ASSETS__*/ []"
    for mark in (version_mark, assets_mark):
        if template.count(mark) != 1:
            sys.exit(f"service-worker.py: {template_path} must hold {mark} once")
    os.remove(template_path)

    assets = {}
    for root, dirs, files in os.walk(dist):
        dirs[:] = sorted(d for d in dirs if not d.startswith("."))
        for name in sorted(files):
            rel = os.path.relpath(os.path.join(root, name), dist).replace(os.sep, "/")
            if name.startswith(".") or rel == "sw.js":
                continue
            with open(os.path.join(root, name), "rb") as f:
                assets[rel] = hashlib.sha256(f.read()).hexdigest()
    listing = "".join(f"{path} {sha}\n" for path, sha in sorted(assets.items()))
    version = hashlib.sha256((listing + template).encode()).hexdigest()[:16]

    text = template.replace(version_mark, json.dumps(version))
    pairs = "".join(f"  {json.dumps([path, sha])},\n" for path, sha in sorted(assets.items()))
    text = text.replace(assets_mark, f"[\n{pairs}]")
    with open(os.path.join(dist, "sw.js"), "w", encoding="utf-8") as f:
        f.write(text)
    print(f"{dist}/sw.js: version {version}, {len(assets)} files")


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    main(sys.argv[1])
