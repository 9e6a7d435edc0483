"""The cases of the bad-input matrix (benchmarks/robustness/bad_inputs.py): data recipes, actions and
expectations.

:func:`run_case` builds and runs one case and judges the outcome against its expectation (never raising).

A case is a plain dict (it travels to a worker process): ``id``, ``group``, ``data`` (a recipe, built by
:func:`make_data`), ``action`` (``fit``, ``modal``, ``simulate``, ``features`` or ``call``), ``params``
(of the estimator) and ``expect``:

- ``{"type": "right", "tol": 0.05}``: exactly the true terms, every coefficient within ``tol``;
- ``{"type": "right_or_warn", "tol": ...}``: that, or a library warning;
- ``{"type": "warn", "warning": "DataWarning"}``: a warning of that class (or a subclass);
- ``{"type": "raise", "error": "ValueError", "match": "regex"}``: that error, its message matching.
"""

from __future__ import annotations

import re
import time
import traceback
import warnings

import numpy as np

K, C = 64.0, 3.2
#: The paper's oscillator: x0' = x1, x1' = -64 x0 - 3.2 x1.
OSC = {(0, "x1"): 1.0, (1, "x0"): -K, (1, "x1"): -C}
F_HZ, ZETA = 8.0 / (2 * np.pi), 0.2


# --------------------------------------------------------------------------------------------------------
# data
# --------------------------------------------------------------------------------------------------------
def _system(d: dict, rng):
    """Clean states (n, 2), time vector and true coefficients of the recipe's system."""
    from sindy_impulse import damped_oscillator

    system = d.get("system", "osc")
    if system == "binary":
        system = "white"
    dt, t_end = d.get("dt", 0.01), d.get("t_end", 4.0)
    if system in ("osc", "duffing"):
        k_nl, a = d.get("k_nl", 0.0), d.get("x0", 1.0)
        ring = damped_oscillator(k_nl=k_nl, x0=(a, 0.0), dt=dt, t_end=t_end)
        truth = dict(OSC)
        if k_nl:
            truth[(1, "x0^3")] = -k_nl
        return ring.x, ring.t, truth
    t = np.arange(int(round(t_end / dt)) + 1) * dt
    if system == "coulomb":
        return _coulomb(d["mu"], t)
    if system == "sine":
        return np.column_stack([np.cos(8 * t), -8 * np.sin(8 * t)]), t, {(0, "x1"): 1.0, (1, "x0"): -K}
    n_states = d.get("states", 2)
    shape = (t.size, n_states)
    noise = {
        "white": lambda: rng.standard_normal(shape),
        "uniform": lambda: rng.uniform(-1, 1, shape),
        "walk": lambda: np.cumsum(rng.standard_normal(shape), axis=0),
        "pink": lambda: _pink(rng, shape),
        "const": lambda: np.full(shape, 3.0),
        "zeros": lambda: np.zeros(shape),
        "binary": lambda: rng.random(shape) > 0.5,
    }[system]()
    return noise, t, None


