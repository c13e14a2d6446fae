#!/usr/bin/env python3
"""Estimate against truth for `lgsvi simulate --tol`, checked (the default) and `--no-check`,
on a wide set of motions: the reference free body, fast spins, a spin near the separatrix,
a full inertia tensor, a torqued body, stiff and mild damping, the heavy top and the
unstable top, a gyrostat with spinning wheels, a free body in space and the orbiting body
(T = 10 and T = 100).

The truth is the largest entry of the difference in R, Omega (and x, xdot) at the end
against a reference that does not come from the run measured:
  - `--exact` (Jacobi elliptic functions) for free bodies with a diagonal inertia;
  - cases/data/se3_forced_refs.json (Taylor and extrapolation in 45-digit arithmetic) for
    FJ1, F1 and O1;
  - otherwise two fixed runs far finer than any --tol run (h = T/400 and T/800, 16 nodes);
    their difference is printed beside each case and is below 1e-14 on every case.

Writes a markdown table to stdout and the scatter to docs/samples/check_estimate_vs_truth.{png,svg}.
Run from the repository root after `cargo build --release` (needs numpy and matplotlib):
    python3 docs/measurements/check_scatter.py
"""
import json
import subprocess
import sys

import numpy as np

LGSVI = "./target/release/lgsvi"
REFS = json.load(open("cases/data/se3_forced_refs.json"))["cases"]
TOLS = [1e-6, 1e-8, 1e-10, 1e-12]

# name, flags, horizon, reference kind ("exact", a reference case name, or "fine")
CASES = [
    ("A, paper's free body", [], 10, "exact"),
    ("fast spin, intermediate axis", ["--omega0", "20,0.1,0.1"], 10, "exact"),
    ("fast spin, major axis", ["--omega0", "0.1,0.1,20"], 10, "exact"),
    ("near the separatrix", ["--omega0", "2,0.01,0.01"], 10, "exact"),
    ("FJ1, full inertia tensor", ["--inertia-tensor", "3.0,0.4,-0.2,0.4,2.6,0.3,-0.2,0.3,3.3",
                                  "--omega0", "-2.0,1.9,-1.0"], 10, "FJ1"),
    ("F1, constant torque", ["--inertia", "3.3,2.5,3.4", "--omega0", "-2.0,1.9,-1.0",
                             "--torque", "0.1,-0.2,0.05"], 10, "F1"),
    ("damping 0.5", ["--damping", "0.5"], 10, "fine"),
    ("damping 20 (stiff)", ["--damping", "20"], 2, "fine"),
    ("B, heavy top", ["--system", "heavy-top"], 10, "fine"),
    ("unstable top", ["--system", "heavy-top", "--attitude0", "-1,0,0,0,1,0,0,0,-1",
                      "--omega0", "1e-3,0,0"], 10, "fine"),
    ("gyrostat, wheels spinning", ["--system", "gyrostat", "--wheel-speeds0", "5,0,-3"], 10, "fine"),
    ("free body in space", ["--system", "se3-body", "--velocity0", "0.1,-0.2,0.05"], 10, "fine"),
    ("O1, orbiting body, T = 10", ["--system", "orbiting-body"], 10, "O1"),
    ("O1, orbiting body, T = 100", ["--system", "orbiting-body"], 100, "O1"),
]


def simulate(flags, t_end, extra):
    args = [LGSVI, "simulate", "--quiet", "--t-end", str(t_end)] + flags + extra
    done = subprocess.run(args, capture_output=True, text=True)
    if done.returncode != 0:
        return None, done.stderr.strip()
    return json.loads(done.stdout), None


def end_state(out):
    v = list(np.ravel(out["R"][-1])) + list(out["omega"][-1])
    for key in ("position", "velocity"):
        if key in out:
            v += list(out[key][-1])
    return np.array(v)


