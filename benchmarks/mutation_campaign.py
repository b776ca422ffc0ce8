"""Mutation run of the campaign's pure parts against fast tests (issue 34).

    .venv/bin/python benchmarks/mutation_campaign.py            # all mutants, 2 at a time
    .venv/bin/python benchmarks/mutation_campaign.py --list     # the mutants only, no test run
    .venv/bin/python benchmarks/mutation_campaign.py --only _jobs.py --workers 1
    .venv/bin/python benchmarks/mutation_campaign.py --only _config.py --within _geometry,campaign_inputs

Modules: ``modal/campaign/_config.py``, ``_jobs.py``, the
``overlapping_input`` of ``modal/measured/_output.py`` (the
campaign's ``--out`` check), ``modal/_hashes.py`` (the
campaign's content hashes), ``modal/_locks.py``, ``_tracking.py``,
``_run.py`` and the pure parts of ``_report.py`` (its numbers and the data
its pictures are made from, not the drawing calls); the simulation is not
mutated here. Each mutant is
one systematic edit of the source, made with :mod:`ast` on a copy of the
tree (never in the checkout): a comparison flipped (``==``/``!=``,
``<``/``<=``, ``in``/``not in``, ``is``/``is not``), ``and``/``or``
swapped, a ``not`` dropped, an ``if`` negated, an arithmetic operator
swapped, a constant changed (numbers +1, ``True``/``False``, strings
``"XX...XX"``), a call's first two arguments swapped, a keyword argument
dropped, a no-argument method call dropped (``p.resolve()`` -> ``p``), a
statement removed (a call, a ``raise``, a ``continue``/``break`` swapped),
an assigned value or a returned one replaced by ``None``. Docstrings,
imports and annotations (not evaluated: ``from __future__ import
annotations``) are not mutated; nor are f-strings' insides.

The tests (``TESTS``, by module) are the fast ones: no Snakemake run. A forked child
per mutant runs them with ``-x -q -p no:cacheprovider`` and a timeout, in
its own copy of the tree, after the parent has imported the heavy
dependencies once. A mutant is killed when the tests fail, time out or cannot start (a
mutant that breaks the import).
Survivors judged equivalent, with the reason, are listed in
``benchmarks/mutation_campaign_equivalent.txt`` (``key<TAB>reason``); the
kill rate is over the others.
"""

from __future__ import annotations

import argparse
import ast
import json
import os
import shutil
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

TARGETS = [  # (path, function or None for the whole module)
    ("modal/campaign/_config.py", None),
    ("modal/campaign/_jobs.py", None),
    ("modal/_hashes.py", None),
    ("modal/measured/_output.py", "overlapping_input"),  # the campaign's --out check (moved there, issue 33)
    ("modal/_locks.py", None),
    ("modal/campaign/_tracking.py", None),
    # the report's numbers and the data its pictures are made from, not the drawing calls
    ("modal/campaign/_report.py", "_colour"),
    ("modal/campaign/_report.py", "_interval"),
    ("modal/campaign/_report.py", "mode_summary"),
    ("modal/campaign/_report.py", "drawn_shapes"),
    ("modal/campaign/_report.py", "_phi"),
    ("modal/campaign/_report.py", "shapes_figure"),
    ("modal/campaign/_run.py", None),
]

