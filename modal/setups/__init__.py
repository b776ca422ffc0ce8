"""Roving-sensor tests: channel tables (what each channel measures, where),
geometry, several setups merged into one set of modes and shapes in the
global frame, and the shapes drawn on the structure."""

from ._channels import direction_from_angles, read_channel_table, read_pyoma_setup, unit_factor
from ._geometry import Geometry, read_geometry
from ._drawing import draw_mode, mode_shape_animation, mode_shape_figure, modes_figure, node_motion
from ._merge import (MergedModes, Setup, check_setups, identify_setup, merge_setups, node_neighbours, node_shapes,
                     normalise, read_setup, required_setups)
from ._results import draw_modes, write_setups
from ._simulated import plate_roving_test, save_geometry, save_setup

# normalise, node_neighbours and required_setups are helpers of the merge (the command line prints the
# majority; a campaign's report draws its shapes by the merge's rule), unit_factor of the channel
# tables, importable from here; the names below are also re-exported by modal.
__all__ = [
    "Geometry", "MergedModes", "Setup", "check_setups", "direction_from_angles", "draw_mode", "draw_modes",
    "identify_setup", "merge_setups", "mode_shape_animation", "mode_shape_figure", "modes_figure",
    "node_motion", "node_shapes", "plate_roving_test", "read_channel_table", "read_geometry",
    "read_pyoma_setup", "read_setup", "save_geometry", "save_setup", "write_setups",
]
