# Chapter 6: simulated beams. Simulation, noise seeds and identification run in
# one job per study x interpretation (each job pays 2-4 s of imports; a single
# identification takes milliseconds).


rule identify:
    input:
        code=ENGINE + STUDY_CODE,
    output:
        "results/identified/{study}_{interpretation}.csv",
    log:
        "results/logs/identify_{study}_{interpretation}.log",
    benchmark:
        "results/benchmarks/identify_{study}_{interpretation}.tsv"
    params:
        study=lambda w: config["studies"][w.study],
        beam=lambda w: config["beams"][config["studies"][w.study]["beam"]],
        signals=lambda w: config["interpretations"][w.interpretation],
        seeds=config["seeds"],
    script:
        "../scripts/identify.py"


rule table:
    input:
        code=TABLE_CODE,
        published=config["published"],
        identified=lambda w: identified(table_spec(w.number)["study"]),
    output:
        csv=report(
            "results/tables/table_{number}.csv",
            caption="../report/table.rst",
            category="Tables",
            labels={"table": "{number}"},
        ),
        md="results/tables/table_{number}.md",
        notes="results/notes/table_{number}.txt",
    log:
        "results/logs/table_{number}.log",
    wildcard_constraints:
        number=beam_table_pattern(),
    params:
        spec=lambda w: table_spec(int(w.number)),
        methods=lambda w: config["studies"][table_spec(int(w.number))["study"]][
            "methods"
        ],
        interpretations=lambda w: config["studies"][
            table_spec(int(w.number))["study"]
        ]["interpretations"],
        first_seed=config["seeds"]["first"],
    script:
        "../scripts/table.py"


rule shape_figures:
    input:
        code=PLOT_CODE,
        identified=identified("demo"),
    output:
        report(
            figure_files(numbers(config["shape_figures"])),
            caption="../report/figure.rst",
            category="Figures",
            subcategory="Mode shapes",
        ),
    log:
        "results/logs/shape_figures.log",
    params:
        figures=config["shape_figures"],
        captions=FIGURE_CAPTIONS,
        beam=config["beams"][config["studies"]["demo"]["beam"]],
        interpretations=config["studies"]["demo"]["interpretations"],
        first_seed=config["seeds"]["first"],
    script:
        "../scripts/shape_figures.py"


rule noise_figures:
    input:
        code=PLOT_CODE,
        identified=identified("noise"),
    output:
        report(
            figure_files(numbers(config["noise_figures"])),
            caption="../report/figure.rst",
            category="Figures",
            subcategory="Noise",
        ),
    log:
        "results/logs/noise_figures.log",
    params:
        figures=config["noise_figures"],
        captions=FIGURE_CAPTIONS,
        interpretations=config["studies"]["noise"]["interpretations"],
        first_seed=config["seeds"]["first"],
    script:
        "../scripts/noise_figures.py"


rule cera_sensitivity:
    input:
        code=PLOT_CODE,
        identified=identified("cera"),
    output:
        csv="results/tables/cera_sensitivity.csv",
        png=report(
            "results/figures/cera_sensitivity.png",
            caption="../report/cera_sensitivity.rst",
            category="Beyond the thesis",
        ),
    log:
        "results/logs/cera_sensitivity.log",
    params:
        interpretations=config["studies"]["cera"]["interpretations"],
        first_seed=config["seeds"]["first"],
        title=EXTRA_CAPTIONS["cera_sensitivity"],
        tables={
            n: (table_spec(n)["case"], table_spec(n)["title"]) for n in tables_of("cera")
        },
        configured=config["studies"]["cera"]["methods"]["cera"]["cols"],
    script:
        "../scripts/cera_sensitivity.py"
