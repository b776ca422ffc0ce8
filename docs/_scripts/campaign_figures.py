"""The campaign pictures of the documentation (docs/img/): a simulated year
of the shear frame (one five-minute record every 24.5 h, its stiffness
following the temperature) and Palisaden's 90 minutes cut into eighteen
5-minute records (../shared/data/palisaden beside the checkout), each run
with ``modal campaign``; the tracked frequencies drawn with their bands and,
for the simulation, the truth.

Run from the checkout: ``.venv/bin/python docs/_scripts/campaign_figures.py``
"""

import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np
import pandas as pd
from matplotlib.figure import Figure

import modal
from modal.campaign import simulate_campaign, tracking_figure

ROOT = Path(__file__).resolve().parents[2]
PALISADEN = ROOT.parent / "shared" / "data" / "palisaden" / "palisaden_accel_100Hz_float32.npy"


def campaign(config: Path, out: Path) -> None:
    subprocess.run([sys.executable, "-m", "modal", "campaign", str(config), "--out", str(out), "--cores", "2"],
                   check=True, capture_output=True)


with tempfile.TemporaryDirectory() as tmp:
    tmp = Path(tmp)
    truth = simulate_campaign(tmp / "year", n_records=358, every_hours=24.5, duration=300.0)
    campaign(tmp / "year" / "campaign.yaml", tmp / "year_out")
    tracked = pd.read_csv(tmp / "year_out" / "tracked.csv", parse_dates=["time"])
    figure = Figure(figsize=(10, 6.5))
    axes = figure.subplots(4, 1, sharex=True)
    for k, ax in enumerate(axes, start=1):
        t, true = tracked[tracked["mode"] == k], truth[truth["mode"] == k]
        ax.errorbar(t["time"], t["freq_hz"], yerr=1.96 * t["freq_std_hz"], fmt=".", ms=2, lw=0.6, color="C0",
                    label="identified, ±1.96 std")
        ax.plot(true["time"], true["freq_hz"], "-", color="C3", lw=0.8, label="true")
        ax.set_ylabel(f"mode {k} (Hz)", fontsize=8)
        ax.tick_params(labelsize=7)
    axes[0].legend(fontsize=7, loc="upper right")
    axes[0].set_title("A simulated year: the shear frame's four modes follow the temperature", fontsize=9)
    figure.tight_layout()
    figure.savefig(ROOT / "docs" / "img" / "campaign_year.png", dpi=90)
    summary = tracked.merge(truth, on=["record", "mode"], suffixes=("", "_true"))
    covered = np.abs(summary["freq_hz"] - summary["freq_hz_true"]) <= 1.96 * summary["freq_std_hz"]
    print("year:", len(truth["record"].unique()), "records;", summary.groupby("mode").size().to_dict(),
          "tracked; coverage of +-1.96 std:", f"{covered.mean():.3f}")

    records = tmp / "palisaden" / "records"
    records.mkdir(parents=True)
    acc = np.load(PALISADEN).astype(float)
    rows = []
    for k in range(18):
        start = pd.Timestamp("2019-01-01 12:00") + pd.Timedelta(minutes=5 * k)
        name = f"palisaden_{start:%H%M}.npz"
        modal.save_record_npz(records / name, acc[k * 30000:(k + 1) * 30000], 0.01)
        rows.append({"path": f"records/{name}", "time": start.isoformat()})
    pd.DataFrame(rows).to_csv(tmp / "palisaden" / "index.csv", index=False)
    (tmp / "palisaden" / "campaign.yaml").write_text(
        "records: {index: index.csv}\nidentify: {excitation: ambient, fmax: 5, highpass_hz: 0.5}\nchunk: 6\n")
    campaign(tmp / "palisaden" / "campaign.yaml", tmp / "palisaden_out")
    tracked = pd.read_csv(tmp / "palisaden_out" / "tracked.csv", parse_dates=["time"])
    references = pd.read_csv(tmp / "palisaden_out" / "references.csv")
    tracking_figure(tracked, references).savefig(ROOT / "docs" / "img" / "campaign_palisaden.png", dpi=80)
    print("palisaden:", references[["mode", "freq_hz", "n_records"]].to_string(index=False))
    print(tracked.groupby("mode")["freq_hz"].agg(["mean", "std", "count"]))
