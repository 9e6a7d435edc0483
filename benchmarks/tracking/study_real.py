"""Real repeated tests through the tracker, read from bare git copies of public repositories under the
mirror folder (``--mirror DIR`` or ``SINDY_IMPULSE_MIRROR``; ``owner+name/repo`` as ``git clone --bare`` or
the search tool's ``fetch`` leaves them) at pinned commits; each record's survey is cached.

=================================================  ============================================  =======
repository (folder)                                files (commit)                                licence
=================================================  ============================================  =======
ladisk/pyFRF (``ladisk+pyFRF``)                    ``data/measurements_1..5.npy`` (55431fd)      MIT
EnesDemirkaya/Vibration-Tester-ADXL357-FFT         ``Example Recordings/...`` (14e12b7, removed  MIT
(``EnesDemirkaya+Vibration-Tester-ADXL357-FFT``)   from later commits)
=================================================  ============================================  =======

pyFRF: five hammer hits on one structure (force and acceleration, 25,600 Hz, 1 s); nothing changed between
them. Vibration-Tester: an aluminium cantilever beam plucked (an initial displacement of 1-4 cm) and
recorded by a MEMS accelerometer polled by a Raspberry Pi (20 s, timestamps uneven around 4-6 kHz: the
records are put on a uniform 2,000 Hz clock by linear interpolation and decimated to 500 Hz with an
anti-alias filter). Two changes of the structure, each tested several times: (1) a box at the beam's tip,
empty (5 plucks) and then holding 150 g of loose sand (6 plucks); the authors show a log-decrement fit per
pluck (their figures' decay rates ``beta``, 1/s, are copied below; their "damping ratio" is ``beta / 2 pi``);
(2) the beam clamped at 50 cm (5 plucks), 40 cm (3) and 60 cm (6); the authors' table
(``Natural_Freq_Calculation_MATLAB/points_data.xlsx``) gives the first two natural frequencies per length.
"""

from __future__ import annotations

import io
import json
import os
import subprocess
import warnings
from pathlib import Path

import numpy as np

PYFRF = ("ladisk/pyFRF", "55431fd3c328ddc719232cc34b891291c9982a2e")
BEAM = ("EnesDemirkaya/Vibration-Tester-ADXL357-FFT", "14e12b7c1a54e64a6b5b240056880f458503f142")
_LSM = "Example Recordings/LSM accelerometer/"
_ADXL = "Example Recordings/tests_for_comparing_1st_nfreq/"
BOX = {
    "empty": [
        f"{_LSM}emptybox5cm/08-05_{t}_50cm acc 7cm ID2cm"
        for t in ("12-09-19", "12-09-52", "14-35-13", "14-36-19", "14-36-57")
    ],
    "sand": [
        f"{_LSM}box5cm_sand_notpacked_150g mass 465g total/08-05_{t}"
        for t in (
            "16-24-01_1cm ID 7cm acc ",
            "16-24-45_1cm ID 7cm acc",
            "16-25-17_1cm ID 7cm acc",
            "16-26-12_2cm ID acc",
            "16-26-47_2cm ID acc",
            "16-27-38_2cm ID acc",
        )
    ],
}
#: The authors' log-decrement decay rates (1/s) shown in their figures, per pluck (several analyses of
#: one pluck listed in the order of the figures; none for the last three empty-box plucks).
BOX_AUTHORS_BETA = {
    "empty": [[0.0398, 0.0491, 0.0394], [0.0421], [], [], []],
    "sand": [
        [-0.0066, -0.0066, 0.0137, 0.0124, 0.0124, 0.0112],
        [0.0115],
        [0.0063],
        [0.0197],
        [0.0175],
        [0.0039, 0.0204],
    ],
}
LENGTHS = {
    "50 cm": [
        f"{_ADXL}50cm_adxl/08-12_{t}_adxl6cmfromtip2cmID"
        for t in ("11-46-55", "11-47-32", "11-47-59", "11-48-28", "11-49-09")
    ],
    "40 cm": [
        f"{_ADXL}40cm_adxl/08-12_{t}_adxl6cmfromtip2cmID" for t in ("11-41-04", "11-41-40", "11-42-08")
    ],
    "60 cm": [
        f"{_ADXL}60cm_adxl/08-12_{t}"
        for t in (
            "21-19-44_2cmIDadxlAt6cm",
            "21-20-44_2cmIDadxlAt6cm",
            "21-21-24_2cmIDadxlAt6cm",
            "21-22-38_4cmID",
            "21-23-29_4cmIDrun1",
            "21-23-58_4cmIDrun1",
        )
    ],
}
#: The authors' first two natural frequencies (Hz) per length (points_data.xlsx).
LENGTH_AUTHORS_HZ = {"50 cm": (6.02, 39.63), "40 cm": (9.383333, 61.53667), "60 cm": (4.25, 27.34667)}


def mirror_folder(arg) -> Path | None:
    value = arg or os.environ.get("SINDY_IMPULSE_MIRROR")
    return Path(value) if value else None


def git_file(mirror: Path, repo_commit: tuple, path: str) -> bytes:
    repo, commit = repo_commit
    git_dir = mirror / repo.replace("/", "+") / "repo"
    out = subprocess.run(["git", f"--git-dir={git_dir}", "show", f"{commit}:{path}"], capture_output=True)
    if out.returncode:
        raise LookupError(
            f"{repo} {path} at {commit[:7]}: {out.stderr.decode().strip()} (get the repository "
            f"with `git clone --bare https://github.com/{repo} {git_dir}`)"
        )
    return out.stdout


