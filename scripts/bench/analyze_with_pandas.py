#!/usr/bin/python3
"""What `fovlab analyze` does for a 2AFC same/different study, written the way an analyst would
with pandas + SciPy, so that the two can be timed against each other (scripts/bench-analysis).

    /usr/bin/python3 scripts/bench/analyze_with_pandas.py RESULTS_DIR|LOG... [--out DIR]
        [--bootstrap 1000] [--seed 1] [--alternative two-sided|greater|less] [--alpha 0.05]
        [--guess-rate G] [--max-lapse 0.1]

Run it with /usr/bin/python3 (Debian 12: pandas 1.5.3, SciPy 1.10.1, NumPy 1.24.2, Python 3.11
for tomllib); the pyenv `python3` on PATH has none of them.

It follows /tmp/fovlab-docs/thresholds.md, statistics.md and psychometric.md (in the repo:
analysis/study/, analysis/statistics/, analysis/fitting/):

- every events.jsonl under the folders given (and the logs given), in sorted path order, each read
  whole with `pd.read_json(path, lines=True)`, then concatenated;
- NOT checked: the hash chain (`chain`: FNV-1a-64 over the previous chain and each event's
  canonical JSON text). Recomputing it needs the exact text of each line minus one member and a
  64-bit FNV loop over every byte in Python -- not cheap in pandas, so it is skipped. fovlab does
  check it (an edited or damaged log is left out there and would be counted here);
- the study analysed is the (study, config_hash) most logs belong to; duplicate participant IDs:
  the first log in path order; a torn last line (no newline at the end) is not read;
- complete trials: trial_start .. trial_end; a `session_resumed` drops an open trial; the answer
  of a trial is its last response; a trial index completed twice keeps the later one;
- groups: the block name (from block_start) and the variant, plus scene "all" when the included
  participants saw more than one scene; participants with an `excluded` event and attention-check
  trials are not counted (the checks only set the fits' guess rate);
- per group and condition: n, k (answers "same"), k/n, exact binomial p (scipy.stats.binomtest),
  Clopper-Pearson 95 % (binomtest(...).proportion_ci(method="exact")), Holm across the group;
- the threshold walk from the best level down; psychometric fits (logistic, Weibull, cumulative
  normal; guess fixed; lapse in [0, 0.1]) by maximum likelihood with scipy.optimize, and a
  parametric bootstrap with numpy's default_rng (its replicates are not fovlab's Pcg32 ones, so
  the intervals differ from fovlab's by sampling).

Writes to --out: conditions.csv (fovlab's columns and number format), thresholds.csv and fits.csv
(this script's own small layouts). Prints the timings of its phases.
"""
import time

T_START = time.perf_counter()

import argparse
import csv
import io
import math
import os
import sys
import tomllib
import zlib

import numpy as np
import pandas as pd
from scipy import optimize, special, stats

T_IMPORTED = time.perf_counter()

# Columns of the events this analysis uses; everything else of a log (stimulus events with their
# per-refresh gaze and hashes, the header's stimuli, ...) is dropped right after reading.
EVENT_COLUMNS = ["event", "trial", "block", "name", "scene", "condition", "variant", "level", "attention_check",
                 "answer", "practice"]
KEPT_EVENTS = ["block_start", "trial_start", "response", "trial_end", "session_resumed", "excluded", "session_end"]
SHAPES = ["logistic", "weibull", "cumulative_normal"]


# ------------------------------------------------------------------------------------------------
# Reading

def find_logs(inputs):
    logs = set()
    for item in inputs:
        if os.path.isfile(item):
            logs.add(item)
            continue
        if not os.path.isdir(item):
            sys.exit(f"analyze_with_pandas: {item}: no such log file or results folder")
        for folder, _, files in os.walk(item):
            if "events.jsonl" in files:
                logs.add(os.path.join(folder, "events.jsonl"))
    return sorted(logs)


