"""Write tests/data/roving_plate/: a simulated roving test of a simply
supported plate (modal.plate_roving_test: 1.2 m x 0.8 m, modes 5.01, 9.64,
15.43, 17.36, 20.05 Hz; 6 setups of 2 references and 3 roving
accelerometers, 120 s at 100 Hz, 2 % noise, seed 0) in the project's own
format: setup_<k>/record.npz (float32) and channels.csv, geometry/nodes.csv
and lines.csv. Deterministic: rerunning writes the same numbers.

Run from the checkout: ``.venv/bin/python tests/data/make_roving_plate.py``
"""

from pathlib import Path

import numpy as np

import modal

OUT = Path(__file__).resolve().parent / "roving_plate"

setups, geometry, (freq_hz, _) = modal.plate_roving_test(modal.SimplySupportedPlate(1.2, 0.8, 20.0, 10.0),
                                                         duration=120.0, fs=100.0, seed=0)
for setup in setups:
    folder = modal.save_setup(setup, OUT / setup.name)
    np.savez(folder / "record.npz", acc=setup.record.acc.astype(np.float32), dt=setup.record.dt)  # half the size
modal.save_geometry(geometry, OUT / "geometry")
print(f"wrote {len(setups)} setups to {OUT}; true frequencies {np.round(freq_hz, 3)} Hz")
