# Report notebooks (papermill) and the reproduction report (one HTML file).
#
# Each notebook reads the workflow's outputs and displays them; it computes
# nothing the engine computes (summary verdicts come from modal.thesis.report).
# Inputs are the files each notebook reads, so a changed table re-executes
# only the notebooks that show it. The file lists (NOTEBOOKS, notebook_inputs,
# report_outputs, ...) live in common.smk: snakemake --lint wants rules and
# functions in separate files.


rule notebook:
    input:
        ENGINE,
        CAPTIONS,
        data=lambda w: notebook_inputs(w.name),
        notebook="notebooks/{name}.ipynb",
    output:
        "results/notebooks/{name}.ipynb",
    params:
        parameters=NOTEBOOK_PARAMETERS,
    log:
        # papermill writes the executed notebook here cell by cell: after a
        # failure it holds the traceback; on success it is copied to output.
        notebook="results/logs/notebook_{name}.ipynb",
        text="results/logs/notebook_{name}.log",
    wildcard_constraints:
        name="|".join(NOTEBOOKS),
    script:
        "../scripts/run_notebook.py"


rule report_html:
    input:
        ENGINE,
        captions=CAPTIONS,
        intro="workflow/report/intro.md",
        outputs=report_inputs(),
    output:
        "results/report.html",
    log:
        "results/logs/report_html.log",
    script:
        "../scripts/report_html.py"