UNITS = "tests/workflow/test_campaign_units.py::"
CAMPAIGN = "tests/workflow/test_campaign.py::"
UNATTENDED = "tests/workflow/test_campaign_unattended.py::"
OPTIONS = "tests/engine/measured/test_options.py::"
TRACKING = "tests/workflow/test_campaign_tracking.py::"
TESTS = {  # by target: the fast tests that reach it, the quickest first
    "_config.py": [UNITS + t for t in (
        "test_a_campaign_read_with_its_defaults_and_layout",
        "test_settings_at_their_bounds_are_taken_beyond_them_refused",
        "test_a_campaign_that_cannot_be_read_says_why", "test_the_index_refusals_name_the_row",
        "test_a_campaign_named_by_a_relative_path_is_named_in_full",
        "test_records_at_one_time_are_in_name_order_and_the_layout_skips_what_does_not_read",
        "test_glob_refusals_and_names", "test_chunks_are_consecutive_and_named_by_number",
        "test_a_geometry_is_read_with_its_channel_table",
        "test_a_geometry_that_names_the_sensors_needs_no_channel_table",
        "test_geometry_refusals_name_the_key_and_the_file")] + [
        CAMPAIGN + "test_campaign_file_refusals", CAMPAIGN + "test_glob_with_times_in_the_names",
        UNATTENDED + "test_the_index_is_data", UNATTENDED + "test_the_campaign_file_is_data",
        OPTIONS + "test_the_campaign_schema_is_the_options_schema",
        OPTIONS + "test_each_option_in_a_campaign_file_reaches_identify_record"],
    "_jobs.py": [UNITS + t for t in (
        "test_a_failure_reason_is_one_line", "test_gather_reads_every_chunk_in_order",
        "test_shapes_are_channels_by_modes_in_channel_order", "test_a_chunk_writes_each_mode_and_each_failure",
        "test_each_warning_of_a_record_is_one_line_in_the_jobs_log", "test_a_chunk_keeps_the_trusted_modes_only",
        "test_a_record_in_other_units_fails_naming_them",
        "test_the_rate_is_compared_to_one_part_in_a_billion")] + [
        OPTIONS + "test_each_option_in_a_campaign_file_reaches_identify_record"],
    "_hashes.py": [UNITS + "test_a_file_hash_is_the_sha256_of_all_its_bytes",
                   UNITS + "test_the_cache_is_trusted_while_the_status_is_unchanged",
                   UNATTENDED + "test_content_hashes_see_a_rewrite_that_keeps_size_and_time"],
    "_output.py": [UNITS + "test_an_output_folder_overlapping_an_input_says_how",
                     UNATTENDED + "test_an_output_folder_over_the_inputs_is_refused"],
    "_locks.py": [UNITS + t for t in (
        "test_stale_locks_are_listed_and_cleared", "test_live_snakemake_processes_are_those_working_here",
        "test_a_command_line_that_is_not_utf8_is_read", "test_the_caller_and_its_parent_are_not_a_run",
        "test_a_left_run_that_does_not_stop_on_sigint_is_returned_alive",
        "test_a_run_left_working_in_the_folder_is_stopped_with_its_jobs_and_nothing_else",
        "test_without_proc_a_left_run_cannot_be_seen_and_nothing_is_signalled",
        "test_a_process_is_alive_until_it_ends_a_zombie_or_reaped")] + [
        "tests/workflow/test_strict.py::test_stale_lock_is_cleared_and_live_run_is_reported"],
    "_tracking.py": [UNITS + "test_the_track_step_writes_every_table"] + [TRACKING + t for t in (
        "test_the_assignment_takes_the_larger_mac", "test_crossing_modes_give_two_references_with_their_own_shapes",
        "test_a_mode_replaced_by_another_shape_at_its_frequency_is_another_reference",
        "test_close_modes_of_similar_shape_seen_together_stay_two",
        "test_the_observed_range_follows_the_reference_shape_only",
        "test_given_references_follow_a_drift_beyond_freq_rtol",
        "test_a_shape_that_matches_no_reference_stays_untracked",
        "test_reference_modes_are_read_renumbered_by_frequency",
        "test_neighbours_are_pairs_within_both_gates_with_their_distance",
        "test_the_medoid_is_the_shape_closest_to_the_others_even_the_last",
        "test_a_mode_in_min_share_of_the_records_is_a_reference_and_empty_results_have_the_columns",
        "test_split_clusters_join_within_the_frequency_margin_bounds_included",
        "test_split_clusters_join_by_shape_and_shared_records_largest_first",
        "test_observed_ranges_bounds_defaults_and_each_reference",
        "test_tracking_gates_include_their_bounds_and_mac_decides_before_frequency",
        "test_tracking_refuses_other_channels_and_returns_its_own_tables",
        "test_large_campaigns_are_clustered_on_a_sample_of_records",
        "test_the_reference_shape_is_the_medoid_of_at_most_400_evenly_spread",
        "test_a_rarer_first_cluster_does_not_hide_the_next")
    ] + [CAMPAIGN + "test_tracking_is_one_to_one_and_gated",
         UNITS + "test_tracked_shapes_are_each_modes_aligned_mean_drawn_in_si_on_its_nodes"],
    "_report.py": [TRACKING + "test_the_report_summary_per_reference_mode",
                   UNITS + "test_tracked_shapes_are_each_modes_aligned_mean_drawn_in_si_on_its_nodes",
                   TRACKING + "test_report_bars_are_clipped_at_zero_and_damping_is_in_percent",
                   UNITS + "test_the_report_step_reads_the_tables_and_draws_the_shapes_given_a_geometry"],
    "_run.py": [UNITS + t for t in (
        "test_the_track_step_writes_every_table",
        "test_the_track_step_takes_given_references_with_their_observed_range",
        "test_the_report_step_reads_the_tables_and_draws_the_shapes_given_a_geometry")],
}


