"""Scoring of the modal-table studies: true and found modes matched, the marks, the ESPRIT baseline.

Shared by the accuracy benchmarks (``modes``, ``detection``, ``short_records``) and ``real_records``:
:func:`match` (per true mode, the closest found mode), :func:`assign` and :func:`judge` (one-to-one
pairing within :data:`MATCH`, a record right when every counted mode is within its marks and nothing is
left unpaired), :func:`esprit_start` (where the classical baseline starts), :func:`esprit_answer` and
:func:`baseline_answer` (single-order and stabilised ESPRIT) and :func:`run_family_case`
(one record of a family of :mod:`benchmarks.accuracy.families` through the survey and the baseline).
"""

from __future__ import annotations

import time
import warnings

import numpy as np
from scipy.optimize import linear_sum_assignment

from benchmarks.accuracy.families import band_snr_db, harmonic_snr_db
from sindy_impulse import identify_modes, impact_record
from sindy_impulse.analysis import esprit
from sindy_impulse.poles import stabilisation
from sindy_impulse.preprocessing import find_impact

#: Marks of the original study (family a): frequency within 0.3 %, damping ratio within 10 %; a found mode
#: farther than ``MATCH`` (1 %) from every true mode is spurious.
F_TOL, Z_TOL, MATCH = 0.003, 0.10, 0.01

def match(true_f, true_z, found_f, found_z):
    """Per true mode: (relative frequency error, relative damping error) of the closest found mode."""
    errors = []
    for f, z in zip(true_f, true_z):
        if len(found_f) == 0:
            errors.append((np.inf, np.inf))
            continue
        j = int(np.argmin(np.abs(np.asarray(found_f) / f - 1)))
        errors.append((abs(found_f[j] / f - 1), abs(found_z[j] / z - 1)))
    spurious = sum(1 for g in found_f if np.min(np.abs(np.asarray(true_f) / g - 1)) > MATCH)
    return errors, spurious


def esprit_start(y, fs) -> int:
    """Where the baseline starts: the detected onset plus a few samples (2 ms, at least 10) that skip the
    hammer's contact, as a practitioner trims it (ESPRIT fails when the forced stretch is included)."""
    return find_impact(y, fs).ringdown_index + max(10, int(0.002 * fs))


#: A harmonic is required to be named only where its band SNR reaches this (family e).
MIN_HARMONIC_SNR_DB = 20.0


def assign(f_true, found_f) -> dict:
    """One-to-one: true mode index -> found mode index, the closest pairs first, only within ``MATCH``."""
    if len(f_true) == 0 or len(found_f) == 0:
        return {}
    cost = np.abs(np.asarray(found_f, float)[None, :] / np.asarray(f_true, float)[:, None] - 1)
    rows, cols = linear_sum_assignment(np.where(cost <= MATCH, cost, 1e6))
    return {int(i): int(j) for i, j in zip(rows, cols) if cost[i, j] <= MATCH}


def judge(case: dict, f_true, z_true, counted, found, rejected=None) -> dict:
    """Score one answer (``found``: (frequency_hz, damping_ratio) pairs) against the truth: every counted
    mode within the case's marks, no found mode left unassigned (spurious), and for family e's harmonic
    records (``rejected`` given: the survey's) a rejected row naming the harmonic."""
    pairs = assign(f_true, [f for f, _ in found])
    errors, problems = [], []
    for i, (f, z) in enumerate(zip(f_true, z_true)):
        if i not in pairs:
            errors.append((np.inf, np.inf))
            problems.append(f"{f:.5g} Hz missed" + ("" if counted[i] else " (not counted)"))
            continue
        g, zeta = found[pairs[i]]
        errors.append((abs(g / f - 1), abs(zeta / z - 1)))
        if errors[-1][0] > case["f_tol"] or errors[-1][1] > case["z_tol"]:
            problems.append(f"{f:.5g} Hz found at {g:.5g} Hz (df/f {g / f - 1:+.1e}), "
                            f"zeta {zeta:.4g} for {z:.4g} (dz/z {zeta / z - 1:+.2f})")
    spurious = [found[j][0] for j in range(len(found)) if j not in pairs.values()]
    problems += [f"spurious mode at {g:.5g} Hz" for g in spurious]
    ok = all(e[0] <= case["f_tol"] and e[1] <= case["z_tol"] for e, c in zip(errors, counted) if c)
    harmonic = case.get("harmonic")
    if harmonic and rejected is not None and case.get("harmonic_snr_db", np.inf) >= MIN_HARMONIC_SNR_DB:
        named = any(f"harmonic {harmonic}" in r.reason for r in rejected)
        if not named:
            problems.append(f"harmonic {harmonic} not named among the rejected rows")
        ok = ok and named
    counted_errors = [e for e, c in zip(errors, counted) if c]
    return {"passed": ok and not spurious, "errors": counted_errors, "spurious": len(spurious),
            "problems": problems}


