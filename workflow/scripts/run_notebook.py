"""Execute one report notebook with papermill -> results/notebooks/{name}.ipynb.

papermill writes the executed notebook to the log notebook cell by cell, so a
failing notebook keeps its traceback there; only a complete run is copied to
the output. The kernel is `python3` resolved to this interpreter (the venv's
ipykernel); anything else is refused rather than silently used. Each notebook
gets the parameters its tagged ``parameters`` cell declares.
"""
import os
import shutil
import sys
from pathlib import Path

import papermill as pm
from jupyter_client.kernelspec import KernelSpecManager

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

source, executed, output = snakemake.input.notebook, snakemake.log.notebook, snakemake.output[0]
declared = pm.inspect_notebook(source)
parameters = {k: v for k, v in snakemake.params.parameters.items() if k in declared}
print(f"parameters: {parameters}", flush=True)
pm.execute_notebook(source, executed, parameters=parameters, kernel_name="python3", language="python",
                    cwd=os.getcwd(), progress_bar=False, log_output=False, execution_timeout=600)
shutil.copyfile(executed, output)
