# Chapter 6: simulated beams. Simulation, noise seeds and identification run in
# one job per study x interpretation (each job pays 2-4 s of imports; a single
# identification takes milliseconds).


rule identify:
    input:
        ENGINE,
    output:
        "results/identified/{study}_{interpretation}.csv",
    params:
        study=lambda w: config["studies"][w.study],
        beam=lambda w: config["beams"][config["studies"][w.study]["beam"]],
        signals=lambda w: config["interpretations"][w.interpretation],
        seeds=config["seeds"],
    log:
        "results/logs/identify_{study}_{interpretation}.log",
    script:
        "../scripts/identify.py"


rule table:
    input:
        ENGINE,
        published=config["published"],
        identified=lambda w: identified(table_spec(w.number)["study"]),
    output:
        csv="results/tables/table_{number}.csv",
        md="results/tables/table_{number}.md",
    params:
        spec=lambda w: table_spec(int(w.number)),
        methods=lambda w: config["studies"][table_spec(int(w.number))["study"]]["methods"],
        interpretations=lambda w: config["studies"][table_spec(int(w.number))["study"]]["interpretations"],
        first_seed=config["seeds"]["first"],
    wildcard_constraints:
        number=beam_table_pattern(),
    log:
        "results/logs/table_{number}.log",
    script:
        "../scripts/table.py"


rule shape_figures:
    input:
        ENGINE,
        identified=identified("demo"),
    output:
        [f"results/figures/figure_{n:02d}.png" for n in numbers(config["shape_figures"])],
    params:
        figures=config["shape_figures"],
        beam=config["beams"][config["studies"]["demo"]["beam"]],
        interpretations=config["studies"]["demo"]["interpretations"],
        first_seed=config["seeds"]["first"],
    log:
        "results/logs/shape_figures.log",
    script:
        "../scripts/shape_figures.py"


rule noise_figures:
    input:
        ENGINE,
        identified=identified("noise"),
    output:
        [f"results/figures/figure_{n:02d}.png" for n in numbers(config["noise_figures"])],
    params:
        figures=config["noise_figures"],
        interpretations=config["studies"]["noise"]["interpretations"],
        first_seed=config["seeds"]["first"],
    log:
        "results/logs/noise_figures.log",
    script:
        "../scripts/noise_figures.py"


rule cera_sensitivity:
    input:
        ENGINE,
        identified=identified("cera"),
    output:
        csv="results/tables/cera_sensitivity.csv",
        png="results/figures/cera_sensitivity.png",
    params:
        interpretations=config["studies"]["cera"]["interpretations"],
        first_seed=config["seeds"]["first"],
    log:
        "results/logs/cera_sensitivity.log",
    script:
        "../scripts/cera_sensitivity.py"
