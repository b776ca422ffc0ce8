# Helpers only: file lists derived from config, and the code each rule reads.
# Snakemake wants rules and functions in separate files.
import functools
import hashlib
import os
import re
import yaml
from pathlib import Path

import modal._hashes
import modal.thesis.claims
import modal.thesis.dependencies
import modal.thesis.search
from modal.thesis.chunks import seed_chunks, study_cases

# --- the run: where results go ---------------------------------------------------
# `run: default` (config/config.yaml) writes the committed results/; any other
# name (`--config run=<name>` or `run:` in a layered config) writes everything,
# tables, figures, notebooks, report, logs, under results/runs/<name>/, so a
# parameter study never touches the committed tables.
RUN = config.get("run", "default")
RESULTS = "results" if RUN == "default" else f"results/runs/{RUN}"


def res(path):
    """``path`` under this run's results folder (``results/`` for the default run)."""
    return f"{RESULTS}/{path}"


wildcard_constraints:
    study=r"[^/]+",
    search=r"[A-Za-z0-9][A-Za-z0-9_-]*",
    setting=r"s\d{3}",
    interpretation=r"[^/_]+",
    chunk=r"\d+",


# --- raw inputs enter with their content ------------------------------------------
# Snakemake reruns a job when an input is newer than its outputs. A raw input
# replaced by different content with an older time (`cp -p`, an unpacked
# archive, a restored backup) would go unseen; so each raw input (published
# values, records, captions, the default config) also enters its rule's
# params as its SHA-256, and the params trigger reruns the job whatever the mtime.
@functools.cache
def sha256(path):
    """SHA-256 of the file at ``path`` (read once per planning)."""
    return modal._hashes.file_hash(path)


def content_hashes(*paths):
    """``{path: sha256}`` of raw input files, for a rule's ``params``."""
    return {str(p): sha256(p) for p in paths}


# --- code inputs ---------------------------------------------------------------
# Snakemake does not see edits to imported modules: each rule declares the
# project modules its script (or notebook) imports, derived from the imports
# themselves (modal.thesis.dependencies: parsed, transitively, with every
# package __init__ on the way), as paths relative to where snakemake runs (so a
# copied project reruns nothing). Templates and captions are files, listed.
# Both are input (params) functions: derived when a job of the rule is
# planned, so a job Snakemake runs in a process of its own (a cluster job, a
# shadowed one) derives its own script's modules only.
@functools.cache
def project_modules(path):
    """The project modules (relative to the project) that the script or
    notebook ``path`` runs, derived once per planning."""
    return tuple(
        modal.thesis.dependencies.code_inputs(path, root=Path(workflow.basedir))
    )


def code_inputs(pattern):
    """An input function: the project modules that the script or notebook
    ``pattern`` (relative to the project; ``{name}`` filled from the job's
    wildcards) runs when it is executed."""

    def modules(wildcards):
        root = Path(workflow.basedir)
        path = pattern.format(**wildcards)
        return [os.path.relpath(root / p) for p in project_modules(path)]

    return modules


def code_hashes(pattern):
    """A params function: ``{module: sha256}`` of the project modules the
    script or notebook ``pattern`` (as for :func:`code_inputs`) runs: an edit
    reruns the rule by content even when the file keeps an older time stamp
    (the code inputs alone are compared by time)."""

    def hashes(wildcards):
        root = Path(workflow.basedir)
        path = pattern.format(**wildcards)
        return {f: sha256(root / f) for f in project_modules(path)}

    return hashes


def code(*names):
    """Paths of project files (``workflow/report/x``), relative to where snakemake runs."""
    return [os.path.relpath(Path(workflow.basedir) / name) for name in names]


REPORT_TEMPLATES = code("workflow/report/report.html.j2", "workflow/report/report.css")
CAPTIONS = "workflow/report/captions.yaml"


# --- the beam chapter (beam.smk) ------------------------------------------------
def table_numbers():
    return sorted(int(n) for n in config["tables"])


def table_spec(number):
    tables = config["tables"]
    return tables[str(number)] if str(number) in tables else tables[int(number)]


def study_of_table(number):
    return table_spec(number)["study"]


