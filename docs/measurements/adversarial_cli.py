"""An adversarial pass over `lgsvi simulate` and `lgsvi optimize`: every system, every
physical and numerical flag (and `--stop-when`, and each of optimize's flags over a
feasible slew), at values a user may type by mistake or on purpose (zero, negative, NaN, infinite,
tiny, huge, the wrong count, stiff, ill-conditioned, far from unit scale).

Each input is run once and classified:

- `panic`: the process panicked or was killed (never acceptable);
- `hang`: no answer within the time limit;
- `multi-line`: an error of more than one line;
- `unclear`: an error that names no flag (`--…`) and none of the causes in `CAUSES`;
- `refused`: a one-line error that names a flag or a cause;
- `ok`: exit 0. A fixed run that succeeded is run again with `--check` (its companion of
  two more nodes measures it): when the measured difference exceeds ten times the run's
  own estimate, and exceeds 1e-10, the run is `suspect` (a possibly silent wrong answer)
  unless its stderr warned.

Every `refused` and `suspect` line is printed with its message, to be read: the script
counts, a person judges whether each message names the cause and the input to change.

Run: `python3 docs/measurements/adversarial_cli.py [path/to/lgsvi]` (default
`target/release/lgsvi`; build it first with `cargo build --release -p lgsvi-cli`).
"""

import itertools
import json
import subprocess
import sys
import tempfile

LGSVI = sys.argv[1] if len(sys.argv) > 1 else "target/release/lgsvi"
TIMEOUT = 120

# Phrases that name a cause without a flag (library errors the CLI passes on).
CAUSES = [
    "ill-conditioned",
    "radius of gyration",
    "attracting",
    "chart's reach",
    "outside the domain",
    "Newton did not converge",
    "not finite",
    "tolerance",
    "--tol",
]

SYSTEMS = {
    "rigid-body": [],
    "heavy-top": ["--system", "heavy-top"],
    "se3-body": ["--system", "se3-body"],
    "orbiting-body": ["--system", "orbiting-body"],
    "gyrostat": [
        "--system",
        "gyrostat",
        "--wheel-axes",
        "1,0,0,0,1,0,0,0,1",
        "--wheel-inertia",
        "0.1,0.1,0.1",
    ],
}

NUMBERS = ["0", "-1", "nan", "inf", "-inf", "1e-300", "1e300", "1e-12", "1e12"]
VECTORS = ["0,0,0", "nan,0,0", "inf,1,1", "1e300,1e300,1e300", "1e-300,0,0", "1,2"]

# (flag, values, systems it applies to; None: all)
FLAGS = [
    ("--inertia", ["1,1,1", "0,1,1", "-1,2,2", "1,1,3", "1e-300,1e-300,1.5e-300",
                   "1e300,1e300,1.5e300", "1e-9,1,1", "1e-4,1,1", "nan,1,1", "1,1"], None),
    ("--inertia-tensor", ["1,0,0,0,1,0,0,0,1", "1,0.5,0,0,1,0,0,0,1",
                          "1,0,0,0,1,0,0,0,-1", "1,0,0,0,1,0,0,0,1e-300",
                          "1,0,0,0,0.5000000001,0.4999999999,0,0.4999999999,0.5000000001"], None),
    ("--omega0", VECTORS + ["100,0,0", "1e6,1e6,1e6"], None),
    ("--quaternion0", ["0,0,0,0", "1,nan,0,0", "2,0,0,0", "1e300,1e300,0,0"], None),
    ("--attitude0", ["1,0,0,0,1,0,0,0,1.0001", "-1,0,0,0,1,0,0,0,1"], None),
    ("--mass", NUMBERS, ["heavy-top", "se3-body", "orbiting-body"]),
    ("--mu", NUMBERS, ["orbiting-body"]),
    ("--position0", VECTORS + ["1e76,0,0", "7e6,0,0"], ["se3-body", "orbiting-body"]),
    ("--velocity0", VECTORS + ["0,1e8,0"], ["se3-body", "orbiting-body"]),
    ("--gravity", NUMBERS, ["heavy-top"]),
    ("--com", VECTORS, ["heavy-top"]),
    ("--gravity-direction", VECTORS, ["heavy-top"]),
    ("--torque", VECTORS + ["1e6,0,0"], ["rigid-body", "heavy-top", "se3-body", "orbiting-body"]),
    ("--damping", ["-1", "nan", "inf", "30", "300", "3000", "1e12"],
     ["rigid-body", "heavy-top", "se3-body", "orbiting-body"]),
    ("--wheel-inertia", ["0,0.1,0.1", "-0.1,0.1,0.1", "nan,0.1,0.1", "1e6,1e6,1e6", "0.1"],
     ["gyrostat"]),
    ("--wheel-axes", ["0,0,0,0,1,0,0,0,1", "1,0,0,1,0,0,0,0,1", "nan,0,0,0,1,0,0,0,1"],
     ["gyrostat"]),
    ("--wheel-speeds0", ["1e300,0,0", "nan,0,0", "1,2"], ["gyrostat"]),
    ("--wheel-torque", ["1e6,0,0", "nan,0,0"], ["gyrostat"]),
    ("--h", ["0", "-0.5", "nan", "1e-9", "7", "100"], None),
    ("--nodes", ["0", "1", "2", "101", "1000"], None),
    ("--quad", ["0", "1", "1000"], None),
    ("--tol", ["0", "-1", "nan", "1e-300", "1e-16", "1", "100"], None),
    ("--t-end", ["0", "-1", "nan", "1e12", "0.3"], None),
    ("--every", ["0", "1000000"], None),
    ("--stop-when", ["omega<0.1", "angle>90", "x_1<0", "r>1e300", "wheel_1>1", "omega_9<0",
                     "omega=0", "omega<nan", "omega<inf", "speed>-1"], None),
]