def tests_for(path: str | None) -> list[str]:
    if path is None:  # the baseline: all of them
        return list(dict.fromkeys(t for tests in TESTS.values() for t in tests))
    return TESTS[Path(path).name]


EQUIVALENT = ROOT / "benchmarks" / "mutation_campaign_equivalent.txt"

COMPARE = {ast.Eq: ast.NotEq, ast.NotEq: ast.Eq, ast.Lt: ast.LtE, ast.LtE: ast.Lt, ast.Gt: ast.GtE,
           ast.GtE: ast.Gt, ast.In: ast.NotIn, ast.NotIn: ast.In, ast.Is: ast.IsNot, ast.IsNot: ast.Is}
BINARY = {ast.Add: ast.Sub, ast.Sub: ast.Add, ast.Mult: ast.Div, ast.Div: ast.Mult, ast.FloorDiv: ast.Div,
          ast.Mod: ast.FloorDiv, ast.LShift: ast.RShift, ast.RShift: ast.LShift, ast.BitOr: ast.BitAnd,
          ast.BitAnd: ast.BitOr, ast.Pow: ast.Mult}


# -- mutants -----------------------------------------------------------------

def _skipped(tree) -> set[int]:
    """ids of nodes never mutated: docstrings, imports, annotations, f-strings."""
    skip = set()

    def all_of(node):
        skip.update(id(n) for n in ast.walk(node))

    for node in ast.walk(tree):
        body = getattr(node, "body", None)
        if isinstance(body, list) and body and isinstance(body[0], ast.Expr) \
                and isinstance(body[0].value, ast.Constant) and isinstance(body[0].value.value, str):
            all_of(body[0])
        if isinstance(node, (ast.Import, ast.ImportFrom, ast.JoinedStr)):
            all_of(node)
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
            if node.returns is not None:
                all_of(node.returns)
            for arg in node.args.args + node.args.kwonlyargs + node.args.posonlyargs:
                if arg.annotation is not None:
                    all_of(arg.annotation)
        if isinstance(node, ast.AnnAssign):
            all_of(node.annotation)
    return skip


