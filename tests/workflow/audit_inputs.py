"""Run one workflow script by hand (mock_snakemake) and list every project file
it opens for reading that its rule does not declare (as an input, output or
log). Used by tests/workflow/test_strict.py; run from the project root:
``python audit_inputs.py RULE [key=value ...] [--configfile FILE]``."""

import runpy
import sys
from pathlib import Path

ROOT = Path.cwd().resolve()
sys.path.insert(0, str(ROOT / "workflow/scripts"))
from _helpers import mock_snakemake  # noqa: E402

rule, *rest = sys.argv[1:]
configfiles = [a.split("=", 1)[1] for a in rest if a.startswith("--configfile=")]
wildcards = dict(a.split("=", 1) for a in rest if not a.startswith("--"))
smk = mock_snakemake(rule, configfiles=configfiles, **wildcards)
declared = {Path(p).resolve() for p in [*smk.input, *smk.output, *smk.log]}
undeclared = set()
WATCHED = ("results", "config", "data", "notebooks")


def hook(event, args):
    if event != "open" or not isinstance(args[0], (str, Path)):
        return
    mode = args[1] if len(args) > 1 and isinstance(args[1], str) else "r"
    path = Path(args[0]).resolve()
    try:
        top = path.relative_to(ROOT).parts[0]
    except (ValueError, IndexError):
        return
    if top in WATCHED and "r" in mode and "+" not in mode and path not in declared and path.is_file():
        undeclared.add(str(path.relative_to(ROOT)))


sys.addaudithook(hook)
runpy.run_path(str(ROOT / f"workflow/scripts/{smk.rule}.py"), init_globals={"snakemake": smk})
print("UNDECLARED:" + ",".join(sorted(undeclared)))
