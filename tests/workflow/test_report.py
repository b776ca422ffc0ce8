"""modal.thesis.report's reproduction summary and notes, and the HTML report
(pandas tables in the jinja2 template), on small hand-made frames."""

import numpy as np
import pandas as pd
import pytest

import modal.thesis.html as html
import modal.thesis.report as report
import modal.thesis.tables as tables
from modal.thesis.report import (VERDICT_CAUSE, VERDICT_CLOSE, VERDICT_NOISE, VERDICT_NOT, VERDICT_REPRODUCED,
                                 VERDICT_STAND_IN)

from workflow_run import ROOT

TEMPLATE = ROOT / "workflow/report/report.html.j2"
PNG = b"\x89PNG\r\n\x1a\n" + b"\x00" * 16


def row(mode, method, published, reproduced, interpretation="named", std=0.0, n_seeds=1, column="", flag="",
        printed=None, seed0_real_pole=False, real_pole_frac=0.0):
    """One tidy row as modal.thesis.tables.compare writes it (printed_match, z, rel_dev derived the same way)."""
    if printed is None:
        printed = "-----" if flag == "absent" else "*" if flag == "real_pole" else f"{published:.4f}"
    digits = len(printed.split(".")[1]) if "." in printed else 0
    match = bool(np.isfinite(reproduced) and printed[:1] not in "*-" and round(reproduced, digits) == float(printed))
    z = (published - reproduced) / std if std > 0 else np.nan
    return dict(table=1, mode=mode, method=method, interpretation=interpretation, column=column, printed=printed,
                published=published, flag=flag, reproduced=reproduced, std=std, n_seeds=n_seeds, z=z,
                rel_dev=(reproduced - published) / published, printed_match=match, seed0_real_pole=seed0_real_pole,
                real_pole_frac=real_pole_frac)


def frame(*rows):
    return pd.DataFrame(list(rows))


EXACT = [2.1623, 8.6493, 19.461]


def all_match(interpretation="named"):
    rows = [row(r + 1, "actual", w, w, interpretation) for r, w in enumerate(EXACT)]
    rows += [row(r + 1, m, w, w * (1 + 1e-7), interpretation) for m in ("tcm", "era") for r, w in enumerate(EXACT)]
    return rows


def test_all_values_match_is_reproduced():
    s = report.reproduction_summary({1: frame(*all_match())}, titles={1: "Demo"})
    assert list(s["table"]) == [1]
    r = s.iloc[0]
    assert r["verdict"] == VERDICT_REPRODUCED
    assert r["title"] == "Demo"
    assert (r["n_published"], r["n_compared"], r["n_match"]) == (9, 6, 6)
    assert r["why"] == "all 6 values match the printed digits"
    assert r["max_abs_rel_dev"] < 1e-6
    assert np.isnan(r["n_within_noise"])  # noise-free table


def test_large_deviation_is_not_reproduced_and_says_where():
    rows = all_match()
    rows[-1] = row(3, "era", 19.461, 25.0)  # ERA mode 3 off by 28 %
    s = report.reproduction_summary({6: frame(*rows)})
    r = s.iloc[0]
    assert r["verdict"] == VERDICT_NOT
    assert r["n_match"] == 5
    assert r["max_abs_rel_dev"] == pytest.approx((25.0 - 19.461) / 19.461)
    assert r["worst"] == "ERA r=3"
    assert "5 of 6 values match" in r["why"] and "28.5 %" in r["why"] and "ERA r=3" in r["why"]


def test_reference_columns_do_not_count():
    rows = all_match()
    rows[0] = row(1, "actual", 2.1623, 9.0)  # a wrong reference value
    rows.append(row(1, "est", 0.83, 5.0))
    r = report.reproduction_summary({1: frame(*rows)}).iloc[0]
    assert r["verdict"] == VERDICT_REPRODUCED
    assert r["n_compared"] == 6 and r["n_published"] == 10


def test_best_interpretation_is_the_one_that_matches():
    lower = [row(r + 1, m, w, w * 1.02, "lower") for m in ("tcm", "era") for r, w in enumerate(EXACT)]
    r = report.reproduction_summary({1: frame(*all_match("named"), *lower)}).iloc[0]
    assert r["interpretation"] == "named" and r["verdict"] == VERDICT_REPRODUCED
    assert "lower: 0/6 match (not reproduced)" in r["by_interpretation"]
    assert "named: 6/6 match (reproduced to the printed digits)" in r["by_interpretation"]


