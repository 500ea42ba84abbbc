#!/usr/bin/env python3
"""Copies one plot of a camdyn report.html into a standalone SVG file.

    scripts/extract_plot.py REPORT.html "CAPTION TEXT" OUT.svg

The plot is the first <figure> whose caption contains CAPTION TEXT; its
<svg> element is written as it is (gnuplot's SVG, self-contained). Used for
the pictures in README.md, e.g. the before/after margin of optimize_jump:

    build/release/camdyn run studies/optimize_jump.json --out out/optimize_jump
    scripts/extract_plot.py out/optimize_jump/report.html "margin P − 10 N at 1300 rpm" docs/optimize_jump_margin.svg
"""
import html
import re
import sys


def main() -> int:
    if len(sys.argv) != 4:
        print(__doc__, file=sys.stderr)
        return 2
    report, caption, out = sys.argv[1:]
    text = open(report, encoding="utf-8").read()
    for figure in re.findall(r"<figure.*?</figure>", text, flags=re.S):
        cap = re.search(r"<figcaption>(.*?)</figcaption>", figure, flags=re.S)
        if not cap or caption not in html.unescape(re.sub(r"<[^>]+>", "", cap.group(1))):
            continue
        svg = re.search(r"<svg.*?</svg>", figure, flags=re.S)
        if not svg:
            break
        with open(out, "w", encoding="utf-8") as f:
            f.write('<?xml version="1.0" encoding="utf-8"?>\n' + svg.group(0) + "\n")
        return 0
    print(f"extract_plot: no plot with caption containing {caption!r} in {report}", file=sys.stderr)
    return 1


if __name__ == "__main__":
    sys.exit(main())
