"""modal.thesis.claims on constructed inputs: a criterion holds on data made
to satisfy it and flips when the data are broken; every claim is quoted
verbatim from the thesis."""

import os
import re
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from modal.thesis import claims as cl
from modal.thesis.tables import inclusion_holds  # noqa: F401  (the criterion the spillover claims use)





def rows(case, method, omegas_by_seed, actual, n=None, real_pole=None):
    """An identified-modes frame: one row per (seed, mode)."""
    out = []
    for seed, omegas in omegas_by_seed.items():
        for k, w in enumerate(omegas):
            out.append(dict(case=case, damping=0.0, noise=0.0, method=method, n=n or len(omegas), cols=-1, seed=seed,
                            mode=k + 1, omega=w, real_pole=bool(real_pole and real_pole(seed, k)),
                            actual=actual[k] if k < len(actual) else np.nan, participating=len(actual)))
    return pd.DataFrame(out)


EXACT = [2.1623, 8.6493, 19.461]


def spillover(tcm_by_n):
    actual = [2.16, 8.65, 19.46, 34.60, 54.06, 77.84]
    return pd.concat([rows("c1", "tcm", {-1: w}, actual, n=n) for n, w in tcm_by_n.items()], ignore_index=True)


def test_tcm_inclusion_claim_flips_when_broken():
    good = {3: [3.07, 13.29, 55.62], 4: [2.40, 9.88, 36.38, 62.82], 5: [2.19, 8.88, 23.68, 50.35, 73.15]}
    data = {"spillover": spillover(good)}
    assert cl._c_tcm_inclusion(data)[0] == "yes"
    assert cl._c_tcm_monotone(data)[0] == "yes"
    broken = {**good, 4: [3.20, 9.88, 36.38, 62.82]}  # mode 1 rises with n: neither interlaced nor monotone
    data = {"spillover": spillover(broken)}
    assert cl._c_tcm_inclusion(data)[0] == "no"
    assert cl._c_tcm_monotone(data)[0] == "partly"


def test_tcm_better_for_lower_modes_is_graded():
    seeds = range(5)
    tcm = rows("c3", "tcm", {s: [EXACT[0] * 1.001, EXACT[1] * 1.002, EXACT[2] * 1.05] for s in seeds}, EXACT)
    era = rows("c3", "era", {s: [EXACT[0] * 1.05, EXACT[1] * 1.01, EXACT[2] * 1.001] for s in seeds}, EXACT)
    data = {"demo": pd.concat([tcm, era], ignore_index=True), "case": {3: "c3"}}
    holds, numbers = cl._c_noise5_frequencies(data)
    assert holds == "yes" and "TCM r=1: 0.1 %" in numbers
    # broken: the ERA better for mode 1 as well -> two of three
    era = rows("c3", "era", {s: [EXACT[0] * 1.0001, EXACT[1] * 1.01, EXACT[2] * 1.001] for s in seeds}, EXACT)
    data["demo"] = pd.concat([tcm, era], ignore_index=True)
    assert cl._c_noise5_frequencies(data)[0] == "partly"


def test_a_missed_mode_counts_as_a_full_error():
    frame = rows("c3", "era", {0: [0.5, EXACT[1], EXACT[2]], 1: [EXACT[0], EXACT[1], EXACT[2]]}, EXACT,
                 real_pole=lambda seed, k: seed == 0 and k == 0)
    errors = cl.mode_errors(frame)
    assert errors.loc[(errors["seed"] == 0) & (errors["mode"] == 1), "error"].item() == 1.0
    assert errors.loc[(errors["seed"] == 1) & (errors["mode"] == 1), "error"].item() == pytest.approx(0.0)


def test_cera_damping_versus_noise_flips():
    actual = [0.441, 1.766, 3.972]
    cera = lambda case, f: rows(case, "cera", {-1: [a * (1 + f) for a in actual]}, actual)
    data = {"cera": pd.concat([cera("c1", 0.0), cera("c2", 0.05), cera("c3", 0.06)], ignore_index=True),
            "case": {7: "c1", 8: "c2", 9: "c3"}, "cera_cols": None}
    assert cl._c_cera_damping_vs_noise(data)[0] == "yes"  # 5 % from damping, 1 % more from noise
    data["cera"] = pd.concat([cera("c1", 0.0), cera("c2", 0.01), cera("c3", 0.2)], ignore_index=True)
    assert cl._c_cera_damping_vs_noise(data)[0] == "no"


def test_claims_are_quoted_verbatim_with_their_sections():
    path = Path(os.environ.get("MODAL_THESIS_TEXT", Path(__file__).resolve().parents[2] / "../shared/thesis.txt"))
    if not path.is_file():
        pytest.skip(f"the thesis text {path} is absent")
    text = re.sub(r"\s+", " ", path.read_text(encoding="utf-8")).replace("$", "")
    assert len(cl.CLAIMS) >= 20
    for claim in cl.CLAIMS:
        quote = re.sub(r"\s+", " ", claim.quote)
        # compared without LaTeX and Markdown markup (m = 3, \\dots, 6; *snr*)
        flat = text.replace("\\dots", "...").replace("*", "")
        assert quote in flat, quote
        assert claim.section.split(".")[0] in {"6", "7", "8"}


def test_headline_counts():
    frame = pd.DataFrame(dict(claim=["a", "b", "c"], section="6.1", criterion="", holds=["yes", "partly", "no"],
                              numbers=""))
    assert cl.claims_headline(frame) == "Of 3 claims of the thesis checked: 1 hold, 1 hold in part, 1 do not."


def test_cera_claims_at_zeta_05_follow_the_numbers():
    # Sec. 6.4's prose case zeta = .05 (no table): mode 1 changes by 23 % from the undamped case, every mode
    # degenerates, modes 1 and 2 above the exact frequency and mode 3 below.
    actual = [0.441, 1.766, 3.972]

    def cera(case, damping, factors):
        return rows(case, "cera", {-1: [a * f for a, f in zip(actual, factors)]}, actual).assign(damping=damping)

    def data(mode1_05):
        frame = pd.concat([cera("c1", 0.0, [0.984, 0.975, 1.0]), cera("c2", 0.02, [1.05, 1.02, 0.993]),
                           cera("c4", 0.05, [0.984 * mode1_05, 1.1, 0.96])], ignore_index=True)
        return {"cera": frame, "case": {7: "c1", 8: "c2", 9: "c3"}, "cera_cols": None}

    assert cl._c_cera_fundamental_05(data(1.23))[0] == "yes"
    assert cl._c_cera_fundamental_05(data(1.25))[0] == "partly"
    assert cl._c_cera_fundamental_05(data(1.10))[0] == "no"
    assert cl._c_cera_degenerate(data(1.23))[0] == "yes"
    assert cl._c_cera_signs(data(1.23))[0] == "yes"
    assert cl._c_cera_signs(data(0.9))[0] == "partly"  # mode 1 below the exact frequency at zeta = .05
    no_05 = data(1.23)
    no_05["cera"] = no_05["cera"][no_05["cera"]["case"] != "c4"]
    assert cl._c_cera_degenerate(no_05)[0] == "no"
