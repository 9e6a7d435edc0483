"""What :func:`~sindy_impulse.identify_modes` hands back: the modes and the modal table."""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from functools import cached_property

import numpy as np

__all__ = ["Mode", "ModalSurvey", "Rejected"]


@dataclass(eq=False)
class Mode:
    """One identified mode: its linear (small-amplitude) values, its model and what it was fitted on.

    Attributes
    ----------
    frequency_hz : float
        Undamped natural frequency ``|lambda| / 2 pi`` of the model's linear part.
    damped_frequency_hz : float
        ``frequency_hz * sqrt(1 - damping_ratio**2)``.
    damping_ratio : float
        ``-Re(lambda) / |lambda|`` of the model's linear part; for a nonlinear mode whose model lacks the
        amplitude-dependent damping its decay shows, the decay envelope's at zero amplitude
        (:mod:`._envelope`; a survey note says so).
    band_hz : (float, float)
        The band the mode was extracted from.
    amplitude : float
        Amplitude of the mode at the hit (sensor units), extrapolated back from the band signal with the
        identified decay rate.
    fit_error : float
        How well the model reproduces the mode's prepared signal: the mean absolute deviation of its
        simulation (restarted every few periods for long records) relative to the local amplitude,
        whatever measure selected the model (``modes.band_fit.fit_error_of``).
    model : ImpulseSINDy
        Fitted on ``states`` over ``t`` (states ``[y, dy]``: the band signal and its derivative), so every
        :mod:`sindy_impulse.analysis` function works on it.
    states, t : ndarray
        Exactly what the model was fitted on.
    snr_db : float
        Signal-to-noise ratio of the band at its first kept sample.
    shape : ndarray of complex or None
        Per channel, the amplitude ratio and phase of the mode relative to the reference channel (several
        sensors only; None for a mode identified jointly with its neighbours or on the record with its
        neighbours subtracted, whose other channels still hold those neighbours).
    residue : float or None
        Driving-point residue ``amplitude * omega_d / (omega_n**p * impulse)`` (``p`` 0, 1, 2 for
        displacement, velocity, acceleration sensors) when the force and the sensor kind are given.
    record : int
        Index of the hit the mode comes from (0 for one record).
    hits : list of Mode
        With repeated hits, the matching mode of each hit (the values above are then the consensus).
    frequency_std_hz, damping_ratio_std : float
        Standard deviations of ``frequency_hz`` and ``damping_ratio`` from the fit itself: the noise of the
        band signal propagated through the linearised fit of the model's simulation to its states
        (:mod:`sindy_impulse.modes.uncertainty`, which gives their measured calibration), plus, for a model
        with nonlinear terms, how far those move the values over the data (a stated systematic term). NaN
        when they cannot be computed (``uncertainty_note`` says why). With repeated hits, the standard
        deviation of the combined value; the hits' scatter is ``frequency_spread_hz``.
    coefficients_std : ndarray or None
        Standard deviation of each of ``model.coefficients()`` from the fit (NaN for terms the model does
        not have).
    nonlinear_chance : float
        The chance that noise alone gives the equation's nonlinear coefficients as far from zero as they
        are, all of them together (a Wald test with their covariance from the fit,
        :func:`sindy_impulse.modes.uncertainty.nonlinear_chance`): small where the equation's nonlinearity
        is real, 1 for an equation without nonlinear terms, NaN where it was not computed (a mode whose
        equation is not fitted to its data, e.g. from its poles).
    uncertainty_note : str
        Why the standard deviations are NaN, or where the reported values come from when not from the
        model ("" when there is nothing to say).
    source : {"poles", "equation", "envelope", "coupling"}
        Where the frequency and damping ratio come from: the decay fit of the record's poles (a linear
        mode, whose equation they define; or a nonlinear mode the paper's fit could not reproduce), the
        identified equation's linear part, or the decay envelope at zero amplitude: the averaged equations
        fitted to the mode's free decay where the paper's fit missed the amplitude dependence it shows
        (they are then its equation), or, for the damping ratio of a nonlinear mode whose equation lacks
        its amplitude-dependent damping, the envelope's decay rate; or the reading of every mode of the
        record together under one nonlinear element's coupling (:mod:`sindy_impulse.modes.coupling`),
        where it moves the mode's own values beyond its standard deviations.
    frequency_spread_hz, damping_ratio_spread : float
        Interquartile range of the hits' values (0 for one hit), kept apart from the standard deviations
        above.
    coordinate_ : int
        The measured coordinate among the states (0: ``y``), read by :func:`analysis.backbone`.
    diagnostics : FitDiagnostics
        The verdict of the mode's identification, with its reasons (:attr:`model`'s ``diagnostics_``).
    """

    frequency_hz: float
    damping_ratio: float
    band_hz: tuple
    amplitude: float
    fit_error: float
    model: object = field(repr=False)
    states: np.ndarray = field(repr=False)
    t: np.ndarray = field(repr=False)
    snr_db: float = math.nan
    shape: np.ndarray | None = field(default=None, repr=False)
    residue: float | None = None
    record: int = 0
    hits: list = field(default_factory=list, repr=False)
    frequency_spread_hz: float = 0.0
    damping_ratio_spread: float = 0.0
    coordinate_: int = 0
    frequency_std_hz: float = math.nan
    damping_ratio_std: float = math.nan
    coefficients_std: np.ndarray | None = field(default=None, repr=False)
    uncertainty_note: str = ""
    source: str = "equation"
    nonlinear_chance: float = math.nan

    @property
    def damped_frequency_hz(self) -> float:
        """``frequency_hz * sqrt(1 - damping_ratio**2)``."""
        return self.frequency_hz * math.sqrt(max(1.0 - self.damping_ratio**2, 0.0))

    @property
    def fitted_fs(self) -> float:
        """The sampling rate (Hz) the mode's model was fitted at: the record's, divided by the band's
        decimation, or multiplied by its resampling for a mode with few samples per period."""
        return float(1.0 / np.median(np.diff(self.t))) if len(self.t) > 1 else math.nan

    @property
    def diagnostics(self):
        """The checks and verdict of the mode's identification (the model's
        :class:`~sindy_impulse.diagnostics.FitDiagnostics`: fit error, terms, frequencies, data problems).

        Computed when first read (:func:`~sindy_impulse.identification.fit_deferred`: the survey fits a
        model per band and reads few verdicts), without a warning; :meth:`report` shows them.
        """
        return getattr(self.model, "diagnostics_", None)

    @cached_property
    def backbone(self):
        """Backbone curve of the mode (:func:`sindy_impulse.analysis.backbone`), computed once.

        The backbone of :attr:`model`; but when the test for nonlinearity (:attr:`nonlinearity`) calls the
        mode nonlinear through a term the model does not have (its ``source`` is ``"search"``: the
        selection kept a linear damper or spring that the data's amplitude dependence contradicts), the
        backbone of the test's nonlinear alternative, which carries that term (its ``backbone_model``), so
        that the curve shows the amplitude dependence the verdict rests on.
        """
        from ..analysis import backbone

        test = self.nonlinearity
        if test.nonlinear and test.source == "search" and test.backbone_model is not None:
            return test.backbone_model
        return backbone(self.model, coordinate=self.coordinate_)

    @cached_property
    def nonlinearity(self):
        """The test for nonlinearity on the mode's states (:func:`analysis.nonlinearity_test`), once."""
        from ..analysis import nonlinearity_test

        return nonlinearity_test(self.model, self.states, self.t)

    @property
    def nonlinear(self) -> bool:
        """The verdict of :attr:`nonlinearity`."""
        return bool(self.nonlinearity.nonlinear)

    def row(self, nonlinear: bool = False, damping_unit: str = "fraction") -> dict:
        """The mode as a row of the modal table.

        ``damping_unit="percent"`` gives the damping values in per cent, under names that say so
        (``damping_ratio_percent``, ``damping_ratio_std_percent``, ``damping_ratio_spread_percent``); the
        default keeps them as fractions under their attribute names.
        """
        from .._utils.units import DAMPING_UNITS, check_damping_unit, damping_key

        scale = DAMPING_UNITS[check_damping_unit(damping_unit)][0]
        row = {
            "frequency_hz": self.frequency_hz,
            "frequency_std_hz": self.frequency_std_hz,
            "damped_frequency_hz": self.damped_frequency_hz,
            damping_key("damping_ratio", damping_unit): scale * self.damping_ratio,
            damping_key("damping_ratio_std", damping_unit): scale * self.damping_ratio_std,
            "band_low_hz": self.band_hz[0],
            "band_high_hz": self.band_hz[1],
            "amplitude": self.amplitude,
            "fit_error": self.fit_error,
            "snr_db": self.snr_db,
            "source": self.source,
        }
        if self.hits:
            row["n_hits"] = len(self.hits)
            row["frequency_spread_hz"] = self.frequency_spread_hz
            row[damping_key("damping_ratio_spread", damping_unit)] = scale * self.damping_ratio_spread
        if self.residue is not None:
            row["residue"] = self.residue
        if nonlinear:
            row["nonlinear"] = self.nonlinear
        return row

    def channel_amplitudes(self) -> np.ndarray | None:
        """Per channel, the mode's amplitude at the hit (``amplitude`` times the magnitude of ``shape``);
        None without a shape (one channel, or a mode whose other channels still hold its neighbours).

        Examples
        --------
        >>> m = Mode(100.0, 0.01, (90.0, 110.0), 2.0, 0.01, None, None, None, shape=np.array([0.5j, 1.0]))
        >>> m.channel_amplitudes().tolist()
        [1.0, 2.0]
        """
        return None if self.shape is None else self.amplitude * np.abs(np.asarray(self.shape))


