#!/usr/bin/env bash
# Set up and run the whole test suite (lint + pytest, slow tests included). Exit non-zero on failure.
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/setup.sh
.venv/bin/ruff check .
.venv/bin/python -m pytest -q "$@"