def reference(flags, t_end, kind):
    if kind == "exact":
        out, err = simulate(flags, t_end, ["--exact", "--h", str(t_end / 10)])
        return end_state(out), 0.0
    if kind == "fine":
        a, _ = simulate(flags, t_end, ["--h", str(t_end / 400), "--nodes", "16", "--every", "400"])
        b, _ = simulate(flags, t_end, ["--h", str(t_end / 800), "--nodes", "16", "--every", "800"])
        return end_state(b), float(np.abs(end_state(a) - end_state(b)).max())
    state = next(s for s in REFS[kind]["states"] if float(s["t"]) == t_end)
    v = [float(x) for x in state["R"]] + [float(x) for x in state["omega"]]
    for key in ("position", "velocity"):
        if key in state:
            v += [float(x) for x in state[key]]
    return np.array(v), 0.0


def main():
    rows = []
    print("| case | T | ref. self-diff | tol | checked: truth | estimate | est/truth | runs | "
          "time, ms | --no-check: truth | estimate | est/truth | time, ms |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    for name, flags, t_end, kind in CASES:
        ref, self_diff = reference(flags, t_end, kind)
        for tol in TOLS:
            cells = []
            for extra in ([], ["--no-check"]):
                out, err = simulate(flags, t_end, ["--tol", str(tol)] + extra)
                if out is None:
                    cells.append(("refused", err))
                    continue
                truth = float(np.abs(end_state(out) - ref).max())
                est = out["stats"]["estimated_error"]
                runs = out["stats"].get("check", {}).get("runs", "")
                cells.append((truth, est, runs, 1e3 * out["stats"]["wall_time_s"]))
                rows.append(dict(case=name, t_end=t_end, tol=tol, checked=not extra,
                                 truth=truth, estimate=est))

            def show(c, checked):
                if c[0] == "refused":
                    return "refused | | |" + (" |" if checked else "")
                truth, est, runs, ms = c
                ratio = est / truth if truth > 0 else float("inf")
                mid = f" {runs} |" if checked else ""
                return f"{truth:.1e} | {est:.1e} | {ratio:.2g} |{mid} {ms:.2f}"
            print(f"| {name} | {t_end} | {self_diff:.0e} | {tol:.0e} | {show(cells[0], True)} | "
                  f"{show(cells[1], False)} |")
            for c in cells:
                if c[0] == "refused":
                    print(f"<!-- {name} tol {tol:.0e}: {c[1]} -->", file=sys.stderr)
    json.dump(rows, open("target/check_scatter.json", "w"), indent=1)
    plot(rows)


def plot(rows):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(7, 6))
    lo, hi = 1e-17, 1e-2
    x = np.array([lo, hi])
    ax.fill_between(x, x / 10, x * 10, color="0.9", label="within 10× of the truth")
    ax.plot(x, x, color="0.5", lw=0.8)
    for checked, marker, color, label in [(False, "x", "tab:red", "--no-check: sum of local estimates"),
                                          (True, "o", "tab:blue", "checked (default): companion difference")]:
        pts = [(r["truth"], r["estimate"]) for r in rows if r["checked"] == checked]
        t, e = np.array(pts).T
        ax.scatter(np.clip(t, lo, hi), np.clip(e, lo, hi), marker=marker, s=22,
                   facecolors="none" if marker == "o" else color, edgecolors=color if marker == "o" else None,
                   color=color, label=label, zorder=3)
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlim(lo, hi)
    ax.set_ylim(lo, hi)
    ax.set_xlabel("true error at the end (max entry of R, Ω, x, ẋ)")
    ax.set_ylabel("the run's estimated_error")
    ax.set_title("lgsvi simulate --tol 1e-6 … 1e-12: estimate against truth\n"
                 f"{len(CASES)} motions (fast spins, unstable top, damping, gyrostat, SE(3), orbit)",
                 fontsize=10)
    ax.legend(loc="upper left", fontsize=8)
    ax.grid(True, which="major", color="0.85", lw=0.5)
    fig.tight_layout()
    for ext in ("png", "svg"):
        fig.savefig(f"docs/samples/check_estimate_vs_truth.{ext}", dpi=110)


if __name__ == "__main__":
    main()
