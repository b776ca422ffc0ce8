# Chapter 7: the grid experiment. One job shakes the virtual grid once per seed
# (or reads the measured record) and runs every identification of the grid
# tables; tables and figures read its files. Table and figure numbers come
# from config (grid.tables, grid.figures).


rule grid_identify:
    input:
        code=ENGINE + GRID_CODE,
        record=grid_inputs(),
    output:
        identified="results/grid/identified.csv",
        selection="results/grid/selection.csv",
        record="results/grid/record_first_seed.npz",
    log:
        "results/logs/grid_identify.log",
    benchmark:
        "results/benchmarks/grid_identify.tsv"
    params:
        spec=config.get("grid"),
    script:
        "../scripts/grid_identify.py"


rule grid_table:
    input:
        code=GRID_TABLE_CODE,
        published=config["published"],
        identified="results/grid/identified.csv",
        selection="results/grid/selection.csv",
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
        number=grid_table_pattern(),
    params:
        spec=config.get("grid"),
        first_seed=config.get("grid", {}).get("seeds", {}).get("first", 0),
    script:
        "../scripts/grid_table.py"


rule grid_figures:
    input:
        code=GRID_PLOT_CODE,
        published=config["published"],
        record="results/grid/record_first_seed.npz",
        selection="results/grid/selection.csv",
    output:
        report(
            figure_files(grid_figures()),
            caption="../report/figure.rst",
            category="Figures",
            subcategory="Grid",
        ),
    log:
        "results/logs/grid_figures.log",
    params:
        spec=config.get("grid"),
        captions=FIGURE_CAPTIONS,
    script:
        "../scripts/grid_figures.py"
