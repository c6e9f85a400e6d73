#!/usr/bin/env bash
# Quick start, command 1: set up .venv, build the four FMUs into dist/, run the default
# closed-loop co-simulation through them and write out/results.csv, out/summary.json and plots.
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/setup.sh
.venv/bin/axir build --out dist
.venv/bin/axir run --out out --plot "$@"
