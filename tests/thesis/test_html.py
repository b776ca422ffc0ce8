"""The HTML report's layout of a measured record's modes."""

from pathlib import Path

import pandas as pd
from matplotlib.figure import Figure

from modal.thesis import html

ROOT = Path(__file__).resolve().parents[2]


def test_measured_modes_table_does_not_take_the_summary_widths(tmp_path):
    """The report's table of a record's modes is not styled as the summary,
    whose second and eleventh columns are held 14em and 22em wide (they
    pushed a six-channel record's last shape column off a 1400 px screen):
    only the summary's and the searches' prose tables carry those rules."""
    png = tmp_path / "diagram.png"
    Figure(figsize=(1, 1)).savefig(png)
    modes = pd.DataFrame({"mode": [1], "freq_hz": [1.88], **{f"phi_{c}": [0.1 * c] for c in range(6)}})
    summary = pd.read_csv(ROOT / "results" / "tables" / "summary.csv")
    page = html.render_report(ROOT / "workflow" / "report" / "report.html.j2", summary, [], {}, {},
                              [dict(heading="record", caption="modes", png=png, frame=modes)],
                              html.provenance(ROOT, {}, {}, ["config/config.yaml"]))
    measured = page[page.index('id="extras"'):].split("</table>")[0]
    assert 'class="dataframe modes"' in measured and "summary" not in measured
    css = (ROOT / "workflow" / "report" / "report.css").read_text()
    widened = [rule for rule in css.splitlines() if "min-width: 1" in rule or "min-width: 2" in rule]
    assert widened and all(rule.startswith(("table.summary", "table.searches")) for rule in widened)
