# The reproduction summary (computed once), the report notebooks (papermill)
# and the HTML report (jinja2 template). Notebooks and the HTML read the
# summary; they compute no verdict. Inputs are the files the notebooks read,
# so a changed table, figure or summary re-executes them.


rule summary:
    input:
        code=code_inputs("workflow/scripts/summary.py"),
        tables=[res(f"tables/table_{n:02d}.csv") for n in all_tables()],
        # the grid tables are judged by the thesis's findings on the virtual grid
        grid=grid_identified_file(),
        published=config["published"],
        searches=search_summary_file(),
    output:
        report(SUMMARY, caption="../report/summary.rst", category="Summary"),
    log:
        res("logs/summary.log"),
    threads: 1
    resources:
        mem_mb=300,
        runtime=10,
    params:
        code=code_hashes("workflow/scripts/summary.py"),
        sha256=content_hashes(*committed_searches()),
        titles=TABLE_TITLES,
        causes=TABLE_CAUSES,
        grid=config.get("grid"),
    script:
        "../scripts/summary.py"


# The thesis's findings (Ch. 6-8) as checks on the regenerated results.
rule claims:
    input:
        code=code_inputs("workflow/scripts/claims.py"),
        identified=[
            res(f"identified/{s}_{claims_interpretation(s)}.csv")
            for s in CLAIM_STUDIES
        ],
        grid=grid_identified_file(),
    output:
        report(CLAIMS, caption="../report/claims.rst", category="Summary"),
    log:
        res("logs/claims.log"),
    threads: 1
    resources:
        mem_mb=500,
        runtime=10,
    params:
        code=code_hashes("workflow/scripts/claims.py"),
        study_names=CLAIM_STUDIES,
        studies=claims_studies(),
        seeds=config["seeds"],
        tables=config["tables"],
        beams=config["beams"],
        grid=config.get("grid"),
    script:
        "../scripts/claims.py"


# One job per notebook (run_notebook.py, papermill's Python API).
rule notebook:
    input:
        code=code_inputs("notebooks/{name}.ipynb"),
        captions=CAPTIONS,
        data=lambda w: notebook_inputs(w.name),
        notebook="notebooks/{name}.ipynb",
    output:
        res("notebooks/{name}.ipynb"),
    log:
        # papermill writes the executed notebook here cell by cell: after a
        # failure it holds the traceback; on success it is copied to output.
        notebook=res("logs/notebook_{name}.ipynb"),
        text=res("logs/notebook_{name}.log"),
    wildcard_constraints:
        name="|".join(NOTEBOOKS),
    threads: 1
    resources:
        mem_mb=800,
        runtime=10,
    params:
        code=code_hashes("notebooks/{name}.ipynb"),
        parameters=lambda w: notebook_parameters(w.name),
        sha256=content_hashes(CAPTIONS, config["published"]),
    script:
        "../scripts/run_notebook.py"


rule report_html:
    input:
        code=code_inputs("workflow/scripts/report_html.py"),
        template=REPORT_TEMPLATES,
        captions=CAPTIONS,
        summary=SUMMARY,
        claims=CLAIMS,
        searches=search_summary_file(),
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
        code=code_hashes("workflow/scripts/report_html.py"),
        sha256=content_hashes(
            CAPTIONS, "config/config.yaml", *REPORT_TEMPLATES, *committed_searches()
        ),
        titles=TABLE_TITLES,
        measured=config.get("measured"),
        # the config the run used, recorded in the report (its differences from the default)
        used_config=config,
        configfiles=[os.path.relpath(f) for f in workflow.configfiles],
        run=RUN,
    script:
        "../scripts/report_html.py"
