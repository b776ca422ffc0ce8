"""The roving-test pictures of the documentation (docs/img/): the Weimar
frame's first modes (its 15 setups in ../shared/data/weimar_frame beside the
checkout), Palisaden's three modes on pyOMA2's geometry and the simulated
plate's five, each merged with ``modal identify`` and drawn by
``modal.mode_shape_figure``.

Run from the checkout: ``.venv/bin/python docs/_scripts/roving_figures.py``
"""

from pathlib import Path
import subprocess
import sys
import tempfile

from PIL import Image

ROOT = Path(__file__).resolve().parents[2]
WEIMAR = ROOT.parent / "shared" / "data" / "weimar_frame"
MODAL = [sys.executable, "-m", "modal", "identify"]


def montage(folder: Path, modes, path: Path, columns: int) -> None:
    images = [Image.open(folder / f"mode_{k}.png") for k in modes]
    w, h = images[0].size
    rows = -(-len(images) // columns)
    sheet = Image.new("RGB", (columns * w, rows * h), "white")
    for i, image in enumerate(images):
        sheet.paste(image, ((i % columns) * w, (i // columns) * h))
    sheet.resize((sheet.width * 2 // 3, sheet.height * 2 // 3)).save(path, optimize=True)


def run(arguments, out: Path) -> None:
    subprocess.run([*MODAL, *arguments, "--out", str(out), "--quiet", "--no-animation"], check=True)


with tempfile.TemporaryDirectory() as tmp:
    tmp = Path(tmp)
    run([*(str(WEIMAR / f"measurement_{k}") for k in range(1, 16)), "--ambient", "--fmax", "15", "--geometry",
         str(WEIMAR)], tmp / "weimar")
    montage(tmp / "weimar", [1, 2, 3, 4, 5, 6], ROOT / "docs" / "img" / "weimar_modes.png", 3)
    data = ROOT / "tests" / "data"
    run([str(data / "palisaden_20hz_30min.npy"), "--fs", "20", "--ambient", "--fmax", "5", "--highpass", "0.5",
         "--geometry", str(data / "palisaden_geometry")], tmp / "palisaden")
    montage(tmp / "palisaden", [1, 2, 3], ROOT / "docs" / "img" / "palisaden_modes.png", 3)
