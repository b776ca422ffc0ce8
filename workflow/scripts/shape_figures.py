"""Mode-shape figures (thesis Figures 1-8): identified mode shapes against the exact ones."""
import modal.thesis.intermediates
import modal.thesis.plots
from _helpers import start_job

start_job(snakemake)

identified = modal.thesis.intermediates.read_interpretations(
    snakemake.input.identified, snakemake.params.study["interpretations"], snakemake.params.study, snakemake.params.seeds)
for path, (title, fig) in zip(snakemake.output, modal.thesis.plots.numbered(snakemake.params.figures,
                                                                          snakemake.params.captions)):
    modal.thesis.plots.shape_figure(snakemake.params.beam, identified, fig["case"], fig["method"],
                                    snakemake.params.seeds["first"], title).savefig(path, dpi=120)
