"""Preparing a raw hammer-test record for per-mode identification.

A hammer hit recorded for seconds at kHz rates (pre-trigger, offset, several lightly damped modes, noise,
often a force channel) becomes one short, decimated signal per mode:

============================  =========================================================================
module                        job
============================  =========================================================================
``onset``                     onset of the hit, end of the hammer contact, double hits
``offset``                    offset and drift: estimate (saying how) and remove
``contact``                   end of the hammer contact from the response (start of the free decay)
``spectrum``, ``floor``       ring-down spectrum, noise floor, detection threshold, candidate peaks
``sinusoids``                 damped sinusoids fitted to a ring-down
``detection``, ``peaks``      which peaks are modes (fitted, tested against the residual's floor)
``partition``                 one band per peak; joint bands for peaks too close for their damping
``filters``                   zero-phase band-pass, its transient, decimation factor
``band``                      one band: band-pass, trim, stop at the noise floor, decimate
``quality``                   offset, clipping, quantisation, SNR, no ring-down
``declipping``                a clipped free decay repaired from its unclipped samples
``pipeline``                  :func:`preprocess`: all of the above, recording every choice
``transformers``              scikit-learn transformers over the functions
============================  =========================================================================

Imported eagerly: ``from .band import extract_band`` binds the function, whatever the order of use.
"""

from .band import BandSignal, band_noise_rms, extract_band, record_end
from .contact import contact_end
from .filters import bandpass, check_band, decimation_factor, filter_gain, transient_samples
from .noise_floor import noise_floor
from .offset import OffsetEstimate, estimate_offset, remove_offset
from .onset import ForcePulse, Impact, find_impact, force_pulses, response_onset
from .partition import band_groups, peak_bands
from .peaks import SpectralPeaks, spectral_peaks
from .pipeline import Preprocessed, preprocess
from .quality import (
    LIMITS,
    QualityReport,
    check_quality,
    clipping_end,
    clipping_mask,
    decay_db,
    quantisation_step,
    ringdown_snr_db,
    saturated_mask,
)
from .sinusoids import DampedSinusoids, fit_damped_sinusoids
from .spectrum import Spectrum, detection_threshold_db, half_power_width, ringdown_spectrum
from .transformers import BandExtractor, ImpactTrimmer, OffsetRemover

__all__ = [
    "LIMITS",
    "BandExtractor",
    "BandSignal",
    "DampedSinusoids",
    "ForcePulse",
    "Impact",
    "ImpactTrimmer",
    "OffsetEstimate",
    "OffsetRemover",
    "Preprocessed",
    "QualityReport",
    "SpectralPeaks",
    "Spectrum",
    "band_groups",
    "band_noise_rms",
    "bandpass",
    "check_band",
    "check_quality",
    "clipping_end",
    "clipping_mask",
    "saturated_mask",
    "contact_end",
    "decay_db",
    "decimation_factor",
    "detection_threshold_db",
    "estimate_offset",
    "extract_band",
    "filter_gain",
    "fit_damped_sinusoids",
    "find_impact",
    "force_pulses",
    "half_power_width",
    "noise_floor",
    "peak_bands",
    "preprocess",
    "quantisation_step",
    "record_end",
    "remove_offset",
    "response_onset",
    "ringdown_snr_db",
    "ringdown_spectrum",
    "spectral_peaks",
    "transient_samples",
]