def _uniform(t, z, fs_grid: float = 2000.0, factor: int = 4):
    """An unevenly sampled record on a uniform clock, decimated with an anti-alias filter."""
    from scipy.signal import decimate

    grid = np.arange(t[0], t[-1], 1 / fs_grid)
    return decimate(np.interp(grid, t, z), factor, ftype="fir"), fs_grid / factor


def _cached_survey(cache: Path, name: str, load) -> dict:
    from sindy_impulse import identify_modes
    from sindy_impulse.tracking import survey_values

    path = cache / "real" / (name.replace("/", "_").replace(" ", "_") + ".json")
    if path.exists():
        return json.loads(path.read_text())
    y, fs, force = load()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        values = survey_values(identify_modes(y, fs=fs, force=force), label=name).to_dict()
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(json.dumps(values))
    return values


def pyfrf_surveys(mirror: Path, cache: Path) -> list:
    def loader(k):
        def load():
            t, force, acc = np.load(io.BytesIO(git_file(mirror, PYFRF, f"data/measurements_{k}.npy")))
            return acc, round(1 / float(np.mean(np.diff(t))), 3), force

        return load

    return [_cached_survey(cache, f"pyFRF measurements_{k}", loader(k)) for k in range(1, 6)]


def beam_surveys(mirror: Path, cache: Path, folders: list) -> list:
    def loader(folder):
        def load():
            t, z = np.load(io.BytesIO(git_file(mirror, BEAM, f"{folder}/accelerometer_data.npy")))
            y, fs = _uniform(t, z)
            return y, fs, None

        return load

    return [_cached_survey(cache, "/".join(f.split("/")[-2:]), loader(f)) for f in folders]


def _state(surveys: list, mode_hz: float) -> dict:
    """Mean frequency, damping ratio and decay rate of the mode nearest ``mode_hz`` over some surveys."""
    from sindy_impulse.tracking import SurveyValues

    f, z = [], []
    for d in surveys:
        modes = SurveyValues.from_dict(d).modes
        if modes:
            m = min(modes, key=lambda m: abs(np.log(m.frequency_hz / mode_hz)))
            if abs(np.log(m.frequency_hz / mode_hz)) < 0.3:
                f.append(m.frequency_hz)
                z.append(m.damping_ratio)
    f, z = np.array(f), np.array(z)
    return {
        "found": len(f),
        "frequency_hz": f.tolist(),
        "damping_ratio": z.tolist(),
        "decay_rate": (2 * np.pi * f * z).tolist(),
    }


def _tracked(surveys: list, n_ref: int, **kw) -> dict:
    from sindy_impulse.tracking import SurveyValues, track

    result = track([SurveyValues.from_dict(d) for d in surveys], reference=n_ref, **kw)
    p = np.stack([result.p[q] for q in result.quantities], axis=2)[result.new].reshape(len(result.new), -1)
    tests = np.isfinite(p).sum(axis=1)
    closest = [float(np.nanmin(row) * n) if n else None for row, n in zip(p, tests)]  # Bonferroni's min p
    return {
        "changed": int(result.changed.sum()),
        "new": len(result.new),
        "tests_per_survey": tests.tolist(),
        "smallest_p_times_tests": closest,
        "lines": result.lines(),
        "notes": result.notes(),
        "tested_modes": [round(t.frequency_hz, 4) for j, t in enumerate(result.tracks) if result.testable[j]],
    }


def pyfrf(mirror: Path, cache: Path) -> dict:
    """The five hits: the first three as reference, and each hit against the other four."""
    surveys = pyfrf_surveys(mirror, cache)
    out = {"first three as reference": _tracked(surveys, 3, min_reference=3)}
    for k in range(5):
        order = [d for i, d in enumerate(surveys) if i != k] + [surveys[k]]
        out[f"hit {k + 1} against the other four"] = _tracked(order, 4, min_reference=4)
    out["modes per hit"] = [len(d["modes"]) for d in surveys]
    return out


def beam(mirror: Path, cache: Path) -> dict:
    """The sand box and the beam lengths, tracked; each state's values beside the authors'."""
    box = {k: beam_surveys(mirror, cache, v) for k, v in BOX.items()}
    lengths = {k: beam_surveys(mirror, cache, v) for k, v in LENGTHS.items()}
    out = {
        "box": {
            "tracked": _tracked(box["empty"] + box["sand"], len(box["empty"])),
            "tracked, modes followed up to a factor e": _tracked(
                box["empty"] + box["sand"], len(box["empty"]), frequency_tolerance=1.0
            ),
            "states": {k: _state(v, 3.9 if k == "empty" else 2.0) for k, v in box.items()},
            "authors_beta": BOX_AUTHORS_BETA,
        }
    }
    sequence = lengths["50 cm"] + lengths["40 cm"] + lengths["60 cm"]
    out["lengths"] = {
        "tracked": _tracked(sequence, len(lengths["50 cm"])),
        "tracked, modes followed up to a factor e": _tracked(
            sequence, len(lengths["50 cm"]), frequency_tolerance=1.0
        ),
        "states": {
            k: {"first": _state(v, LENGTH_AUTHORS_HZ[k][0]), "second": _state(v, LENGTH_AUTHORS_HZ[k][1])}
            for k, v in lengths.items()
        },
        "authors_hz": LENGTH_AUTHORS_HZ,
    }
    return out
