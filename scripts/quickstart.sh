#!/usr/bin/env bash
# From a fresh Debian 12 machine to a first report: installs what is missing,
# builds the release preset, runs studies/quickstart.json and prints the path
# of the report to open in a browser.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

bash scripts/setup.sh release camdyn  # only what the quickstart runs
build/release/camdyn run studies/quickstart.json --out out/quickstart
echo "$(pwd -P)/out/quickstart/report.html"