def read_log(path):
    """One log as a DataFrame; a last line without its newline (torn by a crash) is not read."""
    with open(path, "rb") as f:
        f.seek(0, os.SEEK_END)
        size = f.tell()
        torn = False
        if size > 0:
            f.seek(-1, os.SEEK_END)
            torn = f.read(1) != b"\n"
    if not torn:
        return pd.read_json(path, lines=True, dtype=False, convert_dates=False), False
    with open(path, "rb") as f:
        data = f.read()
    intact = data[: data.rfind(b"\n") + 1].decode("utf-8")
    return pd.read_json(io.StringIO(intact), lines=True, dtype=False, convert_dates=False), True


def study_of(header):
    config = tomllib.loads(header["config_toml"])
    if "conditions" in config:
        sys.exit("analyze_with_pandas.py: a study with a [conditions] file is not supported by this cross-check")
    protocol = config.get("protocol", {})
    levels = config.get("levels", {})
    return {
        "study": header["study"],
        "config_hash": header["config_hash"],
        "protocol": protocol.get("kind", ""),
        "question": protocol.get("question", "same") if protocol.get("kind") == "2afc" else "",
        "level_parameter": levels.get("parameter", ""),
        "levels": [float(v) for v in levels.get("values", [])],
        "higher_is_better": bool(levels.get("higher_is_better", True)),
    }


def read_study(inputs):
    paths = find_logs(inputs)
    if not paths:
        sys.exit("analyze_with_pandas: no events.jsonl to analyse")
    left_out = []
    logs = []  # (path, study, participant, slim events)
    for path in paths:
        try:
            df, torn = read_log(path)
        except ValueError as error:
            left_out.append((path, f"not JSON lines ({error})"))
            continue
        if df.empty or df["event"].iloc[0] != "session_header":
            left_out.append((path, "the first line is not a session_header"))
            continue
        header = df.iloc[0]
        if torn:
            left_out.append((path, "the last line is cut off: not read"))
        events = df.loc[df["event"].isin(KEPT_EVENTS)].reindex(columns=EVENT_COLUMNS)
        logs.append((path, study_of(header), header["participant"], events))
    if not logs:
        sys.exit("analyze_with_pandas: no log could be read")

    # The study (and config version) most logs belong to; ties: the first in path order.
    counts = {}
    chosen = None
    for _, study, _, _ in logs:
        key = (study["study"], study["config_hash"])
        counts[key] = counts.get(key, 0) + 1
        if chosen is None or counts[key] > counts[chosen]:
            chosen = key
    frames, participants, seen = [], [], {}
    study = None
    for path, log_study, participant, events in logs:
        key = (log_study["study"], log_study["config_hash"])
        if key != chosen:
            left_out.append((path, f"study {key}, not {chosen}"))
            continue
        if participant in seen:
            left_out.append((path, f"participant {participant} is also in {seen[participant]} (duplicate)"))
            continue
        seen[participant] = path
        study = study or log_study
        frames.append(events.assign(participant=participant))
        participants.append(participant)
    events = pd.concat(frames, ignore_index=True)
    return study, events, participants, paths, left_out


# ------------------------------------------------------------------------------------------------
# Trials