# `lgsvi optimize`: each flag at adversarial values over a feasible base slew.
OPTIMIZE_BASE = ["--attitude-final=0.5,0.2,0", "--t-end=10", "--steps=20"]
OPTIMIZE_FLAGS = [
    ("--inertia", ["1,1,1", "0,1,1", "-1,2,2", "1,1,3", "1e-300,1e-300,1e-300",
                   "1e300,1e300,1e300", "nan,1,1", "1,1"]),
    ("--attitude-final", ["0,0,0", "nan,0,0", "inf,0,0", "1e300,0,0", "3.14159,0,0",
                          "6.3,0,0", "1,2"]),
    ("--attitude0", ["0,0,3", "nan,0,0"]),
    ("--omega0", ["0,0,0", "nan,0,0", "1e6,0,0", "10,0,0"]),
    ("--omega-final", ["1,0,0", "inf,0,0"]),
    ("--t-end", ["0", "-1", "nan", "inf", "1e-9", "1e9"]),
    ("--torque-max", ["0", "-1", "nan", "inf", "1e-9", "1e300", "1,2", "0.05"]),
    ("--steps", ["0", "1", "2", "2000"]),
    ("--nodes", ["0", "1", "2", "101"]),
    ("--tolerance", ["0", "-1", "nan", "1e-300", "1e-14", "1"]),
    ("--max-iterations", ["0", "1"]),
    ("--cost", ["time", "fuel"]),
]


def run(args):
    """(status, stdout, stderr) or ('hang', '', '') after TIMEOUT seconds."""
    try:
        out = subprocess.run([LGSVI, *args], capture_output=True, text=True, timeout=TIMEOUT)
    except subprocess.TimeoutExpired:
        return "hang", "", ""
    return out.returncode, out.stdout, out.stderr


def estimate(stdout):
    try:
        return json.loads(stdout)["stats"]["estimated_error"]
    except (ValueError, KeyError, TypeError):
        return None


def classify(args):
    status, stdout, stderr = run(args)
    if status == "hang":
        return "hang", ""
    if status < 0 or "panicked" in stderr:
        return "panic", stderr.strip()
    if status != 0:
        message = stderr.strip()
        if len(message.splitlines()) > 1:
            return "multi-line", message
        if "--" in message or any(c in message for c in CAUSES):
            return "refused", message
        return "unclear", message
    if "--tol" in args or "--exact" in args:
        return "ok", stderr.strip()
    own = estimate(stdout)
    status, checked_out, _ = run([*args, "--check"])
    measured = estimate(checked_out) if status == 0 else None
    if own is not None and measured is not None and measured > max(10 * own, 1e-10):
        if "warning" not in stderr:
            return "suspect", f"estimate {own:.1e}, companion measures {measured:.1e}"
    return "ok", stderr.strip()


def main():
    inputs = []
    for (system, base), (flag, values, systems) in itertools.product(SYSTEMS.items(), FLAGS):
        if systems is not None and system not in systems:
            continue
        for value in values:
            # The flag's value replaces the base's (the gyrostat's wheels) and the horizon.
            args = [a for i, a in enumerate(base) if flag not in (a, base[i - 1] if i else "")]
            horizon = [] if flag == "--t-end" else ["--t-end", "4"]
            inputs.append([*args, f"{flag}={value}", *horizon])
    # Combinations a user meets: a LEO satellite, stiff damping under --tol, a thin rod
    # under --tol, a heavy top spun fast.
    inputs += [
        [*SYSTEMS["orbiting-body"], "--mass=1000", "--inertia=1000,1200,1400",
         "--position0=7e6,0,0", "--velocity0=0,7546,0", "--mu=3.986e14", "--omega0=0,0,0.001",
         "--t-end", "600", "--h", "10"],
        ["--damping=3000", "--tol=1e-10", "--t-end", "4"],
        ["--inertia=1e-7,1,1", "--tol=1e-10", "--t-end", "4"],
        [*SYSTEMS["heavy-top"], "--omega0=0,0,300", "--t-end", "4"],
    ]
    commands = [["simulate", *args] for args in inputs]
    for flag, values in OPTIMIZE_FLAGS:
        for value in values:
            base = [a for a in OPTIMIZE_BASE if not a.startswith(flag + "=")]
            commands.append(["optimize", "--quiet", *base, f"{flag}={value}"])
    counts = {}
    with tempfile.TemporaryDirectory() as _:
        for args in commands:
            # One value per flag: the flag's own `=` keeps values with a leading minus.
            kind, message = classify(args)
            counts[kind] = counts.get(kind, 0) + 1
            if kind != "ok" or message:
                print(f"{kind:10} {' '.join(args)}\n           {message[:400]}")
    print(f"\n{len(commands)} inputs: " + ", ".join(f"{k} {v}" for k, v in sorted(counts.items())))


if __name__ == "__main__":
    main()