@dataclass(frozen=True)
class Rejected:
    """A spectral peak (band) that gave no mode, or a record that gave none, and why.

    Attributes
    ----------
    band_hz : (float, float) or None
        The band; None for a row about a whole record (its identification failed).
    reason : str
        Why, in plain words.
    record : int
        Index of the hit (0 for one record).
    evidence : dict
        What the decision rests on (e.g. the error of a failed fit: ``{"error": ..., "message": ...}``).
    code : Reason or None
        Why, as a code (:class:`~sindy_impulse.modes.kinds.Reason`): what programs decide on.
    """

    band_hz: tuple | None
    reason: str
    record: int = 0
    evidence: dict = field(default_factory=dict, compare=False)
    code: object = None


@dataclass(eq=False)
class ModalSurvey:
    """The result of :func:`~sindy_impulse.identify_modes`.

    Attributes
    ----------
    modes : list of Mode
        Sorted by frequency.
    rejected : list of Rejected
        Peaks or bands that gave no mode, with the reason.
    preprocessing : list of Preprocessed
        What preprocessing found and did, per record (onset, offset removed, peaks, bands, decimation).
    notes : list of str
        Remarks a user should read (double hits, no ring-down found, ...).
    poles : list of PoleTable
        The stabilisation diagram of each record (computed by ``identify_modes``, whose candidates start
        from its stable poles; else when first read).
    trace : SurveyTrace
        Per record and stage of the survey's pipeline (:data:`sindy_impulse.modes.survey.SURVEY`), the
        time it took and what it decided (``print(survey.trace)``).
    """

    modes: list
    rejected: list
    preprocessing: list = field(repr=False)
    notes: list = field(default_factory=list)
    trace: list = field(default_factory=list, repr=False)

    def __len__(self) -> int:
        return len(self.modes)

    def __iter__(self):
        return iter(self.modes)

    def __getitem__(self, i):
        return self.modes[i]

    def table(self, nonlinear: bool = False, damping_unit: str = "fraction") -> list[dict]:
        """The modal table: one dict per mode (``pandas.DataFrame(survey.table())`` makes a frame).

        ``nonlinear=True`` adds the verdict of the test for nonlinearity (it refits: slower);
        ``damping_unit="percent"`` gives the damping values in per cent, named ``damping_ratio_percent``
        and so on (:meth:`Mode.row`).
        """
        return [m.row(nonlinear, damping_unit) for m in self.modes]

    @cached_property
    def poles(self) -> list:
        """The stabilisation diagram of each record's free decay (offset removed, from the end of the hit,
        at most :data:`POLE_SAMPLES` samples):
        one :class:`~sindy_impulse.poles.PoleTable` per record (frequency, damping ratio, model order,
        stable or not), computed when first read (:func:`~sindy_impulse.poles.stabilisation`; a record too
        short for it gives an empty table). ``survey.poles[0].modes()`` are the modes the stable poles make.
        """
        return [pole_table(pre) for pre in self.preprocessing]

    def plot(self, axes=None, damping_unit: str = "percent"):
        """Spectrum with the modes marked, and each mode's data against its model
        (:func:`sindy_impulse.plotting.plot_modes`; damping ratios in ``damping_unit``)."""
        from ..plotting import plot_modes

        return plot_modes(self, axes=axes, damping_unit=damping_unit)

    def to_html(
        self,
        path=None,
        *,
        overwrite: bool = False,
        source: str | None = None,
        nonlinearity: bool = True,
        damping_unit: str = "percent",
        channel_names=None,
        notes=None,
    ) -> str:
        """The survey as one self-contained HTML report (:func:`sindy_impulse.report.survey_html`).

        The record(s), the modal table with uncertainties, the stabilisation chart over the spectrum with
        the bands, and per mode the band signal against the model (whole decay and zoom), the equation,
        the backbone, the nonlinearity verdict and the diagnostics; figures inline, nothing loaded from
        the network.

        Parameters
        ----------
        path : str or path-like, optional
            Also write the page there; an existing file is replaced only with ``overwrite=True``.
        overwrite : bool, default=False
            Replace an existing file (else FileExistsError).
        source : str, optional
            Where the record came from (e.g. its file), shown at the top.
        nonlinearity : bool, default=True
            Include the test for nonlinearity (it refits each mode once; cached on the mode).
        damping_unit : {"percent", "fraction"}, default="percent"
            The unit of every damping ratio on the page.
        channel_names : sequence of str, optional
            Names of the record's channels, for the amplitudes and shapes per channel.
        notes : sequence of str, optional
            Notes to show instead of the survey's own.

        Returns
        -------
        str
            The HTML page.

        Examples
        --------
        >>> from sindy_impulse import identify_modes, impact_record
        >>> rec = impact_record([120.0], [0.01], fs=2000, duration=1.0, snr_db=50, random_state=0)
        >>> page = identify_modes(rec.y, fs=rec.fs).to_html(nonlinearity=False)
        >>> "<h2>Modal table</h2>" in page, "http://" in page or "https://" in page
        (True, False)
        """
        from ..report import survey_html, write_html

        page = survey_html(self, source=source, nonlinearity=nonlinearity, damping_unit=damping_unit,
                           channel_names=channel_names, notes=notes)
        if path is not None:
            write_html(path, page, overwrite=overwrite)
        return page

    def to_uff(self, path, *, nodes=None, directions=None, overwrite: bool = False):
        """Write the modal table as a UFF file of data sets 55 (one complex mode shape per mode).

        Each mode's frequency, damping ratio and shape (one complex value per channel; a mode without a
        shape is written as one node with ``1 + 0j``). Needs the ``io`` extra
        (``pip install "sindy-impulse[io]"``); see :func:`sindy_impulse.io.write_uff55`.

        Parameters
        ----------
        path : str or path-like
            The file (``.unv`` or ``.uff``); an existing one is replaced only with ``overwrite=True``.
        nodes, directions : sequence of int, optional
            Node and direction (1, 2, 3 = +X, +Y, +Z) of each channel; default: the channel numbers
            1..n in +Z.
        overwrite : bool, default=False
            Replace an existing file (else FileExistsError).

        Returns
        -------
        pathlib.Path
            The file written (read it back with :func:`sindy_impulse.io.read_uff55`).

        Examples
        --------
        >>> from sindy_impulse.io import read_uff55
        >>> from sindy_impulse import identify_modes, impact_record
        >>> rec = impact_record([120.0, 240.0], [0.005, 0.01], fs=5000, duration=1.0, snr_db=50,
        ...                     random_state=0)
        >>> survey = identify_modes(rec.y, fs=rec.fs)
        >>> import tempfile, os
        >>> with tempfile.TemporaryDirectory() as folder:
        ...     back = read_uff55(survey.to_uff(os.path.join(folder, "modes.unv")))
        >>> [round(m["frequency_hz"], 1) for m in back]
        [120.0, 240.0]
        """
        from ..io import write_uff55

        return write_uff55(path, self.modes, nodes=nodes, directions=directions, overwrite=overwrite)

    def to_uff58(self, path, *, binary: bool = False, overwrite: bool = False):
        """Write each mode's band signal and its model's free decay as UFF 58 time records.

        Two data sets per mode (:func:`sindy_impulse.modes.export.signal_records`): the band signal the
        model was fitted on (``mode.states``' measured coordinate over ``mode.t``, at ``mode.fitted_fs``),
        and the model simulated from the band's first state over the whole of ``mode.t``, on the record's
        clock. ASCII ordinates hold 12 significant digits, binary ones the doubles. Written through
        :func:`sindy_impulse.io.write_record`; needs pyuff (``pip install "sindy-impulse[io]"``).

        Parameters
        ----------
        path, overwrite
            As for :meth:`to_uff`.
        binary : bool, default=False
            Binary data sets (``58b``) instead of ASCII.

        Returns
        -------
        Path
            The file written.

        Examples
        --------
        >>> import os, tempfile, pyuff
        >>> from sindy_impulse import identify_modes, impact_record
        >>> rec = impact_record([120.0, 240.0], [0.005, 0.01], fs=5000, duration=1.0, snr_db=50,
        ...                     random_state=0)
        >>> survey = identify_modes(rec.y, fs=rec.fs)
        >>> with tempfile.TemporaryDirectory() as folder:
        ...     sets = pyuff.UFF(survey.to_uff58(os.path.join(folder, "signals.unv"))).read_sets()
        >>> [s["id1"] for s in sets][:2]
        ['mode 1 120 Hz band signal', 'mode 1 120 Hz model free decay']
        """
        from .export import write_signals

        return write_signals(self, path, binary=binary, overwrite=overwrite)

    def to_frame(self, nonlinear: bool = False, damping_unit: str = "fraction"):
        """The modal table as a :class:`pandas.DataFrame`: one row per mode (index ``mode``), the columns
        of :meth:`table` (frequency, damped frequency, damping ratio, band, amplitude, fit error, SNR;
        hits and spreads, residue, ``nonlinear`` when present; ``damping_unit="percent"``: the damping
        columns in per cent, named ``damping_ratio_percent`` and so on). Needs pandas (an ImportError
        saying ``pip install pandas`` otherwise).

        Examples
        --------
        >>> from sindy_impulse import identify_modes, impact_record
        >>> rec = impact_record([120.0, 240.0], [0.005, 0.01], fs=5000, duration=1.0, snr_db=50,
        ...                     random_state=0)
        >>> frame = identify_modes(rec.y, fs=rec.fs).to_frame()
        >>> frame["frequency_hz"].round(1).tolist(), frame.index.name
        ([120.0, 240.0], 'mode')
        """
        from .export import modal_frame

        return modal_frame(self, nonlinear=nonlinear, damping_unit=damping_unit)

    def __repr__(self) -> str:
        head = f"ModalSurvey({len(self.modes)} mode(s), {len(self.rejected)} rejected)"
        columns = "f_n [Hz]               f_d [Hz]   damping [%]           amplitude   fit error   band [Hz]"
        lines = [head, "  #   " + columns]
        for i, m in enumerate(self.modes):
            zeta = _plus_minus(100 * m.damping_ratio, 100 * m.damping_ratio_std, 4)
            lines.append(
                f"  {i:<3d} {_plus_minus(m.frequency_hz, m.frequency_std_hz, 7):<22s} "
                f"{m.damped_frequency_hz:<10.6g} {zeta:<21s} "
                f"{m.amplitude:<11.4g} {m.fit_error:<11.3g} {m.band_hz[0]:.4g}-{m.band_hz[1]:.4g}"
            )
        lines += [f"  rejected {_band_text(r.band_hz)}: {r.reason}" for r in self.rejected]
        lines += [f"  note: {n}" for n in self.notes]
        return "\n".join(lines)


