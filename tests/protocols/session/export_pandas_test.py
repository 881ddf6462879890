#!/usr/bin/python3
"""trials.csv and steps.csv load cleanly in pandas (issue 18), with the types an analyst expects.

Usage (CTest: ExportCsvLoadsInPandas): export_pandas_test.py FOVLAB SOURCE_DIR SCRATCH_DIR
Runs one simulated session of the tiny 2afc, ramp and slider fixtures, exports each, and reads the
files with pandas.read_csv and no options: numbers must come out numeric, flags boolean, and every
column the docs list must be there. Exit 77 (skipped) when Debian's python3-pandas is missing.
"""
import os
import shutil
import subprocess
import sys

try:
    import pandas as pd
    from pandas.api import types
except ImportError:
    print("skipped: python3-pandas is not installed (scripts/setup installs it)")
    sys.exit(77)

fovlab, source, scratch = sys.argv[1:4]
shutil.rmtree(scratch, ignore_errors=True)
os.makedirs(scratch)
results = os.path.join(scratch, "results")
failures = []


def check(condition, message):
    if not condition:
        failures.append(message)


for fixture, study in (("tiny_2afc", "tiny_2afc"), ("ramp", "tiny_ramp"), ("slider", "tiny_slider")):
    config = os.path.join(source, "tests", "fixtures", "studies", fixture + ".toml")
    subprocess.run([fovlab, "run", config, "--participant", "P1", "--headless", "--observer", "simulated",
                    "--results", results], check=True, stdout=subprocess.DEVNULL)
    folder = os.path.join(results, study)
    subprocess.run([fovlab, "export", folder], check=True, stdout=subprocess.DEVNULL)

    trials = pd.read_csv(os.path.join(folder, "trials.csv"))
    check(len(trials) > 0, f"{study}: no rows")
    for column in ("trial", "block", "dropped_frames", "repeat"):
        check(types.is_integer_dtype(trials[column]), f"{study}: trials.{column} is {trials[column].dtype}, not integer")
    for column in ("onset_s", "end_s"):
        check(types.is_float_dtype(trials[column]), f"{study}: trials.{column} is {trials[column].dtype}, not float")
    check(types.is_numeric_dtype(trials["refresh_hz"]), f"{study}: trials.refresh_hz is {trials['refresh_hz'].dtype}")
    for column in ("attention_check", "excluded"):
        check(types.is_bool_dtype(trials[column]), f"{study}: trials.{column} is {trials[column].dtype}, not bool")
    for column in ("key", "correct", "level_parameter", "session_started_utc", "fovlab_version", "config_hash"):
        check(column in trials.columns, f"{study}: trials.csv lacks {column}")
    check((trials["level_parameter"] == "max_steps").all(), f"{study}: level_parameter is not max_steps")
    # The last column: a headset's late frames, empty (NaN) for these desktop sessions.
    check(trials.columns[-1] == "late_frames", f"{study}: the last column is {trials.columns[-1]}, not late_frames")
    check(trials["late_frames"].isna().all(), f"{study}: a desktop session has late_frames")
    check(pd.to_datetime(trials["session_started_utc"], utc=True).notna().all(), f"{study}: start times do not parse")
    if study == "tiny_2afc":
        check(types.is_float_dtype(trials["level"]), f"{study}: level is {trials['level'].dtype}")
        check(types.is_float_dtype(trials["rt_s"]), f"{study}: rt_s is {trials['rt_s'].dtype}")
        # repeat counts the earlier trials of the same condition: 0, 1, ... within each block.
        comparisons = trials[~trials["attention_check"]]
        check(comparisons.groupby(["block", "condition"])["repeat"].apply(lambda r: list(r) == list(range(len(r)))).all(),
              f"{study}: repeat is not 0, 1, ... per condition")

    steps_path = os.path.join(folder, "steps.csv")
    check(os.path.exists(steps_path) == (study != "tiny_2afc"), f"{study}: steps.csv {'missing' if study != 'tiny_2afc' else 'written'}")
    if study != "tiny_2afc" and os.path.exists(steps_path):
        steps = pd.read_csv(steps_path)
        check(len(steps) > 0, f"{study}: steps.csv has no rows")
        for column in ("trial", "step"):
            check(types.is_integer_dtype(steps[column]), f"{study}: steps.{column} is {steps[column].dtype}")
        for column in ("level", "rt_s"):
            check(types.is_numeric_dtype(steps[column]), f"{study}: steps.{column} is {steps[column].dtype}")
        if study == "tiny_ramp":
            check(types.is_bool_dtype(steps["correct"]), f"{study}: steps.correct is {steps['correct'].dtype}")
            # Every ramp step is a row: the answers of trials.csv, split.
            per_trial = steps.groupby("trial")["answer"].apply(";".join)
            check(list(per_trial) == list(trials.set_index("trial").loc[per_trial.index, "answers"]),
                  f"{study}: steps.csv's answers differ from trials.csv's")
        else:
            check((steps.groupby("trial")["answer"].last() == "save").all(), f"{study}: a slider trial does not end saved")

for failure in failures:
    print("FAIL:", failure)
print(f"{len(failures)} failure(s)")
sys.exit(1 if failures else 0)
