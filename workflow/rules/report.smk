# The reproduction summary (computed once), the report notebooks (papermill)
# and the HTML report (jinja2 template). Notebooks and the HTML read the
# summary; they compute no verdict. Inputs are the files the notebooks read,
# so a changed table, figure or summary re-executes them (all six, in one job).


rule summary:
    input:
        code=code_inputs("workflow/scripts/summary.py"),
        tables=[res(f"tables/table_{n:02d}.csv") for n in all_tables()],
    output:
        report(SUMMARY, caption="../report/summary.rst", category="Summary"),
    log:
        res("logs/summary.log"),
    threads: 1
    resources:
        mem_mb=300,
        runtime=10,
    params:
        titles=TABLE_TITLES,
    script:
        "../scripts/summary.py"


# All notebooks in one job (run_notebook.py), in as many kernels as it has
# threads, side by side: a kernel start and the thesis layer's imports cost
# more than most notebooks' cells, and the notebooks are the workflow's last
# step, so both kernels use cores that would otherwise idle.
rule notebook:
    input:
        code=sorted(
            {f for name in NOTEBOOKS for f in code_inputs(f"notebooks/{name}.ipynb")}
        ),
        captions=CAPTIONS,
        data=sorted(set(d for name in NOTEBOOKS for d in notebook_inputs(name))),
        notebooks=[f"notebooks/{name}.ipynb" for name in NOTEBOOKS],
    output:
        [res(f"notebooks/{name}.ipynb") for name in NOTEBOOKS],
    log:
        # papermill writes each executed notebook here cell by cell: after a
        # failure it holds the traceback; on success it is copied to output.
        notebooks=[res(f"logs/notebook_{name}.ipynb") for name in NOTEBOOKS],
        text=res("logs/notebook.log"),
    threads: 2
    resources:
        mem_mb=1500,
        runtime=10,
    params:
        names=NOTEBOOKS,
        order=NOTEBOOKS_LONGEST_FIRST,
        parameters={name: notebook_parameters(name) for name in NOTEBOOKS},
    script:
        "../scripts/run_notebook.py"


rule report_html:
    input:
        code=code_inputs("workflow/scripts/report_html.py"),
        template=REPORT_TEMPLATES,
        captions=CAPTIONS,
        summary=SUMMARY,
        outputs=report_inputs(),
        default_config="config/config.yaml",
    output:
        report(res("report.html"), caption="../report/report.rst", category="Summary"),
    log:
        res("logs/report_html.log"),
    threads: 1
    resources:
        mem_mb=400,
        runtime=10,
    params:
        titles=TABLE_TITLES,
        configfiles=[os.path.relpath(f) for f in workflow.configfiles],
        run=RUN,
    script:
        "../scripts/report_html.py"
