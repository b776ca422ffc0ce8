"""Scale: Monte Carlo seeds in chunks merge to the unsplit files byte for byte,
the number of jobs grows with the seeds, BLAS threads follow a job's
threads, every job can run as a separate process (cluster-generic executor),
and a named run never touches the committed tables."""

import copy
import os
import re
import shutil
import subprocess
import sys

import pytest
import yaml
from snakemake.utils import update_config

from modal.thesis.search import search_settings

from modal.thesis.chunks import chunk_seeds, merge_chunks, seed_chunks
from modal.thesis.study import run_study
from workflow_run import ROOT, SMALL_CONFIG_FILE, copy_project, run_snakemake

SMALL = yaml.safe_load((ROOT / SMALL_CONFIG_FILE).read_text())
BASE = yaml.safe_load((ROOT / "config/config.yaml").read_text())


# --- seed chunks ----------------------------------------------------------------
def test_seed_chunks_split_the_seeds_in_order():
    assert [list(c) for c in seed_chunks({"first": 7, "count": 10, "chunk": 4})] == [
        [7, 8, 9, 10], [11, 12, 13, 14], [15, 16]]
    assert seed_chunks({"first": 0, "count": 5}) == [range(0, 5)]  # no chunk: one chunk
    for count in range(1, 12):
        for size in range(1, 14):
            chunks = seed_chunks({"first": 3, "count": count, "chunk": size})
            assert len(chunks) == -(-count // size)
            assert [s for c in chunks for s in c] == list(range(3, 3 + count))
            assert all(len(c) == size for c in chunks[:-1])


@pytest.mark.parametrize("key, value", [("count", 0), ("chunk", 0), ("first", -1), ("chunk", 2.5), ("count", True)])
def test_bad_seeds_name_the_key(key, value):
    seeds = {"first": 0, "count": 4, "chunk": 2, key: value}
    with pytest.raises(ValueError, match=f"seeds.{key}"):
        seed_chunks(seeds)


def test_chunk_number_out_of_range_is_refused():
    with pytest.raises(ValueError, match="chunk must be in 0 ... 1"):
        chunk_seeds({"first": 0, "count": 4, "chunk": 2}, 2)
    with pytest.raises(ValueError, match="paths"):
        merge_chunks([], "unused.csv")


@pytest.mark.slow
def test_chunked_beam_study_merges_to_the_unsplit_file_byte_for_byte(tmp_path):
    """Off the thesis geometry: sensors at uneven stations of an 11-part span;
    one noise-free case (chunk 0 only) between two noisy ones; three seeds
    from seed 4 in chunks of two, so the last chunk is shorter."""
    beam = dict(BASE["beams"]["beam5"], stations=11, sensors=[1, 3, 4, 7, 9, 10], impact=3)
    study = dict(BASE["studies"]["demo"], cases={"a": {"damping": 0.01, "noise": 0.03},
                                                 "b": {"damping": 0.02, "noise": 0.0},
                                                 "c": {"damping": 0.0, "noise": 0.05}})
    signals = BASE["interpretations"]["lower"]
    seeds = {"first": 4, "count": 3, "chunk": 2}
    run_study(study, beam, signals, seeds).to_csv(tmp_path / "unsplit.csv", index=False)
    paths = []
    for k in range(len(seed_chunks(seeds))):
        paths.append(tmp_path / f"chunk_{k}.csv")
        run_study(study, beam, signals, seeds, chunk=k).to_csv(paths[-1], index=False)
    merge_chunks(paths, tmp_path / "merged.csv", group_by="case")
    unsplit = (tmp_path / "unsplit.csv").read_bytes()
    assert (tmp_path / "merged.csv").read_bytes() == unsplit
    assert unsplit.count(b"\nb,") == 12  # the noise-free case: once, 6 modes x 2 methods
    with pytest.raises(ValueError, match="chunk: a study without noise"):
        run_study(dict(study, cases={"b": study["cases"]["b"]}), beam, signals, seeds, chunk=1)


def _count_jobs(workdir, *args):
    proc = run_snakemake(workdir, "-n", *args)
    return {rule: int(n) for rule, n in re.findall(r"^(\w+)\s+(\d+)$", proc.stdout, re.M)}


@pytest.mark.slow
def test_identify_jobs_grow_with_the_seeds(tmp_path):
    """Default config: 50 seeds in one chunk of 50; 200 seeds in chunks of 25
    -> eight jobs per noisy study and interpretation (demo and noise: named,
    lower; cera: those and guideline); spillover is noise-free: one job per
    interpretation."""
    work = copy_project(tmp_path, searches=True)
    (work / "more.yaml").write_text(yaml.safe_dump({"seeds": {"first": 0, "count": 200, "chunk": 25},
                                                    "grid": {"seeds": {"first": 0, "count": 10, "chunk": 3}}}))
    default, more = _count_jobs(work), _count_jobs(work, "--configfile", "more.yaml")
    assert (default["identify"], default["grid_identify"]) == ((2 + 2 + 3) * 1 + 2, 2)
    assert (more["identify"], more["grid_identify"]) == ((2 + 2 + 3) * 8 + 2, 4)
    assert default["merge_identified"] == more["merge_identified"] == 2 + 2 + 3 + 2


# --- threads ------------------------------------------------------------------------
def test_blas_threads_follow_the_job_threads():
    """In a process started without any thread variables (a script run by
    hand), OpenBLAS starts one thread per core; start_job's limit brings it
    to the rule's threads."""
    env = {k: v for k, v in os.environ.items()
           if not k.endswith("_NUM_THREADS") and k != "VECLIB_MAXIMUM_THREADS"}
    code = ("import sys; sys.path.insert(0, 'workflow/scripts'); import numpy\n"
            "from threadpoolctl import threadpool_info\n"
            "from _helpers import limit_blas_threads\n"
            "before = max(p['num_threads'] for p in threadpool_info())\n"
            "print(before, limit_blas_threads(1), max(p['num_threads'] for p in threadpool_info()))\n"
            "try:\n    limit_blas_threads(0)\nexcept ValueError as e:\n    print('refused', e)\n")
    out = subprocess.run([sys.executable, "-c", code], cwd=ROOT, env=env, capture_output=True, text=True,
                         check=True).stdout.split("\n")
    before, returned, after = map(int, out[0].split())
    assert before == os.cpu_count() > 1
    assert returned == after == 1
    assert out[1].startswith("refused threads must be a positive integer")


def test_workflow_jobs_log_their_blas_threads(small_workflow):
    log = (small_workflow / "results/logs/identify_noise_lower_0.log").read_text()
    assert log.startswith("threads: 1, BLAS/OpenMP threads in effect: 1")


def test_small_config_runs_one_setting_per_search():
    """config/config.yaml's searches merge with the small config's key by
    key (Snakemake's update_config): a search the small config does not
    name, or a varied key it leaves out, would run the full search (61
    settings instead of 6) in every end-to-end run of the test suite."""
    merged = copy.deepcopy(BASE)
    update_config(merged, SMALL)
    counts = {name: len(search_settings(search, merged["studies"], merged["beams"], merged["tables"]))
              for name, search in merged["searches"].items()}
    assert counts == dict.fromkeys(BASE["searches"], 1)


# --- separate processes: snakemake-executor-plugin-cluster-generic ------------------
TARGETS = ["results/identified/demo_named.csv", "results/identified/demo_lower.csv", "results/grid/identified.csv",
           "results/grid/selection.csv", "results/tables/table_11.csv"]


def test_chunked_run_as_separate_processes_equals_the_local_run(small_workflow, tmp_path):
    """The small config's demonstration study in 2 chunks of unequal size
    (seeds 0-1 and 2) and its grid study in 2 chunks of one seed, each job a
    detached process started by a local submit script, give the identified
    files, the grid's selection and a grid table of the unsplit local run
    byte for byte (the beam tables' rule runs as Slurm jobs in test_slurm)."""
    work = copy_project(tmp_path)
    shutil.copy(ROOT / "tests/workflow/local_submit.sh", work / "local_submit.sh")
    (work / "chunks.yaml").write_text(yaml.safe_dump({"seeds": dict(SMALL["seeds"], chunk=2),
                                                      "grid": {"seeds": dict(SMALL["grid"]["seeds"], chunk=1)}}))
    profile = work / "profile"
    profile.mkdir()
    (profile / "config.yaml").write_text(yaml.safe_dump({
        "executor": "cluster-generic", "cluster-generic-submit-cmd": "bash local_submit.sh", "jobs": 2,
        "latency-wait": 5, "seconds-between-status-checks": 1}))  # the jobs take seconds: look every second
    run_snakemake(work, *TARGETS, "--workflow-profile", "profile", "--configfile", SMALL_CONFIG_FILE, "chunks.yaml")
    assert sorted(p.name for p in (work / "results/identified/chunks").glob("demo_lower_*.csv")) == [
        "demo_lower_0.csv", "demo_lower_1.csv"]
    submitted = list((work / "cluster_logs").iterdir())
    # identify (demo: 2 interpretations x 2 chunks), the grid's 2 chunks, its table job
    assert len(submitted) == 2 * 2 + 2 + 1, sorted(p.name for p in submitted)
    differ = [t for t in TARGETS if (work / t).read_bytes() != (small_workflow / t).read_bytes()]
    assert not differ, f"separate-process chunked run differs from the local run: {differ}"


# --- run names --------------------------------------------------------------------------
@pytest.mark.slow
def test_named_run_never_touches_the_committed_tables(tmp_path):
    work = copy_project(tmp_path)
    shutil.copytree(ROOT / "results/tables", work / "results/tables")  # the committed searches' summary too
    before = {p.name: (p.read_bytes(), p.stat().st_mtime_ns) for p in (work / "results/tables").iterdir()}
    (work / "study.yaml").write_text(yaml.safe_dump({"run": "two_seeds", "seeds": {"first": 0, "count": 2}}))
    run_snakemake(work, "results/runs/two_seeds/tables/table_04.csv", "--configfile", "study.yaml")
    after = {p.name: (p.read_bytes(), p.stat().st_mtime_ns) for p in (work / "results/tables").iterdir()}
    assert after == before
    table = (work / "results/runs/two_seeds/tables/table_04.csv").read_text()
    assert table != (ROOT / "results/tables/table_04.csv").read_text() and ",2," in table  # n_seeds = 2
    # every output of the whole run, report included, lies in the run's folder
    plan = run_snakemake(work, "--configfile", "study.yaml", "--summary").stdout.splitlines()
    outputs = [line.split("\t")[0] for line in plan[1:] if line.strip()]
    assert "results/runs/two_seeds/report.html" in outputs
    assert all(o.startswith("results/runs/two_seeds/") for o in outputs), [
        o for o in outputs if not o.startswith("results/runs/two_seeds/")]


def test_report_names_its_run(small_workflow):
    html = (small_workflow / "results/report.html").read_text(encoding="utf-8")
    assert "Run: default (results/)" in html


@pytest.mark.parametrize("key, value", [("seeds", {"first": 0, "count": 4, "chunk": 0}),
                                        ("seeds", {"first": 0, "count": 4, "chunk": 2.5}),
                                        ("grid", {"seeds": {"first": 0, "count": 4, "chunk": -1}}),
                                        ("run", "../elsewhere"), ("run", "")])
def test_schema_rejects_bad_chunks_and_run_names(key, value):
    from snakemake.utils import validate

    config = yaml.safe_load((ROOT / "config/config.yaml").read_text())
    config[key] = {**config[key], **value} if isinstance(value, dict) else value
    with pytest.raises(Exception, match="chunk|run|does not match"):
        validate(config, str(ROOT / "workflow/schemas/config.schema.yaml"))