def assemble_trials(events):
    """Complete trials, one row each: participant, trial, scene, variant, condition, level,
    attention_check, answer (NaN: no response); and the set of excluded participants."""
    kind = events["event"]
    is_start = kind.eq("trial_start")
    # An attempt runs from a trial_start to the next trial_start or session_resumed (which drops a
    # trial a crash cut off). The logs are concatenated in file order and each begins with its
    # header, so a running count over all of them separates the logs too.
    attempt = (is_start | kind.eq("session_resumed")).cumsum()
    events = events.assign(attempt=attempt)
    starts = events.loc[is_start, ["participant", "attempt", "trial", "block", "condition", "variant", "level",
                                   "attention_check", "practice"]]
    ends = events.loc[kind.eq("trial_end"), ["attempt", "trial"]]
    starts = starts.merge(ends, on=["attempt", "trial"], how="inner")  # complete attempts only
    answers = events.loc[kind.eq("response")].groupby("attempt")["answer"].last()
    trials = starts.join(answers, on="attempt")
    trials = trials.drop_duplicates(["participant", "trial"], keep="last")
    # Practice trials ("practice": true on their trial_start) are never analysed.
    trials = trials.loc[~trials["practice"].fillna(False).astype(bool)].drop(columns="practice")

    blocks = events.loc[kind.eq("block_start"), ["participant", "block", "name", "scene"]].copy()
    blocks["scene"] = blocks["name"].where(blocks["name"].fillna("") != "", blocks["scene"])
    blocks = blocks.drop_duplicates(["participant", "block"], keep="last")[["participant", "block", "scene"]]
    trials["block"] = trials["block"].fillna(0).astype("int64")
    blocks["block"] = blocks["block"].fillna(0).astype("int64")
    trials = trials.merge(blocks, on=["participant", "block"], how="left")
    trials["variant"] = trials["variant"].fillna("")
    trials["attention_check"] = trials["attention_check"].fillna(False).astype(bool)
    excluded = set(events.loc[kind.eq("excluded"), "participant"])
    return trials, excluded


def guess_rate_of(trials, study, args):
    if args.guess_rate is not None:
        return args.guess_rate, "--guess-rate"
    if study["protocol"] == "2afc" and study["question"] == "better":
        return 0.5, "2afc forced choice: chance is 1/2"
    checks = trials.loc[trials["attention_check"] & trials["answer"].notna() & trials["answer"].ne("")]
    if checks.empty:
        return 0.0, "no attention checks: 0"
    false_alarms = int(checks["answer"].ne("same").sum())
    return false_alarms / len(checks), f"attention checks: {false_alarms} of {len(checks)} not judged identical"


# ------------------------------------------------------------------------------------------------
# Tests

def holm(p):
    p = np.asarray(p, dtype=float)
    order = np.argsort(p, kind="stable")
    m = len(p)
    adjusted = np.maximum.accumulate(np.minimum(1.0, (m - np.arange(m)) * p[order]))
    out = np.empty(m)
    out[order] = adjusted
    return out


def stars(p):
    return "***" if p < 0.001 else "**" if p < 0.01 else "*" if p < 0.05 else ""


def condition_table(trials, study, args):
    answered = trials.loc[~trials["attention_check"] & trials["answer"].notna()]
    counted = answered.loc[answered["answer"].isin(["same", "different"])]
    unanswered = len(answered) - len(counted)
    counted = counted.assign(k=counted["answer"].eq("same").astype("int64"))
    pool = trials["scene"].nunique() > 1
    parts = [counted]
    if pool:
        parts.append(counted.assign(scene="all"))
    table = (pd.concat(parts, ignore_index=True)
             .groupby(["scene", "variant", "condition"], sort=False)
             .agg(level=("level", "last"), n=("k", "size"), k=("k", "sum"))
             .reset_index())
    # fovlab's order: groups by (scene, variant), then level (none first), then condition.
    table["has_level"] = table["level"].notna()
    table = table.sort_values(["scene", "variant", "has_level", "level", "condition"], kind="stable",
                              na_position="first").reset_index(drop=True)
    table["proportion"] = table["k"] / table["n"]
    p_values, lower, upper = [], [], []
    for n, k in zip(table["n"], table["k"]):
        p_values.append(stats.binomtest(int(k), int(n), 0.5, alternative=args.alternative).pvalue)
        ci = stats.binomtest(int(k), int(n), 0.5).proportion_ci(confidence_level=0.95, method="exact")
        lower.append(ci.low)
        upper.append(ci.high)
    table["ci_lower"], table["ci_upper"] = lower, upper
    table["p_value"] = np.clip(p_values, 0.0, 1.0)
    table["p_holm"] = table.groupby(["scene", "variant"], sort=False)["p_value"].transform(holm)
    table["stars"] = table["p_value"].map(stars)
    return table, unanswered


