# Helpers only: file lists derived from config.
from pathlib import Path

# Results depend on the engine's code, not only on config: Snakemake does not
# see edits to imported modules by itself.
ENGINE = sorted(str(p) for p in Path("modal").rglob("*.py"))


def table_numbers():
    return sorted(int(n) for n in config["tables"])


def study_of_table(number):
    return config["tables"][str(number)]["study"] if str(number) in config["tables"] else config["tables"][number]["study"]


def table_spec(number):
    tables = config["tables"]
    return tables[str(number)] if str(number) in tables else tables[int(number)]


def identified(study):
    """The identified-modes files of one study, one per interpretation."""
    return [f"results/identified/{study}_{i}.csv" for i in config["studies"][study]["interpretations"]]


def numbers(mapping):
    return sorted(int(n) for n in mapping)


def beam_outputs():
    out = []
    for n in table_numbers():
        out += [f"results/tables/table_{n:02d}.csv", f"results/tables/table_{n:02d}.md"]
    out += [f"results/figures/figure_{n:02d}.png" for n in numbers(config["shape_figures"])]
    out += [f"results/figures/figure_{n:02d}.png" for n in numbers(config["noise_figures"])]
    if "cera" in config["studies"] and config["studies"]["cera"].get("cols_sweep"):
        out += ["results/tables/cera_sensitivity.csv", "results/figures/cera_sensitivity.png"]
    return out
