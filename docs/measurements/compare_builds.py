#!/usr/bin/env python3
"""How far two builds of lgsvi are apart on every reference case: the largest difference in
R, Omega (and x, xdot for SE(3)) over every recorded state of `lgsvi simulate` to T = 10,
for the settings the tests use and a few more. A change to the solver that keeps the
equations (a faster iteration, another linear solver) should move results at rounding
level only.

Run from the repository root, with the older build's binary saved elsewhere
(e.g. `git worktree add /tmp/old <commit> && (cd /tmp/old && cargo build --release)`):
    python3 docs/measurements/compare_builds.py /tmp/old/target/release/lgsvi ./target/release/lgsvi
"""
import json
import subprocess
import sys

CASES = {
    # The paper's free rigid body (case A) and heavy top (case B): the CLI's defaults.
    "A": [],
    "B": ["--system", "heavy-top"],
    # cases/data/se3_forced_refs.json: full tensor, constant torque, orbiting body.
    "FJ1": ["--inertia-tensor", "3.0,0.4,-0.2,0.4,2.6,0.3,-0.2,0.3,3.3", "--omega0", "-2.0,1.9,-1.0"],
    "F1": ["--inertia", "3.3,2.5,3.4", "--omega0", "-2.0,1.9,-1.0", "--torque", "0.1,-0.2,0.05"],
    "O1": ["--system", "orbiting-body"],
}
# (case, chart, h, n): the test settings and the bench's frontier.
RUNS = [
    ("A", "exp", 0.5, 8), ("A", "exp", 1.0, 12), ("A", "exp", 0.5, 16), ("A", "cayley", 0.25, 12),
    ("A", "cayley-unscaled", 0.5, 10),
    ("B", "exp", 0.5, 8), ("B", "exp", 1.0, 12), ("B", "cayley", 0.25, 12),
    ("FJ1", "exp", 0.25, 12), ("FJ1", "cayley", 0.25, 12),
    ("F1", "exp", 0.25, 12), ("F1", "cayley", 0.25, 12),
    ("O1", "exp", 0.5, 12), ("O1", "cayley", 0.5, 12),
]
KEYS = ["R", "omega", "position", "velocity"]


def run(binary, case, chart, h, n):
    args = [binary, "simulate", "--quiet", "--chart", chart, "--h", str(h), "--nodes", str(n),
            "--t-end", "10"] + CASES[case]
    return json.loads(subprocess.run(args, check=True, capture_output=True, text=True).stdout)


def main():
    old, new = sys.argv[1], sys.argv[2]
    worst_all = 0.0
    print("| case | chart, h, n | " + " | ".join(f"max Δ{k}" for k in KEYS) + " |")
    print("|---|---|" + "---|" * len(KEYS))
    for case, chart, h, n in RUNS:
        a, b = run(old, case, chart, h, n), run(new, case, chart, h, n)
        cells = []
        for key in KEYS:
            if key not in a or key not in b:
                cells.append("")
                continue
            d = max(abs(x - y) for sa, sb in zip(a[key], b[key]) for x, y in zip(sa, sb))
            worst_all = max(worst_all, d)
            cells.append(f"{d:.1e}")
        print(f"| {case} | {chart}, {h}, {n} | " + " | ".join(cells) + " |")
    print(f"\nlargest difference over every case and state: {worst_all:.1e}")


if __name__ == "__main__":
    main()
