#!/usr/bin/python3
"""Independent reference fits for psychometric_fit_test.cpp (fixture scipy_reference.json).

Maximum-likelihood fits of the binomial likelihood
    log L = sum_i log C(n_i, k_i) + k_i log p_i + (n_i - k_i) log(1 - p_i),
    p_i = guess + (1 - guess - lapse) * p_see(level_i),
with threshold free, slope > 0, lapse in [0, max_lapse], guess fixed, written here from the
definitions in docs/analysis.md ("Psychometric fits") and sharing no code with fovlab.
Optimiser: scipy.optimize.minimize, Nelder-Mead from a grid of 5 x 4 x 3 starts (threshold,
slope, lapse) on (threshold or log threshold, log slope, lapse) with the lapse clipped into its
bounds, then each of the best five polished with L-BFGS-B on the natural parameters with bounds
(lapse in [0, max_lapse]); the best log likelihood wins.

Profile-likelihood 95 % threshold interval: the thresholds t with
    2 (log L(fit) - max over slope and lapse of log L(t, slope, lapse)) <= chi2.ppf(0.95, 1),
the inner maximum by Nelder-Mead on (log slope, lapse) from 4 x 3 starts polished with L-BFGS-B
(slope > 0, lapse in [0, max_lapse]), each end found by stepping outwards from the fit's threshold
and then scipy.optimize.brentq on the crossing.

Run with Debian 12's /usr/bin/python3 (SciPy 1.10.1, NumPy 1.24.2):
    /usr/bin/python3 tests/analysis/fitting/make_scipy_reference.py > tests/analysis/fitting/scipy_reference.json
"""
import json
import sys

import numpy as np
import scipy
from scipy import optimize, special, stats

CLAMP = 1e-12


def p_see(shape, rising, threshold, slope, x):
    s = 1.0 if rising else -1.0
    if shape == "logistic":
        return special.expit(s * slope * (x - threshold))
    if shape == "cumulative_normal":
        return stats.norm.cdf(s * slope * (x - threshold))
    if shape == "weibull":
        z = np.log(2.0) * (x / threshold) ** slope
        return -np.expm1(-z) if rising else np.exp(-z)
    raise ValueError(shape)


def log_likelihood(case, threshold, slope, lapse):
    x = np.array(case["levels"], float)
    n = np.array(case["n"], float)
    k = np.array(case["k"], float)
    g = case["guess"]
    p = g + (1.0 - g - lapse) * p_see(case["shape"], case["rising"], threshold, slope, x)
    p = np.clip(p, CLAMP, 1.0 - CLAMP)
    coefficients = special.gammaln(n + 1) - special.gammaln(k + 1) - special.gammaln(n - k + 1)
    return float(np.sum(coefficients + k * np.log(p) + (n - k) * np.log1p(-p)))


def fit(case):
    weibull = case["shape"] == "weibull"
    x = np.array(case["levels"], float)
    axis = np.log(x) if weibull else x
    lo, hi = axis.min(), axis.max()
    span = hi - lo
    max_lapse = case["max_lapse"]

    def natural(v):
        t = np.exp(v[0]) if weibull else v[0]
        return t, np.exp(v[1]), float(np.clip(v[2], 0.0, max_lapse))

    def negative_transformed(v):
        if abs(v[1]) > 50:
            return 1e300
        value = -log_likelihood(case, *natural(v))
        return value if np.isfinite(value) else 1e300

    candidates = []
    for t in np.linspace(lo + 0.1 * span, hi - 0.1 * span, 5):
        for s in (0.5, 2.0, 8.0, 32.0):
            for lapse in (0.0, 0.3 * max_lapse, 0.8 * max_lapse):
                start = np.array([t, np.log(s / span), lapse])
                r = optimize.minimize(negative_transformed, start, method="Nelder-Mead",
                                      options={"xatol": 1e-10, "fatol": 1e-12, "maxiter": 20000, "maxfev": 40000})
                candidates.append((r.fun, natural(r.x)))
    candidates.sort(key=lambda c: c[0])
    best = None
    for _, (t, s, lapse) in candidates[:5]:
        lower_t = 1e-12 if weibull else -np.inf
        r = optimize.minimize(lambda q: -log_likelihood(case, *q), np.array([t, s, lapse]), method="L-BFGS-B",
                              bounds=[(lower_t, None), (1e-12, None), (0.0, max_lapse)],
                              options={"ftol": 1e-15, "gtol": 1e-10, "maxiter": 10000})
        for value, params in ((r.fun, tuple(r.x)), (-log_likelihood(case, t, s, lapse), (t, s, lapse))):
            if best is None or value < best[0]:
                best = (value, params)
    t, s, lapse = best[1]
    return {"threshold": float(t), "slope": float(s), "lapse": float(lapse),
            "log_likelihood": log_likelihood(case, t, s, lapse)}


