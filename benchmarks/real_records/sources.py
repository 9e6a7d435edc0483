"""The public real records of the real-record benchmarks, read from bare git copies at pinned commits.

:func:`git_file` reads one file of a repository's bare copy under a mirror folder (``owner+name/repo`` or
``owner+name``, as ``git clone --bare`` or the search tool's ``fetch`` leaves it) and raises
:class:`MissingRepository` with the command that fetches it; :func:`pyfrf_records`, :func:`case1_record`,
:func:`beam_record` and :func:`flutter_records` return the records (``name``, ``set``, ``y``, ``force``,
``fs``) of each set. docs/real-records.md has their provenance and licences.
"""

from __future__ import annotations

import io
import subprocess
import tempfile
from pathlib import Path

import numpy as np
import scipy.io

from sindy_impulse.datasets import load_flutter_rig

#: The environment variable naming the mirror folder.
ENV = "SINDY_IMPULSE_MIRROR"
PYFRF = ("ladisk/pyFRF", "55431fd3c328ddc719232cc34b891291c9982a2e")
VTB = ("vibrationtoolbox/vibration_toolbox", "1bec7f157912c47c24d1356bba54d9dae2d3ba2f")
BEAM = ("PujaChowdhury/Dataset-4-Univariate-signal-with-non-stationarity",
        "42c970f7e931e879f9179475b758267d9c12b538")


class MissingRepository(LookupError):
    """A record set's repository (or the pinned file) is not in the mirror folder."""


def git_file(mirror: Path, repo_commit: tuple, path: str) -> bytes:
    """The bytes of ``path`` at the pinned commit of a bare git copy under ``mirror``."""
    repo, commit = repo_commit
    git_dir = mirror / repo.replace("/", "+") / "repo"
    if not git_dir.is_dir():
        git_dir = mirror / repo.replace("/", "+")
    if not git_dir.is_dir():
        raise MissingRepository(
            f"{repo}: no git copy at {mirror / repo.replace('/', '+')}/repo. Get it with "
            f"`git clone --bare https://github.com/{repo} {mirror / repo.replace('/', '+')}/repo` "
            f"(or the search tool's fetch github:{repo}), then rerun; commit {commit[:7]} is needed."
        )
    out = subprocess.run(["git", f"--git-dir={git_dir}", "show", f"{commit}:{path}"], capture_output=True)
    if out.returncode:
        raise MissingRepository(f"{repo}: {path} at {commit[:7]} not readable: {out.stderr.decode().strip()}")
    return out.stdout


def pyfrf_records(mirror: Path) -> list[dict]:
    """ladisk/pyFRF's five hammer hits (force and acceleration, 25,600 Hz, 1 s)."""
    records = []
    for k in range(1, 6):
        data = np.load(io.BytesIO(git_file(mirror, PYFRF, f"data/measurements_{k}.npy")))
        t, force, acc = data
        records.append({"name": f"pyFRF measurements_{k}", "set": "pyFRF", "y": acc, "force": force,
                        "fs": round(1 / float(np.mean(np.diff(t))), 3)})
    return records


def case1_record(mirror: Path) -> list[dict]:
    """vibration_toolbox's case1.mat: one hit (force and response, 1,280 Hz, 3.2 s)."""
    mat = scipy.io.loadmat(io.BytesIO(git_file(mirror, VTB, "vibration_toolbox/data/case1.mat")))
    fs = float(np.squeeze(mat["Time_Sample_Rate"]))
    return [{"name": "vibration_toolbox case1.mat", "set": "case1", "y": np.ravel(mat["Time_chan_2"]),
             "force": np.ravel(mat["Time_chan_1"]), "fs": fs}]


def beam_record(mirror: Path) -> list[dict]:
    """Dataset-4's cantilever beam tapped once (one accelerometer, 51,200 / 31 Hz, 49.6 s)."""
    import lvm_read

    raw = git_file(mirror, BEAM, "modal_analysis/data/timeseries_data.lvm")
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "timeseries_data.lvm"
        path.write_bytes(raw)
        data = lvm_read.read(str(path), read_from_pickle=False, dump_file=False)[0]["data"]
    return [{"name": "Dataset-4 cantilever beam", "set": "beam", "y": np.asarray(data[:, 1], float),
             "force": None, "fs": 51200 / 31}]


def flutter_records() -> list[dict]:
    """The shipped flutter-rig free decays (heave and pitch, 500 Hz)."""
    rig = load_flutter_rig()
    return [{"name": f"flutter rig record {r} (heave, pitch)", "set": "flutter rig", "y": rig.y[r],
             "force": None, "fs": rig.fs} for r in range(len(rig))]