def _replacements(node, parents):
    """(description, node to replace, replacement source) for one node."""
    out = []

    def expr(new):
        return "(" + ast.unparse(new) + ")"

    if isinstance(node, ast.Compare):
        for k, op in enumerate(node.ops):
            if type(op) in COMPARE:
                new = ast.Compare(node.left, node.ops[:k] + [COMPARE[type(op)]()] + node.ops[k + 1:],
                                  node.comparators)
                out.append(("compare", node, expr(new)))
    elif isinstance(node, ast.BoolOp):
        new = ast.BoolOp(ast.Or() if isinstance(node.op, ast.And) else ast.And(), node.values)
        out.append(("and/or", node, expr(new)))
    elif isinstance(node, ast.UnaryOp) and isinstance(node.op, (ast.Not, ast.USub)):
        out.append(("drop unary", node, expr(node.operand)))
    elif isinstance(node, ast.BinOp) and type(node.op) in BINARY:
        out.append(("arithmetic", node, expr(ast.BinOp(node.left, BINARY[type(node.op)](), node.right))))
    elif isinstance(node, ast.Constant):
        value = node.value
        if isinstance(value, bool):
            out.append(("boolean", node, repr(not value)))
        elif isinstance(value, (int, float)):
            out.append(("number", node, repr(value + 1)))
        elif isinstance(value, str):
            out.append(("string", node, repr("XX" + value + "XX")))
        elif isinstance(value, bytes):
            out.append(("bytes", node, repr(b"XX" + value + b"XX")))
    elif isinstance(node, ast.Call):
        positional = [a for a in node.args if not isinstance(a, ast.Starred)]
        if len(positional) >= 2 and len(positional) == len(node.args):
            args = [node.args[1], node.args[0]] + node.args[2:]
            out.append(("swap arguments", node, expr(ast.Call(node.func, args, node.keywords))))
        for k, kw in enumerate(node.keywords):
            if kw.arg is not None:
                out.append((f"drop keyword {kw.arg}", node,
                            expr(ast.Call(node.func, node.args, node.keywords[:k] + node.keywords[k + 1:]))))
        if isinstance(node.func, ast.Attribute) and not node.args and not node.keywords \
                and not isinstance(parents.get(id(node)), ast.Expr):
            out.append(("drop method call", node, expr(node.func.value)))
    if isinstance(node, ast.If) and not isinstance(node.test, ast.Compare):
        out.append(("negate if", node.test, expr(ast.UnaryOp(ast.Not(), node.test))))
    elif isinstance(node, ast.Expr) and isinstance(node.value, ast.Call):
        out.append(("remove call", node, "pass"))
    elif isinstance(node, ast.Raise):
        out.append(("remove raise", node, "pass"))
    elif isinstance(node, ast.Continue):
        out.append(("continue->break", node, "break"))
    elif isinstance(node, ast.Break):
        out.append(("break->continue", node, "continue"))
    elif isinstance(node, ast.Return) and node.value is not None \
            and not (isinstance(node.value, ast.Constant) and node.value.value is None):
        out.append(("return None", node.value, "None"))
    elif isinstance(node, (ast.Assign, ast.AugAssign, ast.AnnAssign)) and node.value is not None \
            and not (isinstance(node.value, ast.Constant) and node.value.value is None):
        out.append(("assign None", node.value, "None"))
    return out


def mutants(path: str, function: str | None) -> list[dict]:
    """Every mutant of ``path`` (within ``function`` if given): key, line,
    the original and mutated line, the whole mutated source."""
    source = (ROOT / path).read_text()
    raw = source.encode()
    starts = [0]
    for line in raw.splitlines(keepends=True):
        starts.append(starts[-1] + len(line))
    tree = ast.parse(source)
    scope = tree
    if function is not None:
        scope = next(n for n in ast.walk(tree) if isinstance(n, ast.FunctionDef) and n.name == function)
    skip = _skipped(tree)
    parents = {id(child): node for node in ast.walk(tree) for child in ast.iter_child_nodes(node)}
    functions = {}
    for node in ast.walk(tree):
        if isinstance(node, ast.FunctionDef):
            for inner in ast.walk(node):
                functions.setdefault(id(inner), node.name)
    found, seen = [], {}
    for node in ast.walk(scope):
        if id(node) in skip:
            continue
        for op, target, text in _replacements(node, parents):
            if id(target) in skip:
                continue
            a = starts[target.lineno - 1] + target.col_offset
            b = starts[target.end_lineno - 1] + target.end_col_offset
            original = raw[a:b].decode()
            mutated = (raw[:a] + text.encode() + raw[b:]).decode()
            try:
                if ast.dump(ast.parse(mutated)) == ast.dump(tree):
                    continue
                compile(mutated, path, "exec")
            except SyntaxError:
                continue
            where = functions.get(id(target), "<module>")
            base = f"{path}::{where}::{op}: {' '.join(original.split())[:80]} -> {' '.join(text.split())[:80]}"
            seen[base] = seen.get(base, 0) + 1
            key = base if seen[base] == 1 else f"{base} #{seen[base]}"
            found.append({"key": key, "path": path, "line": target.lineno, "op": op, "source": mutated})
    found.sort(key=lambda m: (m["path"], m["line"], m["key"]))
    return found


# -- running -----------------------------------------------------------------