def test_smaller_deviation_wins_between_unreproduced_interpretations():
    far = [row(r + 1, "tcm", w, w * 1.5, "named") for r, w in enumerate(EXACT)]
    near = [row(r + 1, "tcm", w, w * 1.02, "lower") for r, w in enumerate(EXACT)]
    r = report.reproduction_summary({5: frame(*far, *near)}).iloc[0]
    assert r["interpretation"] == "lower" and r["verdict"] == VERDICT_NOT
    assert r["max_abs_rel_dev"] == pytest.approx(0.02)


def noisy(z_values, interpretation="lower"):
    """One noisy table: published values at the given z from a seed mean with std 0.1."""
    return [row(k + 1, "tcm", 10.0 + k, 10.0 + k - z * 0.1, interpretation, std=0.1, n_seeds=50)
            for k, z in enumerate(z_values)]


def test_noisy_table_within_noise_spread():
    # Bonferroni 0.05/6 with 49 degrees of freedom: |t| <= 2.75, t = z / sqrt(1 + 1/50)
    r = report.reproduction_summary({3: frame(*noisy([0.5, -1.5, 1.9, 2.5, -0.1, 1.0]))}).iloc[0]
    assert r["verdict"] == VERDICT_NOISE
    assert r["n_within_noise"] == 6 and r["n_match"] == 0
    assert r["t_critical"] == pytest.approx(2.75, abs=0.01)
    assert "6 of 6 consistent with the seed spread" in r["why"] and "<= 10 %" in r["why"]
    # 2.5 std is within 1 standard error of the bound at 50 seeds: not stable, with the seeds it would need
    assert r["stable"].startswith("no (about")
    far = report.reproduction_summary({3: frame(*noisy([0.5, -1.5, 1.0, 0.2, -0.1, 1.0]))}).iloc[0]
    assert far["verdict"] == VERDICT_NOISE and far["stable"] == "yes"


def test_noise_verdict_does_not_flip_with_the_seed_count():
    """The same published values at the same distance in std: 50 or 200 seeds give the same verdict when stable."""
    for z in ([0.3, -1.0, 5.0], [0.3, -1.0, 0.8]):
        verdicts = set()
        for n in (50, 200):
            rows = [{**r, "n_seeds": n} for r in noisy(z)]
            verdicts.add(report.reproduction_summary({3: frame(*rows)}).iloc[0]["verdict"])
        assert len(verdicts) == 1, (z, verdicts)


def test_wide_spread_does_not_confirm_a_large_deviation():
    # every published value within 2 std, but the seed spread is so wide that 30 % deviations pass the z test
    rows = [row(k + 1, "tcm", 10.0, 13.0, std=3.0, n_seeds=50) for k in range(3)]
    r = report.reproduction_summary({10: frame(*rows)}).iloc[0]
    assert r["verdict"] == VERDICT_NOT
    assert "3 of 3 consistent with the seed spread" in r["why"] and "30 % (TCM r=1) > 10 %" in r["why"]


def test_noisy_table_with_too_few_values_in_the_spread():
    r = report.reproduction_summary({3: frame(*noisy([0.5, -2.5, 3.0, 1.9, -5.0, 1.0]))}).iloc[0]
    assert r["verdict"] == VERDICT_NOT and r["cause"] == "unexplained"
    assert r["n_within_noise"] == 4  # 3.0 and 5.0 std are beyond the Bonferroni bound
    assert "4 of 6 consistent" in r["why"] and "rejected: TCM r=3" in r["why"] and "TCM r=5" in r["why"]
    caused = report.reproduction_summary({3: frame(*noisy([0.5, -2.5, 3.0, 1.9, -5.0, 1.0]))},
                                         causes={3: "the noise definition is not stated"}).iloc[0]
    assert caused["verdict"] == VERDICT_CAUSE and caused["cause"] == "the noise definition is not stated"


def test_noise_free_table_is_never_within_noise_spread():
    rows = [row(r + 1, "tcm", w, w * 1.02) for r, w in enumerate(EXACT)]
    assert report.reproduction_summary({1: frame(*rows)}).iloc[0]["verdict"] == VERDICT_NOT


def test_within_one_percent_is_graded_between_digits_and_noise():
    # Table 5 (lower): every value off the printed digits by at most 0.52 %
    rows = [row(r + 1, "tcm", w, w * (1 + 0.0052 * (-1) ** r)) for r, w in enumerate(EXACT)]
    r = report.reproduction_summary({5: frame(*rows)}).iloc[0]
    assert r["verdict"] == VERDICT_CLOSE
    assert "0 of 3 values match" in r["why"] and "0.52 % (TCM r=1) <= 1 %" in r["why"]
    # a value not identified is not "within 1 %"
    rows[2] = {**rows[2], "reproduced": np.nan, "rel_dev": np.nan}
    assert report.reproduction_summary({5: frame(*rows)}).iloc[0]["verdict"] == VERDICT_NOT


