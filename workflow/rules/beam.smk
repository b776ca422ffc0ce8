# Chapter 6: simulated beams. Simulation, noise seeds and identification run in
# one job per study x interpretation x chunk of `seeds.chunk` seeds (each job
# pays 1-3 s of imports; a single identification takes milliseconds), so more
# seeds mean more jobs; merge_identified joins the chunks in the order of an
# unsplit run, byte for byte.


rule identify:
    input:
        code=code_inputs("workflow/scripts/identify.py"),
    output:
        res("identified/chunks/{study}_{interpretation}_{chunk}.csv"),
    log:
        res("logs/identify_{study}_{interpretation}_{chunk}.log"),
    benchmark:
        res("benchmarks/identify_{study}_{interpretation}_{chunk}.tsv")
    threads: 1
    resources:
        mem_mb=400,
        runtime=lambda w: identify_runtime(w.study),
    params:
        code=code_hashes("workflow/scripts/identify.py"),
        study=lambda w: interpreted_study(w.study, w.interpretation)[0],
        beam=lambda w: interpreted_study(w.study, w.interpretation)[1],
        signals=lambda w: config["interpretations"][w.interpretation],
        seeds=config["seeds"],
        chunk=lambda w: int(w.chunk),
    script:
        "../scripts/identify.py"


rule merge_identified:
    input:
        code=code_inputs("workflow/scripts/merge_chunks.py"),
        chunks=lambda w: identified_chunks(w.study, w.interpretation),
    output:
        res("identified/{study}_{interpretation}.csv"),
    log:
        res("logs/merge_identified_{study}_{interpretation}.log"),
    localrule: True
    threads: 1
    resources:
        mem_mb=300,
        runtime=10,
    params:
        code=code_hashes("workflow/scripts/merge_chunks.py"),
        n_chunks=lambda w: len(study_chunks(w.study)),
    script:
        "../scripts/merge_chunks.py"


# Every beam table in one job (table.py loops over them): the imports are paid
# once, not once per table.
rule table:
    input:
        code=code_inputs("workflow/scripts/table.py"),
        published=config["published"],
        identified=sorted(
            {f for n in table_numbers() for f in identified(study_of_table(n))}
        ),
    output:
        csv=report(
            [res(f"tables/table_{n:02d}.csv") for n in table_numbers()],
            caption="../report/table.rst",
            category="Tables",
        ),
        md=[res(f"tables/table_{n:02d}.md") for n in table_numbers()],
        notes=note_files(table_numbers()),
    log:
        res("logs/table.log"),
    threads: 1
    resources:
        mem_mb=300,
        runtime=10,
    params:
        code=code_hashes("workflow/scripts/table.py"),
        sha256=content_hashes(config["published"]),
        tables={n: table_spec(n) for n in table_numbers()},
        studies={
            study_of_table(n): config["studies"][study_of_table(n)]
            for n in table_numbers()
        },
        beams={
            study_of_table(n): config["beams"][
                config["studies"][study_of_table(n)]["beam"]
            ]
            for n in table_numbers()
        },
        interpretations=config["interpretations"],
        seeds=config["seeds"],
    script:
        "../scripts/table.py"


rule shape_figures:
    input:
        code=code_inputs("workflow/scripts/shape_figures.py"),
        identified=identified("demo"),
    output:
        report(
            figure_files(numbers(config["shape_figures"])),
            caption="../report/figure.rst",
            category="Figures",
            subcategory="Mode shapes",
        ),
    log:
        res("logs/shape_figures.log"),
    threads: 1
    resources:
        mem_mb=400,
        runtime=10,
    params:
        code=code_hashes("workflow/scripts/shape_figures.py"),
        figures=config["shape_figures"],
        captions=FIGURE_CAPTIONS,
        beam=config["beams"][config["studies"]["demo"]["beam"]],
        study=config["studies"]["demo"],
        seeds=config["seeds"],
    script:
        "../scripts/shape_figures.py"


rule noise_figures:
    input:
        code=code_inputs("workflow/scripts/noise_figures.py"),
        identified=identified("noise"),
    output:
        report(
            figure_files(numbers(config["noise_figures"])),
            caption="../report/figure.rst",
            category="Figures",
            subcategory="Noise",
        ),
    log:
        res("logs/noise_figures.log"),
    threads: 1
    resources:
        mem_mb=400,
        runtime=10,
    params:
        code=code_hashes("workflow/scripts/noise_figures.py"),
        figures=config["noise_figures"],
        captions=FIGURE_CAPTIONS,
        study=config["studies"]["noise"],
        seeds=config["seeds"],
    script:
        "../scripts/noise_figures.py"


rule cera_sensitivity:
    input:
        code=code_inputs("workflow/scripts/cera_sensitivity.py"),
        identified=identified("cera"),
    output:
        csv=res("tables/cera_sensitivity.csv"),
        png=report(
            res("figures/cera_sensitivity.png"),
            caption="../report/cera_sensitivity.rst",
            category="Beyond the thesis",
        ),
    log:
        res("logs/cera_sensitivity.log"),
    threads: 1
    resources:
        mem_mb=400,
        runtime=10,
    params:
        code=code_hashes("workflow/scripts/cera_sensitivity.py"),
        study=config["studies"]["cera"],
        seeds=config["seeds"],
        title=EXTRA_CAPTIONS["cera_sensitivity"],
        tables={
            n: (table_spec(n)["case"], table_spec(n)["title"])
            for n in tables_of("cera")
        },
        configured={
            i: interpreted_study("cera", i)[0]["methods"]["cera"]["cols"]
            for i in config["studies"]["cera"]["interpretations"]
        },
    script:
        "../scripts/cera_sensitivity.py"
