"""The thesis reproduction layer: everything that turns the engine into the
thesis's tables, figures and report.

Config checks (:mod:`.config`), the beam studies of Ch. 6 (:mod:`.study`),
the grid chapter (:mod:`.grid_study`), published-against-reproduced tables
(:mod:`.tables`), computed notes and verdicts (:mod:`.report`), figures
(:mod:`.plots`), the HTML page (:mod:`.html`) and the notebooks' display
helpers (:mod:`.display`). It imports the engine (:mod:`modal`); the engine
never imports it. Submodules are imported explicitly (``import
modal.thesis.plots``), so reading a table never loads matplotlib.
"""
