"""
A scikit-learn pipeline from one sensor
=======================================

Only the displacement is measured. :class:`~sindy_impulse.DelayEmbedding` (a scikit-learn transformer)
rebuilds the missing state from a delayed copy of the signal, and :class:`~sindy_impulse.ImpulseSINDy`
identifies the equations in the delay coordinates; a grid search picks the library's degree, scored by
the simulation error as the fit itself is.
"""

import matplotlib.pyplot as plt
from sklearn.model_selection import GridSearchCV
from sklearn.pipeline import make_pipeline

from sindy_impulse import DelayEmbedding, ImpulseSINDy, damped_oscillator
from sindy_impulse.analysis import modal_parameters

runs = [damped_oscillator(snr_db=40, random_state=seed).x[:, 0] for seed in range(3)]
pipe = make_pipeline(DelayEmbedding(), ImpulseSINDy(dt=0.01))
pipe.fit(runs[0])
pipe[-1].print()
print(modal_parameters(pipe[-1]))     # truth: 1.2732 Hz, damping ratio 0.200

# %%
# The grid search over the polynomial degree (each fold refits the embedding and the model):
search = GridSearchCV(ImpulseSINDy(dt=0.01), {"feature_library__degree": [1, 2, 3]}, cv=3)
embedded = [pipe[0].transform(run) for run in runs]
search.fit(embedded)
print(search.best_params_)

# %%
# The first run in delay coordinates and the identified model's simulation from its first point:
q = embedded[0]
t = pipe[0].transform_time(0.01, n_samples=runs[0].size)
sim = pipe[-1].simulate(q[0], t - t[0])
fig, ax = plt.subplots(figsize=(6, 3.5), layout="constrained")
ax.plot(t, q[:, 1], ".", ms=2, label="measured x(t)")
ax.plot(t, sim[:, 1], label="model")
ax.set_xlabel("t (s)")
ax.legend()
plt.show()