def thresholds_of(table, study, args):
    rows = []
    for (scene, variant), group in table.loc[table["has_level"]].groupby(["scene", "variant"], sort=False):
        group = group.drop_duplicates("level", keep="last").sort_values("level",
                                                                        ascending=not study["higher_is_better"])
        threshold, note = None, ""
        for level, proportion, p_holm in zip(group["level"], group["proportion"], group["p_holm"]):
            if proportion < 0.5 and p_holm < args.alpha:  # distinguished from the reference
                if threshold is None:
                    note = f"even the best level tested ({level:g}) fails the criterion"
                break
            threshold = level
        else:
            note = "every level tested passes: the threshold is at or below the most degraded level"
        rows.append({"scene": scene, "variant": variant, "threshold": threshold, "note": note})
    return rows


# ------------------------------------------------------------------------------------------------
# Psychometric fits

CLAMP = 1e-12
LN2 = math.log(2.0)


class Fit:
    """One shape on one group's data: p_report = guess + (1 - guess - lapse) p_see(level), the
    parameters (threshold, slope, lapse) searched as (z0, z1, lapse): z0 = (threshold on the level
    axis - centre) / range (Weibull: log level axis), z1 = log(slope * range), lapse in
    [0, max_lapse] -- the same box as fovlab's."""

    def __init__(self, shape, levels, n, rising, guess, max_lapse):
        self.shape, self.rising, self.guess, self.max_lapse = shape, rising, guess, max_lapse
        self.levels = np.asarray(levels, dtype=float)
        self.n = np.asarray(n, dtype=float)
        axis = np.log(self.levels) if shape == "weibull" else self.levels
        self.axis = axis
        self.centre = 0.5 * (axis.min() + axis.max())
        self.range = axis.max() - axis.min()
        self.bounds = [(-10.5, 10.5), (math.log(1e-3), math.log(1e4)), (0.0, max_lapse)]

    def natural(self, z):
        t_axis = self.centre + self.range * z[0]
        threshold = math.exp(t_axis) if self.shape == "weibull" else t_axis
        return threshold, math.exp(z[1]) / self.range, z[2]

    def report(self, z):
        """p_report and 1 - p_report at every level, each without cancellation."""
        slope = math.exp(z[1]) / self.range
        t_axis = self.centre + self.range * z[0]
        sign = 1.0 if self.rising else -1.0
        if self.shape == "weibull":
            with np.errstate(over="ignore"):  # a huge ratio gives w = inf, exp(-w) = 0: no NaN
                w = LN2 * np.exp(slope * (self.axis - t_axis))
            see, not_see = -np.expm1(-w), np.exp(-w)
            if not self.rising:
                see, not_see = not_see, see
        else:
            x = sign * slope * (self.axis - t_axis)
            if self.shape == "logistic":
                see, not_see = special.expit(x), special.expit(-x)
            else:
                see, not_see = special.ndtr(x), special.ndtr(-x)
        lapse = z[2]
        gain = 1.0 - self.guess - lapse
        return self.guess + gain * see, lapse + gain * not_see

    def nll(self, z, k):
        p, q = self.report(z)
        return -(k @ np.log(np.clip(p, CLAMP, 1 - CLAMP)) + (self.n - k) @ np.log(np.clip(q, CLAMP, 1 - CLAMP)))

    def saturated(self, k):
        rest = self.n - k
        return float(np.sum(special.xlogy(k, k / self.n) + special.xlogy(rest, rest / self.n)))

    def minimise(self, k, starts):
        """L-BFGS-B from each start, the best kept; a replicate that did not converge is None."""
        best = None
        for start in starts:
            result = optimize.minimize(self.nll, start, args=(k,), method="L-BFGS-B", bounds=self.bounds,
                                       options={"ftol": 1e-15, "gtol": 1e-10, "maxiter": 2000})
            # L-BFGS-B often ends with "ABNORMAL_TERMINATION_IN_LNSRCH" at an optimum it cannot
            # improve in floating point; count that as converged when the gradient is small.
            ok = result.success or (result.status == 2 and np.max(np.abs(result.jac)) < 1e-3)
            if ok and (best is None or result.fun < best.fun):
                best = result
        return best


