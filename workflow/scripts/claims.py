"""The thesis's findings as checks -> results/tables/claims.csv (rule
``claims``): each claim quoted with its section, its criterion, whether it
holds and the numbers behind it (modal.thesis.claims)."""

import modal.thesis.claims
import modal.thesis.intermediates
import modal.thesis.tables
from _helpers import start_job

start_job(snakemake)

p = snakemake.params
identified = {study: modal.thesis.intermediates.read_identified(path, p.studies[study], p.seeds)
              for study, path in zip(p.study_names, snakemake.input.identified, strict=True)}
grid = (modal.thesis.intermediates.read_grid_identified(snakemake.input.grid[0], p.grid)
        if snakemake.input.get("grid") else None)
claims = modal.thesis.claims.evaluate_claims(identified, p.tables, p.beams, p.studies, grid, p.grid)
modal.thesis.tables.write_csv(claims, snakemake.output[0])  # text: numbers by precision.percent
