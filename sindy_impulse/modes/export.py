"""A survey's results as files and frames: the band signals and the models' free decays as UFF 58
(:func:`signal_records`, :func:`write_signals`), the modal table as a pandas DataFrame (:func:`modal_frame`).

Each mode contributes two UFF 58 time records: its band signal (the measured coordinate of
``mode.states`` over ``mode.t``: exactly what the model was fitted on, at the rate it was fitted at) and
the free decay of its model, simulated from the band's first state over the whole of ``mode.t``. The two
sit on the same clock (the record's), so a modal-testing tool overlays them directly.
"""

from __future__ import annotations

import warnings

import numpy as np

from ..exceptions import DataWarning

__all__ = ["FRAME_COLUMNS", "modal_frame", "signal_records", "write_signals"]

#: The columns of the modal table every mode has, in order (``Mode.row``); the optional ones (``n_hits``,
#: spreads, ``residue``, ``nonlinear``) follow when the survey has them.
FRAME_COLUMNS = (
    "frequency_hz",
    "frequency_std_hz",
    "damped_frequency_hz",
    "damping_ratio",
    "damping_ratio_std",
    "band_low_hz",
    "band_high_hz",
    "amplitude",
    "fit_error",
    "snr_db",
    "source",
)


def _free_decay(mode, number: int) -> np.ndarray:
    """The model's free decay from the band's first state over ``mode.t`` (the measured coordinate),
    cut where a simulation diverged (with a DataWarning)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # a divergence is reported below, with the mode it concerns
        sim = np.asarray(mode.model.simulate(mode.states[0], mode.t), dtype=float)[:, mode.coordinate_]
    bad = np.flatnonzero(~np.isfinite(sim))
    if bad.size:
        warnings.warn(
            f"mode {number} ({mode.frequency_hz:.6g} Hz): its model's free decay diverged at "
            f"t = {mode.t[bad[0]]:.6g} s; written up to there",
            DataWarning,
            stacklevel=3,
        )
        sim = sim[: bad[0]]
    return sim


def signal_records(survey) -> list:
    """Per mode, its band signal and its model's free decay as two one-channel
    :class:`~sindy_impulse.io.Record` (sampling rate ``mode.fitted_fs``, start ``mode.t[0]``).

    Channel names: ``"mode <k> <f> Hz band signal"`` and ``"mode <k> <f> Hz model free decay"`` (``k``
    from 1, ``f`` the natural frequency). A free decay that diverges is cut there (DataWarning).

    Examples
    --------
    >>> from sindy_impulse import identify_modes, impact_record
    >>> rec = impact_record([120.0, 240.0], [0.005, 0.01], fs=5000, duration=1.0, snr_db=50,
    ...                     random_state=0)
    >>> records = signal_records(identify_modes(rec.y, fs=rec.fs))
    >>> [r.channel_names[0] for r in records][:2]
    ['mode 1 120 Hz band signal', 'mode 1 120 Hz model free decay']
    >>> records[0].n_samples == records[1].n_samples, records[0].t0 == records[1].t0
    (True, True)
    """
    from ..io import Record

    out = []
    for k, mode in enumerate(survey.modes, start=1):
        label = f"mode {k} {mode.frequency_hz:.4g} Hz"
        fs, t0 = mode.fitted_fs, float(mode.t[0])
        band = np.asarray(mode.states[:, mode.coordinate_], dtype=float)
        out.append(Record(band, fs=fs, t0=t0, channel_names=(f"{label} band signal",)))
        decay = _free_decay(mode, k)
        if decay.size:
            out.append(Record(decay, fs=fs, t0=t0, channel_names=(f"{label} model free decay",)))
    return out


def write_signals(survey, path, *, binary: bool = False, overwrite: bool = False):
    """Write :func:`signal_records` as one UFF file of data sets 58 (ASCII, or binary with
    ``binary=True``) through :func:`sindy_impulse.io.write_record`; see
    :meth:`~sindy_impulse.modes.ModalSurvey.to_uff58`."""
    from ..io import write_record

    records = signal_records(survey)
    if not records:
        raise ValueError("the survey has no mode: no band signal to write")
    return write_record(records, path, format="uff", binary=binary, overwrite=overwrite)


def modal_frame(survey, nonlinear: bool = False, damping_unit: str = "fraction"):
    """The modal table as a :class:`pandas.DataFrame`, one row per mode (index ``mode``, from 0), the
    damping columns in ``damping_unit`` (their names say which); see
    :meth:`~sindy_impulse.modes.ModalSurvey.to_frame`."""
    from .._utils.units import damping_key

    try:
        import pandas as pd
    except ImportError as err:
        raise ImportError(
            "ModalSurvey.to_frame() needs pandas, which is not installed: pip install pandas "
            "(or use survey.table(), a list of dicts)"
        ) from err
    rows = survey.table(nonlinear=nonlinear, damping_unit=damping_unit)
    fixed = [damping_key(c, damping_unit) if c.startswith("damping_ratio") else c for c in FRAME_COLUMNS]
    extra = [c for row in rows for c in row if c not in fixed]
    columns = fixed + list(dict.fromkeys(extra))
    frame = pd.DataFrame(rows, columns=columns)
    frame.index.name = "mode"
    return frame