def test_value_not_identified_is_named():
    rows = noisy([0.1, 0.2, 0.3])
    rows[0] = {**rows[0], "reproduced": np.nan, "z": np.nan, "rel_dev": np.nan, "real_pole_frac": 1.0}
    r = report.reproduction_summary({3: frame(*rows)}).iloc[0]
    assert r["verdict"] == VERDICT_NOT  # a value not identified is not consistent with the noise
    rows[1] = {**rows[1], "reproduced": np.nan, "z": np.nan, "rel_dev": np.nan, "real_pole_frac": 1.0}
    r = report.reproduction_summary({3: frame(*rows)}).iloc[0]
    assert r["verdict"] == VERDICT_NOT
    assert "not identified" in r["why"] and "TCM r=1" in r["why"] and "TCM r=2" in r["why"]


def test_printed_real_pole_must_be_a_real_pole():
    base = [row(2, "era", 8.87, 8.87, column="n=4"), row(3, "era", 53.93, 53.93, column="n=4"),
            row(5, "era", np.nan, np.nan, column="n=4", flag="absent")]
    star_ok = row(1, "era", np.nan, 0.5, column="n=4", flag="real_pole", seed0_real_pole=True)
    star_bad = row(1, "era", np.nan, 5.84, column="n=4", flag="real_pole", seed0_real_pole=False)
    ok = report.reproduction_summary({6: frame(*base, star_ok)}).iloc[0]
    assert ok["verdict"] == VERDICT_REPRODUCED and ok["n_compared"] == 3  # the dash cell is not a value
    assert ok["n_published"] == 3
    bad = report.reproduction_summary({6: frame(*base, star_bad)}).iloc[0]
    assert bad["verdict"] == VERDICT_NOT
    assert "real pole (*) not reproduced at ERA r=1 n=4" in bad["why"]


def test_frames_as_read_from_csv(tmp_path):
    """seed0_real_pole comes back from CSV as text/objects; titles come from config."""
    frame(*all_match()).to_csv(tmp_path / "table_01.csv", index=False)
    rows = all_match()
    rows[3] = row(1, "tcm", 2.1623, 3.0)
    frame(*rows).to_csv(tmp_path / "table_02.csv", index=False)
    tables = report.load_tables(tmp_path)
    assert sorted(tables) == [1, 2]
    assert tables[1]["printed"].iloc[0] == "2.1623"
    s = report.reproduction_summary(tables, titles={1: "Identified frequencies"})
    assert list(s["verdict"]) == [VERDICT_REPRODUCED, VERDICT_NOT]
    assert list(s["title"]) == ["Identified frequencies", ""]
    assert sorted(report.load_tables(tmp_path, numbers={2})) == [2]


def test_notes_round_trip(tmp_path):
    notes = ["named: 6 of 6 match", "a note with | and *"]
    report.write_notes(tmp_path / "table_01.txt", notes)
    assert report.read_notes(tmp_path / "table_01.txt") == notes
    assert report.read_notes(tmp_path / "absent.txt") == [] and report.read_notes(None) == []


def test_summary_html_is_one_row_per_table():
    rows = all_match()
    rows[-1] = row(3, "era", 19.461, 25.0)
    tables = {1: frame(*all_match()), 2: frame(*rows), 3: frame(*noisy([0.5, -1.5, 1.9]))}
    summary = report.reproduction_summary(tables, titles={1: "a <b>"})
    shown = html.summary_frame(summary)
    assert list(shown["Table"]) == [1, 2, 3]
    assert list(shown["Verdict"]) == [VERDICT_REPRODUCED, VERDICT_NOT, VERDICT_NOISE]
    # 25 against 19.461: 28.5 % off, in percent to three significant digits
    assert shown["Largest abs. deviation"].iloc[1] == "28.5 %"
    text = html.summary_html(summary)
    assert text.count("<tr") == 1 + 3  # heading and three tables
    assert "a &lt;b&gt;" in text  # escaped by pandas