def copy_tree(dest: Path) -> None:
    """The checkout's files (tracked and untracked, not ignored) into ``dest``."""
    listed = subprocess.run(["git", "ls-files", "-co", "--exclude-standard", "-z"], cwd=ROOT, check=True,
                            capture_output=True).stdout.decode().split("\0")
    for name in filter(None, listed):
        src = ROOT / name
        if src.is_file() and not name.startswith(("mutants/", ".venv/")):
            (dest / name).parent.mkdir(parents=True, exist_ok=True)
            shutil.copy2(src, dest / name)


def run_child(tree: Path, log: Path, tests: list[str]) -> int:
    """In a forked child: the tests on ``tree``'s package; never returns."""
    fd = os.open(log, os.O_WRONLY | os.O_CREAT | os.O_TRUNC)
    os.dup2(fd, 1)
    os.dup2(fd, 2)
    os.setpgid(0, 0)
    os.chdir(tree)
    os.environ["PYTHONPATH"] = str(tree)
    sys.path.insert(0, str(tree))
    import pytest

    # hypothesis (a pytest plugin) is preloaded: pytest may not rewrite its asserts
    code = pytest.main(["-x", "-q", "-p", "no:cacheprovider", "-W", "ignore::pytest.PytestAssertRewriteWarning",
                        "--rootdir", str(tree),
                        *tests])
    sys.stdout.flush()
    sys.stderr.flush()
    os._exit(int(code))


def preload() -> None:
    """The heavy dependencies, once in the parent (the children fork from
    it); ``modal`` itself never: each child imports its mutated copy."""
    import jsonschema  # noqa: F401
    import numpy  # noqa: F401
    import pandas  # noqa: F401
    import pytest  # noqa: F401
    import scipy.linalg  # noqa: F401
    import scipy.signal  # noqa: F401
    import yaml  # noqa: F401
    for name in ("dateutil", "pygments", "matplotlib", "hypothesis"):
        try:
            __import__(name)
        except ImportError:
            pass
    try:
        import pyuff  # noqa: F401
    except ImportError:
        pass
    assert not any(m == "modal" or m.startswith("modal.") for m in sys.modules)


def run(all_mutants, workers: int, timeout: float, work: Path) -> dict[str, str]:
    preload()
    slots = []
    for k in range(workers):
        tree = work / f"tree{k}"
        copy_tree(tree)
        slots.append({"tree": tree, "pid": None, "mutant": None, "started": 0.0, "written": None})
    originals = {m["path"]: (ROOT / m["path"]).read_text() for m in all_mutants}
    verdicts = {}

    def forget(tree, path):
        """The compiled copies of ``path``: a mutant of the same size written
        within a second of the last would pass their (mtime, size) check.
        The tests' own (assertion-rewritten) stay cached: they never change."""
        for pyc in (tree / path).parent.glob(f"__pycache__/{Path(path).stem}.*.pyc"):
            pyc.unlink()

    def launch(slot, mutant):
        for path in {slot["written"], mutant["path"]} - {None}:
            forget(slot["tree"], path)
        if slot["written"]:
            (slot["tree"] / slot["written"]).write_text(originals[slot["written"]])
            slot["written"] = None
        if mutant["path"]:
            (slot["tree"] / mutant["path"]).write_text(mutant["source"])
            slot["written"] = mutant["path"]
        pid = os.fork()
        if pid == 0:
            try:
                run_child(slot["tree"], work / f"log{slots.index(slot)}.txt", tests_for(mutant["path"]))
            except BaseException:
                import traceback
                traceback.print_exc()
            finally:
                os._exit(99)
        slot.update(pid=pid, mutant=mutant, started=time.monotonic())

    # the unmutated tree first: the tests must pass on it
    for k, slot in enumerate(slots):
        launch(slot, {"key": "(baseline)", "path": None})
        code = os.waitstatus_to_exitcode(os.waitpid(slot["pid"], 0)[1])
        slot.update(pid=None, mutant=None)
        if code != 0:
            sys.exit(f"the tests fail on the unmutated tree (exit {code}):\n"
                     f"{(work / f'log{k}.txt').read_text()[-3000:]}")
    queue = list(all_mutants)
    done = 0
    started = time.monotonic()
    while queue or any(s["pid"] for s in slots):
        for slot in slots:
            if slot["pid"] is None and queue:
                launch(slot, queue.pop(0))
        time.sleep(0.05)
        for slot in slots:
            if slot["pid"] is None:
                continue
            pid, status = os.waitpid(slot["pid"], os.WNOHANG)
            timed_out = pid == 0 and time.monotonic() - slot["started"] > timeout
            if timed_out:
                os.killpg(slot["pid"], signal.SIGKILL)
                os.waitpid(slot["pid"], 0)
            elif pid == 0:
                continue
            code = None if timed_out else os.waitstatus_to_exitcode(status)
            key = slot["mutant"]["key"]
            verdicts[key] = "timeout" if timed_out else ("survived" if code == 0 else
                                                         "killed" if code == 1 else f"error {code}")
            done += 1
            if verdicts[key] != "killed":
                print(f"  {verdicts[key]}: {key}", flush=True)
            if done % 25 == 0:
                print(f"{done}/{len(all_mutants)} in {time.monotonic() - started:.0f} s", flush=True)
            slot.update(pid=None, mutant=None)
    return verdicts