def _pink(rng, shape):
    spec = rng.standard_normal((shape[0] // 2 + 1, shape[1])) + 1j * rng.standard_normal(
        (shape[0] // 2 + 1, shape[1])
    )
    spec[0] = 0
    spec[1:] /= np.sqrt(np.arange(1, spec.shape[0]))[:, None]
    x = np.fft.irfft(spec, n=shape[0], axis=0)
    return x / x.std(axis=0)


def _coulomb(mu: float, t: np.ndarray):
    """Ring-down with a sharp Coulomb friction (sign width 1e-3 of the velocity amplitude)."""
    from scipy.integrate import solve_ivp

    c = 0.5
    width = 1e-3 * 8.0

    def rhs(_t, y):
        return [y[1], -K * y[0] - c * y[1] - mu * np.tanh(y[1] / width)]

    sol = solve_ivp(rhs, (0, t[-1]), [1.0, 0.0], t_eval=t, method="LSODA", rtol=1e-8, atol=1e-10)
    truth = {(0, "x1"): 1.0, (1, "x0"): -K, (1, "x1"): -c, (1, "sgn(x1)"): -mu}
    return sol.y.T, t, truth


def _scale_truth(truth: dict, scale: np.ndarray) -> dict:
    """Coefficients after x_i -> s_i x_i: c * s_eq / prod s_j^p_j (monomials and sgn)."""
    out = {}
    for (eq, term), value in truth.items():
        factor = scale[eq]
        for part in term.split():
            if part.startswith("sgn"):
                continue
            name, _, power = part.partition("^")
            factor /= scale[int(name[1:])] ** int(power or 1)
        out[(eq, term)] = value * factor
    return out


def _corrupt(x: np.ndarray, t: np.ndarray, d: dict, rng) -> np.ndarray:
    x = np.array(x, dtype=float)
    amp = np.max(np.abs(x), axis=0)
    if d.get("snr") is not None:
        from sindy_impulse.datasets import add_noise

        x = add_noise(x, d["snr"], random_state=rng)
    if "clip" in d:
        level, states = d["clip"]
        for j in states:
            x[:, j] = np.clip(x[:, j], -level * amp[j], level * amp[j])
    if "quantise" in d:
        step = d["quantise"] * amp
        x = np.round(x / step) * step
    if "step" in d:
        j, size = d["step"]
        x[x.shape[0] // 2 :, j] += size * amp[j]
    if "spike" in d:
        j, size = d["spike"]
        x[x.shape[0] // 3, j] += size * amp[j]
    if "dropout" in d:
        j, length = d["dropout"]
        x[x.shape[0] // 3 : x.shape[0] // 3 + length, j] = 0.0
    offset = np.broadcast_to(np.asarray(d.get("offset", 0.0), dtype=float), (x.shape[1],))
    x = x + offset * amp + np.outer(t, np.asarray(d.get("drift", 0.0)) * amp)
    return x


def _channels(x: np.ndarray, kind: str, rng) -> np.ndarray:
    extra = {
        "copy": lambda: x[:, 0],
        "copy_noise": lambda: x[:, 0] + 1e-6 * np.std(x[:, 0]) * rng.standard_normal(x.shape[0]),
        "scaled": lambda: -2.5 * x[:, 0],
        "combo": lambda: x[:, 0] + 0.1 * x[:, 1],
        "const": lambda: np.full(x.shape[0], 2.0),
        "zeros": lambda: np.zeros(x.shape[0]),
    }[kind]()
    return np.column_stack([x, extra])


def make_data(d: dict):
    """``(x, t, truth)`` of a recipe (truth None when no model is right)."""
    rng = np.random.default_rng(d.get("seed", 0))
    x, t, truth = _system(d, rng)
    scale = np.broadcast_to(np.asarray(d.get("scale", 1.0), dtype=float), (x.shape[1],)).copy()
    x = _corrupt(np.asarray(x, dtype=float) * scale, t, d, rng)
    if truth is not None:
        truth = _scale_truth(truth, scale)
    if "channels" in d:
        x, truth = _channels(x, d["channels"], rng), None
    n = d.get("n")
    if n is not None:
        x, t = x[:n], t[:n]
    kind = d.get("dtype")
    if kind == "bool":
        x = x > np.median(x, axis=0)
    elif kind == "int":
        x = np.round(1000 * x).astype(np.int64)
        truth = None if truth is None else _scale_truth(truth, np.full(x.shape[1], 1000.0))
    elif kind == "float32":
        x = x.astype(np.float32)
    elif kind == "list":
        x = x.tolist()
    elif kind == "dataframe":
        import pandas as pd

        x = pd.DataFrame(x, columns=[f"s{j}" for j in range(x.shape[1])])
    return x, t, truth


# --------------------------------------------------------------------------------------------------------
# actions
# --------------------------------------------------------------------------------------------------------
def _library(name: str | None):
    import pysindy as ps

    from sindy_impulse import MechanicalLibrary

    if name == "mechanical":
        return MechanicalLibrary(degree=3)
    if name == "linear":
        return ps.PolynomialLibrary(degree=1)
    return None


def _fit(spec: dict):
    from sindy_impulse import DelayEmbedding, ImpulseSINDy

    x, t, truth = make_data(spec["data"])
    params = dict(spec.get("params", {}))
    library = _library(params.pop("library", None))
    model = ImpulseSINDy(feature_library=library, **params)
    if spec["data"].get("embed"):
        signal = np.asarray(x)[:, 0]
        embedding = DelayEmbedding().fit(signal)
        model.fit(embedding.transform(signal), t=embedding.transform_time(t))
        return model, None
    trajectories = spec["data"].get("trajectories")
    if trajectories:
        xs = [
            make_data(dict(spec["data"], trajectories=0, seed=k, x0=0.5 + 0.25 * k))[0]
            for k in range(trajectories)
        ]
        ts = [t[: len(xi)] for xi in xs]
        return model.fit(xs, t=ts), truth
    return model.fit(x, t=t if spec["data"].get("t") is None else spec["data"]["t"]), truth


def _coefficients_right(model, truth: dict, tol: float, optional=()) -> tuple[bool, str]:
    """The model has exactly the true terms (and perhaps ``optional`` ones), every true coefficient within
    ``tol`` (relative)."""
    names = model.get_feature_names()
    coef = model.coefficients()
    found = {(i, names[j]): float(coef[i, j]) for i, j in zip(*np.nonzero(coef)) if names[j] not in optional}
    if set(found) != set(truth):
        extra = sorted(set(found) - set(truth))
        missing = sorted(set(truth) - set(found))
        return False, f"terms: extra {extra}, missing {missing}"
    worst = max(abs(found[k] / v - 1) for k, v in truth.items())
    return worst <= tol, f"worst coefficient error {worst:.2g}"


def _right(model, truth, tol, optional=()):
    if truth is None:
        return False, "no model is right for these data"
    return _coefficients_right(model, truth, tol, optional)


def _modal(spec: dict):
    from sindy_impulse.analysis import modal_parameters

    model, _ = _fit(spec)
    f, zeta = modal_parameters(model)
    want_f, want_zeta = spec["expect"].get("f_hz", F_HZ), spec["expect"].get("zeta", ZETA)
    if f.size == 0:
        return False, "no oscillatory mode"
    err = max(abs(f[0] / want_f - 1), abs(zeta[0] / want_zeta - 1))
    detail = f"f {f[0]:.4f} Hz, zeta {zeta[0]:.4f} (error {err:.2g})"
    return bool(err <= spec["expect"].get("tol", 0.0)), detail  # no tol: a warning is expected


def _simulate(spec: dict):
    model, _ = _fit(spec)
    x, t, _ = make_data(spec["data"])
    sim = model.simulate(np.asarray(x)[0] * spec["factor"], t)
    finite = bool(np.all(np.isfinite(sim)))
    return finite, f"simulation {'finite' if finite else 'with NaN rows'}"


def _features(spec: dict):
    from sindy_impulse import SINDyFeatures, damped_oscillator

    rng = np.random.default_rng(0)
    noise = [rng.standard_normal(spec["n"]) * 10.0 ** spec.get("scale", 0) for _ in range(spec["noise"])]
    rings = [damped_oscillator(k=k, snr_db=40, random_state=i).x[:, 0] for i, k in enumerate([49, 64, 81])]
    series = rings[: spec["rings"]] + noise
    features = SINDyFeatures(dt=0.01)
    X = features.fit_transform(series)
    flagged = sorted(np.flatnonzero(np.isnan(X).any(axis=1)).tolist())
    want = list(range(spec["rings"], len(series)))
    return flagged == want, f"flagged {flagged}, noise series {want}"


def run_action(spec: dict):
    """Run a case; returns ``(ok, detail)`` for the expectations that check an answer."""
    action = spec["action"]
    if action == "fit":
        model, truth = _fit(spec)
        return _right(model, truth, spec["expect"].get("tol", 0.05), spec["expect"].get("optional", ()))
    if action == "modal":
        return _modal(spec)
    if action == "simulate":
        return _simulate(spec)
    if action == "features":
        return _features(spec)
    if action == "call":
        return run_call(spec["call"])
    raise ValueError(f"unknown action {action!r}")


# --------------------------------------------------------------------------------------------------------
# scikit-learn style bad calls: name -> (call, error, message regex)
# --------------------------------------------------------------------------------------------------------
def _calls() -> dict:
    from scipy import sparse

    from sindy_impulse import ImpulseSINDy, damped_oscillator

    t, x, x_dot = damped_oscillator()

    def fit(**kw):
        return lambda: ImpulseSINDy(**kw.pop("params", {})).fit(kw.pop("x", x), **{"t": 0.01, **kw})

    def fitted():
        return ImpulseSINDy().fit(x, t=t)

    def put(value, row=7, col=0):
        out = x.copy()
        out[row, col] = value
        return out

    e_v, e_t, e_p = "ValueError", "TypeError", "InvalidParameterError"
    return {
        "x nan": (fit(x=put(np.nan)), e_v, r"x contains 1 non-finite"),
        "x inf": (fit(x=put(np.inf)), e_v, r"x contains 1 non-finite"),
        "x -inf": (fit(x=put(-np.inf, 200, 1)), e_v, r"non-finite"),
        "x empty": (fit(x=np.zeros((0, 2))), e_v, r"x is empty"),
        "x complex": (fit(x=x.astype(complex)), e_v, r"x is complex"),
        "x strings": (fit(x=np.full((401, 2), "a")), e_t, r"non-numeric"),
        "x object": (fit(x=np.array([["a", 1.0]] * 401, dtype=object)), e_t, r"non-numeric"),
        "x 3-D": (fit(x=x[:, :, None]), e_v, r"1-D or 2-D"),
        "x None": (fit(x=None), e_t, r"x"),
        "x sparse": (fit(x=sparse.csr_matrix(x)), e_t, r"sparse"),
        "x scalar": (fit(x=3.0), e_v, r"x"),
        "x one sample": (fit(x=x[:1]), e_v, r"sample"),
        "x two samples": (fit(x=x[:2]), e_v, r"sample"),
        "x ragged list": (fit(x=[x, x[:, :1]], t=[t, t]), e_v, r"states|columns|same"),
        "t decreasing": (fit(t=t[::-1]), e_v, r"increasing"),
        "t repeated": (fit(t=np.r_[t[:5], t[4:-1]]), e_v, r"t\[5\]"),
        "t short": (fit(t=t[:-1]), e_v, r"400 entries"),
        "t 2-D": (fit(t=t[:, None]), e_v, r"scalar"),
        "t nan": (fit(t=np.where(np.arange(401) == 3, np.nan, t)), e_v, r"NaN or inf"),
        "t complex": (fit(t=t + 0j), e_v, r"complex"),
        "t string": (fit(t="0.01"), e_t, r"non-numeric"),
        "t bool": (fit(t=True), e_t, r"time step"),
        "dt negative": (fit(t=-0.01), e_v, r"positive"),
        "dt zero": (fit(t=0.0), e_v, r"positive"),
        "dt inf": (fit(t=np.inf), e_v, r"positive finite"),
        "dt nan": (fit(t=np.nan), e_v, r"positive finite|NaN"),
        "x_dot shape": (fit(x_dot=x_dot[:-1]), e_v, r"x_dot"),
        "x_dot nan": (fit(x_dot=np.where(np.arange(401)[:, None] == 5, np.nan, x_dot)), e_v, r"x_dot"),
        "u wrong length": (fit(u=np.ones(400)), e_v, r"u"),
        "u nan": (fit(u=np.where(np.arange(401) == 5, np.nan, 1.0)), e_v, r"u"),
        "feature_names length": (fit(feature_names=["a", "b", "c"]), e_v, r"feature_names"),
        "param bound_factor": (fit(params={"bound_factor": -1.0}), e_p, r"bound_factor"),
        "param refine_max_iter": (fit(params={"refine_max_iter": 0}), e_p, r"refine_max_iter"),
        "param sweep": (fit(params={"sweep": "yes"}), e_p, r"sweep"),
        "param selection": (fit(params={"selection": "nope"}), e_p, r"selection"),
        "param error_measure": (fit(params={"error_measure": "nope"}), e_p, r"error_measure"),
        "param dt": (lambda: ImpulseSINDy(dt=-1.0).fit(x), e_p, r"dt"),
        "param divergence_factor": (fit(params={"divergence_factor": 0.0}), e_p, r"divergence_factor"),
        "param optimizer": (fit(params={"optimizer": 3}), e_p, r"optimizer"),
        "param feature_library": (fit(params={"feature_library": "poly"}), e_p, r"feature_library"),
        "param differentiation": (fit(params={"differentiation_method": 3}), e_p, r"differentiation"),
        "predict unfitted": (lambda: ImpulseSINDy().predict(x), "NotFittedError", r"not fitted"),
        "simulate unfitted": (lambda: ImpulseSINDy().simulate(x[0], t), "NotFittedError", r"not fitted"),
        "score unfitted": (lambda: ImpulseSINDy().score(x, t=t), "NotFittedError", r"not fitted"),
        "coefficients unfitted": (lambda: ImpulseSINDy().coefficients(), "NotFittedError", r"not fitted"),
        "predict 3 states": (lambda: fitted().predict(np.ones((5, 3))), e_v, r"3 features"),
        "predict 1-D": (lambda: fitted().predict(np.ones(5)), e_v, r"1-D"),
        "predict nan": (lambda: fitted().predict(put(np.nan)), e_v, r"non-finite"),
        "simulate x0 length": (lambda: fitted().simulate(np.ones(3), t), e_v, r"x0 has 3"),
        "simulate x0 nan": (lambda: fitted().simulate(np.array([np.nan, 0.0]), t), e_v, r"x0"),
        "simulate t scalar": (lambda: fitted().simulate(x[0], 4.0), e_v, r"array of time"),
        "simulate t decreasing": (lambda: fitted().simulate(x[0], t[::-1]), e_v, r"increasing"),
        "simulate u unused": (lambda: fitted().simulate(x[0], t, u=np.ones(401)), "DataWarning", r""),
        "score 1 sample": (lambda: fitted().score(x[:1], t=0.01), e_v, r"sample"),
        "modal string": (lambda: _modal_call("model"), e_t, r"ImpulseSINDy"),
        "modal unfitted": (lambda: _modal_call(ImpulseSINDy()), e_v, r"fitted"),
        "modal not square": (lambda: _modal_call(np.zeros((2, 3))), e_v, r"square"),
        "modal nan matrix": (lambda: _modal_call(np.full((2, 2), np.nan)), e_v, r"NaN|non-finite"),
        "pde library": (
            lambda: ImpulseSINDy(feature_library=__import__("pysindy").PDELibrary()).fit(x, t=t),
            "NotImplementedError",
            r"PDE",
        ),
        "features empty": (lambda: _features_call([]), e_v, r"empty"),
        "features 1-D": (lambda: _features_call(np.ones(400)), e_v, r"1-D"),
        "features nan": (lambda: _features_call([np.full(400, np.nan)]), e_v, r"non-finite"),
    }


def _modal_call(model):
    from sindy_impulse.analysis import modal_parameters

    return modal_parameters(model)


def _features_call(X):
    from sindy_impulse import SINDyFeatures

    return SINDyFeatures(dt=0.01).fit_transform(X)


def call_expectations() -> dict:
    """``{name: (error or warning class name, message regex)}`` of the scikit-learn style calls."""
    return {name: (error, match) for name, (_, error, match) in _calls().items()}


def run_call(name: str):
    call, _, _ = _calls()[name]
    call()
    return True, "returned"


# ------------------------------------------------------------------------------------------------------
# a case run and judged against its expectation
# ------------------------------------------------------------------------------------------------------
#: The outcomes that fail the matrix (a wrong answer without a warning, a crash, a hang).
FAILURES = ("silent wrong", "crash", "hang")


def _caught(record) -> list[tuple[str, str, bool]]:
    from sindy_impulse.exceptions import SindyImpulseWarning

    return [
        (w.category.__name__, str(w.message), issubclass(w.category, SindyImpulseWarning)) for w in record
    ]


def _judge(expect: dict, result, record, error) -> tuple[str, str]:
    """Outcome and detail of one case against its expectation."""
    ours = [c for c in record if c[2]]
    kind = expect["type"]
    if error is not None:
        name, message = type(error).__name__, str(error)
        wanted = expect.get("error")
        if kind == "raise" and _is(error, wanted) and re.search(expect.get("match", ""), message):
            return "expected", f"{name}: {message[:90]}"
        if isinstance(error, (ValueError, TypeError)) and message:
            return "refused", f"{name}: {message[:90]}"
        return "crash", f"{name}: {message[:200]}"
    if kind == "raise":
        return ("warned", _names(ours)) if ours else ("silent wrong", "no error raised")
    if kind == "warn":
        wanted = [
            c
            for c in record
            if _is_name(c[0], expect["warning"]) and re.search(expect.get("match", ""), c[1])
        ]
        if wanted:
            return "expected", _names(wanted)
        return ("warned", f"other warning {_names(ours)}") if ours else ("silent wrong", "no warning")
    ok, detail = result
    if ok:
        return "expected", detail + (f"; warned {_names(ours)}" if ours else "")
    if kind == "right_or_warn" and ours:
        return "expected", f"{detail}; warned {_names(ours)}"
    return ("warned", f"{detail}; {_names(ours)}") if ours else ("silent wrong", detail)


def _is(error, wanted: str | None) -> bool:
    return wanted is not None and any(_is_name(c.__name__, wanted) for c in type(error).__mro__)


def _is_name(name: str, wanted: str) -> bool:
    from sindy_impulse import exceptions

    cls = getattr(exceptions, name, None)
    target = getattr(exceptions, wanted, None)
    if cls is not None and target is not None:
        return issubclass(cls, target)
    return name == wanted


def _names(caught) -> str:
    return ", ".join(sorted({c[0] for c in caught}))


def run_case(spec: dict) -> dict:
    """Build and run one case; never raises. Returns ``{"id", "outcome", "detail", "time", ...}``."""
    start = time.perf_counter()
    result, error = None, None
    with warnings.catch_warnings(record=True) as record:
        warnings.simplefilter("always")
        try:
            result = run_action(spec)
        except Exception as err:  # noqa: BLE001 - the matrix records everything
            error = err
            tb = traceback.format_exc(limit=8)
    caught = _caught(record)
    outcome, detail = _judge(spec["expect"], result, caught, error)
    out = {"id": spec["id"], "group": spec["group"], "outcome": outcome, "detail": detail}
    out["time"] = time.perf_counter() - start
    out["warnings"] = sorted({c[0] for c in caught})
    if outcome == "crash" and error is not None:
        out["traceback"] = tb
    return out
