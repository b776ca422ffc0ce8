"""Execute the report notebooks with papermill, in as many kernels as the job
has threads -> results/notebooks/{name}.ipynb, one executed notebook per chapter.

Starting a kernel and importing the thesis layer and matplotlib in it costs
about as much as a notebook's cells, so one job runs every notebook, in
``threads`` kernels side by side (each single-threaded, driven by its own
forked process: papermill is not made for threads): every kernel takes the
next notebook of ``params.order`` (longest first, so the kernels finish
together) until none is left. Before each notebook its kernel's namespace is
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
import multiprocessing
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


notebooks = {name: (source, executed, output) for name, source, executed, output in
             zip(snakemake.params.names, snakemake.input.notebooks, snakemake.log.notebooks, snakemake.output)}
order = snakemake.params.order
if sorted(order) != sorted(notebooks):
    raise ValueError(f"params.order {order} must list the notebooks {list(notebooks)} once each")
for output in snakemake.output:  # a notebook succeeded when its output exists
    Path(output).unlink(missing_ok=True)
# Each kernel single-threaded: the job's threads are its kernels.
KERNEL_ENV = {**os.environ, **{v: "1" for v in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS")}}
fork = multiprocessing.get_context("fork")
taken = fork.Value("i", 0)  # how many notebooks of `order` the kernels have taken


def next_notebook():
    with taken.get_lock():
        taken.value += 1
        return order[taken.value - 1] if taken.value <= len(order) else None


def execute(km, name):
    """Execute notebook ``name`` in the kernel of ``km``; its output only if it succeeds."""
    source, executed, output = notebooks[name]
    run_sync(reset)(km)
    declared = pm.inspect_notebook(source)
    parameters = {k: v for k, v in snakemake.params.parameters[name].items() if k in declared}
    print(f"{name}: parameters: {parameters}", flush=True)
    try:
        pm.execute_notebook(source, executed, parameters=parameters, kernel_name="python3", language="python",
                            cwd=os.getcwd(), progress_bar=False, log_output=False, execution_timeout=600, km=km)
    except pm.PapermillExecutionError as error:
        print(f"{name}: FAILED, traceback in {executed}\n{error}", flush=True)
        return
    shutil.copyfile(executed, output)


def kernel_worker():
    """One kernel, run from a forked process: the next notebook until none is left."""
    km = AsyncKernelManager(kernel_name="python3")
    run_sync(km.start_kernel)(cwd=os.getcwd(), env=KERNEL_ENV,
                              extra_arguments=["--HistoryManager.hist_file=:memory:"])
    try:
        while (name := next_notebook()) is not None:
            execute(km, name)
    finally:
        run_sync(km.shutdown_kernel)(now=True)


sys.stdout.flush()
workers = [fork.Process(target=kernel_worker) for _ in range(min(snakemake.threads, len(order)))]
for worker in workers:
    worker.start()
for worker in workers:
    worker.join()
failed = [name for name, (_, _, output) in notebooks.items() if not os.path.exists(output)]
if failed:
    raise RuntimeError(f"notebooks failed: {', '.join(failed)} (tracebacks in {snakemake.log.notebooks})")