def fit_group(levels, n, k_report, shape, rising, guess, max_lapse, bootstrap, rng):
    fit = Fit(shape, levels, n, rising, guess, max_lapse)
    k = np.asarray(k_report, dtype=float)
    starts = [(t, math.log(s), lapse) for t in (-0.4, -0.2, 0.0, 0.2, 0.4) for s in (1.5, 6.0, 24.0)
              for lapse in (0.047 * max_lapse, 0.73 * max_lapse)]
    best = fit.minimise(k, starts)
    out = {"shape": shape, "rising": rising, "guess": guess, "converged": best is not None}
    if best is None:
        return out
    log_coefficients = float(np.sum(special.gammaln(fit.n + 1) - special.gammaln(k + 1) - special.gammaln(fit.n - k + 1)))
    out["threshold"], out["slope"], out["lapse"] = fit.natural(best.x)
    out["log_likelihood"] = -best.fun + log_coefficients
    out["deviance"] = max(0.0, 2.0 * (fit.saturated(k) + best.fun))
    out["dof"] = len(levels) - 3
    if bootstrap > 0:
        p_report, _ = fit.report(best.x)
        near = [best.x, (best.x[0], best.x[1], 0.047 * max_lapse), (best.x[0], best.x[1], 0.73 * max_lapse)]
        samples, failures = [], 0
        for _ in range(bootstrap):
            k_star = rng.binomial(fit.n.astype(np.int64), p_report).astype(float)
            replicate = fit.minimise(k_star, near)
            if replicate is None:
                failures += 1
                continue
            deviance = max(0.0, 2.0 * (fit.saturated(k_star) + replicate.fun))
            samples.append((*fit.natural(replicate.x), deviance))
        out["bootstrap_samples"], out["bootstrap_failures"] = len(samples), failures
        if samples:
            values = np.array(samples)
            for i, name in enumerate(["threshold", "slope", "lapse"]):
                out[name + "_lower"], out[name + "_upper"] = np.percentile(values[:, i], [2.5, 97.5])
            out["deviance_p_value"] = float(np.mean(values[:, 3] >= out["deviance"]))
    return out


def fits_of(table, study, guess, args):
    fits = []
    for (scene, variant), group in table.loc[table["has_level"]].groupby(["scene", "variant"], sort=False):
        group = group.sort_values("level")
        if group["level"].nunique() < 2:
            continue
        for shape in SHAPES:
            if shape == "weibull" and not (group["level"] > 0).all():
                continue
            group_name = scene if not variant else f"{scene}/{variant}"
            rng = np.random.default_rng([args.seed, zlib.crc32(group_name.encode()), SHAPES.index(shape)])
            fit = fit_group(group["level"].to_numpy(), group["n"].to_numpy(), (group["n"] - group["k"]).to_numpy(),
                            shape, not study["higher_is_better"], guess, args.max_lapse, args.bootstrap, rng)
            fits.append({"scene": scene, "variant": variant, **fit})
    return fits


# ------------------------------------------------------------------------------------------------
# Output

def cell(value):
    if value is None:
        return ""
    if isinstance(value, (bool, np.bool_)):
        return "true" if value else "false"
    if isinstance(value, (int, np.integer)):
        return str(int(value))
    if isinstance(value, (float, np.floating)):
        return "%.10g" % value if math.isfinite(value) else ""
    return str(value)


def write_csv(path, columns, rows):
    with open(path, "w", newline="", encoding="utf-8") as f:
        writer = csv.writer(f, lineterminator="\n")
        writer.writerow(columns)
        for row in rows:
            writer.writerow([cell(row.get(column)) for column in columns])


CONDITION_COLUMNS = ["study", "protocol", "scene", "variant", "condition", "level", "n", "k", "proportion", "ci_lower",
                     "ci_upper", "p_value", "p_holm", "stars", "alternative", "mean_rating", "sd_rating"]