def equivalent() -> dict[str, str]:
    if not EQUIVALENT.exists():
        return {}
    pairs = (line.split("\t", 1) for line in EQUIVALENT.read_text().splitlines()
             if line.strip() and not line.startswith("#"))
    return {k: v for k, v in pairs}


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--timeout", type=float, default=60.0, help="seconds per mutant (default 60)")
    parser.add_argument("--only", help="mutate only the target whose path ends with this")
    parser.add_argument("--within", help="mutate only within these functions (comma-separated names; "
                        "<module> for module-level code)")
    parser.add_argument("--list", action="store_true", help="list the mutants, run nothing")
    parser.add_argument("--json", type=Path, help="write each mutant's verdict here")
    parser.add_argument("--again", type=Path, metavar="JSON",
                        help="run only the mutants not killed in this earlier --json (after adding tests)")
    args = parser.parse_args(argv)
    all_mutants = [m for path, function in TARGETS if not args.only or path.endswith(args.only)
                   for m in mutants(path, function)]
    if args.within:
        names = set(args.within.split(","))
        all_mutants = [m for m in all_mutants if m["key"].split("::")[1] in names]
    if args.again:
        before = json.loads(args.again.read_text())
        all_mutants = [m for m in all_mutants if before.get(m["key"], "survived") == "survived"]
    if args.list:
        for m in all_mutants:
            print(f"{m['line']:4d}  {m['key']}")
        print(f"{len(all_mutants)} mutants")
        return 0
    os.environ.setdefault("OMP_NUM_THREADS", "1")
    os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
    started = time.monotonic()
    with tempfile.TemporaryDirectory(prefix="mutation_campaign_") as work:
        verdicts = run(all_mutants, args.workers, args.timeout, Path(work))
    known = equivalent()
    survivors = [k for k, v in verdicts.items() if v in ("survived", )]
    errors = [k for k, v in verdicts.items() if v.startswith("error")]  # the tests could not even start
    killed = sum(v != "survived" for v in verdicts.values())
    eq = [k for k in survivors if k in known]
    gaps = [k for k in survivors if k not in known]
    stale = sorted(set(known) - set(survivors))
    counted = len(verdicts) - len(eq)
    if args.json:
        args.json.write_text(json.dumps(verdicts, indent=1))
    print(f"\n{len(verdicts)} mutants in {time.monotonic() - started:.0f} s: {killed} killed "
          f"({sum(v == 'timeout' for v in verdicts.values())} by the timeout, {len(errors)} by an error before "
          f"any test ran, e.g. at import), {len(eq)} equivalent ({EQUIVALENT.relative_to(ROOT)}), "
          f"{len(gaps)} survived")
    print(f"killed {killed} of {counted} non-equivalent mutants: {100 * killed / max(counted, 1):.1f} %")
    for k in gaps:
        print(f"  survived: {k}")
    for k in stale:
        if k in verdicts:
            print(f"  listed as equivalent but {verdicts[k]}: {k}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
