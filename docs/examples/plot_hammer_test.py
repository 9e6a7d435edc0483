"""
A hammer test with three modes
==============================

A synthetic hammer test (:func:`~sindy_impulse.datasets.impact_record`: an accelerometer with an offset, a
pre-trigger and 45 dB of noise on a spring-mass chain built to have exactly these three modes) goes in raw;
:func:`~sindy_impulse.identify_modes` returns the modal table with one identified equation per mode.
"""

import matplotlib.pyplot as plt

from sindy_impulse import identify_modes, impact_record

record = impact_record([118.0, 243.0, 402.0], [0.002, 0.004, 0.008], fs=5000.0, duration=1.0,
                       offset=2.0, snr_db=45, random_state=7)
survey = identify_modes(record.y, fs=record.fs, force=record.force)
print(survey)

# %%
# The truth, for comparison:
for f, zeta in zip(record.modes.frequency_hz, record.modes.damping_ratio):
    print(f"{f:8.3f} Hz   damping ratio {zeta:.4f}")

# %%
# Each mode's equation, in its band signal ``y`` and ``dy = y'``:
for mode in survey.modes:
    mode.model.print()

# %%
# The spectrum with the modes' bands, then per mode its band signal against the model: the whole decay as
# peak envelopes on a log axis, and the first periods.
survey.plot()
plt.show()
