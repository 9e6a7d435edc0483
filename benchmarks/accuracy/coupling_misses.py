"""Why the survey misses family g's records: each mode it gets wrong, surveyed again with the element's
coupling of the modes taken away.

Family g's records (:func:`benchmarks.accuracy.families.family_g`) carry a nonlinear element at mass 0: a
cubic spring, an amplitude-dependent damper, or both. The element moves every mode through the displacement
at its place, the sum of all the modes there: a mode's frequency and decay rate change with its own
amplitude (what the survey's averaged equations read) and with every other mode's (the modes' coupling
through the element), and its force holds the modes' combination tones.

For every record of the family that the survey gets wrong (same draws as ``python -m benchmarks modes
--family g``: ``--seed``, record ``i``), each mode out of its marks is surveyed again in records made from
the same configuration (same hit, noise and sensor; :func:`~benchmarks.accuracy.families.element_variants`):

- **alone**: the hit excites that mode only (the other modes at rest, the structure and its element
  unchanged): the element moves the mode through the mode's own amplitude only;
- **alone, element as strong**: as *alone*, with the element made stronger by the share the other modes'
  amplitudes have in moving that mode in the record (to first order), so that the element moves the mode
  at the hit as much as in the record, through its own amplitude;
- **no element**: the record without the element (the same modes, linear).

A mode that is right in both *alone* records and wrong in the record is moved by the other modes'
amplitudes: its error comes from the modes' coupling through the element, which the survey does not model
(it reads each mode against its own amplitude and, in its joint reading, against the amplitudes of the
modes it finds nonlinear, each as a change of frequency and decay rate; not the energy the element passes
between modes, nor the combination tones it puts in a mode's band). A spurious mode that the record without
the element does not have is a product of the element.

    python -m benchmarks coupling_misses --seed 197              # family g, 100 records
    python -m benchmarks coupling_misses --seed 131 --n 30
"""

from __future__ import annotations

import argparse
import warnings

import numpy as np

from benchmarks.accuracy.families import draw, element_variants
from benchmarks.accuracy.scoring import assign
from sindy_impulse import identify_modes, impact_record


def survey(y: np.ndarray, fs: float) -> list[tuple[float, float]]:
    """The survey's (frequency, damping ratio) per mode of a record."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        modes = identify_modes(y, fs=fs).modes
    return [(m.frequency_hz, m.damping_ratio) for m in modes]


def reading(case: dict, found: list, i: int) -> str:
    """``"right"``, ``"wrong"`` or ``"missed"``: true mode ``i`` of ``case`` in the survey's ``found``."""
    f, z = case["config"]["frequencies_hz"][i], case["config"]["damping_ratios"][i]
    pairs = assign([f], [g for g, _ in found])
    if 0 not in pairs:
        return "missed"
    g, zeta = found[pairs[0]]
    return "right" if abs(g / f - 1) <= case["f_tol"] and abs(zeta / z - 1) <= case["z_tol"] else "wrong"


def attribute(case: dict) -> dict | None:
    """The record's failing modes and spurious ones, each read again (see the module); None when the survey
    gets the record right."""
    config = case["config"]
    f_true = np.asarray(config["frequencies_hz"], float)
    rec = impact_record(**config)
    found = survey(rec.y, rec.fs)
    pairs = assign(f_true, [g for g, _ in found])
    failing = [i for i in range(f_true.size) if reading(case, found, i) != "right"]
    spurious = [found[j][0] for j in range(len(found)) if j not in pairs.values()]
    if not failing and not spurious:
        return None
    modes, linear = [], None
    for i in failing:
        row = {"frequency_hz": float(f_true[i]), "damping_ratio": float(config["damping_ratios"][i]),
               "record": reading(case, found, i)}
        for name, (y, fs) in element_variants(config, i).items():
            if name == "no element":  # the same record for every mode: surveyed once
                linear = survey(y, fs) if linear is None else linear
            row[name] = reading(case, linear if name == "no element" else survey(y, fs), i)
        modes.append(row)
    if linear is None:
        linear = survey(*element_variants(config, 0)["no element"])
    products = [g for g in spurious if not any(abs(h / g - 1) <= 0.01 for h, _ in linear)]
    return {"modes": modes, "spurious": spurious, "element_products": products}


def coupling_only(result: dict) -> bool:
    """Whether every failing mode of a missed record is right in both *alone* records, and every spurious
    mode is a product of the element."""
    alone = all(m["alone"] == "right" and m["alone, element as strong"] == "right" for m in result["modes"])
    return alone and len(result["element_products"]) == len(result["spurious"])


def main(argv=None) -> dict:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--n", type=int, default=100, help="records of family g (default 100)")
    parser.add_argument("--quick", action="store_true", help="20 records")
    parser.add_argument("--seed", type=int, default=0)
    args = parser.parse_args(argv)
    rng = np.random.default_rng(args.seed)
    n = 20 if args.quick else args.n
    records, missed = 0, []
    for index in range(n):
        case = draw("g", rng, index)
        try:
            result = attribute(case)
        except ValueError as err:  # as the modes benchmark: a record the generator refuses is left out
            print(f"  [g #{index}] left out: the generator refused the record ({err})", flush=True)
            continue
        records += 1
        if result is None:
            continue
        result["index"] = index
        missed.append(result)
        print(f"  [g #{index}] missed; coupling only: {coupling_only(result)}", flush=True)
        for m in result["modes"]:
            print(f"      {m['frequency_hz']:.5g} Hz (damping ratio {m['damping_ratio']:.4f}): record "
                  f"{m['record']}, alone {m['alone']}, alone with the element as strong "
                  f"{m['alone, element as strong']}, without the element {m['no element']}", flush=True)
        for g in result["spurious"]:
            print(f"      spurious {g:.5g} Hz: "
                  + ("a product of the element" if g in result["element_products"] else
                     "also without the element"), flush=True)
    modes = [m for r in missed for m in r["modes"]]
    right = {name: sum(m[name] == "right" for m in modes)
             for name in ("alone", "alone, element as strong", "no element")}
    coupled = sum(coupling_only(r) for r in missed)
    print(f"family g, seed {args.seed}: {records} records, {records - len(missed)} right; of the "
          f"{len(missed)} missed, {coupled} are missed through the modes' coupling only. Their {len(modes)} "
          f"failing mode(s) read right: alone {right['alone']}, alone with the element as strong "
          f"{right['alone, element as strong']}, without the element {right['no element']}; spurious modes "
          f"{sum(len(r['spurious']) for r in missed)}, of them products of the element "
          f"{sum(len(r['element_products']) for r in missed)}")
    return {"seed": args.seed, "records": records, "missed": len(missed), "coupling_only": coupled,
            "failing_modes": len(modes), "right": right, "details": missed}


if __name__ == "__main__":
    main()
