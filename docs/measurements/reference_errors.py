#!/usr/bin/env python3
"""Errors of `lgsvi simulate` against cases/data/se3_forced_refs.json (FJ1, F1, O1) at every
reference time t <= 10, for a few (chart, h, n), with the wall time of the integration.

Run from the repository root after `cargo build --release`:
    python3 docs/measurements/reference_errors.py
"""
import json
import subprocess

REFS = json.load(open("cases/data/se3_forced_refs.json"))["cases"]
LGSVI = "./target/release/lgsvi"

CASES = {
    "FJ1": ["--inertia-tensor", "3.0,0.4,-0.2,0.4,2.6,0.3,-0.2,0.3,3.3", "--omega0", "-2.0,1.9,-1.0"],
    "F1": ["--inertia", "3.3,2.5,3.4", "--omega0", "-2.0,1.9,-1.0", "--torque", "0.1,-0.2,0.05"],
    "O1": ["--system", "orbiting-body"],
}
KEYS = {"R": "R", "omega": "omega", "position": "position", "velocity": "velocity"}


def run(case, chart, h, n):
    args = [LGSVI, "simulate", "--quiet", "--chart", chart, "--h", str(h), "--nodes", str(n),
            "--t-end", "10"] + CASES[case]
    out = json.loads(subprocess.run(args, check=True, capture_output=True, text=True).stdout)
    times = out["times"]
    worst = {}
    for state in REFS[case]["states"]:
        t = float(state["t"])
        if t > 10:
            continue
        k = min(range(len(times)), key=lambda i: abs(times[i] - t))
        for key, ref in KEYS.items():
            if key not in out or ref not in state:
                continue
            err = max(abs(a - float(b)) for a, b in zip(out[key][k], state[ref]))
            worst[key] = max(worst.get(key, 0.0), err)
    if "work" in out and "work" in REFS[case]["states"][0]:
        for state in REFS[case]["states"]:
            t = float(state["t"])
            if t <= 10:
                k = min(range(len(times)), key=lambda i: abs(times[i] - t))
                worst["work"] = max(worst.get("work", 0.0), abs(out["work"][k] - float(state["work"])))
    return worst, out["stats"]["wall_time_s"]


print(f"{'case':5} {'chart':7} {'h':>5} {'n':>3}  {'max error (R, Ω, x, ẋ, W) at t ≤ 10':60} {'time (s)':>9}")
for case in ["FJ1", "F1", "O1"]:
    charts = ["exp", "cayley"]
    for chart in charts:
        for h, n in [(0.5, 8), (0.5, 12), (0.25, 12)]:
            worst, wall = run(case, chart, h, n)
            text = ", ".join(f"{k} {v:.1e}" for k, v in worst.items())
            print(f"{case:5} {chart:7} {h:5} {n:3}  {text:60} {wall:9.4f}")
