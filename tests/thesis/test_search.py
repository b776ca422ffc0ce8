"""Searches of the thesis's unstated settings (modal.thesis.search): the
settings a search plans, their scores against the printed tables, the best
setting and how the reproduction summary cites them."""

from pathlib import Path

import numpy as np
import pandas as pd
import pytest
import yaml

from modal.thesis import report, search, study, tables

ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="module")
def config():
    with open(ROOT / "config/config.yaml", encoding="utf-8") as fh:
        return yaml.safe_load(fh)


def settings_of(config, spec):
    return search.search_settings(spec, config["studies"], config["beams"], config["tables"])


def test_settings_are_the_product_first_key_slowest(config):
    spec = {"question": "q", "study": "cera", "tables": [7, 9],
            "vary": {"beam.samples_per_period": [5, 10], "methods.cera.cols": [200, 1440, 720]}}
    settings = settings_of(config, spec)
    assert list(settings) == [f"s{k:03d}" for k in range(6)]
    assert [tuple(s["values"].values()) for s in settings.values()] == [
        (5, 200), (5, 1440), (5, 720), (10, 200), (10, 1440), (10, 720)]
    # the config's own setting is marked, and each setting lands where its key says
    assert [s["default"] for s in settings.values()] == [False, False, False, False, True, False]
    s = settings["s003"]
    assert s["beam"]["samples_per_period"] == 10 and s["study"]["methods"]["cera"]["cols"] == 200
    assert s["beam"]["length"] == config["beams"]["beam10"]["length"]
    # only the tables' cases (c1, c3 of Tables 7 and 9), no CERA width sweep inside a setting
    assert sorted(s["study"]["cases"]) == ["c1", "c3"] and "cols_sweep" not in s["study"]
    # planning copies: the config is untouched
    assert config["studies"]["cera"]["methods"]["cera"]["cols"] == 1440 and "cols_sweep" in config["studies"]["cera"]


def test_noise_model_defaults_mark_the_default(config):
    spec = {"question": "q", "study": "demo", "tables": [3],
            "vary": {"noise_model.scale": ["proportional", "channel_rms"]}}
    settings = settings_of(config, spec)
    assert [s["default"] for s in settings.values()] == [False, True]
    assert settings["s000"]["study"]["noise_model"] == {"scale": "proportional", "velocity": "noisy"}


@pytest.mark.parametrize("vary, message", [
    ({"methods.cera.cols": [100]}, "'methods.cera.cols' is not a setting of the study"),  # demo runs no CERA
    ({"beam.stiffness": [1.0]}, "'beam.stiffness' is not a setting of the study"),
])
def test_unknown_keys_are_refused(config, vary, message):
    with pytest.raises(ValueError, match=message):
        settings_of(config, {"question": "q", "study": "demo", "tables": [3], "vary": vary})


def test_too_many_settings_are_refused(config):
    vary = {"methods.era.rows": list(range(1, 30)), "methods.era.cols": list(range(100, 120))}
    with pytest.raises(ValueError, match="580 settings, more than 500"):
        settings_of(config, {"question": "q", "study": "demo", "tables": [3], "vary": vary})


@pytest.mark.slow
def test_score_of_the_own_setting_is_the_tables_verdict(config):
    """Scoring the config's own setting of the noise-free spillover study
    gives Table 6's committed comparison: the same matches and deviations."""
    spec = {"question": "q", "study": "spillover", "tables": [6],
            "vary": {"methods.era.rows": [24], "methods.era.cols": [100]}}
    setting = settings_of(config, spec)["s000"]
    seeds = config["seeds"]
    identified = {name: study.run_study(setting["study"], setting["beam"], config["interpretations"][name], seeds)
                  for name in setting["study"]["interpretations"]}
    published = tables.read_published(ROOT / config["published"])
    scores = search.score_setting(published, identified, {6: config["tables"][6]}, setting["study"], seeds["first"])
    committed = report.assess_table(tables.read_table(ROOT / "results/tables/table_06.csv"))
    assert sorted(scores["interpretation"]) == sorted(committed)
    for _, row in scores.iterrows():
        mine = committed[row["interpretation"]]
        assert row["n_match"] == mine["n_match"] and row["verdict"] == mine["verdict"]
        assert row["mean_abs_dev"] == pytest.approx(mine["mean_abs_dev"], rel=1e-5)  # the file keeps 6 digits
        assert not row["noisy"] and np.isnan(row["log_likelihood"])


def cell(mode, published, mean, std, n_seeds=50):
    return dict(table=3, mode=mode, method="tcm", column="", printed=f"{published}", published=published,
                flag="", reproduced=mean, std=std, n_seeds=n_seeds, rel_dev=(mean - published) / published,
                printed_match=False, seed0_real_pole=False, real_pole_frac=0.0, interpretation="named")