def profile(case, t):
    """max over slope and lapse of log L with the threshold fixed at t (natural units)."""
    weibull = case["shape"] == "weibull"
    x = np.array(case["levels"], float)
    axis = np.log(x) if weibull else x
    span = axis.max() - axis.min()
    max_lapse = case["max_lapse"]

    def negative(v):
        if abs(v[0]) > 50:
            return 1e300
        value = -log_likelihood(case, t, np.exp(v[0]), float(np.clip(v[1], 0.0, max_lapse)))
        return value if np.isfinite(value) else 1e300

    best = None
    for s in (0.5, 2.0, 8.0, 32.0):
        for lapse in (0.0, 0.3 * max_lapse, 0.8 * max_lapse):
            r = optimize.minimize(negative, np.array([np.log(s / span), lapse]), method="Nelder-Mead",
                                  options={"xatol": 1e-10, "fatol": 1e-12, "maxiter": 20000, "maxfev": 40000})
            slope, lap = np.exp(r.x[0]), float(np.clip(r.x[1], 0.0, max_lapse))
            q = optimize.minimize(lambda w: -log_likelihood(case, t, w[0], w[1]), np.array([slope, lap]),
                                  method="L-BFGS-B", bounds=[(1e-12, None), (0.0, max_lapse)],
                                  options={"ftol": 1e-15, "gtol": 1e-10, "maxiter": 10000})
            for value in (-r.fun, -q.fun):
                if best is None or value > best:
                    best = value
    return best


def profile_interval(case, fitted, confidence=0.95):
    weibull = case["shape"] == "weibull"
    cut = stats.chi2.ppf(confidence, 1)
    top = fitted["log_likelihood"]
    t_hat = fitted["threshold"]
    x = np.array(case["levels"], float)
    span = (np.log(x.max()) - np.log(x.min())) if weibull else (x.max() - x.min())

    def gap(axis_t):
        t = np.exp(axis_t) if weibull else axis_t
        return 2.0 * (top - profile(case, t)) - cut

    centre = np.log(t_hat) if weibull else t_hat
    ends = []
    for direction in (-1.0, 1.0):
        step = 0.02 * span
        inside = centre
        while True:
            outside = inside + direction * step
            if gap(outside) > 0:
                break
            inside, step = outside, 2.0 * step
        root = optimize.brentq(gap, min(inside, outside), max(inside, outside), xtol=1e-12, rtol=1e-12)
        ends.append(float(np.exp(root)) if weibull else float(root))
    return {"confidence": confidence, "lower": ends[0], "upper": ends[1]}


CASES = [
    {"name": "logistic_contrast_detection", "shape": "logistic", "rising": True, "guess": 0.0, "max_lapse": 0.1,
     "levels": [0.5, 1.0, 1.5, 2.0, 2.5, 3.0], "n": [30, 30, 30, 30, 30, 30], "k": [2, 5, 13, 22, 27, 28]},
    {"name": "weibull_2afc", "shape": "weibull", "rising": True, "guess": 0.5, "max_lapse": 0.06,
     "levels": [0.01, 0.02, 0.04, 0.08, 0.16, 0.32], "n": [40, 40, 40, 40, 40, 40], "k": [21, 22, 27, 33, 38, 37]},
    {"name": "normal_eccentricity_falling", "shape": "cumulative_normal", "rising": False, "guess": 0.0,
     "max_lapse": 0.1, "levels": [5.0, 10.0, 15.0, 20.0, 25.0, 30.0], "n": [20, 24, 28, 32, 36, 40],
     "k": [19, 20, 17, 11, 6, 3]},
]


def main():
    out = {
        "generator": "tests/analysis/fitting/make_scipy_reference.py",
        "python": sys.version.split()[0],
        "scipy": scipy.__version__,
        "numpy": np.__version__,
        "clamp": CLAMP,
        "cases": [],
    }
    for case in CASES:
        entry = dict(case)
        entry["fit"] = fit(case)
        entry["threshold_profile_interval"] = profile_interval(case, entry["fit"])
        out["cases"].append(entry)
    json.dump(out, sys.stdout, indent=2)
    sys.stdout.write("\n")


if __name__ == "__main__":
    main()
