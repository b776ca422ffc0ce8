#!/usr/bin/env bash
# Regenerate the lock files requirements/*.txt from pyproject.toml, with uv:
#   requirements/all.txt      every extra at once: one consistent set of versions,
#   requirements/EXTRA.txt    one per extra of pyproject.toml, constrained to all.txt
#                             (so every extra pins the same versions),
#   requirements/tools.txt    pip, uv and the build requirements (setuptools).
# Universal (markers for other platforms and Python >= 3.11), from PyPI (or
# UV_DEFAULT_INDEX), with as few versions per package as possible.
#
#   bash workflow/lock.sh             # add what pyproject.toml gained, keep every other pin
#   bash workflow/lock.sh --upgrade   # move every pin to the newest release allowed
#
# uv keeps the versions already in an output file, so rerunning without
# --upgrade changes only what pyproject.toml changed. Commit requirements/.
set -euo pipefail
EXTRA=
source "$(dirname "${BASH_SOURCE[0]}")/setup.sh"
setup_venv
setup_uv || { setup_say "lock.sh needs uv (pip install could not get it)"; exit 1; }
mkdir -p requirements
compile() {  # output file, then uv pip compile arguments
    local out="$1"; shift
    setup_say "locking $out"
    .venv/bin/uv pip compile --quiet --universal --python-version "$MIN_PYTHON" \
        --fork-strategy fewest --custom-compile-command "bash workflow/lock.sh" \
        --annotation-style line --no-progress "$@" -o "$out"
}
compile requirements/all.txt pyproject.toml --all-extras "$@"
# The build requirements of [build-system], and the installers themselves.
.venv/bin/python -c 'import tomllib; print("\n".join(["pip", "uv", *tomllib.load(open("pyproject.toml", "rb"))["build-system"]["requires"]]))' \
    | compile requirements/tools.txt - -c requirements/all.txt "$@"
extras="$(.venv/bin/python -c 'import tomllib; print(*tomllib.load(open("pyproject.toml", "rb"))["project"]["optional-dependencies"])')"
for extra in $extras; do
    compile "requirements/$extra.txt" pyproject.toml --extra "$extra" -c requirements/all.txt "$@"
done
# Locks of extras that pyproject.toml no longer has.
for lock in requirements/*.txt; do
    name="$(basename "$lock" .txt)"
    case " all tools $extras " in *" $name "*) ;; *) setup_say "removing $lock"; rm "$lock" ;; esac
done