FIT_COLUMNS = ["scene", "variant", "shape", "rising", "threshold", "slope", "lapse", "guess", "threshold_lower",
               "threshold_upper", "slope_lower", "slope_upper", "lapse_lower", "lapse_upper", "deviance", "dof",
               "deviance_p_value", "log_likelihood", "converged", "bootstrap_samples", "bootstrap_failures"]


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("inputs", nargs="+", metavar="RESULTS_DIR|LOG")
    parser.add_argument("--out", default="analysis-pandas")
    parser.add_argument("--bootstrap", type=int, default=1000)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--alternative", choices=["two-sided", "greater", "less"], default="two-sided")
    parser.add_argument("--alpha", type=float, default=0.05)
    parser.add_argument("--guess-rate", type=float, default=None)
    parser.add_argument("--max-lapse", type=float, default=0.1)
    args = parser.parse_args()

    t0 = time.perf_counter()
    study, events, participants, paths, left_out = read_study(args.inputs)
    t_read = time.perf_counter()
    if not (study["protocol"] == "2afc" and study["question"] == "same"):
        sys.exit(f"analyze_with_pandas: only 2afc same/different studies (this is {study['protocol']} "
                 f"{study['question']})")
    trials, excluded = assemble_trials(events)
    included = trials.loc[~trials["participant"].isin(excluded)]
    guess, guess_source = guess_rate_of(included, study, args)
    t_assemble = time.perf_counter()
    table, unanswered = condition_table(included, study, args)
    thresholds = thresholds_of(table, study, args)
    t_tests = time.perf_counter()
    fits = fits_of(table, study, guess, args)
    t_fits = time.perf_counter()

    os.makedirs(args.out, exist_ok=True)
    rows = table.assign(study=study["study"], protocol=study["protocol"], alternative=args.alternative)
    rows = [{key: (None if isinstance(value, float) and math.isnan(value) else value) for key, value in row.items()}
            for row in rows.to_dict("records")]
    write_csv(os.path.join(args.out, "conditions.csv"), CONDITION_COLUMNS, rows)
    write_csv(os.path.join(args.out, "thresholds.csv"), ["scene", "variant", "threshold", "note"], thresholds)
    write_csv(os.path.join(args.out, "fits.csv"), FIT_COLUMNS, fits)
    t_write = time.perf_counter()

    print(f"Study {study['study']} (2afc same): {len(participants)} participant(s), {len(excluded)} excluded; "
          f"{len(paths)} log(s), {len(events):,} events kept, {len(included):,} complete trials; "
          f"guess rate {guess:.4g} ({guess_source})")
    for what, reason in left_out:
        print(f"  left out: {what}: {reason}")
    if unanswered:
        print(f"  left out: {unanswered} trial(s) without an answer of this protocol")
    for row in thresholds:
        print(f"  threshold {row['scene'] or '-':<12} {cell(row['threshold']) or 'none'}  {row['note']}")
    for fit in fits:
        if fit.get("threshold") is None:
            print(f"  fit {fit['scene']:<12} {fit['shape']:<18} did not converge")
            continue
        interval = (f" [{fit['threshold_lower']:.5g}, {fit['threshold_upper']:.5g}]"
                    if "threshold_lower" in fit else "")
        failures = f" ({fit['bootstrap_failures']} bootstrap failures)" if fit.get("bootstrap_failures") else ""
        print(f"  fit {fit['scene']:<12} {fit['shape']:<18} threshold {fit['threshold']:.5g}{interval}{failures}")
    print(f"wrote conditions.csv, thresholds.csv, fits.csv to {args.out}")
    print(f"timing: imports {T_IMPORTED - T_START:.2f} s, read {t_read - t0:.2f} s, assemble {t_assemble - t_read:.2f} s, "
          f"tests {t_tests - t_assemble:.3f} s, fits {t_fits - t_tests:.2f} s, write {t_write - t_fits:.3f} s; "
          f"total {t_write - T_START:.2f} s")


if __name__ == "__main__":
    main()
