# The reproduction summary (computed once), the report notebooks (papermill)
# and the HTML report (jinja2 template). Notebooks and the HTML read the
# summary; they compute no verdict. Inputs are the files each one reads, so a
# changed table re-executes only the notebooks that show it.


rule summary:
    input:
        code=SUMMARY_CODE,
        tables=[f"results/tables/table_{n:02d}.csv" for n in all_tables()],
    output:
        report(SUMMARY, caption="../report/summary.rst", category="Summary"),
    log:
        "results/logs/summary.log",
    params:
        titles=TABLE_TITLES,
    script:
        "../scripts/summary.py"


rule notebook:
    input:
        code=NOTEBOOK_CODE,
        captions=CAPTIONS,
        data=lambda w: notebook_inputs(w.name),
        notebook="notebooks/{name}.ipynb",
    output:
        "results/notebooks/{name}.ipynb",
    log:
        # papermill writes the executed notebook here cell by cell: after a
        # failure it holds the traceback; on success it is copied to output.
        notebook="results/logs/notebook_{name}.ipynb",
        text="results/logs/notebook_{name}.log",
    wildcard_constraints:
        name="|".join(NOTEBOOKS),
    params:
        parameters=lambda w: notebook_parameters(w.name),
    script:
        "../scripts/run_notebook.py"


rule report_html:
    input:
        code=REPORT_CODE,
        template=REPORT_TEMPLATES,
        captions=CAPTIONS,
        summary=SUMMARY,
        outputs=report_inputs(),
    output:
        report(
            "results/report.html", caption="../report/report.rst", category="Summary"
        ),
    log:
        "results/logs/report_html.log",
    params:
        titles=TABLE_TITLES,
        configfiles=[os.path.relpath(f) for f in workflow.configfiles],
        default_config="config/config.yaml",
    script:
        "../scripts/report_html.py"
