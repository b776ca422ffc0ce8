#!/usr/bin/env bash
# Set up .venv (first run only) and run the whole test suite. Extra arguments go to pytest.
set -euo pipefail
EXTRA=test
source "$(dirname "${BASH_SOURCE[0]}")/setup.sh"
python -m pytest "$@"
