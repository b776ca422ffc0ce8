# Chapter 7: the grid experiment. One job per chunk of `grid.seeds.chunk`
# virtual shaking tests (or one for the measured record) runs every
# identification of the grid tables; grid_merge joins the chunks (byte for
# byte the unsplit run's files). Tables and figures read the merged files.
# Table and figure numbers come from config (grid.tables, grid.figures).


rule grid_identify:
    input:
        code=code_inputs("workflow/scripts/grid_identify.py"),
        record=grid_inputs(),
    output:
        identified=res("grid/chunks/identified_{chunk}.csv"),
        selection=res("grid/chunks/selection_{chunk}.csv"),
        record=res("grid/chunks/record_{chunk}.npz"),
    log:
        res("logs/grid_identify_{chunk}.log"),
    benchmark:
        res("benchmarks/grid_identify_{chunk}.tsv")
    threads: 1
    resources:
        mem_mb=500,
        runtime=lambda w: grid_identify_runtime(),
    params:
        code=code_hashes("workflow/scripts/grid_identify.py"),
        spec=config.get("grid"),
        chunk=lambda w: int(w.chunk),
        sha256=content_hashes(*grid_inputs()),
    script:
        "../scripts/grid_identify.py"


rule grid_merge:
    input:
        code=code_inputs("workflow/scripts/merge_chunks.py"),
        identified=lambda w: grid_chunk_files("identified"),
        selection=lambda w: grid_chunk_files("selection"),
        record=lambda w: grid_chunk_files("record", "npz")[0],
    output:
        identified=res("grid/identified.csv"),
        selection=res("grid/selection.csv"),
        record=res("grid/record_first_seed.npz"),
    log:
        res("logs/grid_merge.log"),
    localrule: True
    threads: 1
    resources:
        mem_mb=300,
        runtime=10,
    params:
        code=code_hashes("workflow/scripts/merge_chunks.py"),
        n_chunks=len(grid_chunks()),
    script:
        "../scripts/merge_chunks.py"


# Every grid table in one job (grid_table.py loops over them).
rule grid_table:
    input:
        code=code_inputs("workflow/scripts/grid_table.py"),
        published=config["published"],
        identified=res("grid/identified.csv"),
        selection=res("grid/selection.csv"),
    output:
        csv=report(
            [res(f"tables/table_{n:02d}.csv") for n in grid_tables()],
            caption="../report/table.rst",
            category="Tables",
        ),
        md=[res(f"tables/table_{n:02d}.md") for n in grid_tables()],
        notes=note_files(grid_tables()),
    log:
        res("logs/grid_table.log"),
    threads: 1
    resources:
        mem_mb=300,
        runtime=10,
    params:
        code=code_hashes("workflow/scripts/grid_table.py"),
        spec=config.get("grid"),
    script:
        "../scripts/grid_table.py"


rule grid_figures:
    input:
        code=code_inputs("workflow/scripts/grid_figures.py"),
        published=config["published"],
        record=res("grid/record_first_seed.npz"),
        selection=res("grid/selection.csv"),
    output:
        report(
            figure_files(grid_figures()),
            caption="../report/figure.rst",
            category="Figures",
            subcategory="Grid",
        ),
    log:
        res("logs/grid_figures.log"),
    threads: 1
    resources:
        mem_mb=400,
        runtime=10,
    params:
        code=code_hashes("workflow/scripts/grid_figures.py"),
        spec=config.get("grid"),
        captions=FIGURE_CAPTIONS,
    script:
        "../scripts/grid_figures.py"
