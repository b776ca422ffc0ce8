"""Mode-shape figures (thesis Figures 1-8): identified mode shapes against the exact ones."""
import modal.thesis.intermediates
import modal.thesis.plots
from _helpers import mock_snakemake, start_job

if "snakemake" not in globals():
    snakemake = mock_snakemake("shape_figures")
start_job(snakemake)

identified = modal.thesis.intermediates.read_interpretations(
    snakemake.input.identified, snakemake.params.interpretations, snakemake.config["studies"]["demo"],
    snakemake.config["seeds"])
for path, (title, fig) in zip(snakemake.output, modal.thesis.plots.numbered(snakemake.params.figures,
                                                                          snakemake.params.captions)):
    modal.thesis.plots.shape_figure(snakemake.params.beam, identified, fig["case"], fig["method"],
                                    snakemake.params.first_seed, title).savefig(path, dpi=120)
