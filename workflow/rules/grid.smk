# Chapter 7: the grid experiment. One job shakes the virtual grid once per seed
# (or reads the measured record) and runs every identification of Tables
# 10-15; tables and figures read its files.


rule grid_identify:
    input:
        ENGINE,
        grid_inputs(),
    output:
        identified="results/grid/identified.csv",
        selection="results/grid/selection.csv",
        record="results/grid/record_first_seed.npz",
    params:
        spec=config.get("grid"),
    log:
        "results/logs/grid_identify.log",
    script:
        "../scripts/grid_identify.py"


rule grid_table:
    input:
        ENGINE,
        published=config["published"],
        identified="results/grid/identified.csv",
        selection="results/grid/selection.csv",
    output:
        csv="results/tables/table_{number}.csv",
        md="results/tables/table_{number}.md",
    params:
        spec=config.get("grid"),
        first_seed=config.get("grid", {}).get("seeds", {}).get("first", 0),
    wildcard_constraints:
        number="1[0-5]",
    log:
        "results/logs/table_{number}.log",
    script:
        "../scripts/grid_table.py"


rule grid_figures:
    input:
        ENGINE,
        record="results/grid/record_first_seed.npz",
        selection="results/grid/selection.csv",
    output:
        figure_files(GRID_FIGURES),
    params:
        spec=config.get("grid"),
        cutoff=config.get("grid", {}).get("figures_cutoff_hz", 10.0),
    log:
        "results/logs/grid_figures.log",
    script:
        "../scripts/grid_figures.py"
