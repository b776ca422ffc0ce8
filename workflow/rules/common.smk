# Helpers only: file lists derived from config.
from pathlib import Path

# Results depend on the engine's code, not only on config: Snakemake does not
# see edits to imported modules by itself.
# Anchored on the Snakefile's folder, so it holds wherever snakemake is started.
ENGINE = sorted(str(p) for p in (Path(workflow.basedir) / "modal").rglob("*.py"))


def table_numbers():
    return sorted(int(n) for n in config["tables"])


def table_spec(number):
    tables = config["tables"]
    return tables[str(number)] if str(number) in tables else tables[int(number)]


def study_of_table(number):
    return table_spec(number)["study"]


def identified(study):
    """The identified-modes files of one study, one per interpretation."""
    return [f"results/identified/{study}_{i}.csv" for i in config["studies"][study]["interpretations"]]


def numbers(mapping):
    return sorted(int(n) for n in mapping)


def measured_outputs():
    """modes.csv and the stabilisation diagram of every record in config "measured"."""
    names = sorted(config.get("measured") or {})
    return [f"results/measured/{n}/{f}" for n in names for f in ("modes.csv", "stabilisation.png")]


def beam_outputs():
    out = []
    for n in table_numbers():
        out += [f"results/tables/table_{n:02d}.csv", f"results/tables/table_{n:02d}.md"]
    out += [f"results/figures/figure_{n:02d}.png" for n in numbers(config["shape_figures"])]
    out += [f"results/figures/figure_{n:02d}.png" for n in numbers(config["noise_figures"])]
    if "cera" in config["studies"] and config["studies"]["cera"].get("cols_sweep"):
        out += ["results/tables/cera_sensitivity.csv", "results/figures/cera_sensitivity.png"]
    return out


# --- report stage (report.smk): notebooks and the HTML report ---------------

NOTEBOOKS = ["00_summary", "01_method_demo", "02_noise_study", "03_spillover", "04_cera", "05_grid"]
CAPTIONS = "workflow/report/captions.yaml"
# Paths handed to the notebooks' `parameters` cells (each gets those it declares).
NOTEBOOK_PARAMETERS = {
    "tables_dir": "results/tables",
    "figures_dir": "results/figures",
    "identified_dir": "results/identified",
    "captions_file": CAPTIONS,
}


def table_files(numbers):
    return [f"results/tables/table_{n:02d}.{ext}" for n in numbers for ext in ("csv", "md")]


def figure_files(numbers):
    return [f"results/figures/figure_{n:02d}.png" for n in numbers]


def tables_of(*studies):
    return [n for n in table_numbers() if study_of_table(n) in studies]


def noisy_tables():
    """Beam tables whose case adds sensor noise (identified over many seeds)."""
    out = []
    for n in table_numbers():
        spec = table_spec(n)
        case = config["studies"][spec["study"]].get("cases", {}).get(spec.get("case"), {})
        if case.get("noise", 0) > 0:
            out.append(n)
    return out


def cera_sensitivity_files():
    return [f for f in beam_outputs() if "cera_sensitivity" in f]


def notebook_inputs(name):
    """The workflow outputs a notebook reads."""
    if name == "00_summary":
        return beam_outputs() + grid_outputs()
    if name == "01_method_demo":
        return table_files(tables_of("demo")) + figure_files(numbers(config["shape_figures"]))
    if name == "02_noise_study":
        return (figure_files(numbers(config["noise_figures"])) + table_files(noisy_tables())
                + identified("noise"))
    if name == "03_spillover":
        return table_files(tables_of("spillover"))
    if name == "04_cera":
        return table_files(tables_of("cera")) + cera_sensitivity_files()
    if name == "05_grid":
        # grid_outputs() is defined in grid.smk (included after this file,
        # called only once all files are read); whatever it lists, the grid
        # notebook shows, and it names the thesis tables/figures still missing.
        return grid_outputs()
    raise ValueError(f"unknown notebook {name!r}")


def report_inputs():
    """What the HTML report reads: every table and figure the workflow makes."""
    return beam_outputs() + grid_outputs()


def report_outputs():
    """The executed notebooks and the HTML report (called by rule all)."""
    return [f"results/notebooks/{name}.ipynb" for name in NOTEBOOKS] + ["results/report.html"]


# --- grid stage (grid.smk): Chapter 7 ------------------------------------------

GRID_TABLES = [10, 11, 12, 13, 14, 15]
GRID_FIGURES = list(range(12, 22))


def grid_inputs():
    """A measured record is an input; the virtual test needs only the engine."""
    grid = config.get("grid", {})
    if grid.get("source") == "measured":
        return [grid["measured"]["path"]]
    return []


def grid_outputs():
    if "grid" not in config:
        return []
    return table_files(GRID_TABLES) + figure_files(GRID_FIGURES)


def beam_table_pattern():
    return "|".join(f"{n:02d}" for n in table_numbers())
