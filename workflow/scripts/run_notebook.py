"""Execute the report notebooks with papermill, one kernel for all of them ->
results/notebooks/{name}.ipynb, one executed notebook per chapter.

Starting a kernel and importing the thesis layer and matplotlib in it costs
about as much as a notebook's cells, so one job runs every notebook in one
kernel, in the rule's order: before each notebook the kernel's namespace is
cleared (``%reset -f``), its figures closed, its working directory and its
execution counter reset, so each notebook starts as in a fresh kernel except
that modules are already imported.

papermill writes each executed notebook to its log notebook cell by cell, so
a failing notebook keeps its traceback there; the other notebooks still run,
only complete runs are copied to the outputs, and the job fails if any
notebook did. The kernel is `python3` resolved to this interpreter (the
venv's ipykernel); anything else is refused rather than silently used.
"""
import os
import shutil
import sys
from pathlib import Path

import papermill as pm
from jupyter_client.kernelspec import KernelSpecManager
from jupyter_client.manager import AsyncKernelManager
from nbclient.util import run_sync

from _helpers import mock_snakemake

if "snakemake" not in globals():
    snakemake = mock_snakemake("notebook")
log = open(snakemake.log.text, "w")
# The kernel is a subprocess writing to the inherited file descriptors: on
# shutdown jupyter_client interrupts it first, and it logs "KeyboardInterrupt
# caught in kernel" (harmless). Send descriptors 1 and 2 to the log, not the console.
sys.stdout.flush()
sys.stderr.flush()
os.dup2(log.fileno(), 1)
os.dup2(log.fileno(), 2)
sys.stderr = sys.stdout = log

spec = KernelSpecManager().get_kernel_spec("python3")
exe = spec.argv[0]
# jupyter_client replaces a bare "python"/"python3"/"python3.X" by sys.executable
same = exe in {"python", f"python{sys.version_info[0]}", "python%i.%i" % sys.version_info[:2]} or (
    Path(exe).is_absolute() and Path(exe).resolve() == Path(sys.executable).resolve())
if not same:
    raise RuntimeError(f"kernelspec python3 at {spec.resource_dir} runs {exe!r}, not this interpreter "
                       f"{sys.executable}: install ipykernel in this environment or remove that kernelspec")
print(f"kernel python3: {spec.resource_dir} -> {sys.executable}")

# Run before each notebook, outside its history: a fresh namespace, no open
# figures, the project root as working directory, cell numbers from 1.
RESET = f"""\
get_ipython().run_line_magic("reset", "-f")
import os as _os, sys as _sys
_os.chdir({os.getcwd()!r})
if "matplotlib.pyplot" in _sys.modules:
    _sys.modules["matplotlib.pyplot"].close("all")
get_ipython().execution_count = 1
del _os, _sys
"""


async def reset(km):
    kc = km.client()
    kc.start_channels()
    try:
        await kc.wait_for_ready(timeout=60)
        reply = await kc.execute_interactive(RESET, store_history=False, timeout=60)
        if reply["content"]["status"] != "ok":
            raise RuntimeError(f"resetting the kernel failed: {reply['content']}")
    finally:
        kc.stop_channels()


names = snakemake.params.names
km = AsyncKernelManager(kernel_name="python3")
run_sync(km.start_kernel)(cwd=os.getcwd(), extra_arguments=["--HistoryManager.hist_file=:memory:"])
failed = []
try:
    for name, source, executed, output in zip(names, snakemake.input.notebooks, snakemake.log.notebooks,
                                              snakemake.output):
        run_sync(reset)(km)
        declared = pm.inspect_notebook(source)
        parameters = {k: v for k, v in snakemake.params.parameters[name].items() if k in declared}
        print(f"{name}: parameters: {parameters}", flush=True)
        try:
            pm.execute_notebook(source, executed, parameters=parameters, kernel_name="python3", language="python",
                                cwd=os.getcwd(), progress_bar=False, log_output=False, execution_timeout=600,
                                km=km)
        except pm.PapermillExecutionError as error:
            print(f"{name}: FAILED, traceback in {executed}\n{error}", flush=True)
            failed.append(name)
            continue
        shutil.copyfile(executed, output)
finally:
    run_sync(km.shutdown_kernel)(now=True)
if failed:
    raise RuntimeError(f"notebooks failed: {', '.join(failed)} (tracebacks in {snakemake.log.notebooks})")
