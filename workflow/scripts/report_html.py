"""results/report.html: one self-contained page with the reproduction summary,
every thesis table and every figure (PNG embedded as base64)."""
import re
import sys
from pathlib import Path

import yaml

import modal.thesis.report

sys.stderr = open(snakemake.log[0], "w")
captions = yaml.safe_load(Path(snakemake.input.captions).read_text())
files = [Path(f) for f in snakemake.input.outputs]


def numbered(prefix, suffix):
    return {int(m.group(1)): f for f in files if (m := re.fullmatch(rf"{prefix}_(\d\d){suffix}", f.name))}


csvs, mds, pngs = numbered("table", r"\.csv"), numbered("table", r"\.md"), numbered("figure", r"\.png")
tables = {}
for number, path in csvs.items():
    tables.update(modal.thesis.report.load_tables(path.parent, numbers={number}))
summary = modal.thesis.report.reproduction_summary(tables)
# every thesis table and figure has a place; those not produced are listed as missing
table_md = {n: (mds[n].read_text() if n in mds else None) for n in sorted(set(captions["tables"]) | set(mds))}
figures = {n: (pngs[n].read_bytes() if n in pngs else None) for n in sorted(set(captions["figures"]) | set(pngs))}
extras = []
cera = [f for f in files if f.name == "cera_sensitivity.png"]
if cera:
    extras.append(("CERA sensitivity to the Hankel width s", None, cera[0].read_bytes(),
                   captions["extras"]["cera_sensitivity"]))
html = modal.thesis.report.report_html(summary, table_md, figures, captions["figures"], extras,
                                title="Reproduction report", intro=Path(snakemake.input.intro).read_text())
Path(snakemake.output[0]).write_text(html)