#: The stabilisation diagram is computed on at most this many samples of the free decay (the classical
#: baseline's window): enough periods of the lowest modes, a bounded cost on long records.
POLE_SAMPLES = 20_000


def pole_table(pre, max_samples: int | None = POLE_SAMPLES, start: int | None = None, orders=None,
               min_orders: int | None = None):
    """The stabilisation diagram of a preprocessed record's free decay (offset removed, from ``start``,
    default the end of the hit; its first ``max_samples`` samples; at ``orders``, a pole stable at
    ``min_orders``, default the diagram's); an empty table for a record too short for a Hankel matrix."""
    from ..poles import PoleTable, stabilisation
    from ..poles.stabilisation import MIN_ORDERS, ORDERS

    start = pre.impact.ringdown_index if start is None else start
    stop = None if max_samples is None else start + max_samples
    try:
        return stabilisation(pre.y[start:stop], fs=pre.fs, orders=ORDERS if orders is None else orders,
                             min_orders=MIN_ORDERS if min_orders is None else min_orders)
    except ValueError:  # fewer samples than a Hankel matrix needs
        empty = np.empty(0)
        return PoleTable(empty, empty, empty.astype(int), empty.astype(bool), ())


def _plus_minus(value: float, std: float, digits: int) -> str:
    """``value +- std`` (std to two significant digits; ``+- ?`` when it is not known)."""
    if not (math.isfinite(std) and std > 0):
        return f"{value:.{digits}g} ± ?"
    return f"{value:.{digits}g} ± {std:.2g}"


def _band_text(band_hz) -> str:
    """A band as text; a row about a whole record has none."""
    return "record" if band_hz is None else f"{band_hz[0]:.4g}-{band_hz[1]:.4g} Hz"
