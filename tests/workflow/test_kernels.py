"""Committed tables on any CPU: the small config regenerated under two
OpenBLAS kernels writes the same bytes to ``results/tables`` (the precision
rule of ``modal.thesis.precision``).

OpenBLAS picks its kernels for the CPU at run time; ``OPENBLAS_CORETYPE``
forces one. The first run keeps the environment as it is (whatever kernel
this machine runs, including one the machine's setup forces); the second
forces an older kernel that every x86-64 CPU runs. A machine on which no
second kernel can be had fails the test with the reason: a skip would hide
that the check did not run.
"""

import os
import subprocess
import sys

import pytest

from workflow_run import SMALL_CONFIG_FILE, copy_project

pytestmark = pytest.mark.slow

#: Kernels for the second run, oldest first: generic x86-64 ones (OpenBLAS
#: names; "Prescott" runs as its Katmai kernel), safe on any x86-64 CPU.
SECOND_KERNELS = ("Prescott", "Nehalem", "SandyBridge")

#: Every writer of a committed table: the beam and grid tables (table, grid_table),
#: the CERA sensitivity, the claims, the searches and the summary.
TARGETS = [f"results/tables/table_{n:02d}.{ext}" for n in range(1, 16) for ext in ("csv", "md")] + [
    f"results/tables/{name}.csv" for name in ("cera_sensitivity", "claims", "searches", "summary")]


def kernel_in_effect(env) -> str:
    """The OpenBLAS kernel (threadpoolctl's ``architecture``) numpy runs with ``env``."""
    code = ("import threadpoolctl, numpy\n"
            "print(next((p.get('architecture') or '?' for p in threadpoolctl.threadpool_info()"
            " if p['internal_api'] == 'openblas'), 'no OpenBLAS'))")
    done = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, timeout=120)
    return done.stdout.strip() if done.returncode == 0 else f"failed: {done.stderr.strip()[-300:]}"


def two_kernels() -> list[tuple[dict, str]]:
    """``[(env, kernel), (env, kernel)]``: this machine's environment and one
    forcing another kernel; fails the test when there is no second one."""
    first_env = dict(os.environ)
    first = kernel_in_effect(first_env)
    tried = []
    for coretype in SECOND_KERNELS:
        env = dict(os.environ, OPENBLAS_CORETYPE=coretype)
        kernel = kernel_in_effect(env)
        tried.append(f"{coretype} -> {kernel}")
        if kernel != first and not kernel.startswith(("failed", "no OpenBLAS")):
            return [(first_env, first), (env, kernel)]
    pytest.fail(f"cannot run two OpenBLAS kernels here: this machine runs {first!r}; forcing OPENBLAS_CORETYPE "
                f"gave {', '.join(tried)}. The byte-stability of results/tables across CPUs is not checked.")


def regenerate(work, env) -> dict:
    """The small config's committed-table files regenerated in ``work`` with ``env``: name -> bytes."""
    # the targets before --configfile, which takes every argument after it
    proc = subprocess.run([sys.executable, "-m", "snakemake", "--cores", "2", *TARGETS, "--configfile",
                           SMALL_CONFIG_FILE], cwd=work, env=env, capture_output=True, text=True, timeout=1800)
    assert proc.returncode == 0, f"snakemake failed:\n{proc.stdout[-3000:]}\n{proc.stderr[-3000:]}"
    return {p.name: p.read_bytes() for p in sorted((work / "results/tables").iterdir())}


def test_committed_tables_are_byte_identical_under_two_blas_kernels(tmp_path, small_workflow):
    """The session's run of the small config (this machine's environment) is
    the first kernel's; the second runs in a copy of its own."""
    (env_a, kernel_a), (env_b, kernel_b) = two_kernels()
    a = {p.name: p.read_bytes() for p in sorted((small_workflow / "results/tables").iterdir())}
    b = regenerate(copy_project(tmp_path / "b"), env_b)
    assert {p.rsplit("/", 1)[1] for p in TARGETS} <= set(a)
    assert set(a) == set(b)
    changed = sorted(name for name in a if a[name] != b[name])
    assert not changed, f"results/tables differ between the {kernel_a} and {kernel_b} kernels: {changed}"
