#!/usr/bin/python3
"""Independent reference data for quest_plus_test.cpp (fixture quest_plus_reference.json).

QUEST+ (Watson 2017) written here with NumPy from the paper's definitions, sharing no code with
fovlab: the posterior over a (threshold, slope, lapse) grid, threshold-major, starts at the prior
(uniform, or normal over thresholds) and is multiplied by the likelihood of each answer and
normalised; the next level is the one with the least expected posterior entropy, computed the
brute-force way (form both possible posteriors, normalise, take -sum q log q, weight by the
answer's probability), the first in grid order on a tie. p_report = guess + (1 - guess - lapse) *
p_see, with p_see as docs/analysis.md defines it (logistic, cumulative normal, Weibull; falling when
not rising).

Each case runs a simulated observer (NumPy's PCG64 with a fixed seed) for its trials and records,
at every trial, the level index chosen, the expected entropy of every level, and after the answer
the posterior's threshold mean, 95 % equal-tailed interval on the grid and entropy in bits.

Run with Debian 12's /usr/bin/python3 (NumPy 1.24.2, SciPy 1.10.1):
    /usr/bin/python3 tests/study/schedule/make_quest_plus_reference.py > tests/study/schedule/quest_plus_reference.json
"""
import json

import numpy as np
from scipy import special, stats


def p_see(shape, rising, threshold, slope, x):
    s = 1.0 if rising else -1.0
    if shape == "logistic":
        return special.expit(s * slope * (x - threshold))
    if shape == "cumulative_normal":
        return stats.norm.cdf(s * slope * (x - threshold))
    z = np.log(2.0) * (x / threshold) ** slope
    return 1.0 - np.exp(-z) if rising else np.exp(-z)


def entropy(q):
    q = q[q > 0]
    return float(-(q * np.log(q)).sum())


def run(case):
    levels = np.array(case["levels"], dtype=float)
    T, S, L = (np.array(case[k], dtype=float) for k in ("thresholds", "slopes", "lapses"))
    tt, ss, ll = np.meshgrid(T, S, L, indexing="ij")  # threshold-major, as fovlab's grid
    tt, ss, ll = tt.ravel(), ss.ravel(), ll.ravel()
    guess = case["guess"]
    # likelihood of "seen" for each level (rows) and grid point (columns)
    seen = np.array([guess + (1 - guess - ll) * p_see(case["shape"], case["rising"], tt, ss, x) for x in levels])
    prior_t = np.ones(len(T)) if case["prior_sd"] == 0 else np.exp(-0.5 * ((T - case["prior_mean"]) / case["prior_sd"]) ** 2)
    posterior = np.repeat(prior_t, len(S) * len(L))
    posterior /= posterior.sum()
    rng = np.random.Generator(np.random.PCG64(case["observer_seed"]))
    truth = case["observer"]
    steps = []
    for _ in range(case["trials"]):
        expected = []
        for x in range(len(levels)):
            total = 0.0
            for likelihood in (seen[x], 1.0 - seen[x]):
                unnormalised = posterior * likelihood
                p_answer = unnormalised.sum()
                if p_answer > 0:
                    total += p_answer * entropy(unnormalised / p_answer)
            expected.append(total)
        index = int(np.argmin(expected))  # the first minimum
        p_true = guess + (1 - guess - truth["lapse"]) * p_see(case["shape"], case["rising"], truth["threshold"],
                                                               truth["slope"], levels[index])
        answer = bool(rng.random() < p_true)
        posterior = posterior * (seen[index] if answer else 1.0 - seen[index])
        posterior /= posterior.sum()
        marginal = posterior.reshape(len(T), -1).sum(axis=1)
        cumulative = np.cumsum(marginal)
        lower = T[np.argmax(cumulative >= 0.025)]
        upper = T[np.argmax(cumulative >= 0.975)] if cumulative[-1] >= 0.975 else T[-1]
        steps.append({"index": index, "expected_entropies": expected, "seen": answer,
                      "threshold_mean": float((posterior * tt).sum()), "threshold_lower": float(lower),
                      "threshold_upper": float(upper), "entropy_bits": entropy(posterior) / np.log(2.0)})
    return {**case, "steps": steps}


CASES = [
    {"name": "logistic_falling_2afc_same", "shape": "logistic", "rising": False, "guess": 0.05,
     "levels": [2.5, 5, 7.5, 10, 12.5, 15], "thresholds": list(np.linspace(2.5, 15, 26)),
     "slopes": [0.3, 0.6, 1.2, 2.4], "lapses": [0.0, 0.02, 0.04], "prior_mean": 0.0, "prior_sd": 0.0,
     "observer": {"threshold": 8.0, "slope": 1.0, "lapse": 0.02}, "observer_seed": 11, "trials": 30},
    {"name": "weibull_rising_2afc_better", "shape": "weibull", "rising": True, "guess": 0.5,
     "levels": [1, 2, 4, 8, 16, 32, 64], "thresholds": list(np.geomspace(1, 64, 19)),
     "slopes": [1.0, 2.0, 3.5], "lapses": [0.0, 0.03], "prior_mean": 0.0, "prior_sd": 0.0,
     "observer": {"threshold": 10.0, "slope": 2.0, "lapse": 0.01}, "observer_seed": 5, "trials": 25},
    {"name": "normal_rising_prior_pair", "shape": "cumulative_normal", "rising": True, "guess": 0.1,
     "levels": list(np.linspace(0, 1, 11)), "thresholds": list(np.linspace(0, 1, 21)),
     "slopes": [2.0, 5.0, 10.0], "lapses": [0.02], "prior_mean": 0.4, "prior_sd": 0.2,
     "observer": {"threshold": 0.55, "slope": 6.0, "lapse": 0.02}, "observer_seed": 3, "trials": 20},
]

if __name__ == "__main__":
    print(json.dumps({"made_by": "tests/study/schedule/make_quest_plus_reference.py",
                      "numpy": np.__version__, "cases": [run(case) for case in CASES]}, indent=1))
