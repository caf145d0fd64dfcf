#!/usr/bin/env python3
"""Rounds the MOTION values of a BVH file to N decimals (default 3), trailing zeros dropped, in place.

How the page's bundled sample (www/sample.bvh, CMU 13_30 with 4 decimals) was made lighter for the first visit:
0.01 degree and 0.01 length unit (at most 0.005 off) are far below what a mocap system measures (about 0.1 degree),
and its pack is 36 % smaller than at 3 decimals (www/SOURCES.md). Usage: scripts/round-bvh.py FILE.bvh [N]
"""
import sys


def rounded(token: str, decimals: int) -> str:
    text = f"{float(token):.{decimals}f}".rstrip("0").rstrip(".")
    return "0" if text in ("-0", "") else text


def main() -> None:
    path, decimals = sys.argv[1], int(sys.argv[2]) if len(sys.argv) > 2 else 3
    text = open(path, newline="").read()
    head, motion = text.split("MOTION", 1)
    lines = motion.split("\n")
    # lines[0] is empty (the rest of the MOTION line), then `Frames:` and `Frame Time:`
    body = [" ".join(rounded(t, decimals) for t in line.split()) if line.strip() else line for line in lines[3:]]
    with open(path, "w", newline="") as out:
        out.write(head + "MOTION" + "\n".join(lines[:3] + body))


if __name__ == "__main__":
    main()
