#!/usr/bin/env python3
"""Instructions a step of every built-in system, counted by callgrind: the instructions
inside `Integrator::step` (`--toggle-collect`) over a run of `lgsvi simulate`, divided by
its steps. Callgrind counts instructions, not seconds, so the numbers repeat for the same
binary whatever else the machine does; two builds compare by their ratio.

Run from the repository root with one or two binaries (a second one is compared with the
first, e.g. a build of an older commit saved elsewhere):
    python3 docs/measurements/step_instructions.py ./target/release/lgsvi [/tmp/old/lgsvi]
"""
import subprocess
import sys
import tempfile

# (name, simulate's flags, h, n, steps): the systems bench's bodies at n = 8, h = 0.5, and
# the step bench's case A over n.
RUNS = [
    ("free body", [], 0.5, 8, 400),
    ("torque", ["--torque", "0.001,0.002,-0.001"], 0.5, 8, 400),
    ("damping", ["--damping", "0.01"], 0.5, 8, 400),
    ("heavy top", ["--system", "heavy-top"], 0.5, 8, 400),
    ("free body in space", ["--system", "se3-body", "--velocity0", "0.1,-0.2,0.05"], 0.5, 8, 80),
    ("orbiting body", ["--system", "orbiting-body"], 0.5, 8, 80),
    ("gyrostat, 3 wheels", ["--system", "gyrostat", "--wheel-speeds0", "1,2,-1"], 0.5, 8, 80),
    ("case A, n = 4", [], 0.5, 4, 400),
    ("case A, n = 12", [], 0.5, 12, 400),
    ("case A, n = 16", [], 0.5, 16, 200),
    ("case A, n = 24", [], 0.5, 24, 100),
    ("case A, h = 1, n = 10", [], 1.0, 10, 200),
]


def per_step(binary, flags, h, n, steps):
    with tempfile.NamedTemporaryFile(suffix=".cg") as out:
        command = ["valgrind", "--tool=callgrind", "--toggle-collect=*Integrator<*>::step",
                   f"--callgrind-out-file={out.name}", binary, "simulate", "--quiet",
                   "--h", str(h), "--nodes", str(n), "--t-end", str(h * steps)] + flags
        subprocess.run(command, check=True, capture_output=True)
        for line in open(out.name):
            if line.startswith("totals:"):
                return int(line.split()[1]) / steps
    raise RuntimeError("callgrind wrote no totals")


def main():
    binaries = sys.argv[1:3]
    header = "| system, h, n | " + " | ".join(binaries)
    if len(binaries) == 2:
        header += " | change"
    print(header + " |")
    print("|---" * (len(binaries) + 1 + (len(binaries) == 2)) + "|")
    for name, flags, h, n, steps in RUNS:
        counts = [per_step(b, flags, h, n, steps) for b in binaries]
        cells = [f"{c / 1e3:.1f}k" for c in counts]
        if len(counts) == 2:
            cells.append(f"{(counts[1] / counts[0] - 1) * 100:+.2f}%")
        print(f"| {name}, {h}, {n} | " + " | ".join(cells) + " |")


if __name__ == "__main__":
    main()