def test_log_likelihood_is_the_student_t_prediction_density():
    from scipy import stats

    frame = pd.DataFrame([cell(1, 10.0, 10.0, 0.1), cell(2, 20.0, 20.2, 0.1, n_seeds=10)])
    got = report.assess_table(frame)["named"]["log_likelihood"]
    s1, s2 = 0.1 * np.sqrt(1 + 1 / 50), 0.1 * np.sqrt(1 + 1 / 10)
    want = stats.t.logpdf(0.0, 49) - np.log(s1) + stats.t.logpdf(-0.2 / s2, 9) - np.log(s2)
    assert got == pytest.approx(want, rel=1e-12)
    # a printed value further from the seed mean is less likely
    worse = pd.DataFrame([cell(1, 10.0, 10.05, 0.1), cell(2, 20.0, 20.2, 0.1, n_seeds=10)])
    assert report.assess_table(worse)["named"]["log_likelihood"] < got


def scores_frame(rows):
    base = dict(noisy=True, n_compared=6, n_match=0, n_missing=0, mean_abs_dev=0.01, max_abs_dev=0.02,
                max_t=2.0, table=3)
    return pd.DataFrame([{**base, **r} for r in rows])


def test_best_is_by_verdict_then_likelihood():
    rows = [
        dict(setting="s000", values="a = 1", default=True, interpretation="named", rank=5, n_consistent=4,
             log_likelihood=9.0, verdict=report.VERDICT_NOT),
        dict(setting="s001", values="a = 2", default=False, interpretation="named", rank=5, n_consistent=5,
             log_likelihood=12.0, verdict=report.VERDICT_NOT),
        dict(setting="s002", values="a = 3", default=False, interpretation="named", rank=5, n_consistent=6,
             log_likelihood=3.0, verdict=report.VERDICT_NOT),
    ]
    out = search.search_summary("s", {"question": "q"}, scores_frame(rows)).iloc[0]
    assert out["best"] == "a = 2" and not out["explains"]  # same verdict: the likeliest
    assert out["default"] == "a = 1" and "log-likelihood 9.0" in out["default_fit"]
    rows[2].update(rank=2, verdict=report.VERDICT_NOISE)
    out = search.search_summary("s", {"question": "q"}, scores_frame(rows)).iloc[0]
    assert out["best"] == "a = 3" and out["explains"]  # a better verdict beats a higher likelihood
    assert out["best_overall"] == "a = 3 (named)" and out["overall_explains"] == "1 of 1"


def test_noise_free_best_is_the_smallest_deviation():
    rows = [dict(setting=f"s00{k}", values=f"r = {k}", default=k == 0, interpretation="lower", rank=5, noisy=False,
                 n_match=2, n_consistent=np.nan, log_likelihood=np.nan, mean_abs_dev=dev, verdict=report.VERDICT_NOT)
            for k, dev in enumerate([0.2, 0.05, 0.1])]
    out = search.search_summary("s", {"question": "q"}, scores_frame(rows)).iloc[0]
    assert out["best"] == "r = 1" and "mean |deviation| 5.00 %" in out["best_fit"]


def summary_row(explains, cause=None):
    frame = pd.DataFrame([{**cell(k + 1, 10.0 * (k + 1), 10.0 * (k + 1) * 1.05, 0.01), "printed_match": False}
                          for k in range(3)])
    searched = pd.DataFrame([dict(search="s", question="q", table=3, n_settings=4, default="a = 1",
                                  default_verdict="", default_fit="", best="a = 2", best_interpretation="named",
                                  best_verdict=report.VERDICT_NOISE if explains else report.VERDICT_NOT,
                                  best_fit="6/6 consistent", explains=explains, best_overall="", overall_explains="")])
    return report.reproduction_summary({3: frame}, causes={3: cause} if cause else None, searches=searched).iloc[0]


def test_summary_cites_the_searches():
    r = summary_row(explains=True)
    assert r["verdict"] == report.VERDICT_CAUSE
    assert r["cause"].startswith("a setting the thesis does not state; search 's' (4 settings): a = 2 (named) makes")
    r = summary_row(explains=False)
    assert r["verdict"] == report.VERDICT_NOT
    assert r["cause"] == ("unexplained; search 's' (4 settings): no setting explains it; best a = 2 (named): "
                          "6/6 consistent")
    # a supposed cause that its search does not confirm is no known cause
    r = summary_row(explains=False, cause="the noise is not defined")
    assert r["verdict"] == report.VERDICT_NOT and r["cause"].startswith("unexplained (supposed: the noise is not")
    r = summary_row(explains=True, cause="the noise is not defined")
    assert r["verdict"] == report.VERDICT_CAUSE and r["cause"].startswith("the noise is not defined; search 's'")


