"""results/report.html: one self-contained page (jinja2 template under
workflow/report/) with the reproduction summary, every thesis table in its
layout with the computed notes, and every figure (PNG embedded)."""
from pathlib import Path

import pandas as pd
import yaml

import modal.thesis.html
import modal.thesis.report
import modal.thesis.tables
from _helpers import start_job

start_job(snakemake)

captions = yaml.safe_load(Path(snakemake.input.captions).read_text(encoding="utf-8"))
files = {Path(f).name: Path(f) for f in snakemake.input.outputs}
summary = pd.read_csv(snakemake.input.summary)
tables = {}
for number, title in snakemake.params.titles.items():
    csv = files.get(f"table_{number:02d}.csv")
    frame = None if csv is None else modal.thesis.tables.read_table(csv)
    tables[number] = dict(title=title, frame=frame,
                          notes=modal.thesis.report.read_notes(files.get(f"table_{number:02d}.txt")))
figures = {int(n): dict(caption=text, png=files.get(f"figure_{int(n):02d}.png"))
           for n, text in captions["figures"].items()}
extras = []
if "cera_sensitivity.png" in files:
    extras.append(dict(heading="CERA sensitivity to the Hankel width s", png=files["cera_sensitivity.png"],
                       caption=captions["extras"]["cera_sensitivity"]))
for name, spec in sorted((snakemake.params.measured or {}).items()):
    folder = f"measured/{name}/"
    paths = {Path(f).name: Path(f) for f in snakemake.input.outputs if folder in str(f)}
    modes = pd.read_csv(paths["modes.csv"])
    if "setups" in spec:
        extras.append(dict(
            heading=f"Roving test '{name}': {len(spec['setups'])} setups merged, the modes on the structure",
            png=paths["modes.png"], frame=modes.drop(columns="setups").round(4),
            caption=(f"{len(spec['setups'])} setups ({spec['excitation'].replace('_', ' ')}) identified one by one "
                     "and merged through their reference channels, as `modal identify SETUP ... --geometry` does: "
                     "each mode drawn on the geometry (undeformed dashed, measured nodes red); the table gives "
                     "frequency and damping (mean over the setups that selected the mode, the standard deviation "
                     "of that mean and the setups' spread), the setups "
                     "that selected it or held it in their diagram, the smallest reference MAC and the MPC."),
        ))
        continue
    extras.append(dict(
        heading=f"Measured record '{name}': modes from the stabilisation diagram",
        png=paths["stabilisation.png"], frame=modes.round(4),
        caption=(f"{spec['path']} ({spec['excitation'].replace('_', ' ')}): stabilisation diagram over the "
                 "spectrum; the table lists the modes selected automatically (stable poles clustered; mean and "
                 "std of frequency and damping, pole count, MPC, MAMC), as `modal identify` writes them."),
    ))
template = next(Path(t) for t in snakemake.input.template if t.endswith(".j2"))
default = yaml.safe_load(Path(snakemake.input.default_config).read_text(encoding="utf-8"))
provenance = modal.thesis.html.provenance(Path.cwd(), default, snakemake.params.used_config,
                                             snakemake.params.configfiles)
provenance["run"] = snakemake.params.run
claims = pd.read_csv(snakemake.input.claims)
searches = pd.read_csv(snakemake.input.searches[0]) if snakemake.input.searches else None
html = modal.thesis.html.render_report(template, summary, modal.thesis.report.VERDICT_DEFINITIONS, tables, figures,
                                       extras, provenance, claims, searches)
Path(snakemake.output[0]).write_text(html, encoding="utf-8")