def interpreted_study(study, interpretation):
    """(study, beam) of one study as one interpretation reads them
    (modal.thesis.study.interpreted: its own settings of the unstated ones)."""
    from modal.thesis.study import interpreted

    spec = config["studies"][study]
    return interpreted(
        spec,
        config["beams"][spec["beam"]],
        config["interpretations"][interpretation],
        study,
    )


def identified(study):
    """The identified-modes files of one study, one per interpretation."""
    return [
        res(f"identified/{study}_{i}.csv")
        for i in config["studies"][study]["interpretations"]
    ]


# --- Monte Carlo seeds in chunks: one identification job per chunk ----------------
def is_noisy(study):
    """Whether a study has a noisy case (identified once per seed)."""
    return any(c["noise"] > 0 for c in study_cases(config["studies"][study]).values())


def study_chunks(study):
    """Chunk numbers of a study: one per ``seeds.chunk`` seeds if it is noisy,
    else a single chunk (its noise-free cases run once)."""
    return range(len(seed_chunks(config["seeds"])) if is_noisy(study) else 1)


def identify_runtime(study):
    """Minutes to ask a cluster for one identify job: 1 s per seed and case
    (measured: 0.01-0.1 s), at least 10 minutes."""
    n_cases = len(study_cases(config["studies"][study]))
    seeds = config["seeds"]
    return max(10, n_cases * (seeds.get("chunk") or seeds["count"]) // 60)


def grid_identify_runtime():
    """Minutes for one grid_identify job: 30 s per virtual test (measured:
    about 3 s), at least 10 minutes."""
    seeds = config["grid"]["seeds"]
    return max(10, (seeds.get("chunk") or seeds["count"]) // 2)


def identified_chunks(study, interpretation):
    return [
        res(f"identified/chunks/{study}_{interpretation}_{k}.csv")
        for k in study_chunks(study)
    ]


def numbers(mapping):
    return sorted(int(n) for n in mapping)


def measured_names(kind):
    """Names of the "measured" entries with a ``path`` (one record) or with
    ``setups`` (a roving test)."""
    return sorted(
        n for n, spec in (config.get("measured") or {}).items() if kind in spec
    )


def names_regex(names):
    """A wildcard constraint matching exactly ``names`` (none: nothing)."""
    return "|".join(re.escape(n) for n in names) or "(?!)"


def setup_files(spec):
    """Every file of a roving test's setups and geometry folders (its raw
    inputs: an edit reruns it)."""
    roots = [Path(p) for p in spec["setups"]] + (
        [Path(spec["geometry"])] if spec.get("geometry") else []
    )
    return sorted(
        str(f)
        for root in roots
        for f in ([root] if root.is_file() else root.rglob("*"))
        if f.is_file()
    )


def measured_outputs():
    """modes.csv and the stabilisation diagram of every record in config
    "measured"; modes.csv, shapes.csv and the modes drawn of every roving test."""
    return [
        res(f"measured/{n}/{f}")
        for n in measured_names("path")
        for f in ("modes.csv", "stabilisation.png")
    ] + [
        res(f"measured/{n}/{f}")
        for n in measured_names("setups")
        for f in ("modes.csv", "shapes.csv", "modes.png")
    ]


def table_files(numbers):
    return [
        res(f"tables/table_{n:02d}.{ext}") for n in numbers for ext in ("csv", "md")
    ]


def note_files(numbers):
    return [res(f"notes/table_{n:02d}.txt") for n in numbers]


def figure_files(numbers):
    return [res(f"figures/figure_{n:02d}.png") for n in numbers]


def cera_sensitivity_files():
    if "cera" in config["studies"] and config["studies"]["cera"].get("cols_sweep"):
        return [
            res("tables/cera_sensitivity.csv"),
            res("figures/cera_sensitivity.png"),
        ]
    return []


def beam_outputs():
    return (
        table_files(table_numbers())
        + figure_files(numbers(config["shape_figures"]))
        + figure_files(numbers(config["noise_figures"]))
        + cera_sensitivity_files()
    )


# --- searches of unstated settings (search.smk) ------------------------------------
# Parameter studies: computed only with `run_searches: true` (the Snakefile
# includes search.smk then); otherwise the summary and the report cite the
# committed table, a raw input like the published values.
SEARCHES = sorted(config.get("searches", {}))
RUN_SEARCHES = bool(SEARCHES) and config.get("run_searches", False)
SEARCH_SUMMARY = res("tables/searches.csv")
COMMITTED_SEARCHES = "results/tables/searches.csv"


@functools.cache
def search_settings(name):
    """The settings of search ``name`` (modal.thesis.search.search_settings)."""
    return modal.thesis.search.search_settings(
        config["searches"][name], config["studies"], config["beams"], config["tables"]
    )


def search_summary_file():
    """The searches' summary the summary cites: this run's when it computes
    the searches, else the committed one (none without searches)."""
    return [SEARCH_SUMMARY] if RUN_SEARCHES else committed_searches()


def search_outputs():
    """Every search's scores and the searches' summary, when the run computes them."""
    if not RUN_SEARCHES:
        return []
    return [res(f"searches/{n}.csv") for n in SEARCHES] + [SEARCH_SUMMARY]


def committed_searches():
    """The committed searches' summary when it is read (a raw input, hashed)."""
    return [COMMITTED_SEARCHES] if SEARCHES and not RUN_SEARCHES else []


def tables_of(*studies):
    return [n for n in table_numbers() if study_of_table(n) in studies]


# --- the grid chapter (grid.smk): numbers from config ----------------------------
def grid_tables():
    return sorted(int(n) for n in config.get("grid", {}).get("tables", {}))


def grid_figures():
    if "grid" not in config:
        return []
    figures = config["grid"]["figures"]
    return [figures["layout"], *figures["responses"], *figures["filtered"]]


def grid_inputs():
    """A measured record is an input; the virtual test needs only the engine."""
    grid = config.get("grid", {})
    if grid.get("source") == "measured":
        return [grid["measured"]["path"]]
    return []


def grid_chunks():
    """Chunk numbers of the grid's virtual tests (``grid.seeds.chunk``); a
    measured record is one chunk."""
    grid = config["grid"]
    return range(len(seed_chunks(grid["seeds"])) if grid["source"] == "virtual" else 1)


def grid_chunk_files(kind, ext="csv"):
    return [res(f"grid/chunks/{kind}_{k}.{ext}") for k in grid_chunks()]


def grid_outputs():
    return table_files(grid_tables()) + figure_files(grid_figures())


# --- the report (report.smk) ------------------------------------------------------
# The report notebooks in chapter order.
NOTEBOOKS = [
    "00_summary",
    "01_method_demo",
    "02_noise_study",
    "03_spillover",
    "04_cera",
    "05_grid",
]
SUMMARY = res("tables/summary.csv")
CLAIMS = res("tables/claims.csv")
# The beam studies the claims read (modal.thesis.claims), those configured.
CLAIM_STUDIES = [
    s for s in ("demo", "noise", "spillover", "cera") if s in config["studies"]
]


def claims_interpretation(study=None):
    """The interpretation whose identified modes the claims read (config ``claims``):
    of one study (``claims.studies`` where set), or the default."""
    if study is None:
        return config.get("claims", {}).get("interpretation", "named")
    return modal.thesis.claims.claims_readings(config)[0][study]


def claims_studies():
    """Each claim study as the claims read it (modal.thesis.claims.claims_readings)."""
    return modal.thesis.claims.claims_readings(config)[1]


def grid_identified_file():
    """The grid chapter's identified modes, when the config has grid tables."""
    return [res("grid/identified.csv")] if grid_tables() else []


# Handed to the notebooks' `parameters` cells (each gets those it declares):
# paths relative to the project root, where papermill runs them.
NOTEBOOK_PATHS = {
    "tables_dir": res("tables"),
    "figures_dir": res("figures"),
    "identified_dir": res("identified"),
    "summary_file": SUMMARY,
    "claims_file": CLAIMS,
    "grid_dir": res("grid"),
    "captions_file": CAPTIONS,
}


def noisy_tables():
    """Beam tables whose case adds sensor noise (identified over many seeds)."""
    out = []
    for n in table_numbers():
        spec = table_spec(n)
        case = (
            config["studies"][spec["study"]].get("cases", {}).get(spec.get("case"), {})
        )
        if case.get("noise", 0) > 0:
            out.append(n)
    return out


def notebook_parameters(name):
    """Paths, and for the grid notebook the grid's table and figure numbers."""
    demo = config["studies"]["demo"]
    return {
        **NOTEBOOK_PATHS,
        "claims_interpretation": None,
        "claims_config": {
            k: config.get(k)
            for k in (
                "tables",
                "beams",
                "studies",
                "grid",
                "claims",
                "interpretations",
            )
        },
        "published_file": config["published"],
        "table_numbers": grid_tables(),
        "figure_numbers": grid_figures(),
        "beam": config["beams"][demo["beam"]],
        "interpretations": {
            i: config["interpretations"][i] for i in demo["interpretations"]
        },
        "noisy_cases": {
            n: table_spec(n)["case"]
            for n in noisy_tables()
            if study_of_table(n) == "demo"
        },
    }


def all_tables():
    return table_numbers() + grid_tables()


def all_figures():
    return (
        numbers(config["shape_figures"])
        + numbers(config["noise_figures"])
        + grid_figures()
    )


def notebook_inputs(name):
    """The workflow outputs a notebook reads: the summary (its verdicts) and
    the tables, notes and figures of its chapter."""
    return [SUMMARY] + chapter_outputs(name)


def chapter_outputs(name):
    if name == "00_summary":
        # its inventory checks which tables and figures exist; its claims
        # section shows claims.csv and can recompute it from the identified modes
        return (
            table_files(all_tables())
            + figure_files(all_figures())
            + [CLAIMS]
            + [
                res(f"identified/{s}_{i}.csv")
                for s in CLAIM_STUDIES
                for i in config["studies"][s]["interpretations"]
            ]
            + grid_identified_file()
        )
    if name == "01_method_demo":
        numbers_ = tables_of("demo")
        return (
            [config["published"]]
            + table_files(numbers_)
            + note_files(numbers_)
            + figure_files(numbers(config["shape_figures"]))
        )
    if name == "02_noise_study":
        # it reads every table the summary lists to find the noisy ones (grid too)
        return (
            figure_files(numbers(config["noise_figures"]))
            + table_files(all_tables())
            + note_files(all_tables())
            + identified("noise")
            + identified("demo")
        )
    if name == "03_spillover":
        return table_files(tables_of("spillover")) + note_files(tables_of("spillover"))
    if name == "04_cera":
        return (
            table_files(tables_of("cera"))
            + note_files(tables_of("cera"))
            + cera_sensitivity_files()
        )
    if name == "05_grid":
        return grid_outputs() + note_files(grid_tables())
    raise ValueError(f"unknown notebook {name!r}")


def report_inputs():
    """What the HTML report reads: every table, its notes, every figure, and
    the modes and diagram of every measured record."""
    return (
        beam_outputs() + grid_outputs() + note_files(all_tables()) + measured_outputs()
    )


def report_outputs():
    """The summary, the executed notebooks and the HTML report (rule all)."""
    return (
        [SUMMARY, CLAIMS]
        + [res(f"notebooks/{name}.ipynb") for name in NOTEBOOKS]
        + [res("report.html")]
    )


# --- titles and captions: one source each ----------------------------------------
# Table titles: config (tables.N.title, grid.tables.N.title). Figure captions:
# the thesis's, in workflow/report/captions.yaml.
TABLE_TITLES = {
    **{int(n): t["title"] for n, t in config["tables"].items()},
    **{int(n): t["title"] for n, t in config.get("grid", {}).get("tables", {}).items()},
}
# The known cause of each beam table's deviation (tables.N.cause), when given.
TABLE_CAUSES = {
    int(n): t["cause"] for n, t in config["tables"].items() if t.get("cause")
}
with open(Path(workflow.basedir) / CAPTIONS, encoding="utf-8") as _fh:
    _CAPTIONS = yaml.safe_load(_fh)
FIGURE_CAPTIONS = {int(n): text for n, text in _CAPTIONS["figures"].items()}
EXTRA_CAPTIONS = _CAPTIONS["extras"]