def test_two_adjacent_era_real_poles_share_one_row_of_the_thesis_layout():
    # Table 6, n = 4: 2n = 8 states give two real eigenvalues and three complex pairs; the thesis prints one
    # '*' and then the three pairs at r = 2..4. A TCM real pole (one eigenvalue of an n x n problem) keeps its row.
    import pandas as pd

    from modal.thesis.tables import aggregate

    omega = [0.17, 1.67, 8.68, 54.06, 77.84]
    era = pd.DataFrame(dict(method="era", n=4, cols=100, seed=-1, mode=range(1, 6), omega=omega,
                            real_pole=[True, True, False, False, False], actual=[2.16, 8.65, 19.46, 34.6, 54.06]))
    stats = aggregate(era, -1).set_index("mode")
    assert list(stats.index) == [1, 2, 3, 4]
    assert stats.loc[1, "seed0_real_pole"] and stats.loc[1, "real_pole_frac"] == 1.0
    assert list(stats.loc[2:, "reproduced"]) == [8.68, 54.06, 77.84]
    assert list(stats["actual"]) == [2.16, 8.65, 19.46, 34.6]
    tcm = aggregate(era.assign(method="tcm"), -1).set_index("mode")
    assert list(tcm.index) == [1, 2, 3, 4, 5] and tcm.loc[2, "seed0_real_pole"]


def test_a_table_within_one_percent_names_its_remaining_cause():
    # Table 8 under the guideline reading: within 1 %; the config's cause names what remains, with the closest
    # setting of each search that tried it. Without a config cause the column stays empty.
    frame = pd.DataFrame([{**cell(k + 1, 10.0 * (k + 1), 10.0 * (k + 1) * 1.004, 0.0), "n_seeds": 1, "std": 0.0,
                           "printed_match": False} for k in range(3)])
    searched = pd.DataFrame([dict(search="d", question="q", table=3, n_settings=12, default="(not searched)",
                                  default_verdict="", default_fit="", best="m = modal", best_interpretation="g",
                                  best_verdict=report.VERDICT_CLOSE, best_fit="0/3 match", explains=True,
                                  best_overall="", overall_explains="")])
    row = report.reproduction_summary({3: frame}, causes={3: "unexplained"}, searches=searched).iloc[0]
    assert row["verdict"] == report.VERDICT_CLOSE
    assert row["cause"] == ("remaining deviation: unexplained; search 'd' (12 settings): closest m = modal (g): "
                            "0/3 match (within 1 %)")
    assert report.reproduction_summary({3: frame}, searches=searched).iloc[0]["cause"] == ""


def test_era_rows_of_one_mode_across_seeds_stay_one_row():
    # The grid tables aggregate one mode's entries over seeds (modal.thesis.grid_study): every seed is its own
    # identification, so real poles in some seeds pair with nothing and nothing shifts.
    import pandas as pd

    from modal.thesis.tables import aggregate

    frame = pd.DataFrame(dict(method="era", n=4, cols=100, seed=[0, 1, 2], mode=2, omega=[5.7, 26.2, 27.7],
                              real_pole=[True, False, False], actual=8.0))
    stats = aggregate(frame, 0)
    assert len(stats) == 1 and stats["reproduced"].iloc[0] == pytest.approx(26.95)
    assert stats["real_pole_frac"].iloc[0] == pytest.approx(1 / 3) and stats["actual"].iloc[0] == 8.0


def test_a_setting_runs_as_each_interpretation_reads_the_study_searched_values_on_top():
    studies = {"cera": {"beam": "b", "interpretations": ["named", "guideline"], "cases": {"c1": {"damping": 0.0,
                                                                                                   "noise": 0.0}},
                        "methods": {"cera": {"n_modes": 6, "cols": 1440, "start": 0}}, "cols_sweep": [300]}}
    beams = {"b": {"samples_per_period": 10, "period_mode": 6, "n_samples": 3594}}
    tables = {7: {"study": "cera", "case": "c1"}}
    spec = {"study": "cera", "tables": [7], "vary": {"signals.cera": ["displacement"], "methods.cera.cols": [491]}}
    (setting,) = search.search_settings(spec, studies, beams, tables).values()
    assert not setting["default"] and "signals" not in setting["study"]
    guideline = {"tcm": ["velocity", "acceleration"], "era": "acceleration", "cera": "velocity",
                 "studies": {"cera": {"beam": {"period_mode": 3, "n_samples": 899}, "cols_sweep": [500],
                                      "methods": {"cera": {"cols": 500, "eigenproblem": "as_printed"}}}}}
    study, beam, signals = search.setting_under(setting, guideline, "cera")
    assert study["methods"]["cera"] == {"n_modes": 6, "cols": 491, "start": 0, "eigenproblem": "as_printed"}
    assert beam["period_mode"] == 3 and beam["n_samples"] == 899 and "cols_sweep" not in study
    assert signals == {"tcm": ["velocity", "acceleration"], "era": "acceleration", "cera": "displacement"}
    named = {"tcm": ["velocity", "acceleration"], "era": "acceleration", "cera": "acceleration"}
    study, beam, signals = search.setting_under(setting, named, "cera")
    assert study["methods"]["cera"]["cols"] == 491 and beam == beams["b"] and signals["cera"] == "displacement"
    with pytest.raises(ValueError, match="signals.tcm"):
        search.search_settings({**spec, "vary": {"signals.tcm": ["velocity"]}}, studies, beams, tables)
