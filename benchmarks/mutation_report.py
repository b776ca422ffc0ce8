"""Kill rate of a mutmut run, over the mutants not judged equivalent.

    python benchmarks/mutation_report.py RESULTS SURVIVORS_MD

``RESULTS`` is the output of ``mutmut results --all true`` (one
``name: status`` line per mutant). ``SURVIVORS_MD`` is
``benchmarks/mutation_survivors.md``: each table row whose first cell is a
mutant name in backticks and whose second cell starts with ``equivalent``
marks that mutant equivalent. Killed means detected by the tests: killed,
timeout or segfault (a mutant that hangs or crashes the interpreter is caught
too). Exits 1 when fewer than 90 % of the non-equivalent mutants are killed,
or when a survivor is not listed in ``SURVIVORS_MD`` (mutant names change
when an engine module changes: re-judge the survivors then).
"""

from __future__ import annotations

import re
import sys
from collections import Counter
from pathlib import Path

TARGET = 0.90
DETECTED = {"killed", "timeout", "segfault"}
ROW = re.compile(r"^\|\s*`([^`]+)`\s*\|\s*([a-z ]+?)\s*[|(:]")


def statuses(results: str) -> dict[str, str]:
    out = {}
    for line in results.splitlines():
        name, sep, status = line.strip().partition(": ")
        if sep:
            out[name] = status.strip()
    return out


def verdicts(survivors_md: str) -> dict[str, str]:
    """Mutant name -> verdict ("equivalent" or "gap") from the survivors table."""
    out = {}
    for line in survivors_md.splitlines():
        match = ROW.match(line)
        if match:
            out[match.group(1)] = match.group(2).strip()
    return out


def main(results_path: str, survivors_path: str) -> int:
    status = statuses(Path(results_path).read_text())
    verdict = verdicts(Path(survivors_path).read_text()) if Path(survivors_path).exists() else {}
    counts = Counter(status.values())
    total = len(status)
    detected = sum(counts[s] for s in DETECTED)
    undetected = sorted(name for name, s in status.items() if s not in DETECTED)
    equivalent = [name for name in undetected if verdict.get(name) == "equivalent"]
    unjudged = [name for name in undetected if name not in verdict]
    judged = total - len(equivalent)
    rate = detected / judged if judged else float("nan")

    print(f"mutants: {total}  ({', '.join(f'{k} {v}' for k, v in sorted(counts.items()))})")
    print(f"killed (incl. timeouts): {detected}")
    print(f"not killed: {len(undetected)}  (equivalent {len(equivalent)}, real gaps {len(undetected) - len(equivalent)})")
    print(f"kill rate of non-equivalent mutants: {detected}/{judged} = {100 * rate:.1f} %  (target {100 * TARGET:.0f} %)")
    print(f"kill rate of all mutants: {detected}/{total} = {100 * detected / total:.1f} %")
    if unjudged:
        print(f"\n{len(unjudged)} survivor(s) not judged in {survivors_path}:")
        for name in unjudged:
            print(f"  {name}: {status[name]}   (mutmut show {name})")
    return 0 if rate >= TARGET and not unjudged else 1


if __name__ == "__main__":
    sys.exit(main(*sys.argv[1:3]))
