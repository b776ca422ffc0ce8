# Sourced by regenerate.sh and test.sh (with EXTRA set) and lock.sh.
# Creates .venv beside the project (once) and installs exactly the versions
# pinned in requirements/tools.txt and requirements/$EXTRA.txt (written by
# workflow/lock.sh from pyproject.toml), then the project itself, editable,
# without dependencies. uv does the installing: it is installed into .venv
# with pip, at the version tools.txt pins; if that fails (or with
# SETUP_INSTALLER=pip), pip installs the same pins, more slowly.
# A stamp holds the hash of the locks and pyproject.toml, so a rerun with
# nothing changed does nothing. Extras installed earlier stay installed
# (regenerate.sh after test.sh does not remove pytest). SETUP_SKIP=1 installs
# nothing and uses .venv/bin as it is.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$ROOT"
PYTHON="${PYTHON:-python3}"
MIN_PYTHON=3.11  # Snakemake 8 needs it; lock.sh resolves for it and newer

setup_say() { echo "setup: $*" >&2; }

setup_venv() {  # create .venv with $PYTHON, which must be >= MIN_PYTHON
    local py=.venv/bin/python
    [ -x "$py" ] || py="$PYTHON"
    if ! "$py" -c "import sys; sys.exit(sys.version_info < tuple(map(int, '$MIN_PYTHON'.split('.'))))"; then
        setup_say "$py is $("$py" --version 2>&1); the workflow needs Python >= $MIN_PYTHON" \
            "(remove .venv and rerun with PYTHON=python$MIN_PYTHON or newer)"
        return 1
    fi
    if [ ! -x .venv/bin/python ]; then
        setup_say "creating .venv with $("$PYTHON" --version)"
        "$PYTHON" -m venv .venv
    fi
}

setup_uv() {  # put the uv that tools.txt pins into .venv; fails when pip cannot
    local want
    [ "${SETUP_INSTALLER:-uv}" = uv ] || return 1
    want="$(grep -Eo '^uv==[^ ;]+' requirements/tools.txt 2>/dev/null || echo uv)"
    if [ -x .venv/bin/uv ] && [ "uv==$(.venv/bin/uv --version | cut -d' ' -f2)" = "$want" ]; then
        return 0
    fi
    setup_say "installing $want into .venv with pip"
    .venv/bin/python -m pip install --disable-pip-version-check "$want" >&2
}

if [ -n "${EXTRA:-}" ] && [ "${SETUP_SKIP:-}" = 1 ]; then
    # An environment managed otherwise (a cluster module, the fault tests'
    # wrapper .venv): use .venv/bin as it is, install nothing.
    export PATH="$ROOT/.venv/bin:$PATH"
elif [ -n "${EXTRA:-}" ]; then
    if [ ! -f "requirements/$EXTRA.txt" ]; then
        setup_say "requirements/$EXTRA.txt is missing: run bash workflow/lock.sh"
        exit 1
    fi
    STAMP=.venv/.setup-stamp
    # Every extra installed so far (first line of the stamp) and this one.
    SETUP_EXTRAS="$EXTRA"
    if [ -f "$STAMP" ]; then
        for e in $(head -n1 "$STAMP"); do
            if [ -f "requirements/$e.txt" ]; then SETUP_EXTRAS+=" $e"; fi
        done
    fi
    # shellcheck disable=SC2086,SC2046  # one word per extra
    SETUP_EXTRAS="$(echo $(printf '%s\n' $SETUP_EXTRAS | sort -u))"
    SETUP_LOCKS=(requirements/tools.txt)
    for e in $SETUP_EXTRAS; do SETUP_LOCKS+=("requirements/$e.txt"); done
    SETUP_WANT="$(printf '%s\n%s' "$SETUP_EXTRAS" \
        "$(cat "${SETUP_LOCKS[@]}" pyproject.toml | sha256sum | cut -d' ' -f1)")"
    if [ "$(cat "$STAMP" 2>/dev/null)" != "$SETUP_WANT" ]; then
        rm -f "$STAMP"
        setup_venv
        setup_say "installing the pinned versions of: tools $SETUP_EXTRAS"
        if setup_uv; then
            # --compile-bytecode: the .pyc files now, not on first import. Every
            # workflow job imports numpy, pandas, scipy (and matplotlib, papermill);
            # uv writes no .pyc, and where PYTHONDONTWRITEBYTECODE is set Python
            # never does, so each job would compile ~1,700 modules from source
            # (measured: about 60 % of a cold regeneration's CPU time).
            .venv/bin/uv pip sync --compile-bytecode --python .venv/bin/python "${SETUP_LOCKS[@]}"
            .venv/bin/uv pip install --python .venv/bin/python --no-deps --no-build-isolation -e .
        else
            setup_say "uv is not available: installing the same pins with pip (slower)"
            SETUP_ARGS=()
            for lock in "${SETUP_LOCKS[@]}"; do SETUP_ARGS+=(-r "$lock"); done
            .venv/bin/python -m pip install --disable-pip-version-check "${SETUP_ARGS[@]}" >&2
            .venv/bin/python -m pip install --disable-pip-version-check --no-deps \
                --no-build-isolation -e . >&2
        fi
        # shellcheck disable=SC2086  # one argument per extra
        if ! .venv/bin/python workflow/lock_check.py tools $SETUP_EXTRAS; then
            [ "${CI:-}" != true ] || exit 1
        fi
        echo "$SETUP_WANT" > "$STAMP"
        setup_say "done"
    fi
    # A .venv made before --compile-bytecode: compile its packages once. The
    # project's own modules are compiled too (quick when up to date), as
    # Python would on first import unless PYTHONDONTWRITEBYTECODE is set.
    if ! compgen -G ".venv/lib/python3*/site-packages/numpy/__pycache__/__init__.*.pyc" >/dev/null; then
        setup_say "compiling the packages in .venv to bytecode (once)"
        .venv/bin/python -m compileall -q -j 0 .venv/lib/python3*/site-packages >/dev/null || true
    fi
    .venv/bin/python -m compileall -q modal >/dev/null || true
    export PATH="$ROOT/.venv/bin:$PATH"
fi