def survey_answer(rec) -> tuple:
    start = time.perf_counter()
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            survey = identify_modes(rec.y, fs=rec.fs)
        found = [(m.frequency_hz, m.damping_ratio) for m in survey.modes]
        rejected, error = list(survey.rejected), None
    except Exception as exc:  # noqa: BLE001 - an exception is a finding, reported as such
        found, rejected, error = [], [], f"{type(exc).__name__}: {exc}"
    return found, rejected, error, time.perf_counter() - start


def baseline_answer(rec) -> tuple:
    """The stabilised ESPRIT baseline (unchanged): orders 10-60, from the detected onset."""
    start = time.perf_counter()
    try:
        onset = esprit_start(rec.y, rec.fs)
        stable = stabilisation(rec.y[onset:], fs=rec.fs).modes()
        found = [(m.frequency_hz, m.damping_ratio) for m in stable]
    except Exception:  # noqa: BLE001 - a failing baseline is a data point
        found = []
    return found, time.perf_counter() - start


def esprit_answer(rec, onset: int | None = None) -> list:
    """Single-order ESPRIT (:func:`sindy_impulse.analysis.esprit`, the ``a`` / ``high`` table's baseline)
    from ``onset`` (default :func:`esprit_start`): (frequency_hz, damping_ratio) pairs, none where it fails
    (a failing baseline is a data point)."""
    onset = esprit_start(rec.y, rec.fs) if onset is None else onset
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            es = esprit(rec.y[onset:], fs=rec.fs, subtract_tail_mean=0.1)
        return list(zip(es.frequencies_hz, es.damping_ratios))
    except Exception:  # noqa: BLE001 - a failing baseline is a data point
        return []


class RecordRefused(ValueError):
    """The generator refused a drawn configuration (e.g. a nonlinear record that diverges): the record is
    left out of the family, as no survey ran on it."""


def run_family_case(case: dict) -> dict:
    """One record of a family through the survey and the stabilised ESPRIT baseline, both scored
    (:class:`RecordRefused` when the generator refuses the configuration)."""
    try:
        rec = impact_record(**case["config"])
    except ValueError as err:
        raise RecordRefused(str(err)) from err
    f_true = np.asarray(rec.modes.frequency_hz, float)
    z_true = np.asarray(rec.modes.damping_ratio, float)
    counted = np.ones(f_true.size, bool)
    if "min_band_snr_db" in case:
        counted = band_snr_db(rec) >= case["min_band_snr_db"]
    if "harmonic" in case:
        case = dict(case, harmonic_snr_db=harmonic_snr_db(rec, case["harmonic"]))
    found, rejected, error, elapsed = survey_answer(rec)
    base, base_time = baseline_answer(rec)
    ours = judge(case, f_true, z_true, counted, found, rejected)
    if error:
        ours["passed"] = False
        ours["problems"].insert(0, f"exception {error}")
    caught = [r.reason for r in rejected if r.band_hz is None or "error" in r.evidence]
    ours["problems"] += [f"caught failure: {r}" for r in caught]
    return {"case": case, "ours": ours, "theirs": judge(case, f_true, z_true, counted, base),
            "time": elapsed, "base_time": base_time, "error": error, "caught": len(caught),
            "counted": int(counted.sum()), "found": found, "baseline": base}