def test_report_page_from_the_template(tmp_path):
    summary = report.reproduction_summary({1: frame(*all_match())}, titles={1: "Demo"})
    png = tmp_path / "figure_01.png"
    png.write_bytes(PNG)
    page = html.render_report(
        TEMPLATE, summary, report.VERDICT_DEFINITIONS,
        {1: dict(title="Demo", frame=frame(*all_match()), notes=["a <note>"]), 2: dict(title="Later", frame=None)},
        {1: dict(caption="Mode shapes <TCM>", png=png), 2: dict(caption="Noise", png=None)},
        [dict(heading="Extra", caption="Not in the thesis", png=png)],
        html.provenance(ROOT, {"seeds": {"count": 50, "first": 0}}, {"seeds": {"count": 5, "first": 0}},
                        ["config/config.yaml", "my.yaml"]))
    assert page.startswith("<!DOCTYPE html>") and page.rstrip().endswith("</html>")
    assert page.count("data:image/png;base64,") == 2
    assert "<figcaption>Figure 1. Mode shapes &lt;TCM&gt;</figcaption>" in page
    assert "Figure 2 (Noise) not produced yet." in page
    assert "<h3>Table 2. Later</h3>\n<p class=\"missing\">Not produced yet.</p>" in page
    assert "<li>a &lt;note&gt;</li>" in page
    assert page.index('id="summary"') < page.index('id="tables"') < page.index('id="figures"')
    assert "Of 1 tables: 1 reproduced to the printed digits." in page
    assert "src=\"http" not in page and "<link" not in page  # nothing fetched from elsewhere
    # provenance: commit, config layered over the default as a diff, versions, date
    assert "<td><code>seeds.count</code></td><td>50</td><td>5</td>" in page
    assert "<code>my.yaml</code>" in page and "numpy " in page and " UTC" in page
    assert "from commit <code>" in page and "unknown" not in page.split("from commit")[1][:60]
    # wide tables scroll in their own box; headings in words
    assert '<div class="scroll"><table' in page and "ours, named" in page and "tcm (thesis)" not in page
    # the thesis layout: one row per mode, the printed value beside ours
    layout = tables.thesis_layout(frame(*all_match()).assign(actual=np.nan))
    assert list(layout.index) == [1, 2, 3] and layout.loc[1, "tcm (thesis)"] == "2.1623"
    assert layout.loc[1, "tcm (named)"] == "2.1623"


def test_aggregate_matches_modes_across_real_poles():
    # Seed 1 loses mode 1 to a real pole: by position its entries would mix
    # modes; matched to the exact frequencies, every mode keeps its own values.
    import modal.thesis.tables as mt

    rows = []
    exact = [2.0, 8.0, 18.0]
    for seed, entries in ((0, [(2.01, False), (8.02, False), (18.1, False)]),
                          (1, [(0.5, True), (7.98, False), (17.9, False)]),
                          (2, [(1.99, False), (8.00, False), (18.0, False)])):
        for mode, (omega, real) in enumerate(entries, start=1):
            rows.append(dict(method="era", n=3, cols=100, seed=seed, mode=mode, omega=omega, real_pole=real,
                             actual=exact[mode - 1], participating=3))
    stats = mt.aggregate(pd.DataFrame(rows), first_seed=0).set_index("mode")
    assert stats.loc[1, "reproduced"] == pytest.approx(2.0)
    assert stats.loc[1, "missed_frac"] == pytest.approx(1 / 3)
    assert stats.loc[2, "reproduced"] == pytest.approx((8.02 + 7.98 + 8.00) / 3)
    assert stats.loc[3, "reproduced"] == pytest.approx((18.1 + 17.9 + 18.0) / 3)
    assert set(stats["matched_by"]) == {"frequency"}
    # the same entries without real poles: positions are stable, so positions are modes
    clean = pd.DataFrame(rows).assign(real_pole=False)
    assert set(mt.aggregate(clean, first_seed=0)["matched_by"]) == {"position"}


def test_stand_in_table_is_judged_by_its_findings():
    rows = noisy([0.5, -1.0, 1.0])
    ok = [dict(finding="multiple data sets help the ERA", holds=True, numbers="28 % -> 18 %")]
    r = report.reproduction_summary({13: frame(*rows)}, stand_in={13: ok}).iloc[0]
    assert r["verdict"] == VERDICT_STAND_IN and "multiple data sets help the ERA" in r["why"]
    bad = [dict(ok[0], holds=False)]
    r = report.reproduction_summary({13: frame(*rows)}, stand_in={13: bad}).iloc[0]
    assert r["verdict"] == VERDICT_CAUSE and "virtual grid" in r["cause"] and "data sets" in r["cause"]


def test_headline_counts_the_verdicts_in_scale_order():
    tables = {1: frame(*all_match()), 2: frame(*noisy([0.1, 0.2, 9.0])), 3: frame(*noisy([0.1, 0.2, 0.3]))}
    summary = report.reproduction_summary(tables, causes={2: "not stated"})
    assert report.headline(summary) == ("Of 3 tables: 1 reproduced to the printed digits, 1 within 1 %, "
                                        "1 not reproduced, cause known.")
